//! Development probe: Phase I convergence (C₁ + C₂ after k iterations) at some frames.
use sim_core::geometry::isometry::{Isometry, IsometryConfig};
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let name = std::env::args()
        .nth(1)
        .unwrap_or("c6_four_corner_flip".into());
    let script = scenario::get(&name).unwrap();
    let base = SimConfig::default();
    let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
    let mut sim = runner.start(base);
    let mut out = FrameOutput::default();
    let mut k = 0;
    while runner.drive(&mut sim, &mut out) {
        k += 1;
        if k % 60 != 0 {
            continue;
        }
        let sp0 = sim.sheet().sp.clone();
        let fixed = vec![false; sp0.num_vertices()];
        let mut line = format!("f{k}:");
        for it in [0u32, 1, 2, 3, 5, 10, 20, 40, 200] {
            let mut sp = sp0.clone();
            let mut iso = Isometry::new(&sp);
            let cfg = IsometryConfig {
                phase1_max_iters: it,
                ..IsometryConfig::default()
            };
            let r = iso.run(&mut sp, &fixed, &cfg);
            // Mean compression after.
            let mut c = 0.0;
            for e in 0..sp.num_edges() {
                let rest = sp.edge_rest_len_m[e];
                c += ((rest - sp.edge_length_m(e)) / rest).max(0.0);
            }
            line += &format!(
                " {it}:C {:.1e} cm {:.4}%",
                r.c_after,
                100.0 * c / sp.num_edges() as f64
            );
        }
        println!("{line}");
    }
}
