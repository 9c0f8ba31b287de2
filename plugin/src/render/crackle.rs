//! # The crackle under a crumple: the tear's grains, driven by how fast bent paper moves
//!
//! Beyond the seeds (their crumple is silent between events; `sim_core::sound_analysis::crackle`
//! says why and what it measures). The simulation sends, per frame, D = Σ ℓ |θ̇| over the bent
//! hinges (m·rad/s). The seeds' own model of paper fibres giving way is the tear's crackle,
//! w · r^α with amplitude and grain rate linear in the tear's speed ([`super::tearing`], MIG 2015
//! §5); the many small buckles of a crumple are the same kind of sound, so the same generator
//! plays them, driven by D instead of a speed:
//!
//! ```text
//! d    = D² / (D + D₀)                          the knee
//! v_eq = v_ref · √(D_cal · d) / D_REF          (v_ref = the tear's reference speed, 0.1 m/s)
//! y    = LP(tear_noise(v_eq))                   one-pole low-pass at CRACKLE_LP_HZ
//! ```
//!
//! - **D₀ = [`CRACKLE_D0_M_RAD_S`]** (0.3), a knee, not a gate: D²/(D + D₀) is D − D₀ within
//!   D₀²/D above it and falls as D² below it. Measured on the seed scenes: a slide on the table
//!   gives D ≈ 0.2, a shake ≈ 0.5, a crumple while it moves 3–20 (peaks to 90), a crumple held
//!   still 0.01–0.04; so a slide crackles ~18 dB and a settling sheet ~30 dB under a crumple at
//!   D = 5 (both far under their friction and events), while a crumple that slows down fades
//!   out instead of stopping dead at D₀ (a gate there made its last 10 ms windows digital
//!   silence).
//! - **The square root** (D_cal = [`CRACKLE_D_CAL_M_RAD_S`], 5): recordings of crumpling paper
//!   are trains of pulses whose energies follow one power law whatever the sheet's size (Houle &
//!   Sethna 1996, Phys. Rev. E 54, 278): more moving crease makes more pulses, not louder ones.
//!   So the grains' amplitude grows as √D, not D (their density still follows it). Linear in D,
//!   a 10 cm square crumpled slowly crackled ~10 dB under an A4 and fell silent between its
//!   grains (12–14 % of its 10 ms windows below −90 dBFS); at D = D_cal both laws agree, so a
//!   moving crumple's crackle stays where it was set, about 15 dB under its events.
//! - **D_REF = [`CRACKLE_D_REF_M_RAD_S`]** (50): a crumple moving at D ≈ 5 crackles about 15 dB
//!   under its events, filling the gaps between them instead of drowning them.
//! - **The low-pass** (impl. choice, an approximation of the paper's own filtering): the tear's
//!   grains are white; crumple recordings have their centroid at 2.4–4.6 kHz (issue 52), so the
//!   crackle is darkened at [`CRACKLE_LP_HZ`].
//! - Its own noise stream (the renderer's seed mixed with a constant), so it is not the tear's.
//! - Spatialized from the centre of the moving bends, 1/d to each ear, on the crumple bus.

use super::rng::splitmix;
use super::tearing::{TEAR_AMP_REF_SPEED_M_S, TearNoise, TearSettings};

/// Below this deformation rate the sheet does not crackle, m·rad/s.
pub const CRACKLE_D0_M_RAD_S: f32 = 0.3;
/// Deformation rate (above D₀) at which the grains reach ±1, m·rad/s.
pub const CRACKLE_D_REF_M_RAD_S: f32 = 50.0;
/// Deformation rate at which the square-root law meets the linear one, m·rad/s.
pub const CRACKLE_D_CAL_M_RAD_S: f32 = 5.0;
/// Corner of the crackle's low-pass, Hz.
pub const CRACKLE_LP_HZ: f64 = 4000.0;
/// Mixed into the renderer's seed for the crackle's noise stream.
const CRACKLE_SEED_SALT: u64 = 0x6372_6163_6b6c_6521;

/// The crackle generator.
pub struct Crackle {
    noise: TearNoise,
    lp_coeff: f32,
    lp: f32,
}

impl Crackle {
    /// A generator at a sample rate.
    pub fn new(sample_rate_hz: f64, seed: u64) -> Self {
        let fs = sample_rate_hz.max(1.0);
        let lp = 1.0 - (-2.0 * std::f64::consts::PI * CRACKLE_LP_HZ.min(0.45 * fs) / fs).exp();
        Self {
            noise: TearNoise::new(
                sample_rate_hz,
                splitmix(seed ^ CRACKLE_SEED_SALT),
                TearSettings::default(),
            ),
            lp_coeff: lp as f32,
            lp: 0.0,
        }
    }

    /// Back to silence and the start of the noise stream.
    pub fn reset(&mut self) {
        self.noise.reset();
        self.lp = 0.0;
    }

    /// The frame's deformation rate D (m·rad/s), reached after `ramp` samples; not finite: 0.
    pub fn set_rate(&mut self, rate_m_rad_s: f32, ramp: u32) {
        let d = if rate_m_rad_s.is_finite() {
            let d = rate_m_rad_s.max(0.0);
            d * d / (d + CRACKLE_D0_M_RAD_S)
        } else {
            0.0
        };
        let d = (CRACKLE_D_CAL_M_RAD_S * d).sqrt();
        self.noise
            .set_speed(TEAR_AMP_REF_SPEED_M_S * d / CRACKLE_D_REF_M_RAD_S, ramp);
    }

    /// Writes the crackle into `out` (overwriting it); returns the samples the grains ran.
    /// With `skip_idle`, a still sheet costs nothing once the low-pass's tail has ended (below
    /// −200 dB, well within a millisecond of the last grain).
    pub fn render(&mut self, out: &mut [f32], skip_idle: bool) -> usize {
        let ran = self.noise.render(out, skip_idle);
        if ran == 0 && self.lp == 0.0 {
            // All zeros in, nothing left in the filter: zeros out (what the loop would give).
            return 0;
        }
        let c = self.lp_coeff;
        for o in out.iter_mut() {
            self.lp += c * (*o - self.lp);
            // The tail below −200 dB ends (per sample, so the block size does not matter).
            if *o == 0.0 && self.lp.abs() < 1e-10 {
                self.lp = 0.0;
            }
            *o = self.lp;
        }
        ran
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::test_support::rms;

    #[test]
    fn silent_at_rest_faint_under_the_knee_and_louder_with_the_rate() {
        let mut c = Crackle::new(48_000.0, 1);
        let mut out = vec![1.0; 48_000];
        for d in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            c.set_rate(d, 1);
            assert_eq!(c.render(&mut out, true), 0, "{d}");
            assert!(out.iter().all(|v| *v == 0.0), "{d}");
        }
        let mut level = |d: f32| {
            c.set_rate(d, 1);
            c.render(&mut out, true);
            rms(&out[4800..])
        };
        let (held, slide, knee) = (level(0.03), level(0.2), level(CRACKLE_D0_M_RAD_S));
        let (a, b, e) = (level(3.0), level(10.0), level(40.0));
        assert!(
            0.0 < held && held < slide && slide < knee && knee < a,
            "{held} {slide} {knee}"
        );
        assert!(a < b && b < e && e < 1.0, "{a} {b} {e}");
        let db = |x: f64, y: f64| 20.0 * (x / y).log10();
        let five = level(CRACKLE_D_CAL_M_RAD_S);
        // Above the knee the amplitude grows as √D: ×4 in D is +6 dB.
        let twenty = level(4.0 * CRACKLE_D_CAL_M_RAD_S);
        assert!((db(twenty, five) - 6.0).abs() < 2.0, "{}", db(twenty, five));
        // Under it the level falls fast: a slide ≥ 15 dB, a settling sheet ≥ 28 dB under D = 5.
        assert!(db(slide, five) < -15.0, "{}", db(slide, five));
        assert!(db(held, five) < -28.0, "{}", db(held, five));
    }

    #[test]
    fn it_is_not_the_tears_noise() {
        let mut c = Crackle::new(48_000.0, 7);
        let mut t = TearNoise::new(48_000.0, 7, TearSettings::default());
        let (mut a, mut b) = (vec![0.0; 4800], vec![0.0; 4800]);
        c.set_rate(50.3, 1);
        t.set_speed(TEAR_AMP_REF_SPEED_M_S, 1);
        c.render(&mut a, true);
        t.render(&mut b, true);
        let corr: f64 = a.iter().zip(&b).map(|(x, y)| f64::from(x * y)).sum::<f64>()
            / (rms(&a) * rms(&b) * a.len() as f64);
        assert!(corr.abs() < 0.1, "{corr}");
    }
}
