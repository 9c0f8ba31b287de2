//! # The simulation worker thread
//!
//! In real-time use the sheet is simulated on a dedicated thread (never nice-plug's shared
//! background-task thread), started in `activate()` and stopped and joined in `deactivate()` and
//! on drop. It follows the audio sample clock: the audio thread publishes how many samples it has
//! rendered; the worker steps every frame whose span has ended (see
//! [`super::frame_clock`]), applying the commands stamped inside that span first, and publishes
//! the frame's continuous state through a triple buffer and its discrete events through a
//! bounded queue. Between frames it parks for a fraction of a frame; the audio thread never
//! waits for it.
//!
//! If the worker falls behind by more than [`MAX_LAG_FRAMES`] (an overloaded machine), it skips
//! frames instead of trying to catch up, still applying every command, and counts the skips.
//!
//! The steady state does not allocate: the command backlog is preallocated and the simulation
//! preallocates its own storage. Exceptions, all rare and off the audio thread: rebuilding the
//! sheet (reset, size change, restore) and publishing the sheet for the saved project (when the
//! sheet comes to rest, every [`PUBLISH_INTERVAL_FRAMES`] frames while it moves, and when the
//! host saves: `crate::state`, "A save holds the sheet as it is now").

use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crossbeam_queue::ArrayQueue;
use sim_core::{FrameOutput, Sim};

use super::frame_clock::FrameClock;
use super::messages::{
    COMMAND_QUEUE_CAPACITY, SimEvent, SimEventKind, SimSnapshot, WorkerMsg, WorkerMsgKind,
};
use super::meters::Meters;
use super::view::{ViewPublisher, ViewShared};
use crate::state::{SheetStore, StoredSheet};

/// Frames of backlog after which the worker skips ahead rather than catching up.
pub const MAX_LAG_FRAMES: u64 = 40;
/// While the sheet moves, publish it for the saved project this often (frames).
pub const PUBLISH_INTERVAL_FRAMES: u64 = 400;
/// How long the worker parks when there is nothing to do.
const IDLE_PARK: Duration = Duration::from_micros(500);

/// What the worker shares with the audio side.
pub struct WorkerShared {
    /// Samples rendered by the audio thread so far.
    pub audio_clock: AtomicU64,
    /// Set to stop the worker.
    pub stop: AtomicBool,
    /// Commands from the audio thread.
    pub commands: ArrayQueue<WorkerMsg>,
    /// Discrete events to the audio thread.
    pub events: ArrayQueue<SimEvent>,
}

impl WorkerShared {
    /// Empty queues and a clock at 0.
    pub fn new(event_capacity: usize) -> Self {
        Self {
            audio_clock: AtomicU64::new(0),
            stop: AtomicBool::new(false),
            commands: ArrayQueue::new(COMMAND_QUEUE_CAPACITY),
            events: ArrayQueue::new(event_capacity),
        }
    }
}

/// Everything the worker thread owns.
pub struct WorkerState {
    /// The sheet.
    pub sim: Sim,
    /// Frame timing.
    pub clock: FrameClock,
    /// Next frame to step.
    pub next_frame: u64,
    /// Store generation the sheet is based on.
    pub store_generation: u64,
    /// The editor's view buffer.
    pub view: ViewPublisher,
    /// The editor's open flag and consumer end.
    pub view_shared: Arc<ViewShared>,
}

/// A running worker.
pub struct WorkerHandle {
    shared: Arc<WorkerShared>,
    thread: Option<JoinHandle<WorkerState>>,
    meters: Arc<Meters>,
}

impl WorkerHandle {
    /// Spawns the worker thread.
    pub fn spawn(
        state: WorkerState,
        shared: Arc<WorkerShared>,
        snapshots: triple_buffer::Input<SimSnapshot>,
        store: Arc<SheetStore>,
        meters: Arc<Meters>,
    ) -> std::io::Result<Self> {
        let thread_shared = shared.clone();
        let thread_meters = meters.clone();
        let thread = std::thread::Builder::new()
            .name("papier-sim".into())
            .spawn(move || run(state, &thread_shared, snapshots, &store, &thread_meters))?;
        meters.workers_started.fetch_add(1, Ordering::Relaxed);
        meters.worker_running.store(true, Ordering::Release);
        Ok(Self {
            shared,
            thread: Some(thread),
            meters,
        })
    }

    /// Stops the worker and returns its state (the sheet survives deactivation).
    pub fn stop(mut self) -> Option<WorkerState> {
        self.stop_inner()
    }

    fn stop_inner(&mut self) -> Option<WorkerState> {
        let thread = self.thread.take()?;
        self.shared.stop.store(true, Ordering::Release);
        thread.thread().unpark();
        let state = thread.join().ok();
        self.meters.workers_joined.fetch_add(1, Ordering::Relaxed);
        self.meters.worker_running.store(false, Ordering::Release);
        state
    }
}

impl Drop for WorkerHandle {
    fn drop(&mut self) {
        let _ = self.stop_inner();
    }
}

/// Steps one frame and hands its output over. Shared by the worker and the lockstep path.
pub fn step_frame(sim: &mut Sim, out: &mut FrameOutput, meters: &Meters) {
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

/// Rebuilds the sheet from the store after a state load. Returns the generation the sheet is
/// now based on (unchanged when the stored data cannot be used, so that it is not overwritten).
pub fn restore_from_store(sim: &mut Sim, store: &SheetStore, based_on: u64) -> u64 {
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
                nice_plug::nice_warn!(
                    "Papier: the saved sheet cannot be restored ({e}); keeping the current sheet"
                );
                based_on
            }
        },
        StoredSheet::Unreadable(_) => based_on,
    }
}

fn run(
    mut st: WorkerState,
    shared: &WorkerShared,
    mut snapshots: triple_buffer::Input<SimSnapshot>,
    store: &SheetStore,
    meters: &Meters,
) -> WorkerState {
    let mut pending: VecDeque<WorkerMsg> = VecDeque::with_capacity(COMMAND_QUEUE_CAPACITY);
    let mut out = FrameOutput::default();
    let mut snapshot = SimSnapshot::default();
    let mut was_awake = false;
    let mut frames_since_publish = 0u64;
    let mut stepped_total = 0u64;
    // The sheet was built on another thread: the solver's dense kernels make their lazy
    // first-use allocations now, not in the first step that needs them.
    sim_core::warm_up_thread();
    store.set_worker_live(true);

    while !shared.stop.load(Ordering::Acquire) {
        while pending.len() < pending.capacity() {
            match shared.commands.pop() {
                Some(m) => pending.push_back(m),
                None => break,
            }
        }
        let clock = shared.audio_clock.load(Ordering::Acquire);

        // Skip ahead when hopelessly behind: keep at most MAX_LAG_FRAMES of backlog.
        let behind_end = st.clock.end(st.next_frame + MAX_LAG_FRAMES);
        if behind_end <= clock {
            let target = (clock as f64 / st.clock.samples_per_frame()).floor() as u64;
            let skip = target.saturating_sub(st.next_frame + 1);
            st.next_frame += skip;
            meters.frames_skipped.fetch_add(skip, Ordering::Relaxed);
        }

        let mut stepped = 0u32;
        while st.clock.end(st.next_frame) <= clock && !shared.stop.load(Ordering::Acquire) {
            let end = st.clock.end(st.next_frame);
            while pending.front().is_some_and(|m| m.at_sample < end) {
                let Some(m) = pending.pop_front() else { break };
                match m.kind {
                    WorkerMsgKind::Command(cmd) => st.sim.apply(cmd),
                    WorkerMsgKind::RestoreSheet => {
                        st.store_generation =
                            restore_from_store(&mut st.sim, store, st.store_generation);
                        was_awake = false;
                    }
                }
            }
            step_frame(&mut st.sim, &mut out, meters);
            stepped_total += 1;
            st.view.after_frame(&st.view_shared, &st.sim, &out.stats);

            for e in out.sound.crumple() {
                let ev = SimEvent {
                    at_sample: end,
                    kind: SimEventKind::Crumple(*e),
                };
                if shared.events.push(ev).is_err() {
                    meters.events_dropped.fetch_add(1, Ordering::Relaxed);
                }
            }
            snapshot.frames_stepped = stepped_total;
            snapshot.at_sample = end;
            snapshot.sound = out.sound;
            snapshot.sound.take_crumple_count();
            snapshot.stats = out.stats;
            snapshots.write(snapshot);

            // Publish the sheet for the saved project when it comes to rest, and periodically
            // while it moves.
            let awake = !out.stats.asleep;
            frames_since_publish += 1;
            if (was_awake && !awake) || (awake && frames_since_publish >= PUBLISH_INTERVAL_FRAMES) {
                store.try_publish(st.sim.save(), st.store_generation);
                frames_since_publish = 0;
            }
            was_awake = awake;

            st.next_frame += 1;
            stepped += 1;
        }
        // Every frame the audio clock reached is stepped: a host's save gets this sheet.
        if store.serve_save_request(st.store_generation, || st.sim.save()) {
            frames_since_publish = 0;
        }
        if stepped == 0 {
            std::thread::park_timeout(IDLE_PARK);
        }
    }
    store.set_worker_live(false);

    // Apply what is left, so a grab or reset sent just before stopping is not lost.
    while let Some(m) = shared.commands.pop() {
        pending.push_back(m);
    }
    for m in pending {
        match m.kind {
            WorkerMsgKind::Command(cmd) => st.sim.apply(cmd),
            WorkerMsgKind::RestoreSheet => {
                st.store_generation = restore_from_store(&mut st.sim, store, st.store_generation);
            }
        }
    }
    st
}
