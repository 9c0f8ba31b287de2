//! # S_P: the physical (simulation and display) mesh
//!
//! S_P is "S_G enriched with extra vertices so that a standard FEM thin-shell simulator can bend
//! it" (P 459–487, T 734–744; digest-crumpling §1.2, §2.2). It carries, per vertex, the 2D
//! pattern position x̄ (rest state), the 3D position x and velocity v and a lumped mass; per
//! triangle the inverse pattern edge matrix Ū⁻¹ and the pattern area (for the Green strain,
//! T 341–355); per edge the pattern length, the **rest dihedral angle** θ̄_e and the **damage**
//! d_e of the fibre-damage model (P eq. 1 at P 504–519; T eq. 2.1–2.2 at T 753–775: the hinge
//! stiffness becomes `k_b / (1 + d_e)`); and per interior edge a **hinge** (the 4-vertex stencil
//! of the discrete bending energy, T 357–361).
//!
//! All arrays are sized once when the mesh is built; stepping only writes into them. The
//! seeds regenerate S_P from S_G every frame (§2.2); our geometry layer ([`crate::geometry`])
//! keeps S_P's connectivity between singular points (see its module doc) and only writes rest
//! angles, damage, the singular list and positions; a vertex inserted at a singular point
//! ([`crate::sheet::refine`]) builds a new mesh, which allocates (a connectivity change is
//! not a steady-state step).

use crate::math::{M2, V2, V3, barycentric2, sym2_eigen};
use crate::sheet::measure::green_strain;
use crate::sheet::pattern::{Pattern, signed_area};
use crate::sheet::topology::{NONE, Topology, TopologyError};

/// Rest data of one triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriRest {
    /// Inverse of the pattern edge matrix Ū = [x̄₁−x̄₀, x̄₂−x̄₀] (1/m).
    pub dm_inv: M2,
    /// Pattern area Ā, m².
    pub area_m2: f64,
}

/// The bending stencil of one interior edge.
///
/// `v = [x0, x1, x2, x3]`: the edge runs x0 → x1 in face A = (x0, x1, x2) (counter-clockwise);
/// x3 is the wing vertex of face B.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hinge {
    /// Edge index.
    pub edge: u32,
    /// Vertex stencil.
    pub v: [u32; 4],
    /// Geometric weight `|ē|² / (Ā_A + Ā_B)` (dimensionless); the hinge stiffness is
    /// `B·weight / (2 (1 + d_e))`.
    pub weight: f64,
}

/// The physical mesh S_P.
#[derive(Clone, Debug, PartialEq)]
pub struct PhysMesh {
    /// Pattern positions x̄, metres, origin at the sheet centre.
    pub pattern: Vec<V2>,
    /// 3D positions x, world metres.
    pub pos: Vec<V3>,
    /// Velocities, m/s.
    pub vel: Vec<V3>,
    /// Lumped pattern area per vertex, m².
    pub vertex_area_m2: Vec<f64>,
    /// Areal density the masses were lumped with, kg/m².
    pub areal_density_kg_m2: f64,
    /// Incremented whenever the rest shape (pattern) changes, so solvers that cache rest
    /// data refresh it.
    pub rest_version: u64,
    /// Lumped mass per vertex, kg (ρ × lumped area).
    pub mass_kg: Vec<f64>,
    /// Triangles, counter-clockwise in the pattern.
    pub triangles: Vec<[u32; 3]>,
    /// Topology of `triangles`.
    pub topo: Topology,
    /// Rest data per triangle.
    pub tri_rest: Vec<TriRest>,
    /// Pattern length per edge, metres.
    pub edge_rest_len_m: Vec<f64>,
    /// Rest dihedral angle θ̄_e per edge, radians (0 = flat; set around singular vertices).
    pub edge_rest_angle: Vec<f64>,
    /// Fibre damage d_e per edge (≥ 0; bending stiffness is divided by 1 + d_e).
    pub edge_damage: Vec<f64>,
    /// Hinges (interior edges).
    pub hinges: Vec<Hinge>,
    /// Hinge index of each edge, [`NONE`] for boundary edges.
    pub edge_hinge: Vec<u32>,
    /// Persistent interior singular vertices (d-cone apices), in creation order.
    pub singular: Vec<u32>,
}

/// Why a pattern cannot become a simulation mesh.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum MeshError {
    /// The triangle list is not a valid manifold mesh.
    #[error("invalid topology: {0}")]
    Topology(#[from] TopologyError),
    /// A pattern triangle has (nearly) zero or negative area.
    #[error("pattern triangle {0} is degenerate or clockwise")]
    DegenerateTriangle(u32),
    /// A pattern coordinate is not finite.
    #[error("pattern vertex {0} is not finite")]
    NonFinite(u32),
}

impl PhysMesh {
    /// Builds S_P from a pattern, placed flat at height `z_m`, at rest, undamaged.
    pub fn from_pattern(
        p: &Pattern,
        z_m: f64,
        areal_density_kg_m2: f64,
    ) -> Result<Self, MeshError> {
        for (i, q) in p.points.iter().enumerate() {
            if !(q.x.is_finite() && q.y.is_finite()) {
                return Err(MeshError::NonFinite(i as u32));
            }
        }
        let topo = Topology::build(p.points.len(), &p.triangles)?;
        let n = p.points.len();
        let mut tri_rest = Vec::with_capacity(p.triangles.len());
        let mut vertex_area = vec![0.0; n];
        // Reference scale for the degeneracy test.
        let (mut lo, mut hi) = (V2::repeat(f64::MAX), V2::repeat(f64::MIN));
        for q in &p.points {
            lo = lo.inf(q);
            hi = hi.sup(q);
        }
        let scale2 = (hi - lo).norm_squared().max(1e-12);
        for (t, tri) in p.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| p.points[i as usize]);
            let area = signed_area(a, b, c);
            if area.is_nan() || area <= 1e-10 * scale2 {
                return Err(MeshError::DegenerateTriangle(t as u32));
            }
            let dm = M2::from_columns(&[b - a, c - a]);
            let dm_inv = dm
                .try_inverse()
                .ok_or(MeshError::DegenerateTriangle(t as u32))?;
            tri_rest.push(TriRest {
                dm_inv,
                area_m2: area,
            });
            for &v in tri {
                vertex_area[v as usize] += area / 3.0;
            }
        }
        let edge_rest_len_m: Vec<f64> = topo
            .edges
            .iter()
            .map(|e| (p.points[e.v[1] as usize] - p.points[e.v[0] as usize]).norm())
            .collect();
        let mut hinges = Vec::with_capacity(topo.edges.len());
        let mut edge_hinge = vec![NONE; topo.edges.len()];
        for (ei, e) in topo.edges.iter().enumerate() {
            if e.is_boundary() {
                continue;
            }
            let h0 = e.he[0];
            let h1 = e.he[1];
            let x0 = topo.half_edges[h0 as usize].origin;
            let x1 = topo.dest(h0);
            let x2 = topo.opposite(h0);
            let x3 = topo.opposite(h1);
            let fa = topo.half_edges[h0 as usize].face as usize;
            let fb = topo.half_edges[h1 as usize].face as usize;
            let l = edge_rest_len_m[ei];
            edge_hinge[ei] = hinges.len() as u32;
            hinges.push(Hinge {
                edge: ei as u32,
                v: [x0, x1, x2, x3],
                weight: l * l / (tri_rest[fa].area_m2 + tri_rest[fb].area_m2),
            });
        }
        let ne = topo.edges.len();
        Ok(Self {
            pos: p.points.iter().map(|q| V3::new(q.x, q.y, z_m)).collect(),
            vel: vec![V3::zeros(); n],
            mass_kg: vertex_area
                .iter()
                .map(|a| a * areal_density_kg_m2)
                .collect(),
            vertex_area_m2: vertex_area,
            areal_density_kg_m2,
            rest_version: 0,
            pattern: p.points.clone(),
            triangles: p.triangles.clone(),
            topo,
            tri_rest,
            edge_rest_len_m,
            edge_rest_angle: vec![0.0; ne],
            edge_damage: vec![0.0; ne],
            hinges,
            edge_hinge,
            singular: Vec::new(),
        })
    }

    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.pos.len()
    }

    /// Number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.triangles.len()
    }

    /// Number of edges.
    pub fn num_edges(&self) -> usize {
        self.topo.edges.len()
    }

    /// The point of the current surface over pattern point `p` near vertex `v`, with `v` taken
    /// at pattern position `v_pattern` (its position before a move): barycentric in the
    /// triangle of `v`'s star that contains `p`, or comes closest to. `None` for an isolated
    /// vertex.
    pub fn surface_point_over(&self, v: u32, v_pattern: V2, p: V2) -> Option<V3> {
        let at = |i: u32| {
            if i == v {
                v_pattern
            } else {
                self.pattern[i as usize]
            }
        };
        let mut best: Option<(f64, V3)> = None;
        for tri in self.triangles.iter().filter(|t| t.contains(&v)) {
            let [a, b, c] = tri.map(at);
            let [l0, l1, l2] = barycentric2(a, b, c, p);
            let inside = l0.min(l1).min(l2);
            if best.is_none_or(|(m, _)| inside > m) {
                let [x0, x1, x2] = tri.map(|i| self.pos[i as usize]);
                best = Some((inside, x0 * l0 + x1 * l1 + x2 * l2));
            }
        }
        best.map(|(_, x)| x)
    }

    /// Moves interior vertex `v` of the pattern towards `target` (a singular point's drawn
    /// position, thesis §2.4.3: s̄ is fixed in the pattern), as far as the triangles around
    /// it stay well shaped: the full move, else half, else a quarter, else none. The vertex's
    /// 3D position moves to the point of the current surface over the new pattern position
    /// (barycentric in the triangle of the old pattern that contains it); a fraction is taken
    /// only if every triangle around `v` keeps 40–250 % of its pattern area, its orientation,
    /// and a strain under 2 % over the current surface (a tightly folded star does not move). The rest
    /// data of the triangles, edges and hinges around `v` and the lumped masses follow,
    /// computed exactly as [`Self::from_pattern`] does (a sheet rebuilt from the moved
    /// pattern is bit-identical), and `rest_version` is bumped. No allocation. Returns the
    /// pattern displacement made (zero if `v` is on the boundary or no fraction fits).
    pub fn move_pattern_vertex(&mut self, v: u32, target: V2) -> V2 {
        self.move_pattern_vertex_by(v, target, &[1.0, 0.5, 0.25])
    }

    /// [`Self::move_pattern_vertex`] trying only the given fractions of the move, in order
    /// (`&[1.0]`: the full move or none).
    pub fn move_pattern_vertex_by(&mut self, v: u32, target: V2, fractions: &[f64]) -> V2 {
        let vi = v as usize;
        if self.topo.vertex_on_boundary[vi] || !(target.x.is_finite() && target.y.is_finite()) {
            return V2::zeros();
        }
        let old = self.pattern[vi];
        // Every triangle around v keeps 40–250 % of its pattern area, and over the current
        // surface keeps its orientation and stretches or shrinks by less than 2 %.
        let fits = |mesh: &Self, p: V2, x: V3| {
            mesh.triangles.iter().enumerate().all(|(t, tri)| {
                if !tri.contains(&v) {
                    return true;
                }
                let [a, b, c] = tri.map(|i| if i == v { p } else { mesh.pattern[i as usize] });
                let area = signed_area(a, b, c);
                if !(0.4..=2.5).contains(&(area / mesh.tri_rest[t].area_m2)) {
                    return false;
                }
                let [x0, x1, x2] = tri.map(|i| if i == v { x } else { mesh.pos[i as usize] });
                let [y0, y1, y2] = tri.map(|i| mesh.pos[i as usize]);
                let (n_new, n_old) = ((x1 - x0).cross(&(x2 - x0)), (y1 - y0).cross(&(y2 - y0)));
                if n_new.dot(&n_old) <= 0.0 {
                    return false;
                }
                let Some(dm_inv) = M2::from_columns(&[b - a, c - a]).try_inverse() else {
                    return false;
                };
                // Principal Green strains (λ² − 1)/2 for stretch ratios λ within ±2 %.
                let rest = TriRest {
                    dm_inv,
                    area_m2: area,
                };
                let (g, _) = green_strain([x0, x1, x2], &rest);
                let (lo, hi, _) = sym2_eigen(g[(0, 0)], g[(0, 1)], g[(1, 1)]);
                lo > 0.5 * (0.98 * 0.98 - 1.0) && hi < 0.5 * (1.02 * 1.02 - 1.0)
            })
        };
        let Some((p, x)) = fractions.iter().find_map(|&f| {
            let p = old + (target - old) * f;
            let x = self.surface_point_over(v, old, p)?;
            (x.iter().all(|c| c.is_finite()) && fits(self, p, x)).then_some((p, x))
        }) else {
            return V2::zeros();
        };
        self.pos[vi] = x;
        self.pattern[vi] = p;
        for (t, tri) in self.triangles.iter().enumerate() {
            if !tri.contains(&v) {
                continue;
            }
            let [a, b, c] = tri.map(|i| self.pattern[i as usize]);
            let dm = M2::from_columns(&[b - a, c - a]);
            if let Some(dm_inv) = dm.try_inverse() {
                self.tri_rest[t] = TriRest {
                    dm_inv,
                    area_m2: signed_area(a, b, c),
                };
            }
        }
        for (ei, e) in self.topo.edges.iter().enumerate() {
            if e.v.contains(&v) {
                self.edge_rest_len_m[ei] =
                    (self.pattern[e.v[1] as usize] - self.pattern[e.v[0] as usize]).norm();
            }
        }
        for h in &mut self.hinges {
            if h.v.contains(&v) {
                let e = &self.topo.edges[h.edge as usize];
                let fa = self.topo.half_edges[e.he[0] as usize].face as usize;
                let fb = self.topo.half_edges[e.he[1] as usize].face as usize;
                let l = self.edge_rest_len_m[h.edge as usize];
                h.weight = l * l / (self.tri_rest[fa].area_m2 + self.tri_rest[fb].area_m2);
            }
        }
        for a in &mut self.vertex_area_m2 {
            *a = 0.0;
        }
        for (t, tri) in self.triangles.iter().enumerate() {
            for &i in tri {
                self.vertex_area_m2[i as usize] += self.tri_rest[t].area_m2 / 3.0;
            }
        }
        self.set_areal_density(self.areal_density_kg_m2);
        self.rest_version += 1;
        p - old
    }

    /// Re-lumps the masses for a new areal density (no allocation).
    pub fn set_areal_density(&mut self, areal_density_kg_m2: f64) {
        self.areal_density_kg_m2 = areal_density_kg_m2;
        for (m, a) in self.mass_kg.iter_mut().zip(&self.vertex_area_m2) {
            *m = a * areal_density_kg_m2;
        }
    }

    /// After a remeshing: each edge of this (new) mesh that `old_ends` traces back to an edge
    /// of `old` (its old end vertices, or `None`) takes that edge's rest angle and fibre damage;
    /// the others keep theirs (flat and undamaged for a mesh just built).
    pub fn inherit_edge_state(
        &mut self,
        old: &PhysMesh,
        old_ends: impl Fn([u32; 2]) -> Option<[u32; 2]>,
    ) {
        for (ei, e) in self.topo.edges.iter().enumerate() {
            if let Some(oe) = old_ends(e.v).and_then(|[a, b]| old.topo.find_edge(a, b)) {
                self.edge_rest_angle[ei] = old.edge_rest_angle[oe as usize];
                self.edge_damage[ei] = old.edge_damage[oe as usize];
            }
        }
    }

    /// Total mass, kg.
    pub fn total_mass_kg(&self) -> f64 {
        self.mass_kg.iter().sum()
    }

    /// Current 3D length of edge `e`, metres.
    pub fn edge_length_m(&self, e: usize) -> f64 {
        let ed = &self.topo.edges[e];
        (self.pos[ed.v[1] as usize] - self.pos[ed.v[0] as usize]).norm()
    }

    /// Unnormalised normal (twice the area) of triangle `t` in 3D.
    pub fn tri_normal(&self, t: usize) -> V3 {
        let [a, b, c] = self.triangles[t].map(|i| self.pos[i as usize]);
        (b - a).cross(&(c - a))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::pattern::lattice;

    #[test]
    fn masses_and_hinges_of_a4() {
        let p = lattice(0.21, 0.297, 0.033);
        let m = PhysMesh::from_pattern(&p, 0.75, 0.1).unwrap();
        assert!((m.total_mass_kg() - 0.1 * 0.21 * 0.297).abs() < 1e-12);
        let interior = m.topo.edges.iter().filter(|e| !e.is_boundary()).count();
        assert_eq!(m.hinges.len(), interior);
        // Every hinge: x0→x1 is an edge of face A, wings on opposite sides in the pattern.
        for h in &m.hinges {
            let [a, b, c, d] = h.v.map(|i| m.pattern[i as usize]);
            assert!(signed_area(a, b, c) > 0.0);
            assert!(signed_area(b, a, d) > 0.0);
            assert!(h.weight > 0.0 && h.weight.is_finite());
        }
        assert_eq!(m.topo.euler_characteristic(), 1);
    }

    #[test]
    fn degenerate_pattern_is_rejected() {
        let p = Pattern {
            points: vec![V2::new(0.0, 0.0), V2::new(1.0, 0.0), V2::new(2.0, 0.0)],
            triangles: vec![[0, 1, 2]],
        };
        assert_eq!(
            PhysMesh::from_pattern(&p, 0.0, 0.1).unwrap_err(),
            MeshError::DegenerateTriangle(0)
        );
    }

    /// Moving an interior vertex of the pattern: the rest data, masses and 3D position follow
    /// (a flat sheet stays unstrained), and a mesh rebuilt from the moved pattern is
    /// bit-identical in everything the physics reads.
    #[test]
    fn moved_pattern_vertex_matches_a_mesh_built_from_the_moved_pattern() {
        let p = lattice(0.1, 0.1, 0.011);
        let mut sp = PhysMesh::from_pattern(&p, 0.02, 0.08).unwrap();
        let v = (0..sp.num_vertices())
            .filter(|&i| !sp.topo.vertex_on_boundary[i])
            .min_by(|&a, &b| sp.pattern[a].norm().total_cmp(&sp.pattern[b].norm()))
            .unwrap();
        let before = sp.pattern[v];
        let mass: f64 = sp.total_mass_kg();
        let d = sp.move_pattern_vertex(v as u32, before + V2::new(0.003, -0.002));
        assert_eq!(d, V2::new(0.003, -0.002));
        assert_eq!(sp.rest_version, 1);
        let want = sp.pattern[v];
        assert!((sp.pos[v] - V3::new(want.x, want.y, 0.02)).norm() < 1e-12);
        assert!((sp.total_mass_kg() - mass).abs() < 1e-15);
        let mut moved = p.clone();
        moved.points[v] = want;
        let fresh = PhysMesh::from_pattern(&moved, 0.02, 0.08).unwrap();
        assert_eq!(sp.pattern, fresh.pattern);
        assert_eq!(sp.tri_rest, fresh.tri_rest);
        assert_eq!(sp.edge_rest_len_m, fresh.edge_rest_len_m);
        assert_eq!(sp.mass_kg, fresh.mass_kg);
        let w: Vec<f64> = sp.hinges.iter().map(|h| h.weight).collect();
        let wf: Vec<f64> = fresh.hinges.iter().map(|h| h.weight).collect();
        assert_eq!(w, wf);
        // A move that would fold a triangle over is refused; a boundary vertex never moves.
        let far = sp.pattern[v] + V2::new(0.05, 0.0);
        let d = sp.move_pattern_vertex(v as u32, far);
        assert!(d.norm() < 0.011, "moved {d:?} past its neighbours");
        let b = (0..sp.num_vertices())
            .find(|&i| sp.topo.vertex_on_boundary[i])
            .unwrap();
        assert_eq!(sp.move_pattern_vertex(b as u32, V2::zeros()), V2::zeros());
    }
}
