//! The `_atom_site` rows: where the items the atoms need are in a loop,
//! and one row read into an atom (element, names, residue, chain, number,
//! insertion code, position, occupancy, formal charge), passing over rows of models other
//! than the first row's.

use glam::DVec3;

use super::row::{RowError, RowView};
use crate::model::label::{AtomName, ChainId, ElementSymbol, InsertionCode, ResidueName};
use crate::model::pdb::guess::guess_from_name;
use crate::model::pdb::{Raw, check_position, element_label};
use crate::model::{AtomInfo, Label};
use crate::text::excerpt;

/// Where the `_atom_site` items the atoms need are.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct AtomColumns {
    pub(super) group: Option<usize>,
    pub(super) id: Option<usize>,
    pub(super) symbol: Option<usize>,
    pub(super) name: usize,
    pub(super) alt: Option<usize>,
    pub(super) residue: usize,
    pub(super) chain: Option<usize>,
    pub(super) label_chain: Option<usize>,
    pub(super) seq: Option<usize>,
    pub(super) label_seq: Option<usize>,
    pub(super) insertion: Option<usize>,
    pub(super) xyz: [usize; 3],
    pub(super) occupancy: Option<usize>,
    pub(super) charge: Option<usize>,
    pub(super) model: Option<usize>,
}

impl AtomColumns {
    /// The layout of a loop with `columns` (lower case); the error names a
    /// column the atoms need that it lacks.
    pub(super) fn find(columns: &[String]) -> Result<Self, String> {
        let at = |name: &str| columns.iter().position(|c| c == name);
        let either = |a: &str, b: &str| at(a).or_else(|| at(b));
        let need = |c: Option<usize>, name: &str| {
            c.ok_or_else(|| format!("the _atom_site loop has no {name} column"))
        };
        Ok(Self {
            group: at("group_pdb"),
            id: at("id"),
            symbol: at("type_symbol"),
            name: need(either("label_atom_id", "auth_atom_id"), "label_atom_id")?,
            alt: at("label_alt_id"),
            residue: need(either("label_comp_id", "auth_comp_id"), "label_comp_id")?,
            chain: at("auth_asym_id"),
            label_chain: at("label_asym_id"),
            seq: at("auth_seq_id"),
            label_seq: at("label_seq_id"),
            insertion: at("pdbx_pdb_ins_code"),
            xyz: [
                need(at("cartn_x"), "Cartn_x")?,
                need(at("cartn_y"), "Cartn_y")?,
                need(at("cartn_z"), "Cartn_z")?,
            ],
            occupancy: at("occupancy"),
            charge: at("pdbx_formal_charge"),
            model: at("pdbx_pdb_model_num"),
        })
    }
}

/// The `_atom_site` reader's state.
#[derive(Debug, Default)]
pub(super) struct AtomSite {
    pub(super) columns: AtomColumns,
    /// The first row's model number (as written).
    pub(super) model: Option<String>,
    /// Rows read.
    pub(super) rows: usize,
    /// Residues seen without a number: they are numbered in order.
    pub(super) unnumbered: i64,
    /// The previous row's (chain, residue) when it had no number.
    pub(super) previous: Option<(ChainId, ResidueName)>,
}

/// A label read from a value, refused when longer than the label holds.
pub(super) fn label<const N: usize>(
    value: &str,
    what: &str,
    cell: usize,
) -> Result<Label<N>, RowError> {
    if let Some(c) = value.chars().find(char::is_ascii_control) {
        return Err((
            cell,
            format!(
                "control character U+{:04X} in {what} {} (names must be printable)",
                u32::from(c),
                excerpt(value)
            ),
        ));
    }
    Label::new(value).ok_or_else(|| {
        (
            cell,
            format!(
                "{what} {} is longer than the {N} characters bump keeps",
                excerpt(value)
            ),
        )
    })
}

impl AtomSite {
    /// Reads one row into `raw`.
    pub(super) fn row(&mut self, row: &RowView<'_>, raw: &mut Raw) -> Result<(), RowError> {
        let c = self.columns;
        self.rows += 1;
        if let Some(m) = c.model {
            let here = row.raw(m);
            match &self.model {
                None => self.model = Some(here.to_string()),
                Some(first) if first != here => return Ok(()),
                Some(_) => {}
            }
        }
        let hetero = match row.get(c.group) {
            None => false,
            Some(g) if g.eq_ignore_ascii_case("ATOM") => false,
            Some(g) if g.eq_ignore_ascii_case("HETATM") => true,
            Some(g) => {
                return Err((
                    c.group.unwrap_or(0),
                    format!("group_PDB is {}, not ATOM or HETATM", excerpt(g)),
                ));
            }
        };
        let serial = match (c.id, row.get(c.id)) {
            (Some(i), Some(v)) => v.parse::<i64>().map_err(|_| {
                (
                    i,
                    format!("the atom id {} is not a whole number", excerpt(v)),
                )
            })?,
            (Some(i), None) => return Err((i, "the atom id is missing".to_string())),
            (None, _) => i64::try_from(self.rows).unwrap_or(i64::MAX),
        };
        let name: AtomName = match row.get(Some(c.name)) {
            Some(v) => label(v, "the atom name", c.name)?,
            None => return Err((c.name, format!("atom {serial} has no name"))),
        };
        let residue: ResidueName = match row.get(Some(c.residue)) {
            Some(v) => label(v, "the residue name", c.residue)?,
            None => return Err((c.residue, format!("atom {serial} has no residue name"))),
        };
        let element: ElementSymbol = match c.symbol {
            None => Label::truncated(&guess_from_name(&name)),
            Some(s) => match row.get(Some(s)) {
                Some(v) => {
                    // Refuses control characters and overlong symbols.
                    label::<{ ElementSymbol::CAPACITY }>(v, "the element symbol", s)?;
                    element_label(v).unwrap_or_default()
                }
                None => {
                    return Err((
                        s,
                        format!("atom {serial} ({name}) has no element (type_symbol is ? or .)"),
                    ));
                }
            },
        };
        let chain_column = if row.get(c.chain).is_some() {
            c.chain
        } else {
            c.label_chain
        };
        let chain: ChainId = match row.get(chain_column) {
            Some(v) => label(v, "the chain", chain_column.unwrap_or(0))?,
            None => Label::EMPTY,
        };
        let seq_column = if row.get(c.seq).is_some() {
            c.seq
        } else {
            c.label_seq
        };
        let seq = match row.get(seq_column) {
            Some(v) => v.parse::<i64>().map_err(|_| {
                (
                    seq_column.unwrap_or(0),
                    format!("the residue number {} is not a whole number", excerpt(v)),
                )
            })?,
            None => {
                if self.previous != Some((chain, residue)) {
                    self.unnumbered += 1;
                    self.previous = Some((chain, residue));
                }
                self.unnumbered
            }
        };
        if seq_column.is_some() && row.get(seq_column).is_some() {
            self.previous = None;
        }
        let insertion: InsertionCode = match row.get(c.insertion) {
            Some(v) => label(v, "the insertion code", c.insertion.unwrap_or(0))?,
            None => Label::EMPTY,
        };
        let alt = match row.get(c.alt) {
            None => 0,
            Some(v) if v.len() == 1 => v.as_bytes()[0],
            Some(v) => {
                return Err((
                    c.alt.unwrap_or(0),
                    format!("the alternate location {} is not one character", excerpt(v)),
                ));
            }
        };
        let mut xyz = [0.0; 3];
        for ((slot, &col), axis) in xyz
            .iter_mut()
            .zip(&c.xyz)
            .zip(["Cartn_x", "Cartn_y", "Cartn_z"])
        {
            let v = row.raw(col);
            *slot = v.parse::<f64>().map_err(|_| {
                (
                    col,
                    format!("{axis} of atom {serial} is not a number: {}", excerpt(v)),
                )
            })?;
        }
        let position =
            check_position(DVec3::from_array(xyz), serial, &name).map_err(|r| (c.xyz[0], r))?;
        let occupancy = match row.get(c.occupancy) {
            None => 1.0,
            Some(v) => v.parse::<f64>().map_err(|_| {
                (
                    c.occupancy.unwrap_or(0),
                    format!(
                        "the occupancy of atom {serial} is not a number: {}",
                        excerpt(v)
                    ),
                )
            })? as f32,
        };
        // As PDB's columns 79-80 would hold it: a whole number of a few
        // charges.
        let charge = match row.get(c.charge) {
            None => 0,
            Some(v) => v
                .parse::<i8>()
                .ok()
                .filter(|q| (-9..=9).contains(q))
                .ok_or_else(|| {
                    (
                        c.charge.unwrap_or(0),
                        format!(
                            "the formal charge of atom {serial} is not a whole number from -9 to 9: {}",
                            excerpt(v)
                        ),
                    )
                })?,
        };
        raw.push(
            AtomInfo {
                serial,
                name,
                residue,
                seq,
                insertion,
                chain,
                element,
                radius: 0.0,
                polar: false,
                hetero,
            },
            position,
            occupancy,
            alt,
            charge,
        );
        Ok(())
    }
}
