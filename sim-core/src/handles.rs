//! # Handles: hard positional constraints with a controlled tangent plane
//!
//! "Handle positions, interactively controlled by the user, are enforced as hard constraints on
//! the corresponding vertices of S_P … We also provide control on the tangent plane at the
//! handles through the control of neighboring vertices – between two and four fixed vertices
//! around the handle defined the tangent plane according to whether the handle is in a corner,
//! a border of the paper or inside the surface. This enables us to achieve more realistic
//! movements, mimicking the tangent plane control due to the pressure of fingers."
//! (thesis §2.3.1, T 714/730; the TOG paper says "2 neighboring vertices", P 450–453).
//!
//! We read the "two to four" of the thesis as (digest §9 item 9, impl. choice):
//!
//! | location | held neighbours | why |
//! |---|---|---|
//! | corner | 2: the two boundary neighbours (one along each edge) | they span the tangent plane |
//! | border | 3: both boundary neighbours + the most inward neighbour | the edge line alone would let the sheet rotate about it |
//! | interior | 4: the neighbours closest to the ±x, ±y pattern directions | a finger pad |
//!
//! Handles are held by **hands** ([`HandDef`]): one rigid grip over one or two handles (the
//! two fingers of a pinch along an edge move as one body, so the paper between them is never
//! stretched by the grip itself). A hand is a rigid **pose** (reference point + rotation of its
//! frame) carrying the held vertices: vertex k sits at `pos + rot · offset_k`. At grab time the
//! pose starts where the sheet is (reference = centroid of the handle vertices, frame fitted to
//! all held vertices by least squares, offsets = their current local offsets), so a grab never
//! makes the sheet jump, and the fingers keep the patch in the shape it had when grabbed (a
//! flat sheet is held flat; a bent one stays bent in the hand — straightening it kinematically
//! could fold a held triangle over). Neighbours whose 1-ring is crushed or folded at grab time
//! are not held ([`GRAB_MISFIT_FRAC`]). The pose then travels towards its target
//! at the grip speed, never more than a per-frame travel clamp (digest-tearing §4.3 (d): handle
//! travel ≤ 2 % of L_paper per step). Within a frame the substeps interpolate the pose (lerp +
//! slerp), so a frame's motion is spread over its substeps. On release the vertices simply
//! become free: they keep the velocity the kinematic motion gave them.

use serde::{Deserialize, Serialize};

use crate::math::{Rot, V2, V3};
use crate::sheet::Sheet;
use crate::sheet::topology::NONE;

/// A tangent-plane neighbour is only held if, at grab time, its offset differs from the
/// rigidly fitted pattern offset by less than this fraction of its length: the fingers close
/// on the part of the 1-ring that is still nearly isometric, so a grab never freezes a crushed
/// or folded patch into the hand (the rest of the ring stays free).
pub const GRAB_MISFIT_FRAC: f64 = 0.05;

/// Largest number of held neighbours of one handle.
pub const MAX_NEIGHBOURS: usize = 4;

/// Where on the sheet a handle sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HandleLocation {
    /// A corner of the sheet.
    Corner,
    /// On an edge, not a corner.
    Border,
    /// Inside the sheet.
    Interior,
}

/// Which vertices a handle holds, on a given mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandleDef {
    /// The handle vertex.
    pub vertex: u32,
    /// Location class.
    pub location: HandleLocation,
    /// Number of held neighbours.
    pub num_neighbours: u8,
    /// Held neighbours (first `num_neighbours`).
    pub neighbours: [u32; MAX_NEIGHBOURS],
    /// Pattern offsets of the neighbours from the handle vertex (z = 0), metres.
    pub home_offsets: [V3; MAX_NEIGHBOURS],
}

impl HandleDef {
    /// The handle at vertex `v` of `sheet`, with its tangent-plane neighbours.
    pub fn at_vertex(sheet: &Sheet, v: u32) -> Self {
        let sp = &sheet.sp;
        let topo = &sp.topo;
        let p = sp.pattern[v as usize];
        let mut out = Self {
            vertex: v,
            location: HandleLocation::Interior,
            num_neighbours: 0,
            neighbours: [NONE; MAX_NEIGHBOURS],
            home_offsets: [V3::zeros(); MAX_NEIGHBOURS],
        };
        let push = |d: &mut Self, n: u32| {
            if (d.num_neighbours as usize) < MAX_NEIGHBOURS && !d.neighbours.contains(&n) {
                let q = sp.pattern[n as usize] - p;
                d.neighbours[d.num_neighbours as usize] = n;
                d.home_offsets[d.num_neighbours as usize] = V3::new(q.x, q.y, 0.0);
                d.num_neighbours += 1;
            }
        };
        if topo.vertex_on_boundary[v as usize] {
            // Boundary neighbours: those joined to v by a boundary edge.
            let mut bn = [NONE; 2];
            let mut nb = 0;
            for &n in topo.neighbours(v) {
                if let Some(e) = topo.find_edge(v, n)
                    && topo.edges[e as usize].is_boundary()
                    && nb < 2
                {
                    bn[nb] = n;
                    nb += 1;
                }
            }
            let (a, b) = (
                sp.pattern[bn[0] as usize] - p,
                sp.pattern[bn[1] as usize] - p,
            );
            let straight = (a.normalize().dot(&b.normalize()) + 1.0).abs() < 1e-6;
            push(&mut out, bn[0]);
            push(&mut out, bn[1]);
            if straight {
                out.location = HandleLocation::Border;
                // Inward direction: towards the sheet centre, perpendicular to the edge.
                let t = (b - a).normalize();
                let mut inward = V2::new(-t.y, t.x);
                if inward.dot(&(-p)) < 0.0 {
                    inward = -inward;
                }
                let best = topo
                    .neighbours(v)
                    .iter()
                    .copied()
                    .filter(|n| !bn.contains(n))
                    .max_by(|&m, &n| {
                        let dm = (sp.pattern[m as usize] - p).normalize().dot(&inward);
                        let dn = (sp.pattern[n as usize] - p).normalize().dot(&inward);
                        dm.total_cmp(&dn).then(n.cmp(&m))
                    });
                if let Some(n) = best {
                    push(&mut out, n);
                }
            } else {
                out.location = HandleLocation::Corner;
            }
        } else {
            for dir in [V2::x(), -V2::x(), V2::y(), -V2::y()] {
                let best = topo.neighbours(v).iter().copied().max_by(|&m, &n| {
                    let dm = (sp.pattern[m as usize] - p).normalize().dot(&dir);
                    let dn = (sp.pattern[n as usize] - p).normalize().dot(&dir);
                    dm.total_cmp(&dn).then(n.cmp(&m))
                });
                if let Some(n) = best {
                    push(&mut out, n);
                }
            }
        }
        out
    }

    /// A point handle: the vertex alone, no tangent-plane control (the crumple "hands").
    pub fn point(sheet: &Sheet, v: u32) -> Self {
        let mut d = Self::at_vertex(sheet, v);
        d.num_neighbours = 0;
        d.neighbours = [NONE; MAX_NEIGHBOURS];
        d.home_offsets = [V3::zeros(); MAX_NEIGHBOURS];
        d
    }

    /// The held neighbours.
    pub fn neighbours(&self) -> &[u32] {
        &self.neighbours[..self.num_neighbours as usize]
    }
}

/// A rigid pose: position of the handle vertex and rotation of its tangent frame (relative to
/// the flat pattern frame).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position, world metres.
    pub pos_m: [f64; 3],
    /// Rotation as a unit quaternion `[x, y, z, w]`.
    pub rot: [f64; 4],
}

impl Default for Pose {
    fn default() -> Self {
        Self {
            pos_m: [0.0; 3],
            rot: [0.0, 0.0, 0.0, 1.0],
        }
    }
}

impl Pose {
    /// A pose from a position and a rotation.
    pub fn new(pos: V3, rot: Rot) -> Self {
        let q = rot.quaternion();
        Self {
            pos_m: [pos.x, pos.y, pos.z],
            rot: [q.i, q.j, q.k, q.w],
        }
    }

    /// Position.
    pub fn pos(&self) -> V3 {
        V3::new(self.pos_m[0], self.pos_m[1], self.pos_m[2])
    }

    /// Rotation (renormalized).
    pub fn rotation(&self) -> Rot {
        let q = nalgebra::Quaternion::new(self.rot[3], self.rot[0], self.rot[1], self.rot[2]);
        if q.norm() > 0.0 && q.coords.iter().all(|c| c.is_finite()) {
            Rot::from_quaternion(q)
        } else {
            Rot::identity()
        }
    }
}

/// Largest number of vertices a hand holds (two handles with four neighbours each).
pub const MAX_HAND_VERTICES: usize = 2 * (1 + MAX_NEIGHBOURS);

/// A hand: one rigid grip over one or two handles (the two fingers of a pinch along an edge
/// hold the paper as one rigid body; a corner or a crumple point is a hand of its own).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandDef {
    /// Number of vertices held.
    pub num_vertices: u8,
    /// Number of handle vertices (they come first in `vertices`).
    pub num_mains: u8,
    /// Held vertices: the handle vertices, then their tangent-plane neighbours.
    pub vertices: [u32; MAX_HAND_VERTICES],
    /// For each held vertex, the index (in `vertices`) of the handle vertex it belongs to.
    pub main_of: [u8; MAX_HAND_VERTICES],
    /// Pattern offsets of the held vertices from the hand's reference point (z = 0), metres.
    pub home_offsets: [V3; MAX_HAND_VERTICES],
    /// Reference point: the centroid of the handle vertices in the pattern, metres.
    pub home_ref: V2,
}

impl HandDef {
    /// A hand over the given handles (1 or 2); shared neighbours are held once.
    pub fn new(sheet: &Sheet, handles: &[HandleDef]) -> Self {
        let mut d = Self {
            num_vertices: 0,
            num_mains: 0,
            vertices: [NONE; MAX_HAND_VERTICES],
            main_of: [0; MAX_HAND_VERTICES],
            home_offsets: [V3::zeros(); MAX_HAND_VERTICES],
            home_ref: V2::zeros(),
        };
        let mains = &handles[..handles.len().min(2)];
        for h in mains {
            d.home_ref += sheet.sp.pattern[h.vertex as usize] / mains.len() as f64;
        }
        let push = |d: &mut Self, v: u32, main: u8| {
            if (d.num_vertices as usize) < MAX_HAND_VERTICES && !d.vertices.contains(&v) {
                let i = d.num_vertices as usize;
                let q = sheet.sp.pattern[v as usize] - d.home_ref;
                d.vertices[i] = v;
                d.main_of[i] = main;
                d.home_offsets[i] = V3::new(q.x, q.y, 0.0);
                d.num_vertices += 1;
            }
        };
        for (m, h) in mains.iter().enumerate() {
            push(&mut d, h.vertex, m as u8);
        }
        d.num_mains = d.num_vertices;
        for (m, h) in mains.iter().enumerate() {
            for &n in h.neighbours() {
                push(&mut d, n, m as u8);
            }
        }
        d
    }

    /// The held vertices.
    pub fn vertices(&self) -> &[u32] {
        &self.vertices[..self.num_vertices as usize]
    }
}

/// The live state of one hand.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HandState {
    /// Is the hand holding the sheet?
    pub active: bool,
    /// Pose (of the reference point and the hand frame) at the end of the last frame.
    pub pose: Pose,
    /// Pose at the start of the current frame (substep interpolation).
    pub prev_pose: Pose,
    /// Local offsets of the held vertices (in the hand frame), metres, as grabbed.
    pub offsets_m: [[f64; 3]; MAX_HAND_VERTICES],
    /// Bit k set: vertex k of the hand is held (see [`GRAB_MISFIT_FRAC`]).
    pub mask: u16,
    /// Travel speed, m/s.
    pub speed_m_s: f64,
    /// The sheet pulled harder than the grip holds in the last frame: the hand gave way and
    /// does not advance towards its target in the next frame.
    pub slipping: bool,
    /// Caution after slips, (0, 1]: the fraction of its travel speed the hand uses. Halved
    /// by every slip, recovering by 10 % per frame without one, so a hand pushing against a
    /// contradiction creeps at the rate the sheet allows instead of jerking back and forth.
    pub caution: f64,
    /// The target the hand was heading for when it last gave way: while its target stays
    /// there, the hand stays where the sheet pushed it (see [`HandState::advance`]). Saves
    /// from before this field load as `None` (the hand moves on, as it did then).
    #[serde(default)]
    pub yielded_to: Option<Pose>,
    /// Direction of the hand's last slip (unit; zero before the first).
    #[serde(default)]
    pub slip_dir: [f64; 3],
    /// Fraction of the grip's give the next slip takes, (0, 1]: halved by a slip against the
    /// last one's direction, grown again by slips that go on the same way, reset when the
    /// hand heads for a new target (see `GestureRig::apply_slip`). Saves from before it load
    /// with 1.
    #[serde(default = "full_slip_gain")]
    pub slip_gain: f64,
    /// The hand gave way in the last frame: its fingers slide, and sliding fingers hold less
    /// than still ones (kinetic against static friction, `GestureRig::apply_slip`). Saves
    /// from before it load as still.
    #[serde(default)]
    pub sliding: bool,
}

fn full_slip_gain() -> f64 {
    1.0
}

impl HandState {
    /// Takes hold of the sheet where it is: the pose is fitted to the current positions of the
    /// held vertices; tangent-plane neighbours that are not nearly isometric to their handle
    /// vertex are left free.
    pub fn grab(def: &HandDef, pos: &[V3], speed_m_s: f64) -> Self {
        let n = def.num_vertices as usize;
        let nm = def.num_mains as usize;
        let mut reference = V3::zeros();
        for &v in &def.vertices[..nm] {
            reference += pos[v as usize] / nm as f64;
        }
        let rot = fit_frame(def, pos, &reference);
        let inv = rot.inverse();
        let mut offsets = [[0.0; 3]; MAX_HAND_VERTICES];
        let mut mask = 0u16;
        for k in 0..n {
            let o = inv * (pos[def.vertices[k] as usize] - reference);
            offsets[k] = [o.x, o.y, o.z];
        }
        for k in 0..n {
            if k < nm {
                mask |= 1 << k;
                continue;
            }
            let m = def.main_of[k] as usize;
            let rel = V3::from(offsets[k]) - V3::from(offsets[m]);
            let home = def.home_offsets[k] - def.home_offsets[m];
            if (rel - home).norm() <= GRAB_MISFIT_FRAC * home.norm() {
                mask |= 1 << k;
            }
        }
        let pose = Pose::new(reference, rot);
        Self {
            active: true,
            pose,
            prev_pose: pose,
            offsets_m: offsets,
            mask,
            speed_m_s,
            slipping: false,
            caution: 1.0,
            yielded_to: None,
            slip_dir: [0.0; 3],
            slip_gain: 1.0,
            sliding: false,
        }
    }

    /// True if vertex `k` of the hand is held.
    pub fn holds(&self, k: usize) -> bool {
        self.mask & (1 << k) != 0
    }

    /// Moves the pose one frame towards `target`, at most `min(speed × dt, clamp_m)` of travel
    /// (scaled by the caution after slips) and `max_angle_rad` of rotation. Returns true if
    /// anything moved.
    ///
    /// A hand that gave way (the sheet pulled harder than its grip) stays where the sheet
    /// pushed it for as long as its target stays put: it settles where the pull is within its
    /// grip, as a hand holding a crumpled ball does. It moves on when the target moves (a
    /// gesture changes). A hand that crept back towards the same target was pushed out again
    /// every few frames, and a held ball never came to rest (docs/decisions.md, "Hands, grip
    /// and obstacles").
    pub fn advance(&mut self, target: &Pose, dt_s: f64, clamp_m: f64, max_angle_rad: f64) -> bool {
        self.prev_pose = self.pose;
        if self.slipping {
            self.slipping = false;
            self.caution = (self.caution * 0.5).max(1.0 / 64.0);
            self.yielded_to = Some(*target);
            return true;
        }
        if let Some(t) = self.yielded_to {
            if same_pose(&t, target) {
                return false;
            }
            self.yielded_to = None;
            self.slip_gain = 1.0;
        }
        self.caution = (self.caution * 1.1).min(1.0);
        let max_step = (self.speed_m_s * dt_s).min(clamp_m) * self.caution;
        let p = self.pose.pos();
        let d = target.pos() - p;
        let dn = d.norm();
        let mut moved = false;
        let new_p = if dn <= max_step {
            moved |= dn > 0.0;
            target.pos()
        } else {
            moved = true;
            p + d * (max_step / dn)
        };
        let r0 = self.pose.rotation();
        let r1 = target.rotation();
        let ang = r0.angle_to(&r1);
        let new_r = if ang <= max_angle_rad {
            moved |= ang > 0.0;
            r1
        } else {
            moved = true;
            r0.slerp(&r1, max_angle_rad / ang)
        };
        self.pose = Pose::new(new_p, new_r);
        // A rotation already at its target can still read a rounding error's angle: only a
        // pose that changed counts as motion (else a held twist never lets the sheet sleep).
        moved && !same_pose(&self.prev_pose, &self.pose)
    }

    /// Re-anchors the hand where the sheet is now (after a reset, or when a hand that was
    /// overridden by the crumple hands takes its vertices back).
    pub fn reanchor(&mut self, def: &HandDef, pos: &[V3]) {
        let s = Self::grab(def, pos, self.speed_m_s);
        *self = s;
    }

    /// True if the hand has not moved in the current frame (within [`SAME_POSE_M`] and
    /// [`SAME_POSE_RAD`]).
    pub fn is_still(&self) -> bool {
        same_pose(&self.prev_pose, &self.pose)
    }

    /// Position of held vertex `k` at fraction `s` ∈ [0, 1] of the current frame.
    pub fn held_position(&self, k: usize, s: f64) -> V3 {
        let p = self.prev_pose.pos().lerp(&self.pose.pos(), s);
        let r = self.prev_pose.rotation().slerp(&self.pose.rotation(), s);
        p + r * V3::from(self.offsets_m[k])
    }
}

/// True if two poses are the same within [`SAME_POSE_M`] of travel and [`SAME_POSE_RAD`] of
/// rotation (a target recomputed from unchanged gestures).
fn same_pose(a: &Pose, b: &Pose) -> bool {
    (a.pos() - b.pos()).norm() <= SAME_POSE_M
        && a.rotation().angle_to(&b.rotation()) <= SAME_POSE_RAD
}

/// Travel below which a hand's target counts as unchanged, metres.
pub const SAME_POSE_M: f64 = 1e-7;
/// Rotation below which a hand's target counts as unchanged, radians.
pub const SAME_POSE_RAD: f64 = 1e-6;

/// Rotation that best maps the pattern offsets of the held vertices onto their current
/// offsets from `reference` (Kabsch: closest rotation to the 3×3 covariance), with a normal
/// term so that a hand holding a nearly collinear set is still well determined.
fn fit_frame(def: &HandDef, pos: &[V3], reference: &V3) -> Rot {
    let n = def.num_vertices as usize;
    let mut cov = nalgebra::Matrix3::<f64>::zeros();
    let mut cur_n = V3::zeros();
    let mut scale: f64 = 0.0;
    for k in 0..n {
        let a = def.home_offsets[k];
        let b = pos[def.vertices[k] as usize] - reference;
        cov += b * a.transpose();
        scale = scale.max(a.norm());
        for k2 in k + 1..n {
            let a2 = def.home_offsets[k2];
            let s = a.cross(&a2).z;
            if s.abs() <= 1e-12 * a.norm_squared().max(a2.norm_squared()) {
                continue;
            }
            let b2 = pos[def.vertices[k2] as usize] - reference;
            cur_n += b.cross(&b2) * s.signum();
        }
    }
    let nl = cur_n.norm();
    if nl > 0.0 && scale > 0.0 {
        cov += (cur_n / nl) * V3::z().transpose() * scale;
    }
    let r = nalgebra::Rotation3::from_matrix_eps(&cov, 1e-12, 50, nalgebra::Rotation3::identity());
    if r.matrix().iter().all(|c| c.is_finite()) {
        Rot::from_rotation_matrix(&r)
    } else {
        Rot::identity()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::SheetSize;
    use crate::sheet::MeshConfig;

    fn sheet() -> Sheet {
        Sheet::new_flat(SheetSize::A4, MeshConfig::default(), 0.75, 0.1)
    }

    #[test]
    fn neighbour_counts_follow_location() {
        let s = sheet();
        let corner = s.nearest_vertex(V2::new(-0.105, -0.1485), true);
        let border = s.nearest_vertex(V2::new(0.0, 0.1485), true);
        let inner = s.nearest_vertex(V2::new(0.0, 0.0), false);
        let dc = HandleDef::at_vertex(&s, corner);
        let db = HandleDef::at_vertex(&s, border);
        let di = HandleDef::at_vertex(&s, inner);
        assert_eq!(
            (dc.location, dc.num_neighbours),
            (HandleLocation::Corner, 2)
        );
        assert_eq!(
            (db.location, db.num_neighbours),
            (HandleLocation::Border, 3)
        );
        assert_eq!(
            (di.location, di.num_neighbours),
            (HandleLocation::Interior, 4)
        );
        // The border handle's third neighbour is inward (towards −y from the back edge).
        assert!(db.home_offsets[2].y < 0.0);
        // Neighbours of the corner span a plane.
        assert!(dc.home_offsets[0].cross(&dc.home_offsets[1]).norm() > 1e-6);
    }

    #[test]
    fn grab_does_not_move_the_sheet_and_pose_tracks_target_rigidly() {
        let s = sheet();
        let va = s.nearest_vertex(V2::new(-0.05, -0.1485), true);
        let vb = s.nearest_vertex(V2::new(0.05, -0.1485), true);
        let hand = HandDef::new(
            &s,
            &[HandleDef::at_vertex(&s, va), HandleDef::at_vertex(&s, vb)],
        );
        assert_eq!(hand.num_mains, 2);
        assert!(hand.num_vertices >= 7);
        // Bend the sheet a little before grabbing.
        let mut pos = s.sp.pos.clone();
        let r = nalgebra::Rotation3::from_euler_angles(0.2, 0.1, -0.3);
        for p in &mut pos {
            *p = r * (*p - V3::new(0.0, 0.0, 0.75)) + V3::new(0.01, 0.0, 0.8);
        }
        let mut h = HandState::grab(&hand, &pos, 1.0);
        for k in 0..hand.num_vertices as usize {
            assert!(h.holds(k), "a rigidly moved sheet is held everywhere");
            let p = h.held_position(k, 1.0);
            assert!(
                (p - pos[hand.vertices[k] as usize]).norm() < 1e-9,
                "grab moved vertex {k}"
            );
        }
        // Travel towards a target 10 cm up with the identity frame: clamped per frame.
        let target = Pose::new(h.pose.pos() + V3::new(0.0, 0.0, 0.1), Rot::identity());
        let mut frames = 0;
        while h.advance(&target, 0.005, 0.006, 0.05) {
            let step = (h.pose.pos() - h.prev_pose.pos()).norm();
            assert!(step <= 0.005 + 1e-12);
            frames += 1;
            assert!(frames < 1000);
        }
        assert!((h.pose.pos() - target.pos()).norm() < 1e-12);
        // The held vertices are a rigid motion of the grab; with the identity frame they are
        // at their pattern offsets (the sheet was only moved rigidly before the grab).
        for k in 0..hand.num_vertices as usize {
            let off = h.held_position(k, 1.0) - h.pose.pos();
            let err = (off - hand.home_offsets[k]).norm();
            assert!(err < 1e-7, "vertex {k}: {err}");
        }
        // A crushed neighbour is left free.
        let mut crushed = s.sp.pos.clone();
        let k = hand.num_mains as usize; // first neighbour
        let n0 = hand.vertices[k] as usize;
        let m = hand.vertices[hand.main_of[k] as usize] as usize;
        crushed[n0] = crushed[m] + (crushed[n0] - crushed[m]) * 0.5;
        let h2 = HandState::grab(&hand, &crushed, 1.0);
        assert!(!h2.holds(k) && h2.holds(k + 1) && h2.holds(0));
    }

    /// A hand that gave way stays where the sheet pushed it while its target stays put (it
    /// does not creep back into the same push), and moves on when the target moves.
    #[test]
    fn a_hand_that_gave_way_stays_until_its_target_moves() {
        let s = sheet();
        let v = s.nearest_vertex(V2::new(0.0, 0.0), false);
        let hand = HandDef::new(&s, &[HandleDef::at_vertex(&s, v)]);
        let mut h = HandState::grab(&hand, &s.sp.pos, 1.0);
        let target = Pose::new(h.pose.pos() + V3::new(0.0, 0.0, -0.002), h.pose.rotation());
        // Pushed 1 mm away from the target (what `GestureRig::apply_slip` does).
        h.pose = Pose::new(h.pose.pos() + V3::new(0.0, 0.0, 0.001), h.pose.rotation());
        h.slipping = true;
        let pushed = h.pose;
        assert!(
            h.advance(&target, 0.005, 0.006, 0.05),
            "the slip frame counts as motion"
        );
        for _ in 0..50 {
            assert!(!h.advance(&target, 0.005, 0.006, 0.05));
            assert_eq!(
                h.pose, pushed,
                "the hand crept back towards the same target"
            );
        }
        // A target recomputed with rounding noise is the same target.
        let noisy = Pose::new(target.pos() + V3::new(1e-9, 0.0, 0.0), target.rotation());
        assert!(!h.advance(&noisy, 0.005, 0.006, 0.05));
        // A gesture moves the target: the hand moves on (at its cautious speed) and reaches it.
        let moved = Pose::new(target.pos() + V3::new(0.001, 0.0, 0.0), target.rotation());
        let mut frames = 0;
        while h.advance(&moved, 0.005, 0.006, 0.05) {
            frames += 1;
            assert!(frames < 1000);
        }
        assert!((h.pose.pos() - moved.pos()).norm() < 1e-12);
        assert_eq!(h.yielded_to, None);
    }
}
