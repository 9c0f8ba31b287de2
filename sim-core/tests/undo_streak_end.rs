//! The frame let through after a streak of undone frames does not throw the sheet apart
//! (`sim_core::sim`, "The pass-through guard"; issue 55).
//!
//! The case: the suite's coarse stress session with seed 1098 (`papier-lab stress-fixture 1098
//! 19478`): a crumple squeezing a 10 cm square whose every frame crosses it, so the guard undoes
//! `MAX_UNDO_STREAK` frames in a row, each stiffening the crossing pairs' contact ×4 (to ×4096),
//! then lets one through. With the boosts kept, the next frame threw a corner at 3.4 m/s and
//! turned a triangle over (the session failed on it); they are dropped with the streak.
//!
//! Breakage detected: a flipped triangle in the 40 frames; a fixture that no longer reaches the
//! streak fails its own check (no streak of `MAX_UNDO_STREAK`).

mod common;

use sim_core::sim::{FrameOutput, MAX_UNDO_STREAK};

#[test]
fn the_frame_after_an_undo_streak_turns_nothing_over() {
    let mut sim = common::restore_fixture(include_str!("fixtures/stress_seed1098_frame19478.json"));
    let mut out = FrameOutput::default();
    let (mut longest_streak, mut flipped, mut fastest_m_s) = (0u32, 0usize, 0.0f32);
    for _ in 0..40 {
        sim.step(&mut out);
        longest_streak = longest_streak.max(out.stats.undo_streak);
        flipped += out.stats.num_flipped as usize;
        fastest_m_s = fastest_m_s.max(out.stats.max_speed_m_s);
    }
    println!(
        "longest undo streak {longest_streak}, flipped {flipped}, fastest {fastest_m_s:.2} m/s"
    );
    assert!(
        longest_streak >= MAX_UNDO_STREAK,
        "the fixture no longer reaches an undo streak ({longest_streak})"
    );
    assert_eq!(flipped, 0, "triangles turned over after the streak");
}
