//! # Membrane (stretching) energy: Green strain, St Venant–Kirchhoff
//!
//! The seeds' stretching model (thesis T 341–355, background of the ARCSim solver they use,
//! P 438, T 712): per triangle, the deformation gradient `F = U Ū⁻¹` (U = the two 3D edge
//! vectors from vertex 0, Ū the same edges in the pattern) and the Green strain
//! `G = ½(FᵀF − I)`. The printed energy `k_s((1−ν)Tr(G²) + ν Tr(G))²` (T 353) is garbled in the
//! conversion (digest §9 item 11); we use the standard plane-stress St Venant–Kirchhoff energy
//!
//! ```text
//! W = Ā · ( μ tr(G²) + λ/2 tr(G)² ),   λ = k_s ν/(1−ν²),  μ = k_s/(2(1+ν))
//! S = ∂W/∂G / Ā = 2μ G + λ tr(G) I                      (second Piola–Kirchhoff stress)
//! ∂W/∂U = Ā · F S Ū⁻ᵀ                                   (forces on vertices 1, 2; vertex 0 = −sum)
//! ```
//!
//! **Strain-rate damping** uses a dissipation potential of the same form, centred on the
//! strain at the start of the time step: `D = (τ_s/h) Ā (μ |G − G_n|² + λ/2 tr(G − G_n)²)`. Its
//! stress adds to S and its stiffness scales the material term by `τ_s/h` — a viscous membrane
//! that the implicit solver treats exactly like the elastic one.
//!
//! **Hessian.** `δ(F S) = δF S + F δS` with `δS = C:sym(Fᵀ δF)`. The material term is positive
//! semi-definite; the geometric term `δF S` is indefinite when S has a compressive
//! eigenvalue (the sheet wants to buckle). Newton needs a positive-definite system, so the
//! geometric term uses S projected onto the PSD cone (eigenvalues clamped at 0) — the usual
//! "clamped geometric stiffness" (an impl. choice; the seeds do not describe their solver's
//! linearization). Only the Hessian is modified; the energy and forces are exact.
//!
//! **Collapse barrier** (impl. choice). StVK is notoriously soft in strong compression: its
//! stress peaks at a stretch of 1/√3 and vanishes at zero, so a triangle squeezed hard enough
//! collapses and turns over. Below an area ratio `J = area/Ā` of [`BARRIER_J0`] we add
//!
//! ```text
//! W_bar = Ā (λ + 2μ) (J₀ − J)² / J        (C¹ at J₀, → ∞ as J → 0, convex in J)
//! ```
//!
//! which never acts in ordinary bending (J ≈ 1) and makes collapse impossible for the line
//! search of the Newton solver. Its Hessian is Gauss–Newton (`W''(J) ∇J∇Jᵀ`).

use crate::math::{M2, M3, V2, V3, sym2_clamp_psd};
use crate::sheet::measure::green_strain;
use crate::sheet::physical::TriRest;

/// Area ratio below which the collapse barrier acts.
pub const BARRIER_J0: f64 = 0.5;

/// Barrier value, dW/dJ and d²W/dJ² per unit area and unit stiffness, for an area ratio `j`.
#[inline]
fn barrier(j: f64) -> (f64, f64, f64) {
    if j >= BARRIER_J0 {
        return (0.0, 0.0, 0.0);
    }
    if j <= 0.0 {
        return (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
    }
    let d = BARRIER_J0 - j;
    (
        d * d / j,
        -d * (BARRIER_J0 + j) / (j * j),
        2.0 * BARRIER_J0 * BARRIER_J0 / (j * j * j),
    )
}

/// Area ratio J of a triangle, and a closure giving its gradient (per vertex): most
/// triangles are far from the barrier and never ask for it.
#[inline]
fn area_ratio_grad(x: &[V3; 3], rest: &TriRest) -> (f64, impl Fn() -> [V3; 3]) {
    let e1 = x[1] - x[0];
    let e2 = x[2] - x[0];
    let n = e1.cross(&e2);
    let nl = n.norm();
    let s = 1.0 / (2.0 * rest.area_m2);
    let j = if nl <= 0.0 { 0.0 } else { nl * s };
    let grad = move || {
        if nl <= 0.0 {
            return [V3::zeros(); 3];
        }
        let nh = n / nl;
        let g1 = e2.cross(&nh) * s;
        let g2 = nh.cross(&e1) * s;
        [-(g1 + g2), g1, g2]
    };
    (j, grad)
}

/// Material constants of the membrane, already scaled for the simulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MembraneParams {
    /// Lamé λ, N/m.
    pub lambda_n_m: f64,
    /// Lamé μ, N/m.
    pub mu_n_m: f64,
}

/// StVK energy density (per pattern area) of a strain, J/m².
#[inline]
pub fn energy_density(g: &M2, p: &MembraneParams) -> f64 {
    let tr = g[(0, 0)] + g[(1, 1)];
    let gg = g[(0, 0)] * g[(0, 0)] + 2.0 * g[(0, 1)] * g[(1, 0)] + g[(1, 1)] * g[(1, 1)];
    p.mu_n_m * gg + 0.5 * p.lambda_n_m * tr * tr
}

/// StVK stress S = 2μG + λ tr(G) I for a strain, N/m.
#[inline]
pub fn stress(g: &M2, p: &MembraneParams) -> M2 {
    let tr = g[(0, 0)] + g[(1, 1)];
    g * (2.0 * p.mu_n_m) + M2::identity() * (p.lambda_n_m * tr)
}

/// Energy + dissipation of one triangle, J. `damp = τ_s/h` (0 for the pure elastic energy).
#[inline]
pub fn energy(x: [V3; 3], rest: &TriRest, g_prev: &M2, damp: f64, p: &MembraneParams) -> f64 {
    let (g, _) = green_strain(x, rest);
    let mut e = energy_density(&g, p);
    if damp > 0.0 {
        e += damp * energy_density(&(g - g_prev), p);
    }
    let j = (x[1] - x[0]).cross(&(x[2] - x[0])).norm() / (2.0 * rest.area_m2);
    e += (p.lambda_n_m + 2.0 * p.mu_n_m) * barrier(j).0;
    rest.area_m2 * e
}

/// Gradient (per vertex) and Gauss–Newton-safe Hessian blocks (`hess[a][b]` = ∂²/∂x_a∂x_b)
/// of energy + dissipation of one triangle. Returns the energy.
///
/// With `F = Σ_a x_a β_aᵀ` (β_a = row a of `[−1 −1; 1 0; 0 1] Ū⁻¹`, so β₀ = −β₁ − β₂) and
/// `u_a = F β_a`, the derivative of `δ(F S)` in closed form gives, per vertex pair,
///
/// ```text
/// ∂W/∂x_a       = Ā F S β_a
/// ∂²W/∂x_a∂x_b = Ā c_m (μ (β_a·β_b) F Fᵀ + μ u_b u_aᵀ + λ u_a u_bᵀ) + Ā (β_aᵀ S⁺ β_b) I
/// ```
///
/// (`c_m = 1 + τ_s/h`: elastic + viscous material term; S⁺ = S clamped PSD, the geometric
/// term), so the nine blocks cost a handful of outer products.
pub fn grad_hess<const HESS: bool>(
    x: [V3; 3],
    rest: &TriRest,
    g_prev: &M2,
    damp: f64,
    p: &MembraneParams,
    grad: &mut [V3; 3],
    hess: &mut [[M3; 3]; 3],
) -> f64 {
    let (g, f) = green_strain(x, rest);
    let a = rest.area_m2;
    let mut s = stress(&g, p);
    let mut e = energy_density(&g, p);
    if damp > 0.0 {
        let dg = g - g_prev;
        s += stress(&dg, p) * damp;
        e += damp * energy_density(&dg, p);
    }
    let b = &rest.dm_inv;
    let b1 = V2::new(b[(0, 0)], b[(0, 1)]);
    let b2 = V2::new(b[(1, 0)], b[(1, 1)]);
    let beta = [-(b1 + b2), b1, b2];
    // F S (3×2) as its two columns.
    let fs0 = f[0] * s[(0, 0)] + f[1] * s[(1, 0)];
    let fs1 = f[0] * s[(0, 1)] + f[1] * s[(1, 1)];
    let u = beta.map(|bv| f[0] * bv.x + f[1] * bv.y);
    for (gv, bv) in grad.iter_mut().zip(&beta) {
        *gv = (fs0 * bv.x + fs1 * bv.y) * a;
    }

    if !HESS {
        let (j, grad_j) = area_ratio_grad(&x, rest);
        let (wb, dwb, _) = barrier(j);
        if wb > 0.0 {
            let kb = p.lambda_n_m + 2.0 * p.mu_n_m;
            let gj = grad_j();
            e += kb * wb;
            for v in 0..3 {
                grad[v] += gj[v] * (a * kb * dwb);
            }
        }
        return a * e;
    }
    let s_psd = sym2_clamp_psd(&s);
    let cm = 1.0 + damp;
    let mu = a * cm * p.mu_n_m;
    let lam = a * cm * p.lambda_n_m;
    let fft = f[0] * f[0].transpose() + f[1] * f[1].transpose();
    for i in 0..3 {
        for j in i..3 {
            let geo = a * beta[i].dot(&(s_psd * beta[j]));
            let mut blk = fft * (mu * beta[i].dot(&beta[j]))
                + u[j] * u[i].transpose() * mu
                + u[i] * u[j].transpose() * lam;
            for c in 0..3 {
                blk[(c, c)] += geo;
            }
            hess[i][j] = blk;
            if j != i {
                hess[j][i] = blk.transpose();
            }
        }
    }
    // Collapse barrier.
    let kb = p.lambda_n_m + 2.0 * p.mu_n_m;
    let (j, grad_j) = area_ratio_grad(&x, rest);
    let (wb, dwb, d2wb) = barrier(j);
    if wb > 0.0 {
        let gj = grad_j();
        e += kb * wb;
        for v in 0..3 {
            grad[v] += gj[v] * (a * kb * dwb);
        }
        let c = a * kb * d2wb;
        for u in 0..3 {
            for v in 0..3 {
                hess[u][v] += gj[u] * gj[v].transpose() * c;
            }
        }
    }
    a * e
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup() -> ([V3; 3], TriRest, MembraneParams) {
        let dm = M2::new(0.03, 0.012, 0.0, 0.026);
        let rest = TriRest {
            dm_inv: dm.try_inverse().unwrap(),
            area_m2: 0.5 * dm.determinant(),
        };
        let x = [
            V3::new(0.001, -0.002, 0.75),
            V3::new(0.0305, 0.001, 0.752),
            V3::new(0.013, 0.0255, 0.749),
        ];
        (
            x,
            rest,
            MembraneParams {
                lambda_n_m: 1500.0,
                mu_n_m: 2000.0,
            },
        )
    }

    #[test]
    fn rest_state_has_zero_energy_and_force() {
        let (_, rest, p) = setup();
        let x = [
            V3::new(0.0, 0.0, 0.0),
            V3::new(0.03, 0.0, 0.0),
            V3::new(0.012, 0.026, 0.0),
        ];
        let mut g = [V3::zeros(); 3];
        let mut h = [[M3::zeros(); 3]; 3];
        let e = grad_hess::<true>(x, &rest, &M2::zeros(), 0.0, &p, &mut g, &mut h);
        assert!(e.abs() < 1e-20);
        assert!(g.iter().all(|v| v.norm() < 1e-12));
        // Rigid rotation: still zero.
        let r = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1);
        let xr = x.map(|v| r * v + V3::new(1.0, 2.0, 3.0));
        assert!(energy(xr, &rest, &M2::zeros(), 0.0, &p).abs() < 1e-15);
    }

    #[test]
    fn gradient_matches_finite_differences() {
        let (x, rest, p) = setup();
        let gp = M2::new(0.001, 0.0, 0.0, -0.002);
        for damp in [0.0, 3.0] {
            let mut g = [V3::zeros(); 3];
            let mut h = [[M3::zeros(); 3]; 3];
            grad_hess::<true>(x, &rest, &gp, damp, &p, &mut g, &mut h);
            let eps = 1e-8;
            for a in 0..3 {
                for c in 0..3 {
                    let mut xp = x;
                    let mut xm = x;
                    xp[a][c] += eps;
                    xm[a][c] -= eps;
                    let fd = (energy(xp, &rest, &gp, damp, &p) - energy(xm, &rest, &gp, damp, &p))
                        / (2.0 * eps);
                    assert!(
                        (fd - g[a][c]).abs() < 1e-5 * (1.0 + g[a][c].abs()),
                        "damp {damp} v{a} c{c}: fd {fd} vs {}",
                        g[a][c]
                    );
                }
            }
        }
    }

    #[test]
    fn hessian_matches_finite_differences_when_stretched() {
        // Under pure extension S is PSD, so the clamped Hessian is the exact one.
        let (_, rest, p) = setup();
        let x = [
            V3::new(0.0, 0.0, 0.0),
            V3::new(0.0309, 0.0004, 0.001),
            V3::new(0.0125, 0.0268, -0.0005),
        ];
        let mut g = [V3::zeros(); 3];
        let mut h = [[M3::zeros(); 3]; 3];
        grad_hess::<true>(x, &rest, &M2::zeros(), 0.0, &p, &mut g, &mut h);
        let eps = 1e-7;
        for b in 0..3 {
            for c in 0..3 {
                let mut xp = x;
                let mut xm = x;
                xp[b][c] += eps;
                xm[b][c] -= eps;
                let mut gp = [V3::zeros(); 3];
                let mut gm = [V3::zeros(); 3];
                let mut hh = [[M3::zeros(); 3]; 3];
                grad_hess::<true>(xp, &rest, &M2::zeros(), 0.0, &p, &mut gp, &mut hh);
                grad_hess::<true>(xm, &rest, &M2::zeros(), 0.0, &p, &mut gm, &mut hh);
                for a in 0..3 {
                    let fd = (gp[a] - gm[a]) / (2.0 * eps);
                    let col = h[a][b].column(c).into_owned();
                    assert!(
                        (fd - col).norm() < 1e-4 * (1.0 + col.norm()),
                        "block {a}{b} col {c}: fd {fd:?} vs {col:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn barrier_resists_collapse_and_matches_its_gradient() {
        let (_, rest, p) = setup();
        // Squash the triangle to 30 % of its area: inside the barrier.
        let x = [
            V3::new(0.0, 0.0, 0.0),
            V3::new(0.03, 0.0, 0.0),
            V3::new(0.012, 0.026 * 0.3, 0.0),
        ];
        let mut g = [V3::zeros(); 3];
        let mut h = [[M3::zeros(); 3]; 3];
        grad_hess::<true>(x, &rest, &M2::zeros(), 0.0, &p, &mut g, &mut h);
        let eps = 1e-9;
        for a in 0..3 {
            for c in 0..3 {
                let mut xp = x;
                let mut xm = x;
                xp[a][c] += eps;
                xm[a][c] -= eps;
                let fd = (energy(xp, &rest, &M2::zeros(), 0.0, &p)
                    - energy(xm, &rest, &M2::zeros(), 0.0, &p))
                    / (2.0 * eps);
                assert!(
                    (fd - g[a][c]).abs() < 1e-4 * (1.0 + g[a][c].abs()),
                    "v{a} c{c}: {fd} vs {}",
                    g[a][c]
                );
            }
        }
        // The energy grows without bound as the area vanishes.
        let squash = |f: f64| {
            let x = [x[0], x[1], V3::new(0.012, 0.026 * f, 0.0)];
            energy(x, &rest, &M2::zeros(), 0.0, &p)
        };
        assert!(squash(0.01) > 10.0 * squash(0.2));
        assert!(squash(0.0).is_infinite());
    }

    #[test]
    fn hessian_is_symmetric_psd_under_compression() {
        let (_, rest, p) = setup();
        let x = [
            V3::new(0.0, 0.0, 0.0),
            V3::new(0.028, 0.0, 0.0),
            V3::new(0.011, 0.024, 0.0),
        ];
        let mut g = [V3::zeros(); 3];
        let mut h = [[M3::zeros(); 3]; 3];
        grad_hess::<true>(x, &rest, &M2::zeros(), 0.0, &p, &mut g, &mut h);
        let mut full = nalgebra::DMatrix::<f64>::zeros(9, 9);
        for (a, row) in h.iter().enumerate() {
            for (b, blk) in row.iter().enumerate() {
                full.view_mut((3 * a, 3 * b), (3, 3)).copy_from(blk);
            }
        }
        assert!((&full - full.transpose()).norm() < 1e-9 * full.norm());
        let ev = full.symmetric_eigenvalues();
        assert!(ev.iter().all(|&l| l > -1e-9 * full.norm()), "{ev}");
    }
}
