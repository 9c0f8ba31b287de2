//! `papier-render` as a user runs it: a 10 s MIDI file to WAV plus an OBJ sequence, twice,
//! byte-identical; every built-in scene, also played from its MIDI export; and bad input (missing, empty, truncated or random-bytes
//! MIDI and script files, unknown `--set` ids or values, bad options) giving a clear one-line
//! error and a non-zero exit, never a panic.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use papier::gesture_map::MidiInput;
use papier::offline::midi_file::{TimedMidi, write_smf};
use papier_tests::audio::{all_finite_normal, read_stereo};
use papier_tests::paths;

fn run(args: &[&str]) -> Output {
    Command::new(paths::papier_render())
        .args(args)
        .output()
        .expect("run papier-render")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A 10 s gesture performance using the README's MIDI map.
fn ten_second_midi(path: &Path) {
    let mut ev = Vec::new();
    let mut at = |t: f64, input| ev.push(TimedMidi { time_s: t, input });
    at(
        0.2,
        MidiInput::NoteOn {
            key: 48,
            velocity: 0.9,
        },
    );
    at(
        0.3,
        MidiInput::NoteOn {
            key: 50,
            velocity: 0.7,
        },
    );
    for i in 0..=40 {
        let t = 0.5 + i as f64 * 0.05;
        at(
            t,
            MidiInput::Cc {
                cc: 21,
                value: i as f32 / 40.0 * 0.6,
            },
        );
    }
    at(2.6, MidiInput::NoteOff { key: 48 });
    at(3.0, MidiInput::Cc { cc: 22, value: 0.8 });
    at(3.5, MidiInput::Cc { cc: 24, value: 0.7 });
    at(3.5, MidiInput::Cc { cc: 25, value: 0.5 });
    at(5.5, MidiInput::Cc { cc: 24, value: 0.0 });
    at(6.0, MidiInput::Cc { cc: 23, value: 0.9 });
    at(7.0, MidiInput::Cc { cc: 23, value: 0.1 });
    at(7.5, MidiInput::NoteOff { key: 50 });
    at(
        8.0,
        MidiInput::NoteOn {
            key: 36,
            velocity: 1.0,
        },
    );
    at(
        8.2,
        MidiInput::NoteOn {
            key: 55,
            velocity: 1.0,
        },
    );
    at(8.4, MidiInput::Cc { cc: 20, value: 0.5 });
    at(8.8, MidiInput::Cc { cc: 20, value: 0.0 });
    at(8.9, MidiInput::NoteOff { key: 55 });
    std::fs::write(path, write_smf(&ev, 9.0)).unwrap();
}

fn obj_files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    v.sort();
    v
}

#[test]
fn ten_second_midi_renders_wav_and_obj_identically_twice() {
    let dir = paths::scratch("render_cli_midi");
    let mid = dir.join("perf.mid");
    ten_second_midi(&mid);
    let mut wavs = Vec::new();
    for run_idx in 0..2 {
        let out = dir.join(format!("out{run_idx}.wav"));
        let objs = dir.join(format!("obj{run_idx}"));
        let o = run(&[
            "--midi",
            s(&mid),
            "--out",
            s(&out),
            "--obj-dir",
            s(&objs),
            "--obj-fps",
            "10",
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(o.stdout.is_empty(), "--quiet prints nothing on success");
        let (rate, l, r) = read_stereo(&out);
        assert_eq!(rate, 48_000);
        // 9 s of MIDI file plus the 1 s tail.
        assert_eq!(l.len(), 480_000);
        assert!(all_finite_normal(&l) && all_finite_normal(&r));
        let files = obj_files(&objs);
        assert_eq!(files.len(), 101, "one OBJ per 0.1 s, both ends included");
        assert_eq!(files[0].file_name().unwrap(), "frame_00000.obj");
        wavs.push((std::fs::read(&out).unwrap(), files));
    }
    assert!(
        wavs[0].0 == wavs[1].0,
        "two renders give identical WAV bytes"
    );
    for (a, b) in wavs[0].1.iter().zip(&wavs[1].1) {
        assert!(
            std::fs::read(a).unwrap() == std::fs::read(b).unwrap(),
            "{} differs between runs",
            a.display()
        );
    }
    // The OBJ files are what Blender and an isometry check need: v in metres, vt = pattern.
    let text = std::fs::read_to_string(&wavs[0].1[50]).unwrap();
    let v = text.lines().filter(|l| l.starts_with("v ")).count();
    let vt = text.lines().filter(|l| l.starts_with("vt ")).count();
    let f = text.lines().filter(|l| l.starts_with("f ")).count();
    assert!(v > 20 && v == vt && f > 20, "v {v}, vt {vt}, f {f}");
}

#[test]
fn block_size_and_rate_options_are_honoured() {
    let dir = paths::scratch("render_cli_blocks");
    let mid = dir.join("perf.mid");
    ten_second_midi(&mid);
    // The render does not depend on the emulated host block size.
    let mut outs = Vec::new();
    for block in ["1", "333", "16384"] {
        let out = dir.join(format!("b{block}.wav"));
        let o = run(&[
            "--midi",
            s(&mid),
            "--out",
            s(&out),
            "--block",
            block,
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        outs.push(std::fs::read(&out).unwrap());
    }
    assert!(
        outs[0] == outs[1] && outs[1] == outs[2],
        "block size changed the render"
    );
    for rate in ["8000", "44100", "192000"] {
        let out = dir.join(format!("r{rate}.wav"));
        let o = run(&[
            "--midi",
            s(&mid),
            "--out",
            s(&out),
            "--sample-rate",
            rate,
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let (r, l, rr) = read_stereo(&out);
        assert_eq!(r.to_string(), rate);
        assert!(all_finite_normal(&l) && all_finite_normal(&rr));
    }
}

#[test]
fn every_scene_renders_with_finite_meshes_inside_the_room() {
    let dir = paths::scratch("render_cli_scenes");
    let list = run(&["--list-scenes"]);
    assert!(list.status.success());
    let names: Vec<String> = String::from_utf8_lossy(&list.stdout)
        .lines()
        .map(str::to_string)
        .collect();
    assert_eq!(names.len(), 12, "{names:?}");
    for name in &names {
        let out = dir.join(format!("{name}.wav"));
        let objs = dir.join(name);
        let o = run(&[
            "--scene",
            name,
            "--out",
            s(&out),
            "--obj-dir",
            s(&objs),
            "--obj-fps",
            "20",
            "--quiet",
        ]);
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let (_, l, r) = read_stereo(&out);
        assert!(all_finite_normal(&l) && all_finite_normal(&r), "{name}");
        for f in obj_files(&objs) {
            for c in obj_vertices(&f) {
                assert!(c.iter().all(|x| x.is_finite()), "{}: {c:?}", f.display());
                // The room: floor at z = 0, nothing beyond 3 m.
                assert!(
                    c[2] >= -1e-3 && c.iter().all(|x| x.abs() < 3.0),
                    "{}: {c:?}",
                    f.display()
                );
            }
        }
    }
}

/// Vertex positions of an OBJ file.
fn obj_vertices(path: &Path) -> Vec<[f64; 3]> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|rest| {
            let c: Vec<f64> = rest.split(' ').map(|x| x.parse().unwrap()).collect();
            [c[0], c[1], c[2]]
        })
        .collect()
}

/// Distances between corresponding vertices of two meshes, centimetres.
fn distances_cm<'a>(a: &'a [[f64; 3]], b: &'a [[f64; 3]]) -> impl Iterator<Item = f64> + 'a {
    assert_eq!(a.len(), b.len(), "different meshes");
    a.iter().zip(b).map(|(p, q)| {
        100.0 * ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
    })
}

/// Mean distance between corresponding vertices, centimetres.
fn mean_distance_cm(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    distances_cm(a, b).sum::<f64>() / a.len() as f64
}

/// Largest distance between corresponding vertices, centimetres.
fn max_distance_cm(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    distances_cm(a, b).fold(0.0, f64::max)
}

/// Every scene exported as a MIDI performance (`--write-midi`, the README's map) and rendered
/// back from it (`--midi` + the printed `--set` options) moves the sheet as the scene does: over
/// the OBJ frames the sheets differ by a small fraction of how far the scene moves them (mean
/// vertex distance < 1/4 of the largest vertex travel, worst frame < 1/2; measured: 0.1–5 % for
/// the held and slid scenes, 18–21 % for the two crumples, whose buckling 7-bit CCs steer into
/// other but similar folds), and the sound is finite. A performance missing its grabs or
/// gestures leaves the sheet where it was and fails the worst-frame bound.
#[test]
fn every_scene_plays_from_its_midi_performance() {
    let dir = paths::scratch("render_cli_scene_midi");
    let list = run(&["--list-scenes"]);
    let names: Vec<String> = String::from_utf8_lossy(&list.stdout)
        .lines()
        .map(str::to_string)
        .collect();
    assert_eq!(names.len(), 12);
    for name in &names {
        let mid = dir.join(format!("{name}.mid"));
        let o = run(&["--scene", name, "--write-midi", s(&mid)]);
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let stdout = String::from_utf8_lossy(&o.stdout).to_string();
        let line = stdout
            .lines()
            .find(|l| l.contains("render it:"))
            .unwrap_or_else(|| panic!("{name}: no render line in {stdout}"));
        // "papier-render --midi FILE --set a=b ... --out OUT.wav"
        let words: Vec<&str> = line.split_whitespace().collect();
        let mut args: Vec<String> = Vec::new();
        let mut k = 0;
        while k < words.len() {
            if words[k] == "--set" {
                args.push("--set".into());
                args.push(words[k + 1].into());
                k += 1;
            }
            k += 1;
        }
        assert!(
            args.iter().any(|a| a.starts_with("size=")),
            "{name}: {line}"
        );

        let render = |inputs: &[&str], tag: &str| -> PathBuf {
            let objs = dir.join(format!("{name}_{tag}"));
            let _ = std::fs::remove_dir_all(&objs);
            let wav = dir.join(format!("{name}_{tag}.wav"));
            let mut a: Vec<&str> = inputs.to_vec();
            a.extend([
                "--out",
                s(&wav),
                "--obj-dir",
                s(&objs),
                "--obj-fps",
                "10",
                "--quiet",
            ]);
            let o = run(&a);
            assert!(
                o.status.success(),
                "{name} {tag}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
            let (_, l, r) = read_stereo(&wav);
            assert!(
                all_finite_normal(&l) && all_finite_normal(&r),
                "{name} {tag}"
            );
            objs
        };
        let scene = obj_files(&render(&["--scene", name], "scene"));
        let mut midi_args: Vec<&str> = vec!["--midi", s(&mid)];
        midi_args.extend(args.iter().map(String::as_str));
        let midi = obj_files(&render(&midi_args, "midi"));
        // The MIDI render lasts one second longer (a MIDI file's ringing tail).
        assert_eq!(midi.len(), scene.len() + 10, "{name}: OBJ frame counts");
        let first = obj_vertices(&scene[0]);
        let (mut moved, mut worst, mut sum) = (0.0f64, 0.0f64, 0.0);
        for (a, b) in scene.iter().zip(&midi) {
            let (va, vb) = (obj_vertices(a), obj_vertices(b));
            moved = moved.max(max_distance_cm(&first, &va));
            let d = mean_distance_cm(&va, &vb);
            worst = worst.max(d);
            sum += d;
        }
        let mean = sum / scene.len() as f64;
        eprintln!(
            "{name}: sheet moves up to {moved:.1} cm; MIDI vs scene: mean {mean:.2} cm, worst {worst:.2} cm"
        );
        assert!(moved > 1.0, "{name}: the scene does not move the sheet");
        assert!(
            mean < 0.25 * moved && worst < 0.5 * moved,
            "{name}: the MIDI performance moves the sheet differently (mean {mean:.2} cm, worst \
             {worst:.2} cm, the scene moves it {moved:.1} cm)"
        );
    }
}

fn assert_clean_error(o: &Output, what: &str) {
    assert!(!o.status.success(), "{what}: exit status was success");
    assert!(
        matches!(o.status.code(), Some(1 | 2)),
        "{what}: exit code {:?} (a panic gives 101)",
        o.status.code()
    );
    let err = String::from_utf8_lossy(&o.stderr);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{what}: expected one line, got {err:?}");
    assert!(
        lines[0].starts_with("papier-render: error: "),
        "{what}: {err:?}"
    );
    assert!(!err.contains("panicked"), "{what}: {err:?}");
}

#[test]
fn bad_input_gives_a_one_line_error_and_a_nonzero_exit() {
    let dir = paths::scratch("render_cli_bad");
    let out = dir.join("out.wav");
    let good_mid = dir.join("good.mid");
    ten_second_midi(&good_mid);
    let bytes = std::fs::read(&good_mid).unwrap();
    let mut x = 0xDEAD_BEEFu32;
    let random: Vec<u8> = (0..10_000)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x as u8
        })
        .collect();
    let files = [
        ("empty.mid", Vec::new()),
        ("truncated.mid", bytes[..bytes.len() / 2].to_vec()),
        ("random.mid", random.clone()),
        ("empty.toml", Vec::new()),
        ("random.toml", random),
        (
            "truncated.toml",
            b"version = 1\n[[lane]]\nid = \"slide\"\npoints = [[0, ".to_vec(),
        ),
        (
            "unknown_id.toml",
            b"version = 1\n[set]\nloudness = 3\n".to_vec(),
        ),
        (
            "bad_value.toml",
            b"version = 1\n[[lane]]\nid = \"slide\"\npoints = [[0, 7]]\n".to_vec(),
        ),
    ];
    for (name, content) in &files {
        std::fs::write(dir.join(name), content).unwrap();
    }
    let flag = |name: &str| {
        if name.ends_with(".mid") {
            "--midi"
        } else {
            "--script"
        }
    };
    for (name, _) in &files {
        let p = dir.join(name);
        let o = run(&[flag(name), s(&p), "--out", s(&out)]);
        assert_clean_error(&o, name);
    }
    let missing = dir.join("missing.mid");
    let cases: Vec<(&str, Vec<&str>)> = vec![
        (
            "missing midi",
            vec!["--midi", s(&missing), "--out", s(&out)],
        ),
        (
            "missing script",
            vec!["--script", s(&missing), "--out", s(&out)],
        ),
        ("unknown scene", vec!["--scene", "nope", "--out", s(&out)]),
        (
            "unknown --set id",
            vec![
                "--midi",
                s(&good_mid),
                "--out",
                s(&out),
                "--set",
                "volume=3",
            ],
        ),
        (
            "bad --set value",
            vec!["--midi", s(&good_mid), "--out", s(&out), "--set", "size=a3"],
        ),
        (
            "bad --set form",
            vec!["--midi", s(&good_mid), "--out", s(&out), "--set", "size"],
        ),
        ("no input", vec!["--out", s(&out)]),
        ("no output", vec!["--midi", s(&good_mid)]),
        (
            "bad rate",
            vec![
                "--midi",
                s(&good_mid),
                "--out",
                s(&out),
                "--sample-rate",
                "7000",
            ],
        ),
        (
            "bad block",
            vec!["--midi", s(&good_mid), "--out", s(&out), "--block", "0"],
        ),
        (
            "unknown option",
            vec!["--midi", s(&good_mid), "--out", s(&out), "--loud"],
        ),
        (
            "bad db",
            vec![
                "--midi",
                s(&good_mid),
                "--out",
                s(&out),
                "--db",
                s(&missing),
            ],
        ),
        (
            "unwritable out",
            vec!["--midi", s(&good_mid), "--out", "/proc/papier.wav"],
        ),
    ];
    for (what, args) in cases {
        assert_clean_error(&run(&args), what);
    }
}
