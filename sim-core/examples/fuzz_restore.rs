//! A longer run of the saved-sheet mutation test (`tests/save_restore.rs`,
//! `random_json_mutations_never_panic`): mutates a mid-crumple save at random, restores it and
//! steps every accepted sheet, reporting panics and non-finite positions.
//!
//! `cargo run --release -p sim-core --example fuzz_restore -- [CASES] [SEED] [SCENE] [FRAME]`
//! (defaults 2000, 1, c5_full_crumple, 250).

use std::panic::{AssertUnwindSafe, catch_unwind};

use rand::{RngExt, SeedableRng};
use serde_json::Value;
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SavedSheet, Sim, SimConfig};

fn mutate(v: &mut Value, rng: &mut rand_pcg::Pcg32) {
    match v {
        Value::Object(m) if !m.is_empty() => {
            let k = rng.random_range(0..m.len());
            let key = m.keys().nth(k).unwrap().clone();
            mutate(m.get_mut(&key).unwrap(), rng);
        }
        Value::Array(a) if !a.is_empty() => match rng.random_range(0..8u32) {
            0 => {
                let n = rng.random_range(0..a.len());
                a.truncate(n);
            }
            1 => {
                let i = rng.random_range(0..a.len());
                let x = a[i].clone();
                a.push(x);
            }
            _ => {
                let i = rng.random_range(0..a.len());
                mutate(&mut a[i], rng);
            }
        },
        Value::Number(n) if rng.random_range(0..2u32) == 0 => {
            // A plausible neighbour: nudged, sign-flipped or scaled.
            let x = n.as_f64().unwrap_or(0.0);
            let y = match rng.random_range(0..4u32) {
                0 => x + 1.0,
                1 => -x,
                2 => x * 1.001,
                _ => x - 1.0,
            };
            *v = if n.is_u64() && y >= 0.0 && y.fract() == 0.0 {
                Value::from(y as u64)
            } else {
                Value::from(y)
            };
        }
        _ => {
            *v = match rng.random_range(0..8u32) {
                0 => Value::from(1e300),
                1 => Value::from(-1),
                2 => Value::from(0),
                3 => Value::from(u64::MAX),
                4 => Value::from("x"),
                5 => Value::from(0.5),
                6 => Value::from(1u32 << 31),
                _ => Value::Null,
            };
        }
    }
}

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
