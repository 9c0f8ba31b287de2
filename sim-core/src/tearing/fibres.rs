//! # The fibre texture: the paper's resistance to tearing, pixel by pixel
//!
//! T_fibers of eq. 3.2 (M:124, T:1376–1380): a 2D Perlin noise in \[0, 1\]. The seeds publish
//! none of its parameters; the digest's (§1.6, §1.9): fractal Brownian motion of 4 octaves,
//! lacunarity 2, gain 0.5, base wavelength 4 mm, sampled at 4 px/mm. Evaluated on demand at
//! pixel centres (the walk visits a few pixels per millimetre of tear), so a sheet needs no
//! stored texture and the value of a pixel depends on the seed alone.

use noise::{Fbm, MultiFractal, NoiseFn, Perlin};

use crate::math::V2;

/// Pixels per metre of the tear's detail (4 px/mm; T:1390: the texture's resolution is the
/// detail's).
pub const PX_PER_M: f64 = 4000.0;
/// Base wavelength of the fibre noise, metres.
pub const FIBRE_WAVELENGTH_M: f64 = 0.004;
/// Octaves of the fibre noise.
pub const FIBRE_OCTAVES: usize = 4;

/// A pixel of the texture (pattern space, [`PX_PER_M`]).
pub type Px = [i32; 2];

/// The pixel holding pattern point `p`.
pub fn px_of(p: V2) -> Px {
    [
        (p.x * PX_PER_M).round() as i32,
        (p.y * PX_PER_M).round() as i32,
    ]
}

/// The centre of pixel `q`, pattern metres.
pub fn centre_of(q: Px) -> V2 {
    V2::new(f64::from(q[0]), f64::from(q[1])) / PX_PER_M
}

/// The resistance R ∈ \[0, 1\] of a sheet's fibres (seeded).
#[derive(Clone, Debug)]
pub struct FibreTexture {
    fbm: Fbm<Perlin>,
}

impl FibreTexture {
    /// The texture of seed `seed`.
    pub fn new(seed: u32) -> Self {
        let fbm = Fbm::<Perlin>::new(seed)
            .set_octaves(FIBRE_OCTAVES)
            .set_frequency(1.0 / (FIBRE_WAVELENGTH_M * PX_PER_M))
            .set_lacunarity(2.0)
            .set_persistence(0.5);
        Self { fbm }
    }

    /// R at pixel `q`, in \[0, 1\].
    pub fn resistance(&self, q: Px) -> f64 {
        let v = self.fbm.get([f64::from(q[0]), f64::from(q[1])]);
        (0.5 + 0.5 * v).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resistance_is_in_range_seeded_and_varies_at_the_millimetre_scale() {
        let a = FibreTexture::new(7);
        let b = FibreTexture::new(7);
        let c = FibreTexture::new(8);
        let (mut lo, mut hi, mut differ) = (1.0f64, 0.0f64, 0);
        for i in 0..400 {
            let q = [i * 3 - 600, (i * 7) % 500 - 250];
            let r = a.resistance(q);
            assert!((0.0..=1.0).contains(&r));
            assert_eq!(
                r.to_bits(),
                b.resistance(q).to_bits(),
                "same seed, same bits"
            );
            differ += usize::from(r != c.resistance(q));
            lo = lo.min(r);
            hi = hi.max(r);
        }
        assert!(
            differ > 300,
            "another seed, another texture ({differ} of 400 differ)"
        );
        assert!(hi - lo > 0.3, "the texture varies: {lo}..{hi}");
        // Neighbouring pixels are correlated (a wavelength is 16 px), distant ones are not.
        let near: f64 = (0..200)
            .map(|i| (a.resistance([i * 40, 0]) - a.resistance([i * 40 + 1, 0])).abs())
            .sum();
        let far: f64 = (0..200)
            .map(|i| (a.resistance([i * 40, 0]) - a.resistance([i * 40 + 20, 0])).abs())
            .sum();
        assert!(near < 0.5 * far, "near {near}, far {far}");
    }

    #[test]
    fn pixels_and_points_round_trip() {
        let p = V2::new(0.1234, -0.0567);
        let q = px_of(p);
        assert!((centre_of(q) - p).norm() <= 0.5_f64.hypot(0.5) / PX_PER_M + 1e-12);
        assert_eq!(px_of(centre_of([12, -34])), [12, -34]);
    }
}
