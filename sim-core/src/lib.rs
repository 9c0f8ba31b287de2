//! # sim-core: a sheet of paper, simulated
//!
//! Papier's simulation crate. It knows nothing of audio, threads or the plugin: the plugin's
//! worker thread, the offline renderer and the tests all drive it the same way, one frame at a
//! time, in lockstep with whatever clock they follow.
//!
//! The model follows the hybrid crumpling method of the seeds (thesis ch. 2,
//! `../shared/seeds/000_cb4d91e46ec5927f.txt` §2.2–2.5; TOG 2015,
//! `../shared/seeds/001_44bc28f7c5e9f81f.txt` §3–6): a coarse physical mesh S_P is relaxed by a
//! physics step, then a developable-geometry layer S_G keeps the surface piecewise developable.
//!
//! Per frame, in order:
//! 1. commands (gestures, grabs, room changes) are applied ([`control`]);
//! 2. the gesture rig turns gesture values into handle targets ([`gesture_rig`], [`handles`]);
//! 3. the physics step moves S_P with the handles as hard constraints ([`physics`]), against
//!    the room's obstacles with friction ([`collision`]);
//! 4. the geometry layer analyses and corrects the sheet ([`geometry`]: compression analysis,
//!    imaginary rulings, singular vertices and fibre damage, region partition, rulings, cone
//!    fitting, isometry) and publishes [`geometry::GeometryFrame`]; what is still strained
//!    beyond 8 % is projected back ([`physics::strain_limit`]);
//! 5. contacts, metrics ([`metrics`]) and per-frame outputs for sound
//!    ([`sound_input::SoundFrame`]) are written.
//!
//! Inputs are described by [`control::Command`]; scripted inputs (automation lanes and grabs)
//! by [`script::Script`], played by [`script_runner::ScriptRunner`]; the seed scenarios are in
//! [`scenario`] (played and summarized by [`scenario_run`]). [`stress`] drives the sim with
//! hostile random commands (tests, and the long run `cargo run --release -p papier-lab --
//! stress`); `benches/step.rs` and
//! `cargo xtask bench-report` measure it.
//!
//! Entry point: [`sim::Sim`] — `Sim::new(SimConfig)`, `apply(Command)`, `step(&mut FrameOutput)`,
//! `contacts()`, `metrics()`, `write_mesh`, `save` / `restore`.

#![warn(missing_docs)]

pub mod collision;
pub mod control;
pub mod geometry;
pub mod gesture_rig;
pub mod handles;
pub mod material;
pub mod math;
pub mod mesh_snapshot;
pub mod metrics;
pub mod physics;
pub mod room;
pub mod scenario;
pub mod scenario_run;
pub mod script;
pub mod script_runner;
pub mod self_proximity;
pub mod sheet;
pub mod sim;
pub mod sound_analysis;
pub mod sound_input;
pub mod stress;
pub mod tearing;
pub mod triangle_distance;

pub use collision::VertexContact;
pub use control::{Command, GestureParam, GrabSlot, Material, SheetSize};
pub use geometry::{GeometryConfig, GeometryFrame};
pub use mesh_snapshot::MeshSnapshot;
pub use physics::SolverConfig;
pub use physics::sparse::warm_up_thread;
pub use room::RoomConfig;
pub use sheet::MeshConfig;
pub use sim::{FrameOutput, FrameStats, RestoreError, SavedSheet, Sim, SimConfig};
pub use sound_input::SoundFrame;
