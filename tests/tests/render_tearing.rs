//! Tearing noise (L 140–154, T 2022–2050; digest-sound §6 and §12 test 12; digest-tearing §3 and
//! §7 S-1 … S-5): crackle statistics of w·r^α, linear amplitude, "pitch" = grain rate, flat
//! spectrum, exact silence when the tear stops.

mod render_common;

use papier::render::tearing::{
    TEAR_AMP_REF_SPEED_M_S, TEAR_PITCH_REF_SPEED_M_S, TearNoise, TearSettings,
};
use papier::render::{MixLevels, Renderer};
use render_common::*;
use sounddb::analysis::{flatness, third_octave_levels_db, welch_psd};

fn settings(alpha: f32) -> TearSettings {
    TearSettings {
        alpha,
        pitch_follows_speed: true,
    }
}

/// `n` samples of the generator at constant speed (ramped in over 1 sample).
fn tear(rate: f64, alpha: f32, speed: f32, n: usize, seed: u64) -> Vec<f32> {
    let mut t = TearNoise::new(rate, seed, settings(alpha));
    t.set_speed(speed, 1);
    let mut out = vec![0.0f32; n];
    t.render(&mut out, true);
    out
}

fn moments(x: &[f32]) -> (f64, f64) {
    let n = x.len() as f64;
    let m2: f64 = x.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>() / n;
    let m4: f64 = x.iter().map(|v| f64::from(*v).powi(4)).sum::<f64>() / n;
    (m2.sqrt(), m4 / (m2 * m2))
}

fn crest_db(x: &[f32]) -> f64 {
    let peak = x.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    20.0 * (f64::from(peak) / rms(x)).log10()
}

#[test]
fn test12_crackle_statistics_at_alpha_100() {
    // At 44.1 kHz with ρ = 1 the output samples are the grains w·r^α (amplitude 1 at the
    // reference speed). Analytic values (digest-sound §6): RMS 0.0407, kurtosis 181,
    // P(|y| > 0.5) = 0.01·(ln 2 − 0.5)… ≈ 0.15–0.2 %.
    let x = tear(44_100.0, 100.0, TEAR_AMP_REF_SPEED_M_S, 4_000_000, 1);
    let (r, k) = moments(&x[1..]);
    let above = x.iter().filter(|v| v.abs() > 0.5).count() as f64 / x.len() as f64;
    eprintln!("test 12: rms {r:.5} kurtosis {k:.1} P(|y|>0.5) {above:.5}");
    assert!((r / 0.0407 - 1.0).abs() <= 0.03, "rms {r}");
    assert!((150.0..=215.0).contains(&k), "kurtosis {k}");
    assert!((0.0015..=0.0025).contains(&above), "{above}");
}

#[test]
fn test12_alpha_1_is_white_and_amplitude_is_linear() {
    let x = tear(44_100.0, 1.0, TEAR_AMP_REF_SPEED_M_S, 441_000, 2);
    let psd = welch_psd(&x, 44_100.0, 2048);
    let f = flatness(&psd, 44_100.0 / 2048.0, 50.0, 20_000.0);
    assert!(f > 0.9, "flatness {f}");
    // Speeds above the pitch reference: ρ = 1 for both, only the amplitude changes.
    let v = 1.5 * TEAR_PITCH_REF_SPEED_M_S;
    let a = tear(44_100.0, 100.0, v, 2_000_000, 3);
    let b = tear(44_100.0, 100.0, 2.0 * v, 2_000_000, 3);
    let ratio = rms(&b) / rms(&a);
    assert!((ratio - 2.0).abs() <= 0.1, "{ratio}");
}

#[test]
fn s1_silence_when_the_tear_stops() {
    let rate = 48_000.0;
    let mut r = Renderer::new(rate, printer_db(rate), 1);
    r.set_mix(MixLevels::default());
    r.set_scene(anechoic());
    r.set_frame(&frame(0, &[], 0.1));
    let (l, _) = render(&mut r, 4800, 480);
    assert!(rms(&l) > 0.0);
    // The speed drops to 0: the ramp spans the frame interval (≤ 50 ms), then exact zeros.
    r.set_frame(&frame(1, &[], 0.0));
    let (l, rr) = render(&mut r, 48_000, 480);
    let settle = (0.050 * rate) as usize;
    assert!(l[settle..].iter().chain(&rr[settle..]).all(|&v| v == 0.0));
    let before = r.counters().tear_samples_skipped;
    let _ = render(&mut r, 4800, 480);
    assert_eq!(
        r.counters().tear_samples_skipped - before,
        4800,
        "the generator kept running"
    );
}

/// Plays tears that start and stop with frames at the simulation's 200 Hz on a 44.1 kHz clock
/// (220 and 221 samples alternately, as `FrameClock` delivers them), each frame's samples split
/// into calls of the sizes `split` cycles through.
fn stop_and_go(split: &[usize]) -> ((Vec<f32>, Vec<f32>), u64) {
    let rate = 44_100.0;
    let mut r = Renderer::new(rate, printer_db(rate), 3);
    r.set_mix(MixLevels::default());
    r.set_scene(anechoic());
    let (mut l, mut rr) = (Vec::new(), Vec::new());
    let mut k = 0;
    for i in 0..120u64 {
        let speed = if (i / 15) % 2 == 0 { 0.06 } else { 0.0 };
        r.set_frame(&frame(i, &[], speed));
        let mut left = 220 + (i % 2) as usize;
        while left > 0 {
            let m = split[k % split.len()].min(left);
            k += 1;
            let (a, b) = render(&mut r, m, m);
            l.extend(a);
            rr.extend(b);
            left -= m;
        }
    }
    ((l, rr), r.counters().tear_samples)
}

#[test]
fn where_a_tear_stops_does_not_depend_on_the_host_blocks() {
    // The speed ramps over the last frame interval, so after a 220-sample interval it lands one
    // sample before a 221-sample frame ends. Whether the host's block ends there must not decide
    // whether the generator runs for that sample: else the next tear's grains differ.
    let (whole, ran) = stop_and_go(&[512]);
    assert!(rms(&whole.0) > 0.0);
    for split in [&[1usize][..], &[64], &[7, 100, 3]] {
        let (x, ran_x) = stop_and_go(split);
        assert_same(&whole, &x);
        assert_eq!(ran, ran_x, "{split:?}: the generator ran for other samples");
    }
}

#[test]
fn a_sheet_that_does_not_tear_never_runs_the_generator() {
    // Every frame sets the tear speed, 0 when the sheet does not tear: the generator stays idle.
    let rate = 48_000.0;
    let mut r = Renderer::new(rate, printer_db(rate), 1);
    r.set_mix(MixLevels::default());
    r.set_scene(anechoic());
    for i in 0..100 {
        r.set_frame(&frame(i, &[], 0.0));
        let _ = render(&mut r, 240, 64);
    }
    assert_eq!(r.counters().tear_samples, 0);
    assert_eq!(r.counters().tear_samples_skipped, 24_000);
}

#[test]
fn s2_doubling_the_speed_doubles_the_rms() {
    // Pitch held (ρ = 1 above the pitch reference), 2 s each.
    for rate in [44_100.0, 96_000.0] {
        let n = (2.0 * rate) as usize;
        let a = tear(rate, 100.0, 0.12, n, 4);
        let b = tear(rate, 100.0, 0.24, n, 4);
        let ratio = rms(&b) / rms(&a);
        assert!((ratio / 2.0 - 1.0).abs() <= 0.05, "{rate}: {ratio}");
    }
}

#[test]
fn s3_grain_statistics_and_crest_factor() {
    let mut t = TearNoise::new(44_100.0, 5, settings(100.0));
    let n = 2_000_000;
    let mut above = 0usize;
    for _ in 0..n {
        let (_, gain) = t.grain_parts();
        if gain > 0.5 {
            above += 1;
        }
    }
    let frac = above as f64 / n as f64;
    eprintln!(
        "S-3: fraction of grains with r^α > 0.5: {:.4} %",
        100.0 * frac
    );
    assert!((frac - 0.00691).abs() <= 0.001, "{frac}");
    let x = tear(44_100.0, 100.0, TEAR_AMP_REF_SPEED_M_S, 2_000_000, 6);
    let level = 20.0 * rms(&x).log10();
    assert!((level + 27.8).abs() <= 0.5, "{level} dBFS");
    let white = tear(44_100.0, 1.0, TEAR_AMP_REF_SPEED_M_S, 2_000_000, 6);
    let (c100, c1) = (crest_db(&x), crest_db(&white));
    eprintln!("S-3: crest α=100 {c100:.1} dB, α=1 {c1:.1} dB");
    assert!(c100 - c1 > 15.0);
}

#[test]
fn s4_flat_spectrum_at_44k1() {
    let x = tear(44_100.0, 100.0, TEAR_AMP_REF_SPEED_M_S, 4_410_000, 7);
    let df = 44_100.0 / 4096.0;
    let psd = welch_psd(&x, 44_100.0, 4096);
    // Band densities (power / bandwidth) between 100 Hz and 20 kHz within ±3 dB of their mean.
    let levels = third_octave_levels_db(&psd, df);
    let centres = sounddb::analysis::third_octave_centres_hz();
    let dens: Vec<f64> = centres
        .iter()
        .zip(&levels)
        .filter(|(fc, _)| (100.0..=20_000.0).contains(*fc))
        .map(|(fc, l)| l - 10.0 * (fc * (10f64.powf(0.05) - 10f64.powf(-0.05))).log10())
        .collect();
    let mean = dens.iter().sum::<f64>() / dens.len() as f64;
    for d in &dens {
        assert!((d - mean).abs() <= 3.0, "{dens:?}");
    }
}

/// Local maxima of |x| at or above `thr`, per second.
fn peaks_per_s(x: &[f32], thr: f32, rate: f64) -> f64 {
    let n = (1..x.len() - 1)
        .filter(|&i| {
            let a = x[i].abs();
            a >= thr && a >= x[i - 1].abs() && a > x[i + 1].abs()
        })
        .count();
    n as f64 / (x.len() as f64 / rate)
}

#[test]
fn s5_pitch_is_the_grain_rate_at_any_host_rate() {
    // ρ = 0.5 and 1 (speeds 0.05 and 0.1 m/s); peaks above −6 dB of the current amplitude.
    for rate in [44_100.0, 48_000.0, 96_000.0] {
        let n = (60.0 * rate) as usize;
        let v = TEAR_PITCH_REF_SPEED_M_S;
        let slow = tear(rate, 100.0, 0.5 * v, n, 8);
        let fast = tear(rate, 100.0, v, n, 9);
        let a_slow = 0.5 * v / TEAR_AMP_REF_SPEED_M_S;
        let a_fast = v / TEAR_AMP_REF_SPEED_M_S;
        let (ps, pf) = (
            peaks_per_s(&slow, 0.5 * a_slow, rate),
            peaks_per_s(&fast, 0.5 * a_fast, rate),
        );
        eprintln!("S-5 {rate} Hz: {ps:.1} vs {pf:.1} peaks/s");
        assert!((pf / ps / 2.0 - 1.0).abs() <= 0.10, "{rate}: {pf} / {ps}");
    }
}

#[test]
fn tear_output_is_never_denormal_at_any_rate() {
    // S-6 (the realtime part is render_no_alloc; the timing part is the criterion bench).
    let mut g = Lcg(11);
    for rate in [8_000.0, 44_100.0, 96_000.0, 192_000.0] {
        let mut t = TearNoise::new(rate, 12, TearSettings::default());
        let mut out = vec![0.0f32; 997];
        for _ in 0..400 {
            t.set_speed(0.3 * g.next() * g.next(), (g.next() * 2000.0) as u32);
            t.render(&mut out, true);
            assert!(out.iter().all(|v| v.is_finite() && !is_denormal(*v)));
        }
    }
}
