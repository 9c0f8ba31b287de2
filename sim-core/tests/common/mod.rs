//! Helpers shared by the integration tests.

// Each test crate compiles this module and uses only some of it.
#![allow(dead_code)]

pub mod json_mutation;

use sim_core::sim::{SavedSheet, Sim, SimConfig};
use sim_core::stress::StressFixture;

/// Restores a sheet saved as JSON: a regression fixture of `tests/fixtures/`, written by
/// `cargo run --release -p sim-core --example stress_fixture -- SEED FRAME OUT.json`, in the
/// room it was saved in. A bare `SavedSheet` (the fixtures written before the room was kept)
/// restores in the default room.
pub fn restore_fixture(json: &str) -> Sim {
    let fixture = serde_json::from_str::<StressFixture>(json).unwrap_or_else(|_| StressFixture {
        room: SimConfig::default().room,
        sheet: serde_json::from_str::<SavedSheet>(json).expect("the fixture parses"),
    });
    fixture
        .restore(SimConfig::default())
        .expect("the fixture restores")
}

/// True if every S_P position of `sim` is finite.
pub fn positions_finite(sim: &Sim) -> bool {
    sim.sheet()
        .sp
        .pos
        .iter()
        .all(|p| p.iter().all(|c| c.is_finite()))
}
