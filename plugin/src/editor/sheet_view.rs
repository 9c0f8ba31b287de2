//! # The 3D sheet view
//!
//! Draws the latest simulation mesh with egui's painter: perspective projection from an orbit
//! camera ([`super::projection`]), one flat-shaded colour per triangle ([`super::shading`]) by
//! region kind ([`super::region`]), back faces tinted, triangles sorted back to front (painter's
//! algorithm), the outline of the sheet (the torn lips jagged, as their walks), dots on held (handle) and singular vertices, the floor,
//! table and wall ([`super::room_scene`]) and the listener's head, with a map of the room seen
//! from above in a corner ([`super::room_map`]). Drag to orbit, scroll to zoom, double-click to
//! return to the default view.
//!
//! **Where the mesh comes from.** The simulation (worker thread, or the engine in offline
//! lockstep) copies its mesh into the editor's own triple buffer only while the editor is open
//! ([`crate::engine::view`]). [`SheetView::refresh`] locks the consumer end of that buffer on
//! the GUI thread for as long as it takes to copy the newest frame into the view's own storage
//! (a few microseconds; the producer never takes that lock, so neither the worker nor the audio
//! thread can be blocked by it), then draws from the copy.

use egui::{Align2, Color32, FontId, Mesh, Pos2, Rect, Response, Sense, Shape, Stroke, Ui, pos2};
use sim_core::mesh_snapshot::VertexTag;
use sim_core::room::RoomConfig;

use super::palette::{
    BACKGROUND, FLOOR_COLOUR, LISTENER_COLOUR, OUTLINE_COLOUR, TABLE_COLOUR, WALL_COLOUR,
};
use super::projection::{OrbitCamera, Projector};
use super::region::{
    HANDLE_DOT_COLOUR, RegionClassifier, RegionKind, SINGULAR_DOT_COLOUR, kinds_from_partition,
};
use super::room_map::{self, MAP_SIZE_PX};
use super::room_scene::{HEAD_RADIUS_M, RoomScene};
use super::shading::{face_normal, facing, shade};
use super::vec3::{V3, add, scale};
use crate::engine::{ViewFrame, ViewShared};

/// The view's state: camera, a copy of the newest frame, and scratch storage.
#[derive(Debug)]
pub struct SheetView {
    /// The camera.
    pub camera: OrbitCamera,
    camera_home_z_m: f32,
    frame: ViewFrame,
    regions: Vec<RegionKind>,
    classifier: RegionClassifier,
    order: Vec<(f32, u32)>,
    boundary: Vec<[u32; 2]>,
    boundary_of: Vec<[u32; 3]>,
    /// The lip edges drawn jagged (sorted, smaller vertex first): their straight edge is not.
    lip_edges: Vec<[u32; 2]>,
    screen: Vec<Option<(Pos2, f32)>>,
    clipped: Vec<V3>,
    map_edges: Vec<[V3; 2]>,
    /// Where the last [`SheetView::show`] drew its legend and its top-view inset.
    overlays: Overlays,
}

/// The parts of the view drawn over the scene, in window coordinates (logical pixels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlays {
    /// The colour legend (top left).
    pub legend: Rect,
    /// The room map inset (top right).
    pub map: Rect,
}

impl Default for Overlays {
    fn default() -> Self {
        Self {
            legend: Rect::NOTHING,
            map: Rect::NOTHING,
        }
    }
}

impl Default for SheetView {
    fn default() -> Self {
        let home_z = RoomConfig::default().home_height_m() as f32;
        Self {
            camera: OrbitCamera::looking_at([0.0, 0.0, home_z]),
            camera_home_z_m: home_z,
            frame: ViewFrame::default(),
            regions: Vec::new(),
            classifier: RegionClassifier::default(),
            order: Vec::new(),
            boundary: Vec::new(),
            boundary_of: Vec::new(),
            lip_edges: Vec::new(),
            screen: Vec::new(),
            clipped: Vec::new(),
            map_edges: Vec::new(),
            overlays: Overlays::default(),
        }
    }
}

fn copy_into<T: Copy>(dst: &mut Vec<T>, src: &[T]) {
    dst.clear();
    dst.extend_from_slice(src);
}

impl SheetView {
    /// Takes the newest frame from the editor's triple buffer, if there is a new one. Returns
    /// whether the view changed.
    pub fn refresh(&mut self, shared: &ViewShared) -> bool {
        let Ok(mut slot) = shared.output.lock() else {
            return false;
        };
        let Some(output) = slot.as_mut() else {
            return false;
        };
        if !output.update() {
            return false;
        }
        let src = output.output_buffer();
        if !src.valid {
            return false;
        }
        let dst = &mut self.frame;
        dst.valid = true;
        dst.stats = src.stats;
        dst.room = src.room;
        dst.time_s = src.time_s;
        dst.mesh.frame = src.mesh.frame;
        copy_into(&mut dst.mesh.positions_m, &src.mesh.positions_m);
        copy_into(&mut dst.mesh.pattern_m, &src.mesh.pattern_m);
        copy_into(&mut dst.mesh.tags, &src.mesh.tags);
        copy_into(&mut dst.mesh.triangles, &src.mesh.triangles);
        copy_into(&mut dst.mesh.lip_points_m, &src.mesh.lip_points_m);
        copy_into(&mut dst.mesh.lips, &src.mesh.lips);
        copy_into(&mut dst.tri_kind, &src.tri_kind);
        drop(slot);
        if self.frame.tri_kind.len() == self.frame.mesh.triangles.len() {
            kinds_from_partition(&self.frame.tri_kind, &mut self.regions);
        } else {
            self.classifier
                .classify(&self.frame.mesh, &mut self.regions);
        }
        if self.boundary_of != self.frame.mesh.triangles {
            copy_into(&mut self.boundary_of, &self.frame.mesh.triangles);
            boundary_edges(&self.frame.mesh.triangles, &mut self.boundary);
        }
        self.lip_edges.clear();
        self.lip_edges.extend(
            self.frame
                .mesh
                .lips
                .iter()
                .map(|l| [l.edge[0].min(l.edge[1]), l.edge[0].max(l.edge[1])]),
        );
        self.lip_edges.sort_unstable();
        true
    }

    /// Where the last [`SheetView::show`] drew the legend and the room map over the scene.
    pub fn overlays(&self) -> Overlays {
        self.overlays
    }

    /// The frame on display (`valid` is false until the simulation sent one).
    pub fn frame(&self) -> &ViewFrame {
        &self.frame
    }

    /// Number of triangles of each region kind in the frame on display.
    pub fn region_counts(&self) -> [usize; RegionKind::ALL.len()] {
        let mut n = [0; RegionKind::ALL.len()];
        for r in &self.regions {
            if let Some(i) = RegionKind::ALL.iter().position(|k| k == r) {
                n[i] += 1;
            }
        }
        n
    }

    /// Draws the view into the available space. `room` and the listener are the current
    /// parameter values (the room drawn is the frame's while a frame is there).
    pub fn show(
        &mut self,
        ui: &mut Ui,
        room: RoomConfig,
        listener_az_deg: f32,
        listener_dist_m: f32,
    ) -> Response {
        let size = ui.available_size();
        let (rect, response) = ui.allocate_exact_size(size, Sense::click_and_drag());
        if response.dragged() {
            let d = response.drag_delta();
            self.camera.orbit(d.x, d.y);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.camera.zoom(scroll);
            }
        }
        let room = if self.frame.valid {
            self.frame.room
        } else {
            room
        };
        let home_z = room.sanitized().home_height_m() as f32;
        if response.double_clicked() {
            self.camera = OrbitCamera::looking_at([0.0, 0.0, home_z]);
        }
        // Follow the table height, keeping the user's orbit.
        self.camera.target_m[2] += home_z - self.camera_home_z_m;
        self.camera_home_z_m = home_z;

        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 0.0, BACKGROUND);
        let proj = self
            .camera
            .projector([rect.left(), rect.top(), rect.width(), rect.height()]);
        let eye = self.camera.eye_m();
        let scene = RoomScene::new(&room, listener_az_deg, listener_dist_m);

        for [a, b] in &scene.floor_lines {
            if let Some((p, q)) = proj.clip_segment(*a, *b) {
                let (p, q) = (proj.camera_to_screen(p), proj.camera_to_screen(q));
                painter.line_segment(
                    [pos2(p.x_px, p.y_px), pos2(q.x_px, q.y_px)],
                    Stroke::new(1.0, FLOOR_COLOUR),
                );
            }
        }
        if let Some(table) = &scene.table {
            self.polygon(&painter, &proj, table, TABLE_COLOUR);
        }
        let wall_in_front = scene.wall.is_some() && eye[1] > room.wall_dist_cm * 0.01;
        if let (Some(wall), false) = (&scene.wall, wall_in_front) {
            self.polygon(&painter, &proj, wall, WALL_COLOUR);
        }

        // The listener is drawn before the sheet if it is further away than the sheet's home.
        let home_depth = proj.to_camera([0.0, 0.0, home_z])[2];
        let listener_depth = proj.to_camera(scene.listener.head_m)[2];
        let listener_behind = listener_depth > home_depth;
        if listener_behind {
            draw_listener(&painter, &proj, &scene);
        }
        if self.frame.valid {
            self.draw_sheet(&painter, &proj, eye);
        }
        if !listener_behind {
            draw_listener(&painter, &proj, &scene);
        }
        if let (Some(wall), true) = (&scene.wall, wall_in_front) {
            self.polygon(&painter, &proj, wall, WALL_COLOUR.gamma_multiply(0.6));
        }
        self.overlays.legend = self.draw_overlay(&painter, rect);
        let map = Rect::from_min_size(
            pos2(rect.right() - MAP_SIZE_PX - 8.0, rect.top() + 8.0),
            egui::vec2(MAP_SIZE_PX, MAP_SIZE_PX),
        );
        self.map_edges.clear();
        if self.frame.valid {
            let pos = &self.frame.mesh.positions_m;
            self.map_edges.extend(
                self.boundary
                    .iter()
                    .filter_map(|&[a, b]| Some([*pos.get(a as usize)?, *pos.get(b as usize)?])),
            );
        }
        room_map::draw(&painter, map, &scene, &self.map_edges);
        self.overlays.map = map;
        response
    }

    fn polygon(&mut self, painter: &egui::Painter, proj: &Projector, poly: &[V3], fill: Color32) {
        proj.clip_near(poly, &mut self.clipped);
        if self.clipped.len() < 3 {
            return;
        }
        let points: Vec<Pos2> = self
            .clipped
            .iter()
            .map(|c| {
                let s = proj.camera_to_screen(*c);
                pos2(s.x_px, s.y_px)
            })
            .collect();
        painter.add(Shape::convex_polygon(points, fill, Stroke::NONE));
    }

    fn draw_sheet(&mut self, painter: &egui::Painter, proj: &Projector, eye: V3) {
        let mesh = &self.frame.mesh;
        let pos = &mesh.positions_m;
        self.screen.clear();
        self.screen.extend(
            pos.iter()
                .map(|p| proj.project(*p).map(|s| (pos2(s.x_px, s.y_px), s.depth_m))),
        );
        self.order.clear();
        for (i, t) in mesh.triangles.iter().enumerate() {
            let mut depth = 0.0;
            let mut visible = true;
            for &v in t {
                match self.screen.get(v as usize).copied().flatten() {
                    Some((_, d)) => depth += d,
                    None => visible = false,
                }
            }
            if visible {
                self.order.push((depth, i as u32));
            }
        }
        // Far to near.
        self.order.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));

        let mut m = Mesh::default();
        m.reserve_triangles(self.order.len());
        m.reserve_vertices(3 * self.order.len());
        for &(_, ti) in &self.order {
            let t = mesh.triangles[ti as usize];
            let [a, b, c] = t.map(|v| pos[v as usize]);
            let Some(n) = face_normal(a, b, c) else {
                continue;
            };
            let centroid = scale(add(add(a, b), c), 1.0 / 3.0);
            let kind = self
                .regions
                .get(ti as usize)
                .copied()
                .unwrap_or(RegionKind::Flat);
            let [r, g, bl] = shade(kind.colour(), n, facing(n, centroid, eye));
            let colour = Color32::from_rgb(r, g, bl);
            let base = m.vertices.len() as u32;
            for v in t {
                if let Some((p, _)) = self.screen[v as usize] {
                    m.colored_vertex(p, colour);
                }
            }
            m.add_triangle(base, base + 1, base + 2);
        }
        painter.add(Shape::mesh(m));

        for [a, b] in &self.boundary {
            if self.lip_edges.binary_search(&[*a, *b]).is_ok() {
                continue;
            }
            if let (Some((p, _)), Some((q, _))) = (
                self.screen.get(*a as usize).copied().flatten(),
                self.screen.get(*b as usize).copied().flatten(),
            ) {
                painter.line_segment([p, q], Stroke::new(1.0, OUTLINE_COLOUR));
            }
        }
        // The torn lips, jagged (the walk of each lip edge, sim-core tearing/lips.rs).
        for l in &mesh.lips {
            let pts = mesh
                .lip_points_m
                .get(l.start as usize..(l.start + l.len) as usize)
                .unwrap_or(&[]);
            for w in pts.windows(2) {
                if let (Some(p), Some(q)) = (proj.project(w[0]), proj.project(w[1])) {
                    painter.line_segment(
                        [pos2(p.x_px, p.y_px), pos2(q.x_px, q.y_px)],
                        Stroke::new(1.0, OUTLINE_COLOUR),
                    );
                }
            }
        }
        for (v, tag) in mesh.tags.iter().enumerate() {
            let colour = match tag {
                VertexTag::Plain => continue,
                VertexTag::Handle => HANDLE_DOT_COLOUR,
                VertexTag::Singular => SINGULAR_DOT_COLOUR,
            };
            if let Some((p, _)) = self.screen.get(v).copied().flatten() {
                let [r, g, b] = colour;
                painter.circle_filled(p, 3.5, Color32::from_rgb(r, g, b));
                painter.circle_stroke(p, 3.5, Stroke::new(1.0, Color32::from_gray(20)));
            }
        }
    }

    /// Draws the legend and the status lines; returns the legend's rectangle.
    fn draw_overlay(&self, painter: &egui::Painter, rect: Rect) -> Rect {
        let font = FontId::proportional(12.0);
        let text = Color32::from_gray(200);
        let mut y = rect.top() + 8.0;
        let mut legend = Rect::from_min_size(pos2(rect.left() + 8.0, y), egui::Vec2::ZERO);
        for kind in RegionKind::ALL {
            let sw = Rect::from_min_size(pos2(rect.left() + 8.0, y + 2.0), egui::vec2(10.0, 10.0));
            let [r, g, b] = kind.colour();
            painter.rect_filled(sw, 2.0, Color32::from_rgb(r, g, b));
            legend = legend.union(sw);
            legend = legend.union(painter.text(
                pos2(rect.left() + 24.0, y),
                Align2::LEFT_TOP,
                kind.label(),
                font.clone(),
                text,
            ));
            y += 16.0;
        }
        for (colour, label) in [
            (HANDLE_DOT_COLOUR, "held"),
            (SINGULAR_DOT_COLOUR, "singular vertex"),
        ] {
            let [r, g, b] = colour;
            painter.circle_filled(
                pos2(rect.left() + 13.0, y + 7.0),
                4.0,
                Color32::from_rgb(r, g, b),
            );
            legend = legend.union(painter.text(
                pos2(rect.left() + 24.0, y),
                Align2::LEFT_TOP,
                label,
                font.clone(),
                text,
            ));
            y += 16.0;
        }
        let status = if self.frame.valid {
            let s = &self.frame.stats;
            format!(
                "t = {:.2} s · {} vertices · {} triangles{}",
                self.frame.time_s,
                s.num_vertices,
                s.num_triangles,
                if s.asleep { " · at rest" } else { "" }
            )
        } else {
            "waiting for the simulation (it runs while the plugin is active)".to_owned()
        };
        painter.text(
            pos2(rect.left() + 8.0, rect.bottom() - 8.0),
            Align2::LEFT_BOTTOM,
            status,
            font.clone(),
            text,
        );
        painter.text(
            pos2(rect.right() - 8.0, rect.bottom() - 8.0),
            Align2::RIGHT_BOTTOM,
            "drag: orbit · scroll: zoom · double-click: reset view",
            font,
            Color32::from_gray(150),
        );
        legend
    }
}

fn draw_listener(painter: &egui::Painter, proj: &Projector, scene: &RoomScene) {
    let l = &scene.listener;
    let Some(head) = proj.project(l.head_m) else {
        return;
    };
    let r = (HEAD_RADIUS_M * proj.px_per_m_at(head.depth_m)).clamp(3.0, 80.0);
    let c = pos2(head.x_px, head.y_px);
    if let Some(nose) = proj.project(l.nose_m) {
        painter.line_segment(
            [c, pos2(nose.x_px, nose.y_px)],
            Stroke::new((r * 0.25).clamp(1.5, 6.0), LISTENER_COLOUR),
        );
    }
    for ear in [l.left_ear_m, l.right_ear_m] {
        if let Some(e) = proj.project(ear) {
            painter.circle_filled(pos2(e.x_px, e.y_px), (r * 0.3).max(2.0), LISTENER_COLOUR);
        }
    }
    painter.circle_filled(c, r, LISTENER_COLOUR.gamma_multiply(0.55));
    painter.circle_stroke(c, r, Stroke::new(1.5, LISTENER_COLOUR));
    // Where the listener stands (a dot on the floor below the head).
    if let Some(f) = proj.project([l.head_m[0], l.head_m[1], 0.0]) {
        painter.circle_filled(
            pos2(f.x_px, f.y_px),
            2.5,
            LISTENER_COLOUR.gamma_multiply(0.6),
        );
    }
    painter.text(
        pos2(c.x, c.y - r - 4.0),
        Align2::CENTER_BOTTOM,
        "listener",
        FontId::proportional(12.0),
        LISTENER_COLOUR,
    );
}

/// The edges used by exactly one triangle (the sheet's outline, and the lips of tears).
pub fn boundary_edges(triangles: &[[u32; 3]], out: &mut Vec<[u32; 2]>) {
    out.clear();
    let mut edges: Vec<[u32; 2]> = triangles
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .map(|[a, b]| if a < b { [a, b] } else { [b, a] })
        .collect();
    edges.sort_unstable();
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j] == edges[i] {
            j += 1;
        }
        if j - i == 1 {
            out.push(edges[i]);
        }
        i = j;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boundary_of_a_square_of_two_triangles() {
        let mut out = Vec::new();
        boundary_edges(&[[0, 1, 2], [0, 2, 3]], &mut out);
        out.sort_unstable();
        assert_eq!(out, vec![[0, 1], [0, 3], [1, 2], [2, 3]]);
    }

    #[test]
    fn a_closed_surface_has_no_boundary() {
        // A tetrahedron.
        let mut out = Vec::new();
        boundary_edges(&[[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]], &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn refresh_copies_the_newest_frame_and_classifies_it() {
        use sim_core::{Sim, SimConfig};
        let shared = ViewShared::default();
        let mut view = SheetView::default();
        assert!(!view.refresh(&shared), "no buffer installed yet");
        let mut publisher = crate::engine::view::ViewPublisher::install(&shared);
        assert!(!view.refresh(&shared), "nothing published yet");
        let mut sim = Sim::new(SimConfig::default());
        let mut out = sim_core::FrameOutput::default();
        sim.step(&mut out);
        // Closed editor: nothing is copied.
        publisher.after_frame(&shared, &sim, &out.stats);
        assert!(!view.refresh(&shared));
        shared
            .open
            .store(true, std::sync::atomic::Ordering::Relaxed);
        publisher.after_frame(&shared, &sim, &out.stats);
        assert!(view.refresh(&shared));
        let f = view.frame();
        assert!(f.valid);
        assert_eq!(f.mesh.positions_m.len(), out.stats.num_vertices as usize);
        assert_eq!(f.mesh.triangles.len(), out.stats.num_triangles as usize);
        // A fresh flat sheet is all flat, and its outline is a closed loop (as many edges as
        // boundary vertices).
        let counts = view.region_counts();
        assert_eq!(counts[0], f.mesh.triangles.len(), "{counts:?}");
        assert!(!view.boundary.is_empty());
        let mut verts: Vec<u32> = view.boundary.iter().flatten().copied().collect();
        verts.sort_unstable();
        verts.dedup();
        assert_eq!(verts.len(), view.boundary.len());
        // No new frame: nothing to do.
        assert!(!view.refresh(&shared));
    }

    /// A view with its buffer installed and the editor open.
    fn open_view() -> (ViewShared, SheetView, crate::engine::view::ViewPublisher) {
        let shared = ViewShared::default();
        let publisher = crate::engine::view::ViewPublisher::install(&shared);
        shared
            .open
            .store(true, std::sync::atomic::Ordering::Relaxed);
        (shared, SheetView::default(), publisher)
    }

    #[test]
    fn a_crumpled_sheet_shows_the_simulations_partition() {
        use sim_core::geometry::TriKind;
        use sim_core::{Command, GestureParam, GrabSlot, Sim, SimConfig};
        let (shared, mut view, mut publisher) = open_view();
        let mut sim = Sim::new(SimConfig::default());
        let mut out = sim_core::FrameOutput::default();
        sim.apply(Command::Grab {
            slot: GrabSlot::Corners,
            grip: 1.0,
        });
        sim.apply(Command::Gesture {
            param: GestureParam::Crumple,
            value: 0.6,
        });
        for _ in 0..200 {
            sim.step(&mut out);
        }
        let partition = sim.geometry().tri_kind.clone();
        let curved = partition.iter().filter(|&&k| k != TriKind::Flat).count();
        assert!(curved > 0, "the crumple should bend part of the sheet");
        publisher.after_frame(&shared, &sim, &out.stats);
        assert!(view.refresh(&shared));
        let count = |k| partition.iter().filter(|&&x| x == k).count();
        assert_eq!(
            view.region_counts(),
            [
                count(TriKind::Flat),
                count(TriKind::Curved),
                count(TriKind::SingularFan)
            ]
        );
    }

    #[test]
    fn a_torn_sheet_shows_its_lips_jagged_in_place_of_their_straight_edges() {
        use sim_core::{Command, GestureParam, SheetSize, Sim, SimConfig};
        let (shared, mut view, mut publisher) = open_view();
        let mut sim = Sim::new(SimConfig {
            size: SheetSize::A6,
            ..SimConfig::default()
        });
        let mut out = sim_core::FrameOutput::default();
        // Settle on the table first.
        for _ in 0..100 {
            sim.step(&mut out);
        }
        for k in 1..=120 {
            sim.apply(Command::Gesture {
                param: GestureParam::TearAmount,
                value: (k as f32 / 100.0).min(1.0),
            });
            sim.step(&mut out);
        }
        assert!(
            sim.tear().path_length_m > 0.05,
            "{:?}",
            sim.tear().path_length_m
        );
        publisher.after_frame(&shared, &sim, &out.stats);
        assert!(view.refresh(&shared));
        let mesh = &view.frame().mesh;
        assert_eq!(mesh.lips.len(), sim.lips().runs().len());
        assert!(!view.lip_edges.is_empty());
        // Every lip edge is a boundary edge (drawn as its walk, not straight); the rest of the
        // boundary is the outer rectangle.
        for e in &view.lip_edges {
            assert!(view.boundary.binary_search(e).is_ok(), "{e:?}");
        }
        assert!(view.boundary.len() > view.lip_edges.len());
        let jag = mesh.lips.iter().map(|l| l.len).sum::<u32>() as usize;
        assert_eq!(jag, mesh.lip_points_m.len());
        assert!(jag > 4 * mesh.lips.len());
    }
}
