//! # Friction spectra (digest-sound §10.3)
//!
//! Unconstrained cell (l_r, l_c/2), panel bent at 30 % compression (T 1909):
//!
//! ```text
//! |F(f)| = |S_rough(f)| · |H_panel(f)| · fluctuation(f)
//! |S_rough(f)|² = HP₆₀(f) · tilt(f) · bump(f)
//!     HP₆₀   = (f/60)⁴ / (1 + (f/60)⁴)                 hand slides carry little rumble
//!     tilt   = 1 below f_t, (f/f_t)^(tilt_dB/10 / log10 2) above (power; −3 dB/oct for printer)
//!     bump   = 10^(bump_dB/10 · exp(−½ (log2(f/f_b)/0.66)²))   the wooden table, 2–5 kHz
//! |H_panel(f)|² = [ Σ_modes η_b² r⁴ / ((1 − r²)² + η_b² r²)  +  1 / (1 + (f_low/f)⁴) ]
//!                 · 1 / (1 + (f / (20 f_low))²),        r = f / f_mn
//! ```
//!
//! — the 48 lowest modes as the acceleration response of a damped oscillator normalised to a
//! unit peak (rising as r⁴ below the mode, a plateau η_b² above it), η_b = 3 η (the excitation is
//! continuous, which broadens the peaks), plus a diffuse unit floor above the
//! lowest mode f_low (the thousands of higher modes; below f_low the panel barely radiates), the
//! whole "resonance region" rolling off at −6 dB/octave above 20 f_low. The roll-off is our
//! proposal: with a flat diffuse floor the centroid would *rise* with size (wide high modes
//! dominate), against the seeds' observation that the spectrum translates to higher frequencies
//! when the sheet gets smaller (T 1949, Fig. 4.16); tying the region to f_low reproduces that
//! translation (test 5) while keeping Table 4.1's ordering (test 6).
//! `fluctuation` imitates the seeds' measurement — an average over a 200 ms window (T 1909) —
//! as the mean of 8 periodogram-like draws (exponential power per bin), i.e. ±1.5 dB ripple.
//!
//! Constrained (0, 0) cell: `S_rough` alone ("close to a white noise", T 1704), with the same
//! fluctuation, 6 dB below the average unconstrained level ("less loud", T 1704).
//!
//! Levels follow the spectrum convention of [`crate::manifest`] (RMS amplitude per bin): the
//! total RMS of an unconstrained spectrum at the recording speed is 0.05 · (area/100 cm²)^¼.

use super::panel::Panel;
use super::{GenRng, MaterialParams};

/// Explicit modes in a friction spectrum.
pub const FRICTION_MODES: usize = 48;
/// Upper end of the panel's resonance region, in multiples of its lowest mode.
pub const RESONANCE_SPAN: f64 = 20.0;

fn roughness_power(p: &MaterialParams, f: f64) -> f64 {
    if f <= 0.0 {
        return 0.0;
    }
    let x4 = (f / 60.0).powi(4);
    let hp = x4 / (1.0 + x4);
    let tilt = if f > p.tilt_corner_hz {
        (f / p.tilt_corner_hz).powf(p.roughness_tilt_db_oct / 10.0 / std::f64::consts::LOG10_2)
    } else {
        1.0
    };
    let octaves = (f / p.bump_hz).log2() / 0.66;
    let bump = 10f64.powf(p.bump_db / 10.0 * (-0.5 * octaves * octaves).exp());
    hp * tilt * bump
}

fn fluctuation(rng: &mut GenRng) -> f64 {
    let mut s = 0.0;
    for _ in 0..8 {
        s += rng.exponential();
    }
    s / 8.0
}

fn scale_to_rms(power: &mut [f64], rms: f64) -> Vec<f32> {
    let total: f64 = power.iter().sum();
    let g = if total > 0.0 { rms * rms / total } else { 0.0 };
    power.iter().map(|p| (p * g).sqrt() as f32).collect()
}

/// Total RMS of an unconstrained spectrum at the recording speed.
pub fn free_level_rms(straight_cm: f64, curved_cm: f64) -> f64 {
    0.05 * (straight_cm * curved_cm / 100.0).powf(0.25)
}

/// An unconstrained friction spectrum (`bins` bins, bin k at k·rate/(2·bins) Hz).
pub fn free_spectrum(
    p: &MaterialParams,
    straight_cm: f64,
    curved_cm: f64,
    compression: f64,
    rng: &mut GenRng,
    rate: f64,
    bins: usize,
) -> Vec<f32> {
    let panel = Panel::new(straight_cm, curved_cm, compression, p.paper);
    let modes = panel.lowest_modes(FRICTION_MODES, 0.5 * rate);
    let f_low = modes.first().map_or(1000.0, |m| m.freq_hz);
    let eta_b = 3.0 * p.loss_factor;
    let df = rate / (2.0 * bins as f64);
    let mut power: Vec<f64> = (0..bins)
        .map(|k| {
            let f = k as f64 * df;
            if f <= 0.0 {
                return 0.0;
            }
            let mut h = 1.0 / (1.0 + (f_low / f).powi(4));
            for m in &modes {
                let r2 = (f / m.freq_hz).powi(2);
                let e2 = eta_b * eta_b;
                h += e2 * r2 * r2 / ((1.0 - r2).powi(2) + e2 * r2);
            }
            let tail = 1.0 / (1.0 + (f / (RESONANCE_SPAN * f_low)).powi(2));
            roughness_power(p, f) * h * tail * fluctuation(rng)
        })
        .collect();
    scale_to_rms(&mut power, free_level_rms(straight_cm, curved_cm))
}

/// The constrained (0, 0) friction spectrum.
pub fn constrained_spectrum(
    p: &MaterialParams,
    rng: &mut GenRng,
    rate: f64,
    bins: usize,
) -> Vec<f32> {
    let df = rate / (2.0 * bins as f64);
    let mut power: Vec<f64> = (0..bins)
        .map(|k| roughness_power(p, k as f64 * df) * fluctuation(rng))
        .collect();
    // Average unconstrained level over the grid, −6 dB.
    let grid = crate::GRID_CM;
    let mut mean = 0.0;
    for s in grid {
        for c in grid {
            mean += free_level_rms(f64::from(s), f64::from(c));
        }
    }
    mean /= (grid.len() * grid.len()) as f64;
    scale_to_rms(&mut power, mean * 0.5)
}
