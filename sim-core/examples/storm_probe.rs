//! throwaway probe: hands and table in the frames before a stress failure
use sim_core::sim::SimConfig;
use sim_core::stress::{StressConfig, run_with};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let seed: u64 = args.first().map_or(24, |s| s.parse().unwrap());
    let frames: u64 = args.get(1).map_or(19710, |s| s.parse().unwrap());
    let window: u64 = args.get(2).map_or(40, |s| s.parse().unwrap());
    let cfg = StressConfig {
        seed,
        frames,
        sim: SimConfig::default(),
        trace: std::env::var("TRACE").is_ok(),
        ..StressConfig::default()
    };
    let r = run_with(&cfg, |f, sim| {
        if f + window < frames {
            return;
        }
        let sp = &sim.sheet().sp;
        let held: Vec<u32> = sim.rig().held_vertices().collect();
        let mut best = (0.0, 0usize);
        for t in 0..sp.num_triangles() {
            let x = sp.triangles[t].map(|i| sp.pos[i as usize]);
            let (g, _) = sim_core::physics::membrane::green_strain(x, &sp.tri_rest[t]);
            if g.norm() > best.0 {
                best = (g.norm(), t);
            }
        }
        let tri = sp.triangles[best.1];
        let tab: Vec<String> = sim
            .obstacles()
            .planes
            .iter()
            .filter(|p| p.active)
            .map(|p| {
                format!(
                    "{:?} {:.4}->{:.4} v{:.2}",
                    p.kind, p.offset_m, p.target_offset_m, p.speed_m_s
                )
            })
            .collect();
        println!(
            "f{f} strain {:.3} |G|max {:.3} tri {tri:?} held {:?} z {:?} {tab:?}",
            sim.metrics().max_strain,
            best.0,
            tri.map(|v| held.contains(&v)),
            tri.map(|v| (sp.pos[v as usize].z * 1e3).round() / 1e3),
        );
        for (k, h) in sim.rig().state.hands.iter().enumerate() {
            if h.active {
                println!(
                    "   hand {k} pos {:?} caution {:.3} slip {} yielded {}",
                    h.pose.pos().map(|x| (x * 1e4).round() / 1e4).as_slice(),
                    h.caution,
                    h.slipping,
                    h.yielded_to.is_some()
                );
            }
        }
    });
    println!("{:?}", r.failure);
}
