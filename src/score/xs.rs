//! AutoDock Vina's X-Score atom types, as the scoring reads them.
//!
//! The chemistry (`chem`) assigns them; the scoring only needs each type's
//! index and its hydrophobic, donor and acceptor classes. Scoring takes typed
//! atoms, so it works the same with types recorded from Vina itself
//! (`tests/reference/vina/values.json`) and with bump's own typing.

use serde::Serialize;

/// Vina's X-Score atom types (the first 19 of `atom_constants.h`), in
/// Vina's index order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[allow(non_camel_case_types)] // Vina's own names, as every Vina user reads them.
pub enum XsType {
    /// Carbon bonded only to carbon and hydrogen (hydrophobic).
    C_H,
    /// Carbon bonded to a heteroatom.
    C_P,
    /// Nitrogen, neither donor nor acceptor.
    N_P,
    /// Nitrogen donor.
    N_D,
    /// Nitrogen acceptor.
    N_A,
    /// Nitrogen donor and acceptor.
    N_DA,
    /// Oxygen, neither donor nor acceptor.
    O_P,
    /// Oxygen donor.
    O_D,
    /// Oxygen acceptor.
    O_A,
    /// Oxygen donor and acceptor.
    O_DA,
    /// Sulfur.
    S_P,
    /// Phosphorus.
    P_P,
    /// Fluorine (hydrophobic).
    F_H,
    /// Chlorine (hydrophobic).
    Cl_H,
    /// Bromine (hydrophobic).
    Br_H,
    /// Iodine (hydrophobic).
    I_H,
    /// Silicon.
    Si,
    /// Astatine.
    At,
    /// Metal (a donor).
    Met_D,
}

impl XsType {
    /// Every type, in Vina's index order.
    pub const ALL: [XsType; 19] = [
        XsType::C_H,
        XsType::C_P,
        XsType::N_P,
        XsType::N_D,
        XsType::N_A,
        XsType::N_DA,
        XsType::O_P,
        XsType::O_D,
        XsType::O_A,
        XsType::O_DA,
        XsType::S_P,
        XsType::P_P,
        XsType::F_H,
        XsType::Cl_H,
        XsType::Br_H,
        XsType::I_H,
        XsType::Si,
        XsType::At,
        XsType::Met_D,
    ];

    /// Vina's index of the type (0 for C_H … 18 for Met_D).
    pub fn index(self) -> usize {
        self as usize
    }

    /// The name Vina uses (`C_H`, `N_DA`, `Met_D`).
    pub fn name(self) -> &'static str {
        const NAMES: [&str; 19] = [
            "C_H", "C_P", "N_P", "N_D", "N_A", "N_DA", "O_P", "O_D", "O_A", "O_DA", "S_P", "P_P",
            "F_H", "Cl_H", "Br_H", "I_H", "Si", "At", "Met_D",
        ];
        NAMES[self.index()]
    }

    /// The type Vina names `name`.
    pub fn from_name(name: &str) -> Option<XsType> {
        XsType::ALL.into_iter().find(|t| t.name() == name)
    }

    /// True for hydrophobic types (C_H and the halogens).
    pub fn is_hydrophobic(self) -> bool {
        matches!(
            self,
            XsType::C_H | XsType::F_H | XsType::Cl_H | XsType::Br_H | XsType::I_H
        )
    }

    /// True for hydrogen-bond donors (N_D, N_DA, O_D, O_DA, Met_D).
    pub fn is_donor(self) -> bool {
        matches!(
            self,
            XsType::N_D | XsType::N_DA | XsType::O_D | XsType::O_DA | XsType::Met_D
        )
    }

    /// True for hydrogen-bond acceptors (N_A, N_DA, O_A, O_DA).
    pub fn is_acceptor(self) -> bool {
        matches!(self, XsType::N_A | XsType::N_DA | XsType::O_A | XsType::O_DA)
    }
}
