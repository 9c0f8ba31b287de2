//! Does any damaged save make the sim panic or go non-finite? A longer run of the saved-sheet
//! mutation test (sim-core's `tests/save_restore.rs`, `random_json_mutations_never_panic`, with
//! the same mutations, `tests/common/json_mutation.rs`): mutates a mid-crumple save at random,
//! restores it and steps every accepted sheet 20 frames, reporting panics and non-finite
//! positions.
//!
//! `cargo run --release -p papier-lab -- fuzz-restore [CASES] [SEED] [SCENE] [FRAME]`
//! (defaults 2000, 1, c5_full_crumple, 250).

use std::panic::{AssertUnwindSafe, catch_unwind};

use rand::{RngExt, SeedableRng};
use sim_core::sim::{FrameOutput, SavedSheet, Sim, SimConfig};

use crate::args::{at_most, nth};
use crate::play::Play;

#[path = "../../../sim-core/tests/common/json_mutation.rs"]
mod json_mutation;
use json_mutation::mutate;

pub const USAGE: &str = "[CASES] [SEED] [SCENE] [FRAME]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 4)?;
    let cases: usize = nth(args, 0, "CASES")?.unwrap_or(2000);
    let seed: u64 = nth(args, 1, "SEED")?.unwrap_or(1);
    let scene = args.get(2).map_or("c5_full_crumple", String::as_str);
    let frames: u64 = nth(args, 3, "FRAME")?.unwrap_or(250);
    let base = SimConfig::default();
    let mut p = Play::scene(scene, base)?;
    let cfg = p.runner.config(base);
    for _ in 0..frames {
        p.frame();
    }
    let value = serde_json::to_value(p.sim.save())?;
    let mut rng = rand_pcg::Pcg32::seed_from_u64(seed);
    std::panic::set_hook(Box::new(|_| {}));
    let (mut accepted, mut panics, mut nonfinite) = (0, 0, 0);
    for case in 0..cases {
        let mut v = value.clone();
        for _ in 0..rng.random_range(1..4u32) {
            mutate(&mut v, &mut rng);
        }
        let r = catch_unwind(AssertUnwindSafe(|| {
            let saved: SavedSheet = serde_json::from_value(v).ok()?;
            let mut s = Sim::restore(cfg, &saved).ok()?;
            let mut out = FrameOutput::default();
            for _ in 0..20 {
                s.step(&mut out);
            }
            Some(
                s.sheet()
                    .sp
                    .pos
                    .iter()
                    .all(|p| p.iter().all(|c| c.is_finite())),
            )
        }));
        match r {
            Err(_) => {
                panics += 1;
                println!("case {case}: panic");
            }
            Ok(Some(finite)) => {
                accepted += 1;
                if !finite {
                    nonfinite += 1;
                    println!("case {case}: non-finite positions");
                }
            }
            Ok(None) => {}
        }
    }
    let _ = std::panic::take_hook();
    println!(
        "{cases} cases (seed {seed}, {scene}@{frames}): {accepted} accepted, {panics} panics, \
         {nonfinite} non-finite"
    );
    Ok(())
}
