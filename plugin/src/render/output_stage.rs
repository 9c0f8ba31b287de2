//! # Output stage: mix, safety clip, sanitising
//!
//! Many units at linear gains can exceed full scale (digest-sound §4.3), so the last stage is a
//! memoryless **soft clipper**: identity up to [`CLIP_KNEE`] (−0.9 dBFS) — transparent at normal
//! levels, bit-exact below the knee — and a tanh knee above, bounded by ±1:
//!
//! ```text
//! |x| ≤ k:  y = x
//! |x| > k:  y = sign(x) · (k + (1 − k) · tanh((|x| − k)/(1 − k)))      k = 0.9
//! ```
//!
//! Memoryless means no state, hence no effect on chunking invariance. Non-finite samples become 0
//! (counted; none should ever occur) and magnitudes below 1e-30 become exactly 0 — no denormal
//! leaves the renderer.

/// Knee of the soft clipper (linear).
pub const CLIP_KNEE: f32 = 0.9;
/// Smallest non-zero magnitude passed on.
pub const FLUSH_BELOW: f32 = 1e-30;

/// Applies the safety stage to one sample. Returns (sample, clipped, was_nonfinite).
#[inline]
pub fn safety(x: f32) -> (f32, bool, bool) {
    if !x.is_finite() {
        return (0.0, false, true);
    }
    let a = x.abs();
    if a <= CLIP_KNEE {
        if a < FLUSH_BELOW {
            return (0.0, false, false);
        }
        return (x, false, false);
    }
    let span = 1.0 - CLIP_KNEE;
    let y = CLIP_KNEE + span * ((a - CLIP_KNEE) / span).tanh();
    (y.copysign(x), true, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transparent_below_knee_bounded_above() {
        for x in [0.0f32, 0.1, -0.5, 0.9, -0.9] {
            assert_eq!(safety(x).0, x);
        }
        for x in [0.95f32, 2.0, 1e30, -7.0] {
            let (y, clipped, _) = safety(x);
            assert!(clipped && y.abs() <= 1.0 && y.signum() == x.signum());
        }
        assert_eq!(safety(f32::NAN), (0.0, false, true));
        assert_eq!(safety(f32::INFINITY).0, 0.0);
        assert_eq!(safety(1e-35).0, 0.0);
        // Continuous and monotonic through the knee.
        let (a, b) = (safety(0.9).0, safety(0.900_01).0);
        assert!(b >= a && b - a < 1e-4);
    }
}
