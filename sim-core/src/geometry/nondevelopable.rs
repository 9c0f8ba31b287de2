//! # Non-developable vertices (module doc step 5 of [`super`], the addition to the seeds): the Gauss
//! image of a vertex's ring of triangles, and the vertices where two bends cross becoming singular.

use super::*;

impl GeometryLayer {
    /// Step 5 for non-developable vertices (impl. choice, see the module doc): the Gauss
    /// image of a vertex's 1-ring — its triangles' unit normals — lies along one arc where
    /// the sheet is developable (cylinder, cone, twist: one ruling family through the
    /// vertex) and spreads in two directions where ruling families meet at an angle, the
    /// situation the seeds resolve with a singular vertex (P 685–704). The spread is the
    /// square root of the small eigenvalue of the normals' covariance in the tangent plane of
    /// their mean; a smooth doubly curved cap with that angular extent φ would need a
    /// compression of about φ²/6 (the chord ratio sin φ/φ), so a vertex is singular when
    /// φ²/6 > `gauss_eps_factor`·ε_c (a thicker paper, larger ε_c, gets fewer points, as in
    /// the seeds). The most spread vertex first, one per pass; never in a hand's pinch, on a
    /// vertex next to an existing singular vertex (its d-cone explains the spread), or on a
    /// refractory triangle's vertex.
    pub(super) fn treat_nondevelopable(
        &mut self,
        sp: &mut PhysMesh,
        sg: &mut GeomStructure,
        fixed: &[bool],
        frame: u64,
        mut made: u32,
    ) {
        let phi_c2 = 6.0 * self.cfg.gauss_eps_factor * self.eps_c;
        let spacing_m = self.cfg.gauss_min_spacing_m;
        let mut checked = false;
        for _ in 0..self.cfg.max_passes {
            if made >= self.cfg.max_new_singular_per_frame {
                return;
            }
            if !checked {
                for v in 0..sp.num_vertices() {
                    self.vert_spread2[v] = if sp.topo.vertex_on_boundary[v] {
                        0.0
                    } else {
                        self.gauss_spread2(v)
                    };
                }
                checked = true;
            }
            let mut best: Option<(f64, u32)> = None;
            for v in 0..sp.num_vertices() {
                let s2 = self.vert_spread2[v];
                if s2 <= phi_c2 || best.is_some_and(|b| b.0 >= s2) {
                    continue;
                }
                let p = sp.pattern[v];
                let blocked = self.near_held[v]
                    || self.is_singular[v]
                    || self
                        .vertex_tris(v)
                        .iter()
                        .any(|&t| self.refractory_until[t as usize] > frame)
                    || self
                        .out
                        .singular
                        .iter()
                        .any(|s| (s.pos2 - p).norm() < spacing_m);
                if !blocked {
                    best = Some((s2, v as u32));
                }
            }
            let Some((s2, v)) = best else {
                return;
            };
            // e_sing: the most bent edge at v (the strongest ruling through it).
            let mut e_sing: Option<(f64, u32)> = None;
            for &j in sp.topo.neighbours(v) {
                if let Some(e) = sp.topo.find_edge(v, j) {
                    let th = self.out.edge_dihedral_rad[e as usize].abs();
                    if e_sing.is_none_or(|b| th > b.0) {
                        e_sing = Some((th, e));
                    }
                }
            }
            let (start, end) = (
                self.vert_tris_start[v as usize],
                self.vert_tris_start[v as usize + 1],
            );
            for k in start..end {
                let t = self.vert_tris[k as usize] as usize;
                self.refractory_until[t] = frame + REFRACTORY_FRAMES;
            }
            self.vert_spread2[v as usize] = 0.0;
            let Some((_, e)) = e_sing else {
                continue;
            };
            if self.create_singular(
                sp,
                sg,
                fixed,
                e,
                SingularCase::NonDevelopable,
                s2 / 6.0,
                frame,
            ) {
                made += 1;
            }
        }
    }

    /// The triangles around vertex `v`.
    pub(super) fn vertex_tris(&self, v: usize) -> &[u32] {
        let (a, b) = (
            self.vert_tris_start[v] as usize,
            self.vert_tris_start[v + 1] as usize,
        );
        &self.vert_tris[a..b]
    }

    /// φ² of vertex `v`: the small eigenvalue of its ring normals' tangent covariance.
    pub(super) fn gauss_spread2(&self, v: usize) -> f64 {
        let tris = self.vertex_tris(v);
        if tris.len() < 3 {
            return 0.0;
        }
        let mut m = V3::zeros();
        for &t in tris {
            m += self.tri_normal[t as usize];
        }
        let Some(m) = m.try_normalize(1e-9) else {
            return 0.0;
        };
        let helper = if m.x.abs() < 0.9 { V3::x() } else { V3::y() };
        let u = m.cross(&helper).normalize();
        let w = m.cross(&u);
        let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
        for &t in tris {
            let n = self.tri_normal[t as usize];
            let (x, y) = (n.dot(&u), n.dot(&w));
            a += x * x;
            b += x * y;
            c += y * y;
        }
        let k = tris.len() as f64;
        let (lo, _, _) = sym2_eigen(a / k, b / k, c / k);
        lo.max(0.0)
    }
}
