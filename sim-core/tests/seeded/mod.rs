//! A crumple scene played with another seed (`NAME@SEED`, `sim_core::scenario::get_seeded`),
//! shared by the tests that replay the courses found over seeds.

// Each test binary includes this module and uses part of it.
#![allow(dead_code)]

use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{Sim, SimConfig};

/// The script runner of `run` and its sheet, started with `cfg`.
pub fn start(run: &str, cfg: SimConfig) -> (ScriptRunner, Sim) {
    let script = scenario::get_seeded(run).expect("scene");
    let runner = ScriptRunner::new(&script, cfg.frame_rate_hz, cfg.room).expect("runner");
    let sim = runner.start(cfg);
    (runner, sim)
}

/// The default configuration with insertions strained up to `max_start_strain`
/// (`GeometryConfig::insertion_max_start_strain`).
pub fn with_insertion_limit(max_start_strain: f64) -> SimConfig {
    let mut cfg = SimConfig::default();
    cfg.geometry.insertion_max_start_strain = max_start_strain;
    cfg
}
