//! # The room: floor, table, wall, and where the listener stands
//!
//! World frame (metres): x to the right, y away from a listener at azimuth 0 (towards the
//! sheet's back edge), z up. The floor is the plane z = 0 and is always there (it catches a sheet
//! that is dropped with the table switched off); it is a collision plane only, not an acoustic
//! reflector (think carpet). The table top is the plane z = `table_height_cm`; the sheet starts
//! lying flat on it, centred on the z axis. The wall is the vertical plane y = `wall_dist_cm`
//! (behind the back edge), facing −y.
//!
//! The table and the wall are rigid planes for the simulation's collisions and the two reflectors
//! of the sound model's image sources (sound paper eq. 4.7–4.12, digest-sound §5). The listener
//! stands `listener_dist_m` from the sheet's home centre at azimuth `listener_az_deg` (0 = in front
//! of the front edge, +90 = to the right), with the ears [`EAR_HEIGHT_ABOVE_TABLE_M`] above the
//! table top.

use serde::{Deserialize, Serialize};

/// Height of the listener's ears above the table top, in metres (a seated listener).
pub const EAR_HEIGHT_ABOVE_TABLE_M: f64 = 0.45;

/// Limits of the room parameters.
pub const TABLE_HEIGHT_RANGE_CM: (f32, f32) = (40.0, 120.0);
/// Limits of the wall distance, measured from the sheet's home centre.
pub const WALL_DIST_RANGE_CM: (f32, f32) = (2.0, 300.0);

/// An infinite plane `{ x : (x − point)·normal = 0 }`, the solid side being `(x − point)·normal < 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point on the plane, metres.
    pub point_m: [f64; 3],
    /// Unit normal pointing into free space.
    pub normal: [f64; 3],
}

impl Plane {
    /// Signed distance of `p` from the plane (positive on the free side), metres.
    pub fn signed_distance_m(&self, p: [f64; 3]) -> f64 {
        (p[0] - self.point_m[0]) * self.normal[0]
            + (p[1] - self.point_m[1]) * self.normal[1]
            + (p[2] - self.point_m[2]) * self.normal[2]
    }
}

/// Table and wall switches and positions (the plugin's room parameters).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RoomConfig {
    /// Is there a table under the sheet?
    pub table: bool,
    /// Height of the table top above the floor, cm.
    pub table_height_cm: f32,
    /// Is there a wall behind the sheet?
    pub wall: bool,
    /// Distance of the wall from the sheet's home centre, cm.
    pub wall_dist_cm: f32,
}

impl Default for RoomConfig {
    fn default() -> Self {
        Self {
            table: true,
            table_height_cm: 75.0,
            wall: false,
            wall_dist_cm: 40.0,
        }
    }
}

impl RoomConfig {
    /// Returns a copy with every value finite and inside its documented range.
    pub fn sanitized(self) -> Self {
        let d = Self::default();
        let clamp = |v: f32, (lo, hi): (f32, f32), dflt: f32| {
            if v.is_finite() { v.clamp(lo, hi) } else { dflt }
        };
        Self {
            table: self.table,
            table_height_cm: clamp(
                self.table_height_cm,
                TABLE_HEIGHT_RANGE_CM,
                d.table_height_cm,
            ),
            wall: self.wall,
            wall_dist_cm: clamp(self.wall_dist_cm, WALL_DIST_RANGE_CM, d.wall_dist_cm),
        }
    }

    /// Height of the table top (also the sheet's home height, table on or off), metres.
    pub fn home_height_m(&self) -> f64 {
        f64::from(self.table_height_cm) * 0.01
    }

    /// The sheet's home centre: where the flat sheet starts, metres.
    pub fn home_centre_m(&self) -> [f64; 3] {
        [0.0, 0.0, self.home_height_m()]
    }

    /// The floor plane (always present; collision only).
    pub fn floor(&self) -> Plane {
        Plane {
            point_m: [0.0, 0.0, 0.0],
            normal: [0.0, 0.0, 1.0],
        }
    }

    /// The table-top plane, if the table is on.
    pub fn table_plane(&self) -> Option<Plane> {
        self.table.then(|| Plane {
            point_m: [0.0, 0.0, self.home_height_m()],
            normal: [0.0, 0.0, 1.0],
        })
    }

    /// The wall plane, if the wall is on.
    pub fn wall_plane(&self) -> Option<Plane> {
        self.wall.then(|| Plane {
            point_m: [0.0, f64::from(self.wall_dist_cm) * 0.01, 0.0],
            normal: [0.0, -1.0, 0.0],
        })
    }

    /// The acoustic reflectors (table, wall) that are switched on, in that order.
    pub fn reflectors(&self) -> impl Iterator<Item = Plane> {
        self.table_plane().into_iter().chain(self.wall_plane())
    }

    /// Listener position (centre of the head) for an azimuth (degrees, 0 = in front of the
    /// front edge, +90 = right) and a distance (metres) from the sheet's home centre.
    pub fn listener_position_m(&self, azimuth_deg: f64, distance_m: f64) -> [f64; 3] {
        let az = azimuth_deg.to_radians();
        let d = if distance_m.is_finite() {
            distance_m.max(0.05)
        } else {
            1.0
        };
        let h = self.home_height_m() + EAR_HEIGHT_ABOVE_TABLE_M;
        [d * az.sin(), -d * az.cos(), h]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planes_follow_switches() {
        let mut r = RoomConfig::default();
        assert!(r.table_plane().is_some());
        assert!(r.wall_plane().is_none());
        assert_eq!(r.reflectors().count(), 1);
        r.wall = true;
        r.table = false;
        let walls: Vec<_> = r.reflectors().collect();
        assert_eq!(walls.len(), 1);
        assert!((walls[0].point_m[1] - 0.4).abs() < 1e-12);
        assert!(walls[0].signed_distance_m([0.0, 0.0, 0.8]) > 0.0);
    }

    #[test]
    fn sanitize_clamps_and_defaults() {
        let r = RoomConfig {
            table: true,
            table_height_cm: f32::NAN,
            wall: true,
            wall_dist_cm: 1e9,
        }
        .sanitized();
        assert_eq!(r.table_height_cm, 75.0);
        assert_eq!(r.wall_dist_cm, WALL_DIST_RANGE_CM.1);
    }

    #[test]
    fn listener_in_front_at_zero_azimuth() {
        let r = RoomConfig::default();
        let p = r.listener_position_m(0.0, 1.0);
        assert!(p[0].abs() < 1e-12 && (p[1] + 1.0).abs() < 1e-12);
        let q = r.listener_position_m(90.0, 2.0);
        assert!((q[0] - 2.0).abs() < 1e-12 && q[1].abs() < 1e-9);
    }
}
