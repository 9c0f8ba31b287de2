//! # Messages between the audio thread and the simulation worker
//!
//! Everything crossing threads is `Copy`, heap-free and fixed-size:
//! - audio → worker: [`WorkerMsg`] through a bounded lock-free queue (`crossbeam_queue::ArrayQueue`);
//! - worker → audio, continuous state: [`SimSnapshot`] through a `triple_buffer` (latest value
//!   wins; intermediate frames may be skipped, which is fine for continuous state);
//! - worker → audio, discrete events: [`SimEvent`] through a second bounded queue (a triple buffer
//!   would drop them).
//!
//! Which is which follows from what a lost value costs. A crumple event is a sound onset: a
//! skipped snapshot must not swallow it, so it is queued. Contact and tearing are *states* the
//! sound reads every frame — each friction source with its amplitude and slip speed, the tear's
//! speed and tip ([`SoundFrame`]) — and every snapshot carries the whole current state, so
//! a skipped snapshot loses nothing; their onsets and ends are where that state changes. So
//! contact and tear *events* are carried as state in the snapshot, not as
//! queue entries (said in the README); a future impact or tear-start sound that must not be
//! missed gets its own [`SimEvent`] variant.
//!
//! A full queue never blocks: the sender counts the loss.

use sim_core::Command;
use sim_core::room::RoomConfig;
use sim_core::sound_input::{CrumpleEvent, SoundFrame};

/// Capacity of the audio → worker command queue.
pub const COMMAND_QUEUE_CAPACITY: usize = 4096;
/// Capacity of the worker → audio event queue.
pub const EVENT_QUEUE_CAPACITY: usize = 1024;

/// What the audio thread asks of the worker.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WorkerMsgKind {
    /// A simulation command.
    Command(Command),
    /// A project state was loaded: rebuild the sheet from the sheet store, in the loaded
    /// project's room.
    RestoreSheet {
        /// The loaded project's room.
        room: RoomConfig,
    },
}

/// A timestamped message for the worker.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorkerMsg {
    /// Audio sample position the message belongs to.
    pub at_sample: u64,
    /// The message.
    pub kind: WorkerMsgKind,
}

/// The continuous state of one stepped frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SimSnapshot {
    /// Frames stepped so far (0 = none yet).
    pub frames_stepped: u64,
    /// Sound input (its crumple events travel as [`SimEvent`]s instead).
    pub sound: SoundFrame,
}

/// A discrete event of a frame (it sounds with the frame's snapshot).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SimEvent {
    /// A crumpling sound to start.
    Crumple(CrumpleEvent),
}
