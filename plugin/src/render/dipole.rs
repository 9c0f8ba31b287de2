//! # Dipole radiation and image sources (thesis eq. 4.1–4.12; SCA 2016 eq. 1–6)
//!
//! Each resonator radiates as an acoustically compact rigid disk — a **dipole** of radius a,
//! centre **y** and normal **n** (T 1842–1864, `000_cb4d91e46ec5927f.txt`; S 167–182,
//! `002_9b4a8fc30aee6402.txt`; digest-sound §5):
//!
//! ```text
//! p(x, t) ≈ a³ · (cos θ / R) · A(t − R/c),   R = |x − y|,  cos θ = (x − y)/R · n      (4.6)
//! ```
//!
//! A rigid plane (the table, the wall; `RoomConfig::reflectors()`) adds an **image dipole** of the
//! same strength at the mirrored centre and axis (T 1864–1879, S 186–190):
//!
//! ```text
//! ỹ = y − 2((y − q)·m) m,   ñ = n − 2 (n·m) m       (plane through q with unit normal m)
//! P(x, t) = a³ cos θ / R · A(t) + a³ cos θ̃ / R̃ · A(t − (R̃ − R)/c)                      (4.11)
//! P(x, ω) = a³ A(ω) [ cos θ / R · e^{iωR/c} + cos θ̃ / R̃ · e^{iωR̃/c} ]                   (4.12)
//! ```
//!
//! Units use (4.11) as taps (gain, delay) applied with fractional delays; friction spectra use
//! (4.12) through its magnitude, because the phase is randomised afterwards (digest §5.3):
//! `|H(ω)|² = Σ_i g_i² + 2 Σ_{i<j} g_i g_j cos(ω (τ_i − τ_j))` — one image per reflector, first
//! order only (no image of an image), as the seeds (one plane per equation).
//!
//! Our choices (digest-sound §5.3, its proposal):
//!
//! - **Size factor.** The database units already carry the size of the sheet they were recorded
//!   (synthesized) from, so a³ is applied *relative to the entry*: `(a / a_ref)³` with
//!   a_ref = √(l_r · l_c/2 / π) of the selected cell, clamped to [1/8, 8] (±18 dB) so that a
//!   resonator far off the grid cannot explode. Constrained (0, 0) entries have no a_ref: factor 1.
//!   An absolute a³ would spread 2.5 cm vs 30 cm over 65 dB.
//! - **|cos θ| floor** of [`COS_FLOOR`] (sign kept): a real sheet is not a perfect dipole; a
//!   listener in the sheet plane hears the floor instead of silence. The back lobe keeps its
//!   negative polarity (it matters for the image comb).
//! - **Distance** is normalised to 1 m (the seeds' microphone distance, T 1905): gain = … / (R/1 m),
//!   with R ≥ 5 cm.
//! - **Far or weak images are absent** (§11.1): an image later than [`IMAGE_MAX_DELAY_S`] after the
//!   direct sound, more than 40 dB below it, or with the source or the ear behind the plane, is not
//!   created. Without reflectors nothing at all is computed for images.
//! - c = 343 m/s.
//!
//! Validity: compactness needs ka ≪ 1 (f ≪ 1.1 kHz for a = 5 cm) and most paper sound is above;
//! the model is a perceptual approximation, as the seeds say (T 1842); paper self-reflections are
//! ignored (T 1840).

use sim_core::room::Plane;
use sim_core::sound_input::Resonator;

use super::ears::SPEED_OF_SOUND_M_S;

/// Most reflectors (table + wall).
pub const MAX_REFLECTORS: usize = 2;
/// Floor of |cos θ| (digest-sound §5.3 proposal).
pub const COS_FLOOR: f64 = 0.1;
/// Images later than this after the direct sound are treated as absent, s (§11.1).
pub const IMAGE_MAX_DELAY_S: f64 = 0.020;
/// Images weaker than this fraction of the direct gain are treated as absent (−40 dB, §11.1).
pub const IMAGE_MIN_REL_GAIN: f64 = 0.01;
/// Clamp of the (a/a_ref)³ size factor.
pub const SIZE_FACTOR_RANGE: (f64, f64) = (0.125, 8.0);
/// Shortest source–ear distance used, m.
pub const MIN_DISTANCE_M: f64 = 0.05;

/// One propagation path: a gain and an absolute delay.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Path {
    /// Linear gain (signed: the back lobe and mirrored axes flip polarity).
    pub gain: f64,
    /// Propagation delay R/c, s.
    pub delay_s: f64,
}

/// The paths from one source to one ear: the direct one and up to [`MAX_REFLECTORS`] images.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EarPaths {
    /// Direct path.
    pub direct: Path,
    /// Image paths.
    pub images: [Path; MAX_REFLECTORS],
    /// Number of valid images.
    pub num_images: usize,
    /// Images not created (late, weak, or behind the plane).
    pub skipped: usize,
}

impl EarPaths {
    /// All paths (direct first).
    pub fn paths(&self) -> impl Iterator<Item = &Path> {
        std::iter::once(&self.direct).chain(self.images[..self.num_images].iter())
    }

    /// |H(ω)| of (4.12) at angular frequency ω (rad/s), by direct evaluation (reference).
    pub fn magnitude_at(&self, omega: f64) -> f64 {
        let (mut re, mut im) = (0.0, 0.0);
        for p in self.paths() {
            re += p.gain * (omega * p.delay_s).cos();
            im += p.gain * (omega * p.delay_s).sin();
        }
        (re * re + im * im).sqrt()
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// cos θ with the floor, sign kept (0 counts as positive); an undefined axis is omnidirectional.
fn floored_cos(r: [f64; 3], dist: f64, n: [f64; 3], cos_floor: f64) -> f64 {
    let nn = norm(n);
    if nn.is_nan() || nn <= 1e-9 || !nn.is_finite() {
        return 1.0;
    }
    let c = dot(r, n) / (dist * nn);
    let c = if c.is_finite() { c } else { 1.0 };
    if c < 0.0 {
        -c.abs().max(cos_floor)
    } else {
        c.max(cos_floor)
    }
}

/// The (a / a_ref)³ size factor (1 when either radius is unknown).
pub fn size_factor(radius_m: f32, reference_radius_m: Option<f32>) -> f64 {
    match reference_radius_m {
        Some(a_ref) if a_ref > 0.0 && radius_m.is_finite() && radius_m > 0.0 => {
            (f64::from(radius_m) / f64::from(a_ref))
                .powi(3)
                .clamp(SIZE_FACTOR_RANGE.0, SIZE_FACTOR_RANGE.1)
        }
        _ => 1.0,
    }
}

/// Paths from a dipole at `centre` with axis `normal` to `ear`, with one image per reflector,
/// all gains multiplied by `strength` (event amplitude × size factor).
pub fn ear_paths(
    centre: [f64; 3],
    normal: [f64; 3],
    strength: f64,
    ear: [f64; 3],
    reflectors: &[Plane],
    cos_floor: f64,
) -> EarPaths {
    let c = SPEED_OF_SOUND_M_S;
    let r = sub(ear, centre);
    let dist = norm(r).max(MIN_DISTANCE_M);
    let g0 = strength * floored_cos(r, dist, normal, cos_floor) / dist;
    let mut out = EarPaths {
        direct: Path {
            gain: g0,
            delay_s: dist / c,
        },
        ..EarPaths::default()
    };
    for plane in reflectors.iter().take(MAX_REFLECTORS) {
        let m = plane.normal;
        let src_side = dot(sub(centre, plane.point_m), m);
        let ear_side = dot(sub(ear, plane.point_m), m);
        if !(src_side > 0.0 && ear_side > 0.0) {
            out.skipped += 1;
            continue;
        }
        let y_img = [
            centre[0] - 2.0 * src_side * m[0],
            centre[1] - 2.0 * src_side * m[1],
            centre[2] - 2.0 * src_side * m[2],
        ];
        let nm = dot(normal, m);
        let n_img = [
            normal[0] - 2.0 * nm * m[0],
            normal[1] - 2.0 * nm * m[1],
            normal[2] - 2.0 * nm * m[2],
        ];
        let ri = sub(ear, y_img);
        let di = norm(ri).max(MIN_DISTANCE_M);
        let g1 = strength * floored_cos(ri, di, n_img, cos_floor) / di;
        let late = (di - dist) / c > IMAGE_MAX_DELAY_S;
        let weak = g1.abs() < IMAGE_MIN_REL_GAIN * g0.abs();
        if late || weak || !g1.is_finite() {
            out.skipped += 1;
            continue;
        }
        out.images[out.num_images] = Path {
            gain: g1,
            delay_s: di / c,
        };
        out.num_images += 1;
    }
    out
}

/// Paths of a resonator (world metres) to an ear.
pub fn resonator_paths(
    res: &Resonator,
    strength: f64,
    ear: [f64; 3],
    reflectors: &[Plane],
    cos_floor: f64,
) -> EarPaths {
    let v = |a: [f32; 3]| [f64::from(a[0]), f64::from(a[1]), f64::from(a[2])];
    ear_paths(
        v(res.centre_m),
        v(res.normal),
        strength,
        ear,
        reflectors,
        cos_floor,
    )
}

/// Writes |H(ω_j)| of eq. 4.12 for bins j = 0 … out.len()−1 at ω_j = j·Δω (rad/s):
/// `|H|² = Σ g_i² + 2 Σ_{i<j} g_i g_j cos(ω (τ_i − τ_j))` (f32 gains; exactly |g0| when there is
/// no image or only silent ones). Allocation-free and written to vectorise: each cosine is
/// evaluated directly from the bin index — the phase j·u (cycles, u = Δω·Δτ/2π split into a
/// 11-bit head, exact in f32 for j < 8192, and a tail) is reduced to [−½, ½] with the round-to-nearest
/// constant 1.5·2²³, then cos 2πt = T(2πt/4) doubled twice (T: Taylor to degree 8 on
/// [−π/4, π/4], error < 3e-8 before doubling, ≈ 5e-7 after). Returns the number of bins.
pub fn comb_magnitude(paths: &EarPaths, d_omega: f64, out: &mut [f32]) -> u64 {
    let mut gains = [0.0f32; 1 + MAX_REFLECTORS];
    let mut delays = [0.0f64; 1 + MAX_REFLECTORS];
    let mut count = 0;
    for p in paths.paths() {
        gains[count] = p.gain as f32;
        delays[count] = p.delay_s;
        count += 1;
    }
    let mut constant = 0.0f32;
    for g in &gains[..count] {
        constant += g * g;
    }
    // Pair terms: coefficient 2 g_i g_j and phase increment per bin (cycles).
    let mut coef = [0.0f32; 3];
    let mut u_hi = [0.0f32; 3];
    let mut u_lo = [0.0f32; 3];
    let mut num_pairs = 0;
    for i in 0..count {
        for j in i + 1..count {
            let u = d_omega * (delays[i] - delays[j]) / (2.0 * std::f64::consts::PI);
            let u = u - u.round();
            // 11 significant bits: j (< 2¹³) × head has ≤ 24 bits, exact in f32.
            let scale = 2f64.powi(11 - u.abs().max(1e-30).log2().ceil() as i32);
            let hi = (u * scale).round() / scale;
            coef[num_pairs] = 2.0 * gains[i] * gains[j];
            u_hi[num_pairs] = hi as f32;
            u_lo[num_pairs] = (u - hi) as f32;
            num_pairs += 1;
        }
    }
    const ROUND: f32 = 12_582_912.0; // 1.5·2²³
    #[inline(always)]
    fn cos_2pi(t: f32) -> f32 {
        // t ∈ [−½, ½]; y = 2πt/4 ∈ [−π/4, π/4].
        let y = t * std::f32::consts::FRAC_PI_2;
        let y2 = y * y;
        let c = 1.0 + y2 * (-0.5 + y2 * (1.0 / 24.0 + y2 * (-1.0 / 720.0 + y2 * (1.0 / 40_320.0))));
        let c = 2.0 * c * c - 1.0;
        2.0 * c * c - 1.0
    }
    match num_pairs {
        0 => {
            let h = constant.sqrt();
            out.fill(h);
        }
        _ => {
            for (j, o) in out.iter_mut().enumerate() {
                let jf = j as f32;
                let mut h2 = constant;
                for p in 0..3 {
                    // Unused pairs have coef 0 and u 0: they add exactly 0.
                    let a = jf * u_hi[p];
                    let a = a - ((a + ROUND) - ROUND);
                    let t = a + jf * u_lo[p];
                    let t = t - ((t + ROUND) - ROUND);
                    h2 += coef[p] * cos_2pi(t);
                }
                *o = h2.max(0.0).sqrt();
            }
        }
    }
    out.len() as u64
}

/// Accumulates `weight · |H(ω_j)| · spectrum[j]` into `acc` using a scratch buffer of at least
/// `spectrum.len()` samples (see [`comb_magnitude`]). Returns the number of bins.
pub fn accumulate_comb(
    paths: &EarPaths,
    weight: f32,
    d_omega: f64,
    spectrum: &[f32],
    acc: &mut [f32],
    scratch: &mut [f32],
) -> u64 {
    let n = spectrum.len().min(acc.len());
    let h = &mut scratch[..n];
    let bins = comb_magnitude(paths, d_omega, h);
    for ((a, hj), s) in acc[..n].iter_mut().zip(h.iter()).zip(spectrum) {
        *a += (weight * hj) * s;
    }
    bins
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table_at_zero() -> Plane {
        Plane {
            point_m: [0.0, 0.0, 0.0],
            normal: [0.0, 0.0, 1.0],
        }
    }

    #[test]
    fn image_geometry_of_test_9() {
        // digest-sound §12 test 9: y = (0, 0, 0.05), n = +z, table z = 0, listener (1, 0, 0.3).
        let p = ear_paths(
            [0.0, 0.0, 0.05],
            [0.0, 0.0, 1.0],
            1.0,
            [1.0, 0.0, 0.3],
            &[table_at_zero()],
            COS_FLOOR,
        );
        let r: f64 = (1.0f64 + 0.25 * 0.25).sqrt();
        let ri: f64 = (1.0f64 + 0.35 * 0.35).sqrt();
        assert!((p.direct.gain - (0.25 / r) / r).abs() < 1e-12);
        assert_eq!(p.num_images, 1);
        // Mirrored axis −z: the image is heard with negative polarity from above.
        assert!((p.images[0].gain - (-(0.35 / ri) / ri)).abs() < 1e-12);
        assert!(((p.images[0].delay_s - p.direct.delay_s) - (ri - r) / 343.0).abs() < 1e-15);
    }

    #[test]
    fn floor_in_the_sheet_plane_and_back_lobe() {
        let p = ear_paths(
            [0.0; 3],
            [0.0, 0.0, 1.0],
            1.0,
            [1.0, 0.0, 0.0],
            &[],
            COS_FLOOR,
        );
        assert!((p.direct.gain - COS_FLOOR).abs() < 1e-12);
        let q = ear_paths(
            [0.0; 3],
            [0.0, 0.0, 1.0],
            1.0,
            [0.0, 0.0, -1.0],
            &[],
            COS_FLOOR,
        );
        assert!((q.direct.gain + 1.0).abs() < 1e-12);
    }

    #[test]
    fn far_weak_and_hidden_images_are_skipped() {
        // Ear below the table: no image.
        let p = ear_paths(
            [0.0, 0.0, 0.05],
            [1.0, 0.0, 0.0],
            1.0,
            [1.0, 0.0, -0.3],
            &[table_at_zero()],
            COS_FLOOR,
        );
        assert_eq!((p.num_images, p.skipped), (0, 1));
        // Source 4 m above the table, listener next to it: the image is > 20 ms late.
        let p = ear_paths(
            [0.0, 0.0, 4.0],
            [1.0, 0.0, 0.0],
            1.0,
            [1.0, 0.0, 4.0],
            &[table_at_zero()],
            COS_FLOOR,
        );
        assert_eq!(p.num_images, 0);
    }

    #[test]
    fn comb_recurrence_matches_direct_evaluation() {
        let wall = Plane {
            point_m: [0.0, 0.4, 0.0],
            normal: [0.0, -1.0, 0.0],
        };
        let p = ear_paths(
            [0.02, 0.05, 0.1],
            [0.3, -0.2, 0.9],
            1.3,
            [0.085, -1.0, 0.55],
            &[table_at_zero(), wall],
            COS_FLOOR,
        );
        assert_eq!(p.num_images, 2);
        let bins = 4097;
        let d_omega = 2.0 * std::f64::consts::PI * 192_000.0 / 8192.0;
        let spectrum = vec![1.0f32; bins];
        let mut acc = vec![0.0f32; bins];
        let mut scratch = vec![0.0f32; bins];
        assert_eq!(
            accumulate_comb(&p, 0.5, d_omega, &spectrum, &mut acc, &mut scratch),
            bins as u64
        );
        let scale: f64 = p.paths().map(|q| q.gain.abs()).sum();
        for (j, a) in acc.iter().enumerate() {
            let expect = 0.5 * p.magnitude_at(j as f64 * d_omega);
            assert!(
                (f64::from(*a) - expect).abs() < 2e-5 * scale,
                "bin {j}: {a} vs {expect}"
            );
        }
        // Without images (or with silent ones) the magnitude is exactly |g0|.
        let mut silent = p;
        silent.images[0].gain = 0.0;
        silent.images[1].gain = 0.0;
        let mut h = vec![0.0f32; 64];
        comb_magnitude(&silent, d_omega, &mut h);
        assert!(h.iter().all(|v| *v == (p.direct.gain as f32).abs()));
    }

    #[test]
    fn size_factor_is_relative_and_clamped() {
        assert_eq!(size_factor(0.05, None), 1.0);
        assert!((size_factor(0.1, Some(0.05)) - 8.0).abs() < 1e-12);
        assert_eq!(size_factor(1.0, Some(0.01)), SIZE_FACTOR_RANGE.1);
        assert_eq!(size_factor(f32::NAN, Some(0.05)), 1.0);
    }
}
