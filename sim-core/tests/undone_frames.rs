//! An undone frame whose start is strained is relaxed (`sim_core::sim`, "An undone frame
//! relaxed").
//!
//! The cases come from the crumples played with other seeds (`NAME@SEED`,
//! `sim_core::scenario::get_seeded`), found again after the Newton solver began to reuse its
//! factorizations (`sim_core::physics::newton`, "Reused factorizations"), which sent every
//! crumple on another course. Most strained starts were vertices inserted for singular points
//! just off a sharp fold, whose triangles spanned the fold; those now go on the fold edge
//! (`sim_core::sheet::refine`, step 2), so the first case plays with
//! `GeometryConfig::insertion_max_start_strain` infinite — insertions at s̄ whatever their
//! strain, as before — to keep the relaxation covered where it matters most:
//! - S4 with seed 8, insertions at s̄: its 989th driven frame is undone from a start strained
//!   by an insertion inside a tight fold; without the relaxation the undone frames show 0.944
//!   (the scenario health limit is 0.1), relaxed with the hands held the run's undone frames
//!   stay at 0.059.
//! - S4 with seed 217, default configuration: its 633rd driven frame is undone from a start
//!   strained by 0.112 that the relaxation mends (0.010).
//! - C5 with seed 181, default configuration: its 330th frame is undone from a strained start
//!   whose relaxation over the frame's one substep springs the fold through the layer beside
//!   it; over four shorter substeps it does not. Without the relaxation, or with the shorter
//!   retry replaced by the frame's own substeps, its undone frames show 0.156.
//!
//! Breakage detected: each case fails without its part of the relaxation (checked by
//! disabling it); a course that no longer makes such a frame (any change to the crumple's
//! play) fails the first assertion, which says to find another run (`cargo run --release -p
//! papier-lab -- iter-hist s4_crumple@SEED` prints the largest strain, the undone and the
//! relaxed frames of each seed; `INS_STRAIN=inf` plays insertions at s̄).

mod seeded;

use sim_core::sim::{FrameOutput, SimConfig, UNDO_RELAX_STRAIN};

#[test]
fn an_undone_frame_that_starts_strained_is_relaxed_with_the_hands_held() {
    relaxes_within("s4_crumple@8", 1000, f64::INFINITY);
}

/// The default configuration still meets strained undone starts, rarely (S4 seed 217).
#[test]
fn an_undone_frame_is_relaxed_in_the_default_configuration() {
    relaxes_within(
        "s4_crumple@217",
        650,
        SimConfig::default().geometry.insertion_max_start_strain,
    );
}

/// C5 with seed 181, its 330th frame, default configuration: relaxed over the frame's one
/// substep the fold springs through the layer beside it (the relaxation crosses and cannot
/// stand); over four shorter substeps it does not.
#[test]
fn a_relaxation_that_crosses_is_tried_again_with_shorter_substeps() {
    relaxes_within(
        "c5_full_crumple@181",
        350,
        SimConfig::default().geometry.insertion_max_start_strain,
    );
}

/// Plays `run` (`NAME@SEED`) for `frames` frames with insertions strained up to
/// `max_start_strain`: some undone frame is relaxed, and no undone frame exceeds the health
/// limit.
fn relaxes_within(run: &str, frames: u64, max_start_strain: f64) {
    let (mut runner, mut sim) = seeded::start(run, seeded::with_insertion_limit(max_start_strain));
    let mut out = FrameOutput::default();
    let (mut relaxed, mut undone, mut worst) = (Vec::new(), 0u32, 0.0f32);
    // Frames driven (the scene's script resets the sheet, and its frame count, on the way).
    let mut frame = 0u64;
    while frame < frames && runner.drive(&mut sim, &mut out) {
        frame += 1;
        if out.stats.relaxed_undone {
            assert!(
                out.stats.undo_streak > 0,
                "relaxed a frame that was not undone"
            );
            relaxed.push(frame);
        }
        if out.stats.undo_streak > 0 {
            undone += 1;
            worst = worst.max(out.stats.max_strain);
        }
    }
    println!(
        "{run}: relaxed undone frames {relaxed:?}, undone frames {undone}, largest strain {worst:.3}"
    );
    assert!(
        !relaxed.is_empty(),
        "{run}: no undone frame started strained beyond {UNDO_RELAX_STRAIN} in the first \
         {frames} frames: the crumple's course changed; find another run for this test"
    );
    assert!(
        f64::from(worst) < UNDO_RELAX_STRAIN,
        "{run}: an undone frame strained by {worst}, beyond the health limit"
    );
}
