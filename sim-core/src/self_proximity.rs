//! # Self-proximity: how close the sheet comes to itself
//!
//! The seeds had no sheet–sheet contact and capped their crumpling before the sheet could pass
//! through itself (T 1245, T 2014, T 2076; digest-tearing §4.3). Ours
//! ([`crate::physics::sheet_contact`]) holds layers apart that come within 1.5 mm, but fast
//! folds can still tunnel through a coarse mesh within a frame, so the squeeze stays capped
//! where the sheet comes close to itself. A fixed cap on the squeeze does not do that here
//! (point hands buckle the sheet into folds that cross; docs/decisions.md, "The crumple cap
//! follows the sheet; the squeeze stops at 1 mm"), so the gesture rig caps the squeeze where
//! the sheet *actually* comes close to itself: this module measures that closest approach each
//! frame while the crumple hands squeeze.
//!
//! **Measure.** The smallest 3D distance between two triangles of S_P that share no vertex
//! (triangles that share one touch by construction); 0 if two of them intersect. A folded
//! layer can only reach another part of the sheet through such a pair, so the measure falls
//! towards 0 before any pass-through — provided it is sampled faster than layers approach
//! (the rig slows the squeeze from 2 cm on; a fold snapping through faster than that is left to
//! the sim's pass-through guard).
//!
//! **Refined meshes.** On the lattice S_P starts as, two triangles that share no vertex lie
//! at least ≈ 0.87 of the lattice spacing apart in the pattern (a triangle's height). A vertex
//! inserted at a singular point's drawn position ([`crate::sheet::refine`]) makes triangles
//! around it that share no vertex with triangles a fraction of an edge away — one patch of the
//! paper, which would read as two layers already touching and stop the squeeze at once. So
//! pairs closer than 3/4 of the lattice spacing in the pattern are not measured
//! ([`SelfProximity::set_min_pattern_gap_m`]); on the lattice itself no pair is that close
//! (tested), so nothing changes there. The crossing test ([`SelfProximity::any_crossing`])
//! still checks every vertex-disjoint pair: two triangles of one patch that cross are a
//! pass-through all the same (a sharp fold next to an inserted vertex can cross itself —
//! seen in `tests/self_contact.rs`, 0.04 mm deep, when the crossing test skipped them too).
//!
//! **Algorithm.** Broad phase: sort and sweep of the triangles' axis-aligned boxes along x;
//! pairs whose boxes are farther apart than the query reach are not measured, nor are pairs
//! whose box gap (a lower bound of their distance) is no smaller than the closest distance
//! found so far — the last query's closest pair is measured first, so that bound is usually
//! tight from the start (the result is the same minimum in any order). The closest distance so
//! far also narrows the sweep's window (pairs whose boxes are farther apart could only be
//! pruned) and bounds the narrow phase: of a pair's 15 feature pairs, those whose boxes lie
//! farther apart than it are not measured, nor those whose point lies farther from the other's
//! plane or whose edges' lines lie farther apart, nor pairs lying apart along the line through
//! their centroids (side by side, where neither lies wholly on one side of the other's plane)
//! ([`crate::triangle_distance::triangle_distance_below_m`]); the margin keeps every answer the
//! same (all 12 seed scenes bit-identical). The pattern-gap filter answers from the two
//! triangles' pattern boxes when those are clearly farther apart than the gap, and measures
//! only the pairs left; its answer for a pair is kept until the pattern or the triangles change
//! (at mesh events, or where a hand moves a pattern vertex), so each pair's pattern gap is
//! measured once per mesh, not once per frame. The sweep reads the boxes in sweep order from
//! one array and rejects a pair apart by more than the reach along y or z before it computes
//! the gap's norm; the crossing test computes each vertex's side of the other triangle's plane
//! once and stops when a triangle lies wholly on one side
//! ([`crate::triangle_distance::triangles_intersect`]). Each of these prunings gives the same
//! answers and saves time (docs/benchmarks.md, "Self-contact query: the last closest pair
//! first", "Contact queries" and "Query figures moved from the module docs").
//! Narrow phase: the exact triangle distance of [`crate::triangle_distance`] (15
//! closest-feature pairs, or 0 if an edge crosses), not parry3d's GJK, whose absolute
//! tolerances reported layers 7 mm apart as crossing. On a sheet that is nowhere folded over,
//! only near neighbours survive the broad phase. All buffers are kept between calls: the
//! steady state does not allocate.

use std::cell::Cell;

use crate::math::{V2, V3};
use crate::sheet::physical::PhysMesh;
use crate::triangle_distance::{
    centroid_axis_separation_m, plane_separation_m, triangle_distance_below_m, triangles_intersect,
};

/// Box gaps this far beyond the best distance so far still get measured, metres.
const PRUNE_MARGIN_M: f64 = 1e-12;

/// Reusable buffers of the closest-approach query.
#[derive(Clone, Debug, Default)]
pub struct SelfProximity {
    /// Per triangle: box min and max.
    boxes: Vec<(V3, V3)>,
    /// Per triangle: pattern box min and max (a quick test before the pattern gap).
    pattern_boxes: Vec<(V2, V2)>,
    /// Triangle indices sorted by their box's lower x.
    order: Vec<u32>,
    /// The boxes in that order (the sweep's inner loop reads them one after the other).
    sorted: Vec<(V3, V3)>,
    /// Pairs closer than this in the pattern are one patch, not two layers (0 = none).
    min_pattern_gap_m: f64,
    /// The closest pair of the last query, measured first in the next one (speed only: the
    /// result is the same minimum whatever pair comes first).
    last_pair: Option<(u32, u32)>,
    /// Per unordered pair of triangles (`a · n + b`, a < b): the pattern-gap filter's answer,
    /// [`PATCH_UNKNOWN`], [`PATCH_ONE`] or [`PATCH_TWO`]. Valid for the pattern, triangles and
    /// gap it was filled on (`patch_pattern`, `patch_triangles`, `patch_gap_m`); empty when
    /// the mesh has more than [`PATCH_MEMO_MAX_TRIANGLES`] triangles.
    patch: Vec<u8>,
    patch_pattern: Vec<V2>,
    patch_triangles: Vec<[u32; 3]>,
    patch_gap_m: f64,
}

/// Largest mesh whose pattern-gap answers are kept ([`SelfProximity`]`::patch`: one byte per
/// pair of triangles, 1 MiB at this size).
const PATCH_MEMO_MAX_TRIANGLES: usize = 1024;
/// Pair not asked yet.
const PATCH_UNKNOWN: u8 = 0;
/// Pair closer than the gap in the pattern: one patch, not measured.
const PATCH_ONE: u8 = 1;
/// Pair at least the gap apart in the pattern: two layers, measured.
const PATCH_TWO: u8 = 2;

impl SelfProximity {
    /// Empty buffers; they grow to the mesh on the first query.
    pub fn new() -> Self {
        Self::default()
    }

    /// Buffers for meshes of up to `triangles` triangles (no allocation below that).
    pub fn with_capacity(triangles: usize) -> Self {
        Self {
            boxes: Vec::with_capacity(triangles),
            pattern_boxes: Vec::with_capacity(triangles),
            order: Vec::with_capacity(triangles),
            sorted: Vec::with_capacity(triangles),
            min_pattern_gap_m: 0.0,
            last_pair: None,
            patch: Vec::with_capacity(triangles.min(PATCH_MEMO_MAX_TRIANGLES).pow(2)),
            // A triangulated sheet has fewer vertices than triangles.
            patch_pattern: Vec::with_capacity(triangles),
            patch_triangles: Vec::with_capacity(triangles),
            patch_gap_m: 0.0,
        }
    }

    /// Pairs of triangles less than `gap_m` apart in the pattern are not measured (see the
    /// module doc, "Refined meshes").
    pub fn set_min_pattern_gap_m(&mut self, gap_m: f64) {
        self.min_pattern_gap_m = if gap_m.is_finite() {
            gap_m.max(0.0)
        } else {
            0.0
        };
    }

    /// Smallest distance between two vertex-disjoint triangles of `sp`, metres; `f64::INFINITY`
    /// if no such pair is within `reach_m`. 0 if two of them intersect.
    pub fn closest_approach_m(&mut self, sp: &PhysMesh, reach_m: f64) -> f64 {
        let mut best = f64::INFINITY;
        let mut best_pair = None;
        let min_gap_m = self.min_pattern_gap_m;
        let seed = self.last_pair;
        let filtered = min_gap_m > 0.0;
        let nt = sp.triangles.len();
        let mut patch = std::mem::take(&mut self.patch);
        if filtered && nt <= PATCH_MEMO_MAX_TRIANGLES {
            // The filter's answers depend on the pattern, the triangles and the gap only: kept
            // until one of them changes (a mesh event, a pattern vertex moved under a hand).
            let same = patch.len() == nt * nt
                && self.patch_gap_m == min_gap_m
                && self.patch_triangles == sp.triangles
                && self.patch_pattern == sp.pattern;
            if !same {
                patch.clear();
                patch.resize(nt * nt, PATCH_UNKNOWN);
                self.patch_gap_m = min_gap_m;
                self.patch_triangles.clone_from(&sp.triangles);
                self.patch_pattern.clone_from(&sp.pattern);
            }
        } else {
            patch.clear();
        }
        // The sweep skips pairs whose boxes are apart by more than this (the closest distance
        // so far plus the margin): they could not be measured below it.
        let window = Cell::new(f64::INFINITY);
        self.sweep(
            sp,
            reach_m,
            &window,
            seed,
            filtered,
            |gap_m, a, b, pattern_boxes| {
                // The boxes' gap bounds the triangles' distance from below: skip pairs that cannot
                // beat the closest one found so far (the last query's closest pair, measured
                // first, usually sets a tight bound at once). The margin (1 pm, far above f64
                // rounding of millimetre distances) keeps a pair whose box touches its closest
                // points measured, so the minimum is the same whatever pair comes first.
                if gap_m > best + PRUNE_MARGIN_M {
                    return false;
                }
                if filtered {
                    let one_patch = if patch.is_empty() {
                        pattern_closer_than(sp, pattern_boxes, a, b, min_gap_m)
                    } else {
                        let k = a.min(b) as usize * nt + a.max(b) as usize;
                        if patch[k] == PATCH_UNKNOWN {
                            let one = pattern_closer_than(sp, pattern_boxes, a, b, min_gap_m);
                            patch[k] = if one { PATCH_ONE } else { PATCH_TWO };
                        }
                        patch[k] == PATCH_ONE
                    };
                    if one_patch {
                        return false;
                    }
                }
                let (ca, cb) = (corners(sp, a), corners(sp, b));
                // All of one triangle on one side of the other's plane, farther than the best so
                // far: a cheaper lower bound than the box gap.
                if plane_separation_m(ca, cb) > best + PRUNE_MARGIN_M {
                    return false;
                }
                // Side by side: apart along the line through their centroids.
                if centroid_axis_separation_m(ca, cb) > best + PRUNE_MARGIN_M {
                    return false;
                }
                // Pairs of features farther apart than the best so far are not measured.
                let d = triangle_distance_below_m(ca, cb, best + PRUNE_MARGIN_M);
                if d < best {
                    best = d;
                    best_pair = Some((a, b));
                    window.set(best + PRUNE_MARGIN_M);
                }
                false
            },
        );
        self.patch = patch;
        self.last_pair = best_pair;
        if best > reach_m { f64::INFINITY } else { best }
    }

    /// True if two vertex-disjoint triangles of `sp` intersect (an edge of one crosses the
    /// other: [`crate::triangle_distance::triangles_intersect`]). Every such pair is tested, however
    /// close in the pattern. Stops at the first such pair.
    pub fn any_crossing(&mut self, sp: &PhysMesh) -> bool {
        let window = Cell::new(f64::INFINITY);
        self.sweep(sp, 0.0, &window, None, false, |_, a, b, _| {
            triangles_intersect(corners(sp, a), corners(sp, b))
        })
    }

    /// Calls `found(a, b)` for every pair of vertex-disjoint triangles of `sp` that intersect.
    pub fn for_each_crossing(&mut self, sp: &PhysMesh, mut found: impl FnMut(u32, u32)) {
        let window = Cell::new(f64::INFINITY);
        self.sweep(sp, 0.0, &window, None, false, |_, a, b, _| {
            if triangles_intersect(corners(sp, a), corners(sp, b)) {
                found(a, b);
            }
            false
        });
    }

    /// Broad phase: calls `visit(gap, a, b, centre, pattern_boxes)` for every vertex-disjoint
    /// pair of triangles `a`, `b` whose boxes are less than `reach_m` apart (`gap`, metres: the
    /// distance between the two boxes, a lower bound of the triangles' distance; `centre`: the
    /// mesh centroid the narrow phase measures from; `pattern_boxes`: the triangles' pattern
    /// boxes, filled only if `pattern` is set, else empty), until it returns true; returns
    /// whether one did. The pair `seed`, if given and still valid, is visited first (and again in
    /// its turn), oriented as the sweep orients it, so the narrow phase sees the same
    /// triangles in the same order.
    fn sweep(
        &mut self,
        sp: &PhysMesh,
        reach_m: f64,
        window: &Cell<f64>,
        seed: Option<(u32, u32)>,
        pattern: bool,
        mut visit: impl FnMut(f64, u32, u32, &[(V2, V2)]) -> bool,
    ) -> bool {
        let nt = sp.triangles.len();
        if nt == 0 || sp.pos.is_empty() {
            return false;
        }
        let reach_m = reach_m.max(0.0);
        self.boxes.clear();
        self.boxes.extend(sp.triangles.iter().map(|t| {
            let [a, b, c] = t.map(|v| sp.pos[v as usize]);
            (a.inf(&b).inf(&c), a.sup(&b).sup(&c))
        }));
        self.pattern_boxes.clear();
        if pattern {
            self.pattern_boxes.extend(sp.triangles.iter().map(|t| {
                let [a, b, c] = t.map(|v| sp.pattern[v as usize]);
                (a.inf(&b).inf(&c), a.sup(&b).sup(&c))
            }));
        }
        self.order.clear();
        self.order.extend(0..nt as u32);
        let boxes = &self.boxes;
        let pattern_boxes = &self.pattern_boxes;
        self.order
            .sort_unstable_by(|&a, &b| boxes[a as usize].0.x.total_cmp(&boxes[b as usize].0.x));
        self.sorted.clear();
        self.sorted
            .extend(self.order.iter().map(|&t| boxes[t as usize]));
        let box_gap_m = |a: u32, b: u32| {
            let ((la, ha), (lb, hb)) = (boxes[a as usize], boxes[b as usize]);
            (lb - ha).sup(&(la - hb)).sup(&V3::zeros()).norm()
        };
        let disjoint = |a: u32, b: u32| {
            let (ta, tb) = (sp.triangles[a as usize], sp.triangles[b as usize]);
            !ta.iter().any(|v| tb.contains(v))
        };
        if let Some((a, b)) = seed
            && a != b
            && (a as usize) < nt
            && (b as usize) < nt
        {
            let pos = |t: u32| self.order.iter().position(|&o| o == t);
            let (a, b) = if pos(a) < pos(b) { (a, b) } else { (b, a) };
            if disjoint(a, b) && visit(box_gap_m(a, b), a, b, pattern_boxes) {
                return true;
            }
        }
        let sorted = &self.sorted;
        for (i, &a) in self.order.iter().enumerate() {
            let (la, ha) = sorted[i];
            for (j, &(lb, hb)) in sorted.iter().enumerate().skip(i + 1) {
                // The visitor may have narrowed the window since the last pair.
                let reach_m = reach_m.min(window.get());
                if lb.x > ha.x + reach_m {
                    break;
                }
                // Boxes apart by more than the reach along y or z are apart by more than the
                // reach (the gap is at least that component): skipped before the gap's norm.
                // Four comparisons without branches: which of them rejects is unpredictable.
                if (lb.y - ha.y > reach_m)
                    | (la.y - hb.y > reach_m)
                    | (lb.z - ha.z > reach_m)
                    | (la.z - hb.z > reach_m)
                {
                    continue;
                }
                // Mesh neighbours (most of the boxes that overlap) before the gap's norm.
                let b = self.order[j];
                if !disjoint(a, b) {
                    continue;
                }
                let gap_m = box_gap_m(a, b);
                if gap_m > reach_m {
                    continue;
                }
                if visit(gap_m, a, b, pattern_boxes) {
                    return true;
                }
            }
        }
        false
    }
}

/// True if triangles `a` and `b` are less than `min_gap_m` apart in the pattern. Pairs whose
/// pattern boxes are clearly farther apart than that are answered from the boxes (a lower
/// bound of the distance), the others measured ([`pattern_gap_m`]).
fn pattern_closer_than(
    sp: &PhysMesh,
    pattern_boxes: &[(V2, V2)],
    a: u32,
    b: u32,
    min_gap_m: f64,
) -> bool {
    let ((la, ha), (lb, hb)) = (pattern_boxes[a as usize], pattern_boxes[b as usize]);
    let box_gap_m = (lb - ha).sup(&(la - hb)).sup(&V2::zeros()).norm();
    // The margin keeps rounding from ever answering differently from the measure.
    if box_gap_m > min_gap_m * (1.0 + 1e-6) {
        return false;
    }
    pattern_gap_m(sp, sp.triangles[a as usize], sp.triangles[b as usize]) < min_gap_m
}

/// Distance between two vertex-disjoint pattern triangles, metres (they do not overlap in a
/// valid pattern, so it is the smallest vertex-to-edge distance).
fn pattern_gap_m(sp: &PhysMesh, ta: [u32; 3], tb: [u32; 3]) -> f64 {
    let (pa, pb) = (
        ta.map(|v| sp.pattern[v as usize]),
        tb.map(|v| sp.pattern[v as usize]),
    );
    let seg = |p: V2, a: V2, b: V2| {
        let ab = b - a;
        let t = ((p - a).dot(&ab) / ab.norm_squared().max(1e-300)).clamp(0.0, 1.0);
        (a + ab * t - p).norm()
    };
    let mut best = f64::INFINITY;
    for (from, to) in [(&pa, &pb), (&pb, &pa)] {
        for &p in from {
            for k in 0..3 {
                best = best.min(seg(p, to[k], to[(k + 1) % 3]));
            }
        }
    }
    best
}

/// The 3D corners of triangle `t`.
#[inline]
fn corners(sp: &PhysMesh, t: u32) -> [V3; 3] {
    sp.triangles[t as usize].map(|v| sp.pos[v as usize])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::SheetSize;
    use crate::sheet::{MeshConfig, Sheet};

    fn flat() -> PhysMesh {
        Sheet::new_flat(SheetSize::Sq10, MeshConfig::default(), 0.0, 0.1).sp
    }

    /// No two vertex-disjoint triangles of any sheet size's lattice are closer in the pattern
    /// than 3/4 of its spacing: the refined-mesh exclusion leaves lattice sheets unchanged.
    #[test]
    fn lattice_triangles_sharing_no_vertex_are_at_least_three_quarters_of_a_spacing_apart() {
        for size in SheetSize::ALL {
            let mesh = MeshConfig::default();
            let sp = Sheet::new_flat(size, mesh, 0.0, 0.1).sp;
            let limit = 0.75 * mesh.spacing_m(size);
            let mut closest = f64::INFINITY;
            for (a, ta) in sp.triangles.iter().enumerate() {
                for tb in &sp.triangles[a + 1..] {
                    if !ta.iter().any(|v| tb.contains(v)) {
                        closest = closest.min(pattern_gap_m(&sp, *ta, *tb));
                    }
                }
            }
            assert!(closest >= limit, "{size:?}: {closest} < {limit}");
        }
    }

    /// A flat sheet is nowhere close to itself within less than a mesh spacing; the closest
    /// vertex-disjoint triangles of the lattice are a triangle height apart.
    #[test]
    fn a_flat_sheet_keeps_its_distance() {
        let sp = flat();
        let mut q = SelfProximity::new();
        assert_eq!(q.closest_approach_m(&sp, 0.005), f64::INFINITY);
        let d = q.closest_approach_m(&sp, 1.0);
        let min_edge = sp
            .edge_rest_len_m
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        let max_edge = sp.edge_rest_len_m.iter().copied().fold(0.0, f64::max);
        assert!(
            d > 0.5 * min_edge && d <= max_edge,
            "{d} vs edges {min_edge}–{max_edge}"
        );
        assert_eq!(d, brute_force_m(&sp));
    }

    /// Brute force over every vertex-disjoint pair (the reference for the broad phase).
    fn brute_force_m(sp: &PhysMesh) -> f64 {
        let mut best = f64::INFINITY;
        for a in 0..sp.triangles.len() {
            for b in a + 1..sp.triangles.len() {
                if sp.triangles[a].iter().any(|v| sp.triangles[b].contains(v)) {
                    continue;
                }
                best = best.min(crate::triangle_distance::triangle_distance_m(
                    corners(sp, a as u32),
                    corners(sp, b as u32),
                ));
            }
        }
        best
    }

    /// A sheet crumpled by the sim (physics only): at
    /// several frames the swept closest approach equals the brute-force minimum over all
    /// pairs whenever that is within reach (the sweep misses no pair), else it is ∞.
    #[test]
    fn the_sweep_finds_the_brute_force_minimum_on_a_crumpled_sheet() {
        use crate::control::{Command, GestureParam};
        use crate::sim::{FrameOutput, Sim, SimConfig};
        let mut cfg = SimConfig {
            size: SheetSize::Sq10,
            ..SimConfig::default()
        };
        cfg.geometry.enabled = false;
        let mut sim = Sim::new(cfg);
        sim.apply(Command::Gesture {
            param: GestureParam::Crumple,
            value: 1.0,
        });
        let mut out = FrameOutput::default();
        let mut q = SelfProximity::new();
        let mut seeded_filtered = SelfProximity::new();
        let mut within = 0;
        for f in 1..=60 {
            sim.step(&mut out);
            if f % 10 == 0 {
                let sp = &sim.sheet().sp;
                let reach_m = 0.02;
                let brute = brute_force_m(sp);
                let swept = q.closest_approach_m(sp, reach_m);
                // `q` measures last query's closest pair first; a fresh query has no such
                // pair, and the answer must not depend on it (also with the pattern filter).
                assert_eq!(SelfProximity::new().closest_approach_m(sp, reach_m), swept);
                let spacing_m = 0.01;
                seeded_filtered.set_min_pattern_gap_m(0.75 * spacing_m);
                let mut fresh_filtered = SelfProximity::new();
                fresh_filtered.set_min_pattern_gap_m(0.75 * spacing_m);
                assert_eq!(
                    fresh_filtered.closest_approach_m(sp, reach_m),
                    seeded_filtered.closest_approach_m(sp, reach_m),
                    "frame {f}"
                );
                if brute <= reach_m {
                    within += 1;
                    // Equal up to rounding: the sweep measures a pair in its sort order, the
                    // brute force in index order, and the exact distance of two triangles can
                    // differ in the last bits with the argument order (seen: 1.1e-16 m).
                    assert!(
                        (swept - brute).abs() <= 1e-12 * brute,
                        "frame {f}: {swept} vs {brute}"
                    );
                } else {
                    assert_eq!(swept, f64::INFINITY, "frame {f}: brute {brute}");
                }
            }
        }
        assert!(
            within > 0,
            "the crumple never came within reach: the test checks nothing"
        );
    }

    /// The pattern-gap answers kept between queries follow the pattern, the triangles and the
    /// gap: after each changes, a kept query answers as a fresh one.
    #[test]
    fn kept_pattern_answers_follow_the_mesh() {
        let mut sp = flat();
        let gap_m = 0.75 * MeshConfig::default().spacing_m(SheetSize::Sq10);
        let fresh = |sp: &PhysMesh, gap_m: f64| {
            let mut q = SelfProximity::new();
            q.set_min_pattern_gap_m(gap_m);
            q.closest_approach_m(sp, 1.0)
        };
        let mut kept = SelfProximity::with_capacity(sp.triangles.len());
        kept.set_min_pattern_gap_m(gap_m);
        let d0 = kept.closest_approach_m(&sp, 1.0);
        assert!(d0.is_finite());
        assert_eq!(d0, fresh(&sp, gap_m));
        // The pattern shrinks to a third (the 3D sheet stays): pairs that were two layers are
        // now one patch, and the closest measured pair lies farther away.
        for p in &mut sp.pattern {
            *p /= 3.0;
        }
        let d1 = kept.closest_approach_m(&sp, 1.0);
        assert_eq!(d1, fresh(&sp, gap_m));
        assert!(d1 > d0, "{d1} vs {d0}");
        // A smaller gap: more pairs measured again.
        kept.set_min_pattern_gap_m(gap_m / 3.0);
        assert_eq!(kept.closest_approach_m(&sp, 1.0), fresh(&sp, gap_m / 3.0));
        // Other triangles: two swapped.
        sp.triangles.swap(0, 7);
        assert_eq!(kept.closest_approach_m(&sp, 1.0), fresh(&sp, gap_m / 3.0));
    }

    /// A triangle moved onto a far part of the sheet and tilted through it: the closest
    /// approach is 0 and `any_crossing` finds it, also among pairs the approach skips as one
    /// patch; the flat sheet has none.
    #[test]
    fn a_triangle_through_the_sheet_is_a_crossing() {
        let mut sp = flat();
        let mut q = SelfProximity::new();
        assert!(!q.any_crossing(&sp));
        // The triangle nearest the centre goes to straddle the sheet 3 cm away.
        let centroid = |sp: &PhysMesh, t: usize| {
            sp.triangles[t]
                .iter()
                .map(|&v| sp.pos[v as usize])
                .sum::<V3>()
                / 3.0
        };
        let t = (0..sp.triangles.len())
            .min_by(|&a, &b| centroid(&sp, a).norm().total_cmp(&centroid(&sp, b).norm()))
            .unwrap();
        let c = V3::new(0.03, 0.0, 0.0);
        let [a, b, d] = sp.triangles[t].map(|v| v as usize);
        sp.pos[a] = c + V3::new(-0.003, -0.003, 0.002);
        sp.pos[b] = c + V3::new(0.004, -0.002, -0.002);
        sp.pos[d] = c + V3::new(-0.001, 0.004, -0.002);
        assert_eq!(q.closest_approach_m(&sp, 0.01), 0.0);
        assert!(q.any_crossing(&sp));
        // With every pair "one patch" (a pattern gap larger than the sheet), the approach is
        // not measured, but the crossing is still found.
        q.set_min_pattern_gap_m(1.0);
        assert_eq!(q.closest_approach_m(&sp, 0.01), f64::INFINITY);
        assert!(q.any_crossing(&sp));
    }
}
