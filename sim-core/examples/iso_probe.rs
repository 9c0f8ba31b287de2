//! Development probe: the isometry optimizer's effect within frames of one scenario.
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let name = std::env::args().nth(1).unwrap_or("c5_full_crumple".into());
    let script = scenario::get(&name).unwrap();
    let base = SimConfig::default();
    let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
    let mut sim = runner.start(base);
    let mut out = FrameOutput::default();
    let mut k = 0;
    while runner.drive(&mut sim, &mut out) {
        k += 1;
        for e in &sim.geometry().events {
            if matches!(e, sim_core::geometry::ShapeEvent::SingularCreated { .. }) {
                println!("f{k} {e:?}");
            }
        }
        if k % 25 == 0 {
            let g = sim.geometry();
            let i = g.isometry;
            println!(
                "f{k} c_mean {:.4} sing {} flat {} curved {} creases {} rulings {} cones {} maxflatc {:.5} maxcurvc {:.5} iso it {} {} C {:.3e}->{:.3e} maxd {:.2e} meand {:.2e} ev {:?}",
                out.stats.c_mean_pct,
                out.stats.num_singular,
                g.num_flat_regions,
                g.num_curved_regions,
                g.num_creases,
                g.rulings.len(),
                g.cones.len(),
                g.max_flat_compression,
                g.max_curved_compression,
                i.phase1_iters,
                i.phase2_iters,
                i.c_before,
                i.c_after,
                i.max_disp_m,
                i.mean_disp_m,
                g.events.first()
            );
        }
    }
}
