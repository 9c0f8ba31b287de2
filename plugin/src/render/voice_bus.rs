//! # The crumple voices' bus at the unit rate, interpolated to the host rate
//!
//! Above 88 kHz the database stores its units at a half or a quarter of the host rate
//! (`sounddb::unit_decimation`; the embedded database is recorded at 44.1 kHz, so nothing of it
//! lies above 22 kHz). The voice pool then plays every unit at that **unit rate** into a small
//! bus, and this module interpolates the bus once to the host rate: one filter for the sum of
//! all voices instead of every voice's taps running at the host rate. At 96 kHz that halves the
//! voices' multiply-adds, at 192 kHz it quarters them (`docs/benchmarks.md`, "Render path").
//!
//! ## The interpolator
//!
//! An interpolation by D ∈ {2, 4} is a zero-stuffing followed by a low-pass at the unit rate's
//! Nyquist frequency. Written in its polyphase form, output sample D·q + r is a dot product of
//! the last [`TAPS_PER_PHASE`] unit-rate samples with phase r of the prototype:
//!
//! ```text
//! y[D·q + r] = Σ_{j=0}^{K−1} c_r[j] · x[q − j],      c_r[j] = D · h[D·j + r],   K = 32
//! h[n] = (1/D) · sinc((n − (N−1)/2) / D) · kaiser_β(n),   n = 0 … N−1,  N = K·D,  β = 8
//! ```
//!
//! The Kaiser window with β = 8 gives about 80 dB of stop band; with N = 64 taps at D = 2
//! (128 at D = 4) the transition runs from about 20 to 28 kHz when the unit rate is 48 kHz, so
//! the audible band passes flat and the images of a 20 kHz component (at 28 kHz) are 80 dB
//! down. Each phase is scaled to sum to exactly 1, so a constant passes unchanged at every
//! phase. The filter delays the voices by (N − 1)/2 host samples: 0.33 ms at 96 and 192 kHz
//! (0.36 ms at 88.2 and 176.4 kHz) — the crumple units sound that much after the friction and
//! tearing noise of the same frame, far below the friction's own hop of 23 ms. Below 88 kHz
//! the bus is not used at all and the voices play at the host rate as before.
//!
//! ## Chunks, determinism, silence
//!
//! A host chunk of n samples needs ⌈(n − pending)/D⌉ new unit-rate samples; the up to D − 1
//! host samples made beyond the chunk wait for the next one. The bus therefore always has
//! rendered exactly ⌈clock/D⌉ unit-rate samples after a chunk ending at host sample `clock`, so
//! a voice triggered between two chunks starts at unit sample ⌈clock/D⌉ however the host
//! splits its blocks ([`VoiceBus::voice_clock`]), and the output does not depend on the split.
//! When the filter's history and the new samples are all exactly zero, the output is zero
//! without any arithmetic (an idle voice pool costs nothing here).

use sounddb::resample::bessel_i0;

use super::voice_pool::MAX_CHUNK;

/// Prototype taps per phase (K).
pub const TAPS_PER_PHASE: usize = 32;
/// Kaiser window β (≈ 80 dB stop band).
pub const KAISER_BETA: f64 = 8.0;
/// Largest interpolation factor.
pub const MAX_FACTOR: usize = 4;
/// Unit-rate samples rendered at most per host chunk.
const MAX_LOW: usize = MAX_CHUNK + 1;

/// The polyphase coefficients of an interpolation by `factor`, each phase reversed (so a phase
/// is a dot product with the history in time order) and scaled to sum to 1.
pub fn polyphase_coefficients(factor: usize) -> Vec<[f32; TAPS_PER_PHASE]> {
    let d = factor.max(1);
    let n = TAPS_PER_PHASE * d;
    let centre = (n as f64 - 1.0) / 2.0;
    let norm = bessel_i0(KAISER_BETA);
    let h: Vec<f64> = (0..n)
        .map(|i| {
            let t = (i as f64 - centre) / d as f64;
            let sinc = if t == 0.0 {
                1.0
            } else {
                (std::f64::consts::PI * t).sin() / (std::f64::consts::PI * t)
            };
            let u = 2.0 * i as f64 / (n as f64 - 1.0) - 1.0;
            let w = bessel_i0(KAISER_BETA * (1.0 - u * u).max(0.0).sqrt()) / norm;
            sinc * w
        })
        .collect();
    (0..d)
        .map(|r| {
            let phase: Vec<f64> = (0..TAPS_PER_PHASE).map(|j| h[d * j + r]).collect();
            let sum: f64 = phase.iter().sum();
            let mut rev = [0.0f32; TAPS_PER_PHASE];
            for (j, c) in phase.iter().enumerate() {
                rev[TAPS_PER_PHASE - 1 - j] = (c / sum) as f32;
            }
            rev
        })
        .collect()
}

/// Σ c·x over one phase, in eight independent lanes (a plain `sum` of f32 is a serial chain
/// the compiler may not reorder; lanes let it use vector registers).
#[inline]
fn dot(c: &[f32; TAPS_PER_PHASE], x: &[f32]) -> f32 {
    let x = &x[..TAPS_PER_PHASE];
    let mut lanes = [0.0f32; 8];
    for (cc, xc) in c.chunks_exact(8).zip(x.chunks_exact(8)) {
        for l in 0..8 {
            lanes[l] += cc[l] * xc[l];
        }
    }
    ((lanes[0] + lanes[4]) + (lanes[1] + lanes[5]))
        + ((lanes[2] + lanes[6]) + (lanes[3] + lanes[7]))
}

/// The bus: unit-rate buffers for the voices and the interpolator's state.
pub struct VoiceBus {
    factor: usize,
    phases: Vec<[f32; TAPS_PER_PHASE]>,
    /// Per ear: K − 1 samples of history, then the chunk's new unit-rate samples.
    work: [Vec<f32>; 2],
    /// Host-rate samples made beyond the last chunk (fewer than `factor`), per ear.
    pending: [[f32; MAX_FACTOR]; 2],
    num_pending: usize,
    /// Unit-rate samples rendered since reset.
    low_clock: u64,
    /// The history is all exactly zero.
    history_silent: bool,
}

impl VoiceBus {
    /// A bus interpolating by `factor` (2 or 4; 1 passes the voices through at the host rate).
    /// Allocates.
    pub fn new(factor: usize) -> Self {
        let factor = factor.clamp(1, MAX_FACTOR);
        Self {
            factor,
            phases: polyphase_coefficients(factor),
            work: std::array::from_fn(|_| vec![0.0; TAPS_PER_PHASE - 1 + MAX_LOW]),
            pending: [[0.0; MAX_FACTOR]; 2],
            num_pending: 0,
            low_clock: 0,
            history_silent: true,
        }
    }

    /// The interpolation factor D.
    pub fn factor(&self) -> usize {
        self.factor
    }

    /// Unit-rate samples rendered so far: where a voice triggered now starts. No allocation.
    pub fn voice_clock(&self) -> u64 {
        self.low_clock
    }

    /// Back to silence at clock 0. No allocation.
    pub fn reset(&mut self) {
        for w in &mut self.work {
            w.fill(0.0);
        }
        self.pending = [[0.0; MAX_FACTOR]; 2];
        self.num_pending = 0;
        self.low_clock = 0;
        self.history_silent = true;
    }

    /// Host samples one [`Self::render`] call takes at most: [`MAX_CHUNK`] unit-rate samples'
    /// worth, so the voices render as long spans as they do at the host rate below 88 kHz.
    pub fn max_chunk(&self) -> usize {
        MAX_CHUNK * self.factor
    }

    /// Writes `out_l.len()` (≤ [`Self::max_chunk`]) host-rate samples of the voices into `out_l`
    /// and `out_r` (overwritten). `fill(l, r)` must add the next `l.len()` unit-rate samples of the
    /// voices into the zeroed `l` and `r`. No allocation.
    pub fn render(
        &mut self,
        out_l: &mut [f32],
        out_r: &mut [f32],
        mut fill: impl FnMut(&mut [f32], &mut [f32]),
    ) {
        let n = out_l.len().min(out_r.len()).min(self.max_chunk());
        let d = self.factor;
        if d == 1 {
            // No interpolation: the voices play at the host rate.
            out_l[..n].fill(0.0);
            out_r[..n].fill(0.0);
            fill(&mut out_l[..n], &mut out_r[..n]);
            self.low_clock += n as u64;
            return;
        }
        // The samples made beyond the previous chunk come first.
        let from_pending = self.num_pending.min(n);
        for (out, pending) in [&mut *out_l, &mut *out_r]
            .into_iter()
            .zip(&mut self.pending)
        {
            out[..from_pending].copy_from_slice(&pending[..from_pending]);
            pending.copy_within(from_pending.., 0);
        }
        self.num_pending -= from_pending;
        let rest = n - from_pending;
        if rest == 0 {
            return;
        }
        let m = rest.div_ceil(d);
        const H: usize = TAPS_PER_PHASE - 1;
        let [wl, wr] = &mut self.work;
        wl[H..H + m].fill(0.0);
        wr[H..H + m].fill(0.0);
        fill(&mut wl[H..H + m], &mut wr[H..H + m]);
        self.low_clock += m as u64;
        let silent = self.history_silent
            && wl[H..H + m].iter().all(|v| *v == 0.0)
            && wr[H..H + m].iter().all(|v| *v == 0.0);
        let outs = [&mut *out_l, &mut *out_r];
        for ((out, work), pending) in outs.into_iter().zip(&self.work).zip(&mut self.pending) {
            let mut k = from_pending;
            for q in 0..m {
                // work[q + K − 1] is x[q]; the phases are reversed.
                let hist = &work[q..q + TAPS_PER_PHASE];
                for phase in &self.phases {
                    let y = if silent { 0.0 } else { dot(phase, hist) };
                    if k < n {
                        out[k] = y;
                    } else {
                        pending[k - n] = y;
                    }
                    k += 1;
                }
            }
        }
        self.num_pending = m * d - rest;
        for w in &mut self.work {
            w.copy_within(m..m + H, 0);
        }
        self.history_silent = self.work.iter().all(|w| w[..H].iter().all(|v| *v == 0.0));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Interpolates a whole unit-rate signal by feeding it through the bus in host chunks.
    fn interpolate(factor: usize, x: &[f32], chunks: &[usize], total: usize) -> Vec<f32> {
        let mut bus = VoiceBus::new(factor);
        let mut out = vec![0.0f32; total];
        let mut right = vec![0.0f32; total];
        let mut pos = 0usize;
        let mut read = 0usize;
        let mut c = 0;
        while pos < total {
            let n = chunks[c % chunks.len()].min(total - pos);
            c += 1;
            bus.render(&mut out[pos..pos + n], &mut right[pos..pos + n], |l, r| {
                for (i, (a, b)) in l.iter_mut().zip(r.iter_mut()).enumerate() {
                    let v = x.get(read + i).copied().unwrap_or(0.0);
                    *a += v;
                    *b -= v;
                }
                read += l.len();
            });
            pos += n;
        }
        assert!(out.iter().zip(&right).all(|(a, b)| *a == -*b));
        out
    }

    #[test]
    fn each_phase_passes_a_constant_exactly_and_the_filter_is_symmetric() {
        for d in [1usize, 2, 4] {
            let p = polyphase_coefficients(d);
            assert_eq!(p.len(), d);
            for phase in &p {
                let s: f64 = phase.iter().map(|c| f64::from(*c)).sum();
                assert!((s - 1.0).abs() < 1e-6, "D = {d}: {s}");
            }
        }
        // A constant comes out as the same constant once the history is full.
        let x = vec![0.25f32; 400];
        let y = interpolate(2, &x, &[64], 700);
        for v in &y[2 * TAPS_PER_PHASE..700] {
            assert!((v - 0.25).abs() < 1e-6, "{v}");
        }
    }

    #[test]
    fn the_output_does_not_depend_on_the_chunks() {
        let x: Vec<f32> = (0..900)
            .map(|i| ((i * 7919 % 1000) as f32 / 500.0 - 1.0) * 0.3)
            .collect();
        for d in [2usize, 4] {
            let total = 900 * d;
            let a = interpolate(d, &x, &[256], total);
            for chunks in [&[1usize][..], &[3, 250, 7], &[255, 1, 2]] {
                let b = interpolate(d, &x, chunks, total);
                assert_eq!(a, b, "D = {d}, chunks {chunks:?}");
            }
        }
    }

    /// Amplitude of the `hz` component of `y` (host rate `rate`), by correlation under a
    /// Blackman window (so a tone 9 kHz away does not leak into the estimate).
    fn amplitude(y: &[f32], rate: f64, hz: f64) -> f64 {
        let (mut c, mut s, mut wsum) = (0.0, 0.0, 0.0);
        let n = y.len() as f64;
        for (i, v) in y.iter().enumerate() {
            let a = 2.0 * std::f64::consts::PI * i as f64 / n;
            let w = 0.42 - 0.5 * a.cos() + 0.08 * (2.0 * a).cos();
            let ph = 2.0 * std::f64::consts::PI * hz * i as f64 / rate;
            c += w * f64::from(*v) * ph.cos();
            s += w * f64::from(*v) * ph.sin();
            wsum += w;
        }
        2.0 * (c * c + s * s).sqrt() / wsum
    }

    #[test]
    fn the_audible_band_passes_flat_and_images_are_80_db_down() {
        // Unit rate 48 kHz, host 96 and 192 kHz.
        for d in [2usize, 4] {
            let low = 48_000.0;
            let host = low * d as f64;
            for f in [1_000.0, 10_000.0, 19_000.0] {
                let x: Vec<f32> = (0..9_600)
                    .map(|i| (2.0 * std::f64::consts::PI * f * i as f64 / low).sin() as f32)
                    .collect();
                let y = interpolate(d, &x, &[256], 9_600 * d);
                let steady = &y[1_000 * d..9_000 * d];
                let pass = amplitude(steady, host, f);
                assert!((pass - 1.0).abs() < 0.01, "D = {d}, {f} Hz: gain {pass}");
                // The images, at k × the unit rate ± f below the host's Nyquist frequency.
                let mut worst_db = f64::NEG_INFINITY;
                for k in 1..d {
                    for image_hz in [k as f64 * low - f, k as f64 * low + f] {
                        if image_hz < host / 2.0 {
                            let a = amplitude(steady, host, image_hz);
                            worst_db = worst_db.max(20.0 * a.log10());
                        }
                    }
                }
                assert!(worst_db < -75.0, "D = {d}, {f} Hz: image {worst_db:.1} dB");
            }
        }
    }

    #[test]
    fn silence_in_silence_out_and_the_clock_counts_unit_samples() {
        let mut bus = VoiceBus::new(2);
        let (mut l, mut r) = (vec![1.0f32; 101], vec![1.0f32; 101]);
        let mut calls = 0;
        bus.render(&mut l, &mut r, |_, _| calls += 1);
        assert!(l.iter().chain(&r).all(|v| *v == 0.0));
        assert_eq!(calls, 1);
        assert_eq!(bus.voice_clock(), 51);
        // One host sample is already made: a chunk of 1 needs no new unit sample.
        bus.render(&mut l[..1], &mut r[..1], |_, _| calls += 1);
        assert_eq!((calls, bus.voice_clock()), (1, 51));
        bus.reset();
        assert_eq!(bus.voice_clock(), 0);
    }
}
