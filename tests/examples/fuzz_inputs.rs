//! The damaged-input run of `tests/bad_input_files.rs`, longer:
//! `cargo run --release -p papier-tests --example fuzz_inputs -- [CASES] [SEED]` (default 600
//! cases, seed 1) over every built-in scene's script, MIDI performance and frame log. Prints
//! each kind's tally; a failing case's input is kept in `target/test-scratch/fuzz_inputs_SEED` and
//! the run goes on.

#[path = "../tests/input_mutation/mod.rs"]
mod input_mutation;

use input_mutation::{Kind, Tally, bases, mutated, run_case};
use papier_tests::paths;
use rand::SeedableRng;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let cases: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(600);
    let seed: u64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(1);
    // One directory per seed, so that runs with other seeds can go side by side.
    let dir = paths::scratch(&format!("fuzz_inputs_{seed}"));
    let _dbs: Vec<_> = input_mutation::RATES_HZ
        .iter()
        .map(|&r| papier::render::default_db(f64::from(r)))
        .collect();
    let scenes: Vec<&'static str> = sim_core::scenario::names().collect();
    let bases = bases(&dir, &scenes);
    let mut rng = rand_pcg::Pcg32::seed_from_u64(seed);
    let mut per_kind = [Tally::default(); 3];
    let mut failures = 0;
    let started = std::time::Instant::now();
    for case in 0..cases {
        let base = &bases[case % bases.len()];
        let bytes = mutated(base, &mut rng);
        let k = base.kind.index();
        match run_case(base.kind, &bytes, &dir, &mut rng) {
            Ok(t) => per_kind[k].add(&t),
            Err(e) => {
                failures += 1;
                let keep = dir.join(format!("failed_{case}.bin"));
                std::fs::write(&keep, &bytes).unwrap();
                println!(
                    "FAIL case {case} ({}): {e}; input in {}",
                    base.scene,
                    keep.display()
                );
            }
        }
    }
    for (t, kind) in per_kind.iter().zip(Kind::ALL.map(|(_, name)| name)) {
        println!(
            "{kind}: {} cases, {} refused, {} played, {} parsed but too long to play",
            t.cases, t.refused, t.played, t.too_long
        );
    }
    println!(
        "{cases} cases, seed {seed}: {failures} failed, {:.0} s",
        started.elapsed().as_secs_f64()
    );
    if failures > 0 {
        std::process::exit(1);
    }
}
