//! # Cutting S_P along a straight pattern line (strip cutting, with state transfer)
//!
//! When a compression pass of the geometry layer ends, the seeds cut the flat region along
//! the strip's rulings and remesh the strip as a new curved region whose rulings are edges
//! (TOG 2015 §4.2, `001_44bc28f7c5e9f81f.txt` P 459–487; thesis §2.4.3,
//! `000_cb4d91e46ec5927f.txt` T 879–906; digest-crumpling §3.4). A ruling that is an edge is
//! a hinge: the sheet can bend along exactly that straight line, where a lattice crossed
//! obliquely can only bend in a zigzag of its own edges. This module makes a straight pattern
//! line a chain of S_P edges ([`cut_along`]). It is a building block for tearing: the frame
//! loop does not cut strips, because on our lattice the cuts cost frame time and bought no
//! accuracy (docs/decisions.md, "Strip cutting (removed from the frame loop)").
//!
//! ## The cut
//!
//! The caller gives the S_P edges the line crosses, in order along the line, each with the
//! crossing's parameter along the edge (the crossings of the propagation walk,
//! [`super::walk`]). Each crossing becomes a vertex of the chain:
//!
//! - within [`SNAP_FRAC`] of an edge end, that end (no sliver is made);
//! - otherwise a new vertex splitting the edge there: its one or two triangles (u, w, o) and
//!   (w, u, x) become (u, n, o), (n, w, o), (w, n, x), (n, u, x). A split whose new triangles
//!   would have an angle below [`CUT_MIN_ANGLE_RAD`] (12°, as for a vertex insertion) snaps
//!   to the nearer end instead.
//!
//! Splitting the crossed edges one after the other joins them: consecutive crossings are
//! two edges of the one triangle the line runs through between them, and the split of the
//! second edge joins its new vertex to the vertex opposite it in that triangle — the first
//! split's vertex, or the snapped end (an end of either edge is a corner of that triangle). So
//! the chain is made of edges without any search; it is checked all the same, and a broken
//! chain refuses the cut.
//!
//! Then **Lawson flips** about the new vertices, as after a vertex insertion
//! ([`crate::sheet::refine`]): an edge of a triangle with a new vertex whose quad's far vertex
//! lies inside the triangle's circumcircle is swapped for the quad's other diagonal, if the
//! quad is strictly convex, the flip raises its smallest angle, and the edge is not on the cut
//! line, carries no rest angle or damage and is bent by less than
//! [`FLIP_MAX_DIHEDRAL_RAD`]. Without them the splits' small triangles (down to 1/15 of a
//! lattice triangle) folded sharply along the cut line and could be turned over next to a
//! freshly grabbed vertex; a larger minimum angle for splits instead was worse elsewhere
//! (same section of docs/decisions.md).
//!
//! ## State transfer
//!
//! A new vertex lies on a straight edge of a flat triangle, so its 3D position and velocity
//! are the edge's interpolated at the crossing and the sheet's shape and energy do not change:
//! each new edge runs across an old triangle (flat, no rest angle, no damage, the old
//! triangle's strain), and the two halves of a split edge inherit its rest angle and damage
//! (their dihedral is the old edge's). Old vertices keep their index, pattern position, 3D
//! position and velocity; rest data, hinges and lumped masses are rebuilt as
//! [`PhysMesh::from_pattern`] builds them (total mass unchanged); each triangle of the cut
//! mesh names the old triangle under its pattern centroid (unchanged ones keep their index),
//! so per-triangle state follows. Building a mesh allocates: a cut is an event, like a vertex
//! insertion ([`crate::sheet::refine`]).

use super::refine::{
    FLIP_MAX_DIHEDRAL_RAD, ccw_min_angle, in_circle, locate, min_angle, with_directed_edge,
};
use crate::math::V2;
use crate::sheet::measure::dihedral;
use crate::sheet::pattern::{Pattern, signed_area};
use crate::sheet::physical::{MeshError, PhysMesh};

/// A crossing within this fraction of an edge's length from one of its ends uses that end.
pub const SNAP_FRAC: f64 = 0.33;
/// Smallest pattern angle a split may make; a crossing whose split would make a smaller one
/// uses the nearer end of its edge (12°, as for a vertex insertion,
/// [`crate::sheet::refine::MIN_ANGLE_RAD`]).
pub const CUT_MIN_ANGLE_RAD: f64 = super::refine::MIN_ANGLE_RAD;
/// Passes of Delaunay flips about the new vertices, at most.
const MAX_FLIP_PASSES: usize = 8;

/// One S_P edge crossed by the cut line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeCrossing {
    /// The edge's vertices; the parameter runs from the first to the second.
    pub edge: [u32; 2],
    /// Parameter of the crossing along the edge, in [0, 1].
    pub u: f64,
}

/// Why a line cannot be cut.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum CutError {
    /// No crossing was given.
    #[error("the cut line crosses no edge")]
    Empty,
    /// A crossing names two vertices that share no edge.
    #[error("vertices {0} and {1} are not joined by an edge of the sheet")]
    NoEdge(u32, u32),
    /// A crossing parameter is not a number in [0, 1].
    #[error("crossing parameter {0} is not in [0, 1]")]
    BadParameter(f64),
    /// Every crossing snapped to an existing vertex: the line is already (nearly) edges.
    #[error("the line runs through existing vertices only: nothing to cut")]
    NothingToCut,
    /// Two consecutive chain vertices share no edge (not a straight, ordered line).
    #[error("the cut's chain is broken between vertices {0} and {1}")]
    Broken(u32, u32),
    /// The cut pattern is not a valid mesh.
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// A mesh cut along a line.
#[derive(Clone, Debug)]
pub struct Cut {
    /// The cut S_P (state transferred).
    pub mesh: PhysMesh,
    /// The chain of S_P vertices along the line, in the crossings' order: consecutive ones
    /// share an edge.
    pub chain: Vec<u32>,
    /// Vertices added (appended after the old ones).
    pub added: usize,
    /// Delaunay flips made about them.
    pub flips: usize,
    /// Per triangle of the cut mesh, the old triangle under its pattern centroid.
    pub tri_parent: Vec<u32>,
}

/// The mesh being cut: pattern, 3D state and triangles, with the split edges' inheritance.
struct Work {
    points: Vec<V2>,
    pos: Vec<crate::math::V3>,
    vel: Vec<crate::math::V3>,
    triangles: Vec<[u32; 3]>,
    /// (old edge, its new vertex), ends ascending.
    split_of: Vec<([u32; 2], u32)>,
}

fn key(a: u32, b: u32) -> [u32; 2] {
    [a.min(b), a.max(b)]
}

impl Work {
    /// Splits the unsplit old edge (u, w) at parameter `s` (u → w). `None`, changing nothing,
    /// if a new triangle would be poorly shaped.
    fn split(&mut self, u: u32, w: u32, s: f64) -> Option<u32> {
        // Orient along a triangle that holds the directed edge.
        let (u, w, s) = if with_directed_edge(&self.triangles, u, w).is_some() {
            (u, w, s)
        } else {
            (w, u, 1.0 - s)
        };
        let (t1, o) = with_directed_edge(&self.triangles, u, w)?;
        let twin = with_directed_edge(&self.triangles, w, u);
        let n = self.points.len() as u32;
        let p = self.points[u as usize] * (1.0 - s) + self.points[w as usize] * s;
        let mut new_tris = [[u, n, o], [n, w, o], [0; 3], [0; 3]];
        let mut count = 2;
        if let Some((_, x)) = twin {
            new_tris[2] = [w, n, x];
            new_tris[3] = [n, u, x];
            count = 4;
        }
        let at = |i: u32| if i == n { p } else { self.points[i as usize] };
        let worst = new_tris[..count]
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(at);
                ccw_min_angle(a, b, c)
            })
            .fold(f64::INFINITY, f64::min);
        if worst < CUT_MIN_ANGLE_RAD {
            return None;
        }
        let (iu, iw) = (u as usize, w as usize);
        self.points.push(p);
        self.pos.push(self.pos[iu] * (1.0 - s) + self.pos[iw] * s);
        self.vel.push(self.vel[iu] * (1.0 - s) + self.vel[iw] * s);
        self.triangles[t1] = new_tris[0];
        self.triangles.push(new_tris[1]);
        if let Some((t2, _)) = twin {
            self.triangles[t2] = new_tris[2];
            self.triangles.push(new_tris[3]);
        }
        self.split_of.push((key(u, w), n));
        Some(n)
    }

    /// Lawson flips about the new vertices (index ≥ `n0`), as after a vertex insertion: an
    /// edge of a triangle with a new vertex is swapped for the other diagonal of its quad when
    /// the quad's far vertex lies inside the triangle's circumcircle, the quad is strictly
    /// convex and the flip raises the quad's smallest angle — unless the edge is on the cut
    /// line (`chain`), carries a rest angle or damage (its own, or the split edge's it is half
    /// of), or is bent by more than [`FLIP_MAX_DIHEDRAL_RAD`] (a flip would change the shape).
    fn improve(&mut self, sp: &PhysMesh, n0: usize, chain: &[u32]) -> usize {
        let on_chain = |a: u32, b: u32| chain.windows(2).any(|w| key(w[0], w[1]) == key(a, b));
        let mut flips = 0;
        for _ in 0..MAX_FLIP_PASSES {
            let mut flipped = false;
            for t1 in 0..self.triangles.len() {
                let tri = self.triangles[t1];
                if tri.iter().all(|&v| (v as usize) < n0) {
                    continue;
                }
                for k in 0..3 {
                    let (u, w, o1) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                    if on_chain(u, w) || self.creased(sp, u, w) {
                        continue;
                    }
                    let Some((t2, o2)) = with_directed_edge(&self.triangles, w, u) else {
                        continue;
                    };
                    let p = |i: u32| self.points[i as usize];
                    if !in_circle(p(u), p(w), p(o1), p(o2))
                        || signed_area(p(o1), p(o2), p(u)) * signed_area(p(o1), p(o2), p(w)) >= 0.0
                    {
                        continue;
                    }
                    let before = min_angle(p(u), p(w), p(o1)).min(min_angle(p(w), p(u), p(o2)));
                    let after = min_angle(p(o1), p(u), p(o2)).min(min_angle(p(o1), p(o2), p(w)));
                    let theta = dihedral(&[u, w, o1, o2].map(|i| self.pos[i as usize]));
                    if after <= before || theta.abs() > FLIP_MAX_DIHEDRAL_RAD {
                        continue;
                    }
                    self.triangles[t1] = [o1, u, o2];
                    self.triangles[t2] = [o1, o2, w];
                    flips += 1;
                    flipped = true;
                    break;
                }
            }
            if !flipped {
                break;
            }
        }
        flips
    }

    /// True if edge (a, b) carries a rest angle or damage: its own as an old edge, or that of
    /// the old edge it is half of.
    fn creased(&self, sp: &PhysMesh, a: u32, b: u32) -> bool {
        let n0 = sp.num_vertices() as u32;
        let old = if a < n0 && b < n0 {
            Some(key(a, b))
        } else {
            self.split_of
                .iter()
                .find(|&&(k, n)| (a == n && k.contains(&b)) || (b == n && k.contains(&a)))
                .map(|&(k, _)| k)
        };
        old.and_then(|[x, y]| sp.topo.find_edge(x, y))
            .is_some_and(|e| {
                sp.edge_rest_angle[e as usize] != 0.0 || sp.edge_damage[e as usize] != 0.0
            })
    }

    fn has_edge(&self, a: u32, b: u32) -> bool {
        with_directed_edge(&self.triangles, a, b).is_some()
            || with_directed_edge(&self.triangles, b, a).is_some()
    }
}

/// Cuts `sp` along the line through `crossings` (module doc): every crossing becomes a chain
/// vertex, new where it is not within [`SNAP_FRAC`] of an edge end; the state is carried over.
pub fn cut_along(sp: &PhysMesh, crossings: &[EdgeCrossing]) -> Result<Cut, CutError> {
    if crossings.is_empty() {
        return Err(CutError::Empty);
    }
    for c in crossings {
        let [u, w] = c.edge;
        let n = sp.num_vertices() as u32;
        if u >= n || w >= n || sp.topo.find_edge(u, w).is_none() {
            return Err(CutError::NoEdge(u, w));
        }
        if !(0.0..=1.0).contains(&c.u) {
            return Err(CutError::BadParameter(c.u));
        }
    }
    let n0 = sp.num_vertices();
    let mut work = Work {
        points: sp.pattern.clone(),
        pos: sp.pos.clone(),
        vel: sp.vel.clone(),
        triangles: sp.triangles.clone(),
        split_of: Vec::with_capacity(crossings.len()),
    };
    let mut chain: Vec<u32> = Vec::with_capacity(crossings.len());
    for c in crossings {
        let [u, w] = c.edge;
        let nearer = if c.u < 0.5 { u } else { w };
        let v = if c.u < SNAP_FRAC || c.u > 1.0 - SNAP_FRAC {
            nearer
        } else if let Some(&(_, n)) = work.split_of.iter().find(|(k, _)| *k == key(u, w)) {
            n
        } else {
            work.split(u, w, c.u).unwrap_or(nearer)
        };
        if chain.last() != Some(&v) {
            chain.push(v);
        }
    }
    let added = work.points.len() - n0;
    if added == 0 {
        return Err(CutError::NothingToCut);
    }
    let flips = work.improve(sp, n0, &chain);
    if let Some(w) = chain.windows(2).find(|w| !work.has_edge(w[0], w[1])) {
        return Err(CutError::Broken(w[0], w[1]));
    }
    let tri_parent = work
        .triangles
        .iter()
        .enumerate()
        .map(|(i, tri)| {
            if i < sp.triangles.len() && *tri == sp.triangles[i] {
                return i as u32;
            }
            let c = tri
                .iter()
                .fold(V2::zeros(), |s, &v| s + work.points[v as usize])
                / 3.0;
            let fallback = if i < sp.triangles.len() { i as u32 } else { 0 };
            locate(&sp.pattern, &sp.triangles, c).map_or(fallback, |(pt, _)| pt as u32)
        })
        .collect();
    let Work {
        points,
        pos,
        vel,
        triangles,
        split_of,
    } = work;
    let pattern = Pattern { points, triangles };
    let mut mesh = PhysMesh::from_pattern(&pattern, 0.0, sp.areal_density_kg_m2)?;
    mesh.pos = pos;
    mesh.vel = vel;
    // A half of a split edge inherits the old edge's rest angle and damage.
    mesh.inherit_edge_state(sp, |[a, b]| {
        let from = split_of
            .iter()
            .find(|&&(k, n)| (a == n && k.contains(&b)) || (b == n && k.contains(&a)))
            .map_or([a, b], |&(k, _)| k);
        ((from[0] as usize) < n0 && (from[1] as usize) < n0).then_some(from)
    });
    mesh.singular.clone_from(&sp.singular);
    mesh.rest_version = sp.rest_version + 1;
    Ok(Cut {
        mesh,
        chain,
        added,
        flips,
        tri_parent,
    })
}

/// The S_P edges the straight pattern line through `o` along `d` crosses, from border to
/// border, in order along `d`, each with its crossing parameter: the input [`cut_along`]
/// takes, for a line chosen by hand (the geometry layer passes its propagation walk's own
/// crossings). `None` if `o` is not on the sheet.
pub fn line_crossings(sp: &PhysMesh, o: V2, d: V2) -> Option<Vec<EdgeCrossing>> {
    let t0 = locate(&sp.pattern, &sp.triangles, o)?.0 as u32;
    let mut side = [Vec::new(), Vec::new()];
    for (k, dir) in [-d, d].into_iter().enumerate() {
        super::walk::walk(sp, t0, o, dir, 4 * sp.num_triangles(), |c| {
            let h = sp.topo.half_edges[c.half_edge as usize];
            side[k].push(EdgeCrossing {
                edge: [h.origin, sp.topo.dest(c.half_edge)],
                u: c.u,
            });
            true
        });
    }
    let [mut back, ahead] = side;
    back.reverse();
    back.extend(ahead);
    Some(back)
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    use crate::sheet::refine::tests::bent_sheet as sheet;

    /// The crossings of the whole line through `o` along `d` ([`line_crossings`]).
    pub(in crate::sheet) fn line(sp: &PhysMesh, o: V2, d: V2) -> Vec<EdgeCrossing> {
        line_crossings(sp, o, d).expect("the point is on the sheet")
    }

    fn dist_to_line(p: V2, o: V2, d: V2) -> f64 {
        (p - o).perp(&d.normalize()).abs()
    }

    #[test]
    fn an_oblique_line_becomes_a_chain_of_edges_and_the_sheet_keeps_its_shape_and_mass() {
        let mut sp = sheet();
        let (o, d) = (V2::new(0.003, -0.002), V2::new(0.8, 0.35));
        let crossings = line(&sp, o, d);
        assert!(crossings.len() > 8);
        // A folded, damaged edge crossed near its middle.
        let folded = crossings
            .iter()
            .find(|c| (0.4..0.6).contains(&c.u))
            .unwrap();
        let fold = sp.topo.find_edge(folded.edge[0], folded.edge[1]).unwrap() as usize;
        sp.edge_rest_angle[fold] = 0.05;
        sp.edge_damage[fold] = 1.5;
        let cut = cut_along(&sp, &crossings).unwrap();
        let m = &cut.mesh;
        m.topo.validate().unwrap();
        assert_eq!(m.topo.euler_characteristic(), 1);
        assert!(cut.added > 4, "{} vertices added", cut.added);
        assert_eq!(m.num_vertices(), sp.num_vertices() + cut.added);
        // The chain runs from boundary to boundary along the line, joined by edges.
        let (first, last) = (cut.chain[0], *cut.chain.last().unwrap());
        assert!(m.topo.vertex_on_boundary[first as usize]);
        assert!(m.topo.vertex_on_boundary[last as usize]);
        let spacing = 0.1 / 9.0;
        for w in cut.chain.windows(2) {
            assert!(m.topo.find_edge(w[0], w[1]).is_some(), "{w:?}");
        }
        for &v in &cut.chain {
            let p = m.pattern[v as usize];
            // New vertices are on the line; snapped ones within a fifth of an edge of it.
            let tol = if (v as usize) < sp.num_vertices() {
                SNAP_FRAC * spacing * 1.2
            } else {
                1e-12
            };
            assert!(dist_to_line(p, o, d) <= tol, "vertex {v} off the line");
        }
        // The sheet's shape is unchanged: every new vertex is on an old straight edge, and
        // every edge of the cut mesh is exactly as strained as the old triangle it crosses
        // (here none: the cylinder is isometric).
        for (ei, e) in m.topo.edges.iter().enumerate() {
            let [a, b] = e.v.map(|i| i as usize);
            let l = (m.pos[a] - m.pos[b]).norm();
            let lbar = (m.pattern[a] - m.pattern[b]).norm();
            // The chord of the cylinder across a bent old edge is shorter than the arc; old
            // edges and edges across a triangle keep the old triangles' chord strain.
            assert!((l / lbar - 1.0).abs() < 2e-3, "edge {ei}: {l} vs {lbar}");
        }
        for tri in &m.triangles {
            let [a, b, c] = tri.map(|i| m.pattern[i as usize]);
            assert!(min_angle(a, b, c) >= CUT_MIN_ANGLE_RAD - 1e-12);
        }
        let area = |m: &PhysMesh| m.tri_rest.iter().map(|r| r.area_m2).sum::<f64>();
        assert!((area(m) - area(&sp)).abs() < 1e-15);
        assert!((m.total_mass_kg() - sp.total_mass_kg()).abs() < 1e-15);
        // Old vertices keep their state; new ones interpolate their edge's.
        assert_eq!(&m.pos[..sp.num_vertices()], &sp.pos[..]);
        assert_eq!(&m.vel[..sp.num_vertices()], &sp.vel[..]);
        assert_eq!(cut.tri_parent.len(), m.num_triangles());
        for (t, &pt) in cut.tri_parent.iter().enumerate() {
            let c = m.triangles[t]
                .iter()
                .fold(V2::zeros(), |s, &v| s + m.pattern[v as usize])
                / 3.0;
            let [a, b, cc] = sp.triangles[pt as usize].map(|i| sp.pattern[i as usize]);
            let l = crate::math::barycentric2(a, b, cc, c);
            assert!(l.iter().all(|&x| x > -1e-9), "triangle {t}: parent {pt}");
        }
        // The folded edge is split; its halves keep its rest angle and damage, and no other
        // edge has any.
        assert!(m.topo.find_edge(folded.edge[0], folded.edge[1]).is_none());
        let halves: Vec<usize> = (0..m.num_edges())
            .filter(|&ei| m.edge_rest_angle[ei] != 0.0 || m.edge_damage[ei] != 0.0)
            .collect();
        assert_eq!(halves.len(), 2);
        for ei in halves {
            assert_eq!((m.edge_rest_angle[ei], m.edge_damage[ei]), (0.05, 1.5));
            let v = m.topo.edges[ei].v;
            assert!(v.iter().any(|x| folded.edge.contains(x)));
            assert!(v.iter().any(|&x| x as usize >= sp.num_vertices()));
        }
        assert_eq!(m.rest_version, sp.rest_version + 1);
    }

    #[test]
    fn a_line_along_lattice_edges_or_bad_crossings_are_refused() {
        let sp = sheet();
        assert_eq!(cut_along(&sp, &[]).unwrap_err(), CutError::Empty);
        // Through vertices only: every crossing at an edge end.
        let e = sp.topo.edges[50].v;
        let at_end = [EdgeCrossing { edge: e, u: 0.05 }];
        assert_eq!(cut_along(&sp, &at_end).unwrap_err(), CutError::NothingToCut);
        let far = [EdgeCrossing {
            edge: [0, sp.num_vertices() as u32 - 1],
            u: 0.5,
        }];
        assert!(matches!(
            cut_along(&sp, &far).unwrap_err(),
            CutError::NoEdge(..)
        ));
        let nan = [EdgeCrossing {
            edge: e,
            u: f64::NAN,
        }];
        assert!(matches!(
            cut_along(&sp, &nan).unwrap_err(),
            CutError::BadParameter(_)
        ));
        // Two edges far apart are no line.
        let (e1, e2) = (sp.topo.edges[30].v, sp.topo.edges[200].v);
        let apart = [
            EdgeCrossing { edge: e1, u: 0.5 },
            EdgeCrossing { edge: e2, u: 0.5 },
        ];
        assert!(matches!(
            cut_along(&sp, &apart).unwrap_err(),
            CutError::Broken(..)
        ));
    }

    #[test]
    fn lines_in_many_directions_cut_into_valid_well_shaped_meshes() {
        let sp = sheet();
        for k in 0..24 {
            let a = k as f64 * std::f64::consts::PI / 24.0 + 0.013;
            let d = V2::new(a.cos(), a.sin());
            let o = V2::new(0.01 * (k as f64 * 0.7).sin(), 0.008 * (k as f64).cos());
            let crossings = line(&sp, o, d);
            match cut_along(&sp, &crossings) {
                Ok(cut) => {
                    cut.mesh.topo.validate().unwrap();
                    for w in cut.chain.windows(2) {
                        assert!(cut.mesh.topo.find_edge(w[0], w[1]).is_some());
                    }
                    for tri in &cut.mesh.triangles {
                        let [a, b, c] = tri.map(|i| cut.mesh.pattern[i as usize]);
                        assert!(min_angle(a, b, c) >= CUT_MIN_ANGLE_RAD - 1e-12);
                    }
                }
                Err(CutError::NothingToCut) => {}
                Err(e) => panic!("direction {k}: {e}"),
            }
        }
    }
}
