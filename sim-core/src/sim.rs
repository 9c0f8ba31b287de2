//! # The simulation facade
//!
//! [`Sim`] is what the plugin's worker thread, the offline renderer, the tests and the benches
//! drive: apply [`Command`]s, then [`Sim::step`] one frame, read the [`FrameOutput`] (sound
//! input and statistics), the per-vertex contacts ([`Sim::contacts`]) and, when wanted, copy
//! the mesh out ([`Sim::write_mesh`]).
//!
//! Frames have a fixed duration `1 / frame_rate_hz` of simulated time; the caller decides when
//! to step (the plugin follows the audio sample clock, the offline renderer steps in lockstep
//! with the audio). Given the same configuration, seed and command sequence, the output is
//! bit-identical: no hash-map iteration, no time-based seeds, no threads inside a step.
//!
//! ## One frame (digest-crumpling §3.0, steps (a)–(c) of Fig. 16 / Fig. 2.3)
//!
//! The seeds' frame loop: TOG 2015 Fig. 16 (`001_44bc28f7c5e9f81f.txt`), thesis Fig. 2.3
//! (`000_cb4d91e46ec5927f.txt`).
//!
//! 1. (a) while the crumple hands squeeze, the sheet's closest approach to itself
//!    ([`crate::self_proximity`]) limits the squeeze (gesture_rig.rs "Crumple cap") and the
//!    frame's start is kept; the gesture rig moves the handles towards their target poses
//!    ([`crate::gesture_rig`], [`crate::handles`]); moved obstacle planes ease towards their
//!    new place ([`crate::collision`]);
//! 2. (b) `substeps` physics substeps ([`crate::physics`]): held vertices as hard constraints
//!    interpolated across the frame, obstacles with their depth limit, friction;
//! 3. (c) S_G reads its vertex positions from S_P ([`crate::sheet::geometric`]);
//! 4. (d)–(h) the geometry layer ([`crate::geometry`]), its outputs in [`Sim::geometry`];
//!    then what is still strained beyond 8 % is projected back (beyond the seeds:
//!    [`crate::physics::strain_limit`]), the hands regripping the held vertices it moved;
//! 5. while squeezing, a frame that passed the sheet through itself is undone (below);
//! 6. contacts (flag, obstacle, slip speed, normal force), the layers' slip on each other (the
//!    last substep's sheet–sheet pairs, [`crate::physics::sheet_contact::layer_slip`]) and the
//!    metrics are updated;
//! 7. the sound analysis ([`crate::sound_analysis`]) turns the frame's curvature flips, new
//!    singular vertices and sliding contacts into crumple and friction events with their
//!    resonators, written to the frame's [`SoundFrame`], and the statistics are written.
//!
//! ## When a substep or a frame goes wrong
//!
//! The hands are hard constraints: a substep starts with each held vertex at its target and the
//! free vertices where the predictor carries them, and the solve brings them after. The squeeze
//! can also push the sheet through itself. Four remedies act only where the plain frame fails
//! (`substep`, `undo`):
//!
//! ```text
//! substep solved (physics/newton.rs)
//!  ├─ a held vertex's jump turned a triangle over, or the solve stalled or pinned with a
//!  │  triangle strained beyond HOLD_BACK_STRAIN and more than at its start
//!  │    → solve again from the substep's start, at rest, hands back at the frame's start
//!  └─ still turned over, or capped / stalled / pinned with that strain
//!       → solve as 2, 4, 8 shorter substeps (SPLIT_FACTORS), hands interpolated, momentum
//!         kept; where none counts, once more with a slipped hand's offset faded out
//! frame ended crossed while squeezing
//!  → undo: sheet and hands back to the frame's start, at rest, contact stiffened there
//!  ├─ unless the start already crossed, or MAX_UNDO_STREAK frames were undone in a row
//!  └─ a restored start strained beyond UNDO_RELAX_STRAIN: its substeps solved again with
//!     the hands held, then with UNDO_RELAX_FINE_FACTOR × as many, kept if better
//! ```
//!
//! No seed scene stalls, splits, undoes or relaxes a frame, so none plays differently for these
//! (`scenario_probe` hashes); regression fixtures are in `sim-core/tests/fixtures/`
//! (`tests/stalled_substeps.rs`, `tests/undone_frames.rs`, `tests/crossed_start.rs`). Each
//! section below names in quotes the section of `docs/decisions.md` with its figures.
//!
//! ## A substep solved again
//!
//! The second solve, from rest with the hands back, stands if it turns nothing over and, after
//! a stall, leaves at most [`HOLD_BACK_GAIN`] (90 %) of the first solve's strain: a hand's jump
//! can turn a triangle the solve cannot turn back, and without the margin a sheet strained the
//! same either way held its hands back frame after frame ("A substep solved again from rest").
//! Counted in [`FrameStats::held_back_substeps`].
//!
//! ## A substep solved as shorter ones
//!
//! A shorter substep has a closer predictor and a better-conditioned system, and a hand's jump
//! split in parts drags its neighbours along. A split counts if none of its substeps turns a
//! triangle over and it leaves at most [`HOLD_BACK_GAIN`] of the best strain so far; the ladder
//! stops at the first within [`HOLD_BACK_STRAIN`]. Fading a slip's offset is the second ladder,
//! not the first: a slip moves the hand where the sheet pulls it ("A substep solved as shorter
//! ones"). Counted in [`FrameStats::split_substeps`]. "Flipped" then means turned over within
//! one solver step: the reference ([`crate::metrics::MetricsTracker::previous_normals`])
//! advances with the split's substeps, since a region snapping through can turn past 90° in a
//! frame by steps of less ("Flipped triangles counted per solver step").
//!
//! ## The pass-through guard
//!
//! Armed when the frame starts uncrossed: the closest approach above zero, or a crossing sweep
//! where layers touch (skipped when the isometry step has just swept the final positions,
//! [`crate::geometry::GeometryLayer::checked_uncrossed`]). A crossed start stands
//! ([`FrameStats::kept_crossed_start`]) and at most [`MAX_UNDO_STREAK`] frames (0.1 s) are
//! undone in a row, since a crossing the replay cannot avoid froze the squeeze ("The
//! pass-through guard: crossed starts and the undo streak"). An undone frame takes the flipped
//! triangles' reference back. The frame let through after a streak drops the contact's
//! boosts (sheet_contact.rs "Stiffening where the sheet crossed"): it ends crossed, and pairs
//! stiffened ×4 per undone repeat (up to ×4096) threw the crossed layers apart at metres per
//! second in the next frame, turning a triangle over ("Boosts dropped after an undo streak").
//!
//! ## An undone frame relaxed
//!
//! A start strained beyond [`UNDO_RELAX_STRAIN`] (the health limit, 0.1) is relaxed: a mesh
//! change at the frame's start can start strained, and the frame that would relax it is the one
//! undone. The result stands if it turns nothing over, does not cross and lowers the largest
//! strain; the sheet is left at rest either way ("An undone frame relaxed"). Counted in
//! [`FrameStats::relaxed_undone`].
//!
//! ## Sleeping
//!
//! A sheet at rest costs nothing: when no gesture or obstacle is settling and no vertex has
//! left a box of ±[`REST_BOX_M`] around where it was at the start of the last
//! [`SLEEP_FRAMES`] frames (positions, not velocities: a shape the solve and the projections
//! after it agree on is at rest), the velocities are zeroed and the sheet sleeps — `step` then
//! only advances the frame counter (the work counter [`Sim::work_counter`] does not move). Any
//! command that changes something wakes it. The box is [`SLEEP_SPEED_M_S`] over the window: a
//! sheet creeping faster stays awake, as with a per-frame speed test; what the box adds is that
//! a vertex chattering in place — a layer pressed on another by held hands going back and
//! forth by tenths of a millimetre every frame, a limit cycle of the solve and the contact —
//! is at rest (real paper held still does not chatter; docs/decisions.md, "Chatter in place is
//! rest").
//!
//! ## Where each part lives
//!
//! This file holds the sim's state, its commands and the frame loop ([`Sim::step`]). Solving a
//! substep and solving it again is `substep`, undoing a frame `undo`, changing the mesh
//! (insertions, flips) `remesh`, saved sheets `saved`, the phase clock `phase_times`.
//!
//! ## Allocation
//!
//! Everything is allocated in [`Sim::new`] (and on `Reset` / `Size`, which rebuild the
//! sheet); `step`, the other commands and [`Sim::write_mesh`] into a snapshot of sufficient
//! capacity ([`Sim::mesh_capacity`]) do not allocate (tested with a counting allocator).

mod phase_times;
mod remesh;
mod saved;
mod substep;
pub mod tear;
pub mod tear_hands;
mod undo;

pub use phase_times::PhaseTimes;
pub use saved::{RestoreError, SAVED_SHEET_VERSION, SavedSheet};

use phase_times::Stopwatch;

use rand::SeedableRng;

use crate::collision::{CONTACT_SKIN_M, Obstacles, TOUCH_DIST_M, VertexContact, penalty_stiffness};
use crate::control::{Command, GestureParam, Material, SheetSize};
use crate::geometry::{GeometryConfig, GeometryFrame, GeometryLayer};
use crate::gesture_rig::GestureRig;
use crate::gesture_rig::{NUM_SLOT_HANDS, SQUEEZE_REACH_M};
use crate::material::PaperMaterial;
use crate::math::{V2, V3};
use crate::mesh_snapshot::{MeshSnapshot, VertexTag};
use crate::metrics::{Metrics, MetricsTracker};
use crate::physics::{Kinematics, PhysParams, Physics, SolverConfig, SubstepReport};
use crate::room::RoomConfig;
use crate::self_proximity::SelfProximity;
use crate::sheet::pattern::{Pattern, lattice};
use crate::sheet::{MeshConfig, Sheet};
use crate::sound_analysis::{AnalysisConfig, AnalysisInput, AnalysisStats, SoundAnalysis};
use crate::sound_input::SoundFrame;

pub use crate::control::DEFAULT_FRAME_RATE_HZ;

/// Largest vertex speed of a sheet allowed to fall asleep, m/s: 1 mm over the
/// [`SLEEP_FRAMES`] it must stay that slow. A held sheet's free flap creeps into its sag at a few
/// millimetres a second under the linear air drag (real air barely damps so slow a motion), and
/// at 2 mm/s it kept the sheet awake for seconds after the hands stopped.
pub const SLEEP_SPEED_M_S: f64 = 5e-3;
/// Stream constant of the fibre texture's seed, apart from the sheet's stream.
const FIBRE_STREAM: u64 = 0x6669_6272;
/// Consecutive quiet frames before the sheet falls asleep.
pub const SLEEP_FRAMES: u32 = 40;
/// Largest distance of any vertex from where it was at the start of the sleep window at the
/// default frame rate, metres (module doc, "Sleeping"): [`SLEEP_SPEED_M_S`] over
/// [`SLEEP_FRAMES`] frames, 1 mm; at other frame rates the window's duration scales it.
pub const REST_BOX_M: f64 = SLEEP_SPEED_M_S * SLEEP_FRAMES as f64 / DEFAULT_FRAME_RATE_HZ;
/// Strain (largest principal stretch deviation, `Metrics::max_strain`) above which a stalled
/// or pinned substep is solved again from rest with the hands held back (module doc, "A
/// substep solved again"): half the stress tests' bound, five times the seed scenes' health
/// limit.
pub const HOLD_BACK_STRAIN: f64 = 0.5;
/// A substep solved again with the hands held back stands only if it leaves at most this
/// fraction of the first solve's strain (module doc, "A substep solved again").
pub const HOLD_BACK_GAIN: f64 = 0.9;
/// A substep whose solve ended short and strained the sheet is solved again as this many
/// shorter substeps, each count tried in turn until one stands (module doc, "A substep solved
/// as shorter ones").
pub const SPLIT_FACTORS: [u32; 3] = [2, 4, 8];
/// An undone frame whose start is strained beyond this is relaxed from it with the hands held
/// (module doc, "An undone frame relaxed"): the scenario health limit.
pub const UNDO_RELAX_STRAIN: f64 = 0.1;
/// An undone frame's relaxation that passes the sheet through itself is tried again with this
/// many times the frame's substeps (module doc, "An undone frame relaxed").
pub const UNDO_RELAX_FINE_FACTOR: u32 = 4;
/// Frames in a row the pass-through guard may undo before one frame goes through as simulated
/// (`Sim::undo_pass_through`; module doc, "The pass-through guard"): 0.1 s at 200 frames/s.
pub const MAX_UNDO_STREAK: u32 = 20;

/// Everything that defines a sheet before any command.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimConfig {
    /// Sheet size.
    pub size: SheetSize,
    /// Paper grade.
    pub material: Material,
    /// Random seed (singular-point placement, crumple jitter).
    pub seed: u64,
    /// Table and wall.
    pub room: RoomConfig,
    /// Simulation frames per second.
    pub frame_rate_hz: f64,
    /// Physics solver parameters (substeps, iterations, stiffness scaling, damping).
    pub solver: SolverConfig,
    /// Mesh density of new sheets.
    pub mesh: MeshConfig,
    /// The developable-geometry layer (on by default; off = physics only).
    pub geometry: GeometryConfig,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            size: SheetSize::A4,
            material: Material::Printer,
            seed: 1,
            room: RoomConfig::default(),
            frame_rate_hz: DEFAULT_FRAME_RATE_HZ,
            solver: SolverConfig::default(),
            mesh: MeshConfig::default(),
            geometry: GeometryConfig::default(),
        }
    }
}

impl SimConfig {
    /// Returns a copy with every value finite and in range.
    pub fn sanitized(self) -> Self {
        let mut c = self;
        c.room = c.room.sanitized();
        if !(c.frame_rate_hz.is_finite() && (1.0..=100_000.0).contains(&c.frame_rate_hz)) {
            c.frame_rate_hz = DEFAULT_FRAME_RATE_HZ;
        }
        c.solver = c.solver.sanitized();
        c.mesh = c.mesh.sanitized();
        c.geometry = c.geometry.sanitized();
        c
    }
}

/// Per-frame statistics (editor meters, renderer report, benches).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// True if the sheet was asleep and the frame did no work.
    pub asleep: bool,
    /// Vertices of the simulation mesh.
    pub num_vertices: u32,
    /// Triangles of the simulation mesh.
    pub num_triangles: u32,
    /// Persistent interior singular vertices.
    pub num_singular: u32,
    /// Mean edge compression against the pattern, %.
    pub c_mean_pct: f32,
    /// Kinetic energy, joules.
    pub kinetic_energy_j: f32,
    /// Percentage of edges compressed by more than 1 %.
    pub n_comp_pct: f32,
    /// Largest principal stretch deviation |λ − 1| over triangles.
    pub max_strain: f32,
    /// Σ over interior vertices of |2π − Σ angles|, radians.
    pub angle_defect_rad: f32,
    /// Largest vertex speed, m/s.
    pub max_speed_m_s: f32,
    /// Vertices touching an obstacle.
    pub num_contacts: u32,
    /// Vertices held by handles.
    pub num_held: u32,
    /// Triangles whose normal turned over since the previous frame (0 unless the integration
    /// failed).
    pub num_flipped: u32,
    /// Physics substeps integrated in this frame.
    pub substeps: u32,
    /// Solver iterations summed over the frame's substeps.
    pub iterations: u32,
    /// Substeps whose Newton solve ended at the iteration cap, short of its stopping rule.
    pub capped_substeps: u32,
    /// Substeps whose state had to be recovered (non-finite); 0 in a healthy run.
    pub recoveries: u32,
    /// Newton line-search halvings summed over the frame's substeps.
    pub halvings: u32,
    /// Substeps in which the Newton solve pinned free vertices whose triangle every step
    /// would have turned over (physics/newton.rs "Pinning"); 0 in the seed scenes.
    pub pinned_substeps: u32,
    /// Substeps solved again from rest with the hands where the frame started — because a
    /// hand's jump turned a triangle over, or the solve stalled or pinned and left a triangle
    /// strained beyond [`HOLD_BACK_STRAIN`] — whose second solve stood (module doc, "A
    /// substep solved again"); 0 in the seed scenes.
    pub held_back_substeps: u32,
    /// Substeps that turned a triangle over, or whose solve ended short (capped, stalled or
    /// pinned) and left a triangle strained beyond [`HOLD_BACK_STRAIN`], solved again as
    /// shorter ones ([`SPLIT_FACTORS`]) that stood (module doc, "A substep solved as shorter
    /// ones"); 0 in the seed scenes.
    pub split_substeps: u32,
    /// Frames in a row (this one included) whose motion was undone because it would have
    /// passed the sheet through itself (0 = this frame went through; gesture_rig.rs
    /// "Crumple cap").
    pub undo_streak: u32,
    /// This frame was undone from a start strained beyond [`UNDO_RELAX_STRAIN`], and solving
    /// it again from that start with the hands held relaxed it (module doc, "An undone frame
    /// relaxed"); false in the seed scenes.
    pub relaxed_undone: bool,
    /// The pass-through guard found this frame passing the sheet through itself, but the
    /// frame's start crossed already (two layers of one fold, which the closest-approach query
    /// that arms the guard skips), so the frame stood: undoing it would only return to a
    /// crossed start, frame after frame (module doc, "The pass-through guard"); false in the
    /// seed scenes.
    pub kept_crossed_start: bool,
}

/// What one frame produces.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameOutput {
    /// Sound input of the frame.
    pub sound: SoundFrame,
    /// Statistics of the frame.
    pub stats: FrameStats,
}

/// The simulated sheet.
#[derive(Debug)]
pub struct Sim {
    cfg: SimConfig,
    frame: u64,
    sheet: Sheet,
    physics: Physics,
    rig: GestureRig,
    geometry: GeometryLayer,
    obstacles: Obstacles,
    material: PaperMaterial,
    params: PhysParams,
    rng: rand_pcg::Pcg32,
    fixed: Vec<bool>,
    kin_target: Vec<V3>,
    forces: Vec<V3>,
    /// Largest strain of each vertex's triangles (the hands' give, `GestureRig::apply_slip`).
    vertex_strain: Vec<f64>,
    /// The strain limit's scratch (physics/strain_limit.rs).
    strain_limit: crate::physics::strain_limit::StrainLimit,
    contacts: Vec<VertexContact>,
    /// Per vertex, its slip on another layer it is pressed on, m/s (−1: none; `update_contacts`).
    layer_slip: Vec<f32>,
    metrics: MetricsTracker,
    last_metrics: Metrics,
    asleep: bool,
    quiet_frames: u32,
    mesh_capacity: (usize, usize),
    frames_simulated: u64,
    /// S_P vertices inserted for singular vertices since the sheet was made (sim/remesh.rs).
    inserted_vertices: u64,
    /// This frame's pass-through guard found the frame's start crossed already and let the
    /// frame stand (`undo_pass_through`).
    kept_crossed_start: bool,
    /// S_P edges flipped (sim/remesh.rs).
    flipped_edges: u64,
    analysis: SoundAnalysis,
    proximity: SelfProximity,
    /// S_P positions at the start of the frame (kept while the crumple hands squeeze).
    frame_start_pos: Vec<V3>,
    /// S_P positions at the start of every awake frame (the sleep test's motion).
    motion_start_pos: Vec<V3>,
    /// S_P positions at the start of the sleep window (`quiet_frames` frames ago; empty: the
    /// window starts at the next quiet frame).
    rest_box_pos: Vec<V3>,
    /// Velocities at the start of the frame (the air the sheet moves, sound_analysis/air.rs).
    motion_start_vel: Vec<V3>,
    /// S_P pattern at the start of the frame (kept with `frame_start_pos`): a singular point
    /// placed in a frame that is then undone has moved a vertex in the pattern.
    frame_start_pattern: Vec<V2>,
    /// S_P positions before the contact depth limit of a substep.
    pre_limit_pos: Vec<V3>,
    /// Positions and velocities after a substep, kept while it is solved again
    /// (`solve_substep_again`).
    stalled_pos: Vec<V3>,
    stalled_vel: Vec<V3>,
    /// S_P positions and velocities at the start of a substep being solved as shorter ones
    /// (`solve_substep_split`; preallocated).
    split_start_pos: Vec<V3>,
    split_start_vel: Vec<V3>,
    /// `split_start_pos`/`split_start_vel` hold this substep's start already (saved by
    /// `solve_substep_again`).
    split_start_saved: bool,
    /// Where each held vertex starts a split substep, less where its hand held it at the
    /// substep's start (a hand that slipped or re-gripped since): faded out over the split in
    /// the second ladder (preallocated).
    split_jump: Vec<V3>,
    /// The flipped-triangle reference ([`MetricsTracker::previous_normals`]) before a split
    /// substep advanced it, and at the frame's start if a split advanced it this frame
    /// (`frame_normals_saved`): an undone frame goes back to it (preallocated).
    split_start_normals: Vec<V3>,
    frame_start_normals: Vec<V3>,
    frame_normals_saved: bool,
    /// The best split of a substep so far (positions, velocities, flipped-triangle reference),
    /// kept while shorter ones are tried (preallocated).
    split_best_pos: Vec<V3>,
    split_best_vel: Vec<V3>,
    split_best_normals: Vec<V3>,
    /// Whether `step` reads the clock between its phases (benchmarks).
    phase_timing: bool,
    stopwatch: Stopwatch,
    phase_ns: PhaseTimes,
    /// The tear (sim/tear.rs).
    tear: tear::TearProgress,
    /// The fibres' resistance to a pull's tear (tearing/fibres.rs), from the sheet's seed.
    fibres: crate::tearing::fibres::FibreTexture,
    /// The seed the fibres were made from: the sheet's when it was built (a seed changed
    /// later is the next sheet's).
    fibre_seed: u64,
    /// The lips' millimetre detail (tearing/lips.rs), rebuilt where the mesh changes.
    lips: crate::tearing::lips::Lips,
}

impl Sim {
    /// A new flat sheet resting at its home position (on the table, or falling if the table
    /// is off).
    pub fn new(cfg: SimConfig) -> Self {
        let cfg = cfg.sanitized();
        let material = PaperMaterial::of(cfg.material);
        let sheet = Sheet::new_flat(
            cfg.size,
            cfg.mesh,
            cfg.room.home_height_m(),
            material.areal_density_kg_m2,
        );
        let mut sim = Self::with_sheet(cfg, sheet);
        sim.asleep = cfg.room.table && !sim.obstacles.is_moving();
        sim
    }

    fn with_sheet(cfg: SimConfig, mut sheet: Sheet) -> Self {
        let material = PaperMaterial::of(cfg.material);
        // The geometry layer appends singular vertices without allocating.
        let nv = sheet.sp.num_vertices();
        sheet.sp.singular.reserve(nv);
        sheet.sg.vertices.reserve(nv);
        let geometry = GeometryLayer::new(&sheet.sp, cfg.geometry, &material, cfg.seed);
        let params = PhysParams::new(&material, &cfg.solver);
        let n = sheet.sp.num_vertices();
        let mut obstacles = Obstacles::new(&cfg.room);
        // A wall closer than the sheet's half length starts behind the new sheet and eases in.
        obstacles.fit_outside(&sheet.sp.pos);
        let rig = GestureRig::new(&sheet, cfg.room.home_height_m());
        let metrics = MetricsTracker::new(&sheet.sp);
        let mesh_capacity = mesh_capacity_for(&cfg);
        let mut analysis = SoundAnalysis::new(
            AnalysisConfig::default(),
            mesh_capacity.0,
            mesh_capacity.1,
            largest_sheet_m(),
            (sheet.width_m, sheet.length_m),
        );
        analysis.reset(sheet.width_m, sheet.length_m, sheet.sp.singular.len());
        let mut sim = Self {
            physics: Physics::new(&sheet.sp),
            rig,
            geometry,
            obstacles,
            material,
            params,
            rng: rand_pcg::Pcg32::seed_from_u64(cfg.seed),
            fixed: vec![false; n],
            kin_target: vec![V3::zeros(); n],
            forces: vec![V3::zeros(); n],
            vertex_strain: Vec::with_capacity(mesh_capacity.0),
            strain_limit: crate::physics::strain_limit::StrainLimit::with_capacity(
                mesh_capacity.0,
                mesh_capacity.1,
            ),
            contacts: vec![VertexContact::default(); n],
            layer_slip: vec![-1.0; n],
            metrics,
            last_metrics: Metrics::default(),
            asleep: false,
            quiet_frames: 0,
            mesh_capacity,
            frames_simulated: 0,
            inserted_vertices: 0,
            kept_crossed_start: false,
            flipped_edges: 0,
            analysis,
            proximity: {
                // Vertices inserted at singular points make pairs of triangles a fraction of an
                // edge apart in the pattern: one patch, not two layers (self_proximity.rs).
                let mut q = SelfProximity::with_capacity(mesh_capacity.1);
                q.set_min_pattern_gap_m(0.75 * cfg.mesh.spacing_m(sheet.size));
                q
            },
            frame_start_pos: Vec::with_capacity(mesh_capacity.0),
            motion_start_pos: Vec::with_capacity(mesh_capacity.0),
            rest_box_pos: Vec::with_capacity(mesh_capacity.0),
            motion_start_vel: Vec::with_capacity(mesh_capacity.0),
            frame_start_pattern: Vec::with_capacity(mesh_capacity.0),
            pre_limit_pos: Vec::with_capacity(mesh_capacity.0),
            stalled_pos: Vec::with_capacity(mesh_capacity.0),
            stalled_vel: Vec::with_capacity(mesh_capacity.0),
            split_start_pos: Vec::with_capacity(mesh_capacity.0),
            split_start_vel: Vec::with_capacity(mesh_capacity.0),
            split_start_saved: false,
            split_jump: Vec::with_capacity(mesh_capacity.0),
            split_start_normals: Vec::with_capacity(mesh_capacity.1),
            frame_start_normals: Vec::with_capacity(mesh_capacity.1),
            frame_normals_saved: false,
            split_best_pos: Vec::with_capacity(mesh_capacity.0),
            split_best_vel: Vec::with_capacity(mesh_capacity.0),
            split_best_normals: Vec::with_capacity(mesh_capacity.1),
            phase_timing: false,
            stopwatch: Stopwatch::default(),
            phase_ns: PhaseTimes::default(),
            tear: tear::TearProgress::default(),
            fibres: crate::tearing::fibres::FibreTexture::new((cfg.seed ^ FIBRE_STREAM) as u32),
            fibre_seed: cfg.seed,
            cfg,
            frame: 0,
            lips: crate::tearing::lips::Lips::default(),
            sheet,
        };
        sim.rebuild_lips();
        sim.update_contacts();
        sim.last_metrics = sim.metrics.compute(&sim.sheet.sp);
        sim
    }

    /// The configuration (after sanitizing, with the current size, material, seed and room).
    pub fn config(&self) -> &SimConfig {
        &self.cfg
    }

    /// Frames stepped since the sheet was created or reset.
    pub fn frame(&self) -> u64 {
        self.frame
    }

    /// Simulated time, seconds.
    pub fn time_s(&self) -> f64 {
        self.frame as f64 / self.cfg.frame_rate_hz
    }

    /// Turns per-phase timing of `step` on or off (off by default; the simulation is the
    /// same either way). See [`PhaseTimes`].
    pub fn set_phase_timing(&mut self, on: bool) {
        self.phase_timing = on;
    }

    /// Per-phase wall time of the last awake frame (zeros unless phase timing is on).
    pub fn phase_times(&self) -> PhaseTimes {
        self.phase_ns
    }

    /// True when the sheet is at rest and a step does no work.
    pub fn is_asleep(&self) -> bool {
        self.asleep
    }

    /// Current (commanded) value of a gesture.
    pub fn gesture(&self, g: GestureParam) -> f32 {
        self.rig.state.commanded[g.index()]
    }

    /// The crumple squeeze the hands follow now (the rate-limited gesture value) and its limit
    /// where the sheet came close to itself (1 = none; gesture_rig.rs "Crumple cap").
    pub fn crumple_squeeze(&self) -> (f64, f64) {
        (
            self.rig.state.smoothed[GestureParam::Crumple.index()],
            self.rig.state.crumple_limit,
        )
    }

    /// The sheet (S_P and S_G), read-only.
    pub fn sheet(&self) -> &Sheet {
        &self.sheet
    }

    /// Per-vertex contacts after the last frame (same indexing as the S_P vertices).
    pub fn contacts(&self) -> &[VertexContact] {
        &self.contacts
    }

    /// Per S_P vertex, how fast it slid on another layer it was pressed on at the end of the
    /// last frame, m/s; negative where it was pressed on none (the layers' friction sound).
    pub fn layer_slip(&self) -> &[f32] {
        &self.layer_slip
    }

    /// Counts of the last frame's sound analysis (events by kind, vibration regions).
    pub fn analysis_stats(&self) -> &AnalysisStats {
        self.analysis.stats()
    }

    /// The sound analysis (curvature grid, thresholds), read-only.
    pub fn sound_analysis(&self) -> &SoundAnalysis {
        &self.analysis
    }

    /// Outputs of the geometry layer for the last frame: region partition, rulings with
    /// dihedral angles, free curved borders, cones, singular vertices, junctions and this
    /// frame's sudden shape changes (see [`GeometryFrame`]). Indexed like S_P.
    pub fn geometry(&self) -> &GeometryFrame {
        self.geometry.frame()
    }

    /// The geometry layer (configuration, work counter).
    pub fn geometry_layer(&self) -> &GeometryLayer {
        &self.geometry
    }

    /// Metrics of the last frame.
    pub fn metrics(&self) -> &Metrics {
        &self.last_metrics
    }

    /// The obstacles (effective planes).
    pub fn obstacles(&self) -> &Obstacles {
        &self.obstacles
    }

    /// The gesture rig (handles, gestures).
    pub fn rig(&self) -> &GestureRig {
        &self.rig
    }

    /// Work counter: physics substeps integrated since creation (does not move while asleep).
    pub fn work_counter(&self) -> u64 {
        self.physics.substeps_done
    }

    /// Sparse factorizations done by the Newton solver since the last rebuild.
    pub fn factorizations(&self) -> u64 {
        self.physics.factorizations()
    }

    /// True if the next [`Self::step`] starts by inserting an S_P vertex for a singular point
    /// drawn in the last frame, by flipping a compressed edge found then (sim/remesh.rs) or by
    /// tearing the mesh further (sim/tear.rs):
    /// that step allocates (a new mesh), every other step does not. A host that steps the
    /// sheet on its audio thread permits it there.
    pub fn refinement_pending(&self) -> bool {
        self.geometry.pending_singular().is_some()
            || self.geometry.pending_flip().is_some()
            || self.tear.pending
    }

    /// S_P vertices inserted at singular points' drawn positions into the current sheet (since
    /// this sim was made, restored or last rebuilt by a reset or a size change; sim/remesh.rs;
    /// not saved with the sheet).
    pub fn inserted_vertices(&self) -> u64 {
        self.inserted_vertices
    }

    /// S_P edges flipped in flat regions of the current sheet (counted as
    /// [`Self::inserted_vertices`] is).
    pub fn flipped_edges(&self) -> u64 {
        self.flipped_edges
    }

    /// Frames that ran the physics (not asleep) since creation.
    pub fn frames_simulated(&self) -> u64 {
        self.frames_simulated
    }

    fn wake(&mut self) {
        self.asleep = false;
        self.quiet_frames = 0;
        self.rest_box_pos.clear();
    }

    /// Rebuilds a flat sheet with the current configuration (Reset, Size).
    fn rebuild(&mut self) {
        let held = self.rig.state.clone();
        let sheet = Sheet::new_flat(
            self.cfg.size,
            self.cfg.mesh,
            self.cfg.room.home_height_m(),
            self.material.areal_density_kg_m2,
        );
        let frames_simulated = self.frames_simulated;
        let substeps = self.physics.substeps_done;
        let phase_timing = self.phase_timing;
        *self = Self::with_sheet(self.cfg, sheet);
        self.phase_timing = phase_timing;
        self.frames_simulated = frames_simulated;
        self.physics.substeps_done = substeps;
        // Gestures and held slots survive; held handles re-anchor on the new sheet. The
        // crumple starts over: a flat sheet cannot be held at a squeeze, and re-anchoring the
        // crumple hands at the old squeeze yanked the new sheet (2.9 m/s) into a burst of
        // crumple events; if the crumple is still commanded, its hands grab the new sheet in
        // the next frame and squeeze from 0.
        self.rig.state.commanded = held.commanded;
        self.rig.state.smoothed = held.smoothed;
        self.rig.state.smoothed[GestureParam::Crumple.index()] = 0.0;
        self.rig.state.held = held.held;
        self.rig.state.shake_phase_rad = held.shake_phase_rad;
        self.rig.state.grab_seq = held.grab_seq;
        self.rig.state.next_seq = held.next_seq;
        for k in 0..NUM_SLOT_HANDS {
            self.rig.state.hands[k].active = held.hands[k].active;
            self.rig.state.hands[k].speed_m_s = held.hands[k].speed_m_s;
        }
        self.rig
            .rebuild_geometry(&self.sheet, self.cfg.room.home_height_m());
        // A whole sheet: it tears again when the amount rises past its value now (sim/tear.rs).
        let amount = self.rig.state.smoothed[GestureParam::TearAmount.index()];
        self.tear.theta_max_rad = amount;
        self.tear.drive_rad = amount;
        self.tear.pull_floor = self.rig.state.smoothed[GestureParam::PullSeparation.index()];
        self.wake();
    }

    /// Applies one command. Non-finite values are ignored; everything else is clamped.
    pub fn apply(&mut self, cmd: Command) {
        match cmd {
            Command::Reset => self.rebuild(),
            Command::Size(size) => {
                if size != self.cfg.size {
                    self.cfg.size = size;
                    self.rebuild();
                }
            }
            Command::Grab { slot, grip } => {
                self.rig.grab(slot, grip, &self.sheet.sp.pos);
                self.wake();
            }
            Command::Release { slot } => {
                if self.rig.state.held[slot.index()].is_some() {
                    self.rig.release(slot);
                    self.wake();
                }
            }
            Command::ReleaseAll => {
                if self.rig.state.held.iter().any(Option::is_some) {
                    self.rig.release_all();
                    self.wake();
                }
            }
            Command::Gesture { param, value } => {
                if let Some(v) = param.sanitize(value)
                    && v != self.rig.state.commanded[param.index()]
                {
                    self.rig.set_gesture(param, v);
                    self.wake();
                }
            }
            Command::Material(m) => {
                if m != self.cfg.material {
                    self.cfg.material = m;
                    self.material = PaperMaterial::of(m);
                    self.params = PhysParams::new(&self.material, &self.cfg.solver);
                    self.geometry.set_material(&self.material);
                    self.sheet
                        .sp
                        .set_areal_density(self.material.areal_density_kg_m2);
                    self.wake();
                }
            }
            // The new seed is the next sheet's (a reset or a size change): this sheet keeps its
            // fibres, whose seed is saved with it.
            Command::Seed(s) => self.cfg.seed = s,
            Command::Room(r) => {
                let r = r.sanitized();
                if r != self.cfg.room {
                    self.cfg.room = r;
                    self.obstacles.set_room(&r, &self.sheet.sp.pos);
                    self.rig.set_home_height(r.home_height_m());
                    self.wake();
                }
            }
        }
    }

    /// Steps one frame.
    pub fn step(&mut self, out: &mut FrameOutput) {
        out.sound.clear();
        self.frame = self.frame.saturating_add(1);
        out.sound.frame = self.frame;
        out.sound.time_s = self.time_s();
        // The only steps that allocate: an edge flip or a singular vertex's own S_P vertex,
        // found last frame and announced since ([`Self::refinement_pending`], sim/remesh.rs).
        if let Some(f) = self.geometry.take_pending_flip() {
            self.flip_pending_edge(&f);
        }
        if let Some(p) = self.geometry.take_pending_singular() {
            self.place_pending_singular(&p);
        }
        self.apply_pending_tear();
        out.sound.tear.length_m = self.tear.path_length_m as f32;
        if self.asleep {
            self.geometry.idle_frame(self.frame);
            out.stats = self.stats(true, 0, 0, 0);
            return;
        }
        self.frames_simulated += 1;
        self.motion_start_pos.clone_from(&self.sheet.sp.pos);
        self.motion_start_vel.clone_from(&self.sheet.sp.vel);
        self.stopwatch.start(self.phase_timing);
        self.phase_ns = PhaseTimes::default();
        let dt = 1.0 / self.cfg.frame_rate_hz;
        let frame_scale = DEFAULT_FRAME_RATE_HZ / self.cfg.frame_rate_hz;
        let planes_moved = self.obstacles.ease(dt);
        // The crumple cap (gesture_rig.rs "Crumple cap"): the squeeze slows, stops and backs
        // off as the sheet approaches itself, and a frame that would pass it through itself
        // is undone (`undo_pass_through`) — unless the frame starts crossing already (there is
        // nothing clean to go back to) or MAX_UNDO_STREAK frames in a row were undone (one
        // frame then goes through as simulated, so a squeeze never freezes the sheet).
        let mut guard = false;
        if self.rig.is_squeezing() {
            let closest_m = self
                .proximity
                .closest_approach_m(&self.sheet.sp, SQUEEZE_REACH_M);
            self.rig.limit_squeeze(closest_m, frame_scale);
            guard = self.rig.state.undo_streak < MAX_UNDO_STREAK
                && !planes_moved
                && (closest_m > 0.0 || !self.proximity.any_crossing(&self.sheet.sp));
            if guard {
                self.frame_start_pos.clone_from(&self.sheet.sp.pos);
                self.frame_start_pattern.clone_from(&self.sheet.sp.pattern);
            }
        }
        if !guard {
            if self.rig.state.undo_streak >= MAX_UNDO_STREAK {
                // The frame let through ends crossed, and the contact stiffened up to
                // MAX_BOOST by the streak would throw the crossed layers apart (module doc,
                // "The pass-through guard").
                self.physics.clear_contact_boosts();
            }
            self.rig.state.undo_streak = 0;
        }
        self.phase_ns.self_contact_ns = self.stopwatch.lap_ns();
        // The gestures (not the sheet's pull on the hands) move the sheet this frame: the
        // isometry step's trigger (geometry/isometry.rs "When it runs").
        let tear_hands_moving = self.tear_hands_frame();
        let driven =
            planes_moved || self.obstacles.is_moving() || self.rig.is_moving() || tear_hands_moving;
        self.rig.advance_frame(
            dt,
            frame_scale,
            &self.sheet.sp.pos,
            &self.obstacles,
            &mut self.rng,
        );
        let n_sub = self.cfg.solver.substeps;
        let h = dt / f64::from(n_sub);
        let (mut iterations, mut recoveries, mut halvings, mut pinned) = (0u32, 0u32, 0u32, 0u32);
        let (mut held_back, mut capped, mut split) = (0u32, 0u32, 0u32);
        self.frame_normals_saved = false;
        for s in 1..=n_sub {
            let frac = f64::from(s) / f64::from(n_sub);
            self.fill_held(frac);
            self.split_start_saved = false;
            let mut r = self.solve_substep(h);
            let mut again_stood = false;
            if let Some((kept, discarded)) = self.solve_substep_again(frac, h, &mut r) {
                iterations += discarded.iterations;
                halvings += discarded.halvings;
                held_back += u32::from(kept);
                again_stood = kept;
            }
            if !again_stood
                && let Some((kept, discarded)) =
                    self.solve_substep_split(f64::from(s - 1) / f64::from(n_sub), frac, h, &mut r)
            {
                iterations += discarded.iterations;
                halvings += discarded.halvings;
                split += u32::from(kept);
            }
            iterations += r.iterations;
            capped += u32::from(r.capped);
            halvings += r.halvings;
            pinned += u32::from(r.pinned);
            recoveries += u32::from(r.recovered);
            self.limit_penetration();
        }
        self.physics.age_contact_boosts();
        self.sheet.sg.pull_positions(&self.sheet.sp);
        if self.rig.num_active_hands() > 0 {
            crate::physics::elastic_forces(&self.sheet.sp, &self.params, &mut self.forces);
            crate::metrics::vertex_strains(&self.sheet.sp, &mut self.vertex_strain);
            self.rig.apply_slip(
                &self.forces,
                &self.vertex_strain,
                self.cfg.mesh.spacing_m(self.cfg.size),
                frame_scale,
                &self.obstacles,
            );
            self.rig.hold_hinged_pieces(
                &self.sheet.sp.pattern,
                &self.vertex_strain,
                self.cfg.mesh.spacing_m(self.cfg.size),
            );
        }
        self.phase_ns.physics_ns = self.stopwatch.lap_ns();
        if self.cfg.geometry.enabled {
            self.geometry.update(
                &mut self.sheet.sp,
                &mut self.sheet.sg,
                &self.fixed,
                &self.obstacles,
                self.frame,
                driven,
                self.metrics.previous_normals(),
            );
            self.sheet.sg.pull_positions(&self.sheet.sp);
        } else {
            self.geometry.idle_frame(self.frame);
        }
        // Paper does not stretch (physics/strain_limit.rs): what the solve and the isometry
        // step left strained beyond STRAIN_LIMIT is projected back, held vertices sliding in
        // their grips.
        crate::metrics::vertex_strains(&self.sheet.sp, &mut self.vertex_strain);
        let limited = self.strain_limit.apply(
            &mut self.sheet.sp,
            &self.vertex_strain,
            self.metrics.previous_normals(),
        );
        if limited {
            self.sheet.sg.pull_positions(&self.sheet.sp);
            self.geometry.sync_positions(&self.sheet.sp);
            self.rig
                .regrip(&self.sheet.sp.pos, &self.strain_limit.moved);
            self.tear_hands_regrip();
        }
        self.phase_ns.geometry_ns = self.stopwatch.lap_ns();
        let mut relaxed_undone = false;
        self.kept_crossed_start = false;
        if guard {
            // The isometry step may just have swept these very positions for crossings.
            // (Unless the strain limit moved them since.)
            let checked =
                self.cfg.geometry.enabled && self.geometry.checked_uncrossed() && !limited;
            if !checked && self.undo_pass_through(frame_scale) {
                relaxed_undone = self.relax_undone_start(dt);
                self.sheet.sg.pull_positions(&self.sheet.sp);
                self.geometry.sync_positions(&self.sheet.sp);
                self.rig.state.undo_streak += 1;
                // A singular vertex drawn this frame where no S_P vertex could move would get
                // a vertex inserted at the start of the next step (sim/remesh.rs); it is
                // dropped with the undone frame.
                self.geometry.take_pending_singular();
                self.geometry.take_pending_flip();
            } else {
                self.rig.state.undo_streak = 0;
            }
        }
        self.phase_ns.self_contact_ns += self.stopwatch.lap_ns();
        self.update_contacts();
        self.last_metrics = self.metrics.compute(&self.sheet.sp);
        self.analysis.analyze(
            &AnalysisInput {
                sp: &self.sheet.sp,
                contacts: &self.contacts,
                held: &self.fixed,
                time_s: self.time_s(),
                vel_start: &self.motion_start_vel,
                dt_s: dt,
                planes: &self.obstacles.planes,
                pressed_m: self.rig.take_press_m(frame_scale),
                layer_slip: &self.layer_slip,
            },
            &mut out.sound,
        );
        self.phase_ns.analysis_ns = self.stopwatch.lap_ns();
        let tear_moved = self.tear_frame(dt, &mut out.sound);
        self.phase_ns.tear_ns = self.stopwatch.lap_ns();

        // Quiet: nothing drives the sheet and no vertex moved faster than SLEEP_SPEED_M_S
        // over the frame, or none has left the rest box since the window started (module doc,
        // "Sleeping"). Measured on the positions, not the velocities: where the solve and
        // the projections after it (obstacles, isometry, strain limit, a hand giving way)
        // agree on a shape, the sheet stands still whatever velocity the solve reads.
        let moved_m = if self.motion_start_pos.len() == self.sheet.sp.pos.len() {
            self.sheet
                .sp
                .pos
                .iter()
                .zip(&self.motion_start_pos)
                .map(|(a, b)| (a - b).norm())
                .fold(0.0, f64::max)
        } else {
            f64::INFINITY
        };
        let undriven = !planes_moved
            && !tear_hands_moving
            && !self.tear.pending
            && !tear_moved
            && self.tear.drive_rad == self.rig.state.smoothed[GestureParam::TearAmount.index()]
            && !self.rig.is_moving()
            && !self.obstacles.is_moving();
        let pos = &self.sheet.sp.pos;
        if !undriven {
            self.quiet_frames = 0;
            self.rest_box_pos.clear();
        } else {
            if self.rest_box_pos.len() != pos.len() {
                // The window starts with this frame.
                self.rest_box_pos.clear();
                if self.motion_start_pos.len() == pos.len() {
                    self.rest_box_pos.extend_from_slice(&self.motion_start_pos);
                } else {
                    self.rest_box_pos.extend_from_slice(pos);
                }
            }
            let box_m = SLEEP_SPEED_M_S * f64::from(SLEEP_FRAMES) * dt;
            let in_box = pos
                .iter()
                .zip(&self.rest_box_pos)
                .all(|(a, b)| (a - b).norm() <= box_m);
            self.quiet_frames = if in_box || moved_m < SLEEP_SPEED_M_S * dt {
                self.quiet_frames.saturating_add(1)
            } else {
                0
            };
            if !in_box {
                self.rest_box_pos.clear();
                self.rest_box_pos.extend_from_slice(pos);
            }
        }
        if self.quiet_frames >= SLEEP_FRAMES {
            self.asleep = true;
            for v in &mut self.sheet.sp.vel {
                *v = V3::zeros();
            }
            self.update_contacts();
            self.last_metrics = self.metrics.compute(&self.sheet.sp);
        }
        out.stats = self.stats(false, n_sub, iterations, recoveries);
        out.stats.halvings = halvings;
        out.stats.pinned_substeps = pinned;
        out.stats.held_back_substeps = held_back;
        out.stats.split_substeps = split;
        out.stats.capped_substeps = capped;
        out.stats.relaxed_undone = relaxed_undone;
        out.stats.kept_crossed_start = self.kept_crossed_start;
    }

    fn update_contacts(&mut self) {
        let sp = &self.sheet.sp;
        for (i, c) in self.contacts.iter_mut().enumerate() {
            *c = VertexContact::default();
            let x = sp.pos[i];
            let mut best = TOUCH_DIST_M;
            for pl in self.obstacles.active() {
                let d = pl.distance(&x);
                if d < best {
                    best = d;
                    let v = sp.vel[i];
                    let vt = v - pl.normal * v.dot(&pl.normal);
                    let pen = (CONTACT_SKIN_M - d).max(0.0);
                    *c = VertexContact {
                        in_contact: true,
                        obstacle: pl.kind,
                        slip_speed_m_s: vt.norm() as f32,
                        normal_force_n: (penalty_stiffness(sp.mass_kg[i]) * pen) as f32,
                    };
                }
            }
        }
        // Layers pressed on each other: the last substep's pairs still within d̂ (the layers'
        // friction sound).
        self.layer_slip.resize(sp.num_vertices(), -1.0);
        crate::physics::sheet_contact::layer_slip(
            self.physics.sheet_pairs(),
            &sp.pos,
            &sp.vel,
            &mut self.layer_slip,
        );
    }

    fn stats(&self, asleep: bool, substeps: u32, iterations: u32, recoveries: u32) -> FrameStats {
        let m = &self.last_metrics;
        FrameStats {
            asleep,
            num_vertices: m.num_vertices as u32,
            num_triangles: m.num_triangles as u32,
            num_singular: m.num_singular as u32,
            c_mean_pct: m.c_mean_pct as f32,
            kinetic_energy_j: m.kinetic_energy_j as f32,
            n_comp_pct: m.n_comp_pct as f32,
            max_strain: m.max_strain as f32,
            angle_defect_rad: m.angle_defect_sum_rad as f32,
            max_speed_m_s: m.max_speed_m_s as f32,
            num_contacts: self.contacts.iter().filter(|c| c.in_contact).count() as u32,
            num_held: self.rig.held_vertices().count() as u32,
            num_flipped: m.num_flipped as u32,
            substeps,
            iterations,
            capped_substeps: 0,
            recoveries,
            halvings: 0,
            pinned_substeps: 0,
            held_back_substeps: 0,
            split_substeps: 0,
            undo_streak: self.rig.state.undo_streak,
            relaxed_undone: false,
            kept_crossed_start: false,
        }
    }

    /// Upper bounds of the mesh size (vertices, triangles) for preallocating snapshots: the
    /// largest mesh any sheet size can have at the configured density, with room for the
    /// geometry layer's enrichment (×2).
    pub fn mesh_capacity(&self) -> (usize, usize) {
        let (v, t) = self.mesh_capacity;
        (
            v.max(self.sheet.sp.num_vertices()),
            t.max(self.sheet.sp.num_triangles()),
        )
    }

    /// The lips' millimetre detail (empty on a whole sheet).
    pub fn lips(&self) -> &crate::tearing::lips::Lips {
        &self.lips
    }

    /// Walks the lip edges of the current mesh (where the mesh changed; may allocate).
    pub(crate) fn rebuild_lips(&mut self) {
        let (w, l) = (self.sheet.width_m, self.sheet.length_m);
        self.lips.rebuild(&self.sheet.sp, w, l, &self.fibres);
    }

    /// Copies the mesh out, with the lips' detail while it fits the capacity of `out` (no
    /// allocation when `out` has the capacity).
    pub fn write_mesh(&self, out: &mut MeshSnapshot) {
        out.clear();
        out.frame = self.frame;
        let sp = &self.sheet.sp;
        for (p, q) in sp.pos.iter().zip(&sp.pattern) {
            out.positions_m.push([p.x as f32, p.y as f32, p.z as f32]);
            out.pattern_m.push([q.x as f32, q.y as f32]);
            out.tags.push(VertexTag::Plain);
        }
        for v in self.rig.held_vertices() {
            out.tags[v as usize] = VertexTag::Handle;
        }
        for &v in &sp.singular {
            out.tags[v as usize] = VertexTag::Singular;
        }
        out.triangles.extend_from_slice(&sp.triangles);
        out.write_lips(self.lips.runs(), &sp.pattern, &sp.pos);
    }

    /// The sheet as saved in a project.
    pub fn save(&self) -> SavedSheet {
        let sp = &self.sheet.sp;
        let (ownership, suppressed, pending) = self.rig.ownership_state();
        SavedSheet {
            version: SAVED_SHEET_VERSION,
            size: self.cfg.size,
            material: self.cfg.material,
            seed: self.cfg.seed,
            frame: self.frame,
            pattern_m: sp.pattern.iter().map(|q| [q.x, q.y]).collect(),
            triangles: sp.triangles.clone(),
            positions_m: sp.pos.iter().map(|p| [p.x, p.y, p.z]).collect(),
            velocities_m_s: sp.vel.iter().map(|v| [v.x, v.y, v.z]).collect(),
            edge_rest_angle_rad: sp.edge_rest_angle.clone(),
            edge_damage: sp.edge_damage.clone(),
            singular_vertices: sp.singular.clone(),
            rng: self.rng.clone(),
            rig: self.rig.state.clone(),
            rig_ownership: ownership,
            rig_suppressed: suppressed,
            rig_ownership_pending: pending,
            obstacle_offsets_m: self.obstacles.planes.map(|p| p.offset_m),
            obstacle_active: self.obstacles.planes.map(|p| p.active),
            asleep: self.asleep,
            quiet_frames: self.quiet_frames,
            rest_box_m: self.rest_box_pos.iter().map(|p| [p.x, p.y, p.z]).collect(),
            geometry: Some(self.geometry.save()),
            contact_boosts: self.physics.contact_boosts().to_vec(),
            fibre_seed: (self.fibre_seed != self.cfg.seed).then_some(self.fibre_seed),
            hand_defs: self.rig.hand_defs_state(),
            sound_history: Some(self.analysis.save_history()),
            tear: self.tear,
        }
    }

    /// Rebuilds a sheet from saved data; the room, frame rate, solver and mesh settings come
    /// from `cfg`, the size, material and seed from the saved sheet.
    pub fn restore(cfg: SimConfig, saved: &SavedSheet) -> Result<Self, RestoreError> {
        saved.validate_fields()?;
        let mut cfg = cfg.sanitized();
        cfg.size = saved.size;
        cfg.material = saved.material;
        cfg.seed = saved.seed;
        let material = PaperMaterial::of(cfg.material);
        let pattern = Pattern {
            points: saved
                .pattern_m
                .iter()
                .map(|p| V2::new(p[0], p[1]))
                .collect(),
            triangles: saved.triangles.clone(),
        };
        let sheet = Sheet::from_pattern(
            cfg.size,
            &pattern,
            cfg.room.home_height_m(),
            material.areal_density_kg_m2,
        )
        .map_err(|e| RestoreError::BadMesh(e.to_string()))?;
        let ne = sheet.sp.num_edges();
        if saved.edge_rest_angle_rad.len() != ne || saved.edge_damage.len() != ne {
            return Err(RestoreError::Invalid(format!(
                "per-edge arrays have {} and {} entries, the mesh has {ne} edges",
                saved.edge_rest_angle_rad.len(),
                saved.edge_damage.len()
            )));
        }
        let mut sim = Self::with_sheet(cfg, sheet);
        if let Some(fs) = saved.fibre_seed
            && fs != sim.fibre_seed
        {
            sim.fibre_seed = fs;
            sim.fibres = crate::tearing::fibres::FibreTexture::new((fs ^ FIBRE_STREAM) as u32);
            sim.lips.clear();
            sim.rebuild_lips();
        }
        {
            let sp = &mut sim.sheet.sp;
            for (i, p) in saved.positions_m.iter().enumerate() {
                sp.pos[i] = V3::new(p[0], p[1], p[2]);
            }
            for (i, v) in saved.velocities_m_s.iter().enumerate() {
                sp.vel[i] = V3::new(v[0], v[1], v[2]);
            }
            sp.edge_rest_angle
                .copy_from_slice(&saved.edge_rest_angle_rad);
            sp.edge_damage.copy_from_slice(&saved.edge_damage);
            sp.singular.clone_from(&saved.singular_vertices);
        }
        sim.geometry
            .restore(&sim.sheet.sp, &mut sim.sheet.sg, saved.geometry.as_ref())
            .map_err(RestoreError::Invalid)?;
        sim.sheet.sg.pull_positions(&sim.sheet.sp);
        // The singular vertices the sheet already has are not new: no clac for them (the
        // analysis was reset for the bare mesh, before they were restored).
        let (w, l) = (sim.sheet.width_m, sim.sheet.length_m);
        sim.analysis.reset(w, l, sim.sheet.sp.singular.len());
        if let Some(h) = &saved.sound_history {
            sim.analysis
                .restore_history(h)
                .map_err(RestoreError::Invalid)?;
        }
        sim.rng = saved.rng.clone();
        sim.frame = saved.frame;
        sim.asleep = saved.asleep;
        sim.quiet_frames = saved.quiet_frames;
        sim.rest_box_pos.clear();
        if saved.rest_box_m.len() == sim.sheet.sp.num_vertices() {
            sim.rest_box_pos
                .extend(saved.rest_box_m.iter().map(|p| V3::new(p[0], p[1], p[2])));
        }
        for (k, p) in sim.obstacles.planes.iter_mut().enumerate() {
            if p.active && saved.obstacle_active[k] {
                p.offset_m = saved.obstacle_offsets_m[k];
            } else if p.active {
                // Present now but not in the saved room: ease in from outside the sheet.
                p.active = false;
            }
        }
        let room = sim.cfg.room;
        sim.obstacles.set_room(&room, &sim.sheet.sp.pos);
        sim.rig.state = saved.rig.clone();
        sim.rig
            .restore_hand_defs(&saved.hand_defs)
            .map_err(RestoreError::Invalid)?;
        sim.rig
            .restore_ownership(
                &saved.rig_ownership,
                saved.rig_suppressed,
                saved.rig_ownership_pending,
                // Saved before the hands were: they were worked out afresh.
                saved.hand_defs.is_empty(),
            )
            .map_err(RestoreError::Invalid)?;
        sim.physics
            .set_contact_boosts(&saved.contact_boosts, sim.sheet.sp.num_vertices())
            .map_err(RestoreError::Invalid)?;
        saved
            .tear
            .validate(sim.sheet.sp.num_vertices())
            .map_err(RestoreError::Invalid)?;
        sim.tear = saved.tear;
        sim.metrics.reset_normals(&sim.sheet.sp);
        sim.update_contacts();
        sim.last_metrics = sim.metrics.compute(&sim.sheet.sp);
        Ok(sim)
    }
}

/// The largest sheet's width and length, metres (sizes the sound analysis grid).
fn largest_sheet_m() -> (f64, f64) {
    SheetSize::ALL.iter().fold((0.0, 0.0), |acc, s| {
        let (w, l) = s.dims_m();
        (f64::max(acc.0, w), f64::max(acc.1, l))
    })
}

/// The largest (vertices, triangles) over all sheet sizes at the configured density, × 2.
fn mesh_capacity_for(cfg: &SimConfig) -> (usize, usize) {
    let mut best = (0, 0);
    for size in SheetSize::ALL {
        let (w, l) = size.dims_m();
        let p = lattice(w, l, cfg.mesh.spacing_m(size));
        best.0 = best.0.max(p.points.len());
        best.1 = best.1.max(p.triangles.len());
    }
    (2 * best.0, 2 * best.1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::GrabSlot;

    /// An undone frame in which a singular point moved a vertex in the pattern leaves that
    /// vertex on the restored surface over its new pattern position, not at its old 3D point
    /// an edge fraction away from its rest shape.
    #[test]
    fn an_undone_frame_keeps_a_pattern_move_on_the_surface() {
        let mut sim = Sim::new(SimConfig::default());
        let mut out = FrameOutput::default();
        sim.apply(Command::Gesture {
            param: GestureParam::Crumple,
            value: 0.4,
        });
        for _ in 0..120 {
            sim.step(&mut out);
        }
        sim.frame_start_pos.clone_from(&sim.sheet.sp.pos);
        sim.frame_start_pattern.clone_from(&sim.sheet.sp.pattern);
        let strain_at_start = MetricsTracker::new(&sim.sheet.sp)
            .compute(&sim.sheet.sp)
            .max_strain;
        sim.step(&mut out);
        // Half an edge, as a placement does, at the first interior, free vertex that can move.
        let sp = &mut sim.sheet.sp;
        let edge_m = sp.edge_rest_len_m.iter().sum::<f64>() / sp.num_edges() as f64;
        let moved = (0..sp.num_vertices()).find(|&v| {
            let target = sp.pattern[v] + V2::new(0.5 * edge_m, 0.0);
            !sim.fixed[v] && sp.move_pattern_vertex(v as u32, target).norm() > 0.2 * edge_m
        });
        let v = moved.expect("a vertex that can move in the pattern");
        sim.restore_frame_start();
        let strain = MetricsTracker::new(&sim.sheet.sp)
            .compute(&sim.sheet.sp)
            .max_strain;
        assert!(
            strain < strain_at_start + 0.05,
            "vertex {v} moved: strain {strain:.3} (at the frame start {strain_at_start:.3})"
        );
        assert!(sim.sheet.sp.vel.iter().all(|u| *u == V3::zeros()));
    }

    /// Every gesture moves the sheet: from a sheet held by its front edge and shaking (and torn
    /// a little, for the tear's steer and place; pulled, for the pull's asymmetry), setting a
    /// gesture to a value other than its default changes it.
    #[test]
    fn every_gesture_moves_the_sheet() {
        let play = |change: Option<GestureParam>| {
            let mut sim = Sim::new(SimConfig::default());
            let mut out = FrameOutput::default();
            sim.apply(Command::Grab {
                slot: GrabSlot::Front,
                grip: 1.0,
            });
            sim.apply(Command::Gesture {
                param: GestureParam::ShakeDepth,
                value: 0.3,
            });
            let steers_a_tear = matches!(
                change,
                Some(GestureParam::TearSteer | GestureParam::TearPosition)
            );
            if steers_a_tear {
                sim.apply(Command::Gesture {
                    param: GestureParam::TearAmount,
                    value: 0.2,
                });
            }
            if change == Some(GestureParam::PullAsymmetry) {
                sim.apply(Command::Gesture {
                    param: GestureParam::PullSeparation,
                    value: 0.8,
                });
            }
            if let Some(g) = change {
                let (lo, hi) = g.range();
                let value = if g == GestureParam::ShakeDepth {
                    0.8
                } else {
                    lo + 0.8 * (hi - lo)
                };
                assert_ne!(value, g.default_value());
                sim.apply(Command::Gesture { param: g, value });
            }
            // A pull's tear starts slowly (V·E_r grows as it opens): its first mesh step
            // comes after ~100 frames.
            let pulls = matches!(
                change,
                Some(GestureParam::PullSeparation | GestureParam::PullAsymmetry)
            );
            for _ in 0..if pulls { 200 } else { 60 } {
                sim.step(&mut out);
            }
            (crate::scenario_run::state_hash(&sim), steers_a_tear)
        };
        let base = play(None).0;
        // The same tear with the steer and place at their defaults.
        let torn = {
            let mut sim = Sim::new(SimConfig::default());
            let mut out = FrameOutput::default();
            sim.apply(Command::Grab {
                slot: GrabSlot::Front,
                grip: 1.0,
            });
            for (param, value) in [
                (GestureParam::ShakeDepth, 0.3),
                (GestureParam::TearAmount, 0.2),
            ] {
                sim.apply(Command::Gesture { param, value });
            }
            for _ in 0..60 {
                sim.step(&mut out);
            }
            crate::scenario_run::state_hash(&sim)
        };
        assert_ne!(torn, base, "tear_amount moves the sheet");
        for g in GestureParam::ALL {
            let (h, steers) = play(Some(g));
            let reference = if steers {
                torn
            } else if g == GestureParam::PullAsymmetry {
                play(Some(GestureParam::PullSeparation)).0
            } else {
                base
            };
            assert_ne!(h, reference, "{}", g.id());
        }
    }

    #[test]
    fn held_front_edge_follows_lift() {
        let mut sim = Sim::new(SimConfig::default());
        let mut out = FrameOutput::default();
        sim.step(&mut out);
        assert!(out.stats.asleep);
        sim.apply(Command::Grab {
            slot: GrabSlot::Front,
            grip: 1.0,
        });
        sim.apply(Command::Gesture {
            param: GestureParam::Lift,
            value: 1.0,
        });
        for _ in 0..200 {
            sim.step(&mut out);
        }
        let mut m = MeshSnapshot::default();
        sim.write_mesh(&mut m);
        let zmax = m.positions_m.iter().map(|p| p[2]).fold(f32::MIN, f32::max);
        assert!(zmax > 0.75 + 0.1, "front edge lifted: {zmax}");
        assert_eq!(out.stats.num_flipped, 0);
        assert_eq!(out.stats.recoveries, 0);
        assert!(m.tags.contains(&VertexTag::Handle));
    }

    #[test]
    fn a_reset_while_the_crumple_lets_go_gives_a_fresh_still_sheet() {
        let mut sim = Sim::new(SimConfig::default());
        let mut out = FrameOutput::default();
        let crumple = |sim: &mut Sim, value| {
            sim.apply(Command::Gesture {
                param: GestureParam::Crumple,
                value,
            })
        };
        crumple(&mut sim, 0.6);
        for _ in 0..300 {
            sim.step(&mut out);
        }
        crumple(&mut sim, 0.0);
        sim.step(&mut out);
        assert!(sim.crumple_squeeze().0 > 0.05, "still letting go");
        sim.apply(Command::Reset);
        for _ in 0..20 {
            sim.step(&mut out);
            assert!(
                out.stats.max_speed_m_s < 0.1,
                "the new sheet is yanked: {} m/s",
                out.stats.max_speed_m_s
            );
        }
        assert_eq!(sim.crumple_squeeze().0, 0.0);
        // Still commanded across a reset: the hands grab the new sheet and squeeze from 0.
        crumple(&mut sim, 0.6);
        for _ in 0..100 {
            sim.step(&mut out);
        }
        sim.apply(Command::Reset);
        sim.step(&mut out);
        let s = sim.crumple_squeeze().0;
        assert!(s < 0.05, "squeeze restarts from 0: {s}");
        for _ in 0..100 {
            sim.step(&mut out);
        }
        assert!(sim.crumple_squeeze().0 > s, "and goes on");
        assert_eq!(out.stats.num_flipped, 0);
    }

    #[test]
    fn contradictory_hands_slip_instead_of_tearing() {
        // Back and front held firmly, front lifted by L/2 without sliding: the hands would
        // have to stretch the sheet by 12 % on average (much more next to the pinches); they
        // give way instead.
        let mut sim = Sim::new(SimConfig::default());
        for slot in [GrabSlot::Back, GrabSlot::Front] {
            sim.apply(Command::Grab { slot, grip: 1.0 });
        }
        sim.apply(Command::Gesture {
            param: GestureParam::Lift,
            value: 1.0,
        });
        let mut out = FrameOutput::default();
        let mut worst: f64 = 0.0;
        for _ in 0..400 {
            sim.step(&mut out);
            worst = worst.max(sim.metrics().max_strain);
        }
        assert!(worst < 0.1, "strain {worst}");
        // The front hand gave way: its pinch did not reach the lift target (L/2 up, 12 % of
        // stretch away) but stopped where the sheet holds it.
        let front = sim.rig().state.hands[1].pose.pos();
        let target_z = 0.75 + 0.5 * 0.297;
        // (≥ 5 mm short: with the geometry layer's isometry step the balance at the pinch
        // shifts by a millimetre or two; physics alone stops ≥ 10 mm short.)
        assert!(
            front.z < target_z - 0.005,
            "hand at {} vs target {target_z}",
            front.z
        );
        let zmax = sim
            .sheet()
            .sp
            .pos
            .iter()
            .map(|p| p.z)
            .fold(f64::MIN, f64::max);
        assert!(zmax > 0.8, "the front still went up: {zmax}");
    }

    #[test]
    fn dropped_sheet_falls_to_the_floor_and_sleeps() {
        let cfg = SimConfig {
            room: RoomConfig {
                table: false,
                table_height_cm: 40.0,
                ..RoomConfig::default()
            },
            size: SheetSize::A6,
            ..SimConfig::default()
        };
        let mut sim = Sim::new(cfg);
        assert!(!sim.is_asleep());
        let mut out = FrameOutput::default();
        let mut frames = 0;
        while !sim.is_asleep() && frames < 2000 {
            sim.step(&mut out);
            frames += 1;
        }
        assert!(sim.is_asleep(), "asleep after {frames} frames");
        let zmax = sim
            .sheet()
            .sp
            .pos
            .iter()
            .map(|p| p.z)
            .fold(f64::MIN, f64::max);
        assert!(zmax < 0.02, "on the floor: {zmax}");
        assert!(sim.contacts().iter().filter(|c| c.in_contact).count() > 10);
        assert!(
            sim.contacts()
                .iter()
                .all(|c| !c.in_contact || c.obstacle == crate::sound_input::Obstacle::Floor)
        );
    }

    /// A vertex of a hand moved in the pattern (as a singular point placed at it moves it)
    /// before the sheet is saved: the restored rig holds the sheet where the saved one did, so
    /// a grab after reopening does what it would have done (a rig worked out afresh from the
    /// moved pattern holds that vertex elsewhere and does not).
    #[test]
    fn a_saved_sheet_keeps_its_hands_after_a_pattern_move() {
        let mut sim = Sim::new(SimConfig::default());
        let mut out = FrameOutput::default();
        sim.step(&mut out);
        let d = *sim.rig.hand_def(3);
        let v = (d.num_mains as usize..d.num_vertices as usize)
            .map(|j| d.vertices[j])
            .find(|&v| !sim.sheet.sp.topo.vertex_on_boundary[v as usize])
            .expect("an interior vertex in the right hand");
        let to = sim.sheet.sp.pattern[v as usize] + V2::new(-0.004, 0.002);
        assert_ne!(sim.sheet.sp.move_pattern_vertex(v, to), V2::zeros());
        let saved = sim.save();
        let mut fresh_hands = saved.clone();
        fresh_hands.hand_defs.clear();
        let mut back = Sim::restore(SimConfig::default(), &saved).unwrap();
        let mut fresh = Sim::restore(SimConfig::default(), &fresh_hands).unwrap();
        let grab = Command::Grab {
            slot: GrabSlot::Right,
            grip: 1.0,
        };
        let lift = Command::Gesture {
            param: GestureParam::Lift,
            value: 1.0,
        };
        for s in [&mut sim, &mut back, &mut fresh] {
            s.apply(grab);
            s.apply(lift);
            for _ in 0..20 {
                s.step(&mut out);
            }
        }
        assert_eq!(back.save(), sim.save());
        assert_ne!(
            fresh.save().positions_m,
            sim.save().positions_m,
            "hands worked out afresh hold the moved vertex elsewhere"
        );
    }

    #[test]
    fn save_restore_round_trip() {
        let mut sim = Sim::new(SimConfig::default());
        sim.apply(Command::Grab {
            slot: GrabSlot::Back,
            grip: 0.5,
        });
        sim.apply(Command::Gesture {
            param: GestureParam::ShakeDepth,
            value: 1.0,
        });
        let mut out = FrameOutput::default();
        for _ in 0..37 {
            sim.step(&mut out);
        }
        let saved = sim.save();
        let back = Sim::restore(SimConfig::default(), &saved).unwrap();
        assert_eq!(back.save(), saved);
        let mut bad = saved.clone();
        bad.positions_m[3][1] = f64::NAN;
        assert_eq!(
            Sim::restore(SimConfig::default(), &bad).unwrap_err(),
            RestoreError::BadPosition(3)
        );
    }
}
