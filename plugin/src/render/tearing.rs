//! # Tearing noise: white noise × r^α, amplitude and pitch linear in tear speed
//!
//! The seeds' tearing sound (L 140–154, `003_8cfb4a33a3603fcd.txt` §5; T 2022–2050,
//! `000_cb4d91e46ec5927f.txt` §4.4; digest-tearing §3, digest-sound §6):
//!
//! ```text
//! y[k] = w[k] · r[k]^α,   w ~ U(−1, 1),  r ~ U(0, 1) fresh per sample,  α = 100     (L 144–152)
//! "we linearly tune the amplitude and pitch of the modified white noise according to the speed"
//!                                                                                   (L 154, T 2042)
//! ```
//!
//! Our reading of the gaps (digest-tearing §3.3, digest-sound §6):
//!
//! - The noise distribution is uniform (w ~ U(−1, 1)); then RMS = √(1/3 / (2α + 1)) = 0.0407
//!   (−27.8 dBFS) at α = 100, kurtosis ≈ 181, and 1 − 0.5^{1/α} = 0.69 % of the grains have
//!   r^α > 0.5.
//! - **"Pitch" is a playback rate** (the seeds played through FMOD, L 158): the i.i.d. values
//!   ("grains") are produced at a grain rate `44.1 kHz × ρ` — the seeds' rate scaled — independent
//!   of the host rate, with ρ = clamp(v / [`TEAR_PITCH_REF_SPEED_M_S`], 0.25, 1): faster tears,
//!   denser and brighter crackle ("peaks closer for fast tears", L 136). The grain rate saturates
//!   at the host rate below 44.1 kHz.
//! - Between grains the output is **linearly interpolated** (≈ FMOD's resampling). Each grain sits
//!   on the output sample nearest to its time (jitter ≤ ½ sample), so a grain's value is reached
//!   exactly: the count of crackle peaks scales exactly with ρ at any host rate (test S-5), and at
//!   44.1 kHz with ρ = 1 the output *is* the seeds' sequence (flat spectrum, test S-4).
//! - **Amplitude** = v / [`TEAR_AMP_REF_SPEED_M_S`] (linear; peak grains reach ±1 at 0.1 m/s). No
//!   make-up gain: the crest factor is ≈ 28 dB, the mix level sets loudness.
//! - The speed comes once per simulation frame and is **linearly interpolated** across the frame
//!   (`super::smoothing::LinearRamp`), so there is no zipper; it lands exactly on 0 when tearing
//!   stops, and then the generator does not run at all (§11.3, counted). That is decided per
//!   sample, not per `render` call: where the host's blocks end must not decide for how many
//!   samples the generator ran, or the next tear would draw other grains and a render would
//!   depend on the block size (docs/decisions.md, "Smaller rules and the runs that found
//!   them").
//!   A frame that sets the speed it already has (0, every frame of a sheet that does not tear)
//!   leaves the generator idle.
//! - **Denormal safety** (digest-tearing §3.2): r^α underflows f32 for most r (r^100 is subnormal
//!   for r ∈ (0.356, 0.418)). Grains with r^α < 10⁻⁶ (r < 0.871 at α = 100) are exactly 0 — they
//!   carry 6·10⁻¹³ of the energy — and r^α = exp(α ln r) is computed only above that gate.
//! - **Onset** (beyond the seeds): [`TearNoise::onset`] adds a burst that starts as loud and
//!   as dense as a tear at 0.1 m/s and decays in [`ONSET_DECAY_MS`]: a tear that starts, or
//!   starts again after a pause, snaps (the first fibres break at once) before it runs.
//!
//! Spatialization: the seeds do not spatialize tearing. We apply a distance law from the tear tip
//! to each ear (1 m reference, ≥ 10 cm), no dipole (the tear tip has no defined normal) and no
//! images.

use super::rng::NoiseRng;
use super::smoothing::LinearRamp;

/// Crackle exponent α (L 152, T 2040).
pub const TEAR_ALPHA: f32 = 100.0;
/// Speed at which grains reach ±1 (amplitude linear in speed), m/s.
pub const TEAR_AMP_REF_SPEED_M_S: f32 = 0.1;
/// Speed at which the grain rate reaches the seeds' 44.1 kHz, m/s.
pub const TEAR_PITCH_REF_SPEED_M_S: f32 = 0.1;
/// Lowest playback rate ρ.
pub const TEAR_MIN_RATE: f32 = 0.25;
/// Grain rate at ρ = 1, Hz (the seeds' sample rate).
pub const TEAR_GRAIN_RATE_HZ: f64 = 44_100.0;
/// Grains with r^α below this are 0 (denormal gate).
pub const GRAIN_GATE: f32 = 1e-6;
/// A tear onset's burst starts as loud as a tear at [`TEAR_AMP_REF_SPEED_M_S`] (impl. choice).
pub const ONSET_LEVEL: f32 = 1.0;
/// Decay time constant of the onset burst, ms (impl. choice: a snap, not a rip).
pub const ONSET_DECAY_MS: f64 = 4.0;
/// The burst ends below this level.
const ONSET_FLOOR: f32 = 1e-4;

/// Settings of the generator (tests vary them; the renderer uses [`TearSettings::default`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TearSettings {
    /// α.
    pub alpha: f32,
    /// Couple the playback rate to the speed (false: ρ = 1 always).
    pub pitch_follows_speed: bool,
}

impl Default for TearSettings {
    fn default() -> Self {
        Self {
            alpha: TEAR_ALPHA,
            pitch_follows_speed: true,
        }
    }
}

/// The tear-noise generator.
pub struct TearNoise {
    settings: TearSettings,
    sample_rate_hz: f64,
    r_gate: f32,
    rng: NoiseRng,
    seed: u64,
    /// Tear speed, m/s, interpolated per sample.
    speed: LinearRamp,
    /// Sample index (since reset) of the generator.
    n: u64,
    /// The onset burst's level (added to the speed's, in units of the reference speed).
    burst: f32,
    /// Per-sample decay of the burst.
    burst_decay: f32,
    /// Continuous time of the next grain, samples.
    next_time: f64,
    prev_pos: u64,
    prev_val: f32,
    next_pos: u64,
    next_val: f32,
    slope: f32,
}

impl TearNoise {
    /// A generator at a sample rate.
    pub fn new(sample_rate_hz: f64, seed: u64, settings: TearSettings) -> Self {
        let alpha = settings.alpha.max(0.0);
        let r_gate = if alpha > 0.0 {
            (GRAIN_GATE.ln() / alpha).exp()
        } else {
            0.0
        };
        let mut t = Self {
            settings,
            sample_rate_hz,
            r_gate,
            rng: NoiseRng::new(seed, 3),
            seed,
            speed: LinearRamp::default(),
            n: 0,
            burst: 0.0,
            burst_decay: (-1.0 / (ONSET_DECAY_MS * 1e-3 * sample_rate_hz)).exp() as f32,
            next_time: 0.0,
            prev_pos: 0,
            prev_val: 0.0,
            next_pos: 0,
            next_val: 0.0,
            slope: 0.0,
        };
        t.reset();
        t
    }

    /// Stops, clears and reseeds. No allocation.
    pub fn reset(&mut self) {
        self.rng = NoiseRng::new(self.seed, 3);
        self.speed.reset(0.0);
        self.n = 0;
        self.burst = 0.0;
        self.next_time = 0.0;
        self.prev_pos = 0;
        self.prev_val = 0.0;
        self.next_pos = 0;
        self.next_val = 0.0;
        self.slope = 0.0;
    }

    /// New tear speed (m/s), reached linearly over `ramp_samples`.
    pub fn set_speed(&mut self, speed_m_s: f32, ramp_samples: u32) {
        let v = if speed_m_s.is_finite() {
            speed_m_s.abs().min(10.0)
        } else {
            0.0
        };
        self.speed.set_target(v, ramp_samples);
    }

    /// A tear onset: a burst of dense grains at [`ONSET_LEVEL`], decaying with
    /// [`ONSET_DECAY_MS`], on top of the speed's (the first fibres break at once).
    pub fn onset(&mut self) {
        self.burst = ONSET_LEVEL;
    }

    /// True when the speed is and stays 0 and no onset burst plays.
    pub fn is_idle(&self) -> bool {
        self.speed.is_steady() && self.speed.value() == 0.0 && self.burst == 0.0
    }

    /// One grain: w · r^α (0 below the gate).
    #[inline]
    pub fn grain(&mut self) -> f32 {
        let (w, gain) = self.grain_parts();
        w * gain
    }

    /// One grain's noise sample w and crackle gain r^α (0 below the gate).
    #[inline]
    pub fn grain_parts(&mut self) -> (f32, f32) {
        let w = self.rng.signed();
        let r = self.rng.uniform_open0();
        if r < self.r_gate {
            (w, 0.0)
        } else {
            (w, (self.settings.alpha * r.ln()).exp())
        }
    }

    /// Playback rate ρ for a speed.
    pub fn rate_for(&self, speed_m_s: f32) -> f32 {
        if self.settings.pitch_follows_speed {
            (speed_m_s / TEAR_PITCH_REF_SPEED_M_S).clamp(TEAR_MIN_RATE, 1.0)
        } else {
            1.0
        }
    }

    /// Renders `out.len()` mono samples (overwrites). With `skip_idle`, a sample at which the
    /// generator is idle (speed steady at 0) is a zero and the generator does not run: it is
    /// decided per sample, so where a tear stops does not depend on how the host splits its
    /// blocks, nor, therefore, do the grains of the next tear. Returns how many samples the
    /// generator ran for.
    pub fn render(&mut self, out: &mut [f32], skip_idle: bool) -> usize {
        let mut ran = 0;
        for k in 0..out.len() {
            if skip_idle && self.is_idle() {
                // Idle stays idle until the next `set_speed`, i.e. for the rest of this call.
                out[k..].fill(0.0);
                break;
            }
            ran += 1;
            let v = self.speed.tick() + self.burst * TEAR_AMP_REF_SPEED_M_S;
            if self.burst > 0.0 {
                self.burst *= self.burst_decay;
                if self.burst < ONSET_FLOOR {
                    self.burst = 0.0;
                }
            }
            if self.n >= self.next_pos {
                // Reached the next grain: it becomes the previous one; draw a new next grain.
                self.prev_pos = self.next_pos;
                self.prev_val = self.next_val;
                let rho = f64::from(self.rate_for(v));
                let interval = (self.sample_rate_hz / (TEAR_GRAIN_RATE_HZ * rho)).max(1.0);
                self.next_time += interval;
                self.next_pos = (self.next_time.round() as u64).max(self.prev_pos + 1);
                self.next_val = self.grain();
                self.slope =
                    (self.next_val - self.prev_val) / (self.next_pos - self.prev_pos) as f32;
            }
            let y = self.prev_val + self.slope * (self.n - self.prev_pos) as f32;
            out[k] = y * (v / TEAR_AMP_REF_SPEED_M_S);
            self.n += 1;
        }
        ran
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grains_at_44k1_rate_1_are_the_seed_sequence() {
        let mut a = TearNoise::new(44_100.0, 7, TearSettings::default());
        let mut b = TearNoise::new(44_100.0, 7, TearSettings::default());
        a.set_speed(TEAR_AMP_REF_SPEED_M_S, 1);
        let mut out = vec![0.0f32; 1000];
        a.render(&mut out, true);
        // b's grains in order: output sample k (k ≥ 1) is grain k (the first grain sits at 0 and
        // is the initial zero).
        let grains: Vec<f32> = (0..1000).map(|_| b.grain()).collect();
        for k in 1..1000 {
            assert_eq!(out[k], grains[k - 1], "{k}");
        }
    }

    #[test]
    fn idle_generator_is_skipped_and_silent() {
        let mut t = TearNoise::new(48_000.0, 1, TearSettings::default());
        let mut out = vec![1.0f32; 64];
        assert_eq!(t.render(&mut out, true), 0);
        assert!(out.iter().all(|&v| v == 0.0));
        // A speed of 0 set again (every frame of a sheet that does not tear) stays idle.
        t.set_speed(0.0, 10);
        assert!(t.is_idle());
        t.set_speed(0.2, 10);
        assert_eq!(t.render(&mut out, true), 64);
        t.set_speed(0.0, 10);
        // The ramp lands on 0 after 10 samples; the generator stops there, within the call.
        assert_eq!(t.render(&mut out, true), 10);
        assert!(t.is_idle());
        assert!(out[10..].iter().all(|&v| v == 0.0));
    }
}
