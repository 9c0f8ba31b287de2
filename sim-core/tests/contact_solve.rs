//! The Newton solve in the crumple's contact frames (`physics/newton.rs`, `physics/sparse.rs`,
//! `physics/sheet_contact.rs`): the sheet–sheet contact pairs couple vertices of two layers
//! that share no block of the solver's fixed sparsity pattern. With only the pairs' diagonal
//! blocks, Newton's model charges every vertex of a pair the pair stiffness (about 400 m/h²)
//! for a motion that moves both layers together and leaves the gap unchanged; in a crumpled
//! ball, where stacked layers are carried along by the hands, its steps then shrink to about
//! a micrometre per iteration and the frame runs into the iteration cap (measured with a trace
//! of the line search: every step accepted whole, each lowering the energy by its full
//! slope). With the pairs' whole rank-one Hessians in the solve (Woodbury,
//! `SolverConfig::contact_coupling_pairs`), the same frames converge.
//!
//! Breakage detected: a coupling term that is dropped, mis-indexed or of the wrong size makes
//! the crumple's contact frames run into the cap as often as with the diagonal blocks alone.
//! Both runs use the plain Newton method (`SolverConfig::reuse_factor` off): reused
//! factorizations let as many cheap iterations again follow the factorized ones
//! (`physics/newton.rs`, "Reused factorizations"), within which even the diagonal blocks
//! converge (5 of the 400 frames at the cap, measured), so they would hide a broken coupling.

use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

/// Frames of each crumple played (measured on S4 and C5: 125 and 161 of them end at the cap
/// with the diagonal blocks alone, 81 and 101 with the coupling). The cases are courses: C5
/// alone separated them by more than half (106 against 32) until the strain limit
/// (`physics/strain_limit.rs`) changed its course; two crumples summed keep the measure from
/// resting on one course.
const FRAMES: usize = 400;

/// The crumples played.
const CRUMPLES: [&str; 2] = ["s4_crumple", "c5_full_crumple"];

/// Frames that ran into the iteration cap among the first [`FRAMES`] awake frames of `name`
/// with `coupling` pairs in the solve.
fn capped_frames(name: &str, coupling: u32) -> usize {
    let script = scenario::get(name).unwrap();
    let mut cfg = SimConfig::default();
    cfg.solver.contact_coupling_pairs = coupling;
    cfg.solver.reuse_factor = false;
    let mut runner = ScriptRunner::new(&script, cfg.frame_rate_hz, cfg.room).unwrap();
    let mut sim = runner.start(cfg);
    let mut out = FrameOutput::default();
    let (mut capped, mut frames) = (0, 0);
    while frames < FRAMES && runner.drive(&mut sim, &mut out) {
        if out.stats.asleep {
            continue;
        }
        frames += 1;
        capped += usize::from(out.stats.capped_substeps > 0);
    }
    capped
}

#[test]
fn coupling_the_layers_lets_the_crumples_contact_frames_converge() {
    let coupled: usize = CRUMPLES.iter().map(|n| capped_frames(n, 32)).sum();
    let diagonal: usize = CRUMPLES.iter().map(|n| capped_frames(n, 0)).sum();
    eprintln!("frames at the cap: coupled {coupled}, diagonal {diagonal}");
    assert!(
        diagonal > 200,
        "the crumples' contact frames are hard: {diagonal} at the cap"
    );
    assert!(
        4 * coupled <= 3 * diagonal,
        "frames at the iteration cap: {coupled} with coupling, {diagonal} without"
    );
}
