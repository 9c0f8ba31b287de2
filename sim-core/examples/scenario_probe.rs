//! Runs every library scenario with a solver configuration given on the command line and
//! prints a one-line summary per scenario (timing, length error, health, and the final state
//! hash: a change that must not alter the simulation leaves every hash as it was).
//!
//! `cargo run --release -p sim-core --example scenario_probe -- [newton|xpbd] SUBSTEPS ITERS
//! [STRETCH_SCALE] [SPACING_FRAC] [SCENARIO]`; `SHEET_CONTACT=0` switches sheet–sheet contact
//! off, `INSERT=0` vertex insertion at singular points, `FLIP=0` edge flips; `CUT=1` turns strip
//! cutting on; `TOL=METRES` sets the Newton tolerance, `STOP=step` stops Newton on the last step alone.

use sim_core::physics::SolverKind;
use sim_core::scenario;
use sim_core::scenario_run::run_scenario;
use sim_core::sim::SimConfig;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut cfg = SimConfig::default();
    if let Some(k) = args.first() {
        cfg.solver.kind = if k == "xpbd" {
            SolverKind::Xpbd
        } else {
            SolverKind::Newton
        };
    }
    if let Some(s) = args.get(1) {
        cfg.solver.substeps = s.parse().expect("substeps");
    }
    if let Some(s) = args.get(2) {
        cfg.solver.iterations = s.parse().expect("iterations");
    }
    if let Some(s) = args.get(3) {
        cfg.solver.stretch_scale = s.parse().expect("stretch scale");
    }
    if let Some(s) = args.get(4) {
        cfg.mesh.spacing_frac = s.parse().expect("spacing");
    }
    let only = args.get(5).cloned();
    if std::env::var("SHEET_CONTACT").is_ok_and(|v| v == "0") {
        cfg.solver.sheet_contact = false;
    }
    if std::env::var("INSERT").is_ok_and(|v| v == "0") {
        cfg.geometry.insert_singular_vertices = false;
    }
    if std::env::var("FLIP").is_ok_and(|v| v == "0") {
        cfg.geometry.flip_compressed_edges = false;
    }
    if let Some(t) = std::env::var("TOL").ok().and_then(|v| v.parse().ok()) {
        cfg.solver.tolerance_m = t;
    }
    if std::env::var("STOP").is_ok_and(|v| v == "step") {
        cfg.solver.stop_on_error_estimate = false;
    }
    if std::env::var("CUT").is_ok_and(|v| v == "1") {
        cfg.geometry.cut_strips = true;
    }
    println!("{:?}", cfg.solver);
    for name in scenario::names() {
        if only.as_deref().is_some_and(|o| o != name) {
            continue;
        }
        let s = run_scenario(name, cfg, true).expect("scenario");
        println!(
            "{name:30} tris {:4.0} awake {:4}/{:4} med {:6.3} p99 {:6.3} ms geom {:6.3} ms  c_mean {:6.3}% n_comp {:6.2}% strain {:6.3} it/sub {:4.2} flips {} rec {} vmax {:5.2} ke {:.2e} contact {:6.3} ms geometry {:016x} hash {:016x}",
            s.triangles_avg,
            s.awake_frames,
            s.frames,
            s.step_ms_quantile(0.5),
            s.step_ms_quantile(0.99),
            s.geometry_ms_quantile(0.5),
            s.c_mean_pct,
            s.n_comp_pct,
            s.max_strain,
            s.iterations_per_substep,
            s.flips,
            s.recoveries,
            s.max_speed_m_s,
            s.kinetic_energy_max_j,
            s.phase_ns.iter().map(|p| p.self_contact_ns).sum::<u64>() as f64
                / 1e6
                / s.awake_frames.max(1) as f64,
            s.geometry_hash,
            s.final_hash
        );
    }
}
