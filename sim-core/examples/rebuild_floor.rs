//! What rebuilding S_P every frame costs when nothing about it changes: the floor under any
//! per-frame regeneration of S_P (issue 4, deliverable 8; `docs/sp-regeneration-plan.md`).
//!
//! Each scene is played twice: as usual, and with the sheet saved and restored before every
//! frame (`Sim::save` → `Sim::restore`: the mesh adopted again with its state, the solver and
//! its symbolic factorization, the geometry layer, the rig and the per-vertex buffers rebuilt,
//! every cache between frames dropped). The restored sheet continues bit-identically, so both
//! runs play the same frames and the difference is the rebuild alone. Prints, over the awake
//! frames, the median and 99th percentile of the frame as usual, of the frame after a rebuild,
//! and of the rebuild, and whether the two runs ended in the same state.
//!
//! `cargo run --release -p sim-core --example rebuild_floor -- [NAME[@SEED]]...` (default
//! `c5_full_crumple s4_crumple`)

use std::time::Instant;

use sim_core::scenario;
use sim_core::scenario_run::state_hash;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, Sim, SimConfig};

fn quantile(v: &mut [f64], q: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

/// Plays `run`; with `rebuild`, restores the sheet from its save before every frame. Returns
/// the awake frames' step times and rebuild times (ms) and the final state hash.
fn play(run: &str, rebuild: bool) -> (Vec<f64>, Vec<f64>, u64) {
    let script = scenario::get_seeded(run).expect("scene");
    let base = SimConfig::default();
    let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
    let cfg = runner.config(base);
    let mut sim = runner.start(base);
    let mut out = FrameOutput::default();
    let (mut steps, mut rebuilds) = (Vec::new(), Vec::new());
    loop {
        let mut rebuild_ms = 0.0;
        if rebuild {
            let t = Instant::now();
            let saved = sim.save();
            sim = Sim::restore(cfg, &saved).expect("restore");
            rebuild_ms = t.elapsed().as_secs_f64() * 1e3;
        }
        let t = Instant::now();
        if !runner.drive(&mut sim, &mut out) {
            break;
        }
        let step_ms = t.elapsed().as_secs_f64() * 1e3;
        if !out.stats.asleep {
            steps.push(step_ms);
            rebuilds.push(rebuild_ms);
        }
    }
    (steps, rebuilds, state_hash(&sim))
}

fn main() {
    let mut runs: Vec<String> = std::env::args().skip(1).collect();
    if runs.is_empty() {
        runs = vec!["c5_full_crumple".into(), "s4_crumple".into()];
    }
    println!(
        "| scene | awake frames | frame: median / p99 ms | after a rebuild: median / p99 ms | rebuild: median / p99 ms | rebuild + frame: median ms | same end state |"
    );
    println!("|---|---|---|---|---|---|---|");
    for run in &runs {
        let (mut a, _, ha) = play(run, false);
        let (b, r, hb) = play(run, true);
        let mut total: Vec<f64> = b.iter().zip(&r).map(|(x, y)| x + y).collect();
        let (mut b, mut r) = (b, r);
        println!(
            "| {run} | {} | {:.3} / {:.3} | {:.3} / {:.3} | {:.3} / {:.3} | {:.3} | {} |",
            a.len(),
            quantile(&mut a, 0.5),
            quantile(&mut a, 0.99),
            quantile(&mut b, 0.5),
            quantile(&mut b, 0.99),
            quantile(&mut r, 0.5),
            quantile(&mut r, 0.99),
            quantile(&mut total, 0.5),
            if ha == hb { "yes" } else { "no" }
        );
    }
}
