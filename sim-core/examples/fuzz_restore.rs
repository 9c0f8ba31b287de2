//! A longer run of the saved-sheet mutation test (`tests/save_restore.rs`,
//! `random_json_mutations_never_panic`): mutates a mid-crumple save at random, restores it and
//! steps every accepted sheet, reporting panics and non-finite positions.
//!
//! `cargo run --release -p sim-core --example fuzz_restore -- [CASES] [SEED] [SCENE] [FRAME]`
//! (defaults 2000, 1, c5_full_crumple, 250).

use std::panic::{AssertUnwindSafe, catch_unwind};

use rand::{RngExt, SeedableRng};
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SavedSheet, Sim, SimConfig};

#[path = "../tests/common/json_mutation.rs"]
mod json_mutation;
use json_mutation::mutate;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let cases: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(2000);
    let seed: u64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(1);
    let scene = args
        .get(2)
        .cloned()
        .unwrap_or_else(|| "c5_full_crumple".into());
    let frames: u64 = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(250);
    let script = scenario::get(&scene).expect("scene");
    let base = SimConfig::default();
    let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
    let cfg = runner.config(base);
    let mut sim = runner.start(base);
    let mut out = FrameOutput::default();
    for _ in 0..frames {
        runner.drive(&mut sim, &mut out);
    }
    let value = serde_json::to_value(sim.save()).unwrap();
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
    println!(
        "{cases} cases (seed {seed}, {scene}@{frames}): {accepted} accepted, {panics} panics, \
         {nonfinite} non-finite"
    );
}
