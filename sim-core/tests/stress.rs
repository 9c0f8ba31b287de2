//! Stress test: 10⁵ frames of hostile random commands (maximal jumps, NaN/∞ values, grab and
//! release storms, resets, size/material/room switches) on four sessions in parallel, checking
//! after every frame that nothing is non-finite, no triangle turned over, no substep had to be
//! recovered, speeds and strains stay bounded, and that the mesh stays valid
//! ([`sim_core::stress`]). The 10⁶-frame run is the `sim-stress` binary.
//!
//! To fit plain `cargo test` (opt-level 1) in about a minute on two cores, the sessions use a
//! coarser mesh than the default (spacing L_paper/5, ~40 triangles on A4); the binary runs the
//! default mesh.

use sim_core::sheet::MeshConfig;
use sim_core::sim::SimConfig;
use sim_core::stress::{StressConfig, run};

fn session(seed: u64, frames: u64) {
    let cfg = StressConfig {
        seed,
        frames,
        sim: SimConfig {
            mesh: MeshConfig { spacing_frac: 0.2 },
            ..SimConfig::default()
        },
        change_size: true,
        validate_every: 500,
        trace: false,
    };
    let r = run(&cfg);
    assert!(r.ok(), "seed {seed}: {:?}", r.failure);
    assert_eq!(r.frames, frames);
    assert_eq!((r.flips, r.recoveries), (0, 0));
    assert!(
        r.commands > frames / 20,
        "the stream is busy: {} commands",
        r.commands
    );
}

#[test]
fn stress_session_a() {
    session(101, 25_000);
}

#[test]
fn stress_session_b() {
    session(202, 25_000);
}

#[test]
fn stress_session_c() {
    session(303, 25_000);
}

#[test]
fn stress_session_d() {
    session(404, 25_000);
}
