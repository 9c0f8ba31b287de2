//! # Metrics of the sheet: length error, strain, angle defect, energy, mesh health
//!
//! The seeds measure isometry by the edge-length error on S_P (TOG 2015 Table IV, P 1332–1356,
//! 1432–1440; thesis Table 2.4, T 1224–1231, T 1211; digest §6.4):
//!
//! ```text
//! c_e = (l̄_e − l_e) / l̄_e            edge compression against the pattern (T 822)
//! c_mean = mean over edges of max(c_e, 0), in %      (E_length of P 1435–1437)
//! n_comp = % of edges with c_e > 1 %
//! ```
//!
//! The seeds report both averaged over all frames of an example; [`Metrics`] is one frame
//! (the benchmark report averages). Only compression counts in c_mean, as in the seeds ("mean
//! % compression"; extension is not handled by their geometry layer, T 848); extension shows in
//! `max_strain`, the largest principal Green-strain stretch deviation |λ − 1| over triangles.
//!
//! Also: the **angle defect** (Σ over interior vertices of |2π − Σ corner angles|, and the
//! largest one) — zero for a developable surface, so it measures how far physics alone is from
//! a developable sheet (digest §7 item 6); the triangle and singular-vertex counts (Tables II
//! and V); the kinetic energy; and **flipped triangles**: a triangle whose unit normal turned by
//! more than 90° since the previous frame. A 3D surface triangle has no intrinsic "inside",
//! so inversion is defined by orientation continuity; at 200 frames/s a real sheet never turns
//! a facet over within one frame, so a flip means the integration failed (stress tests require
//! zero).

use crate::math::{V3, sym2_eigen};
use crate::sheet::measure::green_strain;
use crate::sheet::physical::PhysMesh;

/// Compression above which an edge counts in n_comp (1 %, P 1437).
pub const N_COMP_THRESHOLD: f64 = 0.01;

/// Largest principal stretch deviation |λ − 1| of triangle `t` of `mesh` at corners `x`
/// (infinite if not finite).
pub fn triangle_strain(mesh: &PhysMesh, t: usize, x: [V3; 3]) -> f64 {
    let (g, _) = green_strain(x, &mesh.tri_rest[t]);
    // C = 2G + I; principal stretches λ = √eig(C).
    let (lo, hi, _) = sym2_eigen(
        2.0 * g[(0, 0)] + 1.0,
        2.0 * g[(0, 1)],
        2.0 * g[(1, 1)] + 1.0,
    );
    let s = (lo.max(0.0).sqrt() - 1.0)
        .abs()
        .max((hi.max(0.0).sqrt() - 1.0).abs());
    if s.is_finite() { s } else { f64::INFINITY }
}

/// The largest [`triangle_strain`] of each vertex's triangles into `out` (one entry per
/// vertex; no allocation when it has the capacity).
pub fn vertex_strains(mesh: &PhysMesh, out: &mut Vec<f64>) {
    out.clear();
    out.resize(mesh.num_vertices(), 0.0);
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let s = triangle_strain(mesh, t, tri.map(|i| mesh.pos[i as usize]));
        for &v in tri {
            let e = &mut out[v as usize];
            *e = e.max(s);
        }
    }
}

/// [`Metrics::max_strain`] of `mesh` with its vertices at `pos` (0 if `pos` does not fit).
pub fn max_strain(mesh: &PhysMesh, pos: &[V3]) -> f64 {
    if pos.len() != mesh.num_vertices() {
        return 0.0;
    }
    mesh.triangles
        .iter()
        .enumerate()
        .map(|(t, tri)| triangle_strain(mesh, t, tri.map(|i| pos[i as usize])))
        .fold(0.0, f64::max)
}

/// Metrics of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Metrics {
    /// Mean edge compression, %.
    pub c_mean_pct: f64,
    /// Percentage of edges compressed by more than 1 %.
    pub n_comp_pct: f64,
    /// Largest principal stretch deviation |λ − 1| over triangles (fraction).
    pub max_strain: f64,
    /// Largest edge compression (fraction).
    pub max_compression: f64,
    /// Σ over interior vertices of |2π − Σ angles|, radians.
    pub angle_defect_sum_rad: f64,
    /// Largest |2π − Σ angles| over interior vertices, radians.
    pub angle_defect_max_rad: f64,
    /// Triangles of S_P.
    pub num_triangles: usize,
    /// Vertices of S_P.
    pub num_vertices: usize,
    /// Persistent interior singular vertices.
    pub num_singular: usize,
    /// Kinetic energy, J.
    pub kinetic_energy_j: f64,
    /// Largest vertex speed, m/s.
    pub max_speed_m_s: f64,
    /// Triangles whose normal turned by more than 90° since the previous frame — or, in a
    /// frame whose substep was solved as shorter ones, since the start of its last one
    /// (sim.rs, "A substep solved as shorter ones": continuity at the solver's resolution).
    pub num_flipped: usize,
    /// Triangles with less than 1 % of their pattern area (or non-finite).
    pub num_degenerate: usize,
}

/// Scratch storage and frame-to-frame memory of the metrics (no allocation per frame).
#[derive(Clone, Debug, Default)]
pub struct MetricsTracker {
    angle_sum: Vec<f64>,
    prev_normal: Vec<V3>,
}

impl MetricsTracker {
    /// Unit normals of the triangles at the end of the previous frame (the reference of the
    /// flipped-triangle count).
    pub fn previous_normals(&self) -> &[V3] {
        &self.prev_normal
    }

    /// Unit normal of triangle `t` at the end of the previous frame (the reference of the
    /// flipped-triangle count).
    pub fn previous_normal(&self, t: usize) -> V3 {
        self.prev_normal.get(t).copied().unwrap_or_else(V3::zeros)
    }

    /// Storage for a mesh, with the current normals as the "previous frame".
    pub fn new(mesh: &PhysMesh) -> Self {
        let mut t = Self {
            angle_sum: vec![0.0; mesh.num_vertices()],
            prev_normal: vec![V3::zeros(); mesh.num_triangles()],
        };
        t.reset_normals(mesh);
        t
    }

    /// Takes the current normals as the reference (after a reset or restore).
    pub fn reset_normals(&mut self, mesh: &PhysMesh) {
        for (t, n) in self.prev_normal.iter_mut().enumerate() {
            *n = mesh
                .tri_normal(t)
                .try_normalize(0.0)
                .unwrap_or_else(V3::zeros);
        }
    }

    /// Takes `normals` (saved from [`Self::previous_normals`] for the same mesh) back as the
    /// reference; ignored if their count does not fit.
    pub fn set_previous_normals(&mut self, normals: &[V3]) {
        if normals.len() == self.prev_normal.len() {
            self.prev_normal.copy_from_slice(normals);
        }
    }

    /// Computes every metric of the current frame and updates the normal memory.
    pub fn compute(&mut self, mesh: &PhysMesh) -> Metrics {
        let mut m = Metrics {
            num_triangles: mesh.num_triangles(),
            num_vertices: mesh.num_vertices(),
            num_singular: mesh.singular.len(),
            ..Metrics::default()
        };
        let ne = mesh.num_edges();
        let (mut sum_c, mut n_comp) = (0.0, 0usize);
        for e in 0..ne {
            let c = (mesh.edge_rest_len_m[e] - mesh.edge_length_m(e)) / mesh.edge_rest_len_m[e];
            if c > 0.0 {
                sum_c += c;
            }
            if c > N_COMP_THRESHOLD {
                n_comp += 1;
            }
            m.max_compression = m.max_compression.max(c);
        }
        if ne > 0 {
            m.c_mean_pct = 100.0 * sum_c / ne as f64;
            m.n_comp_pct = 100.0 * n_comp as f64 / ne as f64;
        }

        for a in &mut self.angle_sum {
            *a = 0.0;
        }
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let x = tri.map(|i| mesh.pos[i as usize]);
            m.max_strain = m.max_strain.max(triangle_strain(mesh, t, x));
            let n = (x[1] - x[0]).cross(&(x[2] - x[0]));
            let area = 0.5 * n.norm();
            if area.is_nan() || area < 0.01 * mesh.tri_rest[t].area_m2 {
                m.num_degenerate += 1;
            }
            let nu = n.try_normalize(0.0).unwrap_or_else(V3::zeros);
            if nu.dot(&self.prev_normal[t]) < 0.0 {
                m.num_flipped += 1;
            }
            self.prev_normal[t] = nu;
            // Corner angles from the 3D edge vectors.
            for k in 0..3 {
                let a = x[(k + 1) % 3] - x[k];
                let b = x[(k + 2) % 3] - x[k];
                let ang = a.cross(&b).norm().atan2(a.dot(&b));
                self.angle_sum[tri[k] as usize] += ang;
            }
        }
        for (v, s) in self.angle_sum.iter().enumerate() {
            if mesh.topo.vertex_on_boundary[v] {
                continue;
            }
            let d = (std::f64::consts::TAU - s).abs();
            m.angle_defect_sum_rad += d;
            m.angle_defect_max_rad = m.angle_defect_max_rad.max(d);
        }
        for (v, mass) in mesh.vel.iter().zip(&mesh.mass_kg) {
            let v2 = v.norm_squared();
            m.kinetic_energy_j += 0.5 * mass * v2;
            m.max_speed_m_s = m.max_speed_m_s.max(v2.sqrt());
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::pattern::lattice;

    #[test]
    fn flat_sheet_is_perfect() {
        let mesh = PhysMesh::from_pattern(&lattice(0.1, 0.1, 0.02), 0.75, 0.1).unwrap();
        let mut t = MetricsTracker::new(&mesh);
        let m = t.compute(&mesh);
        assert!(m.c_mean_pct.abs() < 1e-12 && m.n_comp_pct == 0.0);
        assert!(m.max_strain < 1e-12 && m.angle_defect_sum_rad < 1e-9);
        assert_eq!((m.num_flipped, m.num_degenerate), (0, 0));
        assert_eq!(m.kinetic_energy_j, 0.0);
    }

    #[test]
    fn uniform_compression_is_measured() {
        let mut mesh = PhysMesh::from_pattern(&lattice(0.1, 0.1, 0.02), 0.75, 0.1).unwrap();
        for p in &mut mesh.pos {
            p.x *= 0.98; // 2 % along x
        }
        let mut t = MetricsTracker::new(&mesh);
        let m = t.compute(&mesh);
        assert!(m.c_mean_pct > 0.5 && m.c_mean_pct < 2.0, "{}", m.c_mean_pct);
        assert!(m.n_comp_pct > 10.0);
        assert!((m.max_strain - 0.02).abs() < 1e-9);
        assert!((m.max_compression - 0.02).abs() < 1e-9);
    }

    #[test]
    fn max_strain_at_given_positions_is_the_metric() {
        let mut mesh = PhysMesh::from_pattern(&lattice(0.1, 0.1, 0.02), 0.75, 0.1).unwrap();
        let flat = mesh.pos.clone();
        let v = mesh.num_vertices() / 2;
        mesh.pos[v].z += 0.004;
        let m = MetricsTracker::new(&mesh).compute(&mesh);
        assert!(m.max_strain > 0.01, "{}", m.max_strain);
        assert_eq!(max_strain(&mesh, &mesh.pos), m.max_strain);
        assert!(max_strain(&mesh, &flat) < 1e-12);
        assert_eq!(
            max_strain(&mesh, &flat[1..]),
            0.0,
            "positions that do not fit"
        );
    }

    #[test]
    fn cone_has_angle_defect_and_flip_is_detected() {
        let mut mesh = PhysMesh::from_pattern(&lattice(0.1, 0.1, 0.02), 0.0, 0.1).unwrap();
        let mut t = MetricsTracker::new(&mesh);
        // Push one interior vertex up: a cone, non-developable.
        let c = (0..mesh.num_vertices())
            .find(|&v| !mesh.topo.vertex_on_boundary[v])
            .unwrap();
        mesh.pos[c].z += 0.01;
        let m = t.compute(&mesh);
        assert!(m.angle_defect_max_rad > 0.01);
        // Mirror the sheet through z: every facet flips.
        for p in &mut mesh.pos {
            p.x = -p.x;
        }
        let m = t.compute(&mesh);
        assert_eq!(m.num_flipped, mesh.num_triangles());
    }
}
