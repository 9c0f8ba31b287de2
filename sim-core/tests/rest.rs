//! A held sheet comes to rest (`sim_core::gesture_rig`, "Grip and obstacles"; `sim_core::sim`,
//! "Sleeping"): however the gestures combine, once they stop changing the sheet stops within a
//! second, falls asleep and makes no more crumple events, and neither then nor while the
//! gestures move is a triangle strained by more than 10 % (the hands give way, the strain
//! limit projects what the solve leaves strained: `sim_core::physics::strain_limit`).
//!
//! Cases: the three performances found as a new user would (`tests/fixtures/rest_*.toml`: an
//! edge slid and lifted or slid far, then the crumple gesture; both short edges lifted and
//! twisted), which before churned and crackled forever at a strain of 0.2; and a family of
//! seeded random gesture combinations (`common/gesture_family.rs`), none of them tuned on.
//! `cargo run --release -p papier-lab -- rest-family N SEED DIR` plays more of the family and
//! writes the ones that miss out as scripts; `rest-probe FILE.toml` shows what keeps one moving.
//!
//! Breakage detected: hands that swing back and forth over their balance (each slip
//! overshooting: the three performances), an isometry correction the physics undoes every other
//! frame (family seed 7), a motion flag that a rounding error keeps set (family seed 13), a hand
//! giving way into the table over and over, a flap creeping below the old sleep speed — each
//! kept one of these performances awake when it was found (docs/decisions.md, "A held sheet
//! comes to rest"); a triangle next to a point hand strained to 0.24 as a crumple started
//! (family seed 7) and one sheared to 0.16 between two grips with edges within 5 % (seed 7,
//! with an edge projection), before the strain limit projected triangles.

mod common;

use common::gesture_family::{Performance, performance};
use sim_core::script::Script;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

/// Strain (|λ − 1|) no triangle may exceed, moving or at rest: paper strained by 10 % is
/// paper torn apart.
const STRAIN_MAX: f32 = 0.10;
/// The sheet is asleep this long after the last gesture change, at the latest, seconds.
const SETTLE_S: f64 = 1.0;

/// What a performance did after its last change.
#[derive(Debug)]
struct Rest {
    /// When the sheet fell asleep for good, seconds after the last change (`None`: never).
    settle_s: Option<f64>,
    /// Crumple and clac events from `SETTLE_S` after the last change to the end.
    events_at_rest: u32,
    /// Largest strain of any triangle from `SETTLE_S` after the last change to the end.
    strain_at_rest: f32,
    /// Largest strain of any triangle while the gestures moved.
    strain_moving: f32,
}

fn play(script: &Script, last_change_s: f64) -> Rest {
    let cfg = SimConfig::default();
    let mut runner = ScriptRunner::new(script, cfg.frame_rate_hz, cfg.room).expect("runner");
    let mut sim = runner.start(cfg);
    let mut out = FrameOutput::default();
    let mut rest = Rest {
        settle_s: None,
        events_at_rest: 0,
        strain_at_rest: 0.0,
        strain_moving: 0.0,
    };
    while runner.drive(&mut sim, &mut out) {
        let t = sim.time_s() - last_change_s;
        let s = &out.stats;
        if t <= 0.0 {
            rest.strain_moving = rest.strain_moving.max(s.max_strain);
            continue;
        }
        if s.asleep {
            rest.settle_s.get_or_insert(t);
        } else {
            rest.settle_s = None;
        }
        if t > SETTLE_S {
            let a = sim.analysis_stats();
            rest.events_at_rest += a.crumple_events + a.clac_events + a.impact_events;
            rest.strain_at_rest = rest.strain_at_rest.max(s.max_strain);
        }
    }
    rest
}

fn check(name: &str, rest: &Rest) {
    println!("{name}: {rest:?}");
    let settle = rest
        .settle_s
        .unwrap_or_else(|| panic!("{name}: the sheet never came to rest ({rest:?})"));
    assert!(
        settle <= SETTLE_S,
        "{name}: asleep {settle:.2} s after the last change"
    );
    assert_eq!(rest.events_at_rest, 0, "{name}: crumple events at rest");
    assert!(
        rest.strain_at_rest <= STRAIN_MAX,
        "{name}: strain {} at rest",
        rest.strain_at_rest
    );
    assert!(
        rest.strain_moving <= STRAIN_MAX,
        "{name}: strain {} while the gestures moved",
        rest.strain_moving
    );
}

/// The three performances end asleep, silent and unstrained (each changes nothing after 4 s).
#[test]
fn the_performances_that_churned_come_to_rest() {
    for (name, toml) in [
        (
            "front slid, lifted, crumpled",
            include_str!("fixtures/rest_front_slide_lift_crumple.toml"),
        ),
        (
            "short edges lifted, twisted",
            include_str!("fixtures/rest_short_edges_lift_twist.toml"),
        ),
        (
            "back slid far, crumpled",
            include_str!("fixtures/rest_back_slide_crumple.toml"),
        ),
    ] {
        check(name, &play(&Script::parse(toml).expect("fixture"), 4.0));
    }
}

fn family(seeds: std::ops::Range<u64>) {
    for seed in seeds {
        let p: Performance = performance(seed, 2.5);
        check(
            &format!("family seed {seed}"),
            &play(&p.script(), p.last_change_s),
        );
    }
}

#[test]
fn a_family_of_held_gestures_comes_to_rest_a() {
    family(1..5);
}

#[test]
fn a_family_of_held_gestures_comes_to_rest_b() {
    family(5..9);
}

#[test]
fn a_family_of_held_gestures_comes_to_rest_c() {
    family(9..13);
}
