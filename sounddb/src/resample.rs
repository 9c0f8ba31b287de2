//! # Load-time resampling (never on the audio thread)
//!
//! **Units** are resampled with a Kaiser-windowed sinc (β = 8.6, 24 zero crossings each side,
//! cut-off 0.95 × the lower Nyquist frequency). For integer rates whose reduced ratio L/M has
//! L ≤ 4096 (every usual pair: 44.1 → 48 kHz is 160/147) the kernel is tabulated exactly per
//! polyphase branch; otherwise it is evaluated from a fine table (4096 points per zero crossing)
//! with linear interpolation. Pass band flat to ±0.05 dB up to ~0.9 × Nyquist; stop band below
//! about −80 dB. Cost is O(output length × 48 / min(1, ratio)). A branch's dot product is summed
//! in eight partial sums, in one AVX register where the CPU has AVX (chosen at run time): the
//! same products added in the same order, so the same bits on every x86-64 (no fused
//! multiply-add, which would round differently).
//!
//! **Spectra** are moved from the database's bins (f_k = k·Δf_src) onto the render path's FFT bins
//! (f_j = j·fs/M) by averaging the power spectral density s²/Δf_src — linearly interpolated
//! between source bins — over each destination band [f_j − Δf/2, f_j + Δf/2] (16 points per
//! band). Averaging (rather than point sampling) keeps narrow modal peaks' energy when the
//! destination bins are wider than the source bins. Above the source's last bin the PSD is 0.

use std::f64::consts::PI;

const ZERO_CROSSINGS: usize = 24;
const TABLE_RES: usize = 4096;
const KAISER_BETA: f64 = 8.6;
const CUTOFF: f64 = 0.95;

/// Σ x_i h_i in eight partial sums (the compiler vectorizes them; one running sum it may not
/// reorder), added pairwise at the end: 4–5× faster than one sum, and the units' resampling
/// was half of a render's start-up.
#[inline(always)]
fn dot(x: &[f32], h: &[f32]) -> f32 {
    let mut lanes = [0.0f32; 8];
    let (xc, hc) = (x.chunks_exact(8), h.chunks_exact(8));
    let (xr, hr) = (xc.remainder(), hc.remainder());
    for (a, b) in xc.zip(hc) {
        for ((l, a), b) in lanes.iter_mut().zip(a).zip(b) {
            *l += a * b;
        }
    }
    let mut tail = 0.0f32;
    for (a, b) in xr.iter().zip(hr) {
        tail += a * b;
    }
    ((lanes[0] + lanes[4]) + (lanes[1] + lanes[5]))
        + ((lanes[2] + lanes[6]) + (lanes[3] + lanes[7]))
        + tail
}

/// [`dot`] with its eight partial sums in one AVX register: the same products and sums in
/// the same order (AVX has no fused multiply-add), so the same bits.
///
/// # Safety
/// The CPU must have AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
unsafe fn dot_avx(x: &[f32], h: &[f32]) -> f32 {
    use std::arch::x86_64::{
        _mm256_add_ps, _mm256_loadu_ps, _mm256_mul_ps, _mm256_setzero_ps, _mm256_storeu_ps,
    };
    let n = x.len().min(h.len());
    let chunks = n / 8;
    let mut acc = _mm256_setzero_ps();
    for c in 0..chunks {
        // SAFETY: 8·c + 8 ≤ n, within both slices.
        let (a, b) = unsafe {
            (
                _mm256_loadu_ps(x.as_ptr().add(8 * c)),
                _mm256_loadu_ps(h.as_ptr().add(8 * c)),
            )
        };
        acc = _mm256_add_ps(acc, _mm256_mul_ps(a, b));
    }
    let mut lanes = [0.0f32; 8];
    // SAFETY: `lanes` holds eight floats.
    unsafe { _mm256_storeu_ps(lanes.as_mut_ptr(), acc) };
    let mut tail = 0.0f32;
    for (a, b) in x[8 * chunks..n].iter().zip(&h[8 * chunks..n]) {
        tail += a * b;
    }
    ((lanes[0] + lanes[4]) + (lanes[1] + lanes[5]))
        + ((lanes[2] + lanes[6]) + (lanes[3] + lanes[7]))
        + tail
}

/// Windowed-sinc resampler from one rate to another.
pub struct Resampler {
    ratio: f64,
    /// Kernel cut-off relative to the input Nyquist frequency.
    fc: f64,
    table: Vec<f32>,
    poly: Option<Polyphase>,
}

/// Exact polyphase branches for a rational ratio L/M.
struct Polyphase {
    up: usize,
    down: usize,
    /// Taps on each side (branch length 2·half).
    half: usize,
    /// up × 2·half coefficients; branch p, tap j ↔ input offset j − half + 1 from the base.
    coeffs: Vec<f32>,
}

impl Polyphase {
    /// The output: each sample the dot product of its branch with the input under it.
    #[inline(always)]
    fn process_with(
        &self,
        input: &[f32],
        out_len: usize,
        dot: impl Fn(&[f32], &[f32]) -> f32,
    ) -> Vec<f32> {
        let taps = 2 * self.half;
        let mut out = Vec::with_capacity(out_len);
        for n in 0..out_len {
            let num = n * self.down;
            let (base, phase) = (num / self.up, num % self.up);
            let branch = &self.coeffs[phase * taps..(phase + 1) * taps];
            let first = base as isize - self.half as isize + 1;
            let lo = (-first).max(0) as usize;
            let hi = (input.len() as isize - first).clamp(0, taps as isize) as usize;
            let mut acc = 0.0f32;
            if lo < hi {
                let start = (first + lo as isize) as usize;
                acc = dot(&input[start..start + hi - lo], &branch[lo..hi]);
            }
            out.push(acc);
        }
        out
    }

    /// [`Self::process_with`] on AVX ([`dot_avx`]): the same bits, about twice as fast.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn process_avx(&self, input: &[f32], out_len: usize) -> Vec<f32> {
        // SAFETY: this function runs only where AVX is (its caller checks).
        self.process_with(input, out_len, |x, h| unsafe { dot_avx(x, h) })
    }
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

fn kernel(x: f64, i0b: f64) -> f64 {
    // x in zero crossings.
    let ax = x.abs();
    if ax >= ZERO_CROSSINGS as f64 {
        return 0.0;
    }
    let sinc = if ax < 1e-12 {
        1.0
    } else {
        (PI * ax).sin() / (PI * ax)
    };
    let r = ax / ZERO_CROSSINGS as f64;
    sinc * bessel_i0(KAISER_BETA * (1.0 - r * r).max(0.0).sqrt()) / i0b
}

impl Resampler {
    /// A resampler from `from_hz` to `to_hz`.
    pub fn new(from_hz: f64, to_hz: f64) -> Self {
        let ratio = to_hz / from_hz;
        let fc = CUTOFF * ratio.min(1.0);
        let i0b = bessel_i0(KAISER_BETA);
        let integer = |v: f64| v > 0.0 && (v - v.round()).abs() < 1e-9;
        let poly = (integer(from_hz) && integer(to_hz)).then(|| {
            let (f, t) = (from_hz.round() as u64, to_hz.round() as u64);
            let g = gcd(f, t);
            (t / g, f / g)
        });
        let poly = poly.filter(|&(up, _)| up <= 4096).map(|(up, down)| {
            let half = (ZERO_CROSSINGS as f64 / fc).ceil() as usize + 1;
            let mut coeffs = Vec::with_capacity(up as usize * 2 * half);
            for p in 0..up {
                let delta = p as f64 / up as f64;
                for j in 0..2 * half {
                    // Input index base + j − half + 1; distance t − k = delta − (j − half + 1).
                    let d = delta - (j as f64 - half as f64 + 1.0);
                    coeffs.push((kernel(d * fc, i0b) * fc) as f32);
                }
            }
            Polyphase {
                up: up as usize,
                down: down as usize,
                half,
                coeffs,
            }
        });
        // The fine table serves the ratios without exact branches only.
        let n = if poly.is_some() {
            0
        } else {
            ZERO_CROSSINGS * TABLE_RES + 2
        };
        let table = (0..n)
            .map(|i| {
                let x = i as f64 / TABLE_RES as f64; // in zero crossings
                if x >= ZERO_CROSSINGS as f64 {
                    return 0.0;
                }
                let sinc = if x == 0.0 {
                    1.0
                } else {
                    (PI * x).sin() / (PI * x)
                };
                let r = x / ZERO_CROSSINGS as f64;
                let w = bessel_i0(KAISER_BETA * (1.0 - r * r).max(0.0).sqrt()) / i0b;
                (sinc * w) as f32
            })
            .collect();
        Self {
            ratio,
            fc,
            table,
            poly,
        }
    }

    /// Output length for an input of `n` samples.
    pub fn output_len(&self, n: usize) -> usize {
        ((n as f64) * self.ratio).ceil() as usize
    }

    /// Resamples `input` (zero outside). The output covers the same duration.
    pub fn process(&self, input: &[f32]) -> Vec<f32> {
        if (self.ratio - 1.0).abs() < 1e-12 {
            return input.to_vec();
        }
        if let Some(p) = &self.poly {
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx") {
                // SAFETY: the CPU has AVX (checked just above).
                return unsafe { p.process_avx(input, self.output_len(input.len())) };
            }
            return p.process_with(input, self.output_len(input.len()), dot);
        }
        self.process_table(input)
    }

    /// The ratios without exact polyphase branches: the kernel from the fine table.
    fn process_table(&self, input: &[f32]) -> Vec<f32> {
        let out_len = self.output_len(input.len());
        let half_width = ZERO_CROSSINGS as f64 / self.fc; // in input samples
        let mut out = Vec::with_capacity(out_len);
        for n in 0..out_len {
            let t = n as f64 / self.ratio;
            let lo = ((t - half_width).ceil().max(0.0)) as usize;
            let hi = ((t + half_width).floor() as isize).min(input.len() as isize - 1);
            let mut acc = 0.0f64;
            if hi >= lo as isize {
                for (k, &x) in input.iter().enumerate().take(hi as usize + 1).skip(lo) {
                    let u = ((t - k as f64) * self.fc).abs() * TABLE_RES as f64;
                    let i = u as usize;
                    let frac = (u - i as f64) as f32;
                    let h = self.table[i] + (self.table[i + 1] - self.table[i]) * frac;
                    acc += f64::from(x * h);
                }
            }
            out.push((acc * self.fc) as f32);
        }
        out
    }
}

/// Zeroth-order modified Bessel function of the first kind (series), for Kaiser windows.
pub fn bessel_i0(x: f64) -> f64 {
    let mut sum = 1.0;
    let mut term = 1.0;
    let q = x * x / 4.0;
    for k in 1..64 {
        term *= q / (k as f64 * k as f64);
        sum += term;
        if term < sum * 1e-17 {
            break;
        }
    }
    sum
}

/// Moves a spectrum (`src[k]` = RMS amplitude in the band of width `src_df_hz` around
/// `k·src_df_hz`) onto `dst_bins` bins `j·dst_df_hz`, returning the **power** in each destination
/// band (PSD averaged over the band × `dst_df_hz`).
pub fn spectrum_band_power(
    src: &[f32],
    src_df_hz: f64,
    dst_bins: usize,
    dst_df_hz: f64,
) -> Vec<f64> {
    const POINTS: usize = 16;
    let psd = |f: f64| -> f64 {
        if f < 0.0 {
            return 0.0;
        }
        let x = f / src_df_hz;
        // x ≥ 0: the cast truncates to floor(x) without the library call.
        let k = x as usize;
        if k + 1 >= src.len() {
            return if k + 1 == src.len() {
                f64::from(src[k]).powi(2) / src_df_hz
            } else {
                0.0
            };
        }
        let a = f64::from(src[k]).powi(2);
        let b = f64::from(src[k + 1]).powi(2);
        (a + (b - a) * (x - k as f64)) / src_df_hz
    };
    (0..dst_bins)
        .map(|j| {
            let centre = j as f64 * dst_df_hz;
            let mut acc = 0.0;
            for p in 0..POINTS {
                let f = centre + dst_df_hz * ((p as f64 + 0.5) / POINTS as f64 - 0.5);
                acc += psd(f);
            }
            acc / POINTS as f64 * dst_df_hz
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX path (where the CPU has it) gives the portable path's bits.
    #[test]
    fn the_avx_dot_product_has_the_portable_bits() {
        let r = Resampler::new(44_100.0, 48_000.0);
        let p = r.poly.as_ref().expect("44.1 → 48 kHz has exact branches");
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for len in [1, 7, 53, 54, 55, 1000, 4801] {
            let x: Vec<f32> = (0..len)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    (state >> 40) as f32 / (1u64 << 23) as f32 - 1.0
                })
                .collect();
            let portable = p.process_with(&x, r.output_len(len), dot);
            let used = r.process(&x);
            assert_eq!(portable.len(), used.len());
            for (a, b) in portable.iter().zip(&used) {
                assert_eq!(a.to_bits(), b.to_bits(), "length {len}");
            }
        }
    }

    fn sine(freq: f64, rate: f64, n: usize) -> Vec<f32> {
        (0..n)
            .map(|i| (2.0 * PI * freq * i as f64 / rate).sin() as f32)
            .collect()
    }

    #[test]
    fn sine_survives_up_and_down() {
        for (from, to) in [
            (44_100.0, 48_000.0),
            (44_100.0, 96_000.0),
            (44_100.0, 8_000.0),
            (44_100.0, 47_999.5),
        ] {
            let f = 1000.0;
            let x = sine(f, from, 8000);
            let r = Resampler::new(from, to);
            let y = r.process(&x);
            assert_eq!(y.len(), r.output_len(x.len()));
            let expect = sine(f, to, y.len());
            // Compare away from the edges.
            let m = y.len() / 4;
            let err = y[m..3 * m]
                .iter()
                .zip(&expect[m..3 * m])
                .map(|(a, b)| (a - b).abs())
                .fold(0.0f32, f32::max);
            assert!(err < 2e-3, "{from}->{to}: err {err}");
        }
    }

    #[test]
    fn above_new_nyquist_is_removed() {
        let x = sine(6000.0, 44_100.0, 8000);
        let y = Resampler::new(44_100.0, 8_000.0).process(&x);
        let m = y.len() / 4;
        let rms = (y[m..3 * m].iter().map(|v| v * v).sum::<f32>() / (2 * m) as f32).sqrt();
        assert!(rms < 1e-3, "aliased rms {rms}");
    }

    #[test]
    fn band_power_is_conserved() {
        let src: Vec<f32> = (0..2048)
            .map(|k| 0.01 + (k as f32 * 0.01).sin().abs() * 0.02)
            .collect();
        let total_src: f64 = src.iter().map(|s| f64::from(*s).powi(2)).sum();
        let df = 44_100.0 / 4096.0;
        let dst = spectrum_band_power(&src, df, 1025, 44_100.0 / 2048.0);
        let total_dst: f64 = dst.iter().sum();
        assert!(
            (total_dst / total_src - 1.0).abs() < 0.01,
            "{total_dst} vs {total_src}"
        );
    }
}
