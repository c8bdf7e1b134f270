//! The scoring's section: AutoDock Vina's energy with its gradient from
//! maps and exactly, the maps' build, settle, their cost against receptor
//! size and the maps' error against exact, beside Vina's own times
//! (`bump_testkit::score_bench`, which `cargo bench --bench score` shares).

use bump_testkit::score_bench;

use super::timing::Progress;
use super::{Context, Part, Section};

/// The section.
pub const SECTION: Section = Section {
    name: "score",
    steps,
    run,
};

fn steps(ctx: &Context) -> usize {
    ctx.one_step_with_data()
}

fn run(ctx: &Context, progress: &mut Progress) -> Part {
    let data = match ctx.data_or_skip("Scoring") {
        Ok(d) => d,
        Err(skipped) => return skipped,
    };
    progress.step("scoring");
    Part::text(score_bench::markdown(data, ctx.quick))
}
