//! Newton iterations per frame of a scene (`NAME` or `NAME@SEED`), as a histogram (the last
//! bin: 11 or more, reused-factorization iterations included); `COUPLING=N`, `NOGEOM=1`,
//! `REUSE=0` (`SolverConfig::reuse_factor` off), `INS_STRAIN=X`
//! (`GeometryConfig::insertion_max_start_strain`, `inf` = off), `CUT=0|1`
//! (`GeometryConfig::cut_strips` off / on).
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};
fn main() {
    let name = std::env::args().nth(1).unwrap_or("c5_full_crumple".into());
    let tol: f64 = std::env::args().nth(2).map_or(1e-6, |s| s.parse().unwrap());
    let script = if name.ends_with(".toml") {
        sim_core::script::Script::from_file(std::path::Path::new(&name)).unwrap()
    } else {
        scenario::get_seeded(&name).unwrap()
    };
    let mut cfg = SimConfig::default();
    cfg.solver.tolerance_m = tol;
    if let Some(n) = std::env::var("COUPLING").ok().and_then(|v| v.parse().ok()) {
        cfg.solver.contact_coupling_pairs = n;
    }
    if let Some(x) = std::env::var("INS_STRAIN")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        cfg.geometry.insertion_max_start_strain = x;
    }
    if std::env::var("REUSE").is_ok_and(|v| v == "0") {
        cfg.solver.reuse_factor = false;
    }
    match std::env::var("CUT").as_deref() {
        Ok("0") => cfg.geometry.cut_strips = false,
        Ok("1") => cfg.geometry.cut_strips = true,
        _ => {}
    }
    if std::env::var_os("NOGEOM").is_some() {
        cfg.geometry.enabled = false;
    }
    let mut runner = ScriptRunner::new(&script, cfg.frame_rate_hz, cfg.room).unwrap();
    let mut sim = runner.start(cfg);
    let mut out = FrameOutput::default();
    let mut hist = [0u32; 12];
    let mut times: Vec<u128> = Vec::new();
    let mut maxs = 0f32;
    let mut undone = 0u32;
    let mut relaxed = 0u32;
    let mut kept = 0u32;
    let mut halv = 0u64;
    let mut frames = 0;
    let mut cm = 0.0;
    let mut t = 0u128;
    loop {
        let t0 = std::time::Instant::now();
        if !runner.drive(&mut sim, &mut out) {
            break;
        }
        t += t0.elapsed().as_nanos();
        if out.stats.asleep {
            continue;
        }
        frames += 1;
        times.push(t0.elapsed().as_nanos());
        maxs = maxs.max(out.stats.max_strain);
        hist[out.stats.iterations.min(11) as usize] += 1;
        halv += u64::from(out.stats.halvings);
        undone += u32::from(out.stats.undo_streak > 0);
        relaxed += u32::from(out.stats.relaxed_undone);
        kept += u32::from(out.stats.kept_crossed_start);
        cm += f64::from(out.stats.c_mean_pct);
        if std::env::var_os("NEWTON_TRACE").is_some() {
            eprintln!(
                "END f{} it {} undo {} vmax {:.4} ke {:.3e}",
                out.sound.frame,
                out.stats.iterations,
                out.stats.undo_streak,
                out.stats.max_speed_m_s,
                out.stats.kinetic_energy_j
            );
        }
        if out.sound.frame % 100 == 0 {
            eprintln!("SQ f{} {:?}", out.sound.frame, sim.crumple_squeeze());
        }
        if out.sound.frame % 100 == 0 {
            eprintln!(
                "f{} it {} halv {} undo {}",
                out.sound.frame, out.stats.iterations, out.stats.halvings, out.stats.undo_streak
            );
        }
    }
    times.sort();
    let med = times[times.len() / 2] as f64 / 1e6;
    let p99 = times[times.len() * 99 / 100] as f64 / 1e6;
    println!(
        "{name:28} tol {tol:e}: med {med:.3} p99 {p99:.3} maxstrain {maxs:.3} {:?} halv/f {:.2} c_mean {:.4} % sing {} mean {:.3} ms fb {} undone {} relaxed {} kept_crossed {}",
        hist,
        halv as f64 / frames as f64,
        cm / frames as f64,
        out.stats.num_singular,
        t as f64 / frames as f64 / 1e6,
        0,
        undone,
        relaxed,
        kept
    );
}
