//! Determinism (digest-crumpling §8 test 18): the same configuration, seed and command stream
//! give bit-identical positions and velocities, frame by frame; a different seed changes the
//! seeded parts (the crumple jitter). The hash is compared between runs of this build — a golden
//! constant would tie the test to one CPU's floating-point paths.

use sim_core::scenario;
use sim_core::scenario_run::{run_script, state_hash};
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn hashes(name: &str, seed: Option<u64>) -> Vec<u64> {
    let mut script = scenario::get(name).unwrap();
    if let Some(s) = seed {
        script.set.retain(|(k, _)| k != "seed");
        script.set.push((
            "seed".into(),
            sim_core::script::ScriptValue::Number(s as f64),
        ));
    }
    let base = SimConfig::default();
    let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
    let mut sim = runner.start(base);
    let mut out = FrameOutput::default();
    let mut v = Vec::new();
    while runner.drive(&mut sim, &mut out) {
        v.push(state_hash(&sim));
    }
    v
}

#[test]
fn same_script_and_seed_give_the_same_bits() {
    let a = hashes("c5_full_crumple", None);
    let b = hashes("c5_full_crumple", None);
    assert_eq!(a, b);
    assert!(a.len() > 800);
    let a = hashes("s3_wiggle_near_wall", None);
    assert_eq!(a, hashes("s3_wiggle_near_wall", None));
}

#[test]
fn the_seed_matters_where_randomness_is_used() {
    let a = hashes("c5_full_crumple", Some(1));
    let b = hashes("c5_full_crumple", Some(2));
    assert_ne!(a.last(), b.last(), "crumple jitter depends on the seed");
}

#[test]
fn run_summaries_repeat() {
    let s = scenario::get("s6_slide_on_table").unwrap();
    let a = run_script(&s, SimConfig::default(), false).unwrap();
    let b = run_script(&s, SimConfig::default(), false).unwrap();
    assert_eq!(a, b);
}

#[test]
fn phase_timing_changes_nothing_but_the_clock_readings() {
    // C5 squeezes (self-contact runs) and has the geometry layer on.
    let s = scenario::get("c5_full_crumple").unwrap();
    let timed = run_script(&s, SimConfig::default(), true).unwrap();
    let plain = run_script(&s, SimConfig::default(), false).unwrap();
    assert_eq!(timed.final_hash, plain.final_hash);
    assert_eq!(timed.singular_final, plain.singular_final);
    assert!(plain.phase_ns.is_empty());
    assert_eq!(timed.phase_ns.len() as u64, timed.awake_frames);
    let sum = |f: fn(&sim_core::sim::PhaseTimes) -> u64| timed.phase_ns.iter().map(f).sum::<u64>();
    assert!(sum(|p| p.physics_ns) > 0);
    assert!(sum(|p| p.geometry_ns) > 0);
    assert!(sum(|p| p.self_contact_ns) > 0);
    assert!(sum(|p| p.analysis_ns) > 0);
    // The phases lie inside the step.
    for (p, &step) in timed.phase_ns.iter().zip(&timed.step_ns) {
        let total = p.total_ns();
        assert!(total <= step, "phases {total} ns > step {step} ns");
    }
}
