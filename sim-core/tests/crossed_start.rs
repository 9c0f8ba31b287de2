//! A frame whose start crosses already is not undone (`sim_core::sim`, "The pass-through
//! guard").
//!
//! The case: the crumple S4 played with seed 181, saved after its 181st driven frame
//! (`tests/fixtures/crumple_s4_seed181_frame181.json`, saved by the build of `98eb171`, whose
//! course made it). Its next frame starts with two layers of one fold crossed — triangles close
//! enough in the pattern that the closest-approach query arming the guard treats them as one
//! patch of the sheet and skips them — and ends crossed. Undoing it would return to the crossed
//! start, so the frame stands. (With earlier courses, S4 seed 8 undid 163 frames in a row that
//! way: 0.8 s of a frozen squeeze.) A saved state, because the crumples' courses move with any
//! change of the hands or the solver, and since the hands give way by their balance no course
//! of S4 or C5 over seeds 1–80 starts a frame crossed.
//!
//! Breakage detected: without the rule no frame reports `kept_crossed_start` (the guard then
//! undoes the frame instead); a streak of undone frames fails too.

mod common;

use sim_core::sim::FrameOutput;

#[test]
fn a_frame_that_starts_crossed_is_not_undone_again_and_again() {
    let mut sim =
        common::restore_fixture(include_str!("fixtures/crumple_s4_seed181_frame181.json"));
    let mut out = FrameOutput::default();
    let (mut kept, mut longest_streak) = (Vec::new(), 0u32);
    for frame in 1..=40 {
        sim.step(&mut out);
        if out.stats.kept_crossed_start {
            kept.push(frame);
        }
        longest_streak = longest_streak.max(out.stats.undo_streak);
    }
    println!("frames kept with a crossed start {kept:?}, longest undo streak {longest_streak}");
    assert!(
        !kept.is_empty(),
        "no frame kept its crossed start: the guard undid it"
    );
    assert!(
        longest_streak < 5,
        "{longest_streak} frames undone in a row"
    );
}
