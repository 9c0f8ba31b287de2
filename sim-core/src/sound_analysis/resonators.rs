//! # Resonators: vibration regions and their (l_r, l_c) and disk (T 1782–1810, S 130–143)
//!
//! [`VibrationRegions`] partitions the S_P triangles into the connected components left by the
//! propagation borders (sheet boundary, ridges with |θ| > a_max, edges with a held vertex,
//! edges with both ends in contact); see [`crate::sound_analysis`] for why this equals the
//! seeds' per-event breadth-first search. [`ResonatorFinder`] turns the regions that an event
//! touches into [`Resonator`]s: it keeps the largest ones by area and measures, for each,
//! the free curved border length l_c, the mean ruling length l_r and the disk of the dipole.
//!
//! **l_r on S_P (approximation, said here and in the README):** the region's dominant ruling
//! direction d is the principal eigenvector of Σ_t w_t r_t r_tᵀ over its curved triangles
//! (r_t the triangle's least-curved direction, w_t = area × curvature); a ruling is the chord
//! of the region (in the pattern) along d through a sample point — the union of the region's
//! triangles cut by the line, the connected interval that contains the point — and l_r is the
//! mean chord over up to [`MAX_CHORDS`] sample points (the centroids of the region's most
//! curved triangles, evenly strided). A region with no curved triangle uses the chord through
//! its centroid along its longer pattern extent; it is constrained anyway (l_c = 0).
//!
//! **One measurement per region and frame.** A region's resonator depends only on the frame
//! (mesh, curvature, held and touching vertices), not on the event, so the finder keeps each
//! region's measurement until the regions are computed again ([`VibrationRegions::compute`]
//! bumps a generation counter) and every later event of the frame that selects the region
//! reuses it. Measuring costs up to 12 chords, each clipped against every triangle of the
//! region: when a gesture starts, one big region heard by a dozen events in one frame made the
//! sound analysis take 0.6–0.84 ms instead of its usual 0.09 ms (C5 frames 23–31).

use crate::math::{V2, V3};
use crate::sheet::physical::PhysMesh;
use crate::sheet::topology::NONE;
use crate::sound_input::Resonator;

use super::curvature::Curvature;
use super::{AnalysisConfig, AnalysisInput};

/// Chords sampled per resonator for l_r.
pub const MAX_CHORDS: usize = 12;
/// Largest number of candidate regions of one event.
pub const MAX_CANDIDATES: usize = 64;
/// Largest number of resonators one event can produce.
pub const MAX_SELECTED: usize = 8;

/// Source of [`VibrationRegions`] generations (0 = never computed).
static NEXT_GENERATION: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

/// The frame's partition of S_P triangles into vibration regions.
#[derive(Clone, Debug, Default)]
pub struct VibrationRegions {
    region: Vec<u32>,
    area: Vec<f64>,
    stack: Vec<u32>,
    /// Region triangles grouped by region (CSR).
    members: Vec<u32>,
    offsets: Vec<u32>,
    cursor: Vec<u32>,
    /// New at every [`Self::compute`] (unique in the process, so that no two partitions share
    /// one): measurements of another generation are stale.
    generation: u64,
}

impl VibrationRegions {
    /// Buffers for up to `max_triangles` triangles.
    pub fn with_capacity(max_triangles: usize) -> Self {
        Self {
            region: Vec::with_capacity(max_triangles),
            area: Vec::with_capacity(max_triangles),
            stack: Vec::with_capacity(max_triangles),
            members: Vec::with_capacity(max_triangles),
            offsets: Vec::with_capacity(max_triangles + 1),
            cursor: Vec::with_capacity(max_triangles),
            generation: 0,
        }
    }

    /// True if vibrations do not cross edge `e` (the sheet boundary is handled by topology).
    pub fn is_border(
        sp: &PhysMesh,
        curv: &Curvature,
        contacts: &[crate::collision::VertexContact],
        held: &[bool],
        ridge_rad: f64,
        e: usize,
    ) -> bool {
        let ed = &sp.topo.edges[e];
        let [a, b] = ed.v.map(|v| v as usize);
        let held_at = |v: usize| held.get(v).copied().unwrap_or(false);
        let touching = |v: usize| contacts.get(v).is_some_and(|c| c.in_contact);
        curv.edge_angle_rad[e].abs() > ridge_rad
            || held_at(a)
            || held_at(b)
            || (touching(a) && touching(b))
    }

    /// Computes the partition.
    pub fn compute(
        &mut self,
        sp: &PhysMesh,
        curv: &Curvature,
        contacts: &[crate::collision::VertexContact],
        held: &[bool],
        ridge_rad: f64,
    ) {
        let topo = &sp.topo;
        let nt = sp.num_triangles();
        self.generation = NEXT_GENERATION.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.region.clear();
        self.region.resize(nt, NONE);
        self.area.clear();
        let mut next = 0u32;
        for seed in 0..nt {
            if self.region[seed] != NONE {
                continue;
            }
            let id = next;
            next += 1;
            self.area.push(0.0);
            self.region[seed] = id;
            self.stack.clear();
            self.stack.push(seed as u32);
            while let Some(t) = self.stack.pop() {
                let t = t as usize;
                self.area[id as usize] += curv.tri_area_m2[t];
                for k in 0..3 {
                    let h = 3 * t + k;
                    let twin = topo.half_edges[h].twin;
                    if twin == NONE {
                        continue;
                    }
                    let n = topo.half_edges[twin as usize].face as usize;
                    if self.region[n] != NONE {
                        continue;
                    }
                    let e = topo.he_edge[h] as usize;
                    if Self::is_border(sp, curv, contacts, held, ridge_rad, e) {
                        continue;
                    }
                    self.region[n] = id;
                    self.stack.push(n as u32);
                }
            }
        }
        // Members grouped by region (counting sort, deterministic order).
        let nr = next as usize;
        self.offsets.clear();
        self.offsets.resize(nr + 1, 0);
        for &r in &self.region {
            self.offsets[r as usize + 1] += 1;
        }
        for r in 0..nr {
            self.offsets[r + 1] += self.offsets[r];
        }
        self.cursor.clear();
        self.cursor.extend_from_slice(&self.offsets[..nr]);
        self.members.clear();
        self.members.resize(nt, 0);
        for (t, &r) in self.region.iter().enumerate() {
            let c = &mut self.cursor[r as usize];
            self.members[*c as usize] = t as u32;
            *c += 1;
        }
    }

    /// Number of regions.
    pub fn num_regions(&self) -> usize {
        self.area.len()
    }

    /// Region of triangle `t`.
    pub fn region_of(&self, t: u32) -> u32 {
        self.region.get(t as usize).copied().unwrap_or(NONE)
    }

    /// Pattern area of region `r`, m².
    pub fn area_m2(&self, r: u32) -> f64 {
        self.area[r as usize]
    }

    /// Triangles of region `r`.
    pub fn triangles(&self, r: u32) -> &[u32] {
        let r = r as usize;
        &self.members[self.offsets[r] as usize..self.offsets[r + 1] as usize]
    }
}

/// Picks an event's resonators and measures them.
#[derive(Clone, Debug)]
pub struct ResonatorFinder {
    candidates: Vec<u32>,
    selected: [Resonator; MAX_SELECTED],
    num_selected: usize,
    intervals: Vec<(f64, f64)>,
    samples: Vec<(f64, u32)>,
    /// Per region of the regions' generation `measured_generation`: its resonator, once
    /// measured (module doc, "One measurement per region and frame").
    measured: Vec<Option<Resonator>>,
    measured_generation: u64,
}

impl ResonatorFinder {
    /// Buffers for up to `max_triangles` triangles per region.
    pub fn with_capacity(max_triangles: usize) -> Self {
        Self {
            candidates: Vec::with_capacity(MAX_CANDIDATES),
            selected: [Resonator::default(); MAX_SELECTED],
            num_selected: 0,
            intervals: Vec::with_capacity(max_triangles),
            samples: Vec::with_capacity(max_triangles),
            // A region holds at least one triangle.
            measured: Vec::with_capacity(max_triangles),
            measured_generation: 0,
        }
    }

    /// Starts a new event.
    pub fn begin(&mut self) {
        self.candidates.clear();
        self.num_selected = 0;
    }

    /// Adds a region the event touches (duplicates and `NONE` are ignored).
    pub fn add_region(&mut self, r: u32) {
        if r != NONE && !self.candidates.contains(&r) && self.candidates.len() < MAX_CANDIDATES {
            self.candidates.push(r);
        }
    }

    /// Number of candidate regions so far.
    pub fn num_candidates(&self) -> usize {
        self.candidates.len()
    }

    /// Keeps the `max` largest candidates (by area; ties by region id), measures them and
    /// returns how many resonators are ready.
    pub fn select(
        &mut self,
        sp: &PhysMesh,
        curv: &Curvature,
        regions: &VibrationRegions,
        input: &AnalysisInput<'_>,
        cfg: &AnalysisConfig,
        max: usize,
    ) -> usize {
        self.candidates.sort_unstable_by(|a, b| {
            regions
                .area_m2(*b)
                .total_cmp(&regions.area_m2(*a))
                .then(a.cmp(b))
        });
        let n = self.candidates.len().min(max).min(MAX_SELECTED);
        if self.measured_generation != regions.generation {
            self.measured_generation = regions.generation;
            self.measured.clear();
        }
        // Within capacity: the regions never outnumber the triangles the buffers were sized for.
        let cacheable = regions.num_regions() <= self.measured.capacity();
        if cacheable && self.measured.len() < regions.num_regions() {
            self.measured.resize(regions.num_regions(), None);
        }
        for k in 0..n {
            let r = self.candidates[k];
            let cached = if cacheable {
                self.measured[r as usize]
            } else {
                None
            };
            self.selected[k] = match cached {
                Some(res) => res,
                None => {
                    let res = self.measure(sp, curv, regions.triangles(r), input, cfg);
                    if cacheable {
                        self.measured[r as usize] = Some(res);
                    }
                    res
                }
            };
        }
        self.num_selected = n;
        n
    }

    /// Resonator `k` of the last [`Self::select`] or [`Self::measure_into`].
    pub fn resonator(&self, k: usize) -> Resonator {
        self.selected[k]
    }

    /// Measures an explicit triangle set as the only resonator (used for contact regions that
    /// are entirely pressed on an obstacle).
    pub fn measure_into(
        &mut self,
        sp: &PhysMesh,
        curv: &Curvature,
        tris: &[u32],
        input: &AnalysisInput<'_>,
        cfg: &AnalysisConfig,
    ) {
        self.selected[0] = self.measure(sp, curv, tris, input, cfg);
        self.num_selected = 1;
    }

    /// l_r, l_c and the disk of a set of triangles.
    pub fn measure(
        &mut self,
        sp: &PhysMesh,
        curv: &Curvature,
        tris: &[u32],
        input: &AnalysisInput<'_>,
        cfg: &AnalysisConfig,
    ) -> Resonator {
        let topo = &sp.topo;
        let held_at = |v: u32| input.held.get(v as usize).copied().unwrap_or(false);
        let touching = |v: u32| input.contacts.get(v as usize).is_some_and(|c| c.in_contact);
        let mut area = 0.0;
        let mut centre = V3::zeros();
        let mut normal = V3::zeros();
        let mut centre2 = V2::zeros();
        let mut lc = 0.0;
        let mut tensor = [0.0f64; 3];
        let (mut minp, mut maxp) = (V2::repeat(f64::MAX), V2::repeat(f64::MIN));
        self.samples.clear();
        for &t in tris {
            let t = t as usize;
            let a = curv.tri_area_m2[t];
            let tri = sp.triangles[t];
            let c3 =
                (sp.pos[tri[0] as usize] + sp.pos[tri[1] as usize] + sp.pos[tri[2] as usize]) / 3.0;
            let c2 = (sp.pattern[tri[0] as usize]
                + sp.pattern[tri[1] as usize]
                + sp.pattern[tri[2] as usize])
                / 3.0;
            for &v in &tri {
                let p = sp.pattern[v as usize];
                minp = minp.inf(&p);
                maxp = maxp.sup(&p);
            }
            area += a;
            centre += c3 * a;
            centre2 += c2 * a;
            normal += Curvature::unit_normal(sp, t) * a;
            let curved = curv.tri_max_angle_rad[t] > cfg.flat_angle_rad;
            if curved {
                let w = a * curv.tri_kappa_per_m[t];
                let r = curv.tri_ruling[t];
                tensor[0] += w * r.x * r.x;
                tensor[1] += w * r.x * r.y;
                tensor[2] += w * r.y * r.y;
                self.samples.push((curv.tri_kappa_per_m[t], t as u32));
                for k in 0..3 {
                    let h = 3 * t + k;
                    if topo.half_edges[h].twin != NONE {
                        continue;
                    }
                    let v0 = topo.half_edges[h].origin;
                    let v1 = topo.dest(h as u32);
                    if held_at(v0) || held_at(v1) || touching(v0) || touching(v1) {
                        continue;
                    }
                    // Only the part of the border that crosses the rulings bends: an
                    // edge along the ruling is straight (weight |sin| of the angle).
                    let d = sp.pattern[v1 as usize] - sp.pattern[v0 as usize];
                    let across = d.perp(&curv.tri_ruling[t]).abs();
                    lc += across;
                }
            }
        }
        if area <= 0.0 {
            return Resonator::default();
        }
        centre /= area;
        centre2 /= area;
        let nn = normal.norm();
        let normal = if nn > 1e-12 {
            normal / nn
        } else {
            V3::new(0.0, 0.0, 1.0)
        };
        // Dominant ruling direction.
        let dir = principal(tensor).unwrap_or_else(|| {
            let ext = maxp - minp;
            if ext.x >= ext.y {
                V2::new(1.0, 0.0)
            } else {
                V2::new(0.0, 1.0)
            }
        });
        // Chords through the most curved triangles (evenly strided), or the centroid.
        let mut lr_sum = 0.0;
        let mut lr_n = 0usize;
        if self.samples.is_empty() {
            lr_sum += self.chord(sp, tris, centre2, dir);
            lr_n += 1;
        } else {
            self.samples
                .sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
            let ns = self.samples.len();
            let take = ns.min(MAX_CHORDS);
            for k in 0..take {
                let t = self.samples[k * ns / take].1 as usize;
                let tri = sp.triangles[t];
                let c2 = (sp.pattern[tri[0] as usize]
                    + sp.pattern[tri[1] as usize]
                    + sp.pattern[tri[2] as usize])
                    / 3.0;
                lr_sum += self.chord(sp, tris, c2, dir);
                lr_n += 1;
            }
        }
        let lr = lr_sum / lr_n as f64;
        Resonator {
            lr_cm: (lr * 100.0) as f32,
            lc_cm: (lc * 100.0) as f32,
            centre_m: [centre.x as f32, centre.y as f32, centre.z as f32],
            normal: [normal.x as f32, normal.y as f32, normal.z as f32],
            radius_m: (area / std::f64::consts::PI).sqrt() as f32,
        }
    }

    /// Length of the connected chord of the triangle set along `d` through `p` (pattern).
    fn chord(&mut self, sp: &PhysMesh, tris: &[u32], p: V2, d: V2) -> f64 {
        self.intervals.clear();
        for &t in tris {
            let tri = sp.triangles[t as usize];
            let v = tri.map(|i| sp.pattern[i as usize]);
            if let Some(iv) = clip_line_triangle(p, d, v) {
                self.intervals.push(iv);
            }
        }
        if self.intervals.is_empty() {
            return 0.0;
        }
        self.intervals
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        // Merge into connected runs; keep the run containing t = 0 (or the nearest one).
        const GAP: f64 = 1e-7;
        let mut best = (f64::MAX, 0.0);
        let (mut lo, mut hi) = self.intervals[0];
        let mut consider = |lo: f64, hi: f64| {
            let dist = if lo <= 0.0 && hi >= 0.0 {
                0.0
            } else {
                lo.abs().min(hi.abs())
            };
            if dist < best.0 {
                best = (dist, hi - lo);
            }
        };
        for &(a, b) in &self.intervals[1..] {
            if a <= hi + GAP {
                hi = hi.max(b);
            } else {
                consider(lo, hi);
                lo = a;
                hi = b;
            }
        }
        consider(lo, hi);
        best.1
    }
}

/// The parameter interval of the line p + t·d inside triangle `v` (2D), if any.
fn clip_line_triangle(p: V2, d: V2, v: [V2; 3]) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (f64::MIN, f64::MAX);
    let orient = (v[1] - v[0]).perp(&(v[2] - v[0])).signum();
    if orient == 0.0 {
        return None;
    }
    for k in 0..3 {
        let a = v[k];
        let b = v[(k + 1) % 3];
        // Inside: orient · (b − a) × (x − a) ≥ 0.
        let e = b - a;
        let f0 = orient * e.perp(&(p - a));
        let fd = orient * e.perp(&d);
        if fd.abs() < 1e-15 {
            if f0 < 0.0 {
                return None;
            }
            continue;
        }
        let t = -f0 / fd;
        if fd > 0.0 {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
    }
    (t0 <= t1 && t0.is_finite() && t1.is_finite()).then_some((t0, t1))
}

/// Principal eigenvector of the symmetric `[xx, xy; xy, yy]`, if the matrix is not zero.
fn principal(s: [f64; 3]) -> Option<V2> {
    let (a, b, c) = (s[0], s[1], s[2]);
    let norm = a.abs() + b.abs() + c.abs();
    if norm.is_nan() || norm <= 0.0 {
        return None;
    }
    let mean = 0.5 * (a + c);
    let r = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let l = mean + r;
    let v1 = V2::new(b, l - a);
    let v2 = V2::new(l - c, b);
    let v = if v1.norm_squared() >= v2.norm_squared() {
        v1
    } else {
        v2
    };
    let n = v.norm();
    (n > 1e-300 && n.is_finite()).then(|| v / n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clip_through_unit_triangle() {
        let tri = [V2::new(0.0, 0.0), V2::new(1.0, 0.0), V2::new(0.0, 1.0)];
        let (a, b) = clip_line_triangle(V2::new(0.25, 0.25), V2::new(1.0, 0.0), tri).unwrap();
        assert!(
            (a + 0.25).abs() < 1e-12 && (b - 0.5).abs() < 1e-12,
            "{a} {b}"
        );
        assert!(clip_line_triangle(V2::new(2.0, 2.0), V2::new(1.0, 0.0), tri).is_none());
    }

    #[test]
    fn principal_direction() {
        let d = principal([0.0, 0.0, 2.0]).unwrap();
        assert!(d.y.abs() > 0.999);
        assert!(principal([0.0; 3]).is_none());
    }
}
