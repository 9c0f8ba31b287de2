//! # The air the sheet moves (beyond the seeds)
//!
//! The seeds' sound comes from curvature flips, sudden shape changes and friction (thesis
//! §4.3, T 1760–1810; SCA 2016 §3–4). A sheet shaken by one edge (thesis Fig. 4.21, SCA
//! Fig. 17) keeps its curvature's sign — it curls one way and the shake only changes how much
//! (measured: docs/decisions.md, "Sound realism: why a shaken sheet was silent") — so the seeds'
//! model makes no sound while real paper waved in the air is loud. This is the missing source:
//! a thin plate accelerating through air radiates as a dipole whose pressure is proportional to
//! the area times its normal acceleration at low frequencies (the compact-source limit of a
//! vibrating plate; its axis is the plate's normal).
//!
//! Per frame, over the triangles of S_P none of whose vertices touches an obstacle or is held
//! (a part lying on the table moves no air; a part in the fingers is where a grab jumps the
//! sheet to the hand, which is not a motion through the air):
//!
//! ```text
//! a_t  = mean over the triangle's vertices of (v_end − v_start) / Δt     (the frame's change)
//! s    = Σ_t A_t |a_t · n_t|                                              (m³/s²)
//! c, n = the centroid and the (sign-aligned) normal weighted by A_t |a_t · n_t|
//! ```
//!
//! Decisions, one line each:
//! - **Acceleration over the frame** (v_start = the velocities the frame started with, which
//!   the saved sheet holds, so a reopened sheet sounds as the uninterrupted one): no history
//!   of its own to save.
//! - **|a_n| summed, not a_n**: parts of the sheet that swing against each other do not cancel
//!   (their flows are not one coherent source at the frequencies heard).
//! - **Clamped at [`MAX_ACCEL_M_S2`]** per triangle: an undone or projected frame can move a
//!   vertex by millimetres in one frame, which is not a motion through the air.
//! - The render path turns it into band-limited noise (plugin `render/air.rs`).

use crate::collision::VertexContact;
use crate::math::V3;
use crate::sheet::physical::PhysMesh;
use crate::sound_input::AirState;

/// Largest normal acceleration a triangle counts with, m/s².
pub const MAX_ACCEL_M_S2: f64 = 400.0;

/// The air source of a frame of `dt_s` seconds that started with velocities `vel_start`
/// (module doc). Zero if the inputs do not match the mesh or `dt_s` is not positive. No
/// allocation.
pub fn air_source(
    sp: &PhysMesh,
    vel_start: &[V3],
    contacts: &[VertexContact],
    held: &[bool],
    dt_s: f64,
) -> AirState {
    let n = sp.num_vertices();
    if (dt_s.is_nan() || dt_s <= 0.0)
        || vel_start.len() != n
        || sp.vel.len() != n
        || contacts.len() < n
        || held.len() < n
    {
        return AirState::default();
    }
    let (mut s, mut c, mut nrm) = (0.0f64, V3::zeros(), V3::zeros());
    for (t, tri) in sp.triangles.iter().enumerate() {
        let [i, j, k] = tri.map(|v| v as usize);
        if [i, j, k].iter().any(|&v| contacts[v].in_contact || held[v]) {
            continue;
        }
        let (pi, pj, pk) = (sp.pos[i], sp.pos[j], sp.pos[k]);
        let cross = (pj - pi).cross(&(pk - pi));
        let len = cross.norm();
        if len.is_nan() || len <= 0.0 {
            continue;
        }
        let normal = cross / len;
        let dv =
            (sp.vel[i] - vel_start[i]) + (sp.vel[j] - vel_start[j]) + (sp.vel[k] - vel_start[k]);
        let a_n = (dv.dot(&normal) / (3.0 * dt_s)).clamp(-MAX_ACCEL_M_S2, MAX_ACCEL_M_S2);
        let w = sp.tri_rest[t].area_m2 * a_n.abs();
        if w.is_nan() || w <= 0.0 {
            continue;
        }
        s += w;
        c += (pi + pj + pk) * (w / 3.0);
        // Normals are sign-aligned with the running sum, so a sheet curled over itself does not
        // cancel its own axis.
        nrm += if nrm.dot(&normal) < 0.0 {
            -normal
        } else {
            normal
        } * w;
    }
    if (s.is_nan() || s <= 0.0) || !s.is_finite() {
        return AirState::default();
    }
    let c = c / s;
    let l = nrm.norm();
    let nrm = if l > 0.0 { nrm / l } else { V3::z() };
    AirState {
        strength_m3_s2: s as f32,
        centre_m: [c.x as f32, c.y as f32, c.z as f32],
        normal: [nrm.x as f32, nrm.y as f32, nrm.z as f32],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::pattern::lattice;

    fn flat_sheet() -> PhysMesh {
        PhysMesh::from_pattern(&lattice(0.2, 0.1, 0.025), 0.0, 0.08).unwrap()
    }

    #[test]
    fn a_sheet_accelerating_face_on_moves_air_in_proportion_and_edge_on_none() {
        let mut sp = flat_sheet();
        let n = sp.num_vertices();
        let contacts = vec![VertexContact::default(); n];
        let held = vec![false; n];
        let start = vec![V3::zeros(); n];
        let area: f64 = sp.tri_rest.iter().map(|r| r.area_m2).sum();
        // Face-on (the sheet lies in z = 0): 0.5 m/s gained in 5 ms is 100 m/s².
        sp.vel.fill(V3::new(0.0, 0.0, 0.5));
        let a = air_source(&sp, &start, &contacts, &held, 0.005);
        assert!(
            (f64::from(a.strength_m3_s2) - area * 100.0).abs() < 1e-4,
            "{a:?}"
        );
        assert!((a.normal[2].abs() - 1.0).abs() < 1e-6);
        assert!(a.centre_m[2].abs() < 1e-6);
        // Twice the acceleration, twice the strength; edge-on, none; steady motion, none.
        sp.vel.fill(V3::new(0.0, 0.0, 1.0));
        let b = air_source(&sp, &start, &contacts, &held, 0.005);
        assert!((b.strength_m3_s2 / a.strength_m3_s2 - 2.0).abs() < 1e-5);
        sp.vel.fill(V3::new(0.7, 0.0, 0.0));
        assert_eq!(
            air_source(&sp, &start, &contacts, &held, 0.005).strength_m3_s2,
            0.0
        );
        let moving = sp.vel.clone();
        assert_eq!(
            air_source(&sp, &moving, &contacts, &held, 0.005).strength_m3_s2,
            0.0
        );
    }

    #[test]
    fn parts_on_the_table_and_bad_inputs_move_no_air() {
        let mut sp = flat_sheet();
        let n = sp.num_vertices();
        let held = vec![false; n];
        let start = vec![V3::zeros(); n];
        sp.vel.fill(V3::new(0.0, 0.0, 0.5));
        let touching = vec![
            VertexContact {
                in_contact: true,
                ..Default::default()
            };
            n
        ];
        assert_eq!(
            air_source(&sp, &start, &touching, &held, 0.005),
            AirState::default()
        );
        let free = vec![VertexContact::default(); n];
        assert_eq!(
            air_source(&sp, &start[1..], &free, &held, 0.005),
            AirState::default()
        );
        assert_eq!(
            air_source(&sp, &start, &free, &held, 0.0),
            AirState::default()
        );
        assert_eq!(
            air_source(&sp, &start, &free, &held, f64::NAN),
            AirState::default()
        );
        sp.vel[0] = V3::new(f64::NAN, 0.0, 0.0);
        let a = air_source(&sp, &start, &free, &held, 0.005);
        assert!(air_source(&sp, &start, &free, &vec![true; n], 0.005).strength_m3_s2 == 0.0);
        assert!(a.strength_m3_s2.is_finite());
    }
}
