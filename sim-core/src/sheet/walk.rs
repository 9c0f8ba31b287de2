//! # Straight-line walks across S_P in the pattern
//!
//! Imaginary rulings (digest-crumpling §3.3) and the published rulings are straight lines of
//! the 2D pattern S̄. They are traced triangle by triangle: from a point inside a triangle, the
//! line leaves through exactly one edge (the one with the smallest positive ray parameter);
//! the walk continues in the triangle across that edge until the caller stops it or the sheet
//! boundary is reached. Allocation-free.

use crate::math::V2;
use crate::sheet::physical::PhysMesh;
use crate::sheet::topology::NONE;

/// One edge crossing of a walk.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Edge crossed.
    pub edge: u32,
    /// Half-edge crossed (in `from`).
    pub half_edge: u32,
    /// Triangle left.
    pub from: u32,
    /// Triangle entered, [`NONE`] at the sheet boundary.
    pub to: u32,
    /// Pattern crossing point.
    pub point: V2,
    /// Parameter of the crossing point along the half-edge (origin → destination), in [0, 1].
    pub u: f64,
}

/// Walks from `p0` (inside triangle `t0`) along `d`. `visit` is called for every crossing and
/// returns whether to continue (it is called for the boundary crossing too, which always ends
/// the walk). Returns the last crossing, `None` if no exit was found (degenerate input).
pub fn walk(
    sp: &PhysMesh,
    t0: u32,
    p0: V2,
    d: V2,
    max_steps: usize,
    mut visit: impl FnMut(&Crossing) -> bool,
) -> Option<Crossing> {
    let topo = &sp.topo;
    let (mut t, mut p, mut enter) = (t0, p0, NONE);
    let mut last = None;
    for _ in 0..max_steps {
        let tri = sp.triangles[t as usize];
        let mut best: Option<(f64, usize, f64)> = None;
        for k in 0..3 {
            let h = 3 * t + k as u32;
            if h == enter {
                continue;
            }
            let a = sp.pattern[tri[k] as usize];
            let b = sp.pattern[tri[(k + 1) % 3] as usize];
            let e = b - a;
            let den = d.perp(&e);
            if den.abs() <= 1e-300 {
                continue;
            }
            // s = num_s / den > 0 needs num_s of den's sign: an edge behind the point is
            // skipped before either division (the same test, decided by the signs alone).
            let num_s = (a - p).perp(&e);
            if num_s == 0.0 || (num_s > 0.0) != (den > 0.0) {
                continue;
            }
            let u = (a - p).perp(&d) / den;
            if !(-1e-9..=1.0 + 1e-9).contains(&u) {
                continue;
            }
            let s = num_s / den;
            if s > 1e-12 && best.is_none_or(|b| s < b.0) {
                best = Some((s, k, u.clamp(0.0, 1.0)));
            }
        }
        let (s, k, u) = best?;
        let h = 3 * t + k as u32;
        let twin = topo.half_edges[h as usize].twin;
        let to = if twin == NONE {
            NONE
        } else {
            topo.half_edges[twin as usize].face
        };
        let c = Crossing {
            edge: topo.he_edge[h as usize],
            half_edge: h,
            from: t,
            to,
            point: p + d * s,
            u,
        };
        last = Some(c);
        if !visit(&c) || to == NONE {
            break;
        }
        p = c.point;
        t = to;
        enter = twin;
    }
    last
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::pattern::lattice;

    #[test]
    fn a_walk_crosses_the_sheet_to_the_boundary() {
        let sp = PhysMesh::from_pattern(&lattice(0.1, 0.1, 0.011), 0.0, 0.1).unwrap();
        // Start in the triangle containing the centre.
        let t0 = (0..sp.num_triangles() as u32)
            .find(|&t| {
                let [a, b, c] = sp.triangles[t as usize].map(|i| sp.pattern[i as usize]);
                let o = V2::new(1.3e-3, 0.7e-3);
                use crate::sheet::pattern::signed_area as sa;
                sa(a, b, o) >= 0.0 && sa(b, c, o) >= 0.0 && sa(c, a, o) >= 0.0
            })
            .unwrap();
        let d = V2::new(0.6, 0.8);
        let mut n = 0;
        let o = V2::new(1.3e-3, 0.7e-3);
        let end = walk(&sp, t0, o, d, 1000, |c| {
            // Every crossing lies on the line.
            assert!((c.point - o).perp(&d).abs() < 1e-12);
            n += 1;
            true
        })
        .unwrap();
        assert_eq!(end.to, NONE);
        assert!(n > 3);
        // The end point is on the sheet border (|x| or |y| = half size).
        let q = end.point;
        assert!(
            (q.x.abs() - 0.05).abs() < 1e-6 || (q.y.abs() - 0.05).abs() < 0.01,
            "{q:?}"
        );
    }
}
