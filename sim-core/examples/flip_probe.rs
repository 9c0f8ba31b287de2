//! Edge flips in flat regions (`GeometryConfig::flip_compressed_edges`, digest-crumpling §3.1),
//! per scene: `cargo run --release -p sim-core --example flip_probe [-- NAME[@SEED]...]`
//! (default: every seed scenario). Prints, with flips off and on: edges flipped, singular
//! points, vertices inserted, largest strain, deepest crumple squeeze, undone frames and
//! c_mean. `VERBOSE=1` lists every flip (frame, old edge's compression, the frame's largest
//! strain then).
use sim_core::geometry::ShapeEvent;
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<String> = if args.is_empty() {
        scenario::names().map(str::to_string).collect()
    } else {
        args
    };
    let verbose = std::env::var_os("VERBOSE").is_some();
    println!(
        "| scene | flips | flipped | singular | inserted | max strain | deepest squeeze | undone frames | c_mean % |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for arg in &names {
        for flip in [false, true] {
            // `NAME@SEED` plays the scene with another seed.
            let script = scenario::get_seeded(arg).expect("scene");
            let mut cfg = SimConfig::default();
            cfg.geometry.flip_compressed_edges = flip;
            let mut runner = ScriptRunner::new(&script, cfg.frame_rate_hz, cfg.room).unwrap();
            let mut sim = runner.start(cfg);
            let mut out = FrameOutput::default();
            let (mut frames, mut undone, mut strain, mut cm, mut squeeze) =
                (0u32, 0u32, 0f32, 0.0, 0f32);
            while runner.drive(&mut sim, &mut out) {
                if out.stats.asleep {
                    continue;
                }
                frames += 1;
                undone += u32::from(out.stats.undo_streak > 0);
                strain = strain.max(out.stats.max_strain);
                cm += f64::from(out.stats.c_mean_pct);
                let (sq, lim) = sim.crumple_squeeze();
                squeeze = squeeze.max(sq.min(lim) as f32);
                if verbose {
                    for e in &sim.geometry().events {
                        if let ShapeEvent::EdgeFlipped {
                            diagonal,
                            compression,
                        } = e
                        {
                            println!(
                                "  {arg} f{} flip → {diagonal:?} c_e {:.4} strain {:.3}",
                                out.sound.frame, compression, out.stats.max_strain
                            );
                        }
                    }
                }
            }
            println!(
                "| {arg} | {} | {} | {} | {} | {strain:.3} | {squeeze:.2} | {undone} | {:.4} |",
                if flip { "on" } else { "off" },
                sim.flipped_edges(),
                out.stats.num_singular,
                sim.inserted_vertices(),
                cm / f64::from(frames.max(1))
            );
        }
    }
}
