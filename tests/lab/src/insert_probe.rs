//! Do singular points sit at their drawn position, with and without vertex insertion
//! (`GeometryConfig::insert_singular_vertices`)? Plays each scene in both modes and prints a
//! table: singular points, how many sit exactly at s̄ (pattern distance < 1 µm) and the
//! largest distance, S_P vertices inserted, final mesh size, mean c_mean and worst strain over
//! the awake frames, deepest crumple squeeze, undone frames and the wall time.
//!
//! `cargo run --release -p papier-lab -- insert-probe [NAME[@SEED]|FILE.toml ...]` (default:
//! every library scenario; `ISO=0`: isometry step off; `COUPLING=N`:
//! `SolverConfig::contact_coupling_pairs`; `STOP=step`: Newton stops on its last step alone,
//! `SolverConfig::stop_on_error_estimate`; `REUSE=0`: no reused factorizations,
//! `SolverConfig::reuse_factor`; `PAPIER_TRACE[=STRAIN]`: on stderr, the worst edge of every
//! frame strained beyond STRAIN, default 0.12; `PAPIER_TRACE_SQUEEZE=1`: on stderr, the squeeze
//! every 25 frames).

use std::time::Instant;

use sim_core::sim::SimConfig;

use crate::args::{env_is, env_num};
use crate::play::{self, Play};

pub const USAGE: &str = "[NAME[@SEED]|FILE.toml ...]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    let names = play::scenes_or_all(args);
    // `PAPIER_TRACE[=STRAIN]`: the worst edge of every frame strained beyond STRAIN
    // (default 0.12).
    let trace_above = std::env::var("PAPIER_TRACE")
        .ok()
        .map(|v| v.parse::<f32>().unwrap_or(0.12));
    let trace_squeeze = std::env::var("PAPIER_TRACE_SQUEEZE").is_ok();
    println!(
        "| scene | insertion | singular | at s̄ | max dist mm | inserted | vertices / triangles | c_mean % | max strain | deepest squeeze | undone frames | ms/frame |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for name in &names {
        let script = play::script(name)?;
        for insert in [false, true] {
            let mut cfg = SimConfig::default();
            cfg.geometry.insert_singular_vertices = insert;
            if env_is("ISO", "0") {
                cfg.geometry.isometry.enabled = false;
            }
            if let Some(n) = env_num("COUPLING") {
                cfg.solver.contact_coupling_pairs = n;
            }
            if env_is("REUSE", "0") {
                cfg.solver.reuse_factor = false;
            }
            if env_is("STOP", "step") {
                cfg.solver.stop_on_error_estimate = false;
            }
            let mut p = Play::new(&script, cfg)?;
            let (mut c_sum, mut awake, mut strain) = (0.0f64, 0u64, 0.0f32);
            let mut deepest = 0.0f64;
            let mut undone = 0u64;
            let t0 = Instant::now();
            while p.frame() {
                let (s, sim) = (&p.out.stats, &p.sim);
                if !s.asleep {
                    c_sum += f64::from(s.c_mean_pct);
                    awake += 1;
                    strain = strain.max(s.max_strain);
                }
                if trace_above.is_some_and(|a| s.max_strain > a) {
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
                        "f {} strain {:.3} worst edge {:?} ratio {worst:.3} rest {:.4} m, angle {:.3}, damage {:.2}, singular {:?}",
                        sim.frame(),
                        s.max_strain,
                        ed.v,
                        sp.edge_rest_len_m[we],
                        sp.edge_rest_angle[we],
                        sp.edge_damage[we],
                        ed.v.map(|v| sp.singular.contains(&v)),
                    );
                }
                undone += u64::from(s.undo_streak > 0);
                let (sq, lim) = sim.crumple_squeeze();
                deepest = deepest.max(sq.min(lim));
                if trace_squeeze && sim.frame().is_multiple_of(25) {
                    eprintln!(
                        "f {} squeeze {sq:.3} limit {lim:.3} singular {} nv {}",
                        sim.frame(),
                        sim.geometry().singular.len(),
                        sim.sheet().sp.num_vertices()
                    );
                }
            }
            let ms = t0.elapsed().as_secs_f64() * 1e3 / awake.max(1) as f64;
            let g = p.sim.geometry();
            let dists: Vec<f64> = g
                .singular
                .iter()
                .map(|s| (s.pos2 - s.sampled2).norm())
                .collect();
            let exact = dists.iter().filter(|&&d| d < 1e-6).count();
            let dmax = dists.iter().copied().fold(0.0, f64::max);
            let sp = &p.sim.sheet().sp;
            println!(
                "| {name} | {} | {} | {exact} | {:.1} | {} | {} / {} | {:.4} | {:.3} | {deepest:.2} | {undone} | {:.3} |",
                if insert { "on" } else { "off" },
                g.singular.len(),
                dmax * 1e3,
                p.sim.inserted_vertices(),
                sp.num_vertices(),
                sp.num_triangles(),
                c_sum / awake.max(1) as f64,
                strain,
                ms
            );
        }
    }
    Ok(())
}
