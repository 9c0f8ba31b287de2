//! # Collisions with the room: floor, table top and wall, with Coulomb friction
//!
//! The seeds handle collisions on S_P only, with a BVH, impact zones and repulsion springs
//! (P 442–447, T 712), and call that module "neither really efficient nor accurate" (T 1243).
//! Our obstacles are the rigid planes of the room ([`crate::room`]): the floor z = 0 (always),
//! the table top (if on) and the wall (if on). Against a half-space a vertex test is one dot
//! product, so no broad phase is needed; parry3d's `HalfSpace` would only wrap the same
//! arithmetic (its contact query is used in a test as a cross-check). Sheet–sheet contact is
//! [`crate::physics::sheet_contact`].
//!
//! **Normal response** is a one-sided quadratic penalty inside the implicit step's energy, so
//! the Newton solver sees the obstacle (a sheet pressed on the table by the hands bends instead
//! of penetrating):
//!
//! ```text
//! E_c(x) = ½ k_i · max(0, s − d(x))²,   k_i = m_i ω_c²,   s = g / ω_c²
//! ```
//!
//! with d the signed distance to the plane. Scaling the penalty with the vertex mass makes the
//! contact frequency ω_c the same everywhere (conditioning independent of the mesh), and the
//! skin s makes a vertex resting under gravity sit exactly on the plane (k_i(s − d) = m_i g at
//! d = 0).
//!
//! **Friction** is Coulomb friction in the lagged, smoothed form of incremental-potential
//! contact (Li et al. 2020): at the start of a substep each contact's normal force
//! `λ_i = k_i (s − d_i)` is frozen, and the tangential displacement `u = P_T (x − x_n)` over the
//! substep is resisted by the dissipation potential `μ λ_i f₀(|u|)`, where f₀ is |u| smoothed
//! below `ε_u = ε_v h` (ε_v = [`STICK_SPEED_M_S`]). Below that slip speed friction acts as a
//! very stiff viscous drag (static friction up to creep of a few mm/s); above it, the force
//! is exactly μλ against the slip. The slip speed per vertex (tangential speed relative to
//! the obstacle, m/s) is what the friction sound uses (T 1770).
//!
//! **Depth limit.** A penalty yields in proportion to the force: a corner pressed into the
//! table by a sheet that hands twist or pull down (seconds-long forces of newtons, far above
//! its weight) sank up to 6 mm in `c2_moebius_twist`. Beyond [`MAX_PENETRATION_M`]
//! the penalty is [`HARD_CONTACT_FACTOR`] = 30 times stiffer (inside the implicit step's
//! energy, so the solver lets the sheet give way elsewhere), and after every substep a free
//! vertex still deeper is put back at that depth and loses the normal velocity with which it
//! moves into the plane (relative to a moving plane): the table is rigid. The hard stage must
//! hold a pressed vertex close to the limit by itself: putting a vertex back moves it away
//! from the implicit step's equilibrium, and the next step pushes it in again. But a stiffer
//! stage is a sharper kink in the energy for the Newton solver. 30 is where both hold: at 10 a
//! held ball was put back every frame and never came to rest, at 100 Newton stalled at its
//! iteration cap (docs/decisions.md, "Obstacle depth limit: a ×30 hard stage").
//!
//! Shallower contacts keep the penalty's compliance, whose depth is the normal force that
//! friction uses. Held vertices follow their hands (whose targets are kept out of the planes
//! by the gesture rig). The step (`Sim::limit_penetration`) leaves out the vertices of a
//! triangle that putting back would turn over: they stay a little deeper, the facet keeps its
//! orientation.
//!
//! **Moving obstacles.** A command that moves or switches on a plane must not teleport it
//! through the sheet (a penalty would then explode). Each obstacle's *effective* plane offset
//! eases towards the configured one at [`OBSTACLE_EASE_SPEED_M_S`]; a plane that is switched on
//! starts just outside the sheet's current extent and sweeps to its place, pushing the sheet
//! out smoothly.

use crate::math::V3;
use crate::room::RoomConfig;
use crate::sound_input::Obstacle;

/// Contact frequency ω_c of the penalty, rad/s.
pub const CONTACT_OMEGA_RAD_S: f64 = 4000.0;
/// Slip speed below which friction behaves as viscous sticking, m/s.
pub const STICK_SPEED_M_S: f64 = 2e-3;
/// Speed at which a moved or switched-on obstacle plane travels to its new place, m/s.
pub const OBSTACLE_EASE_SPEED_M_S: f64 = 0.5;
/// Skin: penalty activation distance, metres (`g / ω_c²`).
pub const CONTACT_SKIN_M: f64 =
    crate::math::GRAVITY_M_S2 / (CONTACT_OMEGA_RAD_S * CONTACT_OMEGA_RAD_S);
/// Depth beyond which the contact penalty stiffens, and deepest a free vertex may sink into an
/// obstacle after a substep, metres (see "Depth limit").
pub const MAX_PENETRATION_M: f64 = 5e-4;
/// Stiffness of the contact penalty beyond [`MAX_PENETRATION_M`], as a multiple of k_i (see
/// "Depth limit" for the choice of 30).
pub const HARD_CONTACT_FACTOR: f64 = 30.0;
/// Distance under which a vertex counts as touching an obstacle (for the contact report), m.
pub const TOUCH_DIST_M: f64 = 4.0 * CONTACT_SKIN_M + 1e-4;

/// One rigid plane obstacle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneObstacle {
    /// Which obstacle.
    pub kind: Obstacle,
    /// Is it present?
    pub active: bool,
    /// Unit normal into free space.
    pub normal: V3,
    /// Current (effective) offset: the plane is `{x : x·n = offset}`, metres.
    pub offset_m: f64,
    /// Configured offset the effective one eases to, metres.
    pub target_offset_m: f64,
    /// Normal velocity of the plane during the current frame, m/s.
    pub speed_m_s: f64,
}

impl PlaneObstacle {
    /// Signed distance of `p` (positive in free space), metres.
    #[inline]
    pub fn distance(&self, p: &V3) -> f64 {
        p.dot(&self.normal) - self.offset_m
    }
}

/// Number of obstacles (floor, table, wall).
pub const NUM_OBSTACLES: usize = 3;

/// The room's obstacles in a fixed order: floor, table, wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Obstacles {
    /// The planes.
    pub planes: [PlaneObstacle; NUM_OBSTACLES],
}

impl Obstacles {
    /// Obstacles of a room, already at their configured places.
    pub fn new(room: &RoomConfig) -> Self {
        let mut o = Self {
            planes: [
                PlaneObstacle {
                    kind: Obstacle::Floor,
                    active: true,
                    normal: V3::z(),
                    offset_m: 0.0,
                    target_offset_m: 0.0,
                    speed_m_s: 0.0,
                },
                PlaneObstacle {
                    kind: Obstacle::Table,
                    active: false,
                    normal: V3::z(),
                    offset_m: 0.0,
                    target_offset_m: 0.0,
                    speed_m_s: 0.0,
                },
                PlaneObstacle {
                    kind: Obstacle::Wall,
                    active: false,
                    normal: -V3::y(),
                    offset_m: 0.0,
                    target_offset_m: 0.0,
                    speed_m_s: 0.0,
                },
            ],
        };
        o.set_room(room, &[]);
        for p in &mut o.planes {
            p.offset_m = p.target_offset_m;
        }
        o
    }

    /// Applies a new room. Planes that appear start just outside `positions` (the sheet) and
    /// ease in; planes that move ease to the new offset.
    pub fn set_room(&mut self, room: &RoomConfig, positions: &[V3]) {
        let room = room.sanitized();
        let table = room.table_plane();
        let wall = room.wall_plane();
        for (i, pl) in [(1usize, table), (2usize, wall)] {
            let p = &mut self.planes[i];
            match pl {
                Some(plane) => {
                    let n = V3::new(plane.normal[0], plane.normal[1], plane.normal[2]);
                    let target = n.dot(&V3::new(
                        plane.point_m[0],
                        plane.point_m[1],
                        plane.point_m[2],
                    ));
                    if !p.active {
                        // Start just below the lowest sheet vertex (on the solid side).
                        let min_d = positions
                            .iter()
                            .map(|x| x.dot(&n))
                            .fold(f64::INFINITY, f64::min);
                        p.offset_m = if min_d.is_finite() {
                            target.min(min_d - 2.0 * CONTACT_SKIN_M)
                        } else {
                            target
                        };
                    }
                    p.active = true;
                    p.normal = n;
                    p.target_offset_m = target;
                }
                None => {
                    // An absent plane has no place: it keeps none (so a saved and restored
                    // room is the same room) and does not ease.
                    p.active = false;
                    p.offset_m = 0.0;
                    p.target_offset_m = 0.0;
                    p.speed_m_s = 0.0;
                }
            }
        }
    }

    /// Moves every active plane that has part of `positions` on its solid side back until the
    /// whole set is outside (the plane then eases in). Used when a new sheet appears (new sim,
    /// reset, size change) in a room whose wall cuts through the sheet's home place.
    pub fn fit_outside(&mut self, positions: &[V3]) {
        for p in &mut self.planes {
            if !p.active {
                continue;
            }
            let min_d = positions
                .iter()
                .map(|x| p.distance(x))
                .fold(f64::INFINITY, f64::min);
            if min_d.is_finite() && min_d < 0.0 {
                p.offset_m += min_d - 2.0 * CONTACT_SKIN_M;
            }
        }
    }

    /// Puts every free vertex deeper than [`MAX_PENETRATION_M`] inside an active plane back at
    /// that depth and removes its velocity into the plane (see "Depth limit" in the module
    /// doc). `fixed` marks held vertices (left alone). Returns the number of vertices moved.
    pub fn limit_penetration(&self, pos: &mut [V3], vel: &mut [V3], fixed: &[bool]) -> usize {
        let mut moved = 0;
        for pl in self.planes.iter().filter(|p| p.active) {
            for ((x, v), &held) in pos.iter_mut().zip(vel.iter_mut()).zip(fixed) {
                let d = pl.distance(x);
                if held || d >= -MAX_PENETRATION_M {
                    continue;
                }
                *x += pl.normal * (-MAX_PENETRATION_M - d);
                let vn = v.dot(&pl.normal) - pl.speed_m_s;
                if vn < 0.0 {
                    *v -= pl.normal * vn;
                }
                moved += 1;
            }
        }
        moved
    }

    /// Moves each present plane towards its target by at most the ease speed × `dt_s`.
    /// Returns true if any plane moved.
    pub fn ease(&mut self, dt_s: f64) -> bool {
        let mut moved = false;
        for p in self.planes.iter_mut().filter(|p| p.active) {
            let d = p.target_offset_m - p.offset_m;
            let max = OBSTACLE_EASE_SPEED_M_S * dt_s;
            let step = d.clamp(-max, max);
            p.speed_m_s = if dt_s > 0.0 { step / dt_s } else { 0.0 };
            if step != 0.0 {
                p.offset_m += step;
                moved = true;
            }
        }
        moved
    }

    /// True while some plane has not reached its configured place.
    pub fn is_moving(&self) -> bool {
        self.planes
            .iter()
            .any(|p| p.active && p.offset_m != p.target_offset_m)
    }

    /// Active planes.
    pub fn active(&self) -> impl Iterator<Item = &PlaneObstacle> {
        self.planes.iter().filter(|p| p.active)
    }

    /// Pushes a point out of every active plane (to distance `margin_m`). Used for kinematic
    /// handle targets, which no physics pushes out.
    pub fn push_out(&self, p: &mut V3, margin_m: f64) {
        for pl in self.active() {
            let d = pl.distance(p);
            if d < margin_m {
                *p += pl.normal * (margin_m - d);
            }
        }
    }
}

/// The contact state of one vertex after a frame (for the sound engine).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexContact {
    /// True if the vertex touches an obstacle.
    pub in_contact: bool,
    /// What it touches (meaningful when `in_contact`).
    pub obstacle: Obstacle,
    /// Tangential speed relative to the obstacle, m/s.
    pub slip_speed_m_s: f32,
    /// Normal force, N.
    pub normal_force_n: f32,
}

/// Contact-energy terms of one vertex against one plane, frozen at the start of a substep.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LaggedContact {
    /// Obstacle index (into [`Obstacles::planes`]), or `u8::MAX` for none.
    pub plane: u8,
    /// Frozen normal force λ, N.
    pub lambda_n: f64,
}

/// Penalty stiffness of a vertex of mass `m_kg`, N/m.
#[inline]
pub fn penalty_stiffness(m_kg: f64) -> f64 {
    m_kg * CONTACT_OMEGA_RAD_S * CONTACT_OMEGA_RAD_S
}

/// Smoothed friction magnitude f₁(y) = d f₀ / dy with y = |u| / ε_u (IPC, Li et al. 2020).
#[inline]
pub fn friction_f1(y: f64) -> f64 {
    if y >= 1.0 { 1.0 } else { y * (2.0 - y) }
}

/// Smoothed friction potential f₀(|u|) with ε_u, metres.
#[inline]
pub fn friction_f0(u: f64, eps_u: f64) -> f64 {
    if u >= eps_u {
        u
    } else {
        let y = u / eps_u;
        eps_u * (-y * y * y / 3.0 + y * y + 1.0 / 3.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn room_planes_and_easing() {
        let room = RoomConfig::default();
        let mut o = Obstacles::new(&room);
        assert!(o.planes[1].active && !o.planes[2].active);
        assert!((o.planes[1].offset_m - 0.75).abs() < 1e-12);
        // Switch the wall on at 2 cm while a sheet spans y ∈ [−0.15, 0.15]: it starts behind
        // the sheet and eases in.
        let sheet = [V3::new(0.0, -0.15, 0.75), V3::new(0.0, 0.15, 0.75)];
        let mut r2 = room;
        r2.wall = true;
        r2.wall_dist_cm = 2.0;
        o.set_room(&r2, &sheet);
        let wall = o.planes[2];
        assert!(wall.active);
        assert!(
            wall.distance(&sheet[1]) > 0.0,
            "wall starts outside the sheet"
        );
        assert!((wall.target_offset_m + 0.02).abs() < 1e-12);
        let mut frames = 0;
        while o.is_moving() {
            o.ease(0.005);
            frames += 1;
            assert!(frames < 1000);
        }
        assert!((o.planes[2].distance(&V3::new(0.0, 0.02, 0.0))).abs() < 1e-12);
        assert!(frames > 10, "eased over several frames");
    }

    /// A wall switched off while it eases in is gone: it moves no more (it would keep the
    /// sheet awake and the pass-through guard off) and is the same as in a room built without
    /// it (so a sheet saved and restored there continues identically).
    #[test]
    fn a_plane_switched_off_while_easing_stops_and_keeps_no_place() {
        let sheet = [V3::new(0.0, -0.15, 0.75), V3::new(0.0, 0.15, 0.75)];
        let room = RoomConfig {
            wall: true,
            wall_dist_cm: 2.0,
            ..RoomConfig::default()
        };
        let mut o = Obstacles::new(&RoomConfig::default());
        o.set_room(&room, &sheet);
        assert!(o.ease(0.005) && o.is_moving(), "the wall eases in");
        let off = RoomConfig {
            wall: false,
            ..room
        };
        o.set_room(&off, &sheet);
        assert!(!o.ease(0.005), "an absent wall does not move");
        assert!(!o.is_moving());
        assert_eq!(o.planes, Obstacles::new(&off).planes);
    }

    #[test]
    fn distance_agrees_with_parry_halfspace() {
        use parry3d::math::{Pose, Vector};
        use parry3d::query::PointQuery;
        use parry3d::shape::HalfSpace;
        let o = Obstacles::new(&RoomConfig::default());
        let table = o.planes[1];
        let hs = HalfSpace::new(Vector::new(0.0, 0.0, 1.0));
        let pose = Pose::translation(0.0, 0.0, table.offset_m as f32);
        for p in [V3::new(0.1, 0.2, 0.8), V3::new(-0.3, 0.0, 0.7)] {
            let q = Vector::new(p.x as f32, p.y as f32, p.z as f32);
            let proj = hs.project_point(&pose, q, false);
            let d_parry = if proj.is_inside {
                -(q - proj.point).length()
            } else {
                (q - proj.point).length()
            };
            assert!((f64::from(d_parry) - table.distance(&p)).abs() < 1e-5);
        }
    }

    #[test]
    fn friction_potential_is_smooth() {
        let e = 1e-5;
        assert!((friction_f0(e, e) - e).abs() < 1e-18);
        assert!((friction_f0(0.0, e) - e / 3.0).abs() < 1e-18);
        // f1 is the derivative of f0 (in units of y).
        let u = 0.4 * e;
        let d = 1e-9 * e;
        let fd = (friction_f0(u + d, e) - friction_f0(u - d, e)) / (2.0 * d);
        assert!((fd - friction_f1(u / e)).abs() < 1e-6);
    }

    /// A free vertex 6 mm inside the table comes back to the depth limit and stops moving
    /// into it (keeping its tangential velocity); a vertex within the limit, a held vertex and
    /// a vertex above the table are left alone.
    #[test]
    fn a_deep_free_vertex_is_put_back_at_the_depth_limit() {
        let o = Obstacles::new(&RoomConfig::default());
        let top = o.planes[1].offset_m;
        let mut pos = vec![
            V3::new(0.0, 0.0, top - 0.006),
            V3::new(0.1, 0.0, top - 0.0002),
            V3::new(0.2, 0.0, top - 0.006),
            V3::new(0.3, 0.0, top + 0.01),
        ];
        let mut vel = vec![V3::new(0.3, 0.0, -0.5); 4];
        let fixed = [false, false, true, false];
        let before = (pos.clone(), vel.clone());
        assert_eq!(o.limit_penetration(&mut pos, &mut vel, &fixed), 1);
        assert!((o.planes[1].distance(&pos[0]) + MAX_PENETRATION_M).abs() < 1e-12);
        assert_eq!(vel[0], V3::new(0.3, 0.0, 0.0));
        assert_eq!(&pos[1..], &before.0[1..]);
        assert_eq!(&vel[1..], &before.1[1..]);
    }
}
