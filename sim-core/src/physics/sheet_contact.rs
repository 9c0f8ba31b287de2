//! # Sheet–sheet contact: the paper does not pass through itself
//!
//! The seeds have no sheet–sheet contact: they stop crumpling before the sheet could pass
//! through itself (T 1245, T 2014, T 2076; digest-tearing §4.3). The gesture rig does the same
//! ([`crate::gesture_rig`] "Crumple cap", [`crate::self_proximity`]), and a frame that would
//! still cross is undone by the sim's pass-through guard. A cap can only stop a squeeze; it
//! cannot hold two layers apart that the sheet's own motion brings together (a fold settling,
//! a layer sliding over another, a held ball pressed on). This module is that force: two parts
//! of the sheet closer than [`SHEET_CONTACT_DIST_M`] push apart.
//!
//! ## Model (impl. choice: penalty on separating planes, frozen per substep)
//!
//! At the start of every substep the sheet is searched for **contact pairs**: a vertex and a
//! triangle it does not belong to, or two edges with no common vertex, closer than a reach
//! that covers this substep's travel. Each pair is frozen as a stencil of four vertices with
//! weights w_i and a unit normal n from its closest points (vertex − triangle point, or edge
//! point − edge point), so that its gap is linear in the positions:
//!
//! ```text
//! g(x) = n · Σ_i w_i x_i          vertex–triangle: w = (1, −β_a, −β_b, −β_c)  (β: barycentric)
//!                                  edge–edge:       w = (1 − s, s, −(1 − t), −t)
//! E_pair(x) = ½ k (d̂ − g)²                     if g < d̂
//! ```
//!
//! with d̂ = [`SHEET_CONTACT_DIST_M`] and k = m ω_c² from the pair's mass (½ Σ |w_i| m_i) —
//! the obstacles' soft contact stiffness ([`crate::collision`]) without their hard stage: a
//! layer caught between an obstacle and another layer must yield to the obstacle (with a hard
//! stage a held crumpled sheet was pressed into a rising table; docs/decisions.md, "Sheet–sheet
//! contact: soft only, stiffened where it crossed"). g ≥ d̂ is the
//! half-space beyond the pair's separating plane, the usual linearization of a distance
//! constraint over one time step. It is added to the incremental potential of
//! [`crate::physics`], so the Newton solver's line search treats it like every other term.
//! Its Hessian k (w ⊗ n)(w ⊗ n)ᵀ couples the pair's vertices, which the fixed sparsity
//! pattern of the Cholesky solve does not hold. It is rank one, so the solve takes it whole
//! through the Woodbury identity ([`crate::physics::sparse::BlockSystem::add_rank_one`]) for up
//! to `SolverConfig::contact_coupling_pairs` active pairs (32); pairs beyond that add only
//! their diagonal blocks k w_i² n nᵀ (positive semi-definite, so the Newton direction stays a
//! descent direction). The diagonal blocks alone are a poor model where layers lie on each
//! other: a motion that carries both layers along leaves the gap unchanged, yet the blocks
//! charge each vertex k ≈ 400 m/h² for it, and Newton creeps by micrometre steps to its
//! iteration cap (the figures: docs/decisions.md, "Contact coupling: 32 pairs";
//! `sim-core/tests/contact_solve.rs` checks S4's first 400 frames).
//!
//! **Which pairs.** Two parts of the sheet that are close *in the pattern* are close in 3D by
//! construction (a developable sheet is an isometry of its pattern, which never lengthens a
//! distance): they are one patch, not two layers. Pairs closer than
//! [`MIN_PATTERN_GAP_FACTOR`]·d̂ in the pattern are therefore skipped, so a flat sheet — and the
//! tiny triangles around an inserted vertex — feel no contact at rest. Everything farther apart
//! in the pattern is a candidate, however the sheet is folded; in particular a sharp fold at
//! one lattice edge meets the next triangle across the fold and stops short of folding through
//! it. Pairs whose distance is zero at the start of the substep (already crossed) are left to
//! the sim's pass-through guard: no normal can tell which side they came from.
//!
//! **Stiffening where the sheet crossed (impl. choice, after IPC's adaptive stiffness).** A
//! penalty is finite: pressed hard enough — a fold's stored bending energy, or a hand's hard
//! constraint on the other side — two layers pass through each other, and the sim's
//! pass-through guard undoes the frame. Going back to the frame's start does not remove the
//! cause, and the replay crossed again, frame after frame: the pair was found and simply
//! pushed through, and more substeps did not help. So an undone frame stiffens the contact
//! where it crossed: every pair whose vertices all belong to two triangles that crossed gets
//! its k multiplied by [`BOOST_STEP`] (×4, again on each repeat, up to [`MAX_BOOST`]) for
//! [`BOOST_FRAMES`] frames (1 s) after the last crossing, and the replay holds the layers
//! apart (docs/decisions.md, "Sheet–sheet contact: soft only, stiffened where it crossed"). At
//! most [`MAX_BOOSTS`] boosts are kept (preallocated, the oldest goes); they
//! are saved with the sheet and kept across a vertex insertion (old vertices keep their
//! index).
//!
//! **Approximations, said plainly.** No friction between layers (they slide freely); the
//! separating planes are fixed within a substep, so a layer moving faster than the reach in
//! one substep can tunnel (the reach grows with the substep's fastest vertex, up to
//! [`MAX_REACH_M`]); paper thickness is not modelled, d̂ is a numerical skin.
//!
//! **Cost and allocation.** Broad phase: vertices and triangles, and edges among themselves,
//! sorted along the axis of the sheet's largest extent and swept with boxes grown by the
//! reach. The boxes are kept in sweep order in one array, sweep axis first, and a box apart
//! by more than the reach along any axis is skipped before anything is measured. Narrow phase:
//! a cheap lower bound first — the point's distance from the triangle's plane, the distance
//! between the two edges' lines — then the exact closest features of
//! [`crate::triangle_distance`], which most pairs that pass the boxes never reach. The bounds
//! carry a relative margin, so the pairs found are the same, in the same order, as without
//! them, and they are forced inline, since left to the compiler their speed varied from one
//! build to the next (figures: docs/benchmarks.md, "Contact queries" and "Query figures moved
//! from the module docs"). On a sheet that is nowhere folded over no
//! pair survives, and a pair that never comes within d̂ adds exactly nothing (the solve is
//! bit-identical to one without contact). Buffers are sized in [`SheetContact::new`]; pairs
//! beyond their capacity are dropped (counted), never allocated.

use crate::collision::penalty_stiffness;
use crate::math::{M3, V3};
use crate::sheet::physical::PhysMesh;
use crate::triangle_distance::{
    line_line_gap_m, point_plane_gap_m, point_triangle, segment_segment,
};

/// Contact distance d̂: two parts of the sheet closer than this push apart, metres.
pub const SHEET_CONTACT_DIST_M: f64 = 1.5e-3;
/// Pairs closer than this multiple of d̂ in the pattern are one patch, not two layers.
pub const MIN_PATTERN_GAP_FACTOR: f64 = 2.0;
/// Smallest search reach beyond d̂, metres.
pub const MIN_REACH_M: f64 = 2e-3;
/// Largest search reach beyond d̂, metres.
pub const MAX_REACH_M: f64 = 2e-2;
/// Pairs kept per vertex + edge of the mesh (beyond that they are dropped and counted).
const PAIRS_PER_ELEMENT: usize = 16;
/// Relative margin on the cheap lower bounds of a pair's distance (rounding), so that they
/// reject only pairs the exact distance rejects as well.
const GAP_BOUND_MARGIN: f64 = 1e-9;
/// Pairs closer than this at the start of a substep have crossed already: no normal.
const CROSSED_M: f64 = 1e-7;

/// One frozen contact pair: gap g = n · Σ w_i x_{v_i}.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheetPair {
    /// Stencil vertices (vertex–triangle: the vertex, then the triangle's three; edge–edge:
    /// the first edge's two, then the second's).
    pub v: [u32; 4],
    /// Stencil weights (sum 0: a rigid translation leaves the gap unchanged).
    pub w: [f64; 4],
    /// Unit normal of the separating plane, from the second part towards the first.
    pub n: V3,
    /// Soft-stage stiffness k, N/m.
    pub k_n_m: f64,
}

impl SheetPair {
    /// Gap at positions `x`, metres.
    #[inline]
    pub fn gap_m(&self, x: &[V3]) -> f64 {
        let mut p = V3::zeros();
        for (&v, &w) in self.v.iter().zip(&self.w) {
            p += x[v as usize] * w;
        }
        self.n.dot(&p)
    }

    /// Energy and its derivative along the gap, (E, dE/dg), at gap `g`; also the second
    /// derivative d²E/dg².
    #[inline]
    pub fn energy_of_gap(&self, g: f64) -> (f64, f64, f64) {
        let pen = SHEET_CONTACT_DIST_M - g;
        if pen <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let k = self.k_n_m;
        (0.5 * k * pen * pen, -k * pen, k)
    }

    /// Adds the pair's energy gradient into `grad`, skipping `fixed` vertices, and hands its
    /// Hessian `d²E/dg² · (w ⊗ n)(w ⊗ n)ᵀ` to `hess` as `(self, d²E/dg²)`; returns the energy
    /// (0 if inactive, and then `hess` is not called).
    #[inline]
    pub fn accumulate(
        &self,
        x: &[V3],
        fixed: &[bool],
        grad: &mut [V3],
        mut hess: impl FnMut(&SheetPair, f64),
    ) -> f64 {
        let (e, de, d2e) = self.energy_of_gap(self.gap_m(x));
        if e == 0.0 {
            return 0.0;
        }
        for (&v, &w) in self.v.iter().zip(&self.w) {
            if !fixed[v as usize] {
                grad[v as usize] += self.n * (de * w);
            }
        }
        hess(self, d2e);
        e
    }

    /// The diagonal blocks `d2e · w_i² n nᵀ` of the pair's Hessian, through `diag(vertex,
    /// block)`, skipping `fixed` vertices: the fallback when its rank-one term does not fit
    /// the solver's low-rank capacity.
    pub fn diagonal_blocks(&self, d2e: f64, fixed: &[bool], mut diag: impl FnMut(u32, &M3)) {
        let nn = self.n * self.n.transpose();
        for (&v, &w) in self.v.iter().zip(&self.w) {
            if !fixed[v as usize] && w != 0.0 {
                diag(v, &(nn * (d2e * w * w)));
            }
        }
    }
}

/// Pair search with reusable buffers.
#[derive(Clone, Debug, Default)]
pub struct SheetContact {
    /// Vertex indices sorted along the sweep axis.
    v_order: Vec<u32>,
    /// The triangles' boxes, sorted by their lower end along the sweep axis, sweep axis
    /// first (the sweeps read them one after the other).
    t_sorted: Vec<SweepBox>,
    /// The edges' boxes, sorted the same way.
    e_sorted: Vec<SweepBox>,
    /// The pairs of the current substep.
    pairs: Vec<SheetPair>,
    /// Pairs dropped since creation because the buffer was full.
    pub dropped: u64,
    /// Stiffness boosts of the layers that crossed in undone frames.
    boosts: Vec<Boost>,
}

/// A stiffness boost for the pairs among the six vertices of two triangles that crossed
/// (saved with the sheet: a continuation must see the same stiffness).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Boost {
    /// The two triangles' vertices, sorted.
    pub verts: [u32; 6],
    /// Stiffness factor, 1–[`MAX_BOOST`].
    pub factor: f64,
    /// Frames left before it expires, 1–[`BOOST_FRAMES`].
    pub frames_left: u32,
}

/// Boosts kept at once (the oldest goes when full).
pub const MAX_BOOSTS: usize = 32;
/// A crossing multiplies its pairs' stiffness by this (again on every repeat).
pub const BOOST_STEP: f64 = 4.0;
/// Largest boost.
pub const MAX_BOOST: f64 = 4096.0;
/// Frames a boost lasts after its last crossing.
pub const BOOST_FRAMES: u32 = 200;

impl SheetContact {
    /// Buffers for a mesh (allocates; the search never does).
    pub fn new(mesh: &PhysMesh) -> Self {
        let (nv, nt, ne) = (mesh.num_vertices(), mesh.num_triangles(), mesh.num_edges());
        Self {
            v_order: Vec::with_capacity(nv),
            t_sorted: Vec::with_capacity(nt),
            e_sorted: Vec::with_capacity(ne),
            pairs: Vec::with_capacity(PAIRS_PER_ELEMENT * (nv + ne)),
            dropped: 0,
            boosts: Vec::with_capacity(MAX_BOOSTS),
        }
    }

    /// Triangles `a` and `b` crossed: stiffen the pairs among their vertices.
    pub fn boost_crossing(&mut self, a: [u32; 3], b: [u32; 3]) {
        let mut verts = [a[0], a[1], a[2], b[0], b[1], b[2]];
        verts.sort_unstable();
        if let Some(bo) = self.boosts.iter_mut().find(|bo| bo.verts == verts) {
            bo.factor = (bo.factor * BOOST_STEP).min(MAX_BOOST);
            bo.frames_left = BOOST_FRAMES;
            return;
        }
        if self.boosts.len() == MAX_BOOSTS {
            let (i, _) = self
                .boosts
                .iter()
                .enumerate()
                .min_by_key(|(i, bo)| (bo.frames_left, *i))
                .expect("full");
            self.boosts.remove(i);
        }
        self.boosts.push(Boost {
            verts,
            factor: BOOST_STEP,
            frames_left: BOOST_FRAMES,
        });
    }

    /// One frame passed: boosts age and expire.
    pub fn age_boosts(&mut self) {
        for bo in &mut self.boosts {
            bo.frames_left = bo.frames_left.saturating_sub(1);
        }
        self.boosts.retain(|bo| bo.frames_left > 0);
    }

    /// Drops every boost.
    pub fn clear_boosts(&mut self) {
        self.boosts.clear();
    }

    /// The active boosts.
    pub fn boosts(&self) -> &[Boost] {
        &self.boosts
    }

    /// Replaces the active boosts (a restored sheet); refuses entries out of range for a
    /// mesh of `num_vertices`.
    pub fn set_boosts(&mut self, boosts: &[Boost], num_vertices: usize) -> Result<(), String> {
        if boosts.len() > MAX_BOOSTS {
            return Err(format!(
                "{} contact boosts, at most {MAX_BOOSTS}",
                boosts.len()
            ));
        }
        for b in boosts {
            let ok = b.verts.iter().all(|&v| (v as usize) < num_vertices)
                && b.verts.is_sorted()
                && b.factor.is_finite()
                && (1.0..=MAX_BOOST).contains(&b.factor)
                && (1..=BOOST_FRAMES).contains(&b.frames_left);
            if !ok {
                return Err(format!("invalid contact boost {b:?}"));
            }
        }
        self.boosts.clear();
        self.boosts.extend_from_slice(boosts);
        Ok(())
    }

    fn boost_of(&self, p: &SheetPair) -> f64 {
        let mut f = 1.0f64;
        for bo in &self.boosts {
            if p.v
                .iter()
                .zip(&p.w)
                .all(|(v, &w)| w == 0.0 || bo.verts.binary_search(v).is_ok())
            {
                f = f.max(bo.factor);
            }
        }
        f
    }

    /// The pairs found by the last [`Self::find`].
    pub fn pairs(&self) -> &[SheetPair] {
        &self.pairs
    }

    /// Forgets all pairs (contact off).
    pub fn clear(&mut self) {
        self.pairs.clear();
    }

    /// Finds the contact pairs of `mesh` at its current positions within d̂ + `reach_m`
    /// (clamped to [`MIN_REACH_M`]–[`MAX_REACH_M`]).
    pub fn find(&mut self, mesh: &PhysMesh, reach_m: f64) {
        self.pairs.clear();
        let x = &mesh.pos;
        if x.is_empty() || mesh.triangles.is_empty() {
            return;
        }
        let reach_m = if reach_m.is_finite() {
            reach_m.clamp(MIN_REACH_M, MAX_REACH_M)
        } else {
            MAX_REACH_M
        } + SHEET_CONTACT_DIST_M;
        let (lo, hi) = x
            .iter()
            .fold((x[0], x[0]), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
        let ext = hi - lo;
        let axis = ext.imax();
        let min_gap = MIN_PATTERN_GAP_FACTOR * SHEET_CONTACT_DIST_M;

        let others = [(axis + 1) % 3, (axis + 2) % 3];
        let sweep_box = |l: V3, h: V3, id: usize| SweepBox {
            lo: [l[axis], l[others[0]], l[others[1]]],
            hi: [h[axis], h[others[0]], h[others[1]]],
            id: id as u32,
        };
        // Sorted by the lower end along the sweep axis, then index: one order, however the
        // sort runs.
        let by_lower_end =
            |a: &SweepBox, b: &SweepBox| a.lo[0].total_cmp(&b.lo[0]).then(a.id.cmp(&b.id));
        self.t_sorted.clear();
        self.t_sorted
            .extend(mesh.triangles.iter().enumerate().map(|(i, t)| {
                let [a, b, c] = t.map(|v| x[v as usize]);
                sweep_box(a.inf(&b).inf(&c), a.sup(&b).sup(&c), i)
            }));
        self.t_sorted.sort_unstable_by(by_lower_end);
        self.e_sorted.clear();
        self.e_sorted
            .extend(mesh.topo.edges.iter().enumerate().map(|(i, e)| {
                let [a, b] = e.v.map(|v| x[v as usize]);
                sweep_box(a.inf(&b), a.sup(&b), i)
            }));
        self.e_sorted.sort_unstable_by(by_lower_end);
        self.v_order.clear();
        self.v_order.extend(0..x.len() as u32);
        self.v_order
            .sort_unstable_by(|&a, &b| x[a as usize][axis].total_cmp(&x[b as usize][axis]));
        let cap = self.pairs.capacity();
        let mut dropped = 0u64;

        // Vertex–triangle: a triangle's box starts at most `max_w` before its end.
        let max_w = self
            .t_sorted
            .iter()
            .map(|b| b.hi[0] - b.lo[0])
            .fold(0.0, f64::max);
        let t_sorted = &self.t_sorted;
        for &v in &self.v_order {
            let q = x[v as usize];
            let p = [q[axis], q[others[0]], q[others[1]]];
            let from = p[0] - reach_m - max_w;
            let start = t_sorted.partition_point(|b| b.lo[0] < from);
            for b in &t_sorted[start..] {
                if b.lo[0] > p[0] + reach_m {
                    break;
                }
                // The box starts before the point plus the reach (above); it may end before
                // the point minus the reach (the window starts a box width earlier).
                if (p[0] - b.hi[0] > reach_m) | b.apart_across(&p, &p, reach_m) {
                    continue;
                }
                let tri = mesh.triangles[b.id as usize];
                if tri.contains(&v) {
                    continue;
                }
                if let Some(pair) = vertex_triangle(mesh, v, tri, reach_m, min_gap) {
                    if self.pairs.len() < cap {
                        self.pairs.push(pair);
                    } else {
                        dropped += 1;
                    }
                }
            }
        }

        // Edge–edge: a forward sweep over the sorted edges.
        let e_sorted = &self.e_sorted;
        for (i, a) in e_sorted.iter().enumerate() {
            let ea = mesh.topo.edges[a.id as usize].v;
            for b in &e_sorted[i + 1..] {
                if b.lo[0] > a.hi[0] + reach_m {
                    break;
                }
                // Along the sweep axis the boxes overlap within the reach: `b` starts after `a`
                // starts and before `a` ends plus the reach.
                if b.apart_across(&a.lo, &a.hi, reach_m) {
                    continue;
                }
                let eb = mesh.topo.edges[b.id as usize].v;
                if ea.iter().any(|v| eb.contains(v)) {
                    continue;
                }
                if let Some(pair) = edge_edge(mesh, ea, eb, reach_m, min_gap) {
                    if self.pairs.len() < cap {
                        self.pairs.push(pair);
                    } else {
                        dropped += 1;
                    }
                }
            }
        }
        self.dropped += dropped;
        if !self.boosts.is_empty() {
            for i in 0..self.pairs.len() {
                let f = self.boost_of(&self.pairs[i]);
                self.pairs[i].k_n_m *= f;
            }
        }
    }
}

/// An element's box in a sweep, its coordinates ordered sweep axis first.
#[derive(Clone, Copy, Debug)]
struct SweepBox {
    lo: [f64; 3],
    hi: [f64; 3],
    /// The element (triangle or edge) index.
    id: u32,
}

impl SweepBox {
    /// Whether this box lies farther than `reach_m` from the box `lo`–`hi` along one of the two
    /// axes across the sweep (the sweep itself handles the sweep axis, where most of the
    /// comparisons would be known already). Four comparisons without branches: most boxes a
    /// sweep meets are apart along one axis or the other, and which one is unpredictable.
    #[inline]
    fn apart_across(&self, lo: &[f64; 3], hi: &[f64; 3], reach_m: f64) -> bool {
        (self.lo[1] - hi[1] > reach_m)
            | (lo[1] - self.hi[1] > reach_m)
            | (self.lo[2] - hi[2] > reach_m)
            | (lo[2] - self.hi[2] > reach_m)
    }
}

/// Pattern point of vertex `i` in the plane z = 0.
#[inline]
fn pat(mesh: &PhysMesh, i: u32) -> V3 {
    let p = mesh.pattern[i as usize];
    V3::new(p.x, p.y, 0.0)
}

/// Soft-stage stiffness of a stencil: k = m ω_c² with m = ½ Σ |w_i| m_i.
fn stiffness(mesh: &PhysMesh, v: &[u32; 4], w: &[f64; 4]) -> f64 {
    let m: f64 = v
        .iter()
        .zip(w)
        .map(|(&i, &wi)| wi.abs() * mesh.mass_kg[i as usize])
        .sum();
    penalty_stiffness(0.5 * m)
}

/// The pair of vertex `v` and triangle `tri` if they are closer than `reach_m` in 3D and at
/// least `min_gap_m` apart in the pattern.
fn vertex_triangle(
    mesh: &PhysMesh,
    v: u32,
    tri: [u32; 3],
    reach_m: f64,
    min_gap_m: f64,
) -> Option<SheetPair> {
    let p = mesh.pos[v as usize];
    let t = tri.map(|i| mesh.pos[i as usize]);
    // Farther than the reach from the triangle's plane: no need to project (the margin keeps
    // every pair the projection would keep).
    if point_plane_gap_m(p, t) > reach_m * (1.0 + GAP_BOUND_MARGIN) {
        return None;
    }
    let (d, beta) = point_triangle(p, t);
    if d >= reach_m || d < CROSSED_M {
        return None;
    }
    let q: V3 = tri
        .iter()
        .zip(&beta)
        .map(|(&i, &w)| mesh.pos[i as usize] * w)
        .sum();
    let n = (p - q) / d;
    // One patch in the pattern: no contact.
    let (gap, _) = point_triangle(pat(mesh, v), tri.map(|i| pat(mesh, i)));
    if gap < min_gap_m {
        return None;
    }
    let vs = [v, tri[0], tri[1], tri[2]];
    let w = [1.0, -beta[0], -beta[1], -beta[2]];
    Some(SheetPair {
        v: vs,
        w,
        n,
        k_n_m: stiffness(mesh, &vs, &w),
    })
}

/// The pair of edges `ea` and `eb` (no common vertex) if they are closer than `reach_m` in 3D
/// and at least `min_gap_m` apart in the pattern.
fn edge_edge(
    mesh: &PhysMesh,
    ea: [u32; 2],
    eb: [u32; 2],
    reach_m: f64,
    min_gap_m: f64,
) -> Option<SheetPair> {
    let (a, b) = (
        ea.map(|i| mesh.pos[i as usize]),
        eb.map(|i| mesh.pos[i as usize]),
    );
    // Lines farther apart than the reach: so are the segments.
    if line_line_gap_m(a, b) > reach_m * (1.0 + GAP_BOUND_MARGIN) {
        return None;
    }
    let (d, sa, sb) = segment_segment(a, b);
    if d >= reach_m || d < CROSSED_M {
        return None;
    }
    let pa = mesh.pos[ea[0] as usize] * sa[0] + mesh.pos[ea[1] as usize] * sa[1];
    let pb = mesh.pos[eb[0] as usize] * sb[0] + mesh.pos[eb[1] as usize] * sb[1];
    let n = (pa - pb) / d;
    // One patch in the pattern: no contact. (Closest points at an end of an edge duplicate a
    // vertex–triangle pair; keeping both only doubles a stiffness locally.)
    let (gap, _, _) = segment_segment(ea.map(|i| pat(mesh, i)), eb.map(|i| pat(mesh, i)));
    if gap < min_gap_m {
        return None;
    }
    let vs = [ea[0], ea[1], eb[0], eb[1]];
    let w = [sa[0], sa[1], -sb[0], -sb[1]];
    Some(SheetPair {
        v: vs,
        w,
        n,
        k_n_m: stiffness(mesh, &vs, &w),
    })
}

/// Share of a pair a stencil vertex must carry (|w_i|) to count as sliding with it.
const SLIDING_WEIGHT: f64 = 0.25;

/// How fast each vertex slides on another layer it is pressed on (the layers' friction sound,
/// `sound_analysis/friction_events.rs`): for every pair of `pairs` still within d̂ at positions
/// `x`, its relative tangential speed |(I − n nᵀ) Σ w_i v_i| (the weights sum to 0, so this is
/// the vertex's or edge point's speed relative to the other layer), given to each stencil vertex
/// that carries at least a quarter of the pair, the fastest of its pairs. `out[v]` is negative
/// where a vertex is pressed on no layer. Pairs naming vertices beyond `x` (a stale pair set
/// after a mesh change) are skipped.
pub fn layer_slip(pairs: &[SheetPair], x: &[V3], vel: &[V3], out: &mut [f32]) {
    out.fill(-1.0);
    let n = x.len().min(vel.len()).min(out.len());
    for pair in pairs {
        if pair.v.iter().any(|&v| v as usize >= n) || pair.gap_m(x) >= SHEET_CONTACT_DIST_M {
            continue;
        }
        let rel: V3 = pair
            .v
            .iter()
            .zip(&pair.w)
            .map(|(&v, &w)| vel[v as usize] * w)
            .sum();
        let slip = (rel - pair.n * rel.dot(&pair.n)).norm() as f32;
        for (&v, &w) in pair.v.iter().zip(&pair.w) {
            if w.abs() >= SLIDING_WEIGHT {
                let s = &mut out[v as usize];
                *s = s.max(slip);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::SheetSize;
    use crate::math::V2;
    use crate::sheet::{MeshConfig, Sheet};

    fn sheet() -> Sheet {
        Sheet::new_flat(SheetSize::A4, MeshConfig::default(), 0.0, 0.08)
    }

    /// The sheet folded about x = 0 onto a layer 1 mm above the other half.
    fn folded_sheet() -> Sheet {
        let mut s = sheet();
        for p in &mut s.sp.pos {
            if p.x < 0.0 {
                *p = V3::new(-p.x, p.y, 1e-3);
            }
        }
        s
    }

    #[test]
    fn layers_pressed_together_slide_at_their_relative_tangential_speed() {
        let s = folded_sheet();
        let mut c = SheetContact::new(&s.sp);
        c.find(&s.sp, MIN_REACH_M);
        assert!(!c.pairs().is_empty());
        let n = s.sp.num_vertices();
        let top = |i: usize| s.sp.pos[i].z > 0.5e-3;
        let mut out = vec![0.0f32; n];
        // The top layer slides along y at 5 cm/s and sinks at 3 cm/s; the bottom one is still.
        let vel: Vec<V3> = (0..n)
            .map(|i| {
                if top(i) {
                    V3::new(0.0, 0.05, -0.03)
                } else {
                    V3::zeros()
                }
            })
            .collect();
        layer_slip(c.pairs(), &s.sp.pos, &vel, &mut out);
        let pressed: Vec<usize> = (0..n).filter(|&i| out[i] >= 0.0).collect();
        assert!(pressed.iter().any(|&i| top(i)) && pressed.iter().any(|&i| !top(i)));
        // Vertices well inside both layers see the slip; the sinking does not count (an edge
        // pair's normal may lean a little: 2 %).
        let inner = |i: usize| s.sp.pos[i].x > 0.03 && s.sp.pos[i].y.abs() < 0.1;
        let inside: Vec<usize> = pressed.iter().copied().filter(|&i| inner(i)).collect();
        assert!(inside.len() > 10, "{}", inside.len());
        for &i in &inside {
            assert!((out[i] - 0.05).abs() < 1e-3, "vertex {i}: {}", out[i]);
        }
        // Both layers moving together do not slide; nothing is pressed once they part.
        let together = vec![V3::new(0.0, 0.05, -0.01); n];
        layer_slip(c.pairs(), &s.sp.pos, &together, &mut out);
        assert!(out.iter().all(|&v| v < 1e-9));
        let mut apart = s.sp.pos.clone();
        for (i, p) in apart.iter_mut().enumerate() {
            if top(i) {
                p.z += 0.01;
            }
        }
        layer_slip(c.pairs(), &apart, &vel, &mut out);
        assert!(out.iter().all(|&v| v < 0.0));
    }

    #[test]
    fn a_flat_sheet_has_no_active_pairs() {
        let s = sheet();
        let mut c = SheetContact::new(&s.sp);
        c.find(&s.sp, MIN_REACH_M);
        assert!(c.pairs().is_empty(), "{:?}", c.pairs().first());
        // A long reach finds neighbours across the lattice, none of them within d̂.
        c.find(&s.sp, MAX_REACH_M);
        assert!(!c.pairs().is_empty());
        assert!(
            c.pairs()
                .iter()
                .all(|p| p.gap_m(&s.sp.pos) > SHEET_CONTACT_DIST_M)
        );
    }

    #[test]
    fn a_sheet_folded_onto_itself_finds_pairs_that_push_apart() {
        let s = folded_sheet();
        let mut c = SheetContact::new(&s.sp);
        c.find(&s.sp, MIN_REACH_M);
        assert!(!c.pairs().is_empty());
        let mut grad = vec![V3::zeros(); s.sp.num_vertices()];
        let fixed = vec![false; s.sp.num_vertices()];
        let mut e = 0.0;
        for pair in c.pairs() {
            assert!((pair.w.iter().sum::<f64>()).abs() < 1e-6);
            assert!((pair.n.norm() - 1.0).abs() < 1e-9);
            e += pair.accumulate(&s.sp.pos, &fixed, &mut grad, |_, _| {});
        }
        assert!(e > 0.0);
        // The upper layer is pushed up, the lower one down (−gradient = force).
        let up: f64 =
            s.sp.pos
                .iter()
                .zip(&grad)
                .filter(|(p, _)| p.z > 0.5e-3)
                .map(|(_, g)| -g.z)
                .sum();
        let down: f64 =
            s.sp.pos
                .iter()
                .zip(&grad)
                .filter(|(p, _)| p.z < 0.5e-3 && p.x > 1e-6)
                .map(|(_, g)| -g.z)
                .sum();
        assert!(up > 0.0 && down < 0.0, "up {up} down {down}");
    }

    /// A crossing stiffens exactly the pairs among the two crossed triangles' vertices, by
    /// [`BOOST_STEP`] and again on a repeat, and the boost expires [`BOOST_FRAMES`] frames
    /// after the last crossing. Detects a boost that stiffens nothing (the undo loop it breaks
    /// comes back), one that stiffens the whole sheet, or one that never ends.
    #[test]
    fn a_crossing_stiffens_its_pairs_until_the_boost_expires() {
        let s = folded_sheet();
        let mut c = SheetContact::new(&s.sp);
        c.find(&s.sp, MIN_REACH_M);
        let base: Vec<SheetPair> = c.pairs().to_vec();
        assert!(base.len() > 4);
        // The two triangles of the first vertex–triangle pair: one holding its vertex, the
        // other the pair's triangle.
        let p0 = *base
            .iter()
            .find(|p| p.w[0] == 1.0)
            .expect("a vertex–triangle pair");
        let tri_b = [p0.v[1], p0.v[2], p0.v[3]];
        let tri_a = *s
            .sp
            .triangles
            .iter()
            .find(|t| t.contains(&p0.v[0]))
            .unwrap();
        let inside = |p: &SheetPair| {
            p.v.iter()
                .zip(&p.w)
                .all(|(v, &w)| w == 0.0 || tri_a.contains(v) || tri_b.contains(v))
        };
        let factors = |c: &SheetContact| -> Vec<f64> {
            c.pairs()
                .iter()
                .zip(&base)
                .map(|(p, b)| {
                    assert_eq!((p.v, p.w), (b.v, b.w));
                    p.k_n_m / b.k_n_m
                })
                .collect()
        };
        c.boost_crossing(tri_a, tri_b);
        c.find(&s.sp, MIN_REACH_M);
        let f = factors(&c);
        for (b, &k) in base.iter().zip(&f) {
            let want = if inside(b) { BOOST_STEP } else { 1.0 };
            assert!((k - want).abs() < 1e-12, "{b:?}: ×{k}");
        }
        assert!(f.iter().any(|&k| k > 1.0) && f.contains(&1.0));
        // The same crossing again (either order): stiffer still.
        c.boost_crossing(tri_b, tri_a);
        c.find(&s.sp, MIN_REACH_M);
        let top = factors(&c).into_iter().fold(0.0, f64::max);
        assert!((top - BOOST_STEP * BOOST_STEP).abs() < 1e-9, "×{top}");
        for _ in 1..BOOST_FRAMES {
            c.age_boosts();
        }
        c.find(&s.sp, MIN_REACH_M);
        assert!(factors(&c).iter().any(|&k| k > 1.0), "expired early");
        c.age_boosts();
        c.find(&s.sp, MIN_REACH_M);
        assert!(factors(&c).iter().all(|&k| k == 1.0), "never expires");
        // A full table replaces its oldest entry, never grows.
        for i in 0..2 * MAX_BOOSTS as u32 {
            c.boost_crossing([i, i + 1, i + 2], [i + 3, i + 4, i + 5]);
        }
        assert_eq!(c.boosts.len(), MAX_BOOSTS);
        assert!(c.boosts.capacity() == MAX_BOOSTS);
    }

    /// Two pieces of paper, one held 3 mm above the other and driven down at 0.5 m/s into it:
    /// with contact the free lower piece is pushed ahead and the two never cross; without, the upper one passes through (so the test can fail).
    #[test]
    fn a_piece_driven_onto_another_pushes_it_ahead() {
        use crate::collision::Obstacles;
        use crate::control::Material;
        use crate::material::PaperMaterial;
        use crate::physics::{Kinematics, PhysParams, Physics, SolverConfig};
        use crate::room::RoomConfig;
        use crate::self_proximity::SelfProximity;
        use crate::sheet::pattern::{Pattern, lattice};

        // Two 10 cm pieces side by side in the pattern (far apart there: two layers).
        let piece = lattice(0.1, 0.1, 0.02);
        let n = piece.points.len() as u32;
        let shift = V2::new(0.15, 0.0);
        let pattern = Pattern {
            points: piece
                .points
                .iter()
                .map(|p| p - shift)
                .chain(piece.points.iter().map(|p| p + shift))
                .collect(),
            triangles: piece
                .triangles
                .iter()
                .copied()
                .chain(piece.triangles.iter().map(|t| t.map(|v| v + n)))
                .collect(),
        };
        // Returns (crossed or passed through, how far the lower piece went down, m).
        let run = |contact: bool| -> (bool, f64) {
            let mut mesh = PhysMesh::from_pattern(&pattern, 0.75, 0.08).unwrap();
            let nv = mesh.num_vertices();
            // The first piece (held) lies 3 mm over the second (free), slightly turned.
            let fixed: Vec<bool> = (0..nv).map(|i| i < n as usize).collect();
            let rot = nalgebra::Rotation3::from_axis_angle(&V3::z_axis(), 0.3);
            for i in 0..n as usize {
                let q =
                    mesh.pos[i] + V3::new(2.0 * shift.x, 0.0, 0.0) - V3::new(shift.x, 0.0, 0.75);
                mesh.pos[i] = rot * q + V3::new(shift.x, 0.0, 0.75 + 3e-3);
            }
            let z_lower = |m: &PhysMesh| (n as usize..nv).map(|i| m.pos[i].z).sum::<f64>();
            let z0 = z_lower(&mesh);
            let cfg = SolverConfig {
                sheet_contact: contact,
                ..SolverConfig::default()
            };
            let params = PhysParams::new(&PaperMaterial::of(Material::Printer), &cfg);
            let obstacles = Obstacles::new(&RoomConfig {
                table: false,
                ..RoomConfig::default()
            });
            let mut physics = Physics::new(&mesh);
            let mut target = mesh.pos.clone();
            let mut prox = SelfProximity::new();
            let h = 0.005 / f64::from(cfg.substeps);
            for _ in 0..10 * cfg.substeps {
                for (t, &f) in target.iter_mut().zip(&fixed) {
                    if f {
                        t.z -= 0.5 * h;
                    }
                }
                let kin = Kinematics {
                    fixed: &fixed,
                    target: &target,
                };
                physics.substep(&mut mesh, kin, &obstacles, &params, &cfg, h);
                if prox.any_crossing(&mesh) {
                    return (true, 0.0);
                }
            }
            // Passed through: the held piece ended below the free one.
            let z_upper = (0..n as usize).map(|i| mesh.pos[i].z).sum::<f64>();
            (
                z_upper < z_lower(&mesh),
                (z0 - z_lower(&mesh)) / f64::from(n),
            )
        };
        let (crossed, pushed_m) = run(true);
        assert!(!crossed, "the pieces crossed with contact");
        // The held piece went down 2.5 cm; the free one was pushed most of that way.
        assert!(pushed_m > 0.015, "lower piece pushed {pushed_m} m");
        assert!(run(false).0, "the pieces never crossed without contact");
    }

    #[test]
    fn gradient_matches_finite_differences() {
        let mut s = sheet();
        for p in &mut s.sp.pos {
            if p.x < 0.0 {
                *p = V3::new(-p.x + 1e-4, p.y + 2e-4, 0.4e-3);
            }
        }
        let mut c = SheetContact::new(&s.sp);
        c.find(&s.sp, MIN_REACH_M);
        let pair = *c
            .pairs()
            .iter()
            .find(|p| p.energy_of_gap(p.gap_m(&s.sp.pos)).0 > 0.0)
            .expect("an active pair");
        let n = s.sp.num_vertices();
        let fixed = vec![false; n];
        let mut grad = vec![V3::zeros(); n];
        pair.accumulate(&s.sp.pos, &fixed, &mut grad, |_, _| {});
        let h = 1e-9;
        for &v in &pair.v {
            for k in 0..3 {
                let mut xp = s.sp.pos.clone();
                xp[v as usize][k] += h;
                let mut xm = s.sp.pos.clone();
                xm[v as usize][k] -= h;
                let ep = pair.energy_of_gap(pair.gap_m(&xp)).0;
                let em = pair.energy_of_gap(pair.gap_m(&xm)).0;
                let fd = (ep - em) / (2.0 * h);
                let g = grad[v as usize][k];
                assert!((fd - g).abs() <= 1e-4 * g.abs().max(1e-3), "{fd} vs {g}");
            }
        }
    }

    #[test]
    fn pairs_close_in_the_pattern_are_one_patch() {
        // A vertex lying on a triangle it does not belong to, but whose pattern point is
        // within the gap of that triangle in the pattern too, is no contact.
        let mut s = sheet();
        let t = s.sp.triangles[0];
        // Find a vertex not in t and move its pattern point next to t.
        let v = (0..s.sp.num_vertices() as u32)
            .find(|v| !t.contains(v))
            .unwrap();
        let centre_p = t.iter().map(|&i| s.sp.pattern[i as usize]).sum::<V2>() / 3.0;
        let centre = t.iter().map(|&i| s.sp.pos[i as usize]).sum::<V3>() / 3.0;
        s.sp.pattern[v as usize] = centre_p;
        s.sp.pos[v as usize] = centre + V3::new(0.0, 0.0, 5e-4);
        let mut c = SheetContact::new(&s.sp);
        c.find(&s.sp, MIN_REACH_M);
        assert!(c.pairs().iter().all(|p| p.v[0] != v || p.v[1..] != t[..]));
        // Far in the pattern, the same 3D configuration is a contact.
        s.sp.pattern[v as usize] = centre_p + V2::new(0.05, 0.0);
        c.find(&s.sp, MIN_REACH_M);
        assert!(c.pairs().iter().any(|p| p.v[0] == v && p.v[1..] == t[..]));
    }
}
