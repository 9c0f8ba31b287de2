//! Does every held sheet come to rest? Plays `N` performances of the rest family (seeded random
//! gesture combinations that end held still, `sim-core/tests/common/gesture_family.rs`) and
//! prints, per performance: how long after its last gesture change the sheet fell asleep, the
//! largest strain while it moved and at the end, the crumple events of its last second, and
//! the step time (median and p99 of the awake frames after the last change). Performances that
//! miss a target (settle ≤ 1 s, strain ≤ 0.1, no event in the last second) are written as
//! scripts to `DIR` when given, to be played again with `rest-probe` or `papier-render`.
//!
//! `cargo run --release -p papier-lab -- rest-family [N] [FIRST_SEED] [DIR]` (default 24, 1).

use std::time::Instant;

use sim_core::sim::SimConfig;

use crate::args::{at_most, nth};
use crate::play::Play;

#[path = "../../../sim-core/tests/common/gesture_family.rs"]
mod gesture_family;

pub const USAGE: &str = "[N] [FIRST_SEED] [DIR]";

/// Held still this long after the last change.
const HOLD_S: f64 = 3.0;

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 3)?;
    let n: u64 = nth(args, 0, "N")?.unwrap_or(24);
    let first: u64 = nth(args, 1, "FIRST_SEED")?.unwrap_or(1);
    let dir = args.get(2);
    println!(
        "{:>5} {:>8} {:>7} {:>7} {:>6} {:>8} {:>8}  verdict",
        "seed", "settle_s", "strain", "end", "events", "med_ms", "p99_ms"
    );
    let (mut failed, mut worst_settle, mut worst_strain) = (0, 0.0f64, 0.0f32);
    let mut held_ms: Vec<f64> = Vec::new();
    for seed in first..first + n {
        let perf = gesture_family::performance(seed, HOLD_S);
        let mut p = Play::new(&perf.script(), SimConfig::default())?;
        let (mut strain, mut settle_s, mut events_last) = (0.0f32, None, 0u32);
        let mut steps_ms: Vec<f64> = Vec::new();
        let end_s = perf.last_change_s + HOLD_S;
        loop {
            let t0 = Instant::now();
            if !p.frame() {
                break;
            }
            let ms = t0.elapsed().as_secs_f64() * 1e3;
            let t = p.sim.time_s();
            let s = &p.out.stats;
            strain = strain.max(s.max_strain);
            let a = p.sim.analysis_stats();
            if t > end_s - 1.0 {
                events_last += a.crumple_events + a.clac_events + a.impact_events;
            }
            if t > perf.last_change_s {
                if s.asleep {
                    settle_s.get_or_insert(t - perf.last_change_s);
                } else {
                    settle_s = None;
                    steps_ms.push(ms);
                }
            }
        }
        steps_ms.sort_by(f64::total_cmp);
        let pct = |q: f64| {
            steps_ms
                .get(((steps_ms.len() as f64 - 1.0) * q).round() as usize)
                .copied()
                .unwrap_or(0.0)
        };
        held_ms.extend_from_slice(&steps_ms);
        let end_strain = p.sim.metrics().max_strain as f32;
        let ok = settle_s.is_some_and(|s| s <= 1.0) && strain <= 0.1 && events_last == 0;
        failed += u32::from(!ok);
        worst_settle = worst_settle.max(settle_s.unwrap_or(f64::INFINITY));
        worst_strain = worst_strain.max(strain);
        println!(
            "{:>5} {:>8} {strain:>7.3} {end_strain:>7.3} {events_last:>6} {:>8.2} {:>8.2}  {}",
            perf.seed,
            settle_s.map_or("never".into(), |s| format!("{s:.2}")),
            pct(0.5),
            pct(0.99),
            if ok { "ok" } else { "MISSED" }
        );
        if !ok && let Some(d) = dir {
            std::fs::create_dir_all(d)?;
            std::fs::write(format!("{d}/rest_family_{seed}.toml"), &perf.toml)?;
        }
    }
    held_ms.sort_by(f64::total_cmp);
    let p99 = held_ms
        .get(((held_ms.len() as f64 - 1.0) * 0.99).round() as usize)
        .copied()
        .unwrap_or(0.0);
    println!(
        "{n} performances: {failed} missed; worst settle {worst_settle:.2} s, worst strain \
         {worst_strain:.3}; awake frames after the last change: {} (p99 step {p99:.2} ms)",
        held_ms.len()
    );
    Ok(())
}
