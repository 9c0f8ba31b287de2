//! # Math aliases and small helpers
//!
//! One precision for the whole simulation: `f64` (digest-crumpling §10 recommends double
//! precision in the geometry; the implicit solver's Newton steps and the line search benefit
//! from it too). Vectors and small matrices are nalgebra's stack types; the aliases keep the
//! choice in one place.

pub use nalgebra::{Matrix2, Matrix3, UnitQuaternion, Vector2, Vector3};

/// A 3D vector (world metres, velocities in m/s, forces in N).
pub type V3 = Vector3<f64>;
/// A 2D vector (pattern metres).
pub type V2 = Vector2<f64>;
/// A 3×3 matrix.
pub type M3 = Matrix3<f64>;
/// A 2×2 matrix.
pub type M2 = Matrix2<f64>;
/// A rotation.
pub type Rot = UnitQuaternion<f64>;

/// Gravitational acceleration, m/s².
pub const GRAVITY_M_S2: f64 = 9.81;

/// `[x, y, z]` → vector.
#[inline]
pub fn v3(a: [f64; 3]) -> V3 {
    V3::new(a[0], a[1], a[2])
}

/// Vector → `[x, y, z]`.
#[inline]
pub fn arr3(v: &V3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// True if every component is finite.
#[inline]
pub fn finite3(v: &V3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

/// Barycentric coordinates of `p` in the 2D triangle (a, b, c) (pattern points): weights
/// summing to 1, all ≥ 0 inside; non-finite for a degenerate triangle.
pub fn barycentric2(a: V2, b: V2, c: V2, p: V2) -> [f64; 3] {
    let det = (b - a).perp(&(c - a));
    let l1 = (p - a).perp(&(c - a)) / det;
    let l2 = (b - a).perp(&(p - a)) / det;
    [1.0 - l1 - l2, l1, l2]
}

/// Eigen-decomposition of a symmetric 2×2 matrix `[[a, b], [b, c]]`: returns
/// `(λ_min, λ_max, v_min)` with `v_min` the unit eigenvector of `λ_min` (closed form,
/// digest-crumpling §3.2).
pub fn sym2_eigen(a: f64, b: f64, c: f64) -> (f64, f64, V2) {
    let mean = 0.5 * (a + c);
    let half_diff = 0.5 * (a - c);
    let r = (half_diff * half_diff + b * b).sqrt();
    let lo = mean - r;
    let hi = mean + r;
    let v = if b.abs() > 1e-300 {
        V2::new(b, lo - a)
    } else if a <= c {
        V2::new(1.0, 0.0)
    } else {
        V2::new(0.0, 1.0)
    };
    let n = v.norm();
    let v = if n > 0.0 { v / n } else { V2::new(1.0, 0.0) };
    (lo, hi, v)
}

/// Clamps the eigenvalues of a symmetric 2×2 matrix to be non-negative (projection onto the
/// positive semi-definite cone).
pub fn sym2_clamp_psd(m: &M2) -> M2 {
    let (lo, hi, v) = sym2_eigen(m[(0, 0)], 0.5 * (m[(0, 1)] + m[(1, 0)]), m[(1, 1)]);
    let w = V2::new(-v.y, v.x);
    v * v.transpose() * lo.max(0.0) + w * w.transpose() * hi.max(0.0)
}

/// Wraps an angle to (−π, π].
#[inline]
pub fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    if a > -PI && a <= PI {
        return a;
    }
    let r = a.rem_euclid(TAU);
    if r > PI { r - TAU } else { r }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sym2_eigen_matches_definition() {
        for &(a, b, c) in &[
            (2.0, 0.5, 1.0),
            (1.0, 0.0, 3.0),
            (3.0, 0.0, 1.0),
            (1.0, -2.0, 1.0),
        ] {
            let (lo, hi, v) = sym2_eigen(a, b, c);
            let m = M2::new(a, b, b, c);
            assert!(((m * v) - v * lo).norm() < 1e-12);
            assert!(lo <= hi);
            assert!((lo + hi - (a + c)).abs() < 1e-12);
        }
    }

    #[test]
    fn psd_clamp_removes_negative_part() {
        let m = M2::new(1.0, 0.0, 0.0, -2.0);
        let p = sym2_clamp_psd(&m);
        assert!((p - M2::new(1.0, 0.0, 0.0, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn wrap_angle_range() {
        use std::f64::consts::PI;
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-1.5 * PI) - 0.5 * PI).abs() < 1e-12);
        assert_eq!(wrap_angle(0.3), 0.3);
    }
}
