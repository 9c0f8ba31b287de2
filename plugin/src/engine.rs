//! # The engine: gestures in, sheet stepped, sound out
//!
//! One engine serves the plugin's `process()` and the offline renderer `papier-render`; both
//! drive it the same way, block by block:
//!
//! 1. [`Engine::begin_block`] with the current parameter values: changed gesture, sheet and
//!    room parameters become simulation commands stamped at the block start; mix and listener
//!    changes go to the render path;
//! 2. [`Engine::midi`] for each MIDI message of the block, in time order, with its offset: the
//!    shared mapping ([`crate::gesture_map`]) turns it into a command stamped at its sample;
//! 3. [`Engine::render`] fills the block.
//!
//! ```text
//!  host / papier-render                 audio thread                      sim worker thread
//!  ──────────────────                 ────────────                      ─────────────────
//!  params, MIDI ──► Engine::begin_block / midi ──► commands ══ArrayQueue══►  apply, Sim::step
//!                                                                            │ per frame
//!                   Engine::render ◄══ triple_buffer (SimSnapshot) ═══════════┤
//!                        │         ◄══ ArrayQueue (SimEvent: crumple) ════════┘
//!                        ▼                 ▲ audio sample clock (AtomicU64) ──► worker paces on it
//!                 Renderer (units, friction iFFT, tear noise, dipole + images) ──► output
//! ```
//!
//! Two ways to run the sheet ([`SimMode`]):
//! - **Threaded** (real time): the worker thread above. The audio thread never waits: it renders
//!   with the latest snapshot and whatever events have arrived. Latency from a gesture to its
//!   sound is at most one simulation frame plus one block (plus the step time).
//! - **Lockstep** (offline: the host's offline render mode, `papier-render`, tests): the engine
//!   steps the sheet itself, exactly at each frame boundary inside the block. Output is then a
//!   pure function of the inputs and their sample times: it does not depend on the block size or
//!   on how the host splits blocks, and two renders give identical bits.
//!
//! In both modes frame `k` is stepped when the audio clock reaches the end of its span, after
//! applying every command stamped before that end ([`frame_clock`]), by the one frame loop
//! ([`frame_loop`]).
//!
//! The engine knows no plugin framework: the plugin face adapts nice-plug's parameters, events
//! and persistence to it, and hands it the allocation checker's permit ([`AllocPermit`]).

pub mod frame_clock;
pub mod frame_loop;
pub mod messages;
pub mod meters;
pub mod param_values;
pub mod sheet_store;
pub mod view;
pub mod volume_changes;
pub mod worker;

use std::sync::Arc;
use std::sync::atomic::Ordering;

use sim_core::sound_input::SoundFrame;
use sim_core::{Command, GestureParam, Sim};
use sounddb::SoundDb;

pub use self::frame_clock::FrameClock;
pub use self::frame_loop::{AllocPermit, permit_always};
use self::frame_loop::{FrameLoop, PublishRule};
use self::messages::{EVENT_QUEUE_CAPACITY, SimEvent, SimSnapshot, WorkerMsg, WorkerMsgKind};
pub use self::meters::Meters;
pub use self::param_values::{ParamError, ParamValues, sim_config};
pub use self::sheet_store::SheetStore;
pub use self::view::{ViewFrame, ViewShared};
use self::volume_changes::VolumeChanges;
use self::worker::{WorkerHandle, WorkerShared, WorkerState};
use crate::gesture_map::{self, Action, MidiInput, NOTE_RELEASE_ALL, NOTE_RESET};
use crate::phrase::{PhraseBank, PhrasePlayer};
use crate::render::{MixLevels, Renderer, Scene};

/// How the sheet is simulated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SimMode {
    /// Stepped inline by the engine at frame boundaries (offline, deterministic).
    Lockstep,
    /// Stepped by a worker thread that follows the audio clock (real time).
    Threaded,
}

/// Brings a freshly built sheet's gestures in line with the parameters (its size, material,
/// seed and room come from [`sim_config`]). Only what differs is applied.
pub fn sync_fresh_sim(sim: &mut Sim, params: &ParamValues) {
    for g in GestureParam::ALL {
        let value = params.gestures[g.index()];
        if sim.gesture(g).to_bits() != value.to_bits() {
            sim.apply(Command::Gesture { param: g, value });
        }
    }
}

/// Queues a message for the sheet; a full queue drops it and counts it.
fn send_to(host: &mut Host, meters: &Meters, at_sample: u64, kind: WorkerMsgKind) {
    let queued = match host {
        Host::Lockstep(l) => l.frames.queue(WorkerMsg { at_sample, kind }),
        Host::Threaded(t) => t
            .shared
            .commands
            .push(WorkerMsg { at_sample, kind })
            .is_ok(),
    };
    if !queued {
        meters.commands_dropped.fetch_add(1, Ordering::Relaxed);
    }
}

/// Lowest gain the MIDI volume can produce, dB (CC 7 = 0 maps here, not to −∞).
const MIN_VOLUME_DB: f32 = -120.0;

/// Why an engine could not be started.
#[derive(Debug, thiserror::Error)]
pub enum EngineError {
    /// The worker thread could not be spawned.
    #[error("cannot start the simulation thread: {0}")]
    Spawn(#[from] std::io::Error),
}

struct Lockstep {
    frames: FrameLoop,
    /// Runs what may allocate on the audio thread (a rebuild, a mesh change, a publish).
    permit: AllocPermit,
}

struct Threaded {
    worker: WorkerHandle,
    shared: Arc<WorkerShared>,
    snapshots: triple_buffer::Output<SimSnapshot>,
    last_frames: u64,
}

enum Host {
    Lockstep(Lockstep),
    Threaded(Threaded),
}

/// The engine (see the module docs).
pub struct Engine {
    clock: u64,
    frames: FrameClock,
    last: ParamValues,
    /// The MIDI volume and its changes not yet reached, each at its sample ([`volume_changes`]).
    midi_volume: MidiVolume,
    renderer: Renderer,
    store: Arc<SheetStore>,
    store_generation: u64,
    meters: Arc<Meters>,
    host: Host,
    /// Copies of the sound frames delivered in lockstep mode, while recording.
    recorded: Option<Vec<SoundFrame>>,
    /// Phrases playing from notes ([`crate::phrase`]).
    phrases: PhrasePlayer,
}

/// The MIDI volume (linear gain) in effect and its queued changes.
struct MidiVolume {
    gain: f32,
    changes: VolumeChanges,
}

impl MidiVolume {
    /// Queues `gain` from sample `at`; a change the full queue gives up takes effect now.
    fn push(&mut self, at: u64, gain: f32, renderer: &mut Renderer, last: &ParamValues) {
        if let Some(early) = self.changes.push(at, gain) {
            self.set(early, renderer, last);
        }
    }

    /// Applies the changes due at or before sample `now` and returns the sample the current
    /// segment must end at for the next one (or `limit`).
    fn until(&mut self, now: u64, limit: u64, renderer: &mut Renderer, last: &ParamValues) -> u64 {
        if let Some(g) = self.changes.take_due(now) {
            self.set(g, renderer, last);
        }
        self.changes.next_at().map_or(limit, |at| at.min(limit))
    }

    fn set(&mut self, gain: f32, renderer: &mut Renderer, last: &ParamValues) {
        self.gain = gain;
        renderer.set_mix(mix_levels(last, gain));
    }
}

/// The render path's mix for these parameters and a MIDI volume (linear gain).
pub(crate) fn mix_levels(p: &ParamValues, midi_volume: f32) -> MixLevels {
    let vol_db = if midi_volume > 0.0 {
        (20.0 * midi_volume.log10()).max(MIN_VOLUME_DB)
    } else {
        MIN_VOLUME_DB
    };
    MixLevels {
        crumple_db: p.mix_crumple_db,
        friction_db: p.mix_friction_db,
        tear_db: p.mix_tear_db,
        output_db: p.gain_db + vol_db,
    }
}

/// The render path's room and listener for these parameters.
pub(crate) fn scene(p: &ParamValues) -> Scene {
    Scene {
        room: p.room,
        listener_az_deg: p.listener_az_deg,
        listener_dist_m: p.listener_dist_m,
    }
}

impl Engine {
    /// Starts an engine around a sheet. `store_generation` is the sheet store generation the
    /// sheet is based on. `params` are the parameter values the sheet already reflects (the
    /// first [`Engine::begin_block`] sends what differs from them): for a fresh sheet, the values
    /// it was built and [synced](sync_fresh_sim) with; for a sheet kept across a deactivation,
    /// the values at deactivation; for a sheet restored from a project, the loaded values.
    /// `permit` runs what may allocate on the thread that calls [`Engine::render`] in lockstep
    /// mode (the plugin passes its allocation checker's permit; offline code
    /// [`permit_always`]). Allocates (call from `activate()` or offline code).
    pub fn new(
        mode: SimMode,
        sample_rate_hz: f64,
        sim: Sim,
        params: &ParamValues,
        db: Arc<SoundDb>,
        store: Arc<SheetStore>,
        store_generation: u64,
        meters: Arc<Meters>,
        view: Arc<ViewShared>,
        permit: AllocPermit,
    ) -> Result<Self, EngineError> {
        let frames = FrameClock::new(sample_rate_hz, sim.config().frame_rate_hz);
        let mut renderer = Renderer::new(sample_rate_hz, db, params.seed);
        renderer.set_mix(mix_levels(params, 1.0));
        renderer.set_scene(scene(params));
        // Start at the mix, do not glide to it from 0 dB.
        renderer.snap_gains();
        let host = match mode {
            SimMode::Lockstep => Host::Lockstep(Lockstep {
                frames: FrameLoop::new(sim, store_generation, &view, PublishRule::EveryBlock),
                permit,
            }),
            SimMode::Threaded => {
                let shared = Arc::new(WorkerShared::new(EVENT_QUEUE_CAPACITY));
                let (input, output) = triple_buffer::triple_buffer(&SimSnapshot::default());
                let worker = WorkerHandle::spawn(
                    WorkerState {
                        frames: FrameLoop::new(
                            sim,
                            store_generation,
                            &view,
                            PublishRule::RestAndInterval,
                        ),
                        clock: frames,
                    },
                    shared.clone(),
                    input,
                    store.clone(),
                    meters.clone(),
                )?;
                Host::Threaded(Threaded {
                    worker,
                    shared,
                    snapshots: output,
                    last_frames: 0,
                })
            }
        };
        Ok(Self {
            clock: 0,
            frames,
            last: *params,
            midi_volume: MidiVolume {
                gain: 1.0,
                changes: VolumeChanges::default(),
            },
            renderer,
            store,
            store_generation,
            meters,
            host,
            recorded: None,
            phrases: PhrasePlayer::new(Arc::new(PhraseBank::default())),
        })
    }

    /// The parameter values the engine last saw.
    pub fn last_params(&self) -> ParamValues {
        self.last
    }

    /// Samples rendered so far.
    pub fn clock(&self) -> u64 {
        self.clock
    }

    /// The frame clock.
    pub fn frame_clock(&self) -> FrameClock {
        self.frames
    }

    /// The simulation mode.
    pub fn mode(&self) -> SimMode {
        match self.host {
            Host::Lockstep(_) => SimMode::Lockstep,
            Host::Threaded(_) => SimMode::Threaded,
        }
    }

    /// The sheet, when it is stepped inline (lockstep mode).
    pub fn lockstep_sim(&self) -> Option<&Sim> {
        match &self.host {
            Host::Lockstep(l) => Some(l.frames.sim()),
            Host::Threaded(_) => None,
        }
    }

    /// Starts or stops keeping a copy of every sound frame the sheet delivers to the render path
    /// in lockstep mode, in order (one per stepped frame, crumple events included), for
    /// [`Self::drain_recorded_frames`]; `papier-render --write-frames` logs them. Off by default;
    /// while on, a delivered frame may allocate (offline use; drain often). Threaded mode does
    /// not record.
    pub fn record_frames(&mut self, on: bool) {
        self.recorded = on.then(Vec::new);
    }

    /// The frames recorded since the last call, oldest first (nothing when not recording).
    pub fn drain_recorded_frames(&mut self) -> impl Iterator<Item = SoundFrame> + '_ {
        self.recorded.iter_mut().flat_map(|v| v.drain(..))
    }

    /// Sets the render path's mix, room and listener to `p` at once (no glide). For
    /// `activate()`: the engine is built with the values its sheet reflects (those at the last
    /// deactivation, so that parameter changes made while inactive reach the sheet as
    /// commands), but the sound must start at the current values, not fade to them.
    /// No allocation.
    pub fn start_sound_at(&mut self, p: &ParamValues) {
        self.renderer.set_mix(mix_levels(p, self.midi_volume.gain));
        self.renderer.set_scene(scene(p));
        self.renderer.snap_gains();
    }

    /// The render path (for counters).
    pub fn renderer(&self) -> &Renderer {
        &self.renderer
    }

    /// Clears the render path's voices and noise state (the sheet is kept). Allocation-free.
    pub fn reset_audio(&mut self) {
        self.renderer.reset();
    }

    /// Replaces the sound database; returns the old one to be dropped off the audio thread.
    pub fn swap_db(&mut self, db: Arc<SoundDb>) -> Arc<SoundDb> {
        self.renderer.swap_db(db)
    }

    fn send(&mut self, at_sample: u64, kind: WorkerMsgKind) {
        send_to(&mut self.host, &self.meters, at_sample, kind);
    }

    fn command(&mut self, at_sample: u64, cmd: Command) {
        self.send(at_sample, WorkerMsgKind::Command(cmd));
    }

    /// Replaces the phrase bank (every phrase stops); returns the old one, to be dropped off the
    /// audio thread. Allocation-free.
    pub fn swap_phrases(&mut self, bank: Arc<PhraseBank>) -> Arc<PhraseBank> {
        self.phrases.swap_bank(bank)
    }

    /// The phrase bank in use.
    pub fn phrase_bank(&self) -> &Arc<PhraseBank> {
        self.phrases.bank()
    }

    /// Phrases playing now.
    pub fn phrases_playing(&self) -> usize {
        self.phrases.playing()
    }

    /// Sends the phrases' commands stamped before sample `to`.
    fn advance_phrases(&mut self, to: u64) {
        let Self {
            phrases,
            host,
            meters,
            frames,
            last,
            ..
        } = self;
        phrases.advance(to, frames, last, |at, cmd| {
            send_to(host, meters, at, WorkerMsgKind::Command(cmd));
        });
    }

    /// Start of a block (or of a sub-block after a parameter change): diffs the parameters.
    /// Allocation-free.
    pub fn begin_block(&mut self, p: &ParamValues) {
        let at = self.clock;
        self.advance_phrases(at);
        let generation = self.store.generation();
        let restored = generation != self.store_generation;
        if restored {
            // A project state was loaded: the sheet comes from the store, and the loaded
            // parameters are the ones it was saved with. No size/material change may rebuild
            // it, and its gesture state (which may come from MIDI CCs) is kept: the latest change
            // before the save wins, as it did while playing.
            self.store_generation = generation;
            // In the loaded room: a sheet continues as saved only in the room it was saved in.
            self.send(at, WorkerMsgKind::RestoreSheet { room: p.room });
        } else {
            if p.size != self.last.size {
                self.command(at, Command::Size(p.size));
            }
            if p.material != self.last.material {
                self.command(at, Command::Material(p.material));
            }
            if p.seed != self.last.seed {
                self.command(at, Command::Seed(p.seed));
            }
        }
        if !restored && p.room != self.last.room {
            self.command(at, Command::Room(p.room));
        }
        for g in GestureParam::ALL {
            let v = p.gestures[g.index()];
            if !restored && v.to_bits() != self.last.gestures[g.index()].to_bits() {
                self.command(at, Command::Gesture { param: g, value: v });
            }
        }
        if p.room != self.last.room
            || p.listener_az_deg != self.last.listener_az_deg
            || p.listener_dist_m != self.last.listener_dist_m
        {
            self.renderer.set_scene(scene(p));
        }
        if p.mix_crumple_db != self.last.mix_crumple_db
            || p.mix_friction_db != self.last.mix_friction_db
            || p.mix_tear_db != self.last.mix_tear_db
            || p.gain_db != self.last.gain_db
        {
            self.renderer.set_mix(mix_levels(p, self.midi_volume.gain));
        }
        self.last = *p;
    }

    /// A MIDI message at `offset` samples into the current block. Allocation-free.
    pub fn midi(&mut self, input: MidiInput, offset: u32) {
        let at = self.clock + u64::from(offset);
        self.advance_phrases(at);
        match input {
            MidiInput::NoteOn { key, velocity } => {
                if key == NOTE_RESET || key == NOTE_RELEASE_ALL {
                    self.phrases.stop_all();
                } else if self.phrases.note_on(at, key, velocity, self.last.seed) {
                    self.meters.phrase_hits.fetch_add(1, Ordering::Relaxed);
                    return;
                }
            }
            MidiInput::NoteOff { key } => {
                let Self {
                    phrases,
                    host,
                    meters,
                    ..
                } = self;
                phrases.note_off(at, key, |at, cmd| {
                    send_to(host, meters, at, WorkerMsgKind::Command(cmd));
                });
            }
            MidiInput::AllNotesOff => self.phrases.stop_all(),
            MidiInput::Cc { cc, .. } => {
                if matches!(cc, 120 | 121 | 123) {
                    self.phrases.stop_all();
                }
            }
        }
        match gesture_map::map(input) {
            Action::None => {}
            Action::Sim(cmd) => self.command(at, cmd),
            Action::Volume(v) => self.volume_at(at, v),
            Action::ResetControllers => {
                for g in GestureParam::ALL {
                    let value = self.last.gestures[g.index()];
                    self.command(at, Command::Gesture { param: g, value });
                }
                self.volume_at(at, 1.0);
            }
        }
    }

    /// The MIDI volume becomes `gain` at sample `at` (queued; [`Self::render`] applies it there).
    fn volume_at(&mut self, at: u64, gain: f32) {
        self.midi_volume
            .push(at, gain, &mut self.renderer, &self.last);
    }

    fn deliver(renderer: &mut Renderer, sound: &SoundFrame, meters: &Meters) {
        renderer.set_frame(sound);
        for e in sound.crumple() {
            renderer.trigger(e);
        }
        meters.record_sound(sound);
    }

    /// Renders one block into `left` and `right` (same length, any length). Allocation-free in
    /// threaded mode; in lockstep mode only a sheet rebuild (reset, size change, restore), a
    /// step that changes the mesh (`Sim::refinement_pending`) and the publish for the saved
    /// project at the end of a block in which the sheet moved allocate, inside the permit.
    pub fn render(&mut self, left: &mut [f32], right: &mut [f32]) {
        let n = left.len().min(right.len());
        self.advance_phrases(self.clock + n as u64);
        match &mut self.host {
            Host::Lockstep(l) => {
                // The sheet was built on another thread than this one: the solver's dense
                // kernels make their lazy first-use allocations on a thread's first call
                // (once; a no-op afterwards), permitted like a rebuild.
                (l.permit)(&mut sim_core::warm_up_thread);
                let mut pos = 0usize;
                loop {
                    let end = self.frames.end(l.frames.next_frame());
                    if end <= self.clock + pos as u64 {
                        let out = l
                            .frames
                            .step(&self.frames, &self.store, &self.meters, l.permit);
                        Self::deliver(&mut self.renderer, &out.sound, &self.meters);
                        if let Some(rec) = &mut self.recorded {
                            let sound = out.sound;
                            (l.permit)(&mut || rec.push(sound));
                        }
                        continue;
                    }
                    if pos >= n {
                        // Published at the block's end, so a save between blocks holds the
                        // sheet as it is.
                        l.frames.end_block(&self.store, l.permit);
                        break;
                    }
                    let now = self.clock + pos as u64;
                    let until = self
                        .midi_volume
                        .until(now, end, &mut self.renderer, &self.last);
                    let seg_end = n.min((until - self.clock) as usize);
                    self.renderer
                        .render(&mut left[pos..seg_end], &mut right[pos..seg_end]);
                    pos = seg_end;
                }
            }
            Host::Threaded(t) => {
                if t.snapshots.update() {
                    let snap = t.snapshots.output_buffer();
                    if snap.frames_stepped != t.last_frames {
                        t.last_frames = snap.frames_stepped;
                        self.renderer.set_frame(&snap.sound);
                        self.meters.record_sound(&snap.sound);
                    }
                }
                while let Some(ev) = t.shared.events.pop() {
                    match ev {
                        SimEvent::Crumple(e) => {
                            self.renderer.trigger(&e);
                            self.meters.crumple_events.fetch_add(1, Ordering::Relaxed);
                        }
                    }
                }
                // Split at each MIDI volume change of the block.
                let mut pos = 0usize;
                while pos < n {
                    let now = self.clock + pos as u64;
                    let until = self.midi_volume.until(
                        now,
                        self.clock + n as u64,
                        &mut self.renderer,
                        &self.last,
                    );
                    let seg_end = (until - self.clock) as usize;
                    self.renderer
                        .render(&mut left[pos..seg_end], &mut right[pos..seg_end]);
                    pos = seg_end;
                }
            }
        }
        // Belt and braces: the render path guarantees finite, normal output; never let a NaN,
        // an infinity or a subnormal out.
        let mut peak = 0.0f32;
        for s in left[..n].iter_mut().chain(right[..n].iter_mut()) {
            if !(s.is_normal() || *s == 0.0) {
                *s = 0.0;
            }
            peak = peak.max(s.abs());
        }
        self.meters.record_peak(peak);
        let playing = self.phrases.notes_playing();
        for (word, bits) in self.meters.phrase_notes.iter().zip(playing) {
            word.store(bits, Ordering::Relaxed);
        }
        self.clock += n as u64;
        if let Host::Threaded(t) = &self.host {
            // The worker polls this clock; no syscall (unpark) from the audio thread.
            t.shared.audio_clock.store(self.clock, Ordering::Release);
        }
    }

    /// Stops the engine and returns the sheet and the store generation it is based on.
    pub fn into_sim(self) -> Option<(Sim, u64)> {
        match self.host {
            Host::Lockstep(l) => Some(l.frames.into_sim()),
            Host::Threaded(t) => Some(t.worker.stop()?.frames.into_sim()),
        }
    }
}
