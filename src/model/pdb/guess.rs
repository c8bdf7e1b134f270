//! Elements for atoms whose element field is blank or unreadable, guessed
//! from the atom name by the PDB's alignment convention.

use crate::model::element;

/// Residue names whose atoms are only C, N, O, S, P and H: amino acids (with
/// common protonation-state names), nucleotides and caps. Their atom names
/// start with the element letter, whatever the column alignment.
const POLYMER_RESIDUES: &[&str] = &[
    "ALA", "ARG", "ASN", "ASP", "CYS", "GLN", "GLU", "GLY", "HIS", "ILE", "LEU", "LYS", "MET",
    "PHE", "PRO", "SER", "THR", "TRP", "TYR", "VAL", "HID", "HIE", "HIP", "HSD", "HSE", "HSP",
    "CYX", "ASH", "GLH", "LYN", "ACE", "NME", "NMA", "DA", "DC", "DG", "DT", "DU", "DI", "A", "C",
    "G", "U", "I",
];

/// Guesses an element from a PDB atom-name field (columns 13–16, unstripped)
/// and its residue name, by the PDB convention that the element symbol is
/// right-justified in columns 13–14:
/// - in standard polymer residues and waters, the first letter of the name;
/// - when column 13 is blank or a digit, the first letter (`" CA "` is carbon);
/// - when column 13 is a letter: a four-character name starting with `H` is
///   hydrogen (`HG21`); a name whose letters are exactly two and form an
///   element symbol, or equal the residue name, is that element (`FE`,
///   `CL1 `, `CA` in residue `CA`); otherwise the first letter.
///
/// `None` when the name has no letter.
pub fn guess_pdb_element(name: &str, residue: &str) -> Option<String> {
    let trimmed = name.trim();
    let letters: String = trimmed
        .chars()
        .skip_while(|c| c.is_ascii_digit())
        .take_while(|c| c.is_ascii_alphabetic())
        .collect();
    let first = letters.chars().next()?.to_ascii_uppercase().to_string();
    let residue = residue.trim().to_ascii_uppercase();
    if POLYMER_RESIDUES.contains(&residue.as_str()) || crate::model::is_water(&residue) {
        return Some(first);
    }
    let col13_letter = name.chars().next().is_some_and(|c| c.is_ascii_alphabetic());
    if !col13_letter || letters.len() < 2 {
        return Some(first);
    }
    if first == "H" && trimmed.len() == 4 {
        return Some(first);
    }
    let upper = letters.to_ascii_uppercase();
    let two = &upper[..2];
    if (letters.len() == 2 || upper == residue) && is_element_symbol(two) {
        return Some(element::normalize_symbol(two));
    }
    Some(first)
}

/// The symbols of the 118 elements.
const ELEMENT_SYMBOLS: [&str; 118] = [
    "H", "He", "Li", "Be", "B", "C", "N", "O", "F", "Ne", "Na", "Mg", "Al", "Si", "P", "S", "Cl",
    "Ar", "K", "Ca", "Sc", "Ti", "V", "Cr", "Mn", "Fe", "Co", "Ni", "Cu", "Zn", "Ga", "Ge", "As",
    "Se", "Br", "Kr", "Rb", "Sr", "Y", "Zr", "Nb", "Mo", "Tc", "Ru", "Rh", "Pd", "Ag", "Cd", "In",
    "Sn", "Sb", "Te", "I", "Xe", "Cs", "Ba", "La", "Ce", "Pr", "Nd", "Pm", "Sm", "Eu", "Gd", "Tb",
    "Dy", "Ho", "Er", "Tm", "Yb", "Lu", "Hf", "Ta", "W", "Re", "Os", "Ir", "Pt", "Au", "Hg", "Tl",
    "Pb", "Bi", "Po", "At", "Rn", "Fr", "Ra", "Ac", "Th", "Pa", "U", "Np", "Pu", "Am", "Cm", "Bk",
    "Cf", "Es", "Fm", "Md", "No", "Lr", "Rf", "Db", "Sg", "Bh", "Hs", "Mt", "Ds", "Rg", "Cn", "Nh",
    "Fl", "Mc", "Lv", "Ts", "Og",
];

/// True when `symbol` (any case) is an element's symbol, or `D` (deuterium).
pub fn is_element_symbol(symbol: &str) -> bool {
    symbol.eq_ignore_ascii_case("D")
        || ELEMENT_SYMBOLS
            .iter()
            .any(|e| e.eq_ignore_ascii_case(symbol))
}

/// The element for an atom whose element could not be guessed from its
/// name's alignment: the first letter of its name (after any leading
/// digits), or `X`.
pub(super) fn guess_from_name(name: &str) -> String {
    name.chars()
        .find(|c| c.is_ascii_alphabetic())
        .map_or_else(|| "X".to_string(), |c| c.to_ascii_uppercase().to_string())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    #[test]
    fn element_guessing_follows_pdb_alignment() {
        let g = |n: &str, r: &str| guess_pdb_element(n, r).unwrap();
        assert_eq!(g(" CA ", "ALA"), "C");
        assert_eq!(g("CA  ", "ALA"), "C"); // left-aligned, but a polymer residue
        assert_eq!(g("CA  ", "CA"), "Ca");
        assert_eq!(g("FE  ", "HEM"), "Fe");
        assert_eq!(g(" C1 ", "TOP"), "C");
        assert_eq!(g("CL1 ", "LIG"), "Cl");
        assert_eq!(g("CAB ", "LIG"), "C");
        assert_eq!(g("HG21", "LIG"), "H");
        assert_eq!(g("1HG2", "LIG"), "H");
        assert_eq!(g(" OH2", "TIP"), "O");
        assert!(guess_pdb_element(" 12 ", "LIG").is_none());
    }

    #[test]
    fn element_symbols_are_known_in_any_case() {
        for s in ["C", "cl", "FE", "Og", "d"] {
            assert!(is_element_symbol(s), "{s}");
        }
        for s in ["Qq", "", "X", "CA1"] {
            assert!(!is_element_symbol(s), "{s}");
        }
    }
}
