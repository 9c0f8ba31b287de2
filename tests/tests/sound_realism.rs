//! Sound realism (issue 52): the sounds the seeds' model does not make, measured on rendered
//! families of gestures not tuned on. Each test runs the real simulation driven by a script and
//! the real render path in lockstep at 48 kHz, as `papier-render` does.
//!
//! - a sheet held up by an edge and shaken at 3–6 Hz is heard (≥ −40 dBFS at the default mix),
//!   louder at a faster rate, from the air it moves (`sound_analysis/air.rs`, `render/air.rs`);
//! - a crumple that moves crackles between its events (`sound_analysis/crackle.rs`,
//!   `render/crackle.rs`), and a sheet slid flat on the table or held still does neither;
//! - a sheet slapping the table claps (`sound_analysis/impact.rs`): a sheet held by an edge that
//!   lies on the table and shaken claps on every swing, a flap let go claps as it lands, and a
//!   sheet lying still or slid flat never does.

mod render_common;

use render_common::{play_script, play_script_with_stats, printer_db, render, renderer, rms};

use papier::render::Scene;
use sim_core::script::Script;
use sim_core::sound_input::SoundFrame;

const RATE: f64 = 48_000.0;
const FRAME_RATE: f64 = sim_core::sim::DEFAULT_FRAME_RATE_HZ;

/// Plays script text and records every frame's sound input.
fn play(text: &str) -> Vec<SoundFrame> {
    play_script(&Script::parse(text).unwrap(), None)
}

/// Renders recorded frames in lockstep (events triggered at their frame), both channels summed;
/// with `keep` choosing what of each frame is heard. Returns the samples and the renderer's
/// (air, crackle) sample counts.
fn render_frames(frames: &[SoundFrame], keep: impl Fn(&mut SoundFrame)) -> (Vec<f32>, u64, u64) {
    let mut r = renderer(RATE, printer_db(RATE), 3, Scene::default());
    let per_frame = (RATE / FRAME_RATE) as usize;
    let mut out = Vec::with_capacity(frames.len() * per_frame);
    for f in frames {
        let mut g = *f;
        keep(&mut g);
        for e in g.crumple() {
            r.trigger(e);
        }
        r.set_frame(&g);
        let (l, rr) = render(&mut r, per_frame, per_frame);
        out.extend(l.iter().zip(&rr).map(|(a, b)| 0.5 * (a + b)));
    }
    let c = r.counters();
    (out, c.air_samples, c.crackle_samples)
}

fn dbfs(x: &[f32]) -> f64 {
    20.0 * rms(x).max(1e-12).log10()
}

/// Where the shaken sheet is held.
#[derive(Clone, Copy)]
enum Held {
    /// By its front edge, lifted to 0.9 with no table under it, shaken from 0.8 s.
    UpInTheAir,
    /// By its back edge, which lies on the table, shaken from 0.3 s: the free part lifts and
    /// slaps down on every swing.
    OnTheTable,
}

/// A sheet held as `held` and shaken at `rate_hz` with `depth` for 3 s.
fn shake(held: Held, size: &str, seed: u32, rate_hz: f64, depth: f64) -> String {
    let (table, slot, lift, start_s) = match held {
        Held::UpInTheAir => (
            "table = false\n",
            "front",
            "[[lane]]\nid = \"lift\"\ninterp = \"smooth\"\npoints = [[0.0, 0.0], [0.5, 0.9]]\n",
            0.8,
        ),
        Held::OnTheTable => ("", "back", "", 0.3),
    };
    format!(
        "version = 1\nduration_s = 3.0\n[set]\nsize = \"{size}\"\nseed = {seed}\n{table}\
         [[grab]]\nslot = \"{slot}\"\non_s = 0.0\n{lift}\
         [[lane]]\nid = \"shake_rate_hz\"\ninterp = \"step\"\npoints = [[0.0, {rate_hz}]]\n\
         [[lane]]\nid = \"shake_depth\"\ninterp = \"step\"\npoints = [[0.0, 0.0], [{start_s}, {depth}]]\n"
    )
}

/// Crumple events in each whole shake period from two periods after the shake starts at 0.8 s
/// (the swing has built up).
fn events_per_period(frames: &[SoundFrame], rate_hz: f64) -> Vec<usize> {
    let first = ((0.8 + 2.0 / rate_hz) * FRAME_RATE).round() as usize;
    let per_period = FRAME_RATE / rate_hz;
    let whole = ((frames.len() - first) as f64 / per_period).floor() as usize;
    (0..whole)
        .map(|k| {
            let a = first + (k as f64 * per_period).round() as usize;
            let b = first + ((k + 1) as f64 * per_period).round() as usize;
            frames[a..b].iter().map(|f| f.crumple().len()).sum()
        })
        .collect()
}

#[test]
fn a_sheet_shaken_in_the_air_is_heard_and_louder_at_a_faster_rate() {
    // A family: sizes, seeds, depths (the issue's CC 90 is 0.709); rates 3, 4.5 and 6 Hz. No
    // table: the sheet hangs in the air from the hand, so what is heard is the air it moves
    // and the flaps its curvature flips make.
    let per_frame = (RATE / FRAME_RATE) as usize;
    let from = (1.2 * FRAME_RATE) as usize * per_frame;
    let mut all = Vec::new();
    for (size, seed, depth) in [
        ("a4", 1, 0.5),
        ("a5", 2, 0.709),
        ("a4", 3, 0.9),
        ("a6", 4, 0.709),
        ("a4", 5, 0.709),
    ] {
        let mut levels = Vec::new();
        for rate in [3.0, 4.5, 6.0] {
            let frames = play(&shake(Held::UpInTheAir, size, seed, rate, depth));
            let (out, air, _) = render_frames(&frames, |_| {});
            assert!(air > 0);
            let level = dbfs(&out[from..]);
            let periods = events_per_period(&frames, rate);
            eprintln!(
                "{size} seed {seed} depth {depth} at {rate} Hz: {level:.1} dBFS, events per swing {periods:?}"
            );
            // Heard at the default mix (issue 52's target, −40 dBFS), every sheet and rate.
            assert!(
                level >= -40.0,
                "{size} seed {seed} at {rate} Hz: {level:.1} dBFS"
            );
            // At the issue's depth or more the free part flips in every swing.
            if depth >= 0.7 {
                assert!(
                    periods.iter().all(|&n| n > 0),
                    "{size} seed {seed} at {rate} Hz: a swing without an event: {periods:?}"
                );
            }
            levels.push(level);
        }
        all.push((size, seed, levels));
    }
    for (size, seed, levels) in &all {
        // Louder at a faster rate, every sheet (the level saturates once the flaps flip in
        // every swing: measured 3 → 6 Hz +2.1 dB on the A6 card, +4 to +8 dB on the others).
        assert!(
            levels.windows(2).all(|w| w[1] > w[0]) && levels[2] > levels[0] + 1.5,
            "{size} seed {seed}: {levels:?}"
        );
    }
    // A smaller sheet moves less air: the A6 is the quietest at every rate.
    for k in 0..3 {
        let a6 = all.iter().find(|a| a.0 == "a6").unwrap().2[k];
        assert!(
            all.iter().filter(|a| a.0 != "a6").all(|a| a.2[k] > a6),
            "rate {k}: {all:?}"
        );
    }
}

#[test]
fn a_crumple_that_moves_crackles_between_its_events() {
    // The corners crumpled in (an unseen scene: A5, its own seed and ramp), only the crackle
    // heard: it sounds while the sheet's bends move, and stops when the hands hold.
    let text = r#"version = 1
duration_s = 4.0
[set]
size = "a5"
seed = 77
[[grab]]
slot = "corners"
on_s = 0.0
[[lane]]
id = "crumple"
interp = "smooth"
points = [[0.0, 0.0], [1.8, 0.7], [4.0, 0.7]]
"#;
    let frames = play(text);
    let (out, _, crackle) = render_frames(&frames, |f| {
        f.take_crumple_count();
        f.air = Default::default();
        let mut g = SoundFrame::default();
        g.crackle = f.crackle;
        *f = g;
    });
    assert!(crackle > 0, "no crackle");
    let per_frame = (RATE / FRAME_RATE) as usize;
    let win = (0.01 * RATE) as usize;
    let moving = &out[(0.3 * RATE) as usize..(1.6 * RATE) as usize];
    let silent = moving.chunks(win).filter(|c| dbfs(c) < -90.0).count();
    let windows = moving.len() / win;
    eprintln!(
        "crackle while moving: {:.1} dBFS, {silent} of {windows} windows silent",
        dbfs(moving)
    );
    assert!(
        silent * 10 <= windows,
        "{silent} of {windows} windows silent"
    );
    // Held still at the end: the sheet comes to rest and the crackle stops.
    let last = &out[out.len() - 20 * per_frame..];
    assert_eq!(dbfs(last), -240.0, "the held sheet still crackles");
}

#[test]
fn a_flat_slide_and_a_still_sheet_move_no_air_and_do_not_crackle() {
    let slide = r#"version = 1
duration_s = 2.0
[set]
size = "a4"
seed = 5
[[grab]]
slot = "back"
on_s = 0.0
[[lane]]
id = "slide"
interp = "smooth"
points = [[0.0, 0.0], [1.5, 0.4]]
"#;
    let (out, air, crackle) = render_frames(&play(slide), |f| {
        let mut g = SoundFrame::default();
        g.air = f.air;
        g.crackle = f.crackle;
        *f = g;
    });
    eprintln!(
        "flat slide: air and crackle {:.1} dBFS ({air} / {crackle} samples)",
        dbfs(&out)
    );
    assert!(dbfs(&out) < -70.0, "{}", dbfs(&out));
    let still = "version = 1\nduration_s = 1.0\n";
    let (out, air, crackle) = render_frames(&play(still), |_| {});
    assert_eq!((air, crackle), (0, 0));
    assert!(out.iter().all(|v| *v == 0.0));
}

#[test]
fn a_sheet_slapped_on_the_table_claps_on_every_swing() {
    for (size, seed, rate_hz, depth) in [
        ("a4", 11, 3.0, 0.8),
        ("a5", 12, 4.5, 0.6),
        ("a4", 13, 6.0, 0.7),
        ("a6", 14, 5.0, 0.9),
    ] {
        let script = Script::parse(&shake(Held::OnTheTable, size, seed, rate_hz, depth)).unwrap();
        let (frames, stats) = play_script_with_stats(&script, None);
        // Every shake period from 1 s on (the swing has built up) has an impact.
        let per_period = (FRAME_RATE / rate_hz).ceil() as usize;
        let first = FRAME_RATE as usize;
        let periods: Vec<u32> = stats[first..]
            .chunks(per_period)
            .filter(|c| c.len() == per_period)
            .map(|c| c.iter().map(|s| s.impact_events).sum())
            .collect();
        let (out, _, _) = render_frames(&frames, |_| {});
        eprintln!(
            "{size} shaken on the table at {rate_hz} Hz: impacts per period {periods:?}, {:.1} dBFS",
            dbfs(&out[(RATE as usize)..])
        );
        assert!(
            periods.iter().all(|&n| n > 0),
            "{size} at {rate_hz} Hz: a swing without a clap: {periods:?}"
        );
    }
}

#[test]
fn a_flap_let_go_claps_as_it_lands_and_a_resting_sheet_never_does() {
    // The front edge lifted to 0.5 and let go at 1.5 s: the sheet falls back onto the table.
    let drop = r#"version = 1
duration_s = 2.5
[set]
size = "a5"
seed = 21
[[grab]]
slot = "front"
on_s = 0.0
off_s = 1.5
[[lane]]
id = "lift"
interp = "smooth"
points = [[0.0, 0.0], [1.0, 0.5]]
"#;
    let (frames, stats) = play_script_with_stats(&Script::parse(drop).unwrap(), None);
    let landing = (1.5 * FRAME_RATE) as usize..(2.2 * FRAME_RATE) as usize;
    let loudest = frames[landing.clone()]
        .iter()
        .flat_map(|f| f.crumple())
        .filter(|e| e.resonator.is_constrained())
        .map(|e| e.amplitude)
        .fold(0.0f32, f32::max);
    let impacts: u32 = stats[landing].iter().map(|s| s.impact_events).sum();
    eprintln!("flap let go: {impacts} impacts, the loudest clac {loudest:.2}");
    assert!(impacts > 0 && loudest > 0.2, "{impacts} impacts, {loudest}");
    // Lying still, or slid flat by one edge: no impact at all.
    for text in [
        "version = 1\nduration_s = 1.0\n".to_string(),
        "version = 1\nduration_s = 2.0\n[[grab]]\nslot = \"back\"\non_s = 0.0\n[[lane]]\n\
         id = \"slide\"\ninterp = \"smooth\"\npoints = [[0.0, 0.0], [1.5, 0.4]]\n"
            .to_string(),
    ] {
        let (_, stats) = play_script_with_stats(&Script::parse(&text).unwrap(), None);
        let impacts: u32 = stats.iter().map(|s| s.impact_events).sum();
        assert_eq!(impacts, 0, "{text}");
    }
}
