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
//! ## How Papier stores S_G: a persistent part here, a per-frame part in the geometry layer
//!
//! The seeds rebuild S_P from S_G every frame, so their S_G must carry the regions as
//! polygons over its own vertices. Papier keeps a fixed S_P lattice (the geometry module's
//! simplifications say why) and computes the partition **on S_P triangles** each frame, so
//! S_G is stored in two parts:
//!
//! - [`GeomStructure`] (this module) holds what persists: the corners and boundary samples of
//!   ∂S̄ (the thesis samples the 10 cm sheet's boundary with "12 vertices", T 1130; digest §9
//!   item 2) and the interior singular vertices, appended in creation order by the geometry
//!   layer and never removed (their pattern position is fixed, P 63–66). Step (c) of the frame
//!   loop ([`GeomStructure::pull_positions`]) copies their 3D positions from S_P.
//! - [`crate::geometry::GeometryFrame`] holds what the seeds recompute each frame: the flat,
//!   curved and crease regions (as S_P triangle sets), every curved region's ordered rulings
//!   with pattern and 3D endpoints, its cones and gap cones with pattern and 3D apices, the
//!   junction points and the held (handle) vertices.
//!   [`crate::geometry::GeometryFrame::sg_vertices`] lists the whole S_G vertex set of a frame
//!   — corners, boundary samples, singular, junction and handle vertices, each with its pattern
//!   and 3D position — as [`GVertex`] values of the matching [`VKind`].

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
    /// A junction point on ∂S between a curved and a flat region (slides along ∂S̄; per
    /// frame, from [`crate::geometry::GeometryFrame::junctions`]).
    Junction,
    /// A handle ("finger") vertex held by the user (per frame, from
    /// [`crate::geometry::GeometryFrame::held`]).
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

impl GVertex {
    /// The S_G vertex of S_P's singular vertex `v`: its pattern and 3D position, no boundary
    /// parameter.
    pub fn interior_singular(sp: &PhysMesh, v: u32) -> Self {
        GVertex {
            p2: sp.pattern[v as usize],
            p3: sp.pos[v as usize],
            kind: VKind::InteriorSingular,
            bound_s_m: None,
            sp_index: v,
        }
    }
}

/// The geometric structure S_G.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GeomStructure {
    /// The persistent vertices: corners, boundary samples and interior singular vertices
    /// (appended in creation order, never removed).
    pub vertices: Vec<GVertex>,
    /// The boundary loops ∂S̄ (S_G vertex indices, counter-clockwise), one per piece of the
    /// sheet: one until a tear separates it ([`crate::tearing`]).
    pub boundary_loops: Vec<Vec<u32>>,
}

/// Target number of S_G boundary samples of a new sheet (T 1130: 12 for the 10 cm square).
pub const INITIAL_BOUNDARY_SAMPLES: usize = 12;

impl GeomStructure {
    /// The initial structure of a flat sheet over `sp`: its boundary samples.
    ///
    /// Boundary samples are taken from the S_P boundary loop, about
    /// [`INITIAL_BOUNDARY_SAMPLES`] of them spread by arc length, always including the four
    /// corners (vertices where the boundary turns).
    pub fn initial(sp: &PhysMesh) -> Self {
        let loops = boundary_loops(sp);
        let loop_length = |lp: &[u32]| {
            let n = lp.len();
            (0..n)
                .map(|i| (sp.pattern[lp[(i + 1) % n] as usize] - sp.pattern[lp[i] as usize]).norm())
                .sum::<f64>()
        };
        // One spacing for every piece: a torn-off piece is sampled as densely as the sheet.
        let spacing =
            loops.first().map_or(0.0, |lp| loop_length(lp)) / INITIAL_BOUNDARY_SAMPLES as f64;
        let mut vertices = Vec::new();
        let mut boundary_loops = Vec::with_capacity(loops.len());
        for loop_sp in &loops {
            let n = loop_sp.len();
            let first = vertices.len() as u32;
            let mut perimeter = 0.0;
            let mut s_of = Vec::with_capacity(n);
            for i in 0..n {
                s_of.push(perimeter);
                let a = sp.pattern[loop_sp[i] as usize];
                let b = sp.pattern[loop_sp[(i + 1) % n] as usize];
                perimeter += (b - a).norm();
            }
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
            boundary_loops.push((first..vertices.len() as u32).collect());
        }
        Self {
            vertices,
            boundary_loops,
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

    /// Checks the structure against S_P: S_G ⊂ S_P with matching pattern positions, at least
    /// three corners per boundary loop, boundary loops over boundary vertices that together
    /// enclose the pattern's area counter-clockwise, and interior singular vertices off the
    /// boundary.
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
            let on_boundary = sp.topo.vertex_on_boundary[v.sp_index as usize];
            match v.kind {
                VKind::Boundary | VKind::Corner if !on_boundary => {
                    return Err(format!("S_G boundary vertex {i} is inside the sheet"));
                }
                VKind::InteriorSingular if on_boundary => {
                    return Err(format!("S_G singular vertex {i} is on the boundary"));
                }
                VKind::Junction | VKind::Handle => {
                    return Err(format!(
                        "S_G vertex {i}: per-frame kind stored as persistent"
                    ));
                }
                _ => {}
            }
        }
        let mut area = 0.0;
        for lp in &self.boundary_loops {
            let n = lp.len();
            let mut corners = 0;
            for k in 0..n {
                let (a, b) = (lp[k], lp[(k + 1) % n]);
                if a >= nv || b >= nv {
                    return Err("boundary loop index out of range".into());
                }
                corners += usize::from(self.vertices[a as usize].kind == VKind::Corner);
                let (pa, pb) = (self.vertices[a as usize].p2, self.vertices[b as usize].p2);
                area += 0.5 * pa.perp(&pb);
            }
            // A rectangle has 4; a piece torn off a corner has 3 (its corner and the tear's ends).
            if corners < 3 {
                return Err(format!("a boundary loop with {corners} corners, want ≥ 3"));
            }
        }
        if self.boundary_loops.is_empty() {
            return Err("no boundary loop".into());
        }
        let sp_area: f64 = sp.tri_rest.iter().map(|t| t.area_m2).sum();
        if (area - sp_area).abs() > 1e-9 * sp_area.max(1e-12) {
            return Err(format!(
                "the boundary loops enclose {area} m², the sheet is {sp_area} m²"
            ));
        }
        Ok(())
    }
}

/// The S_P boundary as a counter-clockwise vertex loop, starting at the vertex with the
/// smallest (y, x) pattern position (the front-left corner of a rectangle); on a torn sheet,
/// the loop through that vertex ([`boundary_loops`] has them all).
pub fn boundary_loop(sp: &PhysMesh) -> Vec<u32> {
    let mut visited = vec![false; sp.num_vertices()];
    next_boundary_loop(sp, &mut visited).unwrap_or_default()
}

/// Every S_P boundary loop (counter-clockwise), each starting at its vertex with the smallest
/// (y, x) pattern position, in the order of those vertices: one per piece (a tear's slit is
/// part of its piece's loop).
pub fn boundary_loops(sp: &PhysMesh) -> Vec<Vec<u32>> {
    let mut visited = vec![false; sp.num_vertices()];
    let mut out = Vec::new();
    while let Some(lp) = next_boundary_loop(sp, &mut visited) {
        out.push(lp);
    }
    out
}

/// The loop through the unvisited boundary vertex with the smallest (y, x) pattern position.
fn next_boundary_loop(sp: &PhysMesh, visited: &mut [bool]) -> Option<Vec<u32>> {
    let topo = &sp.topo;
    let start = (0..sp.num_vertices() as u32)
        .filter(|&v| topo.vertex_on_boundary[v as usize] && !visited[v as usize])
        .min_by(|&a, &b| {
            let (pa, pb) = (sp.pattern[a as usize], sp.pattern[b as usize]);
            pa.y.total_cmp(&pb.y).then(pa.x.total_cmp(&pb.x))
        })?;
    let mut out = Vec::new();
    let mut v = start;
    loop {
        out.push(v);
        visited[v as usize] = true;
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
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::pattern::lattice;

    #[test]
    fn initial_structure_samples_the_boundary() {
        for &(w, l, s) in &[(0.21, 0.297, 0.033), (0.1, 0.1, 0.011)] {
            let sp = PhysMesh::from_pattern(&lattice(w, l, s), 0.75, 0.1).unwrap();
            let sg = GeomStructure::initial(&sp);
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
}
