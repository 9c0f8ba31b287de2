//! Stress test: 10⁵ frames of hostile random commands (maximal jumps, NaN/∞ values, grab and
//! release storms, resets, size/material/room switches, and phases held still) on four
//! sessions in parallel, checking
//! after every frame that nothing is non-finite, no triangle turned over, no substep had to be
//! recovered, speeds and strains stay bounded, that the mesh stays valid, and every 250 frames
//! that the sheet saved and restored continues bit-identically ([`sim_core::stress`]). The 10⁶-frame run is `cargo run --release -p papier-lab -- stress`.
//!
//! To fit plain `cargo test` (opt-level 1) in about a minute on two cores, the sessions use a
//! coarser mesh than the default (spacing L_paper/5, ~40 triangles on A4); the binary runs the
//! default mesh.

use sim_core::stress::{StressConfig, run_with};

fn session(seed: u64, frames: u64) -> sim_core::stress::StressReport {
    let cfg = StressConfig {
        trace: std::env::var_os("STRESS_TRACE").is_some(),
        ..StressConfig::test_session(seed, frames)
    };
    // Geometry-layer invariants after every frame: the interior singular count never
    // decreases within a sheet's life (a reset starts a new sheet, a tear step may drop the
    // singular vertices it ran through), every singular point stays
    // at its pattern position, the published partition is consistent and c_mean is bounded.
    // A tear that runs through a singular vertex makes it a lip vertex: the list restarts.
    let mut last: (u64, usize) = (0, 0);
    let mut last_mesh_steps = 0u32;
    let mut first_pos: Vec<sim_core::math::V2> = Vec::new();
    let mut worst_c_mean: f64 = 0.0;
    let r = run_with(&cfg, |_, sim| {
        let g = sim.geometry();
        let n = g.singular.len();
        let torn_on = sim.tear().mesh_steps != last_mesh_steps;
        last_mesh_steps = sim.tear().mesh_steps;
        if sim.frame() > last.0 && !torn_on {
            assert!(n >= last.1, "seed {seed}: singular count {} → {n}", last.1);
        } else {
            first_pos.clear();
        }
        for (k, s) in g.singular.iter().enumerate() {
            if k < first_pos.len() {
                assert_eq!(
                    first_pos[k], s.pos2,
                    "seed {seed}: a singular point moved in 2D"
                );
            } else {
                first_pos.push(s.pos2);
            }
        }
        last = (sim.frame(), n);
        assert_eq!(g.tri_region.len(), sim.sheet().sp.num_triangles());
        assert!(g.tri_region.iter().all(|&r| (r as usize) < g.regions.len()));
        assert!(
            g.rulings
                .iter()
                .all(|r| r.length_m.is_finite() && r.dihedral_rad.is_finite())
        );
        assert!(g.max_vertex_jump_m.is_finite());
        worst_c_mean = worst_c_mean.max(sim.metrics().c_mean_pct);
    });
    assert!(
        worst_c_mean < 5.0,
        "seed {seed}: c_mean reached {worst_c_mean} %"
    );
    assert!(r.ok(), "seed {seed}: {:?}", r.failure);
    assert_eq!(r.frames, frames);
    assert_eq!((r.flips, r.recoveries), (0, 0));
    assert!(
        r.commands > frames / 20,
        "the stream is busy: {} commands",
        r.commands
    );
    // The stream held still now and then, and the sheet came to rest each time (checked
    // inside the run: asleep within a second, silent, strained by at most 10 %).
    assert!(r.holds > 0, "seed {seed}: no hold-still phase");
    // The wild tear values tore sheets in two (restored, validated and checked like the rest).
    assert!(
        r.torn_frames > 0 && r.separated_frames > 0,
        "seed {seed}: no torn sheet ({} torn, {} separated frames)",
        r.torn_frames,
        r.separated_frames
    );
    println!(
        "seed {seed}: {} holds, the sheet asleep at most {} frames after the rig stopped",
        r.holds, r.max_settle_frames
    );
    r
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
