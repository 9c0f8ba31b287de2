//! # Flap and clac clips (digest-sound §10.3)
//!
//! **Flap** (free resonator; the seeds twisted a sheet bent at 10 % compression to flip its
//! curvature, T 1909; "a few hundreds of milliseconds", T 1704):
//!
//! 1. *Excitation*: 1–4 snap-through sub-bursts within 20 ms, each 0.5–3 ms of white noise under
//!    an exponential envelope (τ = duration/3), with energies drawn from the crumpling acoustic
//!    emission power law P(E) ∝ E^−1.4 on [0.05, 1] (Houle & Sethna 1996, Kramer & Lobkovsky 1996,
//!    cited at S 78).
//! 2. *Modal part*: the 48 lowest panel modes ([`super::panel`]) below 0.45 fs, each a two-pole
//!    resonator `y[n] = 2r cos ω · y[n−1] − r² y[n−2] + sin ω · x[n−1]` (unit-amplitude impulse
//!    response r^n sin(nω)), weighted by the mode shape at a random strike point,
//!    `sin(mπx₀/a) sin(nπy₀/b)` with x₀/a, y₀/b ∈ [0.15, 0.85]. Decay T60 = 2.2/(η f), i.e.
//!    r = exp(−π η f / fs), with η = loss factor × U(0.8, 1.25). Each recursion stops once its
//!    mode has decayed by 80 dB after the last burst.
//! 3. *Diffuse part* (our addition: the panel has thousands of modes up to 20 kHz, far more than
//!    48): noise high-passed (one pole) at the last explicit mode, under the sum of the bursts'
//!    exponential envelopes with decay π η f_d, f_d = clamp(2 f_last, 1, 8 kHz); peak 0.5 × the
//!    modal peak.
//! 4. *Rattle*: the excitation through a one-pole high-pass at 500 Hz, peak −10 dB re the modal
//!    part.
//! 5. Length: last burst + 1.2 T60 of the lowest mode, clamped to 0.2–0.8 s (T 1967); 20 ms
//!    raised-cosine fade-out.
//! 6. Level: peak = 0.2 · √(area / 100 cm²), clamped to [0.02, 0.9], times U(0.7, 1): bigger
//!    radiating sheets are louder. This normalisation is our choice (the seeds' level came from a
//!    1 m microphone we do not have; digest-sound §10.3 item 5).
//!
//! **Clac** (constrained; "sharp, dampened in a few milliseconds", T 1704): noise under an
//! exponential decay of τ = 1–3 ms, high-passed at 60–150 Hz and softened by a one-pole low-pass
//! at 2–3.5 kHz, plus 2–4 heavily damped modes at 3–8 kHz (T60 3–9 ms), plus the snap's air
//! pulse, 60–120 ms long, peak 0.3 × U(0.7, 1).
//!
//! *The air pulse* (beyond the seeds): a crease snapping through jerks the patch around it, and
//! the air it pushes radiates a pressure pulse ∝ its volume acceleration — a first derivative of
//! a Gaussian peaking at 140–240 Hz (a snap of a few milliseconds), its peak 0.12 × the click's.
//! It is what gives a crumple its body: clacs carry most of a crumple's event energy (their
//! amplitudes are far above the flaps'), and a white click has its 125 Hz octave 15 dB under its
//! 4 kHz octave, where real crumple recordings have it 9–15 dB under the loudest (issue 52). The
//! digest's 300–800 Hz high-pass and an unfiltered click made the seed crumples' 125–250 Hz
//! octaves 16–23 dB under the loudest. Level and corners are a calibration against those
//! recordings' octave profile (docs/decisions.md, "Sound realism: the crumple's body").

use super::panel::Panel;
use super::{FLAP_COMPRESSION, GenRng, MaterialParams};

/// Number of explicit modes of a flap clip.
pub const FLAP_MODES: usize = 48;

/// Corner range of the one-pole low-pass that softens a clac's click, Hz.
pub const CLAC_LOW_PASS_HZ: (f64, f64) = (2_000.0, 3_500.0);
/// Peak frequency range of a clac's air pulse, Hz.
pub const CLAC_PULSE_HZ: (f64, f64) = (140.0, 240.0);
/// Peak of a clac's air pulse relative to its click.
pub const CLAC_PULSE_REL: f64 = 0.12;

/// One sub-burst of the excitation.
struct Burst {
    start: usize,
    len: usize,
    tau: f64,
    amp: f64,
}

fn one_pole_hp_coeff(fc_hz: f64, rate: f64) -> f64 {
    let rc = 1.0 / (2.0 * std::f64::consts::PI * fc_hz);
    let dt = 1.0 / rate;
    rc / (rc + dt)
}

fn low_pass(x: &[f64], fc_hz: f64, rate: f64) -> Vec<f64> {
    let a = 1.0 - (-2.0 * std::f64::consts::PI * fc_hz / rate).exp();
    let mut y = 0.0;
    x.iter()
        .map(|&v| {
            y += a * (v - y);
            y
        })
        .collect()
}

fn high_pass(x: &[f64], fc_hz: f64, rate: f64) -> Vec<f64> {
    let a = one_pole_hp_coeff(fc_hz, rate);
    let mut out = Vec::with_capacity(x.len());
    let (mut y, mut prev) = (0.0, 0.0);
    for &v in x {
        y = a * (y + v - prev);
        prev = v;
        out.push(y);
    }
    out
}

/// Adds a two-pole modal resonator driven by `exc` (zero after its end) into `out`, running it
/// until it has decayed by 80 dB after the excitation.
fn add_mode(out: &mut [f64], exc: &[f64], freq_hz: f64, eta: f64, weight: f64, rate: f64) {
    let w = 2.0 * std::f64::consts::PI * freq_hz / rate;
    let sigma = std::f64::consts::PI * eta * freq_hz; // 1/s
    let r = (-sigma / rate).exp();
    let (c1, c2, g) = (2.0 * r * w.cos(), -r * r, w.sin() * weight);
    // 80 dB = ln(10^4) = 9.21 time constants.
    let ring = (9.21 / sigma * rate) as usize;
    let stop = (exc.len() + ring).min(out.len());
    let (mut y1, mut y2, mut xprev) = (0.0f64, 0.0f64, 0.0f64);
    for (n, o) in out.iter_mut().enumerate().take(stop) {
        let y = c1 * y1 + c2 * y2 + g * xprev;
        xprev = if n < exc.len() { exc[n] } else { 0.0 };
        y2 = y1;
        y1 = y;
        *o += y;
    }
}

fn peak(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

fn finish(mut y: Vec<f64>, target_peak: f64, fade_s: f64, rate: f64) -> Vec<f32> {
    let n = y.len();
    let fade = ((fade_s * rate) as usize).min(n);
    for i in 0..fade {
        let t = (i as f64 + 0.5) / fade as f64;
        y[n - fade + i] *= 0.5 + 0.5 * (std::f64::consts::PI * t).cos();
    }
    let p = peak(&y);
    let g = if p > 0.0 { target_peak / p } else { 0.0 };
    y.iter().map(|v| (v * g) as f32).collect()
}

/// A flap clip for a sheet of `straight_cm` × `curved_cm` (see the module docs).
pub fn flap_clip(
    p: &MaterialParams,
    straight_cm: f64,
    curved_cm: f64,
    rng: &mut GenRng,
    rate_hz: u32,
) -> Vec<f32> {
    let rate = f64::from(rate_hz);
    let panel = Panel::new(straight_cm, curved_cm, FLAP_COMPRESSION, p.paper);
    let modes = panel.lowest_modes(FLAP_MODES, 0.45 * rate);
    let eta = p.loss_factor * rng.range(0.8, 1.25);
    let (x0, y0) = (rng.range(0.15, 0.85), rng.range(0.15, 0.85));

    // Excitation.
    let num_bursts = 1 + (rng.uniform() * 4.0) as usize;
    let first = (0.0005 * rate) as usize;
    let mut bursts = Vec::with_capacity(num_bursts);
    for b in 0..num_bursts {
        let start = if b == 0 {
            first
        } else {
            first + (rng.range(0.0, 0.020) * rate) as usize
        };
        let dur = rng.range(0.0005, 0.003);
        bursts.push(Burst {
            start,
            len: (dur * rate).max(2.0) as usize,
            tau: dur / 3.0 * rate,
            amp: rng.power_law(1.4, 0.05, 1.0).sqrt(),
        });
    }
    let exc_len = bursts.iter().map(|b| b.start + b.len).max().unwrap_or(1);
    let mut exc = vec![0.0f64; exc_len];
    for b in &bursts {
        for i in 0..b.len {
            exc[b.start + i] += b.amp * rng.signed() * (-(i as f64) / b.tau).exp();
        }
    }

    let f_low = modes.first().map_or(1000.0, |m| m.freq_hz);
    let f_last = modes.last().map_or(1000.0, |m| m.freq_hz);
    let t60_low = 2.2 / (eta * f_low);
    let len_s = (exc_len as f64 / rate + 1.2 * t60_low).clamp(0.2, 0.8);
    let len = (len_s * rate) as usize;

    // Modal part.
    let mut modal = vec![0.0f64; len];
    let pi = std::f64::consts::PI;
    for m in &modes {
        // Mode shape at the strike point (x0, y0 are fractions of a and b).
        let shape = (f64::from(m.m) * pi * x0).sin() * (f64::from(m.n) * pi * y0).sin();
        add_mode(&mut modal, &exc, m.freq_hz, eta, shape, rate);
    }
    let modal_peak = peak(&modal).max(1e-12);

    // Diffuse part.
    let f_d = (2.0 * f_last).clamp(1000.0, 8000.0);
    let sigma_d = pi * eta * f_d;
    let tau_d = rate / sigma_d; // samples
    let diffuse_len = (exc_len + (9.21 * tau_d) as usize).min(len);
    let mut diffuse_src = vec![0.0f64; diffuse_len];
    for (n, d) in diffuse_src.iter_mut().enumerate() {
        let mut env = 0.0;
        for bu in &bursts {
            if n >= bu.start {
                env += bu.amp * (-((n - bu.start) as f64) / tau_d).exp();
            }
        }
        *d = rng.signed() * env;
    }
    let mut diffuse = high_pass(&diffuse_src, f_last.min(0.4 * rate), rate);
    let dp = peak(&diffuse).max(1e-12);
    diffuse.iter_mut().for_each(|v| *v *= 0.5 * modal_peak / dp);

    // Rattle.
    let mut rattle = high_pass(&exc, 500.0, rate);
    let rp = peak(&rattle).max(1e-12);
    rattle
        .iter_mut()
        .for_each(|v| *v *= 0.316 * modal_peak / rp);

    let mut y = modal;
    for (o, d) in y.iter_mut().zip(&diffuse) {
        *o += d;
    }
    for (o, r) in y.iter_mut().zip(&rattle) {
        *o += r;
    }
    let area_ratio = (straight_cm * curved_cm) / 100.0;
    let target = (0.2 * area_ratio.sqrt()).clamp(0.02, 0.9) * rng.range(0.7, 1.0);
    finish(y, target, 0.020, rate)
}

/// A clac clip (see the module docs).
pub fn clac_clip(rng: &mut GenRng, rate_hz: u32) -> Vec<f32> {
    let rate = f64::from(rate_hz);
    let len = (rng.range(0.060, 0.120) * rate) as usize;
    let tau = rng.range(0.001, 0.003) * rate;
    let start = (0.0003 * rate) as usize;
    let exc_len = (start + (9.21 * tau) as usize).min(len);
    let mut exc = vec![0.0f64; exc_len];
    for (n, e) in exc.iter_mut().enumerate().skip(start) {
        *e = rng.signed() * (-((n - start) as f64) / tau).exp();
    }
    let hp_hz = rng.range(60.0, 150.0);
    let lp_hz = rng.range(CLAC_LOW_PASS_HZ.0, CLAC_LOW_PASS_HZ.1);
    let mut y = low_pass(&high_pass(&exc, hp_hz, rate), lp_hz, rate);
    y.resize(len, 0.0);
    let base = peak(&y).max(1e-12);
    let mut modal = vec![0.0f64; len];
    let num_modes = 2 + (rng.uniform() * 3.0) as usize;
    for _ in 0..num_modes {
        let f = rng.range(3000.0, 8000.0).min(0.45 * rate);
        let t60 = rng.range(0.003, 0.009);
        let eta = 2.2 / (t60 * f);
        add_mode(&mut modal, &exc, f, eta, rng.range(0.5, 1.0), rate);
    }
    let mp = peak(&modal).max(1e-12);
    for (o, m) in y.iter_mut().zip(&modal) {
        *o += m * base / mp;
    }
    // The snap's air pulse (beyond the seeds): pressure ∝ the volume acceleration of the patch
    // that jumps, a first derivative of a Gaussian peaking at f_p (a snap of a few ms).
    let f_pulse = rng.range(CLAC_PULSE_HZ.0, CLAC_PULSE_HZ.1);
    let sigma = rate / (2.0 * std::f64::consts::PI * f_pulse); // samples
    let centre = start as f64 + 3.0 * sigma;
    let end = ((centre + 4.0 * sigma) as usize).min(len);
    // The pulse's extremes are ±e^(−½) = ±0.6065 at t = ±σ: scaled to a peak of
    // CLAC_PULSE_REL × the click's.
    let g = CLAC_PULSE_REL * base / (-0.5f64).exp();
    for (n, o) in y.iter_mut().enumerate().take(end) {
        let t = (n as f64 - centre) / sigma;
        *o -= g * t * (-0.5 * t * t).exp();
    }
    finish(y, 0.3 * rng.range(0.7, 1.0), 0.005, rate)
}

#[cfg(test)]
mod tests {
    use super::super::{Material, clip_rng};
    use super::*;

    #[test]
    fn flap_lengths_and_levels() {
        let p = Material::Printer.params();
        for (s, c) in [(2.5, 2.5), (10.0, 10.0), (30.0, 30.0)] {
            let mut rng = clip_rng(1, 1, s as f32, c as f32, 0);
            let x = flap_clip(&p, s, c, &mut rng, 44_100);
            let secs = x.len() as f64 / 44_100.0;
            assert!((0.2..=0.8).contains(&secs), "{s}x{c}: {secs} s");
            let pk = x.iter().fold(0.0f32, |m, v| m.max(v.abs()));
            assert!(pk > 0.01 && pk <= 0.9, "{pk}");
            assert!(x.iter().all(|v| v.is_finite()));
            // The end is faded to silence.
            assert!(x.last().unwrap().abs() < 1e-3);
        }
    }

    #[test]
    fn clac_is_short_and_damped() {
        let mut rng = clip_rng(1, 2, 0.0, 0.0, 0);
        let x = clac_clip(&mut rng, 44_100);
        let pk = x.iter().fold(0.0f32, |m, v| m.max(v.abs()));
        // After 30 ms the clac is more than 60 dB down.
        let late = x[(0.03 * 44_100.0) as usize..]
            .iter()
            .fold(0.0f32, |m, v| m.max(v.abs()));
        assert!(late < pk * 1e-3, "late {late} vs peak {pk}");
    }
}
