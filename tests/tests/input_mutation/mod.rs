//! Hostile edits of `papier-render`'s input files, each case played through
//! [`papier::offline::render`] as the command would play it. Shared by `tests/bad_input_files.rs`
//! (a CI-sized run) and `examples/fuzz_inputs.rs` (the same, longer); included with
//! `mod input_mutation;`.
//!
//! The brief's rule for bad input: a clear error or a safe default, never a panic, NaN or lost
//! data. A case passes when the render either refuses the input with a one-line error or
//! writes a WAV whose every sample is finite and within ±1 (the output stage's safety clip) and
//! which a render of the same input at another block size reproduces byte for byte.
//!
//! Inputs start from real ones, so that most edits reach past the first check:
//! - **scripts**: each built-in scene's TOML, cut to 0.6 s; edits at the token level (a number
//!   made hostile or nudged, a string emptied or garbled, a line dropped, doubled or swapped, the
//!   text truncated);
//! - **MIDI files**: each scene's MIDI performance (`--write-midi`), its first 0.6 s; edits at
//!   the byte level (bits flipped, bytes set to 0x00/0x7F/0x80/0xFF, a 7-bit byte set to another
//!   7-bit value, spans deleted, doubled or inserted, a 32-bit length overwritten, a run of 0xFF
//!   written, the file truncated);
//! - **frame logs**: the sound frames a scene's render recorded (`--write-frames`); a line's JSON
//!   edited with the saved-sheet mutator of `sim-core/tests/common/json_mutation.rs`, or lines
//!   dropped, doubled, swapped or truncated.
//!
//! Each case renders at a random rate (8–192 kHz) and block size (1–16384). A case whose edited
//! input would play for more than [`MAX_PLAYED_S`] is parsed but not played (an edit can make a
//! script an hour long, which is valid).

#![allow(dead_code)]

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use papier::offline::cli::{InputSpec, RenderOptions};
use papier::offline::midi_file::{MidiFile, write_smf};
use papier::offline::{self, frame_replay};
use rand::RngExt;
use rand_pcg::Pcg32;
use serde_json::Value;

#[path = "../../../sim-core/tests/common/json_mutation.rs"]
mod json_mutation;

/// Length the base scripts and MIDI files are cut to, s.
pub const BASE_LENGTH_S: f64 = 0.6;
/// Longest edited input that is played, s.
pub const MAX_PLAYED_S: f64 = 2.0;
/// Sample rates drawn.
pub const RATES_HZ: [u32; 7] = [8_000, 22_050, 44_100, 48_000, 88_200, 96_000, 192_000];
/// Block sizes drawn.
pub const BLOCKS: [usize; 7] = [1, 7, 64, 333, 512, 4096, 16_384];

/// The kind of input file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A TOML automation script.
    Script,
    /// A Standard MIDI File.
    Midi,
    /// A JSON-lines sound-frame log.
    Frames,
}

impl Kind {
    /// Every kind, in [`Kind::index`] order, with a name for tallies.
    pub const ALL: [(Kind, &'static str); 3] = [
        (Kind::Script, "scripts"),
        (Kind::Midi, "MIDI files"),
        (Kind::Frames, "frame logs"),
    ];

    /// Position in [`Kind::ALL`].
    pub fn index(self) -> usize {
        match self {
            Kind::Script => 0,
            Kind::Midi => 1,
            Kind::Frames => 2,
        }
    }
}

/// A valid input to start edits from.
pub struct Base {
    /// What it is.
    pub kind: Kind,
    /// Which scene it came from.
    pub scene: &'static str,
    /// The file's bytes.
    pub bytes: Vec<u8>,
}

/// What one case did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Cases run.
    pub cases: u64,
    /// Refused with a one-line error.
    pub refused: u64,
    /// Played to a WAV.
    pub played: u64,
    /// Accepted by the parser but longer than [`MAX_PLAYED_S`], not played.
    pub too_long: u64,
}

impl Tally {
    /// Adds another tally.
    pub fn add(&mut self, o: &Tally) {
        self.cases += o.cases;
        self.refused += o.refused;
        self.played += o.played;
        self.too_long += o.too_long;
    }
}

/// A scene's script text with its duration set to `length_s`.
fn short_script(scene: &str, length_s: f64) -> String {
    let text = sim_core::scenario::text(scene).expect("built-in scene");
    // Set where the scene sets it, else right after `version`.
    let has_own = text
        .lines()
        .any(|l| l.trim_start().starts_with("duration_s"));
    let line_of = format!("duration_s = {length_s}\n");
    let mut out = String::new();
    for line in text.lines() {
        if line.trim_start().starts_with("duration_s") {
            out.push_str(&line_of);
            continue;
        }
        out.push_str(line);
        out.push('\n');
        if !has_own && line.trim_start().starts_with("version") {
            out.push_str(&line_of);
        }
    }
    out
}

/// The base inputs, written next to `dir`'s cases: for each of `scenes`, its short script,
/// the first [`BASE_LENGTH_S`] of its MIDI performance, and the frame log of its short script's
/// render.
pub fn bases(dir: &Path, scenes: &[&'static str]) -> Vec<Base> {
    std::fs::create_dir_all(dir).unwrap();
    let mut out = Vec::new();
    for &scene in scenes {
        let script = short_script(scene, BASE_LENGTH_S);
        let script_path = dir.join(format!("{scene}.toml"));
        std::fs::write(&script_path, &script).unwrap();
        out.push(Base {
            kind: Kind::Script,
            scene,
            bytes: script.into_bytes(),
        });

        let midi_path = dir.join(format!("{scene}.mid"));
        offline::write_midi(&[InputSpec::Scene(scene.to_string())], &midi_path).unwrap();
        let full = MidiFile::from_file(&midi_path).unwrap();
        let events: Vec<_> = full
            .events
            .into_iter()
            .filter(|e| e.time_s < BASE_LENGTH_S)
            .collect();
        out.push(Base {
            kind: Kind::Midi,
            scene,
            bytes: write_smf(&events, BASE_LENGTH_S),
        });

        let log_path = dir.join(format!("{scene}.jsonl"));
        let mut opts = RenderOptions::new(
            vec![InputSpec::Script(script_path)],
            dir.join(format!("{scene}.wav")),
        );
        opts.write_frames = Some(log_path.clone());
        opts.quiet = true;
        offline::render(&opts).unwrap();
        out.push(Base {
            kind: Kind::Frames,
            scene,
            bytes: std::fs::read(&log_path).unwrap(),
        });
    }
    out
}

/// A hostile or plausible replacement for a number token.
fn number_token(tok: &str, rng: &mut Pcg32) -> String {
    let x: f64 = tok.parse().unwrap_or(0.0);
    match rng.random_range(0..14u32) {
        0 => "1e308".into(),
        1 => "-1e308".into(),
        2 => "nan".into(),
        3 => "inf".into(),
        4 => "-inf".into(),
        5 => "-0.0".into(),
        6 => "5e-324".into(),
        7 => "0".into(),
        8 => "9223372036854775807".into(),
        9 => "-1".into(),
        10 => format!("{}", -x),
        11 => format!("{}", x * 1000.0),
        12 => format!("{}", x + 1.0),
        _ => format!("{:?}", x * 1.001),
    }
}

/// Splits `text` into tokens, keeping separators, so that a token can be replaced in place.
fn tokens(text: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut cur = String::new();
    let mut in_num = false;
    for c in text.chars() {
        let num_char = c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E');
        if num_char && (in_num || c.is_ascii_digit() || c == '-' || c == '.') {
            if !in_num && !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
            in_num = true;
            cur.push(c);
        } else {
            if in_num && !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
            in_num = false;
            cur.push(c);
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// One token-level or line-level edit of a TOML text.
pub fn mutate_text(text: &str, rng: &mut Pcg32) -> String {
    match rng.random_range(0..10u32) {
        0..=4 => {
            // A number made hostile or nudged.
            let mut toks = tokens(text);
            let nums: Vec<usize> = (0..toks.len())
                .filter(|&i| toks[i].parse::<f64>().is_ok())
                .collect();
            if nums.is_empty() {
                return text.to_string();
            }
            let i = nums[rng.random_range(0..nums.len())];
            toks[i] = number_token(&toks[i], rng);
            toks.concat()
        }
        5 => {
            // A string emptied or garbled.
            let quotes: Vec<usize> = text.match_indices('"').map(|(i, _)| i).collect();
            if quotes.len() < 2 {
                return text.to_string();
            }
            let k = rng.random_range(0..quotes.len() / 2) * 2;
            let (a, b) = (quotes[k] + 1, quotes[k + 1]);
            let repl = match rng.random_range(0..4u32) {
                0 => "",
                1 => "front\u{0}",
                2 => "ä🙂",
                _ => "slide",
            };
            format!("{}{}{}", &text[..a], repl, &text[b..])
        }
        6..=8 => {
            // A line dropped, doubled or swapped with another.
            let mut lines: Vec<&str> = text.lines().collect();
            if lines.is_empty() {
                return text.to_string();
            }
            let i = rng.random_range(0..lines.len());
            match rng.random_range(0..3u32) {
                0 => {
                    lines.remove(i);
                }
                1 => lines.insert(i, lines[i]),
                _ => {
                    let j = rng.random_range(0..lines.len());
                    lines.swap(i, j);
                }
            }
            let mut s = lines.join("\n");
            s.push('\n');
            s
        }
        _ => {
            // Truncated at a character boundary.
            let cut = rng.random_range(0..=text.len());
            let cut = (0..=cut).rev().find(|&c| text.is_char_boundary(c)).unwrap();
            text[..cut].to_string()
        }
    }
}

/// One byte-level edit.
pub fn mutate_bytes(bytes: &mut Vec<u8>, rng: &mut Pcg32) {
    if bytes.is_empty() {
        bytes.push(rng.random_range(0..=255u8));
        return;
    }
    let n = bytes.len();
    let i = rng.random_range(0..n);
    match rng.random_range(0..12u32) {
        0 | 1 => bytes[i] ^= 1 << rng.random_range(0..8u32),
        8..=10 => {
            // A 7-bit byte (a MIDI data byte, delta time or length) set to another 7-bit
            // value: the edit most likely to leave a file that still parses, with other notes,
            // controller values and timing.
            let j = (0..n)
                .map(|k| (i + k) % n)
                .find(|&k| bytes[k] < 0x80)
                .unwrap_or(i);
            bytes[j] = [0, 1, 0x40, 0x7F, rng.random_range(0..0x80u8)][rng.random_range(0..5usize)];
        }
        2 => bytes[i] = [0x00, 0x7F, 0x80, 0xFF][rng.random_range(0..4usize)],
        3 => {
            let len = rng.random_range(1..=(n - i).min(16));
            bytes.drain(i..i + len);
        }
        4 => {
            let len = rng.random_range(1..=(n - i).min(16));
            let span: Vec<u8> = bytes[i..i + len].to_vec();
            bytes.splice(i..i, span);
        }
        5 => {
            let len = rng.random_range(1..=8usize);
            let junk: Vec<u8> = (0..len).map(|_| rng.random_range(0..=255u8)).collect();
            bytes.splice(i..i, junk);
        }
        6 if n >= 4 => {
            // A 32-bit big-endian length (chunk sizes, tempo) overwritten.
            let i = rng.random_range(0..=n - 4);
            let v: u32 = [0, 1, 0x7FFF_FFFF, u32::MAX, n as u32 + 1][rng.random_range(0..5usize)];
            bytes[i..i + 4].copy_from_slice(&v.to_be_bytes());
        }
        7 => {
            // A variable-length quantity made endless or huge.
            let len = rng.random_range(1..=5usize).min(n - i);
            for b in &mut bytes[i..i + len] {
                *b = 0xFF;
            }
        }
        _ => bytes.truncate(i),
    }
}

/// One edit of a JSON-lines log.
pub fn mutate_log(text: &str, rng: &mut Pcg32) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if lines.is_empty() {
        return text.to_string();
    }
    let i = rng.random_range(0..lines.len());
    match rng.random_range(0..8u32) {
        0..=4 => {
            if let Ok(mut v) = serde_json::from_str::<Value>(&lines[i]) {
                json_mutation::mutate(&mut v, rng);
                lines[i] = v.to_string();
            } else {
                lines[i].push('}');
            }
        }
        5 => {
            lines.remove(i);
        }
        6 => {
            let j = rng.random_range(0..lines.len());
            lines.swap(i, j);
        }
        _ => {
            let l = &lines[i];
            let cut = rng.random_range(0..=l.len());
            let cut = (0..=cut).rev().find(|&c| l.is_char_boundary(c)).unwrap();
            lines[i] = l[..cut].to_string();
        }
    }
    let mut s = lines.join("\n");
    s.push('\n');
    s
}

/// An edited copy of `base` (1–3 edits).
pub fn mutated(base: &Base, rng: &mut Pcg32) -> Vec<u8> {
    let edits = match base.kind {
        Kind::Midi => rng.random_range(1..=2u32),
        _ => rng.random_range(1..=3u32),
    };
    let mut bytes = base.bytes.clone();
    for _ in 0..edits {
        bytes = match base.kind {
            Kind::Script => mutate_text(&String::from_utf8_lossy(&bytes), rng).into_bytes(),
            Kind::Midi => {
                mutate_bytes(&mut bytes, rng);
                bytes
            }
            Kind::Frames => mutate_log(&String::from_utf8_lossy(&bytes), rng).into_bytes(),
        };
    }
    bytes
}

/// How long an input would play if the renderer accepts it, or `None` when its own parser
/// refuses it (the render then must refuse it too).
fn played_length_s(kind: Kind, path: &Path, bytes: &[u8]) -> Option<f64> {
    match kind {
        Kind::Script => std::str::from_utf8(bytes)
            .ok()
            .and_then(|t| sim_core::script::Script::parse(t).ok())
            .map(|s| s.duration_s),
        Kind::Midi => MidiFile::parse(bytes).ok().map(|m| m.length_s + 1.0),
        Kind::Frames => frame_replay::scan(path).ok().map(|s| s.last_time_s),
    }
}

/// Runs one case: writes `bytes` to `dir`, renders it at a drawn rate and block size, and
/// checks the outcome. `Err` describes a failure (a panic, a multi-line error, a non-finite or
/// out-of-range sample, a missing WAV).
pub fn run_case(kind: Kind, bytes: &[u8], dir: &Path, rng: &mut Pcg32) -> Result<Tally, String> {
    let ext = match kind {
        Kind::Script => "toml",
        Kind::Midi => "mid",
        Kind::Frames => "jsonl",
    };
    let input: PathBuf = dir.join(format!("case.{ext}"));
    let out = dir.join("case.wav");
    std::fs::write(&input, bytes).map_err(|e| e.to_string())?;
    let _ = std::fs::remove_file(&out);
    let mut tally = Tally {
        cases: 1,
        ..Tally::default()
    };
    let length = catch_unwind(AssertUnwindSafe(|| played_length_s(kind, &input, bytes)))
        .map_err(|_| "the input's parser panicked".to_string())?;
    if length.is_some_and(|l| l.is_nan() || l > MAX_PLAYED_S) {
        tally.too_long = 1;
        return Ok(tally);
    }
    let spec = match kind {
        Kind::Script => InputSpec::Script(input.clone()),
        Kind::Midi => InputSpec::Midi(input.clone()),
        Kind::Frames => InputSpec::Frames(input.clone()),
    };
    let mut opts = RenderOptions::new(vec![spec], out.clone());
    opts.sample_rate_hz = RATES_HZ[rng.random_range(0..RATES_HZ.len())];
    opts.block = BLOCKS[rng.random_range(0..BLOCKS.len())];
    opts.quiet = true;
    let what = format!(
        "{kind:?} at {} Hz, block {}",
        opts.sample_rate_hz, opts.block
    );
    let result = catch_unwind(AssertUnwindSafe(|| offline::render(&opts)))
        .map_err(|_| format!("{what}: the render panicked"))?;
    match result {
        Err(e) => {
            let msg = e.to_string();
            if msg.is_empty() || msg.contains('\n') {
                return Err(format!("{what}: not a one-line error: {msg:?}"));
            }
            if std::env::var_os("FUZZ_VERBOSE").is_some() {
                eprintln!("refused ({what}): {msg}");
            }
            tally.refused = 1;
        }
        Ok(report) => {
            if length.is_none() {
                return Err(format!(
                    "{what}: played an input its own parser refuses ({} s)",
                    report.length_s
                ));
            }
            let mut wav = hound::WavReader::open(&out)
                .map_err(|e| format!("{what}: rendered, but the WAV does not open: {e}"))?;
            for (k, s) in wav.samples::<f32>().enumerate() {
                let s = s.map_err(|e| format!("{what}: the WAV is damaged: {e}"))?;
                if !s.is_finite() || s.abs() > 1.0 {
                    return Err(format!("{what}: sample {k} is {s}"));
                }
            }
            // The same input at another block size: the same bytes (a render is a pure
            // function of its inputs, whatever `--block` is).
            let first = std::fs::read(&out).map_err(|e| e.to_string())?;
            let mut again = opts.clone();
            again.block = BLOCKS[(BLOCKS.iter().position(|&b| b == opts.block).unwrap_or(0)
                + rng.random_range(1..BLOCKS.len()))
                % BLOCKS.len()];
            catch_unwind(AssertUnwindSafe(|| offline::render(&again)))
                .map_err(|_| format!("{what}: the render panicked at block {}", again.block))?
                .map_err(|e| format!("{what}: refused at block {}: {e}", again.block))?;
            if std::fs::read(&out).map_err(|e| e.to_string())? != first {
                return Err(format!(
                    "{what}: block {} renders other samples",
                    again.block
                ));
            }
            tally.played = 1;
        }
    }
    Ok(tally)
}
