//! How many Newton iterations do a scene's frames take? Plays a scene and prints the
//! iterations per awake frame as a histogram (the last bin: 11 or more, reused-factorization
//! iterations included), with the frame time's median, p99 and mean, the largest strain,
//! halvings per frame, c_mean and the frames undone by the pass-through guard.
//!
//! `cargo run --release -p papier-lab -- iter-hist [NAME[@SEED]|FILE.toml] [TOL]` (default
//! c5_full_crumple, Newton tolerance 1e-6 m); `COUPLING=N` (`SolverConfig::contact_coupling_pairs`),
//! `NOGEOM=1` (geometry layer off), `REUSE=0` (`SolverConfig::reuse_factor` off), `INS_STRAIN=X`
//! (`GeometryConfig::insertion_max_start_strain`, `inf` = off); `NEWTON_TRACE=1` prints every
//! frame's iterations on stderr (every 100th frame's always are).

use sim_core::sim::SimConfig;

use crate::args::{at_most, env_is, env_num, nth};
use crate::play::Play;

pub const USAGE: &str = "[NAME[@SEED]|FILE.toml] [TOL]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 2)?;
    let name = args.first().map_or("c5_full_crumple", String::as_str);
    let tol: f64 = nth(args, 1, "TOL")?.unwrap_or(1e-6);
    let mut cfg = SimConfig::default();
    cfg.solver.tolerance_m = tol;
    if let Some(n) = env_num("COUPLING") {
        cfg.solver.contact_coupling_pairs = n;
    }
    if let Some(x) = env_num("INS_STRAIN") {
        cfg.geometry.insertion_max_start_strain = x;
    }
    if env_is("REUSE", "0") {
        cfg.solver.reuse_factor = false;
    }
    if std::env::var_os("NOGEOM").is_some() {
        cfg.geometry.enabled = false;
    }
    let trace = std::env::var_os("NEWTON_TRACE").is_some();
    let mut p = Play::scene(name, cfg)?;
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
        if !p.frame() {
            break;
        }
        t += t0.elapsed().as_nanos();
        let s = &p.out.stats;
        if s.asleep {
            continue;
        }
        frames += 1;
        times.push(t0.elapsed().as_nanos());
        maxs = maxs.max(s.max_strain);
        hist[s.iterations.min(11) as usize] += 1;
        halv += u64::from(s.halvings);
        undone += u32::from(s.undo_streak > 0);
        relaxed += u32::from(s.relaxed_undone);
        kept += u32::from(s.kept_crossed_start);
        cm += f64::from(s.c_mean_pct);
        let frame = p.out.sound.frame;
        if trace {
            eprintln!(
                "END f{frame} it {} undo {} vmax {:.4} ke {:.3e}",
                s.iterations, s.undo_streak, s.max_speed_m_s, s.kinetic_energy_j
            );
        }
        if frame % 100 == 0 {
            eprintln!("SQ f{frame} {:?}", p.sim.crumple_squeeze());
            eprintln!(
                "f{frame} it {} halv {} undo {}",
                s.iterations, s.halvings, s.undo_streak
            );
        }
    }
    anyhow::ensure!(!times.is_empty(), "{name}: the sheet never woke up");
    times.sort();
    let med = times[times.len() / 2] as f64 / 1e6;
    let p99 = times[times.len() * 99 / 100] as f64 / 1e6;
    println!(
        "{name:28} tol {tol:e}: med {med:.3} p99 {p99:.3} maxstrain {maxs:.3} {:?} halv/f {:.2} c_mean {:.4} % sing {} mean {:.3} ms fb {} undone {} relaxed {} kept_crossed {}",
        hist,
        halv as f64 / frames as f64,
        cm / frames as f64,
        p.out.stats.num_singular,
        t as f64 / frames as f64 / 1e6,
        0,
        undone,
        relaxed,
        kept
    );
    Ok(())
}
