//! # The sheet slapping the table (beyond the seeds)
//!
//! The seeds hear a sudden change of shape or connectivity as a "clac" (T 1247, T 1261) and make
//! one only where the geometry layer creates a singular vertex. A sheet shaken by an edge that
//! lies on the table, or a flap dropped onto it, changes its contact suddenly — real paper
//! slaps — and made no sound (issue 52: a table shake at −78.7 dBFS). This source turns the
//! table's sudden stop of the sheet into one clac per frame:
//!
//! ```text
//! v_n,i = −(v_start,i · n_o − u_o)  for each vertex i touching a plane o (table, floor,
//!                                  wall), not held; n_o the plane's normal, u_o its own
//!                                  speed along it (a wall moved by the room)
//! I     = Σ_{v_n,i > v_min} A_i v_n,i                        (area × approach speed, m³/s)
//! amplitude = min(I / (A_ref v_ref), 4),  A_ref = 5 × 5 cm, v_ref = 1 m/s
//! ```
//!
//! played by the database's constrained (0, 0) cell at the impacting patch (the centroid
//! weighted by A_i v_n,i, the plane's normal, the radius of the disk of the impacting area);
//! one clac per plane hit in the frame.
//!
//! Decisions, one line each:
//! - **Approach speed from the frame's start velocities** (which the saved sheet holds): the
//!   penalty contact stops a vertex within ~1.6 ms (ω_c = 4000 rad/s), so a vertex that touches
//!   at the end of a frame it started approaching at v_n is an impact of this frame, and the
//!   next frame starts near rest: one event per slap with no history of its own to save.
//! - **v_min = 5 cm/s**: a sheet resting, sliding or pressed by the hands has |v_z| of mm/s, and
//!   a sheet settling after a gesture below it; a flap slapped by a shake reaches 0.2–1 m/s.
//! - **The planes only**: the table, the floor and the wall, whose normals the simulation
//!   passes in (without them the table and the floor face up and the wall is not heard). The
//!   sheet's own layers are left out: two layers have no normal of their own, and the layers
//!   have no friction yet. The approach is relative to the plane, so a sheet following a wall
//!   that recedes, or pushed by one that advances, does not clap.
//! - **Amplitude on the clacs' scale** (their amplitude is a summed dihedral in radians, up to 4):
//!   a 10 × 10 cm flap slapping at 0.5 m/s is a clac of amplitude 2.

use crate::collision::{PlaneObstacle, VertexContact};
use crate::math::V3;
use crate::sheet::physical::PhysMesh;
use crate::sound_input::{CrumpleEvent, Obstacle, Resonator};

/// Slowest approach that counts as an impact, m/s.
pub const IMPACT_MIN_SPEED_M_S: f64 = 0.05;
/// Reference impact: this area…, m².
pub const IMPACT_REF_AREA_M2: f64 = 25e-4;
/// …arriving at this speed has amplitude 1, m/s.
pub const IMPACT_REF_SPEED_M_S: f64 = 1.0;
/// Largest impact amplitude (the clacs' cap).
pub const MAX_IMPACT_AMPLITUDE: f64 = 4.0;

/// Obstacles a sheet can slap, in the order of their events.
const PLANE_KINDS: [Obstacle; 3] = [Obstacle::Table, Obstacle::Floor, Obstacle::Wall];

/// The frame's impacts on the planes, one per plane hit (module doc), into `out` (at most 3).
/// Returns how many. No allocation.
pub fn impact_events(
    sp: &PhysMesh,
    vel_start: &[V3],
    contacts: &[VertexContact],
    held: &[bool],
    planes: &[PlaneObstacle],
    out: &mut [Option<CrumpleEvent>; 3],
) -> usize {
    let mut n = 0;
    for kind in PLANE_KINDS {
        let (normal, speed) = match planes.iter().find(|p| p.kind == kind) {
            Some(p) => (p.normal, p.speed_m_s),
            None if kind == Obstacle::Wall => continue,
            None => (V3::z(), 0.0),
        };
        out[n] = impact_on(sp, vel_start, contacts, held, kind, normal, speed);
        if out[n].is_some() {
            n += 1;
        }
    }
    n
}

/// The frame's impact on the plane `kind` of unit `normal` moving at `speed_m_s` along it, if
/// the sheet hit it.
fn impact_on(
    sp: &PhysMesh,
    vel_start: &[V3],
    contacts: &[VertexContact],
    held: &[bool],
    kind: Obstacle,
    normal: V3,
    speed_m_s: f64,
) -> Option<CrumpleEvent> {
    let n = sp.num_vertices();
    if vel_start.len() != n || contacts.len() < n || held.len() < n || sp.vertex_area_m2.len() != n
    {
        return None;
    }
    let (mut sum, mut area, mut centre) = (0.0f64, 0.0f64, V3::zeros());
    for i in 0..n {
        let c = contacts[i];
        if !c.in_contact || held[i] || c.obstacle != kind {
            continue;
        }
        let v_n = speed_m_s - vel_start[i].dot(&normal);
        if v_n.is_nan() || v_n <= IMPACT_MIN_SPEED_M_S || !v_n.is_finite() {
            continue;
        }
        let a = sp.vertex_area_m2[i];
        let w = a * v_n;
        if !w.is_finite() {
            continue;
        }
        sum += w;
        area += a;
        centre += sp.pos[i] * w;
    }
    if sum.is_nan() || sum <= 0.0 {
        return None;
    }
    let centre = centre / sum;
    let amplitude = (sum / (IMPACT_REF_AREA_M2 * IMPACT_REF_SPEED_M_S)).min(MAX_IMPACT_AMPLITUDE);
    let radius_m = (area / std::f64::consts::PI).sqrt();
    Some(CrumpleEvent {
        amplitude: amplitude as f32,
        resonator: Resonator {
            // The impacting patch's size as its (unused) ruling length; l_c = 0: constrained.
            lr_cm: (200.0 * radius_m) as f32,
            lc_cm: 0.0,
            centre_m: [centre.x as f32, centre.y as f32, centre.z as f32],
            normal: [normal.x as f32, normal.y as f32, normal.z as f32],
            radius_m: radius_m as f32,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::pattern::lattice;

    fn flat_sheet() -> PhysMesh {
        PhysMesh::from_pattern(&lattice(0.2, 0.1, 0.025), 0.0, 0.08).unwrap()
    }

    /// The first impact of the frame with no planes given (the table and the floor face up).
    fn impact_event(
        sp: &PhysMesh,
        vel: &[V3],
        contacts: &[VertexContact],
        held: &[bool],
    ) -> Option<CrumpleEvent> {
        let mut out = [None; 3];
        impact_events(sp, vel, contacts, held, &[], &mut out);
        out[0]
    }

    /// A flat sheet, every vertex touching `obstacle`, none held: (sheet, vertex count,
    /// contacts, held flags).
    fn on_obstacle(obstacle: Obstacle) -> (PhysMesh, usize, Vec<VertexContact>, Vec<bool>) {
        let sp = flat_sheet();
        let n = sp.num_vertices();
        (sp, n, vec![on(obstacle); n], vec![false; n])
    }

    fn on(obstacle: Obstacle) -> VertexContact {
        VertexContact {
            in_contact: true,
            obstacle,
            ..VertexContact::default()
        }
    }

    #[test]
    fn a_sheet_landing_flat_is_one_impact_linear_in_its_speed() {
        let (sp, n, contacts, held) = on_obstacle(Obstacle::Table);
        let area: f64 = sp.vertex_area_m2.iter().sum();
        let e = impact_event(&sp, &vec![V3::new(0.0, 0.0, -0.2); n], &contacts, &held).unwrap();
        let expected = area * 0.2 / (IMPACT_REF_AREA_M2 * IMPACT_REF_SPEED_M_S);
        assert!((f64::from(e.amplitude) - expected).abs() < 1e-5, "{e:?}");
        assert!(e.resonator.is_constrained());
        assert!(
            (f64::from(e.resonator.radius_m) - (area / std::f64::consts::PI).sqrt()).abs() < 1e-6
        );
        assert_eq!(e.resonator.normal, [0.0, 0.0, 1.0]);
        // Twice the speed, twice the amplitude (below the cap).
        let f = impact_event(&sp, &vec![V3::new(0.0, 0.0, -0.4); n], &contacts, &held).unwrap();
        assert!((f.amplitude / e.amplitude - 2.0).abs() < 1e-5);
        // The cap.
        let g = impact_event(&sp, &vec![V3::new(0.0, 0.0, -50.0); n], &contacts, &held).unwrap();
        assert_eq!(f64::from(g.amplitude), MAX_IMPACT_AMPLITUDE);
    }

    #[test]
    fn resting_sliding_rising_held_or_wall_contacts_are_no_impact() {
        let (sp, n, table, free) = on_obstacle(Obstacle::Table);
        // At rest, sliding, settling below v_min, lifting off.
        for v in [
            V3::zeros(),
            V3::new(0.3, 0.1, 0.0),
            V3::new(0.0, 0.0, -0.04),
            V3::new(0.0, 0.0, 0.5),
        ] {
            assert!(
                impact_event(&sp, &vec![v; n], &table, &free).is_none(),
                "{v:?}"
            );
        }
        let down = vec![V3::new(0.0, 0.0, -0.5); n];
        // Not touching, held, on the wall or on the sheet itself.
        assert!(impact_event(&sp, &down, &vec![VertexContact::default(); n], &free).is_none());
        assert!(impact_event(&sp, &down, &table, &vec![true; n]).is_none());
        for o in [Obstacle::Wall, Obstacle::SelfContact] {
            assert!(impact_event(&sp, &down, &vec![on(o); n], &free).is_none());
        }
        // NaN velocities and mismatched inputs are ignored.
        assert!(impact_event(&sp, &vec![V3::new(0.0, 0.0, f64::NAN); n], &table, &free).is_none());
        assert!(impact_event(&sp, &down[..1], &table, &free).is_none());
    }

    #[test]
    fn only_the_vertices_that_hit_count_and_place_the_clac() {
        let (sp, n, contacts, held) = on_obstacle(Obstacle::Table);
        // The half with x > 0 slaps down; the other half rests.
        let vel: Vec<V3> = sp
            .pos
            .iter()
            .map(|p| {
                if p.x > 0.0 {
                    V3::new(0.0, 0.0, -0.5)
                } else {
                    V3::zeros()
                }
            })
            .collect();
        let e = impact_event(&sp, &vel, &contacts, &held).unwrap();
        assert!(e.resonator.centre_m[0] > 0.03, "{e:?}");
        let hit: f64 = (0..n)
            .filter(|&i| sp.pos[i].x > 0.0)
            .map(|i| sp.vertex_area_m2[i])
            .sum();
        let expected = hit * 0.5 / (IMPACT_REF_AREA_M2 * IMPACT_REF_SPEED_M_S);
        assert!((f64::from(e.amplitude) - expected).abs() < 1e-5);
    }

    #[test]
    fn a_wall_slap_is_heard_along_the_walls_normal_when_the_wall_is_given() {
        let (sp, n, wall, held) = on_obstacle(Obstacle::Wall);
        // The wall faces −y; the sheet arrives moving +y.
        let plane = PlaneObstacle {
            kind: Obstacle::Wall,
            active: true,
            normal: -V3::y(),
            offset_m: -0.4,
            target_offset_m: -0.4,
            speed_m_s: 0.0,
        };
        let vel = vec![V3::new(0.0, 0.3, 0.0); n];
        let mut out = [None; 3];
        assert_eq!(
            impact_events(&sp, &vel, &wall, &held, &[plane], &mut out),
            1
        );
        let e = out[0].unwrap();
        assert_eq!(e.resonator.normal, [0.0, -1.0, 0.0]);
        assert!(e.resonator.is_constrained());
        // Moving away from it, or with the wall not given: nothing.
        let away = vec![V3::new(0.0, -0.3, 0.0); n];
        assert_eq!(
            impact_events(&sp, &away, &wall, &held, &[plane], &mut out),
            0
        );
        assert_eq!(impact_events(&sp, &vel, &wall, &held, &[], &mut out), 0);
        // A wall receding at the sheet's speed (its offset along −y growing: speed −0.3 along
        // its normal) with the sheet following it: no approach, no clap.
        let receding = PlaneObstacle {
            speed_m_s: -0.3,
            ..plane
        };
        assert_eq!(
            impact_events(&sp, &vel, &wall, &held, &[receding], &mut out),
            0
        );
    }
}
