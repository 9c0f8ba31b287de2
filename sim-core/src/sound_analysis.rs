//! # Sound analysis: crumple, "clac" and friction events, and their resonators, from the sheet
//!
//! The analysis half of the seeds' sound model (thesis ch. 4 §4.3.1–4.3.3,
//! `../shared/seeds/000_cb4d91e46ec5927f.txt` T 1760–1810; SCA 2016,
//! `../shared/seeds/002_9b4a8fc30aee6402.txt` §3–4, S 110–160; digest-sound §1–2). Every frame
//! that the sheet moves, it turns the geometry of S_P into the sound input of the frame
//! ([`SoundFrame`]): which crumpling sounds start now, which contact regions slide, and the
//! resonator that selects and spatializes each sound.
//!
//! ## The four steps
//!
//! 1. **Curvature** ([`curvature`]): the signed dihedral angle θ_e of every interior edge; the
//!    mean curvature of every vertex, H_v = Σ_{e∋v} θ_e ℓ_e / (4 A_v) (the integrated mean
//!    curvature θℓ/2 of an edge, shared by its two ends, over a third of the incident pattern
//!    area); and per triangle a discrete shape operator in the pattern plane whose
//!    least-curved direction is the local ruling (on a developable surface the direction of
//!    zero curvature *is* the ruling).
//! 2. **Crumple events** ([`curvature_grid`]): as in the seeds (T 1772, S 126), the mean
//!    curvature is sampled on a regular grid fixed in the *pattern* (1 cm by default; the grid
//!    outlives any remeshing of S_P because it lives in material coordinates), each grid point
//!    keeps its previous value, and a point belongs to a crumpling region when its curvature
//!    sign flipped with |ΔH| > ε_H. An event is a 4-connected component of such points with
//!    the same direction of flip; its amplitude is Σ_v Δ_v, measured as an area integral
//!    (Σ Δ_v · h², metres) and normalised so that 1.0 is a full flip between ±10 m⁻¹
//!    (radius 5 cm) over a 5 × 5 cm patch (the seeds give no gain constant, digest-sound §13
//!    item 7; this one puts the crackle of a crumple at the level of the slide in the demo). **Frame-rate adaptation (impl. choice):** the
//!    seeds compared consecutive animation frames at 1–10 frames/s; at our 200 frames/s a flip
//!    is spread over several frames, each below any useful threshold. Each point therefore
//!    compares its curvature with its last *confident* value (|H| > H_conf) instead of the
//!    previous frame: a flip from a confident convex state to a confident concave one counts
//!    once, whatever the frame rate, and noise around zero never counts. ε_H, the seeds' open
//!    ε_c (digest-sound §13 item 1), is 1 m⁻¹ by default ([`AnalysisConfig`]).
//! 3. **Sudden shape changes, the "clac"** (T 1247, 1261; digest-crumpling §5.2): a new
//!    persistent singular vertex of the geometry layer starts a crumple event at that vertex
//!    whose resonator is constrained (l_c = 0, the database's (0, 0) cell), since in the seeds
//!    a clac is a crumpling event on a constrained resonator. Its amplitude is the summed
//!    |dihedral| of the edges around the new vertex, in radians.
//! 4. **Impacts** ([`impact`], beyond the seeds): the sheet slapping the table, the floor or
//!    the wall (vertices that arrive faster than 5 cm/s) is a sudden change of contact, so a
//!    clac on the constrained cell whose amplitude is the impacting area × speed.
//! 5. **Friction events** ([`friction_events`]): connected components of S_P vertices in contact
//!    with an obstacle (T 1770); the amplitude is the mean tangential slip speed relative to the
//!    obstacle (S 153). Components slower than 2 mm/s are still (no sound). Beyond the seeds,
//!    the sheet's layers pressed on each other rub the same way (`AnalysisInput::layer_slip`,
//!    the sheet–sheet contact pairs' relative slip): a crumple's layers sliding are heard.
//!
//! ## Resonators (T 1782–1810, S 130–143; [`resonators`])
//!
//! Vibrations spread over the sheet until they meet a propagation border: the sheet's edge, a
//! **ridge** (|θ_e| > a_max = 0.5 rad, T 1784), an edge with a held ("anchored") vertex, or an
//! edge in contact with an obstacle (both ends touching). The seeds run a breadth-first search
//! over the regions of S_G from each event; since the search only depends on the borders, this
//! module partitions the S_P triangles once per frame into the connected components that the
//! borders leave ("vibration regions"), and an event's resonators are the distinct regions its
//! grid points (or contact vertices) touch — the same sets the seeds' BFS reaches, computed
//! once for all events. A curved region cut by a ridge is split at that ridge, which is the
//! seeds' "sub-part up to that ruling".
//!
//! For each resonator:
//! - **l_c**: the length of its free curved borders: sheet-boundary edges of curved triangles
//!   (some interior edge bent by more than θ_0 = 0.01 rad, the seeds' flatness threshold,
//!   digest-sound §13 item 2) whose ends are neither held nor in contact (digest-sound §2.4),
//!   each counted by its extent across the local ruling (a border running along a ruling is
//!   straight and does not bend: the digest's "mean dihedral across the adjacent rulings");
//!   l_c = 0 makes the resonator constrained;
//! - **l_r**: the mean ruling length — the region's dominant ruling direction (area- and
//!   curvature-weighted mean of the per-triangle least-curved directions), and the mean chord
//!   of the region along that direction through up to [`resonators::MAX_CHORDS`] sample
//!   points, i.e. the distance between a ruling's two border hits (digest-sound §2.1
//!   fallback). When the geometry layer's rulings are available this is the same quantity
//!   measured on the rulings it has;
//! - the **disk** of the dipole model (digest-sound §2.4 proposal): area-weighted centroid,
//!   area-weighted mean normal, radius √(area/π).
//!
//! Each event gives up to [`AnalysisConfig::max_resonators_per_event`] resonators (the largest
//! by area), each playing at the full event amplitude (the seeds do not split it, Algorithm 4).
//!
//! ## Memory between frames, saved with the sheet
//!
//! Only the curvature grid remembers anything from one frame to the next: each point's last
//! confident curvature and the time of its last flip (the refractory time). Both go into the
//! saved sheet ([`SavedSoundHistory`]), so a reopened sheet makes the crumple events the
//! uninterrupted one would; the count of singular vertices already clacked is the saved
//! sheet's own. Everything else (curvature, vibration regions, resonators, friction) is
//! recomputed from the sheet each frame.
//!
//! ## Cost and allocation
//!
//! All buffers are sized in [`SoundAnalysis::new`] for the mesh capacity and the grid of the
//! largest sheet; [`SoundAnalysis::analyze`] does not allocate. A sleeping sheet is not
//! analysed at all (the simulation skips the call). The analysis of a ~140-triangle sheet
//! costs tens of microseconds (benchmarks: `docs/benchmarks.md`), against the seeds' 5–75 ms.

pub mod air;
pub mod crackle;
pub mod curvature;
pub mod curvature_grid;
pub mod friction_events;
pub mod impact;
pub mod resonators;

use serde::{Deserialize, Serialize};

use crate::collision::{PlaneObstacle, VertexContact};
use crate::sheet::physical::PhysMesh;
use crate::sound_input::{CrumpleEvent, Resonator, SoundFrame};

use curvature::Curvature;
use curvature_grid::CurvatureGrid;
use friction_events::FrictionFinder;
use resonators::{ResonatorFinder, VibrationRegions};

/// Tunable thresholds of the analysis (defaults from the seeds where they give one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnalysisConfig {
    /// Spacing of the curvature grid in the pattern, metres (digest-sound §2.2: 0.5–1 cm).
    pub grid_spacing_m: f64,
    /// ε_H: smallest curvature change of a flipping grid point, 1/m (the seeds' unstated ε_c).
    pub flip_threshold_per_m: f64,
    /// H_conf: a grid point's curvature sign counts only when |H| exceeds this, 1/m.
    pub confident_curvature_per_m: f64,
    /// a_max: dihedral angle of a ridge that stops vibrations, radians (T 1784).
    pub ridge_angle_rad: f64,
    /// θ_0: dihedral angle below which the sheet is flat, radians (T 1252).
    pub flat_angle_rad: f64,
    /// Slowest contact region that rubs audibly, m/s.
    pub min_slip_speed_m_s: f64,
    /// Largest number of resonators per event (the largest by area are kept).
    pub max_resonators_per_event: usize,
    /// Σ Δ_v·h² (metres) of a unit-amplitude crumple event.
    pub crumple_reference_m: f64,
    /// Quietest crumple event kept (amplitude, linear); weaker ones are counted and dropped.
    pub min_event_amplitude: f64,
    /// After a flip, a grid point cannot flip again for this long, seconds.
    pub refractory_s: f64,
}

impl Default for AnalysisConfig {
    fn default() -> Self {
        Self {
            grid_spacing_m: 0.01,
            flip_threshold_per_m: 2.0,
            confident_curvature_per_m: 0.5,
            ridge_angle_rad: 0.5,
            flat_angle_rad: 0.01,
            min_slip_speed_m_s: 0.002,
            max_resonators_per_event: 4,
            crumple_reference_m: 0.05,
            min_event_amplitude: 0.002,
            refractory_s: 0.025,
        }
    }
}

/// What the analysis reads from the sheet each frame.
#[derive(Clone, Copy, Debug)]
pub struct AnalysisInput<'a> {
    /// The physical mesh S_P (positions, pattern, topology, singular vertices).
    pub sp: &'a PhysMesh,
    /// Per-vertex contact with the obstacles (same indexing as S_P).
    pub contacts: &'a [VertexContact],
    /// Per-vertex "held by a hand" flags (same indexing as S_P).
    pub held: &'a [bool],
    /// Simulated time of the frame, seconds (refractory periods).
    pub time_s: f64,
    /// Velocities at the frame's start (same indexing as S_P), for the air ([`air`]).
    pub vel_start: &'a [crate::math::V3],
    /// The frame's length, seconds (0: no air this frame).
    pub dt_s: f64,
    /// The obstacles' planes (their normals place the impacts, [`impact`]); empty: the table
    /// and the floor face up, the wall is not heard.
    pub planes: &'a [PlaneObstacle],
    /// The crumple hands' closing this frame that the squeeze, held at its limit, did not
    /// follow, metres summed over the hands (the press, [`crackle`]).
    pub pressed_m: f64,
    /// Per vertex, the tangential speed at which it slides on another layer of the sheet it is
    /// pressed on, m/s; negative: not pressed on a layer (same indexing as S_P; empty: no
    /// layers rub, [`friction_events`]).
    pub layer_slip: &'a [f32],
}

/// Counts of one frame's analysis (meters, reports, tests).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AnalysisStats {
    /// Crumple events detected from curvature flips.
    pub crumple_events: u32,
    /// "Clac" events from new singular vertices.
    pub clac_events: u32,
    /// "Clac" events from the sheet slapping the table or floor ([`impact`]).
    pub impact_events: u32,
    /// Sliding contact regions.
    pub friction_events: u32,
    /// Sliding regions of the sheet on its own layers.
    pub layer_friction_events: u32,
    /// Grid points that flipped this frame.
    pub flipped_points: u32,
    /// Crumple events quieter than the minimum amplitude (dropped).
    pub quiet_events: u32,
    /// Vibration regions of the frame's partition.
    pub regions: u32,
}

/// The analysis' memory between frames, saved with the sheet ([`crate::sim::SavedSheet`]) so
/// that a reopened sheet sounds as the uninterrupted one would: without it, a grid point whose
/// curvature was confidently convex when the project was saved and turns concave in the next
/// frames makes no crumple event, and a point still in its refractory time may flip again.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SavedSoundHistory {
    /// Grid columns and rows.
    pub grid_dims: [u32; 2],
    /// Each grid point's last confident mean curvature, 1/m (0: none yet); row-major.
    pub confident_curvature_per_m: Vec<f32>,
    /// Simulated time of each grid point's last flip, seconds (`None`: never).
    pub last_flip_s: Vec<Option<f64>>,
}

/// The per-frame analysis, with all its buffers.
#[derive(Clone, Debug)]
pub struct SoundAnalysis {
    cfg: AnalysisConfig,
    curvature: Curvature,
    grid: CurvatureGrid,
    regions: VibrationRegions,
    finder: ResonatorFinder,
    friction: FrictionFinder,
    known_singular: usize,
    stats: AnalysisStats,
    #[cfg(test)]
    test_time_s: f64,
}

impl SoundAnalysis {
    /// Buffers for meshes of up to `max_vertices` / `max_triangles` and a sheet of
    /// `width_m` × `length_m` (the grid is sized for the largest sheet, `max_sheet_m`).
    pub fn new(
        cfg: AnalysisConfig,
        max_vertices: usize,
        max_triangles: usize,
        max_sheet_m: (f64, f64),
        sheet_m: (f64, f64),
    ) -> Self {
        let mut grid = CurvatureGrid::with_capacity(
            cfg.grid_spacing_m,
            max_sheet_m,
            max_vertices,
            max_triangles,
        );
        grid.resize(sheet_m.0, sheet_m.1);
        Self {
            cfg,
            curvature: Curvature::with_capacity(max_vertices, max_triangles),
            grid,
            regions: VibrationRegions::with_capacity(max_triangles),
            finder: ResonatorFinder::with_capacity(max_triangles),
            friction: FrictionFinder::with_capacity(max_vertices),
            known_singular: 0,
            stats: AnalysisStats::default(),
            #[cfg(test)]
            test_time_s: 0.0,
        }
    }

    /// The configuration.
    pub fn config(&self) -> &AnalysisConfig {
        &self.cfg
    }

    /// Forgets the history (a new flat sheet of `width_m` × `length_m`, or a restored one with
    /// `num_singular` singular vertices already present).
    pub fn reset(&mut self, width_m: f64, length_m: f64, num_singular: usize) {
        self.grid.resize(width_m, length_m);
        self.known_singular = num_singular;
        self.stats = AnalysisStats::default();
    }

    /// The memory between frames, for a saved sheet.
    pub fn save_history(&self) -> SavedSoundHistory {
        let (nx, ny) = self.grid.dims();
        let (h_ref, last_flip_s) = self.grid.history();
        SavedSoundHistory {
            grid_dims: [nx as u32, ny as u32],
            confident_curvature_per_m: h_ref.to_vec(),
            last_flip_s: last_flip_s
                .iter()
                .map(|&t| (t != f64::NEG_INFINITY).then_some(t))
                .collect(),
        }
    }

    /// Restores [`Self::save_history`] after [`Self::reset`] for the same sheet. A history for
    /// another grid (saved by a build with another grid spacing) is left out: the history starts
    /// afresh, as for a sheet saved before it was kept, rather than the sheet not opening.
    /// Returns an error message (and changes nothing) if a history for this grid has the wrong
    /// length or a non-finite value.
    pub fn restore_history(&mut self, saved: &SavedSoundHistory) -> Result<(), String> {
        let (nx, ny) = self.grid.dims();
        if saved.grid_dims != [nx as u32, ny as u32] {
            return Ok(());
        }
        let last: Vec<f64> = saved
            .last_flip_s
            .iter()
            .map(|t| t.unwrap_or(f64::NEG_INFINITY))
            .collect();
        self.grid
            .restore_history(&saved.confident_curvature_per_m, &last)
    }

    /// Counts of the last analysed frame.
    pub fn stats(&self) -> &AnalysisStats {
        &self.stats
    }

    /// Mean curvature of the grid points (row-major, `grid_dims()`), 1/m, for inspection.
    pub fn grid_curvature(&self) -> &[f32] {
        self.grid.curvature()
    }

    /// Grid columns and rows.
    pub fn grid_dims(&self) -> (usize, usize) {
        self.grid.dims()
    }

    #[cfg(test)]
    fn test_clock(&mut self) -> f64 {
        self.test_time_s += 1.0;
        self.test_time_s
    }

    /// The flaps at a tear's tip (beyond the seeds: they colour the tear noise): of the
    /// vibration regions of the last [`Self::analyze`] that touch the tip vertex's fan or the
    /// tip's triangle, the larger free one (l_c > 0), else the largest. Call after `analyze` on
    /// the same mesh. No allocation.
    pub fn flap_resonator(
        &mut self,
        input: &AnalysisInput<'_>,
        tip_vertex: Option<u32>,
        tip_triangle: Option<u32>,
    ) -> Option<Resonator> {
        let sp = input.sp;
        let num_tris = sp.triangles.len() as u32;
        self.finder.begin();
        if let Some(v) = tip_vertex.filter(|&v| (v as usize) < sp.num_vertices()) {
            for t in self.curvature.vertex_triangles(sp, v) {
                if t < num_tris {
                    self.finder.add_region(self.regions.region_of(t));
                }
            }
        }
        if let Some(t) = tip_triangle.filter(|&t| t < num_tris) {
            self.finder.add_region(self.regions.region_of(t));
        }
        let cfg = self.cfg;
        let n = self
            .finder
            .select(sp, &self.curvature, &self.regions, input, &cfg, 2);
        (0..n)
            .map(|k| self.finder.resonator(k))
            .find(|r| !r.is_constrained())
            .or_else(|| (n > 0).then(|| self.finder.resonator(0)))
    }

    /// Analyses one frame and appends its events to `out`.
    pub fn analyze(&mut self, input: &AnalysisInput<'_>, out: &mut SoundFrame) {
        let cfg = self.cfg;
        let sp = input.sp;
        self.stats = AnalysisStats::default();
        self.curvature.compute(sp, cfg.ridge_angle_rad);
        self.regions.compute(
            sp,
            &self.curvature,
            input.contacts,
            input.held,
            cfg.ridge_angle_rad,
        );
        self.stats.regions = self.regions.num_regions() as u32;

        // The air the sheet moves (beyond the seeds, [`air`]).
        out.air = air::air_source(sp, input.vel_start, input.contacts, input.held, input.dt_s);
        // The crackle under the events (beyond the seeds, [`crackle`]).
        out.crackle = crackle::crackle_source(sp);
        if input.pressed_m > 0.0 {
            let press = crackle::press_source(sp, input.held, input.pressed_m, input.dt_s);
            out.crackle = crackle::merged(out.crackle, press);
        }

        // Crumple events from curvature flips.
        self.grid.sample(sp, &self.curvature);
        let flips = self.grid.detect_flips(&cfg, input.time_s);
        self.stats.flipped_points = flips.flipped_points;
        let h2 = self.grid.spacing_m().0 * self.grid.spacing_m().1;
        for k in 0..self.grid.num_events() {
            let ev = self.grid.event(k);
            let amplitude = (ev.sum_delta * h2 / cfg.crumple_reference_m).min(8.0) as f32;
            if f64::from(amplitude) < cfg.min_event_amplitude {
                self.stats.quiet_events += 1;
                continue;
            }
            self.finder.begin();
            for &t in self.grid.event_triangles(k) {
                self.finder.add_region(self.regions.region_of(t));
            }
            let n = self.finder.select(
                sp,
                &self.curvature,
                &self.regions,
                input,
                &cfg,
                cfg.max_resonators_per_event,
            );
            for r in 0..n {
                out.push_crumple(CrumpleEvent {
                    amplitude,
                    resonator: self.finder.resonator(r),
                });
            }
            self.stats.crumple_events += 1;
        }

        // "Clac": new persistent singular vertices (appended by the geometry layer).
        let singular = &sp.singular;
        if singular.len() < self.known_singular {
            // A new sheet or a restore the caller did not announce: nothing is new.
            self.known_singular = singular.len();
        }
        for &v in &singular[self.known_singular..] {
            if v as usize >= sp.num_vertices() {
                continue;
            }
            let amplitude = self.curvature.vertex_angle_sum(sp, v).clamp(0.05, 4.0) as f32;
            self.finder.begin();
            for t in self.curvature.vertex_triangles(sp, v) {
                self.finder.add_region(self.regions.region_of(t));
            }
            let n = self
                .finder
                .select(sp, &self.curvature, &self.regions, input, &cfg, 1);
            for r in 0..n {
                let mut res = self.finder.resonator(r);
                res.lc_cm = 0.0;
                out.push_crumple(CrumpleEvent {
                    amplitude,
                    resonator: res,
                });
            }
            self.stats.clac_events += 1;
        }
        self.known_singular = singular.len();

        // The sheet slapping the table, the floor or the wall (beyond the seeds, [`impact`]).
        let mut impacts = [None; 3];
        let n = impact::impact_events(
            sp,
            input.vel_start,
            input.contacts,
            input.held,
            input.planes,
            &mut impacts,
        );
        for e in impacts[..n].iter().flatten() {
            if f64::from(e.amplitude) >= cfg.min_event_amplitude {
                out.push_crumple(*e);
                self.stats.impact_events += 1;
            } else {
                self.stats.quiet_events += 1;
            }
        }

        // Friction.
        (self.stats.friction_events, self.stats.layer_friction_events) = self.friction.detect(
            sp,
            &self.curvature,
            &self.regions,
            &mut self.finder,
            input,
            &cfg,
            out,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::VertexContact;
    use crate::math::{V2, V3};
    use crate::sheet::pattern::Pattern;
    use crate::sound_input::Obstacle;

    /// A square-grid pattern of `n × n` cells over `[−s/2, s/2]²` (diagonals alternate).
    fn grid_sheet(size_m: f64, n: usize) -> PhysMesh {
        let h = size_m / n as f64;
        let mut points = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                points.push(V2::new(
                    -0.5 * size_m + i as f64 * h,
                    -0.5 * size_m + j as f64 * h,
                ));
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                if (i + j) % 2 == 0 {
                    triangles.push([a, b, c]);
                    triangles.push([a, c, d]);
                } else {
                    triangles.push([a, b, d]);
                    triangles.push([b, c, d]);
                }
            }
        }
        PhysMesh::from_pattern(&Pattern { points, triangles }, 0.0, 0.1).unwrap()
    }

    fn analysis_for(sp: &PhysMesh, size_m: f64) -> SoundAnalysis {
        SoundAnalysis::new(
            AnalysisConfig::default(),
            sp.num_vertices(),
            sp.num_triangles(),
            (size_m, size_m),
            (size_m, size_m),
        )
    }

    /// Sets z to Σ_k a_k · exp(−|p − c_k|² / 2σ²).
    fn bumps(sp: &mut PhysMesh, list: &[(V2, f64)], sigma_m: f64) {
        for (x, p) in sp.pos.iter_mut().zip(&sp.pattern) {
            let z: f64 = list
                .iter()
                .map(|(c, a)| a * (-(p - c).norm_squared() / (2.0 * sigma_m * sigma_m)).exp())
                .sum();
            *x = V3::new(p.x, p.y, z);
        }
    }

    fn run(an: &mut SoundAnalysis, sp: &PhysMesh) -> SoundFrame {
        let contacts = vec![VertexContact::default(); sp.num_vertices()];
        let held = vec![false; sp.num_vertices()];
        let mut out = SoundFrame::default();
        let time_s = an.test_clock();
        an.analyze(
            &AnalysisInput {
                sp,
                contacts: &contacts,
                held: &held,
                time_s,
                vel_start: &[],
                dt_s: 0.0,
                planes: &[],
                pressed_m: 0.0,
                layer_slip: &[],
            },
            &mut out,
        );
        out
    }

    /// digest-sound §12 test 13: a 2 × 2 cm patch whose curvature flips gives exactly one
    /// event with amplitude Σ Δ_v; below ε_H none; two separate patches two.
    #[test]
    fn curvature_flip_events() {
        let size = 0.24;
        let mut sp = grid_sheet(size, 60);
        let sigma = 0.008;
        // Peak mean curvature |H| = a/σ² = 4 /m (a flip changes it by 8 /m > ε_H = 2 /m);
        // the opposite-signed flank ring of a Gaussian peaks at 0.135 of that, 0.54 /m, a
        // 1.1 /m change, below ε_H.
        let cfg = AnalysisConfig::default();
        assert_eq!(cfg.flip_threshold_per_m, 2.0);
        let a = 4.0 * sigma * sigma;
        let centre = V2::new(0.0, 0.0);

        let mut an = analysis_for(&sp, size);
        bumps(&mut sp, &[(centre, a)], sigma);
        let first = run(&mut an, &sp);
        assert_eq!(first.crumple().len(), 0, "a first state is no flip");
        let before: Vec<f32> = an.grid_curvature().to_vec();
        bumps(&mut sp, &[(centre, -a)], sigma);
        let out = run(&mut an, &sp);
        assert_eq!(an.stats().crumple_events, 1, "{:?}", an.stats());
        assert!(!out.crumple().is_empty());
        // Amplitude = Σ over the flipped points of |ΔH| (× cell area / reference).
        let after = an.grid_curvature();
        let mut sum = 0.0f64;
        for (b, a) in before.iter().zip(after) {
            if b.abs() > cfg.confident_curvature_per_m as f32
                && a.abs() > cfg.confident_curvature_per_m as f32
                && b.signum() != a.signum()
                && (a - b).abs() > cfg.flip_threshold_per_m as f32
            {
                sum += f64::from((a - b).abs());
            }
        }
        assert!(sum > 0.0);
        let h2 = 0.01 * 0.01;
        let want = (sum * h2 / cfg.crumple_reference_m) as f32;
        let got = out.crumple()[0].amplitude;
        assert!(
            (got - want).abs() <= 1e-4 * want.max(1e-6),
            "{got} vs {want}"
        );

        // The same flip with |H| = 0.8 /m: confident signs (> 0.5 /m), but |ΔH| = 1.6 /m
        // < ε_H → nothing.
        let mut an = analysis_for(&sp, size);
        let small = a * 0.8 / 4.0;
        bumps(&mut sp, &[(centre, small)], sigma);
        run(&mut an, &sp);
        bumps(&mut sp, &[(centre, -small)], sigma);
        let out = run(&mut an, &sp);
        assert_eq!(an.stats().crumple_events, 0, "{:?}", an.stats());
        assert!(out.crumple().is_empty());

        // Two separated patches → two events.
        let mut an = analysis_for(&sp, size);
        let (c1, c2) = (V2::new(-0.06, 0.0), V2::new(0.06, 0.0));
        bumps(&mut sp, &[(c1, a), (c2, a)], sigma);
        run(&mut an, &sp);
        bumps(&mut sp, &[(c1, -a), (c2, -a)], sigma);
        run(&mut an, &sp);
        assert_eq!(an.stats().crumple_events, 2, "{:?}", an.stats());
    }

    /// Folds the sheet along x = 0 by `angle` (the half x > 0 turns about the y axis).
    fn folded(size_m: f64, n: usize, angle: f64) -> PhysMesh {
        let mut sp = grid_sheet(size_m, n);
        for (x, p) in sp.pos.iter_mut().zip(&sp.pattern) {
            *x = if p.x <= 0.0 {
                V3::new(p.x, p.y, 0.0)
            } else {
                V3::new(p.x * angle.cos(), p.y, p.x * angle.sin())
            };
        }
        sp
    }

    fn regions_of(sp: &PhysMesh, contacts: &[VertexContact], held: &[bool]) -> (u32, u32, usize) {
        let mut c = Curvature::with_capacity(sp.num_vertices(), sp.num_triangles());
        c.compute(sp, 0.5);
        let mut r = VibrationRegions::with_capacity(sp.num_triangles());
        r.compute(sp, &c, contacts, held, 0.5);
        // A triangle left of the fold and one right of it.
        let find = |x: f64| {
            (0..sp.num_triangles())
                .find(|&t| {
                    let c: V2 = sp.triangles[t]
                        .iter()
                        .map(|&v| sp.pattern[v as usize])
                        .sum();
                    (c.x / 3.0 - x).abs() < 0.02 && (c.y / 3.0).abs() < 0.02
                })
                .unwrap() as u32
        };
        (
            r.region_of(find(-0.05)),
            r.region_of(find(0.05)),
            r.num_regions(),
        )
    }

    /// digest-sound §12 test 14: a ridge above a_max splits the resonators, below it does not;
    /// held and contact edges stop propagation too.
    #[test]
    fn ridges_anchors_and_contacts_bound_resonators() {
        let (size, n) = (0.2, 10);
        let none_c = vec![VertexContact::default(); (n + 1) * (n + 1)];
        let none_h = vec![false; (n + 1) * (n + 1)];
        let (a, b, k) = regions_of(&folded(size, n, 0.6), &none_c, &none_h);
        assert_ne!(a, b, "a 0.6 rad ridge separates the halves");
        assert_eq!(k, 2);
        let (a, b, k) = regions_of(&folded(size, n, 0.4), &none_c, &none_h);
        assert_eq!(a, b, "a 0.4 rad fold does not");
        assert_eq!(k, 1);

        // Held vertices along the fold line stop propagation.
        let flat = folded(size, n, 0.0);
        let mut held = none_h.clone();
        for (v, p) in flat.pattern.iter().enumerate() {
            if p.x.abs() < 1e-9 {
                held[v] = true;
            }
        }
        let (a, b, _) = regions_of(&flat, &none_c, &held);
        assert_ne!(a, b, "an anchored line separates");
        // So do contact lines.
        let mut contacts = none_c.clone();
        for (v, p) in flat.pattern.iter().enumerate() {
            if p.x.abs() < 1e-9 {
                contacts[v].in_contact = true;
            }
        }
        let (a, b, _) = regions_of(&flat, &contacts, &none_h);
        assert_ne!(a, b, "a contact line separates");

        // An event in region A gets resonator {A} only: half the sheet's area.
        let sp = folded(size, n, 0.6);
        let mut an = analysis_for(&sp, size);
        let mut out = SoundFrame::default();
        let input = AnalysisInput {
            sp: &sp,
            contacts: &none_c,
            held: &none_h,
            time_s: 0.0,
            vel_start: &[],
            dt_s: 0.0,
            planes: &[],
            pressed_m: 0.0,
            layer_slip: &[],
        };
        an.analyze(&input, &mut out);
        an.finder.begin();
        an.finder.add_region(an.regions.region_of(0));
        let got = an
            .finder
            .select(&sp, &an.curvature, &an.regions, &input, &an.cfg, 4);
        assert_eq!(got, 1);
        let r = an.finder.resonator(0);
        let half_disk = (0.5 * size * size / std::f64::consts::PI).sqrt() as f32;
        assert!(
            (r.radius_m - half_disk).abs() < 1e-4,
            "{} vs {half_disk}",
            r.radius_m
        );
        // Flat halves have no free curved border: constrained.
        assert!(r.is_constrained());
    }

    /// Every event of a frame that selects a region gets the one measurement of that region,
    /// and the next frame measures again (resonators.rs, "One measurement per region and
    /// frame").
    #[test]
    fn a_region_is_measured_once_per_frame() {
        let (size, n) = (0.2, 20);
        let mut sp = grid_sheet(size, n);
        let c = vec![VertexContact::default(); sp.num_vertices()];
        let h = vec![false; sp.num_vertices()];
        let mut an = analysis_for(&sp, size);
        let rolled = |sp: &mut PhysMesh, r_m: f64| {
            for (x, p) in sp.pos.iter_mut().zip(&sp.pattern) {
                let phi = p.x / r_m;
                *x = V3::new(r_m * phi.sin(), p.y, r_m * (1.0 - phi.cos()));
            }
        };
        let mut measured = Vec::new();
        for r_m in [0.08, 0.05] {
            rolled(&mut sp, r_m);
            let input = AnalysisInput {
                sp: &sp,
                contacts: &c,
                held: &h,
                time_s: 0.0,
                vel_start: &[],
                dt_s: 0.0,
                planes: &[],
                pressed_m: 0.0,
                layer_slip: &[],
            };
            an.analyze(&input, &mut SoundFrame::default());
            assert_eq!(an.regions.num_regions(), 1);
            let fresh = ResonatorFinder::with_capacity(sp.num_triangles()).measure(
                &sp,
                &an.curvature,
                an.regions.triangles(0),
                &input,
                &an.cfg,
            );
            for _event in 0..2 {
                an.finder.begin();
                an.finder.add_region(0);
                an.finder
                    .select(&sp, &an.curvature, &an.regions, &input, &an.cfg, 1);
                assert_eq!(an.finder.resonator(0), fresh);
            }
            measured.push(fresh);
        }
        // The tighter roll is a different resonator: the second frame did not reuse the first.
        assert_ne!(measured[0], measured[1]);
    }

    /// A half-cylinder (curved, free edges) vs a flat sheet: l_c and l_r.
    #[test]
    fn curved_region_parameters() {
        let (size, n) = (0.2, 20);
        let mut sp = grid_sheet(size, n);
        let r_m = 0.08;
        for (x, p) in sp.pos.iter_mut().zip(&sp.pattern) {
            let phi = p.x / r_m;
            *x = V3::new(r_m * phi.sin(), p.y, r_m * (1.0 - phi.cos()));
        }
        let c = vec![VertexContact::default(); sp.num_vertices()];
        let h = vec![false; sp.num_vertices()];
        let mut an = analysis_for(&sp, size);
        let input = AnalysisInput {
            sp: &sp,
            contacts: &c,
            held: &h,
            time_s: 0.0,
            vel_start: &[],
            dt_s: 0.0,
            planes: &[],
            pressed_m: 0.0,
            layer_slip: &[],
        };
        let mut out = SoundFrame::default();
        an.analyze(&input, &mut out);
        assert_eq!(an.regions.num_regions(), 1);
        an.finder.begin();
        an.finder.add_region(0);
        an.finder
            .select(&sp, &an.curvature, &an.regions, &input, &an.cfg, 1);
        let r = an.finder.resonator(0);
        // Rulings run along y across the whole 20 cm sheet; the free curved borders are the
        // two bent 20 cm edges (the straight sides along the rulings do not bend): l_c = 40 cm.
        assert!((r.lr_cm - 20.0).abs() < 1.0, "l_r {}", r.lr_cm);
        assert!((r.lc_cm - 40.0).abs() < 2.0, "l_c {}", r.lc_cm);
        // The disk: normal along +z (mean of the cylinder's normals), radius √(A/π).
        assert!(r.normal[2] > 0.9, "{:?}", r.normal);
        // Holding the whole border makes it constrained.
        let held: Vec<bool> = sp.topo.vertex_on_boundary.clone();
        let input = AnalysisInput {
            sp: &sp,
            contacts: &c,
            held: &held,
            time_s: 1.0,
            vel_start: &[],
            dt_s: 0.0,
            planes: &[],
            pressed_m: 0.0,
            layer_slip: &[],
        };
        an.analyze(&input, &mut out);
        let t = (0..sp.num_triangles() as u32)
            .find(|&t| {
                sp.triangles[t as usize]
                    .iter()
                    .all(|&v| !sp.topo.vertex_on_boundary[v as usize])
            })
            .unwrap();
        an.finder.begin();
        an.finder.add_region(an.regions.region_of(t));
        an.finder
            .select(&sp, &an.curvature, &an.regions, &input, &an.cfg, 1);
        assert!(an.finder.resonator(0).is_constrained());
    }

    /// A sheet rolled about the y axis with radius `r_m` (rulings along y; the arc length is
    /// the pattern x) and an extra kink of `kink_rad` along the ruling x = `x_k` (a grid line).
    fn rolled_with_kink(size_m: f64, n: usize, r_m: f64, x_k: f64, kink_rad: f64) -> PhysMesh {
        let mut sp = grid_sheet(size_m, n);
        // Centre line (x, z) at arc length s: the tangent turns by s/r, plus the kink after x_k.
        let plain = |s: f64| (r_m * (s / r_m).sin(), r_m * (1.0 - (s / r_m).cos()));
        let at = |s: f64| {
            if s <= x_k + 1e-12 {
                plain(s)
            } else {
                let (xk, zk) = plain(x_k);
                let a = |s: f64| s / r_m + kink_rad;
                (
                    xk + r_m * (a(s).sin() - a(x_k).sin()),
                    zk - r_m * (a(s).cos() - a(x_k).cos()),
                )
            }
        };
        for (x, p) in sp.pos.iter_mut().zip(&sp.pattern) {
            let (cx, cz) = at(p.x);
            *x = V3::new(cx, p.y, cz);
        }
        sp
    }

    /// digest-sound §12 test 14, curved case: in a curved region (every ruling line bent by
    /// 0.1 rad, above θ_0), one internal ruling bent by more than a_max (0.1 + 0.45 rad) stops
    /// the vibrations: an event on one side gets only the partial region up to that ruling
    /// (its area, its free curved borders, still unconstrained), not the whole curved region;
    /// with the ruling bent by 0.1 + 0.25 rad < a_max the same event gets the whole sheet.
    /// Detects a ridge test that ignores curved regions, a partial region that is expanded
    /// past the ridge, and a partial region measured as the whole one.
    #[test]
    fn ridge_inside_a_curved_region_gives_a_partial_resonator() {
        let (size, n, r_m, x_k) = (0.2, 20, 0.1, 0.05);
        let h = vec![false; (n + 1) * (n + 1)];
        let c = vec![VertexContact::default(); (n + 1) * (n + 1)];
        // The resonators of an event on the triangle at pattern (−0.05, 0), side A.
        let resonators_from_a = |sp: &PhysMesh| {
            let mut an = analysis_for(sp, size);
            let input = AnalysisInput {
                sp,
                contacts: &c,
                held: &h,
                time_s: 0.0,
                vel_start: &[],
                dt_s: 0.0,
                planes: &[],
                pressed_m: 0.0,
                layer_slip: &[],
            };
            an.analyze(&input, &mut SoundFrame::default());
            let t = (0..sp.num_triangles())
                .find(|&t| {
                    let m: V2 = sp.triangles[t]
                        .iter()
                        .map(|&v| sp.pattern[v as usize])
                        .sum::<V2>()
                        / 3.0;
                    (m.x + 0.05).abs() < 0.01 && m.y.abs() < 0.01
                })
                .unwrap() as u32;
            an.finder.begin();
            an.finder.add_region(an.regions.region_of(t));
            let k = an
                .finder
                .select(sp, &an.curvature, &an.regions, &input, &an.cfg, 4);
            let area = an.regions.area_m2(an.regions.region_of(t));
            let res: Vec<_> = (0..k).map(|r| an.finder.resonator(r)).collect();
            (an.regions.num_regions(), area, res)
        };

        // Sanity of the construction: the kink line is the only ridge, the rest is curved.
        let sp = rolled_with_kink(size, n, r_m, x_k, 0.45);
        let mut curv = Curvature::with_capacity(sp.num_vertices(), sp.num_triangles());
        curv.compute(&sp, 0.5);
        let ridges = curv.edge_angle_rad.iter().filter(|a| a.abs() > 0.5).count();
        assert_eq!(ridges, n, "one ridge line of {n} edges");

        let (regions, area, res) = resonators_from_a(&sp);
        assert_eq!(regions, 2);
        assert_eq!(res.len(), 1, "only the partial region: {res:?}");
        let r = res[0];
        let part_area = (x_k + 0.5 * size) * size;
        assert!((area - part_area).abs() < 1e-6, "{area} vs {part_area}");
        let disk = (part_area / std::f64::consts::PI).sqrt() as f32;
        assert!((r.radius_m - disk).abs() < 1e-4, "{} vs {disk}", r.radius_m);
        // Still a curved (unconstrained) resonator; its free curved borders are the two bent
        // sheet edges up to the ridge, 2 × 15 cm (the ridge itself is not a free border),
        // within one 1 cm cell per edge: a border triangle whose only bent edge is the ridge
        // counts as flat (measured: 28 cm). The whole sheet's 40 cm is far outside.
        assert!(!r.is_constrained());
        let lc_part = 2.0 * (x_k + 0.5 * size) * 100.0;
        assert!(
            (f64::from(r.lc_cm) - lc_part).abs() <= 2.0 + 1e-3,
            "l_c {}",
            r.lc_cm
        );
        assert!((r.lr_cm - 20.0).abs() < 1.0, "l_r {}", r.lr_cm);

        // Below a_max the bent ruling does not stop the vibrations: the whole sheet.
        let sp = rolled_with_kink(size, n, r_m, x_k, 0.25);
        let (regions, area, res) = resonators_from_a(&sp);
        assert_eq!(regions, 1);
        assert_eq!(res.len(), 1);
        assert!((area - size * size).abs() < 1e-6, "{area}");
        assert!(
            (f64::from(res[0].lc_cm) - 2.0 * size * 100.0).abs() < 2.0,
            "l_c {}",
            res[0].lc_cm
        );
    }

    /// Friction: a flat sheet sliding on the table is one constrained source at the mean slip
    /// speed; a sheet with a curled free half gives an unconstrained one; a still sheet none.
    #[test]
    fn friction_sources() {
        let (size, n) = (0.2, 20);
        let sp = grid_sheet(size, n);
        let nv = sp.num_vertices();
        let held = vec![false; nv];
        let mut contacts = vec![
            VertexContact {
                in_contact: true,
                slip_speed_m_s: 0.1,
                ..Default::default()
            };
            nv
        ];
        let mut an = analysis_for(&sp, size);
        let mut out = SoundFrame::default();
        an.analyze(
            &AnalysisInput {
                sp: &sp,
                contacts: &contacts,
                held: &held,
                time_s: 0.0,
                vel_start: &[],
                dt_s: 0.0,
                planes: &[],
                pressed_m: 0.0,
                layer_slip: &[],
            },
            &mut out,
        );
        assert_eq!(out.friction().len(), 1);
        let f = out.friction()[0];
        assert!((f.slip_speed_m_s - 0.1).abs() < 1e-6);
        assert!(f.resonator.is_constrained());

        // Curl the x > 0 half up; only x ≤ 0 touches the table.
        let mut curled = sp.clone();
        let r_m = 0.05;
        for (v, (x, p)) in curled.pos.iter_mut().zip(&curled.pattern).enumerate() {
            if p.x > 0.0 {
                let phi = p.x / r_m;
                *x = V3::new(r_m * phi.sin(), p.y, r_m * (1.0 - phi.cos()));
                contacts[v].in_contact = false;
            }
        }
        let mut out = SoundFrame::default();
        an.analyze(
            &AnalysisInput {
                sp: &curled,
                contacts: &contacts,
                held: &held,
                time_s: 0.0,
                vel_start: &[],
                dt_s: 0.0,
                planes: &[],
                pressed_m: 0.0,
                layer_slip: &[],
            },
            &mut out,
        );
        assert_eq!(an.stats().friction_events, 1);
        assert!(
            out.friction().iter().any(|f| !f.resonator.is_constrained()),
            "{:?}",
            out.friction()
        );

        // Still: nothing.
        for c in &mut contacts {
            c.slip_speed_m_s = 0.0;
        }
        let mut out = SoundFrame::default();
        an.analyze(
            &AnalysisInput {
                sp: &curled,
                contacts: &contacts,
                held: &held,
                time_s: 0.0,
                vel_start: &[],
                dt_s: 0.0,
                planes: &[],
                pressed_m: 0.0,
                layer_slip: &[],
            },
            &mut out,
        );
        assert!(out.friction().is_empty());
    }

    /// A layer sliding on another rubs like the table (beyond the seeds): a set of vertices
    /// pressed on a layer is one friction source at its mean slip; where they touch the table
    /// they rub there instead; a layer resting on another is silent.
    #[test]
    fn layers_sliding_on_each_other_rub() {
        let (size, n) = (0.2, 20);
        let sp = grid_sheet(size, n);
        let nv = sp.num_vertices();
        let held = vec![false; nv];
        let mut contacts = vec![VertexContact::default(); nv];
        // The x > 0.05 strip is pressed on another layer: slip 4 cm/s, 2 cm/s on its edge.
        let mut slip = vec![-1.0f32; nv];
        for (v, p) in sp.pattern.iter().enumerate() {
            if p.x > 0.05 {
                slip[v] = if p.x > 0.06 { 0.04 } else { 0.02 };
            }
        }
        let mut an = analysis_for(&sp, size);
        let run = |an: &mut SoundAnalysis, contacts: &[VertexContact], slip: &[f32]| {
            let mut out = SoundFrame::default();
            an.analyze(
                &AnalysisInput {
                    sp: &sp,
                    contacts,
                    held: &held,
                    time_s: 0.0,
                    vel_start: &[],
                    dt_s: 0.0,
                    planes: &[],
                    pressed_m: 0.0,
                    layer_slip: slip,
                },
                &mut out,
            );
            out
        };
        let out = run(&mut an, &contacts, &slip);
        assert_eq!(an.stats().layer_friction_events, 1);
        assert_eq!(an.stats().friction_events, 0);
        let f = out.friction()[0];
        assert_eq!(f.obstacle, Obstacle::SelfContact);
        let (strip, edge) = (
            sp.pattern.iter().filter(|p| p.x > 0.05).count(),
            sp.pattern
                .iter()
                .filter(|p| p.x > 0.05 && p.x <= 0.06)
                .count(),
        );
        let mean = (0.04 * (strip - edge) as f64 + 0.02 * edge as f64) / strip as f64;
        assert!((f64::from(f.slip_speed_m_s) - mean).abs() < 1e-6, "{f:?}");
        // The strip lies on the table: it rubs on the table, not on the layer.
        for (c, p) in contacts.iter_mut().zip(&sp.pattern) {
            c.in_contact = p.x > 0.05;
            c.slip_speed_m_s = 0.01;
        }
        let out = run(&mut an, &contacts, &slip);
        assert_eq!(an.stats().layer_friction_events, 0);
        assert!(out.friction().iter().all(|f| f.obstacle == Obstacle::Table));
        // Pressed on the layer and still (or slower than the slowest audible rub): silent.
        contacts.fill(VertexContact::default());
        slip.iter_mut()
            .filter(|s| **s >= 0.0)
            .for_each(|s| *s = 0.001);
        let out = run(&mut an, &contacts, &slip);
        assert!(out.friction().is_empty());
    }

    /// A new singular vertex is a "clac": one constrained crumple event.
    #[test]
    fn new_singular_vertex_is_a_clac() {
        let (size, n) = (0.2, 10);
        let mut sp = folded(size, n, 0.3);
        let mut an = analysis_for(&sp, size);
        run(&mut an, &sp);
        sp.singular.push(60);
        let out = run(&mut an, &sp);
        assert_eq!(an.stats().clac_events, 1);
        assert_eq!(out.crumple().len(), 1);
        assert!(out.crumple()[0].resonator.is_constrained());
        assert!(out.crumple()[0].amplitude > 0.0);
        // Persistent: the next frame does not repeat it.
        run(&mut an, &sp);
        assert_eq!(an.stats().clac_events, 0);
    }
}
