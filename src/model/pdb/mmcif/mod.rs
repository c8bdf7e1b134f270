//! The mmCIF side of loading: a CIF tokenizer that reads the first data
//! block line by line and keeps two categories, `_atom_site` (the atoms)
//! and `_struct_conn` (the bonds between residues), as loops or as single
//! items; every other category is read past without being kept.
//!
//! Tokens follow CIF 1.1: whitespace-separated values, a value opening
//! with a quote running to the same quote followed by a blank or the line's
//! end, `#` outside quotes opening a comment, a line opening with `;` a text
//! field that runs to the next such line, and the reserved words `data_`,
//! `loop_`, `save_`, `global_`, `stop_`. Tags are matched whatever their
//! case. `?` and `.` (unquoted) mean a value unknown or not applicable.
//!
//! An `_atom_site` row gives the atom: `group_PDB` (ATOM or HETATM),
//! `id`, `type_symbol`, `label_atom_id`, `label_alt_id`, `label_comp_id`,
//! the author's chain and residue number where given (`auth_asym_id`,
//! `auth_seq_id`, else the label ones), `pdbx_PDB_ins_code`, `Cartn_x/y/z`,
//! `occupancy` and `pdbx_PDB_model_num` (rows of models other than the
//! first row's are passed over). Every problem names the line and column
//! of the value: a row with too few or too many values (where rows are
//! one per line, as every mmCIF writer puts them), a coordinate that is not
//! a number, a missing column the atoms need.

mod atom_site;
mod reader;
mod row;
mod struct_conn;
mod tokens;

use std::io::Read;

use super::{Raw, ascii_line, line_error};
use crate::model::LoadError;
use crate::text::LineReader;
use reader::CifReader;
use tokens::Token;

/// Longest text field kept, bytes; a longer one is read past, and refused
/// only where a kept category wants its value.
const MAX_TEXT_FIELD: usize = 4096;

/// At most this many warnings about `struct_conn` rows are given one by one.
const MAX_BOND_WARNINGS: usize = 5;

/// Reads the atoms of mmCIF text's first model (of its first data block)
/// and its `struct_conn` bonds.
///
/// # Errors
/// [`LoadError::Parse`] naming the line and column of what is wrong; a line
/// reader's failure ([`super::line_error`]).
pub(super) fn read_mmcif<R: Read>(
    lines: &mut LineReader<R>,
    label: &str,
) -> Result<Raw, LoadError> {
    let mut reader = CifReader::new(label);
    let mut scratch = String::new();
    let mut tokens: Vec<Token> = Vec::new();
    while let Some((number, bytes)) = lines.next_line().map_err(|e| line_error(label, e))? {
        let line = ascii_line(bytes, &mut scratch);
        if reader.line(number, line, &mut tokens)? {
            break;
        }
    }
    reader.finish(lines.line_number())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use glam::DVec3;

    use super::*;
    use crate::model::BondOrder;

    fn read(text: &str) -> Result<Raw, LoadError> {
        let mut lines = LineReader::new(text.as_bytes(), 1 << 20);
        read_mmcif(&mut lines, "t.cif")
    }

    #[test]
    fn other_categories_text_fields_and_later_blocks_are_passed_over() {
        let text = "data_X\n_cell.a 1\n_struct.title\n;\nloop_\n_atom_site.id\n;\nloop_\n_atom_site.id\n\
                    _atom_site.label_atom_id\n_atom_site.label_comp_id\n_atom_site.Cartn_x\n\
                    _atom_site.Cartn_y\n_atom_site.Cartn_z\n1 N ALA 1 2 3\n2 CA ALA 4 5 6\n#\n\
                    data_Y\nloop_\n_atom_site.id\n";
        let raw = read(text).unwrap();
        assert_eq!(raw.atoms.len(), 2);
        assert_eq!(raw.atoms[1].name, "CA");
        assert_eq!(raw.atoms[1].element, "C");
        assert_eq!(raw.positions[1], DVec3::new(4.0, 5.0, 6.0));
    }

    #[test]
    fn a_single_atom_may_be_written_as_items() {
        let text = "data_X\n_atom_site.id 7\n_atom_site.type_symbol Fe\n_atom_site.label_atom_id FE\n\
                    _atom_site.label_comp_id HEM\n_atom_site.Cartn_x 1\n_atom_site.Cartn_y 2\n\
                    _atom_site.Cartn_z 3\n_other.x y\n";
        let raw = read(text).unwrap();
        assert_eq!(raw.atoms.len(), 1);
        assert_eq!(
            (raw.atoms[0].serial, raw.atoms[0].element.as_str()),
            (7, "Fe")
        );
    }

    #[test]
    fn rows_may_run_over_lines_where_the_first_did() {
        let text = "data_X\nloop_\n_atom_site.id\n_atom_site.label_atom_id\n_atom_site.label_comp_id\n\
                    _atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n1 N ALA\n1 2 3\n2 CA\nALA 4 5 6\n";
        assert_eq!(read(text).unwrap().atoms.len(), 2);
        let cut = text.replace("ALA 4 5 6\n", "ALA 4 5\n");
        let e = read(&cut).unwrap_err().to_string();
        assert!(
            e.contains("t.cif:11:1: the _atom_site loop ends inside a row: 5 of its 6"),
            "{e}"
        );
    }

    #[test]
    fn an_unclosed_text_field_is_named() {
        let e = read("data_X\n_a.b\n;\ntext\n").unwrap_err().to_string();
        assert!(e.starts_with("t.cif:3:1: a text field"), "{e}");
    }

    #[test]
    fn covalent_struct_conn_rows_become_bonds() {
        let text = "data_X\nloop_\n_struct_conn.id\n_struct_conn.conn_type_id\n\
                    _struct_conn.ptnr1_auth_asym_id\n_struct_conn.ptnr1_auth_seq_id\n\
                    _struct_conn.ptnr1_label_atom_id\n_struct_conn.ptnr1_label_comp_id\n\
                    _struct_conn.ptnr1_symmetry\n_struct_conn.ptnr2_auth_asym_id\n\
                    _struct_conn.ptnr2_auth_seq_id\n_struct_conn.ptnr2_label_atom_id\n\
                    _struct_conn.ptnr2_label_comp_id\n_struct_conn.ptnr2_symmetry\n\
                    _struct_conn.pdbx_value_order\n\
                    disulf1 disulf A 3 SG CYS 1_555 A 40 SG CYS 1_555 ?\n\
                    covale1 covale A 5 C1 NAG 1_555 A 6 O4 NAG 1_555 sing\n\
                    metalc1 metalc A 7 ZN ZN 1_555 A 3 SG CYS 1_555 ?\n\
                    disulf2 disulf A 3 SG CYS 1_555 A 40 SG CYS 2_555 ?\n";
        let raw = read(text).unwrap();
        let named = &raw.bonds.named;
        assert_eq!(named.len(), 2);
        assert_eq!((named[0].a.seq, named[0].b.seq), (3, 40));
        assert_eq!(named[0].order, BondOrder::Unspecified);
        assert_eq!(named[1].order, BondOrder::Single);
        assert_eq!(named[1].b.name, "O4");
    }
}
