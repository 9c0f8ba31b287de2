//! Does a change leave the sound analysis' input bit-identical? Hashes every frame's sound
//! input (`SoundFrame`, all fields at full precision through its `Debug` form) per scene: a
//! change that should leave it unchanged (a cache, a reordering) must leave these hashes as
//! they were.
//!
//! `cargo run --release -p papier-lab -- sound-hash [NAME[@SEED]|FILE.toml ...]` (default:
//! every library scenario).

use std::hash::{DefaultHasher, Hasher};

use sim_core::sim::SimConfig;

use crate::play::{self, Play};

pub const USAGE: &str = "[NAME[@SEED]|FILE.toml ...]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    for name in play::scenes_or_all(args) {
        let mut p = Play::scene(&name, SimConfig::default())?;
        let mut h = DefaultHasher::new();
        let mut frames = 0u64;
        while p.frame() {
            h.write(format!("{:?}", p.out.sound).as_bytes());
            frames += 1;
        }
        println!("{name:30} frames {frames:5} sound {:016x}", h.finish());
    }
    Ok(())
}
