//! A vertex inserted for a singular point next to a sharp fold starts unstrained
//! (`sim_core::sheet::refine`, step 2; README "A singular vertex next to a fold").
//!
//! The case: the crumple S4 played with seed 115 (`sim_core::scenario::get_seeded`; found again
//! after the hands began to give way by their balance, which changed every crumple's course).
//! With insertions at s̄ whatever their strain (`GeometryConfig::insertion_max_start_strain`
//! infinite), vertices land just off sharply folded edges and the sheet reaches a strain of
//! 0.236. In the default configuration such vertices go on the fold edge and the whole run
//! stays under the scenario health limit (largest strain 0.063).
//!
//! Breakage detected: the default run exceeding the limit; and if the run with insertions at
//! s̄ no longer exceeds it, the crumple's course has changed and the case must be found again
//! (`INS_STRAIN=inf cargo run --release -p papier-lab -- iter-hist s4_crumple@SEED`).

mod seeded;

use sim_core::sim::{FrameOutput, SimConfig, UNDO_RELAX_STRAIN};

/// Largest strain of any frame of `run`, insertions strained up to `max_start_strain`.
fn largest_strain(run: &str, max_start_strain: f64) -> f32 {
    let (mut runner, mut sim) = seeded::start(run, seeded::with_insertion_limit(max_start_strain));
    let mut out = FrameOutput::default();
    let mut worst = 0.0f32;
    while runner.drive(&mut sim, &mut out) {
        worst = worst.max(out.stats.max_strain);
    }
    worst
}

#[test]
fn a_singular_vertex_next_to_a_fold_starts_unstrained() {
    let run = "s4_crumple@115";
    let at_s = largest_strain(run, f64::INFINITY);
    let default = largest_strain(
        run,
        SimConfig::default().geometry.insertion_max_start_strain,
    );
    println!("{run}: largest strain {at_s:.3} with insertions at s̄, {default:.3} by default");
    assert!(
        f64::from(at_s) > UNDO_RELAX_STRAIN,
        "{run} with insertions at s̄ stays under the limit ({at_s}): its course changed; find \
         another run"
    );
    assert!(
        f64::from(default) < UNDO_RELAX_STRAIN,
        "{run}: strain {default} beyond the health limit"
    );
}
