//! # The torn edge's detail: a directed-noise walk (eq. 3.2)
//!
//! Between the tip's old and new places the torn edge follows the pixels the tear most likely
//! goes through (M:122–138, T:1374–1392, Fig. 3.8):
//!
//! ```text
//! ν_t(q) = (1 − p)·(1 − R(q)) + p·G_t(q)
//! G_t(q) = exp(−d(q)² / 2σ_G²),  d = distance from q to the segment [s_t, s_t+1]
//! ```
//!
//! From the old tip's pixel, the walker steps to the 8-neighbour with the largest ν among those
//! within π/2 of the target and strictly closer to it, until it reaches the target pixel. p
//! blends the fibres' noise (p → 0: rough) with the straight segment (p → 1: smooth). Decisions
//! (digest-tearing §1.6; not in the seeds): σ_G = 0.75 mm; p = 0.2 by default (the digest's 0.5
//! walks within 0.1 mm of the straight line: no millimetre jag); the strict
//! decrease of the squared distance makes the walk end (the printed rule can step back and
//! forth), in fewer steps than the squared distance; ties go to the first neighbour in a fixed
//! order (deterministic).

use crate::math::V2;

use super::fibres::{FibreTexture, Px, centre_of};

/// Width σ_G of the Gaussian around the segment, metres.
pub const SIGMA_G_M: f64 = 0.00075;
/// Default blend p of eq. 3.2: the edge strays 0.4 mm from the straight tear on average
/// (1.7 px at 4 px/mm over the tests' family; the digest's 0.5 gives 0.09 mm, a cut, not a tear).
pub const DEFAULT_BLEND: f64 = 0.2;

/// The 8 neighbours, in the fixed order ties are broken in.
const NEIGHBOURS: [Px; 8] = [
    [1, 0],
    [1, 1],
    [0, 1],
    [-1, 1],
    [-1, 0],
    [-1, -1],
    [0, -1],
    [1, -1],
];

fn d2(a: Px, b: Px) -> i64 {
    let (dx, dy) = (i64::from(a[0] - b[0]), i64::from(a[1] - b[1]));
    dx * dx + dy * dy
}

/// Distance from `q` to the segment [a, b], metres.
fn segment_distance_m(q: V2, a: V2, b: V2) -> f64 {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let t = if l2 > 0.0 {
        ((q - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (q - (a + ab * t)).norm()
}

/// Walks from pixel `from` to pixel `to` over `fibres` with blend `blend` (p of eq. 3.2,
/// clamped to \[0, 1\]), the Gaussian centred on the segment between the pattern points `s0` and
/// `s1` (the tip's old and new places); writes the pixels visited, `from` and `to` included,
/// into `out` (cleared first; no allocation when it has the capacity, at most
/// `d²(from, to) + 1` pixels).
pub fn walk(
    fibres: &FibreTexture,
    from: Px,
    to: Px,
    s0: V2,
    s1: V2,
    blend: f64,
    out: &mut Vec<Px>,
) {
    let p = if blend.is_finite() {
        blend.clamp(0.0, 1.0)
    } else {
        DEFAULT_BLEND
    };
    out.clear();
    out.push(from);
    let mut cur = from;
    while cur != to {
        let here = d2(cur, to);
        let (gx, gy) = (i64::from(to[0] - cur[0]), i64::from(to[1] - cur[1]));
        let mut best: Option<(f64, Px)> = None;
        for n in NEIGHBOURS {
            let q = [cur[0] + n[0], cur[1] + n[1]];
            // Within π/2 of the target, and strictly closer to it.
            if i64::from(n[0]) * gx + i64::from(n[1]) * gy <= 0 || d2(q, to) >= here {
                continue;
            }
            let d = segment_distance_m(centre_of(q), s0, s1);
            let g = (-d * d / (2.0 * SIGMA_G_M * SIGMA_G_M)).exp();
            let nu = (1.0 - p) * (1.0 - fibres.resistance(q)) + p * g;
            if best.is_none_or(|(b, _)| nu > b) {
                best = Some((nu, q));
            }
        }
        // The neighbour along the target's direction always qualifies.
        let Some((_, q)) = best else { break };
        cur = q;
        out.push(cur);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tearing::fibres::px_of;

    /// Mean distance of a walk's pixels from its straight segment, pixels.
    fn roughness_px(path: &[Px], a: Px, b: Px) -> f64 {
        let (a2, b2) = (centre_of(a), centre_of(b));
        path.iter()
            .map(|&q| segment_distance_m(centre_of(q), a2, b2))
            .sum::<f64>()
            / path.len() as f64
            * super::super::fibres::PX_PER_M
    }

    /// A family of seeded tears in every direction (none tuned on).
    fn family() -> impl Iterator<Item = (u32, V2, V2)> {
        (0..24u32).map(|k| {
            let a = f64::from(k) * 0.2618; // 15° apart
            let s0 = V2::new(0.01 * f64::from(k % 5), -0.02 + 0.003 * f64::from(k % 7));
            let len = 0.01 + 0.002 * f64::from(k % 6);
            (k, s0, s0 + V2::new(a.cos(), a.sin()) * len)
        })
    }

    #[test]
    fn every_walk_ends_at_its_target_through_neighbouring_pixels() {
        let mut out = Vec::new();
        for (seed, s0, s1) in family() {
            let fibres = FibreTexture::new(seed);
            for blend in [0.0, 0.3, 0.5, 1.0, f64::NAN] {
                let (from, to) = (px_of(s0), px_of(s1));
                walk(&fibres, from, to, s0, s1, blend, &mut out);
                assert_eq!(out.first(), Some(&from));
                assert_eq!(out.last(), Some(&to), "seed {seed}, p {blend}");
                assert!(out.len() as i64 <= d2(from, to) + 1);
                for w in out.windows(2) {
                    let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
                    assert!(dx.abs() <= 1 && dy.abs() <= 1 && (dx, dy) != (0, 0));
                }
            }
        }
        // A walk to where it starts is the one pixel.
        walk(
            &FibreTexture::new(1),
            [3, 4],
            [3, 4],
            V2::zeros(),
            V2::zeros(),
            0.5,
            &mut out,
        );
        assert_eq!(out, vec![[3, 4]]);
    }

    #[test]
    fn the_walk_roughens_as_the_blend_falls() {
        let mut out = Vec::new();
        let mut mean = |blend: f64| {
            family()
                .map(|(seed, s0, s1)| {
                    let (from, to) = (px_of(s0), px_of(s1));
                    walk(&FibreTexture::new(seed), from, to, s0, s1, blend, &mut out);
                    roughness_px(&out, from, to)
                })
                .sum::<f64>()
                / 24.0
        };
        let (smooth, half, rough) = (mean(1.0), mean(0.5), mean(0.0));
        println!("mean distance from the segment: p 1 {smooth:.2} px, 0.5 {half:.2}, 0 {rough:.2}");
        assert!(
            smooth < 0.6,
            "the Gaussian alone follows the segment: {smooth}"
        );
        assert!(smooth < half && half < rough, "{smooth} < {half} < {rough}");
        assert!(
            rough > 2.0,
            "the fibres alone make a jagged edge: {rough} px"
        );
    }

    #[test]
    fn the_same_seed_walks_the_same_pixels() {
        let (s0, s1) = (V2::new(0.0, 0.0), V2::new(0.02, 0.005));
        let (mut a, mut b) = (Vec::new(), Vec::new());
        walk(
            &FibreTexture::new(3),
            px_of(s0),
            px_of(s1),
            s0,
            s1,
            0.3,
            &mut a,
        );
        walk(
            &FibreTexture::new(3),
            px_of(s0),
            px_of(s1),
            s0,
            s1,
            0.3,
            &mut b,
        );
        assert_eq!(a, b);
        walk(
            &FibreTexture::new(4),
            px_of(s0),
            px_of(s1),
            s0,
            s1,
            0.3,
            &mut b,
        );
        assert_ne!(a, b);
    }
}
