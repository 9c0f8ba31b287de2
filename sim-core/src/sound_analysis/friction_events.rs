//! # Friction events (T 1770, S 153; digest-sound §2.2)
//!
//! A friction event is a connected set of S_P vertices touching an obstacle (the contact
//! flags of [`crate::collision`], the same proximity test the physics uses); its amplitude is
//! the mean tangential speed of those vertices relative to the obstacle (the seeds take "the
//! mean speed of its vertices"; the SCA paper says the relative frictional motion, so the
//! normal component is removed). Sets slower than `min_slip_speed_m_s` are silent.
//!
//! Resonators of a friction event: contact edges are propagation borders, so the part of the
//! sheet that rubs drives the vibration regions that *border* the contact — the regions of
//! triangles that have a vertex in the set but are not entirely pressed on the obstacle (a
//! lifted flap, a curled edge). Each free one becomes one friction source (the largest
//! `max_resonators_per_event`); constrained ones (flat, or with no free curved border) do not
//! ring and rub as a single source. A set with no such rim (the sheet lies flat) is one
//! constrained resonator made of its pressed triangles: the seeds' quiet, nearly white
//! "constrained friction" (T 1704).
//!
//! **Layers rubbing on each other (beyond the seeds).** The seeds hear friction only against
//! the table (T 1770); in a real crumple the layers of the sheet slide over each other and rub.
//! [`FrictionFinder::detect`] also makes the same sets from the vertices pressed on another
//! layer (`AnalysisInput::layer_slip`: the tangential speed of their sheet–sheet contact pairs,
//! [`crate::physics::sheet_contact`]), each set rubbing as [`Obstacle::SelfContact`] through
//! the same resonators and the same friction spectra as the table (no paper-on-paper
//! recordings: an approximation). The contact between layers is frictionless in the physics,
//! so a layer slides as far as its contact lets it; the speed heard is that slip.

use crate::sheet::physical::PhysMesh;
use crate::sheet::topology::NONE;
use crate::sound_input::{FrictionSource, Obstacle, SoundFrame};

use super::curvature::Curvature;
use super::resonators::{ResonatorFinder, VibrationRegions};
use super::{AnalysisConfig, AnalysisInput};

/// Contact components and their resonators.
#[derive(Clone, Debug, Default)]
pub struct FrictionFinder {
    label: Vec<u32>,
    stack: Vec<u32>,
    members: Vec<u32>,
    pressed: Vec<u32>,
}

impl FrictionFinder {
    /// Buffers for up to `max_vertices` vertices.
    pub fn with_capacity(max_vertices: usize) -> Self {
        Self {
            label: Vec::with_capacity(max_vertices),
            stack: Vec::with_capacity(max_vertices),
            members: Vec::with_capacity(max_vertices),
            pressed: Vec::with_capacity(4 * max_vertices),
        }
    }

    /// Finds the sliding contact sets on the obstacles, then the sets of vertices pressed on
    /// another layer of the sheet and sliding on it (`AnalysisInput::layer_slip`; a vertex
    /// touching an obstacle rubs there instead), appends their friction sources to `out` and
    /// returns the numbers of sliding sets: on obstacles, between layers.
    #[allow(clippy::too_many_arguments)]
    pub fn detect(
        &mut self,
        sp: &PhysMesh,
        curv: &Curvature,
        regions: &VibrationRegions,
        finder: &mut ResonatorFinder,
        input: &AnalysisInput<'_>,
        cfg: &AnalysisConfig,
        out: &mut SoundFrame,
    ) -> (u32, u32) {
        let on_obstacle = |v: usize| {
            input
                .contacts
                .get(v)
                .filter(|c| c.in_contact)
                .map(|c| (c.slip_speed_m_s, c.obstacle))
        };
        let on_layer = |v: usize| {
            input
                .layer_slip
                .get(v)
                .filter(|s| **s >= 0.0 && on_obstacle(v).is_none())
                .map(|s| (*s, Obstacle::SelfContact))
        };
        let obstacles = self.detect_sets(sp, curv, regions, finder, input, cfg, on_obstacle, out);
        let layers = self.detect_sets(sp, curv, regions, finder, input, cfg, on_layer, out);
        (obstacles, layers)
    }

    /// Connected sets of the vertices where `at` gives (slip speed, obstacle).
    #[allow(clippy::too_many_arguments)]
    fn detect_sets(
        &mut self,
        sp: &PhysMesh,
        curv: &Curvature,
        regions: &VibrationRegions,
        finder: &mut ResonatorFinder,
        input: &AnalysisInput<'_>,
        cfg: &AnalysisConfig,
        at: impl Fn(usize) -> Option<(f32, Obstacle)>,
        out: &mut SoundFrame,
    ) -> u32 {
        let nv = sp.num_vertices();
        let touching = |v: usize| at(v).is_some();
        self.label.clear();
        self.label.resize(nv, NONE);
        let mut events = 0u32;
        for seed in 0..nv {
            if !touching(seed) || self.label[seed] != NONE {
                continue;
            }
            // One connected contact set.
            self.members.clear();
            self.stack.clear();
            self.stack.push(seed as u32);
            self.label[seed] = seed as u32;
            let mut speed = 0.0f64;
            let mut counts = [0u32; 4];
            while let Some(v) = self.stack.pop() {
                self.members.push(v);
                let (slip, obstacle) = at(v as usize).unwrap_or_default();
                speed += f64::from(slip);
                counts[obstacle_index(obstacle)] += 1;
                for &w in sp.topo.neighbours(v) {
                    let w = w as usize;
                    if w < nv && touching(w) && self.label[w] == NONE {
                        self.label[w] = seed as u32;
                        self.stack.push(w as u32);
                    }
                }
            }
            let mean = speed / self.members.len() as f64;
            if !(mean.is_finite() && mean >= cfg.min_slip_speed_m_s) {
                continue;
            }
            events += 1;
            let obstacle = OBSTACLES[counts
                .iter()
                .enumerate()
                .max_by_key(|(i, c)| (**c, std::cmp::Reverse(*i)))
                .map_or(0, |(i, _)| i)];
            // Rim regions and pressed triangles around the set.
            finder.begin();
            self.pressed.clear();
            for &v in &self.members {
                for t in curv.vertex_triangles(sp, v) {
                    let tri = sp.triangles[t as usize];
                    if tri.iter().all(|&u| touching(u as usize)) {
                        if !self.pressed.contains(&t) {
                            self.pressed.push(t);
                        }
                    } else {
                        finder.add_region(regions.region_of(t));
                    }
                }
            }
            let n = if finder.num_candidates() > 0 {
                finder.select(sp, curv, regions, input, cfg, cfg.max_resonators_per_event)
            } else if !self.pressed.is_empty() {
                self.pressed.sort_unstable();
                finder.measure_into(sp, curv, &self.pressed, input, cfg);
                1
            } else {
                0
            };
            // Constrained regions do not ring: all of them rub as one nearly white source
            // (the largest, first in area order); each free region is its own source.
            let mut constrained_done = false;
            for r in 0..n {
                let resonator = finder.resonator(r);
                if resonator.is_constrained() {
                    if constrained_done {
                        continue;
                    }
                    constrained_done = true;
                }
                out.push_friction(FrictionSource {
                    slip_speed_m_s: mean as f32,
                    obstacle,
                    resonator,
                });
            }
        }
        events
    }
}

const OBSTACLES: [Obstacle; 4] = [
    Obstacle::Table,
    Obstacle::Wall,
    Obstacle::Floor,
    Obstacle::SelfContact,
];

fn obstacle_index(o: Obstacle) -> usize {
    match o {
        Obstacle::Table => 0,
        Obstacle::Wall => 1,
        Obstacle::Floor => 2,
        Obstacle::SelfContact => 3,
    }
}
