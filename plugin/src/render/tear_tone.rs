//! # Tear tone: the tear noise coloured by the flaps at the tip (beyond the seeds)
//!
//! The seeds' tear is white crackle (w · r^α, [`super::tearing`]), and they say it lacks the
//! "specific tone" of a real tear (thesis T 2046, `000_cb4d91e46ec5927f.txt` §4.4; MIG 2015 §5,
//! `003_8cfb4a33a3603fcd.txt`). Here every fibre break rings the flaps at the tip: the crackle is
//! filtered by a short kernel whose magnitude is the database's friction spectrum of the flaps'
//! cell (l_r, l_c of the largest free region at the tip, `sim_core::Sim`'s tear frame) — the
//! seeds' own data for how a patch of that size sounds when it is excited by a broadband source.
//!
//! ```text
//! |H_j| = √(mean of S(ω)² over the friction bins within kernel bin j)     S: the cell's spectrum
//! h     = Hann · rotate_{K/2}(iFFT_K(|H|))  (zero phase → linear phase),  Σ h² = 1
//! y[t]  = Σ_τ x[τ] · h_{cell at τ}[t − τ]
//! ```
//!
//! Decisions, one line each:
//! - **Energy kept** (Σ h² = 1): white crackle keeps its level, so the seeds' amplitude law
//!   (linear in speed) and the mix level mean what they meant; the colour moves energy between
//!   bands only.
//! - **K ≈ 2.5 ms** (128 taps at 44.1/48 kHz, 32–256): the friction spectra are smooth
//!   envelopes; a 380 Hz resolution keeps their shape and costs little. Latency K/2 (1.3 ms).
//! - **Scatter, not gather**: each non-zero input sample adds x · h to an accumulator, so the
//!   crackle's zero samples (most grains are gated to 0) cost nothing, and a new kernel applies
//!   to the grains from then on while earlier grains ring out with theirs: no click at a switch.
//! - **No flaps, no database**: a frame without a resonator keeps the last kernel; before any,
//!   or without a usable database, the kernel is a delay of K/2 (the seeds' white crackle).
//! - The kernel is designed on the audio thread when the cell changes (one K-point real iFFT,
//!   preallocated); idle, the stage costs nothing once its tail has rung out. Taps at the
//!   kernel's ends below −80 dB of its peak are skipped ([`TAP_FLOOR`]); the white kernel is
//!   one tap (a delay).

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner};
use sim_core::sound_input::Resonator;
use sounddb::SoundDb;

/// Kernel length in seconds (rounded up to a power of two of samples).
pub const KERNEL_S: f64 = 0.0025;
/// Shortest kernel, taps.
pub const MIN_KERNEL: usize = 32;
/// Longest kernel, taps.
pub const MAX_KERNEL: usize = 256;
/// Taps at the kernel's ends below this fraction of its peak are skipped (−80 dB).
pub const TAP_FLOOR: f32 = 1e-4;

/// The colouring stage.
pub struct TearTone {
    k: usize,
    kernel: Vec<f32>,
    /// The kernel's taps above [`TAP_FLOOR`] of its peak: the rest are skipped.
    taps: std::ops::Range<usize>,
    cell: Option<u16>,
    acc: Vec<f32>,
    /// Samples of the accumulator that may still be non-zero.
    ringing: usize,
    ifft: Arc<dyn ComplexToReal<f32>>,
    spec: Vec<Complex<f32>>,
    time: Vec<f32>,
    scratch: Vec<Complex<f32>>,
    designs: u64,
}

impl TearTone {
    /// A stage for `max_block` samples per [`Self::process`] call at a rate. Allocates.
    pub fn new(sample_rate_hz: f64, max_block: usize) -> Self {
        let k = ((sample_rate_hz * KERNEL_S).ceil().max(1.0) as usize)
            .next_power_of_two()
            .clamp(MIN_KERNEL, MAX_KERNEL);
        let ifft = RealFftPlanner::<f32>::new().plan_fft_inverse(k);
        let mut t = Self {
            k,
            kernel: vec![0.0; k],
            taps: k / 2..k / 2 + 1,
            cell: None,
            acc: vec![0.0; max_block + k],
            ringing: 0,
            spec: ifft.make_input_vec(),
            time: ifft.make_output_vec(),
            scratch: ifft.make_scratch_vec(),
            ifft,
            designs: 0,
        };
        t.reset();
        t
    }

    /// Kernel length K, taps.
    pub fn kernel_len(&self) -> usize {
        self.k
    }

    /// The current kernel.
    pub fn kernel(&self) -> &[f32] {
        &self.kernel
    }

    /// Kernels designed since `new` (a cell change each).
    pub fn designs(&self) -> u64 {
        self.designs
    }

    /// Back to the white kernel and silence. No allocation.
    pub fn reset(&mut self) {
        self.acc.fill(0.0);
        self.ringing = 0;
        self.set_white();
    }

    fn set_white(&mut self) {
        self.kernel.fill(0.0);
        self.kernel[self.k / 2] = 1.0;
        self.taps = self.k / 2..self.k / 2 + 1;
        self.cell = None;
    }

    /// The taps above [`TAP_FLOOR`] of the peak.
    fn trim(&mut self) {
        let peak = self.kernel.iter().fold(0.0f32, |m, h| m.max(h.abs()));
        let keep = |h: &f32| h.abs() >= TAP_FLOOR * peak;
        let lo = self.kernel.iter().position(keep).unwrap_or(0);
        let hi = self.kernel.iter().rposition(keep).map_or(lo, |i| i + 1);
        self.taps = lo..hi;
    }

    /// The flaps of this frame: designs their kernel if their cell changed. A resonator of
    /// radius 0 (no flaps) keeps the kernel; an unusable database gives the white one.
    /// No allocation.
    pub fn set_resonator(&mut self, res: &Resonator, db: &SoundDb, db_usable: bool) {
        if !db_usable {
            if self.cell.is_some() {
                self.set_white();
            }
            return;
        }
        if res.radius_m.is_nan() || res.radius_m <= 0.0 {
            return;
        }
        let Some(cell) = db.friction_lookup(res.lr_cm, res.lc_cm) else {
            return;
        };
        if self.cell == Some(cell.0) {
            return;
        }
        self.design(db.friction_spectrum(cell), db.frame_len());
        self.cell = Some(cell.0);
        self.designs += 1;
    }

    /// Designs the kernel from a magnitude spectrum on the bins of an M-point frame.
    fn design(&mut self, spectrum: &[f32], m: usize) {
        let k = self.k;
        if m == 0 || spectrum.is_empty() {
            self.set_white();
            return;
        }
        // Kernel bin j spans friction bins whose frequency is within half a kernel bin of j's.
        let ratio = m as f64 / k as f64;
        for (j, c) in self.spec.iter_mut().enumerate() {
            let lo = ((j as f64 - 0.5) * ratio).ceil().max(0.0) as usize;
            let hi = (((j as f64 + 0.5) * ratio).ceil() as usize).min(spectrum.len());
            let (mut sum, mut n) = (0.0f64, 0usize);
            for &s in spectrum.get(lo..hi).unwrap_or(&[]) {
                sum += f64::from(s) * f64::from(s);
                n += 1;
            }
            let mag = if n > 0 { (sum / n as f64).sqrt() } else { 0.0 };
            *c = Complex::new(mag as f32, 0.0);
        }
        // DC and Nyquist must be real (they are); the transform cannot fail on its own sizes.
        if self
            .ifft
            .process_with_scratch(&mut self.spec, &mut self.time, &mut self.scratch)
            .is_err()
        {
            self.set_white();
            return;
        }
        let mut energy = 0.0f64;
        for n in 0..k {
            let w = (std::f64::consts::PI * (n as f64 + 0.5) / k as f64).sin();
            let h = f64::from(self.time[(n + k / 2) % k]) * w * w;
            self.kernel[n] = h as f32;
            energy += h * h;
        }
        if energy > 0.0 && energy.is_finite() {
            let g = (1.0 / energy.sqrt()) as f32;
            for h in &mut self.kernel {
                *h *= g;
            }
            self.trim();
        } else {
            self.set_white();
        }
    }

    /// Colours `buf` in place (its samples are the crackle; zeros where the generator was idle).
    /// `input_silent`: the caller knows `buf` is all zeros (then only the tail plays, and an
    /// idle stage returns at once). At most `max_block` samples. No allocation.
    pub fn process(&mut self, buf: &mut [f32], input_silent: bool) {
        let n = buf.len().min(self.acc.len() - self.k);
        let k = self.k;
        if input_silent && self.ringing == 0 {
            return;
        }
        if !input_silent {
            let (lo, hi) = (self.taps.start, self.taps.end);
            let taps = &self.kernel[lo..hi];
            for (t, &x) in buf[..n].iter().enumerate() {
                if x != 0.0 {
                    for (a, h) in self.acc[t + lo..t + hi].iter_mut().zip(taps) {
                        *a += x * h;
                    }
                }
            }
            self.ringing = n + k;
        }
        buf[..n].copy_from_slice(&self.acc[..n]);
        self.acc.copy_within(n..n + k, 0);
        self.acc[k..n + k].fill(0.0);
        self.ringing = self.ringing.saturating_sub(n);
        if self.ringing == 0 {
            self.acc[..k].fill(0.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noise(n: usize, seed: u32) -> Vec<f32> {
        let mut s = seed.wrapping_mul(2_654_435_761).max(1);
        (0..n)
            .map(|_| {
                s ^= s << 13;
                s ^= s >> 17;
                s ^= s << 5;
                (s as f32 / u32::MAX as f32) * 2.0 - 1.0
            })
            .collect()
    }

    #[test]
    fn white_kernel_is_a_delay_of_half_its_length() {
        let mut t = TearTone::new(48_000.0, 256);
        assert_eq!(t.kernel_len(), 128);
        let x = noise(256, 3);
        let mut y = x.clone();
        t.process(&mut y, false);
        for i in 64..256 {
            assert_eq!(y[i], x[i - 64]);
        }
        assert!(y[..64].iter().all(|&v| v == 0.0));
    }

    #[test]
    fn block_splits_do_not_change_the_output() {
        let spectrum: Vec<f32> = (0..1121).map(|b| 1.0 / (1.0 + b as f32 / 40.0)).collect();
        let x = noise(3000, 9);
        let run = |sizes: &[usize]| {
            let mut t = TearTone::new(48_000.0, 512);
            t.design(&spectrum, 2240);
            let mut out = Vec::new();
            let mut i = 0;
            let mut s = 0;
            while i < x.len() {
                let n = sizes[s % sizes.len()].min(x.len() - i);
                let mut b = x[i..i + n].to_vec();
                t.process(&mut b, false);
                out.extend(b);
                i += n;
                s += 1;
            }
            out
        };
        let a = run(&[512]);
        let b = run(&[1, 7, 300, 64]);
        assert_eq!(a, b);
    }

    #[test]
    fn a_low_spectrum_darkens_and_keeps_the_energy() {
        // Magnitude falling 12 dB/octave above 1 kHz on a 2240-point frame at 48 kHz.
        let df = 48_000.0 / 2240.0;
        let spectrum: Vec<f32> = (0..1121)
            .map(|b| {
                let f = (b as f32 * df).max(1.0);
                1.0 / (1.0 + (f / 1000.0).powi(2))
            })
            .collect();
        let mut t = TearTone::new(48_000.0, 4096);
        t.design(&spectrum, 2240);
        let energy: f32 = t.kernel().iter().map(|h| h * h).sum();
        assert!((energy - 1.0).abs() < 1e-4, "{energy}");
        let x = noise(4096, 5);
        let mut y = x.clone();
        t.process(&mut y, false);
        // High-band energy share: first differences weigh high frequencies.
        let hf = |v: &[f32]| {
            let d: f32 = v.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum();
            d / v.iter().map(|s| s * s).sum::<f32>()
        };
        assert!(hf(&y[256..]) < 0.2 * hf(&x[256..]), "{} {}", hf(&y), hf(&x));
        let ex: f32 = x[256..3800].iter().map(|s| s * s).sum();
        let ey: f32 = y[256..3800].iter().map(|s| s * s).sum();
        assert!((ey / ex - 1.0).abs() < 0.2, "{}", ey / ex);
    }

    #[test]
    fn silence_costs_nothing_once_the_tail_rang_out() {
        let mut t = TearTone::new(44_100.0, 256);
        let mut b = noise(100, 1);
        t.process(&mut b, false);
        let mut z = vec![0.0f32; 256];
        t.process(&mut z, true);
        assert!(z[..28].iter().any(|&v| v != 0.0));
        let mut z2 = vec![0.0f32; 256];
        t.process(&mut z2, true);
        assert!(z2.iter().all(|&v| v == 0.0));
        assert_eq!(t.ringing, 0);
    }
}
