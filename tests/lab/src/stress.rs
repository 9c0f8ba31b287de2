//! Does the sim keep its invariants over a long hostile run? The long stress run (10⁶ frames by
//! default) of [`sim_core::stress`]: random, partly absurd commands (gestures, grabs, sizes,
//! materials, seeds, rooms) frame after frame.
//!
//! ```text
//! cargo run --release -p papier-lab -- stress [--frames N] [--seed S] [--sessions K]
//!     [--stretch-scale K] [--no-geometry] [--contact-coupling N] [--no-reuse]
//!     [--restore-check-every N] [--restore-check-frames N] [--trace]
//! ```
//!
//! `--no-reuse` turns off the reused factorizations (`SolverConfig::reuse_factor`);
//! `--contact-coupling N` sets `SolverConfig::contact_coupling_pairs` (0: the contact pairs'
//! diagonal Hessian blocks only); `--restore-check-every N` saves and restores the sheet every
//! N frames (default 1000, 0: never) and checks that the restored sheet continues bit-identically,
//! with the same sound input, for the next `--restore-check-frames` frames (default 4).
//!
//! The frames are split into `K` sessions with seeds `S, S+1, …` (each a fresh sheet, sizes
//! and materials changing within a session). Exits with status 1 on the first violated
//! invariant (non-finite state, flipped triangle, recovered substep, speed or strain out of
//! bounds, invalid mesh, a restored sheet that does not continue bit-identically).

use std::time::Instant;

use sim_core::sim::SimConfig;
use sim_core::stress::{StressConfig, run as stress_run};

use crate::args::{bad, parse};

pub const USAGE: &str = "[--frames N] [--seed S] [--sessions K] [--stretch-scale K] [--no-geometry] [--contact-coupling N] [--no-reuse] [--restore-check-every N] [--restore-check-frames N] [--trace]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    let mut frames: u64 = 1_000_000;
    let mut seed: u64 = 1;
    let mut sessions: u64 = 20;
    let mut trace = false;
    let mut restore_check_every: u64 = 1000;
    let mut restore_check_frames: u64 = 4;
    let mut geometry = true;
    let mut reuse = true;
    let mut coupling: Option<u32> = None;
    let mut stretch_scale: Option<f64> = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut val = || {
            it.next()
                .map(String::as_str)
                .ok_or_else(|| bad(format!("{a} needs a value")))
        };
        match a.as_str() {
            "--frames" => frames = parse(val()?, a)?,
            "--seed" => seed = parse(val()?, a)?,
            "--sessions" => sessions = parse(val()?, a)?,
            "--trace" => trace = true,
            "--restore-check-every" => restore_check_every = parse(val()?, a)?,
            "--restore-check-frames" => restore_check_frames = parse(val()?, a)?,
            "--no-geometry" => geometry = false,
            "--no-reuse" => reuse = false,
            "--contact-coupling" => coupling = Some(parse(val()?, a)?),
            "--stretch-scale" => stretch_scale = Some(parse(val()?, a)?),
            other => return Err(bad(format!("unknown argument {other}"))),
        }
    }
    let sessions = sessions.max(1);
    let per = frames.div_ceil(sessions);
    let t0 = Instant::now();
    let mut total = 0u64;
    let (mut vmax, mut kemax, mut strain, mut asleep, mut cmds) =
        (0.0f64, 0.0f64, 0.0f64, 0u64, 0u64);
    for s in 0..sessions {
        let mut sim = SimConfig::default();
        sim.geometry.enabled = geometry;
        sim.solver.reuse_factor = reuse;
        if let Some(k) = stretch_scale {
            sim.solver.stretch_scale = k;
        }
        if let Some(n) = coupling {
            sim.solver.contact_coupling_pairs = n;
        }
        let cfg = StressConfig {
            seed: seed + s,
            frames: per.min(frames - total),
            sim,
            change_size: true,
            validate_every: 1000,
            restore_check_every,
            restore_check_frames,
            trace,
        };
        let r = stress_run(&cfg);
        total += r.frames;
        vmax = vmax.max(r.max_speed_m_s);
        kemax = kemax.max(r.max_kinetic_energy_j);
        strain = strain.max(r.max_strain);
        asleep += r.asleep_frames;
        cmds += r.commands;
        println!(
            "session {s:3} seed {:3}: {:7} frames, {:6} commands, {:6} asleep, vmax {:6.2} m/s, KE {:.2e} J, strain {:.3}, flips {}, recoveries {}, singular ≤ {}, c_mean ≤ {:.3} %, vertices ≤ {}, {} holds (asleep ≤ {} frames after the rig stopped)",
            seed + s,
            r.frames,
            r.commands,
            r.asleep_frames,
            r.max_speed_m_s,
            r.max_kinetic_energy_j,
            r.max_strain,
            r.flips,
            r.recoveries,
            r.max_singular,
            r.max_c_mean_pct,
            r.max_vertices,
            r.holds,
            r.max_settle_frames
        );
        if let Some((f, msg)) = r.failure {
            anyhow::bail!("FAIL: session {s} (seed {}), frame {f}: {msg}", seed + s);
        }
        if total >= frames {
            break;
        }
    }
    let secs = t0.elapsed().as_secs_f64();
    println!(
        "OK: {total} frames ({cmds} commands, {asleep} asleep) in {secs:.1} s ({:.3} ms/frame); max speed {vmax:.2} m/s, max KE {kemax:.2e} J, max strain {strain:.3}; no NaN, no flipped triangle, no recovery, mesh valid, singular counts never decreased, c_mean bounded, saved sheets continued bit-identically with the same sound input, every hold came to rest",
        secs * 1e3 / total.max(1) as f64
    );
    Ok(())
}
