//! # The crackle of a sheet being deformed (beyond the seeds)
//!
//! The seeds sound a crumple by its events: curvature flips and sudden shape changes (thesis
//! §4.3.1–4.3.2, T 1760–1780; SCA 2016 §3). Between events their sheet is silent, and so was
//! ours: 43–58 % of the 10 ms windows of a crumple that moves were digital silence, where a
//! recording of real crumpling is a continuous crackle with bursts on top (issue 52; figures in
//! docs/benchmarks.md, "Sound realism"). The crackle under the events comes from the many small
//! buckles and fibre bonds that give way wherever a bent or creased part of the sheet keeps
//! moving; its rate follows how fast the sheet's bends change. This module measures that rate:
//!
//! ```text
//! θ̇_e = Σ_i ∇_{x_i} θ_e · v_i                       (the hinge's bending rate, exact)
//! D   = Σ_e ℓ_e |θ̇_e| · min(1, |θ_e| / θ_ref)        (m·rad/s)
//! c   = the centroid of the hinges' midpoints weighted by their terms
//! ```
//!
//! Decisions, one line each:
//! - **The rate from the velocities** (∇θ · v), not from the last frame's angles: no history
//!   of its own, so a reopened sheet crackles as the uninterrupted one (its velocities are
//!   saved).
//! - **Weighted by how bent the hinge is** (θ_ref = [`CRACKLE_REF_ANGLE_RAD`], the ridge angle
//!   a_max of the resonators, T 1784): a flat sheet bending gently is silent; a crease or a
//!   ridge that moves crackles, as real paper does.
//! - **Rigid motions give 0** (∇θ is orthogonal to them): a sheet slid or carried does not
//!   crackle.
//! - **Pressing (beyond the mesh).** A squeeze held at its limit (gesture_rig.rs "Crumple
//!   cap": the sheet has come within 1 mm of itself) stands still while the crumple value goes
//!   on rising or falling: a ball the mesh cannot fold further. Real paper pressed harder, or
//!   let go, keeps crackling as its creases give and spring back. The hands' closing the
//!   squeeze did not follow, s (m/s, summed over the hands, at most the hands' speed), adds
//!   D_press = κ s with κ = [`PRESS_CRACKLE_RAD`], the crackle a free squeeze makes per m/s
//!   of its hands (median 8.7 on C5 and 10.5 on S4 before their squeezes stop), centred on the
//!   held vertices. An approximation: no motion and no events come with it.
//! - The render path plays it as the tear's crackle noise (r^α grains) with amplitude and grain
//!   rate following D (plugin `render/crackle.rs`).

use crate::math::V3;
use crate::physics::bending::dihedral_grad;
use crate::sheet::physical::PhysMesh;
use crate::sound_input::CrackleState;

/// The bend at which a moving hinge crackles fully, radians (the ridge angle a_max).
pub const CRACKLE_REF_ANGLE_RAD: f64 = 0.5;

/// The crackle of a held-back squeeze per m/s of its hands' closing, radians (module doc,
/// "Pressing").
pub const PRESS_CRACKLE_RAD: f64 = 10.0;

/// The crackle of the hands pressing a squeeze held at its limit (module doc, "Pressing"):
/// `pressed_m` of closing in a frame of `dt_s`, centred on the `held` vertices. No allocation.
pub fn press_source(sp: &PhysMesh, held: &[bool], pressed_m: f64, dt_s: f64) -> CrackleState {
    let d = PRESS_CRACKLE_RAD * pressed_m / dt_s;
    if d.is_nan() || d <= 0.0 || !d.is_finite() {
        return CrackleState::default();
    }
    let (mut c, mut n) = (V3::zeros(), 0.0f64);
    for (p, _) in sp.pos.iter().zip(held).filter(|(_, h)| **h) {
        c += p;
        n += 1.0;
    }
    let c = if n > 0.0 { c / n } else { V3::zeros() };
    CrackleState {
        rate_m_rad_s: d as f32,
        centre_m: [c.x as f32, c.y as f32, c.z as f32],
    }
}

/// Two crackles as one: the rates add, the centre is their rate-weighted mean.
pub fn merged(a: CrackleState, b: CrackleState) -> CrackleState {
    let d = a.rate_m_rad_s + b.rate_m_rad_s;
    if d.is_nan() || d <= 0.0 {
        return CrackleState::default();
    }
    let (wa, wb) = (a.rate_m_rad_s / d, b.rate_m_rad_s / d);
    CrackleState {
        rate_m_rad_s: d,
        centre_m: std::array::from_fn(|k| a.centre_m[k] * wa + b.centre_m[k] * wb),
    }
}

/// The sheet's crackle rate D and where it comes from (module doc). No allocation.
pub fn crackle_source(sp: &PhysMesh) -> CrackleState {
    let (mut d, mut c) = (0.0f64, V3::zeros());
    for h in &sp.hinges {
        let idx = h.v.map(|v| v as usize);
        let x = idx.map(|i| sp.pos[i]);
        let Some((theta, grad)) = dihedral_grad(&x) else {
            continue;
        };
        let weight = (theta.abs() / CRACKLE_REF_ANGLE_RAD).min(1.0);
        if weight.is_nan() || weight <= 0.0 {
            continue;
        }
        let rate: f64 = grad.iter().zip(&idx).map(|(g, &i)| g.dot(&sp.vel[i])).sum();
        let [a, b] = sp.topo.edges[h.edge as usize].v.map(|v| v as usize);
        let len = (sp.pattern[a] - sp.pattern[b]).norm();
        let term = len * rate.abs() * weight;
        if (term.is_nan() || term <= 0.0) || !term.is_finite() {
            continue;
        }
        d += term;
        c += (x[0] + x[1]) * (0.5 * term);
    }
    if d.is_nan() || d <= 0.0 {
        return CrackleState::default();
    }
    let c = c / d;
    CrackleState {
        rate_m_rad_s: d as f32,
        centre_m: [c.x as f32, c.y as f32, c.z as f32],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::pattern::lattice;

    fn sheet() -> PhysMesh {
        PhysMesh::from_pattern(&lattice(0.2, 0.1, 0.025), 0.0, 0.08).unwrap()
    }

    /// Folds the sheet (centred on the origin) about x = 0 by `angle` (the right half rotated about the y axis) and
    /// gives the right half the angular speed `omega` about the fold.
    fn fold(sp: &mut PhysMesh, angle: f64, omega: f64) {
        for i in 0..sp.num_vertices() {
            let p = sp.pattern[i];
            if p.x > 0.0 {
                let r = p.x;
                sp.pos[i] = V3::new(r * angle.cos(), p.y, r * angle.sin());
                sp.vel[i] = V3::new(-r * angle.sin(), 0.0, r * angle.cos()) * omega;
            } else {
                sp.pos[i] = V3::new(p.x, p.y, 0.0);
                sp.vel[i] = V3::zeros();
            }
        }
    }

    #[test]
    fn a_moving_crease_crackles_in_proportion_and_rigid_or_still_sheets_do_not() {
        let mut sp = sheet();
        // Flat and still; flat and carried; flat and bending slowly at the start: silent.
        assert_eq!(crackle_source(&sp), CrackleState::default());
        sp.vel.fill(V3::new(0.3, -0.2, 0.5));
        assert_eq!(crackle_source(&sp).rate_m_rad_s, 0.0);
        // A crease of 1 rad closing at 2 rad/s, then at 4 rad/s.
        fold(&mut sp, 1.0, 2.0);
        let a = crackle_source(&sp);
        fold(&mut sp, 1.0, 4.0);
        let b = crackle_source(&sp);
        assert!(a.rate_m_rad_s > 0.0);
        assert!(
            (b.rate_m_rad_s / a.rate_m_rad_s - 2.0).abs() < 1e-3,
            "{a:?} {b:?}"
        );
        // About the crease's length × the closing speed (the lattice's fold line is ~10 cm).
        assert!((0.1..0.4).contains(&a.rate_m_rad_s), "{a:?}");
        assert!(a.centre_m[0].abs() < 0.02, "{a:?}");
        // The creased sheet carried rigidly: silent.
        fold(&mut sp, 1.0, 0.0);
        sp.vel.fill(V3::new(0.0, 0.0, 1.0));
        assert!(crackle_source(&sp).rate_m_rad_s < 1e-9);
        // A gentle bend (0.05 rad) closing as fast crackles a tenth as much.
        fold(&mut sp, 0.05, 2.0);
        let c = crackle_source(&sp);
        assert!(c.rate_m_rad_s < 0.15 * a.rate_m_rad_s, "{c:?} {a:?}");
    }

    #[test]
    fn a_press_crackles_in_proportion_at_the_held_vertices_and_merges_by_rate() {
        let sp = sheet();
        let mut held = vec![false; sp.num_vertices()];
        assert_eq!(
            press_source(&sp, &held, 0.0, 0.005),
            CrackleState::default()
        );
        assert_eq!(
            press_source(&sp, &held, f64::NAN, 0.005),
            CrackleState::default()
        );
        held[0] = true;
        held[1] = true;
        let a = press_source(&sp, &held, 0.001, 0.005);
        let b = press_source(&sp, &held, 0.002, 0.005);
        assert!((f64::from(a.rate_m_rad_s) - PRESS_CRACKLE_RAD * 0.2).abs() < 1e-5);
        assert!((b.rate_m_rad_s / a.rate_m_rad_s - 2.0).abs() < 1e-6);
        let c = (sp.pos[0] + sp.pos[1]) * 0.5;
        assert!((f64::from(a.centre_m[0]) - c.x).abs() < 1e-6);
        assert!((f64::from(a.centre_m[1]) - c.y).abs() < 1e-6);
        // Merged: the rates add, the centre moves toward the stronger one.
        let mut far = a;
        far.centre_m = [1.0, 0.0, 0.0];
        far.rate_m_rad_s = 3.0 * a.rate_m_rad_s;
        let m = merged(a, far);
        assert_eq!(m.rate_m_rad_s, 4.0 * a.rate_m_rad_s);
        assert!((m.centre_m[0] - (0.25 * a.centre_m[0] + 0.75)).abs() < 1e-6);
        assert_eq!(merged(CrackleState::default(), a), a);
    }
}
