//! # Dihedral angles, local shape and flat/curved classification with hysteresis (module doc steps
//! 1–2 of [`super`]; TOG 2015 §3.1 and §3.6, thesis T 813, 965).

use super::*;

impl GeometryLayer {
    /// Step 1: dihedral angles, shape operators, ruling directions, bends.
    pub(super) fn analyse_shape(&mut self, sp: &PhysMesh) {
        let th = &mut self.out.edge_dihedral_rad;
        for h in &sp.hinges {
            let x = h.v.map(|i| sp.pos[i as usize]);
            let a = dihedral(&x);
            th[h.edge as usize] = if a.is_finite() { a } else { 0.0 };
        }
        let topo = &sp.topo;
        for t in 0..sp.num_triangles() {
            let tri = sp.triangles[t];
            let area = sp.tri_rest[t].area_m2;
            // A crease: one edge much sharper than the other two bounds a flat facet; it is
            // left out of the facet's own curvature (the seeds' flat regions separated by an
            // edge between two flat regions, T 740).
            let mut ths = [0.0f64; 3];
            for (k, th_k) in ths.iter_mut().enumerate() {
                let e = topo.he_edge[3 * t + k] as usize;
                if !topo.edges[e].is_boundary() {
                    *th_k = th[e];
                }
            }
            let kmax = (0..3)
                .max_by(|&i, &j| ths[i].abs().total_cmp(&ths[j].abs()))
                .unwrap_or(0);
            let others: f64 = (0..3).filter(|&k| k != kmax).map(|k| ths[k].abs()).sum();
            let crease_k = (ths[kmax].abs() >= THETA0_RAD
                && ths[kmax].abs() > CREASE_DOMINANCE * others + THETA0_RAD)
                .then_some(kmax);
            let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
            for k in 0..3 {
                if Some(k) == crease_k || ths[k] == 0.0 {
                    continue;
                }
                let p = sp.pattern[tri[k] as usize];
                let q = sp.pattern[tri[(k + 1) % 3] as usize];
                let d = q - p;
                let len = d.norm();
                if len <= 0.0 {
                    continue;
                }
                let m = V2::new(d.y, -d.x) / len;
                let w = ths[k] * len / (2.0 * area);
                a += w * m.x * m.x;
                b += w * m.x * m.y;
                c += w * m.y * m.y;
            }
            let (lo, hi, vlo) = sym2_eigen(a, b, c);
            let (kappa, ruling) = if lo.abs() >= hi.abs() {
                (lo, V2::new(-vlo.y, vlo.x))
            } else {
                (hi, vlo)
            };
            self.tri_kappa[t] = kappa;
            let small = if lo.abs() >= hi.abs() { hi } else { lo };
            self.tri_aniso[t] = if kappa != 0.0 {
                (small / kappa).abs()
            } else {
                1.0
            };
            self.tri_ruling[t] = ruling;
            self.tri_shape[t] = [a, b, c];
            self.tri_bend[t] = kappa.abs() * self.tri_h[t];
            let x = tri.map(|i| sp.pos[i as usize]);
            self.tri_normal[t] = (x[1] - x[0])
                .cross(&(x[2] - x[0]))
                .try_normalize(0.0)
                .unwrap_or_else(V3::z);
        }
        // Region-scale ruling directions: the shape operator summed over a triangle and its
        // edge neighbours (area weights cancel: each S̄_t is already per unit area and the
        // lattice's triangles are near-equal). A single triangle's three hinges give a noisy
        // direction where one of them carries most of the bend; the sum over the four
        // triangles follows the region's generators and keeps one generalized cone in one
        // region (partition and ruling tracing use it; the conflict tests keep the local one).
        for t in 0..sp.num_triangles() {
            let mut acc = self.tri_shape[t];
            for k in 0..3 {
                let tw = topo.half_edges[3 * t + k].twin;
                if tw != NONE {
                    let n = self.tri_shape[topo.half_edges[tw as usize].face as usize];
                    for i in 0..3 {
                        acc[i] += n[i];
                    }
                }
            }
            let (lo, hi, vlo) = sym2_eigen(acc[0], acc[1], acc[2]);
            self.tri_ruling_smooth[t] = if lo.abs() >= hi.abs() {
                V2::new(-vlo.y, vlo.x)
            } else {
                vlo
            };
        }
    }

    /// Step 2: flat/curved hysteresis per triangle.
    pub(super) fn classify(&mut self) {
        self.prev_curved.copy_from_slice(&self.curved);
        for t in 0..self.curved.len() {
            let b = self.tri_bend[t];
            if self.curved[t] {
                if b < THETA_LOW_RAD {
                    self.curved[t] = false;
                }
            } else if b > THETA_HIGH_RAD {
                self.curved[t] = true;
            }
        }
    }

    /// Vertices held this frame or next to one: the triangles around them are strained by the
    /// hands' hard constraints, not by the sheet's shape.
    pub(super) fn mark_near_held(&mut self, sp: &PhysMesh, fixed: &[bool]) {
        for (v, n) in self.near_held.iter_mut().enumerate() {
            *n = fixed[v];
        }
        for e in &sp.topo.edges {
            let (a, b) = (e.v[0] as usize, e.v[1] as usize);
            if fixed[a] || fixed[b] {
                self.near_held[a] = true;
                self.near_held[b] = true;
            }
        }
    }
}
