//! When, where and why does a scene create singular points? Plays a scene and prints every
//! singular point created and every strip turned curved (with its frame), every 50th frame's
//! largest flat and curved compression, curved regions and singular count, and at the end how
//! far the singular points sit from their drawn positions.
//!
//! `cargo run --release -p papier-lab -- singular-probe NAME[@SEED]|FILE.toml`
//! (`PAPIER_CURVED_FACTOR=F` and `PAPIER_GAUSS_FACTOR=F` override
//! `GeometryConfig::curved_eps_factor` and `gauss_eps_factor`).

use sim_core::geometry::ShapeEvent;
use sim_core::sim::SimConfig;

use crate::args::{at_most, bad, env_num};
use crate::play::Play;

pub const USAGE: &str = "NAME[@SEED]|FILE.toml";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 1)?;
    let name = args
        .first()
        .ok_or_else(|| bad("a scenario name or script file is missing"))?;
    let mut cfg = SimConfig::default();
    if let Some(f) = env_num("PAPIER_CURVED_FACTOR") {
        cfg.geometry.curved_eps_factor = f;
    }
    if let Some(f) = env_num("PAPIER_GAUSS_FACTOR") {
        cfg.geometry.gauss_eps_factor = f;
    }
    let mut p = Play::scene(name, cfg)?;
    let (mut fmax, mut cmax) = (0.0f64, 0.0f64);
    while p.frame() {
        let sim = &p.sim;
        let g = sim.geometry();
        fmax = fmax.max(g.max_flat_compression);
        cmax = cmax.max(g.max_curved_compression);
        for e in &g.events {
            if let ShapeEvent::SingularCreated { .. } | ShapeEvent::StripCurved { .. } = e {
                println!("f {:4} {e:?}", sim.frame());
            }
        }
        if sim.frame().is_multiple_of(50) {
            println!(
                "f {:4} flat c {:.4} curved c {:.4} curved regions {} singular {}",
                sim.frame(),
                g.max_flat_compression,
                g.max_curved_compression,
                g.num_curved_regions,
                g.singular.len()
            );
        }
    }
    println!("max flat compression {fmax:.4}, max curved compression {cmax:.4}");
    let g = p.sim.geometry();
    let at = g
        .singular
        .iter()
        .filter(|s| (s.pos2 - s.sampled2).norm() < 1e-9)
        .count();
    let d: Vec<String> = g
        .singular
        .iter()
        .map(|s| format!("{:.1}", (s.pos2 - s.sampled2).norm() * 1000.0))
        .collect();
    println!(
        "placement: {at} of {} singular points at their drawn position; distances mm: {}",
        g.singular.len(),
        d.join(" ")
    );
    Ok(())
}
