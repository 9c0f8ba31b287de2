//! # Deterministic noise source of the render path
//!
//! PCG-32 (`rand_pcg::Pcg32`, a stable algorithm, so a seed gives the same noise on every
//! platform) with the few draws the DSP needs. Each consumer (variant choice, friction phases,
//! tear grains) owns its own stream derived from the renderer seed by SplitMix64, so skipping work
//! in one (e.g. no tearing) never shifts the noise of another.

use rand_pcg::Pcg32;
use rand_pcg::rand_core::{Rng, SeedableRng};

/// SplitMix64 finaliser (seed derivation).
pub fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A seeded noise stream.
#[derive(Clone, Debug)]
pub struct NoiseRng {
    rng: Pcg32,
}

impl NoiseRng {
    /// The stream `stream` of renderer seed `seed`.
    pub fn new(seed: u64, stream: u64) -> Self {
        Self {
            rng: Pcg32::seed_from_u64(splitmix(seed ^ splitmix(stream))),
        }
    }

    /// Raw 32 bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        self.rng.next_u32()
    }

    /// Uniform in [0, 1) with 24-bit resolution.
    #[inline]
    pub fn uniform(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Uniform in (0, 1] with 24-bit resolution (never 0, for logarithms).
    #[inline]
    pub fn uniform_open0(&mut self) -> f32 {
        ((self.next_u32() >> 8) + 1) as f32 * (1.0 / 16_777_216.0)
    }

    /// Uniform in [−1, 1).
    #[inline]
    pub fn signed(&mut self) -> f32 {
        2.0 * self.uniform() - 1.0
    }

    /// Uniform integer in 0..n (n ≥ 1), by multiply-shift.
    #[inline]
    pub fn below(&mut self, n: u32) -> u32 {
        ((u64::from(self.next_u32()) * u64::from(n.max(1))) >> 32) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_repeat_and_differ() {
        let mut a = NoiseRng::new(1, 2);
        let mut b = NoiseRng::new(1, 2);
        let mut c = NoiseRng::new(1, 3);
        let va: Vec<u32> = (0..8).map(|_| a.next_u32()).collect();
        let vb: Vec<u32> = (0..8).map(|_| b.next_u32()).collect();
        let vc: Vec<u32> = (0..8).map(|_| c.next_u32()).collect();
        assert_eq!(va, vb);
        assert_ne!(va, vc);
        let mut r = NoiseRng::new(5, 0);
        for _ in 0..10_000 {
            let u = r.uniform();
            assert!((0.0..1.0).contains(&u));
            let o = r.uniform_open0();
            assert!(o > 0.0 && o <= 1.0);
            assert!(r.below(3) < 3);
        }
    }
}
