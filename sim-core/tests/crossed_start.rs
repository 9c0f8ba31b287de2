//! A frame whose start crosses already is not undone (`sim_core::sim`, "The pass-through
//! guard").
//!
//! The case: the crumple S4 played with seed 8 (`sim_core::scenario::get_seeded`). Around its
//! 238th frame two layers of one fold end a frame crossed — two triangles 39 mm apart in the
//! pattern, close enough that the closest-approach query arming the guard treats them as one
//! patch of the sheet and skips them. The next frame starts crossed, the guard is armed all the
//! same, the frame ends crossed, and undoing it returned to the crossed start: before, the
//! guard undid 163 frames in a row (0.8 s of a frozen squeeze). Now such a frame stands, as a
//! frame does when the guard sees its start crossing.
//!
//! Breakage detected: a streak of undone frames (the old behaviour); and if no frame reports
//! `kept_crossed_start`, the crumple's course has changed and the case must be found again
//! (`cargo run --release -p sim-core --example iter_hist -- s4_crumple@SEED` prints the undone
//! and kept-crossed frames of each seed).

mod seeded;

use sim_core::sim::{FrameOutput, SimConfig};

#[test]
fn a_frame_that_starts_crossed_is_not_undone_again_and_again() {
    let run = "s4_crumple@8";
    let (mut runner, mut sim) = seeded::start(run, SimConfig::default());
    let mut out = FrameOutput::default();
    let (mut kept, mut longest_streak) = (0u32, 0u32);
    for _ in 0..300 {
        assert!(runner.drive(&mut sim, &mut out));
        kept += u32::from(out.stats.kept_crossed_start);
        longest_streak = longest_streak.max(out.stats.undo_streak);
    }
    println!(
        "{run}: {kept} frames kept with a crossed start, longest undo streak {longest_streak}"
    );
    assert!(
        kept > 0,
        "{run}: no frame started crossed: the crumple's course changed; find another run"
    );
    assert!(
        longest_streak < 5,
        "{run}: {longest_streak} frames undone in a row"
    );
}
