//! Helpers shared by the integration tests.

// Each test crate compiles this module and uses only some of it.
#![allow(dead_code)]

pub mod gesture_family;
pub mod json_mutation;

use sim_core::scenario_run::state_hash;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SavedSheet, Sim, SimConfig};
use sim_core::stress::StressFixture;

/// Restores a sheet saved as JSON: a regression fixture of `tests/fixtures/`, written by
/// `cargo run --release -p papier-lab -- stress-fixture SEED FRAME OUT.json`, in the
/// room it was saved in. A bare `SavedSheet` (the fixtures written before the room was kept)
/// restores in the default room.
pub fn restore_fixture(json: &str) -> Sim {
    let fixture = serde_json::from_str::<StressFixture>(json).unwrap_or_else(|_| StressFixture {
        room: SimConfig::default().room,
        sheet: serde_json::from_str::<SavedSheet>(json).expect("the fixture parses"),
    });
    fixture
        .restore(SimConfig::default())
        .expect("the fixture restores")
}

/// True if every S_P position of `sim` is finite.
pub fn positions_finite(sim: &Sim) -> bool {
    sim.sheet()
        .sp
        .pos
        .iter()
        .all(|p| p.iter().all(|c| c.is_finite()))
}

/// Plays the rest of `runner`'s script on `sim` and on `restored` (a sheet restored from it)
/// side by side, and asserts that they stay identical every frame: state bits, frame stats,
/// crumple and friction events. Returns the frames played.
pub fn continue_identically(
    name: &str,
    runner: &mut ScriptRunner,
    sim: &mut Sim,
    restored: &mut Sim,
) -> u64 {
    let mut cmds = Vec::new();
    let (mut o1, mut o2) = (FrameOutput::default(), FrameOutput::default());
    let mut n = 0;
    while {
        cmds.clear();
        runner.next_frame(&mut cmds)
    } {
        for c in &cmds {
            sim.apply(*c);
            restored.apply(*c);
        }
        sim.step(&mut o1);
        restored.step(&mut o2);
        assert_eq!(
            state_hash(sim),
            state_hash(restored),
            "{name}: diverged at frame {n}"
        );
        assert_eq!(o1.stats, o2.stats);
        assert_eq!(
            o1.sound.crumple(),
            o2.sound.crumple(),
            "{name}: crumple events differ at frame {n}"
        );
        assert_eq!(o1.sound.friction(), o2.sound.friction());
        n += 1;
    }
    n
}

/// Checks a (possibly torn) sheet of pattern size `w` × `l` after frame `k`: topology, each
/// piece a disc, at most two pieces, S_G valid, the pattern's area kept to 1e-9, no flat
/// pattern triangle, finite positions. Returns the number of pieces.
pub fn check_torn_mesh(sim: &Sim, k: u32, w: f64, l: f64) -> usize {
    let sp = &sim.sheet().sp;
    sp.topo.validate().unwrap();
    let pieces = sp
        .topo
        .validate_pieces()
        .unwrap_or_else(|e| panic!("frame {k}: {e}"));
    assert!(pieces <= 2);
    sim.sheet()
        .sg
        .validate(sp)
        .unwrap_or_else(|e| panic!("frame {k}: {e}"));
    let area: f64 = sp.tri_rest.iter().map(|t| t.area_m2).sum();
    assert!((area - w * l).abs() <= 1e-9 * w * l, "frame {k}: area");
    // With the area conserved, no pattern triangle turned over means none overlaps.
    assert!(
        sp.tri_rest.iter().all(|t| t.area_m2 > 0.0),
        "frame {k}: a flat triangle"
    );
    assert!(positions_finite(sim), "frame {k}: positions");
    pieces
}

/// Sets gesture `param` of `sim` to `value`.
pub fn set_gesture(sim: &mut Sim, param: sim_core::control::GestureParam, value: f32) {
    sim.apply(sim_core::control::Command::Gesture { param, value });
}

/// A flat sheet of `size` and `seed` on the table, with its pattern width and length, metres.
pub fn sheet_on_table(size: sim_core::control::SheetSize, seed: u64) -> (Sim, f64, f64) {
    let sim = Sim::new(SimConfig {
        size,
        seed,
        ..SimConfig::default()
    });
    let (w, l) = (sim.sheet().width_m, sim.sheet().length_m);
    (sim, w, l)
}

/// Steps frame `k` of a tearing sheet and checks it: only an announced frame changes the mesh,
/// the torn mesh keeps its invariants ([`check_torn_mesh`]), the torn length never decreases
/// (`last_length_m`, updated).
pub fn step_torn(sim: &mut Sim, out: &mut FrameOutput, k: u32, last_length_m: &mut f32) {
    let (w, l) = (sim.sheet().width_m, sim.sheet().length_m);
    let vertices_before = sim.sheet().sp.num_vertices();
    let announced = sim.refinement_pending();
    sim.step(out);
    if sim.sheet().sp.num_vertices() != vertices_before {
        assert!(announced, "frame {k}: an unannounced mesh change");
    }
    check_torn_mesh(sim, k, w, l);
    assert!(
        out.sound.tear.length_m >= *last_length_m,
        "frame {k}: torn length decreased"
    );
    *last_length_m = out.sound.tear.length_m;
}
