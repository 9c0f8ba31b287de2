//! # The jagged lips: the torn edge's millimetre detail over the mesh's straight cuts
//!
//! The mesh is cut in straight steps a few millimetres to a centimetre long
//! ([`crate::sheet::tear_step`]); the seeds draw the torn edge's detail over such a coarse cut:
//! the same directed-noise walk (eq. 3.2, [`super::walk`]) runs along every new boundary
//! segment, and two textures, each transparent on one side of the walk, show the jag (thesis
//! T:1577–1586, `../shared/seeds/000_cb4d91e46ec5927f.txt` §3.2; digest-tearing §1.8). Here
//! every lip edge (a boundary edge not on the sheet's outer rectangle) carries the walk between
//! its two ends as a polyline in pattern space; the snapshot maps it into 3D through the lip's
//! triangle (barycentric coordinates, extrapolated a fraction of a millimetre past the edge), and
//! the editor draws it instead of the straight edge.
//!
//! Decisions, one line each:
//! - **One walk per pattern edge**: the two lips of a cut have the same pattern positions; the
//!   walk always runs from the end with the smaller pixel, so both lips get the same jag (their
//!   teeth fit, as a real tear's do).
//! - **Pinned every [`LIP_PIECE_M`]** (4 mm): a lip edge is 0.5–2.5 cm long, and one walk over
//!   it strays up to 5 mm from the edge (the fibres pull it along their valleys); the seeds walk
//!   between tip steps of a few millimetres, so the edge is walked in pieces that long, each
//!   with its Gaussian on its own piece (the jag then strays 0.2–0.3 mm from the straight edge
//!   on average and under 2 mm at most; figures in docs/decisions.md).
//! - **[`LIP_POINTS`] points a lip edge** (evenly picked from the walk's pixels, the ends exact):
//!   32 keep the fibre noise's millimetre detail on a 2.5 cm edge and bound the storage.
//! - **Built when the mesh changes** (an announced frame, which may allocate): walks of lip
//!   edges the previous mesh already had are kept, so a tear step walks only its new edges.
//! - **Display only**: the physics, the contacts and the sound see the straight edges (the jag
//!   is ≤ 1–2 mm; the seeds' tear too is textured, not meshed, at this scale).

use crate::math::V2;
use crate::sheet::physical::PhysMesh;

use super::fibres::{FibreTexture, Px, px_of};
use super::walk::{DEFAULT_BLEND, walk};

/// Points of a lip edge's polyline, its two ends included.
pub const LIP_POINTS: usize = 32;
/// Longest piece of a lip edge walked on its own, metres: the walk is pinned to the straight
/// edge at least this often.
pub const LIP_PIECE_M: f64 = 0.004;

/// A vertex on the outer rectangle is within this of its side, metres.
const SIDE_TOLERANCE_M: f64 = 1e-9;

/// The detail of one lip edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LipRun {
    /// The edge's vertices, in its triangle's (counter-clockwise) order.
    pub edge: [u32; 2],
    /// The triangle the edge bounds.
    pub triangle: u32,
    /// Points used in [`Self::pattern_m`].
    pub len: u8,
    /// The polyline from `edge[0]` to `edge[1]`, pattern metres.
    pub pattern_m: [[f64; 2]; LIP_POINTS],
}

impl LipRun {
    /// The used points.
    pub fn points(&self) -> &[[f64; 2]] {
        &self.pattern_m[..usize::from(self.len)]
    }
}

/// The detail of every lip edge of a sheet.
#[derive(Clone, Debug, Default)]
pub struct Lips {
    runs: Vec<LipRun>,
    previous: Vec<LipRun>,
    path: Vec<Px>,
    piece: Vec<Px>,
}

/// True if the pattern point lies on the side `side` (0 = x, 1 = y) of the rectangle at ±half.
fn on_side(p: V2, side: usize, half: f64) -> Option<i8> {
    let c = p[side];
    if (c - half).abs() <= SIDE_TOLERANCE_M {
        Some(1)
    } else if (c + half).abs() <= SIDE_TOLERANCE_M {
        Some(-1)
    } else {
        None
    }
}

/// True if the edge (a, b) lies along one side of the `width_m` × `length_m` rectangle.
fn on_rectangle(a: V2, b: V2, width_m: f64, length_m: f64) -> bool {
    (0..2).any(|side| {
        let half = if side == 0 { width_m } else { length_m } / 2.0;
        matches!((on_side(a, side, half), on_side(b, side, half)), (Some(x), Some(y)) if x == y)
    })
}

/// A key of an undirected pattern edge (its ends' bits, the smaller first).
fn key(a: V2, b: V2) -> [u64; 4] {
    let (ka, kb) = (
        [a.x.to_bits(), a.y.to_bits()],
        [b.x.to_bits(), b.y.to_bits()],
    );
    if ka <= kb {
        [ka[0], ka[1], kb[0], kb[1]]
    } else {
        [kb[0], kb[1], ka[0], ka[1]]
    }
}

impl Lips {
    /// The runs, one per lip edge, in the order of the mesh's boundary half-edges.
    pub fn runs(&self) -> &[LipRun] {
        &self.runs
    }

    /// Forgets every run (a whole sheet).
    pub fn clear(&mut self) {
        self.runs.clear();
    }

    /// Finds the lip edges of `sp` (a sheet cut from a `width_m` × `length_m` rectangle) and
    /// gives each its walk on `fibres`; walks of edges the previous call saw are reused. May
    /// allocate (call where the mesh changes).
    pub fn rebuild(&mut self, sp: &PhysMesh, width_m: f64, length_m: f64, fibres: &FibreTexture) {
        std::mem::swap(&mut self.runs, &mut self.previous);
        self.runs.clear();
        self.previous.sort_unstable_by_key(|r| {
            let p = r.points();
            key(
                V2::new(p[0][0], p[0][1]),
                V2::new(p[p.len() - 1][0], p[p.len() - 1][1]),
            )
        });
        for (h, he) in sp.topo.half_edges.iter().enumerate() {
            if he.twin != crate::sheet::topology::NONE {
                continue;
            }
            let (a, b) = (he.origin, sp.topo.dest(h as u32));
            let (pa, pb) = (sp.pattern[a as usize], sp.pattern[b as usize]);
            if on_rectangle(pa, pb, width_m, length_m) {
                continue;
            }
            let mut run = LipRun {
                edge: [a, b],
                triangle: he.face,
                len: 0,
                pattern_m: [[0.0; 2]; LIP_POINTS],
            };
            let k = key(pa, pb);
            let found = self
                .previous
                .binary_search_by_key(&k, |r| {
                    let p = r.points();
                    key(
                        V2::new(p[0][0], p[0][1]),
                        V2::new(p[p.len() - 1][0], p[p.len() - 1][1]),
                    )
                })
                .ok()
                .map(|i| self.previous[i]);
            match found {
                Some(old) => {
                    run.len = old.len;
                    let n = usize::from(old.len);
                    let same = old.pattern_m[0] == [pa.x, pa.y];
                    for i in 0..n {
                        run.pattern_m[i] = old.pattern_m[if same { i } else { n - 1 - i }];
                    }
                }
                None => self.walk_edge(&mut run, pa, pb, fibres),
            }
            self.runs.push(run);
        }
    }

    /// The walk from `pa` to `pb` in pieces of at most [`LIP_PIECE_M`], run from the end with
    /// the smaller pixel and picked down to [`LIP_POINTS`] points.
    fn walk_edge(&mut self, run: &mut LipRun, pa: V2, pb: V2, fibres: &FibreTexture) {
        let (qa, qb) = (px_of(pa), px_of(pb));
        let forward = qa <= qb;
        let (s0, s1) = if forward { (pa, pb) } else { (pb, pa) };
        let pieces = ((s1 - s0).norm() / LIP_PIECE_M).ceil().max(1.0) as usize;
        self.path.clear();
        for k in 0..pieces {
            let a = s0 + (s1 - s0) * (k as f64 / pieces as f64);
            let b = s0 + (s1 - s0) * ((k + 1) as f64 / pieces as f64);
            walk(
                fibres,
                px_of(a),
                px_of(b),
                a,
                b,
                DEFAULT_BLEND,
                &mut self.piece,
            );
            let skip = usize::from(k > 0);
            self.path
                .extend_from_slice(self.piece.get(skip..).unwrap_or(&[]));
        }
        let m = self.path.len();
        let n = m.clamp(2, LIP_POINTS);
        for i in 0..n {
            let j = if m < 2 {
                0
            } else {
                (i * (m - 1) + (n - 1) / 2) / (n - 1)
            };
            let c = super::fibres::centre_of(self.path[j.min(m - 1)]);
            let slot = if forward { i } else { n - 1 - i };
            run.pattern_m[slot] = [c.x, c.y];
        }
        // The ends are the vertices themselves.
        run.pattern_m[0] = [pa.x, pa.y];
        run.pattern_m[n - 1] = [pb.x, pb.y];
        run.len = n as u8;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_along_the_rectangle_are_not_lips() {
        let (w, l) = (0.2, 0.3);
        let v = |x: f64, y: f64| V2::new(x, y);
        assert!(on_rectangle(v(-0.1, 0.0), v(-0.1, 0.05), w, l));
        assert!(on_rectangle(v(0.0, 0.15), v(0.05, 0.15), w, l));
        // Corner to corner across the sheet, and a cut ending on the border.
        assert!(!on_rectangle(v(-0.1, -0.15), v(0.1, 0.15), w, l));
        assert!(!on_rectangle(v(0.0, 0.149), v(0.0, 0.15), w, l));
        // Both ends on opposite sides.
        assert!(!on_rectangle(v(-0.1, 0.0), v(0.1, 0.0), w, l));
    }

    #[test]
    fn a_walk_keeps_its_ends_and_both_directions_give_one_jag() {
        let fibres = FibreTexture::new(7);
        let mut lips = Lips::default();
        let (pa, pb) = (V2::new(0.0123, -0.0311), V2::new(0.0201, -0.0254));
        let blank = LipRun {
            edge: [0, 1],
            triangle: 0,
            len: 0,
            pattern_m: [[0.0; 2]; LIP_POINTS],
        };
        let (mut ab, mut ba) = (blank, blank);
        lips.walk_edge(&mut ab, pa, pb, &fibres);
        lips.walk_edge(&mut ba, pb, pa, &fibres);
        assert_eq!(usize::from(ab.len), LIP_POINTS);
        assert_eq!(ab.points()[0], [pa.x, pa.y]);
        assert_eq!(ab.points()[LIP_POINTS - 1], [pb.x, pb.y]);
        let reversed: Vec<_> = ba.points().iter().rev().copied().collect();
        assert_eq!(ab.points(), &reversed[..]);
    }
}
