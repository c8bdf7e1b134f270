//! Elements and van der Waals radii.
//!
//! The default radii are Bondi's (1964) table; elements Bondi lacks take the
//! values of Mantina et al. (2009), "Consistent van der Waals radii for the whole
//! main group". Metals take their ionic radii instead (Shannon 1976, six-fold
//! coordination, in the oxidation state they mostly have in biological
//! structures), as Chimera and ChimeraX give ions: a metal's contacts are
//! coordination bonds of about 2 Å (Zn–N 2.05, Mg–O 2.1, Ca–O 2.4), which van
//! der Waals radii would count as overlaps of 0.9–1.5 Å, deeper than any
//! clash cutoff. An element no table knows gets [`UNKNOWN_RADIUS`] and the
//! loader reports a warning. `RadiiSet::Thesis` uses the radii Turk's thesis
//! quotes for C, O, N and S (section 5.2) and the default table for the rest.

use serde::Serialize;

/// Radius given to an element no table knows, in Å.
pub const UNKNOWN_RADIUS: f32 = 2.0;

/// Which table of van der Waals radii to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RadiiSet {
    /// Bondi (1964), completed with Mantina et al. (2009); ionic radii for metals.
    #[default]
    Bondi,
    /// Turk (1989): C 1.74, O 1.40, N 1.54, S 1.80; the default table for the rest.
    Thesis,
}

impl RadiiSet {
    /// Parses `bondi` or `thesis`.
    pub fn parse(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "bondi" => Some(Self::Bondi),
            "thesis" => Some(Self::Thesis),
            _ => None,
        }
    }

    /// The table's name as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Bondi => "bondi",
            Self::Thesis => "thesis",
        }
    }

    /// The radius of `element` (a symbol in any case, e.g. `C`, `Cl`, `CL`),
    /// or `None` when neither table knows it.
    pub fn radius(self, element: &str) -> Option<f32> {
        let sym = normalize_symbol(element);
        if self == Self::Thesis {
            match sym.as_str() {
                "C" => return Some(1.74),
                "O" => return Some(1.40),
                "N" => return Some(1.54),
                "S" => return Some(1.80),
                _ => {}
            }
        }
        ionic(&sym)
            .or_else(|| bondi(&sym))
            .or_else(|| mantina(&sym))
    }
}

/// Upper-cases the first letter and lower-cases the rest (`CL` -> `Cl`).
pub fn normalize_symbol(element: &str) -> String {
    let t = element.trim();
    let mut out = String::with_capacity(t.len());
    for (i, c) in t.chars().enumerate() {
        if i == 0 {
            out.extend(c.to_uppercase());
        } else {
            out.extend(c.to_lowercase());
        }
    }
    out
}

/// True for hydrogen and deuterium.
pub fn is_hydrogen(symbol: &str) -> bool {
    matches!(normalize_symbol(symbol).as_str(), "H" | "D")
}

/// True for nitrogen and oxygen: the atoms that can form a hydrogen bond, whose
/// pairs get the contact rule's extra allowance.
pub fn is_polar(symbol: &str) -> bool {
    matches!(normalize_symbol(symbol).as_str(), "N" | "O")
}

/// The metals protein and ligand structures hold as ions or coordination
/// centres, with Shannon's (1976, Acta Cryst. A32, 751, Table 1) effective
/// ionic radii in six-fold coordination, high spin where there is a choice,
/// in the oxidation state given beside each.
fn ionic(sym: &str) -> Option<f32> {
    Some(match sym {
        "Li" => 0.76,  // +1
        "Na" => 1.02,  // +1
        "K" => 1.38,   // +1
        "Rb" => 1.52,  // +1
        "Cs" => 1.67,  // +1
        "Be" => 0.45,  // +2
        "Mg" => 0.72,  // +2
        "Ca" => 1.00,  // +2
        "Sr" => 1.18,  // +2
        "Ba" => 1.35,  // +2
        "Al" => 0.535, // +3
        "Ga" => 0.62,  // +3
        "In" => 0.80,  // +3
        "Tl" => 1.50,  // +1
        "Pb" => 1.19,  // +2
        "Bi" => 1.03,  // +3
        "Sc" => 0.745, // +3
        "Ti" => 0.605, // +4
        "V" => 0.58,   // +4 (vanadyl)
        "Cr" => 0.615, // +3
        "Mn" => 0.83,  // +2
        "Fe" => 0.78,  // +2
        "Co" => 0.745, // +2
        "Ni" => 0.69,  // +2
        "Cu" => 0.73,  // +2
        "Zn" => 0.74,  // +2
        "Y" => 0.90,   // +3
        "Zr" => 0.72,  // +4
        "Mo" => 0.59,  // +6
        "Ru" => 0.68,  // +3
        "Rh" => 0.665, // +3
        "Pd" => 0.86,  // +2
        "Ag" => 1.15,  // +1
        "Cd" => 0.95,  // +2
        "W" => 0.60,   // +6
        "Os" => 0.63,  // +4
        "Ir" => 0.68,  // +3
        "Pt" => 0.80,  // +2
        "Au" => 1.37,  // +1
        "Hg" => 1.02,  // +2
        "La" => 1.032, // +3, and the lanthanides after it
        "Ce" => 1.01,
        "Pr" => 0.99,
        "Nd" => 0.983,
        "Sm" => 0.958,
        "Eu" => 0.947,
        "Gd" => 0.938,
        "Tb" => 0.923,
        "Dy" => 0.912,
        "Ho" => 0.901,
        "Er" => 0.89,
        "Tm" => 0.88,
        "Yb" => 0.868,
        "Lu" => 0.861,
        "U" => 0.73, // +6 (uranyl)
        _ => return None,
    })
}

/// Bondi, A. (1964) J. Phys. Chem. 68, 441, Table I, less the metals [`ionic`] gives.
fn bondi(sym: &str) -> Option<f32> {
    Some(match sym {
        "H" | "D" => 1.20,
        "He" => 1.40,
        "C" => 1.70,
        "N" => 1.55,
        "O" => 1.52,
        "F" => 1.47,
        "Ne" => 1.54,
        "Si" => 2.10,
        "P" => 1.80,
        "S" => 1.80,
        "Cl" => 1.75,
        "Ar" => 1.88,
        "As" => 1.85,
        "Se" => 1.90,
        "Br" => 1.85,
        "Kr" => 2.02,
        "Te" => 2.06,
        "I" => 1.98,
        "Xe" => 2.16,
        "Sn" => 2.17,
        _ => return None,
    })
}

/// Mantina, M. et al. (2009) J. Phys. Chem. A 113, 5806, Table 12, for the
/// main-group elements Bondi lacks, less the metals [`ionic`] gives.
fn mantina(sym: &str) -> Option<f32> {
    Some(match sym {
        "B" => 1.92,
        "Ge" => 2.11,
        "Sb" => 2.06,
        "Po" => 1.97,
        "At" => 2.02,
        "Rn" => 2.20,
        "Fr" => 3.48,
        "Ra" => 2.83,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bondi_values_from_the_issue() {
        let b = RadiiSet::Bondi;
        for (e, r) in [
            ("H", 1.20),
            ("C", 1.70),
            ("N", 1.55),
            ("O", 1.52),
            ("F", 1.47),
            ("P", 1.80),
            ("S", 1.80),
            ("CL", 1.75),
            ("Br", 1.85),
            ("I", 1.98),
            ("SE", 1.90),
        ] {
            assert_eq!(b.radius(e), Some(r), "{e}");
        }
    }

    #[test]
    fn thesis_overrides_four_elements_only() {
        let t = RadiiSet::Thesis;
        assert_eq!(t.radius("C"), Some(1.74));
        assert_eq!(t.radius("O"), Some(1.40));
        assert_eq!(t.radius("N"), Some(1.54));
        assert_eq!(t.radius("S"), Some(1.80));
        assert_eq!(t.radius("Cl"), Some(1.75));
    }

    #[test]
    fn mantina_fills_gaps_and_unknowns_are_none() {
        assert_eq!(RadiiSet::Bondi.radius("B"), Some(1.92));
        assert_eq!(RadiiSet::Bondi.radius("Ge"), Some(2.11));
        assert_eq!(RadiiSet::Bondi.radius("Og"), None);
        assert_eq!(RadiiSet::Bondi.radius(""), None);
    }

    #[test]
    fn metals_take_ionic_radii_so_coordination_is_a_touch() {
        for set in [RadiiSet::Bondi, RadiiSet::Thesis] {
            assert_eq!(set.radius("ZN"), Some(0.74));
            assert_eq!(set.radius("Fe"), Some(0.78));
            assert_eq!(set.radius("Mg"), Some(0.72));
        }
        assert_eq!(RadiiSet::Bondi.radius("Ca"), Some(1.00));
        assert_eq!(RadiiSet::Bondi.radius("Se"), Some(1.90));
        // Coordination distances (Harding's surveys of metal sites in
        // proteins) leave less overlap than the default clash cutoff, 0.6 Å.
        let b = RadiiSet::Bondi;
        for (metal, donor, d) in [
            ("Zn", "N", 2.05),
            ("Zn", "S", 2.33),
            ("Mg", "O", 2.07),
            ("Ca", "O", 2.36),
            ("Na", "O", 2.41),
            ("K", "O", 2.84),
            ("Fe", "N", 2.0),
            ("Mn", "O", 2.19),
            ("Cu", "N", 2.02),
        ] {
            let overlap = b.radius(metal).expect(metal) + b.radius(donor).expect(donor) - d;
            assert!(overlap < 0.6, "{metal}–{donor} {overlap}");
        }
    }

    #[test]
    fn polar_and_hydrogen() {
        assert!(is_polar("n") && is_polar("O") && !is_polar("C"));
        assert!(is_hydrogen("H") && is_hydrogen("d") && !is_hydrogen("HG"));
    }
}
