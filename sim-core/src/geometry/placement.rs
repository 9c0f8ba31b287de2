//! # Singular-point placement law (digest-crumpling §3.5, P 659–668, T 933)
//!
//! A new singular point s̄ is drawn near the 2D segment ē_sing: **uniform along it** and
//! **normally distributed across it** with the density χ(s̄) = exp(−d²/σ²), i.e. a signed
//! offset δ ~ N(0, σ²/2) (std σ/√2) along the segment's unit normal. The random numbers come
//! from the sheet's seeded generator only (determinism, digest §8 test 18); the normal deviate
//! is Box–Muller (no extra dependency).
//!
//! σ: digest §9 item 1 — the seeds give 0.1 cm (P 667 body text), 0.01/0.1 cm (P 1085–1087
//! caption) and 0.001/0.01 without unit (T 1132). We use 0.1 cm for printer paper as the
//! default and a smaller σ for thinner/crisper grades ([`crate::material`]).

use rand::RngExt;

use crate::math::V2;

/// One draw of the placement law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The sampled pattern position s̄, metres.
    pub pos: V2,
    /// Parameter along the segment, uniform in [0, 1).
    pub t: f64,
    /// Signed perpendicular offset, metres (normal with std σ/√2).
    pub offset_m: f64,
}

/// A standard normal deviate (Box–Muller, one of the pair).
pub fn standard_normal(rng: &mut rand_pcg::Pcg32) -> f64 {
    // u1 in (0, 1] so that ln(u1) is finite.
    let u1 = 1.0 - rng.random::<f64>();
    let u2 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Draws s̄ about the segment `a`–`b` with spread `sigma_m`.
pub fn sample_near_segment(a: V2, b: V2, sigma_m: f64, rng: &mut rand_pcg::Pcg32) -> Placement {
    let t = rng.random::<f64>();
    let offset_m = standard_normal(rng) * sigma_m * std::f64::consts::FRAC_1_SQRT_2;
    let d = b - a;
    let len = d.norm();
    let n = if len > 0.0 {
        V2::new(-d.y, d.x) / len
    } else {
        V2::zeros()
    };
    Placement {
        pos: a + d * t + n * offset_m,
        t,
        offset_m,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    /// Digest §8 test 4: 10⁵ samples about a 3 cm edge with σ = 0.1 cm.
    #[test]
    fn along_uniform_and_across_normal_with_std_sigma_over_sqrt2() {
        let mut rng = rand_pcg::Pcg32::seed_from_u64(7);
        let (a, b) = (V2::new(0.01, 0.02), V2::new(0.01 + 0.018, 0.02 + 0.024));
        let sigma = 0.001;
        let n = 100_000;
        let mut ts = Vec::with_capacity(n);
        let (mut s1, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let p = sample_near_segment(a, b, sigma, &mut rng);
            // The position agrees with (t, offset).
            let d = b - a;
            let t_back = (p.pos - a).dot(&d) / d.norm_squared();
            assert!((t_back - p.t).abs() < 1e-9);
            ts.push(p.t);
            s1 += p.offset_m;
            s2 += p.offset_m * p.offset_m;
        }
        // Kolmogorov–Smirnov against U(0,1): p > 0.01 ⇔ D < 1.628/√n (asymptotic).
        ts.sort_by(f64::total_cmp);
        let mut d_ks: f64 = 0.0;
        for (i, &t) in ts.iter().enumerate() {
            let lo = i as f64 / n as f64;
            let hi = (i + 1) as f64 / n as f64;
            d_ks = d_ks.max((t - lo).abs()).max((hi - t).abs());
        }
        assert!(d_ks < 1.628 / (n as f64).sqrt(), "KS D = {d_ks}");
        let mean = s1 / n as f64;
        let std = (s2 / n as f64 - mean * mean).sqrt();
        let want = sigma / 2f64.sqrt();
        assert!((std / want - 1.0).abs() < 0.02, "std {std} vs {want}");
        assert!(
            mean.abs() < 4.0 * want / (n as f64).sqrt() + 1e-12,
            "mean {mean}"
        );
    }

    #[test]
    fn same_seed_same_draws() {
        let mut r1 = rand_pcg::Pcg32::seed_from_u64(3);
        let mut r2 = rand_pcg::Pcg32::seed_from_u64(3);
        for _ in 0..10 {
            let (a, b) = (V2::zeros(), V2::new(0.03, 0.0));
            assert_eq!(
                sample_near_segment(a, b, 1e-3, &mut r1),
                sample_near_segment(a, b, 1e-3, &mut r2)
            );
        }
    }
}
