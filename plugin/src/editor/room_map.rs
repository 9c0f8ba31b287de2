//! # The room map: the room seen from above
//!
//! A small inset in the corner of the sheet view: the table, the wall, the outline of the
//! sheet and the listener (head, nose towards the sheet), seen from above with the back of the
//! room (+y) at the top. It keeps the listener in sight while the 3D camera is close to the
//! sheet (the listener usually stands a metre or more away, behind the 3D camera). The scale
//! follows the listener distance and the wall so that everything fits.

use egui::{Align2, Color32, FontId, Painter, Pos2, Rect, Stroke, pos2};

use super::palette::{LISTENER_COLOUR, TABLE_COLOUR};
use super::region::RegionKind;
use super::room_scene::{HEAD_RADIUS_M, RoomScene};
use super::vec3::V3;

/// Side of the map, logical pixels.
pub const MAP_SIZE_PX: f32 = 150.0;
/// Smallest half range of the map, metres.
pub const MIN_HALF_RANGE_M: f32 = 0.45;

/// World (x, y) → map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapTransform {
    /// Where the sheet's home centre is drawn.
    pub centre: Pos2,
    /// Scale, pixels per metre.
    pub px_per_m: f32,
}

impl MapTransform {
    /// A map of `rect` showing `half_range_m` metres around the home centre in every direction.
    pub fn fit(rect: Rect, half_range_m: f32) -> Self {
        let half = half_range_m.max(1e-3);
        Self {
            centre: rect.center(),
            px_per_m: 0.5 * rect.width().min(rect.height()) / half,
        }
    }

    /// Map position of a world point (its height is ignored).
    pub fn to_map(&self, p: V3) -> Pos2 {
        pos2(
            self.centre.x + p[0] * self.px_per_m,
            self.centre.y - p[1] * self.px_per_m,
        )
    }
}

/// The half range that shows the listener and the wall with a margin.
pub fn half_range_m(scene: &RoomScene) -> f32 {
    let h = scene.listener.head_m;
    let listener = h[0].abs().max(h[1].abs()) + 2.0 * HEAD_RADIUS_M;
    let wall = scene.wall.map_or(0.0, |w| w[0][1].abs() + 0.05);
    (1.15 * listener.max(wall)).max(MIN_HALF_RANGE_M)
}

/// Draws the map into `rect`. `sheet_edges` are the sheet's outline as pairs of positions.
pub fn draw(painter: &Painter, rect: Rect, scene: &RoomScene, sheet_edges: &[[V3; 2]]) {
    let painter = painter.with_clip_rect(rect);
    painter.rect_filled(rect, 4.0, Color32::from_rgba_premultiplied(16, 18, 24, 210));
    let t = MapTransform::fit(rect.shrink(6.0), half_range_m(scene));
    if let Some(table) = &scene.table {
        let pts: Vec<Pos2> = table.iter().map(|p| t.to_map(*p)).collect();
        painter.add(egui::Shape::convex_polygon(pts, TABLE_COLOUR, Stroke::NONE));
    }
    if let Some(w) = &scene.wall {
        painter.line_segment(
            [t.to_map(w[0]), t.to_map(w[1])],
            Stroke::new(3.0, Color32::from_rgb(120, 140, 170)),
        );
    }
    let [r, g, b] = RegionKind::Flat.colour();
    let paper = Stroke::new(1.5, Color32::from_rgb(r, g, b));
    for [a, b] in sheet_edges {
        painter.line_segment([t.to_map(*a), t.to_map(*b)], paper);
    }
    let l = &scene.listener;
    let head = t.to_map(l.head_m);
    let r = (HEAD_RADIUS_M * t.px_per_m).max(4.0);
    painter.line_segment(
        [head, t.to_map(l.nose_m)],
        Stroke::new(2.0, LISTENER_COLOUR),
    );
    painter.circle_filled(head, r, LISTENER_COLOUR.gamma_multiply(0.55));
    painter.circle_stroke(head, r, Stroke::new(1.5, LISTENER_COLOUR));
    painter.text(
        rect.left_top() + egui::vec2(5.0, 3.0),
        Align2::LEFT_TOP,
        "top view",
        FontId::proportional(11.0),
        Color32::from_gray(170),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::vec2;
    use sim_core::room::RoomConfig;

    #[test]
    fn home_is_central_and_back_is_up() {
        let rect = Rect::from_min_size(pos2(100.0, 100.0), vec2(150.0, 150.0));
        let t = MapTransform::fit(rect, 1.0);
        assert_eq!(t.to_map([0.0, 0.0, 0.75]), rect.center());
        assert!(
            t.to_map([0.0, 0.5, 0.0]).y < rect.center().y,
            "+y (back) is up"
        );
        assert!(t.to_map([0.5, 0.0, 0.0]).x > rect.center().x, "+x is right");
        // The half range reaches the edge.
        assert!((t.to_map([1.0, 0.0, 0.0]).x - rect.right()).abs() < 1e-4);
    }

    #[test]
    fn the_listener_and_the_wall_fit() {
        let room = RoomConfig {
            wall: true,
            wall_dist_cm: 250.0,
            ..RoomConfig::default()
        };
        for (az, dist) in [(0.0, 0.3), (37.0, 2.0), (-120.0, 5.0)] {
            let scene = RoomScene::new(&room, az, dist);
            let rect = Rect::from_min_size(pos2(0.0, 0.0), vec2(MAP_SIZE_PX, MAP_SIZE_PX));
            let t = MapTransform::fit(rect, half_range_m(&scene));
            let head = t.to_map(scene.listener.head_m);
            assert!(rect.shrink(2.0).contains(head), "{az} {dist}: {head:?}");
            let wall = t.to_map(scene.wall.unwrap()[0]);
            assert!(wall.y >= rect.top(), "{az} {dist}");
        }
        let near = RoomScene::new(&RoomConfig::default(), 0.0, 0.2);
        assert_eq!(half_range_m(&near), MIN_HALF_RANGE_M);
    }
}
