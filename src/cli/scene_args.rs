//! Options shared by the commands that load a receptor and a drug, and the
//! loading itself (files or the built-in scene).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, bail};
use bump::collide::{ColliderKind, ContactRule};
use bump::model::{
    self, Hydrogens, LigandSpec, LoadOptions, Molecule, RadiiSet, builtin, receptor_only,
    receptor_only_owned, split_complex_owned,
};
use bump::motion::Pose;
use bump::motion::range::check_position;
use bump::scene::{COINCIDENT_WITHIN, Scene};
use clap::Args;
use glam::DVec3;

/// Where the receptor and drug come from, and how they are judged.
#[derive(Debug, Args, Clone)]
pub struct SceneArgs {
    /// Receptor file (PDB, mmCIF, optionally .gz), or a complex to split with
    /// --ligand, or `builtin` (the default) for the thesis's triple ring and E.
    #[arg(default_value = "builtin")]
    pub receptor: String,
    /// Drug file (SDF, MOL2, PDB or mmCIF). Without it the drug is split from the
    /// receptor file with --ligand (default: auto).
    pub drug: Option<PathBuf>,
    /// Drug residue in the receptor file: RESNAME, RESNAME:CHAIN:SEQ or auto
    /// (SEQ may end in an insertion code, as in 52A).
    #[arg(long)]
    pub ligand: Option<String>,
    /// SDF record (MOL2 molecule, PDBQT model: a docking's pose) to read
    /// from the drug file (1-based).
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = parse_whole)]
    pub record: Option<usize>,
    /// Radius table: bondi (Bondi 1964, Mantina 2009; ionic radii for metals) or
    /// thesis (Turk 1989).
    #[arg(long, default_value = "bondi", value_parser = parse_radii)]
    pub radii: RadiiSet,
    /// Hydrogens: drop (default) or keep.
    #[arg(long, default_value = "drop", value_parser = parse_hydrogens)]
    pub hydrogens: Hydrogens,
    /// Overlap r_i + r_j − d (Å) at which a pair collides.
    #[arg(long, default_value_t = 0.6, allow_hyphen_values = true, value_parser = parse_f32)]
    pub overlap: f32,
    /// Extra overlap (Å) allowed between two N/O atoms (possible H-bond).
    #[arg(long, default_value_t = 0.4, allow_hyphen_values = true, value_parser = parse_f32)]
    pub hbond_allowance: f32,
    /// Collider: brute, grid or hashed.
    #[arg(long, default_value = "hashed", value_parser = parse_collider)]
    pub collider: ColliderKind,
    /// Most bytes a gzipped file may decompress to (e.g. 4GiB; default
    /// 2GiB, or the environment variable BUMP_MAX_DECOMPRESSED).
    #[arg(long, value_name = "SIZE", value_parser = parse_byte_size)]
    pub max_decompressed: Option<u64>,
}

pub fn parse_radii(s: &str) -> Result<RadiiSet, String> {
    RadiiSet::parse(s).ok_or_else(|| format!("unknown radii `{s}` (bondi or thesis)"))
}

pub fn parse_hydrogens(s: &str) -> Result<Hydrogens, String> {
    match s {
        "drop" => Ok(Hydrogens::Drop),
        "keep" => Ok(Hydrogens::Keep),
        _ => Err(format!("unknown hydrogens mode `{s}` (drop or keep)")),
    }
}

fn parse_collider(s: &str) -> Result<ColliderKind, String> {
    ColliderKind::parse(s).ok_or_else(|| format!("unknown collider `{s}` (brute, grid or hashed)"))
}

/// Parses a length in Å kept in single precision: a number that single
/// precision holds (not rounded to 0 or infinity on the way), or NaN, which
/// the option's own check refuses with its name.
pub fn parse_f32(s: &str) -> Result<f32, String> {
    let v: f64 = s.trim().parse().map_err(|e| format!("`{s}`: {e}"))?;
    let single = v as f32;
    if v.is_finite() && (single.is_infinite() || (single == 0.0 && v != 0.0)) {
        return Err(format!(
            "`{s}` is out of range (at most {:e} in size, and 0 or at least {:e})",
            f32::MAX,
            f32::MIN_POSITIVE
        ));
    }
    if v.is_infinite() {
        return Err(format!("`{s}`: not a finite number"));
    }
    Ok(single)
}

/// Parses a count or a 1-based number: a whole number, 0 or more (the
/// option's own check refuses 0 where it means nothing).
pub fn parse_whole(s: &str) -> Result<usize, String> {
    s.trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a whole number (0, 1, 2, ...)"))
}

/// Parses `X,Y,Z` into a vector of finite numbers.
pub fn parse_vec3(s: &str) -> Result<DVec3, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("`{s}`: {e} (expected X,Y,Z)"))?;
    match v.as_slice() {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(DVec3::new(*x, *y, *z)),
        _ => Err(format!("`{s}`: expected three finite numbers X,Y,Z")),
    }
}

/// A turn about an axis through the drug's centre: `AX,AY,AZ,DEG`.
#[derive(Debug, Clone, Copy)]
pub struct Turn {
    /// Axis (any non-zero length).
    pub axis: DVec3,
    /// Angle in degrees.
    pub degrees: f64,
}

impl Turn {
    /// No turn (what an absent `--turn` means).
    pub const NONE: Turn = Turn {
        axis: DVec3::Z,
        degrees: 0.0,
    };

    /// The angle in degrees within (−180, 180] that turns the same way:
    /// reduced in full precision, so that 1e20° is the turn it names (in
    /// radians first, its rounding error would be whole turns). A step's
    /// screw runs this way, the shorter way round.
    pub fn shorter_way(&self) -> f64 {
        let r = self.degrees.rem_euclid(360.0);
        if r > 180.0 { r - 360.0 } else { r }
    }

    /// [`Turn::shorter_way`] in radians.
    pub fn radians(&self) -> f64 {
        self.shorter_way().to_radians()
    }
}

/// Parses `AX,AY,AZ,DEG`.
pub fn parse_turn(s: &str) -> Result<Turn, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("`{s}`: {e} (expected AX,AY,AZ,DEG)"))?;
    match v.as_slice() {
        [x, y, z, d] if v.iter().all(|c| c.is_finite()) => {
            let axis = DVec3::new(*x, *y, *z);
            // Scaled to its largest component first, so that neither 1e300
            // nor 1e-300 over- or underflows on the way to a unit vector.
            let largest = axis.abs().max_element();
            if largest == 0.0 {
                return if *d == 0.0 {
                    Ok(Turn { axis, degrees: 0.0 })
                } else {
                    Err(format!("`{s}`: the turn axis is zero"))
                };
            }
            Ok(Turn {
                axis: (axis / largest).normalize(),
                degrees: *d,
            })
        }
        _ => Err(format!("`{s}`: expected four finite numbers AX,AY,AZ,DEG")),
    }
}

/// Refuses a drug pose (relative to the receptor) whose centre lies beyond
/// [`bump::motion::MAX_COORDINATE`] of the origin, naming the option that put it there:
/// the range check the session and the log reader use
/// ([`bump::motion::range`]).
pub fn within_range(scene: &Scene, option: &str, rel: &Pose) -> anyhow::Result<()> {
    let world = scene.world_from_relative(rel);
    match check_position(world.translation) {
        Ok(_) => Ok(()),
        Err(e) => bail!("{option}: the drug's centre would be {e}"),
    }
}

/// The drug's pose relative to the receptor after `--move` and `--turn`
/// (the turn about the drug's heavy-atom centroid), refused as
/// [`within_range`] refuses it under `--move`.
pub fn placed(scene: &Scene, translate: Option<DVec3>, turn: Option<Turn>) -> anyhow::Result<Pose> {
    let turn = turn.unwrap_or(Turn::NONE);
    let rel = scene.file_relative(DVec3::ZERO).moved(
        translate.unwrap_or(DVec3::ZERO),
        turn.axis,
        turn.radians(),
    );
    within_range(scene, "--move", &rel)?;
    Ok(rel)
}

/// Parses a size in bytes (`2GiB`, `500M`, `1000000`).
pub fn parse_byte_size(s: &str) -> Result<u64, String> {
    bump::text::parse_byte_size(s)
}

/// Refuses a `BUMP_MAX_DECOMPRESSED` that does not hold a size, which the
/// loader would pass over.
pub fn check_environment() -> anyhow::Result<()> {
    if let Ok(v) = std::env::var(model::DECOMPRESSED_LIMIT_VAR) {
        parse_byte_size(&v)
            .map_err(|e| anyhow::anyhow!("{}: {e}", model::DECOMPRESSED_LIMIT_VAR))?;
    }
    Ok(())
}

/// A loaded scene with where it came from.
pub struct LoadedScene {
    /// Receptor, drug, rule and collider.
    pub scene: Scene,
    /// Receptor source (file path or `builtin`).
    pub receptor_source: String,
    /// Drug source.
    pub drug_source: String,
    /// Time to build the collider, µs.
    pub build_us: f64,
}

impl SceneArgs {
    /// The contact rule these options describe.
    pub fn rule(&self) -> anyhow::Result<ContactRule> {
        Ok(ContactRule::new(self.overlap, self.hbond_allowance)?)
    }

    fn load_options(&self) -> LoadOptions {
        LoadOptions {
            radii: self.radii,
            hydrogens: self.hydrogens,
            sdf_record: None,
            decompressed_limit: self.max_decompressed,
        }
    }

    /// Loads the molecules (printing loader warnings to stderr) and builds
    /// the scene, with a plain collider ([`Scene::new_plain`]).
    pub fn load(&self) -> anyhow::Result<LoadedScene> {
        let rule = self.rule()?;
        if self.record.is_some() && self.drug.is_none() {
            bail!(
                "--record picks a record of an SDF, MOL2 or PDBQT drug file; no drug file was given"
            );
        }
        let (receptor, drug, drug_source) = if self.receptor == "builtin" {
            if self.drug.is_some() || self.ligand.is_some() {
                bail!("the built-in scene takes no drug file and no --ligand");
            }
            let (r, d) = builtin::scene(self.radii);
            (r, d, "builtin".to_string())
        } else {
            let path = PathBuf::from(&self.receptor);
            let loaded = model::load(&path, &self.load_options())?;
            warn(&loaded.warnings);
            match &self.drug {
                Some(drug_path) => {
                    if self.ligand.is_some() {
                        bail!(
                            "--ligand splits the receptor file; it cannot be used with a drug file"
                        );
                    }
                    // Taken, not copied: a large receptor is held once.
                    let receptor = receptor_only_owned(loaded.structure)?;
                    let mut opts = self.load_options();
                    opts.sdf_record = self.record;
                    let d = model::load(drug_path, &opts)?;
                    warn(&d.warnings);
                    let mut drug = receptor_only(&d.structure)?;
                    drug.name = d.structure.name.clone();
                    (receptor, drug, drug_path.display().to_string())
                }
                None => {
                    let text = self.ligand.as_deref().unwrap_or("auto");
                    let spec = LigandSpec::parse(text)
                        .map_err(|e| anyhow::anyhow!("--ligand {text}: {e}"))?;
                    let (r, d) = split_complex_owned(loaded.structure, &spec)?;
                    let name = d.name.clone();
                    (r, d, format!("{} ({name})", self.receptor))
                }
            }
        };
        check_usable(&receptor, &drug)?;
        let t0 = Instant::now();
        // The commands ask a few queries and exit: no clearance map.
        let scene = Scene::new_plain(receptor, drug, rule, self.collider);
        let build_us = t0.elapsed().as_secs_f64() * 1e6;
        warn_coincident(&scene, self.drug.is_some());
        Ok(LoadedScene {
            scene,
            receptor_source: self.receptor.clone(),
            drug_source,
            build_us,
        })
    }
}

fn check_usable(receptor: &Molecule, drug: &Molecule) -> anyhow::Result<()> {
    if receptor.is_empty() {
        bail!("{}: the receptor has no atoms", receptor.name);
    }
    if drug.is_empty() {
        bail!("{}: the drug has no atoms", drug.name);
    }
    Ok(())
}

/// Warns when drug atoms lie on receptor atoms at the file pose, naming one
/// such pair and, when the receptor atom belongs to a hetero group and the
/// drug came as its own file, the `--ligand` that would split it instead.
fn warn_coincident(scene: &Scene, drug_file: bool) {
    let on_top = scene.coincident_atoms(&scene.file_relative(DVec3::ZERO));
    let Some(first) = on_top.first() else {
        return;
    };
    let (Some(r), Some(d)) = (
        scene.receptor.atoms.get(first.receptor as usize),
        scene.drug.atoms.get(first.drug as usize),
    ) else {
        return;
    };
    let hint = if drug_file && r.hetero {
        format!(
            "; the receptor file seems to hold the drug as well: give only that file and pick the drug with --ligand {}",
            r.residue
        )
    } else {
        "; they collide whatever the motion".to_string()
    };
    eprintln!(
        "bump: warning: {} of {} drug atoms lie within {COINCIDENT_WITHIN} Å of a receptor atom at the file pose (e.g. drug {} {} on receptor {} {}/{}{} {}, {:.2} Å apart){hint}",
        on_top.len(),
        scene.drug.len(),
        d.residue,
        d.name,
        r.residue,
        r.chain,
        r.seq,
        r.insertion,
        r.name,
        first.distance
    );
}

fn warn(warnings: &[String]) {
    for w in warnings {
        eprintln!("bump: warning: {w}");
    }
}

/// Runs `f` `n` times and returns the median wall time in µs with the last result.
pub fn timed<T>(n: usize, mut f: impl FnMut() -> T) -> anyhow::Result<(T, f64)> {
    let mut times = Vec::with_capacity(n.max(1));
    let mut out = None;
    for _ in 0..n.max(1) {
        let t0 = Instant::now();
        out = Some(f());
        times.push(t0.elapsed().as_secs_f64() * 1e6);
    }
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    out.map(|o| (o, median)).context("no run")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turns_run_the_shorter_way_in_full_precision() {
        for (asked, runs) in [
            (0.0, 0.0),
            (90.0, 90.0),
            (180.0, 180.0),
            (-180.0, 180.0),
            (270.0, -90.0),
            (-270.0, 90.0),
            (360.0, 0.0),
            (725.0, 5.0),
            (-30.0, -30.0),
            // Exact: 1e20 = 360·277777777777777777 + 280.
            (1e20, -80.0),
            (3.6e19, 0.0),
        ] {
            let turn = Turn {
                axis: DVec3::X,
                degrees: asked,
            };
            assert_eq!(turn.shorter_way(), runs, "{asked}");
        }
        let huge = Turn {
            axis: DVec3::X,
            degrees: 1e300,
        };
        assert!(huge.shorter_way().abs() <= 180.0);
        assert!(huge.radians().is_finite());
    }
}
