//! # The simulation worker thread
//!
//! In real-time use the sheet is simulated on a dedicated thread (never nice-plug's shared
//! background-task thread), started in `activate()` and stopped and joined in `deactivate()` and
//! on drop. It follows the audio sample clock: the audio thread publishes how many samples it has
//! rendered; the worker steps every frame whose span has ended with the shared frame loop
//! ([`super::frame_loop`]), and hands each frame's continuous state over through a triple buffer
//! and its discrete events through a bounded queue. Between frames it serves a host's save
//! request and parks for a fraction of a frame; the audio thread never waits for it.
//!
//! If the worker falls behind by more than [`MAX_LAG_FRAMES`] (an overloaded machine), it skips
//! frames instead of trying to catch up, still applying every command, and counts the skips.
//!
//! The steady state does not allocate: the command backlog is preallocated and the simulation
//! preallocates its own storage. Exceptions, all rare and off the audio thread: rebuilding the
//! sheet (reset, size change, restore), a frame that changes the mesh, and publishing the sheet
//! for the saved project ([`super::frame_loop::PublishRule::RestAndInterval`]).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use crossbeam_queue::ArrayQueue;

use super::frame_clock::FrameClock;
use super::frame_loop::{FrameLoop, permit_always};
use super::messages::{COMMAND_QUEUE_CAPACITY, SimEvent, SimSnapshot, WorkerMsg};
use super::meters::Meters;
use super::sheet_store::SheetStore;

/// Frames of backlog after which the worker skips ahead rather than catching up.
pub const MAX_LAG_FRAMES: u64 = 40;
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
    /// The sheet and its frame loop.
    pub frames: FrameLoop,
    /// Frame timing.
    pub clock: FrameClock,
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

fn run(
    mut st: WorkerState,
    shared: &WorkerShared,
    mut snapshots: triple_buffer::Input<SimSnapshot>,
    store: &SheetStore,
    meters: &Meters,
) -> WorkerState {
    let mut snapshot = SimSnapshot::default();
    let mut stepped_total = 0u64;
    // The sheet was built on another thread: the solver's dense kernels make their lazy
    // first-use allocations now, not in the first step that needs them.
    sim_core::warm_up_thread();
    store.set_worker_live(true);

    while !shared.stop.load(Ordering::Acquire) {
        while st.frames.queue_room() > 0 {
            match shared.commands.pop() {
                Some(m) => {
                    st.frames.queue(m);
                }
                None => break,
            }
        }
        let clock = shared.audio_clock.load(Ordering::Acquire);

        // Skip ahead when hopelessly behind: keep at most MAX_LAG_FRAMES of backlog.
        let next = st.frames.next_frame();
        if st.clock.end(next + MAX_LAG_FRAMES) <= clock {
            let target = (clock as f64 / st.clock.samples_per_frame()).floor() as u64;
            let skip = target.saturating_sub(next + 1);
            st.frames.skip(skip);
            meters.frames_skipped.fetch_add(skip, Ordering::Relaxed);
        }

        let mut stepped = 0u32;
        while st.clock.end(st.frames.next_frame()) <= clock && !shared.stop.load(Ordering::Acquire)
        {
            let out = st.frames.step(&st.clock, store, meters, permit_always);
            stepped_total += 1;
            for e in out.sound.crumple() {
                if shared.events.push(SimEvent::Crumple(*e)).is_err() {
                    meters.events_dropped.fetch_add(1, Ordering::Relaxed);
                }
            }
            snapshot.frames_stepped = stepped_total;
            snapshot.sound = out.sound;
            snapshot.sound.take_crumple_count();
            snapshots.write(snapshot);
            stepped += 1;
        }
        // Every frame the audio clock reached is stepped: a host's save gets this sheet.
        st.frames.serve_save_request(store);
        if stepped == 0 {
            std::thread::park_timeout(IDLE_PARK);
        }
    }
    store.set_worker_live(false);

    // Apply what is left, so a grab or reset sent just before stopping is not lost.
    while let Some(m) = shared.commands.pop() {
        if !st.frames.queue(m) {
            st.frames.apply_all(store);
            st.frames.queue(m);
        }
    }
    st.frames.apply_all(store);
    st
}
