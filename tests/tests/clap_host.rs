//! The bundled `Papier.clap` in a real CLAP host (`clack-host`): descriptor and parameters,
//! processing at 44.1 and 96 kHz with maximum block sizes 1, 64, 512 and 4096, notes and
//! automation, state save/load byte-identity, corrupt state, and the offline render against
//! `papier-render`.

use std::process::Command;

use papier::gesture_map::MidiInput;
use papier::offline::midi_file::{TimedMidi, write_smf};
use papier_tests::audio::{all_finite_normal, read_stereo};
use papier_tests::clap::{Bundle, HostEvent, Instance, serial};
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

#[test]
fn processes_at_44k_and_96k_with_every_maximum_block_size() {
    let _serial = serial();
    let b = bundle();
    for sr in [44_100.0, 96_000.0] {
        for max in [1u32, 64, 512, 4096] {
            let mut inst = instance(&b);
            let events = phrase(&inst, sr);
            // Varying block sizes up to the maximum, as hosts do.
            let sizes = [max, (max / 3).max(1), 1, max];
            let total = (0.35 * sr) as u64;
            let (l, r) = inst
                .render(sr, max, &sizes, total, &events)
                .unwrap_or_else(|e| panic!("{sr} Hz, max {max}: {e}"));
            assert_eq!(l.len() as u64, total);
            assert!(
                all_finite_normal(&l) && all_finite_normal(&r),
                "{sr} Hz, max {max}"
            );
        }
    }
}

#[test]
fn extreme_and_fractional_sample_rates_stay_finite() {
    let _serial = serial();
    let b = bundle();
    // clap-validator processes at 8 kHz to 768 kHz, fractional rates included.
    for sr in [8_000.0, 22_050.5, 44_100.25, 192_000.0, 384_000.0, 768_000.0] {
        for offline in [false, true] {
            let mut inst = instance(&b);
            inst.set_offline(offline).unwrap();
            let events = phrase(&inst, sr);
            let (l, r) = inst
                .render(sr, 2027, &[2027, 17, 1, 256], (0.3 * sr) as u64, &events)
                .unwrap_or_else(|e| panic!("{sr} Hz: {e}"));
            assert!(all_finite_normal(&l) && all_finite_normal(&r), "{sr} Hz offline {offline}");
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
            assert_eq!(again, text, "{}: {v} -> {text:?} -> {back} -> {again:?}", p.name);
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

#[test]
fn offline_render_equals_papier_render() {
    let _serial = serial();
    let sr = 48_000u32;
    let dir = paths::scratch("clap_offline_equivalence");
    // Times on the 1/960 s grid of the MIDI file writer, so both sides see the same samples.
    let midi = [
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
    ];
    let timed: Vec<TimedMidi> = midi
        .iter()
        .map(|(t, m)| TimedMidi {
            time_s: *t,
            input: *m,
        })
        .collect();
    std::fs::write(dir.join("in.mid"), write_smf(&timed, 3.0)).unwrap();
    std::fs::write(
        dir.join("in.toml"),
        "version = 1\nduration_s = 3.0\n[[lane]]\nid = \"slide\"\ninterp = \"step\"\n\
         points = [[0.7, 0.5], [1.6, 0.25]]\n",
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
        .args(["--sample-rate", "48000", "--block", "300", "--quiet"])
        .status()
        .unwrap();
    assert!(status.success());
    let (rate, rl, rr) = read_stereo(&out);
    assert_eq!(rate, sr);

    let b = bundle();
    let mut inst = instance(&b);
    inst.set_offline(true).unwrap();
    let sample = |t: f64| (t * f64::from(sr)).round() as u64;
    let mut events: Vec<HostEvent> = midi
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
    events.push(HostEvent::Param {
        at: sample(0.7),
        id: slide,
        value: 0.5,
    });
    events.push(HostEvent::Param {
        at: sample(1.6),
        id: slide,
        value: 0.25,
    });
    let (hl, hr) = inst
        .render(
            f64::from(sr),
            512,
            &[512, 100, 37, 512, 1, 255],
            rl.len() as u64,
            &events,
        )
        .unwrap();
    assert_eq!(hl.len(), rl.len());
    let first_diff = hl
        .iter()
        .zip(&rl)
        .chain(hr.iter().zip(&rr))
        .position(|(a, b)| a.to_bits() != b.to_bits());
    assert_eq!(
        first_diff, None,
        "host offline render differs from papier-render"
    );
}
