//! Tearing noise (L 140–154, T 2022–2050; digest-sound §6 and §12 test 12; digest-tearing §3 and
//! §7 S-1 … S-5): crackle statistics of w·r^α, linear amplitude, "pitch" = grain rate, flat
//! spectrum, exact silence when the tear stops; beyond the seeds, the onset burst and the colour
//! of the flaps (render/tear_tone.rs).

mod render_common;

use papier::render::tearing::{
    TEAR_AMP_REF_SPEED_M_S, TEAR_PITCH_REF_SPEED_M_S, TearNoise, TearSettings,
};
use papier::render::{MixLevels, Renderer};
use render_common::*;
use sim_core::sound_input::Resonator;
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
    // The speed drops to 0: the ramp spans the frame interval (≤ 50 ms), the flaps' kernel
    // rings for at most its length, then exact zeros.
    r.set_frame(&frame(1, &[], 0.0));
    let (l, rr) = render(&mut r, 48_000, 480);
    let settle = (0.050 * rate) as usize + papier::render::tear_tone::MAX_KERNEL;
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

/// A renderer playing only the tear (crumple and friction mixes off), anechoic.
fn tear_only(rate: f64) -> Renderer {
    let mut r = Renderer::new(rate, printer_db(rate), 1);
    r.set_mix(MixLevels {
        crumple_db: -200.0,
        friction_db: -200.0,
        ..MixLevels::default()
    });
    r.set_scene(anechoic());
    r.snap_gains();
    r
}

/// Spectral centroid, Hz, of a Welch PSD from 50 Hz to 16 kHz.
fn centroid_hz(x: &[f32], rate: f64) -> f64 {
    let psd = welch_psd(x, rate, 2048);
    let df = rate / 2048.0;
    let (mut num, mut den) = (0.0, 0.0);
    for (k, p) in psd.iter().enumerate() {
        let f = k as f64 * df;
        if (50.0..=16_000.0).contains(&f) {
            num += f * p;
            den += p;
        }
    }
    num / den
}

#[test]
fn the_tear_takes_the_colour_of_its_flaps_and_keeps_its_level() {
    let rate = 48_000.0;
    let n = 48_000;
    // At the pitch reference the grains fall on every sample: the crackle is white, so the
    // kernel alone gives the colour (slower tears multiply it by their grain rate's low-pass).
    let play = |res: Option<Resonator>| {
        let mut r = tear_only(rate);
        let mut f = frame(0, &[], TEAR_PITCH_REF_SPEED_M_S);
        if let Some(res) = res {
            f.tear.resonator = res;
        }
        r.set_frame(&f);
        render(&mut r, n, 512).0
    };
    let white = play(None);
    let white_c = centroid_hz(&white[4800..], rate);
    // The friction of the same patches, alone: the colour the tear should take.
    let rubbed = |res: Resonator| {
        let mut r = Renderer::new(rate, printer_db(rate), 1);
        r.set_scene(anechoic());
        r.set_frame(&frame(0, &[friction(0.1, res)], 0.0));
        render(&mut r, n, 512).0
    };
    let mut pairs = Vec::new();
    for (lr, lc) in [
        (1.0, 0.0),
        (3.0, 6.0),
        (8.0, 16.0),
        (15.0, 30.0),
        (25.0, 0.0),
    ] {
        let res = resonator(lr, lc);
        let torn = play(Some(res));
        let level_db = 20.0 * (rms(&torn[4800..]) / rms(&white[4800..])).log10();
        let (tc, fc) = (
            centroid_hz(&torn[4800..], rate),
            centroid_hz(&rubbed(res)[4800..], rate),
        );
        eprintln!(
            "l_r {lr} l_c {lc}: tear {tc:.0} Hz, friction {fc:.0} Hz, white {white_c:.0} Hz, {level_db:+.2} dB"
        );
        assert!(
            level_db.abs() < 2.0,
            "l_r {lr}: {level_db:.2} dB from white"
        );
        pairs.push((tc, fc));
    }
    // The tear's centroid moves with the friction's: the order of the cells is kept and each
    // lies nearer its friction's centroid than the white crackle's does.
    for (a, b) in pairs.iter().zip(&pairs[1..]) {
        if (a.1 - b.1).abs() > 300.0 {
            assert_eq!(a.0 < b.0, a.1 < b.1, "{pairs:?}");
        }
    }
    for &(tc, fc) in &pairs {
        assert!(
            (tc - fc).abs() < (white_c - fc).abs(),
            "{pairs:?}, white {white_c:.0}"
        );
    }
}

#[test]
fn a_tear_onset_snaps_louder_than_the_running_tear() {
    let rate = 44_100.0;
    let play = |onset: bool| {
        let mut r = tear_only(rate);
        let mut f = frame(0, &[], 0.01);
        f.tear.onset = onset;
        r.set_frame(&f);
        let out = render(&mut r, 44_100, 64).0;
        (out, r.counters().tear_onsets)
    };
    let (snap, n_snap) = play(true);
    let (plain, n_plain) = play(false);
    assert_eq!((n_snap, n_plain), (1, 0));
    let ms = |a: f64, b: f64| &snap[(a * 44.1) as usize..(b * 44.1) as usize];
    let msp = |a: f64, b: f64| &plain[(a * 44.1) as usize..(b * 44.1) as usize];
    let first = 20.0 * (rms(ms(0.0, 10.0)) / rms(msp(0.0, 10.0))).log10();
    assert!(first > 10.0, "the first 10 ms are {first:.1} dB louder");
    // 40 ms on the burst has died away (τ = 4 ms): the running tear as without the onset.
    let later = 20.0 * (rms(ms(40.0, 1000.0)) / rms(msp(40.0, 1000.0))).log10();
    assert!(later.abs() < 2.0, "{later:.2} dB after 40 ms");
}

#[test]
fn the_tear_is_heard_from_its_tip() {
    // The same tear with its tip left, right, and far behind the sheet (the listener is in
    // front, at azimuth 0, its left ear at −x): the nearer ear is louder, the two sides
    // mirror, distance lowers it.
    let rate = 48_000.0;
    let play = |tip: [f32; 3]| {
        let mut r = tear_only(rate);
        let mut f = frame(0, &[], 0.05);
        f.tear.tip_m = tip;
        r.set_frame(&f);
        let (l, rr) = render(&mut r, 48_000, 512);
        (rms(&l[4800..]), rms(&rr[4800..]))
    };
    let z = 0.76;
    let (ll, lr) = play([-0.3, 0.0, z]);
    let (rl, rr) = play([0.3, 0.0, z]);
    let (fl, fr) = play([0.0, 1.5, z]);
    let (left_ratio, right_ratio) = (ll / lr, rl / rr);
    // A distance law per ear (no head shadow): the ears are ~9 cm from the head's centre, so a
    // tip 30 cm aside at 1 m is ~4 % louder in the near ear.
    assert!(
        left_ratio > 1.02 && right_ratio < 0.98,
        "ear ratios {left_ratio} {right_ratio}"
    );
    assert!(
        (left_ratio * right_ratio - 1.0).abs() < 0.05,
        "the two sides mirror: {left_ratio} × {right_ratio}"
    );
    let (near, far) = (ll.max(lr), fl.max(fr));
    assert!(far < 0.8 * near, "farther is quieter: {far} vs {near}");
}
