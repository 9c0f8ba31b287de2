//! # The tearing hands: two grips either side of the tear that open it
//!
//! The seeds' tearing hands hold the sheet either side of the crack (an index and a thumb each,
//! MIG 2015 M:97, thesis T:1333) and turn about the tip in the table's plane; the flaps between
//! them form a cone whose apex is the tip (M:87–95). Here, when a tear starts, two grips take
//! hold of the sheet [`HAND_OFFSET_M`] either side of the start, just inside the back edge
//! (the [`GRIP_VERTICES`] vertices nearest each grip point on its own side of the tear), and
//! hold them as hard constraints while `tear_amount` is above 0; at 0 they let go. A pull
//! (sim/tear.rs) takes the back edge at Roman's pulling points instead, from the moment
//! `pull_sep` rises, and lets go when it is back at 0 (or the sheet is in two).
//!
//! Decision (beyond the seeds): the left hand **lifts** its flap as the tear grows
//! ([`LIFT_PER_TORN`] × the torn length, at most [`MAX_LIFT_M`], at most [`LIFT_STEP_M`] a
//! frame) while the right one holds its flap on the table: a real two-hand tear twists the
//! halves out of the plane (mode III), which is what makes it visible and lets the pieces part;
//! the in-plane turn of the seeds alone leaves a hairline slit on a sheet lying flat. The
//! lifted flap bends about a line through the tip: the cone at the tip comes from the physics
//! and the geometry layer, as every other cone of the sheet does.
//!
//! Decisions, one line each:
//! - The tearing hands hold only a sheet no gesture hand holds: a grab lets them go, and a tear
//!   started in the gesture hands runs without them (two sets of hard grips fought over the
//!   sheet in the hostile stress runs: a sheet held still never slept, a triangle turned over).
//! - A vertex a gesture hand holds stays with that hand (the user's hands come first).
//! - Where the strain limit moves a held vertex, the grip slips by the mean move (as the
//!   gesture hands do, `GestureRig::regrip`): paper does not stretch under the tearing hands.
//! - A pull's hands open the tear the same way (lifting the left flap), not by moving apart
//!   in the table's plane: spreading them 0.1 × the torn length stored the pull's strain in
//!   the ligament ahead of the tip, which flung the left piece 40 cm across the table at
//!   2.7 m/s when it broke (docs/decisions.md, "Tearing I: the pull").
//! - The grips' vertices keep their indices through the tear's mesh steps (old vertices keep
//!   their index), so the hands hold on while the mesh is cut.

use serde::{Deserialize, Serialize};

use crate::math::{V2, V3};

/// Distance of each grip from the tear's start along the back edge, metres.
pub const HAND_OFFSET_M: f64 = 0.04;
/// Distance of the grip points inside the back edge, metres.
pub const HAND_INSET_M: f64 = 0.01;
/// Vertices each grip holds.
pub const GRIP_VERTICES: usize = 3;
/// Lift of the left flap per metre torn.
pub const LIFT_PER_TORN: f64 = 0.5;
/// Largest lift of the left flap, metres.
pub const MAX_LIFT_M: f64 = 0.06;
/// Largest change of the lift per frame, metres.
pub const LIFT_STEP_M: f64 = 0.0015;

/// One grip: the vertices it holds and where it holds them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TearGrip {
    /// Vertices held (the first `count`).
    pub vertices: [u32; GRIP_VERTICES],
    /// Number of vertices held.
    pub count: u8,
    /// Where each vertex is held at zero lift, metres.
    pub anchors_m: [[f64; 3]; GRIP_VERTICES],
}

/// The two tearing hands (saved with the tear).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TearHands {
    /// The hands hold the sheet.
    pub active: bool,
    /// Left (−x) and right grips.
    pub grips: [TearGrip; 2],
    /// Lift of the left grip at the end of the last frame and of this one, metres.
    pub lift_prev_m: f64,
    /// Lift of the left grip at the end of this frame, metres.
    pub lift_m: f64,
}

impl TearHands {
    /// Takes hold on either side of the tear's `start` (pattern), the left grip `offsets_m[0]`
    /// (< 0) and the right one `offsets_m[1]` (> 0) along the back edge, on a sheet whose
    /// pattern is `pattern` and positions `pos`; `taken(v)` says whether a gesture hand holds
    /// `v`.
    pub fn grab(
        &mut self,
        start: V2,
        offsets_m: [f64; 2],
        pattern: &[V2],
        pos: &[V3],
        taken: impl Fn(u32) -> bool,
    ) {
        *self = Self::default();
        for (k, side) in [-1.0f64, 1.0].into_iter().enumerate() {
            let at = start + V2::new(offsets_m[k], -HAND_INSET_M);
            let mut best = [(f64::INFINITY, u32::MAX); GRIP_VERTICES];
            for (v, q) in pattern.iter().enumerate() {
                // On the hand's own side of the tear, and not held already.
                if (q.x - start.x) * side <= 0.0 || taken(v as u32) {
                    continue;
                }
                let d = (q - at).norm_squared();
                if d < best[GRIP_VERTICES - 1].0 {
                    best[GRIP_VERTICES - 1] = (d, v as u32);
                    best.sort_by(|a, b| a.0.total_cmp(&b.0));
                }
            }
            let g = &mut self.grips[k];
            for (d, v) in best {
                if d.is_finite() {
                    let i = usize::from(g.count);
                    g.vertices[i] = v;
                    g.anchors_m[i] = pos[v as usize].into();
                    g.count += 1;
                }
            }
        }
        self.active = self.grips.iter().any(|g| g.count > 0);
    }

    /// Advances the lift for a tear of `torn_m` (called once a frame, before the substeps).
    /// Returns whether the hands move this frame.
    pub fn advance(&mut self, torn_m: f64) -> bool {
        self.lift_prev_m = self.lift_m;
        if !self.active {
            return false;
        }
        let target = (LIFT_PER_TORN * torn_m).clamp(0.0, MAX_LIFT_M);
        let d = (target - self.lift_m).clamp(-LIFT_STEP_M, LIFT_STEP_M);
        self.lift_m += if d.is_finite() { d } else { 0.0 };
        self.lift_m != self.lift_prev_m
    }

    /// Writes the held vertices at fraction `s` of the frame into `fixed`/`target`, leaving
    /// the vertices a gesture hand holds (`fixed` already) to it.
    pub fn fill(&self, s: f64, fixed: &mut [bool], target: &mut [V3]) {
        if !self.active {
            return;
        }
        let lift = self.lift_prev_m + (self.lift_m - self.lift_prev_m) * s;
        for (k, g) in self.grips.iter().enumerate() {
            for i in 0..usize::from(g.count) {
                let v = g.vertices[i] as usize;
                if v >= fixed.len() || fixed[v] {
                    continue;
                }
                fixed[v] = true;
                target[v] = V3::from(g.anchors_m[i]) + Self::opened(k, lift);
            }
        }
    }

    /// The grips slip by the mean move of their vertices the strain limit `moved` (`pos`: the
    /// positions after it). Returns whether one slipped.
    pub fn regrip(&mut self, pos: &[V3], moved: &[bool], rig_holds: impl Fn(u32) -> bool) -> bool {
        if !self.active {
            return false;
        }
        let mut any = false;
        for (k, g) in self.grips.iter_mut().enumerate() {
            let open = Self::opened(k, self.lift_m);
            let (mut shift, mut n) = (V3::zeros(), 0.0);
            for i in 0..usize::from(g.count) {
                let v = g.vertices[i] as usize;
                if moved.get(v).copied().unwrap_or(false) && !rig_holds(v as u32) {
                    shift += pos[v] - (V3::from(g.anchors_m[i]) + open);
                    n += 1.0;
                }
            }
            if n > 0.0 {
                let d = shift / n;
                if d.iter().all(|c| c.is_finite()) {
                    for a in &mut g.anchors_m[..usize::from(g.count)] {
                        *a = (V3::from(*a) + d).into();
                    }
                    any = true;
                }
            }
        }
        any
    }

    /// Where grip `k` holds its vertices relative to their anchors at a lift `lift_m`.
    fn opened(k: usize, lift_m: f64) -> V3 {
        V3::new(0.0, 0.0, if k == 0 { lift_m } else { 0.0 })
    }

    /// Lets go.
    pub fn release(&mut self) {
        *self = Self::default();
    }

    /// Checks a restored state against a mesh of `num_vertices` vertices.
    pub fn validate(&self, num_vertices: usize) -> Result<(), String> {
        let ok = self.grips.iter().all(|g| {
            usize::from(g.count) <= GRIP_VERTICES
                && g.vertices[..usize::from(g.count)]
                    .iter()
                    .all(|&v| (v as usize) < num_vertices)
                && g.anchors_m.iter().flatten().all(|c| c.is_finite())
        }) && self.lift_m.is_finite()
            && self.lift_prev_m.is_finite();
        if ok {
            Ok(())
        } else {
            Err("the tearing hands' state is not valid".into())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::SheetSize;
    use crate::sheet::{MeshConfig, Sheet};

    #[test]
    fn the_grips_hold_either_side_of_the_start_and_the_left_one_lifts() {
        let sheet = Sheet::new_flat(SheetSize::A4, MeshConfig::default(), 0.75, 0.08);
        let start = V2::new(0.01, 0.5 * sheet.length_m);
        let mut h = TearHands::default();
        h.grab(
            start,
            [-HAND_OFFSET_M, HAND_OFFSET_M],
            &sheet.sp.pattern,
            &sheet.sp.pos,
            |_| false,
        );
        assert!(h.active);
        for (k, g) in h.grips.iter().enumerate() {
            assert_eq!(usize::from(g.count), GRIP_VERTICES);
            for &v in &g.vertices {
                let q = sheet.sp.pattern[v as usize];
                assert_eq!(q.x < start.x, k == 0, "grip {k} holds vertex {v} at {q:?}");
                assert!(q.y > 0.3 * sheet.length_m);
            }
        }
        // The lift follows the torn length, at most a step a frame, up to its bound.
        let mut lifts = Vec::new();
        for _ in 0..100 {
            h.advance(0.2);
            lifts.push(h.lift_m);
        }
        assert!((lifts[0] - LIFT_STEP_M).abs() < 1e-15);
        assert!((lifts[99] - MAX_LIFT_M.min(0.1)).abs() < 1e-12);
        let n = sheet.sp.num_vertices();
        let (mut fixed, mut target) = (vec![false; n], vec![V3::zeros(); n]);
        h.fill(1.0, &mut fixed, &mut target);
        let g = h.grips[0];
        let v = g.vertices[0] as usize;
        assert!(fixed[v] && (target[v].z - sheet.sp.pos[v].z - h.lift_m).abs() < 1e-12);
        let w = h.grips[1].vertices[0] as usize;
        assert!(fixed[w] && target[w] == sheet.sp.pos[w]);
        // A vertex the gesture hands hold stays theirs.
        let mut fixed = vec![false; n];
        fixed[v] = true;
        target[v] = V3::zeros();
        h.fill(1.0, &mut fixed, &mut target);
        assert_eq!(target[v], V3::zeros());
    }
}
