//! A sheet chattering in place is at rest (`sim_core::sim`, "Sleeping"; issue 55).
//!
//! The case: the suite's coarse stress session with seed 1041 (`papier-lab stress-fixture 1041
//! 20040`), saved 12 frames after its hands stopped: an A6 torn and crumpled, held by its eight
//! crumple points, one layer pressed on another. Held still, it settles, then goes on jumping
//! by tenths of a millimetre every dozen frames or so — a limit cycle of the solve and the
//! contact — without leaving a 1 mm box. A sleep test on each frame's motion never found
//! [`SLEEP_FRAMES`] slow frames in a row: the session failed its hold, awake 401 frames after
//! the hands stopped, chattering at 2–5 cm/s by then.
//!
//! Breakage detected: without the box the sheet is still awake after 200 frames (the test
//! checks that no [`SLEEP_FRAMES`] slow frames in a row came before the sleep, so the per-frame
//! test alone would not have slept yet); a box that let a sheet creep away would show as a
//! spread of the window's positions beyond it.

mod common;

use sim_core::sim::{FrameOutput, REST_BOX_M, SLEEP_FRAMES, SLEEP_SPEED_M_S};

#[test]
fn a_held_sheet_chattering_in_place_falls_asleep() {
    let mut sim = common::restore_fixture(include_str!("fixtures/stress_seed1041_frame20040.json"));
    let mut out = FrameOutput::default();
    // Per frame: positions at its end and whether a vertex moved faster than the sleep speed
    // over it (the per-frame test, which needs SLEEP_FRAMES slow frames in a row).
    let dt_s = 1.0 / sim_core::sim::DEFAULT_FRAME_RATE_HZ;
    let mut frames: Vec<(Vec<sim_core::math::V3>, bool)> = Vec::new();
    let mut asleep_at = None;
    for frame in 1..=200u32 {
        sim.step(&mut out);
        if out.stats.asleep {
            asleep_at = Some(frame);
            break;
        }
        let pos = sim.sheet().sp.pos.clone();
        let moved_m = frames.last().map_or(f64::INFINITY, |(p, _)| {
            pos.iter()
                .zip(p)
                .map(|(a, b)| (a - b).norm())
                .fold(0.0, f64::max)
        });
        frames.push((pos, moved_m >= SLEEP_SPEED_M_S * dt_s));
    }
    let at = asleep_at.expect("the held sheet was awake 200 frames (1 s) after restoring");
    let window = &frames[frames.len().saturating_sub(SLEEP_FRAMES as usize)..];
    let fast = window.iter().filter(|f| f.1).count();
    // The longest run of slow frames: the per-frame test sleeps after SLEEP_FRAMES of them.
    let (mut run, mut longest) = (0u32, 0u32);
    for f in &frames {
        run = if f.1 { 0 } else { run + 1 };
        longest = longest.max(run);
    }
    let spread_m = window
        .iter()
        .flat_map(|(p, _)| p.iter().zip(&window[0].0).map(|(a, b)| (a - b).norm()))
        .fold(0.0, f64::max);
    println!(
        "asleep at frame {at}; {fast} of the last {} frames faster than the sleep speed, longest slow run {longest}, spread {spread_m:.2e} m",
        window.len()
    );
    assert!(
        longest < SLEEP_FRAMES,
        "{longest} slow frames in a row: the fixture no longer chatters, a per-frame test sleeps too"
    );
    // The window's frames stay within two box half-widths of each other.
    assert!(spread_m <= 2.0 * REST_BOX_M, "spread {spread_m} m");
}
