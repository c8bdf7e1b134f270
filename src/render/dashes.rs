//! Dashed segments: a hydrogen bond from donor to acceptor drawn as dashes
//! of a fixed length in Å, centred on the bond so both ends look alike.

use glam::DVec3;

/// The dashes of the segment `a`–`b`: pieces `dash` Å long separated by
/// `gap` Å, as many whole dashes as fit, centred on the segment (a segment
/// shorter than one dash is one dash, the segment itself). Empty for a
/// degenerate segment or non-positive lengths.
pub fn dashes(a: DVec3, b: DVec3, dash: f64, gap: f64) -> Vec<(DVec3, DVec3)> {
    let len = (b - a).length();
    if !(len > 1e-9 && dash > 0.0 && gap >= 0.0 && len.is_finite()) {
        return Vec::new();
    }
    let u = (b - a) / len;
    if len <= dash {
        return vec![(a, b)];
    }
    // n dashes and n − 1 gaps fit in len.
    let n = ((len + gap) / (dash + gap)).floor().max(1.0) as usize;
    let used = n as f64 * dash + (n - 1) as f64 * gap;
    let start = 0.5 * (len - used);
    (0..n)
        .map(|k| {
            let s = start + k as f64 * (dash + gap);
            (a + u * s, a + u * (s + dash))
        })
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
}
