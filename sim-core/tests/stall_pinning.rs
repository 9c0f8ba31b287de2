//! Regression test of the Newton solver's pinning (`sim_core::physics::newton`, "Pinning"): a
//! substep whose line search refuses every step because one triangle would turn over pins that
//! triangle's free vertices, and the rest of the sheet goes on following the hands.
//!
//! The fixture is the sheet after frame 6 452 of the hostile stress session
//! `sim-stress --seed 2 --sessions 1`, written by
//! `cargo run --release -p sim-core --example stress_fixture -- 2 6452 OUT.json`. Without
//! pinning its next frame stalled after 5 iterations and 70 halvings and ended with a triangle
//! next to a hand stretched to 2.07× its length (strain 1.065 > `MAX_STRAIN`), which this
//! test then fails on; with pinning that frame ends at strain 0.699.

use sim_core::sim::{FrameOutput, Sim, SimConfig};
use sim_core::stress::MAX_STRAIN;

#[test]
fn a_stalled_solve_pins_the_turning_triangle_and_the_sheet_follows_the_hands() {
    let saved = serde_json::from_str(include_str!("fixtures/stress_seed2_frame6452.json"))
        .expect("the fixture parses");
    let mut sim = Sim::restore(SimConfig::default(), &saved).expect("the fixture restores");
    let mut out = FrameOutput::default();
    for frame in 1..=3 {
        sim.step(&mut out);
        let strain = sim.metrics().max_strain;
        println!(
            "frame {frame}: strain {strain:.3}, halvings {}, pinned substeps {}",
            out.stats.halvings, out.stats.pinned_substeps
        );
        assert!(
            strain < MAX_STRAIN,
            "frame {frame}: strain {strain} beyond the stress bound"
        );
        assert_eq!(
            out.stats.num_flipped, 0,
            "frame {frame}: a triangle turned over"
        );
        assert!(
            sim.sheet()
                .sp
                .pos
                .iter()
                .all(|p| p.iter().all(|c| c.is_finite()))
        );
    }
}
