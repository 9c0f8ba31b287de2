//! An undone frame whose start is strained is relaxed (`sim_core::sim`, "An undone frame
//! relaxed").
//!
//! The cases come from the crumples played with other seeds (`NAME@SEED`,
//! `sim_core::scenario::get_seeded`). Most strained starts were vertices inserted for singular
//! points just off a sharp fold, whose triangles spanned the fold; those now go on the fold edge
//! (`sim_core::sheet::refine`, step 2), so the first case plays with
//! `GeometryConfig::insertion_max_start_strain` infinite — insertions at s̄ whatever their
//! strain — to keep the relaxation covered where it matters most:
//! - S4 with seed 8, insertions at s̄: an undone frame starts from an insertion strained inside a
//!   tight fold; relaxed with the hands held, the run's undone frames stay under the health
//!   limit.
//! - S4 with seed 217, default configuration, saved after its 632nd driven frame
//!   (`tests/fixtures/crumple_s4_seed217_frame632.json`): its next frame is undone from a start
//!   strained by 0.112 that the relaxation mends.
//! - C5 with seed 181, default configuration, saved after its 329th frame
//!   (`tests/fixtures/crumple_c5_seed181_frame329.json`): its next frame is undone from a
//!   strained start whose relaxation over the frame's one substep springs the fold through the
//!   layer beside it; over four shorter substeps it does not.
//!
//! The last two are saved states (by the build of `98eb171`, whose courses made them): since the
//! hands give way by their balance, the crumples' courses over seeds 1–80 rarely undo a frame
//! from a strained start (S4 seed 1 once).
//!
//! Breakage detected: each case fails without its part of the relaxation; a course that no
//! longer makes such a frame fails the first assertion, which says to find another run
//! (`cargo run --release -p papier-lab -- iter-hist s4_crumple@SEED` prints the largest strain,
//! the undone and the relaxed frames of each seed; `INS_STRAIN=inf` plays insertions at s̄).

mod common;
mod seeded;

use sim_core::sim::{FrameOutput, UNDO_RELAX_STRAIN};

#[test]
fn an_undone_frame_that_starts_strained_is_relaxed_with_the_hands_held() {
    relaxes_within("s4_crumple@8", 1000, f64::INFINITY);
}

/// The default configuration still meets strained undone starts, rarely (S4 seed 217).
#[test]
fn an_undone_frame_is_relaxed_in_the_default_configuration() {
    relaxes_from(include_str!("fixtures/crumple_s4_seed217_frame632.json"));
}

/// C5 with seed 181, its 330th frame, default configuration: relaxed over the frame's one
/// substep the fold springs through the layer beside it (the relaxation crosses and cannot
/// stand); over four shorter substeps it does not.
#[test]
fn a_relaxation_that_crosses_is_tried_again_with_shorter_substeps() {
    relaxes_from(include_str!("fixtures/crumple_c5_seed181_frame329.json"));
}

/// Steps the sheet saved in `fixture` (no further commands: its gestures go on as commanded)
/// for 20 frames: some undone frame is relaxed, and no undone frame exceeds the health limit.
fn relaxes_from(fixture: &str) {
    let mut sim = common::restore_fixture(fixture);
    let mut out = FrameOutput::default();
    let (mut relaxed, mut worst) = (Vec::new(), 0.0f32);
    for frame in 1..=20 {
        sim.step(&mut out);
        if out.stats.relaxed_undone {
            assert!(
                out.stats.undo_streak > 0,
                "relaxed a frame that was not undone"
            );
            relaxed.push(frame);
        }
        if out.stats.undo_streak > 0 {
            worst = worst.max(out.stats.max_strain);
        }
    }
    println!("relaxed undone frames {relaxed:?}, largest strain of an undone frame {worst:.3}");
    assert!(!relaxed.is_empty(), "no undone frame was relaxed");
    assert!(
        f64::from(worst) < UNDO_RELAX_STRAIN,
        "an undone frame strained by {worst}, beyond the health limit"
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
