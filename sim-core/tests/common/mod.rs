//! Helpers shared by the integration tests.

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
