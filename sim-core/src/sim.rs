//! # The simulation facade
//!
//! [`Sim`] is what the plugin's worker thread, the offline renderer, the tests and the benches
//! drive: apply [`Command`]s, then [`Sim::step`] one frame, read the [`FrameOutput`] (sound
//! input and statistics) and, when wanted, copy the mesh out ([`Sim::write_mesh`]).
//!
//! Frames have a fixed duration `1 / frame_rate_hz` of simulated time; the caller decides when to
//! step (the plugin follows the audio sample clock, the offline renderer steps in lockstep with
//! the audio). Given the same configuration, seed and command sequence, the output is
//! bit-identical.
//!
//! **Current state of this module:** the sheet is a flat triangulated pattern whose held points
//! move kinematically towards the gesture targets; points that are not held do not move. The
//! physics step (StVK membrane, hinge bending, implicit integration, collisions) replaces this
//! kinematic stage in the sim-core part 1 work.

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::control::{Command, GestureParam, GrabSlot, Material, SheetSize};
use crate::mesh_snapshot::{MeshSnapshot, VertexTag};
use crate::room::RoomConfig;
use crate::sound_input::SoundFrame;

/// Default number of simulation frames per second of simulated time.
pub const DEFAULT_FRAME_RATE_HZ: f64 = 200.0;

/// Version of [`SavedSheet`]; bump it (and migrate) whenever its meaning changes.
pub const SAVED_SHEET_VERSION: u32 = 1;

/// Everything that defines a sheet before any command.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimConfig {
    /// Sheet size.
    pub size: SheetSize,
    /// Paper grade.
    pub material: Material,
    /// Random seed (singular-point placement, crumple jitter).
    pub seed: u64,
    /// Table and wall.
    pub room: RoomConfig,
    /// Simulation frames per second.
    pub frame_rate_hz: f64,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            size: SheetSize::A4,
            material: Material::Printer,
            seed: 1,
            room: RoomConfig::default(),
            frame_rate_hz: DEFAULT_FRAME_RATE_HZ,
        }
    }
}

/// Per-frame statistics (editor meters, renderer report).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// True if the sheet was asleep and the frame did no work.
    pub asleep: bool,
    /// Vertices of the simulation mesh.
    pub num_vertices: u32,
    /// Triangles of the simulation mesh.
    pub num_triangles: u32,
    /// Persistent interior singular vertices.
    pub num_singular: u32,
    /// Mean edge compression against the pattern, %.
    pub c_mean_pct: f32,
    /// Kinetic energy, joules.
    pub kinetic_energy_j: f32,
}

/// What one frame produces.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameOutput {
    /// Sound input of the frame.
    pub sound: SoundFrame,
    /// Statistics of the frame.
    pub stats: FrameStats,
}

/// A sheet as saved in a project: enough to reopen it identically.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SavedSheet {
    /// Format version ([`SAVED_SHEET_VERSION`]).
    pub version: u32,
    /// Sheet size.
    pub size: SheetSize,
    /// Paper grade.
    pub material: Material,
    /// Seed.
    pub seed: u64,
    /// Frame counter.
    pub frame: u64,
    /// 3D positions, metres.
    pub positions_m: Vec<[f64; 3]>,
}

/// Why a saved sheet could not be restored.
#[derive(Debug, Error, PartialEq)]
pub enum RestoreError {
    /// Written by a newer or unknown format version.
    #[error("saved sheet has version {0}, this build reads version {SAVED_SHEET_VERSION}")]
    Version(u32),
    /// Vertex count does not match the sheet's mesh.
    #[error("saved sheet has {found} vertices, a {size:?} sheet has {expected}")]
    VertexCount {
        /// Sheet size.
        size: SheetSize,
        /// Expected count.
        expected: usize,
        /// Count in the saved data.
        found: usize,
    },
    /// A position is NaN, infinite or absurdly far away.
    #[error("saved sheet has a non-finite or out-of-room position at vertex {0}")]
    BadPosition(usize),
}

/// Target grid spacing of the kinematic sheet's pattern, metres.
const GRID_SPACING_M: f64 = 0.025;

/// The simulated sheet.
#[derive(Clone, Debug)]
pub struct Sim {
    cfg: SimConfig,
    frame: u64,
    nx: usize,
    ny: usize,
    pattern: Vec<[f64; 2]>,
    rest: Vec<[f64; 3]>,
    pos: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    held: [Option<f32>; 5],
    gesture: [f32; GestureParam::COUNT],
    asleep: bool,
}

impl Sim {
    /// A new flat sheet resting at its home position.
    pub fn new(cfg: SimConfig) -> Self {
        let mut cfg = cfg;
        cfg.room = cfg.room.sanitized();
        if !(cfg.frame_rate_hz.is_finite() && cfg.frame_rate_hz >= 1.0) {
            cfg.frame_rate_hz = DEFAULT_FRAME_RATE_HZ;
        }
        let (w, l) = cfg.size.dims_m();
        let nx = ((w / GRID_SPACING_M).round() as usize).max(2);
        let ny = ((l / GRID_SPACING_M).round() as usize).max(2);
        let mut pattern = Vec::with_capacity((nx + 1) * (ny + 1));
        for j in 0..=ny {
            for i in 0..=nx {
                pattern.push([
                    (i as f64 / nx as f64 - 0.5) * w,
                    (j as f64 / ny as f64 - 0.5) * l,
                ]);
            }
        }
        let mut triangles = Vec::with_capacity(2 * nx * ny);
        let idx = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
        for j in 0..ny {
            for i in 0..nx {
                triangles.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
                triangles.push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
            }
        }
        let h = cfg.room.home_height_m();
        let rest: Vec<[f64; 3]> = pattern.iter().map(|p| [p[0], p[1], h]).collect();
        let mut gesture = [0.0; GestureParam::COUNT];
        for g in GestureParam::ALL {
            gesture[g.index()] = g.default_value();
        }
        Self {
            cfg,
            frame: 0,
            nx,
            ny,
            pattern,
            pos: rest.clone(),
            rest,
            triangles,
            held: [None; 5],
            gesture,
            asleep: true,
        }
    }

    /// The configuration (after sanitizing).
    pub fn config(&self) -> &SimConfig {
        &self.cfg
    }

    /// Frames stepped since the sheet was created or reset.
    pub fn frame(&self) -> u64 {
        self.frame
    }

    /// Simulated time, seconds.
    pub fn time_s(&self) -> f64 {
        self.frame as f64 / self.cfg.frame_rate_hz
    }

    /// True when the sheet is at rest and a step does no work.
    pub fn is_asleep(&self) -> bool {
        self.asleep
    }

    /// Current value of a gesture.
    pub fn gesture(&self, g: GestureParam) -> f32 {
        self.gesture[g.index()]
    }

    /// Applies one command. Non-finite values are ignored; everything else is clamped.
    pub fn apply(&mut self, cmd: Command) {
        match cmd {
            Command::Reset => {
                let cfg = self.cfg;
                let gesture = self.gesture;
                *self = Sim::new(cfg);
                self.gesture = gesture;
            }
            Command::Grab { slot, grip } => {
                let g = if grip.is_finite() {
                    grip.clamp(0.0, 1.0)
                } else {
                    0.5
                };
                self.held[slot.index()] = Some(g);
                self.asleep = false;
            }
            Command::Release { slot } => {
                self.held[slot.index()] = None;
                self.asleep = false;
            }
            Command::ReleaseAll => {
                self.held = [None; 5];
                self.asleep = false;
            }
            Command::Gesture { param, value } => {
                if let Some(v) = param.sanitize(value) {
                    self.gesture[param.index()] = v;
                    self.asleep = false;
                }
            }
            Command::Size(size) => {
                if size != self.cfg.size {
                    let mut cfg = self.cfg;
                    cfg.size = size;
                    let gesture = self.gesture;
                    let held = self.held;
                    *self = Sim::new(cfg);
                    self.gesture = gesture;
                    self.held = held;
                }
            }
            Command::Material(m) => self.cfg.material = m,
            Command::Seed(s) => self.cfg.seed = s,
            Command::Room(r) => {
                self.cfg.room = r.sanitized();
                self.asleep = false;
            }
        }
    }

    fn slot_holds(&self, slot: GrabSlot, i: usize, j: usize) -> bool {
        match slot {
            GrabSlot::Back => j == self.ny,
            GrabSlot::Front => j == 0,
            GrabSlot::Left => i == 0,
            GrabSlot::Right => i == self.nx,
            GrabSlot::Corners => (i == 0 || i == self.nx) && (j == 0 || j == self.ny),
        }
    }

    /// Steps one frame.
    pub fn step(&mut self, out: &mut FrameOutput) {
        out.sound.clear();
        self.frame += 1;
        out.sound.frame = self.frame;
        out.sound.time_s = self.time_s();
        let any_held = self.held.iter().any(Option::is_some);
        if self.asleep && !any_held {
            out.stats = self.stats(true);
            return;
        }
        let (_, l) = self.cfg.size.dims_m();
        let t = self.time_s();
        let slide = f64::from(self.gesture(GestureParam::Slide)) * 0.5 * l;
        let lift = f64::from(self.gesture(GestureParam::Lift)) * 0.5 * l;
        let depth = f64::from(self.gesture(GestureParam::ShakeDepth)) * 0.05 * l;
        let rate = f64::from(self.gesture(GestureParam::ShakeRateHz));
        let shake = depth * (std::f64::consts::TAU * rate * t).sin();
        let dt = 1.0 / self.cfg.frame_rate_hz;
        let mut moved = false;
        for j in 0..=self.ny {
            for i in 0..=self.nx {
                let v = j * (self.nx + 1) + i;
                let mut grip = None;
                for slot in GrabSlot::ALL {
                    if let Some(g) = self.held[slot.index()]
                        && self.slot_holds(slot, i, j)
                    {
                        grip = Some(grip.map_or(g, |x: f32| x.max(g)));
                    }
                }
                let Some(grip) = grip else { continue };
                let front = j * 2 < self.ny;
                let r = self.rest[v];
                let target = [
                    r[0],
                    r[1] + if front { slide } else { 0.0 },
                    r[2] + if front { lift } else { 0.0 } + shake,
                ];
                // Travel speed grows with grip: 0.2 m/s at grip 0 to 2 m/s at grip 1.
                let max_step = (0.2 + 1.8 * f64::from(grip)) * dt;
                let p = &mut self.pos[v];
                let d = [target[0] - p[0], target[1] - p[1], target[2] - p[2]];
                let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                if n > 1e-9 {
                    let s = (max_step / n).min(1.0);
                    for k in 0..3 {
                        p[k] += d[k] * s;
                    }
                    moved = true;
                }
            }
        }
        self.asleep = !moved && !any_held;
        out.stats = self.stats(false);
    }

    fn stats(&self, asleep: bool) -> FrameStats {
        FrameStats {
            asleep,
            num_vertices: self.pos.len() as u32,
            num_triangles: self.triangles.len() as u32,
            num_singular: 0,
            c_mean_pct: 0.0,
            kinetic_energy_j: 0.0,
        }
    }

    /// Upper bounds of the mesh size, for preallocating snapshots.
    pub fn mesh_capacity(&self) -> (usize, usize) {
        (self.pos.len(), self.triangles.len())
    }

    /// Copies the mesh out (no allocation when `out` has the capacity).
    pub fn write_mesh(&self, out: &mut MeshSnapshot) {
        out.clear();
        out.frame = self.frame;
        for (p, q) in self.pos.iter().zip(&self.pattern) {
            out.positions_m
                .push([p[0] as f32, p[1] as f32, p[2] as f32]);
            out.pattern_m.push([q[0] as f32, q[1] as f32]);
        }
        for j in 0..=self.ny {
            for i in 0..=self.nx {
                let held = GrabSlot::ALL
                    .iter()
                    .any(|s| self.held[s.index()].is_some() && self.slot_holds(*s, i, j));
                out.tags.push(if held {
                    VertexTag::Handle
                } else {
                    VertexTag::Plain
                });
            }
        }
        out.triangles.extend_from_slice(&self.triangles);
    }

    /// The sheet as saved in a project.
    pub fn save(&self) -> SavedSheet {
        SavedSheet {
            version: SAVED_SHEET_VERSION,
            size: self.cfg.size,
            material: self.cfg.material,
            seed: self.cfg.seed,
            frame: self.frame,
            positions_m: self.pos.clone(),
        }
    }

    /// Rebuilds a sheet from saved data; the room and frame rate come from `cfg`.
    pub fn restore(cfg: SimConfig, saved: &SavedSheet) -> Result<Self, RestoreError> {
        if saved.version != SAVED_SHEET_VERSION {
            return Err(RestoreError::Version(saved.version));
        }
        let mut cfg = cfg;
        cfg.size = saved.size;
        cfg.material = saved.material;
        cfg.seed = saved.seed;
        let mut sim = Sim::new(cfg);
        if saved.positions_m.len() != sim.pos.len() {
            return Err(RestoreError::VertexCount {
                size: saved.size,
                expected: sim.pos.len(),
                found: saved.positions_m.len(),
            });
        }
        for (i, p) in saved.positions_m.iter().enumerate() {
            if !p.iter().all(|c| c.is_finite() && c.abs() < 100.0) {
                return Err(RestoreError::BadPosition(i));
            }
        }
        sim.pos.clone_from(&saved.positions_m);
        sim.frame = saved.frame;
        Ok(sim)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn held_front_edge_follows_lift() {
        let mut sim = Sim::new(SimConfig::default());
        let mut out = FrameOutput::default();
        sim.step(&mut out);
        assert!(out.stats.asleep);
        sim.apply(Command::Grab {
            slot: GrabSlot::Front,
            grip: 1.0,
        });
        sim.apply(Command::Gesture {
            param: GestureParam::Lift,
            value: 1.0,
        });
        for _ in 0..200 {
            sim.step(&mut out);
        }
        let mut m = MeshSnapshot::default();
        sim.write_mesh(&mut m);
        let zmax = m.positions_m.iter().map(|p| p[2]).fold(f32::MIN, f32::max);
        assert!(zmax > 0.75 + 0.1, "front edge lifted: {zmax}");
    }

    #[test]
    fn save_restore_round_trip() {
        let mut sim = Sim::new(SimConfig::default());
        sim.apply(Command::Grab {
            slot: GrabSlot::Back,
            grip: 0.5,
        });
        sim.apply(Command::Gesture {
            param: GestureParam::ShakeDepth,
            value: 1.0,
        });
        let mut out = FrameOutput::default();
        for _ in 0..37 {
            sim.step(&mut out);
        }
        let saved = sim.save();
        let back = Sim::restore(SimConfig::default(), &saved).unwrap();
        assert_eq!(back.save(), saved);
        let mut bad = saved.clone();
        bad.positions_m[3][1] = f64::NAN;
        assert_eq!(
            Sim::restore(SimConfig::default(), &bad).unwrap_err(),
            RestoreError::BadPosition(3)
        );
    }
}
