//! Lists the frames of a scene (`NAME` or `NAME@SEED`) whose largest strain exceeds half a
//! limit (default 0.1: the scenario health limit), with the frame's Newton iterations,
//! halvings, held vertices, undo streak and speed; for a frame beyond the limit, its most
//! strained triangle with its vertices.
//!
//! `cargo run --release -p sim-core --example strain_frames -- s4_crumple@2 [LIMIT]`
//! (`ITERS=N` and `SUBSTEPS=N` set the solver's iteration cap and substeps per frame).
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let name = std::env::args().nth(1).unwrap_or("s4_crumple@2".into());
    let limit: f32 = std::env::args()
        .nth(2)
        .map_or(0.1, |s| s.parse().unwrap_or(0.1));
    let script = scenario::get_seeded(&name).expect("scene");
    let mut cfg = SimConfig::default();
    if let Some(n) = std::env::var("ITERS").ok().and_then(|v| v.parse().ok()) {
        cfg.solver.iterations = n;
    }
    if let Some(n) = std::env::var("SUBSTEPS").ok().and_then(|v| v.parse().ok()) {
        cfg.solver.substeps = n;
    }
    let mut runner = ScriptRunner::new(&script, cfg.frame_rate_hz, cfg.room).expect("runner");
    let mut sim = runner.start(cfg);
    let mut out = FrameOutput::default();
    let mut frame = 0u32;
    while runner.drive(&mut sim, &mut out) {
        let s = &out.stats;
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
            println!(
                "  worst triangle {t} {:?} (strain {:.3}); held {held:?}; {} vertices, {} inserted so far",
                sp.triangles[t],
                strain(t),
                sp.pos.len(),
                sim.inserted_vertices()
            );
        }
        frame += 1;
    }
}
