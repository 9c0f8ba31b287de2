//! # Orbit camera and perspective projection
//!
//! The sheet view looks at the sheet from an orbiting camera. World frame (sim-core's room
//! frame, metres): x right, y away from a listener at azimuth 0, z up.
//!
//! ```text
//!            z                    eye = target + d·(cos φ·sin θ, −cos φ·cos θ, sin φ)
//!            │   eye                θ = yaw (same convention as the listener azimuth:
//!            │  ╱                      0 = in front of the front edge, +90° = to the right)
//!            │ ╱ d                  φ = pitch above the table plane
//!   target ──●───── x
//!           ╱
//!          y (away)
//! ```
//!
//! Camera basis: forward `f = (target − eye)/|…|`, right `r = f × z/|…|`, up `u = r × f`. A
//! point `p` has camera coordinates `(x, y, z) = ((p−eye)·r, (p−eye)·u, (p−eye)·f)`, `z` being
//! its depth, and lands on the screen at
//!
//! ```text
//!   sx = cx + F·x/z,   sy = cy − F·y/z,   F = ½·min(width, height) / tan(fov/2)
//! ```
//!
//! (screen y grows downwards). Points closer than [`NEAR_M`] are not projected; polygons are
//! clipped against that plane first ([`Projector::clip_near`]).

use super::vec3::{V3, add, cross, dot, normalized, scale, sub};

/// Near clipping distance, metres.
pub const NEAR_M: f32 = 0.02;
/// Pitch limits, radians: the camera stays above the table plane and never looks straight
/// down (where the right vector would be undefined).
pub const PITCH_RANGE_RAD: (f32, f32) = (0.035, 1.50);
/// Distance limits from the target, metres.
pub const DISTANCE_RANGE_M: (f32, f32) = (0.15, 6.0);
/// Orbit speed, radians per logical pixel dragged.
pub const ORBIT_RAD_PER_PX: f32 = 0.008;
/// Zoom speed: the distance is divided by `exp(ZOOM_PER_PX · scroll)` (scroll in points).
pub const ZOOM_PER_PX: f32 = 0.0025;

/// An orbiting camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at, world metres.
    pub target_m: V3,
    /// Azimuth of the eye around the target, radians (0 = in front, on the −y side).
    pub yaw_rad: f32,
    /// Elevation of the eye above the horizontal through the target, radians.
    pub pitch_rad: f32,
    /// Eye–target distance, metres.
    pub distance_m: f32,
    /// Vertical (or, in a tall viewport, horizontal) field of view, radians.
    pub fov_rad: f32,
}

impl OrbitCamera {
    /// The default view of a sheet whose home centre is `home_m`: from the front right, above.
    pub fn looking_at(home_m: V3) -> Self {
        Self {
            target_m: add(home_m, [0.0, 0.03, 0.04]),
            yaw_rad: 35f32.to_radians(),
            pitch_rad: 38f32.to_radians(),
            distance_m: 0.95,
            fov_rad: 40f32.to_radians(),
        }
    }

    /// Eye position, world metres.
    pub fn eye_m(&self) -> V3 {
        let (sy, cy) = self.yaw_rad.sin_cos();
        let (sp, cp) = self.pitch_rad.sin_cos();
        add(
            self.target_m,
            scale([cp * sy, -cp * cy, sp], self.distance_m),
        )
    }

    /// Orbits by a mouse drag (logical pixels): dragging right turns the scene to the right,
    /// dragging down tilts it towards the viewer (the eye rises).
    pub fn orbit(&mut self, dx_px: f32, dy_px: f32) {
        if !(dx_px.is_finite() && dy_px.is_finite()) {
            return;
        }
        self.yaw_rad = wrap_pi(self.yaw_rad - dx_px * ORBIT_RAD_PER_PX);
        self.pitch_rad =
            (self.pitch_rad + dy_px * ORBIT_RAD_PER_PX).clamp(PITCH_RANGE_RAD.0, PITCH_RANGE_RAD.1);
    }

    /// Zooms by a scroll amount (points; positive = scroll up = closer).
    pub fn zoom(&mut self, scroll_px: f32) {
        if !scroll_px.is_finite() {
            return;
        }
        self.distance_m = (self.distance_m * (-ZOOM_PER_PX * scroll_px).exp())
            .clamp(DISTANCE_RANGE_M.0, DISTANCE_RANGE_M.1);
    }

    /// The projector for a viewport (logical pixels: left, top, width, height).
    pub fn projector(&self, viewport_px: [f32; 4]) -> Projector {
        let eye = self.eye_m();
        let forward = normalized(sub(self.target_m, eye)).unwrap_or([0.0, 1.0, 0.0]);
        let right = normalized(cross(forward, [0.0, 0.0, 1.0])).unwrap_or([1.0, 0.0, 0.0]);
        let up = cross(right, forward);
        let [left, top, w, h] = viewport_px;
        let half = 0.5 * w.min(h).max(1.0);
        Projector {
            eye_m: eye,
            right,
            up,
            forward,
            focal_px: half / (0.5 * self.fov_rad).tan(),
            centre_px: [left + 0.5 * w, top + 0.5 * h],
        }
    }
}

fn wrap_pi(a: f32) -> f32 {
    let tau = std::f32::consts::TAU;
    let w = (a + std::f32::consts::PI).rem_euclid(tau) - std::f32::consts::PI;
    if w.is_finite() { w } else { 0.0 }
}

/// A point on the screen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projected {
    /// Screen x, logical pixels.
    pub x_px: f32,
    /// Screen y, logical pixels (down).
    pub y_px: f32,
    /// Depth along the view direction, metres.
    pub depth_m: f32,
}

/// World → screen for one camera pose and viewport.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projector {
    /// Eye position, world metres.
    pub eye_m: V3,
    /// Camera right, world.
    pub right: V3,
    /// Camera up, world.
    pub up: V3,
    /// Camera forward (view direction), world.
    pub forward: V3,
    /// Focal length, logical pixels.
    pub focal_px: f32,
    /// Viewport centre, logical pixels.
    pub centre_px: [f32; 2],
}

impl Projector {
    /// Camera coordinates (right, up, depth) of a world point, metres.
    pub fn to_camera(&self, p_m: V3) -> V3 {
        let d = sub(p_m, self.eye_m);
        [dot(d, self.right), dot(d, self.up), dot(d, self.forward)]
    }

    /// Screen position of a point in camera coordinates (depth must be ≥ [`NEAR_M`]).
    pub fn camera_to_screen(&self, c: V3) -> Projected {
        let inv = 1.0 / c[2].max(NEAR_M);
        Projected {
            x_px: self.centre_px[0] + self.focal_px * c[0] * inv,
            y_px: self.centre_px[1] - self.focal_px * c[1] * inv,
            depth_m: c[2],
        }
    }

    /// Screen position of a world point, or `None` if it is behind the near plane.
    pub fn project(&self, p_m: V3) -> Option<Projected> {
        let c = self.to_camera(p_m);
        (c[2] >= NEAR_M && c.iter().all(|v| v.is_finite())).then(|| self.camera_to_screen(c))
    }

    /// Pixels per metre for something at `depth_m` (sizes of markers).
    pub fn px_per_m_at(&self, depth_m: f32) -> f32 {
        self.focal_px / depth_m.max(NEAR_M)
    }

    /// Clips a world segment against the near plane; camera coordinates of what is left.
    pub fn clip_segment(&self, a_m: V3, b_m: V3) -> Option<(V3, V3)> {
        let a = self.to_camera(a_m);
        let b = self.to_camera(b_m);
        match (a[2] >= NEAR_M, b[2] >= NEAR_M) {
            (true, true) => Some((a, b)),
            (false, false) => None,
            (a_in, _) => {
                let t = (NEAR_M - a[2]) / (b[2] - a[2]);
                let m = add(a, scale(sub(b, a), t));
                Some(if a_in { (a, m) } else { (m, b) })
            }
        }
    }

    /// Clips a convex world polygon against the near plane (Sutherland–Hodgman) and returns its
    /// vertices in camera coordinates, appended to `out` (cleared first). Empty if it lies
    /// entirely behind the plane.
    pub fn clip_near(&self, polygon_m: &[V3], out: &mut Vec<V3>) {
        out.clear();
        let n = polygon_m.len();
        for i in 0..n {
            let a = self.to_camera(polygon_m[i]);
            let b = self.to_camera(polygon_m[(i + 1) % n]);
            let a_in = a[2] >= NEAR_M;
            let b_in = b[2] >= NEAR_M;
            if a_in {
                out.push(a);
            }
            if a_in != b_in {
                let t = (NEAR_M - a[2]) / (b[2] - a[2]);
                out.push(add(a, scale(sub(b, a), t)));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam() -> OrbitCamera {
        OrbitCamera {
            target_m: [0.0, 0.0, 0.75],
            yaw_rad: 0.0,
            pitch_rad: 0.3,
            distance_m: 1.0,
            fov_rad: 40f32.to_radians(),
        }
    }

    const VIEWPORT: [f32; 4] = [10.0, 20.0, 400.0, 300.0];

    #[test]
    fn eye_is_in_front_at_zero_yaw_and_on_the_right_at_90() {
        let mut c = cam();
        let e = c.eye_m();
        assert!(e[0].abs() < 1e-6 && e[1] < 0.0 && e[2] > 0.75);
        c.yaw_rad = std::f32::consts::FRAC_PI_2;
        let e = c.eye_m();
        assert!(e[0] > 0.9 && e[1].abs() < 1e-6);
        // The eye is exactly `distance` from the target.
        let d = super::super::vec3::length(sub(e, c.target_m));
        assert!((d - 1.0).abs() < 1e-5);
    }

    #[test]
    fn target_lands_in_the_viewport_centre() {
        let p = cam().projector(VIEWPORT);
        let s = p.project([0.0, 0.0, 0.75]).unwrap();
        assert!((s.x_px - 210.0).abs() < 1e-3 && (s.y_px - 170.0).abs() < 1e-3);
        assert!((s.depth_m - 1.0).abs() < 1e-5);
    }

    #[test]
    fn screen_axes_follow_the_world_from_the_front() {
        let p = cam().projector(VIEWPORT);
        let c = p.project([0.0, 0.0, 0.75]).unwrap();
        let right = p.project([0.1, 0.0, 0.75]).unwrap();
        let up = p.project([0.0, 0.0, 0.85]).unwrap();
        let away = p.project([0.0, 0.1, 0.75]).unwrap();
        assert!(right.x_px > c.x_px + 10.0, "+x is to the right");
        assert!(up.y_px < c.y_px - 10.0, "+z is up on the screen");
        assert!(away.y_px < c.y_px, "seen from above, +y recedes upwards");
        assert!(away.depth_m > c.depth_m, "+y is further away");
    }

    #[test]
    fn perspective_shrinks_with_depth() {
        let p = cam().projector(VIEWPORT);
        let near = p.project([0.1, -0.3, 0.75]).unwrap();
        let near0 = p.project([0.0, -0.3, 0.75]).unwrap();
        let far = p.project([0.1, 0.3, 0.75]).unwrap();
        let far0 = p.project([0.0, 0.3, 0.75]).unwrap();
        assert!((near.x_px - near0.x_px) > (far.x_px - far0.x_px) * 1.2);
        // The size at a depth matches the pixels-per-metre helper.
        let w = near.x_px - near0.x_px;
        assert!((w - 0.1 * p.px_per_m_at(near.depth_m)).abs() < 0.01 * w);
    }

    #[test]
    fn points_behind_the_eye_are_not_projected() {
        let c = cam();
        let p = c.projector(VIEWPORT);
        let behind = add(c.eye_m(), scale(p.forward, -0.5));
        assert_eq!(p.project(behind), None);
    }

    #[test]
    fn near_clipping_cuts_a_polygon_crossing_the_eye_plane() {
        let c = cam();
        let p = c.projector(VIEWPORT);
        let e = c.eye_m();
        // A quad in the plane through the eye spanned by forward and right: half behind.
        let f = p.forward;
        let r = p.right;
        let quad = [
            add(e, add(scale(f, -1.0), scale(r, -1.0))),
            add(e, add(scale(f, 1.0), scale(r, -1.0))),
            add(e, add(scale(f, 1.0), scale(r, 1.0))),
            add(e, add(scale(f, -1.0), scale(r, 1.0))),
        ];
        let mut out = Vec::new();
        p.clip_near(&quad, &mut out);
        assert_eq!(out.len(), 4);
        assert!(out.iter().all(|v| v[2] >= NEAR_M - 1e-5));
        // Entirely behind: nothing left.
        let behind: Vec<V3> = quad.iter().map(|q| add(*q, scale(f, -3.0))).collect();
        p.clip_near(&behind, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn segments_are_cut_at_the_near_plane() {
        let c = cam();
        let p = c.projector(VIEWPORT);
        let e = c.eye_m();
        let ahead = add(e, scale(p.forward, 1.0));
        let behind = add(e, scale(p.forward, -1.0));
        let (a, b) = p.clip_segment(behind, ahead).unwrap();
        assert!((a[2] - NEAR_M).abs() < 1e-5 && (b[2] - 1.0).abs() < 1e-5);
        let (a, b) = p.clip_segment(ahead, behind).unwrap();
        assert!((a[2] - 1.0).abs() < 1e-5 && (b[2] - NEAR_M).abs() < 1e-5);
        assert_eq!(p.clip_segment(behind, add(behind, [0.1, 0.0, 0.0])), None);
    }

    #[test]
    fn orbit_and_zoom_stay_in_range() {
        let mut c = cam();
        c.orbit(0.0, 1e6);
        assert_eq!(c.pitch_rad, PITCH_RANGE_RAD.1);
        c.orbit(0.0, -1e6);
        assert_eq!(c.pitch_rad, PITCH_RANGE_RAD.0);
        c.orbit(1e5, 0.0);
        assert!(c.yaw_rad.abs() <= std::f32::consts::PI + 1e-4);
        c.zoom(1e6);
        assert_eq!(c.distance_m, DISTANCE_RANGE_M.0);
        c.zoom(-1e6);
        assert_eq!(c.distance_m, DISTANCE_RANGE_M.1);
        let before = c;
        c.orbit(f32::NAN, 1.0);
        c.zoom(f32::INFINITY);
        assert_eq!(c, before, "non-finite input is ignored");
        // Scrolling up brings the camera closer.
        let mut c = cam();
        c.zoom(100.0);
        assert!(c.distance_m < 1.0);
    }
}
