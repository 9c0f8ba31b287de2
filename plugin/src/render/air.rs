//! # The air the sheet moves: band-limited noise, level linear in the sheet's acceleration
//!
//! Beyond the seeds (their model makes no sound while a sheet is shaken: the curvature's sign
//! does not flip; docs/decisions.md, "Sound realism: why a shaken sheet was silent"). The
//! simulation sends, per frame, s = Σ A |a_n| over the free parts of the sheet (area × normal
//! acceleration, `sim_core::sound_analysis::air`); the pressure a thin plate radiates into air
//! at low frequencies is proportional to it. Here it becomes noise:
//!
//! ```text
//! y = (s / S_REF) · RMS_REF · LP₂(LP₁(HP(w))) / g,    w ~ U(−1, 1) grains at 8 kHz
//! ```
//!
//! - **Grains tied to time**: w is a grain every 1/[`AIR_GRAIN_RATE_HZ`] s, linearly
//!   interpolated, each grain's value a hash of the renderer's seed and its index (not a running
//!   stream): the same grains at the same times at every sample rate (so a render at 44.1 kHz
//!   and one at 48 kHz are the same sound band by band), whatever the host's blocks and
//!   whenever the generator was idle.
//! - **The colour** (impl. choice, an approximation): a one-pole high-pass at
//!   [`AIR_HP_HZ`] and two one-pole low-passes at [`AIR_LP_HZ`] — a whoosh with a rustle on
//!   top, darker than the crumple and friction sounds; `g` is the filters' RMS gain on white
//!   noise, measured once when the generator is made (no allocation), so the level does not
//!   depend on the sample rate.
//! - **The level**: x = s / [`AIR_S_REF_M3_S2`] (an A4 sheet accelerating face-on at 6.4
//!   m/s²), linear at first and bent at a knee, level = x / (1 + x / [`AIR_KNEE`]) times
//!   [`AIR_RMS_REF`] (−20 dBFS): a sheet flapping hard does not push the air as one plate (its
//!   flow separates), and the loudest shakes stay clear of the output stage's clipper
//!   (impl. choice). Calibrated so that an A4 held up by an edge and shaken at 4.5 Hz plays
//!   about −30 dBFS at the default mix (a crumple's level; s ≈ 0.2), checked on a family of other
//!   shakes (`tests/tests/sound_realism.rs`); a slide on the table sends s ≈ 0.003 (inaudible),
//!   a sheet at rest 0. It comes once per frame and is
//!   ramped linearly across the frame, as the tear's speed is ([`super::tearing`]); at 0 and
//!   steady the generator does not run (decided per sample, so renders do not depend on the
//!   block size).
//! - **Where**: from the moving area's centre, 1/d to each ear (≥ 10 cm) times a dipole
//!   pattern with a floor, 0.25 + 0.75 |n · r̂| (the sheet is not one rigid disk: its parts'
//!   axes differ); the renderer applies it ([`super::Renderer`]).
//! - It plays on the crumple bus (the "Crumple Level" mix sets the sheet's own sounds).

use super::rng::splitmix;
use super::smoothing::LinearRamp;

/// s at which the noise has [`AIR_RMS_REF`] (before the knee), m³/s².
pub const AIR_S_REF_M3_S2: f32 = 0.4;
/// Knee of the level: level = x / (1 + x / K) for x = s / S_REF.
pub const AIR_KNEE: f32 = 2.0;
/// RMS of the noise at s = [`AIR_S_REF_M3_S2`] (before the distance law and the mix).
pub const AIR_RMS_REF: f32 = 0.1;
/// High-pass corner, Hz.
pub const AIR_HP_HZ: f64 = 200.0;
/// Low-pass corner (two poles), Hz.
pub const AIR_LP_HZ: f64 = 2500.0;
/// Largest level (in units of the reference) a frame can ask for.
pub const AIR_MAX_LEVEL: f32 = 8.0;
/// Grains of the noise per second (the same at every sample rate).
pub const AIR_GRAIN_RATE_HZ: f64 = 8000.0;
/// Mixed into the renderer's seed for the grains' hashes.
const AIR_SALT: u64 = 0x6169_725f_6e6f_6973;
/// Mixed in for the grains that measure the filters' gain.
const GAIN_SALT: u64 = 0x6761_696e_5f61_6972;
/// Samples measuring the filters' gain.
const GAIN_SAMPLES: usize = 16_384;

/// The filter chain's state.
#[derive(Clone, Copy, Debug, Default)]
struct Chain {
    hp_x: f32,
    hp_y: f32,
    lp1: f32,
    lp2: f32,
}

impl Chain {
    #[inline]
    fn tick(&mut self, x: f32, c: &Coeffs) -> f32 {
        let hp = c.hp * (self.hp_y + x - self.hp_x);
        self.hp_x = x;
        self.hp_y = hp;
        self.lp1 += c.lp * (hp - self.lp1);
        self.lp2 += c.lp * (self.lp1 - self.lp2);
        self.lp2
    }
}

#[derive(Clone, Copy, Debug)]
struct Coeffs {
    hp: f32,
    lp: f32,
}

/// Grain `k` of the stream `key`: uniform in [−1, 1).
#[inline]
fn grain(key: u64, k: u64) -> f32 {
    let bits = splitmix(key.wrapping_add(k)) >> 40;
    bits as f32 * (2.0 / (1u64 << 24) as f32) - 1.0
}

/// Linearly interpolated grains: the value at sample `n` of a rate of `grains_per_sample`.
#[derive(Clone, Copy, Debug)]
struct Grains {
    key: u64,
    grains_per_sample: f64,
    /// Index of the cached pair and its two values.
    k: u64,
    g0: f32,
    g1: f32,
}

impl Grains {
    fn new(key: u64, grains_per_sample: f64) -> Self {
        Self {
            key,
            grains_per_sample,
            k: 0,
            g0: grain(key, 0),
            g1: grain(key, 1),
        }
    }

    #[inline]
    fn at(&mut self, n: u64) -> f32 {
        let p = n as f64 * self.grains_per_sample;
        let k = p as u64;
        if k != self.k {
            if k == self.k + 1 {
                self.g0 = self.g1;
            } else {
                self.g0 = grain(self.key, k);
            }
            self.g1 = grain(self.key, k + 1);
            self.k = k;
        }
        self.g0 + (self.g1 - self.g0) * (p - k as f64) as f32
    }
}

/// The air-noise generator.
pub struct AirNoise {
    grains: Grains,
    /// Samples since the reset (the grains' clock; it runs while idle too).
    n: u64,
    coeffs: Coeffs,
    chain: Chain,
    /// 1 / the chain's RMS on uniform white noise, times the reference RMS.
    norm: f32,
    /// Level (s / S_REF), interpolated per sample.
    level: LinearRamp,
}

impl AirNoise {
    /// A generator at a sample rate.
    pub fn new(sample_rate_hz: f64, seed: u64) -> Self {
        let fs = sample_rate_hz.max(1.0);
        let rc_hp = 1.0 / (2.0 * std::f64::consts::PI * AIR_HP_HZ);
        let hp = (rc_hp / (rc_hp + 1.0 / fs)) as f32;
        let lp = (1.0 - (-2.0 * std::f64::consts::PI * AIR_LP_HZ.min(0.45 * fs) / fs).exp()) as f32;
        let coeffs = Coeffs { hp, lp };
        let per_sample = AIR_GRAIN_RATE_HZ / fs;
        // The chain's RMS gain on the same kind of noise, measured on grains of their own.
        let mut probe = Grains::new(splitmix(seed ^ GAIN_SALT), per_sample);
        let mut chain = Chain::default();
        let mut sum = 0.0f64;
        for k in 0..2 * GAIN_SAMPLES as u64 {
            let y = chain.tick(probe.at(k), &coeffs);
            if k >= GAIN_SAMPLES as u64 {
                sum += f64::from(y) * f64::from(y);
            }
        }
        let rms = (sum / GAIN_SAMPLES as f64).sqrt() as f32;
        Self {
            grains: Grains::new(splitmix(seed ^ AIR_SALT), per_sample),
            n: 0,
            coeffs,
            chain: Chain::default(),
            norm: if rms > 0.0 { AIR_RMS_REF / rms } else { 0.0 },
            level: LinearRamp::default(),
        }
    }

    /// Back to silence and the start of the noise stream.
    pub fn reset(&mut self) {
        self.grains = Grains::new(self.grains.key, self.grains.grains_per_sample);
        self.n = 0;
        self.chain = Chain::default();
        self.level.reset(0.0);
    }

    /// The frame's air strength s (m³/s²), reached after `ramp` samples. Not finite or
    /// negative: 0.
    pub fn set_strength(&mut self, strength_m3_s2: f32, ramp: u32) {
        let level = if strength_m3_s2.is_finite() && strength_m3_s2 > 0.0 {
            let x = strength_m3_s2 / AIR_S_REF_M3_S2;
            (x / (1.0 + x / AIR_KNEE)).min(AIR_MAX_LEVEL)
        } else {
            0.0
        };
        self.level.set_target(level, ramp);
    }

    /// Writes the noise into `out` (overwriting it); returns the samples it ran. With
    /// `skip_idle`, samples at a steady level of 0 are 0 without drawing noise.
    pub fn render(&mut self, out: &mut [f32], skip_idle: bool) -> usize {
        let mut ran = 0;
        for o in out.iter_mut() {
            let idle = self.level.is_steady() && self.level.value() == 0.0;
            let n = self.n;
            self.n += 1;
            if idle && skip_idle {
                if self.chain.lp2 != 0.0 || self.chain.hp_y != 0.0 || self.chain.hp_x != 0.0 {
                    self.chain = Chain::default();
                }
                *o = 0.0;
                continue;
            }
            let g = self.level.tick();
            let y = self.chain.tick(self.grains.at(n), &self.coeffs);
            *o = g * self.norm * y;
            ran += 1;
        }
        ran
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::test_support::rms;

    #[test]
    fn the_level_follows_the_strength_at_every_rate() {
        for rate in [22_050.0, 44_100.0, 48_000.0, 96_000.0] {
            let mut a = AirNoise::new(rate, 7);
            let n = rate as usize;
            let mut out = vec![0.0; n];
            // At the reference the knee takes a third off; well under it the level is linear.
            a.set_strength(AIR_S_REF_M3_S2, 1);
            a.render(&mut out, true);
            let r1 = rms(&out[n / 4..]);
            let want = f64::from(AIR_RMS_REF) / (1.0 + 1.0 / f64::from(AIR_KNEE));
            assert!((r1 / want - 1.0).abs() < 0.1, "{rate}: {r1}");
            a.set_strength(0.02 * AIR_S_REF_M3_S2, 1);
            a.render(&mut out, true);
            let r2 = rms(&out[n / 4..]);
            a.set_strength(0.005 * AIR_S_REF_M3_S2, 1);
            a.render(&mut out, true);
            let r3 = rms(&out[n / 4..]);
            assert!((r2 / r3 - 4.0).abs() < 0.4, "{rate}: {r2} / {r3}");
        }
    }

    #[test]
    fn silent_and_idle_at_zero_and_for_bad_input() {
        let mut a = AirNoise::new(48_000.0, 1);
        let mut out = vec![1.0; 4800];
        assert_eq!(a.render(&mut out, true), 0);
        assert!(out.iter().all(|v| *v == 0.0));
        for bad in [f32::NAN, f32::INFINITY, -1.0] {
            a.set_strength(bad, 100);
            assert_eq!(a.render(&mut out, true), 0, "{bad}");
        }
        a.set_strength(1e9, 1);
        a.render(&mut out, true);
        assert!(out.iter().all(|v| v.is_finite() && v.abs() < 8.0));
        // Back to 0 over a ramp, then idle again.
        a.set_strength(0.0, 240);
        let ran = a.render(&mut out, true);
        assert_eq!(ran, 240);
        assert!(out[240..].iter().all(|v| *v == 0.0));
    }

    #[test]
    fn the_block_size_does_not_change_the_samples() {
        let run = |block: usize| {
            let mut a = AirNoise::new(48_000.0, 3);
            let mut all = Vec::new();
            let mut buf = vec![0.0; block];
            for f in 0..40 {
                // A frame of 240 samples; the level changes at each frame's start.
                a.set_strength(if f % 7 < 3 { 0.0 } else { 0.1 * f as f32 }, 240);
                let mut left = 240;
                while left > 0 {
                    let m = left.min(block);
                    a.render(&mut buf[..m], true);
                    all.extend_from_slice(&buf[..m]);
                    left -= m;
                }
            }
            all
        };
        let a = run(240);
        for block in [1, 17, 64, 240] {
            assert_eq!(run(block), a, "block {block}");
        }
    }

    #[test]
    fn the_colour_is_a_whoosh_below_the_crackle() {
        // Energy below 2 kHz exceeds the energy above 6 kHz by more than 10 dB.
        let rate = 48_000.0;
        let mut a = AirNoise::new(rate, 9);
        let n = 1 << 15;
        let mut out = vec![0.0; n];
        a.set_strength(1.0, 1);
        a.render(&mut out, true);
        let mut planner = rustfft::FftPlanner::<f32>::new();
        let fft = planner.plan_fft_forward(n);
        let mut buf: Vec<rustfft::num_complex::Complex<f32>> = out
            .iter()
            .map(|&x| rustfft::num_complex::Complex::new(x, 0.0))
            .collect();
        fft.process(&mut buf);
        let band = |lo: f64, hi: f64| {
            let (a, b) = (
                (lo / rate * n as f64) as usize,
                (hi / rate * n as f64) as usize,
            );
            buf[a..b]
                .iter()
                .map(|c| f64::from(c.norm_sqr()))
                .sum::<f64>()
        };
        let low = band(100.0, 2000.0);
        let high = band(6000.0, 20_000.0);
        assert!(10.0 * (low / high).log10() > 10.0, "{low} vs {high}");
    }
}
