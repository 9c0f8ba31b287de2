//! What happens right after a given frame of a hostile stress session? Saves the sheet of the
//! session at that frame with the session's room, as JSON (regression fixtures:
//! `sim-core/tests/fixtures/`, [`sim_core::stress::StressFixture`]), then steps the restored
//! sheet a few frames and prints each frame's largest strain, line-search halvings and pinned
//! substeps.
//!
//! `cargo run --release -p papier-lab -- stress-fixture [SEED] [FRAME] [OUT.json]` (default
//! seed 2, frame 6452, `stress_seedSEED_frameFRAME.json`) saves the state after frame FRAME of
//! `papier-lab stress --seed SEED --sessions 1` (with `TEST_SESSION=1`: of the test suite's
//! coarse session, `StressConfig::test_session`, as `sim-core/tests/stress.rs` runs it); `REUSE=0` steps the restored sheet without
//! reused factorizations, `ITERS=N` with N Newton iterations per substep, `SUBSTEPS=N` with N
//! substeps per frame.

use anyhow::Context;
use sim_core::sim::{FrameOutput, SimConfig};
use sim_core::stress::{StressConfig, StressFixture, run_with};

use crate::args::{at_most, env_is, env_num, nth};

pub const USAGE: &str = "[SEED] [FRAME] [OUT.json]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 3)?;
    let seed: u64 = nth(args, 0, "SEED")?.unwrap_or(2);
    let frame: u64 = nth(args, 1, "FRAME")?.unwrap_or(6452);
    let path = args
        .get(2)
        .cloned()
        .unwrap_or_else(|| format!("stress_seed{seed}_frame{frame}.json"));
    let cfg = if env_is("TEST_SESSION", "1") {
        StressConfig::test_session(seed, frame + 1)
    } else {
        StressConfig {
            seed,
            frames: frame + 1,
            sim: SimConfig::default(),
            ..StressConfig::default()
        }
    };
    let mut saved = None;
    let report = run_with(&cfg, |f, sim| {
        if f == frame {
            saved = Some(StressFixture::of(sim));
        }
    });
    let Some(saved) = saved else {
        anyhow::bail!(
            "the session ended before frame {frame}: {:?}",
            report.failure
        );
    };
    let json = serde_json::to_string(&saved)?;
    std::fs::write(&path, &json).with_context(|| format!("writing {path}"))?;
    println!("{path}: {} bytes", json.len());
    // `REUSE=0`: the restored sheet steps without reused factorizations
    // (`SolverConfig::reuse_factor`).
    let mut replay = cfg.sim;
    replay.solver.reuse_factor = !env_is("REUSE", "0");
    if let Some(n) = env_num("ITERS") {
        replay.solver.iterations = n;
    }
    if let Some(n) = env_num("SUBSTEPS") {
        replay.solver.substeps = n;
    }
    let mut sim = saved.restore(replay).context("restoring the sheet")?;
    let mut out = FrameOutput::default();
    for k in 1..=3 {
        sim.step(&mut out);
        println!(
            "restored + {k}: strain {:.3}, halvings {}, iterations {}, pinned substeps {}, flipped {}",
            sim.metrics().max_strain,
            out.stats.halvings,
            out.stats.iterations,
            out.stats.pinned_substeps,
            out.stats.num_flipped
        );
    }
    Ok(())
}
