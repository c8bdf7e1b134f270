//! Per-element data for perception: covalent radii, usual valences, and
//! which elements are metals.
//!
//! Covalent radii are Cordero et al. (2008), "Covalent radii revisited",
//! Dalton Trans. 2832 (sp3 carbon; the values the PDB's and Open Babel's bond
//! perception use within a few hundredths of an Å).

/// Covalent radius (Å) of a normalised element symbol, or `None` when the
/// table lacks it.
pub fn covalent_radius(element: &str) -> Option<f64> {
    Some(match element {
        "H" | "D" => 0.31,
        "B" => 0.84,
        "C" => 0.76,
        "N" => 0.71,
        "O" => 0.66,
        "F" => 0.57,
        "Si" => 1.11,
        "P" => 1.07,
        "S" => 1.05,
        "Cl" => 1.02,
        "As" => 1.19,
        "Se" => 1.20,
        "Br" => 1.20,
        "Te" => 1.38,
        "I" => 1.39,
        "At" => 1.50,
        "Li" => 1.28,
        "Na" => 1.66,
        "K" => 2.03,
        "Mg" => 1.41,
        "Ca" => 1.76,
        "Mn" => 1.39,
        "Fe" => 1.32,
        "Co" => 1.26,
        "Ni" => 1.24,
        "Cu" => 1.32,
        "Zn" => 1.22,
        "Cd" => 1.44,
        "Hg" => 1.32,
        _ => return None,
    })
}

/// Extra length over the sum of covalent radii still read as a bond (Å):
/// Open Babel's and the PDB's tolerance.
pub const BOND_TOLERANCE: f64 = 0.45;

/// Shortest distance read as a bond (Å): closer atoms are a clash or an
/// alternate location, not a bond.
pub const MIN_BOND_LENGTH: f64 = 0.4;

/// True for the elements perception treats as organic: they take part in
/// distance-perceived bonds and have usual valences.
pub fn is_organic(element: &str) -> bool {
    matches!(
        element,
        "H" | "D"
            | "B"
            | "C"
            | "N"
            | "O"
            | "F"
            | "Si"
            | "P"
            | "S"
            | "Cl"
            | "As"
            | "Se"
            | "Br"
            | "Te"
            | "I"
            | "At"
    )
}

/// The metals: groups 1 and 2 (less H), the transition metals, the
/// lanthanides and actinides, and the post-transition metals.
const METALS: &[&str] = &[
    "Li", "Na", "K", "Rb", "Cs", "Fr", "Be", "Mg", "Ca", "Sr", "Ba", "Ra", "Sc", "Ti", "V", "Cr",
    "Mn", "Fe", "Co", "Ni", "Cu", "Zn", "Y", "Zr", "Nb", "Mo", "Tc", "Ru", "Rh", "Pd", "Ag", "Cd",
    "Hf", "Ta", "W", "Re", "Os", "Ir", "Pt", "Au", "Hg", "La", "Ce", "Pr", "Nd", "Pm", "Sm", "Eu",
    "Gd", "Tb", "Dy", "Ho", "Er", "Tm", "Yb", "Lu", "Ac", "Th", "Pa", "U", "Np", "Pu", "Am", "Al",
    "Ga", "In", "Sn", "Tl", "Pb", "Bi", "Po", "Ge", "Sb",
];

/// True for metals. Their contacts are coordination, not covalent bonds:
/// perception gives them no bonds, so a histidine bound to a zinc keeps its
/// hydrogen.
pub fn is_metal(element: &str) -> bool {
    METALS.contains(&element)
}

/// True for halogens.
pub fn is_halogen(element: &str) -> bool {
    matches!(element, "F" | "Cl" | "Br" | "I" | "At")
}

/// The usual valences of a neutral atom, smallest first (the number of
/// hydrogens an atom gets is the smallest valence at least its bond order
/// sum, less that sum). Empty for elements without one (metals).
pub fn valences(element: &str) -> &'static [u8] {
    match element {
        "H" | "D" | "F" | "Cl" | "Br" | "I" | "At" => &[1],
        "B" => &[3],
        "C" | "Si" => &[4],
        // Pentavalent N is written charge-separated (nitro, N-oxide).
        "N" => &[3],
        "As" => &[3, 5],
        "O" => &[2],
        "P" => &[3, 5],
        "S" | "Se" | "Te" => &[2, 4, 6],
        _ => &[],
    }
}

/// The usual valences of an atom with a formal charge: a charged N, P or O
/// is isoelectronic with the next (cation) or previous (anion) group
/// (NH4+ like CH4, O- like F), as RDKit and Open Babel count it.
pub fn charged_valences(element: &str, charge: i8) -> Vec<u8> {
    let base = valences(element);
    if charge == 0 {
        return base.to_vec();
    }
    let shift = |v: u8| -> Option<u8> {
        match element {
            // Group 15/16 cations gain a bond, anions lose one.
            "N" | "P" | "O" | "S" | "As" | "Se" => {
                u8::try_from(i16::from(v) + i16::from(charge)).ok()
            }
            // Carbon and boron lose one bond either way (carbocation, carbanion, borate gains).
            "C" | "Si" => u8::try_from(i16::from(v) - i16::from(charge.abs())).ok(),
            "B" => u8::try_from(i16::from(v) - i16::from(charge)).ok(),
            _ => u8::try_from(i16::from(v) - i16::from(charge.abs())).ok(),
        }
    };
    base.iter().filter_map(|&v| shift(v)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metals_and_valences() {
        assert!(is_metal("Zn") && is_metal("Sm") && !is_metal("C") && !is_metal("Se"));
        assert_eq!(valences("N"), &[3]);
        assert_eq!(charged_valences("N", 1), vec![4]);
        assert_eq!(charged_valences("O", -1), vec![1]);
        assert_eq!(charged_valences("C", -1), vec![3]);
        assert!(covalent_radius("C").is_some() && covalent_radius("Xx").is_none());
    }
}
