//! How large S_P would be if it were regenerated from S_G every frame the way the seeds do
//! (TOG 2015 §4, P 608–629; digest-crumpling §3.4): every curved region's quads between
//! neighbouring rulings split into four triangles about their barycentre, a cone fan around a
//! singular apex kept as one triangle per pair of neighbouring rulings, flat regions
//! triangulated again (counted here as the triangles they have now, a lower bound: their
//! Delaunay triangulation must also take every ruling end on their border). Compared, frame
//! by frame, with the S_P the simulation runs on (docs/sp-regeneration-plan.md).
//!
//! `cargo run --release -p sim-core --example seed_sp_size -- [NAME[@SEED] ...]` (default:
//! every seed scene)
use sim_core::geometry::RegionKind;
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn percentile(v: &mut [usize], p: usize) -> usize {
    v.sort_unstable();
    v.get((v.len().saturating_sub(1)) * p / 100)
        .copied()
        .unwrap_or(0)
}

fn main() {
    let mut names: Vec<String> = std::env::args().skip(1).collect();
    if names.is_empty() {
        names = scenario::names().map(str::to_string).collect();
    }
    println!(
        "{:28} {:>7} {:>16} {:>22} {:>10}",
        "scene", "frames", "S_P tris med/max", "seeds' S_P med/p99/max", "ratio med"
    );
    for name in names {
        let script = scenario::get_seeded(&name).expect("scene");
        let cfg = SimConfig::default();
        let mut runner = ScriptRunner::new(&script, cfg.frame_rate_hz, cfg.room).expect("runner");
        let mut sim = runner.start(cfg);
        let mut out = FrameOutput::default();
        let (mut ours, mut seeds, mut ratio) = (Vec::new(), Vec::new(), Vec::new());
        while runner.drive(&mut sim, &mut out) {
            if out.stats.asleep {
                continue;
            }
            let g = sim.geometry();
            let regenerated: usize = g
                .regions
                .iter()
                .map(|r| {
                    let gaps = (r.num_rulings as usize).saturating_sub(1);
                    match r.kind {
                        RegionKind::Flat => r.num_triangles as usize,
                        RegionKind::Curved if r.singular_apex != u32::MAX => gaps,
                        RegionKind::Curved => 4 * gaps,
                        _ => 0,
                    }
                })
                .sum();
            let n = sim.sheet().sp.num_triangles();
            ours.push(n);
            seeds.push(regenerated);
            ratio.push(100 * regenerated / n.max(1));
        }
        let frames = ours.len();
        println!(
            "{:28} {:>7} {:>9}/{:<6} {:>9}/{}/{:<6} {:>9.2}×",
            name,
            frames,
            percentile(&mut ours, 50),
            percentile(&mut ours, 100),
            percentile(&mut seeds, 50),
            percentile(&mut seeds, 99),
            percentile(&mut seeds, 100),
            percentile(&mut ratio, 50) as f64 / 100.0
        );
    }
}
