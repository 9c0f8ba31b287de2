//! # Compression analysis: the stretch tensor of a triangle (digest-crumpling §3.2)
//!
//! For a triangle with 3D edges e₀ = x₁ − x₀, e₁ = x₂ − x₀ and pattern edges ē₀, ē₁ the
//! deformation gradient is F = [e₀ e₁]·[ē₀ ē₁]⁻¹ (P 574–582, T 842–850). The right stretch
//! tensor U = (FᵀF)^{1/2} has its eigenvectors in the **pattern** frame, so nothing has to be
//! mapped back: all remeshing decisions are taken in 2D (P 559–560, T 836).
//!
//! FᵀF is computed without a local 3D frame: FᵀF = Ū⁻ᵀ G Ū⁻¹ with G the Gram matrix of the
//! 3D edges (eᵢ·eⱼ), which is invariant under rigid motions, exactly what the in-plane frame of
//! the seeds achieves. Its eigenvalues μ are the squared principal stretches λ² (closed form,
//! [`crate::math::sym2_eigen`]).
//!
//! Digest §9 item 7 (thesis T 848, "largest eigenvector λ with 0 < λ < 1"): we read it as the
//! largest compression, so the triangle's compression ratio is **c_t = 1 − λ_min**, and v is the
//! eigenvector of λ_min (direction of maximal compression); v⊥ (minimal compression) is the
//! direction of the new rulings.

use crate::math::{M2, V2, V3, sym2_eigen};

/// Principal stretches of one triangle and their pattern directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stretch {
    /// Smallest principal stretch λ_min (1 = congruent, < 1 compressed).
    pub lambda_min: f64,
    /// Largest principal stretch λ_max.
    pub lambda_max: f64,
    /// Unit pattern direction of maximal compression v (eigenvector of λ_min).
    pub v: V2,
    /// Unit pattern direction of minimal compression v⊥ (the new ruling direction).
    pub v_perp: V2,
}

impl Stretch {
    /// Compression ratio c_t = 1 − λ_min (negative when the triangle is only stretched).
    pub fn compression(&self) -> f64 {
        1.0 - self.lambda_min
    }
}

/// The stretch tensor of a triangle with 3D corners `x` and inverse pattern edge matrix
/// `dm_inv` (see [`crate::sheet::physical::TriRest`]).
pub fn stretch_tensor(x: &[V3; 3], dm_inv: &M2) -> Stretch {
    let e0 = x[1] - x[0];
    let e1 = x[2] - x[0];
    let g = M2::new(e0.dot(&e0), e0.dot(&e1), e0.dot(&e1), e1.dot(&e1));
    let c = dm_inv.transpose() * g * dm_inv;
    let (mu_lo, mu_hi, v) = sym2_eigen(c[(0, 0)], 0.5 * (c[(0, 1)] + c[(1, 0)]), c[(1, 1)]);
    Stretch {
        lambda_min: mu_lo.max(0.0).sqrt(),
        lambda_max: mu_hi.max(0.0).sqrt(),
        v,
        v_perp: V2::new(-v.y, v.x),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Rot, V3};

    fn dm_inv(p: &[V2; 3]) -> M2 {
        M2::from_columns(&[p[1] - p[0], p[2] - p[0]])
            .try_inverse()
            .unwrap()
    }

    /// Digest §8 test 1: a triangle compressed by 5 % along a known direction, rigidly moved.
    #[test]
    fn compressed_triangle_gives_lambda_and_directions() {
        let p = [
            V2::new(0.0, 0.0),
            V2::new(0.03, 0.005),
            V2::new(0.01, 0.028),
        ];
        let d = V2::new(0.8, 0.6);
        let dp = V2::new(-d.y, d.x);
        let rot = Rot::from_euler_angles(0.3, -1.1, 2.0);
        let shift = V3::new(0.1, -0.2, 0.75);
        let x = p.map(|q| {
            let along = q.dot(&d) * 0.95;
            let across = q.dot(&dp);
            let q2 = d * along + dp * across;
            rot * V3::new(q2.x, q2.y, 0.0) + shift
        });
        let s = stretch_tensor(&x, &dm_inv(&p));
        assert!((s.lambda_min - 0.95).abs() < 1e-9, "{}", s.lambda_min);
        assert!((s.lambda_max - 1.0).abs() < 1e-9);
        assert!((s.compression() - 0.05).abs() < 1e-9);
        assert!(s.v.dot(&d).abs() > 1.0 - 1e-9, "v ∥ d: {:?}", s.v);
        assert!(s.v_perp.dot(&d).abs() < 1e-9, "v⊥ ⟂ d");
    }

    #[test]
    fn congruent_triangle_is_not_compressed() {
        let p = [V2::new(0.0, 0.0), V2::new(0.02, 0.0), V2::new(0.0, 0.02)];
        let rot = Rot::from_euler_angles(1.0, 0.5, -0.2);
        let x = p.map(|q| rot * V3::new(q.x, q.y, 0.0));
        let s = stretch_tensor(&x, &dm_inv(&p));
        assert!((s.lambda_min - 1.0).abs() < 1e-12 && (s.lambda_max - 1.0).abs() < 1e-12);
        assert!(s.compression() <= 1e-3);
    }
}
