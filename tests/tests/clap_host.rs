//! The bundled `Papier.clap` in a real CLAP host (`clack-host`): descriptor and parameters,
//! processing at 44.1 and 96 kHz with maximum block sizes 1, 64, 512, 4096 and 16384, notes and
//! automation with an audible effect, state save/load byte-identity, corrupt state, the offline
//! render against `papier-render`; clap-validator's checks as far as this host can run them
//! (parameter fuzzing with sample-accurate changes, wildcard note events, params flush, state
//! while active); and the user sound database chosen through the state.

use std::process::Command;

use clack_host::prelude::ClapId;
use papier::gesture_map::MidiInput;
use papier::offline::midi_file::{TimedMidi, write_smf};
use papier_tests::audio::{all_finite_normal, peak, read_stereo};
use papier_tests::clap::{Bundle, HostEvent, Instance, NoteKind, ParamDesc, serial};
use papier_tests::paths;

fn bundle() -> Bundle {
    Bundle::load(&paths::clap_bundle()).expect("load Papier.clap")
}

/// Compares two saved states without printing kilobytes of bytes.
fn assert_same_state(a: &[u8], b: &[u8], what: &str) {
    if a != b {
        let dir = paths::scratch(&format!("state_diff_{}", what.replace(' ', "_")));
        let _ = std::fs::write(dir.join("a.bin"), a);
        let _ = std::fs::write(dir.join("b.bin"), b);
        // Skip the 8-byte length prefix to show where the JSON differs.
        let pos = a
            .iter()
            .zip(b)
            .skip(8)
            .position(|(x, y)| x != y)
            .map_or(a.len().min(b.len()), |p| p + 8);
        let lo = pos.saturating_sub(60);
        panic!(
            "{what}: states differ at byte {pos} (lengths {} and {}; both in {}):\n  {}\n  {}",
            a.len(),
            b.len(),
            dir.display(),
            String::from_utf8_lossy(&a[lo..(pos + 60).min(a.len())]),
            String::from_utf8_lossy(&b[lo..(pos + 60).min(b.len())]),
        );
    }
}

fn instance(b: &Bundle) -> Instance {
    b.instance().expect("instantiate Papier")
}

/// A gesture phrase: grab the front edge, lift and twist it by CC, automate slide, release,
/// reset. `sr` converts seconds to samples.
fn phrase(inst: &Instance, sr: f64) -> Vec<HostEvent> {
    let at = |t: f64| (t * sr).round() as u64;
    let slide = inst.param("Slide");
    vec![
        HostEvent::NoteOn {
            at: at(0.01),
            key: 50,
            velocity: 0.8,
        },
        HostEvent::Midi {
            at: at(0.05),
            data: [0xB0, 22, 100],
        },
        HostEvent::Param {
            at: at(0.08),
            id: slide,
            value: 0.5,
        },
        HostEvent::Midi {
            at: at(0.12),
            data: [0xB3, 23, 20],
        },
        HostEvent::NoteOn {
            at: at(0.15),
            key: 48,
            velocity: 1.0,
        },
        HostEvent::NoteOff {
            at: at(0.2),
            key: 50,
        },
        HostEvent::NoteOff {
            at: at(0.25),
            key: -1,
        },
        HostEvent::Midi {
            at: at(0.27),
            data: [0x90, 36, 127],
        },
    ]
}

#[test]
fn descriptor_and_parameters_are_what_a_daw_expects() {
    let _serial = serial();
    let b = bundle();
    let (id, name, features) = b.descriptor();
    assert_eq!(id, "org.papier.papier");
    assert_eq!(name, "Papier");
    assert!(features.iter().any(|f| f == "instrument"), "{features:?}");
    assert!(features.iter().any(|f| f == "stereo"), "{features:?}");
    let inst = instance(&b);
    let names: Vec<&str> = inst.params.iter().map(|p| p.name.as_str()).collect();
    for expected in [
        "Crumple",
        "Slide",
        "Lift",
        "Twist",
        "Shake Depth",
        "Shake Rate",
        "Tear Amount",
        "Tear Steer",
        "Tear Position",
        "Pull Separation",
        "Pull Asymmetry",
        "Size",
        "Material",
        "Seed",
        "Table",
        "Table Height",
        "Wall",
        "Wall Distance",
        "Listener Azimuth",
        "Listener Distance",
        "Crumple Level",
        "Friction Level",
        "Tear Level",
        "Output Gain",
    ] {
        assert!(
            names.contains(&expected),
            "missing parameter {expected}: {names:?}"
        );
    }
    assert_eq!(inst.params.len(), 24, "{names:?}");
    let gestures = inst.params.iter().find(|p| p.name == "Slide").unwrap();
    assert_eq!(gestures.module, "Gestures");
    let size = inst.params.iter().find(|p| p.name == "Size").unwrap();
    assert_eq!(size.module, "Sheet");
}

/// −60 dBFS: a render whose peak stays below this is treated as silent.
const AUDIBLE: f32 = 1e-3;
/// How much louder than the idle render (no events) the phrase must be: a clear audible effect.
const PHRASE_OVER_IDLE: f32 = 10.0;

/// Processing at 44.1 and 96 kHz with maximum block sizes 1, 64, 512 and 4096 (and varying
/// block sizes up to the maximum), in real-time and offline mode. Detects a failure to
/// activate or process, output of the wrong length, NaN/Inf/subnormal samples, and, offline,
/// events that have no audible effect: the phrase must peak above −60 dBFS and at least ten
/// times above the idle render of the same configuration (measured: phrase peaks of 0.45–0.47,
/// idle exactly silent). In real time the sheet is simulated on its own thread, which the
/// test's faster-than-real-time processing outruns, so what is heard there depends on timing
/// (measured: anything from silence to 0.04) and only finiteness is checked.
#[test]
fn processes_at_44k_and_96k_with_every_maximum_block_size() {
    let _serial = serial();
    let b = bundle();
    for sr in [44_100.0, 96_000.0] {
        for max in [1u32, 64, 512, 4096] {
            for offline in [false, true] {
                let what = format!("{sr} Hz, max {max}, offline {offline}");
                // Varying block sizes up to the maximum, as hosts do.
                let sizes = [max, (max / 3).max(1), 1, max];
                let total = (0.35 * sr) as u64;
                let mut inst = instance(&b);
                inst.set_offline(offline).unwrap();
                let events = phrase(&inst, sr);
                let played = inst
                    .render(sr, max, &sizes, total, &events)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                let mut inst = instance(&b);
                inst.set_offline(offline).unwrap();
                let idle = inst
                    .render(sr, max, &sizes, total, &[])
                    .unwrap_or_else(|e| panic!("{what}, idle: {e}"));
                for out in [&played, &idle] {
                    assert_eq!(out.0.len() as u64, total, "{what}");
                    assert!(
                        all_finite_normal(&out.0) && all_finite_normal(&out.1),
                        "{what}"
                    );
                }
                let (p, q) = (stereo_peak(&played), stereo_peak(&idle));
                println!("{what}: phrase peak {p:e}, idle peak {q:e}");
                assert!(
                    !offline || (p >= AUDIBLE && p >= PHRASE_OVER_IDLE * q),
                    "{what}: the phrase is not clearly audible (peak {p:e}, idle {q:e})"
                );
            }
        }
    }
}

#[test]
fn extreme_and_fractional_sample_rates_stay_finite() {
    let _serial = serial();
    let b = bundle();
    // clap-validator processes at 8 kHz to 768 kHz, fractional rates included.
    for sr in [
        8_000.0, 22_050.5, 44_100.25, 192_000.0, 384_000.0, 768_000.0,
    ] {
        for offline in [false, true] {
            let mut inst = instance(&b);
            inst.set_offline(offline).unwrap();
            let events = phrase(&inst, sr);
            let (l, r) = inst
                .render(sr, 2027, &[2027, 17, 1, 256], (0.3 * sr) as u64, &events)
                .unwrap_or_else(|e| panic!("{sr} Hz: {e}"));
            assert!(
                all_finite_normal(&l) && all_finite_normal(&r),
                "{sr} Hz offline {offline}"
            );
        }
    }
}

#[test]
fn parameter_values_round_trip_through_text() {
    let _serial = serial();
    let b = bundle();
    let mut inst = instance(&b);
    let params = inst.params.clone();
    for p in &params {
        for t in [0.0, 0.25, 0.5, 0.77, 1.0] {
            let v = p.min + t * (p.max - p.min);
            let v = if p.max - p.min >= 1.0 && p.max.fract() == 0.0 && p.min.fract() == 0.0 {
                v.round()
            } else {
                v
            };
            let text = inst
                .value_to_text(p.id, v)
                .unwrap_or_else(|| panic!("{}: no text for {v}", p.name));
            let back = inst
                .text_to_value(p.id, &text)
                .unwrap_or_else(|| panic!("{}: {text:?} does not parse back", p.name));
            let again = inst.value_to_text(p.id, back).unwrap();
            assert_eq!(
                again, text,
                "{}: {v} -> {text:?} -> {back} -> {again:?}",
                p.name
            );
        }
    }
}

fn split_state(bytes: &[u8]) -> serde_json::Value {
    assert!(bytes.len() > 8, "state too short");
    let n = u64::from_le_bytes(bytes[..8].try_into().unwrap()) as usize;
    assert_eq!(n, bytes.len() - 8, "length prefix");
    serde_json::from_slice(&bytes[8..]).expect("state is JSON")
}

fn join_state(v: &serde_json::Value) -> Vec<u8> {
    let json = serde_json::to_vec(v).unwrap();
    let mut out = (json.len() as u64).to_le_bytes().to_vec();
    out.extend_from_slice(&json);
    out
}

#[test]
fn saved_state_reloads_and_resaves_byte_identically() {
    let _serial = serial();
    let b = bundle();
    let mut a = instance(&b);
    a.set_offline(true).unwrap();
    let sr = 48_000.0;
    let mut events = phrase(&a, sr);
    // Leave the sheet in a non-default place, and non-default parameters.
    events.retain(|e| {
        !matches!(
            e,
            HostEvent::Midi {
                data: [0x90, 36, _],
                ..
            }
        )
    });
    let size = a.param("Size");
    let crumple_level = a.param("Crumple Level");
    // Stepped parameters take their step index in CLAP (0–3 for the four sizes): 1 = A5.
    events.push(HostEvent::Param {
        at: 10,
        id: size,
        value: 1.0,
    });
    events.push(HostEvent::Param {
        at: 20,
        id: crumple_level,
        value: 0.25,
    });
    // Long enough for the released sheet to come to rest (a sheet in motion keeps moving after
    // reopening, as it should).
    a.render(sr, 512, &[], (6.0 * sr) as u64, &events).unwrap();
    let s1 = a.save_state().unwrap();
    let v1 = split_state(&s1);
    assert_eq!(v1["params"]["size"], serde_json::json!({"string": "a5"}));
    assert!(
        v1["fields"]["sheet"].is_string(),
        "the sheet is saved: {v1}"
    );
    assert_ne!(v1["fields"]["sheet"], "null", "a sheet that moved is saved");

    let mut c = instance(&b);
    c.load_state(&s1).unwrap();
    let s2 = c.save_state().unwrap();
    assert_same_state(&s1, &s2, "re-save after load");
    assert_eq!(c.param_value(size), a.param_value(size));

    // Reading the state a few bytes at a time (as some hosts stream it) gives the same result.
    let mut d = instance(&b);
    d.load_state_in_chunks(&s1, 3).unwrap();
    assert_same_state(&d.save_state().unwrap(), &s1, "load in 3-byte chunks");

    // Reopening means activating and playing on: a sheet at rest stays exactly as saved.
    d.set_offline(true).unwrap();
    d.render(sr, 256, &[], (0.2 * sr) as u64, &[]).unwrap();
    assert_same_state(&d.save_state().unwrap(), &s1, "idle reopened project");
}

/// A project saved with a torn sheet reopens torn (issue 51): the sheet torn in two by the tear
/// gesture through the host's parameters, saved, reopened in a new instance, resaved byte for
/// byte, and played on: still two pieces (the same mesh), the tear not going on (the amount
/// stays at its highest value), the sound finite.
#[test]
fn a_torn_sheet_saves_with_the_project_and_reopens_torn() {
    let _serial = serial();
    let b = bundle();
    let sr = 48_000.0;
    let mut a = instance(&b);
    a.set_offline(true).unwrap();
    let (pos, amount) = (a.param("Tear Position"), a.param("Tear Amount"));
    let mut events = vec![HostEvent::Param {
        at: 0,
        id: pos,
        value: 0.4,
    }];
    // Tear Amount ramped 0 → 1 over 2 s, a point every 10 ms.
    events.extend((1..=200u64).map(|k| HostEvent::Param {
        at: k * 480,
        id: amount,
        value: k as f64 / 200.0,
    }));
    let (l, r) = a.render(sr, 512, &[], (4.0 * sr) as u64, &events).unwrap();
    assert!(all_finite_normal(&l) && all_finite_normal(&r));
    let s1 = a.save_state().unwrap();
    let sheet = saved_sheet(&s1);
    assert_eq!(sheet["tear"]["separated"], true, "torn in two at the save");
    let vertices = sheet["pattern_m"].as_array().unwrap().len();
    let torn_m = sheet["tear"]["path_length_m"].as_f64().unwrap();
    assert!(torn_m > 0.2, "torn {torn_m} m");

    let mut c = instance(&b);
    c.load_state(&s1).unwrap();
    assert_same_state(&c.save_state().unwrap(), &s1, "torn re-save after load");
    assert_eq!(c.param_value(amount), Some(1.0));
    c.set_offline(true).unwrap();
    let (l, r) = c.render(sr, 256, &[], sr as u64, &[]).unwrap();
    assert!(all_finite_normal(&l) && all_finite_normal(&r));
    let reopened = saved_sheet(&c.save_state().unwrap());
    assert_eq!(reopened["tear"]["separated"], true, "reopened torn");
    assert_eq!(
        reopened["pattern_m"].as_array().unwrap().len(),
        vertices,
        "the torn mesh played on"
    );
    assert_eq!(reopened["tear"]["path_length_m"].as_f64().unwrap(), torn_m);
}

/// A project saved in another room than the one the instance last played in (the wall on, the
/// table higher) reopens in its own room: an instance that played in the default room and was
/// deactivated, then loads the project and plays a crumple, ends where a fresh instance playing
/// the same does. (A sheet is restored in the room of the simulation's configuration, and a
/// parked simulation still had the old room: the table sank back to its old height as soon as
/// the sheet woke.)
#[test]
fn a_project_reopens_in_its_own_room_after_the_instance_played_in_another() {
    let _serial = serial();
    let b = bundle();
    let sr = 48_000.0;
    let mut a = instance(&b);
    a.set_offline(true).unwrap();
    let room = [("Wall", 1.0), ("Wall Distance", 0.6), ("Table Height", 0.5)];
    let events: Vec<HostEvent> = room
        .iter()
        .map(|&(name, value)| HostEvent::Param {
            at: 0,
            id: a.param(name),
            value,
        })
        .collect();
    // Long enough for the sheet to settle on the raised table and sleep.
    a.render(sr, 512, &[], (6.0 * sr) as u64, &events).unwrap();
    let saved = a.save_state().unwrap();
    assert_ne!(
        split_state(&saved)["fields"]["sheet"],
        "null",
        "the sheet moved"
    );

    let crumple = [HostEvent::Param {
        at: 10,
        id: a.param("Crumple"),
        value: 0.3,
    }];
    let reopen = |played_before: bool| {
        let mut c = instance(&b);
        c.set_offline(true).unwrap();
        if played_before {
            c.render(sr, 256, &[], (0.2 * sr) as u64, &[]).unwrap();
        }
        c.load_state(&saved).unwrap();
        c.render(sr, 256, &[], (3.0 * sr) as u64, &crumple).unwrap();
        c.save_state().unwrap()
    };
    let fresh = reopen(false);
    assert_ne!(
        split_state(&fresh)["fields"]["sheet"],
        split_state(&saved)["fields"]["sheet"],
        "the crumple moved the sheet"
    );
    assert_same_state(
        &reopen(true),
        &fresh,
        "reopened after playing in another room",
    );

    // Loaded while playing in the default room: the sheet stays exactly as saved, asleep
    // (the loaded room goes to the simulation before the sheet, so the room change does not
    // wake it: a woken sheet settles again and is saved anew, a frame counter later).
    let mut c = instance(&b);
    c.set_offline(true).unwrap();
    let second = |t: f64| (t * sr) as u64;
    let ((), l, r) = c
        .process_concurrently(sr, 256, &[], |inst, audio| {
            assert!(audio.play_and_wait(second(0.2)), "audio thread failed");
            inst.load_state(&saved).unwrap();
            assert!(audio.play_and_wait(second(1.5)), "audio thread failed");
        })
        .unwrap();
    assert!(all_finite_normal(&l) && all_finite_normal(&r));
    assert_same_state(
        &c.save_state().unwrap(),
        &saved,
        "loaded while playing in another room",
    );
}

/// The sheet in a saved state (its JSON).
fn saved_sheet(state: &[u8]) -> serde_json::Value {
    let v = split_state(state);
    let text = v["fields"]["sheet"]
        .as_str()
        .expect("the sheet field is JSON text");
    serde_json::from_str(text).expect("the sheet is JSON")
}

/// A project saved while the sheet moves holds the sheet as it is at the save, offline and in
/// real time (the worker thread answers the save). Before, the sheet was published only when it
/// came to rest and every 400 frames (2 s) while it moved: a project saved 2.5 s into a shake
/// stored the sheet of 2.0 s.
#[test]
fn a_project_saved_mid_gesture_holds_the_sheet_as_it_is_at_the_save() {
    let _serial = serial();
    let b = bundle();
    let sr = 48_000.0;
    let second = |t: f64| (t * sr) as u64;
    // 2.5 s at 48 kHz: 500 frames of 240 samples.
    let frames = 500;
    // The front edge grabbed and shaken: the sheet moves all along (a crumple comes to rest
    // in the hands and sleeps within a second).
    let shake = |inst: &Instance| {
        vec![
            HostEvent::NoteOn {
                at: 10,
                key: 50,
                velocity: 0.8,
            },
            HostEvent::Param {
                at: 20,
                id: inst.param("Shake Depth"),
                value: 0.5,
            },
        ]
    };
    let check = |state: &[u8], what: &str| {
        let sheet = saved_sheet(state);
        assert_eq!(sheet["frame"], frames, "{what}: the saved sheet's frame");
        assert_eq!(
            sheet["asleep"], false,
            "{what}: the sheet moved at the save"
        );
    };

    // Offline, saved while active (a render that ends deactivates the plugin, which publishes
    // the sheet anyway).
    let mut a = instance(&b);
    a.set_offline(true).unwrap();
    let events = shake(&a);
    let (offline, l, r) = a
        .process_concurrently(sr, 512, &events, |inst, audio| {
            assert!(audio.play_and_wait(second(2.5)), "audio thread failed");
            inst.save_state().unwrap()
        })
        .unwrap();
    assert!(all_finite_normal(&l) && all_finite_normal(&r));
    check(&offline, "offline");

    // In real time: the audio thread is held to about real-time pace (10 ms blocks, 10 ms
    // apart) so the worker keeps up without skipping frames, as in a host.
    let mut c = instance(&b);
    c.set_offline(false).unwrap();
    let events = shake(&c);
    let (real_time, l, r) = c
        .process_concurrently(sr, 480, &events, |inst, audio| {
            for k in 1..=250 {
                assert!(audio.play_and_wait(second(0.01) * k), "audio thread failed");
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
            inst.save_state().unwrap()
        })
        .unwrap();
    assert!(all_finite_normal(&l) && all_finite_normal(&r));
    check(&real_time, "in real time");
}

#[test]
fn corrupt_state_is_rejected_and_the_plugin_keeps_its_values() {
    let _serial = serial();
    let b = bundle();
    let mut p = instance(&b);
    let defaults = p.save_state().unwrap();
    let mut x = 0x9E37_79B9u32;
    let mut random = |n: usize| -> Vec<u8> {
        (0..n)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                x as u8
            })
            .collect()
    };
    let mut truncated = defaults.clone();
    truncated.truncate(defaults.len() / 2);
    for bad in [
        vec![],
        random(1 << 20),
        random(1 << 20),
        random(1 << 20),
        truncated,
    ] {
        assert!(
            p.load_state(&bad).is_err(),
            "corrupt state of {} bytes was accepted",
            bad.len()
        );
        assert_same_state(
            &p.save_state().unwrap(),
            &defaults,
            "after a rejected state",
        );
    }

    // Valid JSON whose sheet is unreadable: the parameters load, the sheet is kept verbatim
    // (never lost), and the plugin still runs.
    let mut v = split_state(&defaults);
    v["fields"]["sheet"] =
        serde_json::Value::String("{\"version\":99,\"from\":\"the future\"}".into());
    v["params"]["slide"] = serde_json::json!({"f32": 0.75});
    let odd = join_state(&v);
    p.load_state(&odd).unwrap();
    let back = split_state(&p.save_state().unwrap());
    assert_eq!(back["fields"]["sheet"], v["fields"]["sheet"]);
    assert_eq!(back["params"]["slide"], serde_json::json!({"f32": 0.75}));
    let (l, r) = p.render(44_100.0, 128, &[], 4410, &[]).unwrap();
    assert!(all_finite_normal(&l) && all_finite_normal(&r));
}

/// The MIDI of the offline-equivalence renders: grab, lift, shake, twist, second grab, release,
/// reset, then a phrase (note 62, the quick tear: the render lasts until it has played). Times are on the 1/960 s grid of the MIDI file writer, so both sides see the same
/// samples.
fn equivalence_midi() -> Vec<(f64, MidiInput)> {
    vec![
        (
            0.1,
            MidiInput::NoteOn {
                key: 50,
                velocity: 100.0 / 127.0,
            },
        ),
        (
            0.5,
            MidiInput::Cc {
                cc: 22,
                value: 100.0 / 127.0,
            },
        ),
        (
            0.75,
            MidiInput::Cc {
                cc: 24,
                value: 90.0 / 127.0,
            },
        ),
        (
            1.0,
            MidiInput::Cc {
                cc: 23,
                value: 20.0 / 127.0,
            },
        ),
        (
            1.25,
            MidiInput::NoteOn {
                key: 48,
                velocity: 64.0 / 127.0,
            },
        ),
        (2.0, MidiInput::NoteOff { key: 50 }),
        (
            2.5,
            MidiInput::NoteOn {
                key: 36,
                velocity: 1.0,
            },
        ),
        (
            2.75,
            MidiInput::NoteOn {
                key: 62,
                velocity: 90.0 / 127.0,
            },
        ),
    ]
}

/// The slide automation of the offline-equivalence renders: (time s, value).
const EQUIVALENCE_SLIDE: [(f64, f64); 2] = [(0.7, 0.5), (1.6, 0.25)];

/// Renders [`equivalence_midi`] and [`EQUIVALENCE_SLIDE`] (3 s) with `papier-render` at `sr`,
/// with `extra` arguments; returns the stereo output.
fn papier_render_equivalence(name: &str, sr: u32, extra: &[&str]) -> (Vec<f32>, Vec<f32>) {
    let dir = paths::scratch(name);
    let timed: Vec<TimedMidi> = equivalence_midi()
        .iter()
        .map(|(t, m)| TimedMidi {
            time_s: *t,
            input: *m,
        })
        .collect();
    std::fs::write(dir.join("in.mid"), write_smf(&timed, 3.0)).unwrap();
    let points: Vec<String> = EQUIVALENCE_SLIDE
        .iter()
        .map(|(t, v)| format!("[{t}, {v}]"))
        .collect();
    std::fs::write(
        dir.join("in.toml"),
        format!(
            "version = 1\nduration_s = 3.0\n[[lane]]\nid = \"slide\"\ninterp = \"step\"\n\
             points = [{}]\n",
            points.join(", ")
        ),
    )
    .unwrap();
    let out = dir.join("render.wav");
    let status = Command::new(paths::papier_render())
        .args(["--midi"])
        .arg(dir.join("in.mid"))
        .arg("--script")
        .arg(dir.join("in.toml"))
        .arg("--out")
        .arg(&out)
        .args([
            "--sample-rate",
            &sr.to_string(),
            "--block",
            "300",
            "--quiet",
        ])
        .args(extra)
        .status()
        .unwrap();
    assert!(status.success(), "papier-render {extra:?} failed");
    let (rate, l, r) = read_stereo(&out);
    assert_eq!(rate, sr);
    (l, r)
}

/// [`equivalence_midi`] and [`EQUIVALENCE_SLIDE`] as host events at `sr`.
fn equivalence_events(inst: &Instance, sr: u32) -> Vec<HostEvent> {
    let sample = |t: f64| (t * f64::from(sr)).round() as u64;
    let mut events: Vec<HostEvent> = equivalence_midi()
        .iter()
        .map(|(t, m)| {
            let data = match *m {
                MidiInput::NoteOn { key, velocity } => {
                    [0x90, key, (velocity * 127.0).round() as u8]
                }
                MidiInput::NoteOff { key } => [0x80, key, 0],
                MidiInput::Cc { cc, value } => [0xB0, cc, (value * 127.0).round() as u8],
                MidiInput::AllNotesOff => [0xB0, 123, 0],
            };
            HostEvent::Midi {
                at: sample(*t),
                data,
            }
        })
        .collect();
    let slide = inst.param("Slide");
    for (t, v) in EQUIVALENCE_SLIDE {
        events.push(HostEvent::Param {
            at: sample(t),
            id: slide,
            value: v,
        });
    }
    events
}

/// Index of the first sample where two stereo renders differ bit-wise.
fn first_difference(a: &(Vec<f32>, Vec<f32>), b: &(Vec<f32>, Vec<f32>)) -> Option<usize> {
    assert_eq!(a.0.len(), b.0.len(), "render lengths");
    a.0.iter()
        .zip(&b.0)
        .chain(a.1.iter().zip(&b.1))
        .position(|(x, y)| x.to_bits() != y.to_bits())
}

/// Largest absolute sample of a stereo render.
fn stereo_peak(x: &(Vec<f32>, Vec<f32>)) -> f32 {
    peak(&x.0).max(peak(&x.1))
}

/// Detects any divergence between the plugin in a host's offline render mode and
/// `papier-render` on the same MIDI and automation (different block sizes on both sides), and,
/// since equal silence would prove nothing, a render that is silent.
#[test]
fn offline_render_equals_papier_render() {
    let _serial = serial();
    let sr = 48_000u32;
    let reference = papier_render_equivalence("clap_offline_equivalence", sr, &[]);
    let b = bundle();
    let mut inst = instance(&b);
    inst.set_offline(true).unwrap();
    let events = equivalence_events(&inst, sr);
    let host = inst
        .render(
            f64::from(sr),
            512,
            &[512, 100, 37, 512, 1, 255],
            reference.0.len() as u64,
            &events,
        )
        .unwrap();
    assert_eq!(
        first_difference(&host, &reference),
        None,
        "host offline render differs from papier-render"
    );
    let p = stereo_peak(&host);
    assert!(
        p >= AUDIBLE,
        "the compared render is (nearly) silent, peak {p:e}: the equality proves nothing"
    );
}

/// A small deterministic random generator (xorshift64*), so that fuzzing runs are reproducible.
struct Rng(u64);

impl Rng {
    fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A random value of `p` in its CLAP range (whole numbers for stepped parameters).
    fn value(&mut self, p: &ParamDesc) -> f64 {
        let v = p.min + self.next_f64() * (p.max - p.min);
        if p.stepped { v.round() } else { v }
    }
}

/// Checks that the plugin reports `expected` (CLAP id, value) for every parameter.
fn assert_values(inst: &mut Instance, expected: &[(ClapId, f64)], what: &str) {
    for &(id, v) in expected {
        let name = inst
            .params
            .iter()
            .find(|p| p.id == id)
            .map(|p| p.name.clone())
            .unwrap_or_default();
        let got = inst
            .param_value(id)
            .unwrap_or_else(|| panic!("{what}: no value for {name}"));
        assert!(
            (got - v).abs() <= 1e-4 * (1.0 + v.abs()),
            "{what}: {name} is {got}, expected {v}"
        );
    }
}

/// clap-validator's parameter fuzzing with sample-accurate changes: every parameter gets a new
/// random value every 10, 100 or 1000 samples (in the middle of blocks of varying sizes) for
/// 3 s of audio while the sheet is held and crumpled, in real-time and offline mode. Detects a
/// panic, an error from `process`, NaN/Inf/subnormal output, output beyond the soft clipper's
/// bound of ±1, and parameter events that are not applied (the last values must be the ones the
/// plugin reports).
#[test]
fn parameter_fuzzing_with_sample_accurate_changes_stays_finite_and_bounded() {
    let _serial = serial();
    let b = bundle();
    let sr = 48_000.0;
    let total = (3.0 * sr) as u64;
    let mut rng = Rng(0x5EED_1234_ABCD_0001);
    for (interval, offline) in [(10u64, false), (100, false), (1000, false), (100, true)] {
        let mut inst = instance(&b);
        inst.set_offline(offline).unwrap();
        let params = inst.params.clone();
        let mut events = vec![
            HostEvent::NoteOn {
                at: 0,
                key: 50,
                velocity: 0.9,
            },
            HostEvent::NoteOn {
                at: 5,
                key: 55,
                velocity: 0.6,
            },
        ];
        let mut last = Vec::new();
        let mut at = 0;
        while at < total {
            last.clear();
            for p in &params {
                let value = rng.value(p);
                events.push(HostEvent::Param {
                    at,
                    id: p.id,
                    value,
                });
                last.push((p.id, value));
            }
            // The gestures through MIDI too, so that the sheet moves whatever the fuzzer does.
            events.push(HostEvent::Midi {
                at,
                data: [0xB0, 1, (rng.next_f64() * 127.0) as u8],
            });
            at += interval;
        }
        let (l, r) = inst
            .render(sr, 512, &[512, 10, 333, 1, 512], total, &events)
            .unwrap_or_else(|e| panic!("every {interval} samples, offline {offline}: {e}"));
        assert!(
            all_finite_normal(&l) && all_finite_normal(&r),
            "every {interval} samples, offline {offline}: non-finite or subnormal output"
        );
        let p = peak(&l).max(peak(&r));
        assert!(
            p <= 1.0,
            "every {interval} samples, offline {offline}: peak {p} beyond full scale"
        );
        assert_values(
            &mut inst,
            &last,
            &format!("after fuzzing every {interval} samples"),
        );
    }
}

/// clap-validator's largest maximum block size, 16384, with full-size blocks. Detects a failure
/// to activate or process at that size, non-finite output, and, in offline mode, output that
/// depends on the block size (it must equal the same render in blocks of 512) or is silent.
#[test]
fn processes_with_a_maximum_block_of_16384() {
    let _serial = serial();
    let b = bundle();
    for sr in [44_100.0, 48_000.0] {
        let total = (1.5 * sr) as u64;
        let mut renders = Vec::new();
        for (max, sizes) in [
            (16_384u32, vec![16_384u32, 16_384, 7, 16_384]),
            (512, vec![]),
        ] {
            let mut inst = instance(&b);
            inst.set_offline(true).unwrap();
            let events = phrase(&inst, sr);
            let out = inst
                .render(sr, max, &sizes, total, &events)
                .unwrap_or_else(|e| panic!("{sr} Hz, max {max}: {e}"));
            assert!(all_finite_normal(&out.0) && all_finite_normal(&out.1));
            renders.push(out);
        }
        assert_eq!(
            first_difference(&renders[0], &renders[1]),
            None,
            "{sr} Hz: blocks of 16384 and of 512 render differently"
        );
        let p = stereo_peak(&renders[0]);
        assert!(p >= AUDIBLE, "{sr} Hz: silent render (peak {p:e})");
        // Real time, the same block sizes.
        let mut inst = instance(&b);
        let events = phrase(&inst, sr);
        let (l, r) = inst
            .render(sr, 16_384, &[16_384, 3, 16_384], total, &events)
            .unwrap_or_else(|e| panic!("{sr} Hz real time, max 16384: {e}"));
        assert!(all_finite_normal(&l) && all_finite_normal(&r));
    }
}

/// CLAP note events with wildcard (−1) port, channel, key and note id, notes off and chokes for
/// notes that were never on, a note on with no key, and a note port that does not exist, as
/// clap-validator sends them. Detects a crash or non-finite output; and, in offline mode, any
/// difference from the same performance sent as plain notes: a note on whose port, channel and
/// note id are wildcards must still grab, a wildcard note off (or choke) must let every hand go,
/// and the unmatched events must do nothing.
#[test]
fn wildcard_and_unmatched_note_events_are_harmless() {
    let _serial = serial();
    let b = bundle();
    let sr = 48_000.0;
    let at = |t: f64| (t * sr).round() as u64;
    let note = |at: u64, kind: NoteKind, port: i16, channel: i16, key: i16, note_id: i32| {
        HostEvent::Note {
            at,
            kind,
            port,
            channel,
            key,
            note_id,
            velocity: 0.8,
        }
    };
    let plain = |inst: &Instance| phrase(inst, sr);
    let wild = |inst: &Instance| {
        let mut e: Vec<HostEvent> = phrase(inst, sr)
            .into_iter()
            .map(|e| match e {
                // Port, channel and note id unspecified: the key alone says which hand.
                HostEvent::NoteOn { at: t, key, .. } => {
                    note(t, NoteKind::On, -1, -1, i16::from(key), -1)
                }
                // A note off for key 50 on any port and channel, with any note id.
                HostEvent::NoteOff { at: t, key: 50 } => note(t, NoteKind::Off, -1, -1, 50, -1),
                // Everything a wildcard: every note, i.e. every hand lets go.
                HostEvent::NoteOff { at: t, .. } => note(t, NoteKind::Off, -1, -1, -1, -1),
                other => other,
            })
            .collect();
        // Before anything is held: offs and chokes of notes never played, a note on without a
        // key, a note on a port the plugin does not have and its off.
        e.extend([
            note(0, NoteKind::Off, 0, 0, 53, -1),
            note(0, NoteKind::Off, -1, -1, -1, -1),
            note(at(0.001), NoteKind::Choke, -1, -1, -1, -1),
            note(at(0.002), NoteKind::Choke, 0, 3, 52, 77),
            note(at(0.003), NoteKind::On, 0, 0, -1, -1),
            note(at(0.004), NoteKind::Off, 0, 0, -1, 4),
            note(at(0.005), NoteKind::On, 7, 0, 59, -1),
            note(at(0.3), NoteKind::Off, 0, 9, 127, 12345),
            note(at(0.3), NoteKind::Choke, -1, -1, 48, 99),
        ]);
        e
    };
    let mut outs = Vec::new();
    for (events_of, offline) in [
        (&plain as &dyn Fn(&Instance) -> Vec<HostEvent>, true),
        (&wild, true),
        (&wild, false),
    ] {
        let mut inst = instance(&b);
        inst.set_offline(offline).unwrap();
        let events = events_of(&inst);
        let out = inst
            .render(sr, 256, &[256, 31, 256], at(0.5), &events)
            .unwrap();
        assert!(all_finite_normal(&out.0) && all_finite_normal(&out.1));
        assert!(stereo_peak(&out) <= 1.0);
        outs.push(out);
    }
    let p = stereo_peak(&outs[0]);
    assert!(p >= AUDIBLE, "the plain performance is silent (peak {p:e})");
    assert_eq!(
        first_difference(&outs[0], &outs[1]),
        None,
        "wildcard note events did not act as the plain notes do"
    );
}

/// Parameter values sent through `clap_plugin_params.flush` without any processing, inactive
/// and then active but not processing, as hosts do while the transport is stopped. Detects
/// flushed values that are not applied (`get_value` must report them), flush and `process`
/// disagreeing about the same values, and flushed values that processing then ignores (a gain
/// flushed to "off" must make the next render exactly silent).
#[test]
fn params_flush_without_processing_applies_values() {
    let _serial = serial();
    let b = bundle();
    let mut rng = Rng(0xF1_0511);
    let mut a = instance(&b);
    let params = a.params.clone();
    let values: Vec<(ClapId, f64)> = params.iter().map(|p| (p.id, rng.value(p))).collect();
    a.flush_params(&values).expect("flush while inactive");
    assert_values(&mut a, &values, "after an inactive flush");

    // The same values through process events: the plugin reports the same.
    let mut c = instance(&b);
    c.set_offline(true).unwrap();
    let events: Vec<HostEvent> = values
        .iter()
        .map(|&(id, value)| HostEvent::Param { at: 0, id, value })
        .collect();
    c.render(48_000.0, 64, &[], 64, &events).unwrap();
    for &(id, _) in &values {
        assert_eq!(
            a.param_value(id),
            c.param_value(id),
            "flush and process disagree on parameter {id:?}"
        );
    }

    // Active, not processing: flush again, then play.
    let sr = 48_000.0;
    let mut d = instance(&b);
    d.activate(sr, 512).unwrap();
    let more: Vec<(ClapId, f64)> = params.iter().map(|p| (p.id, rng.value(p))).collect();
    d.flush_params(&more).expect("flush while active");
    assert_values(&mut d, &more, "after an active flush");
    d.deactivate();
    d.render(sr, 512, &[], 4800, &[]).unwrap();
    assert_values(&mut d, &more, "after processing");

    // Processing uses the flushed values: output gain flushed to its minimum ("off") silences
    // the phrase that plays at the default gain.
    let gain = a.param("Output Gain");
    let gain_desc = params.iter().find(|p| p.id == gain).unwrap().clone();
    let mut outs = Vec::new();
    for g in [gain_desc.min, gain_desc.default] {
        let mut d = instance(&b);
        d.set_offline(true).unwrap();
        d.activate(sr, 512).unwrap();
        d.flush_params(&[(gain, g)]).expect("flush while active");
        d.deactivate();
        let events = phrase(&d, sr);
        outs.push(d.render(sr, 512, &[], (0.6 * sr) as u64, &events).unwrap());
    }
    // The engine starts at the mix (it does not glide there from 0 dB), so "off" is silent
    // from the first sample.
    let whole = |o: &(Vec<f32>, Vec<f32>)| peak(&o.0).max(peak(&o.1));
    let (off, on) = (whole(&outs[0]), whole(&outs[1]));
    println!("peak {off:e} with the gain off, {on:e} at the default");
    assert!(on >= AUDIBLE, "silent at the default gain (peak {on:e})");
    assert_eq!(off, 0.0, "output gain flushed to off, but the plugin plays");
}

/// Saving and loading the state while the plugin is active in real-time mode and its audio
/// thread is processing, as a DAW does on undo or when the user loads a preset during
/// playback. Detects a save that misses parameter values set by events, a load that does not
/// apply the values (or that the running audio thread then overwrites), a re-save that differs
/// in its parameters, a deadlock between the two threads, and non-finite output around the
/// loads.
#[test]
fn state_save_and_load_while_active_in_real_time_keeps_parameter_values() {
    let _serial = serial();
    let b = bundle();
    let sr = 48_000.0;
    let mut fresh = instance(&b);
    let defaults = fresh.save_state().unwrap();
    let mut inst = instance(&b);
    inst.set_offline(false).unwrap();
    let params = inst.params.clone();
    let mut rng = Rng(0x57A7E);
    let values: Vec<(ClapId, f64)> = params.iter().map(|p| (p.id, rng.value(p))).collect();
    let default_values: Vec<(ClapId, f64)> = params.iter().map(|p| (p.id, p.default)).collect();
    let mut events: Vec<HostEvent> = values
        .iter()
        .map(|&(id, value)| HostEvent::Param { at: 0, id, value })
        .collect();
    // The phrase's notes and CCs, not its slide automation (the values above must stay).
    events.extend(
        phrase(&inst, sr)
            .into_iter()
            .filter(|e| !matches!(e, HostEvent::Param { .. })),
    );
    let second = |t: f64| (t * sr) as u64;
    let ((), l, r) = inst
        .process_concurrently(sr, 256, &events, |inst, audio| {
            assert!(audio.play_and_wait(second(0.1)), "audio thread failed");
            assert_values(inst, &values, "set by events while playing");
            let saved = inst.save_state().unwrap();
            // Load while the audio thread runs on.
            audio.play_to(second(0.6));
            inst.load_state(&defaults).unwrap();
            assert_values(inst, &default_values, "defaults loaded while playing");
            inst.load_state(&saved).unwrap();
            assert_values(inst, &values, "state loaded back while playing");
            assert!(audio.wait(), "audio thread failed");
            assert!(audio.processed() >= second(0.6));
            let resaved = inst.save_state().unwrap();
            assert_eq!(
                split_state(&resaved)["params"],
                split_state(&saved)["params"],
                "re-saved parameters differ"
            );
            assert!(audio.play_and_wait(second(0.8)), "audio thread failed");
            inst.idle();
            assert_values(inst, &values, "after playing on");
        })
        .unwrap();
    assert!(l.len() as u64 >= second(0.8));
    assert!(all_finite_normal(&l) && all_finite_normal(&r));
    assert!(peak(&l).max(peak(&r)) <= 1.0);
}

/// Writes a small valid user sound database into `dir` (the clac cell, three flap cells and two
/// friction spectra of the embedded database), so it sounds different from the default.
fn write_small_db(dir: &std::path::Path) {
    let (full, _) = papier::render::default_db::embedded_database().unwrap();
    let mut db = papier_tests::small_db::from(&full);
    db.info.name = "clap host test".into();
    db.write_dir(dir).unwrap();
}

/// `state` with the persisted user database folder set to `dir`.
fn with_db_path(state: &serde_json::Value, dir: &std::path::Path) -> serde_json::Value {
    let mut v = state.clone();
    v["fields"]["db_path"] =
        serde_json::Value::String(serde_json::to_string(&dir.to_str().unwrap()).unwrap());
    v
}

/// The user sound database (issue 5), chosen through the saved state as when a project that
/// uses one is opened, rendered offline at 44.1 kHz (the loader's default rate is 48 kHz).
/// Detects: a folder that is not loaded (the render equals the default database's), loaded
/// differently from `papier-render --db` (e.g. a database resampled for the wrong rate being
/// swapped in), a folder that is lost on save or does not play again after reloading, and a
/// broken folder that silences the plugin or changes its sound instead of leaving the default
/// database playing (the broken choice itself must be kept in the state).
#[test]
fn user_sound_database_from_the_state_plays_and_a_broken_one_keeps_the_default() {
    let _serial = serial();
    let sr = 44_100u32;
    let dir = paths::scratch("clap_user_db");
    let db_dir = dir.join("db");
    write_small_db(&db_dir);
    let broken = dir.join("broken");
    std::fs::create_dir_all(&broken).unwrap();
    std::fs::write(
        broken.join("manifest.toml"),
        "format = \"papier-sounddb\"\nversion = 1\nname = [oops\n",
    )
    .unwrap();
    let reference = papier_render_equivalence(
        "clap_user_db_reference",
        sr,
        &["--db", db_dir.to_str().unwrap()],
    );
    let total = reference.0.len() as u64;
    let b = bundle();
    let render = |inst: &mut Instance| {
        inst.set_offline(true).unwrap();
        let events = equivalence_events(inst, sr);
        inst.render(f64::from(sr), 512, &[512, 77, 300], total, &events)
            .unwrap()
    };

    let mut a = instance(&b);
    let initial = split_state(&a.save_state().unwrap());
    assert_eq!(initial["fields"]["db_path"], "null", "embedded by default");
    let default = render(&mut a);
    let p = stereo_peak(&default);
    assert!(p >= AUDIBLE, "the default database is silent (peak {p:e})");

    let with_db = with_db_path(&initial, &db_dir);
    let mut u = instance(&b);
    u.load_state(&join_state(&with_db)).unwrap();
    let user = render(&mut u);
    let p = stereo_peak(&user);
    assert!(p >= AUDIBLE, "the user database is silent (peak {p:e})");
    assert!(
        first_difference(&user, &default).is_some(),
        "the user database sounds exactly like the default one: not loaded"
    );
    assert_eq!(
        first_difference(&user, &reference),
        None,
        "the plugin plays the user database differently from papier-render --db"
    );

    // The folder survives saving after playing, and plays again when that state is reloaded
    // (with the initial sheet, so that the same performance gives the same samples).
    let mut saved = split_state(&u.save_state().unwrap());
    assert_eq!(saved["fields"]["db_path"], with_db["fields"]["db_path"]);
    saved["fields"]["sheet"] = initial["fields"]["sheet"].clone();
    let mut w = instance(&b);
    w.load_state(&join_state(&saved)).unwrap();
    assert_eq!(
        first_difference(&render(&mut w), &user),
        None,
        "the reloaded project does not play its user database"
    );

    // A broken folder: the default database plays on, and the choice stays in the project.
    for bad in [broken.clone(), dir.join("missing")] {
        let with_bad = with_db_path(&initial, &bad);
        let mut x = instance(&b);
        x.load_state(&join_state(&with_bad)).unwrap();
        let out = render(&mut x);
        assert_eq!(
            first_difference(&out, &default),
            None,
            "{}: a broken database did not leave the default playing",
            bad.display()
        );
        assert_eq!(
            split_state(&x.save_state().unwrap())["fields"]["db_path"],
            with_bad["fields"]["db_path"]
        );
    }
}
