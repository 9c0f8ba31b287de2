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
    /// φ²/6 exceeds this × ε_c (impl. choice, see the module doc).
    pub gauss_eps_factor: f64,
    /// A non-developable vertex closer than this (pattern distance, metres) to an existing
    /// singular vertex is explained by that vertex's d-cone and not made singular.
    pub gauss_min_spacing_m: f64,
    /// The isometry optimizer.
    pub isometry: IsometryConfig,
    /// Place a singular vertex exactly at its drawn position s̄: when the nearest S_P vertex
    /// cannot move there in full, a new S_P vertex is inserted at s̄ after the frame
    /// ([`crate::sheet::refine`]; off = the nearest vertex moves part of the way, or not at all,
    /// and S_P's connectivity never changes; for the bench report's comparison rows). On by
    /// default (see the module doc, "Implementation decisions").
    pub insert_singular_vertices: bool,
    /// Largest start strain (|l/l̄ − 1| of its edges) of a vertex inserted at s̄ before the
    /// insertion looks for a less strained place close by: the foot of s̄ on a folded edge,
    /// or the nudges of [`crate::sheet::refine::insert_vertex_near`] (see the module doc,
    /// "Implementation decisions"). Default
    /// [`crate::sheet::refine::SPLIT_START_STRAIN_MAX`] (5 %); infinite: at s̄ whatever the
    /// strain (the tests use it to make strained insertions on purpose).
    pub insertion_max_start_strain: f64,
    /// Flip a compressed S_P edge inside a flat region whose quad's other diagonal is not
    /// compressed (the seeds' flip rule, T 826; done by the sim at the start of the next step,
    /// [`crate::sheet::refine::flip_edge`]). On by default (see the module doc, step 2).
    pub flip_compressed_edges: bool,
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
