//! Development probe: sheet–sheet contact pairs and self-crossings, per frame.
//!
//! `cargo run --release -p sim-core --example contact_trace -- NAME@SEED on|off FROM TO`
//! (`on`: vertex insertion at singular points). Prints the frames in FROM..=TO with an active
//! contact pair, a crossing or an undone frame (every frame with `ALL=1`), with the sleep
//! state and the fastest vertex, and the crossing triangle pairs with their pattern distance.
use sim_core::physics::sheet_contact::{SHEET_CONTACT_DIST_M, SheetContact};
use sim_core::room::RoomConfig;
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::self_proximity::SelfProximity;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let insert = args.get(1).is_some_and(|a| a == "on");
    let (f0, f1): (u64, u64) = (args[2].parse().unwrap(), args[3].parse().unwrap());
    let script = scenario::get_seeded(&args[0]).unwrap();
    let mut cfg = SimConfig::default();
    cfg.geometry.insert_singular_vertices = insert;
    let mut runner = ScriptRunner::new(&script, cfg.frame_rate_hz, RoomConfig::default()).unwrap();
    let mut sim = runner.start(cfg);
    let mut out = FrameOutput::default();
    let mut prox = SelfProximity::new();
    while runner.drive(&mut sim, &mut out) {
        let f = sim.frame();
        if f < f0 || f > f1 {
            continue;
        }
        let sp = &sim.sheet().sp;
        let mut c = SheetContact::new(sp);
        c.find(sp, 0.0);
        let active = c
            .pairs()
            .iter()
            .filter(|p| p.gap_m(&sp.pos) < SHEET_CONTACT_DIST_M)
            .count();
        let ming = c
            .pairs()
            .iter()
            .map(|p| p.gap_m(&sp.pos))
            .fold(f64::INFINITY, f64::min);
        let cross = prox.any_crossing(sp);
        let closest = prox.closest_approach_m(sp, 0.02);
        let (sq, lim) = sim.crumple_squeeze();
        if std::env::var("ALL").is_err() && active == 0 && out.stats.undo_streak == 0 && !cross {
            continue;
        }
        if cross {
            let tris = &sp.triangles;
            for a in 0..tris.len() {
                for b in a + 1..tris.len() {
                    if tris[a].iter().any(|v| tris[b].contains(v)) {
                        continue;
                    }
                    let ca = tris[a].map(|v| sp.pos[v as usize]);
                    let cb = tris[b].map(|v| sp.pos[v as usize]);
                    if sim_core::triangle_distance::triangles_intersect(ca, cb) {
                        let pa = tris[a].map(|v| sp.pattern[v as usize]);
                        let pb = tris[b].map(|v| sp.pattern[v as usize]);
                        let pd = pa
                            .iter()
                            .flat_map(|x| pb.iter().map(move |y| (x - y).norm()))
                            .fold(f64::INFINITY, f64::min);
                        println!(
                            "   crossing {:?} {:?} pattern vertex gap {:.1} mm",
                            tris[a],
                            tris[b],
                            pd * 1e3
                        );
                    }
                }
            }
        }
        println!(
            "f {f} pairs {} active {active} min gap {:.2} mm crossing {cross} closest {:.2} mm squeeze {sq:.3} lim {lim:.3} undo {} verts {} asleep {} vmax {:.4}",
            c.pairs().len(),
            ming * 1e3,
            closest * 1e3,
            out.stats.undo_streak,
            sp.num_vertices(),
            sim.is_asleep(),
            sp.vel.iter().map(|v| v.norm()).fold(0.0, f64::max)
        );
    }
}
