//! Debug: two hands pulling the sheet taut.
use sim_core::control::{Command, GestureParam, GrabSlot};
use sim_core::sim::{FrameOutput, Sim, SimConfig};

fn main() {
    let mut cfg = SimConfig::default();
    cfg.solver.iterations = std::env::args().nth(1).map_or(3, |s| s.parse().unwrap());
    cfg.solver.substeps = std::env::args().nth(2).map_or(1, |s| s.parse().unwrap());
    let mut sim = Sim::new(cfg);
    for slot in [GrabSlot::Back, GrabSlot::Front] {
        sim.apply(Command::Grab { slot, grip: 1.0 });
    }
    sim.apply(Command::Gesture {
        param: GestureParam::Lift,
        value: 1.0,
    });
    let mut out = FrameOutput::default();
    let mut forces = vec![sim_core::math::V3::zeros(); sim.sheet().sp.num_vertices()];
    for f in 0..120 {
        sim.step(&mut out);
        let p = sim_core::physics::PhysParams::new(
            &sim_core::material::PaperMaterial::of(sim.config().material),
            &sim.config().solver,
        );
        sim_core::physics::elastic_forces(&sim.sheet().sp, &p, &mut forces);
        let held: Vec<u32> = sim.rig().held_vertices().collect();
        let fsum: f64 = held.iter().map(|&v| forces[v as usize].norm()).sum();
        let hs: Vec<String> = sim.rig().state.hands[..4]
            .iter()
            .map(|h| {
                format!(
                    "{:.3}{}",
                    h.pose.pos_m[2],
                    if h.slipping { "s" } else { "" }
                )
            })
            .collect();
        if f == 119 {
            let sp = &sim.sheet().sp;
            for (t, tri) in sp.triangles.iter().enumerate() {
                let x = tri.map(|i| sp.pos[i as usize]);
                let (g, _) = sim_core::physics::membrane::green_strain(x, &sp.tri_rest[t]);
                let n = g.norm();
                if n > 0.02 {
                    let h: Vec<bool> = tri.iter().map(|v| held.contains(v)).collect();
                    let pat: Vec<[f64; 2]> = tri
                        .iter()
                        .map(|&v| [sp.pattern[v as usize].x, sp.pattern[v as usize].y])
                        .collect();
                    println!("tri {t} |G| {n:.3} held {h:?} pattern {pat:?}");
                }
            }
        }
        println!(
            "f {f} strain {:.3} it {} |F|sum {fsum:.2} handles z {hs:?}",
            out.stats.max_strain, out.stats.iterations
        );
    }
}
