//! Which effect has a solver configuration on every library scenario? Runs each scenario with
//! the configuration given on the command line and prints a one-line summary per scenario
//! (timing, length error, health, and the final state hash: a change that must not alter the
//! simulation leaves every hash as it was).
//!
//! `cargo run --release -p papier-lab -- scenario-probe [newton SUBSTEPS ITERS [STRETCH_SCALE]
//! [SPACING_FRAC] [SCENE]]` (`SCENE`: one scene alone, `NAME`, `NAME@SEED` or `FILE.toml`);
//! `SHEET_CONTACT=0` switches sheet–sheet contact off, `INSERT=0` vertex insertion at singular
//! points, `FLIP=0` edge flips; `TOL=METRES` sets the Newton tolerance, `STOP=step` stops Newton
//! on the last step alone.

use sim_core::scenario_run::run_script;
use sim_core::sim::SimConfig;

use crate::args::{at_most, bad, env_is, env_num, nth};
use crate::play;

pub const USAGE: &str = "[newton SUBSTEPS ITERS [STRETCH_SCALE] [SPACING_FRAC] [SCENE]]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 6)?;
    let mut cfg = SimConfig::default();
    if let Some(k) = args.first()
        && k != "newton"
    {
        return Err(bad(format!(
            "the solver is newton (the only one), not {k:?}"
        )));
    }
    if let Some(s) = nth(args, 1, "SUBSTEPS")? {
        cfg.solver.substeps = s;
    }
    if let Some(s) = nth(args, 2, "ITERS")? {
        cfg.solver.iterations = s;
    }
    if let Some(s) = nth(args, 3, "STRETCH_SCALE")? {
        cfg.solver.stretch_scale = s;
    }
    if let Some(s) = nth(args, 4, "SPACING_FRAC")? {
        cfg.mesh.spacing_frac = s;
    }
    if env_is("SHEET_CONTACT", "0") {
        cfg.solver.sheet_contact = false;
    }
    if env_is("INSERT", "0") {
        cfg.geometry.insert_singular_vertices = false;
    }
    if env_is("FLIP", "0") {
        cfg.geometry.flip_compressed_edges = false;
    }
    if let Some(t) = env_num("TOL") {
        cfg.solver.tolerance_m = t;
    }
    if env_is("STOP", "step") {
        cfg.solver.stop_on_error_estimate = false;
    }
    let scenes = play::scenes_or_all(&args[args.len().min(5)..]);
    // Every scene loads before the first runs: a bad name fails at once.
    let scripts = scenes
        .iter()
        .map(|n| play::script(n))
        .collect::<anyhow::Result<Vec<_>>>()?;
    println!("{:?}", cfg.solver);
    for (name, script) in scenes.iter().zip(&scripts) {
        let s = run_script(script, cfg, true)?;
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
    Ok(())
}
