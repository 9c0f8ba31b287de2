//! Development probe: singular points at their drawn position, with and without vertex
//! insertion (`GeometryConfig::insert_singular_vertices`), per seed scene.
//!
//! `cargo run --release -p sim-core --example insert_probe [-- NAME[@SEED]...]` (`ISO=0`: isometry
//! step off; `CUT=1`: strip cutting on, `GeometryConfig::cut_strips`, the strips cut shown after
//! the vertices inserted, with the vertices coarsening took out again; `COUPLING=N`: `SolverConfig::contact_coupling_pairs`;
//! `STOP=step`: Newton stops on its last step alone, `SolverConfig::stop_on_error_estimate`;
//! `REUSE=0`: no reused factorizations, `SolverConfig::reuse_factor`)
//!
//! Per scene and mode: singular points, how many sit exactly at s̄ (pattern distance
//! < 1 µm) and the largest distance, S_P vertices inserted, final mesh size, mean c_mean and
//! worst strain over the awake frames, and the wall time.
use std::time::Instant;

use sim_core::room::RoomConfig;
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<String> = if args.is_empty() {
        scenario::names().map(str::to_string).collect()
    } else {
        args
    };
    println!(
        "| scene | insertion | singular | at s̄ | max dist mm | inserted | vertices / triangles | c_mean % | max strain | deepest squeeze | undone frames | ms/frame |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for arg in &names {
        // `NAME@SEED` plays the scene with another seed.
        let script = scenario::get_seeded(arg).expect("scenario");
        let name = arg;
        for insert in [false, true] {
            let mut cfg = SimConfig::default();
            cfg.geometry.insert_singular_vertices = insert;
            if std::env::var("ISO").is_ok_and(|v| v == "0") {
                cfg.geometry.isometry.enabled = false;
            }
            let cut = std::env::var("CUT").is_ok_and(|v| v == "1");
            cfg.geometry.cut_strips = cut;
            if let Some(n) = std::env::var("COUPLING").ok().and_then(|v| v.parse().ok()) {
                cfg.solver.contact_coupling_pairs = n;
            }
            if std::env::var("REUSE").is_ok_and(|v| v == "0") {
                cfg.solver.reuse_factor = false;
            }
            if std::env::var("STOP").is_ok_and(|v| v == "step") {
                cfg.solver.stop_on_error_estimate = false;
            }
            let mut runner = ScriptRunner::new(&script, cfg.frame_rate_hz, RoomConfig::default())
                .expect("runner");
            let mut sim = runner.start(cfg);
            let mut out = FrameOutput::default();
            let (mut c_sum, mut awake, mut strain) = (0.0f64, 0u64, 0.0f32);
            let mut deepest = 0.0f64;
            let mut undone = 0u64;
            let t0 = Instant::now();
            while runner.drive(&mut sim, &mut out) {
                if !out.stats.asleep {
                    c_sum += f64::from(out.stats.c_mean_pct);
                    awake += 1;
                    strain = strain.max(out.stats.max_strain);
                }
                // `PAPIER_TRACE[=STRAIN]`: the worst edge of every frame strained beyond STRAIN
                // (default 0.12).
                let trace_above = std::env::var("PAPIER_TRACE")
                    .ok()
                    .map(|v| v.parse::<f32>().unwrap_or(0.12));
                if trace_above.is_some_and(|a| out.stats.max_strain > a) {
                    let sp = &sim.sheet().sp;
                    let (mut worst, mut we) = (0.0f64, 0usize);
                    for e in 0..sp.num_edges() {
                        let r = sp.edge_length_m(e) / sp.edge_rest_len_m[e] - 1.0;
                        if r.abs() > worst.abs() {
                            (worst, we) = (r, e);
                        }
                    }
                    let ed = sp.topo.edges[we];
                    eprintln!(
                        "f {} strain {:.3} worst edge {:?} ratio {worst:.3} rest {:.4} m, angle {:.3}, damage {:.2}, singular {:?}, cuts so far {}",
                        sim.frame(),
                        out.stats.max_strain,
                        ed.v,
                        sp.edge_rest_len_m[we],
                        sp.edge_rest_angle[we],
                        sp.edge_damage[we],
                        ed.v.map(|v| sp.singular.contains(&v)),
                        sim.cut_strips()
                    );
                }
                undone += u64::from(out.stats.undo_streak > 0);
                let (sq, lim) = sim.crumple_squeeze();
                deepest = deepest.max(sq.min(lim));
                if std::env::var("PAPIER_TRACE_SQUEEZE").is_ok() && sim.frame().is_multiple_of(25) {
                    eprintln!(
                        "f {} squeeze {sq:.3} limit {lim:.3} singular {} nv {}",
                        sim.frame(),
                        sim.geometry().singular.len(),
                        sim.sheet().sp.num_vertices()
                    );
                }
            }
            let ms = t0.elapsed().as_secs_f64() * 1e3 / awake.max(1) as f64;
            let g = sim.geometry();
            let dists: Vec<f64> = g
                .singular
                .iter()
                .map(|s| (s.pos2 - s.sampled2).norm())
                .collect();
            let exact = dists.iter().filter(|&&d| d < 1e-6).count();
            let dmax = dists.iter().copied().fold(0.0, f64::max);
            let sp = &sim.sheet().sp;
            println!(
                "| {name} | {} | {} | {exact} | {:.1} | {}{} | {} / {} | {:.4} | {:.3} | {deepest:.2} | {undone} | {:.3} |",
                if insert { "on" } else { "off" },
                g.singular.len(),
                dmax * 1e3,
                sim.inserted_vertices(),
                if cut {
                    format!(
                        " + {} cuts, {} vertices taken out",
                        sim.cut_strips(),
                        sim.collapsed_vertices()
                    )
                } else {
                    String::new()
                },
                sp.num_vertices(),
                sp.num_triangles(),
                c_sum / awake.max(1) as f64,
                strain,
                ms
            );
        }
    }
}
