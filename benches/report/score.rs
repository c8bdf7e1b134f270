//! The scoring's section: AutoDock Vina's energy with its gradient from
//! maps and exactly, the maps' build, settle, their cost against receptor
//! size and the maps' error against exact, beside Vina's own times
//! (`bump_testkit::score_bench`, which `cargo bench --bench score` shares),
//! then settle's rates from perturbed crystal poses on every complex of the
//! Vina reference (`bump_testkit::settle_rates`, which `tests/settle.rs`
//! checks).

use bump_testkit::{score_bench, settle_rates};

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
    let runs = if ctx.quick { 2 } else { 12 };
    Part::text(score_bench::markdown(data, ctx.quick) + &settle_rates::markdown(data, runs))
}
