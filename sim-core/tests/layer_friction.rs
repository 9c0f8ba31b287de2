//! The layers of a crumpled sheet rub on each other (issue 52, beyond the seeds:
//! sound_analysis/friction_events.rs "Layers rubbing on each other"). A family of seeded
//! crumples not tuned on — a random sheet and paper, held by its corners or not, squeezed to
//! 0.6–1.0 along a ramp of 0.8–2.5 s, held, then let go — played through the sim. Checked:
//! most crumples that bring the sheet onto itself make layer friction sources; a layer never
//! slides faster than twice the sheet's fastest vertex (the slip is a relative speed); once
//! the sheet sleeps nothing rubs.

use rand::{RngExt, SeedableRng};
use sim_core::script::Script;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};
use sim_core::sound_input::Obstacle;

/// What one crumple's layers did.
#[derive(Debug, Default)]
struct Layers {
    /// Frames with sheet–sheet contact pairs pressed (layer slip ≥ 0 somewhere).
    pressed_frames: u32,
    /// Frames with a layer friction source.
    rubbing_frames: u32,
    /// Largest slip heard, m/s.
    max_slip_m_s: f32,
    /// Largest ratio of a source's slip to twice the frame's fastest vertex.
    worst_ratio: f32,
    /// Friction sources of any kind in frames where the sheet was asleep.
    asleep_sources: u32,
}

fn crumple(seed: u64) -> String {
    let mut rng = rand_pcg::Pcg32::seed_from_u64(0x1a7e_f00d ^ seed);
    let size = ["a4", "a5", "a6", "sq10"][rng.random_range(0..4)];
    let material = ["printer", "tracing", "banknote"][rng.random_range(0..3)];
    let interp = ["linear", "smooth"][rng.random_range(0..2)];
    let grab = if rng.random_bool(0.5) {
        "[[grab]]\nslot = \"corners\"\non_s = 0.1\n"
    } else {
        ""
    };
    let t0: f64 = rng.random_range(0.2..0.5);
    let t1 = t0 + rng.random_range(0.8..2.5);
    let amount: f64 = rng.random_range(0.6..1.0);
    let t2 = t1 + rng.random_range(0.2..0.8);
    let t3 = t2 + rng.random_range(0.3..1.0);
    format!(
        "version = 1\nduration_s = {:.3}\n[set]\nsize = \"{size}\"\nmaterial = \"{material}\"\n\
         seed = {}\n{grab}[[lane]]\nid = \"crumple\"\ninterp = \"{interp}\"\n\
         points = [[{t0:.3}, 0.0], [{t1:.3}, {amount:.3}], [{t2:.3}, {amount:.3}], [{t3:.3}, 0.0]]\n",
        t3 + 1.5,
        100 + seed,
    )
}

fn play(text: &str) -> Layers {
    let script = Script::parse(text).expect("script");
    let cfg = SimConfig::default();
    let mut runner = ScriptRunner::new(&script, cfg.frame_rate_hz, cfg.room).expect("runner");
    let mut sim = runner.start(cfg);
    let mut out = FrameOutput::default();
    let mut l = Layers::default();
    while runner.drive(&mut sim, &mut out) {
        if out.stats.asleep {
            l.asleep_sources += out.sound.friction().len() as u32;
            continue;
        }
        l.pressed_frames += u32::from(sim.layer_slip().iter().any(|&s| s >= 0.0));
        let fastest = out.stats.max_speed_m_s;
        let mut rubbing = false;
        for f in out.sound.friction() {
            if f.obstacle == Obstacle::SelfContact {
                rubbing = true;
                l.max_slip_m_s = l.max_slip_m_s.max(f.slip_speed_m_s);
                l.worst_ratio = l
                    .worst_ratio
                    .max(f.slip_speed_m_s / (2.0 * fastest).max(1e-9));
            }
        }
        l.rubbing_frames += u32::from(rubbing);
    }
    l
}

#[test]
fn a_crumpled_sheet_rubs_on_itself_while_it_moves_and_not_at_rest() {
    let mut pressed = 0;
    let mut rubbing = 0;
    for seed in 0..12 {
        let l = play(&crumple(seed));
        println!("crumple {seed}: {l:?}");
        assert!(l.worst_ratio <= 1.0 + 1e-4, "crumple {seed}: {l:?}");
        assert_eq!(l.asleep_sources, 0, "crumple {seed}: rubs while asleep");
        if l.pressed_frames >= 10 {
            pressed += 1;
            rubbing += u32::from(l.rubbing_frames >= 5);
        }
    }
    println!("{rubbing} of {pressed} crumples with layers pressed rubbed");
    assert!(
        pressed >= 4,
        "only {pressed} of 12 crumples pressed layers together"
    );
    assert!(
        4 * rubbing >= 3 * pressed,
        "{rubbing} of {pressed} crumples with layers pressed rubbed"
    );
}
