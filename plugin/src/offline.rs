//! # The offline renderer (`papier-render`)
//!
//! Renders Papier without a host, with the same engine code as the plugin's `process()`: the
//! renderer plays the part of a host with sample-accurate automation. It feeds the engine
//! blocks of `--block` samples, splits a block wherever a parameter changes (as nice-plug does
//! for the plugin), calls [`Engine::begin_block`] at each (sub-)block start and hands over MIDI
//! messages with their offsets. The sheet is stepped in lockstep with the audio
//! ([`SimMode::Lockstep`]), so two renders of the same input give the same bytes, whatever the
//! block size.
//!
//! Inputs ([`cli`]): Standard MIDI Files ([`midi_file`]), TOML scripts and built-in scenes
//! ([`sim_core::script`]), merged on one timeline ([`timeline`]). Output: a stereo WAV (32-bit
//! float) via `hound`, and optionally the sheet as a sequence of Wavefront OBJ files and the
//! sound input as a frame log (`--write-frames`). A frame log can also be the input
//! (`--frames`): it is then played through the render path alone, with no sheet
//! ([`frame_replay`]).

pub mod cli;
pub mod frame_replay;
pub mod midi_export;
pub mod midi_file;
pub mod timeline;

use std::io::{BufWriter, IsTerminal};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::Instant;

use sim_core::metrics::Metrics;
use sim_core::script::Script;
use sim_core::{MeshSnapshot, Sim};
use sounddb::SoundDb;
use thiserror::Error;

use self::cli::{InputSpec, RenderOptions};
use self::frame_replay::{FrameRecorder, RecordedLog};
use self::midi_export::MidiExport;
use self::midi_file::MidiFile;
use self::timeline::{HostEvent, Timeline};
use crate::engine::{Engine, FrameClock, Meters, ParamValues, SimMode};
use crate::render::Renderer;
use crate::state::SheetStore;

/// Longest render accepted, seconds (one hour).
pub const MAX_RENDER_S: f64 = 3600.0;

/// Why a render failed. Every message is one line.
#[derive(Debug, Error)]
pub enum OfflineError {
    /// Bad command line.
    #[error("{0}")]
    Usage(String),
    /// An input cannot be used.
    #[error("{0}")]
    Input(String),
    /// Output cannot be written.
    #[error("{0}")]
    Output(String),
    /// The engine could not start.
    #[error("{0}")]
    Engine(String),
}

impl OfflineError {
    /// Process exit code: 2 for usage errors, 1 otherwise.
    pub fn exit_code(&self) -> i32 {
        match self {
            OfflineError::Usage(_) => 2,
            _ => 1,
        }
    }
}

/// What a render did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderReport {
    /// Output file.
    pub out: PathBuf,
    /// Rendered length, seconds.
    pub length_s: f64,
    /// Sample rate, Hz.
    pub sample_rate_hz: u32,
    /// Simulation frames stepped.
    pub frames: u64,
    /// Frames in which the sheet slept.
    pub frames_asleep: u64,
    /// Mean step time, ms.
    pub mean_step_ms: f64,
    /// Longest step time, ms.
    pub max_step_ms: f64,
    /// Crumple events delivered to the sound.
    pub crumple_events: u64,
    /// Interior singular vertices at the end.
    pub num_singular: u32,
    /// Accuracy of the sheet against its 2D pattern (sim_core::metrics), when a sheet was
    /// simulated: the last frame's figures and the worst seen at the end of any sub-block.
    pub sheet: Option<SheetAccuracy>,
    /// Peak sample, linear.
    pub peak: f32,
    /// RMS over both channels, linear.
    pub rms: f32,
    /// OBJ frames written.
    pub obj_frames: u64,
    /// The frame log played (`--frames`): no sheet was simulated, `frames` counts its frames.
    pub frame_log_in: Option<PathBuf>,
    /// The frame log written (`--write-frames`).
    pub frame_log_out: Option<RecordedLog>,
    /// Wall-clock time, seconds.
    pub wall_s: f64,
}

/// How isometric the simulated sheet stayed (see `sim_core::metrics::Metrics`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SheetAccuracy {
    /// The last frame's metrics.
    pub end: Metrics,
    /// Largest mean edge compression seen, %.
    pub max_c_mean_pct: f64,
    /// Largest share of edges compressed > 1 % seen, %.
    pub max_n_comp_pct: f64,
    /// Largest principal Green strain seen.
    pub max_strain: f64,
}

impl SheetAccuracy {
    fn observe(&mut self, m: &Metrics) {
        self.end = *m;
        self.max_c_mean_pct = self.max_c_mean_pct.max(m.c_mean_pct);
        self.max_n_comp_pct = self.max_n_comp_pct.max(m.n_comp_pct);
        self.max_strain = self.max_strain.max(m.max_strain);
    }
}

/// The built-in scene names.
pub fn scene_names() -> Vec<&'static str> {
    sim_core::scenario::names().collect()
}

fn load_scene(name: &str) -> Result<Script, OfflineError> {
    if sim_core::scenario::text(name).is_none() {
        return Err(OfflineError::Input(format!(
            "unknown scene {name:?}; available: {}",
            scene_names().join(", ")
        )));
    }
    sim_core::scenario::get(name).map_err(|e| OfflineError::Input(format!("scene {name}: {e}")))
}

/// The sound database: the embedded default, or a user database from `--db` (loaded, checked
/// and prepared for the sample rate; warnings about a partial database are printed).
fn load_db(
    path: Option<&Path>,
    sample_rate_hz: f64,
    quiet: bool,
) -> Result<Arc<SoundDb>, OfflineError> {
    match path {
        None => Ok(crate::render::default_db(sample_rate_hz)),
        Some(p) => {
            let (db, state) = crate::db_loader::load(p, sample_rate_hz)
                .map_err(|e| OfflineError::Input(format!("--db {}: {e}", p.display())))?;
            if let crate::db_loader::DbState::Ready { warnings, .. } = &state
                && !quiet
            {
                for w in warnings {
                    eprintln!("papier-render: warning: --db {}: {w}", p.display());
                }
            }
            Ok(db)
        }
    }
}

fn write_obj(
    dir: &Path,
    index: u64,
    sim: &Sim,
    mesh: &mut MeshSnapshot,
) -> Result<(), OfflineError> {
    sim.write_mesh(mesh);
    let path = dir.join(format!("frame_{index:05}.obj"));
    let file = std::fs::File::create(&path)
        .map_err(|e| OfflineError::Output(format!("cannot write {}: {e}", path.display())))?;
    let mut w = BufWriter::new(file);
    mesh.write_obj(&mut w)
        .and_then(|_| std::io::Write::flush(&mut w))
        .map_err(|e| OfflineError::Output(format!("cannot write {}: {e}", path.display())))
}

/// Reads every input onto one sorted timeline (scripts validated against the parameters).
fn read_inputs(
    inputs: &[InputSpec],
    sr: f64,
    frames: FrameClock,
) -> Result<Timeline, OfflineError> {
    let params = ParamValues::default();
    let mut tl = Timeline::default();
    for input in inputs {
        match input {
            InputSpec::Midi(p) => {
                let f = MidiFile::from_file(p)
                    .map_err(|e| OfflineError::Input(format!("--midi {}: {e}", p.display())))?;
                tl.add_midi(&f, sr);
            }
            InputSpec::Script(p) => {
                let s = Script::from_file(p)
                    .map_err(|e| OfflineError::Input(format!("--script {}: {e}", p.display())))?;
                let mut scratch = params;
                tl.add_script(&p.display().to_string(), &s, sr, frames, &mut scratch)
                    .map_err(OfflineError::Input)?;
            }
            InputSpec::Scene(name) => {
                let s = load_scene(name)?;
                let mut scratch = params;
                tl.add_script(&format!("scene {name}"), &s, sr, frames, &mut scratch)
                    .map_err(OfflineError::Input)?;
            }
            InputSpec::Frames(p) => {
                return Err(OfflineError::Usage(format!(
                    "--frames {}: a frame log holds sounds, not gestures; it plays on its own",
                    p.display()
                )));
            }
        }
    }
    tl.finish();
    Ok(tl)
}

/// Writes the inputs as a MIDI performance (README map) to `out` ([`midi_export`]).
pub fn write_midi(inputs: &[InputSpec], out: &Path) -> Result<MidiExport, OfflineError> {
    let sr = 48_000.0;
    let frames = FrameClock::new(sr, sim_core::sim::DEFAULT_FRAME_RATE_HZ);
    let tl = read_inputs(inputs, sr, frames)?;
    let x = midi_export::export(&tl, sr);
    if let Some(parent) = out.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent).map_err(|e| {
            OfflineError::Output(format!("cannot create {}: {e}", parent.display()))
        })?;
    }
    std::fs::write(out, x.to_smf())
        .map_err(|e| OfflineError::Output(format!("cannot write {}: {e}", out.display())))?;
    Ok(x)
}

/// The stereo WAV being written, with its running peak and energy.
struct AudioOut {
    path: PathBuf,
    wav: hound::WavWriter<BufWriter<std::fs::File>>,
    samples: u64,
    sum_sq: f64,
    peak: f32,
}

impl AudioOut {
    /// Creates the file (and its folder).
    fn create(path: &Path, sample_rate_hz: u32) -> Result<Self, OfflineError> {
        if let Some(parent) = path.parent()
            && !parent.as_os_str().is_empty()
        {
            std::fs::create_dir_all(parent).map_err(|e| {
                OfflineError::Output(format!("cannot create {}: {e}", parent.display()))
            })?;
        }
        let spec = hound::WavSpec {
            channels: 2,
            sample_rate: sample_rate_hz,
            bits_per_sample: 32,
            sample_format: hound::SampleFormat::Float,
        };
        let wav = hound::WavWriter::create(path, spec)
            .map_err(|e| OfflineError::Output(format!("cannot write {}: {e}", path.display())))?;
        Ok(Self {
            path: path.to_path_buf(),
            wav,
            samples: 0,
            sum_sq: 0.0,
            peak: 0.0,
        })
    }

    fn error(&self, e: hound::Error) -> OfflineError {
        OfflineError::Output(format!("cannot write {}: {e}", self.path.display()))
    }

    /// Appends a block (both channels the same length).
    fn write(&mut self, left: &[f32], right: &[f32]) -> Result<(), OfflineError> {
        for (&l, &r) in left.iter().zip(right) {
            self.sum_sq += f64::from(l) * f64::from(l) + f64::from(r) * f64::from(r);
            self.peak = self.peak.max(l.abs()).max(r.abs());
            if let Err(e) = self
                .wav
                .write_sample(l)
                .and_then(|_| self.wav.write_sample(r))
            {
                return Err(self.error(e));
            }
        }
        self.samples += left.len().min(right.len()) as u64;
        Ok(())
    }

    /// Finalizes the file; returns (peak, RMS over both channels).
    fn finish(self) -> Result<(f32, f32), OfflineError> {
        let path = self.path;
        self.wav
            .finalize()
            .map_err(|e| OfflineError::Output(format!("cannot write {}: {e}", path.display())))?;
        let rms = if self.samples > 0 {
            (self.sum_sq / (2 * self.samples) as f64).sqrt() as f32
        } else {
            0.0
        };
        Ok((self.peak, rms))
    }
}

/// What the engine does to every block it renders, and the replay too: never let a NaN, an
/// infinity or a subnormal out (the render path already guarantees finite, normal output).
fn sanitize(left: &mut [f32], right: &mut [f32]) {
    for s in left.iter_mut().chain(right.iter_mut()) {
        if !(s.is_normal() || *s == 0.0) {
            *s = 0.0;
        }
    }
}

fn progress_bar(total: u64, quiet: bool) -> indicatif::ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let pb = indicatif::ProgressBar::new(total);
    pb.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} rendering [{bar:40}] {percent:>3}% {elapsed} (eta {eta})",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    pb
}

/// The frame log among the inputs, if any (it must then be the only input).
fn frame_log_input(inputs: &[InputSpec]) -> Result<Option<&Path>, OfflineError> {
    let log = inputs.iter().find_map(|i| match i {
        InputSpec::Frames(p) => Some(p.as_path()),
        _ => None,
    });
    if log.is_some() && inputs.len() > 1 {
        return Err(OfflineError::Usage(
            "--frames plays a recorded log on its own: drop the other inputs".into(),
        ));
    }
    Ok(log)
}

/// Renders according to the options.
pub fn render(opts: &RenderOptions) -> Result<RenderReport, OfflineError> {
    let started = Instant::now();
    let sr = f64::from(opts.sample_rate_hz);

    // The inputs: a frame log (validated whole before anything is written), or the timeline.
    let log_in = frame_log_input(&opts.inputs)?;
    if log_in.is_some() && (opts.obj_dir.is_some() || opts.write_frames.is_some()) {
        return Err(OfflineError::Usage(
            "--frames has no sheet: drop --obj-dir and --write-frames".into(),
        ));
    }
    let frames = FrameClock::new(sr, sim_core::sim::DEFAULT_FRAME_RATE_HZ);
    let (tl, log_scan) = match log_in {
        Some(p) => (Timeline::default(), Some(frame_replay::scan(p)?)),
        None => (read_inputs(&opts.inputs, sr, frames)?, None),
    };

    // Parameters: defaults, then the scripts' [set] tables, then --seed and --set.
    let mut params = ParamValues::default();
    for (id, v) in &tl.initial {
        params
            .set(id, v)
            .map_err(|e| OfflineError::Input(e.to_string()))?;
    }
    if let Some(seed) = opts.seed {
        params.seed = seed;
    }
    for s in &opts.sets {
        params
            .set_from_arg(s)
            .map_err(|e| OfflineError::Usage(format!("--set {s}: {e}")))?;
    }
    let length_s = log_scan.map_or(tl.length_s, |l| l.last_time_s);
    if !(length_s.is_finite() && length_s > 0.0 && length_s <= MAX_RENDER_S) {
        let what = match (log_in, log_scan) {
            (Some(p), Some(l)) => format!(
                "--frames {}: the log lasts {:.3} s (its last frame's time_s)",
                p.display(),
                l.last_time_s
            ),
            _ => format!("the inputs last {length_s:.3} s"),
        };
        return Err(OfflineError::Input(format!(
            "{what}; a render must last more than 0 and at most {MAX_RENDER_S} s"
        )));
    }
    let total = (length_s * sr).round() as u64;

    let db = load_db(opts.db.as_deref(), sr, opts.quiet)?;
    if let Some(dir) = &opts.obj_dir {
        std::fs::create_dir_all(dir).map_err(|e| {
            OfflineError::Output(format!("cannot create --obj-dir {}: {e}", dir.display()))
        })?;
    }
    let mut recorder = match &opts.write_frames {
        Some(p) => Some(FrameRecorder::create(
            p,
            crate::sim_config(&params).frame_rate_hz,
        )?),
        None => None,
    };
    let mut audio = AudioOut::create(&opts.out, opts.sample_rate_hz)?;
    let progress = progress_bar(total, opts.quiet);

    if let (Some(path), Some(scan)) = (log_in, log_scan) {
        // Replay: the render path as the engine sets it up and feeds it, without a sheet.
        let mut renderer = Renderer::new(sr, db, params.seed);
        renderer.set_mix(crate::engine::mix_levels(&params, 1.0));
        renderer.set_scene(crate::engine::scene(&params));
        renderer.snap_gains();
        let played = frame_replay::play(
            path,
            &mut renderer,
            total,
            opts.block,
            &mut audio,
            &progress,
        )?;
        let (peak, rms) = audio.finish()?;
        progress.finish_and_clear();
        debug_assert!(played.frames <= scan.frames);
        return Ok(RenderReport {
            out: opts.out.clone(),
            length_s: total as f64 / sr,
            sample_rate_hz: opts.sample_rate_hz,
            frames: played.frames,
            crumple_events: played.crumple_events,
            peak,
            rms,
            frame_log_in: Some(path.to_path_buf()),
            wall_s: started.elapsed().as_secs_f64(),
            ..RenderReport::default()
        });
    }

    let meters = Arc::new(Meters::default());
    let mut sim = Sim::new(crate::sim_config(&params));
    crate::engine::sync_fresh_sim(&mut sim, &params);
    let mut engine = Engine::new(
        SimMode::Lockstep,
        sr,
        sim,
        &params,
        db,
        Arc::new(SheetStore::default()),
        0,
        meters.clone(),
        Arc::new(crate::engine::ViewShared::default()),
    )
    .map_err(|e| OfflineError::Engine(e.to_string()))?;
    // The render path's seed is fixed when the engine is built (a later seed change reseeds the
    // sheet only); the log header records it with the other sound settings at t = 0.
    let sound_seed = params.seed;
    let not_in_log = frame_replay::sound_changes_after_start(&tl);
    engine.record_frames(recorder.is_some());

    let mut left = vec![0.0f32; opts.block];
    let mut right = vec![0.0f32; opts.block];
    let mut mesh = {
        let probe = Sim::new(crate::sim_config(&params));
        let (v, t) = probe.mesh_capacity();
        MeshSnapshot::with_capacity(v * 2, t * 2)
    };
    let obj_at = |i: u64| (i as f64 * sr / opts.obj_fps).round() as u64;
    let mut next_obj = 0u64;
    let mut next_event = 0usize;
    let mut pos = 0u64;
    let events = &tl.events;
    let mut accuracy = SheetAccuracy::default();

    while pos < total {
        let block_end = (pos + opts.block as u64).min(total);
        let mut sub = pos;
        while sub < block_end {
            // Parameter changes at this sample start a new sub-block.
            let mut changed = sub == pos;
            while next_event < events.len() && events[next_event].0 <= sub {
                if let HostEvent::Param { id, value } = &events[next_event].1 {
                    if events[next_event].0 == sub || sub == 0 {
                        params
                            .set(id, value)
                            .map_err(|e| OfflineError::Input(e.to_string()))?;
                        changed = true;
                    }
                    next_event += 1;
                } else {
                    break;
                }
            }
            if changed {
                engine.begin_block(&params);
            }
            if sub == 0
                && let Some(rec) = &mut recorder
            {
                let mut start = engine.last_params();
                start.seed = sound_seed;
                rec.header(
                    &opts.inputs,
                    opts.sample_rate_hz,
                    &start,
                    not_in_log.clone(),
                )?;
            }
            // The sub-block ends at the next parameter change or OBJ frame.
            let mut sub_end = block_end;
            let mut k = next_event;
            while k < events.len() && events[k].0 < block_end {
                if matches!(events[k].1, HostEvent::Param { .. }) && events[k].0 > sub {
                    sub_end = sub_end.min(events[k].0);
                    break;
                }
                k += 1;
            }
            if opts.obj_dir.is_some() && obj_at(next_obj) > sub {
                sub_end = sub_end.min(obj_at(next_obj));
            }
            // MIDI inside [sub, sub_end), in order.
            while next_event < events.len() && events[next_event].0 < sub_end {
                match &events[next_event].1 {
                    HostEvent::Midi(m) => {
                        engine.midi(*m, (events[next_event].0 - sub) as u32);
                        next_event += 1;
                    }
                    HostEvent::Param { .. } => break,
                }
            }
            if let Some(dir) = &opts.obj_dir {
                while obj_at(next_obj) <= sub {
                    if let Some(sim) = engine.lockstep_sim() {
                        write_obj(dir, next_obj, sim, &mut mesh)?;
                    }
                    next_obj += 1;
                }
            }
            let n = (sub_end - sub) as usize;
            let off = (sub - pos) as usize;
            engine.render(&mut left[off..off + n], &mut right[off..off + n]);
            if let Some(sim) = engine.lockstep_sim() {
                accuracy.observe(sim.metrics());
            }
            if let Some(rec) = &mut recorder {
                for f in engine.drain_recorded_frames() {
                    rec.record(&f)?;
                }
            }
            sub = sub_end;
        }
        let n = (block_end - pos) as usize;
        audio.write(&left[..n], &right[..n])?;
        pos = block_end;
        progress.set_position(pos);
    }
    if let Some(dir) = &opts.obj_dir {
        while obj_at(next_obj) <= total {
            if let Some(sim) = engine.lockstep_sim() {
                write_obj(dir, next_obj, sim, &mut mesh)?;
            }
            next_obj += 1;
        }
    }
    let (peak, rms) = audio.finish()?;
    let frame_log_out = match recorder {
        Some(rec) => Some(rec.finish()?),
        None => None,
    };
    progress.finish_and_clear();

    let frames_stepped = meters.frames_stepped.load(Ordering::Relaxed);
    let num_singular = meters.num_singular.load(Ordering::Relaxed);
    Ok(RenderReport {
        out: opts.out.clone(),
        length_s: total as f64 / sr,
        sample_rate_hz: opts.sample_rate_hz,
        frames: frames_stepped,
        frames_asleep: meters.frames_asleep.load(Ordering::Relaxed),
        mean_step_ms: if frames_stepped > 0 {
            meters.total_step_ns.load(Ordering::Relaxed) as f64 * 1e-6 / frames_stepped as f64
        } else {
            0.0
        },
        max_step_ms: meters.max_step_ns.load(Ordering::Relaxed) as f64 * 1e-6,
        crumple_events: meters.crumple_events.load(Ordering::Relaxed),
        num_singular,
        sheet: Some(accuracy),
        peak,
        rms,
        obj_frames: if opts.obj_dir.is_some() { next_obj } else { 0 },
        frame_log_in: None,
        frame_log_out,
        wall_s: started.elapsed().as_secs_f64(),
    })
}

fn db_string(x: f32) -> String {
    if x > 0.0 {
        format!("{:.1} dBFS", 20.0 * x.log10())
    } else {
        "silent".into()
    }
}

impl std::fmt::Display for RenderReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "papier-render: {:.2} s at {} Hz -> {} (stereo, 32-bit float)",
            self.length_s,
            self.sample_rate_hz,
            self.out.display()
        )?;
        match &self.frame_log_in {
            Some(log) => writeln!(
                f,
                "  log:   {} frames played from {} (no sheet simulated)",
                self.frames,
                log.display()
            )?,
            None => writeln!(
                f,
                "  sim:   {} frames ({:.0} % asleep), step mean {:.3} ms, max {:.3} ms, {} singular points",
                self.frames,
                if self.frames > 0 {
                    100.0 * self.frames_asleep as f64 / self.frames as f64
                } else {
                    0.0
                },
                self.mean_step_ms,
                self.max_step_ms,
                self.num_singular
            )?,
        }
        if let Some(a) = &self.sheet {
            writeln!(
                f,
                "  sheet: c_mean {:.3} %, n_comp {:.2} %, max strain {:.4} at the end \
                 (worst: c_mean {:.3} %, n_comp {:.2} %, strain {:.4})",
                a.end.c_mean_pct,
                a.end.n_comp_pct,
                a.end.max_strain,
                a.max_c_mean_pct,
                a.max_n_comp_pct,
                a.max_strain
            )?;
        }
        writeln!(
            f,
            "  audio: peak {}, RMS {}, {} crumple events",
            db_string(self.peak),
            db_string(self.rms),
            self.crumple_events
        )?;
        if self.obj_frames > 0 {
            writeln!(f, "  obj:   {} frames", self.obj_frames)?;
        }
        if let Some(log) = &self.frame_log_out {
            writeln!(
                f,
                "  log:   {} sound frames -> {}\n  replay it: {}",
                log.frames,
                log.path.display(),
                log.replay_command()
            )?;
            if !log.not_in_log.is_empty() {
                writeln!(
                    f,
                    "  not in the log (the inputs change them after t = 0): {}",
                    log.not_in_log.join(", ")
                )?;
            }
        }
        write!(
            f,
            "  took {:.2} s ({:.1}x real time)",
            self.wall_s,
            if self.wall_s > 0.0 {
                self.length_s / self.wall_s
            } else {
                0.0
            }
        )
    }
}

/// `papier-render`'s entry point: parses the arguments (without the program name), renders,
/// prints the report, and returns the exit code.
pub fn main_with_args(args: &[String]) -> i32 {
    let cli = match cli::parse(args) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("papier-render: error: {e}");
            return 2;
        }
    };
    match cli {
        cli::Cli::Help => {
            println!("{}", cli::USAGE);
            0
        }
        cli::Cli::ListScenes => {
            for n in scene_names() {
                println!("{n}");
            }
            0
        }
        cli::Cli::WriteMidi { inputs, out, quiet } => match write_midi(&inputs, &out) {
            Ok(x) => {
                if !quiet {
                    let sets: String = x.sets.iter().map(|s| format!(" --set {s}")).collect();
                    println!(
                        "papier-render: wrote {} ({} messages, {:.2} s)\n  render it: papier-render --midi {}{sets} --out OUT.wav",
                        out.display(),
                        x.events.len(),
                        x.length_s,
                        out.display()
                    );
                    if !x.dropped.is_empty() {
                        println!(
                            "  not in the file (no MIDI control for them): {}",
                            x.dropped.join(", ")
                        );
                    }
                }
                0
            }
            Err(e) => {
                eprintln!("papier-render: error: {e}");
                e.exit_code()
            }
        },
        cli::Cli::Render(opts) => match render(&opts) {
            Ok(report) => {
                if !opts.quiet {
                    println!("{report}");
                }
                0
            }
            Err(e) => {
                eprintln!("papier-render: error: {e}");
                e.exit_code()
            }
        },
    }
}
