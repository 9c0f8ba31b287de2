//! Friction noise (digest-sound §4.2, §12 tests 1, 7, 8, 18): random-phase iFFT fidelity,
//! power-complementary overlap-add, continuity at hop boundaries, one iFFT per hop and ear for
//! any number of sources, sample-rate independence.

mod render_common;

use papier::render::{RenderOptions, Renderer};
use render_common::*;
use sounddb::analysis::{third_octave_centres_hz, welch_psd};
use sounddb::resample::spectrum_band_power;

/// Sums a PSD (bin k at k·df) into 1/3-octave band powers for bands whose upper edge is ≤ hi.
fn bands(psd: &[f64], df: f64, lo: f64, hi: f64) -> Vec<(f64, f64)> {
    third_octave_centres_hz()
        .into_iter()
        .filter(|&fc| fc >= lo && fc * 10f64.powf(0.05) <= hi)
        .map(|fc| {
            let (a, b) = (fc / 10f64.powf(0.05), fc * 10f64.powf(0.05));
            let p: f64 = psd
                .iter()
                .enumerate()
                .filter(|(k, _)| {
                    let f = *k as f64 * df;
                    f >= a && f < b
                })
                .map(|(_, v)| v * df)
                .sum();
            (fc, p)
        })
        .collect()
}

/// Direct-path gain from a dipole (centre, normal +z) to an ear, 1 m reference, cos floor 0.1.
fn direct_gain(centre: [f32; 3], ear: [f64; 3]) -> f64 {
    let r = [
        ear[0] - f64::from(centre[0]),
        ear[1] - f64::from(centre[1]),
        ear[2] - f64::from(centre[2]),
    ];
    let d = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    (r[2] / d).max(0.1) / d
}

#[test]
fn test7_ifft_noise_matches_the_target_psd_and_has_no_hop_flutter() {
    let rate = 44_100.0;
    let db = printer_db(rate);
    let mut r = renderer(rate, db, 5, anechoic());
    let res = resonator(10.0, 20.0);
    r.set_frame(&frame(0, &[friction(0.1, res)], 0.0));
    let n = (10.5 * rate) as usize;
    let (l, _) = render(&mut r, n, 4096);
    let x = &l[(0.5 * rate) as usize..];

    // Target: the database spectrum of cell (10, 10), PSD s²/Δf, times the direct gain².
    let (raw, _) = papier::render::default_db::embedded_database().unwrap();
    let spec = raw
        .spectra
        .iter()
        .find(|s| {
            s.cell
                == sounddb::Cell::Free {
                    straight_cm: 10.0,
                    curved_cm: 10.0,
                }
        })
        .unwrap();
    let g = direct_gain(res.centre_m, r.ears().ear_m[0]);
    let nfft = 4096;
    let df = rate / nfft as f64;
    let target: Vec<f64> = spectrum_band_power(&spec.magnitudes, rate / 4096.0, nfft / 2 + 1, df)
        .iter()
        .map(|p| p / df * g * g)
        .collect();
    let measured = welch_psd(x, rate, nfft);
    let mb = bands(&measured, df, 50.0, 20_000.0);

    // (a) Against the exact expectation of the synthesis: the prepared bin powers |X_j|² spread by
    // the sine window's power response, PSD(f) = 2/(H fs) Σ_j |X_j|² (|W(f−f_j)|² + |W(f+f_j)|²),
    // over the whole 50 Hz – 20 kHz range.
    let prepared = printer_db(rate);
    let id = prepared.friction_lookup(res.lr_cm, res.lc_cm).unwrap();
    let xj = prepared.friction_spectrum(id);
    let (m, hop) = r.friction_frame();
    let model: Vec<f64> = (0..=nfft / 2)
        .map(|k| {
            let f = k as f64 * df;
            let fj0 = (f / (rate / m as f64)).round() as isize;
            let mut s = 0.0;
            for j in (fj0 - 24).max(1)..(fj0 + 24).min(xj.len() as isize - 1) {
                let fj = j as f64 * rate / m as f64;
                let a = f64::from(xj[j as usize]).powi(2) * g * g;
                s += a
                    * (sine_window_power(m, (f - fj) / rate)
                        + sine_window_power(m, (f + fj) / rate));
            }
            2.0 * s / (hop as f64 * rate)
        })
        .collect();
    let eb = bands(&model, df, 50.0, 20_000.0);
    let mut worst = 0.0f64;
    for ((fc, e), (_, v)) in eb.iter().zip(&mb) {
        let d = 10.0 * (v / e).log10();
        worst = worst.max(d.abs());
        assert!(
            d.abs() <= 1.0,
            "band {fc:.0} Hz vs synthesis model: {d:+.2} dB"
        );
    }
    eprintln!(
        "test 7: worst 1/3-octave deviation from the synthesis model {worst:.2} dB (50 Hz–20 kHz)"
    );

    // (b) Against the database spectrum itself: equal wherever a 1/3-octave band is wider than the
    // 21.5 Hz frame resolution of the seeds' 2048-sample frame (≥ 100 Hz).
    let tb = bands(&target, df, 100.0, 20_000.0);
    let mb100 = bands(&measured, df, 100.0, 20_000.0);
    let mut worst = 0.0f64;
    for ((fc, t), (_, v)) in tb.iter().zip(&mb100) {
        let d = 10.0 * (v / t).log10();
        worst = worst.max(d.abs());
        assert!(d.abs() <= 1.0, "band {fc:.0} Hz vs database: {d:+.2} dB");
    }
    eprintln!("test 7: worst 1/3-octave deviation from the database {worst:.2} dB (100 Hz–20 kHz)");

    // Short-term RMS in 256-sample blocks: the hop (1024 = 4 blocks) component.
    let depth = hop_modulation_db(x, 256, 4);
    eprintln!("test 7: hop-rate modulation {depth:.1} dB");
    assert!(depth < -30.0, "hop-rate modulation {depth:.1} dB");
}

/// |W(ν)|² of the length-m sine window sin(π(n+½)/m) at normalised frequency ν (cycles/sample).
fn sine_window_power(m: usize, nu: f64) -> f64 {
    let a = std::f64::consts::PI / m as f64;
    let b = 2.0 * std::f64::consts::PI * nu;
    // w(n) = (e^{ia(n+½)} − e^{−ia(n+½)}) / 2i; geometric sums of e^{in(±a−b)}.
    let geo = |t: f64| -> (f64, f64) {
        // Σ_{n<m} e^{i n t} = (1 − e^{i m t}) / (1 − e^{i t})
        let (nr, ni) = (1.0 - (m as f64 * t).cos(), -(m as f64 * t).sin());
        let (dr, di) = (1.0 - t.cos(), -t.sin());
        let den = dr * dr + di * di;
        if den < 1e-24 {
            return (m as f64, 0.0);
        }
        ((nr * dr + ni * di) / den, (ni * dr - nr * di) / den)
    };
    let (p_r, p_i) = geo(a - b);
    let (q_r, q_i) = geo(-a - b);
    // e^{ia/2}·P − e^{−ia/2}·Q, then / 2i
    let (c, s) = ((a / 2.0).cos(), (a / 2.0).sin());
    let re = (c * p_r - s * p_i) - (c * q_r + s * q_i);
    let im = (c * p_i + s * p_r) - (c * q_i - s * q_r);
    (re * re + im * im) / 4.0
}

/// Depth (dB) of the component of the block-RMS sequence at 1/period blocks⁻¹.
fn hop_modulation_db(x: &[f32], block: usize, period: usize) -> f64 {
    let e: Vec<f64> = x.chunks_exact(block).map(rms).collect();
    let n = e.len() / period * period;
    let (mut re, mut im, mut sum) = (0.0, 0.0, 0.0);
    for (i, v) in e[..n].iter().enumerate() {
        let ph = 2.0 * std::f64::consts::PI * (i % period) as f64 / period as f64;
        re += v * ph.cos();
        im += v * ph.sin();
        sum += v;
    }
    20.0 * (2.0 * (re * re + im * im).sqrt() / sum).log10()
}

#[test]
fn the_flutter_statistic_detects_an_amplitude_complementary_window() {
    // Self-check of the statistic above: overlap-add of independent noise frames with a Hann
    // window (amplitude-complementary, NOT power-complementary) dips 3 dB mid-overlap.
    let (m, hop) = (2048usize, 1024usize);
    let mut g = Lcg(3);
    let mut out = vec![0.0f32; 200 * hop + m];
    for f in 0..200 {
        for i in 0..m {
            let w = 0.5 - 0.5 * (2.0 * std::f32::consts::PI * i as f32 / m as f32).cos();
            out[f * hop + i] += w * (g.next() - 0.5);
        }
    }
    let depth = hop_modulation_db(&out[m..200 * hop], 256, 4);
    assert!(depth > -25.0, "Hann OLA modulation only {depth:.1} dB");
}

#[test]
fn test8_no_discontinuity_at_hop_boundaries() {
    let rate = 44_100.0;
    let mut r = renderer(rate, printer_db(rate), 8, anechoic());
    let (m, hop) = r.friction_frame();
    // 7/150 s at 44.1 kHz (sounddb::prepared, "Friction frame length at other rates").
    assert_eq!((m, hop), (2058, 1029));
    // The spectrum changes at every frame: speed alternates, cells move.
    let mut steps = Vec::new();
    for i in 0..2000 {
        let res = resonator(if i % 2 == 0 { 5.0 } else { 20.0 }, 20.0);
        steps.push(Step {
            frame: frame(
                i,
                &[friction(if i % 3 == 0 { 0.05 } else { 0.15 }, res)],
                0.0,
            ),
            events: Vec::new(),
        });
    }
    let (l, _) = drive(&mut r, &steps, 221, &[221]);
    let x = &l[4 * hop..];
    let start = 4 * hop; // x[0] is at an absolute multiple of the hop
    let _ = start;
    let mut mean_at = vec![0.0f64; hop];
    let mut max_at = vec![0.0f64; hop];
    let mut count = vec![0usize; hop];
    for n in 1..x.len() {
        let d = f64::from((x[n] - x[n - 1]).abs());
        let phase = n % hop;
        mean_at[phase] += d;
        max_at[phase] = max_at[phase].max(d);
        count[phase] += 1;
    }
    for (m, c) in mean_at.iter_mut().zip(&count) {
        *m /= *c as f64;
    }
    let median = |v: &[f64]| {
        let mut s: Vec<f64> = v[1..].to_vec();
        s.sort_by(f64::total_cmp);
        s[s.len() / 2]
    };
    let (mean_med, max_med) = (median(&mean_at), median(&max_at));
    eprintln!(
        "test 8: boundary mean |Δx| {:.3e} vs median {:.3e}; max {:.3e} vs median {:.3e}",
        mean_at[0], mean_med, max_at[0], max_med
    );
    assert!(mean_at[0] <= 1.5 * mean_med);
    assert!(max_at[0] <= 1.5 * max_med);
}

#[test]
fn test1_one_ifft_per_hop_and_ear_for_any_number_of_sources() {
    // digest-sound §12 test 1 (its timing part is the criterion bench): the iFFT count does not
    // depend on the number of sources — they are summed before the transform (T 1830).
    let rate = 44_100.0;
    let db = printer_db(rate);
    let run = |k: usize| {
        let mut r = renderer(rate, db.clone(), 1, table_and_wall());
        let sources: Vec<_> = (0..k)
            .map(|i| {
                let mut res = resonator(
                    [2.5, 5.0, 10.0, 20.0][i % 4],
                    2.0 * [5.0, 15.0, 30.0][i % 3],
                );
                res.centre_m[0] = 0.02 * i as f32;
                friction(0.1, res)
            })
            .collect();
        r.set_frame(&frame(0, &sources, 0.0));
        let _ = render(&mut r, 100 * 1024, 512);
        *r.counters()
    };
    let one = run(1);
    let sixteen = run(16);
    assert_eq!(one.friction_ffts, sixteen.friction_ffts);
    // 100 hops rendered: boundaries at the starts of hops 1 … 99, each making one frame per ear
    // (hop 0 has no history yet).
    assert_eq!(one.friction_hops, 99);
    assert_eq!(sixteen.friction_ffts, 2 * 99);
    assert!(sixteen.friction_comb_bins > one.friction_comb_bins);
}

#[test]
fn test18_same_scene_same_spectrum_at_44k1_48k_96k() {
    let seconds = 8.0;
    let mut spectra = Vec::new();
    for rate in [44_100.0, 48_000.0, 96_000.0] {
        let mut r = renderer(rate, printer_db(rate), 4, table_and_wall());
        let (m, hop) = r.friction_frame();
        let hop_ms = 1000.0 * hop as f64 / rate;
        assert!(
            (20.0..=24.0).contains(&hop_ms),
            "{rate}: hop {hop_ms} ms (M = {m})"
        );
        let frame_len = (rate / 100.0) as usize;
        let frames = (seconds * 100.0) as usize;
        let mut steps = busy_steps(frames, 7);
        for s in &mut steps {
            s.frame.tear.speed_m_s = 0.0;
        }
        let (l, _) = drive(&mut r, &steps, frame_len, &[frame_len]);
        // Same analysis resolution (10.77 Hz) at every rate.
        let nfft = ((rate * 4096.0 / 44_100.0) as usize) & !1;
        let psd = welch_psd(&l, rate, nfft);
        spectra.push(bands(&psd, rate / nfft as f64, 50.0, 18_000.0));
    }
    let mut worst = 0.0f64;
    for other in &spectra[1..] {
        for ((_, a), (_, b)) in spectra[0].iter().zip(other) {
            let d = 10.0 * (b / a).log10();
            worst = worst.max(d.abs());
        }
    }
    for other in &spectra[1..] {
        for ((fc, a), (_, b)) in spectra[0].iter().zip(other) {
            let d = 10.0 * (b / a).log10();
            assert!(d.abs() <= 1.5, "band {fc:.0} Hz: {d:+.2} dB");
        }
    }
    eprintln!("test 18: worst band difference {worst:.2} dB");
}

#[test]
fn friction_stops_after_its_tail_and_the_skip_changes_nothing() {
    // §11.2: no friction → no iFFT after the tail; output identical to the no-skip reference.
    let rate = 48_000.0;
    let db = printer_db(rate);
    let mut steps = Vec::new();
    for i in 0..400 {
        let src = if (50..150).contains(&i) {
            vec![friction(0.1, resonator(10.0, 20.0))]
        } else {
            Vec::new()
        };
        steps.push(Step {
            frame: frame(i, &src, 0.0),
            events: Vec::new(),
        });
    }
    let mut fast = renderer(rate, db.clone(), 2, anechoic());
    let mut reference = renderer(rate, db, 2, anechoic());
    reference.set_options(RenderOptions {
        skip_silent_friction: false,
        skip_idle_tear: false,
        ..RenderOptions::default()
    });
    let a = drive(&mut fast, &steps, 240, &[240]);
    let b = drive(&mut reference, &steps, 240, &[240]);
    assert_same(&a, &b);
    let c = fast.counters();
    assert!(c.friction_hops_skipped > 0 && c.friction_samples_silent > 0);
    assert_eq!(reference.counters().friction_hops_skipped, 0);
    assert!(c.friction_ffts < reference.counters().friction_ffts);
    // Silent after the tail: frame 150 ends the sources; 2 hops later nothing.
    let (hop, end) = (fast.friction_frame().1, 150 * 240);
    let tail_end = (end / hop + 3) * hop;
    assert!(a.0[tail_end..].iter().all(|&v| v == 0.0));
    assert!(rms(&a.0[60 * 240..140 * 240]) > 1e-3);
}

#[test]
fn friction_level_is_linear_in_slip_speed() {
    let rate = 44_100.0;
    let db = printer_db(rate);
    let level = |v: f32| {
        let mut r = renderer(rate, db.clone(), 9, anechoic());
        r.set_frame(&frame(0, &[friction(v, resonator(15.0, 30.0))], 0.0));
        let (l, _) = render(&mut r, 3 * 44_100, 1024);
        rms(&l[8192..])
    };
    let ratio = level(0.2) / level(0.05);
    assert!((ratio - 4.0).abs() < 0.04, "{ratio}");
}

#[test]
fn wrong_rate_database_is_not_played() {
    let db48 = printer_db(48_000.0);
    let mut r = Renderer::new(44_100.0, db48, 1);
    assert!(!r.db_usable());
    r.set_frame(&frame(0, &[friction(0.1, resonator(10.0, 20.0))], 0.0));
    r.trigger(&crumple(1.0, resonator(10.0, 20.0)));
    let (l, rr) = render(&mut r, 10_000, 512);
    assert!(l.iter().chain(&rr).all(|&v| v == 0.0));
    assert_eq!(r.counters().triggers_without_unit, 1);
}

#[test]
fn comb_cache_reuses_static_geometry_exactly_and_moving_geometry_closely() {
    // §11.6: a source that has not moved reuses its |H(ω)| — same output as recomputing it.
    let rate = 44_100.0;
    let db = printer_db(rate);
    let sources = |shift: f32| -> Vec<_> {
        (0..4)
            .map(|k| {
                let mut res = resonator([5.0, 10.0, 20.0, 30.0][k], 20.0);
                res.centre_m[0] = 0.05 * k as f32 + shift;
                friction(0.1, res)
            })
            .collect()
    };
    let steps = |moving: bool| -> Vec<Step> {
        (0..300)
            .map(|i| Step {
                // Moving: 0.1 mm per frame (2 cm/s), 0.5 mm per hop: the cached comb is reused
                // for about two hops, then recomputed.
                frame: frame(
                    i,
                    &sources(if moving { 0.0001 * i as f32 } else { 0.0 }),
                    0.0,
                ),
                events: Vec::new(),
            })
            .collect()
    };
    for moving in [false, true] {
        let mut cached = renderer(rate, db.clone(), 3, table_and_wall());
        let mut fresh = renderer(rate, db.clone(), 3, table_and_wall());
        fresh.set_options(RenderOptions {
            cache_geometry: false,
            ..RenderOptions::default()
        });
        let a = drive(&mut cached, &steps(moving), 220, &[220]);
        let b = drive(&mut fresh, &steps(moving), 220, &[220]);
        let (ca, cb) = (cached.counters(), fresh.counters());
        assert!(ca.friction_comb_cache_hits > 0, "{ca:?}");
        assert_eq!(cb.friction_comb_cache_hits, 0);
        assert!(ca.friction_comb_bins < cb.friction_comb_bins);
        if moving {
            let err: f64 =
                a.0.iter()
                    .zip(&b.0)
                    .map(|(x, y)| f64::from(x - y).powi(2))
                    .sum();
            let sig: f64 = b.0.iter().map(|y| f64::from(*y).powi(2)).sum();
            let rel = 10.0 * (err / sig).log10();
            eprintln!("comb cache on a moving source: error {rel:.1} dB re signal");
            assert!(rel < -30.0, "{rel}");
        } else {
            assert_same(&a, &b);
        }
    }
}
