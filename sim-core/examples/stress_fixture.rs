//! Saves the sheet of a hostile stress session at a given frame with the session's room, as JSON
//! (regression fixtures: `sim-core/tests/fixtures/`, [`sim_core::stress::StressFixture`]), then
//! steps the restored sheet a few frames and prints each
//! frame's largest strain, line-search halvings and pinned substeps.
//!
//! `cargo run --release -p sim-core --example stress_fixture -- SEED FRAME OUT.json` saves the
//! state after frame FRAME of `sim-stress --seed SEED --sessions 1`; `REUSE=0` steps the restored
//! sheet without reused factorizations, `ITERS=N` with N Newton iterations per substep,
//! `SUBSTEPS=N` with N substeps per frame.
use sim_core::sim::{FrameOutput, SimConfig};
use sim_core::stress::{StressConfig, StressFixture, run_with};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let seed: u64 = args.first().map_or(2, |s| s.parse().expect("seed"));
    let frame: u64 = args.get(1).map_or(6452, |s| s.parse().expect("frame"));
    let path = args
        .get(2)
        .cloned()
        .unwrap_or_else(|| format!("stress_seed{seed}_frame{frame}.json"));
    let cfg = StressConfig {
        seed,
        frames: frame + 1,
        sim: SimConfig::default(),
        ..StressConfig::default()
    };
    let mut saved = None;
    let report = run_with(&cfg, |f, sim| {
        if f == frame {
            saved = Some(StressFixture::of(sim));
        }
    });
    let Some(saved) = saved else {
        panic!(
            "the session ended before frame {frame}: {:?}",
            report.failure
        );
    };
    let json = serde_json::to_string(&saved).expect("serialize");
    std::fs::write(&path, &json).expect("write");
    println!("{path}: {} bytes", json.len());
    // `REUSE=0`: the restored sheet steps without reused factorizations
    // (`SolverConfig::reuse_factor`).
    let mut replay = SimConfig::default();
    replay.solver.reuse_factor = !std::env::var("REUSE").is_ok_and(|v| v == "0");
    if let Some(n) = std::env::var("ITERS").ok().and_then(|v| v.parse().ok()) {
        replay.solver.iterations = n;
    }
    if let Some(n) = std::env::var("SUBSTEPS").ok().and_then(|v| v.parse().ok()) {
        replay.solver.substeps = n;
    }
    let mut sim = saved.restore(replay).expect("restore");
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
}
