//! Does a held sheet come to rest? Plays a scene and prints, per window of 50 frames, the
//! awake frames' mean step time and Newton iterations, the isometry step's mean largest
//! displacement, the mean largest vertex speed and the singular count, then the frames undone
//! by the pass-through guard.
//!
//! `cargo run --release -p papier-lab -- hold-probe [NAME[@SEED]|FILE.toml] [TRIGGER|every]`
//! (default c5_full_crumple) — TRIGGER sets `IsometryConfig::trigger_compression` (`every` =
//! `None`, the step in every frame).

use std::time::Instant;

use sim_core::sim::SimConfig;

use crate::args::{at_most, parse};
use crate::play::Play;

pub const USAGE: &str = "[NAME[@SEED]|FILE.toml] [TRIGGER|every]";

/// Frames per printed window.
const WINDOW: u64 = 50;

#[derive(Clone, Copy, Default)]
struct Window {
    frames: u64,
    step_ns: u128,
    iterations: u64,
    iso_disp_m: f64,
    max_speed_m_s: f64,
    singular: u32,
}

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 2)?;
    let name = args.first().map_or("c5_full_crumple", String::as_str);
    let mut cfg = SimConfig::default();
    if let Some(t) = args.get(1) {
        cfg.geometry.isometry.trigger_compression = match t.as_str() {
            "every" => None,
            t => Some(parse(t, "TRIGGER")?),
        };
    }
    let mut p = Play::scene(name, cfg)?;
    let mut windows: Vec<Window> = Vec::new();
    let mut undone = 0u64;
    loop {
        let t0 = Instant::now();
        if !p.frame() {
            break;
        }
        // The step time includes applying the frame's commands (negligible).
        let step_ns = t0.elapsed().as_nanos();
        let s = &p.out.stats;
        if s.asleep {
            continue;
        }
        let k = (p.out.sound.frame / WINDOW) as usize;
        if windows.len() <= k {
            windows.resize(k + 1, Window::default());
        }
        let w = &mut windows[k];
        w.frames += 1;
        w.step_ns += step_ns;
        w.iterations += u64::from(s.iterations);
        w.iso_disp_m += p.sim.geometry().isometry.max_disp_m;
        w.max_speed_m_s += f64::from(s.max_speed_m_s);
        w.singular = s.num_singular;
        undone += u64::from(s.undo_streak > 0);
    }
    for (k, w) in windows.iter().enumerate() {
        if w.frames == 0 {
            continue;
        }
        let n = w.frames as f64;
        println!(
            "frames {:4}–{:4}: awake {:3}  step {:.3} ms  Newton it. {:5.2}  isometry {:6.1} µm  vmax {:.4} m/s  singular {}",
            k as u64 * WINDOW,
            (k as u64 + 1) * WINDOW,
            w.frames,
            w.step_ns as f64 / n / 1e6,
            w.iterations as f64 / n,
            w.iso_disp_m / n * 1e6,
            w.max_speed_m_s / n,
            w.singular
        );
    }
    println!("{name}: {undone} frames undone by the pass-through guard");
    Ok(())
}
