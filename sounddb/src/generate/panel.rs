//! # A bent sheet as a shallow cylindrical panel (digest-sound §10.3)
//!
//! The seeds' recorded sheets were rectangles (l_r × l_c/2) bent along their l_c/2 edge
//! (T 1808, T 1907): a shallow cylindrical panel with
//!
//! - a = l_r, the axial length (along the rulings, straight);
//! - b = l_c/2, the arc length of the curved edge;
//! - R_c, the radius of curvature, from the compression factor c_f ("the endpoints of a 10 cm
//!   border compressed by 30 % are 7 cm apart", T 1907): chord/arc = sin(φ/2)/(φ/2) = 1 − c_f,
//!   R_c = b/φ.
//!
//! Simply supported shallow-shell (Donnell) natural frequencies:
//!
//! ```text
//! α_m = mπ/a,  β_n = nπ/b,  k² = α_m² + β_n²,  D = E h³ / (12 (1 − ν²))
//! ω_mn² = [ D k⁴ + E h α_m⁴ / (R_c² k⁴) ] / ρ_s
//! ```
//!
//! The membrane term makes the lowest modes those with many half-waves across the curve
//! (β ≫ α); e.g. a 10 × 10 cm panel at 30 % compression has its lowest mode near 475 Hz (m = 1,
//! n = 5) and a ring frequency √(E h/ρ_s)/(2π R_c) ≈ 10 kHz, as in digest-sound §10.3. Smaller
//! panels ring higher ("the spectrum is translated towards higher frequencies when the size
//! decreases", T 1949). This is a linear model: no snap-through nonlinearity, no fibre crackle
//! (digest-sound §10.4).

/// Paper properties used by the panel model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperProps {
    /// Areal density ρ_s, kg/m².
    pub density_kg_m2: f64,
    /// Thickness h, m.
    pub thickness_m: f64,
    /// Young's modulus E, Pa.
    pub youngs_pa: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
}

impl PaperProps {
    /// Bending stiffness D = E h³ / (12 (1 − ν²)), N·m.
    pub fn bending_stiffness(&self) -> f64 {
        self.youngs_pa * self.thickness_m.powi(3) / (12.0 * (1.0 - self.poisson * self.poisson))
    }
}

/// One mode of the panel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mode {
    /// Half-waves along the straight (axial) edge.
    pub m: u32,
    /// Half-waves along the curved edge.
    pub n: u32,
    /// Natural frequency, Hz.
    pub freq_hz: f64,
}

/// A curved panel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Panel {
    /// Axial length a = l_r, m.
    pub a_m: f64,
    /// Arc length b = l_c/2, m.
    pub b_m: f64,
    /// Radius of curvature, m (infinite for a flat panel).
    pub radius_m: f64,
    /// Paper.
    pub paper: PaperProps,
}

/// Radius of curvature of an arc of length `arc_m` whose chord is (1 − compression) × arc.
pub fn radius_for_compression(arc_m: f64, compression: f64) -> f64 {
    if compression <= 1e-6 {
        return f64::INFINITY;
    }
    let target = (1.0 - compression).clamp(1e-3, 1.0);
    // sin(x)/x decreases on (0, π): bisection for x = φ/2.
    let (mut lo, mut hi) = (1e-9f64, std::f64::consts::PI - 1e-9);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if mid.sin() / mid > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let phi = lo + hi; // 2x
    arc_m / phi
}

impl Panel {
    /// A panel of `straight_cm` × `curved_cm` bent to `compression`.
    pub fn new(straight_cm: f64, curved_cm: f64, compression: f64, paper: PaperProps) -> Self {
        let b_m = curved_cm * 0.01;
        Self {
            a_m: straight_cm * 0.01,
            b_m,
            radius_m: radius_for_compression(b_m, compression),
            paper,
        }
    }

    /// Natural frequency of mode (m, n), Hz.
    pub fn freq_hz(&self, m: u32, n: u32) -> f64 {
        let pi = std::f64::consts::PI;
        let alpha = f64::from(m) * pi / self.a_m;
        let beta = f64::from(n) * pi / self.b_m;
        let k2 = alpha * alpha + beta * beta;
        let k4 = k2 * k2;
        let d = self.paper.bending_stiffness();
        let membrane = if self.radius_m.is_finite() {
            self.paper.youngs_pa * self.paper.thickness_m * alpha.powi(4)
                / (self.radius_m * self.radius_m * k4)
        } else {
            0.0
        };
        ((d * k4 + membrane) / self.paper.density_kg_m2).sqrt() / (2.0 * pi)
    }

    /// The `count` lowest modes below `max_hz`, sorted by frequency.
    pub fn lowest_modes(&self, count: usize, max_hz: f64) -> Vec<Mode> {
        let mut modes = Vec::new();
        for m in 1..=24u32 {
            for n in 1..=40u32 {
                let f = self.freq_hz(m, n);
                if f < max_hz {
                    modes.push(Mode { m, n, freq_hz: f });
                }
            }
        }
        modes.sort_by(|x, y| x.freq_hz.total_cmp(&y.freq_hz));
        modes.truncate(count);
        modes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PRINTER: PaperProps = PaperProps {
        density_kg_m2: 0.08,
        thickness_m: 1e-4,
        youngs_pa: 4e9,
        poisson: 0.3,
    };

    #[test]
    fn compression_example_of_the_thesis() {
        // 10 cm at 30 %: chord 7 cm.
        let r = radius_for_compression(0.1, 0.3);
        let phi = 0.1 / r;
        let chord = 2.0 * r * (phi / 2.0).sin();
        assert!((chord - 0.07).abs() < 1e-9, "{chord}");
    }

    #[test]
    fn digest_reference_frequencies() {
        // digest-sound §10.3: 10×10 cm 30 % → ≈ 475 Hz; 2.5×2.5 → ≈ 3.7 kHz; 30×15 → ≈ 128 Hz;
        // 10×10 at 10 % → ≈ 350 Hz.
        for (s, c, comp, expect) in [
            (10.0, 10.0, 0.3, 475.0),
            (2.5, 2.5, 0.3, 3700.0),
            (30.0, 15.0, 0.3, 128.0),
            (10.0, 10.0, 0.1, 350.0),
        ] {
            let f = Panel::new(s, c, comp, PRINTER).lowest_modes(1, 1e6)[0].freq_hz;
            assert!(
                (f / expect - 1.0).abs() < 0.08,
                "{s}x{c}@{comp}: {f} vs {expect}"
            );
        }
    }

    #[test]
    fn smaller_panels_ring_higher() {
        let mut last = 0.0;
        for size in [30.0, 20.0, 10.0, 5.0, 2.5] {
            let f = Panel::new(size, size, 0.1, PRINTER).lowest_modes(1, 1e6)[0].freq_hz;
            assert!(f > last);
            last = f;
        }
    }
}
