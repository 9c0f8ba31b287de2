//! # The audio render path
//!
//! Turns per-frame sound input from the simulation ([`sim_core::SoundFrame`] and
//! [`sim_core::sound_input::CrumpleEvent`]s) into stereo audio: database units for crumpling,
//! inverse-FFT friction noise, procedural tearing noise, each spatialized as a dipole with image
//! sources (thesis ch. 4; SCA 2016; digest-sound). Free of nice-plug types so the plugin, the
//! offline renderer, the tests and the benches share it.
//!
//! **Current state:** the render path outputs silence; the synthesis is built in the sound issue.

use std::sync::Arc;

use sim_core::RoomConfig;
use sim_core::sound_input::{CrumpleEvent, SoundFrame};
use sounddb::SoundDb;

/// Mix levels, in dB.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MixLevels {
    /// Crumple units level, dB.
    pub crumple_db: f32,
    /// Friction noise level, dB.
    pub friction_db: f32,
    /// Tearing noise level, dB.
    pub tear_db: f32,
    /// Output gain, dB (includes MIDI volume).
    pub output_db: f32,
}

impl Default for MixLevels {
    fn default() -> Self {
        Self {
            crumple_db: 0.0,
            friction_db: 0.0,
            tear_db: 0.0,
            output_db: 0.0,
        }
    }
}

/// Listener and reflectors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scene {
    /// Table and wall.
    pub room: RoomConfig,
    /// Listener azimuth, degrees (0 = in front of the front edge, +90 = right).
    pub listener_az_deg: f32,
    /// Listener distance from the sheet's home centre, metres.
    pub listener_dist_m: f32,
}

impl Default for Scene {
    fn default() -> Self {
        Self {
            room: RoomConfig::default(),
            listener_az_deg: 0.0,
            listener_dist_m: 1.0,
        }
    }
}

/// The render path.
pub struct Renderer {
    db: Arc<SoundDb>,
}

impl Renderer {
    /// Builds a renderer (allocates everything it will ever need).
    pub fn new(_sample_rate_hz: f64, db: Arc<SoundDb>, _seed: u64) -> Self {
        Self { db }
    }

    /// Clears voices, noise state and smoothers (no allocation).
    pub fn reset(&mut self) {}

    /// New mix levels (smoothed internally).
    pub fn set_mix(&mut self, _mix: MixLevels) {}

    /// New listener / room geometry.
    pub fn set_scene(&mut self, _scene: Scene) {}

    /// Continuous input of a new frame (friction sources, tear).
    pub fn set_frame(&mut self, _frame: &SoundFrame) {}

    /// Starts a crumple unit at the beginning of the next [`render`](Self::render) call.
    pub fn trigger(&mut self, _event: &CrumpleEvent) {}

    /// Renders `left.len()` samples (any length) into the two channels (overwrites them).
    pub fn render(&mut self, left: &mut [f32], right: &mut [f32]) {
        left.fill(0.0);
        right.fill(0.0);
    }

    /// Replaces the database; returns the old one so the caller can drop it off the audio thread.
    pub fn swap_db(&mut self, db: Arc<SoundDb>) -> Arc<SoundDb> {
        std::mem::replace(&mut self.db, db)
    }
}
