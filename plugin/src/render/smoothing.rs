//! # Smoothing of control values (no zipper noise)
//!
//! - [`GainSmoother`]: one-pole glide of a linear gain towards its target (time constant
//!   [`MIX_SMOOTHING_MS`]), snapping exactly onto the target once within 1e-6 (or once a step no longer changes the
//!   f32 value) so that a steady
//!   gain is bit-exact and never decays into denormals. Used for the mix levels.
//! - [`LinearRamp`]: linear interpolation from the current value to a new target over a given
//!   number of samples, landing exactly on the target. Used for the per-frame inputs (tear speed):
//!   the simulation sends ~200 frames/s, the ramp spans the measured frame interval, so the value
//!   is interpolated across each frame instead of stepping.
//!
//! Both advance one sample at a time, so the output does not depend on how `render()` calls are
//! split.

/// Time constant of the mix-level smoothing, ms.
pub const MIX_SMOOTHING_MS: f64 = 10.0;

/// One-pole gain smoother.
#[derive(Clone, Copy, Debug)]
pub struct GainSmoother {
    current: f32,
    target: f32,
    coeff: f32,
}

impl GainSmoother {
    /// A smoother at `value`, with the time constant [`MIX_SMOOTHING_MS`] at `sample_rate_hz`.
    pub fn new(value: f32, sample_rate_hz: f64) -> Self {
        let tau = MIX_SMOOTHING_MS * 1e-3 * sample_rate_hz;
        Self {
            current: value,
            target: value,
            coeff: (1.0 - (-1.0 / tau).exp()) as f32,
        }
    }

    /// New target.
    pub fn set_target(&mut self, target: f32) {
        self.target = if target.is_finite() { target } else { 0.0 };
    }

    /// Jumps to the target.
    pub fn snap(&mut self) {
        self.current = self.target;
    }

    /// True when the value sits on its target.
    pub fn is_steady(&self) -> bool {
        self.current == self.target
    }

    /// The current value.
    pub fn value(&self) -> f32 {
        self.current
    }

    /// Advances one sample and returns the new value.
    #[inline]
    pub fn tick(&mut self) -> f32 {
        if self.current != self.target {
            let d = self.target - self.current;
            let next = self.current + d * self.coeff;
            // Snap once within 1e-6 or when the step no longer changes the f32 value.
            if d.abs() <= 1e-6 || next == self.current {
                self.current = self.target;
            } else {
                self.current = next;
            }
        }
        self.current
    }
}

/// Linear ramp to a target over a number of samples.
#[derive(Clone, Copy, Debug, Default)]
pub struct LinearRamp {
    current: f32,
    target: f32,
    step: f32,
    remaining: u32,
}

impl LinearRamp {
    /// Starts a ramp from the current value to `target` over `samples` samples (≥ 1). A target
    /// equal to the current value leaves the ramp steady there (a ramp from x to x would hold x
    /// anyway; steady, a consumer that skips work on a steady value skips it now).
    pub fn set_target(&mut self, target: f32, samples: u32) {
        let target = if target.is_finite() { target } else { 0.0 };
        if target == self.current {
            self.reset(target);
            return;
        }
        let samples = samples.max(1);
        self.target = target;
        self.step = (target - self.current) / samples as f32;
        self.remaining = samples;
    }

    /// Jumps to `value`.
    pub fn reset(&mut self, value: f32) {
        *self = Self {
            current: value,
            target: value,
            step: 0.0,
            remaining: 0,
        };
    }

    /// The current value.
    pub fn value(&self) -> f32 {
        self.current
    }

    /// The target.
    pub fn target(&self) -> f32 {
        self.target
    }

    /// True when the ramp has arrived.
    pub fn is_steady(&self) -> bool {
        self.remaining == 0
    }

    /// Advances one sample and returns the new value.
    #[inline]
    pub fn tick(&mut self) -> f32 {
        if self.remaining > 0 {
            self.remaining -= 1;
            self.current = if self.remaining == 0 {
                self.target
            } else {
                self.current + self.step
            };
        }
        self.current
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gain_smoother_reaches_target_exactly() {
        let mut g = GainSmoother::new(0.0, 48_000.0);
        g.set_target(1.0);
        let mut v = 0.0;
        for _ in 0..48_000 {
            v = g.tick();
        }
        assert_eq!(v, 1.0);
        assert!(g.is_steady());
        g.set_target(0.0);
        for _ in 0..48_000 {
            v = g.tick();
        }
        assert_eq!(v, 0.0);
    }

    #[test]
    fn ramp_lands_on_target() {
        let mut r = LinearRamp::default();
        r.set_target(2.0, 4);
        let v: Vec<f32> = (0..6).map(|_| r.tick()).collect();
        assert_eq!(v, vec![0.5, 1.0, 1.5, 2.0, 2.0, 2.0]);
        r.set_target(0.0, 3);
        for _ in 0..3 {
            r.tick();
        }
        assert_eq!(r.value(), 0.0);
        assert!(r.is_steady());
    }

    #[test]
    fn a_target_equal_to_the_value_is_steady_at_once() {
        let mut r = LinearRamp::default();
        r.set_target(0.0, 100);
        assert!(r.is_steady());
        r.set_target(1.0, 4);
        r.tick();
        // Mid-ramp, the current value as the target: steady there, no further step.
        let here = r.value();
        r.set_target(here, 4);
        assert!(r.is_steady());
        assert_eq!(r.tick(), here);
    }
}
