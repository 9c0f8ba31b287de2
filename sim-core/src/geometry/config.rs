//! # The geometry layer's settings ([`GeometryConfig`]: which of the seeds' steps run, and the
//! impl. choices' thresholds; the parent module's doc says what each step does).

use super::*;

/// Settings of the geometry layer (part of [`crate::SimConfig`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeometryConfig {
    /// Run the layer at all (off = physics only, for comparisons).
    pub enabled: bool,
    /// Compression limit ε_c override (fraction); `None` = the material's.
    pub eps_c: Option<f64>,
    /// Placement spread σ override, metres; `None` = the material's.
    pub sigma_m: Option<f64>,
    /// Propagation passes per frame (digest §3.4: repeat until no compressed flat triangle;
    /// capped, rechecked next frame).
    pub max_passes: u32,
    /// New singular vertices per frame, at most.
    pub max_new_singular_per_frame: u32,
    /// A curved triangle compressed along its own rulings starts a pass only when its
    /// compression exceeds this × ε_c (impl. choice, see the module doc).
    pub curved_eps_factor: f64,
    /// A vertex whose ring normals spread by φ in two directions becomes singular when
    /// φ²/6 exceeds this × ε_c (impl. choice, see the module doc); infinite = off.
    pub gauss_eps_factor: f64,
    /// A non-developable vertex closer than this (pattern distance, metres) to an existing
    /// singular vertex is explained by that vertex's d-cone and not made singular.
    pub gauss_min_spacing_m: f64,
    /// The isometry optimizer.
    pub isometry: IsometryConfig,
    /// Place a singular vertex exactly at its drawn position s̄: when the nearest S_P vertex
    /// cannot move there in full, a new S_P vertex is inserted at s̄ after the frame
    /// ([`crate::sheet::refine`]; off = the nearest vertex moves part of the way, or not at all,
    /// and S_P's connectivity never changes). On by default (see the module doc, "A singular
    /// point gets an S_P vertex at s̄").
    pub insert_singular_vertices: bool,
    /// Largest start strain (|l/l̄ − 1| of its edges) of a vertex inserted at s̄ before the
    /// insertion looks for a less strained place close by: the foot of s̄ on a folded edge,
    /// or the nudges of [`crate::sheet::refine::insert_vertex_near`] (see the module doc, "A
    /// singular point gets an S_P vertex at s̄"). Default
    /// [`crate::sheet::refine::SPLIT_START_STRAIN_MAX`] (5 %); infinite: at s̄ whatever the
    /// strain (the behaviour before 2026-11-29, kept for comparisons and tests).
    pub insertion_max_start_strain: f64,
    /// Flip a compressed S_P edge inside a flat region whose quad's other diagonal is not
    /// compressed (the seeds' flip rule, T 826; done by the sim at the start of the next step,
    /// [`crate::sheet::refine::flip_edge`]). On by default (see the module doc, "Edge flips").
    pub flip_compressed_edges: bool,
    /// Cut S_P along a new strip's imaginary ruling, so that the ruling becomes a chain of
    /// S_P edges the sheet can bend along (the seeds' strip cutting, TOG P 459–487; done by the
    /// sim at the start of the next step, [`crate::sheet::cut`]). Off by default: every cut
    /// adds triangles and Newton work for as long as the sheet stays bent along it
    /// (coarsening, [`Self::coarsen_flat_regions`], takes them out only where it opens out
    /// flat again; see the module doc, "Strip cutting").
    pub cut_strips: bool,
    /// Take a vertex that a strip cut added out of S_P again once the sheet is flat, unheld
    /// and at rest around it (plan step 2 of `docs/sp-regeneration-plan.md`; done by the sim at
    /// the start of the next step, [`crate::sheet::coarsen`]). Only vertices beyond the
    /// initial lattice that are not singular are candidates — with `cut_strips` off there are
    /// none. On by default (see the module doc, "Coarsening").
    pub coarsen_flat_regions: bool,
    /// Regenerate S_P from S_G after every awake frame in which the sheet has a curved region
    /// (the seeds' step (g), TOG §4.1 / §5; [`crate::sheet::regenerate`], done by the sim at the
    /// end of the step), and run the isometry step (h) on the regenerated S_P instead of inside
    /// the layer. Off by default: measured over every seed scene, the mode costs 3.7–8.9× the
    /// default's frame, is 5–300× less accurate (c_mean) and creates singular points where the
    /// default has none, and it allocates (`docs/sp-regeneration-plan.md`, "Per-frame
    /// regeneration, built and measured").
    pub regenerate_sp: bool,
}

impl Default for GeometryConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            eps_c: None,
            sigma_m: None,
            max_passes: 4,
            max_new_singular_per_frame: 1,
            curved_eps_factor: 40.0,
            gauss_eps_factor: 15.0,
            gauss_min_spacing_m: 0.02,
            isometry: IsometryConfig::default(),
            insert_singular_vertices: true,
            insertion_max_start_strain: crate::sheet::refine::SPLIT_START_STRAIN_MAX,
            flip_compressed_edges: true,
            cut_strips: false,
            coarsen_flat_regions: true,
            regenerate_sp: false,
        }
    }
}

impl GeometryConfig {
    /// Returns a copy with every value finite and in range.
    pub fn sanitized(self) -> Self {
        let mut c = self;
        c.eps_c = c.eps_c.filter(|e| e.is_finite() && *e > 0.0 && *e < 0.5);
        c.sigma_m = c.sigma_m.filter(|s| s.is_finite() && *s >= 0.0 && *s < 0.1);
        c.max_passes = c.max_passes.min(64);
        c.max_new_singular_per_frame = c.max_new_singular_per_frame.min(16);
        if !(c.curved_eps_factor.is_finite() && c.curved_eps_factor >= 1.0) {
            c.curved_eps_factor = Self::default().curved_eps_factor;
        }
        if c.gauss_eps_factor.is_nan() || c.gauss_eps_factor < 1.0 {
            c.gauss_eps_factor = Self::default().gauss_eps_factor;
        }
        if !(c.gauss_min_spacing_m.is_finite() && (0.0..1.0).contains(&c.gauss_min_spacing_m)) {
            c.gauss_min_spacing_m = Self::default().gauss_min_spacing_m;
        }
        if c.insertion_max_start_strain.is_nan() || c.insertion_max_start_strain < 0.0 {
            c.insertion_max_start_strain = Self::default().insertion_max_start_strain;
        }
        let i = &mut c.isometry;
        i.phase1_max_iters = i.phase1_max_iters.min(200);
        i.phase2_max_iters = i.phase2_max_iters.min(1000);
        let d = IsometryConfig::default();
        if !(i.phase1_tol.is_finite() && i.phase1_tol >= 0.0) {
            i.phase1_tol = d.phase1_tol;
        }
        if !(i.phase2_rel_tol.is_finite() && i.phase2_rel_tol > 0.0) {
            i.phase2_rel_tol = d.phase2_rel_tol;
        }
        if !(i.proximity.is_finite() && i.proximity > 0.0 && i.proximity < 1e3) {
            i.proximity = d.proximity;
        }
        if i.max_speed_m_s.is_nan() || i.max_speed_m_s < 0.0 {
            i.max_speed_m_s = d.max_speed_m_s;
        }
        if let Some(m) = i.phase1_min_decrease
            && !(0.0..1.0).contains(&m)
        {
            i.phase1_min_decrease = d.phase1_min_decrease;
        }
        if let Some(t) = i.trigger_compression
            && !(0.0..1.0).contains(&t)
        {
            i.trigger_compression = d.trigger_compression;
        }
        c
    }
}
