//! A frame whose start crosses already is not undone (`sim_core::sim`, "The pass-through
//! guard").
//!
//! The case: the crumple S4 played with seed 181 (`sim_core::scenario::get_seeded`; found
//! after the Newton solver began to reuse its factorizations, which changed every crumple's
//! course). Its 182nd driven frame starts with two layers of one fold crossed — triangles
//! close enough in the pattern that the closest-approach query arming the guard treats them
//! as one patch of the sheet and skips them — and ends crossed. Undoing it would return to the
//! crossed start, so the frame stands. (With the seeds' earlier courses, S4 seed 8 undid 163
//! frames in a row that way: 0.8 s of a frozen squeeze.)
//!
//! Breakage detected: without the rule no frame reports `kept_crossed_start` (checked: the
//! guard then undoes the frame instead); a streak of undone frames fails too. If the crumple's
//! course changes, no frame starts crossed and the case must be found again (`cargo run
//! --release -p papier-lab -- iter-hist s4_crumple@SEED` prints the undone and kept-crossed
//! frames of each seed).

mod seeded;

use sim_core::sim::{FrameOutput, SimConfig};

#[test]
fn a_frame_that_starts_crossed_is_not_undone_again_and_again() {
    let run = "s4_crumple@181";
    let (mut runner, mut sim) = seeded::start(run, SimConfig::default());
    let mut out = FrameOutput::default();
    let (mut kept, mut longest_streak) = (Vec::new(), 0u32);
    let mut frame = 0u32;
    while frame < 300 && runner.drive(&mut sim, &mut out) {
        frame += 1;
        if out.stats.kept_crossed_start {
            kept.push(frame);
        }
        longest_streak = longest_streak.max(out.stats.undo_streak);
    }
    println!(
        "{run}: frames kept with a crossed start {kept:?}, longest undo streak {longest_streak}"
    );
    let kept = kept.len();
    assert!(
        kept > 0,
        "{run}: no frame kept its crossed start: the guard undid it, or the crumple's course \
         changed (find another run)"
    );
    assert!(
        longest_streak < 5,
        "{run}: {longest_streak} frames undone in a row"
    );
}
