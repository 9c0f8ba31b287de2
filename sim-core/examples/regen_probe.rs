//! S_P regenerated from S_G every frame against the default event-driven S_P (issue 4,
//! deliverable 8; [`sim_core::sheet::regenerate`], `GeometryConfig::regenerate_sp`).
//!
//! Plays each scene twice, with regeneration off and on, and prints over the awake frames the
//! median and 99th percentile of the frame time with the median physics, geometry and
//! regeneration phases, the mean and largest c_mean (edge-length error against the pattern,
//! %), the mean n_comp (%), the singular points at the end, the mean and largest S_P
//! (triangles), and how many regenerations were adopted, gave S_P back unchanged, and were
//! refused (by reason, [`sim_core::sim::RegenCounts`]).
//!
//! `cargo run --release -p sim-core --example regen_probe -- [--regenerated-only]
//! [NAME[@SEED]]...` (default: every seed scene, both modes)

use std::time::Instant;

use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, RegenCounts, SimConfig};

fn quantile(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

struct Run {
    ms: Vec<f64>,
    c_mean: Vec<f64>,
    n_comp: Vec<f64>,
    singular: u32,
    max_tris: u32,
    regen: RegenCounts,
    finite: bool,
    /// Per awake frame: physics, geometry (with the regeneration), regeneration, ms.
    phases: [Vec<f64>; 3],
    tris: Vec<f64>,
}

fn play(run: &str, regen: bool) -> Run {
    let script = scenario::get_seeded(run).expect("scene");
    let mut base = SimConfig::default();
    base.geometry.regenerate_sp = regen;
    let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
    let mut sim = runner.start(base);
    let mut out = FrameOutput::default();
    let mut r = Run {
        ms: Vec::new(),
        c_mean: Vec::new(),
        n_comp: Vec::new(),
        singular: 0,
        max_tris: 0,
        regen: RegenCounts::default(),
        finite: true,
        phases: Default::default(),
        tris: Vec::new(),
    };
    sim.set_phase_timing(true);
    loop {
        let t = Instant::now();
        if !runner.drive(&mut sim, &mut out) {
            break;
        }
        let ms = t.elapsed().as_secs_f64() * 1e3;
        if !out.stats.asleep {
            r.ms.push(ms);
            r.c_mean.push(f64::from(out.stats.c_mean_pct));
            r.n_comp.push(f64::from(out.stats.n_comp_pct));
            let p = sim.phase_times();
            for (v, ns) in r
                .phases
                .iter_mut()
                .zip([p.physics_ns, p.geometry_ns, p.regeneration_ns])
            {
                v.push(ns as f64 * 1e-6);
            }
            r.tris.push(f64::from(out.stats.num_triangles));
        }
        r.finite &= sim
            .sheet()
            .sp
            .pos
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite()));
        r.max_tris = r.max_tris.max(out.stats.num_triangles);
        r.singular = out.stats.num_singular;
    }
    r.regen = sim.regenerations();
    r
}

fn main() {
    let mut runs: Vec<String> = std::env::args().skip(1).collect();
    let only_regenerated = runs.iter().any(|a| a == "--regenerated-only");
    runs.retain(|a| a != "--regenerated-only");
    if runs.is_empty() {
        runs = scenario::names().map(|s| s.to_string()).collect();
    }
    println!(
        "| scene | S_P | awake frames | frame median / p99 ms | physics / geometry / regeneration median ms | c_mean mean / max % | n_comp mean % | singular | S_P triangles mean / max | regenerations adopted / unchanged / refused | refused: thin / outside / merged / invalid / capacity / crossing / adoption | finite |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for run in &runs {
        for regen in [false, true] {
            if !regen && only_regenerated {
                continue;
            }
            let mut r = play(run, regen);
            let n = r.c_mean.len().max(1) as f64;
            println!(
                "| {run} | {} | {} | {:.3} / {:.3} | {:.3} / {:.3} / {:.3} | {:.4} / {:.4} | {:.3} | {} | {:.0} / {} | {} / {} / {} | {} / {} / {} / {} / {} / {} / {} | {} |",
                if regen { "regenerated" } else { "event-driven" },
                r.ms.len(),
                quantile(&mut r.ms, 0.5),
                quantile(&mut r.ms, 0.99),
                quantile(&mut r.phases[0], 0.5),
                quantile(&mut r.phases[1], 0.5),
                quantile(&mut r.phases[2], 0.5),
                r.c_mean.iter().sum::<f64>() / n,
                r.c_mean.iter().copied().fold(0.0, f64::max),
                r.n_comp.iter().sum::<f64>() / n,
                r.singular,
                r.tris.iter().sum::<f64>() / n,
                r.max_tris,
                r.regen.adopted,
                r.regen.unchanged,
                r.regen.refused(),
                r.regen.thin,
                r.regen.outside,
                r.regen.merged,
                r.regen.invalid,
                r.regen.capacity,
                r.regen.crossing,
                r.regen.adoption,
                r.finite,
            );
        }
    }
}
