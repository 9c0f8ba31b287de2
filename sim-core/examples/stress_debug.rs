//! Replays a stress seed and prints the state around the first failure (debugging aid).
use sim_core::math::V3;
use sim_core::sim::SimConfig;
use sim_core::stress::{StressConfig, run_with};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let seed: u64 = args.first().map_or(1, |s| s.parse().unwrap());
    let frames: u64 = args.get(1).map_or(1000, |s| s.parse().unwrap());
    let cfg = StressConfig {
        seed,
        frames,
        sim: SimConfig::default(),
        ..StressConfig::default()
    };
    let mut prev: Vec<V3> = Vec::new();
    let mut prev_pos: Vec<V3> = Vec::new();
    let r = run_with(&cfg, |f, sim| {
        let sp = &sim.sheet().sp;
        let normals: Vec<V3> = (0..sp.num_triangles())
            .map(|t| sp.tri_normal(t).normalize())
            .collect();
        if f + 3 >= frames && prev.len() == normals.len() {
            let held: Vec<u32> = sim.rig().held_vertices().collect();
            for t in 0..normals.len() {
                if normals[t].dot(&prev[t]) < 0.0 {
                    let tri = sp.triangles[t];
                    println!("frame {f}: triangle {t} {tri:?} flipped");
                    for v in tri {
                        println!(
                            "   v{v} held {} prev {:?} now {:?}",
                            held.contains(&v),
                            prev_pos[v as usize].as_slice(),
                            sp.pos[v as usize].as_slice()
                        );
                    }
                }
            }
            println!("frame {f}: held {held:?}");
            for pl in sim.obstacles().planes.iter() {
                println!(
                    "   {:?} active {} offset {} target {}",
                    pl.kind, pl.active, pl.offset_m, pl.target_offset_m
                );
            }
            let mut tri_strain: Vec<(f64, usize)> = (0..sp.num_triangles())
                .map(|t| {
                    let x = sp.triangles[t].map(|i| sp.pos[i as usize]);
                    let (g, _) = sim_core::physics::membrane::green_strain(x, &sp.tri_rest[t]);
                    (g.norm(), t)
                })
                .collect();
            tri_strain.sort_by(|a, b| b.0.total_cmp(&a.0));
            for &(g, t) in tri_strain.iter().take(4) {
                let tri = sp.triangles[t];
                let hv: Vec<bool> = tri.iter().map(|v| held.contains(v)).collect();
                let j = sp.tri_normal(t).norm() / (2.0 * sp.tri_rest[t].area_m2);
                println!("   strained tri {t} {tri:?} |G| {g:.3} J {j:.3} held {hv:?}");
            }
            let zmin = sp.pos.iter().map(|p| p.z).fold(f64::MAX, f64::min);
            println!("   zmin {zmin}");
            for (k, h) in sim.rig().state.hands.iter().enumerate() {
                if h.active {
                    println!(
                        "   handle {k} pose {:?} prev {:?} slipping {}",
                        h.pose.pos_m, h.prev_pose.pos_m, h.slipping
                    );
                }
            }
        }
        prev = normals;
        prev_pos = sp.pos.clone();
    });
    println!("{:?}", r.failure);
}
