//! Atom colours: CPK element colours (as in Jmol/PyMOL), carbons tinted per
//! molecule so receptor and drug are told apart, the contact highlight, and
//! the diverging scale of per-atom score contributions.

/// Colour of atoms in contact (magenta: no element has it).
pub const HIGHLIGHT: [f32; 3] = [1.0, 0.1, 0.9];

/// Colour of a pair pressed to the `soft` limit; pressed atoms are graded
/// from [`HIGHLIGHT`] towards it by depth ([`contact_colour`]).
pub const PRESSED_DEEP: [f32; 3] = [1.0, 0.8, 0.0];

/// The colour an atom in contact is drawn with at highlight `level`
/// ([`crate::session::Session::highlight_level`]; at least 1): the
/// highlight at 1, [`PRESSED_DEEP`] at [`crate::session::PRESS_LEVELS`], in
/// equal steps between. The shaders' `contact_colour` computes the same.
pub fn contact_colour(level: u8) -> [f32; 3] {
    let top = crate::session::PRESS_LEVELS;
    let t = f32::from(level.clamp(1, top) - 1) / f32::from(top - 1);
    std::array::from_fn(|k| HIGHLIGHT[k] + t * (PRESSED_DEEP[k] - HIGHLIGHT[k]))
}

/// Background colour (linear RGB).
pub const BACKGROUND: [f64; 3] = [0.02, 0.02, 0.035];

/// Carbon colour of molecule `body`: grey for the first (the receptor),
/// green for the second (the drug), then cyan, orange, violet, ...
pub fn carbon(body: usize) -> [f32; 3] {
    const CARBONS: [[f32; 3]; 6] = [
        [0.62, 0.62, 0.62],
        [0.15, 0.78, 0.15],
        [0.10, 0.70, 0.80],
        [0.95, 0.55, 0.15],
        [0.60, 0.40, 0.90],
        [0.85, 0.75, 0.35],
    ];
    CARBONS[body % CARBONS.len()]
}

/// CPK colour of `element` (normalised symbol) in molecule `body`.
pub fn element(symbol: &str, body: usize) -> [f32; 3] {
    match symbol {
        "C" => carbon(body),
        "H" | "D" => [0.92, 0.92, 0.92],
        "N" => [0.19, 0.31, 0.97],
        "O" => [1.0, 0.05, 0.05],
        "S" => [1.0, 0.85, 0.19],
        "P" => [1.0, 0.5, 0.0],
        "F" | "Cl" => [0.12, 0.94, 0.12],
        "Br" => [0.65, 0.16, 0.16],
        "I" => [0.58, 0.0, 0.58],
        "Se" => [1.0, 0.63, 0.0],
        "Fe" => [0.88, 0.4, 0.2],
        "Zn" | "Cu" | "Ni" | "Co" | "Mn" => [0.49, 0.5, 0.69],
        "Ca" | "Mg" => [0.24, 1.0, 0.0],
        "Na" | "K" => [0.67, 0.36, 0.95],
        _ => [1.0, 0.08, 0.58],
    }
}

/// The contribution (kcal/mol per atom) at which the diverging scale is
/// fully blue (−) or fully red (+).
pub const CONTRIBUTION_RANGE: f64 = 0.5;

/// Steps of the scale on each side of neutral: contributions are
/// quantised to `2 × CONTRIBUTION_LEVELS + 1` colours, so an atom's colour
/// is uploaded again only when it crosses a step.
pub const CONTRIBUTION_LEVELS: i8 = 8;

/// Favourable end of the scale (linear RGB).
pub const FAVOURABLE: [f32; 3] = [0.02, 0.12, 1.0];
/// Neutral middle of the scale.
pub const NEUTRAL: [f32; 3] = [1.0, 1.0, 1.0];
/// Unfavourable end of the scale.
pub const UNFAVOURABLE: [f32; 3] = [1.0, 0.02, 0.02];

/// The step of contribution `e` on the scale: −[`CONTRIBUTION_LEVELS`]
/// (at or below −[`CONTRIBUTION_RANGE`]) to +[`CONTRIBUTION_LEVELS`];
/// 0 for a non-finite value.
pub fn contribution_level(e: f64) -> i8 {
    if !e.is_finite() {
        return 0;
    }
    let l = f64::from(CONTRIBUTION_LEVELS);
    (e / CONTRIBUTION_RANGE * l).round().clamp(-l, l) as i8
}

/// The colour of step `level` (clamped to the scale): white at 0, blending
/// linearly to [`FAVOURABLE`] below and [`UNFAVOURABLE`] above.
pub fn level_color(level: i8) -> [f32; 3] {
    let n = CONTRIBUTION_LEVELS;
    let l = level.clamp(-n, n);
    let f = f32::from(l.unsigned_abs()) / f32::from(n);
    let end = if l < 0 { FAVOURABLE } else { UNFAVOURABLE };
    [0, 1, 2].map(|k| NEUTRAL[k] * (1.0 - f) + end[k] * f)
}

/// The colour of contribution `e` (kcal/mol): favourable blue, neutral
/// white, unfavourable red.
pub fn contribution(e: f64) -> [f32; 3] {
    level_color(contribution_level(e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_contribution_scale_diverges_from_white() {
        assert_eq!(contribution(0.0), NEUTRAL);
        assert_eq!(contribution(-CONTRIBUTION_RANGE), FAVOURABLE);
        assert_eq!(contribution(-3.0), FAVOURABLE);
        assert_eq!(contribution(2.0), UNFAVOURABLE);
        assert_eq!(contribution(f64::NAN), NEUTRAL);
        // Half way: half way between white and the end, in linear RGB.
        let h = contribution(-CONTRIBUTION_RANGE / 2.0);
        assert!((h[0] - 0.51).abs() < 1e-6 && (h[2] - 1.0).abs() < 1e-6);
        // Quantised: a change within a step keeps the colour.
        assert_eq!(contribution_level(0.01), 0);
        assert_eq!(contribution_level(0.07), contribution_level(0.09));
        assert_eq!(contribution_level(-0.0625), -1);
        // Monotone: more favourable is never less blue.
        let mut last = 0.0f32;
        for i in 0..=20 {
            let c = contribution(-0.05 * f64::from(i));
            assert!(1.0 - c[0] >= last);
            last = 1.0 - c[0];
        }
    }

    /// The graded contact colours run from the highlight to the deep press,
    /// and the shaders carry the same constants.
    #[test]
    fn pressed_contacts_are_graded_as_the_shaders_grade_them() {
        assert_eq!(contact_colour(1), HIGHLIGHT);
        assert_eq!(contact_colour(crate::session::PRESS_LEVELS), PRESSED_DEEP);
        assert_eq!(contact_colour(200), PRESSED_DEEP);
        // Green rises level by level: each deeper level is told apart.
        for l in 1..crate::session::PRESS_LEVELS {
            assert!(contact_colour(l + 1)[1] > contact_colour(l)[1]);
        }
        let deep = format!(
            "const PRESSED_DEEP: vec3<f32> = vec3<f32>({:?}, {:?}, {:?});",
            PRESSED_DEEP[0], PRESSED_DEEP[1], PRESSED_DEEP[2]
        );
        let levels = format!(
            "const PRESS_LEVELS: u32 = {}u;",
            crate::session::PRESS_LEVELS
        );
        for shader in [
            include_str!("../../shaders/spheres.wgsl"),
            include_str!("../../shaders/cylinders.wgsl"),
        ] {
            assert!(shader.contains(&deep), "{deep}");
            assert!(shader.contains(&levels), "{levels}");
        }
    }
}
