//! Development probe: when, where and why a scenario creates singular points.
//!
//! `cargo run --release -p sim-core --example singular_probe -- NAME[@SEED]|FILE.toml`
//! (`PAPIER_CURVED_FACTOR=F` and `PAPIER_GAUSS_FACTOR=F` override `GeometryConfig::curved_eps_factor`
//! and `gauss_eps_factor`; `CUT=1` turns strip cutting on, `GeometryConfig::cut_strips`).
use sim_core::geometry::ShapeEvent;
use sim_core::room::RoomConfig;
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let name = std::env::args()
        .nth(1)
        .expect("scenario name or script file");
    let script = if name.ends_with(".toml") {
        sim_core::script::Script::parse(&std::fs::read_to_string(&name).expect("file"))
            .expect("script")
    } else {
        scenario::get_seeded(&name).expect("scenario")
    };
    let mut cfg = SimConfig::default();
    cfg.geometry.cut_strips = std::env::var("CUT").is_ok_and(|v| v == "1");
    if let Some(f) = std::env::var("PAPIER_CURVED_FACTOR")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        cfg.geometry.curved_eps_factor = f;
    }
    if let Some(f) = std::env::var("PAPIER_GAUSS_FACTOR")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        cfg.geometry.gauss_eps_factor = f;
    }
    let mut runner =
        ScriptRunner::new(&script, cfg.frame_rate_hz, RoomConfig::default()).expect("runner");
    let mut sim = runner.start(cfg);
    let mut out = FrameOutput::default();
    let (mut fmax, mut cmax) = (0.0f64, 0.0f64);
    while runner.drive(&mut sim, &mut out) {
        let g = sim.geometry();
        fmax = fmax.max(g.max_flat_compression);
        cmax = cmax.max(g.max_curved_compression);
        for e in &g.events {
            if let ShapeEvent::SingularCreated { .. }
            | ShapeEvent::StripCurved { .. }
            | ShapeEvent::StripCut { .. } = e
            {
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
    let g = sim.geometry();
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
}
