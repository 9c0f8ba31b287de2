//! # The 2D pattern S̄ and its initial triangulation
//!
//! The seeds sample flat regions "uniformly and isotropically" and connect the samples by a
//! Delaunay triangulation (P 459–481, T 734–742; digest-crumpling §2.2). For the initial, flat,
//! undamaged sheet this module builds the same kind of mesh directly: a triangular lattice of
//! nearly equilateral triangles over the rectangle `[−W/2, W/2] × [−L/2, L/2]` (origin at the
//! sheet centre, x across the width, y along the length), with the boundary sampled exactly on
//! the rectangle and the four corners present. Odd rows are offset by half a spacing, so no
//! preferred fold direction is built in (a regular right-triangle grid would favour folds
//! along its diagonals).
//!
//! Two neighbouring rows are "zipped" together: walking both rows left to right, each step adds
//! the triangle whose new diagonal is shorter, which is the Delaunay choice for two rows of
//! points. Triangles are counter-clockwise in the pattern.
//!
//! Density: the target edge length is `spacing_frac × L_paper` (L_paper = the longer side,
//! digest §4.1). The seeds' densities ρ_bound = 1.2/cm and ρ_int = 6/cm² give far more
//! triangles than their measured 87–156 (digest §9 item 2), so density is a knob
//! ([`crate::sheet::MeshConfig`]) calibrated on triangle counts instead.

use crate::math::V2;

/// The pattern of a flat sheet: vertex positions and counter-clockwise triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct Pattern {
    /// Pattern positions, metres, origin at the sheet centre.
    pub points: Vec<V2>,
    /// Triangles, counter-clockwise in the pattern.
    pub triangles: Vec<[u32; 3]>,
}

/// Builds the lattice pattern of a `width_m × length_m` sheet with target edge `spacing_m`.
///
/// # Panics
/// Panics if a dimension or the spacing is not finite and positive.
pub fn lattice(width_m: f64, length_m: f64, spacing_m: f64) -> Pattern {
    assert!(width_m.is_finite() && width_m > 0.0);
    assert!(length_m.is_finite() && length_m > 0.0);
    assert!(spacing_m.is_finite() && spacing_m > 0.0);
    let row_h = spacing_m * 3f64.sqrt() * 0.5;
    let n_rows = ((length_m / row_h).round() as usize).max(1);
    let n_cols = ((width_m / spacing_m).round() as usize).max(1);
    let dx = width_m / n_cols as f64;
    let (x0, y0) = (-0.5 * width_m, -0.5 * length_m);

    let mut points = Vec::new();
    let mut rows: Vec<(usize, usize)> = Vec::with_capacity(n_rows + 1); // (first index, count)
    for j in 0..=n_rows {
        let y = if j == n_rows {
            0.5 * length_m
        } else {
            y0 + length_m * j as f64 / n_rows as f64
        };
        let first = points.len();
        if j % 2 == 0 {
            for i in 0..=n_cols {
                let x = if i == n_cols {
                    0.5 * width_m
                } else {
                    x0 + dx * i as f64
                };
                points.push(V2::new(x, y));
            }
        } else {
            points.push(V2::new(x0, y));
            for i in 0..n_cols {
                points.push(V2::new(x0 + dx * (i as f64 + 0.5), y));
            }
            points.push(V2::new(0.5 * width_m, y));
        }
        rows.push((first, points.len() - first));
    }

    let mut triangles = Vec::new();
    for j in 0..n_rows {
        let (a0, na) = rows[j];
        let (b0, nb) = rows[j + 1];
        let (mut i, mut k) = (0usize, 0usize);
        while i + 1 < na || k + 1 < nb {
            let advance_a = if i + 1 >= na {
                false
            } else if k + 1 >= nb {
                true
            } else {
                // Shorter new diagonal wins (Delaunay between two rows); ties go to row A.
                let da = (points[a0 + i + 1] - points[b0 + k]).norm_squared();
                let db = (points[b0 + k + 1] - points[a0 + i]).norm_squared();
                da <= db * (1.0 + 1e-12)
            };
            let (ai, bk) = ((a0 + i) as u32, (b0 + k) as u32);
            if advance_a {
                triangles.push([ai, ai + 1, bk]);
                i += 1;
            } else {
                triangles.push([ai, bk + 1, bk]);
                k += 1;
            }
        }
    }
    Pattern { points, triangles }
}

/// Signed area of a pattern triangle (positive when counter-clockwise), m².
pub fn signed_area(a: V2, b: V2, c: V2) -> f64 {
    0.5 * ((b - a).perp(&(c - a)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_covers_the_rectangle_with_ccw_triangles() {
        for &(w, l, s) in &[
            (0.21, 0.297, 0.033),
            (0.1, 0.1, 0.011),
            (0.105, 0.148, 0.02),
        ] {
            let p = lattice(w, l, s);
            let mut area = 0.0;
            for t in &p.triangles {
                let a = signed_area(
                    p.points[t[0] as usize],
                    p.points[t[1] as usize],
                    p.points[t[2] as usize],
                );
                assert!(a > 0.0, "triangle {t:?} not ccw");
                area += a;
            }
            assert!((area - w * l).abs() < 1e-12, "area {area} vs {}", w * l);
            // The four corners are vertices.
            for c in [
                V2::new(-w / 2.0, -l / 2.0),
                V2::new(w / 2.0, -l / 2.0),
                V2::new(-w / 2.0, l / 2.0),
                V2::new(w / 2.0, l / 2.0),
            ] {
                assert!(p.points.iter().any(|q| (q - c).norm() < 1e-12));
            }
        }
    }

    #[test]
    fn triangles_are_well_shaped() {
        let p = lattice(0.21, 0.297, 0.033);
        for t in &p.triangles {
            let [a, b, c] = t.map(|i| p.points[i as usize]);
            let e = [(b - a).norm(), (c - b).norm(), (a - c).norm()];
            let longest = e.iter().cloned().fold(0.0, f64::max);
            let area = signed_area(a, b, c);
            // Height over the longest edge at least 30 % of it (no slivers).
            assert!(2.0 * area / longest > 0.3 * longest, "sliver {t:?}");
        }
    }
}
