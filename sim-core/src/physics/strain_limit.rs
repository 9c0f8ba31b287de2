//! # Strain limiting: paper does not stretch
//!
//! Paper stretches by about 1 % before it tears; a triangle strained by 10 % is paper torn apart
//! (digest-crumpling §2.1: the seeds' "medium" stiffness keeps edges within a few percent; their
//! isometry step, T 738–760, restores compressed edges only). The implicit solve with a medium
//! stiffness, a hand moving faster than the sheet follows, or two hands that disagree can leave
//! triangles strained beyond that for a frame. After the frame's solve and isometry step, the
//! triangles strained beyond [`STRAIN_LIMIT`] (|λ − 1| of [`crate::metrics::triangle_strain`])
//! are projected, one after the other in a few Gauss–Seidel passes, to the nearest shape whose
//! principal stretches lie within [`STRAIN_LIMIT_TO`] of 1 (the deformation gradient's singular
//! values clamped, the centroid kept) — the strain limiting of cloth simulation (Provot 1995;
//! Thomaszewski et al. 2009) applied as a last guard, not as the material model.
//!
//! Decisions, one line each:
//! - Held vertices move like free ones: a finger does not hold paper that is torn apart under
//!   it, it slides; the caller moves the grip with them (`GestureRig::regrip`).
//! - Equal weights for the three vertices (the centroid stays, not the centre of mass): the
//!   lumped masses differ by at most the boundary's factor 2.
//! - A moved vertex loses the part of its velocity against its move and keeps the rest (an
//!   inelastic projection): kept whole, that velocity drove the vertex back into the strain
//!   every frame and kept a held sheet awake; set from the move, it would add energy.
//! - Triangles, not edges: projecting edges within ±5 % was tried and left right triangles
//!   sheared to 16 % (edge lengths bound the stretch along three directions, not the shear).
//! - A projected triangle keeps the side of its normal at the frame's start: a (nearly)
//!   collapsed triangle's singular vectors could otherwise turn it over.
//! - Nor does it turn a neighbour over: a triangle the solve left turned nearly 90° from the
//!   frame's start can be pushed past it by a neighbour's projection; the vertices of any
//!   triangle so turned are put back where the solve left them (its strain stays; a turned
//!   triangle is a failed frame, a strained one is not).
//! - 32 passes at most: 8 left a triangle at 0.20 in one family performance where several
//!   grips met; the passes stop as soon as nothing is beyond the limit.

use nalgebra::{Matrix2, Matrix3x2};

use crate::math::V3;
use crate::metrics::triangle_strain;
use crate::sheet::measure::green_strain;
use crate::sheet::physical::PhysMesh;

/// Triangle strain (|λ − 1|) beyond which a triangle is projected.
pub const STRAIN_LIMIT: f64 = 0.08;
/// Principal stretch deviation (|λ − 1|) the projection brings a triangle back to.
pub const STRAIN_LIMIT_TO: f64 = 0.05;
/// Gauss–Seidel passes at most.
pub const STRAIN_LIMIT_PASSES: usize = 32;

/// Scratch for [`StrainLimit::apply`] (no allocation once sized).
#[derive(Clone, Debug, Default)]
pub struct StrainLimit {
    /// Vertices the last [`StrainLimit::apply`] moved.
    pub moved: Vec<bool>,
    flagged: Vec<usize>,
    start: Vec<V3>,
}

impl StrainLimit {
    /// Scratch with room for `num_vertices` and `num_triangles`.
    pub fn with_capacity(num_vertices: usize, num_triangles: usize) -> Self {
        Self {
            moved: Vec::with_capacity(num_vertices),
            flagged: Vec::with_capacity(num_triangles),
            start: Vec::with_capacity(num_vertices),
        }
    }

    /// Projects the edges of the triangles of `sp` strained beyond [`STRAIN_LIMIT`] (module
    /// doc); `vertex_strain` is [`crate::metrics::vertex_strains`] of `sp` (a triangle is
    /// checked only if one of its vertices exceeds the limit or has moved);
    /// `reference_normals` are the triangles' normals at the frame's start, whose side a
    /// projected triangle keeps (empty: its own). Marks the moved vertices in
    /// [`Self::moved`] and returns true if any moved.
    pub fn apply(
        &mut self,
        sp: &mut PhysMesh,
        vertex_strain: &[f64],
        reference_normals: &[V3],
    ) -> bool {
        self.moved.clear();
        self.moved.resize(sp.num_vertices(), false);
        if !vertex_strain.iter().any(|&s| s > STRAIN_LIMIT) {
            return false;
        }
        self.start.clone_from(&sp.pos);
        let mut any = false;
        for _ in 0..STRAIN_LIMIT_PASSES {
            self.flagged.clear();
            for (t, tri) in sp.triangles.iter().enumerate() {
                // Checked: triangles at a strained vertex, and those a move may have strained.
                if !tri.iter().any(|&v| {
                    self.moved[v as usize]
                        || vertex_strain
                            .get(v as usize)
                            .is_some_and(|&s| s > STRAIN_LIMIT)
                }) {
                    continue;
                }
                if triangle_strain(sp, t, tri.map(|i| sp.pos[i as usize])) > STRAIN_LIMIT {
                    self.flagged.push(t);
                }
            }
            if self.flagged.is_empty() {
                break;
            }
            for &t in &self.flagged {
                let tri = sp.triangles[t];
                let reference = reference_normals.get(t).copied().filter(|n| n.norm() > 0.0);
                if project_triangle(sp, t, reference) {
                    for v in tri {
                        self.moved[v as usize] = true;
                    }
                    any = true;
                }
            }
        }
        if any {
            self.undo_turns(sp, reference_normals);
        }
        // The velocity that drove a vertex into the strain goes with it (an inelastic
        // projection: the component against the move is removed, none is added).
        for ((v, x), x0) in sp.vel.iter_mut().zip(&sp.pos).zip(&self.start) {
            let d = x - x0;
            let n = d.norm();
            if n > 0.0 {
                let u = d / n;
                let into = v.dot(&u);
                if into < 0.0 {
                    *v -= u * into;
                }
            }
        }
        any
    }
}

impl StrainLimit {
    /// Puts back where they were the vertices of every triangle the projections turned over
    /// (its normal against `reference_normals`, or its start's, while it was not at the start):
    /// a projected triangle keeps its side, but its moves can push a neighbour already turned
    /// nearly 90° by the solve past it. Repeated until none is turned (each round puts back at
    /// least one moved vertex, so it ends; all of them back is the start).
    fn undo_turns(&mut self, sp: &mut PhysMesh, reference_normals: &[V3]) {
        let normal = |x: &[V3], tri: &[u32; 3]| {
            let [a, b, c] = tri.map(|i| x[i as usize]);
            (b - a).cross(&(c - a))
        };
        loop {
            let mut put_back = false;
            for (t, tri) in sp.triangles.iter().enumerate() {
                if !tri.iter().any(|&v| self.moved[v as usize]) {
                    continue;
                }
                let at_start = normal(&self.start, tri);
                let reference = reference_normals
                    .get(t)
                    .copied()
                    .filter(|n| n.norm() > 0.0)
                    .unwrap_or(at_start);
                let turned = |n: V3| n.dot(&reference) < 0.0;
                if turned(normal(&sp.pos, tri)) && !turned(at_start) {
                    for &v in tri {
                        let v = v as usize;
                        if self.moved[v] {
                            sp.pos[v] = self.start[v];
                            self.moved[v] = false;
                            put_back = true;
                        }
                    }
                }
            }
            if !put_back {
                break;
            }
        }
    }
}

/// Moves the vertices of triangle `t` to the nearest shape whose principal stretches lie
/// within [`STRAIN_LIMIT_TO`] of 1, keeping its centroid: the deformation gradient F = U Σ Vᵀ
/// with Σ clamped, applied to the pattern triangle, on the side of `reference_normal` (else of
/// its current normal). Returns true if it moved them.
fn project_triangle(sp: &mut PhysMesh, t: usize, reference_normal: Option<V3>) -> bool {
    let tri = sp.triangles[t].map(|i| i as usize);
    let x = tri.map(|i| sp.pos[i]);
    let (_, [f0, f1]) = green_strain(x, &sp.tri_rest[t]);
    let f = Matrix3x2::from_columns(&[f0, f1]);
    let svd = f.svd(true, true);
    let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
        return false;
    };
    let (lo, hi) = (1.0 - STRAIN_LIMIT_TO, 1.0 + STRAIN_LIMIT_TO);
    let sigma = svd.singular_values.map(|s| s.clamp(lo, hi));
    let mut f = u * Matrix2::from_diagonal(&sigma) * v_t;
    if !f.iter().all(|c| c.is_finite()) {
        return false;
    }
    let p = tri.map(|i| sp.pattern[i]);
    let pc = (p[0] + p[1] + p[2]) / 3.0;
    let xc = (x[0] + x[1] + x[2]) / 3.0;
    let place = |f: &Matrix3x2<f64>| p.map(|pk| xc + f * (pk - pc));
    let mut y = place(&f);
    // The projection keeps the triangle's side: a triangle (nearly) collapsed has no side of
    // its own, and its singular vectors could turn it over; then the second one is mirrored.
    let normal = |x: &[V3; 3]| (x[1] - x[0]).cross(&(x[2] - x[0]));
    let reference = reference_normal.unwrap_or_else(|| normal(&x));
    if normal(&y).dot(&reference) < 0.0 {
        let mut u = u;
        u.set_column(1, &(-u.column(1)));
        f = u * Matrix2::from_diagonal(&sigma) * v_t;
        y = place(&f);
    }
    for (k, &i) in tri.iter().enumerate() {
        sp.pos[i] = y[k];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::SheetSize;
    use crate::metrics::max_strain;
    use crate::sheet::{MeshConfig, Sheet};

    fn sheet() -> Sheet {
        Sheet::new_flat(SheetSize::Sq10, MeshConfig::default(), 0.0, 0.1)
    }

    #[test]
    fn a_stretched_sheet_is_brought_back_within_the_limit() {
        let mut s = sheet();
        // Pull one vertex a third of an edge outwards.
        let v = 0usize;
        let a = s.sp.topo.adjacency[s.sp.topo.adjacency_offsets[v] as usize] as usize;
        let d = s.sp.pos[v] - s.sp.pos[a];
        s.sp.pos[v] += d / 3.0;
        let before = max_strain(&s.sp, &s.sp.pos);
        assert!(before > STRAIN_LIMIT, "setup strains the sheet ({before})");
        let mut vs = Vec::new();
        crate::metrics::vertex_strains(&s.sp, &mut vs);
        let mut lim = StrainLimit::default();
        assert!(lim.apply(&mut s.sp, &vs, &[]));
        let after = max_strain(&s.sp, &s.sp.pos);
        assert!(after <= STRAIN_LIMIT, "strain {before} -> {after}");
        assert!(lim.moved[v]);
    }

    #[test]
    fn the_projections_turn_no_neighbour_over() {
        // Each triangle's reference normal 0.2° short of lying in the sheet: a flat sheet is
        // on its side of every one, and any neighbour a projection tilts the wrong way by
        // 0.2° would turn over. Randomly lifted vertices strain many triangles.
        use rand::{RngExt, SeedableRng};
        for seed in 0..20u64 {
            let mut rng = rand_pcg::Pcg32::seed_from_u64(seed);
            let mut s = sheet();
            let reference: Vec<V3> = (0..s.sp.num_triangles())
                .map(|_| {
                    let phi = rng.random_range(0.0..std::f64::consts::TAU);
                    let theta = (90.0f64 - 0.2).to_radians();
                    V3::new(
                        phi.cos() * theta.sin(),
                        phi.sin() * theta.sin(),
                        theta.cos(),
                    )
                })
                .collect();
            for x in s.sp.pos.iter_mut() {
                if rng.random_range(0..4u32) == 0 {
                    x.z += rng.random_range(-0.004..0.004);
                }
            }
            let start = s.sp.pos.clone();
            let mut vs = Vec::new();
            crate::metrics::vertex_strains(&s.sp, &mut vs);
            let mut lim = StrainLimit::default();
            assert!(
                lim.apply(&mut s.sp, &vs, &reference),
                "seed {seed}: nothing strained"
            );
            for (t, tri) in s.sp.triangles.iter().enumerate() {
                let n = |x: &[V3]| {
                    let [a, b, c] = tri.map(|i| x[i as usize]);
                    (b - a).cross(&(c - a))
                };
                if n(&start).dot(&reference[t]) >= 0.0 {
                    assert!(
                        n(&s.sp.pos).dot(&reference[t]) >= 0.0,
                        "seed {seed}: triangle {t} turned"
                    );
                }
            }
        }
    }

    #[test]
    fn a_sheet_within_the_limit_is_left_alone() {
        let mut s = sheet();
        s.sp.pos[7].z += 0.001;
        let pos = s.sp.pos.clone();
        let mut vs = Vec::new();
        crate::metrics::vertex_strains(&s.sp, &mut vs);
        let mut lim = StrainLimit::default();
        assert!(!lim.apply(&mut s.sp, &vs, &[]));
        assert_eq!(s.sp.pos, pos);
        assert!(lim.moved.iter().all(|m| !m));
    }
}
