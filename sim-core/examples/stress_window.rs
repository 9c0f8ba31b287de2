//! Replays a stress seed up to frame N and prints each frame's largest strain from frame A on
//! (debugging aid; stderr shows what the sim reports meanwhile).
use sim_core::sim::SimConfig;
use sim_core::stress::{StressConfig, run_with};

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let seed: u64 = a[0].parse().unwrap();
    let from: u64 = a[1].parse().unwrap();
    let to: u64 = a[2].parse().unwrap();
    let cfg = StressConfig {
        seed,
        frames: to + 1,
        sim: SimConfig::default(),
        ..StressConfig::default()
    };
    let r = run_with(&cfg, |f, sim| {
        if f >= from {
            eprintln!(
                "frame {f}: strain {:.3} vmax {:.2} held {}",
                sim.metrics().max_strain,
                sim.metrics().max_speed_m_s,
                sim.rig().held_vertices().count()
            );
        }
    });
    eprintln!("failure {:?}", r.failure);
}
