//! # The gesture rig: gesture values → handle targets
//!
//! The seeds drive the sheet by handles, hard constraints with a controlled tangent plane
//! (T 714/730, P 388–394, 450; digest-tearing §4.1), moved by a user. A plugin is driven by
//! notes and automation instead, so the rig maps *absolute* gesture values (digest-tearing
//! §4.3 design rule (a)) to handle target poses; notes grab and release groups of handles.
//!
//! ## Slots (grab/release)
//!
//! | slot | handles (pattern position) |
//! |---|---|
//! | back / front | 2 on the back (+y) / front (−y) edge at 25 % and 75 % of the width (a pinch) |
//! | left / right | 2 on the left (−x) / right (+x) edge at 25 % and 75 % of the length |
//! | corners | the 4 corners |
//!
//! Each handle holds its vertex and 2–4 tangent-plane neighbours ([`crate::handles`]). A grab
//! takes hold where the sheet is; the pose then travels to its target at the grip speed
//! `0.05 + 1.95·grip` m/s (grip = note velocity 0–1), never more than
//! [`TRAVEL_CLAMP_FRAC`] × L_paper per frame. Release frees the vertices with their velocity.
//!
//! ## Target pose of a handle
//!
//! Home pose = pattern position at the table-top height, flat frame. Then:
//! - **slide** s ∈ [0,1]: towards the sheet centre along the inward normal of the handle's own
//!   edge by s·span/4 (span = the sheet's extent across that edge: the length for back/front,
//!   the width for left/right; corners move diagonally by (W/4, L/4)·s). Back + front held →
//!   the edges approach (the sheet curves up, S1/C1); front only → the front edge pushes the
//!   sheet along the table (S6) towards the wall at +y (S3).
//! - **lift** ℓ ∈ [0,1]: the front group (handles with pattern y < 0) rises by ℓ·L/2.
//! - **twist** τ ∈ [−1,1]: the front group's positions and frames rotate by τ·π about the
//!   sheet's long axis (the line x = 0 parallel to y at the group's lifted height); positive τ
//!   raises the right (+x) side (Möbius-like twist C2, flap S5, one-corner lift C6).
//! - **shake** d, f: every active handle moves vertically by `d·0.05·L·sin(φ)`, φ advancing by
//!   2π·f·dt each frame (a continuous phase, so rate changes do not jump).
//! - **crumple** c ∈ [0,1]: while c > 0, 8 boundary points (4 corners + 4 edge midpoints)
//!   become handles ("two hands squeezing") whose targets move towards the centre,
//!   `centre + (1 − c·k)(p − centre)` with k = [`CRUMPLE_CAP`], plus a seeded jitter, a lift of
//!   ≈ c·0.1·L and a tilt of the held patch (inner side up, c·[`CRUMPLE_TILT_RAD`]). They take
//!   precedence over slot handles on the same vertices; c back to 0 releases them.
//!
//! **Crumple cap.** Without sheet–sheet contact (a later issue) the squeeze must stop before the
//! sheet passes through itself; the seeds capped their crumpling for the same reason (no
//! self-collision, point handles only: T 1245, T 2014, T 2076) and digest-tearing §4.3 caps
//! the squeeze at 0.6. k = 0.6 leaves the ring of hands at 40 % of the sheet's size at c = 1.
//!
//! **Rate limits.** Gesture values are followed through slew-rate limits derived from the
//! travel clamp (a value jump becomes a continuous sweep, so e.g. a twist jump rotates the
//! hands along arcs instead of moving them through each other), then each handle pose is
//! clamped again. Tear and pull gestures are stored but have no effect yet (tearing is a later
//! issue).

use serde::{Deserialize, Serialize};

use crate::collision::Obstacles;
use crate::control::{GestureParam, GrabSlot};
use crate::handles::{HandleDef, HandleState, MAX_NEIGHBOURS, Pose};
use crate::math::{Rot, V2, V3};
use crate::sheet::Sheet;

/// Slot handles: back 2, front 2, left 2, right 2, corners 4.
pub const NUM_SLOT_HANDLES: usize = 12;
/// Crumple handles: 4 corners + 4 edge midpoints.
pub const NUM_CRUMPLE_HANDLES: usize = 8;
/// All handles.
pub const NUM_HANDLES: usize = NUM_SLOT_HANDLES + NUM_CRUMPLE_HANDLES;
/// Crumple squeeze cap k: at c = 1 the hands are at (1 − k) of their home distance.
pub const CRUMPLE_CAP: f64 = 0.6;
/// Tilt of a crumple handle's frame at c = 1, radians.
pub const CRUMPLE_TILT_RAD: f64 = 0.6;
/// Per-frame handle travel clamp as a fraction of L_paper, at the default frame rate (it is a
/// speed: 4 L_paper/s; at other frame rates the per-frame clamp scales accordingly).
pub const TRAVEL_CLAMP_FRAC: f64 = 0.02;
/// Per-frame rotation clamp of a handle frame at the default frame rate, radians
/// (digest-tearing §4.3 (d)).
pub const ROTATION_CLAMP_RAD: f64 = 0.05;
/// Shake amplitude at depth 1, as a fraction of the sheet length.
pub const SHAKE_AMPLITUDE_FRAC: f64 = 0.05;

/// Grip speed of a slot handle for a grip (velocity) 0–1, m/s.
pub fn grip_speed_m_s(grip: f32) -> f64 {
    0.05 + 1.95 * f64::from(grip.clamp(0.0, 1.0))
}

/// Speed of the crumple handles, m/s (grip 0.5).
const CRUMPLE_SPEED_M_S: f64 = 1.025;

/// Slot of each slot handle.
const SLOT_OF: [GrabSlot; NUM_SLOT_HANDLES] = [
    GrabSlot::Back,
    GrabSlot::Back,
    GrabSlot::Front,
    GrabSlot::Front,
    GrabSlot::Left,
    GrabSlot::Left,
    GrabSlot::Right,
    GrabSlot::Right,
    GrabSlot::Corners,
    GrabSlot::Corners,
    GrabSlot::Corners,
    GrabSlot::Corners,
];

/// Geometry of one handle on the current sheet.
#[derive(Clone, Copy, Debug, PartialEq)]
struct HandleInfo {
    def: HandleDef,
    /// Home pattern position (of the handle vertex).
    home: V2,
    /// Displacement per unit of slide (pattern), metres.
    slide: V2,
}

/// Serializable state of the rig (part of a saved sheet).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RigState {
    /// Commanded gesture values (plain units), in [`GestureParam::ALL`] order.
    pub commanded: [f32; GestureParam::COUNT],
    /// Rate-limited gesture values the targets follow.
    pub smoothed: [f64; GestureParam::COUNT],
    /// Grip of each held slot, in [`GrabSlot::ALL`] order (`None` = not held).
    pub held: [Option<f32>; 5],
    /// Handle states: 12 slot handles, then 8 crumple handles.
    pub handles: [HandleState; NUM_HANDLES],
    /// Crumple handles are active.
    pub crumple_active: bool,
    /// Crumple jitter per crumple handle: (dx, dy) as fractions of L_paper, lift factor.
    pub crumple_jitter: [[f64; 3]; NUM_CRUMPLE_HANDLES],
    /// Shake phase, radians.
    pub shake_phase_rad: f64,
}

impl Default for RigState {
    fn default() -> Self {
        let mut commanded = [0.0; GestureParam::COUNT];
        let mut smoothed = [0.0; GestureParam::COUNT];
        for g in GestureParam::ALL {
            commanded[g.index()] = g.default_value();
            smoothed[g.index()] = f64::from(g.default_value());
        }
        Self {
            commanded,
            smoothed,
            held: [None; 5],
            handles: [HandleState::default(); NUM_HANDLES],
            crumple_active: false,
            crumple_jitter: [[0.0, 0.0, 1.0]; NUM_CRUMPLE_HANDLES],
            shake_phase_rad: 0.0,
        }
    }
}

/// The rig: handle geometry on the current sheet plus its state.
#[derive(Clone, Debug)]
pub struct GestureRig {
    info: [HandleInfo; NUM_HANDLES],
    /// The state (gestures, grabs, handle poses).
    pub state: RigState,
    /// Suppressed slot handles (their vertex is held by a crumple handle).
    suppressed: [bool; NUM_HANDLES],
    /// Held vertices: (vertex, handle, neighbour index or `u8::MAX` for the handle vertex).
    ownership: Vec<(u32, u8, u8)>,
    /// Per-vertex claim while computing the ownership (handle index or `u8::MAX`).
    claim: Vec<u8>,
    ownership_dirty: bool,
    home_z_m: f64,
    width_m: f64,
    length_m: f64,
}

impl GestureRig {
    /// A rig for `sheet` whose home height is `home_z_m`.
    pub fn new(sheet: &Sheet, home_z_m: f64) -> Self {
        let mut rig = Self {
            info: [HandleInfo {
                def: HandleDef::at_vertex(sheet, 0),
                home: V2::zeros(),
                slide: V2::zeros(),
            }; NUM_HANDLES],
            state: RigState::default(),
            suppressed: [false; NUM_HANDLES],
            ownership: Vec::with_capacity(NUM_HANDLES * (1 + MAX_NEIGHBOURS)),
            claim: Vec::new(),
            ownership_dirty: true,
            home_z_m,
            width_m: sheet.width_m,
            length_m: sheet.length_m,
        };
        rig.rebuild_geometry(sheet, home_z_m);
        rig
    }

    /// Recomputes the handle geometry for a (new) sheet and re-anchors every active handle
    /// where the sheet is. Allocates only if the sheet has more vertices than before.
    pub fn rebuild_geometry(&mut self, sheet: &Sheet, home_z_m: f64) {
        let (w, l) = (sheet.width_m, sheet.length_m);
        self.width_m = w;
        self.length_m = l;
        self.home_z_m = home_z_m;
        let (hw, hl) = (0.5 * w, 0.5 * l);
        let mut pts: [(V2, V2); NUM_HANDLES] = [(V2::zeros(), V2::zeros()); NUM_HANDLES];
        let s_back = V2::new(0.0, -l / 4.0);
        let s_side = V2::new(w / 4.0, 0.0);
        pts[0] = (V2::new(-hw + 0.25 * w, hl), s_back);
        pts[1] = (V2::new(-hw + 0.75 * w, hl), s_back);
        pts[2] = (V2::new(-hw + 0.25 * w, -hl), -s_back);
        pts[3] = (V2::new(-hw + 0.75 * w, -hl), -s_back);
        pts[4] = (V2::new(-hw, -hl + 0.25 * l), s_side);
        pts[5] = (V2::new(-hw, -hl + 0.75 * l), s_side);
        pts[6] = (V2::new(hw, -hl + 0.25 * l), -s_side);
        pts[7] = (V2::new(hw, -hl + 0.75 * l), -s_side);
        let corners = [
            V2::new(-hw, -hl),
            V2::new(hw, -hl),
            V2::new(hw, hl),
            V2::new(-hw, hl),
        ];
        for (k, c) in corners.iter().enumerate() {
            pts[8 + k] = (*c, V2::new(-c.x.signum() * w / 4.0, -c.y.signum() * l / 4.0));
            pts[12 + k] = (*c, V2::zeros());
        }
        let mids = [
            V2::new(0.0, -hl),
            V2::new(hw, 0.0),
            V2::new(0.0, hl),
            V2::new(-hw, 0.0),
        ];
        for (k, m) in mids.iter().enumerate() {
            pts[16 + k] = (*m, V2::zeros());
        }
        for (k, (p, slide)) in pts.iter().enumerate() {
            let v = sheet.nearest_vertex(*p, true);
            self.info[k] = HandleInfo {
                def: HandleDef::at_vertex(sheet, v),
                home: sheet.sp.pattern[v as usize],
                slide: *slide,
            };
        }
        if self.claim.len() != sheet.sp.num_vertices() {
            self.claim = vec![u8::MAX; sheet.sp.num_vertices()];
        }
        for k in 0..NUM_HANDLES {
            if self.state.handles[k].active {
                let def = self.info[k].def;
                self.state.handles[k].reanchor(&def, &sheet.sp.pos);
            }
        }
        self.ownership_dirty = true;
    }

    /// Sets the home height (the table top) the targets are measured from.
    pub fn set_home_height(&mut self, home_z_m: f64) {
        self.home_z_m = home_z_m;
    }

    /// L_paper, metres.
    fn l_paper(&self) -> f64 {
        self.width_m.max(self.length_m)
    }

    /// A hand takes hold of a slot (a second grab of a held slot only changes the grip).
    pub fn grab(&mut self, slot: GrabSlot, grip: f32, pos: &[V3]) {
        let grip = if grip.is_finite() { grip.clamp(0.0, 1.0) } else { 0.5 };
        let speed = grip_speed_m_s(grip);
        let was = self.state.held[slot.index()].is_some();
        self.state.held[slot.index()] = Some(grip);
        for k in 0..NUM_SLOT_HANDLES {
            if SLOT_OF[k] == slot {
                if was {
                    self.state.handles[k].speed_m_s = speed;
                } else {
                    let def = self.info[k].def;
                    self.state.handles[k] = HandleState::grab(&def, pos, speed);
                }
            }
        }
        self.ownership_dirty = true;
    }

    /// The hand holding `slot` lets go.
    pub fn release(&mut self, slot: GrabSlot) {
        self.state.held[slot.index()] = None;
        for k in 0..NUM_SLOT_HANDLES {
            if SLOT_OF[k] == slot {
                self.state.handles[k].active = false;
            }
        }
        self.ownership_dirty = true;
    }

    /// Every hand lets go (crumple handles stay while crumple > 0).
    pub fn release_all(&mut self) {
        for s in GrabSlot::ALL {
            self.release(s);
        }
    }

    /// Sets a gesture value (already sanitized by the caller).
    pub fn set_gesture(&mut self, g: GestureParam, value: f32) {
        self.state.commanded[g.index()] = value;
    }

    /// True if the rig will move something in the next frame.
    pub fn is_moving(&self) -> bool {
        let any_active = self.state.handles.iter().any(|h| h.active);
        let shaking = any_active && self.state.smoothed[GestureParam::ShakeDepth.index()] > 0.0;
        let settling = GestureParam::ALL
            .iter()
            .any(|g| f64::from(self.state.commanded[g.index()]) != self.state.smoothed[g.index()]);
        let crumple_pending = (self.state.commanded[GestureParam::Crumple.index()] > 0.0)
            != self.state.crumple_active;
        shaking || settling || crumple_pending || self.ownership_dirty
    }

    /// Number of active handles (crumple handles included, suppressed ones excluded).
    pub fn num_active_handles(&self) -> usize {
        (0..NUM_HANDLES)
            .filter(|&k| self.state.handles[k].active && !self.suppressed[k])
            .count()
    }

    /// Advances the rig by one frame: gesture slew, crumple on/off, target poses, handle poses.
    /// Returns true if any handle moved.
    pub fn advance_frame(&mut self, dt_s: f64, frame_scale: f64, pos: &[V3], rng: &mut rand_pcg::Pcg32) -> bool {
        let l = self.l_paper();
        let clamp_m = TRAVEL_CLAMP_FRAC * l * frame_scale;
        let max_angle = ROTATION_CLAMP_RAD * frame_scale;
        self.slew_gestures(clamp_m, max_angle);
        let crumple_smoothed = self.state.smoothed[GestureParam::Crumple.index()];
        let rate = self.state.smoothed[GestureParam::ShakeRateHz.index()];

        // Crumple handles on/off.
        let c_cmd = self.state.commanded[GestureParam::Crumple.index()];
        if c_cmd > 0.0 && !self.state.crumple_active {
            self.state.crumple_active = true;
            use rand::RngExt;
            for k in 0..NUM_CRUMPLE_HANDLES {
                self.state.crumple_jitter[k] = [
                    rng.random_range(-0.03..0.03),
                    rng.random_range(-0.03..0.03),
                    rng.random_range(0.6..1.4),
                ];
                let def = self.info[NUM_SLOT_HANDLES + k].def;
                self.state.handles[NUM_SLOT_HANDLES + k] = HandleState::grab(&def, pos, CRUMPLE_SPEED_M_S);
            }
            self.ownership_dirty = true;
        } else if self.state.crumple_active && c_cmd <= 0.0 && crumple_smoothed <= 0.0 {
            self.state.crumple_active = false;
            for k in NUM_SLOT_HANDLES..NUM_HANDLES {
                self.state.handles[k].active = false;
            }
            self.ownership_dirty = true;
        }
        if self.ownership_dirty {
            self.recompute_ownership(pos);
        }

        // Shake phase.
        self.state.shake_phase_rad = (self.state.shake_phase_rad + std::f64::consts::TAU * rate * dt_s)
            .rem_euclid(std::f64::consts::TAU);
        let mut moved = false;
        for k in 0..NUM_HANDLES {
            if !self.state.handles[k].active || self.suppressed[k] {
                continue;
            }
            let target = self.target_pose(k);
            let def = self.info[k].def;
            moved |= self.state.handles[k].advance(&def, &target, dt_s, clamp_m, max_angle);
        }
        moved
    }

    fn slew_gestures(&mut self, clamp_m: f64, max_angle: f64) {
        let (w, l) = (self.width_m, self.length_m);
        let lp = self.l_paper();
        for gp in GestureParam::ALL {
            let i = gp.index();
            let target = f64::from(self.state.commanded[i]);
            let rate = match gp {
                GestureParam::Slide => 4.0 * clamp_m / lp,
                GestureParam::Lift => 2.0 * clamp_m / l,
                GestureParam::Twist => (max_angle / std::f64::consts::PI)
                    .min(clamp_m / (std::f64::consts::PI * 0.5 * w)),
                GestureParam::Crumple => clamp_m / (CRUMPLE_CAP * 0.5 * lp),
                GestureParam::ShakeDepth => clamp_m / (SHAKE_AMPLITUDE_FRAC * l),
                _ => f64::INFINITY,
            };
            let cur = self.state.smoothed[i];
            let d = target - cur;
            self.state.smoothed[i] = if d.abs() <= rate { target } else { cur + rate * d.signum() };
        }
    }

    /// Target pose of handle `k` from the smoothed gestures.
    fn target_pose(&self, k: usize) -> Pose {
        let g = |p: GestureParam| self.state.smoothed[p.index()];
        let info = &self.info[k];
        let l = self.length_m;
        let lp = self.l_paper();
        let z0 = self.home_z_m;
        let shake = g(GestureParam::ShakeDepth) * SHAKE_AMPLITUDE_FRAC * l * self.state.shake_phase_rad.sin();
        if k >= NUM_SLOT_HANDLES {
            let j = k - NUM_SLOT_HANDLES;
            let c = g(GestureParam::Crumple);
            let jit = self.state.crumple_jitter[j];
            let p = info.home * (1.0 - c * CRUMPLE_CAP) + V2::new(jit[0], jit[1]) * (c * lp);
            let lift = c * 0.1 * l * jit[2];
            let inward = -info.home.normalize();
            let axis = V3::new(inward.x, inward.y, 0.0).cross(&V3::z());
            let rot = nalgebra::Unit::try_new(axis, 1e-12)
                .map(|a| Rot::from_axis_angle(&a, c * CRUMPLE_TILT_RAD))
                .unwrap_or_else(Rot::identity);
            return Pose::new(V3::new(p.x, p.y, z0 + lift + shake), rot);
        }
        let p = info.home + info.slide * g(GestureParam::Slide);
        let front = info.home.y < 0.0;
        let mut pos = V3::new(p.x, p.y, z0 + shake);
        let mut rot = Rot::identity();
        if front {
            pos.z += g(GestureParam::Lift) * 0.5 * l;
            let phi = g(GestureParam::Twist) * std::f64::consts::PI;
            if phi != 0.0 {
                // Rotation about −y by φ raises the +x side.
                let r = Rot::from_axis_angle(&-V3::y_axis(), phi);
                let axis_pt = V3::new(0.0, pos.y, pos.z);
                pos = axis_pt + r * (pos - axis_pt);
                rot = r;
            }
        }
        Pose::new(pos, rot)
    }

    fn recompute_ownership(&mut self, pos: &[V3]) {
        self.ownership.clear();
        for c in &mut self.claim {
            *c = u8::MAX;
        }
        let was_suppressed = self.suppressed;
        self.suppressed = [false; NUM_HANDLES];
        let order = |crumple: bool| {
            if crumple {
                NUM_SLOT_HANDLES..NUM_HANDLES
            } else {
                0..NUM_SLOT_HANDLES
            }
        };
        for crumple in [true, false] {
            // Handle vertices first, then neighbours.
            for k in order(crumple) {
                if !self.state.handles[k].active {
                    continue;
                }
                let v = self.info[k].def.vertex as usize;
                if self.claim[v] != u8::MAX {
                    self.suppressed[k] = true;
                    continue;
                }
                self.claim[v] = k as u8;
                self.ownership.push((v as u32, k as u8, u8::MAX));
            }
            for k in order(crumple) {
                if !self.state.handles[k].active || self.suppressed[k] {
                    continue;
                }
                let def = self.info[k].def;
                for (j, &n) in def.neighbours().iter().enumerate() {
                    if self.claim[n as usize] == u8::MAX {
                        self.claim[n as usize] = k as u8;
                        self.ownership.push((n, k as u8, j as u8));
                    }
                }
            }
        }
        // A handle that gets its vertices back starts again from where the sheet is.
        for k in 0..NUM_HANDLES {
            if was_suppressed[k] && !self.suppressed[k] && self.state.handles[k].active {
                let def = self.info[k].def;
                self.state.handles[k].reanchor(&def, pos);
            }
        }
        self.ownership_dirty = false;
    }

    /// Writes the kinematic constraints at fraction `s` ∈ [0, 1] of the current frame:
    /// `fixed[v]` for held vertices and their positions in `target` (pushed out of the
    /// obstacles).
    pub fn fill_kinematics(&self, s: f64, fixed: &mut [bool], target: &mut [V3], obstacles: &Obstacles) {
        for f in fixed.iter_mut() {
            *f = false;
        }
        for &(v, k, j) in &self.ownership {
            let h = &self.state.handles[k as usize];
            let pp = h.prev_pose.pos().lerp(&h.pose.pos(), s);
            let mut p = if j == u8::MAX {
                pp
            } else {
                let j = j as usize;
                let r = h.prev_pose.rotation().slerp(&h.pose.rotation(), s);
                let a = V3::from(h.prev_offsets_m[j]);
                let b = V3::from(h.offsets_m[j]);
                pp + r * a.lerp(&b, s)
            };
            obstacles.push_out(&mut p, 0.0);
            fixed[v as usize] = true;
            target[v as usize] = p;
        }
    }

    /// Vertices currently held (for tags and stats).
    pub fn held_vertices(&self) -> impl Iterator<Item = u32> + '_ {
        self.ownership.iter().map(|o| o.0)
    }

    /// True if vertex `v` is a handle vertex (not a neighbour) of an active handle.
    pub fn is_handle_vertex(&self, v: u32) -> bool {
        self.ownership.iter().any(|o| o.0 == v && o.2 == u8::MAX)
    }

    /// The suppression flags and whether the ownership is pending recomputation (saved with
    /// the sheet for exact continuation).
    pub fn ownership_flags(&self) -> ([bool; NUM_HANDLES], bool) {
        (self.suppressed, self.ownership_dirty)
    }

    /// Restores the flags of [`Self::ownership_flags`] after `state` was restored. The
    /// ownership itself is a function of the state and the flags, recomputed here (without
    /// re-anchoring any handle) unless it was pending.
    pub fn restore_ownership(&mut self, suppressed: [bool; NUM_HANDLES], dirty: bool, pos: &[V3]) {
        self.suppressed = suppressed;
        if dirty {
            self.ownership_dirty = true;
        } else {
            self.recompute_ownership(pos);
        }
    }

    /// The handle definition of handle `k` (tests and diagnostics).
    pub fn handle_def(&self, k: usize) -> &HandleDef {
        &self.info[k].def
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::SheetSize;
    use crate::room::RoomConfig;
    use crate::sheet::MeshConfig;
    use rand::SeedableRng;

    fn setup() -> (Sheet, GestureRig, Obstacles, rand_pcg::Pcg32) {
        let sheet = Sheet::new_flat(SheetSize::A4, MeshConfig::default(), 0.75, 0.1);
        let rig = GestureRig::new(&sheet, 0.75);
        (sheet, rig, Obstacles::new(&RoomConfig::default()), rand_pcg::Pcg32::seed_from_u64(1))
    }

    fn run(rig: &mut GestureRig, sheet: &Sheet, rng: &mut rand_pcg::Pcg32, frames: usize) {
        for _ in 0..frames {
            rig.advance_frame(0.005, 1.0, &sheet.sp.pos, rng);
        }
    }

    #[test]
    fn slide_brings_back_and_front_together() {
        let (sheet, mut rig, obs, mut rng) = setup();
        rig.grab(GrabSlot::Back, 1.0, &sheet.sp.pos);
        rig.grab(GrabSlot::Front, 1.0, &sheet.sp.pos);
        rig.set_gesture(GestureParam::Slide, 1.0);
        run(&mut rig, &sheet, &mut rng, 200);
        let n = sheet.sp.num_vertices();
        let (mut fixed, mut target) = (vec![false; n], vec![V3::zeros(); n]);
        rig.fill_kinematics(1.0, &mut fixed, &mut target, &obs);
        let back = rig.info[0].def.vertex as usize;
        let front = rig.info[2].def.vertex as usize;
        let gap = target[back].y - target[front].y;
        let l = sheet.length_m;
        // Home gap L, each edge moved L/4 inwards.
        assert!((gap - 0.5 * l).abs() < 1e-9, "gap {gap}");
        assert!(fixed.iter().filter(|&&f| f).count() >= 4 * 4);
    }

    #[test]
    fn lift_and_twist_move_only_the_front_group() {
        let (sheet, mut rig, obs, mut rng) = setup();
        rig.grab(GrabSlot::Corners, 1.0, &sheet.sp.pos);
        rig.set_gesture(GestureParam::Lift, 0.5);
        rig.set_gesture(GestureParam::Twist, 0.25);
        run(&mut rig, &sheet, &mut rng, 300);
        let n = sheet.sp.num_vertices();
        let (mut fixed, mut target) = (vec![false; n], vec![V3::zeros(); n]);
        rig.fill_kinematics(1.0, &mut fixed, &mut target, &obs);
        let l = sheet.length_m;
        let fl = rig.info[8].def.vertex as usize; // front-left
        let fr = rig.info[9].def.vertex as usize; // front-right
        let br = rig.info[10].def.vertex as usize;
        assert!((target[br].z - 0.75).abs() < 1e-9, "back corner stays");
        // Front corners rotated by π/4 about the axis at height 0.75 + L/4: right side up.
        let zc = 0.75 + 0.25 * l;
        let hw = 0.5 * sheet.width_m;
        let s = (std::f64::consts::PI / 4.0).sin() * hw;
        assert!((target[fr].z - (zc + s)).abs() < 1e-9, "{}", target[fr].z);
        assert!((target[fl].z - (zc - s)).abs() < 1e-9);
    }

    #[test]
    fn crumple_takes_precedence_and_releases() {
        let (sheet, mut rig, obs, mut rng) = setup();
        rig.grab(GrabSlot::Corners, 1.0, &sheet.sp.pos);
        rig.set_gesture(GestureParam::Crumple, 1.0);
        run(&mut rig, &sheet, &mut rng, 5);
        assert!(rig.state.crumple_active);
        for k in 8..12 {
            assert!(rig.suppressed[k], "corner slot handle {k} suppressed");
        }
        assert_eq!(rig.num_active_handles(), 8);
        run(&mut rig, &sheet, &mut rng, 400);
        let n = sheet.sp.num_vertices();
        let (mut fixed, mut target) = (vec![false; n], vec![V3::zeros(); n]);
        rig.fill_kinematics(1.0, &mut fixed, &mut target, &obs);
        let c0 = rig.info[12].def.vertex as usize;
        let r = V2::new(target[c0].x, target[c0].y).norm();
        let r0 = sheet.sp.pattern[c0].norm();
        assert!(r < 0.5 * r0, "corner squeezed towards the centre: {r} vs {r0}");
        rig.set_gesture(GestureParam::Crumple, 0.0);
        run(&mut rig, &sheet, &mut rng, 400);
        assert!(!rig.state.crumple_active);
        assert_eq!(rig.num_active_handles(), 4, "corner slot handles back");
        assert!(!rig.is_moving());
    }

    #[test]
    fn jumps_are_rate_limited() {
        let (sheet, mut rig, _obs, mut rng) = setup();
        rig.grab(GrabSlot::Front, 1.0, &sheet.sp.pos);
        rig.set_gesture(GestureParam::Twist, 1.0);
        rig.advance_frame(0.005, 1.0, &sheet.sp.pos, &mut rng);
        assert!(rig.state.smoothed[GestureParam::Twist.index()] <= ROTATION_CLAMP_RAD / std::f64::consts::PI + 1e-12);
        let h = &rig.state.handles[2];
        assert!((h.pose.pos() - h.prev_pose.pos()).norm() <= TRAVEL_CLAMP_FRAC * sheet.length_m + 1e-12);
    }
}
