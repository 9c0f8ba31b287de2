//! MIDI volume (CC 7) takes effect at the sample its message carries, not at the start of the
//! host block that carries it (`plugin/src/engine/volume_changes.rs`): a render with a volume
//! change is the same in any block size, and identical to the render without it up to the
//! message's sample.

use papier::gesture_map::MidiInput;
use papier::offline::cli::{InputSpec, RenderOptions};
use papier::offline::midi_file::{MidiFile, TimedMidi, write_smf};
use papier_tests::audio::read_stereo;
use papier_tests::paths;

/// Volume message time, s: on no frame boundary (5 ms) and no block boundary below.
const VOLUME_AT_S: f64 = 0.5013;
const RATE_HZ: u32 = 48_000;

/// A crumple held at a steady squeeze, with (or without) the volume dropped to 0.3 at
/// [`VOLUME_AT_S`].
fn performance(path: &std::path::Path, with_volume: bool) {
    let mut ev = vec![TimedMidi {
        time_s: 0.0,
        input: MidiInput::NoteOn {
            key: 55,
            velocity: 1.0,
        },
    }];
    for i in 0..=40 {
        ev.push(TimedMidi {
            time_s: 0.05 + 0.02 * i as f64,
            input: MidiInput::Cc {
                cc: 20,
                value: 0.02 * i as f32,
            },
        });
    }
    if with_volume {
        ev.push(TimedMidi {
            time_s: VOLUME_AT_S,
            input: MidiInput::Cc { cc: 7, value: 0.3 },
        });
    }
    ev.sort_by(|a, b| a.time_s.total_cmp(&b.time_s));
    std::fs::write(path, write_smf(&ev, 1.0)).unwrap();
}

fn render(dir: &std::path::Path, midi: &std::path::Path, block: usize) -> (Vec<f32>, Vec<f32>) {
    let out = dir.join(format!(
        "{}_{block}.wav",
        midi.file_stem().unwrap().to_string_lossy()
    ));
    let mut opts = RenderOptions::new(vec![InputSpec::Midi(midi.to_path_buf())], out.clone());
    opts.sample_rate_hz = RATE_HZ;
    opts.block = block;
    opts.quiet = true;
    papier::offline::render(&opts).unwrap();
    let (_, l, r) = read_stereo(&out);
    (l, r)
}

#[test]
fn a_volume_change_acts_at_its_sample_in_any_block_size() {
    let dir = paths::scratch("midi_volume");
    let (with, without) = (dir.join("with.mid"), dir.join("without.mid"));
    performance(&with, true);
    performance(&without, false);
    let reference = render(&dir, &with, 1);
    for block in [7, 512, 4096] {
        let x = render(&dir, &with, block);
        assert!(
            x.0.iter()
                .zip(&reference.0)
                .all(|(a, b)| a.to_bits() == b.to_bits())
                && x.1
                    .iter()
                    .zip(&reference.1)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
            "block {block} renders other samples"
        );
    }
    let plain = render(&dir, &without, 4096);
    // The message's sample as the file stores it (ticks of about 1 ms).
    let stored = MidiFile::from_file(&with).unwrap();
    let volume_s = stored
        .events
        .iter()
        .find(|e| matches!(e.input, MidiInput::Cc { cc: 7, .. }))
        .unwrap()
        .time_s;
    assert!((volume_s - VOLUME_AT_S).abs() < 2e-3);
    let at = (volume_s * f64::from(RATE_HZ)).round() as usize;
    // Before the message (it falls inside a 4096-sample block): the same samples.
    let first_diff = (0..plain.0.len())
        .find(|&i| plain.0[i].to_bits() != reference.0[i].to_bits())
        .expect("the volume change changed nothing");
    assert!(
        first_diff >= at,
        "the volume acted at sample {first_diff}, before its message at {at}"
    );
    // After it the sound is there, and quieter: 0.3 on the General MIDI curve is −21 dB; the
    // mix glides there in 10 ms.
    let energy = |x: &[f32]| x.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>();
    let tail = at + RATE_HZ as usize / 50..plain.0.len();
    let (e_plain, e_with) = (energy(&plain.0[tail.clone()]), energy(&reference.0[tail]));
    assert!(e_plain > 0.0, "no sound after the volume change");
    let drop_db = 10.0 * (e_with / e_plain).log10();
    assert!(
        (-30.0..-12.0).contains(&drop_db),
        "the volume change lowered the sound by {drop_db:.1} dB"
    );
}
