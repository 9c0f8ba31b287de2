//! # Saved sheets: everything needed to reopen a sheet identically
//!
//! A plugin project stores the sheet (its damage is part of the instrument's state, and
//! automation recall needs bit-identical continuation, digest-crumpling §8 test 18). The saved
//! form holds the pattern and topology (the geometry layer will change them), positions,
//! velocities, per-edge rest angles and damage, the singular vertices, the RNG state, the frame
//! counter, the gesture rig (commanded and rate-limited gestures, grips, handle poses, crumple
//! jitter, shake phase, and where each hand holds the sheet: [`crate::gesture_rig::SavedHandDef`]),
//! the effective obstacle planes, the sleep state and the sound analysis' memory
//! ([`crate::sound_analysis::SavedSoundHistory`]: a reopened sheet sounds as it would have). The room, frame rate and solver settings
//! are configuration, not saved state: a sheet continues bit-identically when it is restored
//! with the configuration it was saved under (the stress runs check this, [`crate::stress`]).
//! Restoring validates
//! every field and answers with a [`RestoreError`] — never a panic — for anything
//! inconsistent: wrong version, counts, out-of-range indices, non-finite values, positions
//! outside a sane room box, invalid meshes.

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::control::{GestureParam, Material, SheetSize};
use crate::gesture_rig::{NUM_HANDS, RigState};

/// Version of [`SavedSheet`]; bump it (and migrate) whenever its meaning changes.
///
/// History: 1 = positions only (kinematic placeholder); 2 = the physical sheet; 3 = plus the
/// geometry layer's state ([`SavedSheet::geometry`]); 4 = plus the tear
/// ([`SavedSheet::tear`]: a torn sheet's pattern has two lips at one place, which version 3
/// never held). Version 2 is still read (migration: the singular vertices, rest angles and
/// damage it already holds are kept, the layer's flat/curved state and generator start
/// fresh); version 3 opens untorn.
pub const SAVED_SHEET_VERSION: u32 = 4;
/// Oldest version [`crate::Sim::restore`] reads.
pub const OLDEST_READABLE_VERSION: u32 = 2;

/// Half-extent of the room box positions must lie in, metres.
pub const ROOM_BOX_HALF_M: f64 = 50.0;
/// Largest accepted frame counter and grab sequence number (2⁵³: exact in f64, centuries
/// of frames).
pub const MAX_SAVED_COUNTER: u64 = 1 << 53;
/// Largest accepted saved speed, m/s.
pub const MAX_SAVED_SPEED_M_S: f64 = 200.0;

/// A sheet as saved in a project: enough to reopen it identically.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SavedSheet {
    /// Format version ([`SAVED_SHEET_VERSION`]).
    pub version: u32,
    /// Sheet size.
    pub size: SheetSize,
    /// Paper grade.
    pub material: Material,
    /// Seed (used by the next reset).
    pub seed: u64,
    /// Frame counter.
    pub frame: u64,
    /// Pattern positions of the S_P vertices, metres.
    pub pattern_m: Vec<[f64; 2]>,
    /// S_P triangles (counter-clockwise in the pattern).
    pub triangles: Vec<[u32; 3]>,
    /// 3D positions, metres.
    pub positions_m: Vec<[f64; 3]>,
    /// Velocities, m/s.
    pub velocities_m_s: Vec<[f64; 3]>,
    /// Rest dihedral angle per edge (canonical edge order of the triangles), radians.
    pub edge_rest_angle_rad: Vec<f64>,
    /// Fibre damage per edge.
    pub edge_damage: Vec<f64>,
    /// Persistent interior singular vertices.
    pub singular_vertices: Vec<u32>,
    /// State of the sheet's random number generator.
    pub rng: rand_pcg::Pcg32,
    /// The gesture rig.
    pub rig: RigState,
    /// Held vertices: (vertex, hand, index of the vertex in the hand).
    pub rig_ownership: Vec<(u32, u8, u8)>,
    /// Slot hands suppressed by crumple hands.
    pub rig_suppressed: [bool; NUM_HANDS],
    /// The rig's vertex ownership was pending recomputation.
    pub rig_ownership_pending: bool,
    /// Effective offsets of the obstacle planes (floor, table, wall), metres.
    pub obstacle_offsets_m: [f64; 3],
    /// Which obstacle planes were present.
    pub obstacle_active: [bool; 3],
    /// The sheet was asleep.
    pub asleep: bool,
    /// Consecutive quiet frames counted towards sleep.
    pub quiet_frames: u32,
    /// Where each vertex was at the start of the sleep window ([`crate::sim::REST_BOX_M`];
    /// absent in older saves, or empty: the window starts at the next quiet frame).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rest_box_m: Vec<[f64; 3]>,
    /// The geometry layer's persistent state (version ≥ 3; absent in version 2).
    #[serde(default)]
    pub geometry: Option<crate::geometry::SavedGeometry>,
    /// Sheet–sheet contact stiffened where the sheet crossed itself in an undone frame
    /// ([`crate::physics::sheet_contact`]; absent in older saves: none).
    #[serde(default)]
    pub contact_boosts: Vec<crate::physics::sheet_contact::Boost>,
    /// The seed the sheet's fibres were made from, if not `seed` (a seed changed after the
    /// sheet was built is the next sheet's; absent in older saves: `seed`).
    #[serde(default)]
    pub fibre_seed: Option<u64>,
    /// Where each hand of the rig holds the sheet ([`crate::gesture_rig::SavedHandDef`];
    /// absent in older saves: worked out afresh from the sheet, as then).
    #[serde(default)]
    pub hand_defs: Vec<crate::gesture_rig::SavedHandDef>,
    /// The sound analysis' memory between frames
    /// ([`crate::sound_analysis::SavedSoundHistory`]; absent in older saves: it starts afresh).
    #[serde(default)]
    pub sound_history: Option<crate::sound_analysis::SavedSoundHistory>,
    /// The tear (version ≥ 4; absent in older saves: untorn).
    #[serde(default)]
    pub tear: crate::sim::tear::TearProgress,
}

/// Why a saved sheet could not be restored.
#[derive(Debug, Error, PartialEq)]
pub enum RestoreError {
    /// Written by a newer or unknown format version.
    #[error("saved sheet has version {0}, this build reads version {SAVED_SHEET_VERSION}")]
    Version(u32),
    /// A per-vertex array does not match the number of pattern vertices.
    #[error(
        "saved sheet has {found} entries in a per-vertex array, the pattern has {expected} vertices ({size:?})"
    )]
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
    /// The pattern or triangles do not form a valid sheet mesh.
    #[error("saved sheet mesh is invalid: {0}")]
    BadMesh(String),
    /// Another field is inconsistent or out of range.
    #[error("saved sheet is invalid: {0}")]
    Invalid(String),
}

fn finite(v: f64) -> bool {
    v.is_finite()
}

impl SavedSheet {
    /// Checks everything that does not need the mesh to be built.
    pub(crate) fn validate_fields(&self) -> Result<(), RestoreError> {
        if !(OLDEST_READABLE_VERSION..=SAVED_SHEET_VERSION).contains(&self.version) {
            return Err(RestoreError::Version(self.version));
        }
        if self.frame > MAX_SAVED_COUNTER
            || self.rig.next_seq > MAX_SAVED_COUNTER
            || self.rig.grab_seq.iter().any(|&q| q > self.rig.next_seq)
        {
            return Err(RestoreError::Invalid(
                "frame or grab counters are out of range".into(),
            ));
        }
        let n = self.pattern_m.len();
        if n < 3 {
            return Err(RestoreError::BadMesh(format!("only {n} pattern vertices")));
        }
        for len in [self.positions_m.len(), self.velocities_m_s.len()] {
            if len != n {
                return Err(RestoreError::VertexCount {
                    size: self.size,
                    expected: n,
                    found: len,
                });
            }
        }
        let (w, l) = self.size.dims_m();
        let tol = 1e-6;
        for (i, p) in self.pattern_m.iter().enumerate() {
            if !(finite(p[0]) && finite(p[1]))
                || p[0].abs() > 0.5 * w + tol
                || p[1].abs() > 0.5 * l + tol
            {
                return Err(RestoreError::BadMesh(format!(
                    "pattern vertex {i} is not finite or outside the {:?} sheet",
                    self.size
                )));
            }
        }
        for (i, p) in self.positions_m.iter().enumerate() {
            let ok = p.iter().all(|c| finite(*c))
                && p[0].abs() <= ROOM_BOX_HALF_M
                && p[1].abs() <= ROOM_BOX_HALF_M
                && (-1.0..=ROOM_BOX_HALF_M).contains(&p[2]);
            if !ok {
                return Err(RestoreError::BadPosition(i));
            }
        }
        for (i, v) in self.velocities_m_s.iter().enumerate() {
            let s2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            if !(finite(s2) && s2 <= MAX_SAVED_SPEED_M_S * MAX_SAVED_SPEED_M_S) {
                return Err(RestoreError::Invalid(format!(
                    "velocity of vertex {i} is not finite or too large"
                )));
            }
        }
        if self.triangles.is_empty() {
            return Err(RestoreError::BadMesh("no triangles".into()));
        }
        for (i, &a) in self.edge_rest_angle_rad.iter().enumerate() {
            if !(finite(a) && a.abs() <= std::f64::consts::PI) {
                return Err(RestoreError::Invalid(format!(
                    "rest angle of edge {i} is out of range"
                )));
            }
        }
        for (i, &d) in self.edge_damage.iter().enumerate() {
            if !(finite(d) && (0.0..=1e6).contains(&d)) {
                return Err(RestoreError::Invalid(format!(
                    "damage of edge {i} is out of range"
                )));
            }
        }
        let mut sing = self.singular_vertices.clone();
        sing.sort_unstable();
        for w in sing.windows(2) {
            if w[0] == w[1] {
                return Err(RestoreError::Invalid(format!(
                    "singular vertex {} is listed twice",
                    w[0]
                )));
            }
        }
        if let Some(&s) = sing.last()
            && s as usize >= n
        {
            return Err(RestoreError::Invalid(format!(
                "singular vertex {s} does not exist"
            )));
        }
        self.validate_rig()?;
        for (k, o) in self.obstacle_offsets_m.iter().enumerate() {
            if !(finite(*o) && o.abs() <= ROOM_BOX_HALF_M) {
                return Err(RestoreError::Invalid(format!(
                    "obstacle {k} offset is out of range"
                )));
            }
        }
        Ok(())
    }

    fn validate_rig(&self) -> Result<(), RestoreError> {
        let r = &self.rig;
        for g in GestureParam::ALL {
            let v = r.commanded[g.index()];
            if g.sanitize(v) != Some(v) {
                return Err(RestoreError::Invalid(format!(
                    "gesture {} value {v} is out of range",
                    g.id()
                )));
            }
            let s = r.smoothed[g.index()];
            let (lo, hi) = g.range();
            if !(finite(s) && s >= f64::from(lo) - 1e-9 && s <= f64::from(hi) + 1e-9) {
                return Err(RestoreError::Invalid(format!(
                    "smoothed gesture {} is out of range",
                    g.id()
                )));
            }
        }
        for (i, h) in r.held.iter().enumerate() {
            if let Some(g) = h
                && !(g.is_finite() && (0.0..=1.0).contains(g))
            {
                return Err(RestoreError::Invalid(format!(
                    "grip of slot {i} is out of range"
                )));
            }
        }
        for (k, h) in r.hands.iter().enumerate() {
            let nums = h
                .pose
                .pos_m
                .iter()
                .chain(&h.prev_pose.pos_m)
                .chain(h.offsets_m.iter().flatten());
            let mut ok = true;
            for c in nums {
                ok &= finite(*c) && c.abs() <= ROOM_BOX_HALF_M;
            }
            if let Some(t) = &h.yielded_to {
                for c in &t.pos_m {
                    ok &= finite(*c) && c.abs() <= ROOM_BOX_HALF_M;
                }
                ok &= t.rot.iter().all(|c| finite(*c));
            }
            for q in [h.pose.rot, h.prev_pose.rot] {
                let n2: f64 = q.iter().map(|c| c * c).sum();
                ok &= finite(n2) && (n2 - 1.0).abs() < 1e-6;
            }
            ok &= finite(h.speed_m_s) && (0.0..=100.0).contains(&h.speed_m_s);
            ok &= finite(h.caution) && (0.0..=1.0).contains(&h.caution);
            if !ok {
                return Err(RestoreError::Invalid(format!(
                    "hand {k} state is out of range"
                )));
            }
        }
        for j in &r.crumple_jitter {
            if !j.iter().all(|c| finite(*c) && c.abs() <= 10.0) {
                return Err(RestoreError::Invalid(
                    "crumple jitter is out of range".into(),
                ));
            }
        }
        if !(finite(r.shake_phase_rad) && r.shake_phase_rad.abs() <= 100.0) {
            return Err(RestoreError::Invalid("shake phase is out of range".into()));
        }
        Ok(())
    }
}
