//! # The room around the sheet, as geometry to draw
//!
//! Builds what the sheet view draws besides the sheet, from [`RoomConfig`] (sim-core's room
//! frame: floor z = 0, table top z = `table_height_cm`, wall plane y = `wall_dist_cm` facing
//! −y; x right, y away from a listener at azimuth 0, z up) and the listener parameters:
//!
//! - the floor as a grid of lines (it is always there: a collision plane);
//! - the table top as a finite rectangle around the sheet's home (the simulation's table is an
//!   infinite plane; [`TABLE_HALF_SIZE_M`] is only what is drawn), cut at the wall;
//! - the wall as a rectangle from the floor to above the table;
//! - the listener's head at [`RoomConfig::listener_position_m`], with its nose towards the
//!   sheet's home centre and its two ears.

use sim_core::room::RoomConfig;

use super::vec3::{V3, add, cross, from_f64, normalized, scale, sub};

/// Half extents (x, y) of the drawn table top, metres.
pub const TABLE_HALF_SIZE_M: [f32; 2] = [0.55, 0.40];
/// Half extent of the drawn floor grid, metres, and its line spacing.
pub const FLOOR_HALF_SIZE_M: f32 = 1.5;
/// Floor grid spacing, metres.
pub const FLOOR_GRID_M: f32 = 0.25;
/// Half width of the drawn wall, metres.
pub const WALL_HALF_WIDTH_M: f32 = 0.9;
/// How far the drawn wall rises above the table top, metres.
pub const WALL_ABOVE_TABLE_M: f32 = 0.7;
/// Radius of the listener's head, metres.
pub const HEAD_RADIUS_M: f32 = 0.09;

/// The listener marker.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ListenerMarker {
    /// Centre of the head, world metres.
    pub head_m: V3,
    /// Tip of the nose (towards the sheet), world metres.
    pub nose_m: V3,
    /// Left ear, world metres.
    pub left_ear_m: V3,
    /// Right ear, world metres.
    pub right_ear_m: V3,
}

/// The room's drawable geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct RoomScene {
    /// Floor grid lines (z = 0).
    pub floor_lines: Vec<[V3; 2]>,
    /// Table top corners (counter-clockwise seen from above), if the table is on.
    pub table: Option<[V3; 4]>,
    /// Wall corners, if the wall is on.
    pub wall: Option<[V3; 4]>,
    /// The listener.
    pub listener: ListenerMarker,
}

impl RoomScene {
    /// The geometry of `room` with a listener at `azimuth_deg`, `distance_m`.
    pub fn new(room: &RoomConfig, azimuth_deg: f32, distance_m: f32) -> Self {
        let room = room.sanitized();
        let table_z = room.home_height_m() as f32;
        let wall_y = room.wall.then_some(room.wall_dist_cm * 0.01);

        let mut floor_lines = Vec::new();
        let steps = (FLOOR_HALF_SIZE_M / FLOOR_GRID_M).round() as i32;
        let far_y = wall_y.unwrap_or(FLOOR_HALF_SIZE_M).min(FLOOR_HALF_SIZE_M);
        for i in -steps..=steps {
            let v = i as f32 * FLOOR_GRID_M;
            floor_lines.push([[v, -FLOOR_HALF_SIZE_M, 0.0], [v, far_y, 0.0]]);
            if v <= far_y {
                floor_lines.push([[-FLOOR_HALF_SIZE_M, v, 0.0], [FLOOR_HALF_SIZE_M, v, 0.0]]);
            }
        }

        let table = room.table.then(|| {
            let [hx, hy] = TABLE_HALF_SIZE_M;
            let back = wall_y.map_or(hy, |w| w.min(hy));
            [
                [-hx, -hy, table_z],
                [hx, -hy, table_z],
                [hx, back, table_z],
                [-hx, back, table_z],
            ]
        });
        let wall = wall_y.map(|y| {
            let top = table_z + WALL_ABOVE_TABLE_M;
            [
                [-WALL_HALF_WIDTH_M, y, 0.0],
                [WALL_HALF_WIDTH_M, y, 0.0],
                [WALL_HALF_WIDTH_M, y, top],
                [-WALL_HALF_WIDTH_M, y, top],
            ]
        });

        let head =
            from_f64(room.listener_position_m(f64::from(azimuth_deg), f64::from(distance_m)));
        let home = from_f64(room.home_centre_m());
        let mut to_sheet = sub(home, head);
        to_sheet[2] = 0.0;
        let facing = normalized(to_sheet).unwrap_or([0.0, 1.0, 0.0]);
        // Facing f (horizontal), up z: the right ear is at f × z.
        let right = cross(facing, [0.0, 0.0, 1.0]);
        let listener = ListenerMarker {
            head_m: head,
            nose_m: add(head, scale(facing, HEAD_RADIUS_M * 1.5)),
            left_ear_m: sub(head, scale(right, HEAD_RADIUS_M)),
            right_ear_m: add(head, scale(right, HEAD_RADIUS_M)),
        };
        Self {
            floor_lines,
            table,
            wall,
            listener,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_sits_at_its_height_and_the_wall_at_its_distance() {
        let room = RoomConfig {
            table: true,
            table_height_cm: 80.0,
            wall: true,
            wall_dist_cm: 30.0,
        };
        let s = RoomScene::new(&room, 0.0, 1.0);
        let t = s.table.unwrap();
        assert!(t.iter().all(|p| (p[2] - 0.8).abs() < 1e-6));
        // The table stops at the wall.
        assert!(t.iter().all(|p| p[1] <= 0.3 + 1e-6));
        let w = s.wall.unwrap();
        assert!(w.iter().all(|p| (p[1] - 0.3).abs() < 1e-6));
        assert!(w.iter().any(|p| p[2] == 0.0) && w.iter().any(|p| p[2] > 0.8));
        // No floor line runs through the wall.
        assert!(s.floor_lines.iter().flatten().all(|p| p[1] <= 0.3 + 1e-6));
    }

    #[test]
    fn switched_off_planes_are_not_drawn() {
        let room = RoomConfig {
            table: false,
            wall: false,
            ..RoomConfig::default()
        };
        let s = RoomScene::new(&room, 0.0, 1.0);
        assert!(s.table.is_none() && s.wall.is_none());
        assert!(!s.floor_lines.is_empty());
    }

    #[test]
    fn listener_in_front_faces_the_sheet_with_ears_left_and_right() {
        let s = RoomScene::new(&RoomConfig::default(), 0.0, 1.0);
        let l = s.listener;
        assert!((l.head_m[1] + 1.0).abs() < 1e-5 && l.head_m[0].abs() < 1e-5);
        assert!(
            l.nose_m[1] > l.head_m[1],
            "the nose points at the sheet (+y)"
        );
        assert!(l.left_ear_m[0] < l.head_m[0] && l.right_ear_m[0] > l.head_m[0]);
        // To the right of the sheet (+90°) the listener looks towards −x.
        let r = RoomScene::new(&RoomConfig::default(), 90.0, 2.0).listener;
        assert!((r.head_m[0] - 2.0).abs() < 1e-4);
        assert!(r.nose_m[0] < r.head_m[0]);
        assert!(
            r.right_ear_m[1] > r.head_m[1],
            "facing −x, the right ear is at +y"
        );
    }
}
