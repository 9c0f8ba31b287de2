//! # S_G: the coarse geometric structure of the sheet
//!
//! The seeds store a sheet twice (P 277–313, 337–354; T 651–665; digest-crumpling §1):
//! S_G = {𝒞, ℱ} partitions the pattern into **flat regions** F (sets of pairwise coplanar
//! triangles) and **curved regions** C (generalized cones described by an ordered list of
//! rulings, each ruling joining two S_G vertices). S_G vertices are boundary samples, interior
//! singular vertices (d-cone apices, persistent, P 63–66), junction points (where curved and
//! flat regions meet on ∂S, not persistent, P 303–306) and handle ("finger") vertices
//! (P 388–394, T 714). Every S_G vertex is also an S_P vertex (P 351–354, T 665): the map is
//! [`GVertex::sp_index`].
//!
//! This module is the **data model** only. The operations (compression analysis, ruling
//! propagation, singular-point creation, junction tracking, cone fitting, isometry; digest
//! §3.1–3.8) are in [`crate::geometry`], which computes the per-frame partition on S_P and
//! publishes it as [`crate::geometry::GeometryFrame`]; of this structure it maintains the
//! interior singular vertices (appended here as [`VKind::InteriorSingular`]), while `flats`
//! and `curved` keep the initial coarse structure (see the geometry module's simplifications).
//! Here a new sheet gets the initial
//! structure: one flat region covering the whole pattern, whose vertices are the four corners
//! and a sparse sampling of the boundary (the thesis samples the 10 cm sheet's boundary with
//! "12 vertices", T 1130; digest §9 item 2), triangulated by ear clipping; and step (c) of the
//! frame loop ([`GeomStructure::pull_positions`]) copies the 3D positions from S_P.
//!
//! Suggested structures follow digest §1.3; cones keep optional apices (`None` = at infinity,
//! a generalized cylinder, P 933) and their ruling index range.

use crate::math::{V2, V3};
use crate::sheet::pattern::signed_area;
use crate::sheet::physical::PhysMesh;
use crate::sheet::topology::NONE;

/// Kind of an S_G vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum VKind {
    /// A sample on the boundary ∂S.
    Boundary,
    /// A corner of the sheet (a boundary vertex that is never moved along ∂S).
    Corner,
    /// An interior singular vertex (d-cone apex): persistent, never moved in 2D.
    InteriorSingular,
    /// A junction point on ∂S between a curved and a flat region (slides along ∂S̄).
    Junction,
    /// A handle ("finger") vertex held by the user.
    Handle,
}

/// A vertex of S_G.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GVertex {
    /// Pattern position p̄, metres.
    pub p2: V2,
    /// 3D position p, metres (pulled from S_P each frame).
    pub p3: V3,
    /// Kind.
    pub kind: VKind,
    /// Arc-length parameter along ∂S̄ for boundary-like vertices, metres from the front-left
    /// corner counter-clockwise; `None` for interior vertices.
    pub bound_s_m: Option<f64>,
    /// Index of the same vertex in S_P.
    pub sp_index: u32,
}

/// A ruling of a curved region: a straight segment between two S_G vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ruling {
    /// First endpoint (S_G vertex index).
    pub a: u32,
    /// Second endpoint (S_G vertex index).
    pub b: u32,
}

/// A generalized cone of a curved region, covering rulings `first..=last`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// Apex in the pattern; `None` when the apex is at infinity (generalized cylinder).
    pub apex2: Option<V2>,
    /// Apex in 3D; `None` at infinity.
    pub apex3: Option<V3>,
    /// First ruling index.
    pub first: u32,
    /// Last ruling index (inclusive).
    pub last: u32,
    /// True for a gap ("junction") cone between two fitted cones (P 895–901).
    pub is_gap: bool,
}

/// A curved region: an ordered family of rulings, segmented into cones.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurvedRegion {
    /// Rulings, ordered across the region.
    pub rulings: Vec<Ruling>,
    /// Cone segmentation of the rulings.
    pub cones: Vec<Cone>,
    /// Interior singular apex, when the region is a fan around one (case ii, P 277–287).
    pub singular_apex: Option<u32>,
}

/// A flat region: planar triangles over S_G vertices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlatRegion {
    /// Triangles (S_G vertex indices), counter-clockwise in the pattern.
    pub tris: Vec<[u32; 3]>,
}

/// The geometric structure S_G.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GeomStructure {
    /// Vertices.
    pub vertices: Vec<GVertex>,
    /// Flat regions ℱ.
    pub flats: Vec<FlatRegion>,
    /// Curved regions 𝒞.
    pub curved: Vec<CurvedRegion>,
    /// The boundary loop ∂S̄ (S_G vertex indices, counter-clockwise).
    pub boundary_loop: Vec<u32>,
}

/// Target number of S_G boundary samples of a new sheet (T 1130: 12 for the 10 cm square).
pub const INITIAL_BOUNDARY_SAMPLES: usize = 12;

impl GeomStructure {
    /// The initial structure of a flat sheet over `sp`: one flat region.
    ///
    /// Boundary samples are taken from the S_P boundary loop, about
    /// [`INITIAL_BOUNDARY_SAMPLES`] of them spread by arc length, always including the four
    /// corners (vertices where the boundary turns).
    pub fn initial(sp: &PhysMesh) -> Self {
        let loop_sp = boundary_loop(sp);
        let n = loop_sp.len();
        let mut perimeter = 0.0;
        let mut s_of = Vec::with_capacity(n);
        for i in 0..n {
            s_of.push(perimeter);
            let a = sp.pattern[loop_sp[i] as usize];
            let b = sp.pattern[loop_sp[(i + 1) % n] as usize];
            perimeter += (b - a).norm();
        }
        let spacing = perimeter / INITIAL_BOUNDARY_SAMPLES as f64;
        let mut vertices = Vec::new();
        let mut last_s = f64::NEG_INFINITY;
        for i in 0..n {
            let prev = sp.pattern[loop_sp[(i + n - 1) % n] as usize];
            let cur = sp.pattern[loop_sp[i] as usize];
            let next = sp.pattern[loop_sp[(i + 1) % n] as usize];
            let turn = signed_area(prev, cur, next).abs();
            let corner = turn > 1e-12 * perimeter * perimeter;
            let far_enough =
                s_of[i] - last_s >= 0.999 * spacing && perimeter - s_of[i] >= 0.5 * spacing;
            if corner || far_enough {
                vertices.push(GVertex {
                    p2: cur,
                    p3: sp.pos[loop_sp[i] as usize],
                    kind: if corner {
                        VKind::Corner
                    } else {
                        VKind::Boundary
                    },
                    bound_s_m: Some(s_of[i]),
                    sp_index: loop_sp[i],
                });
                last_s = s_of[i];
            }
        }
        let boundary_loop: Vec<u32> = (0..vertices.len() as u32).collect();
        let pts: Vec<V2> = vertices.iter().map(|v| v.p2).collect();
        let tris = ear_clip(&pts);
        Self {
            vertices,
            flats: vec![FlatRegion { tris }],
            curved: Vec::new(),
            boundary_loop,
        }
    }

    /// Step (c) of the frame loop (P 482–487, T 744): S_G vertices read their 3D positions from
    /// S_P.
    pub fn pull_positions(&mut self, sp: &PhysMesh) {
        for v in &mut self.vertices {
            v.p3 = sp.pos[v.sp_index as usize];
        }
    }

    /// Number of interior singular vertices.
    pub fn num_singular(&self) -> usize {
        self.vertices
            .iter()
            .filter(|v| v.kind == VKind::InteriorSingular)
            .count()
    }

    /// Checks the structure against S_P: indices in range, S_G ⊂ S_P with matching pattern
    /// positions, counter-clockwise flat triangles, and flat triangles covering the pattern
    /// area when there is no curved region.
    pub fn validate(&self, sp: &PhysMesh) -> Result<(), String> {
        let nv = self.vertices.len() as u32;
        for (i, v) in self.vertices.iter().enumerate() {
            let Some(q) = sp.pattern.get(v.sp_index as usize) else {
                return Err(format!("S_G vertex {i} maps to a missing S_P vertex"));
            };
            if (q - v.p2).norm() > 1e-9 {
                return Err(format!(
                    "S_G vertex {i} is not at its S_P vertex's pattern position"
                ));
            }
        }
        let mut area = 0.0;
        for f in &self.flats {
            for t in &f.tris {
                if t.iter().any(|&i| i >= nv) {
                    return Err("flat triangle index out of range".into());
                }
                let a = signed_area(
                    self.vertices[t[0] as usize].p2,
                    self.vertices[t[1] as usize].p2,
                    self.vertices[t[2] as usize].p2,
                );
                if a <= 0.0 {
                    return Err(format!("flat triangle {t:?} is not counter-clockwise"));
                }
                area += a;
            }
        }
        for c in &self.curved {
            for r in &c.rulings {
                if r.a >= nv || r.b >= nv {
                    return Err("ruling index out of range".into());
                }
            }
        }
        if self.curved.is_empty() {
            let sp_area: f64 = sp.tri_rest.iter().map(|t| t.area_m2).sum();
            if (area - sp_area).abs() > 1e-9 * sp_area.max(1e-12) {
                return Err(format!(
                    "flat regions cover {area} m², the sheet is {sp_area} m²"
                ));
            }
        }
        Ok(())
    }
}

/// The S_P boundary as a counter-clockwise vertex loop, starting at the vertex with the
/// smallest (y, x) pattern position (the front-left corner of a rectangle).
pub fn boundary_loop(sp: &PhysMesh) -> Vec<u32> {
    let topo = &sp.topo;
    let start = (0..sp.num_vertices() as u32)
        .filter(|&v| topo.vertex_on_boundary[v as usize])
        .min_by(|&a, &b| {
            let (pa, pb) = (sp.pattern[a as usize], sp.pattern[b as usize]);
            pa.y.total_cmp(&pb.y).then(pa.x.total_cmp(&pb.x))
        })
        .unwrap_or(0);
    let mut out = Vec::new();
    let mut v = start;
    loop {
        out.push(v);
        // The boundary half-edge leaving v (stored preferentially by the topology).
        let h = topo.vertex_he[v as usize];
        if h == NONE || topo.half_edges[h as usize].twin != NONE {
            break;
        }
        v = topo.dest(h);
        if v == start || out.len() > sp.num_vertices() {
            break;
        }
    }
    out
}

/// Ear-clipping triangulation of a simple counter-clockwise polygon (collinear vertices
/// allowed), preferring the best-shaped ear at each step. O(n³) — only for small polygons.
pub fn ear_clip(pts: &[V2]) -> Vec<[u32; 3]> {
    let mut idx: Vec<u32> = (0..pts.len() as u32).collect();
    let mut out = Vec::with_capacity(pts.len().saturating_sub(2));
    while idx.len() > 3 {
        let n = idx.len();
        let mut best: Option<(f64, usize)> = None;
        for k in 0..n {
            let (ia, ib, ic) = (idx[(k + n - 1) % n], idx[k], idx[(k + 1) % n]);
            let (a, b, c) = (pts[ia as usize], pts[ib as usize], pts[ic as usize]);
            let area = signed_area(a, b, c);
            let scale = (b - a)
                .norm_squared()
                .max((c - b).norm_squared())
                .max(1e-300);
            if area <= 1e-12 * scale {
                continue;
            }
            let contains_other = idx.iter().any(|&j| {
                j != ia && j != ib && j != ic && {
                    let p = pts[j as usize];
                    signed_area(a, b, p) >= 0.0
                        && signed_area(b, c, p) >= 0.0
                        && signed_area(c, a, p) >= 0.0
                }
            });
            if contains_other {
                continue;
            }
            // Shape quality: area over the squared longest edge.
            let longest = (b - a)
                .norm_squared()
                .max((c - b).norm_squared())
                .max((a - c).norm_squared());
            let q = area / longest;
            if best.is_none_or(|(bq, _)| q > bq) {
                best = Some((q, k));
            }
        }
        let Some((_, k)) = best else { break };
        let n = idx.len();
        out.push([idx[(k + n - 1) % n], idx[k], idx[(k + 1) % n]]);
        idx.remove(k);
    }
    if idx.len() == 3 {
        let [a, b, c] = [idx[0], idx[1], idx[2]];
        if signed_area(pts[a as usize], pts[b as usize], pts[c as usize]) > 0.0 {
            out.push([a, b, c]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::pattern::lattice;

    #[test]
    fn initial_structure_is_one_flat_region_over_the_sheet() {
        for &(w, l, s) in &[(0.21, 0.297, 0.033), (0.1, 0.1, 0.011)] {
            let sp = PhysMesh::from_pattern(&lattice(w, l, s), 0.75, 0.1).unwrap();
            let sg = GeomStructure::initial(&sp);
            assert_eq!(sg.flats.len(), 1);
            assert!(sg.curved.is_empty());
            assert_eq!(sg.num_singular(), 0);
            let corners = sg
                .vertices
                .iter()
                .filter(|v| v.kind == VKind::Corner)
                .count();
            assert_eq!(corners, 4);
            assert!(
                (10..=20).contains(&sg.vertices.len()),
                "{} boundary samples",
                sg.vertices.len()
            );
            sg.validate(&sp).unwrap();
        }
    }

    #[test]
    fn boundary_loop_is_closed_and_ccw() {
        let sp = PhysMesh::from_pattern(&lattice(0.21, 0.297, 0.033), 0.0, 0.1).unwrap();
        let lp = boundary_loop(&sp);
        let nb = sp.topo.vertex_on_boundary.iter().filter(|&&b| b).count();
        assert_eq!(lp.len(), nb);
        let mut area = 0.0;
        for i in 0..lp.len() {
            let a = sp.pattern[lp[i] as usize];
            let b = sp.pattern[lp[(i + 1) % lp.len()] as usize];
            area += 0.5 * a.perp(&b);
        }
        assert!((area - 0.21 * 0.297).abs() < 1e-12);
    }

    #[test]
    fn ear_clip_handles_collinear_points() {
        let pts = vec![
            V2::new(0.0, 0.0),
            V2::new(1.0, 0.0),
            V2::new(2.0, 0.0),
            V2::new(2.0, 1.0),
            V2::new(1.0, 1.0),
            V2::new(0.0, 1.0),
        ];
        let t = ear_clip(&pts);
        assert_eq!(t.len(), 4);
        let area: f64 = t
            .iter()
            .map(|t| signed_area(pts[t[0] as usize], pts[t[1] as usize], pts[t[2] as usize]))
            .sum();
        assert!((area - 2.0).abs() < 1e-12);
    }
}
