//! # Flat shading of the sheet
//!
//! Each triangle gets one colour: its region colour ([`super::region`]) scaled by a Lambert
//! term from a fixed light, two-sided. The face the eye sees is the front (the side the
//! triangle's counter-clockwise normal points to, which is up for a sheet lying on the table)
//! or the back; back faces are tinted so the reverse of the paper reads as such.
//!
//! ```text
//!   n = (b − a) × (c − a) / |…|            facing = front if n·(eye − centroid) > 0
//!   n_v = n (front) or −n (back)           k = AMBIENT + (1 − AMBIENT)·max(0, n_v·L)
//!   colour = k · (base, or base blended towards BACK_TINT for a back face)
//! ```

use super::vec3::{V3, cross, dot, normalized, sub};

/// Direction towards the light (world): above, slightly in front and to the left.
pub const LIGHT_DIR: V3 = [-0.339_683, -0.509_525, 0.790_569];
/// Light that every face gets, whatever its orientation (0–1).
pub const AMBIENT: f32 = 0.38;
/// Colour the back side of the paper is blended towards.
pub const BACK_TINT: [u8; 3] = [120, 150, 205];
/// How much of [`BACK_TINT`] a back face takes (0–1).
pub const BACK_TINT_AMOUNT: f32 = 0.45;

/// Which side of a triangle the eye sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Facing {
    /// The side the counter-clockwise normal points to (the top of a sheet on the table).
    Front,
    /// The reverse.
    Back,
}

/// Unit normal of triangle `(a, b, c)` (right-handed, counter-clockwise), `None` if degenerate.
pub fn face_normal(a: V3, b: V3, c: V3) -> Option<V3> {
    normalized(cross(sub(b, a), sub(c, a)))
}

/// Which side of a face with normal `normal` through `point` an eye at `eye` sees.
pub fn facing(normal: V3, point: V3, eye: V3) -> Facing {
    if dot(normal, sub(eye, point)) >= 0.0 {
        Facing::Front
    } else {
        Facing::Back
    }
}

/// Brightness (AMBIENT–1) of a face whose normal, turned towards the viewer, is `n_view`.
pub fn brightness(n_view: V3) -> f32 {
    AMBIENT + (1.0 - AMBIENT) * dot(n_view, LIGHT_DIR).max(0.0)
}

/// The shaded colour of a face: `base` (tinted for a back face) times its brightness.
pub fn shade(base: [u8; 3], normal: V3, facing_side: Facing) -> [u8; 3] {
    let (n_view, rgb) = match facing_side {
        Facing::Front => (normal, base),
        Facing::Back => (
            [-normal[0], -normal[1], -normal[2]],
            blend(base, BACK_TINT, BACK_TINT_AMOUNT),
        ),
    };
    let k = brightness(n_view);
    rgb.map(|c| (f32::from(c) * k).round().clamp(0.0, 255.0) as u8)
}

/// `(1 − t)·a + t·b`, per channel.
pub fn blend(a: [u8; 3], b: [u8; 3], t: f32) -> [u8; 3] {
    let t = t.clamp(0.0, 1.0);
    [0, 1, 2].map(|i| (f32::from(a[i]) * (1.0 - t) + f32::from(b[i]) * t).round() as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_direction_is_a_unit_vector_from_above() {
        let l = LIGHT_DIR;
        assert!((dot(l, l) - 1.0).abs() < 1e-5);
        assert!(l[2] > 0.5);
    }

    #[test]
    fn ccw_triangle_on_the_table_faces_up() {
        let n = face_normal([0.0, 0.0, 0.75], [0.1, 0.0, 0.75], [0.0, 0.1, 0.75]).unwrap();
        assert!((n[2] - 1.0).abs() < 1e-6);
        assert_eq!(facing(n, [0.0, 0.0, 0.75], [0.3, -0.5, 1.2]), Facing::Front);
        assert_eq!(facing(n, [0.0, 0.0, 0.75], [0.3, -0.5, 0.2]), Facing::Back);
        assert_eq!(
            face_normal([0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]),
            None
        );
    }

    #[test]
    fn brightness_follows_the_light_and_never_drops_below_ambient() {
        assert!((brightness(LIGHT_DIR) - 1.0).abs() < 1e-5);
        let away = LIGHT_DIR.map(|v| -v);
        assert_eq!(brightness(away), AMBIENT);
        let up = brightness([0.0, 0.0, 1.0]);
        let side = brightness([1.0, 0.0, 0.0]);
        assert!(up > side, "a face turned to the light is brighter");
    }

    #[test]
    fn back_faces_are_tinted_and_front_faces_keep_their_hue() {
        let base = [240, 236, 224];
        let up = [0.0, 0.0, 1.0];
        let front = shade(base, up, Facing::Front);
        // Same hue: channels scale together.
        let k = f32::from(front[0]) / 240.0;
        assert!((f32::from(front[2]) / 224.0 - k).abs() < 0.01);
        // Seen from below, the same face shows its (tinted) back.
        let back = shade(base, [0.0, 0.0, -1.0], Facing::Back);
        let back_ratio = f32::from(back[2]) / f32::from(back[0]);
        assert!(back_ratio > 224.0 / 240.0 + 0.05, "back is bluer: {back:?}");
    }

    #[test]
    fn blend_endpoints() {
        assert_eq!(blend([0, 100, 200], [200, 100, 0], 0.0), [0, 100, 200]);
        assert_eq!(blend([0, 100, 200], [200, 100, 0], 1.0), [200, 100, 0]);
        assert_eq!(blend([0, 100, 200], [200, 100, 0], 0.5), [100, 100, 100]);
    }
}
