//! The complexes of the Vina reference (`tests/reference/vina/values.json`,
//! made by `tests/reference/vina/make_reference.py`) and how bump loads
//! them as the reference prepared them: what the agreement, typing and
//! settle tests and the report share.

use std::path::Path;

use bump::model::{self, LigandSpec, LoadOptions, Molecule};

/// The shared complexes of the Vina reference: id, receptor file, ligand
/// residue in the receptor file (empty: none) and ligand SDF.
pub const COMPLEXES: &[(&str, &str, &str, Option<&str>)] = &[
    ("1hvr_XK2", "1hvr.pdb", "XK2:A", None),
    ("1rx1_NAP", "1rx1.pdb", "NAP:A", None),
    (
        "1s3v_TQD",
        "1s3v_protein.pdb",
        "",
        Some("1s3v_ligand_tqd.sdf"),
    ),
    ("1u72_MTX", "1u72.pdb", "MTX:A", None),
    ("3nzd_D2Q", "3nzd.cif", "D2Q:A", None),
    ("3ptb_BEN", "3ptb.pdb", "BEN", Some("benzamidine_3ptb.sdf")),
    ("4dfr_MTX", "4dfr.pdb", "MTX:A", None),
    (
        "6xg5_TOP",
        "6xg5_tmp_prepared.pdb",
        "TOP",
        Some("trimethoprim_top_6xg5pose.sdf"),
    ),
];

/// A complex loaded by bump as the reference prepared it: the receptor is
/// the file's polymer (`ATOM` records: every hetero group, waters, ions and
/// cofactors included, left out, as `make_reference.py` does), the drug the
/// SDF or the named residue.
pub fn load_complex(dir: &Path, id: &str) -> (Molecule, Molecule) {
    let &(_, file, residue, sdf) = COMPLEXES.iter().find(|c| c.0 == id).expect("a complex");
    let s = model::load(&dir.join(file), &LoadOptions::default())
        .expect(file)
        .structure;
    let polymer: Vec<usize> = (0..s.atoms.len()).filter(|&i| !s.atoms[i].hetero).collect();
    let receptor = model::select::molecule_from(&s, &polymer, format!("{file} polymer"));
    let drug = match sdf {
        Some(f) => {
            let d = model::load(&dir.join(f), &LoadOptions::default()).expect(f);
            model::receptor_only(&d.structure).expect(f)
        }
        None => {
            let spec = LigandSpec::parse(residue).expect("spec");
            model::split_complex(&s, &spec).expect(id).1
        }
    };
    (receptor, drug)
}
