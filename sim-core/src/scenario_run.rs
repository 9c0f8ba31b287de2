//! # Running a scenario and summarizing it
//!
//! Plays a script ([`crate::script_runner::ScriptRunner`]) through a [`Sim`] and gathers what
//! the tests, the criterion benches and the benchmark report (`cargo xtask bench-report`)
//! need: per-frame wall time of `Sim::step` and of its phases (optional), the seeds' length-error metrics averaged
//! over all frames as in TOG Table IV (c_mean, n_comp; P 1432–1440), worst strain, triangle
//! counts, solver iterations, health counters (flipped triangles, recoveries) and a hash of
//! the final state (determinism).

use std::time::Instant;

use crate::scenario::{self, ScenarioError};
use crate::script::Script;
use crate::script_runner::{RunnerError, ScriptRunner};
use crate::sim::{FrameOutput, PhaseTimes, Sim, SimConfig};

/// Why a run could not start.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// Unknown or broken scenario.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// The script cannot drive the simulation.
    #[error(transparent)]
    Runner(#[from] RunnerError),
}

/// Summary of one run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunSummary {
    /// Frames played.
    pub frames: u64,
    /// Frames in which the physics ran (not asleep).
    pub awake_frames: u64,
    /// Wall time of `Sim::step` per awake frame, nanoseconds (empty unless timed).
    pub step_ns: Vec<u64>,
    /// Per-phase wall time of each awake frame (empty unless timed).
    pub phase_ns: Vec<PhaseTimes>,
    /// c_mean averaged over all frames, %.
    pub c_mean_pct: f64,
    /// n_comp averaged over all frames, %.
    pub n_comp_pct: f64,
    /// Largest per-frame c_mean, %.
    pub c_mean_max_pct: f64,
    /// Largest principal strain deviation seen.
    pub max_strain: f64,
    /// Angle defect (sum over interior vertices) averaged over frames, radians.
    pub angle_defect_rad: f64,
    /// Average triangle count.
    pub triangles_avg: f64,
    /// Largest triangle count.
    pub triangles_max: u32,
    /// Solver iterations per substep, averaged over awake frames.
    pub iterations_per_substep: f64,
    /// Flipped triangles summed over frames (0 in a healthy run).
    pub flips: u64,
    /// Recovered substeps summed over frames (0 in a healthy run).
    pub recoveries: u64,
    /// Largest kinetic energy, J.
    pub kinetic_energy_max_j: f64,
    /// Largest vertex speed, m/s.
    pub max_speed_m_s: f64,
    /// Hash of the final positions and velocities.
    pub final_hash: u64,
    /// Hash of every frame's published geometry (rulings with their ends, lengths, dihedrals
    /// and normals; cones; singular points): equal hashes mean the layer's outputs were
    /// bit-identical in every frame, which [`Self::final_hash`] alone does not show (the
    /// physics never reads the rulings).
    pub geometry_hash: u64,
    /// Interior singular vertices at the end (the count never decreases).
    pub singular_final: u32,
    /// Frame of the first singular vertex, if any.
    pub first_singular_frame: Option<u64>,
    /// Most curved regions in one frame.
    pub curved_regions_max: u32,
    /// Most cones (gap cones included) in one frame.
    pub cones_max: u32,
    /// Largest vertex jump made by the geometry layer, metres.
    pub jump_max_m: f64,
    /// Geometry events over the run (sudden shape changes).
    pub geometry_events: u64,
}

impl RunSummary {
    /// The `q`-quantile (0–1) of the step times, milliseconds (0 if not timed).
    pub fn step_ms_quantile(&self, q: f64) -> f64 {
        quantile_ms(self.step_ns.clone(), q)
    }

    /// The `q`-quantile (0–1) of the geometry layer's own time per awake frame, milliseconds
    /// (0 if not timed).
    pub fn geometry_ms_quantile(&self, q: f64) -> f64 {
        let ns: Vec<u64> = self.phase_ns.iter().map(|p| p.geometry_ns).collect();
        quantile_ms(ns, q)
    }

    /// Mean step time over awake frames, milliseconds.
    pub fn step_ms_mean(&self) -> f64 {
        if self.step_ns.is_empty() {
            return 0.0;
        }
        self.step_ns.iter().sum::<u64>() as f64 * 1e-6 / self.step_ns.len() as f64
    }
}

/// The `q`-quantile (0–1) of nanosecond samples, milliseconds (0 for no samples).
fn quantile_ms(mut ns: Vec<u64>, q: f64) -> f64 {
    if ns.is_empty() {
        return 0.0;
    }
    ns.sort_unstable();
    let i = ((ns.len() - 1) as f64 * q.clamp(0.0, 1.0)).round() as usize;
    ns[i] as f64 * 1e-6
}

/// FNV-1a offset basis.
const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;

/// Folds the bits of `values` into the FNV-1a hash `h`.
fn fnv(mut h: u64, values: impl IntoIterator<Item = f64>) -> u64 {
    for c in values {
        for b in c.to_bits().to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

/// FNV-1a hash of the bits of every position and velocity of a sim.
pub fn state_hash(sim: &Sim) -> u64 {
    let sp = &sim.sheet().sp;
    fnv(
        FNV_START,
        sp.pos.iter().chain(&sp.vel).flat_map(|v| v.iter().copied()),
    )
}

/// Folds one frame's published geometry into `h` (see [`RunSummary::geometry_hash`]).
pub fn geometry_frame_hash(h: u64, g: &crate::geometry::GeometryFrame) -> u64 {
    let mut h = fnv(h, [g.rulings.len() as f64, g.cones.len() as f64]);
    for r in &g.rulings {
        h = fnv(
            h,
            [
                r.a2.x, r.a2.y, r.b2.x, r.b2.y, r.a3.x, r.a3.y, r.a3.z, r.b3.x, r.b3.y, r.b3.z,
            ]
            .into_iter()
            .chain([
                r.length_m,
                r.dihedral_rad,
                r.curvature_per_m,
                f64::from(r.region),
            ])
            .chain(r.normal.iter().copied()),
        );
    }
    for c in &g.cones {
        h = fnv(
            h,
            [f64::from(c.first_ruling), f64::from(c.last_ruling)]
                .into_iter()
                .chain(c.apex2.iter().flat_map(|a| [a.x, a.y])),
        );
    }
    for s in &g.singular {
        h = fnv(h, [s.pos2.x, s.pos2.y, s.pos3.x, s.pos3.y, s.pos3.z]);
    }
    h
}

/// Plays a script from a fresh sheet (`base` + the script's `[set]`), optionally timing
/// every awake `Sim::step`.
pub fn run_script(script: &Script, base: SimConfig, timed: bool) -> Result<RunSummary, RunError> {
    let mut runner = ScriptRunner::new(script, base.frame_rate_hz, base.room)?;
    let mut sim = runner.start(base);
    let mut out = FrameOutput::default();
    let mut cmds = Vec::with_capacity(64);
    let mut s = RunSummary {
        step_ns: Vec::with_capacity(if timed {
            runner.num_frames() as usize
        } else {
            0
        }),
        phase_ns: Vec::with_capacity(if timed {
            runner.num_frames() as usize
        } else {
            0
        }),
        ..RunSummary::default()
    };
    sim.set_phase_timing(timed);
    let (mut iters, mut substeps) = (0u64, 0u64);
    let mut geometry_hash = FNV_START;
    while {
        cmds.clear();
        runner.next_frame(&mut cmds)
    } {
        for c in cmds.drain(..) {
            sim.apply(c);
        }
        let awake = !sim.is_asleep();
        let t0 = timed.then(Instant::now);
        sim.step(&mut out);
        if let Some(t0) = t0
            && awake
        {
            s.step_ns.push(t0.elapsed().as_nanos() as u64);
            s.phase_ns.push(sim.phase_times());
        }
        let st = &out.stats;
        s.frames += 1;
        s.awake_frames += u64::from(!st.asleep);
        s.c_mean_pct += f64::from(st.c_mean_pct);
        s.n_comp_pct += f64::from(st.n_comp_pct);
        s.c_mean_max_pct = s.c_mean_max_pct.max(f64::from(st.c_mean_pct));
        s.max_strain = s.max_strain.max(f64::from(st.max_strain));
        s.angle_defect_rad += f64::from(st.angle_defect_rad);
        s.triangles_avg += f64::from(st.num_triangles);
        s.triangles_max = s.triangles_max.max(st.num_triangles);
        s.flips += u64::from(st.num_flipped);
        s.recoveries += u64::from(st.recoveries);
        s.kinetic_energy_max_j = s.kinetic_energy_max_j.max(f64::from(st.kinetic_energy_j));
        s.max_speed_m_s = s.max_speed_m_s.max(f64::from(st.max_speed_m_s));
        iters += u64::from(st.iterations);
        substeps += u64::from(st.substeps);
        let g = sim.geometry();
        geometry_hash = geometry_frame_hash(geometry_hash, g);
        s.singular_final = st.num_singular;
        if st.num_singular > 0 && s.first_singular_frame.is_none() {
            s.first_singular_frame = Some(s.frames);
        }
        s.curved_regions_max = s.curved_regions_max.max(g.num_curved_regions);
        s.cones_max = s.cones_max.max(g.cones.len() as u32);
        s.jump_max_m = s.jump_max_m.max(g.max_vertex_jump_m);
        s.geometry_events += g.events.len() as u64;
    }
    if s.frames > 0 {
        let n = s.frames as f64;
        s.c_mean_pct /= n;
        s.n_comp_pct /= n;
        s.angle_defect_rad /= n;
        s.triangles_avg /= n;
    }
    if substeps > 0 {
        s.iterations_per_substep = iters as f64 / substeps as f64;
    }
    s.final_hash = state_hash(&sim);
    s.geometry_hash = geometry_hash;
    Ok(s)
}

/// Plays a library scenario (see [`crate::scenario`]).
pub fn run_scenario(name: &str, base: SimConfig, timed: bool) -> Result<RunSummary, RunError> {
    let script = scenario::get(name)?;
    run_script(&script, base, timed)
}
