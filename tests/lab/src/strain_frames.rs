//! Where does a scene strain the sheet? Lists the frames whose largest strain exceeds half a
//! limit (default 0.1: the scenario health limit), with the frame's Newton iterations,
//! halvings, held vertices, undo streak and speed; for a frame beyond the limit, its most
//! strained triangle with its vertices.
//!
//! `cargo run --release -p papier-lab -- strain-frames [NAME[@SEED]|FILE.toml] [LIMIT]`
//! (default s4_crumple@2; `ITERS=N` and `SUBSTEPS=N` set the solver's iteration cap and
//! substeps per frame).

use sim_core::sim::SimConfig;

use crate::args::{at_most, env_num, nth};
use crate::play::Play;

pub const USAGE: &str = "[NAME[@SEED]|FILE.toml] [LIMIT]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 2)?;
    let name = args.first().map_or("s4_crumple@2", String::as_str);
    let limit: f32 = nth(args, 1, "LIMIT")?.unwrap_or(0.1);
    let mut cfg = SimConfig::default();
    if let Some(n) = env_num("ITERS") {
        cfg.solver.iterations = n;
    }
    if let Some(n) = env_num("SUBSTEPS") {
        cfg.solver.substeps = n;
    }
    let mut p = Play::scene(name, cfg)?;
    let mut frame = 0u32;
    while p.frame() {
        let (s, sim) = (&p.out.stats, &p.sim);
        if s.max_strain > limit * 0.5 {
            println!(
                "frame {frame:5}: strain {:.3} it {} halv {} held {} pinned {} held back {} undo {} vmax {:.3} m/s sing {} contacts {} tris {}",
                s.max_strain,
                s.iterations,
                s.halvings,
                s.num_held,
                s.pinned_substeps,
                s.held_back_substeps,
                s.undo_streak,
                s.max_speed_m_s,
                s.num_singular,
                s.num_contacts,
                s.num_triangles
            );
        }
        if s.max_strain > limit {
            let sp = &sim.sheet().sp;
            let strain = |t: usize| {
                let x = sp.triangles[t].map(|i| sp.pos[i as usize]);
                sim_core::metrics::triangle_strain(sp, t, x)
            };
            let t = (0..sp.triangles.len())
                .max_by(|&a, &b| strain(a).total_cmp(&strain(b)))
                .unwrap_or(0);
            let held: Vec<u32> = sim.rig().held_vertices().collect();
            let hands = sp.triangles[t].map(|v| sim.rig().hand_of(v));
            println!(
                "  worst triangle {t} {:?} (strain {:.3}, hands {hands:?}); held {held:?}; {} vertices, {} inserted so far",
                sp.triangles[t],
                strain(t),
                sp.pos.len(),
                sim.inserted_vertices()
            );
        }
        frame += 1;
    }
    Ok(())
}
