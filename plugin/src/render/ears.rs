//! # Two ears around the listener (stereo)
//!
//! The seeds are mono (one listening point, digest-sound §13.10). For stereo we evaluate the
//! spatial model at **two points 17 cm apart** — the ears, ±[`EAR_HALF_SPACING_M`] from the head
//! centre — as digest-sound §4.3 proposes. The head centre is
//! `RoomConfig::listener_position_m(az, dist)` (ears 45 cm above the table top); the head faces
//! the sheet's home centre horizontally, so "right" is `facing × up`. The ears are omnidirectional
//! points: no head shadow, no pinna, no HRTF — the interaural time and level differences and the
//! per-ear comb of the image sources are what makes the stereo image. For units the interaural
//! time difference is rendered exactly (fractional delays); for friction and tearing noise only
//! the levels and the comb differ per ear (their phase is random anyway).
//!
//! Delays are measured from the head centre: a path of length R to an ear is delayed by
//! `(R − R_centre)/c + EAR_HALF_SPACING_M/c`, which is ≥ 0 by the triangle inequality, so every
//! unit is heard [`EAR_HALF_SPACING_M`]/c ≈ 0.25 ms after its trigger at the latest-ear-first
//! position — a fixed, inaudible latency that keeps every tap causal.

use sim_core::RoomConfig;

use super::Scene;

/// Half the distance between the ears, m.
pub const EAR_HALF_SPACING_M: f64 = 0.085;

/// Speed of sound, m/s (the seeds give none; 343 m/s at 20 °C, digest-sound §5.3).
pub const SPEED_OF_SOUND_M_S: f64 = 343.0;

/// Index of the left ear.
pub const LEFT: usize = 0;
/// Index of the right ear.
pub const RIGHT: usize = 1;

/// The listener's head.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ears {
    /// Head centre, world metres.
    pub centre_m: [f64; 3],
    /// Left and right ear positions, world metres.
    pub ear_m: [[f64; 3]; 2],
}

impl Ears {
    /// The ears for a scene.
    pub fn from_scene(scene: &Scene) -> Self {
        let room: RoomConfig = scene.room;
        let centre = room.listener_position_m(
            f64::from(scene.listener_az_deg),
            f64::from(scene.listener_dist_m),
        );
        let home = room.home_centre_m();
        Self::at(centre, home)
    }

    /// Ears of a head at `centre_m` facing `look_at_m` horizontally.
    pub fn at(centre_m: [f64; 3], look_at_m: [f64; 3]) -> Self {
        let (fx, fy) = (look_at_m[0] - centre_m[0], look_at_m[1] - centre_m[1]);
        let len = (fx * fx + fy * fy).sqrt();
        let (fx, fy) = if len > 1e-9 {
            (fx / len, fy / len)
        } else {
            (0.0, 1.0)
        };
        // right = facing × up = (fy, −fx, 0)
        let right = [fy, -fx, 0.0];
        let h = EAR_HALF_SPACING_M;
        let ear = |s: f64| {
            [
                centre_m[0] + s * h * right[0],
                centre_m[1] + s * h * right[1],
                centre_m[2] + s * h * right[2],
            ]
        };
        Self {
            centre_m,
            ear_m: [ear(-1.0), ear(1.0)],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn right_ear_is_on_the_right() {
        // Listener in front (az 0) at y = −1: right is +x.
        let e = Ears::at([0.0, -1.0, 1.2], [0.0, 0.0, 0.75]);
        assert!((e.ear_m[RIGHT][0] - EAR_HALF_SPACING_M).abs() < 1e-12);
        assert!((e.ear_m[LEFT][0] + EAR_HALF_SPACING_M).abs() < 1e-12);
        // Listener at +90° (x = +1) looking towards −x: right is +y.
        let e = Ears::at([1.0, 0.0, 1.2], [0.0, 0.0, 0.75]);
        assert!((e.ear_m[RIGHT][1] - EAR_HALF_SPACING_M).abs() < 1e-12);
        let s = Ears::from_scene(&Scene::default());
        assert!((s.centre_m[1] + 1.0).abs() < 1e-9);
    }
}
