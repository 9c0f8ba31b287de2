//! # Closest features between the sheet's triangles and edges
//!
//! The sheet's self-contact queries ([`crate::self_proximity`]: how close the sheet comes to
//! itself, whether it crosses itself; [`crate::physics::sheet_contact`]: which parts push
//! apart) all reduce to three exact primitives:
//!
//! - **point–triangle**: the closest point of a triangle to a point, as barycentric weights
//!   (parry3d's Voronoi-region projection, `Triangle::project_local_point_and_get_location`);
//! - **segment–segment**: the closest points of two segments, as weights on each (parry3d's
//!   `closest_points_segment_segment_with_locations_nD`, Ericson's clamped solution);
//! - **segment crosses triangle**: the signs of four signed volumes (orientation tests, f64).
//!
//! Two triangles that do not intersect are as far apart as the closest of their 6
//! vertex–triangle and 9 edge–edge pairs; two that intersect have an edge of one crossing the
//! other (each end of their intersection segment lies on an edge of one of them).
//!
//! **Why not parry3d's `distance` / `intersection_test` on two `Triangle`s.** In metres, their
//! GJK on two flat shapes answered *distance 0, intersecting* for two triangles of a crumpled sheet whose
//! closest approach is 7 mm (the three vertices of one lie 7–31 mm on the same side of the
//! other's plane; regression test below). The sim's pass-through guard then undid frames that
//! crossed nothing and the crumple cap stopped squeezing at phantom contacts. The primitives
//! above are direct formulas and are checked here against brute-force sampling.
//!
//! parry3d works in f32 with absolute tolerances; every query runs in coordinates relative to
//! one of its points and scaled to unit size (f32 then keeps ~10⁻⁷ of the query's size, and
//! the tolerances act relative to it), and weights come back as f64, from which the closest
//! points and distances are recomputed in f64 on the features.

use parry3d::math::Vector;
use parry3d::query::PointQueryWithLocation;
use parry3d::query::details::closest_points_segment_segment_with_locations_nD;
use parry3d::shape::Triangle;

use crate::math::V3;

/// f32 vector of `(p − origin) · scale` for parry3d.
#[inline]
fn rel(p: V3, origin: V3, scale: f64) -> Vector {
    let d = (p - origin) * scale;
    Vector::new(d.x as f32, d.y as f32, d.z as f32)
}

/// Scale that brings a query to unit size: parry3d's tolerances are absolute (f32 ε on
/// squared lengths), so in metres a 5 cm segment pair less than 20° from parallel was taken
/// for parallel (test below); in units of the query's own size they are relative.
#[inline]
fn unit_scale(lengths: impl IntoIterator<Item = f64>) -> f64 {
    let l = lengths.into_iter().fold(0.0, f64::max);
    if l > 1e-30 { 1.0 / l } else { 1.0 }
}

/// Closest point of triangle `t` to `p`: (distance, barycentric weights of the point on `t`).
pub fn point_triangle(p: V3, t: [V3; 3]) -> (f64, [f64; 3]) {
    let k = unit_scale(t.map(|x| (x - p).norm()));
    let [a, b, c] = t.map(|x| rel(x, p, k));
    let (_, loc) = Triangle::new(a, b, c).project_local_point_and_get_location(Vector::ZERO, false);
    // `solid = false`: never `OnSolid`; a degenerate triangle falls back to its first vertex.
    let w = loc
        .barycentric_coordinates()
        .map_or([1.0, 0.0, 0.0], |w| w.map(f64::from));
    // Weights summing to exactly 1 and the point built from edge vectors: the point lies on
    // the triangle to f64 rounding (f32 weights applied to absolute positions would move it
    // off by ~10⁻⁷ of the coordinates).
    // The f32 weights can sum past 1 (or, with a sliver, dip below 0) by f32 rounding: put back
    // on the simplex, so the point lies on the triangle and the distance never falls below the
    // exact lower bounds the queries prune with (plane, box and axis gaps), which would make a
    // query's minimum depend on the order it meets the pairs.
    let (w1, w2) = (w[1].max(0.0), w[2].max(0.0));
    let (w1, w2) = if w1 + w2 > 1.0 {
        (w1 / (w1 + w2), w2 / (w1 + w2))
    } else {
        (w1, w2)
    };
    let w = [(1.0 - w1 - w2).max(0.0), w1, w2];
    let q = t[0] + (t[1] - t[0]) * w[1] + (t[2] - t[0]) * w[2];
    ((p - q).norm(), w)
}

/// Closest points of segments `a` and `b`: (distance, weights on `a`, weights on `b`).
pub fn segment_segment(a: [V3; 2], b: [V3; 2]) -> (f64, [f64; 2], [f64; 2]) {
    let o = a[0];
    let k = unit_scale([(a[1] - o).norm(), (b[0] - o).norm(), (b[1] - o).norm()]);
    let [a0, a1] = a.map(|x| rel(x, o, k));
    let [b0, b1] = b.map(|x| rel(x, o, k));
    let (la, lb) = closest_points_segment_segment_with_locations_nD((&a0, &a1), (&b0, &b1));
    // Kept on the segments (as the triangle's weights above).
    let (sa, sb) = (
        f64::from(la.barycentric_coordinates()[1]).clamp(0.0, 1.0),
        f64::from(lb.barycentric_coordinates()[1]).clamp(0.0, 1.0),
    );
    let (wa, wb) = ([1.0 - sa, sa], [1.0 - sb, sb]);
    let pa = a[0] + (a[1] - a[0]) * sa;
    let pb = b[0] + (b[1] - b[0]) * sb;
    ((pa - pb).norm(), wa, wb)
}

/// Signed volume (×6) of the tetrahedron (a, b, c, d).
#[inline]
fn orient(a: V3, b: V3, c: V3, d: V3) -> f64 {
    (b - a).cross(&(c - a)).dot(&(d - a))
}

/// True if segment `pq` crosses or touches triangle `t` (a segment lying in the triangle's
/// plane counts as not crossing: the sheet's triangles are never exactly coplanar and
/// overlapping).
pub fn segment_crosses_triangle(p: V3, q: V3, t: [V3; 3]) -> bool {
    let [a, b, c] = t;
    crosses_with_sides(p, q, orient(a, b, c, p), orient(a, b, c, q), t)
}

/// [`segment_crosses_triangle`] with the signed volumes of `p` and `q` about `t`'s plane
/// (`dp`, `dq`) given.
#[inline]
fn crosses_with_sides(p: V3, q: V3, dp: f64, dq: f64, t: [V3; 3]) -> bool {
    if (dp > 0.0 && dq > 0.0) || (dp < 0.0 && dq < 0.0) || (dp == 0.0 && dq == 0.0) {
        return false;
    }
    let [a, b, c] = t;
    // The line pq passes through the triangle iff it turns the same way about its three edges.
    let (s0, s1, s2) = (orient(p, q, a, b), orient(p, q, b, c), orient(p, q, c, a));
    (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0) || (s0 <= 0.0 && s1 <= 0.0 && s2 <= 0.0)
}

/// True if an edge of `q` crosses triangle `t`: [`segment_crosses_triangle`] for the three
/// edges, with each vertex's side of `t`'s plane computed once (the same signed volumes, so
/// the same answers) and no edge tested when all three vertices lie strictly on one side.
fn edges_cross(q: [V3; 3], t: [V3; 3]) -> bool {
    let d = q.map(|x| orient(t[0], t[1], t[2], x));
    if (d[0] > 0.0 && d[1] > 0.0 && d[2] > 0.0) || (d[0] < 0.0 && d[1] < 0.0 && d[2] < 0.0) {
        return false;
    }
    (0..3).any(|k| crosses_with_sides(q[k], q[(k + 1) % 3], d[k], d[(k + 1) % 3], t))
}

/// True if triangles `a` and `b` intersect (an edge of one crosses the other).
pub fn triangles_intersect(a: [V3; 3], b: [V3; 3]) -> bool {
    edges_cross(a, b) || edges_cross(b, a)
}

/// A lower bound of the distance between triangles `a` and `b`, metres: how far all of one
/// lies on one side of the other's plane (0 where neither is wholly on one side). Three dot
/// products per plane: a closest-approach query skips most pairs on it.
pub fn plane_separation_m(a: [V3; 3], b: [V3; 3]) -> f64 {
    let side = |t: [V3; 3], q: [V3; 3]| {
        let n = (t[1] - t[0]).cross(&(t[2] - t[0]));
        let l = n.norm();
        if l <= 0.0 || !l.is_finite() {
            return 0.0;
        }
        let d = q.map(|x| (x - t[0]).dot(&n) / l);
        let (lo, hi) = (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]));
        lo.max(-hi).max(0.0)
    };
    side(a, b).max(side(b, a))
}

/// A lower bound of the distance between triangles `a` and `b`, metres: their gap along the
/// line through their centroids (0 where their projections on it overlap). Six dot products:
/// it separates pairs side by side, where neither lies wholly on one side of the other's
/// plane ([`plane_separation_m`] answers 0).
#[inline]
pub fn centroid_axis_separation_m(a: [V3; 3], b: [V3; 3]) -> f64 {
    let ca = (a[0] + a[1] + a[2]) / 3.0;
    let cb = (b[0] + b[1] + b[2]) / 3.0;
    let Some(u) = (cb - ca).try_normalize(1e-300) else {
        return 0.0;
    };
    let pa = a.map(|x| x.dot(&u));
    let pb = b.map(|x| x.dot(&u));
    let gap = pb[0].min(pb[1]).min(pb[2]) - pa[0].max(pa[1]).max(pa[2]);
    if gap.is_finite() { gap.max(0.0) } else { 0.0 }
}

/// Smallest sine of the angle between the two vectors whose cross product gives a plane's or
/// a common normal's direction in [`point_plane_gap_m`] and [`line_line_gap_m`]. Below it
/// (a sliver triangle, nearly parallel lines) the normal's direction carries more rounding
/// than the callers' margins (10⁻⁹ relative) cover, and the bound answers 0: the pair is
/// measured exactly instead.
const MIN_NORMAL_SINE: f64 = 1e-4;

/// A lower bound of the distance between point `p` and triangle `t`, metres: its distance
/// from the triangle's plane (0 for a sliver or degenerate triangle). A handful of flops
/// against the exact projection of [`point_triangle`]: a pair search rejects most candidates
/// on it.
#[inline(always)]
pub fn point_plane_gap_m(p: V3, t: [V3; 3]) -> f64 {
    plane_of(t).gap_m(p)
}

/// A triangle's plane for [`point_plane_gap_m`]: its corner, its (unnormalized) normal and the
/// product of the two edges' lengths it came from.
#[derive(Clone, Copy)]
struct Plane {
    origin: V3,
    normal: V3,
    scale: f64,
}

impl Plane {
    /// [`point_plane_gap_m`] of `p` against this plane.
    #[inline(always)]
    fn gap_m(&self, p: V3) -> f64 {
        normal_gap_m(self.normal, self.scale, p - self.origin)
    }
}

#[inline(always)]
fn plane_of(t: [V3; 3]) -> Plane {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    Plane {
        origin: t[0],
        normal: e1.cross(&e2),
        scale: e1.norm() * e2.norm(),
    }
}

/// A lower bound of the distance between segments `a` and `b`, metres: the distance between
/// the two lines they lie on, along their common normal (0 for nearly parallel or degenerate
/// segments, where that normal is not well defined). The cheap test before
/// [`segment_segment`].
#[inline(always)]
pub fn line_line_gap_m(a: [V3; 2], b: [V3; 2]) -> f64 {
    let (da, db) = (a[1] - a[0], b[1] - b[0]);
    normal_gap_m(da.cross(&db), da.norm() * db.norm(), b[0] - a[0])
}

/// |d · n| / |n| for a normal `n = u × v` with `scale = |u| |v|`, or 0 where u and v are
/// within [`MIN_NORMAL_SINE`] of parallel (or not finite).
#[inline(always)]
fn normal_gap_m(n: V3, scale: f64, d: V3) -> f64 {
    let l = n.norm();
    if l <= MIN_NORMAL_SINE * scale || !l.is_finite() {
        return 0.0;
    }
    (d.dot(&n) / l).abs()
}

/// Distance between triangles `a` and `b`, metres (0 if they intersect).
pub fn triangle_distance_m(a: [V3; 3], b: [V3; 3]) -> f64 {
    triangle_distance_below_m(a, b, f64::INFINITY)
}

/// [`triangle_distance_m`] wherever that is below `bound_m`; otherwise some distance of at
/// least `bound_m`. A vertex–triangle or edge–edge pair whose bounding boxes, or whose plane or
/// lines ([`point_plane_gap_m`], [`line_line_gap_m`]), lie farther apart than `bound_m` is not
/// measured: its distance is at least that gap, so it cannot be the closest pair of a result
/// below the bound (a caller after the smallest distance passes
/// the smallest so far, with a margin far above rounding).
pub fn triangle_distance_below_m(a: [V3; 3], b: [V3; 3], bound_m: f64) -> f64 {
    if triangles_intersect(a, b) {
        return 0.0;
    }
    let (box_a, box_b) = (bounding_box(&a), bounding_box(&b));
    // A feature pair whose box gap or cheap lower bound (plane or line distance) exceeds the
    // bound is not measured; the relative margin keeps rounding from skipping one the exact
    // measure would put below it.
    let skip = |lower_m: f64| lower_m > bound_m * (1.0 + 1e-9);
    let (plane_a, plane_b) = (plane_of(a), plane_of(b));
    let mut best = f64::INFINITY;
    for k in 0..3 {
        if !skip(box_gap_m((a[k], a[k]), box_b)) && !skip(plane_b.gap_m(a[k])) {
            best = best.min(point_triangle(a[k], b).0);
        }
        if !skip(box_gap_m((b[k], b[k]), box_a)) && !skip(plane_a.gap_m(b[k])) {
            best = best.min(point_triangle(b[k], a).0);
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            let ea = [a[i], a[(i + 1) % 3]];
            let eb = [b[j], b[(j + 1) % 3]];
            if !skip(box_gap_m(bounding_box(&ea), bounding_box(&eb)))
                && !skip(line_line_gap_m(ea, eb))
            {
                best = best.min(segment_segment(ea, eb).0);
            }
        }
    }
    best
}

/// Lower and upper corners of the points' axis-aligned box.
#[inline]
fn bounding_box(p: &[V3]) -> (V3, V3) {
    p.iter()
        .skip(1)
        .fold((p[0], p[0]), |(lo, hi), q| (lo.inf(q), hi.sup(q)))
}

/// Distance between two axis-aligned boxes (0 if they overlap), metres.
#[inline]
fn box_gap_m(a: (V3, V3), b: (V3, V3)) -> f64 {
    (b.0 - a.1).sup(&(a.0 - b.1)).sup(&V3::zeros()).norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg32;

    fn mm(a: [f64; 3]) -> V3 {
        V3::new(a[0], a[1], a[2]) * 1e-3
    }

    #[test]
    fn two_triangles_of_a_crumpled_sheet_seven_millimetres_apart() {
        // S_P triangles [19, 20, 27] and [83, 28, 35] of the full crumple (seed 1, vertex
        // insertion on, frame 229), positions rounded to 0.1 mm. parry3d 0.31's GJK
        // `distance` / `intersection_test` on these answer 0 / intersecting.
        let a = [
            mm([31.3, -55.8, 766.4]),
            mm([64.0, -68.0, 769.8]),
            mm([45.1, -60.3, 797.7]),
        ];
        let b = [
            mm([55.9, -56.8, 796.7]),
            mm([78.1, -48.9, 794.8]),
            mm([51.9, -30.0, 782.7]),
        ];
        assert!(!triangles_intersect(a, b));
        let d = triangle_distance_m(a, b);
        // All of b lies ≥ 7.09 mm on one side of a's plane.
        assert!(d >= 7.0e-3, "{d}");
        assert!(d < 12e-3, "{d}");
    }

    /// A random vector in the cube [0, s)³.
    pub(super) fn rand_v3(rng: &mut Pcg32, s: f64) -> V3 {
        V3::new(
            rng.random::<f64>(),
            rng.random::<f64>(),
            rng.random::<f64>(),
        ) * s
    }

    /// Two random triangles of 5 cm, the second shifted by a random offset up to `off_m`.
    fn random_pair(rng: &mut Pcg32, off_m: f64) -> ([V3; 3], [V3; 3]) {
        let a = [rand_v3(rng, 0.05), rand_v3(rng, 0.05), rand_v3(rng, 0.05)];
        let off = rand_v3(rng, off_m);
        let b = [
            rand_v3(rng, 0.05) + off,
            rand_v3(rng, 0.05) + off,
            rand_v3(rng, 0.05) + off,
        ];
        (a, b)
    }

    /// Brute-force distance by sampling both triangles.
    fn sampled_distance(a: [V3; 3], b: [V3; 3], n: usize) -> f64 {
        let pts = |t: [V3; 3]| {
            let mut v = Vec::new();
            for i in 0..=n {
                for j in 0..=n - i {
                    let (u, w) = (i as f64 / n as f64, j as f64 / n as f64);
                    v.push(t[0] * (1.0 - u - w) + t[1] * u + t[2] * w);
                }
            }
            v
        };
        let (pa, pb) = (pts(a), pts(b));
        pa.iter()
            .flat_map(|p| pb.iter().map(move |q| (p - q).norm()))
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn random_pairs_agree_with_sampling_and_crossing() {
        let mut rng = Pcg32::seed_from_u64(11);
        let (mut crossing, mut apart) = (0, 0);
        for _ in 0..300 {
            let (a, b) = random_pair(&mut rng, 0.03);
            let d = triangle_distance_m(a, b);
            let s = sampled_distance(a, b, 40);
            if triangles_intersect(a, b) {
                crossing += 1;
                assert_eq!(d, 0.0);
                // Sampling comes close to an intersection (≤ a sample spacing × size).
                assert!(s < 3e-3, "sampled {s}");
            } else {
                apart += 1;
                // The exact distance is a lower bound of the sampled one, and close to it.
                assert!(d <= s + 1e-9, "{d} > sampled {s}");
                assert!(s - d < 3e-3, "{d} vs sampled {s}");
            }
        }
        assert!(crossing > 15 && apart > 15, "{crossing} / {apart}");
    }

    /// Below its bound the bounded distance is the distance itself, bit for bit; otherwise it
    /// is never below the bound (and skips measuring, which the count shows).
    #[test]
    fn the_bounded_distance_is_exact_below_its_bound() {
        let mut rng = Pcg32::seed_from_u64(7);
        let mut pruned = 0;
        for _ in 0..500 {
            let (a, b) = random_pair(&mut rng, 0.08);
            let d = triangle_distance_m(a, b);
            for bound in [0.0, 0.3 * d, d * (1.0 + 1e-9), 2.0 * d, 0.01, 0.05] {
                let got = triangle_distance_below_m(a, b, bound);
                if d < bound {
                    assert_eq!(got, d, "bound {bound}");
                } else {
                    assert!(got >= bound, "{got} < bound {bound} (distance {d})");
                    pruned += usize::from(got != d);
                }
            }
        }
        assert!(pruned > 100, "{pruned}");
    }

    /// The centroid-line gap is a lower bound of the distance, and it separates pairs the
    /// plane test cannot (side by side, neither wholly on one side of the other's plane).
    #[test]
    fn the_centroid_line_gap_never_exceeds_the_distance() {
        let mut rng = Pcg32::seed_from_u64(7);
        let (mut positive, mut beyond_planes) = (0, 0);
        for _ in 0..2000 {
            let (a, b) = random_pair(&mut rng, 0.06);
            let (lb, d) = (centroid_axis_separation_m(a, b), triangle_distance_m(a, b));
            assert!(lb <= d * (1.0 + 1e-12) + 1e-15, "{lb} > {d}");
            positive += usize::from(lb > 0.0);
            beyond_planes += usize::from(lb > plane_separation_m(a, b));
        }
        assert!(
            positive > 200 && beyond_planes > 100,
            "{positive} {beyond_planes}"
        );
        // Two triangles side by side in one plane: 2 cm apart along x, no plane gap.
        let a = [
            V3::zeros(),
            V3::new(0.01, 0.0, 0.0),
            V3::new(0.0, 0.01, 0.0),
        ];
        let b = a.map(|v| V3::new(0.03 - v.x, v.y, 0.0));
        assert_eq!(plane_separation_m(a, b), 0.0);
        let g = centroid_axis_separation_m(a, b);
        assert!(g > 0.0 && g <= triangle_distance_m(a, b) + 1e-15, "{g}");
        // Coincident centroids: no direction, no bound.
        assert_eq!(centroid_axis_separation_m(a, a), 0.0);
    }

    #[test]
    fn plane_separation_never_exceeds_the_distance() {
        let mut rng = Pcg32::seed_from_u64(5);
        let mut positive = 0;
        for _ in 0..500 {
            let (a, b) = random_pair(&mut rng, 0.06);
            let (lb, d) = (plane_separation_m(a, b), triangle_distance_m(a, b));
            assert!(lb <= d + 1e-12, "{lb} > {d}");
            positive += usize::from(lb > 0.0);
        }
        assert!(positive > 100, "{positive}");
    }

    #[test]
    fn the_plane_and_line_gaps_never_exceed_the_distance() {
        // Random features at every scale from 1 mm to 1 m, and near-parallel segments.
        let mut rng = Pcg32::seed_from_u64(11);
        let (mut p_used, mut l_used) = (0, 0);
        for i in 0..20_000 {
            let s = 10f64.powf(-3.0 + 3.0 * f64::from(i % 100) / 100.0);
            let off = rand_v3(&mut rng, s);
            let t = [
                rand_v3(&mut rng, s),
                rand_v3(&mut rng, s),
                rand_v3(&mut rng, s),
            ];
            let p = rand_v3(&mut rng, s) + off;
            let (d, _) = point_triangle(p, t);
            let g = point_plane_gap_m(p, t);
            assert!(
                g <= d * (1.0 + 1e-9) + 1e-15,
                "plane gap {g} > distance {d}"
            );
            p_used += usize::from(g > 0.5 * d);
            let a = [rand_v3(&mut rng, s), rand_v3(&mut rng, s)];
            let mut b = [rand_v3(&mut rng, s) + off, rand_v3(&mut rng, s) + off];
            if i % 10 == 0 {
                // Almost parallel to `a`.
                b[1] = b[0] + (a[1] - a[0]) * 0.7 + rand_v3(&mut rng, s * 1e-7);
            }
            let (d, _, _) = segment_segment(a, b);
            let g = line_line_gap_m(a, b);
            assert!(
                g <= d * (1.0 + 1e-6) + 1e-12 * s,
                "line gap {g} > distance {d}"
            );
            l_used += usize::from(g > 0.5 * d);
        }
        // The bounds are not vacuous.
        assert!(p_used > 5_000 && l_used > 2_000, "{p_used} {l_used}");
    }

    /// The closest points lie on the features (weights on the simplex), so a distance is never
    /// below the exact lower bounds the queries prune with: f32 weights that summed past 1 put
    /// the point up to ~10⁻⁸ of an edge outside its triangle, and a closest-approach query then
    /// found a smaller minimum when it met the pairs in another order (a sheet restored from a
    /// save squeezed at another speed: stress seed 1039).
    #[test]
    fn closest_points_lie_on_their_features() {
        let mut rng = Pcg32::seed_from_u64(29);
        let mut on_edge = 0;
        for i in 0..20_000 {
            let s = 10f64.powf(-3.0 + 2.0 * f64::from(i % 100) / 100.0);
            let t = [
                rand_v3(&mut rng, s),
                rand_v3(&mut rng, s),
                rand_v3(&mut rng, s),
            ];
            let p = rand_v3(&mut rng, 2.0 * s);
            let (_, w) = point_triangle(p, t);
            assert!(w.iter().all(|&x| x >= 0.0), "{w:?}");
            assert!(w[1] + w[2] <= 1.0 + 1e-15, "{w:?}");
            on_edge += usize::from(w.contains(&0.0));
            let (a, b) = (
                [rand_v3(&mut rng, s), rand_v3(&mut rng, s)],
                [rand_v3(&mut rng, s), rand_v3(&mut rng, s)],
            );
            let (_, wa, wb) = segment_segment(a, b);
            assert!(wa.iter().chain(&wb).all(|x| (0.0..=1.0).contains(x)));
        }
        assert!(on_edge > 5_000, "{on_edge}");
    }

    #[test]
    fn a_segment_through_a_triangle_crosses_it_and_one_beside_does_not() {
        let t = [V3::zeros(), V3::x(), V3::y()];
        let through = segment_crosses_triangle(V3::new(0.2, 0.2, -1.0), V3::new(0.2, 0.2, 1.0), t);
        let beside = segment_crosses_triangle(V3::new(0.8, 0.8, -1.0), V3::new(0.8, 0.8, 1.0), t);
        let short = segment_crosses_triangle(V3::new(0.2, 0.2, 0.5), V3::new(0.2, 0.2, 1.0), t);
        assert!(through && !beside && !short);
    }

    #[test]
    fn triangles_intersect_answers_as_its_six_edge_tests() {
        // The shared side tests and the early exit must not change an answer, also for
        // triangles sharing a vertex, touching at a vertex or lying in one plane.
        let by_edges = |a: [V3; 3], b: [V3; 3]| {
            (0..3).any(|k| segment_crosses_triangle(a[k], a[(k + 1) % 3], b))
                || (0..3).any(|k| segment_crosses_triangle(b[k], b[(k + 1) % 3], a))
        };
        let mut rng = Pcg32::seed_from_u64(5);
        let (mut yes, mut no) = (0, 0);
        for i in 0..4000 {
            let (a, mut b) = random_pair(&mut rng, 0.02);
            match i % 4 {
                1 => b[0] = a[1],
                2 => b = b.map(|x| V3::new(x.x, x.y, 0.0)),
                3 => b[2] = a[0] + (a[1] - a[0]) * 0.5,
                _ => {}
            }
            let a = if i % 4 == 2 {
                a.map(|x| V3::new(x.x, x.y, 0.0))
            } else {
                a
            };
            let got = triangles_intersect(a, b);
            assert_eq!(got, by_edges(a, b), "pair {i}");
            if got { yes += 1 } else { no += 1 }
        }
        assert!(yes > 100 && no > 100, "{yes} crossing, {no} apart");
    }
}

#[cfg(test)]
mod primitives {
    use super::*;
    use rand::SeedableRng;
    use rand_pcg::Pcg32;

    /// Point–triangle and segment–segment against dense sampling, at centimetre and at
    /// sub-millimetre scale (parry3d's absolute tolerances once mistook near-parallel 5 cm
    /// segments for parallel ones: 20.1 mm answered where 17.4 mm was right).
    #[test]
    fn primitives_are_never_farther_than_sampling_at_any_scale() {
        let mut rng = Pcg32::seed_from_u64(3);
        for size in [0.05, 3e-4] {
            let mut r = |s: f64| super::tests::rand_v3(&mut rng, s);
            for _ in 0..300 {
                let t = [r(size), r(size), r(size)];
                let p = r(1.6 * size);
                let (d, w) = point_triangle(p, t);
                assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
                let n = 60;
                let mut best = f64::INFINITY;
                for i in 0..=n {
                    for j in 0..=n - i {
                        let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                        best = best.min((t[0] * (1.0 - u - v) + t[1] * u + t[2] * v - p).norm());
                    }
                }
                assert!(d <= best + 1e-6 * size, "point {d} > sampled {best}");
                let (a, b) = ([r(size), r(size)], [r(size), r(size)]);
                let (d, _, _) = segment_segment(a, b);
                let n = 200;
                let mut best = f64::INFINITY;
                for i in 0..=n {
                    for j in 0..=n {
                        let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                        let pa = a[0] * (1.0 - u) + a[1] * u;
                        best = best.min((pa - b[0] * (1.0 - v) - b[1] * v).norm());
                    }
                }
                assert!(d <= best + 1e-6 * size, "segments {d} > sampled {best}");
            }
        }
    }
}
