//! # The developable-geometry layer (steps (d)–(h) of the seeds' frame loop)
//!
//! After the physics has moved S_P and S_G has read its positions (steps (a)–(c),
//! [`crate::sim`]), this layer runs the seeds' geometric analysis on S_P and publishes what sound
//! and tearing need ([`GeometryFrame`], read through `Sim::geometry`). Seeds: TOG 2015 §4–6
//! (`001_44bc28f7c5e9f81f.txt`) and thesis §2.4–2.5 (`000_cb4d91e46ec5927f.txt`); spec:
//! `../shared/notes/digest-crumpling.md` §3. A decision below names in quotes its section of
//! `docs/decisions.md`, where its figures and the variants that lost are.
//!
//! ## One awake frame
//!
//! In the Fig. 16 order (digest §9 item 3: the documented Step 1 → 3 order, not Algorithm 1's):
//!
//! 1. **Local shape** (§3.1): the signed dihedral θ_e of every S_P edge
//!    ([`crate::physics::bending::dihedral`]); per triangle the pattern shape operator
//!    S̄_t = Σ_e θ_e |ē| / (2Ā_t) · m̄_e m̄_eᵀ (m̄_e: in-plane normal of edge e), whose large
//!    eigenvalue κ_t is the curvature and whose other eigenvector is the ruling direction r̄_t;
//!    β_t = |κ_t|·h_t is the bend across the triangle.
//! 2. **Flat / curved classification** (§3.1, §3.6): flat → curved when β_t > θ0 = 0.01 rad,
//!    back only when β_t < θ0/10 (hysteresis, P 792–797, T 965). Flat regions are flat triangles
//!    joined across edges with |θ_e| < θ0 (P 537–542): a region splits when one of its edges
//!    bends beyond θ0 (T 813), and that edge is a crease (T 740). Junctions are where flat meets
//!    curved (P 303–306). **Edge flip** (T 811–828): the frame's most compressed flat-region edge
//!    whose quad's other diagonal is not compressed is flipped by the sim at the start of the
//!    next step ([`GeometryLayer::take_pending_flip`], [`crate::sheet::refine::flip_edge`]),
//!    reported as [`ShapeEvent::EdgeFlipped`].
//! 3. **Compression analysis** (§3.2): the stretch tensor of every flat triangle
//!    ([`stretch`]); the most compressed one, c_t = 1 − λ_min > ε_c, starts a pass.
//! 4. **Imaginary-ruling propagation** (§3.3, Appendix A): from it along ±v⊥ in the pattern
//!    ([`crate::sheet::walk`]) through flat triangles of its region to a border: the sheet boundary, a crease,
//!    or a curved region, which is extended if its rulings are parallel to v⊥ (within
//!    [`CONFLICT_RAD`]) and crossed to its first ruling bent beyond θ_sing if they conflict
//!    (P 693–704). Borders {∂S, ∂S} make a cylinder (Fig. 7), {∂S, singular} a cone (Fig. 8),
//!    {singular, singular} a degenerate strip (Fig. 9); the strip turns curved. At most
//!    [`GeometryConfig::max_passes`] passes per frame (§3.4).
//! 5. **Singular vertices** (§3.5) at crease and conflict borders: s̄ drawn with the seeds' law
//!    about ē_sing ([`placement`]: seeded RNG, σ from the material); never removed, never moved
//!    in 2D.
//! 6. **Fibre damage** (§2.3, P eq. 1, T eq. 2.1–2.2): each of the N_i edges of a new interior
//!    singular vertex gets rest angle ±Θ_rest/N_i (π/8, the sign of its fold) and damage D/N_i
//!    (D = 10, k_b/(1 + d)), so a crumpled sheet keeps its d-cones while a smoothly bent one
//!    springs back (P 489–491).
//! 7. **Regions and rulings** (§5.1): curved regions grown from their most bent triangle,
//!    crease regions (one ruling per crease edge, dihedral θ_e), and straight rulings traced
//!    along r̄_t through each curved region with 2D/3D ends, length, tangent-plane normal and
//!    dihedral angle (the mean signed κ along the ruling × the ruling spacing: the angle between
//!    neighbouring rulings' tangent planes, as the seeds' quads have).
//! 8. **Cones** (§3.7, [`cone`]): rulings ordered across a region, apex by least squares on the
//!    Blaschke cylinder, segments split at ε_blaschke = 0.5 % L_paper; a region holding a
//!    singular vertex is one cone about it (T 977). Then ruling realignment through each cone's
//!    pattern apex and boundary resampling to 1/ρ_bound ([`realign`], §3.7 steps 1–7).
//! 9. **Isometry** (§3.8, [`isometry`]): Phase I (edge directions, two Lagrange multipliers,
//!    2×2 solves), Phase II (positions, least squares, held vertices fixed).
//! 10. **Events** ("clac", T 1247, 1261): new singular vertices and curved regions, flattened
//!     triangles, flat-region splits, junction moves and the frame's largest vertex jump, in
//!     [`GeometryFrame::events`], never smoothed.
//!
//! ## Implementation decisions
//!
//! - S_P is the lattice, changed only where S_G gains a vertex or an edge is flipped; regions,
//!   rulings and cones are computed on S_P triangles, and realignment moves S_G's published
//!   rulings only: a new mesh costs more than a frame ("S_P changes at S_G's events, not every
//!   frame"; the seeds' per-frame regeneration, built and measured, lost: "Per-frame S_P
//!   regeneration (removed)").
//! - A singular point gets an S_P vertex at s̄: the nearest eligible vertex moves there
//!   ([`crate::sheet::physical::PhysMesh::move_pattern_vertex`]) or the sim inserts one after
//!   the frame ([`PendingSingular`], [`crate::sheet::refine`]); with no eligible vertex nothing
//!   is made (the seeds' rare failure, P 1631). The seeds never move a singular vertex in 2D
//!   ("A singular point gets an S_P vertex at s̄").
//! - Insertions go to a less strained place next to s̄ (its foot on a folded edge, or a nudged
//!   point) when s̄ would start strained beyond 5 %: such a start could not relax within its
//!   frame ("Insertion next to s̄").
//! - Flips change S_P itself, S_G's flat regions being S_P triangles, and only where the quad
//!   bends across its other diagonal: a quad merely squeezed in its plane, as the whole sheet is
//!   at a crumple's onset, keeps its triangles ("Compressed-edge flips, and their guards").
//! - An edge sharper than its triangle's two others by [`CREASE_DOMINANCE`] is left out of that
//!   facet's shape operator: a sharp fold between two flat parts is two flat regions and a crease.
//! - A curved triangle compressed along its own ruling (|κ_small/κ_big| < [`ANISO_MAX`], within
//!   [`CONFLICT_RAD`]) by more than `curved_eps_factor`·ε_c (40) starts a pass in place: on a
//!   fixed S_P that is the situation that buckles into a d-cone (P 685–692).
//! - θ_sing is θ0 × (S_P edge / ruling spacing 1/ρ_bound), since one of our dihedrals spans that
//!   many of the seeds' rulings; a region conflicts only when bent beyond θ_sing with a defined
//!   ruling direction (a weakly bent or twisted one simply grows).
//! - A vertex whose ring normals spread by φ in two directions, φ²/6 > 15·ε_c, becomes singular
//!   ([`SingularCase::NonDevelopable`], `nondevelopable`): our converged physics folds instead
//!   of compressing, so compression alone finds no d-cone in the full crumple ("Non-developable
//!   vertices (the Gauss-image test)").
//! - No pass starts at or beside a triangle touching a held vertex and no singular vertex goes on
//!   or next to one: the hand's constraint strains them. A pass's start waits
//!   [`REFRACTORY_FRAMES`] before it starts another.
//! - A curved region is one family of rulings (region-scale directions within 45°), and a lone
//!   flat facet touching it joins it ("Curved regions: one family of rulings").
//! - The isometry restores compressed edges only, as the seeds treat compression alone (T 848); it
//!   never moves a vertex deeper into an obstacle, is discarded if it turns a facet by more than
//!   0.3 rad or over or crosses the sheet, and is skipped in fast frames and on a still sheet
//!   without a 1 % compression ("Isometry: compression-only targets", "Isometry: when it runs").
//! - Curvature analysis on the fine mesh replaces the seeds' per-region ruling bookkeeping; the
//!   digest's §9 ambiguities are resolved as "Digest §9 discrepancies, resolved" lists.
//! - `GeometryConfig::{enabled, insert_singular_vertices, flip_compressed_edges}` off: for the
//!   bench report's comparison rows.
//!
//! ## Where each step lives
//!
//! This file holds the layer's state, its frame loop ([`GeometryLayer::update`]) and the tests
//! that play several steps together; each step is a child module implementing its part of
//! [`GeometryLayer`]:
//!
//! | step | module |
//! |---|---|
//! | 1–2 shape, classification, flips | `shape`, `flip` |
//! | 3–4 compression, propagation, strips | `compression` ([`stretch`], [`crate::sheet::walk`]) |
//! | 5 singular vertices, 6 fibre damage | `singular` ([`placement`]), `nondevelopable` |
//! | 7 partition, rulings | `partition`, `rulings` |
//! | 8 cones, realignment, resampling | `region_cones` ([`cone`]), [`realign`] |
//! | 9 isometry | `isometry_step` ([`isometry`]) |
//! | 10 published outputs and events | `frame` ([`GeometryFrame`], [`ShapeEvent`]) |
//! | settings, saved state, mesh changes | `config`, `saved`, `remesh` |
//!
//! ## Allocation and determinism
//!
//! Every buffer is sized in [`GeometryLayer::new`] from S_P (a vertex insertion or an edge flip
//! builds a new layer, [`GeometryLayer::remeshed`]); `update` only writes into them (in-place
//! `sort_unstable_by` with index tie-breaks). The only randomness is the layer's own `Pcg32`,
//! seeded from the sheet's seed and saved with the sheet.

mod compression;
pub mod cone;
mod config;
mod flip;
mod frame;
pub mod isometry;
mod isometry_step;
mod nondevelopable;
mod partition;
pub mod placement;
pub mod realign;
mod region_cones;
mod remesh;
mod rulings;
mod saved;
mod shape;
mod singular;
pub mod stretch;

use rand::SeedableRng;

use crate::collision::{CONTACT_SKIN_M, Obstacles};
use crate::material::PaperMaterial;
use crate::math::{V2, V3, sym2_eigen};
use crate::self_proximity::SelfProximity;
use crate::sheet::geometric::{GVertex, GeomStructure, VKind};
use crate::sheet::measure::dihedral;
use crate::sheet::physical::PhysMesh;
use crate::sheet::topology::NONE;
use crate::sheet::walk;
use cone::{RulingPlane, apex_in_pattern, gap_apex, segment};
use isometry::{Isometry, IsometryConfig, IsometryReport};

pub use config::GeometryConfig;
pub use frame::{
    ConeInfo, FreeBorderEdge, GeometryFrame, PendingFlip, PendingSingular, Region, RegionKind,
    RulingInfo, ShapeEvent, SingularCase, SingularPoint, TriKind,
};
pub use saved::SavedGeometry;

/// Coplanarity threshold θ0 (P 1515–1519, Table VI), radians.
pub const THETA0_RAD: f64 = 0.01;
/// Junction hysteresis: a curved triangle turns flat below θ_low = θ0/10 (P 792).
pub const THETA_LOW_RAD: f64 = THETA0_RAD / 10.0;
/// Junction hysteresis: a flat triangle turns curved above θ_high = θ0 (P 792).
pub const THETA_HIGH_RAD: f64 = THETA0_RAD;
/// Plastic rest-angle budget per singular vertex Θ_rest = π/8 (P 510–518, T 775).
pub const THETA_REST_RAD: f64 = std::f64::consts::PI / 8.0;
/// Bending damage per singular vertex D = 10 (T 767–775).
pub const DAMAGE_D: f64 = 10.0;
/// Boundary sampling density ρ_bound = 1.2 per cm (Table VI), per metre.
pub const RHO_BOUND_PER_M: f64 = 120.0;
/// ε_blaschke as a fraction of L_paper (0.5 %, Table VI).
pub const EPS_BLASCHKE_FRAC: f64 = 0.005;
/// Ridge threshold a_max of the sound model (digest §9 item 12), radians.
pub const RIDGE_RAD: f64 = 0.5;
/// Largest angle between v⊥ and a curved region's rulings for the propagation to merge into
/// it instead of conflicting (impl. choice), radians.
pub const CONFLICT_RAD: f64 = 0.35;
/// A triangle's ruling direction is well defined when its small principal curvature is
/// below this fraction of the large one (|κ_small/κ_big|; a twisted, saddle-like triangle has
/// ≈ 1 and has no ruling to conflict with).
pub const ANISO_MAX: f64 = 0.3;
/// An edge whose |θ| exceeds this × the sum of the triangle's two other |θ| (plus θ0) is a
/// crease bounding a flat facet, not part of the facet's curvature (impl. choice).
pub const CREASE_DOMINANCE: f64 = 4.0;
/// Frames a triangle that started a propagation pass waits before starting another.
pub const REFRACTORY_FRAMES: u64 = 20;
/// Cosine of the largest facet rotation the isometry step may make in one frame (0.3 rad).
pub const ISO_MAX_TURN_COS: f64 = 0.955_336_489_125_606;
/// Undriven, the isometry step runs again only when the largest edge compression exceeds the
/// one it last met by this factor (see the isometry step, module doc step 9).
pub const ISO_REBUILT_FACTOR: f64 = 1.1;
/// A vertex jump above this is reported as an event, metres.
pub const JUMP_EVENT_M: f64 = 5e-4;
/// Capacity of the per-frame event list.
pub const MAX_EVENTS: usize = 64;
/// Longest propagation walk, in triangles.
const MAX_WALK: usize = 256;

/// Where a propagation direction ended.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Border {
    /// Sheet boundary: a free border.
    Free,
    /// A curved region with compatible rulings (it grows).
    Compatible,
    /// A crease edge (case B).
    Crease(u32),
    /// A bent ruling inside a conflicting curved region (case A).
    InCurved(u32),
    /// The walk failed (degenerate) or ran too long.
    None,
}

/// Whether a partition may turn lone flat facets beside curved triangles curved
/// ([`GeometryLayer::restore`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Promote {
    Yes,
    No,
}

/// The geometry layer: persistent state and preallocated workspace.
#[derive(Clone, Debug)]
pub struct GeometryLayer {
    cfg: GeometryConfig,
    eps_c: f64,
    sigma_m: f64,
    l_paper_m: f64,
    spacing_m: f64,
    theta_sing: f64,
    out: GeometryFrame,
    curved: Vec<bool>,
    prev_curved: Vec<bool>,
    refractory_until: Vec<u64>,
    is_singular: Vec<bool>,
    near_held: Vec<bool>,
    tri_kappa: Vec<f64>,
    tri_aniso: Vec<f64>,
    tri_ruling: Vec<V2>,
    tri_shape: Vec<[f64; 3]>,
    grow_order: Vec<u32>,
    crease_edges: Vec<(u32, u32, u32)>,
    grow_stack: Vec<u32>,
    grown: Vec<bool>,
    tri_ruling_smooth: Vec<V2>,
    tri_bend: Vec<f64>,
    tri_normal: Vec<V3>,
    tri_h: Vec<f64>,
    vert_tris_start: Vec<u32>,
    vert_tris: Vec<u32>,
    vert_spread2: Vec<f64>,
    uf: Vec<u32>,
    root_region: Vec<u32>,
    order: Vec<u32>,
    /// Per region, where its curved triangles end in `order` (the trace's buckets); one more
    /// than the regions' capacity.
    region_end: Vec<u32>,
    covered: Vec<bool>,
    ruling_tris: Vec<u32>,
    strip: Vec<u32>,
    vflat: Vec<bool>,
    vcurved: Vec<bool>,
    junction_prev: Vec<bool>,
    planes: Vec<RulingPlane>,
    ruling_next: Vec<RulingInfo>,
    ruling_map: Vec<u32>,
    pos_before: Vec<V3>,
    /// Crossing test of the isometry's correction.
    proximity: SelfProximity,
    iso: Isometry,
    rng: rand_pcg::Pcg32,
    iso_undriven_compression: f64,
    frames_processed: u64,
    /// A singular vertex waiting for its inserted S_P vertex (at most one per frame).
    pending: Option<PendingSingular>,
    /// An edge waiting to be flipped (at most one per frame).
    pending_flip: Option<PendingFlip>,
    /// This frame's event list was started before the layer ran ([`Self::start_events_early`]).
    keep_events: bool,
    /// The isometry step's crossing test found S_P's final positions of this frame crossing
    /// nowhere ([`Self::checked_uncrossed`]).
    checked_uncrossed: bool,
}

fn find(uf: &mut [u32], mut x: u32) -> u32 {
    while uf[x as usize] != x {
        let p = uf[uf[x as usize] as usize];
        uf[x as usize] = p;
        x = p;
    }
    x
}

fn union(uf: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(uf, a), find(uf, b));
    if ra != rb {
        // Lower index wins: deterministic roots.
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        uf[hi as usize] = lo;
    }
}

/// Seed of the layer's generator, derived from the sheet's seed (a separate stream from the
/// gesture rig's).
fn layer_seed(seed: u64) -> u64 {
    seed ^ 0x9e37_79b9_7f4a_7c15
}

impl GeometryLayer {
    /// A layer for `sp` (a new, flat sheet: every triangle flat, no singular vertex).
    pub fn new(sp: &PhysMesh, cfg: GeometryConfig, mat: &PaperMaterial, seed: u64) -> Self {
        let mut s = Self::unpublished(sp, cfg, mat, seed);
        s.refresh(sp, Promote::Yes);
        s
    }

    /// [`Self::new`] without publishing the current shape: for a layer whose state is
    /// restored next ([`Self::restore`] publishes it then).
    fn unpublished(sp: &PhysMesh, cfg: GeometryConfig, mat: &PaperMaterial, seed: u64) -> Self {
        let cfg = cfg.sanitized();
        let (nv, nt, ne) = (sp.num_vertices(), sp.num_triangles(), sp.num_edges());
        let (mut lo, mut hi) = (V2::repeat(f64::MAX), V2::repeat(f64::MIN));
        for q in &sp.pattern {
            lo = lo.inf(q);
            hi = hi.sup(q);
        }
        let ext = hi - lo;
        let spacing_m = sp.edge_rest_len_m.iter().sum::<f64>() / ne.max(1) as f64;
        let nreg = nt + ne;
        let out = GeometryFrame {
            tri_region: vec![0; nt],
            tri_kind: vec![TriKind::Flat; nt],
            regions: Vec::with_capacity(nreg),
            rulings: Vec::with_capacity(nreg),
            free_borders: Vec::with_capacity(ne),
            singular: Vec::with_capacity(nv),
            cones: Vec::with_capacity(2 * nreg),
            junctions: Vec::with_capacity(nv),
            held: Vec::with_capacity(nv),
            edge_dihedral_rad: vec![0.0; ne],
            events: Vec::with_capacity(MAX_EVENTS),
            ..GeometryFrame::default()
        };
        let mut s = Self {
            cfg,
            eps_c: 0.0,
            sigma_m: 0.0,
            l_paper_m: ext.x.max(ext.y).max(1e-6),
            spacing_m,
            theta_sing: THETA0_RAD * (spacing_m * RHO_BOUND_PER_M).max(1.0),
            out,
            curved: vec![false; nt],
            prev_curved: vec![false; nt],
            refractory_until: vec![0; nt],
            is_singular: vec![false; nv],
            near_held: vec![false; nv],
            tri_kappa: vec![0.0; nt],
            tri_aniso: vec![1.0; nt],
            tri_ruling: vec![V2::x(); nt],
            tri_shape: vec![[0.0; 3]; nt],
            grow_order: Vec::with_capacity(nt),
            crease_edges: Vec::with_capacity(ne),
            grow_stack: Vec::with_capacity(nt),
            grown: vec![false; nt],
            tri_ruling_smooth: vec![V2::x(); nt],
            tri_bend: vec![0.0; nt],
            tri_normal: vec![V3::z(); nt],
            tri_h: sp
                .tri_rest
                .iter()
                .map(|r| (4.0 * r.area_m2 / 3f64.sqrt()).sqrt())
                .collect(),
            vert_tris_start: Vec::new(),
            vert_tris: Vec::new(),
            vert_spread2: vec![0.0; nv],
            uf: (0..nt as u32).collect(),
            root_region: vec![NONE; nt],
            order: Vec::with_capacity(nt),
            region_end: Vec::with_capacity(nt + ne + 1),
            covered: vec![false; nt],
            ruling_tris: Vec::with_capacity(2 * MAX_WALK + 2),
            strip: Vec::with_capacity(2 * MAX_WALK + 2),
            vflat: vec![false; nv],
            vcurved: vec![false; nv],
            junction_prev: vec![false; nv],
            planes: Vec::with_capacity(nreg),
            ruling_next: Vec::with_capacity(nreg),
            ruling_map: Vec::with_capacity(nreg),
            pos_before: vec![V3::zeros(); nv],
            proximity: SelfProximity::with_capacity(sp.num_triangles()),
            iso: Isometry::new(sp),
            rng: rand_pcg::Pcg32::seed_from_u64(layer_seed(seed)),
            iso_undriven_compression: 0.0,
            checked_uncrossed: false,
            frames_processed: 0,
            pending: None,
            pending_flip: None,
            keep_events: false,
        };
        let mut count = vec![0u32; nv + 1];
        for tri in &sp.triangles {
            for &v in tri {
                count[v as usize + 1] += 1;
            }
        }
        for v in 0..nv {
            count[v + 1] += count[v];
        }
        let mut fill = count.clone();
        s.vert_tris = vec![0; 3 * nt];
        for (t, tri) in sp.triangles.iter().enumerate() {
            for &v in tri {
                s.vert_tris[fill[v as usize] as usize] = t as u32;
                fill[v as usize] += 1;
            }
        }
        s.vert_tris_start = count;
        s.set_material(mat);
        for &v in &sp.singular {
            s.is_singular[v as usize] = true;
        }
        s
    }

    /// Publishes the partition, rulings and cones of the current shape without changing
    /// anything (a new or restored sheet, before its first awake frame).
    fn refresh(&mut self, sp: &PhysMesh, promote: Promote) {
        self.analyse_shape(sp);
        self.partition(sp, promote);
        self.trace_rulings(sp);
        self.fit_cones();
        self.realign_rulings(sp);
        self.out.events.clear();
        self.out.junction_moves = 0;
    }

    /// Applies a material's ε_c and σ (unless overridden by the configuration).
    pub fn set_material(&mut self, mat: &PaperMaterial) {
        self.eps_c = self.cfg.eps_c.unwrap_or(mat.eps_c);
        self.sigma_m = self.cfg.sigma_m.unwrap_or(mat.sigma_m);
    }

    /// The configuration.
    pub fn config(&self) -> &GeometryConfig {
        &self.cfg
    }

    /// Compression limit ε_c in use.
    pub fn eps_c(&self) -> f64 {
        self.eps_c
    }

    /// Placement spread σ in use, metres.
    pub fn sigma_m(&self) -> f64 {
        self.sigma_m
    }

    /// The outputs of the last processed frame.
    pub fn frame(&self) -> &GeometryFrame {
        &self.out
    }

    /// Work counter: frames the layer processed (does not move while the sheet sleeps).
    pub fn frames_processed(&self) -> u64 {
        self.frames_processed
    }

    /// Clears the per-frame event list (a frame in which the layer did not run).
    pub fn idle_frame(&mut self, frame: u64) {
        self.out.frame = frame;
        self.checked_uncrossed = false;
        if !std::mem::take(&mut self.keep_events) {
            self.out.events.clear();
            self.out.events_dropped = 0;
        }
        self.out.max_vertex_jump_m = 0.0;
        self.out.junction_moves = 0;
    }

    /// True if this frame's isometry step tested S_P's positions as it left them and found no
    /// two vertex-disjoint triangles crossing (the test of
    /// [`crate::self_proximity::SelfProximity::any_crossing`]). The sim's pass-through guard
    /// then has nothing to find and skips its own sweep of the same positions (`Sim::step`);
    /// false when the step did not run, was reverted before its test, or left a crossing.
    pub fn checked_uncrossed(&self) -> bool {
        self.checked_uncrossed
    }

    /// Re-reads the singular points' 3D positions from S_P, after the sim moved S_P once the
    /// layer had run (the pass-through guard undoing a frame, `Sim::step`).
    pub fn sync_positions(&mut self, sp: &PhysMesh) {
        for s in &mut self.out.singular {
            s.pos3 = sp.pos[s.sp_vertex as usize];
        }
    }

    /// Runs steps (d)–(h) on an awake frame. `fixed`: vertices held this frame (kept in place
    /// by the isometry step). `driven`: a hand or an obstacle moved the sheet this frame (the
    /// isometry step's trigger, [`IsometryConfig::trigger_compression`]). `start_normals`:
    /// the triangles' unit normals at the start of the frame, from which the physics never
    /// turns a triangle over, and neither may the isometry step (empty: no such reference).
    #[allow(clippy::too_many_arguments)] // the frame loop's state, passed explicitly
    pub fn update(
        &mut self,
        sp: &mut PhysMesh,
        sg: &mut GeomStructure,
        fixed: &[bool],
        obstacles: &Obstacles,
        frame: u64,
        driven: bool,
        start_normals: &[V3],
    ) {
        self.frames_processed += 1;
        self.out.frame = frame;
        if !std::mem::take(&mut self.keep_events) {
            self.out.events.clear();
            self.out.events_dropped = 0;
        }
        self.out.held.clear();
        self.out
            .held
            .extend((0..fixed.len() as u32).filter(|&v| fixed[v as usize]));
        self.analyse_shape(sp);
        self.classify();
        self.mark_near_held(sp, fixed);
        if self.cfg.flip_compressed_edges {
            self.find_flip(sp, frame);
        }
        let flats_before = self.out.num_flat_regions;
        let made = self.treat_compression(sp, sg, fixed, frame);
        self.treat_nondevelopable(sp, sg, fixed, frame, made);
        self.partition(sp, Promote::Yes);
        if flats_before > 0 && self.out.num_flat_regions > flats_before {
            let after = self.out.num_flat_regions;
            self.out.push_event(ShapeEvent::FlatRegionSplit {
                before: flats_before,
                after,
            });
        }
        self.trace_rulings(sp);
        self.fit_cones();
        self.realign_rulings(sp);
        self.isometry(sp, fixed, obstacles, driven, start_normals);
        self.sync_positions(sp);
    }

    /// Starts this frame's event list before the layer runs (the sim places a pending singular
    /// vertex at the start of its step): the list is cleared now and kept when the layer runs.
    pub fn start_events_early(&mut self) {
        if !self.keep_events {
            self.out.events.clear();
            self.out.events_dropped = 0;
        }
        self.keep_events = true;
    }
}

/// A tiny sideways offset of a walk's start so that a line from a lattice triangle's
/// centroid does not run exactly through a vertex (an equilateral lattice has vertices right
/// above its centroids).
fn off_line(d: V2, h: f64) -> V2 {
    V2::new(-d.y, d.x) * (1e-3 * h)
}

/// Makes S_G's interior singular vertices match `sp.singular` (in order).
pub fn sync_sg_singular(sg: &mut GeomStructure, sp: &PhysMesh) {
    sg.vertices.retain(|v| v.kind != VKind::InteriorSingular);
    for &v in &sp.singular {
        sg.vertices.push(GVertex::interior_singular(sp, v));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::Obstacles;
    use crate::room::RoomConfig;
    use crate::sheet::pattern::lattice;

    fn sheet() -> (PhysMesh, GeomStructure) {
        let sp = PhysMesh::from_pattern(&lattice(0.1, 0.1, 0.011), 0.0, 0.1).unwrap();
        let sg = GeomStructure::initial(&sp);
        (sp, sg)
    }

    /// A layer on its own (no sim): a singular point goes to the nearest vertex, moved towards
    /// s̄ (inserting a vertex at s̄ is the sim's part, tested in `sim/remesh.rs`).
    fn layer(sp: &PhysMesh) -> GeometryLayer {
        let cfg = GeometryConfig {
            isometry: IsometryConfig {
                enabled: false,
                ..IsometryConfig::default()
            },
            insert_singular_vertices: false,
            ..GeometryConfig::default()
        };
        GeometryLayer::new(
            sp,
            cfg,
            &PaperMaterial::of(crate::control::Material::Printer),
            1,
        )
    }

    /// The layer's frame for the test sheet placed on `shape` (pattern → 3D), no vertex held.
    fn shaped_frame(shape: &dyn Fn(V2) -> V3) -> GeometryFrame {
        let (mut sp, mut sg) = sheet();
        for i in 0..sp.num_vertices() {
            sp.pos[i] = shape(sp.pattern[i]);
        }
        let mut g = layer(&sp);
        let fixed = vec![false; sp.num_vertices()];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        g.frame().clone()
    }

    fn centre_triangle(sp: &PhysMesh, p: V2) -> usize {
        use crate::sheet::pattern::signed_area as sa;
        (0..sp.num_triangles())
            .find(|&t| {
                let [a, b, c] = sp.triangles[t].map(|i| sp.pattern[i as usize]);
                sa(a, b, p) >= 0.0 && sa(b, c, p) >= 0.0 && sa(c, a, p) >= 0.0
            })
            .unwrap()
    }

    /// Digest §8 test 2 (T 818–826, Fig. 2.5), on the lattice's own quad: two triangles
    /// (u, w, x1), (w, u, x2) sharing the edge e1 = u–w, positions set by hand (the four
    /// corners "held"). Squeezing u and w together by 0.3 % and lifting x1 by 0.35 mm bends
    /// the quad by less than θ0: one flat region, e1 compressed, the other diagonal x1–x2 not,
    /// so the layer asks for e1 to be flipped. On the flipped mesh, folding the quad along the
    /// new diagonal by 0.05 rad (≥ θ0) splits it into two flat regions with a crease between.
    #[test]
    fn a_compressed_flat_edge_is_flipped_and_the_fold_across_it_splits_the_region() {
        let s = 0.1;
        let h = s * 3f64.sqrt() / 2.0;
        let pattern = crate::sheet::pattern::Pattern {
            points: vec![
                V2::new(0.0, 0.0),
                V2::new(s, 0.0),
                V2::new(s / 2.0, h),
                V2::new(s / 2.0, -h),
            ],
            triangles: vec![[0, 1, 2], [1, 0, 3]],
        };
        let mut sp = PhysMesh::from_pattern(&pattern, 0.0, 0.08).unwrap();
        let mut sg = GeomStructure::initial(&sp);
        sp.pos[0].x += 0.0015 * s;
        sp.pos[1].x -= 0.0015 * s;
        sp.pos[2].z += 3.5e-4;
        let mut g = layer(&sp);
        let fixed = vec![false; 4];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        let e1 = sp.topo.find_edge(0, 1).unwrap() as usize;
        assert!(g.frame().edge_dihedral_rad[e1].abs() < THETA0_RAD);
        let f = *g.pending_flip().expect("e1 is to be flipped");
        assert_eq!(f.edge, [0, 1]);
        assert!((f.compression - 0.003).abs() < 1e-4, "{}", f.compression);
        assert!(f.other_compression <= 0.0);
        // The same quad squeezed flat in its plane keeps its edge.
        let mut flat = PhysMesh::from_pattern(&pattern, 0.0, 0.08).unwrap();
        flat.pos[0].x += 0.0015 * s;
        flat.pos[1].x -= 0.0015 * s;
        let mut gf = layer(&flat);
        let mut sgf = GeomStructure::initial(&flat);
        gf.update(&mut flat, &mut sgf, &fixed, &obstacles, 1, true, &[]);
        assert!(gf.pending_flip().is_none());
        // The sim's part: flip, carry the layer over.
        let g_taken = g.take_pending_flip();
        assert_eq!(g_taken, Some(f));
        let flip = crate::sheet::refine::flip_edge(&sp, e1 as u32).unwrap();
        assert_eq!(flip.diagonal, [2, 3]);
        let mut sp2 = flip.mesh;
        let mut sg2 = GeomStructure::initial(&sp2);
        let mut g2 = g
            .remeshed(
                &sp2,
                &mut sg2,
                &flip.tri_parent,
                &PaperMaterial::of(crate::control::Material::Printer),
                1,
            )
            .unwrap();
        g2.edge_flipped(&f, flip.diagonal);
        assert!(g2.frame().events.iter().any(|e| matches!(
            e,
            ShapeEvent::EdgeFlipped {
                diagonal: [2, 3],
                ..
            }
        )));
        // Fold about x1–x2: u turns by 0.05 rad about that line, the other three stay.
        for (i, q) in pattern.points.iter().enumerate() {
            sp2.pos[i] = V3::new(q.x, q.y, 0.0);
        }
        let phi: f64 = 0.05;
        let r = s / 2.0;
        sp2.pos[0] = V3::new(s / 2.0 - r * phi.cos(), 0.0, r * phi.sin());
        g2.update(&mut sp2, &mut sg2, &fixed, &obstacles, 2, true, &[]);
        let e2 = sp2.topo.find_edge(2, 3).unwrap() as usize;
        assert!((g2.frame().edge_dihedral_rad[e2].abs() - phi).abs() < 1e-9);
        let fr = g2.frame();
        assert_eq!(fr.num_flat_regions, 2, "{:?}", fr.regions);
        assert_ne!(fr.tri_region[0], fr.tri_region[1]);
        assert!(g2.pending_flip().is_none(), "nothing is compressed now");
    }

    /// A pending flip is saved with the sheet; a corrupt one is refused.
    #[test]
    fn a_pending_flip_survives_save_and_restore_and_a_corrupt_one_is_refused() {
        let (sp, mut sg) = sheet();
        let mut g = layer(&sp);
        g.pending_flip = Some(PendingFlip {
            edge: [3, 9],
            compression: 0.002,
            other_compression: -0.001,
            frame: 7,
        });
        let saved = g.save();
        let mut r = layer(&sp);
        r.restore(&sp, &mut sg, Some(&saved)).unwrap();
        assert_eq!(r.pending_flip(), g.pending_flip());
        for bad in [
            ([9, 3], 0.002, 0.0, 7),
            ([3, 100_000], 0.002, 0.0, 7),
            ([3, 9], f64::NAN, 0.0, 7),
        ] {
            let mut s2 = saved.clone();
            s2.pending_flip = Some(bad);
            assert!(layer(&sp).restore(&sp, &mut sg, Some(&s2)).is_err());
        }
    }

    /// Digest §8 test 3, case {∂S, ∂S} (Fig. 7): a flat sheet compressed along x gives
    /// rulings parallel to v⊥ = ±y, both borders free, and no singular vertex.
    #[test]
    fn compressed_flat_sheet_propagates_to_two_free_borders() {
        let (mut sp, mut sg) = sheet();
        for i in 0..sp.num_vertices() {
            sp.pos[i].x *= 0.99;
        }
        let mut g = layer(&sp);
        let t = centre_triangle(&sp, V2::new(1.3e-3, 0.7e-3));
        let x = sp.triangles[t].map(|i| sp.pos[i as usize]);
        let s = stretch::stretch_tensor(&x, &sp.tri_rest[t].dm_inv);
        assert!((s.compression() - 0.01).abs() < 1e-9);
        assert!(s.v_perp.x.abs() < 1e-9, "rulings ∥ v⊥ = y: {:?}", s.v_perp);
        g.analyse_shape(&sp);
        g.classify();
        let b = g.propagate(&sp, t as u32, s.v_perp);
        assert_eq!(b, [Border::Free, Border::Free]);
        assert!(
            g.strip.len() >= 8,
            "the strip crosses the sheet: {}",
            g.strip.len()
        );
        let fixed = vec![false; sp.num_vertices()];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        assert!(g.frame().singular.is_empty());
        assert!(
            g.frame()
                .events
                .iter()
                .any(|e| matches!(e, ShapeEvent::StripCurved { cylinder: true, .. }))
        );
    }

    /// Digest §8 test 3, case {∂S, singular on a crease} (Fig. 6c): a sheet folded along a
    /// lattice row into two flat regions, compressed across the fold, gets a singular vertex
    /// next to the crease, with fibre damage around it; the crease is published as a ruling.
    #[test]
    fn propagation_into_a_crease_creates_a_singular_vertex() {
        let (mut sp, mut sg) = sheet();
        // The lattice row nearest y = 0.
        let y0 = sp
            .pattern
            .iter()
            .map(|q| q.y)
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap();
        let ang: f64 = 0.3;
        for i in 0..sp.num_vertices() {
            let q = sp.pattern[i];
            let x = q.x * 0.995;
            sp.pos[i] = if q.y > y0 + 1e-9 {
                let d = q.y - y0;
                V3::new(x, y0 + d * ang.cos(), d * ang.sin())
            } else {
                V3::new(x, q.y, 0.0)
            };
        }
        let mut g = layer(&sp);
        let fixed = vec![false; sp.num_vertices()];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        let f = g.frame();
        assert!(
            f.num_flat_regions >= 2,
            "{} flat regions",
            f.num_flat_regions
        );
        assert!(f.num_creases >= 1);
        assert!(
            f.rulings
                .iter()
                .any(|r| r.sp_edge != NONE && (r.dihedral_rad.abs() - ang).abs() < 1e-6)
        );
        assert_eq!(f.singular.len(), 1);
        let s = f.singular[0];
        assert_eq!(s.case, SingularCase::Crease);
        // Next to the crease (within one edge of the fold row), 2D position fixed.
        assert!((s.pos2.y - y0).abs() < 0.012, "{:?}", s.pos2);
        assert!((s.sampled2.y - y0).abs() < 0.01);
        let n = sp.topo.valence(s.sp_vertex) as f64;
        for &j in sp.topo.neighbours(s.sp_vertex) {
            let e = sp.topo.find_edge(s.sp_vertex, j).unwrap() as usize;
            assert!((sp.edge_rest_angle[e].abs() - THETA_REST_RAD / n).abs() < 1e-12);
            assert!((sp.edge_damage[e] - DAMAGE_D / n).abs() < 1e-12);
        }
        assert_eq!(sg.num_singular(), 1);
    }

    /// A region containing a singular vertex is one cone with that apex; curved regions of a
    /// bent sheet have rulings along the bend's generators and free borders.
    #[test]
    fn bent_sheet_has_a_curved_region_with_generator_rulings() {
        let (mut sp, mut sg) = sheet();
        let r = 0.05;
        for i in 0..sp.num_vertices() {
            let q = sp.pattern[i];
            let a = q.x / r;
            sp.pos[i] = V3::new(r * a.sin(), q.y, r * (1.0 - a.cos()));
        }
        let mut g = layer(&sp);
        let fixed = vec![false; sp.num_vertices()];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        let f = g.frame();
        assert!(f.num_curved_regions >= 1);
        let big = f
            .regions
            .iter()
            .enumerate()
            .max_by_key(|(_, r)| r.num_triangles)
            .unwrap();
        assert_eq!(big.1.kind, RegionKind::Curved);
        let rs = f.region_rulings(big.0 as u32);
        assert!(rs.len() >= 3);
        for q in rs {
            let d = (q.b2 - q.a2).normalize();
            assert!(d.y.abs() > 0.95, "generator ∥ y: {d:?}");
        }
        assert!(big.1.free_border_len_m > 0.05);
        assert!(big.1.mean_ruling_len_m > 0.05);
        assert!(
            f.cones
                .iter()
                .any(|c| c.region == big.0 as u32 && !c.is_gap)
        );
        assert!(f.singular.is_empty());
    }

    /// Digest §8 test 6 (ruling realignment and boundary resampling, P 871–884, T 1103–1112):
    /// a sheet rolled onto a circular cone whose apex lies 10 cm off its edge. Every ruling of a
    /// fitted cone passes within 1e-6 cm of the cone's pattern apex ā_proj, which lies near
    /// the true apex; neighbouring rulings' border ends are ≤ 1/ρ_bound apart; a rolled
    /// cylinder's rulings come out parallel.
    #[test]
    fn rulings_are_realigned_to_their_cone_and_the_border_resampled() {
        let run = shaped_frame;
        // A circular cone of half-angle α with its apex at the origin, unrolled about the
        // pattern point `apex`: generator angle φ → ψ = φ / sin α around the axis (isometric).
        let apex = V2::new(-0.15, 0.0);
        let (sin_a, cos_a) = (0.6f64, 0.8f64);
        let cone = |q: V2| {
            let d = q - apex;
            let (r, psi) = (d.norm(), d.y.atan2(d.x) / sin_a);
            V3::new(r * cos_a, r * sin_a * psi.cos(), r * sin_a * psi.sin())
        };
        let f = run(&cone);
        let gap_max = 1.0 / RHO_BOUND_PER_M + 1e-9;
        let on_edge = |p: V2| 0.05 - p.x.abs().max(p.y.abs()) < 1e-9;
        let (mut checked, mut gaps, mut short, mut edge_gaps, mut edge_short) = (0, 0, 0, 0, 0);
        // (A stray curved triangle at the border may form a one-ruling region of its own.)
        for c in f
            .cones
            .iter()
            .filter(|c| !c.is_gap && c.last_ruling > c.first_ruling + 1)
        {
            let a = c.apex2.expect("a cone, not a cylinder");
            assert!((a - apex).norm() < 0.01, "fitted apex {a:?}, true {apex:?}");
            let rs = &f.rulings[c.first_ruling as usize..=c.last_ruling as usize];
            for (k, r) in rs.iter().enumerate() {
                let d = (r.b2 - r.a2).normalize();
                let off = (a - r.a2).perp(&d).abs();
                assert!(off < 1e-8, "ruling {k} misses ā by {off} m");
                checked += 1;
                if k == 0 {
                    continue;
                }
                // Ends on the same straight sheet edge: the resampled spacing holds exactly.
                let p = &rs[k - 1];
                for (e, g) in [(p.a2, r.a2), (p.b2, r.b2)] {
                    let gap = (e - g).norm();
                    gaps += 1;
                    short += usize::from(gap <= gap_max);
                    let same_edge = on_edge(e)
                        && on_edge(g)
                        && ((e.x - g.x).abs() < 1e-9 || (e.y - g.y).abs() < 1e-9);
                    if same_edge {
                        edge_gaps += 1;
                        edge_short += usize::from(gap <= gap_max);
                        // Rulings planned on a chord across a corner land a little farther
                        // apart on the border (module doc).
                        assert!(
                            gap <= 1.25 * gap_max,
                            "gap {gap} m on the sheet edge at ruling {k}: {e:?} {g:?}"
                        );
                    }
                }
            }
        }
        // Inside the sheet, a region's border is ragged where a crease cuts into it, and
        // neighbouring rulings end at different depths: most gaps still meet 1/ρ.
        assert!(edge_gaps >= 10, "{edge_gaps} gaps on the sheet edge");
        assert!(
            10 * edge_short >= 9 * edge_gaps,
            "{edge_short} of {edge_gaps} gaps on the sheet edge ≤ 1/ρ"
        );
        assert!(
            10 * short >= 8 * gaps,
            "{short} of {gaps} border gaps ≤ 1/ρ"
        );
        assert!(checked >= 10, "{checked} rulings checked");
        assert!(f.rulings.iter().any(|r| r.resampled));
        // Resampled rulings are traced on S_P too: their ends lie as close to the true cone
        // as the others' (S_P's chords sag by l²/8R ≈ 0.25 mm here).
        let err = |resampled: bool| {
            f.rulings
                .iter()
                .filter(|r| r.resampled == resampled && r.sp_edge == NONE)
                .flat_map(|r| [(r.a2, r.a3), (r.b2, r.b3)])
                .map(|(p2, p3)| (cone(p2) - p3).norm())
                .fold(0.0, f64::max)
        };
        let (e_resampled, e_traced) = (err(true), err(false));
        assert!(e_resampled <= 1.5 * e_traced, "{e_resampled} vs {e_traced}");
        // A cylinder (rolled about y): parallel rulings along y.
        let radius = 0.05;
        let f = run(&|q: V2| {
            let t = q.x / radius;
            V3::new(radius * t.sin(), q.y, radius * (1.0 - t.cos()))
        });
        let mut parallel = 0;
        let big = (0..f.regions.len())
            .max_by_key(|&r| f.regions[r].num_triangles)
            .unwrap() as u32;
        for c in f
            .cones
            .iter()
            .filter(|c| c.region == big && !c.is_gap && c.apex2.is_none())
        {
            let rs = &f.rulings[c.first_ruling as usize..=c.last_ruling as usize];
            let d0 = (rs[0].b2 - rs[0].a2).normalize();
            for r in rs {
                let d = (r.b2 - r.a2).normalize();
                assert!(
                    d.perp(&d0).abs() < 1e-9,
                    "cylinder rulings not parallel: {d:?} {d0:?}"
                );
                assert!(d.x.abs() < 0.05, "cylinder ruling not along y: {d:?}");
                parallel += 1;
            }
        }
        assert!(parallel >= 5, "{parallel} rulings in cylinders");
    }

    /// S_G of a frame ([`GeometryFrame::sg_vertices`]): a sheet flat for x < 0 and rolled for
    /// x > 0, held at two vertices, lists its corners and boundary samples, a junction point
    /// on each border the bend crosses, the held vertices as handles, and, once two folds
    /// cross, the new singular vertex — each at its S_P vertex's pattern and 3D position.
    #[test]
    fn frame_lists_every_kind_of_sg_vertex_with_its_positions() {
        let obstacles = Obstacles::new(&RoomConfig::default());
        let check = |shape: &dyn Fn(V2) -> V3, held: &[usize]| {
            let (mut sp, mut sg) = sheet();
            for i in 0..sp.num_vertices() {
                sp.pos[i] = shape(sp.pattern[i]);
            }
            let mut g = layer(&sp);
            let mut fixed = vec![false; sp.num_vertices()];
            for &v in held {
                fixed[v] = true;
            }
            g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
            sg.validate(&sp).unwrap();
            let mut count = [0usize; 5];
            for v in g.frame().sg_vertices(&sg, &sp) {
                let i = v.sp_index as usize;
                assert_eq!(v.p2, sp.pattern[i]);
                assert_eq!(v.p3, sp.pos[i]);
                let on_boundary = sp.topo.vertex_on_boundary[i];
                match v.kind {
                    VKind::Boundary | VKind::Corner | VKind::Junction => assert!(on_boundary),
                    VKind::InteriorSingular => assert!(!on_boundary),
                    VKind::Handle => assert!(fixed[i]),
                }
                count[v.kind as usize] += 1;
            }
            count
        };
        let r = 0.02;
        let half_roll = |q: V2| {
            if q.x <= 0.0 {
                V3::new(q.x, q.y, 0.0)
            } else {
                let a = q.x / r;
                V3::new(r * a.sin(), q.y, r * (1.0 - a.cos()))
            }
        };
        let [boundary, corner, singular, junction, handle] = check(&half_roll, &[0, 5]);
        assert!(boundary >= 4, "{boundary} boundary samples");
        assert_eq!(corner, 4);
        assert_eq!(singular, 0);
        assert!(
            junction >= 2,
            "{junction} junction points: the bend crosses two borders"
        );
        assert_eq!(handle, 2);
        let roof = |q: V2| V3::new(q.x, q.y, 0.5 * (q.x.abs() + q.y.abs()));
        let [_, _, singular, _, handle] = check(&roof, &[]);
        assert!(
            singular >= 1,
            "the crossing of two folds is a singular vertex"
        );
        assert_eq!(handle, 0);
    }

    /// The non-developable-vertex detector: a sheet bent along one direction only (a tight
    /// cylinder) has no singular vertex, one folded along two crossing lines (a pyramid-like
    /// roof, z = a(|x| + |y|)) gets one at the crossing.
    #[test]
    fn crossing_bends_make_a_singular_vertex_and_a_cylinder_does_not() {
        let run = |shape: &dyn Fn(V2) -> V3| {
            shaped_frame(shape)
                .singular
                .iter()
                .filter(|s| s.case == SingularCase::NonDevelopable)
                .map(|s| s.pos2)
                .collect::<Vec<_>>()
        };
        let r = 0.02;
        let cylinder = run(&|q: V2| {
            let a = q.x / r;
            V3::new(r * a.sin(), q.y, r * (1.0 - a.cos()))
        });
        assert!(cylinder.is_empty(), "{cylinder:?}");
        let c = 0.0; // the pattern is centred on the origin
        let roof = run(&|q: V2| V3::new(q.x, q.y, 0.5 * ((q.x - c).abs() + (q.y - c).abs())));
        assert!(!roof.is_empty(), "no singular vertex where two folds cross");
        let p = roof[0];
        assert!((p - V2::new(c, c)).norm() < 0.02, "at {p:?}");
    }

    /// A rounded fold running obliquely across the lattice: two flat regions, no one-triangle
    /// flat region between the fold's zigzag edges, and the fold itself a few regions (a
    /// curved strip and the creases beside it), not one per S_P edge.
    #[test]
    fn oblique_fold_is_two_flat_regions_and_one_fold() {
        let (mut sp, mut sg) = sheet();
        let n = V2::new(1.0, 0.35).normalize();
        for i in 0..sp.num_vertices() {
            let q = sp.pattern[i];
            let d = q.dot(&n) - 0.004;
            // The far side turns by 0.8 rad over a rounded band 2.5 cm wide (two to three
            // rows of triangles), as a fold of the simulated sheet does.
            let (w, turn) = (0.025, 0.8f64);
            let r = w / turn;
            let (along, z) = if d <= 0.0 {
                (d, 0.0)
            } else if d < w {
                (r * (d / r).sin(), r * (1.0 - (d / r).cos()))
            } else {
                let (c, s) = (turn.cos(), turn.sin());
                (
                    r * turn.sin() + (d - w) * c,
                    r * (1.0 - turn.cos()) + (d - w) * s,
                )
            };
            let t = q - n * q.dot(&n);
            let p2 = t + n * (along + 0.004);
            sp.pos[i] = V3::new(p2.x, p2.y, z);
        }
        let mut g = layer(&sp);
        let fixed = vec![false; sp.num_vertices()];
        let obstacles = Obstacles::new(&RoomConfig::default());
        g.update(&mut sp, &mut sg, &fixed, &obstacles, 1, true, &[]);
        let f = g.frame();
        let flats: Vec<u32> = f
            .regions
            .iter()
            .filter(|r| r.kind == RegionKind::Flat)
            .map(|r| r.num_triangles)
            .collect();
        let fold = f.regions.len() - flats.len();
        println!("flat regions {flats:?}, fold regions {fold}");
        assert_eq!(flats.len(), 2, "{flats:?}");
        assert!(flats.iter().all(|&n| n >= 20), "{flats:?}");
        assert!((1..=3).contains(&fold), "{fold} fold regions");
    }

    /// A test sheet with the default layer (isometry on), squeezed along x and stepped one
    /// still or driven frame at a time.
    struct IsoRig {
        sp: PhysMesh,
        sg: GeomStructure,
        flat: Vec<V3>,
        layer: GeometryLayer,
        frame: u64,
    }

    impl IsoRig {
        fn new() -> Self {
            let (sp, sg) = sheet();
            let layer = GeometryLayer::new(
                &sp,
                GeometryConfig::default(),
                &PaperMaterial::of(crate::control::Material::Printer),
                1,
            );
            let flat = sp.pos.clone();
            Self {
                sp,
                sg,
                flat,
                layer,
                frame: 0,
            }
        }

        /// Places the sheet squeezed by `squeeze` along x, runs one frame and returns whether
        /// the isometry step ran.
        fn runs(&mut self, squeeze: f64, driven: bool) -> bool {
            self.place(squeeze, 0.0);
            self.step(driven, &[]);
            self.layer.frame().isometry.phase1_iters > 0
        }

        /// Places the sheet squeezed by `squeeze` along x and rippled by `ripple_m` in z.
        fn place(&mut self, squeeze: f64, ripple_m: f64) {
            for (p, q) in self.sp.pos.iter_mut().zip(&self.flat) {
                let z = ripple_m * (40.0 * q.x).sin() * (25.0 * q.y).cos();
                *p = V3::new(q.x * (1.0 - squeeze), q.y, q.z + z);
            }
        }

        /// Runs one frame with `start_normals` as the frame's start.
        fn step(&mut self, driven: bool, start_normals: &[V3]) {
            self.frame += 1;
            let fixed = vec![false; self.sp.num_vertices()];
            let obstacles = Obstacles::new(&RoomConfig::default());
            self.layer.update(
                &mut self.sp,
                &mut self.sg,
                &fixed,
                &obstacles,
                self.frame,
                driven,
                start_normals,
            );
        }

        /// Unit normals of the triangles.
        fn normals(&self) -> Vec<V3> {
            self.sp
                .triangles
                .iter()
                .map(|t| {
                    let x = t.map(|i| self.sp.pos[i as usize]);
                    (x[1] - x[0]).cross(&(x[2] - x[0])).normalize()
                })
                .collect()
        }
    }

    /// The isometry step never turns a triangle over from the frame's start, even one the
    /// physics left at 90° from it: here the start normal of the triangle the step turns most
    /// is set perpendicular to its normal before the step, on the side the step turns away
    /// from, and the step is reverted.
    #[test]
    fn isometry_never_turns_a_triangle_over_from_the_frame_start() {
        let mut free = IsoRig::new();
        free.place(0.02, 2e-3);
        let before = free.normals();
        free.step(true, &before);
        assert!(!free.layer.frame().isometry_reverted);
        let after = free.normals();
        let (t, turn) = (0..before.len())
            .map(|t| (t, 1.0 - before[t].dot(&after[t])))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        assert!(turn > 1e-9, "the step turns triangle {t} ({turn:e})");
        let mut start = before.clone();
        let away = after[t] - before[t] * after[t].dot(&before[t]);
        start[t] = (-away.normalize() + before[t] * 1e-9).normalize();
        let mut rig = IsoRig::new();
        rig.place(0.02, 2e-3);
        rig.step(true, &start);
        assert!(rig.layer.frame().isometry_reverted);
        assert!(
            !rig.layer.checked_uncrossed(),
            "reverted before the crossing test"
        );
        let n = rig.normals();
        assert!(n[t].dot(&start[t]) >= 0.0, "triangle {t} not turned over");
        assert!(
            (n[t] - before[t]).norm() < 1e-12,
            "triangle {t} kept as before the step"
        );
    }

    /// The isometry step tells the sim when it has already found the final positions
    /// uncrossed (the pass-through guard then skips its own sweep): after a step that ran its
    /// crossing test, not after one that did not run or was reverted before the test.
    #[test]
    fn isometry_reports_positions_it_found_uncrossed() {
        let mut rig = IsoRig::new();
        rig.place(0.02, 2e-3);
        let n = rig.normals();
        rig.step(true, &n);
        assert!(!rig.layer.frame().isometry_reverted);
        assert!(rig.layer.checked_uncrossed());
        let crossed = rig.layer.proximity.any_crossing(&rig.sp);
        assert!(!crossed, "the positions left are uncrossed");
        // Reverted before the test: `isometry_never_turns_a_triangle_over_from_the_frame_start`.
        // Idle frame: nothing checked.
        rig.layer.idle_frame(99);
        assert!(!rig.layer.checked_uncrossed());
    }

    /// The isometry step's trigger (isometry.rs "When it runs"): on a still sheet (no
    /// gesture moving it) it runs only if some edge is compressed by more than 1 %; while a
    /// gesture drives the sheet it runs every frame.
    #[test]
    fn isometry_runs_when_driven_or_compressed_beyond_the_trigger() {
        let runs = |squeeze: f64, driven: bool| IsoRig::new().runs(squeeze, driven);
        assert!(
            !runs(0.005, false),
            "0.5 % on a still sheet: physics' equilibrium kept"
        );
        assert!(runs(0.005, true), "0.5 % while a gesture drives the sheet");
        assert!(runs(0.02, false), "2 % on a still sheet");
    }

    /// Undriven, the isometry step corrects a compression once; the physics rebuilding the
    /// same compression (the hands' doing) does not make it run again, even after passing below
    /// the trigger on its way back (forgetting it there made the step run every other frame on
    /// a held sheet, which then never slept); a 10 % larger one or a driven frame does.
    #[test]
    fn isometry_skips_a_compression_it_already_met() {
        let mut rig = IsoRig::new();
        let mut runs = |squeeze: f64, driven: bool| rig.runs(squeeze, driven);
        assert!(runs(0.02, false), "first undriven 2 %");
        assert!(!runs(0.02, false), "the same 2 % rebuilt");
        assert!(!runs(0.021, false), "5 % more");
        assert!(runs(0.023, false), "15 % more");
        assert!(!runs(0.023, false), "that one rebuilt");
        assert!(runs(0.023, true), "driven");
        assert!(runs(0.02, false), "undriven after a driven frame");
        assert!(!runs(0.005, false), "below the trigger");
        assert!(!runs(0.02, false), "the same 2 % rebuilt after a dip");
        assert!(runs(0.0225, false), "10 % more than the one met");
    }
}
