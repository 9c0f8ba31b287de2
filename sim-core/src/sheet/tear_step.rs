//! # One step of a tear through S_P: cut along the tip's move, then open it
//!
//! The procedural tear moves its crack tip in straight steps (eq. 3.1, [`crate::tearing::tip`];
//! MIG 2015 M:116–120, thesis T:1363–1372). [`advance_tear`] carries one step into the mesh:
//! the pattern segment from the tip to its new place becomes a chain of S_P edges
//! ([`super::cut::cut_along`] on the segment's crossings), and the chain is opened into two lips
//! ([`super::unzip::unzip`]). A tear starts at a point of the sheet's border (M:114) and
//! continues from its tip vertex; the step ends at the last edge the segment crosses, so the
//! new tip is a vertex at most one triangle short of the point aimed at (the next step goes on
//! from there). A step that reaches the border splits the sheet.
//!
//! Decisions, one line each:
//! - Straight segments, one per step: the detail of the torn edge ([`crate::tearing::walk`])
//!   is finer than S_P's triangles and belongs to the lips' drawing, not to the mesh.
//! - A segment that runs along existing edges (every crossing within
//!   [`super::cut::SNAP_FRAC`] of a vertex) is torn along them: a tear follows the mesh where
//!   the mesh already follows the tear.
//! - The crossings at or behind the tip are dropped (the tip's own triangle is where the step
//!   starts).

use super::cut::{Cut, CutError, EdgeCrossing, SNAP_FRAC, cut_along, line_crossings};
use super::physical::PhysMesh;
use super::unzip::{UnzipError, unzip};
use crate::math::V2;

/// Where a tear step starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TearFrom {
    /// A point on the sheet's border (pattern metres): the tear's first step.
    Border(V2),
    /// The crack tip, a vertex of S_P.
    Tip(u32),
}

/// A mesh torn one step further.
#[derive(Clone, Debug)]
pub struct TearStep {
    /// The torn S_P (state transferred).
    pub mesh: PhysMesh,
    /// The chain of vertices opened, from the step's start to the new tip.
    pub chain: Vec<u32>,
    /// Per triangle of the torn mesh, the triangle of the old one under its pattern centroid.
    pub tri_parent: Vec<u32>,
    /// The new tip (the chain's last vertex); on the border if the sheet came apart.
    pub tip: u32,
}

/// Why a step cannot tear.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum TearError {
    /// The step is shorter than the triangle it starts in, or not a number.
    #[error("the step crosses no edge")]
    TooShort,
    /// The start is not on the sheet.
    #[error("the tear's start is not on the sheet")]
    OffSheet,
    /// Cutting along the step failed.
    #[error(transparent)]
    Cut(#[from] CutError),
    /// Opening the chain failed.
    #[error(transparent)]
    Unzip(#[from] UnzipError),
    /// The opened mesh would not be pieces that are discs (a vertex joining two triangles by
    /// their corner alone: the cut ran through a vertex with a border on both sides).
    #[error("the step would leave {0}")]
    NotDiscs(String),
}

/// Drops the chain's ends that run along the border (crossings snapped to neighbouring border
/// vertices): a tear enters the sheet at the last border vertex before the inside and leaves
/// it at the first one after.
fn trim_along_border(mesh: &PhysMesh, chain: &mut Vec<u32>) {
    let topo = &mesh.topo;
    let along_border = |a: u32, b: u32| {
        topo.find_edge(a, b)
            .is_some_and(|e| topo.edges[e as usize].is_boundary())
    };
    let lead = chain
        .windows(2)
        .take_while(|w| along_border(w[0], w[1]))
        .count();
    chain.drain(..lead);
    let trail = chain
        .windows(2)
        .rev()
        .take_while(|w| along_border(w[0], w[1]))
        .count();
    chain.truncate(chain.len() - trail);
}

/// How far inside the sheet the segment's walk starts, as a fraction of the step.
const START_INSIDE_FRAC: f64 = 1e-3;

/// Tears `sp` from `from` towards the pattern point `to` (module doc).
pub fn advance_tear(sp: &PhysMesh, from: TearFrom, to: V2) -> Result<TearStep, TearError> {
    let start = match from {
        TearFrom::Border(p) => p,
        TearFrom::Tip(v) => *sp.pattern.get(v as usize).ok_or(TearError::OffSheet)?,
    };
    let seg = to - start;
    let len = seg.norm();
    if !(len > 0.0 && len.is_finite()) {
        return Err(TearError::TooShort);
    }
    let d = seg / len;
    let o = start + d * (START_INSIDE_FRAC * len);
    let crossings = line_crossings(sp, o, d).ok_or(TearError::OffSheet)?;
    // The crossings of the step: ahead of its start and before its end.
    let along = |c: &EdgeCrossing| {
        let [a, b] = c.edge.map(|v| sp.pattern[v as usize]);
        (a + (b - a) * c.u - start).dot(&d)
    };
    let behind = match from {
        TearFrom::Border(_) => -START_INSIDE_FRAC * len,
        TearFrom::Tip(_) => START_INSIDE_FRAC * len,
    };
    let step: Vec<EdgeCrossing> = crossings
        .into_iter()
        .filter(|c| {
            let s = along(c);
            s > behind && s <= len && !matches!(from, TearFrom::Tip(v) if c.edge.contains(&v))
        })
        .collect();
    if step.is_empty() {
        return Err(TearError::TooShort);
    }
    let (mesh, mut chain, tri_parent) = match cut_along(sp, &step) {
        Ok(Cut {
            mesh,
            chain,
            tri_parent,
            ..
        }) => (mesh, chain, tri_parent),
        Err(CutError::NothingToCut) => {
            // Along existing edges: the snapped ends are the chain.
            let mut chain: Vec<u32> = Vec::with_capacity(step.len());
            for c in &step {
                let v = if c.u < SNAP_FRAC {
                    c.edge[0]
                } else {
                    c.edge[1]
                };
                if chain.last() != Some(&v) {
                    chain.push(v);
                }
            }
            (sp.clone(), chain, (0..sp.triangles.len() as u32).collect())
        }
        Err(e) => return Err(e.into()),
    };
    if let TearFrom::Tip(v) = from
        && chain.first() != Some(&v)
    {
        chain.insert(0, v);
    }
    trim_along_border(&mesh, &mut chain);
    let opened = unzip(&mesh, &chain)?;
    // Refused, not repaired: the tip goes on and a later step cuts elsewhere.
    opened
        .mesh
        .topo
        .validate_pieces()
        .map_err(TearError::NotDiscs)?;
    let tip = *chain.last().ok_or(TearError::TooShort)?;
    Ok(TearStep {
        mesh: opened.mesh,
        chain,
        tri_parent,
        tip,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::SheetSize;
    use crate::sheet::{MeshConfig, Sheet};

    fn flat(size: SheetSize) -> Sheet {
        Sheet::new_flat(size, MeshConfig::default(), 0.0, 0.08)
    }

    /// Torn length: half the pattern length of the boundary edges not on the sheet's outline.
    fn torn_length_m(sp: &PhysMesh, w: f64, l: f64) -> f64 {
        let on_outline =
            |p: V2| (p.x.abs() - w / 2.0).abs() < 1e-9 || (p.y.abs() - l / 2.0).abs() < 1e-9;
        sp.topo
            .edges
            .iter()
            .filter(|e| e.is_boundary())
            .filter(|e| {
                let [a, b] = e.v.map(|v| sp.pattern[v as usize]);
                !(on_outline(a) && on_outline(b) && on_outline((a + b) / 2.0))
            })
            .map(|e| (sp.pattern[e.v[1] as usize] - sp.pattern[e.v[0] as usize]).norm())
            .sum::<f64>()
            / 2.0
    }

    fn area(sp: &PhysMesh) -> f64 {
        sp.tri_rest.iter().map(|r| r.area_m2).sum()
    }

    /// A tear in `steps` equal steps from the back edge at `x0` towards the front at `x1`.
    fn tear(size: SheetSize, x0: f64, x1: f64, steps: usize) -> (Vec<PhysMesh>, f64, f64) {
        let sheet = flat(size);
        let (w, l) = (sheet.width_m, sheet.length_m);
        let (a, b) = (V2::new(x0, -l / 2.0), V2::new(x1, l / 2.0 + 0.01));
        let mut sp = sheet.sp;
        let mut from = TearFrom::Border(a);
        let mut out = Vec::new();
        for k in 1..=steps {
            let to = a + (b - a) * (k as f64 / steps as f64);
            let st = advance_tear(&sp, from, to).unwrap_or_else(|e| panic!("step {k}: {e}"));
            st.mesh.topo.validate().unwrap();
            from = TearFrom::Tip(st.tip);
            sp = st.mesh;
            out.push(sp.clone());
            if sp.topo.pieces().len() == 2 {
                break;
            }
        }
        (out, w, l)
    }

    #[test]
    fn a_tear_in_steps_across_the_sheet_grows_and_leaves_two_pieces_with_its_area() {
        for (size, x0, x1) in [
            (SheetSize::A6, 0.003, 0.003),
            (SheetSize::A6, -0.02, 0.015),
            (SheetSize::Sq10, 0.011, -0.02),
            (SheetSize::A5, 0.0, 0.04),
        ] {
            let whole = area(&flat(size).sp);
            let (meshes, w, l) = tear(size, x0, x1, 8);
            let mut torn = 0.0;
            for (k, sp) in meshes.iter().enumerate() {
                let t = torn_length_m(sp, w, l);
                assert!(
                    t >= torn - 1e-12,
                    "step {k}: torn length fell {torn} -> {t}"
                );
                torn = t;
                assert!((area(sp) - whole).abs() <= 1e-9 * whole);
            }
            let last = meshes.last().unwrap();
            assert_eq!(
                last.topo.pieces().len(),
                2,
                "{size:?}: two pieces at the end"
            );
            for sp in &meshes[..meshes.len() - 1] {
                assert_eq!(sp.topo.pieces().len(), 1);
            }
            let straight = (V2::new(x1, l / 2.0) - V2::new(x0, -l / 2.0)).norm();
            assert!(
                torn >= 0.98 * straight && torn <= 1.3 * straight,
                "{size:?}: torn {torn} m for a {straight} m tear"
            );
        }
    }

    /// The lips of a straight tear follow its line to within the mesh's resolution: a
    /// crossing within SNAP_FRAC of a vertex tears through that vertex.
    #[test]
    fn a_straight_tear_stays_on_its_line_to_the_meshs_resolution() {
        for x in [0.004, -0.013, 0.021] {
            let (meshes, w, l) = tear(SheetSize::A6, x, x, 6);
            let sp = meshes.last().unwrap();
            let worst = sp
                .topo
                .edges
                .iter()
                .filter(|e| e.is_boundary())
                .flat_map(|e| e.v)
                .map(|v| sp.pattern[v as usize])
                .filter(|p| p.x.abs() < w / 2.0 - 1e-9 && p.y.abs() < l / 2.0 - 1e-9)
                .map(|p| (p.x - x).abs())
                .fold(0.0, f64::max);
            let spacing = MeshConfig::default().spacing_m(SheetSize::A6);
            assert!(
                worst <= SNAP_FRAC * spacing * std::f64::consts::SQRT_2,
                "a lip vertex {worst} m off the line (spacing {spacing} m)"
            );
        }
    }

    #[test]
    fn steps_that_cannot_tear_are_refused() {
        let sheet = flat(SheetSize::A6);
        let sp = &sheet.sp;
        let b = V2::new(0.0, -sheet.length_m / 2.0);
        assert_eq!(
            advance_tear(sp, TearFrom::Border(b), b).unwrap_err(),
            TearError::TooShort
        );
        assert_eq!(
            advance_tear(sp, TearFrom::Border(V2::new(1.0, 1.0)), V2::zeros()).unwrap_err(),
            TearError::OffSheet
        );
        assert_eq!(
            advance_tear(sp, TearFrom::Tip(u32::MAX), V2::zeros()).unwrap_err(),
            TearError::OffSheet
        );
    }
}
