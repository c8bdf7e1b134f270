//! `bump steer`: the fixed steering controller ([`bump::session::steer`]):
//! from a clear start along a direction (a vector, or `K/N`: the report's
//! run K of N, with its seed), towards the file pose (and, with
//! `--flexible`, the file torsions), through a collision response; reports
//! whether the drug got there, and with `--settle` what the session's
//! settle made of the end. `--escape` runs it the other way, from the file
//! pose out to the start: does the pocket let the drug out?

use bump::collide::Response;
use bump::rng::sphere_direction;
use bump::session::Settings;
use bump::session::steer::{MAX_FRAMES, REACHED_RMSD, SteerOptions, steer};
use clap::Args;
use glam::DVec3;

use super::scene_args::{SceneArgs, parse_vec3};

/// Arguments of `bump steer`.
#[derive(Debug, Args)]
pub struct SteerArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Direction of the start from the file pose: X,Y,Z (any length), or
    /// K/N, the K-th (from 0) of N directions spread evenly over the
    /// sphere, as the benchmark report numbers its runs.
    #[arg(long, value_name = "X,Y,Z|K/N", value_parser = parse_direction, allow_hyphen_values = true)]
    direction: Direction,
    /// Collision response: stop, touch, slide, soft or pass.
    #[arg(long, default_value = "soft", value_parser = parse_response)]
    response: Response,
    /// How far beyond the contact rule `soft` lets a pair press, Å.
    #[arg(long, default_value_t = bump::collide::soft::DEFAULT_LIMIT)]
    soft_limit: f64,
    /// Turn the drug's rotatable bonds too: each starts 60° off its file
    /// angle (either way, seeded) and is steered back 5° a frame at most.
    #[arg(long)]
    flexible: bool,
    /// Settle after the run (the session's settle, as key G).
    #[arg(long)]
    settle: bool,
    /// Seed of the start's torsion turns (with --flexible); 1 by default,
    /// K+1 with --direction K/N, as the benchmark report seeds its run K.
    #[arg(long)]
    seed: Option<u64>,
    /// Run the other way: from the file pose (and file torsions) out to
    /// the start; reached then means within 2 Å RMSD of the start.
    #[arg(long)]
    escape: bool,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// Where the start lies from the file pose.
#[derive(Debug, Clone, Copy)]
enum Direction {
    /// Along this vector.
    Along(DVec3),
    /// Along the `k`-th of `n` Fibonacci directions.
    Of { k: usize, n: usize },
}

impl Direction {
    /// The vector, and the seed the report gives this run.
    fn resolve(self) -> (DVec3, u64) {
        match self {
            Self::Along(v) => (v, 1),
            Self::Of { k, n } => (sphere_direction(k, n), k as u64 + 1),
        }
    }
}

/// The most directions `K/N` may spread over the sphere.
const MAX_DIRECTIONS: usize = 1_000_000;

fn parse_direction(s: &str) -> Result<Direction, String> {
    let Some((k, n)) = s.split_once('/') else {
        return parse_vec3(s).map(Direction::Along);
    };
    let number = |t: &str| {
        t.trim()
            .parse::<usize>()
            .map_err(|e| format!("`{s}`: {e} (expected K/N, the K-th of N directions)"))
    };
    let (k, n) = (number(k)?, number(n)?);
    if !(1..=MAX_DIRECTIONS).contains(&n) || k >= n {
        return Err(format!(
            "`{s}`: expected K/N with 0 ≤ K < N ≤ {MAX_DIRECTIONS}"
        ));
    }
    Ok(Direction::Of { k, n })
}

fn parse_response(s: &str) -> Result<Response, String> {
    Response::parse(s)
        .ok_or_else(|| format!("unknown response `{s}` (stop, touch, slide, soft or pass)"))
}

/// Runs `bump steer`.
pub fn run(args: &SteerArgs) -> anyhow::Result<()> {
    if !(0.0..=bump::collide::soft::MAX_LIMIT).contains(&args.soft_limit) {
        anyhow::bail!(
            "--soft-limit must be between 0 and {} Å, got {}",
            bump::collide::soft::MAX_LIMIT,
            args.soft_limit
        );
    }
    let (direction, seed) = args.direction.resolve();
    let loaded = args.scene.load()?;
    let settings = Settings {
        rule: loaded.scene.rule,
        collider: args.scene.collider,
        soft_limit: args.soft_limit,
        ..Settings::default()
    };
    let r = steer(
        loaded.scene.receptor,
        loaded.scene.drug,
        settings,
        direction,
        &SteerOptions {
            response: args.response,
            flexible: args.flexible,
            settle: args.settle,
            seed: args.seed.unwrap_or(seed),
            escape: args.escape,
        },
    )?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&r)?);
        return Ok(());
    }
    let [x, y, z] = r.direction;
    outln!(
        "{} {:.1} Å along ({x:.3}, {y:.3}, {z:.3}), response {}{}",
        if r.escape {
            "from the file pose out to the start"
        } else {
            "start"
        },
        r.start_distance,
        r.response.name(),
        if r.flexible {
            format!(
                ", flexible ({} rotatable bonds, {} of them turned 60° at the start)",
                r.torsions,
                r.start_torsions.iter().filter(|t| **t != 0.0).count()
            )
        } else {
            String::new()
        }
    );
    outln!(
        "{} (symmetry-corrected heavy-atom RMSD ≤ {REACHED_RMSD} Å to the {}{}); best {:.2} Å, final {:.2} Å after {} of at most {MAX_FRAMES} frames",
        if r.reached { "reached" } else { "not reached" },
        if r.escape { "start" } else { "file pose" },
        r.reached_frame
            .map(|f| format!(" at frame {f}"))
            .unwrap_or_default(),
        r.best_rmsd,
        r.final_rmsd,
        r.frames
    );
    outln!(
        "ends {:.2} Å from the {}'s centre, turned {:.1}° from its orientation{}",
        r.final_offset,
        if r.escape { "start" } else { "file pose" },
        r.final_turn,
        if r.flexible {
            format!(
                ", its bonds {:.1}° (RMS) from their angles",
                r.final_torsion_rms
            )
        } else {
            String::new()
        }
    );
    outln!(
        "deepest overlap beyond the contact rule: {:.3} Å with the receptor ({:.1} Å of the path deeper than the soft limit), {:.3} Å within the drug beyond its start's {:.3} Å; a step takes {:.1} µs (median), {:.1} µs (p99)",
        r.deepest_overlap,
        r.path_beyond_limit,
        r.deepest_inner_overlap,
        r.start_inner_overlap,
        r.step_us_median,
        r.step_us_p99
    );
    if let Some(c) = r.end_push_into_surface {
        outln!(
            "ends pressed against the receptor, pushing {:.0}° off the inward normal of its smoothed surface (0°: head-on into its body)",
            c.clamp(-1.0, 1.0).acos().to_degrees()
        );
    }
    if let Some(s) = &r.settled {
        outln!(
            "settle: {}; RMSD {:.2} Å{}; {}",
            if s.applied {
                "applied"
            } else {
                "found no pose free of overlaps, nothing changed"
            },
            s.rmsd,
            s.score
                .map(|e| format!(", Vina inter {e:.2} kcal/mol"))
                .unwrap_or_default(),
            if s.collides {
                "collides"
            } else {
                "collision-free"
            }
        );
    }
    Ok(())
}
