//! How often does the test suite's stress session fail, over many seeds? Runs
//! [`StressConfig::test_session`] (the coarse session `sim-core/tests/stress.rs` runs) for seeds
//! FIRST … FIRST+N−1 on all cores and prints each one's outcome, then the count of failures.
//!
//! `cargo run --release -p papier-lab -- stress-family N FIRST [FRAMES]` (default 25 000 frames).

use sim_core::stress::{StressConfig, run_with};

use crate::args::{at_most, nth};

pub const USAGE: &str = "N FIRST [FRAMES]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 3)?;
    let n: u64 = nth(args, 0, "N")?.unwrap_or(8);
    let first: u64 = nth(args, 1, "FIRST")?.unwrap_or(1);
    let frames: u64 = nth(args, 2, "FRAMES")?.unwrap_or(25_000);
    let seeds: Vec<u64> = (first..first + n).collect();
    let one = |seed: u64| {
        let cfg = StressConfig::test_session(seed, frames);
        // The last frame a tear step was made or the vertex count changed (a hold that fails
        // after one is a sheet moving on its own, not hands that disagree).
        let (mut steps, mut verts, mut last_tear, mut last_mesh) = (0, 0, 0, 0);
        let failure = run_with(&cfg, |f, sim| {
            if sim.tear().mesh_steps != steps {
                steps = sim.tear().mesh_steps;
                last_tear = f;
            }
            if sim.sheet().sp.num_vertices() != verts {
                verts = sim.sheet().sp.num_vertices();
                last_mesh = f;
            }
        })
        .failure
        .map(|(f, why)| {
            (
                f,
                format!("{why} [last tear step {last_tear}, mesh change {last_mesh}]"),
            )
        });
        (seed, failure)
    };
    // Two workers, seeds taken in turn.
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut outcomes: Vec<(u64, Option<(u64, String)>)> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..2)
            .map(|_| {
                s.spawn(|| {
                    let mut got = Vec::new();
                    loop {
                        let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(&seed) = seeds.get(i) else { break };
                        got.push(one(seed));
                    }
                    got
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    outcomes.sort_by_key(|o| o.0);
    let mut failed = 0;
    for (seed, f) in &outcomes {
        match f {
            None => println!("{seed:>6}  ok"),
            Some((frame, why)) => {
                failed += 1;
                println!("{seed:>6}  frame {frame}: {why}");
            }
        }
    }
    println!("{failed} of {n} sessions failed");
    Ok(())
}
