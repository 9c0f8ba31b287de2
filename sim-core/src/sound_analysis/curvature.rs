//! # Discrete curvature of S_P: signed dihedral angles, vertex mean curvature, local rulings
//!
//! - **Signed dihedral** θ_e of an interior edge (x0 → x1 in face A, twin in face B):
//!   θ = atan2(ê·(n_A × n_B), n_A·n_B), with both normals taken from the pattern's
//!   counter-clockwise orientation, so the sign says on which side of the sheet the edge bends
//!   (consistent over the whole sheet; boundary edges have θ = 0).
//! - **Vertex mean curvature** H_v = Σ_{e∋v} θ_e ℓ_e / (4 A_v): an edge carries the integrated
//!   mean curvature θ_e ℓ_e / 2 (exact on a cylinder of radius R meshed along its rulings:
//!   θ = s/R for a ruling spacing s, H = 1/(2R) over the strip ℓ·s), shared by its two ends;
//!   A_v is a third of the pattern area of the incident triangles. Units 1/m.
//! - **Triangle shape operator** in the pattern plane: S_t = Σ_{e∈t} (θ_e ℓ_e / (2 A_t)) m_e m_eᵀ
//!   with m_e the unit in-plane normal of the edge (pattern), each edge's bending shared by its
//!   two triangles. On a developable surface one eigenvalue vanishes; its eigenvector is the
//!   ruling direction, and the other eigenvalue the curvature across the rulings.
//!
//! All arrays are preallocated for the mesh capacity ([`Curvature::with_capacity`]).

use crate::math::{V2, V3};
use crate::sheet::physical::PhysMesh;
use crate::sheet::topology::NONE;

/// Per-frame curvature of S_P.
#[derive(Clone, Debug, Default)]
pub struct Curvature {
    /// Signed dihedral angle per edge (canonical edge order), radians.
    pub edge_angle_rad: Vec<f64>,
    /// Mean curvature per vertex, 1/m.
    pub vertex_h_per_m: Vec<f64>,
    /// Least-curved (ruling) direction per triangle, unit pattern vector.
    pub tri_ruling: Vec<V2>,
    /// Largest |principal curvature| per triangle, 1/m.
    pub tri_kappa_per_m: Vec<f64>,
    /// Largest |θ_e| over the triangle's interior edges, radians.
    pub tri_max_angle_rad: Vec<f64>,
    /// Pattern area per triangle, m².
    pub tri_area_m2: Vec<f64>,
    vertex_area: Vec<f64>,
    /// Per triangle: its (unnormalized) 3D normal and that normal's length, computed once and
    /// read by the angles of its three edges.
    tri_normal: Vec<(V3, f64)>,
}

impl Curvature {
    /// Buffers for up to `max_vertices` vertices and `max_triangles` triangles.
    pub fn with_capacity(max_vertices: usize, max_triangles: usize) -> Self {
        let max_edges = max_vertices + max_triangles + 1;
        Self {
            edge_angle_rad: Vec::with_capacity(max_edges),
            vertex_h_per_m: Vec::with_capacity(max_vertices),
            tri_ruling: Vec::with_capacity(max_triangles),
            tri_kappa_per_m: Vec::with_capacity(max_triangles),
            tri_max_angle_rad: Vec::with_capacity(max_triangles),
            tri_area_m2: Vec::with_capacity(max_triangles),
            vertex_area: Vec::with_capacity(max_vertices),
            tri_normal: Vec::with_capacity(max_triangles),
        }
    }

    /// Computes everything for the current S_P. Ridges (|θ| > `ridge_rad`) bound vibration
    /// regions, so they do not count in the triangles' own curvature (the facets beside a
    /// sharp crease are flat).
    pub fn compute(&mut self, sp: &PhysMesh, ridge_rad: f64) {
        let topo = &sp.topo;
        let nv = sp.num_vertices();
        let nt = sp.num_triangles();
        let ne = topo.edges.len();
        self.edge_angle_rad.clear();
        self.edge_angle_rad.resize(ne, 0.0);
        self.vertex_h_per_m.clear();
        self.vertex_h_per_m.resize(nv, 0.0);
        self.vertex_area.clear();
        self.vertex_area.resize(nv, 0.0);
        self.tri_area_m2.clear();
        self.tri_area_m2.resize(nt, 0.0);

        for (t, tri) in sp.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| sp.pattern[i as usize]);
            let area = 0.5 * ((b - a).perp(&(c - a))).abs();
            self.tri_area_m2[t] = area;
            for &v in tri {
                self.vertex_area[v as usize] += area / 3.0;
            }
        }
        self.tri_normal.clear();
        self.tri_normal.extend((0..nt).map(|t| {
            let n = sp.tri_normal(t);
            (n, n.norm())
        }));
        for (e, edge) in topo.edges.iter().enumerate() {
            if edge.is_boundary() {
                continue;
            }
            let ha = edge.he[0];
            let hb = edge.he[1];
            let fa = topo.half_edges[ha as usize].face as usize;
            let fb = topo.half_edges[hb as usize].face as usize;
            let (na, nan) = self.tri_normal[fa];
            let (nb, nbn) = self.tri_normal[fb];
            let x0 = sp.pos[topo.half_edges[ha as usize].origin as usize];
            let x1 = sp.pos[topo.dest(ha) as usize];
            let d = x1 - x0;
            let len = d.norm();
            if len <= 0.0 || nan <= 0.0 || nbn <= 0.0 {
                continue;
            }
            let s = d.dot(&na.cross(&nb)) / (len * nan * nbn);
            let c = na.dot(&nb) / (nan * nbn);
            let theta = s.atan2(c);
            if !theta.is_finite() {
                continue;
            }
            self.edge_angle_rad[e] = theta;
            let rest_len = sp.edge_rest_len_m.get(e).copied().unwrap_or(len);
            let contrib = theta * rest_len / 4.0;
            self.vertex_h_per_m[edge.v[0] as usize] += contrib;
            self.vertex_h_per_m[edge.v[1] as usize] += contrib;
        }
        for (h, a) in self.vertex_h_per_m.iter_mut().zip(&self.vertex_area) {
            *h = if *a > 0.0 { *h / *a } else { 0.0 };
        }

        self.tri_ruling.clear();
        self.tri_kappa_per_m.clear();
        self.tri_max_angle_rad.clear();
        for t in 0..nt {
            let area = self.tri_area_m2[t];
            let mut s = [0.0f64; 3]; // xx, xy, yy
            let mut max_angle = 0.0f64;
            for k in 0..3 {
                let h = (3 * t + k) as u32;
                let e = topo.he_edge[h as usize] as usize;
                let theta = self.edge_angle_rad[e];
                if topo.half_edges[h as usize].twin == NONE || theta.abs() > ridge_rad {
                    continue;
                }
                max_angle = max_angle.max(theta.abs());
                let p0 = sp.pattern[topo.half_edges[h as usize].origin as usize];
                let p1 = sp.pattern[topo.dest(h) as usize];
                let d = p1 - p0;
                let l = d.norm();
                if l <= 0.0 || area <= 0.0 {
                    continue;
                }
                let m = V2::new(-d.y, d.x) / l;
                let w = theta * l / (2.0 * area);
                s[0] += w * m.x * m.x;
                s[1] += w * m.x * m.y;
                s[2] += w * m.y * m.y;
            }
            let (ruling, kappa) = least_curved(s);
            self.tri_ruling.push(ruling);
            self.tri_kappa_per_m.push(kappa);
            self.tri_max_angle_rad.push(max_angle);
        }
    }

    /// Σ |θ_e| over the edges incident to vertex `v`, radians.
    pub fn vertex_angle_sum(&self, sp: &PhysMesh, v: u32) -> f64 {
        sp.topo
            .neighbours(v)
            .iter()
            .filter_map(|&w| sp.topo.find_edge(v, w))
            .map(|e| self.edge_angle_rad[e as usize].abs())
            .sum()
    }

    /// The triangles around vertex `v` (walks the half-edge fan; at most 32).
    pub fn vertex_triangles<'a>(&self, sp: &'a PhysMesh, v: u32) -> impl Iterator<Item = u32> + 'a {
        sp.topo
            .neighbours(v)
            .iter()
            .filter_map(move |&w| sp.topo.find_edge(v, w))
            .flat_map(move |e| {
                let ed = sp.topo.edges[e as usize];
                ed.he
                    .into_iter()
                    .filter(|&h| h != NONE)
                    .map(move |h| sp.topo.half_edges[h as usize].face)
            })
    }

    /// Unit normal of triangle `t` (zero when degenerate).
    pub fn unit_normal(sp: &PhysMesh, t: usize) -> V3 {
        let n = sp.tri_normal(t);
        let l = n.norm();
        if l > 0.0 { n / l } else { V3::zeros() }
    }
}

/// The eigenvector of the smaller-magnitude eigenvalue of the symmetric 2×2 `[xx, xy; xy, yy]`
/// and the larger magnitude.
fn least_curved(s: [f64; 3]) -> (V2, f64) {
    let (a, b, c) = (s[0], s[1], s[2]);
    let mean = 0.5 * (a + c);
    let r = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let (l1, l2) = (mean + r, mean - r);
    let (small, big) = if l1.abs() < l2.abs() {
        (l1, l2)
    } else {
        (l2, l1)
    };
    // Eigenvector of `small`: (b, small − a) or (small − c, b).
    let v1 = V2::new(b, small - a);
    let v2 = V2::new(small - c, b);
    let v = if v1.norm_squared() >= v2.norm_squared() {
        v1
    } else {
        v2
    };
    let n = v.norm();
    let dir = if n > 1e-300 && n.is_finite() {
        v / n
    } else {
        V2::new(1.0, 0.0)
    };
    (dir, if big.is_finite() { big.abs() } else { 0.0 })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::pattern::lattice;

    /// A sheet rolled around the y axis (cylinder of radius `r`, rulings along y).
    pub(crate) fn rolled(r_m: f64, sign: f64) -> PhysMesh {
        let p = lattice(0.2, 0.2, 0.02);
        let mut sp = PhysMesh::from_pattern(&p, 0.0, 0.1).unwrap();
        for (x, q) in sp.pos.iter_mut().zip(&sp.pattern) {
            let phi = q.x / r_m;
            *x = V3::new(r_m * phi.sin(), q.y, sign * r_m * (1.0 - phi.cos()));
        }
        sp
    }

    #[test]
    fn cylinder_mean_curvature_and_rulings() {
        let r = 0.1;
        let mut c = Curvature::with_capacity(2000, 2000);
        let up = rolled(r, 1.0);
        c.compute(&up, 0.5);
        // Interior vertices: H = 1/(2R) = 5 /m within the discretisation error.
        let interior: Vec<f64> = (0..up.num_vertices())
            .filter(|&v| !up.topo.vertex_on_boundary[v])
            .map(|v| c.vertex_h_per_m[v])
            .collect();
        let mean = interior.iter().sum::<f64>() / interior.len() as f64;
        assert!((mean.abs() - 5.0).abs() < 0.5, "mean H {mean}");
        assert!(interior.iter().all(|h| h.signum() == mean.signum()));
        // Rulings along y, curvature across ≈ 1/R.
        let (mut along, mut n) = (0.0, 0);
        for t in 0..up.num_triangles() {
            if c.tri_kappa_per_m[t] > 1.0 {
                along += c.tri_ruling[t].y.abs();
                n += 1;
            }
        }
        assert!(n > up.num_triangles() / 2);
        assert!(
            along / n as f64 > 0.9,
            "ruling alignment {}",
            along / n as f64
        );
        // The other side: opposite sign.
        let down = rolled(r, -1.0);
        let mut c2 = Curvature::with_capacity(2000, 2000);
        c2.compute(&down, 0.5);
        let mean2 = (0..down.num_vertices())
            .filter(|&v| !down.topo.vertex_on_boundary[v])
            .map(|v| c2.vertex_h_per_m[v])
            .sum::<f64>()
            / interior.len() as f64;
        assert!(mean2 * mean < 0.0, "{mean2} vs {mean}");
    }

    #[test]
    fn flat_sheet_has_no_curvature() {
        let p = lattice(0.2, 0.2, 0.02);
        let sp = PhysMesh::from_pattern(&p, 0.5, 0.1).unwrap();
        let mut c = Curvature::with_capacity(2000, 2000);
        c.compute(&sp, 0.5);
        assert!(c.vertex_h_per_m.iter().all(|h| *h == 0.0));
        assert!(c.edge_angle_rad.iter().all(|a| *a == 0.0));
        assert!(c.tri_kappa_per_m.iter().all(|k| *k == 0.0));
    }
}
