//! # Frame clock: where simulation frames fall on the sample timeline
//!
//! The simulation runs at a fixed frame rate (sim-core's `frame_rate_hz`, 200 Hz by default);
//! audio runs at the host's sample rate. Frame `k` covers the sample span
//! `[start(k), start(k + 1))` with `start(k) = round(k · fs / f_frame)`. The frame is stepped
//! once the audio clock reaches the end of its span — its inputs (every command stamped before
//! that end) are then all known — and its output sounds from that sample on. Both the offline
//! lockstep path and the real-time worker follow this rule, which is why a render does not depend
//! on how the host splits blocks.

/// Maps frame indices to sample positions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameClock {
    samples_per_frame: f64,
    frame_rate_hz: f64,
}

impl FrameClock {
    /// A clock for a sample rate and a frame rate (both sanitized: a rate that is not finite and
    /// positive falls back to 48 kHz / 200 Hz).
    pub fn new(sample_rate_hz: f64, frame_rate_hz: f64) -> Self {
        let fs = if sample_rate_hz.is_finite() && sample_rate_hz > 0.0 {
            sample_rate_hz
        } else {
            48_000.0
        };
        let ff = if frame_rate_hz.is_finite() && frame_rate_hz > 0.0 {
            frame_rate_hz
        } else {
            200.0
        };
        Self {
            samples_per_frame: (fs / ff).max(1.0),
            frame_rate_hz: ff,
        }
    }

    /// First sample of frame `k`.
    pub fn start(&self, k: u64) -> u64 {
        (k as f64 * self.samples_per_frame).round() as u64
    }

    /// One past the last sample of frame `k`: when it is stepped.
    pub fn end(&self, k: u64) -> u64 {
        self.start(k + 1)
    }

    /// Simulated time at the start of frame `k`, seconds: `k / f_frame`, the same at every
    /// sample rate (where `start(k) / fs` is rounded to a sample).
    pub fn time_s(&self, k: u64) -> f64 {
        k as f64 / self.frame_rate_hz
    }

    /// The sample at which an input stamped `t_s` seconds is given: its own sample rounded,
    /// kept within the span of the frame its time falls in (frame ⌊t · f_frame⌋: a time on a
    /// boundary belongs to the frame it starts), so that at every sample rate the input reaches
    /// the same frame (rounding to the sample alone moved an input within half a sample of a
    /// boundary to the other frame at some rates). It moves by at most 1.5 samples.
    pub fn input_sample(&self, t_s: f64, sample_rate_hz: f64) -> u64 {
        let t = if t_s.is_finite() { t_s.max(0.0) } else { 0.0 };
        // The epsilon puts a time written as a boundary (0.2 s) on it despite its binary error.
        let k = (t * self.frame_rate_hz + 1e-9).floor() as u64;
        let s = (t * sample_rate_hz).round() as u64;
        s.clamp(self.start(k), self.end(k) - 1)
    }

    /// The sample rate it was built for, Hz (after sanitizing).
    pub fn sample_rate_hz(&self) -> f64 {
        self.samples_per_frame * self.frame_rate_hz
    }

    /// Samples per frame (fractional).
    pub fn samples_per_frame(&self) -> f64 {
        self.samples_per_frame
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_tile_the_timeline() {
        for fs in [
            8_000.0, 44_100.0, 48_000.0, 88_200.0, 96_000.0, 192_000.0, 44_100.5,
        ] {
            let c = FrameClock::new(fs, 200.0);
            let mut total = 0;
            for k in 0..10_000 {
                let (a, b) = (c.start(k), c.end(k));
                assert!(b > a, "frame {k} at {fs} Hz is empty");
                assert_eq!(a, total);
                total = b;
            }
            let expect = (10_000.0 * fs / 200.0_f64).round() as u64;
            assert_eq!(total, expect);
        }
    }

    #[test]
    fn an_input_reaches_the_same_frame_at_every_rate() {
        let rates = [
            8_000.0, 22_050.0, 32_000.0, 44_100.0, 48_000.0, 88_200.0, 96_000.0, 192_000.0,
        ];
        for i in 0..20_000 {
            // Times all over, many within a sample of a frame boundary.
            let t = i as f64 * 0.000_613_7 + if i % 3 == 0 { 1e-6 } else { 0.0 };
            let k = (t * 200.0 + 1e-9).floor() as u64;
            for fs in rates {
                let c = FrameClock::new(fs, 200.0);
                let s = c.input_sample(t, fs);
                assert!(
                    c.start(k) <= s && s < c.end(k),
                    "t {t} at {fs} Hz: sample {s}"
                );
                // Half a sample of rounding, and the frame's own start rounded by as much.
                assert!(
                    (s as f64 - t * fs).abs() <= 1.5,
                    "t {t} moved to {s} at {fs} Hz"
                );
            }
        }
        let c = FrameClock::new(44_100.0, 200.0);
        assert_eq!(c.input_sample(0.2, 44_100.0), c.start(40));
        assert_eq!(c.input_sample(f64::NAN, 44_100.0), 0);
    }

    #[test]
    fn bad_rates_fall_back() {
        let c = FrameClock::new(f64::NAN, -1.0);
        assert_eq!(c.samples_per_frame(), 240.0);
    }
}
