//! Hashes every frame's sound input (`SoundFrame`, all fields at full precision through its
//! `Debug` form) over the seed scenarios: a change that should leave the sound analysis'
//! output bit-identical (a cache, a reordering) must leave these hashes unchanged.
//!
//! `cargo run --release -p sim-core --example sound_hash [SCENARIO ...]`

use std::hash::{DefaultHasher, Hasher};

use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<&str> = if args.is_empty() {
        scenario::names().collect()
    } else {
        args.iter().map(String::as_str).collect()
    };
    for name in names {
        let script = scenario::get(name).expect("scenario");
        let cfg = SimConfig::default();
        let mut runner = ScriptRunner::new(&script, cfg.frame_rate_hz, cfg.room).expect("runner");
        let mut sim = runner.start(cfg);
        let mut out = FrameOutput::default();
        let mut h = DefaultHasher::new();
        let mut frames = 0u64;
        while runner.drive(&mut sim, &mut out) {
            h.write(format!("{:?}", out.sound).as_bytes());
            frames += 1;
        }
        println!("{name:30} frames {frames:5} sound {:016x}", h.finish());
    }
}
