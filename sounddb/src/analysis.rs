//! # Spectral measures (importer, generator checks, tests)
//!
//! Off-line helpers, allocation allowed:
//!
//! - [`welch_psd`]: one-sided power spectral density (units²/Hz) by Welch's method (periodic Hann
//!   window, 50 % overlap), the estimator of digest-sound §9 / test 7;
//! - [`band_rms_spectrum`]: the database spectrum convention (RMS amplitude per bin of width
//!   fs/(2·bins), see [`crate::manifest`]) from a signal;
//! - [`third_octave_levels_db`]: power per 1/3-octave band (IEC centre frequencies, base-10);
//! - [`octave_profile_db`]: power per octave (centres 125 Hz … 16 kHz) relative to the loudest
//!   octave, the profile issue 52 compares with real crumple recordings;
//! - [`centroid_hz`], [`flatness`]: spectral centroid and flatness (geometric / arithmetic mean of
//!   the power);
//! - [`log_band_histogram`] and [`qf_distance`]: the quadratic-form distance between unit-sum
//!   histograms of magnitude spectra used by the seeds' Table 4.1 (T 1915, S 218; Pele & Werman
//!   2010), with the binning we fix in digest-sound §9: 64 log-spaced bands from 50 Hz to 20 kHz,
//!   linear magnitude, triangular kernel A_ij = max(0, 1 − |i − j|/T), T = 3;
//! - [`lsd_db`]: log-spectral distance.

use realfft::RealFftPlanner;

/// Welch PSD of `x` at `rate_hz` with segments of `n` samples (power of two recommended).
/// Returns `n/2 + 1` values, bin k at k·rate/n Hz, in units²/Hz (one-sided).
pub fn welch_psd(x: &[f32], rate_hz: f64, n: usize) -> Vec<f64> {
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(n);
    let window: Vec<f64> = (0..n)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos())
        .collect();
    let w2: f64 = window.iter().map(|w| w * w).sum();
    let mut acc = vec![0.0f64; n / 2 + 1];
    let mut buf = fft.make_input_vec();
    let mut spec = fft.make_output_vec();
    let hop = n / 2;
    let mut frames = 0usize;
    let mut start = 0;
    while start + n <= x.len() {
        for i in 0..n {
            buf[i] = f64::from(x[start + i]) * window[i];
        }
        // Lengths come from the plan, so this cannot fail.
        let _ = fft.process(&mut buf, &mut spec);
        for (a, c) in acc.iter_mut().zip(&spec) {
            *a += c.norm_sqr();
        }
        frames += 1;
        start += hop;
    }
    let frames = frames.max(1) as f64;
    let last = n / 2;
    for (k, a) in acc.iter_mut().enumerate() {
        let one_sided = if k == 0 || k == last { 1.0 } else { 2.0 };
        *a = *a / frames * one_sided / (rate_hz * w2);
    }
    acc
}

/// The database spectrum (RMS amplitude per band of width rate/(2·bins)) of `x`, averaged over
/// all Hann-windowed frames of 2·bins samples with 75 % overlap; power-averaged, then square root.
pub fn band_rms_spectrum(x: &[f32], rate_hz: f64, bins: usize) -> Vec<f32> {
    let n = 2 * bins;
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(n);
    let window: Vec<f64> = (0..n)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos())
        .collect();
    let w2: f64 = window.iter().map(|w| w * w).sum();
    let mut acc = vec![0.0f64; bins + 1];
    let mut buf = fft.make_input_vec();
    let mut spec = fft.make_output_vec();
    let hop = (n / 4).max(1);
    let mut frames = 0usize;
    let mut start = 0;
    loop {
        for i in 0..n {
            buf[i] = x.get(start + i).map_or(0.0, |v| f64::from(*v)) * window[i];
        }
        let _ = fft.process(&mut buf, &mut spec);
        for (a, c) in acc.iter_mut().zip(&spec) {
            *a += c.norm_sqr();
        }
        frames += 1;
        start += hop;
        if start + n > x.len() {
            break;
        }
    }
    // PSD one-sided = 2|X|²/(fs Σw²); band power = PSD · fs/n.
    let _ = rate_hz;
    acc.iter()
        .take(bins)
        .map(|a| ((a / frames as f64) * 2.0 / (n as f64 * w2)).sqrt() as f32)
        .collect()
}

/// Nominal 1/3-octave band centres from 50 Hz to 20 kHz (base-10, IEC 61260).
pub fn third_octave_centres_hz() -> Vec<f64> {
    (17..=43).map(|i| 10f64.powf(i as f64 / 10.0)).collect()
}

/// Power (sum of PSD × bin width) per 1/3-octave band, dB, from a one-sided PSD whose bin k is
/// at k·df_hz. Bands with no bin get the interpolated PSD at their centre.
pub fn third_octave_levels_db(psd: &[f64], df_hz: f64) -> Vec<f64> {
    third_octave_centres_hz()
        .iter()
        .map(|&fc| {
            let lo = fc / 10f64.powf(0.05);
            let hi = fc * 10f64.powf(0.05);
            let mut p = 0.0;
            let mut count = 0;
            for (k, v) in psd.iter().enumerate() {
                let f = k as f64 * df_hz;
                if f >= lo && f < hi {
                    p += v * df_hz;
                    count += 1;
                }
            }
            if count == 0 {
                let k = ((fc / df_hz).round() as usize).min(psd.len().saturating_sub(1));
                p = psd.get(k).copied().unwrap_or(0.0) * (hi - lo);
            }
            10.0 * p.max(1e-30).log10()
        })
        .collect()
}

/// Octave centres of [`octave_profile_db`], Hz.
pub const OCTAVE_CENTRES_HZ: [f64; 8] = [125.0, 250.0, 500.0, 1e3, 2e3, 4e3, 8e3, 16e3];

/// Power per octave (band [c/√2, c·√2) around each of [`OCTAVE_CENTRES_HZ`]) of a power spectrum
/// (bin k at k·df_hz), in dB relative to the loudest octave (0 for it; −300 for an empty one).
pub fn octave_profile_db(power: &[f64], df_hz: f64) -> [f64; 8] {
    let mut e = [0.0f64; 8];
    for (k, p) in power.iter().enumerate() {
        let f = k as f64 * df_hz;
        for (o, c) in OCTAVE_CENTRES_HZ.iter().enumerate() {
            if f >= c / std::f64::consts::SQRT_2 && f < c * std::f64::consts::SQRT_2 {
                e[o] += p;
            }
        }
    }
    let loudest = e.iter().copied().fold(0.0, f64::max);
    if loudest <= 0.0 {
        return [-300.0; 8];
    }
    e.map(|v| 10.0 * (v / loudest).max(1e-30).log10())
}

/// Spectral centroid of a power spectrum (bin k at k·df_hz), Hz.
pub fn centroid_hz(power: &[f64], df_hz: f64) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (k, p) in power.iter().enumerate() {
        num += k as f64 * df_hz * p;
        den += p;
    }
    if den > 0.0 { num / den } else { 0.0 }
}

/// Spectral flatness (geometric mean / arithmetic mean) of a power spectrum over bins whose
/// frequency lies in [lo_hz, hi_hz].
pub fn flatness(power: &[f64], df_hz: f64, lo_hz: f64, hi_hz: f64) -> f64 {
    let vals: Vec<f64> = power
        .iter()
        .enumerate()
        .filter(|(k, _)| {
            let f = *k as f64 * df_hz;
            f >= lo_hz && f <= hi_hz
        })
        .map(|(_, p)| p.max(1e-30))
        .collect();
    if vals.is_empty() {
        return 0.0;
    }
    let n = vals.len() as f64;
    let geo = (vals.iter().map(|p| p.ln()).sum::<f64>() / n).exp();
    let arith = vals.iter().sum::<f64>() / n;
    geo / arith
}

/// Unit-sum histogram of a magnitude spectrum (bin k at k·df_hz) over 64 log-spaced bands from
/// 50 Hz to 20 kHz: each band holds the mean magnitude of its bins (bands without a bin take the
/// nearest bin), then the histogram is normalised to sum 1.
pub fn log_band_histogram(magnitude: &[f64], df_hz: f64) -> Vec<f64> {
    const BANDS: usize = 64;
    let (lo, hi) = (50.0f64, 20_000.0f64);
    let edge = |i: usize| lo * (hi / lo).powf(i as f64 / BANDS as f64);
    let mut h: Vec<f64> = (0..BANDS)
        .map(|b| {
            let (a, z) = (edge(b), edge(b + 1));
            let mut sum = 0.0;
            let mut n = 0;
            for (k, m) in magnitude.iter().enumerate() {
                let f = k as f64 * df_hz;
                if f >= a && f < z {
                    sum += m;
                    n += 1;
                }
            }
            if n == 0 {
                let k = ((0.5 * (a + z) / df_hz).round() as usize).min(magnitude.len() - 1);
                magnitude[k]
            } else {
                sum / n as f64
            }
        })
        .collect();
    let total: f64 = h.iter().sum();
    if total > 0.0 {
        h.iter_mut().for_each(|v| *v /= total);
    }
    h
}

/// Quadratic-form distance √((P−Q)ᵀ A (P−Q)) with A_ij = max(0, 1 − |i−j|/T), T = 3.
pub fn qf_distance(p: &[f64], q: &[f64]) -> f64 {
    const T: f64 = 3.0;
    let d: Vec<f64> = p.iter().zip(q).map(|(a, b)| a - b).collect();
    let mut s = 0.0;
    for i in 0..d.len() {
        for j in 0..d.len() {
            let a = (1.0 - (i as f64 - j as f64).abs() / T).max(0.0);
            s += d[i] * a * d[j];
        }
    }
    s.max(0.0).sqrt()
}

/// Log-spectral distance between two power spectra over bins in [lo_hz, hi_hz], dB.
pub fn lsd_db(p: &[f64], q: &[f64], df_hz: f64, lo_hz: f64, hi_hz: f64) -> f64 {
    let mut acc = 0.0;
    let mut n = 0;
    for (k, (a, b)) in p.iter().zip(q).enumerate() {
        let f = k as f64 * df_hz;
        if f >= lo_hz && f <= hi_hz {
            let d = 10.0 * (a.max(1e-30) / b.max(1e-30)).log10();
            acc += d * d;
            n += 1;
        }
    }
    if n == 0 { 0.0 } else { (acc / n as f64).sqrt() }
}

#[cfg(test)]
mod tests {
    #[test]
    fn octave_profile_of_white_noise_rises_3_db_per_octave() {
        // Flat power per Hz: each octave holds twice the previous one's power.
        let df = 1.0;
        let power = vec![1.0; 24_000];
        let p = super::octave_profile_db(&power, df);
        assert!(p[7].abs() < 1e-9, "{p:?}");
        for o in 0..7 {
            assert!((p[o + 1] - p[o] - 3.01).abs() < 0.05, "{p:?}");
        }
        assert_eq!(super::octave_profile_db(&[0.0; 10], df), [-300.0; 8]);
    }

    use super::*;

    #[test]
    fn welch_of_a_sine_has_its_power() {
        let rate = 48_000.0;
        let x: Vec<f32> = (0..48_000)
            .map(|i| (2.0 * std::f64::consts::PI * 1000.0 * i as f64 / rate).sin() as f32)
            .collect();
        let psd = welch_psd(&x, rate, 4096);
        let df = rate / 4096.0;
        let total: f64 = psd.iter().sum::<f64>() * df;
        assert!((total - 0.5).abs() < 0.01, "{total}");
        assert!((centroid_hz(&psd, df) - 1000.0).abs() < 20.0);
    }

    #[test]
    fn band_rms_convention() {
        // White noise of variance σ² spread over `bins` bands: each band holds σ²/bins.
        let mut state = 1u64;
        let x: Vec<f32> = (0..200_000)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((state >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 2.0
            })
            .collect();
        let s = band_rms_spectrum(&x, 44_100.0, 512);
        let total: f64 = s.iter().map(|v| f64::from(*v).powi(2)).sum();
        assert!((total / (1.0 / 3.0) - 1.0).abs() < 0.03, "{total}");
    }

    #[test]
    fn qf_is_zero_for_equal_and_grows() {
        let a: Vec<f64> = (0..64).map(|i| if i == 10 { 1.0 } else { 0.0 }).collect();
        let b: Vec<f64> = (0..64).map(|i| if i == 12 { 1.0 } else { 0.0 }).collect();
        let c: Vec<f64> = (0..64).map(|i| if i == 30 { 1.0 } else { 0.0 }).collect();
        assert_eq!(qf_distance(&a, &a), 0.0);
        assert!(qf_distance(&a, &b) < qf_distance(&a, &c));
    }
}
