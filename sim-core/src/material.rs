//! # Paper materials: mass, stretching and bending stiffness, friction
//!
//! The seeds give no stiffness values, only that stiffness "only needs to be of medium range …
//! no ill-conditioned system needs to be solved" (TOG 2015, `001_44bc28f7c5e9f81f.txt`
//! P 88–91; thesis `000_cb4d91e46ec5927f.txt` T 606–608, T 371) because a separate geometric
//! layer enforces isometry (digest-crumpling §2.1, §7 item 13). We start from the paper
//! material of ARCSim (the solver the seeds used, P 435–437, T 712):
//!
//! | quantity | printer (ARCSim "paper") | unit |
//! |---|---|---|
//! | areal density ρ | 0.1 | kg/m² |
//! | stretching stiffness k_s (Young's modulus × thickness) | 0.5 × 10⁶ | N/m |
//! | bending stiffness B | 0.4 × 10⁻³ | N·m |
//!
//! ## Scaling (what the simulation actually uses)
//!
//! Everything is in SI units (metres, kilograms, seconds); the seeds' centimetres only appear
//! in thresholds that are converted where they are used.
//!
//! - **ρ and B are kept physical.** Together with gravity they set what one sees and hears: the
//!   bending length ℓ_b = (B / ρg)^{1/3} ≈ 7.4 cm (how far a sheet overhangs a table edge
//!   before drooping) and the flexural wave speed. Both are converted to per-element values
//!   consistently with the mesh: masses are lumped by pattern area (⅓ of each incident
//!   triangle), and the hinge stiffness is `B·|ē|²/(2(Ā₁+Ā₂))`, the discrete-shell form of the
//!   seeds' `k_b Σ (θ_e − θ̄_e)² |ē| / h̄_e` (T 357–361) calibrated so that a bent lattice has
//!   the plate energy ½Bκ² per area (see [`crate::physics::bending`]).
//! - **k_s is scaled down** by `SolverConfig::stretch_scale` (default in
//!   [`crate::physics::SolverConfig`]). With the physical k_s the ratio of membrane to bending
//!   stiffness on a 3 cm element is k_s·ℓ²/B ≈ 10⁶: the coarse mesh locks (it cannot bend
//!   without stretching) and the implicit system becomes exactly the ill-conditioned problem
//!   the seeds avoid. The scaled k_s keeps in-plane strain well below the buckling strain of a
//!   single element while the solver stays well conditioned; the residual compression is what
//!   the metrics (c_mean, n_comp) report and what the isometry step of [`crate::geometry`] reduces.
//!   The benchmark report sweeps this trade-off; the default factor 0.03 (printer paper:
//!   k_s = 15 kN/m, k_s·ℓ²/B ≈ 30 on a 3 cm element) measured the lowest error at equal cost
//!   (physics alone it over-stretches the full crumple; the geometry layer's isometry step
//!   keeps it bounded).
//!
//! ## The three grades
//!
//! Printer paper uses the ARCSim values. The other grades are scaled from it by the usual
//! thin-plate laws (B ∝ E·t³, k_s ∝ E·t, ρ ∝ t) with plausible thickness and fibre changes;
//! they are impl. choices, not seed data:
//!
//! - **tracing**: thinner (t ≈ 0.75×) but denser, glassy fibres (E ≈ 1.6×): ρ = 0.065,
//!   k_s = 0.6 MN/m, B = 0.27 mN·m; crisp, so a larger compression limit ε_c;
//! - **banknote**: cotton rag, about as heavy as printer paper but limp and cloth-like after
//!   handling (E ≈ 0.45×, t ≈ 1.05×): ρ = 0.09, k_s = 0.25 MN/m, B = 0.2 mN·m, more friction.
//!
//! ε_c (compression limit, digest §4.1, Table VI default 1e-3) and σ (singular-point spread,
//! default 0.1 cm, digest §9 item 1) are carried here for the geometry layer ([`crate::geometry`]):
//! thicker/stiffer grades get a larger ε_c and σ (P 1309–1314, P 1085–1087).

use crate::control::Material;

/// Physical constants of one paper grade.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperMaterial {
    /// Areal density ρ, kg/m².
    pub areal_density_kg_m2: f64,
    /// Stretching stiffness k_s (Young's modulus × thickness), N/m, before solver scaling.
    pub stretch_stiffness_n_m: f64,
    /// Bending stiffness B, N·m.
    pub bending_stiffness_n_m: f64,
    /// Poisson ratio ν.
    pub poisson: f64,
    /// Coulomb friction coefficient against the table, wall and floor.
    pub friction_mu: f64,
    /// Compression limit ε_c of the geometry layer (fraction, not %).
    pub eps_c: f64,
    /// Spread σ of the singular-point placement law, metres.
    pub sigma_m: f64,
}

impl PaperMaterial {
    /// The constants of a grade.
    pub const fn of(m: Material) -> Self {
        match m {
            Material::Printer => Self {
                areal_density_kg_m2: 0.1,
                stretch_stiffness_n_m: 0.5e6,
                bending_stiffness_n_m: 0.4e-3,
                poisson: 0.3,
                friction_mu: 0.35,
                eps_c: 1e-3,
                sigma_m: 0.1e-2,
            },
            Material::Tracing => Self {
                areal_density_kg_m2: 0.065,
                stretch_stiffness_n_m: 0.6e6,
                bending_stiffness_n_m: 0.27e-3,
                poisson: 0.3,
                friction_mu: 0.25,
                eps_c: 2e-3,
                sigma_m: 0.05e-2,
            },
            Material::Banknote => Self {
                areal_density_kg_m2: 0.09,
                stretch_stiffness_n_m: 0.25e6,
                bending_stiffness_n_m: 0.2e-3,
                poisson: 0.3,
                friction_mu: 0.45,
                eps_c: 1e-3,
                sigma_m: 0.1e-2,
            },
        }
    }

    /// Bending length ℓ_b = (B / ρg)^{1/3}, metres.
    pub fn bending_length_m(&self) -> f64 {
        (self.bending_stiffness_n_m / (self.areal_density_kg_m2 * crate::math::GRAVITY_M_S2)).cbrt()
    }

    /// Lamé parameters (λ, μ) of the plane-stress membrane, N/m, for a stretching stiffness
    /// `k_s`: λ = k_s·ν/(1−ν²), μ = k_s/(2(1+ν)).
    pub fn lame_n_m(&self, k_s: f64) -> (f64, f64) {
        let nu = self.poisson;
        (k_s * nu / (1.0 - nu * nu), k_s / (2.0 * (1.0 + nu)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn printer_bending_length_is_a_few_cm() {
        let l = PaperMaterial::of(Material::Printer).bending_length_m();
        assert!((0.06..0.09).contains(&l), "{l}");
    }

    #[test]
    fn grades_are_distinct_and_positive() {
        for m in Material::ALL {
            let p = PaperMaterial::of(m);
            assert!(p.areal_density_kg_m2 > 0.0 && p.stretch_stiffness_n_m > 0.0);
            assert!(p.bending_stiffness_n_m > 0.0 && p.friction_mu > 0.0);
            let (l, mu) = p.lame_n_m(1.0);
            assert!(l > 0.0 && mu > 0.0);
        }
        assert_ne!(
            PaperMaterial::of(Material::Printer),
            PaperMaterial::of(Material::Tracing)
        );
    }
}
