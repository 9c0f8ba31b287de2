//! Pressing a squeeze held at its limit (gesture_rig.rs "Crumple cap", "Pressing";
//! sound_analysis/crackle.rs "Pressing"): once the sheet has come within a millimetre of itself
//! the crumple hands stop, but while the crumple value goes on rising (or falls back above the
//! limit) the sheet crackles as a ball pressed harder or let go does; when the value stops, the
//! press stops with it and the sheet comes to rest. Without the press these frames were
//! digital silence (issue 52: 23 % of S4's and 27 % of C5's moving windows).
//!
//! Crumples not tuned on: sizes, papers, ramps and seeds of their own, each squeezed to 1.0 so
//! that the squeeze stops on the way (checked: a crumple that never stops fails the test).

use sim_core::control::GestureParam;
use sim_core::script::Script;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

/// What one crumple did while its squeeze was held at the limit.
#[derive(Debug, Default)]
struct Pressed {
    /// Frames in which the value moved above the held squeeze's limit.
    frames: u32,
    /// Of those (after the first, which the press follows by a frame), frames with no crackle.
    silent: u32,
    /// Median crackle rate over those frames, m·rad/s.
    median_rate: f32,
    /// Crackle rate once the sheet fell asleep after the last change, largest.
    asleep_rate: f32,
    /// Seconds from the last change to sleep (`None`: never).
    settle_s: Option<f64>,
}

fn play(text: &str, last_change_s: f64) -> Pressed {
    let script = Script::parse(text).expect("script");
    let cfg = SimConfig::default();
    let mut runner = ScriptRunner::new(&script, cfg.frame_rate_hz, cfg.room).expect("runner");
    let mut sim = runner.start(cfg);
    let mut out = FrameOutput::default();
    let mut p = Pressed::default();
    let mut rates = Vec::new();
    let i = GestureParam::Crumple.index();
    let mut last_cmd = 0.0f32;
    let mut pressed_before = false;
    while runner.drive(&mut sim, &mut out) {
        let state = &sim.rig().state;
        let cmd = state.commanded[i];
        let limit = state.crumple_limit;
        let above = |c: f32| f64::from(c).max(limit);
        let pressing = limit < 1.0 && above(cmd) != above(last_cmd);
        last_cmd = cmd;
        if pressing {
            p.frames += 1;
            if pressed_before {
                let rate = out.sound.crackle.rate_m_rad_s;
                p.silent += u32::from(rate <= 0.0);
                rates.push(rate);
            }
        }
        pressed_before = pressing;
        let t = sim.time_s() - last_change_s;
        if t > 0.0 {
            if out.stats.asleep {
                p.settle_s.get_or_insert(t);
                p.asleep_rate = p.asleep_rate.max(out.sound.crackle.rate_m_rad_s);
            } else {
                p.settle_s = None;
            }
        }
    }
    rates.sort_by(f32::total_cmp);
    p.median_rate = rates.get(rates.len() / 2).copied().unwrap_or(0.0);
    p
}

#[test]
fn a_squeeze_held_at_its_limit_crackles_while_the_value_moves_and_rests_after() {
    for (size, material, seed, interp, ramp_s) in [
        ("a4", "printer", 31, "linear", 2.0),
        ("a5", "tracing", 32, "smooth", 2.5),
        ("a4", "banknote", 33, "smooth", 3.0),
        ("a6", "printer", 34, "linear", 1.5),
    ] {
        let hold_s = ramp_s + 0.5;
        let text = format!(
            "version = 1\nduration_s = {:.2}\n[set]\nsize = \"{size}\"\nmaterial = \"{material}\"\n\
             seed = {seed}\n[[grab]]\nslot = \"corners\"\non_s = 0.0\n[[lane]]\nid = \"crumple\"\n\
             interp = \"{interp}\"\npoints = [[0.0, 0.0], [{ramp_s:.2}, 1.0], [{hold_s:.2}, 1.0], \
             [{:.2}, 0.6]]\n",
            hold_s + 2.0,
            hold_s + 0.5,
        );
        let p = play(&text, hold_s + 0.5);
        println!("{size} {material} {seed} {interp}: {p:?}");
        assert!(p.frames >= 20, "{size}: the squeeze never stopped ({p:?})");
        assert_eq!(p.silent, 0, "{size}: silent frames while pressing ({p:?})");
        assert!(p.median_rate >= 1.0, "{size}: a faint press ({p:?})");
        let settle = p.settle_s.expect("the pressed sheet never came to rest");
        assert!(
            settle <= 1.0,
            "{size}: asleep {settle:.2} s after the last change"
        );
        assert_eq!(p.asleep_rate, 0.0, "{size}: crackle while asleep");
    }
}
