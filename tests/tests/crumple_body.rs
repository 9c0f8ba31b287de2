//! The spectral body of a crumple (issue 52 item 4), over a family of seeded crumples not tuned
//! on: real crumple recordings have their 125–500 Hz octaves 9–15 dB under the loudest octave and
//! a spectral centroid of 2.4–4.6 kHz. Each crumple, from its seed: a random sheet (A4, A5, A6 or
//! the 10 cm square) and paper, held by its four corners, crumpled from rest to 0.5–1.0 over
//! 1–4 s, half of them twisted too. Each is rendered by `papier-render`'s own path (the engine in
//! lockstep, the embedded database, the default mix, 48 kHz) and its octave profile measured over
//! the whole take. The family's median octave levels must lie in 8–15 dB under the loudest and
//! its median centroid in 2.5–5 kHz.

mod render_common;

use rand::{RngExt, SeedableRng};
use render_common::{median, render_script_mono};
use sounddb::analysis;

const CRUMPLES: u64 = 8;
const RATE: f64 = 48_000.0;

/// The script of crumple `seed`.
fn crumple(seed: u64) -> String {
    let mut rng = rand_pcg::Pcg32::seed_from_u64(0xc0de_b0d7 ^ seed);
    let size = ["a4", "a5", "a6", "sq10"][rng.random_range(0..4)];
    let material = ["printer", "tracing", "banknote"][rng.random_range(0..3)];
    let t0: f64 = rng.random_range(0.2..0.8);
    let t1 = t0 + rng.random_range(1.0..4.0);
    let amount: f64 = rng.random_range(0.5..1.0);
    let twist = if rng.random_bool(0.5) {
        let v: f64 = rng.random_range(-0.6..0.6);
        format!(
            "[[lane]]\nid = \"twist\"\ninterp = \"linear\"\npoints = [[{t0:.3}, 0.0], [{t1:.3}, {v:.3}]]\n"
        )
    } else {
        String::new()
    };
    format!(
        "version = 1\nduration_s = {:.3}\n[set]\nsize = \"{size}\"\nmaterial = \"{material}\"\n\
         seed = {}\n[[grab]]\nslot = \"corners\"\non_s = 0.1\n\
         [[lane]]\nid = \"crumple\"\ninterp = \"linear\"\npoints = [[{t0:.3}, 0.0], [{t1:.3}, {amount:.3}]]\n{twist}",
        t1 + 0.8,
        seed + 1
    )
}

/// Octave levels re the loudest octave, dB, and the centroid, Hz.
fn profile(x: &[f32]) -> ([f64; 8], f64) {
    let n = 8192;
    let psd = analysis::welch_psd(x, RATE, n);
    let df = RATE / n as f64;
    (
        analysis::octave_profile_db(&psd, df),
        analysis::centroid_hz(&psd, df),
    )
}

#[test]
fn a_crumple_has_body_below_500_hz_and_a_centroid_of_a_real_one() {
    let mut levels: Vec<[f64; 8]> = Vec::new();
    let mut centroids = Vec::new();
    for seed in 0..CRUMPLES {
        let x = render_script_mono("body", &format!("crumple_{seed}"), &crumple(seed));
        let (l, c) = profile(&x);
        eprintln!(
            "crumple {seed}: centroid {c:.0} Hz, octaves {}",
            l.map(|v| format!("{v:.1}")).join(" ")
        );
        levels.push(l);
        centroids.push(c);
    }
    let c = median(centroids);
    let body: Vec<f64> = (0..3)
        .map(|o| median(levels.iter().map(|l| l[o]).collect()))
        .collect();
    eprintln!("median: centroid {c:.0} Hz, 125 / 250 / 500 Hz octaves {body:.1?} dB");
    for (o, v) in body.iter().enumerate() {
        assert!(
            (-15.0..=-8.0).contains(v),
            "the {} Hz octave sits {v:.1} dB under the loudest (real crumples: 8–15)",
            analysis::OCTAVE_CENTRES_HZ[o]
        );
    }
    assert!(
        (2_500.0..=5_000.0).contains(&c),
        "median centroid {c:.0} Hz (real crumples: 2.4–4.6 kHz)"
    );
}
