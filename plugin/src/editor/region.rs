//! # Region kinds: what colour each part of the sheet gets
//!
//! The sheet view colours each triangle by the kind of region it belongs to. The developable
//! model of crumpled paper splits a sheet into flat facets, smoothly curved (developable)
//! regions and small regions around singular vertices (d-cone apexes); the colours make that
//! structure visible while the sheet is played.
//!
//! **Where the kinds come from.** The geometry layer of the simulation partitions the sheet
//! every frame (`sim_core::geometry::GeometryFrame::tri_kind`: flat facets, curved regions
//! fitted by generalized cones, fans around singular vertices; thesis §2.4, TOG 2015 §4–5), and
//! the view shows exactly that partition ([`kinds_from_partition`]). When the layer is off (or
//! a frame carries no partition) the view derives the kinds from the mesh alone
//! ([`RegionClassifier`]), an approximation:
//! - *around a singular vertex*: a triangle touching a vertex tagged `Singular`;
//! - *curved*: a triangle whose normal deviates from the area-weighted normals of its own
//!   vertices by more than a sheet bent to a radius of [`CURVED_MAX_RADIUS_M`] would make it
//!   deviate (a discrete curvature estimate: deviation angle α over a triangle of size h means a
//!   bend radius ≈ h / 2α, independent of the mesh resolution);
//! - *flat*: everything else.
//!
//! A new kind is one more [`RegionKind`] variant with its colour and label.

use sim_core::MeshSnapshot;
use sim_core::geometry::TriKind;
use sim_core::mesh_snapshot::VertexTag;

use super::vec3::{V3, add, cross, dot, length, normalized, sub};

/// Bend radius below which a triangle counts as curved, metres.
pub const CURVED_MAX_RADIUS_M: f32 = 0.25;

/// The kind of region a triangle belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RegionKind {
    /// A flat facet.
    Flat,
    /// A smoothly bent (developable) region.
    Curved,
    /// Around a singular vertex (d-cone apex).
    Singular,
}

impl RegionKind {
    /// Every kind, in legend order.
    pub const ALL: [RegionKind; 3] = [RegionKind::Flat, RegionKind::Curved, RegionKind::Singular];

    /// Base (fully lit, front side) colour, sRGB.
    pub const fn colour(self) -> [u8; 3] {
        match self {
            RegionKind::Flat => [245, 236, 212],
            RegionKind::Curved => [238, 206, 138],
            RegionKind::Singular => [232, 112, 92],
        }
    }

    /// Legend label.
    pub const fn label(self) -> &'static str {
        match self {
            RegionKind::Flat => "flat",
            RegionKind::Curved => "curved",
            RegionKind::Singular => "around singular vertices",
        }
    }
}

/// Colour of the dots drawn on handle (held) vertices.
pub const HANDLE_DOT_COLOUR: [u8; 3] = [70, 205, 120];
/// Colour of the dots drawn on singular vertices.
pub const SINGULAR_DOT_COLOUR: [u8; 3] = [215, 45, 40];

impl From<TriKind> for RegionKind {
    fn from(k: TriKind) -> Self {
        match k {
            TriKind::Flat => RegionKind::Flat,
            TriKind::Curved => RegionKind::Curved,
            TriKind::SingularFan => RegionKind::Singular,
        }
    }
}

/// The simulation's partition as view kinds, into `out` (cleared first; no allocation once
/// `out` has the capacity).
pub fn kinds_from_partition(partition: &[TriKind], out: &mut Vec<RegionKind>) {
    out.clear();
    out.extend(partition.iter().map(|&k| RegionKind::from(k)));
}

/// Derives per-triangle region kinds from a mesh snapshot (keeps its scratch storage).
#[derive(Debug, Default)]
pub struct RegionClassifier {
    vertex_normals: Vec<V3>,
}

impl RegionClassifier {
    /// Classifies every triangle of `mesh` into `out` (resized to the triangle count).
    pub fn classify(&mut self, mesh: &MeshSnapshot, out: &mut Vec<RegionKind>) {
        out.clear();
        let pos = &mesh.positions_m;
        let n = pos.len();
        self.vertex_normals.clear();
        self.vertex_normals.resize(n, [0.0; 3]);
        let valid = |t: &[u32; 3]| t.iter().all(|&v| (v as usize) < n);
        // Area-weighted vertex normals (the unnormalized cross product is 2·area·normal).
        for t in mesh.triangles.iter().filter(|t| valid(t)) {
            let [a, b, c] = t.map(|v| pos[v as usize]);
            let w = cross(sub(b, a), sub(c, a));
            for &v in t {
                let vn = &mut self.vertex_normals[v as usize];
                *vn = add(*vn, w);
            }
        }
        let max_angle_per_m = 1.0 / (2.0 * CURVED_MAX_RADIUS_M);
        for t in &mesh.triangles {
            if !valid(t) {
                out.push(RegionKind::Flat);
                continue;
            }
            let singular = t
                .iter()
                .any(|&v| mesh.tags.get(v as usize) == Some(&VertexTag::Singular));
            if singular {
                out.push(RegionKind::Singular);
                continue;
            }
            let [a, b, c] = t.map(|v| pos[v as usize]);
            let w = cross(sub(b, a), sub(c, a));
            let area2 = length(w);
            let (Some(fn_), true) = (normalized(w), area2 > 0.0) else {
                out.push(RegionKind::Flat);
                continue;
            };
            let size_m = area2.sqrt(); // h for a right isosceles triangle with legs h
            let mut max_dev = 0.0f32;
            for &v in t {
                if let Some(vn) = normalized(self.vertex_normals[v as usize]) {
                    // 1 − cos α ≈ α²/2 for small α, exact enough and free of acos edge cases.
                    let dev = (2.0 * (1.0 - dot(fn_, vn)).max(0.0)).sqrt();
                    max_dev = max_dev.max(dev);
                }
            }
            out.push(if max_dev > max_angle_per_m * size_m {
                RegionKind::Curved
            } else {
                RegionKind::Flat
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid sheet of `nx × ny` squares of side `h`, lifted by `z(x, y)`.
    fn grid(nx: u32, ny: u32, h: f32, z: impl Fn(f32, f32) -> f32) -> MeshSnapshot {
        let mut m = MeshSnapshot::default();
        for j in 0..=ny {
            for i in 0..=nx {
                let (x, y) = (i as f32 * h, j as f32 * h);
                m.positions_m.push([x, y, z(x, y)]);
                m.pattern_m.push([x, y]);
                m.tags.push(VertexTag::Plain);
            }
        }
        let id = |i: u32, j: u32| j * (nx + 1) + i;
        for j in 0..ny {
            for i in 0..nx {
                m.triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                m.triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        m
    }

    fn count(kinds: &[RegionKind], k: RegionKind) -> usize {
        kinds.iter().filter(|&&x| x == k).count()
    }

    #[test]
    fn partition_kinds_map_one_to_one() {
        let partition = [
            TriKind::Flat,
            TriKind::SingularFan,
            TriKind::Curved,
            TriKind::Flat,
        ];
        let mut out = vec![RegionKind::Curved; 9];
        kinds_from_partition(&partition, &mut out);
        assert_eq!(
            out,
            [
                RegionKind::Flat,
                RegionKind::Singular,
                RegionKind::Curved,
                RegionKind::Flat
            ]
        );
    }

    #[test]
    fn a_flat_sheet_is_flat() {
        let m = grid(10, 10, 0.01, |_, _| 0.75);
        let mut out = Vec::new();
        RegionClassifier::default().classify(&m, &mut out);
        assert_eq!(out.len(), m.triangles.len());
        assert_eq!(count(&out, RegionKind::Flat), out.len());
    }

    #[test]
    fn a_tight_bend_is_curved_and_a_gentle_one_is_not() {
        // A cylinder of radius r about the y axis, at two resolutions.
        for h in [0.005, 0.01] {
            let cyl = |r: f32| move |x: f32, _y: f32| r - (r * r - (x - 0.05) * (x - 0.05)).sqrt();
            let mut out = Vec::new();
            let mut c = RegionClassifier::default();
            let n = (0.1 / h) as u32;
            c.classify(&grid(n, n, h, cyl(0.06)), &mut out);
            let curved = count(&out, RegionKind::Curved);
            assert!(
                curved > out.len() * 8 / 10,
                "r = 6 cm, h = {h}: {curved} of {} curved",
                out.len()
            );
            c.classify(&grid(n, n, h, cyl(2.0)), &mut out);
            assert_eq!(count(&out, RegionKind::Curved), 0, "r = 2 m, h = {h}");
        }
    }

    #[test]
    fn a_fold_is_curved_only_along_the_crease() {
        // Two flat halves meeting at x = 0.05 at 90°.
        let m = grid(10, 10, 0.01, |x, _| (x - 0.05).max(0.0));
        let mut out = Vec::new();
        RegionClassifier::default().classify(&m, &mut out);
        let curved = count(&out, RegionKind::Curved);
        // The triangles touching the crease column (2 columns × 10 rows × 2 triangles).
        assert!((20..=40).contains(&curved), "{curved}");
        assert!(count(&out, RegionKind::Flat) >= out.len() - 40);
    }

    #[test]
    fn triangles_touching_a_singular_vertex_are_singular() {
        let mut m = grid(4, 4, 0.01, |_, _| 0.0);
        let centre = 2 * 5 + 2;
        m.tags[centre] = VertexTag::Singular;
        m.tags[0] = VertexTag::Handle;
        let mut out = Vec::new();
        RegionClassifier::default().classify(&m, &mut out);
        let touching = m
            .triangles
            .iter()
            .filter(|t| t.contains(&(centre as u32)))
            .count();
        assert_eq!(touching, 6);
        assert_eq!(count(&out, RegionKind::Singular), touching);
    }

    #[test]
    fn bad_indices_do_not_panic() {
        let mut m = grid(2, 2, 0.01, |_, _| 0.0);
        m.triangles.push([0, 1, 999]);
        let mut out = Vec::new();
        RegionClassifier::default().classify(&m, &mut out);
        assert_eq!(out.len(), m.triangles.len());
    }

    #[test]
    fn kinds_have_distinct_colours_and_labels() {
        for (i, a) in RegionKind::ALL.iter().enumerate() {
            for b in &RegionKind::ALL[i + 1..] {
                assert_ne!(a.colour(), b.colour());
                assert_ne!(a.label(), b.label());
            }
        }
    }
}
