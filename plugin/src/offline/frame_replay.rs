//! # Frame logs in `papier-render`: replay (`--frames`) and recording (`--write-frames`)
//!
//! A frame log ([`super::frame_log`]) holds the sound input of a render, one
//! [`SoundFrame`] per line. `--write-frames FILE` records the frames the simulated sheet delivers
//! to the render path during an ordinary render ([`FrameRecorder`]); `--frames FILE` plays a log
//! (recorded so, or written by another tool) through the same render path ([`Renderer`], set up
//! as the engine sets it up) without simulating a sheet (`play`).
//!
//! ## Timing
//!
//! The engine steps frame k (200 per second) when the audio clock reaches the end of its span,
//! and the frame sounds from that sample on ([`crate::engine::frame_clock`]); a frame's `time_s`
//! is the end of the frame. Replay therefore delivers each frame at the sample of its `time_s`
//! ([`frame_sample`]): at `FrameClock::start(j)` when `time_s` is a whole number j of 200 Hz frame
//! periods (so a log written at 200 frames/s lands on the engine's own samples at every sample
//! rate, 44.1 kHz included), otherwise at `round(time_s · fs)`. Frames stamped at or before t = 0
//! are delivered before the first sample; frames that fall on the same sample are all delivered,
//! in file order (every crumple event plays; the last frame's friction and tear hold). Between
//! frames the last frame's friction and tear continue, as in the engine. The render ends at the
//! last frame's `time_s`, like the recorded render did; to let the last sounds ring, end the log
//! with an empty frame (`{"frame":N,"time_s":T}`) at the time the render should stop.
//!
//! A log is read twice: once to validate every line and find its length before anything is
//! written (a bad line stops the render with its line number, the output is not created), once
//! streamed while rendering, so an hour-long log is never held in memory.
//!
//! ## Recording
//!
//! The recorder writes the delivered frames in order and re-stamps them on the render's timeline:
//! the i-th frame (from 1) gets `frame` = i and `time_s` = i / frame rate. (The sheet's own frame
//! counter restarts at every reset or size change, which a log's increasing indices forbid.)
//! The log starts with `#` comment lines, which readers skip: what was rendered, the replay
//! command with the `--seed` and `--set` options that give the replay the render's sound settings
//! at t = 0 (seed, room, listener, mix), and the sound settings the inputs change after t = 0,
//! which a log of sound frames cannot carry.
//!
//! ## Replay = render
//!
//! With those options, a replay at the recording's sample rate reproduces the recorded render's
//! audio bit for bit, provided the inputs change no sound setting after t = 0 (the header then
//! lists none) and send no MIDI volume: the renderer is built with the same seed, mix and scene,
//! is given the same frames at the same samples, and its output does not depend on how the
//! render calls are split. The log is exact: numbers are written as the shortest decimal that
//! reads back to the same `f32`. A log plays at any sample rate.

use std::fs::File;
use std::io::{BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};

use sim_core::sound_input::SoundFrame;

use super::OfflineError;
use super::cli::InputSpec;
use super::frame_log::{FrameLogError, FrameLogReader, write_frame};
use super::timeline::{HostEvent, Timeline};
use super::wav_out::{AudioOut, sanitize};
use crate::engine::{FrameClock, ParamValues};
use crate::gesture_map::{self, Action};
use crate::render::Renderer;

/// The frame rate whose grid replay snaps to, Hz (the simulation's).
pub const LOG_FRAME_RATE_HZ: f64 = sim_core::sim::DEFAULT_FRAME_RATE_HZ;

/// Parameters that shape the render path's output, besides the sound input itself: the seed of
/// the sound's noise, the room (reflectors), the listener and the mix.
pub const SOUND_PARAM_IDS: [&str; 11] = [
    "seed",
    "table",
    "table_height_cm",
    "wall",
    "wall_dist_cm",
    "listener_az_deg",
    "listener_dist_m",
    "mix_crumple_db",
    "mix_friction_db",
    "mix_tear_db",
    "gain_db",
];

/// The sample at which a frame stamped `time_s` is delivered (see the module docs).
pub fn frame_sample(time_s: f64, sample_rate_hz: f64) -> u64 {
    if time_s.is_nan() || time_s <= 0.0 {
        return 0;
    }
    let periods = time_s * LOG_FRAME_RATE_HZ;
    let whole = periods.round();
    if (periods - whole).abs() < 1e-6 {
        FrameClock::new(sample_rate_hz, LOG_FRAME_RATE_HZ).start(whole as u64)
    } else {
        (time_s * sample_rate_hz).round() as u64
    }
}

fn open_log(path: &Path) -> Result<FrameLogReader<BufReader<File>>, OfflineError> {
    let file = File::open(path).map_err(|e| {
        OfflineError::Input(format!("--frames {}: cannot open: {e}", path.display()))
    })?;
    Ok(FrameLogReader::new(BufReader::new(file)))
}

fn log_error(path: &Path, e: FrameLogError) -> OfflineError {
    let text = match e {
        // A record is one line: serde's "at line 1 column N" would contradict the log's line.
        FrameLogError::Parse { line, message } => format!(
            "frame log line {line}: {}",
            message.replace(" at line 1 column ", " at column ")
        ),
        // The reader counts the lines it has read; the one that failed is the next.
        FrameLogError::Io { line, source } => {
            format!("frame log line {}: cannot read: {source}", line + 1)
        }
        other => other.to_string(),
    };
    OfflineError::Input(format!("--frames {}: {text}", path.display()))
}

/// What a validating pass over a log found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogScan {
    /// Number of frames.
    pub frames: u64,
    /// `time_s` of the last frame: the length of the replay, seconds.
    pub last_time_s: f64,
}

/// Reads and validates a whole log without keeping it. A log with no frame is an error.
pub fn scan(path: &Path) -> Result<LogScan, OfflineError> {
    let mut frames = 0u64;
    let mut last_time_s = 0.0;
    for f in open_log(path)? {
        let f = f.map_err(|e| log_error(path, e))?;
        frames += 1;
        last_time_s = f.time_s;
    }
    if frames == 0 {
        return Err(OfflineError::Input(format!(
            "--frames {}: no frames (the log is empty or holds only blank and comment lines)",
            path.display()
        )));
    }
    Ok(LogScan {
        frames,
        last_time_s,
    })
}

/// What a replay delivered.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Replayed {
    /// Frames delivered to the render path.
    pub frames: u64,
    /// Crumple events triggered.
    pub crumple_events: u64,
}

/// Hands a frame to the render path as the engine does: continuous input, then its events.
fn deliver(renderer: &mut Renderer, f: &SoundFrame, done: &mut Replayed) {
    renderer.set_frame(f);
    for e in f.crumple() {
        renderer.trigger(e);
    }
    done.frames += 1;
    done.crumple_events += f.crumple().len() as u64;
}

/// Plays the log at `path` (validated by [`scan`]) through `renderer` for `total` samples, in
/// blocks of `block`, into `out`.
pub(super) fn play(
    path: &Path,
    renderer: &mut Renderer,
    total: u64,
    block: usize,
    out: &mut AudioOut,
    progress: &indicatif::ProgressBar,
) -> Result<Replayed, OfflineError> {
    let sr = renderer.sample_rate_hz();
    let mut reader = open_log(path)?;
    let mut next = || reader.next().transpose().map_err(|e| log_error(path, e));
    let mut pending = next()?;
    let mut done = Replayed::default();
    let mut left = vec![0.0f32; block];
    let mut right = vec![0.0f32; block];
    let mut pos = 0u64;
    while pos < total {
        let block_end = (pos + block as u64).min(total);
        let mut sub = pos;
        while sub < block_end {
            // Every frame due at this sample, in file order.
            while let Some(f) = pending
                .as_ref()
                .filter(|f| frame_sample(f.time_s, sr) <= sub)
            {
                deliver(renderer, f, &mut done);
                pending = next()?;
            }
            let sub_end = match &pending {
                Some(f) => frame_sample(f.time_s, sr).clamp(sub + 1, block_end),
                None => block_end,
            };
            let (a, b) = ((sub - pos) as usize, (sub_end - pos) as usize);
            renderer.render(&mut left[a..b], &mut right[a..b]);
            sub = sub_end;
        }
        let n = (block_end - pos) as usize;
        sanitize(&mut left[..n], &mut right[..n]);
        out.write(&left[..n], &right[..n])?;
        pos = block_end;
        progress.set_position(pos);
    }
    // Frames due exactly at the end (the engine steps those too; nothing sounds after them).
    while let Some(f) = pending
        .as_ref()
        .filter(|f| frame_sample(f.time_s, sr) <= total)
    {
        deliver(renderer, f, &mut done);
        pending = next()?;
    }
    Ok(done)
}

/// The `--seed` and `--set` options that give a replay these sound settings (as the engine
/// would hand them to the render path).
pub fn replay_options(p: &ParamValues) -> Vec<String> {
    let on = |b: bool| if b { "on" } else { "off" };
    let mut v = vec!["--seed".to_string(), p.seed.to_string()];
    for s in [
        format!("table={}", on(p.room.table)),
        format!("table_height_cm={}", p.room.table_height_cm),
        format!("wall={}", on(p.room.wall)),
        format!("wall_dist_cm={}", p.room.wall_dist_cm),
        format!("listener_az_deg={}", p.listener_az_deg),
        format!("listener_dist_m={}", p.listener_dist_m),
        format!("mix_crumple_db={}", p.mix_crumple_db),
        format!("mix_friction_db={}", p.mix_friction_db),
        format!("mix_tear_db={}", p.mix_tear_db),
        format!("gain_db={}", p.gain_db),
    ] {
        v.push("--set".into());
        v.push(s);
    }
    v
}

/// Sound settings the timeline changes after t = 0, and MIDI volume messages: what a frame log
/// cannot carry. (A later seed change reseeds the sheet only; the render path keeps its seed.)
pub fn sound_changes_after_start(tl: &Timeline) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for (at, e) in &tl.events {
        let name = match e {
            HostEvent::Param { id, .. }
                if *at > 0 && id != "seed" && SOUND_PARAM_IDS.contains(&id.as_str()) =>
            {
                id.clone()
            }
            HostEvent::Midi(m) if matches!(gesture_map::map(*m), Action::Volume(_)) => {
                "MIDI volume (CC 7)".to_string()
            }
            _ => continue,
        };
        if !out.contains(&name) {
            out.push(name);
        }
    }
    out
}

/// How a render was asked for, for the log's header.
pub fn describe_inputs(inputs: &[InputSpec]) -> String {
    inputs
        .iter()
        .map(|i| match i {
            InputSpec::Midi(p) => format!("--midi {}", p.display()),
            InputSpec::Script(p) => format!("--script {}", p.display()),
            InputSpec::Scene(n) => format!("--scene {n}"),
            InputSpec::Frames(p) => format!("--frames {}", p.display()),
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// What a recording wrote.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RecordedLog {
    /// The log file.
    pub path: PathBuf,
    /// Frames written.
    pub frames: u64,
    /// `--seed` / `--set` options that replay it with the render's sound settings at t = 0.
    pub replay_options: Vec<String>,
    /// Sound settings the inputs changed after t = 0 (not in the log).
    pub not_in_log: Vec<String>,
}

impl RecordedLog {
    /// The command line that replays the log.
    pub fn replay_command(&self) -> String {
        format!(
            "papier-render --frames {} {} --out OUT.wav",
            self.path.display(),
            self.replay_options.join(" ")
        )
    }
}

/// Writes the frames of a simulated render as a log (see the module docs).
pub struct FrameRecorder {
    out: BufWriter<File>,
    frame_rate_hz: f64,
    log: RecordedLog,
}

impl FrameRecorder {
    /// Creates the log file (and its folder) for frames stepped at `frame_rate_hz`.
    pub fn create(path: &Path, frame_rate_hz: f64) -> Result<Self, OfflineError> {
        let bad = |e: std::io::Error| {
            OfflineError::Output(format!(
                "cannot write --write-frames {}: {e}",
                path.display()
            ))
        };
        if let Some(parent) = path.parent()
            && !parent.as_os_str().is_empty()
        {
            std::fs::create_dir_all(parent).map_err(bad)?;
        }
        Ok(Self {
            out: BufWriter::new(File::create(path).map_err(bad)?),
            frame_rate_hz,
            log: RecordedLog {
                path: path.to_path_buf(),
                ..RecordedLog::default()
            },
        })
    }

    fn io(&self, e: std::io::Error) -> OfflineError {
        OfflineError::Output(format!(
            "cannot write --write-frames {}: {e}",
            self.log.path.display()
        ))
    }

    /// Writes the header comment (call once, before the first frame): the inputs and rate, and
    /// the replay settings from `params`, the values the render path started with.
    pub fn header(
        &mut self,
        inputs: &[InputSpec],
        sample_rate_hz: u32,
        params: &ParamValues,
        not_in_log: Vec<String>,
    ) -> Result<(), OfflineError> {
        self.log.replay_options = replay_options(params);
        self.log.not_in_log = not_in_log;
        let mut text = format!(
            "# Papier sound-frame log (JSON lines, papier::offline::frame_log), {} frames/s on the \
             render's timeline\n# recorded by papier-render {} at {sample_rate_hz} Hz\n# replay: {}\n",
            self.frame_rate_hz,
            describe_inputs(inputs),
            self.log.replay_command()
        );
        if !self.log.not_in_log.is_empty() {
            text.push_str(&format!(
                "# not in the log (the inputs change them after t = 0): {}\n",
                self.log.not_in_log.join(", ")
            ));
        }
        self.out.write_all(text.as_bytes()).map_err(|e| self.io(e))
    }

    /// Writes the next frame, re-stamped on the render's timeline.
    pub fn record(&mut self, frame: &SoundFrame) -> Result<(), OfflineError> {
        let mut f = *frame;
        self.log.frames += 1;
        f.frame = self.log.frames;
        f.time_s = self.log.frames as f64 / self.frame_rate_hz;
        write_frame(&mut self.out, &f).map_err(|e| self.io(e))
    }

    /// Flushes the file; returns what was written.
    pub fn finish(mut self) -> Result<RecordedLog, OfflineError> {
        self.out.flush().map_err(|e| self.io(e))?;
        Ok(self.log)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame stamped on the 200 Hz grid is delivered at the sample where the engine steps that
    /// frame, at every supported rate (44.1 kHz included); off the grid at the nearest sample,
    /// at or before t = 0 at the first. Detects replay timing drifting from the engine's (the
    /// replay would no longer be bit-identical to the render).
    #[test]
    fn frames_on_the_grid_land_where_the_engine_steps_them() {
        for rate in [8_000.0, 44_100.0, 48_000.0, 96_000.0, 192_000.0] {
            let clock = FrameClock::new(rate, LOG_FRAME_RATE_HZ);
            for k in 0..5_000u64 {
                // The engine delivers frame k (0-based) at end(k); its log time is (k + 1) / 200.
                let t = (k + 1) as f64 / LOG_FRAME_RATE_HZ;
                assert_eq!(frame_sample(t, rate), clock.end(k), "{rate} Hz, frame {k}");
            }
        }
        // Off the grid: the nearest sample; at or before 0: the first.
        assert_eq!(frame_sample(0.0123, 48_000.0), 590);
        assert_eq!(frame_sample(-1.0, 48_000.0), 0);
        assert_eq!(frame_sample(0.0, 48_000.0), 0);
    }

    /// The `--seed`/`--set` options written in a log's header parse back (through the command
    /// line parser and `ParamValues::set_from_arg`) to exactly the sound settings they came from,
    /// the largest seed included. Detects a header option the parser rejects (the replay command
    /// would fail) or rounds (the replay would not be bit-identical).
    #[test]
    fn replay_options_read_back_to_the_same_values() {
        let d = ParamValues::default();
        let p = ParamValues {
            // The largest seed the parameter (and `--seed`) accepts.
            seed: crate::engine::param_values::MAX_SEED as u64,
            room: sim_core::RoomConfig {
                wall: true,
                wall_dist_cm: 17.3,
                ..d.room
            },
            listener_az_deg: -31.7,
            mix_friction_db: -7.25,
            ..d
        };
        let opts = replay_options(&p);
        let args: Vec<String> = opts.clone();
        let crate::offline::cli::Cli::Render(o) = crate::offline::cli::parse(
            &[
                vec![
                    "--frames".to_string(),
                    "x.jsonl".into(),
                    "--out".into(),
                    "x.wav".into(),
                ],
                args,
            ]
            .concat(),
        )
        .unwrap() else {
            panic!()
        };
        let mut q = ParamValues {
            seed: o.seed.unwrap(),
            ..ParamValues::default()
        };
        for s in &o.sets {
            q.set_from_arg(s).unwrap();
        }
        assert_eq!(q, p, "{opts:?}");
    }
}
