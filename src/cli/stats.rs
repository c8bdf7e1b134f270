//! `bump stats`: Turk's Table 1 (atoms per grid cell) for real files.

use std::path::PathBuf;

use bump::collide::stats::{DensityRow, THESIS_HASH_CELLS, density, thesis_cell_size};
use bump::model::{self, Hydrogens, LoadOptions, RadiiSet, receptor_only};
use clap::Args;
use serde::Serialize;

use super::scene_args::{parse_f32, parse_hydrogens, parse_radii, parse_whole};

/// Arguments of `bump stats`.
#[derive(Debug, Args)]
pub struct StatsArgs {
    /// Structure files (PDB, mmCIF, SDF, MOL2; .gz allowed). Waters are left out.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Cell edge in Å (default: the diameter of the largest atom, as the thesis).
    #[arg(long, value_parser = parse_f32, allow_negative_numbers = true)]
    cell: Option<f32>,
    /// Buckets of the hashed table.
    #[arg(
        long,
        default_value_t = THESIS_HASH_CELLS,
        allow_negative_numbers = true,
        value_parser = parse_whole
    )]
    hash_cells: usize,
    /// Radius table: thesis (Turk 1989, the default here, as Table 1) or
    /// bondi (Bondi 1964, Mantina 2009); metals take ionic radii in both.
    #[arg(long, default_value = "thesis", value_parser = parse_radii)]
    radii: RadiiSet,
    /// Hydrogens: drop (default) or keep, as in check and touch.
    #[arg(long, default_value = "drop", value_parser = parse_hydrogens)]
    hydrogens: Hydrogens,
    /// The older spelling of `--hydrogens keep`.
    #[arg(long, hide = true, conflicts_with = "hydrogens")]
    keep_hydrogens: bool,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct FileRow {
    file: String,
    #[serde(flatten)]
    row: DensityRow,
}

/// Largest hashed table `--hash-cells` may ask for (a 256 MiB count).
const MAX_HASH_CELLS: usize = 1 << 26;

/// Most sphere–cell tests one file may cost: about 10 s. The thesis's cell
/// (one atom diameter) costs at most 27 per atom; a cell of 0.5 Å on the
/// 272k-atom assembly costs some 25 s and 2 GB.
const MAX_CELL_VISITS: f64 = 5e7;

/// Sphere–cell tests that counting `mol` with cells of `cell` Å makes.
fn cell_visits(mol: &model::Molecule, cell: f32) -> f64 {
    mol.atoms
        .iter()
        .map(|a| (f64::from(2.0 * a.radius / cell).ceil() + 1.0).powi(3))
        .sum()
}

/// Runs `bump stats`.
pub fn run(args: &StatsArgs) -> anyhow::Result<()> {
    let radii = args.radii;
    if !args.hash_cells.is_power_of_two() || args.hash_cells > MAX_HASH_CELLS {
        anyhow::bail!(
            "--hash-cells must be a power of two up to {MAX_HASH_CELLS}, got {}",
            args.hash_cells
        );
    }
    if let Some(c) = args.cell
        && !(c.is_finite() && c > 0.1)
    {
        anyhow::bail!("--cell must be a cell edge above 0.1 Å, got {c}");
    }
    let opts = LoadOptions {
        radii,
        hydrogens: if args.keep_hydrogens {
            Hydrogens::Keep
        } else {
            args.hydrogens
        },
        sdf_record: None,
        decompressed_limit: None,
    };
    let mut rows = Vec::new();
    for f in &args.files {
        let loaded = model::load(f, &opts)?;
        for w in &loaded.warnings {
            eprintln!("bump: warning: {w}");
        }
        let mol = receptor_only(&loaded.structure)?;
        let cell = args.cell.unwrap_or_else(|| thesis_cell_size(&mol));
        let visits = cell_visits(&mol, cell);
        if visits > MAX_CELL_VISITS {
            anyhow::bail!(
                "{}: with {cell} Å cells each atom's sphere would be tested against {:.0} cells on average ({visits:.2e} tests in all, at most {MAX_CELL_VISITS:e}); choose a larger --cell",
                f.display(),
                visits / mol.len().max(1) as f64
            );
        }
        rows.push(FileRow {
            file: f.display().to_string(),
            row: density(&mol, cell, args.hash_cells),
        });
    }
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    outln!(
        "average atoms per non-empty cell ({} radii; sphere overlap counts an atom in every cell it touches)",
        radii.name()
    );
    outln!(
        "{:<28} {:>7} {:>6} | {:>14} {:>14} | {:>14} {:>14}",
        "file",
        "atoms",
        "cell Å",
        "hashed overlap",
        "grid overlap",
        "hashed centre",
        "grid centre"
    );
    for r in &rows {
        let name = std::path::Path::new(&r.file)
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| r.file.clone());
        outln!(
            "{:<28} {:>7} {:>6.2} | {:>14.2} {:>14.2} | {:>14.2} {:>14.2}",
            name,
            r.row.atoms,
            r.row.cell_size,
            r.row.hashed_overlap.atoms_per_cell,
            r.row.grid_overlap.atoms_per_cell,
            r.row.hashed_centre.atoms_per_cell,
            r.row.grid_centre.atoms_per_cell
        );
    }
    Ok(())
}
