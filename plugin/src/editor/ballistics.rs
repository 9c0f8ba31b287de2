//! # Meter ballistics: how the editor's meters move
//!
//! The engine publishes raw figures as atomics ([`crate::engine::Meters`]): the output peak
//! since the editor last looked, and monotone event counters. The editor turns them into
//! readable displays at its own repaint rate:
//!
//! - [`PeakMeter`]: instant attack, linear release of [`PEAK_RELEASE_DB_PER_S`], plus a peak
//!   marker held for [`PEAK_HOLD_S`] and then released the same way;
//! - [`RateMeter`]: a counter differentiated over windows of [`RATE_WINDOW_S`] (events per
//!   second), robust to a counter that restarts (a new engine) and to stalls of the GUI.

/// Lowest level a meter shows, dBFS.
pub const METER_FLOOR_DB: f32 = -72.0;
/// Release speed of the peak meter, dB per second.
pub const PEAK_RELEASE_DB_PER_S: f32 = 24.0;
/// How long the peak marker stays before it falls, seconds.
pub const PEAK_HOLD_S: f32 = 1.5;
/// Differentiation window of the rate meters, seconds.
pub const RATE_WINDOW_S: f64 = 0.5;

/// Linear amplitude → dBFS, floored at [`METER_FLOOR_DB`].
pub fn to_db(amplitude: f32) -> f32 {
    if amplitude.is_finite() && amplitude > 0.0 {
        (20.0 * amplitude.log10()).max(METER_FLOOR_DB)
    } else {
        METER_FLOOR_DB
    }
}

/// Peak meter with release and a held peak marker.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakMeter {
    /// Displayed level, dBFS.
    pub level_db: f32,
    /// Held peak marker, dBFS.
    pub hold_db: f32,
    hold_age_s: f32,
}

impl Default for PeakMeter {
    fn default() -> Self {
        Self {
            level_db: METER_FLOOR_DB,
            hold_db: METER_FLOOR_DB,
            hold_age_s: 0.0,
        }
    }
}

impl PeakMeter {
    /// Feeds the peak (linear) seen over the last `dt_s` seconds.
    pub fn update(&mut self, peak: f32, dt_s: f32) {
        let dt = if dt_s.is_finite() {
            dt_s.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let new_db = to_db(peak);
        let released = (self.level_db - PEAK_RELEASE_DB_PER_S * dt).max(METER_FLOOR_DB);
        self.level_db = new_db.max(released);
        if new_db >= self.hold_db {
            self.hold_db = new_db;
            self.hold_age_s = 0.0;
        } else {
            self.hold_age_s += dt;
            if self.hold_age_s > PEAK_HOLD_S {
                self.hold_db = (self.hold_db - PEAK_RELEASE_DB_PER_S * dt)
                    .max(self.level_db)
                    .max(METER_FLOOR_DB);
            }
        }
    }
}

/// Events per second from a monotone counter.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RateMeter {
    start: Option<(f64, u64)>,
    /// Last computed rate, per second.
    pub rate_per_s: f32,
}

impl RateMeter {
    /// Feeds the counter's value at time `now_s`; returns the current rate.
    pub fn update(&mut self, count: u64, now_s: f64) -> f32 {
        match self.start {
            Some((t0, c0)) if count >= c0 && now_s >= t0 => {
                let dt = now_s - t0;
                if dt >= RATE_WINDOW_S {
                    self.rate_per_s = ((count - c0) as f64 / dt) as f32;
                    self.start = Some((now_s, count));
                }
            }
            // First sample, a restarted counter or time going backwards: start over.
            _ => {
                self.start = Some((now_s, count));
                self.rate_per_s = 0.0;
            }
        }
        self.rate_per_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn db_conversion() {
        assert_eq!(to_db(1.0), 0.0);
        assert!((to_db(0.5) + 6.0206).abs() < 1e-3);
        assert_eq!(to_db(0.0), METER_FLOOR_DB);
        assert_eq!(to_db(f32::NAN), METER_FLOOR_DB);
    }

    #[test]
    fn peak_attacks_instantly_and_releases_linearly() {
        let mut m = PeakMeter::default();
        m.update(1.0, 0.016);
        assert_eq!(m.level_db, 0.0);
        assert_eq!(m.hold_db, 0.0);
        // One second of silence: the level falls by the release rate.
        for _ in 0..10 {
            m.update(0.0, 0.1);
        }
        assert!(
            (m.level_db + PEAK_RELEASE_DB_PER_S).abs() < 1e-3,
            "{}",
            m.level_db
        );
        // The marker is still held for PEAK_HOLD_S, then falls but never below the level.
        assert_eq!(m.hold_db, 0.0);
        for _ in 0..10 {
            m.update(0.0, 0.1);
        }
        assert!(m.hold_db < 0.0 && m.hold_db >= m.level_db);
        // Eventually both reach the floor and stay there.
        for _ in 0..100 {
            m.update(0.0, 0.1);
        }
        assert_eq!(m.level_db, METER_FLOOR_DB);
        assert_eq!(m.hold_db, METER_FLOOR_DB);
    }

    #[test]
    fn peak_ignores_absurd_time_steps() {
        let mut m = PeakMeter::default();
        m.update(1.0, 0.0);
        m.update(0.0, f32::NAN);
        assert_eq!(m.level_db, 0.0);
        m.update(0.0, 1e9);
        assert!(
            (m.level_db + PEAK_RELEASE_DB_PER_S).abs() < 1e-3,
            "clamped to 1 s"
        );
    }

    #[test]
    fn rate_is_the_counter_slope_over_a_window() {
        let mut r = RateMeter::default();
        assert_eq!(r.update(100, 10.0), 0.0);
        // Inside the window, the previous rate stays.
        assert_eq!(r.update(110, 10.2), 0.0);
        // 50 events in 0.5 s.
        assert!((r.update(150, 10.5) - 100.0).abs() < 1e-3);
        // Next window: 20 events in 1 s (a GUI stall) = 20/s.
        assert!((r.update(170, 11.5) - 20.0).abs() < 1e-3);
    }

    #[test]
    fn rate_restarts_with_the_counter() {
        let mut r = RateMeter::default();
        r.update(1000, 0.0);
        assert!(r.update(2000, 1.0) > 0.0);
        // A new engine starts counting from zero: no negative or huge rate.
        assert_eq!(r.update(5, 1.1), 0.0);
        assert!((r.update(55, 1.6) - 100.0).abs() < 1e-3);
        assert_eq!(r.update(60, 0.0), 0.0, "time going backwards restarts too");
    }
}
