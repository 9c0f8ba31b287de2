//! S_P regenerated from S_G every frame (issue 4 deliverable 8, opt-in:
//! `GeometryConfig::regenerate_sp`; `sheet/regenerate.rs`, `sim/remesh.rs`), played through a
//! whole seed scene: the regeneration really runs (most awake frames adopt a new S_P), the
//! sheet stays a finite, valid, single-piece manifold within its capacity, singular points are
//! never lost, the same input gives the same bits, and a sheet saved mid-scene continues
//! bit-identically. With the mode off (the default) nothing is regenerated.

mod common;

use sim_core::scenario;
use sim_core::scenario_run::state_hash;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, Sim, SimConfig};

fn config(regenerate: bool) -> SimConfig {
    let mut c = SimConfig::default();
    c.geometry.regenerate_sp = regenerate;
    c
}

/// Plays `name` with the mode set as given; checks every frame; returns the per-frame state
/// hashes and the sim at the end.
fn play(name: &str, regenerate: bool) -> (Vec<u64>, Sim) {
    let script = scenario::get(name).unwrap();
    let base = config(regenerate);
    let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
    let mut sim = runner.start(base);
    let mut out = FrameOutput::default();
    let mut hashes = Vec::new();
    let mut singular = 0;
    let mut frame = 0;
    while runner.drive(&mut sim, &mut out) {
        let sp = &sim.sheet().sp;
        assert!(
            sp.pos
                .iter()
                .chain(&sp.vel)
                .all(|v| v.iter().all(|c| c.is_finite())),
            "{name}: not finite at frame {frame}"
        );
        if frame % 10 == 0 {
            sp.topo.validate().unwrap();
            assert_eq!(sp.topo.euler_characteristic(), 1, "{name}: frame {frame}");
            let (cap_v, cap_t) = sim.mesh_capacity();
            assert!(sp.num_vertices() <= cap_v && sp.num_triangles() <= cap_t);
        }
        assert!(
            out.stats.num_singular >= singular,
            "{name}: a singular point was lost at frame {frame}"
        );
        singular = out.stats.num_singular;
        assert!(out.stats.c_mean_pct.is_finite());
        hashes.push(state_hash(&sim));
        frame += 1;
    }
    (hashes, sim)
}

#[test]
fn a_full_crumple_regenerated_every_frame_stays_sound_and_repeats() {
    let (a, sim) = play("c5_full_crumple", true);
    let r = sim.regenerations();
    // The mode runs: most awake frames (C5 has ~900, nearly all with a curved region) adopt a
    // regenerated S_P; the refusals are counted by reason and stay the exception.
    assert!(
        r.adopted > 300 && r.adopted > 2 * r.refused(),
        "{r:?} over {} frames",
        sim.frames_simulated()
    );
    // A crumpled sheet does not spring back: it keeps its singular points.
    assert!(
        sim.sheet().sp.singular.len() >= 15,
        "{:?}",
        sim.sheet().sp.singular.len()
    );
    let (b, _) = play("c5_full_crumple", true);
    assert_eq!(a, b, "same input, same bits");
}

#[test]
fn the_default_regenerates_nothing() {
    let (_, sim) = play("c4_double_bend", false);
    assert_eq!(sim.regenerations(), Default::default());
}

#[test]
fn a_regenerating_sheet_saved_mid_scene_continues_bit_identically() {
    let script = scenario::get("c4_double_bend").unwrap();
    let base = config(true);
    let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
    let cfg = runner.config(base);
    let mut sim = runner.start(base);
    let mut out = FrameOutput::default();
    for _ in 0..300 {
        assert!(runner.drive(&mut sim, &mut out));
    }
    assert!(sim.regenerations().adopted > 0, "{:?}", sim.regenerations());
    let saved = sim.save();
    let mut restored = Sim::restore(cfg, &saved).unwrap();
    assert_eq!(state_hash(&restored), state_hash(&sim));
    let n = common::continue_identically("c4_double_bend", &mut runner, &mut sim, &mut restored);
    assert!(n > 100);
}
