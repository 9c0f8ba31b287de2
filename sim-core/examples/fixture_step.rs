//! Restores a saved sheet (JSON, as `stress_fixture` writes it, in its room; a bare saved sheet
//! in the default room) and steps it a few frames,
//! printing each frame's largest strain, halvings, pinned, held-back and split substeps.
//!
//! `cargo run --release -p sim-core --example fixture_step -- STATE.json [FRAMES]`
use sim_core::sim::{FrameOutput, SavedSheet, SimConfig};
use sim_core::stress::StressFixture;

fn main() {
    let path = std::env::args().nth(1).expect("STATE.json");
    let frames: u32 = std::env::args()
        .nth(2)
        .map_or(3, |s| s.parse().expect("frames"));
    let json = std::fs::read_to_string(&path).expect("read");
    let fixture = serde_json::from_str::<StressFixture>(&json).unwrap_or_else(|_| StressFixture {
        room: SimConfig::default().room,
        sheet: serde_json::from_str::<SavedSheet>(&json).expect("parse"),
    });
    let mut cfg = SimConfig::default();
    cfg.geometry.enabled = std::env::var("NOGEOM").is_err();
    let mut sim = fixture.restore(cfg).expect("restore");
    let mut out = FrameOutput::default();
    for k in 1..=frames {
        sim.step(&mut out);
        let s = &out.stats;
        if std::env::var("STATS").is_ok() {
            println!("{s:?}");
        }
        println!(
            "+{k}: strain {:.3}, halvings {}, iterations {}, pinned {}, held back {}, split {}, flipped {}",
            sim.metrics().max_strain,
            s.halvings,
            s.iterations,
            s.pinned_substeps,
            s.held_back_substeps,
            s.split_substeps,
            s.num_flipped
        );
    }
}
