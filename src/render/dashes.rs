//! Dashed segments: a hydrogen bond from donor to acceptor drawn as dashes
//! of a fixed length in Å, centred on the bond so both ends look alike.

use glam::DVec3;

/// The dashes of a segment `len` Å long as parts `(t0, t1)` of it (0 at
/// its start, 1 at its end): pieces `dash` Å long separated by `gap` Å, as
/// many whole dashes as fit, centred (a segment shorter than one dash is
/// one dash, the segment itself). Empty for a degenerate segment or
/// non-positive lengths. The renderer draws each as a short cylinder
/// between the two atoms.
pub fn dash_ranges(len: f64, dash: f64, gap: f64) -> Vec<(f64, f64)> {
    if !(len > 1e-9 && dash > 0.0 && gap >= 0.0 && len.is_finite()) {
        return Vec::new();
    }
    if len <= dash {
        return vec![(0.0, 1.0)];
    }
    // n dashes and n − 1 gaps fit in len.
    let n = ((len + gap) / (dash + gap)).floor().max(1.0) as usize;
    let used = n as f64 * dash + (n - 1) as f64 * gap;
    let start = 0.5 * (len - used);
    (0..n)
        .map(|k| {
            let s = start + k as f64 * (dash + gap);
            (s / len, (s + dash) / len)
        })
        .collect()
}

/// The dashes of the segment `a`–`b` ([`dash_ranges`]) as end points.
pub fn dashes(a: DVec3, b: DVec3, dash: f64, gap: f64) -> Vec<(DVec3, DVec3)> {
    dash_ranges((b - a).length(), dash, gap)
        .into_iter()
        .map(|(t0, t1)| (a.lerp(b, t0), a.lerp(b, t1)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dashes_are_centred_whole_and_on_the_segment() {
        let (a, b) = (DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0));
        let d = dashes(a, b, 0.4, 0.3);
        // 4 dashes and 3 gaps: 2.5 Å, centred: 0.25 Å margins.
        assert_eq!(d.len(), 4);
        assert!((d[0].0.x - 0.25).abs() < 1e-12);
        assert!((d[3].1.x - 2.75).abs() < 1e-12);
        for (p, q) in &d {
            assert!(((q.x - p.x) - 0.4).abs() < 1e-12);
            assert_eq!((p.y, p.z, q.y, q.z), (0.0, 0.0, 0.0, 0.0));
        }
        for w in d.windows(2) {
            assert!(((w[1].0.x - w[0].1.x) - 0.3).abs() < 1e-12);
        }
        // Symmetric: the same dashes from the other end.
        let r = dashes(b, a, 0.4, 0.3);
        assert!((r[0].0.x - 2.75).abs() < 1e-12);
        assert_eq!(dashes(a, DVec3::new(0.2, 0.0, 0.0), 0.4, 0.3).len(), 1);
        assert!(dashes(a, a, 0.4, 0.3).is_empty());
        assert!(dashes(a, b, 0.0, 0.3).is_empty());
    }

    #[test]
    fn dash_ranges_are_whole_dashes_in_order_inside_the_segment() {
        for len in [0.1, 0.3, 0.31, 1.0, 2.9, 3.0, 3.5] {
            let r = dash_ranges(len, 0.3, 0.2);
            assert!(!r.is_empty(), "{len}");
            let mut last = 0.0;
            for &(t0, t1) in &r {
                assert!(
                    t0 >= last - 1e-12 && t1 > t0 && t1 <= 1.0 + 1e-12,
                    "{len}: {r:?}"
                );
                if len > 0.3 {
                    assert!(((t1 - t0) * len - 0.3).abs() < 1e-9, "{len}: {r:?}");
                }
                last = t1;
            }
            // Centred: equal margins at both ends.
            let (first, end) = (r[0].0, 1.0 - r[r.len() - 1].1);
            assert!((first - end).abs() < 1e-9, "{len}: {r:?}");
            // As many as fit: one more would not.
            let n = r.len() as f64;
            assert!(n * 0.3 + (n - 1.0) * 0.2 <= len.max(0.3) + 1e-9);
            assert!((n + 1.0) * 0.3 + n * 0.2 > len);
        }
        // A 2.9 Å hydrogen bond: 6 dashes (6 × 0.3 + 5 × 0.2 = 2.8 Å).
        assert_eq!(dash_ranges(2.9, 0.3, 0.2).len(), 6);
    }
}
