//! # Ruling realignment and boundary resampling (step 8b of the frame loop)
//!
//! Spec: TOG 2015 §5.3 (`001_44bc28f7c5e9f81f.txt`, P 871–884), thesis §2.5
//! (`000_cb4d91e46ec5927f.txt`, T 1103–1112); digest-crumpling §3.7 steps 1–7, acceptance
//! test 6. After the cone fit ([`super::cone`]) every curved region is a chain of generalized
//! cones and gap cones, but its rulings are still the lines traced along the local ruling
//! direction of the shape operator, which pass only near the fitted apex. This step makes
//! S_G's rulings exactly those of the fitted cones:
//!
//! 1. **Realignment.** For each fitted cone with pattern apex ā (the seeds' ā_proj: the 3D
//!    apex projected on the line of the best-fitting ruling r_j and carried to 2D by its
//!    parameter along r_j, [`super::cone::apex_in_pattern`]), every traced ruling is turned
//!    about the point it was traced through (its anchor) until its 2D line passes through ā,
//!    and is traced again across the region on S_P: new 2D ends where the line leaves the
//!    region, 3D ends on the S_P edges it crosses, new mean curvature and tangent normal. The
//!    end towards the apex stops at ā when the apex lies inside the region (a d-cone's
//!    generators end at its tip, T 977: a region holding a singular vertex is one cone with
//!    that apex). A cone with its apex at infinity (a generalized cylinder) gets rulings
//!    parallel to its mean 2D ruling direction (digest §3.7 step 7; impl. choice: the mean
//!    over the cone's rulings, by doubled angles, rather than r_j's alone).
//! 2. **Boundary resampling.** Walking across the region, wherever two neighbouring rulings'
//!    ends on the region's border are farther apart than 1/ρ_bound (0.83 cm, Table VI), k
//!    rulings are inserted between them so that every gap is ≤ 1/ρ_bound (T 1112). An inserted
//!    ruling belongs to the cone spanning the gap: through its apex ā (a fitted cone, or the
//!    gap cone between two fitted cones, whose apex is the crossing of their extremal
//!    rulings, P 895–901) at the direction interpolated between its neighbours', or, without
//!    an apex, parallel to them. Its line is placed on the chords between the neighbours'
//!    border ends (the seeds place boundary samples evenly) and then traced on S_P like the
//!    realigned rulings, through the point where it crosses the segment between the
//!    neighbours' anchors, so its ends lie on the region's real border and its 3D ends on
//!    S_P (the seeds interpolate them cubically along the 3D border; measured here, chord
//!    ends interpolated that way missed the surface by up to 7 mm where the border turns a
//!    corner, traced ends by 0.15 mm). Where the border turns a corner between two
//!    neighbours, traced ends can come out farther apart than the chords said, and where a
//!    crease cuts into the region its border is ragged: a wider gap stays there (retrying
//!    with more rulings tripled the step's cost, measured). Two rulings next to each other in
//!    the order across the region whose ends are more than [`ADJACENT_GAP_EDGES`] S_P edges
//!    apart do not border the same stretch of border (one ends at a crease, the other runs
//!    on): there is nothing to interpolate between them and that gap is not resampled
//!    (measured in C6: without this rule a frame inserted ~230 rulings, up to 64 per gap, and
//!    the layer's median time tripled). A ruling whose two ends
//!    both lie within 0.1/ρ_bound of its predecessor's (two traced rulings turned onto the
//!    same line) is dropped: the seeds' "add or remove rulings".
//! 3. **Dihedral angles.** A ruling stands for a strip of the region as wide as half the
//!    distance to each neighbour, so its published dihedral is its mean curvature × that
//!    width (the angle between the tangent planes of neighbouring rulings; before resampling,
//!    the S_P edge was the width).
//!
//! **Approximation, said plainly.** The seeds resample S_G's boundary *vertices* and then
//! regenerate S_P from the realigned rulings. S_P keeps its connectivity here (module doc of
//! [`super`]), so realignment and resampling act on S_G's published rulings and cones only:
//! the physics does not see them. Allocation-free: the rebuilt ruling list goes into a
//! preallocated buffer of the same capacity; rulings that would not fit are not inserted.

use super::{GeometryLayer, MAX_WALK, NONE, RHO_BOUND_PER_M, RegionKind, RulingInfo, walk};
use std::ops::Range;

use crate::math::{V2, V3};
use crate::sheet::physical::PhysMesh;

/// Most rulings inserted into one gap (a sparse region of a huge sheet stays bounded).
pub const MAX_INSERTED_PER_GAP: usize = 16;

/// Two neighbouring rulings whose border ends are more than this many S_P edges apart do not
/// border the same stretch of the region's border: the gap between them is not resampled.
pub const ADJACENT_GAP_EDGES: f64 = 3.0;

/// Two rulings whose ends are all closer than this fraction of 1/ρ_bound are one ruling.
pub const DUPLICATE_FRAC: f64 = 0.1;

/// Unit 2D direction of the ruling through `anchor` of a cone with pattern apex `apex`
/// (pointing away from the apex), or `axis` for a cone with its apex at infinity or an
/// anchor on the apex.
pub fn cone_direction(anchor: V2, apex: Option<V2>, axis: V2) -> V2 {
    apex.and_then(|a| (anchor - a).try_normalize(1e-12))
        .unwrap_or(axis)
}

/// Parameter u ∈ [0, 1] along the segment p → q where the line o + s·d crosses it; `None`
/// when the line is parallel to the segment or crosses its extension.
pub fn line_hits_chord(o: V2, d: V2, p: V2, q: V2) -> Option<f64> {
    let e = q - p;
    let den = d.perp(&e);
    if den.abs() <= 1e-12 * d.norm() * e.norm() {
        return None;
    }
    let u = (p - o).perp(&d) / den;
    (-1e-9..=1.0 + 1e-9).contains(&u).then(|| u.clamp(0.0, 1.0))
}

/// Rulings to insert into a border gap of `gap_m` so that no gap exceeds 1/ρ.
pub fn inserts_for_gap(gap_m: f64, rho_per_m: f64) -> usize {
    let k = (gap_m * rho_per_m * (1.0 - 1e-9)).ceil() - 1.0;
    if k.is_finite() && k > 0.0 {
        (k as usize).min(MAX_INSERTED_PER_GAP)
    } else {
        0
    }
}

/// `q`'s ends paired with `p`'s: (end near `p.a`, end near `p.b`) as (2D, 3D).
fn paired_ends(p: &RulingInfo, q: &RulingInfo) -> [(V2, V3); 2] {
    let same = (p.a2 - q.a2).norm() + (p.b2 - q.b2).norm();
    let crossed = (p.a2 - q.b2).norm() + (p.b2 - q.a2).norm();
    if same <= crossed {
        [(q.a2, q.a3), (q.b2, q.b3)]
    } else {
        [(q.b2, q.b3), (q.a2, q.a3)]
    }
}

/// The larger and the mean of the two border gaps between neighbouring rulings.
fn border_gaps(p: &RulingInfo, q: &RulingInfo) -> (f64, f64) {
    let [qa, qb] = paired_ends(p, q);
    let (ga, gb) = ((p.a2 - qa.0).norm(), (p.b2 - qb.0).norm());
    (ga.max(gb), 0.5 * (ga + gb))
}

/// Mean 2D direction of rulings (doubled angles: a line has no sign), oriented like the first.
fn mean_direction(rs: &[RulingInfo]) -> V2 {
    let (mut c2, mut s2) = (0.0, 0.0);
    for r in rs {
        let d = (r.b2 - r.a2).try_normalize(0.0).unwrap_or_else(V2::x);
        c2 += d.x * d.x - d.y * d.y;
        s2 += 2.0 * d.x * d.y;
    }
    let ang = 0.5 * f64::atan2(s2, c2);
    let axis = V2::new(ang.cos(), ang.sin());
    match rs.first() {
        Some(r) if axis.dot(&(r.b2 - r.a2)) < 0.0 => -axis,
        _ => axis,
    }
}

impl GeometryLayer {
    /// Step 8b: realigns every curved region's rulings to its fitted cones and resamples its
    /// border (module doc). Rebuilds `out.rulings`, the regions' ruling ranges and statistics,
    /// and the cones' ruling indices.
    pub(super) fn realign_rulings(&mut self, sp: &PhysMesh) {
        let rho = RHO_BOUND_PER_M;
        self.ruling_next.clear();
        self.ruling_map.clear();
        // The cones were pushed region by region (fit_cones): each region's are one run.
        let mut cones = 0..0;
        for region in 0..self.out.regions.len() {
            let reg = self.out.regions[region];
            let first = reg.first_ruling as usize;
            let end = first + reg.num_rulings as usize;
            let new_first = self.ruling_next.len();
            let all = &self.out.cones;
            cones.start = cones.end;
            while cones.start < all.len() && (all[cones.start].region as usize) < region {
                cones.start += 1;
            }
            cones.end = cones.start;
            while cones.end < all.len() && all[cones.end].region as usize == region {
                cones.end += 1;
            }
            if reg.kind == RegionKind::Curved && end > first {
                self.realign_region(sp, region as u32, cones.clone(), first, end);
            }
            for i in first..end {
                let kept = self.ruling_next.len();
                let r = self.out.rulings[i];
                let duplicate = self.ruling_next[new_first..].last().is_some_and(|p| {
                    let [qa, qb] = paired_ends(p, &r);
                    r.sp_edge == NONE
                        && (p.a2 - qa.0).norm().max((p.b2 - qb.0).norm()) < DUPLICATE_FRAC / rho
                });
                if duplicate || kept >= self.ruling_next.capacity() {
                    self.ruling_map.push(kept.saturating_sub(1) as u32);
                } else {
                    self.ruling_map.push(kept as u32);
                    self.ruling_next.push(r);
                }
                if reg.kind == RegionKind::Curved
                    && i + 1 < end
                    && self.ruling_next.len() > new_first
                {
                    // Room for the originals still to come.
                    let budget = self
                        .ruling_next
                        .capacity()
                        .saturating_sub(self.ruling_next.len() + (end - i - 1));
                    self.resample_gap(sp, region as u32, cones.clone(), i, budget);
                }
            }
            let n = self.ruling_next.len() - new_first;
            let reg = &mut self.out.regions[region];
            reg.first_ruling = new_first as u32;
            reg.num_rulings = n as u32;
            if reg.kind == RegionKind::Curved && n > 0 {
                let w_default = (1.0 / rho).max(self.spacing_m);
                let rs = &mut self.ruling_next[new_first..];
                // Each neighbour gap serves the ruling on either side: measured once.
                let mut before = None;
                for k in 0..n {
                    let after = (k + 1 < n).then(|| border_gaps(&rs[k], &rs[k + 1]).1);
                    let w = match (before, after) {
                        (Some(b), Some(a)) => 0.5 * (a + b),
                        (Some(g), None) | (None, Some(g)) => g,
                        (None, None) => w_default,
                    };
                    rs[k].dihedral_rad = rs[k].curvature_per_m * w;
                    before = after;
                }
                reg.mean_ruling_len_m = rs.iter().map(|r| r.length_m).sum::<f64>() / n as f64;
                reg.max_abs_dihedral_rad =
                    rs.iter().map(|r| r.dihedral_rad.abs()).fold(0.0, f64::max);
            }
        }
        for c in &mut self.out.cones {
            c.first_ruling = self.ruling_map[c.first_ruling as usize];
            c.last_ruling = self.ruling_map[c.last_ruling as usize];
        }
        std::mem::swap(&mut self.out.rulings, &mut self.ruling_next);
    }

    /// Realigns, in place, the traced rulings `first..end` of a curved region to the fitted
    /// (non-gap) cones that hold them.
    fn realign_region(
        &mut self,
        sp: &PhysMesh,
        region: u32,
        cones: Range<usize>,
        first: usize,
        end: usize,
    ) {
        for ci in cones {
            let c = self.out.cones[ci];
            if c.is_gap {
                continue;
            }
            let (lo, hi) = (c.first_ruling as usize, c.last_ruling as usize + 1);
            if lo < first || hi > end {
                continue;
            }
            let axis = mean_direction(&self.out.rulings[lo..hi]);
            let apex = c.apex2.zip(c.apex3);
            for i in lo..hi {
                let r = self.out.rulings[i];
                if r.anchor_tri == NONE {
                    continue;
                }
                let d = cone_direction(r.anchor2, c.apex2, axis);
                let stop = apex.filter(|(a2, _)| (r.anchor2 - a2).norm() > 1e-12);
                self.out.rulings[i] = self.trace_line(sp, region, r.anchor_tri, r.anchor2, d, stop);
            }
        }
    }

    /// Inserts the rulings that close the border gap between the last kept ruling (at the
    /// end of `ruling_next`, region starting at `new_first`) and the original ruling `i + 1`.
    fn resample_gap(
        &mut self,
        sp: &PhysMesh,
        region: u32,
        cones: Range<usize>,
        i: usize,
        budget: usize,
    ) {
        let rho = RHO_BOUND_PER_M;
        let last = self.ruling_next.len() - 1;
        let p = self.ruling_next[last];
        let q = self.out.rulings[i + 1];
        let (gap, _) = border_gaps(&p, &q);
        let k = inserts_for_gap(gap, rho).min(budget);
        // Neighbours in the order across the region whose ends are farther apart than a few
        // S_P edges do not border the same stretch of the region's border (a ragged region):
        // nothing to interpolate between them.
        if k == 0 || gap > ADJACENT_GAP_EDGES * self.spacing_m.max(1.0 / rho) {
            return;
        }
        let [qa, qb] = paired_ends(&p, &q);
        // The cone spanning the gap: a fitted cone holding both, else the gap cone between.
        let cone = self.out.cones[cones].iter().find(|c| {
            if c.is_gap {
                c.first_ruling as usize == i && c.last_ruling as usize == i + 1
            } else {
                (c.first_ruling as usize) <= i && i < c.last_ruling as usize
            }
        });
        let (apex, apex3) = (cone.and_then(|c| c.apex2), cone.and_then(|c| c.apex3));
        let dp = (p.b2 - p.a2).try_normalize(0.0).unwrap_or_else(V2::x);
        // Chord parameters of the j-th of k inserted rulings: through the apex, the ends on
        // the wider side are spaced evenly and the other side follows (where the line
        // crosses its chord); without an apex both sides are spaced evenly.
        let a_wider = (qa.0 - p.a2).norm() >= (qb.0 - p.b2).norm();
        let place = |j: usize, k: usize| -> (f64, f64) {
            let f = j as f64 / (k + 1) as f64;
            let Some(a) = apex else {
                return (f, f);
            };
            let (wide, other) = if a_wider {
                ((p.a2, qa.0), (p.b2, qb.0))
            } else {
                ((p.b2, qb.0), (p.a2, qa.0))
            };
            let t = wide.0 * (1.0 - f) + wide.1 * f;
            let u = (t - a)
                .try_normalize(1e-12)
                .and_then(|d| line_hits_chord(a, d, other.0, other.1))
                .unwrap_or(f);
            if a_wider { (f, u) } else { (u, f) }
        };
        // The fewest rulings that leave no gap wider than 1/ρ on either side. `placed[j - 1]`
        // keeps place(j, k) for the k tried last, so the chosen k's are not placed twice.
        let (len_a, len_b) = ((qa.0 - p.a2).norm(), (qb.0 - p.b2).norm());
        let mut placed = [(0.0, 0.0); MAX_INSERTED_PER_GAP];
        let fits = |k: usize, placed: &mut [(f64, f64)]| {
            let (mut prev_a, mut prev_b) = (0.0, 0.0);
            (1..=k + 1).all(|j| {
                let (ua, ub) = if j > k {
                    (1.0, 1.0)
                } else {
                    placed[j - 1] = place(j, k);
                    placed[j - 1]
                };
                let ok = (ua - prev_a) * len_a <= 1.0 / rho && (ub - prev_b) * len_b <= 1.0 / rho;
                (prev_a, prev_b) = (ua, ub);
                ok
            })
        };
        let mut k = k;
        let k_max = (k + 2).min(MAX_INSERTED_PER_GAP).min(budget);
        let complete = loop {
            if k >= k_max {
                break false;
            }
            if fits(k, &mut placed) {
                break true;
            }
            k += 1;
        };
        if !complete {
            for (j, slot) in placed.iter_mut().enumerate().take(k) {
                *slot = place(j + 1, k);
            }
        }
        for &(ua, ub) in &placed[..k] {
            let a2 = p.a2 * (1.0 - ua) + qa.0 * ua;
            let b2 = p.b2 * (1.0 - ub) + qb.0 * ub;
            // Traced on S_P through the point where its line crosses the segment between
            // the neighbours' anchors (inside the region), a end towards the apex.
            let mut d = (b2 - a2).try_normalize(1e-12).unwrap_or(dp);
            if let Some(a) = apex
                && d.dot(&(a2 - a)) < 0.0
            {
                d = -d;
            }
            let traced = line_hits_chord(a2, d, p.anchor2, q.anchor2)
                .filter(|_| p.anchor_tri != NONE && q.anchor_tri != NONE)
                .and_then(|s| {
                    // Walk from the nearer anchor.
                    let c = p.anchor2 + (q.anchor2 - p.anchor2) * s;
                    let t = if s <= 0.5 {
                        locate(sp, p.anchor_tri, p.anchor2, c)
                    } else {
                        locate(sp, q.anchor_tri, q.anchor2, c)
                    }?;
                    (self.out.tri_region[t as usize] == region).then_some((t, c))
                });
            // A trace cut short (a line along an S_P edge, a crease cutting into the
            // region) is left out: the gap stays wider there.
            let min_len = 0.5 * p.length_m.min(q.length_m);
            let r = traced
                .map(|(t, c)| {
                    let stop = apex.zip(apex3).filter(|(a, _)| (c - a).norm() > 1e-12);
                    // A cylinder's line may run along a lattice edge, which a walk cannot
                    // follow: shift it by a hair (it stays parallel), as the first trace
                    // does.
                    let c = if apex.is_none() {
                        c + super::off_line(d, self.tri_h[t as usize])
                    } else {
                        c
                    };
                    RulingInfo {
                        resampled: true,
                        ..self.trace_line(sp, region, t, c, d, stop)
                    }
                })
                .filter(|r| r.length_m >= min_len);
            let Some(r) = r else {
                continue;
            };
            self.ruling_next.push(r);
        }
    }
}

/// The S_P triangle holding `to`, found by walking the pattern from `from` (inside
/// `from_tri`); `None` if the sheet's border lies between them.
fn locate(sp: &PhysMesh, from_tri: u32, from: V2, to: V2) -> Option<u32> {
    let len = (to - from).norm();
    let Some(dir) = (to - from).try_normalize(1e-15) else {
        return Some(from_tri);
    };
    let (mut tri, mut reached) = (from_tri, false);
    walk::walk(sp, from_tri, from, dir, MAX_WALK, |c| {
        if (c.point - from).dot(&dir) >= len {
            reached = true;
            return false;
        }
        if c.to == NONE {
            return false;
        }
        tri = c.to;
        true
    });
    reached.then_some(tri)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_direction_points_away_from_the_apex_or_along_the_axis() {
        let d = cone_direction(V2::new(1.0, 1.0), Some(V2::new(1.0, -2.0)), V2::x());
        assert!((d - V2::y()).norm() < 1e-15);
        assert_eq!(cone_direction(V2::new(1.0, 1.0), None, V2::x()), V2::x());
        assert_eq!(
            cone_direction(V2::new(1.0, 1.0), Some(V2::new(1.0, 1.0)), V2::x()),
            V2::x()
        );
    }

    #[test]
    fn line_crosses_a_chord_at_its_parameter() {
        let u = line_hits_chord(
            V2::zeros(),
            V2::new(1.0, 1.0),
            V2::new(0.0, 2.0),
            V2::new(4.0, 2.0),
        );
        assert!((u.unwrap() - 0.5).abs() < 1e-15);
        // Parallel, and crossing the extension only.
        assert!(
            line_hits_chord(V2::zeros(), V2::x(), V2::new(0.0, 1.0), V2::new(1.0, 1.0)).is_none()
        );
        assert!(
            line_hits_chord(V2::zeros(), V2::y(), V2::new(1.0, 1.0), V2::new(2.0, 1.0)).is_none()
        );
    }

    #[test]
    fn gaps_get_just_enough_rulings() {
        let rho = RHO_BOUND_PER_M;
        assert_eq!(inserts_for_gap(0.5 / rho, rho), 0);
        assert_eq!(inserts_for_gap(1.0 / rho, rho), 0);
        assert_eq!(inserts_for_gap(1.5 / rho, rho), 1);
        assert_eq!(inserts_for_gap(3.0 / rho, rho), 2);
        assert_eq!(inserts_for_gap(f64::NAN, rho), 0);
        assert_eq!(inserts_for_gap(1e9, rho), MAX_INSERTED_PER_GAP);
        for g in [1.2, 2.7, 5.01, 9.9] {
            let k = inserts_for_gap(g / rho, rho);
            assert!(
                g / (k + 1) as f64 <= 1.0 + 1e-12 && g / k as f64 > 1.0,
                "{g}: {k}"
            );
        }
    }
}
