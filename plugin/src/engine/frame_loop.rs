//! # The frame loop: commands in, one simulation frame stepped, the sheet published
//!
//! The one place where the sheet is stepped, whoever steps it: the worker thread in real time
//! ([`super::worker`]) and the engine itself in lockstep (offline) mode ([`super::Engine`]).
//!
//! ```text
//! queue(msg @ sample)            messages stamped on the audio timeline, in order
//! step(clock):                   frame k = next_frame, span [start(k), end(k))
//!   apply every message with at_sample < end(k)   (commands; a loaded project's sheet)
//!   Sim::step → FrameOutput      (timed into the meters)
//!   editor view copy             (only while the window is open)
//!   publish bookkeeping          (moved? came to rest? due for the saved project?)
//! ```
//!
//! Decisions:
//! - Frame `k` is stepped once the audio clock reaches `end(k)`, after every message stamped
//!   before it ([`FrameClock`]): a render does not depend on how the host splits blocks.
//! - Steps that allocate (a rebuild by reset or size change, a restore, a frame that changes
//!   the mesh, announced by `Sim::refinement_pending`) run inside the caller's
//!   [`AllocPermit`]: the lockstep path runs on the audio thread under the plugin's allocation
//!   checker, which must let exactly those through; the worker passes [`permit_always`].
//! - The sheet is published for the saved project by one of two rules ([`PublishRule`]): the
//!   worker publishes when the sheet comes to rest and every [`PUBLISH_INTERVAL_FRAMES`] while
//!   it moves (a save request gets the sheet as it is between frames), the lockstep path at the
//!   end of each block in which it moved (no worker answers a save request offline).
//! - How a frame's output reaches the render path differs by thread (queue + triple buffer, or
//!   a direct call), so [`FrameLoop::step`] returns the output and the caller delivers it.

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::Instant;

use sim_core::control::Command;
use sim_core::room::RoomConfig;
use sim_core::{FrameOutput, Sim};

use super::frame_clock::FrameClock;
use super::messages::{COMMAND_QUEUE_CAPACITY, WorkerMsg, WorkerMsgKind};
use super::meters::Meters;
use super::sheet_store::{SheetStore, StoredSheet};
use super::view::{ViewPublisher, ViewShared};

/// While the sheet moves, the worker publishes it for the saved project this often (frames).
pub const PUBLISH_INTERVAL_FRAMES: u64 = 400;

/// Runs a closure that may allocate. The plugin face passes its allocation checker's permit
/// (the audio thread under `assert_process_allocs`); code with no checker passes
/// [`permit_always`].
pub type AllocPermit = fn(&mut dyn FnMut());

/// The permit for code no allocation checker watches (the worker thread, offline tools).
pub fn permit_always(f: &mut dyn FnMut()) {
    f();
}

/// Runs `f` under `permit`, returning its value.
fn permitted<T>(permit: AllocPermit, f: impl FnOnce() -> T) -> T {
    let mut f = Some(f);
    let mut out = None;
    permit(&mut || {
        if let Some(f) = f.take() {
            out = Some(f());
        }
    });
    match out {
        Some(v) => v,
        // A permit must call the closure; should one not, run it here.
        None => f.map(|f| f()).expect("the closure ran or is still there"),
    }
}

/// When the sheet is published for the saved project.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PublishRule {
    /// When it comes to rest and every [`PUBLISH_INTERVAL_FRAMES`] frames while it moves; a
    /// save request is served between frames (the worker thread).
    RestAndInterval,
    /// At the end of every block in which it moved ([`FrameLoop::end_block`]; lockstep).
    EveryBlock,
}

/// The sheet and everything stepping it needs (see the module doc).
pub struct FrameLoop {
    sim: Box<Sim>,
    out: Box<FrameOutput>,
    pending: VecDeque<WorkerMsg>,
    next_frame: u64,
    store_generation: u64,
    view: ViewPublisher,
    view_shared: Arc<ViewShared>,
    rule: PublishRule,
    was_awake: bool,
    /// A frame moved the sheet (or let it come to rest) since it was last published.
    unpublished: bool,
    frames_since_publish: u64,
}

impl FrameLoop {
    /// A loop around `sim`, based on sheet store generation `store_generation`; installs a
    /// fresh editor view buffer. Allocates (call from `activate()` or offline code).
    pub fn new(
        sim: Sim,
        store_generation: u64,
        view_shared: &Arc<ViewShared>,
        rule: PublishRule,
    ) -> Self {
        Self {
            sim: Box::new(sim),
            out: Box::default(),
            pending: VecDeque::with_capacity(COMMAND_QUEUE_CAPACITY),
            next_frame: 0,
            store_generation,
            view: ViewPublisher::install(view_shared),
            view_shared: view_shared.clone(),
            rule,
            was_awake: false,
            unpublished: false,
            frames_since_publish: 0,
        }
    }

    /// The sheet.
    pub fn sim(&self) -> &Sim {
        &self.sim
    }

    /// The store generation the sheet is based on.
    pub fn store_generation(&self) -> u64 {
        self.store_generation
    }

    /// The next frame to step.
    pub fn next_frame(&self) -> u64 {
        self.next_frame
    }

    /// Skips `frames` frames without stepping them (an overloaded worker catching up); their
    /// messages still apply with the next frame stepped.
    pub fn skip(&mut self, frames: u64) {
        self.next_frame += frames;
    }

    /// Queues a message; false (and nothing queued) when the backlog is full.
    pub fn queue(&mut self, msg: WorkerMsg) -> bool {
        if self.pending.len() < self.pending.capacity() {
            self.pending.push_back(msg);
            true
        } else {
            false
        }
    }

    /// Room left in the backlog.
    pub fn queue_room(&self) -> usize {
        self.pending.capacity() - self.pending.len()
    }

    /// Steps frame [`Self::next_frame`] (its span's end on `clock` must have been reached):
    /// applies the messages stamped before that end, steps the sheet, copies it for the editor
    /// and publishes it if [`PublishRule::RestAndInterval`] says so. Returns the frame's output.
    pub fn step(
        &mut self,
        clock: &FrameClock,
        store: &SheetStore,
        meters: &Meters,
        permit: AllocPermit,
    ) -> &FrameOutput {
        let end = clock.end(self.next_frame);
        while self.pending.front().is_some_and(|m| m.at_sample < end) {
            let Some(m) = self.pending.pop_front() else {
                break;
            };
            self.apply(m.kind, store, permit);
        }
        let (sim, out) = (&mut self.sim, &mut self.out);
        if sim.refinement_pending() {
            // This step changes the mesh (announced by the sim): permitted like a reset.
            permitted(permit, || step_timed(sim, out, meters));
        } else {
            step_timed(sim, out, meters);
        }
        self.view
            .after_frame(&self.view_shared, &self.sim, &self.out.stats);
        let awake = !self.out.stats.asleep;
        let came_to_rest = self.was_awake && !awake;
        self.unpublished |= awake || self.was_awake;
        self.was_awake = awake;
        self.frames_since_publish += 1;
        if self.rule == PublishRule::RestAndInterval
            && (came_to_rest || (awake && self.frames_since_publish >= PUBLISH_INTERVAL_FRAMES))
        {
            store.try_publish(self.sim.save(), self.store_generation);
            self.frames_since_publish = 0;
        }
        self.next_frame += 1;
        &self.out
    }

    /// End of an audio block ([`PublishRule::EveryBlock`]): publishes the sheet if it moved
    /// since it was last published (under `permit`: a save allocates).
    pub fn end_block(&mut self, store: &SheetStore, permit: AllocPermit) {
        if self.rule == PublishRule::EveryBlock && self.unpublished {
            let (sim, generation) = (&self.sim, self.store_generation);
            let published = permitted(permit, || store.try_publish(sim.save(), generation));
            self.unpublished = !published;
        }
    }

    /// Between frames ([`PublishRule::RestAndInterval`]): serves a host's save request with the
    /// sheet as it is now. Returns whether one was served.
    pub fn serve_save_request(&mut self, store: &SheetStore) -> bool {
        let sim = &self.sim;
        let served = store.serve_save_request(self.store_generation, || sim.save());
        if served {
            self.frames_since_publish = 0;
        }
        served
    }

    /// Applies every queued message without stepping (a worker that stops: a grab or reset
    /// sent just before is not lost).
    pub fn apply_all(&mut self, store: &SheetStore) {
        while let Some(m) = self.pending.pop_front() {
            self.apply(m.kind, store, permit_always);
        }
    }

    /// Stops the loop: the sheet and the store generation it is based on.
    pub fn into_sim(self) -> (Sim, u64) {
        (*self.sim, self.store_generation)
    }

    fn apply(&mut self, kind: WorkerMsgKind, store: &SheetStore, permit: AllocPermit) {
        match kind {
            WorkerMsgKind::Command(cmd) => {
                let sim = &mut self.sim;
                if matches!(cmd, Command::Reset | Command::Size(_)) {
                    // A new sheet is built: permitted.
                    permitted(permit, || sim.apply(cmd));
                } else {
                    sim.apply(cmd);
                }
            }
            WorkerMsgKind::RestoreSheet { room } => {
                let (sim, based_on) = (&mut self.sim, self.store_generation);
                self.store_generation =
                    permitted(permit, || restore_sheet(sim, store, based_on, room));
                self.was_awake = false;
            }
        }
    }
}

/// Steps `sim` once into `out`, recording the step time and the frame's figures in `meters`.
fn step_timed(sim: &mut Sim, out: &mut FrameOutput, meters: &Meters) {
    let t0 = Instant::now();
    sim.step(out);
    let ns = t0.elapsed().as_nanos().min(u128::from(u64::MAX)) as u64;
    meters.record_step(
        ns,
        out.stats.asleep,
        out.stats.num_singular,
        out.stats.c_mean_pct,
    );
}

/// Rebuilds the sheet from the store after a project load, in the loaded project's `room` (a
/// sheet is restored in the room of the sim's configuration, and continues as saved only in
/// the room it was saved in). Returns the generation the sheet is now based on (unchanged when
/// the stored data cannot be used, so that it is not overwritten). Allocates.
pub fn restore_sheet(sim: &mut Sim, store: &SheetStore, based_on: u64, room: RoomConfig) -> u64 {
    if sim.config().room != room {
        sim.apply(Command::Room(room));
    }
    let generation = store.generation();
    match store.get() {
        StoredSheet::Empty => {
            *sim = Sim::new(*sim.config());
            generation
        }
        StoredSheet::Valid(saved) => match Sim::restore(*sim.config(), &saved) {
            Ok(restored) => {
                *sim = restored;
                generation
            }
            Err(e) => {
                tracing::warn!(
                    "Papier: the saved sheet cannot be restored ({e}); keeping the current sheet"
                );
                based_on
            }
        },
        StoredSheet::Unreadable(_) => based_on,
    }
}
