//! # The editor's view of the sheet
//!
//! While the editor window is open, whoever steps the sheet (the worker thread, or the engine in
//! offline lockstep) copies the mesh, the geometry layer's partition (region kind per triangle)
//! and the frame statistics into a triple buffer at display
//! rate ([`VIEW_EVERY_FRAMES`]); the editor reads the latest copy when it repaints. The copy is
//! skipped entirely while the window is closed. Nothing here touches the audio thread's data:
//! the editor has its own triple buffer, and its consumer end is only ever locked by the GUI
//! thread and by `activate()` (which installs a fresh one when the engine restarts).
//!
//! The three buffers are allocated with room for [`VIEW_MAX_VERTICES`] vertices and
//! [`VIEW_MAX_TRIANGLES`] triangles, so a copy does not allocate unless a mesh outgrows them.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use crossbeam_queue::ArrayQueue;

use sim_core::geometry::TriKind;
use sim_core::mesh_snapshot::LIP_CAPACITY_POINTS;
use sim_core::room::RoomConfig;
use sim_core::sim::FrameStats;
use sim_core::{MeshSnapshot, Sim};

use crate::gesture_map::MidiInput;

/// Capacity of the editor → audio message queue.
pub const GUI_MIDI_CAPACITY: usize = 256;

/// Copy the mesh every this many simulation frames (200 Hz / 3 ≈ 67 Hz).
pub const VIEW_EVERY_FRAMES: u32 = 3;
/// Vertex capacity of the view buffers.
pub const VIEW_MAX_VERTICES: usize = 4096;
/// Triangle capacity of the view buffers.
pub const VIEW_MAX_TRIANGLES: usize = 8192;

/// One copy of the sheet for the editor.
#[derive(Clone, Debug, Default)]
pub struct ViewFrame {
    /// False until a real frame was written.
    pub valid: bool,
    /// The mesh (3D positions, pattern, tags, triangles).
    pub mesh: MeshSnapshot,
    /// Statistics of the frame.
    pub stats: FrameStats,
    /// The room the sheet is in.
    pub room: RoomConfig,
    /// Simulated time, seconds.
    pub time_s: f64,
    /// The geometry layer's partition, one kind per triangle of `mesh` (flat, curved, around a
    /// singular vertex); empty when the layer is off or its frame does not match the mesh.
    pub tri_kind: Vec<TriKind>,
}

impl ViewFrame {
    fn with_room(vertices: usize, triangles: usize) -> Self {
        // Filled (not just reserved) so that the triple buffer's clones keep the capacity.
        let mut mesh = MeshSnapshot::with_capacity(vertices, triangles);
        mesh.positions_m.resize(vertices, [0.0; 3]);
        mesh.pattern_m.resize(vertices, [0.0; 2]);
        mesh.tags.resize(vertices, Default::default());
        mesh.triangles.resize(triangles, [0; 3]);
        mesh.lip_points_m.resize(LIP_CAPACITY_POINTS, [0.0; 3]);
        mesh.lips
            .resize(LIP_CAPACITY_POINTS / 2, Default::default());
        Self {
            valid: false,
            mesh,
            tri_kind: vec![TriKind::Flat; triangles],
            ..Self::default()
        }
    }
}

/// State shared by the editor and the engine.
pub struct ViewShared {
    /// Set by the editor while its window is open.
    pub open: AtomicBool,
    /// Frames copied for the view (for tests and the meter).
    pub frames_written: AtomicU64,
    /// The consumer end of the current view buffer.
    pub output: Mutex<Option<triple_buffer::Output<ViewFrame>>>,
    /// Messages from the editor's buttons (grab, release, reset), handled by the audio thread at
    /// the start of its next block exactly like MIDI notes — the same command path.
    pub gui_midi: ArrayQueue<MidiInput>,
}

impl Default for ViewShared {
    fn default() -> Self {
        Self {
            open: AtomicBool::new(false),
            frames_written: AtomicU64::new(0),
            output: Mutex::new(None),
            gui_midi: ArrayQueue::new(GUI_MIDI_CAPACITY),
        }
    }
}

/// The producer end, owned by whoever steps the sheet.
pub struct ViewPublisher {
    input: triple_buffer::Input<ViewFrame>,
    countdown: u32,
}

impl ViewPublisher {
    /// Creates a fresh view buffer and installs its consumer end (allocates; call from
    /// `activate()` or offline code).
    pub fn install(shared: &ViewShared) -> Self {
        let (input, output) = triple_buffer::triple_buffer(&ViewFrame::with_room(
            VIEW_MAX_VERTICES,
            VIEW_MAX_TRIANGLES,
        ));
        if let Ok(mut slot) = shared.output.lock() {
            *slot = Some(output);
        }
        Self {
            input,
            countdown: 0,
        }
    }

    /// After a frame: copies the sheet if the editor is open and a copy is due.
    pub fn after_frame(&mut self, shared: &ViewShared, sim: &Sim, stats: &FrameStats) {
        if !shared.open.load(Ordering::Relaxed) {
            self.countdown = 0;
            return;
        }
        if self.countdown > 0 {
            self.countdown -= 1;
            return;
        }
        self.countdown = VIEW_EVERY_FRAMES - 1;
        let frame = self.input.input_buffer_mut();
        sim.write_mesh(&mut frame.mesh);
        frame.stats = *stats;
        frame.room = sim.config().room;
        frame.time_s = sim.time_s();
        // The partition, only when it describes this very mesh (a sleeping or disabled layer
        // leaves the view to derive the kinds itself). Within the prefilled capacity: no
        // allocation.
        frame.tri_kind.clear();
        let kinds = &sim.geometry().tri_kind;
        if sim.config().geometry.enabled && kinds.len() == frame.mesh.triangles.len() {
            frame.tri_kind.extend_from_slice(kinds);
        }
        frame.valid = true;
        self.input.publish();
        shared.frames_written.fetch_add(1, Ordering::Relaxed);
    }
}
