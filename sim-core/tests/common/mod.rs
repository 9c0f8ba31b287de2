//! Helpers shared by the integration tests.

use sim_core::sim::{Sim, SimConfig};

/// Restores a sheet saved as JSON: a regression fixture of `tests/fixtures/`, written by
/// `cargo run --release -p sim-core --example stress_fixture -- SEED FRAME OUT.json`.
pub fn restore_fixture(json: &str) -> Sim {
    let saved = serde_json::from_str(json).expect("the fixture parses");
    Sim::restore(SimConfig::default(), &saved).expect("the fixture restores")
}
