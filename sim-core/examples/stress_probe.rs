//! Development probe: the geometry layer around a stress-session frame.
use sim_core::sim::SimConfig;
use sim_core::stress::{StressConfig, run_with};
fn main() {
    let seed: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1);
    let upto: u64 = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(3326);
    let mut sim = SimConfig::default();
    sim.geometry.isometry.enabled = std::env::var("NOISO").is_err();
    if let Ok(f) = std::env::var("CEF") {
        sim.geometry.curved_eps_factor = f.parse().unwrap();
    }
    let cfg = StressConfig {
        seed,
        frames: upto,
        sim,
        change_size: true,
        validate_every: 0,
        restore_check_every: 0,
        restore_check_frames: 1,
        trace: false,
    };
    let r = run_with(&cfg, |f, sim| {
        if f + 8 >= upto {
            let g = sim.geometry();
            println!(
                "f{f} sing {} jump {:.2e} reverted {} iso {:?} held {} events {:?}",
                g.singular.len(),
                g.max_vertex_jump_m,
                g.isometry_reverted,
                (g.isometry.phase1_iters, g.isometry.max_disp_m),
                sim.rig().held_vertices().count(),
                g.events
                    .iter()
                    .filter(|e| !matches!(e, sim_core::geometry::ShapeEvent::JunctionsMoved { .. }))
                    .collect::<Vec<_>>()
            );
        }
    });
    println!("{:?}", r.failure);
}
