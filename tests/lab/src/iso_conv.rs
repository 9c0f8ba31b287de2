//! How fast does the isometry step's Phase I converge? Every 60 frames of a scene, runs the
//! step on a copy of the sheet with a cap of k Phase I iterations for k in 0, 1, 2, 3, 5, 10,
//! 20, 40, 200, and prints C₁ + C₂ after it and the mean edge compression.
//!
//! `cargo run --release -p papier-lab -- iso-conv [NAME[@SEED]|FILE.toml]` (default
//! c6_four_corner_flip).

use sim_core::geometry::isometry::{Isometry, IsometryConfig, Targets};
use sim_core::sim::SimConfig;

use crate::args::at_most;
use crate::play::Play;

pub const USAGE: &str = "[NAME[@SEED]|FILE.toml]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 1)?;
    let name = args.first().map_or("c6_four_corner_flip", String::as_str);
    let mut p = Play::scene(name, SimConfig::default())?;
    let mut k = 0;
    while p.frame() {
        k += 1;
        if k % 60 != 0 {
            continue;
        }
        let sp0 = p.sim.sheet().sp.clone();
        let fixed = vec![false; sp0.num_vertices()];
        let mut line = format!("f{k}:");
        for it in [0u32, 1, 2, 3, 5, 10, 20, 40, 200] {
            let mut sp = sp0.clone();
            let mut iso = Isometry::new(&sp);
            let cfg = IsometryConfig {
                phase1_max_iters: it,
                ..IsometryConfig::default()
            };
            // The frame loop's targets.
            let r = iso.run(&mut sp, &fixed, &cfg, Targets::CompressionOnly);
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
    Ok(())
}
