//! The `_struct_conn` rows: covalent connections (`covale*`, `disulf`)
//! between atoms of the asymmetric unit become bonds named by their atoms,
//! resolved once the atoms are read; other connections and bonds to
//! symmetry copies are not bonds.

use super::atom_site::label;
use super::row::{RowError, RowView};
use crate::model::pdb::Raw;
use crate::model::pdb::bonds::{AtomRef, NamedBond};
use crate::model::{BondOrder, Label};
use crate::text::excerpt;

/// Where the `_struct_conn` items the bonds need are, for each partner.
#[derive(Debug, Default, Clone)]
pub(super) struct ConnColumns {
    pub(super) kind: Option<usize>,
    pub(super) order: Option<usize>,
    pub(super) partners: [Partner; 2],
}

/// The columns naming one partner of a `_struct_conn` row.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct Partner {
    pub(super) chain: Option<usize>,
    pub(super) label_chain: Option<usize>,
    pub(super) seq: Option<usize>,
    pub(super) label_seq: Option<usize>,
    pub(super) insertion: Option<usize>,
    pub(super) name: Option<usize>,
    pub(super) residue: Option<usize>,
    pub(super) alt: Option<usize>,
    pub(super) symmetry: Option<usize>,
}

impl ConnColumns {
    pub(super) fn find(columns: &[String]) -> Self {
        let at = |name: &str| columns.iter().position(|c| c == name);
        let partner = |p: &str| Partner {
            chain: at(&format!("{p}_auth_asym_id")),
            label_chain: at(&format!("{p}_label_asym_id")),
            seq: at(&format!("{p}_auth_seq_id")),
            label_seq: at(&format!("{p}_label_seq_id")),
            insertion: at(&format!("pdbx_{p}_pdb_ins_code")),
            name: at(&format!("{p}_label_atom_id"))
                .or_else(|| at(&format!("pdbx_{p}_auth_atom_id"))),
            residue: at(&format!("{p}_label_comp_id")).or_else(|| at(&format!("{p}_auth_comp_id"))),
            alt: at(&format!("pdbx_{p}_label_alt_id")),
            symmetry: at(&format!("{p}_symmetry")),
        };
        Self {
            kind: at("conn_type_id"),
            order: at("pdbx_value_order"),
            partners: [partner("ptnr1"), partner("ptnr2")],
        }
    }
}

/// The `_struct_conn` reader's state.
#[derive(Debug, Default)]
pub(super) struct StructConn {
    pub(super) columns: ConnColumns,
    /// Rows skipped for a problem.
    pub(super) warnings: usize,
}

impl StructConn {
    /// Reads one row: a covalent bond (`covale*`, `disulf`) between atoms
    /// of this asymmetric unit becomes a pending bond; other connections
    /// (metal coordination, hydrogen bonds, mismatches) are not bonds.
    pub(super) fn row(&mut self, row: &RowView<'_>, raw: &mut Raw) -> Result<(), RowError> {
        let c = self.columns.clone();
        let Some(kind) = row.get(c.kind) else {
            return Ok(());
        };
        let kind = kind.to_ascii_lowercase();
        if !(kind.starts_with("covale") || kind == "disulf") {
            return Ok(());
        }
        let order = match row.get(c.order).map(str::to_ascii_lowercase).as_deref() {
            Some("sing") => BondOrder::Single,
            Some("doub") => BondOrder::Double,
            Some("trip") => BondOrder::Triple,
            Some("arom") => BondOrder::Aromatic,
            _ => BondOrder::Unspecified,
        };
        let mut ends = [None; 2];
        for (end, p) in ends.iter_mut().zip(c.partners) {
            if row.get(p.symmetry).is_some_and(|s| s != "1_555") {
                // A bond to a symmetry copy: not an atom of the file.
                return Ok(());
            }
            *end = Some(partner(row, &p)?);
        }
        if let [Some(a), Some(b)] = ends {
            raw.bonds.named.push(NamedBond { a, b, order });
        }
        Ok(())
    }
}

/// One partner of a `_struct_conn` row, named as atoms keep their names.
pub(super) fn partner(row: &RowView<'_>, p: &Partner) -> Result<AtomRef, RowError> {
    let chain_column = if row.get(p.chain).is_some() {
        p.chain
    } else {
        p.label_chain
    };
    let seq_column = if row.get(p.seq).is_some() {
        p.seq
    } else {
        p.label_seq
    };
    let name_column = p.name.unwrap_or(0);
    let Some(name) = row.get(p.name) else {
        return Err((
            name_column,
            "a bond partner without an atom name".to_string(),
        ));
    };
    let seq = match row.get(seq_column) {
        Some(v) => v.parse().map_err(|_| {
            (
                seq_column.unwrap_or(0),
                format!("the residue number {} is not a whole number", excerpt(v)),
            )
        })?,
        None => {
            return Err((
                name_column,
                "a bond partner without a residue number".to_string(),
            ));
        }
    };
    Ok(AtomRef {
        chain: match row.get(chain_column) {
            Some(v) => label(v, "the chain", chain_column.unwrap_or(0))?,
            None => Label::EMPTY,
        },
        seq,
        insertion: match row.get(p.insertion) {
            Some(v) => label(v, "the insertion code", p.insertion.unwrap_or(0))?,
            None => Label::EMPTY,
        },
        name: label(name, "the atom name", name_column)?,
        residue: match row.get(p.residue) {
            Some(v) => label(v, "the residue name", p.residue.unwrap_or(0))?,
            None => Label::EMPTY,
        },
        alt: match row.get(p.alt) {
            Some(v) if v.len() == 1 => v.as_bytes()[0],
            _ => 0,
        },
    })
}
