//! # Generalized-cone fitting and segmentation (digest-crumpling §3.7; P 799–901, T 975–1114)
//!
//! Every ruling i of a curved region has a tangent plane that is constant along it; as a point
//! of the Blaschke cylinder it is (n_i, w_i) with |n_i| = 1 and the plane n_i·x + w_i = 0.
//! All tangent planes of a cone pass through its apex a, so the apex is the least-squares
//! solution of (P eq. 2, T eq. 2.3)
//!
//! ```text
//! a* = argmin_a Σ_i (n_i·a + w_i)²   ⇒   (Σ n_i n_iᵀ) a = −Σ w_i n_i
//! ```
//!
//! solved by a symmetric eigen-decomposition of the 3×3 normal matrix N. Eigenvalues below
//! [`RANK_TOL`]·λ_max are dropped (pseudo-inverse): coplanar normals mean a generalized
//! **cylinder** with its apex at infinity (P 933), in the direction of the dropped eigenvector;
//! two rulings are always rank-deficient and give a cylinder-or-line fit with zero error.
//!
//! **Error units** (digest §9 item 6): ε_blaschke is a length (0.5 % of L_paper) while e(a) is
//! a sum of squared distances; we compare the RMS distance √(e/N).
//!
//! **Segmentation** (Algorithms 2–3, T 1026–1101; digest §9 item 13): the closed-interval
//! version of the digest — fit the whole range, drop the end ruling with the larger residual
//! until the RMS error is below ε_blaschke (or two rulings remain), then recurse on the dropped
//! front and back ranges. Consecutive segments never share a ruling; the gap between the last
//! ruling of one and the first of the next is a **gap (junction) cone** whose apex is the
//! crossing point of those two rulings (P 895–901, T 1107), `None` if they are parallel.

use nalgebra::SymmetricEigen;

use crate::math::{M3, V2, V3};

/// Relative eigenvalue threshold below which the normal matrix is rank-deficient.
pub const RANK_TOL: f64 = 1e-6;

/// One ruling as the fit sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RulingPlane {
    /// Unit tangent-plane normal n_i (oriented consistently across the region).
    pub n: V3,
    /// Plane offset w_i = −n_i·m_i (m_i: a point of the ruling), metres.
    pub w: f64,
    /// Pattern endpoints.
    pub a2: V2,
    /// Pattern endpoints.
    pub b2: V2,
    /// 3D endpoints.
    pub a3: V3,
    /// 3D endpoints.
    pub b3: V3,
}

/// Result of one apex fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ApexFit {
    /// Apex in 3D, `None` at infinity (generalized cylinder).
    pub apex3: Option<V3>,
    /// Least-squares point (the apex, or a point of the cylinder's axis line).
    pub point: V3,
    /// RMS plane–apex distance √(e/N), metres.
    pub rms_m: f64,
}

fn residual(r: &RulingPlane, a: &V3) -> f64 {
    r.n.dot(a) + r.w
}

/// Least-squares apex of a set of rulings. `far_m`: an apex farther than this from the
/// rulings' centroid is treated as at infinity.
pub fn fit_apex(r: &[RulingPlane], far_m: f64) -> ApexFit {
    let mut n = M3::zeros();
    let mut rhs = V3::zeros();
    let mut centroid = V3::zeros();
    for q in r {
        n += q.n * q.n.transpose();
        rhs -= q.n * q.w;
        centroid += (q.a3 + q.b3) * 0.5;
    }
    if r.is_empty() {
        return ApexFit {
            apex3: None,
            point: V3::zeros(),
            rms_m: 0.0,
        };
    }
    centroid /= r.len() as f64;
    let eig = SymmetricEigen::new(n);
    let lmax = eig.eigenvalues.max();
    let mut point = V3::zeros();
    let mut deficient = lmax <= 0.0;
    // Solve about the centroid so the dropped directions keep the point near the rulings.
    let rhs_c = rhs - n * centroid;
    for k in 0..3 {
        let l = eig.eigenvalues[k];
        let v = eig.eigenvectors.column(k).into_owned();
        if lmax > 0.0 && l > RANK_TOL * lmax {
            point += v * (v.dot(&rhs_c) / l);
        } else {
            deficient = true;
        }
    }
    point += centroid;
    let mut e = 0.0;
    for q in r {
        e += residual(q, &point).powi(2);
    }
    let mut rms_m = (e / r.len() as f64).sqrt();
    if deficient && lmax > 0.0 {
        // Apex at infinity in direction d (the dropped eigenvector): every tangent plane
        // contains d, so the error is the normals' deviation from ⟂ d, times the mean ruling
        // length (a distance, comparable with ε_blaschke).
        let k = eig.eigenvalues.imin();
        let d = eig.eigenvectors.column(k).into_owned();
        let len = r.iter().map(|q| (q.b3 - q.a3).norm()).sum::<f64>() / r.len() as f64;
        let ang2 = r.iter().map(|q| q.n.dot(&d).powi(2)).sum::<f64>() / r.len() as f64;
        rms_m = ang2.sqrt() * len;
    }
    let far = (point - centroid).norm() > far_m;
    ApexFit {
        apex3: if deficient || far || r.len() < 3 {
            None
        } else {
            Some(point)
        },
        point,
        rms_m,
    }
}

/// One segment of the segmentation: rulings `first..=last` and their fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// First ruling index.
    pub first: usize,
    /// Last ruling index (inclusive).
    pub last: usize,
    /// The fit.
    pub fit: ApexFit,
}

/// Segments `r[i0..=i1]` into cones with RMS error ≤ `eps_m`, calling `emit` in ruling order.
pub fn segment(
    r: &[RulingPlane],
    i0: usize,
    i1: usize,
    eps_m: f64,
    far_m: f64,
    emit: &mut impl FnMut(Segment),
) {
    if i1 < i0 || i1 >= r.len() {
        return;
    }
    let (mut f, mut b) = (i0, i1);
    let mut fit = fit_apex(&r[f..=b], far_m);
    while fit.rms_m > eps_m && b > f + 1 {
        let p = fit.point;
        if residual(&r[f], &p).abs() > residual(&r[b], &p).abs() {
            f += 1;
        } else {
            b -= 1;
        }
        fit = fit_apex(&r[f..=b], far_m);
    }
    if f > i0 {
        segment(r, i0, f - 1, eps_m, far_m, emit);
    }
    emit(Segment {
        first: f,
        last: b,
        fit,
    });
    if b < i1 {
        segment(r, b + 1, i1, eps_m, far_m, emit);
    }
}

/// Pattern position of a fitted apex: the apex projected on the 3D line of the ruling with
/// the smallest residual, carried to 2D by its parameter along that (isometric, straight)
/// ruling (P 871–884, digest §3.7 steps 1–3). `None` for an apex at infinity.
pub fn apex_in_pattern(r: &[RulingPlane], fit: &ApexFit) -> Option<V2> {
    let a = fit.apex3?;
    let best = r
        .iter()
        .min_by(|p, q| residual(p, &a).abs().total_cmp(&residual(q, &a).abs()))?;
    let d = best.b3 - best.a3;
    let d2 = d.norm_squared();
    if d2 <= 0.0 {
        return None;
    }
    let t = (a - best.a3).dot(&d) / d2;
    Some(best.a2 + (best.b2 - best.a2) * t)
}

/// Apex of the gap cone between two rulings: the crossing of their pattern lines and the
/// midpoint of the closest approach of their 3D lines; `None` if (nearly) parallel.
pub fn gap_apex(p: &RulingPlane, q: &RulingPlane) -> Option<(V2, V3)> {
    let (d1, d2) = (p.b2 - p.a2, q.b2 - q.a2);
    let den = d1.perp(&d2);
    if den.abs() <= 1e-9 * d1.norm() * d2.norm() {
        return None;
    }
    let s = (q.a2 - p.a2).perp(&d2) / den;
    let x2 = p.a2 + d1 * s;
    let (e1, e2) = (p.b3 - p.a3, q.b3 - q.a3);
    let w0 = p.a3 - q.a3;
    let (a, b, c) = (e1.dot(&e1), e1.dot(&e2), e2.dot(&e2));
    let (d, e) = (e1.dot(&w0), e2.dot(&w0));
    let den3 = a * c - b * b;
    let x3 = if den3.abs() > 1e-12 * a * c {
        let sc = (b * e - c * d) / den3;
        let tc = (a * e - b * d) / den3;
        ((p.a3 + e1 * sc) + (q.a3 + e2 * tc)) * 0.5
    } else {
        p.a3 + e1 * s
    };
    Some((x2, x3))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rulings of a generalized cone with apex `apex` whose directions follow a curve
    /// `dir(s)` (unit vectors), for the parameters `ss`; each ruling from t = 1 to t = 3 (cm
    /// scale: the apex is outside the segment).
    fn cone_rulings(apex: V3, dir: impl Fn(f64) -> V3, ss: &[f64]) -> Vec<RulingPlane> {
        let mut out = Vec::new();
        let mut prev_n: Option<V3> = None;
        for &s in ss {
            let d = dir(s).normalize();
            let h = 1e-6;
            let dd = (dir(s + h).normalize() - dir(s - h).normalize()) / (2.0 * h);
            let mut n = d.cross(&dd).normalize();
            if let Some(p) = prev_n
                && p.dot(&n) < 0.0
            {
                n = -n;
            }
            prev_n = Some(n);
            let a3 = apex + d * 0.01;
            let b3 = apex + d * 0.03;
            out.push(RulingPlane {
                n,
                w: -n.dot(&a3),
                a2: V2::new(s, 0.0),
                b2: V2::new(s, 1.0),
                a3,
                b3,
            });
        }
        out
    }

    /// Digest §8 test 5, exact cone: apex (1, 2, 3) cm, 8 rulings, 1 segment.
    #[test]
    fn exact_cone_apex_is_recovered() {
        let apex = V3::new(0.01, 0.02, 0.03);
        let ss: Vec<f64> = (0..8).map(|i| 0.15 * i as f64).collect();
        let r = cone_rulings(apex, |s| V3::new(s.cos(), s.sin(), 0.6 + 0.3 * s * s), &ss);
        let fit = fit_apex(&r, 10.0);
        let a = fit.apex3.expect("finite apex");
        assert!(
            (a - apex).norm() < 1e-8,
            "apex error {} m",
            (a - apex).norm()
        );
        let mut segs = Vec::new();
        segment(&r, 0, r.len() - 1, 5e-4, 10.0, &mut |s| segs.push(s));
        assert_eq!(segs.len(), 1);
        assert_eq!((segs[0].first, segs[0].last), (0, 7));
    }

    /// Cylinder: parallel rulings give an apex at infinity and one segment.
    #[test]
    fn cylinder_has_apex_at_infinity() {
        let ss: Vec<f64> = (0..8).map(|i| 0.2 * i as f64).collect();
        let mut r = Vec::new();
        for &s in &ss {
            let base = V3::new(0.05 * s.cos(), 0.05 * s.sin(), 0.0);
            let tangent = V3::new(-s.sin(), s.cos(), 0.0);
            let n = V3::z().cross(&tangent).normalize();
            r.push(RulingPlane {
                n,
                w: -n.dot(&base),
                a2: V2::new(s, 0.0),
                b2: V2::new(s, 1.0),
                a3: base,
                b3: base + V3::z() * 0.1,
            });
        }
        let fit = fit_apex(&r, 10.0);
        assert!(fit.apex3.is_none());
        assert!(fit.rms_m < 1e-9);
        let mut segs = Vec::new();
        segment(&r, 0, r.len() - 1, 5e-4, 10.0, &mut |s| segs.push(s));
        assert_eq!(segs.len(), 1);
    }

    /// Two cones joined: ≥ 2 segments, each within ε_blaschke, and a gap cone at the
    /// crossing of the extremal rulings.
    #[test]
    fn two_cones_give_two_segments_and_a_gap_cone() {
        let a1 = V3::new(0.0, 0.0, 0.0);
        let a2 = V3::new(0.0, 0.05, 0.04);
        let ss1: Vec<f64> = (0..6).map(|i| 0.12 * i as f64).collect();
        let ss2: Vec<f64> = (0..6).map(|i| 1.0 + 0.12 * i as f64).collect();
        let mut r = cone_rulings(a1, |s| V3::new(s.cos(), s.sin(), 0.5), &ss1);
        let mut r2 = cone_rulings(a2, |s| V3::new(s.cos(), s.sin(), 1.5 - 0.4 * s), &ss2);
        // Keep the normal orientation consistent across the join.
        if r2[0].n.dot(&r[5].n) < 0.0 {
            for q in &mut r2 {
                q.n = -q.n;
                q.w = -q.w;
            }
        }
        // Pattern lines that cross between the two groups.
        for (k, q) in r2.iter_mut().enumerate() {
            q.a2 = V2::new(2.0 + k as f64, 0.0);
            q.b2 = V2::new(2.5 + k as f64, 1.0);
        }
        r.extend(r2);
        let eps = 5e-4;
        let mut segs = Vec::new();
        segment(&r, 0, r.len() - 1, eps, 10.0, &mut |s| segs.push(s));
        assert!(segs.len() >= 2, "{} segments", segs.len());
        for s in &segs {
            assert!(s.fit.rms_m <= eps, "segment rms {}", s.fit.rms_m);
        }
        for w in segs.windows(2) {
            assert!(w[0].last < w[1].first);
        }
        // Gap cone between the first two segments.
        let (p, q) = (&r[segs[0].last], &r[segs[1].first]);
        let g = gap_apex(p, q);
        if let Some((x2, _)) = g {
            // On both pattern lines.
            let on = |r: &RulingPlane| (x2 - r.a2).perp(&(r.b2 - r.a2)).abs();
            assert!(on(p) < 1e-9 && on(q) < 1e-9);
        }
        // Segments of at least three rulings inside one cone recover its apex.
        let mut recovered = 0;
        for s in &segs {
            if let Some(a) = s.fit.apex3 {
                if s.last <= 5 && s.last >= s.first + 2 {
                    assert!((a - a1).norm() < 1e-6, "{a:?}");
                    recovered += 1;
                }
                if s.first >= 6 && s.last >= s.first + 2 {
                    assert!((a - a2).norm() < 1e-6, "{a:?}");
                    recovered += 1;
                }
            }
        }
        assert!(recovered >= 1);
    }

    #[test]
    fn apex_maps_to_the_pattern_along_the_best_ruling() {
        let apex = V3::new(0.01, 0.02, 0.03);
        let ss: Vec<f64> = (0..5).map(|i| 0.2 * i as f64).collect();
        let mut r = cone_rulings(apex, |s| V3::new(s.cos(), s.sin(), 0.7), &ss);
        // Isometric pattern: ruling from t = 1 cm to 3 cm away from the apex, apex at 2D origin
        // along each direction (angle-preserving development not needed for one ruling).
        for q in &mut r {
            q.a2 = V2::new(0.01, 0.0);
            q.b2 = V2::new(0.03, 0.0);
        }
        let fit = fit_apex(&r, 10.0);
        let a2 = apex_in_pattern(&r, &fit).unwrap();
        assert!(a2.norm() < 1e-8, "{a2:?}");
    }
}
