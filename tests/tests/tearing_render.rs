//! Tearing I end to end through `papier-render`, as a sound designer plays it: a MIDI
//! performance (CC 28 places the tear, CC 26 ramps the tear amount 0 → 127) with the crumple
//! and friction mixes off leaves the sheet in two pieces in its last OBJ frame and sounds; the
//! tear is silent before it starts and sounds within 5 ms of the first frame its tip moves
//! (`--write-frames`); a faster ramp tears faster and louder, and a slower one crackles more.

use std::path::{Path, PathBuf};
use std::process::Command;

use papier::gesture_map::MidiInput;
use papier::offline::frame_log::FrameRecord;
use papier::offline::midi_file::{TimedMidi, write_smf};
use papier_tests::audio::{all_finite_normal, read_stereo};
use papier_tests::paths;
use papier_tests::paths::arg as s;

const RATE_HZ: f64 = 48_000.0;

/// A tear performance: CC 28 = `pos` at 0.1 s, CC 26 ramped 0 → 1 from 0.3 s over `ramp_s`.
fn tear_midi(path: &Path, pos: f32, ramp_s: f64) {
    let mut ev = vec![TimedMidi {
        time_s: 0.1,
        input: MidiInput::Cc { cc: 28, value: pos },
    }];
    for k in 0..=127 {
        ev.push(TimedMidi {
            time_s: 0.3 + ramp_s * f64::from(k) / 127.0,
            input: MidiInput::Cc {
                cc: 26,
                value: k as f32 / 127.0,
            },
        });
    }
    std::fs::write(path, write_smf(&ev, 0.3 + ramp_s + 0.5)).unwrap();
}

struct Take {
    left: Vec<f32>,
    right: Vec<f32>,
    frames: Vec<FrameRecord>,
    last_obj: PathBuf,
}

/// Renders MIDI file `mid` to `wav` with OBJ frames at 10 fps in `objs` and the `extra`
/// options; returns the OBJ files in order.
fn render_midi(mid: &Path, wav: &Path, objs: &Path, extra: &[&str]) -> Vec<PathBuf> {
    let mut args = vec![
        "--midi",
        s(mid),
        "--out",
        s(wav),
        "--obj-dir",
        s(objs),
        "--obj-fps",
        "10",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let o = Command::new(paths::papier_render())
        .args(&args)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut files: Vec<PathBuf> = std::fs::read_dir(objs)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
}

fn render(dir: &Path, name: &str, pos: f32, ramp_s: f64) -> Take {
    let mid = dir.join(format!("{name}.mid"));
    tear_midi(&mid, pos, ramp_s);
    let (wav, objs, log) = (
        dir.join(format!("{name}.wav")),
        dir.join(format!("{name}_obj")),
        dir.join(format!("{name}.jsonl")),
    );
    let mut files = render_midi(
        &mid,
        &wav,
        &objs,
        &[
            "--write-frames",
            s(&log),
            "--set",
            "mix_crumple_db=-60",
            "--set",
            "mix_friction_db=-60",
        ],
    );
    let (rate, left, right) = read_stereo(&wav);
    assert_eq!(f64::from(rate), RATE_HZ);
    assert!(all_finite_normal(&left) && all_finite_normal(&right));
    let frames = std::fs::read_to_string(&log)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    Take {
        left,
        right,
        frames,
        last_obj: files.pop().unwrap(),
    }
}

/// Pieces of an OBJ mesh: its faces joined through shared `v` indices. Checks that the file
/// has one `vt` per `v` and that every face uses the same index for both (the lips are two
/// vertices at one pattern position).
fn obj_pieces(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    let mut faces: Vec<[usize; 3]> = Vec::new();
    let (mut nv, mut nvt) = (0, 0);
    for line in text.lines() {
        let mut w = line.split_whitespace();
        match w.next() {
            Some("v") => nv += 1,
            Some("vt") => nvt += 1,
            Some("f") => {
                let idx: Vec<usize> = w
                    .map(|t| {
                        let (v, vt) = t.split_once('/').unwrap();
                        assert_eq!(v, vt, "{}: a face's v and vt differ", path.display());
                        v.parse::<usize>().unwrap() - 1
                    })
                    .collect();
                faces.push([idx[0], idx[1], idx[2]]);
            }
            _ => {}
        }
    }
    assert_eq!(nv, nvt, "{}: one vt per v", path.display());
    let mut parent: Vec<usize> = (0..nv).collect();
    fn root(p: &mut [usize], mut a: usize) -> usize {
        while p[a] != a {
            p[a] = p[p[a]];
            a = p[a];
        }
        a
    }
    for f in &faces {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, f[0]), root(&mut parent, f[k]));
            parent[a] = b;
        }
    }
    let mut roots: Vec<usize> = faces.iter().map(|f| root(&mut parent, f[0])).collect();
    roots.sort_unstable();
    roots.dedup();
    roots.len()
}

fn rms_db(x: &[f32]) -> f64 {
    let e: f64 = x.iter().map(|&v| f64::from(v) * f64::from(v)).sum::<f64>() / x.len() as f64;
    10.0 * e.max(1e-30).log10()
}

#[test]
fn a_midi_tear_performance_leaves_two_pieces_and_sounds_from_its_first_moving_frame() {
    let dir = paths::scratch("tearing_render");
    for (name, pos) in [("middle", 0.5), ("left", 0.2)] {
        let take = render(&dir, name, pos, 2.5);
        assert_eq!(
            obj_pieces(&take.last_obj),
            2,
            "{name}: two pieces at the end"
        );
        // The first frame whose tip moves, and the first sample that sounds.
        let first = take
            .frames
            .iter()
            .find(|f| f.tear.speed_m_s > 0.0)
            .expect("the tear moved");
        let start_s = first.time_s;
        let onset = take
            .left
            .iter()
            .zip(&take.right)
            .position(|(l, r)| *l != 0.0 || *r != 0.0)
            .expect("the tear sounds");
        let onset_s = onset as f64 / RATE_HZ;
        assert!(
            (onset_s - start_s).abs() <= 0.005 + 1.0 / RATE_HZ,
            "{name}: the sound starts at {onset_s:.4} s, the tip moves in the frame of {start_s:.4} s"
        );
        let sounding = &take.left[onset..onset + (RATE_HZ as usize)];
        assert!(
            rms_db(sounding) > -50.0,
            "{name}: {:.1} dBFS",
            rms_db(sounding)
        );
    }
}

#[test]
fn a_faster_tear_is_louder() {
    let dir = paths::scratch("tearing_render_speed");
    let (slow, fast) = (
        render(&dir, "slow", 0.5, 4.0),
        render(&dir, "fast", 0.5, 2.0),
    );
    // The same stretch of tear (its first 40 %) at both speeds: the RMS over the time it
    // takes, from the frame log's speeds and the audio.
    let level = |t: &Take| {
        let moving: Vec<&FrameRecord> = t
            .frames
            .iter()
            .filter(|f| f.tear.speed_m_s > 0.0 && f.tear.length_m < 0.4 * 0.297)
            .collect();
        let (a, b) = (
            ((moving[0].time_s - 0.005) * RATE_HZ) as usize,
            (moving[moving.len() - 1].time_s * RATE_HZ) as usize,
        );
        let mean_speed = moving
            .iter()
            .map(|f| f64::from(f.tear.speed_m_s))
            .sum::<f64>()
            / moving.len() as f64;
        (
            rms_db(&t.left[a..b]),
            mean_speed,
            envelope_kurtosis(&t.left[a..b]),
        )
    };
    let ((slow_db, slow_v, slow_k), (fast_db, fast_v, fast_k)) = (level(&slow), level(&fast));
    assert!(
        (fast_v / slow_v - 2.0).abs() < 0.2,
        "twice the ramp rate: speeds {slow_v:.4} and {fast_v:.4} m/s"
    );
    assert!(
        fast_db > slow_db + 3.0,
        "twice as fast: {slow_db:.1} → {fast_db:.1} dBFS"
    );
    // A slow tear crackles more (M:136): its 1 ms energy envelope is the more impulsive.
    assert!(
        slow_k > fast_k,
        "envelope kurtosis: slow {slow_k:.1}, fast {fast_k:.1}"
    );
}

/// Kurtosis of the energy envelope in 1 ms windows (3 for a steady Gaussian envelope, large for
/// sparse bursts).
fn envelope_kurtosis(x: &[f32]) -> f64 {
    let n = (RATE_HZ / 1000.0) as usize;
    let e: Vec<f64> = x
        .chunks_exact(n)
        .map(|c| c.iter().map(|&v| f64::from(v) * f64::from(v)).sum::<f64>() / n as f64)
        .collect();
    let mean = e.iter().sum::<f64>() / e.len() as f64;
    let var = e.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / e.len() as f64;
    e.iter().map(|v| (v - mean).powi(4)).sum::<f64>() / e.len() as f64 / (var * var)
}

/// The same tear performance renders the same bits twice and at every host block size, the
/// torn sheet's OBJ sequence included.
#[test]
fn a_tear_renders_the_same_bits_at_every_block_size() {
    let dir = paths::scratch("tearing_render_blocks");
    let mid = dir.join("tear.mid");
    tear_midi(&mid, 0.3, 1.5);
    let mut takes = Vec::new();
    for (k, block) in ["512", "1", "37", "16384", "512"].iter().enumerate() {
        let (wav, objs) = (dir.join(format!("{k}.wav")), dir.join(format!("obj{k}")));
        let files = render_midi(&mid, &wav, &objs, &["--block", block]);
        assert_eq!(obj_pieces(files.last().unwrap()), 2, "block {block}");
        let objs: Vec<Vec<u8>> = files.iter().map(|f| std::fs::read(f).unwrap()).collect();
        takes.push((std::fs::read(&wav).unwrap(), objs));
    }
    for (k, t) in takes.iter().enumerate().skip(1) {
        assert!(t.0 == takes[0].0, "take {k}: the WAV differs");
        assert!(t.1 == takes[0].1, "take {k}: the OBJ sequence differs");
    }
}
