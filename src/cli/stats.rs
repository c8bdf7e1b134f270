//! `bump stats`: Turk's Table 1 (atoms per grid cell) for real files.

use std::path::PathBuf;

use bump::collide::stats::{DensityRow, THESIS_HASH_CELLS, density, thesis_cell_size};
use bump::model::{self, Hydrogens, LoadOptions, RadiiSet, receptor_only};
use clap::Args;
use serde::Serialize;

use super::scene_args::{parse_hydrogens, parse_radii};

/// Arguments of `bump stats`.
#[derive(Debug, Args)]
pub struct StatsArgs {
    /// Structure files (PDB, mmCIF, SDF; .gz allowed). Waters are left out.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Cell edge in Å (default: the diameter of the largest atom, as the thesis).
    #[arg(long)]
    cell: Option<f32>,
    /// Buckets of the hashed table.
    #[arg(long, default_value_t = THESIS_HASH_CELLS)]
    hash_cells: usize,
    /// Radius table: thesis (Turk 1989, the default here, as Table 1) or
    /// bondi (Bondi 1964, Mantina 2009).
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

/// Runs `bump stats`.
pub fn run(args: &StatsArgs) -> anyhow::Result<()> {
    let radii = args.radii;
    if !args.hash_cells.is_power_of_two() {
        anyhow::bail!(
            "--hash-cells must be a power of two, got {}",
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
    };
    let mut rows = Vec::new();
    for f in &args.files {
        let loaded = model::load(f, &opts)?;
        for w in &loaded.warnings {
            eprintln!("bump: warning: {w}");
        }
        let mol = receptor_only(&loaded.structure)?;
        let cell = args.cell.unwrap_or_else(|| thesis_cell_size(&mol));
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
