//! # The crack tip's step (eq. 3.1)
//!
//! "Rotating a single hand produces a tear in the direction of the thumb of that hand" (M:116,
//! T:1363); with both hands (M:118 eq. 1, T:1370 eq. 3.1):
//!
//! ```text
//! v_k = (T_k − s_t) / ‖T_k − s_t‖        the unit direction from the tip to thumb k
//! t   = C · (Δθ₁ v₁ + Δθ₂ v₂)            the tip's step; ‖t‖ is the tear's speed (M:120)
//! ```
//!
//! C is "a constant that controls the tearing speed"; no value is given (M:120). Decisions
//! (digest-tearing §1.5, not in the seeds): C is a length per radian chosen by the caller; a
//! step whose component along the forward direction (the bisector of v₁ and v₂) is negative
//! does not move the tip, since a tear never closes; a thumb on the tip gives no direction.

use crate::math::V2;

/// The forward direction at tip `s`: the unit bisector of the directions to the two thumbs
/// (zero if they cancel or a thumb is on the tip).
pub fn forward(s: V2, thumbs: [V2; 2]) -> V2 {
    let f = unit(thumbs[0] - s) + unit(thumbs[1] - s);
    unit(f)
}

/// The step t of eq. 3.1 of tip `s` for the two hands' rotations `dtheta_rad` (their thumbs at
/// `thumbs`) with speed constant `c_m_per_rad`; zero where it would run backwards (module doc).
pub fn step(s: V2, thumbs: [V2; 2], dtheta_rad: [f64; 2], c_m_per_rad: f64) -> V2 {
    let t =
        (unit(thumbs[0] - s) * dtheta_rad[0] + unit(thumbs[1] - s) * dtheta_rad[1]) * c_m_per_rad;
    let f = forward(s, thumbs);
    if !t.iter().all(|c| c.is_finite()) || (f != V2::zeros() && t.dot(&f) < 0.0) {
        return V2::zeros();
    }
    t
}

fn unit(v: V2) -> V2 {
    let n = v.norm();
    if n > 0.0 && n.is_finite() {
        v / n
    } else {
        V2::zeros()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const C: f64 = 0.05;

    /// Thumbs either side of the axis +y through the tip at the origin, `spread` apart,
    /// `ahead` in front.
    fn thumbs(spread: f64, ahead: f64) -> [V2; 2] {
        [V2::new(-spread / 2.0, ahead), V2::new(spread / 2.0, ahead)]
    }

    #[test]
    fn one_hand_tears_towards_its_thumb() {
        let s = V2::new(0.01, -0.02);
        for (k, th) in [thumbs(0.06, 0.05), thumbs(0.02, 0.1)]
            .into_iter()
            .enumerate()
        {
            for hand in 0..2 {
                let mut d = [0.0; 2];
                d[hand] = 0.1 + 0.05 * k as f64;
                let t = step(s, th, d, C);
                let to_thumb = (th[hand] - s).normalize();
                assert!(
                    (t.normalize() - to_thumb).norm() < 1e-12,
                    "{t:?} vs {to_thumb:?}"
                );
                assert!((t.norm() - C * d[hand]).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn the_step_is_linear_in_the_rotations() {
        let (s, th) = (
            V2::new(0.0, 0.0),
            [V2::new(-0.04, 0.05), V2::new(0.03, 0.06)],
        );
        let a = step(s, th, [0.02, 0.05], C);
        let b = step(s, th, [0.04, 0.10], C);
        let c = step(s, th, [0.02, 0.0], C) + step(s, th, [0.0, 0.05], C);
        assert!((b - a * 2.0).norm() < 1e-15);
        assert!((c - a).norm() < 1e-15);
    }

    #[test]
    fn symmetric_hands_stay_on_the_axis_and_unequal_ones_steer() {
        let s = V2::zeros();
        let th = thumbs(0.08, 0.05);
        let t = step(s, th, [0.1, 0.1], C);
        assert!(t.x.abs() < 1e-15 && t.y > 0.0, "{t:?}");
        // More rotation in the left hand steers towards the left thumb (−x), and back.
        assert!(step(s, th, [0.15, 0.05], C).x < 0.0);
        assert!(step(s, th, [0.05, 0.15], C).x > 0.0);
    }

    #[test]
    fn a_tear_never_closes() {
        let s = V2::zeros();
        let th = thumbs(0.08, 0.05);
        assert_eq!(step(s, th, [-0.1, -0.1], C), V2::zeros());
        assert_eq!(step(s, th, [f64::NAN, 0.1], C), V2::zeros());
        // A thumb on the tip gives no direction; the other hand still tears.
        let t = step(s, [s, th[1]], [0.1, 0.1], C);
        assert!((t.normalize() - th[1].normalize()).norm() < 1e-12);
    }
}
