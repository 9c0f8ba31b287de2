//! One performance, one take at every sample rate: the sheet's timeline does not depend on the
//! audio rate, for scenes (scripts) and MIDI performances alike (`papier::offline::timeline`: a lane is read at each frame's exact time, not at
//! its rounded sample; `papier::engine::FrameClock::time_s`). `papier-render` plays a scene at
//! several rates; the OBJ sequence (the sheet) and the sound-frame log (every crumple and
//! friction event with its resonators) must be the same bytes at each.
//!
//! Breakage detected: before the frame times were exact, `s4_crumple` gave other sheets at 22.05
//! and 44.1 kHz, and `c5_full_crumple` three different sheets over 22.05, 44.1, 48 and 96 kHz
//! (a 5 ms frame is 220.5 and 110.25 samples there).

use std::path::Path;
use std::process::Command;

use papier::gesture_map::MidiInput;
use papier::offline::midi_file::{TimedMidi, write_smf};
use papier_tests::paths;

/// The sheet (OBJ files at 25 per second, concatenated) and the frame log without its header
/// comments, rendered from `scene` (a built-in scene, or a MIDI file's path) at `rate_hz`.
fn take(dir: &Path, scene: &str, rate_hz: u32) -> (Vec<u8>, String) {
    let name = Path::new(scene).file_stem().unwrap().to_str().unwrap();
    let tag = format!("{name}_{rate_hz}");
    let objs = dir.join(format!("obj_{tag}"));
    let log = dir.join(format!("{tag}.jsonl"));
    let input = if scene.ends_with(".mid") {
        "--midi"
    } else {
        "--scene"
    };
    let out = Command::new(paths::papier_render())
        .args([input, scene, "--sample-rate", &rate_hz.to_string()])
        .args(["--out", dir.join(format!("{tag}.wav")).to_str().unwrap()])
        .args(["--obj-dir", objs.to_str().unwrap(), "--obj-fps", "25"])
        .args(["--write-frames", log.to_str().unwrap(), "--quiet"])
        .output()
        .expect("run papier-render");
    assert!(
        out.status.success(),
        "{tag}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut files: Vec<_> = std::fs::read_dir(&objs)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() > 10, "{tag}: {} OBJ files", files.len());
    let sheet = files
        .iter()
        .flat_map(|f| std::fs::read(f).unwrap())
        .collect();
    let events = std::fs::read_to_string(&log)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n");
    (sheet, events)
}

fn same_at_every_rate(scenes: &[&str], rates: &[u32]) {
    let dir = tempfile_dir().join("renders");
    std::fs::create_dir_all(&dir).unwrap();
    for scene in scenes {
        let (sheet, events) = take(&dir, scene, 48_000);
        assert!(events.contains("crumple") || events.contains("friction"));
        for &r in rates.iter().filter(|&&r| r != 48_000) {
            let (s, e) = take(&dir, scene, r);
            assert!(
                s == sheet,
                "{scene}: another sheet at {r} Hz than at 48 kHz"
            );
            assert!(
                e == events,
                "{scene}: other sound events at {r} Hz than at 48 kHz"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn tempfile_dir() -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!(
        "papier-sample-rates-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The two crumples that diverged, at the eight rates of the issue.
#[test]
fn the_crumples_are_the_same_sheet_and_events_at_every_rate() {
    same_at_every_rate(&["s4_crumple", "c5_full_crumple"], &RATES);
}

/// A MIDI performance (README map: grabs on notes, gesture CCs ramped, a reset, a crumple) at
/// the eight rates, its events off the frame boundaries as a player's are.
#[test]
fn a_midi_performance_is_the_same_sheet_and_events_at_every_rate() {
    let dir = tempfile_dir();
    let mut ev = Vec::new();
    let mut at = |t: f64, input| ev.push(TimedMidi { time_s: t, input });
    at(
        0.2013,
        MidiInput::NoteOn {
            key: 48,
            velocity: 0.9,
        },
    );
    at(
        0.3377,
        MidiInput::NoteOn {
            key: 50,
            velocity: 0.7,
        },
    );
    for i in 0..=30 {
        let t = 0.5 + i as f64 * 0.0371;
        at(
            t,
            MidiInput::Cc {
                cc: 21,
                value: i as f32 / 30.0 * 0.6,
            },
        );
        at(
            t + 0.013,
            MidiInput::Cc {
                cc: 22,
                value: i as f32 / 30.0 * 0.5,
            },
        );
    }
    at(1.9, MidiInput::NoteOff { key: 48 });
    at(
        2.1,
        MidiInput::NoteOn {
            key: 55,
            velocity: 1.0,
        },
    );
    for i in 0..=20 {
        let t = 2.2 + i as f64 * 0.0433;
        at(
            t,
            MidiInput::Cc {
                cc: 20,
                value: i as f32 / 20.0 * 0.8,
            },
        );
    }
    at(
        3.4,
        MidiInput::NoteOn {
            key: 36,
            velocity: 1.0,
        },
    );
    at(
        3.6,
        MidiInput::NoteOn {
            key: 50,
            velocity: 0.5,
        },
    );
    at(3.8, MidiInput::Cc { cc: 24, value: 0.6 });
    at(3.8, MidiInput::Cc { cc: 25, value: 0.5 });
    let midi = dir.join("performance.mid");
    std::fs::write(&midi, write_smf(&ev, 4.5)).unwrap();
    same_at_every_rate(&[midi.to_str().unwrap()], &RATES);
}

/// The eight rates of the issue.
const RATES: [u32; 8] = [
    22_050, 32_000, 44_100, 48_000, 88_200, 96_000, 176_400, 192_000,
];

/// The other seed scenes at the eight rates, in two halves (run side by side).
#[test]
fn the_other_seed_scenes_are_the_same_at_every_rate_a() {
    same_at_every_rate(
        &[
            "c1_first_sharp_feature",
            "c2_moebius_twist",
            "c3_unload_after_singularity",
            "c4_double_bend",
            "c6_four_corner_flip",
        ],
        &RATES,
    );
}

#[test]
fn the_other_seed_scenes_are_the_same_at_every_rate_b() {
    same_at_every_rate(
        &[
            "s1_slide_release_pinch",
            "s2_shake",
            "s3_wiggle_near_wall",
            "s5_fold_and_revert",
            "s6_slide_on_table",
        ],
        &RATES,
    );
}

/// The 44.1 and 48 kHz renders of the crumples are the same performance band by band: every
/// 1/3-octave level from 79 Hz to 16 kHz within 0.5 dB (the friction frames last 7/150 s at both
/// rates, so a source gets the same random-phase frames at the same times; `sounddb::prepared`).
#[test]
fn the_crumples_sound_the_same_at_44_1_and_48_khz_band_by_band() {
    use sounddb::analysis::{third_octave_centres_hz, third_octave_levels_db, welch_psd};
    let dir = tempfile_dir();
    let levels = |scene: &str, rate: u32| {
        let out = dir.join(format!("{scene}_{rate}.wav"));
        let o = Command::new(paths::papier_render())
            .args([
                "--scene",
                scene,
                "--sample-rate",
                &rate.to_string(),
                "--out",
                out.to_str().unwrap(),
                "--quiet",
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let (_, l, r) = papier_tests::audio::read_stereo(&out);
        let mono: Vec<f32> = l.iter().zip(&r).map(|(a, b)| 0.5 * (a + b)).collect();
        // The same analysis window in seconds at both rates (85 ms, 11.7 Hz bins).
        let n = (f64::from(rate) * 4096.0 / 48_000.0).round() as usize;
        let psd = welch_psd(&mono, f64::from(rate), n);
        third_octave_levels_db(&psd, f64::from(rate) / n as f64)
    };
    let centres = third_octave_centres_hz();
    for scene in ["s4_crumple", "c5_full_crumple"] {
        let (a, b) = (levels(scene, 44_100), levels(scene, 48_000));
        for (k, &fc) in centres.iter().enumerate() {
            if (75.0..=16_500.0).contains(&fc) {
                assert!(
                    (a[k] - b[k]).abs() <= 0.5,
                    "{scene}: {fc:.0} Hz band {:.2} dB at 44.1 kHz, {:.2} dB at 48 kHz",
                    a[k],
                    b[k]
                );
            }
        }
    }
}
