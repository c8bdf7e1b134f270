//! Atom colours: CPK element colours (as in Jmol/PyMOL), carbons tinted per
//! molecule so receptor and drug are told apart, and the contact highlight.

/// Colour of atoms in contact (magenta: no element has it).
pub const HIGHLIGHT: [f32; 3] = [1.0, 0.1, 0.9];

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
