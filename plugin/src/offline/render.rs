//! # Rendering: the inputs played through the engine in lockstep, sample-accurately
//!
//! The renderer plays the part of a host with sample-accurate automation: it feeds the engine
//! blocks of `--block` samples, splits a block wherever a parameter changes (as nice-plug does
//! for the plugin) or an OBJ frame falls, calls [`Engine::begin_block`] at each (sub-)block start
//! and hands over MIDI messages with their offsets. A frame log (`--frames`) is played through
//! the render path alone ([`super::frame_replay`]).

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::Instant;

use sim_core::script::Script;
use sim_core::{MeshSnapshot, Sim};
use sounddb::SoundDb;

use super::cli::{InputSpec, RenderOptions};
use super::frame_replay::{self, FrameRecorder};
use super::midi_file::MidiFile;
use super::obj_out::write_obj;
use super::progress::progress_bar;
use super::report::{RenderReport, SheetAccuracy};
use super::timeline::{HostEvent, Timeline};
use super::wav_out::AudioOut;
use super::{MAX_RENDER_S, OfflineError, load_scene};
use crate::engine::{
    Engine, FrameClock, Meters, ParamValues, SheetStore, SimMode, ViewShared, mix_levels,
    permit_always, scene, sim_config, sync_fresh_sim,
};
use crate::gesture_map::MidiInput;
use crate::phrase::player::SLOWEST_SPEED;
use crate::render::Renderer;

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
            let (db, info) = crate::render::user_db::load(p, sample_rate_hz)
                .map_err(|e| OfflineError::Input(format!("--db {}: {e}", p.display())))?;
            if !quiet {
                for w in &info.warnings {
                    eprintln!("papier-render: warning: --db {}: {w}", p.display());
                }
            }
            Ok(db)
        }
    }
}

/// Reads every input onto one sorted timeline (scripts validated against the parameters).
pub(super) fn read_inputs(
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
                tl.add_midi(&f, sr, frames);
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
    for name in &opts.presets {
        crate::preset::find(name)
            .and_then(|p| p.apply_to(&mut params))
            .map_err(|e| OfflineError::Usage(e.0))?;
    }
    if let Some(seed) = opts.seed {
        params.seed = seed;
    }
    for s in &opts.sets {
        params
            .set_from_arg(s)
            .map_err(|e| OfflineError::Usage(format!("--set {s}: {e}")))?;
    }
    // The phrases the MIDI notes play; the render lasts until the last one struck has played
    // (at the slowest velocity).
    let bank = Arc::new(super::phrase_bank(opts.phrases.as_deref()));
    for e in &bank.errors {
        if !opts.quiet {
            eprintln!("papier-render: warning: {e}");
        }
    }
    let mut length_s = log_scan.map_or(tl.length_s, |l| l.last_time_s);
    if log_scan.is_none() {
        for (at, e) in &tl.events {
            if let HostEvent::Midi(MidiInput::NoteOn { key, .. }) = e
                && let Some(p) = bank.get(*key)
            {
                length_s =
                    length_s.max(*at as f64 / sr + p.duration_s / f64::from(SLOWEST_SPEED) + 1.0);
            }
        }
    }
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
        Some(p) => Some(FrameRecorder::create(p, sim_config(&params).frame_rate_hz)?),
        None => None,
    };
    let mut audio = AudioOut::create(&opts.out, opts.sample_rate_hz)?;
    let progress = progress_bar(total, opts.quiet);

    if let (Some(path), Some(scan)) = (log_in, log_scan) {
        // Replay: the render path as the engine sets it up and feeds it, without a sheet.
        let mut renderer = Renderer::new(sr, db, params.seed);
        renderer.set_mix(mix_levels(&params, 1.0));
        renderer.set_scene(scene(&params));
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
    let mut sim = Sim::new(sim_config(&params));
    sync_fresh_sim(&mut sim, &params);
    let mut engine = Engine::new(
        if opts.realtime {
            SimMode::Threaded
        } else {
            SimMode::Lockstep
        },
        sr,
        sim,
        &params,
        db,
        Arc::new(SheetStore::default()),
        0,
        meters.clone(),
        Arc::new(ViewShared::default()),
        permit_always,
    )
    .map_err(|e| OfflineError::Engine(e.to_string()))?;
    engine.swap_phrases(bank);
    // The render path's seed is fixed when the engine is built (a later seed change reseeds the
    // sheet only); the log header records it with the other sound settings at t = 0.
    let sound_seed = params.seed;
    let not_in_log = frame_replay::sound_changes_after_start(&tl);
    engine.record_frames(recorder.is_some());

    let mut left = vec![0.0f32; opts.block];
    let mut right = vec![0.0f32; opts.block];
    let mut mesh = {
        let probe = Sim::new(sim_config(&params));
        let (v, t) = probe.mesh_capacity();
        MeshSnapshot::with_capacity(v * 2, t * 2)
    };
    let obj_at = |i: u64| (i as f64 * sr / opts.obj_fps).round() as u64;
    let mut next_obj = 0u64;
    let mut next_event = 0usize;
    let mut pos = 0u64;
    let events = &tl.events;
    let mut accuracy = SheetAccuracy::default();

    let played_from = Instant::now();
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
            // The OBJ frames due here, before the sub-block's end is set by the next one (an
            // OBJ frame written after it ended a sub-block only at the block's end).
            if let Some(dir) = &opts.obj_dir {
                while obj_at(next_obj) <= sub {
                    if let Some(sim) = engine.lockstep_sim() {
                        write_obj(dir, next_obj, sim, &mut mesh)?;
                    }
                    next_obj += 1;
                }
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
        if opts.realtime {
            // The next block is due when the audio clock reaches this one's end.
            let due = played_from + std::time::Duration::from_secs_f64(pos as f64 / sr);
            if let Some(wait) = due.checked_duration_since(Instant::now()) {
                std::thread::sleep(wait);
            }
        }
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

    // Live, the worker's last frames are in the meters once it stopped.
    drop(engine);
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
        sheet: (!opts.realtime).then_some(accuracy),
        peak,
        rms,
        obj_frames: if opts.obj_dir.is_some() { next_obj } else { 0 },
        frame_log_in: None,
        frame_log_out,
        wall_s: started.elapsed().as_secs_f64(),
        frames_skipped: opts
            .realtime
            .then(|| meters.frames_skipped.load(Ordering::Relaxed)),
    })
}
