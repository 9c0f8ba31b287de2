//! What do edge flips in flat regions (`GeometryConfig::flip_compressed_edges`,
//! digest-crumpling §3.1) change, per scene? Plays each scene with flips off and on and prints
//! a table: edges flipped, singular points, vertices inserted, largest strain, deepest crumple
//! squeeze, undone frames and c_mean.
//!
//! `cargo run --release -p papier-lab -- flip-probe [NAME[@SEED]|FILE.toml ...]` (default:
//! every library scenario). `VERBOSE=1` lists every flip (frame, old edge's compression, the
//! frame's largest strain then).

use sim_core::geometry::ShapeEvent;
use sim_core::sim::SimConfig;

use crate::play::{self, Play};

pub const USAGE: &str = "[NAME[@SEED]|FILE.toml ...]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    let names = play::scenes_or_all(args);
    let verbose = std::env::var_os("VERBOSE").is_some();
    println!(
        "| scene | flips | flipped | singular | inserted | max strain | deepest squeeze | undone frames | c_mean % |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for arg in &names {
        let script = play::script(arg)?;
        for flip in [false, true] {
            let mut cfg = SimConfig::default();
            cfg.geometry.flip_compressed_edges = flip;
            let mut p = Play::new(&script, cfg)?;
            let (mut frames, mut undone, mut strain, mut cm, mut squeeze) =
                (0u32, 0u32, 0f32, 0.0, 0f32);
            while p.frame() {
                let s = &p.out.stats;
                if s.asleep {
                    continue;
                }
                frames += 1;
                undone += u32::from(s.undo_streak > 0);
                strain = strain.max(s.max_strain);
                cm += f64::from(s.c_mean_pct);
                let (sq, lim) = p.sim.crumple_squeeze();
                squeeze = squeeze.max(sq.min(lim) as f32);
                if verbose {
                    for e in &p.sim.geometry().events {
                        if let ShapeEvent::EdgeFlipped {
                            diagonal,
                            compression,
                        } = e
                        {
                            println!(
                                "  {arg} f{} flip → {diagonal:?} c_e {:.4} strain {:.3}",
                                p.out.sound.frame, compression, s.max_strain
                            );
                        }
                    }
                }
            }
            println!(
                "| {arg} | {} | {} | {} | {} | {strain:.3} | {squeeze:.2} | {undone} | {:.4} |",
                if flip { "on" } else { "off" },
                p.sim.flipped_edges(),
                p.out.stats.num_singular,
                p.sim.inserted_vertices(),
                cm / f64::from(frames.max(1))
            );
        }
    }
    Ok(())
}
