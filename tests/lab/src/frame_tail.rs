//! Which frames of a scene are the slowest, and where does their time go (the p99 target)?
//! Lists the slowest awake frames with their phases, Newton iterations and whether the step
//! adopted a new mesh, after the scene's median, p99 and maximum and each phase's median.
//!
//! `cargo run --release -p papier-lab -- frame-tail [NAME[@SEED]|FILE.toml] [TOP]` (default
//! c5_full_crumple, the top 20); `REPLAYS=N` keeps each frame's minimum over N runs.

use sim_core::sim::{PhaseTimes, SimConfig};

use crate::args::{at_most, env_num, nth};
use crate::play::{self, Play};

pub const USAGE: &str = "[NAME[@SEED]|FILE.toml] [TOP]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 2)?;
    let name = args.first().map_or("c5_full_crumple", String::as_str);
    let top: usize = nth(args, 1, "TOP")?.unwrap_or(20);
    let script = play::script(name)?;
    let cfg = SimConfig::default();
    // Per-frame minimum over REPLAYS runs (default 1): the run is deterministic, so every
    // replay plays the same frames and the minimum strips the host's noise.
    let replays: usize = env_num("REPLAYS").unwrap_or(1);
    let mut rows: Vec<(u64, u64, bool, PhaseTimes, u32, u32)> = Vec::new();
    for replay in 0..replays.max(1) {
        let mut p = Play::new(&script, cfg)?;
        p.sim.set_phase_timing(true);
        let mut frame = 0u64;
        let mut i = 0;
        loop {
            let pending = p.sim.refinement_pending();
            let t0 = std::time::Instant::now();
            if !p.frame() {
                break;
            }
            let ns = t0.elapsed().as_nanos() as u64;
            frame += 1;
            if p.out.stats.asleep {
                continue;
            }
            let row = (
                ns,
                frame,
                pending,
                p.sim.phase_times(),
                p.out.stats.iterations,
                p.out.stats.substeps,
            );
            if replay == 0 {
                rows.push(row);
            } else if ns < rows[i].0 {
                rows[i] = row;
            }
            i += 1;
        }
    }
    anyhow::ensure!(!rows.is_empty(), "{name}: the sheet never woke up");
    let mut all: Vec<u64> = rows.iter().map(|r| r.0).collect();
    all.sort_unstable();
    let q = |f: f64| all[((all.len() - 1) as f64 * f).round() as usize] as f64 * 1e-6;
    // A mesh change's own cost: the frame minus its phases (the rebuild runs before them).
    let adoption_ms: Vec<f64> = rows
        .iter()
        .filter(|r| r.2)
        .map(|r| {
            let p = r.3;
            (r.0 as f64 - p.total_ns() as f64) * 1e-6
        })
        .collect();
    println!(
        "{name}: {} awake frames, median {:.3} ms, p99 {:.3} ms, max {:.3} ms, adoptions {} costing {:.3} ms on average",
        all.len(),
        q(0.5),
        q(0.99),
        q(1.0),
        adoption_ms.len(),
        adoption_ms.iter().sum::<f64>() / adoption_ms.len().max(1) as f64
    );
    // Each phase's median over the awake frames (phases of each frame's fastest replay).
    let phase_median = |f: &dyn Fn(&PhaseTimes) -> u64| {
        let mut v: Vec<u64> = rows.iter().map(|r| f(&r.3)).collect();
        v.sort_unstable();
        v[v.len() / 2] as f64 * 1e-6
    };
    println!(
        "phase medians: self {:.3} phys {:.3} geom {:.3} anal {:.3} tear {:.4} ms",
        phase_median(&|p| p.self_contact_ns),
        phase_median(&|p| p.physics_ns),
        phase_median(&|p| p.geometry_ns),
        phase_median(&|p| p.analysis_ns),
        phase_median(&|p| p.tear_ns)
    );
    rows.sort_by_key(|r| std::cmp::Reverse(r.0));
    for (ns, f, pending, p, it, sub) in rows.iter().take(top) {
        let other = *ns as i64 - p.total_ns() as i64;
        println!(
            "frame {f:5} {:6.3} ms  adopt {pending:5}  self {:5.3} phys {:5.3} geom {:5.3} anal {:5.3} other {:5.3}  it {it} / {sub}",
            *ns as f64 * 1e-6,
            p.self_contact_ns as f64 * 1e-6,
            p.physics_ns as f64 * 1e-6,
            p.geometry_ns as f64 * 1e-6,
            p.analysis_ns as f64 * 1e-6,
            other as f64 * 1e-6
        );
    }
    Ok(())
}
