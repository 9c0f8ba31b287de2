//! # Coarsening S_P: removing a vertex of a flat region by an edge collapse, with state transfer
//!
//! The seeds regenerate S_P from S_G every frame, so a flat region is always meshed by "coarse
//! flat triangles" however often a strip was cut into it before (TOG 2015 §4.1,
//! `001_44bc28f7c5e9f81f.txt` P 351–354; thesis §2.4, `000_cb4d91e46ec5927f.txt` T 734–744;
//! digest-crumpling §2.2). Our S_P keeps its connectivity between events
//! ([`crate::geometry`], "Simplifications"), and the events only add vertices: a strip cut
//! ([`super::cut`]) lays a line of new vertices into the sheet. Once the sheet has opened out
//! flat again around such a vertex, it has no shape left to carry, and only costs Newton work
//! and triangles. This module takes it out again ([`collapse_vertex`]); which vertex, and when,
//! is the geometry layer's choice ([`crate::geometry`], "Coarsening"). Plan step 2 of
//! `docs/sp-regeneration-plan.md`.
//!
//! ## The collapse
//!
//! Vertex v is merged into one of its neighbours u (a half-edge collapse v → u): the one or two
//! triangles that hold the edge (u, v) disappear, every other triangle of v's star takes u in
//! v's place, and v is removed from the vertex list — **vertices after v move down by one**
//! ([`Collapse::new_index`]), all others keep their index. Refused (nothing changes):
//!
//! - v is a singular vertex (persistent forever, thesis §2.4.3) or out of range;
//! - an edge of v's star carries a rest angle or fibre damage (a crease keeps its place), or
//!   is bent by more than the caller's `max_dihedral_rad` (the star is not flat: the collapse
//!   would change the sheet's shape);
//! - v lies on the sheet's border and is not on the straight line between its two border
//!   neighbours (the border's outline would change);
//! - no neighbour u passes the link condition (u and v share exactly the neighbours opposite
//!   their edge — else the mesh would fold onto itself) and keeps every new triangle
//!   counter-clockwise in the pattern with its angles at least
//!   [`crate::sheet::refine::MIN_ANGLE_RAD`]. Of those that do, the one whose worst new angle
//!   is largest is taken. A border vertex collapses only along the border.
//!
//! Then **Lawson flips** about u, as after a cut or an insertion: an edge of u's new star whose
//! quad's far vertex lies inside the circumcircle is swapped, if the quad is strictly convex,
//! the flip raises its smallest angle, and the edge is flat (uncreased, bent by less than
//! [`crate::sheet::refine::FLIP_MAX_DIHEDRAL_RAD`]). After a cut, this brings back the lattice's
//! diagonals where the cut's own flips had turned them.
//!
//! ## State transfer
//!
//! Every remaining vertex keeps its pattern position, 3D position and velocity; rest data,
//! hinges and lumped masses are rebuilt as [`PhysMesh::from_pattern`] builds them, so v's mass
//! goes to the vertices around it and the total mass is unchanged. v's own momentum goes with
//! it: the caller collapses only a vertex that moves with its neighbours (the geometry layer
//! asks for a relative speed under 1 cm/s), so what is lost is at most v's mass times that.
//! Edges that exist in both meshes keep their rest angle and damage; the new ones (u to v's
//! former neighbours, flipped diagonals) start flat and undamaged, as v's star was. Each
//! triangle names its old triangle ([`Collapse::tri_parent`]: itself, or for a triangle a flip
//! made, the old triangle under its pattern centroid), so per-triangle state follows. Building
//! a mesh allocates: a collapse is an event, like a cut.

use super::refine::{
    FLIP_MAX_DIHEDRAL_RAD, MIN_ANGLE_RAD, ccw_min_angle, in_circle, locate, min_angle,
    with_directed_edge,
};
use crate::math::{V2, V3};
use crate::physics::bending::dihedral;
use crate::sheet::pattern::{Pattern, signed_area};
use crate::sheet::physical::{MeshError, PhysMesh};

/// Passes of Delaunay flips about the surviving vertex, at most.
const MAX_FLIP_PASSES: usize = 8;

/// A border vertex is on the line between its border neighbours when its distance from that
/// line is below this fraction of the neighbours' distance.
const COLLINEAR_FRAC: f64 = 1e-9;

/// Why a vertex cannot be collapsed.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum CollapseError {
    /// The vertex does not exist.
    #[error("vertex {0} is not a vertex of the sheet")]
    NoVertex(u32),
    /// Singular vertices are persistent.
    #[error("vertex {0} is a singular vertex")]
    Singular(u32),
    /// An edge of the vertex's star carries a rest angle or fibre damage.
    #[error("an edge at vertex {0} carries a rest angle or fibre damage")]
    Creased(u32),
    /// The vertex's star is bent.
    #[error("the sheet is bent at vertex {0} ({1:.4} rad)")]
    Bent(u32, f64),
    /// A border vertex off the straight line between its border neighbours.
    #[error("border vertex {0} is a corner of the sheet's outline")]
    Corner(u32),
    /// No neighbour can take the vertex's place with well-shaped triangles.
    #[error("no neighbour of vertex {0} can take its place with well-shaped triangles")]
    NoTarget(u32),
    /// The coarsened pattern is not a valid mesh.
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// A mesh with one vertex collapsed into a neighbour.
#[derive(Clone, Debug)]
pub struct Collapse {
    /// The coarsened S_P (state transferred).
    pub mesh: PhysMesh,
    /// The removed vertex (old index).
    pub removed: u32,
    /// The neighbour that took its place (old index).
    pub into: u32,
    /// Delaunay flips made about `into`.
    pub flips: usize,
    /// Per triangle of the coarsened mesh, its old triangle.
    pub tri_parent: Vec<u32>,
}

impl Collapse {
    /// The new index of old vertex `old` (`None` for the removed vertex): vertices after the
    /// removed one move down by one.
    pub fn new_index(&self, old: u32) -> Option<u32> {
        new_index(self.removed, old)
    }
}

/// The new index of old vertex `old` once `removed` is gone.
pub fn new_index(removed: u32, old: u32) -> Option<u32> {
    match old.cmp(&removed) {
        std::cmp::Ordering::Less => Some(old),
        std::cmp::Ordering::Equal => None,
        std::cmp::Ordering::Greater => Some(old - 1),
    }
}

/// Smallest pattern angle of `tris` (0 if one is not counter-clockwise).
fn worst_angle(points: &[V2], tris: &[[u32; 3]]) -> f64 {
    tris.iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| points[i as usize]);
            ccw_min_angle(a, b, c)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Checks that `v`'s star is flat and uncreased (module doc).
fn check_star(sp: &PhysMesh, v: u32, max_dihedral_rad: f64) -> Result<(), CollapseError> {
    for &j in sp.topo.neighbours(v) {
        let Some(e) = sp.topo.find_edge(v, j) else {
            continue;
        };
        let e = e as usize;
        if sp.edge_rest_angle[e] != 0.0 || sp.edge_damage[e] != 0.0 {
            return Err(CollapseError::Creased(v));
        }
        let edge = sp.topo.edges[e];
        if edge.is_boundary() {
            continue;
        }
        let h = edge.he[0];
        let quad = [
            sp.topo.half_edges[h as usize].origin,
            sp.topo.dest(h),
            sp.topo.opposite(h),
            sp.topo.opposite(edge.he[1]),
        ];
        let theta = dihedral(&quad.map(|i| sp.pos[i as usize]));
        if theta.is_nan() || theta.abs() > max_dihedral_rad {
            return Err(CollapseError::Bent(v, theta));
        }
    }
    Ok(())
}

/// True if (u, v) passes the link condition: u and v share exactly the neighbours opposite
/// their edge (one on the border, two inside).
fn link_ok(sp: &PhysMesh, v: u32, u: u32) -> bool {
    let Some(e) = sp.topo.find_edge(v, u) else {
        return false;
    };
    let shared = if sp.topo.edges[e as usize].is_boundary() {
        1
    } else {
        2
    };
    let nu = sp.topo.neighbours(u);
    let common = sp
        .topo
        .neighbours(v)
        .iter()
        .filter(|j| nu.contains(j))
        .count();
    common == shared
}

/// The neighbour that can best take the place of vertex `v` (module doc: a border vertex on
/// the straight line between its border neighbours slides along the border, the link
/// condition holds, the merged triangles stay counter-clockwise with angles of at least
/// [`MIN_ANGLE_RAD`]; the one whose worst new angle is largest), or `None`. `star`: the
/// indices of the triangles around `v`. Checks neither the star's shape nor singularity
/// ([`collapse_vertex`] does). Allocation-free.
pub fn collapse_target(sp: &PhysMesh, v: u32, star: &[u32]) -> Option<u32> {
    let border_v = sp.topo.vertex_on_boundary[v as usize];
    let along = |u: u32| {
        sp.topo
            .find_edge(v, u)
            .is_some_and(|e| sp.topo.edges[e as usize].is_boundary())
    };
    let neighbours = sp.topo.neighbours(v);
    if border_v {
        let mut ends = neighbours.iter().copied().filter(|&j| along(j));
        let (Some(a), Some(b), None) = (ends.next(), ends.next(), ends.next()) else {
            return None;
        };
        let (pa, pb, pv) = (
            sp.pattern[a as usize],
            sp.pattern[b as usize],
            sp.pattern[v as usize],
        );
        let ab = pb - pa;
        if (pv - pa).perp(&ab).abs() > COLLINEAR_FRAC * ab.norm_squared()
            || (pv - pa).dot(&ab) <= 0.0
            || (pv - pb).dot(&ab) >= 0.0
        {
            return None;
        }
    }
    let mut best: Option<(f64, u32)> = None;
    for &u in neighbours {
        if (border_v && !along(u)) || !link_ok(sp, v, u) {
            continue;
        }
        let worst = star
            .iter()
            .map(|&t| sp.triangles[t as usize])
            .filter(|t| !t.contains(&u))
            .map(|t| {
                let [a, b, c] = t.map(|i| sp.pattern[if i == v { u } else { i } as usize]);
                ccw_min_angle(a, b, c)
            })
            .fold(f64::INFINITY, f64::min);
        if worst >= MIN_ANGLE_RAD
            && best.is_none_or(|(bw, bu)| worst > bw || (worst == bw && u < bu))
        {
            best = Some((worst, u));
        }
    }
    best.map(|(_, u)| u)
}

/// Collapses vertex `v` of `sp` into the best of its neighbours (module doc), if its star is
/// flat within `max_dihedral_rad`, uncreased and not singular; the state is carried over.
pub fn collapse_vertex(
    sp: &PhysMesh,
    v: u32,
    max_dihedral_rad: f64,
) -> Result<Collapse, CollapseError> {
    let n = sp.num_vertices();
    if v as usize >= n {
        return Err(CollapseError::NoVertex(v));
    }
    if sp.singular.contains(&v) {
        return Err(CollapseError::Singular(v));
    }
    check_star(sp, v, max_dihedral_rad)?;
    let star: Vec<u32> = (0..sp.num_triangles() as u32)
        .filter(|&t| sp.triangles[t as usize].contains(&v))
        .collect();
    let Some(u) = collapse_target(sp, v, &star) else {
        return Err(if sp.topo.vertex_on_boundary[v as usize] {
            CollapseError::Corner(v)
        } else {
            CollapseError::NoTarget(v)
        });
    };
    // Old-index triangles with their parents, v merged into u.
    let mut tris: Vec<([u32; 3], u32)> = Vec::with_capacity(sp.num_triangles());
    for (t, tri) in sp.triangles.iter().enumerate() {
        if tri.contains(&u) && tri.contains(&v) {
            continue;
        }
        tris.push((tri.map(|i| if i == v { u } else { i }), t as u32));
    }
    let flips = improve(sp, &mut tris, u);
    let fan: Vec<[u32; 3]> = tris
        .iter()
        .map(|&(t, _)| t)
        .filter(|t| t.contains(&u))
        .collect();
    if worst_angle(&sp.pattern, &fan) < MIN_ANGLE_RAD {
        return Err(CollapseError::NoTarget(v));
    }
    let map = |i: u32| new_index(v, i).unwrap_or(u);
    let keep = |i: usize| i != v as usize;
    let points: Vec<V2> = (0..n).filter(|&i| keep(i)).map(|i| sp.pattern[i]).collect();
    let pos: Vec<V3> = (0..n).filter(|&i| keep(i)).map(|i| sp.pos[i]).collect();
    let vel: Vec<V3> = (0..n).filter(|&i| keep(i)).map(|i| sp.vel[i]).collect();
    let triangles: Vec<[u32; 3]> = tris.iter().map(|&(t, _)| t.map(map)).collect();
    let tri_parent: Vec<u32> = tris
        .iter()
        .map(|&(t, p)| {
            if t == sp.triangles[p as usize].map(|i| if i == v { u } else { i }) {
                return p;
            }
            let c = t
                .iter()
                .fold(V2::zeros(), |s, &i| s + sp.pattern[i as usize])
                / 3.0;
            locate(&sp.pattern, &sp.triangles, c).map_or(p, |(pt, _)| pt as u32)
        })
        .collect();
    let pattern = Pattern { points, triangles };
    let mut mesh = PhysMesh::from_pattern(&pattern, 0.0, sp.areal_density_kg_m2)?;
    mesh.pos = pos;
    mesh.vel = vel;
    // Back from new to old indices: the removed vertex's slot is skipped.
    let old = |i: u32| if i >= v { i + 1 } else { i };
    mesh.inherit_edge_state(sp, |e| Some(e.map(old)));
    mesh.singular = sp
        .singular
        .iter()
        .filter_map(|&s| new_index(v, s))
        .collect();
    mesh.rest_version = sp.rest_version + 1;
    Ok(Collapse {
        mesh,
        removed: v,
        into: u,
        flips,
        tri_parent,
    })
}

/// Lawson flips of the edges of `u`'s star (module doc); old indices. Returns the flips made.
fn improve(sp: &PhysMesh, tris: &mut [([u32; 3], u32)], u: u32) -> usize {
    let p = |i: u32| sp.pattern[i as usize];
    let plain: Vec<[u32; 3]> = tris.iter().map(|&(t, _)| t).collect();
    let mut plain = plain;
    let mut flips = 0;
    for _ in 0..MAX_FLIP_PASSES {
        let mut flipped = false;
        for t1 in 0..plain.len() {
            let tri = plain[t1];
            if !tri.contains(&u) {
                continue;
            }
            for k in 0..3 {
                let (a, b, o1) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                // Old edges keep a crease where they have one; a new edge (u to a former
                // neighbour of the removed vertex) is flat.
                let creased = sp.topo.find_edge(a, b).is_some_and(|e| {
                    sp.edge_rest_angle[e as usize] != 0.0 || sp.edge_damage[e as usize] != 0.0
                });
                if creased {
                    continue;
                }
                let Some((t2, o2)) = with_directed_edge(&plain, b, a) else {
                    continue;
                };
                if !in_circle(p(a), p(b), p(o1), p(o2))
                    || signed_area(p(o1), p(o2), p(a)) * signed_area(p(o1), p(o2), p(b)) >= 0.0
                {
                    continue;
                }
                let before = min_angle(p(a), p(b), p(o1)).min(min_angle(p(b), p(a), p(o2)));
                let after = min_angle(p(o1), p(a), p(o2)).min(min_angle(p(o1), p(o2), p(b)));
                let theta = dihedral(&[a, b, o1, o2].map(|i| sp.pos[i as usize]));
                if after <= before || theta.is_nan() || theta.abs() > FLIP_MAX_DIHEDRAL_RAD {
                    continue;
                }
                plain[t1] = [o1, a, o2];
                plain[t2] = [o1, o2, b];
                flips += 1;
                flipped = true;
                break;
            }
        }
        if !flipped {
            break;
        }
    }
    for (slot, t) in tris.iter_mut().zip(plain) {
        slot.0 = t;
    }
    flips
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::cut::cut_along;
    use crate::sheet::cut::tests::line;
    use crate::sheet::pattern::lattice;

    fn flat_sheet() -> PhysMesh {
        PhysMesh::from_pattern(&lattice(0.1, 0.1, 0.1 / 9.0), 0.0, 0.08).unwrap()
    }

    /// Collapses every vertex from `first` on that can go, last first; returns the mesh.
    fn coarsen_all(mut sp: PhysMesh, first: usize) -> PhysMesh {
        loop {
            let next = (first..sp.num_vertices())
                .rev()
                .find_map(|v| collapse_vertex(&sp, v as u32, 0.01).ok());
            match next {
                Some(c) => sp = c.mesh,
                None => return sp,
            }
        }
    }

    #[test]
    fn a_cut_in_a_flat_sheet_is_taken_out_again() {
        let sp = flat_sheet();
        let cut = cut_along(&sp, &line(&sp, V2::new(0.003, -0.002), V2::new(0.8, 0.35))).unwrap();
        assert!(cut.added > 4);
        let before = cut.mesh.clone();
        let back = coarsen_all(cut.mesh, sp.num_vertices());
        back.topo.validate().unwrap();
        assert_eq!(back.topo.euler_characteristic(), 1);
        // Every vertex the cut added is gone, the lattice's are where they were.
        assert_eq!(back.num_vertices(), sp.num_vertices());
        assert_eq!(back.pattern, sp.pattern);
        assert_eq!(back.pos, sp.pos);
        assert_eq!(back.num_triangles(), sp.num_triangles());
        // Same outline and area, same total mass.
        let area = |m: &PhysMesh| m.tri_rest.iter().map(|r| r.area_m2).sum::<f64>();
        assert!((area(&back) - area(&sp)).abs() < 1e-15);
        assert!((back.total_mass_kg() - before.total_mass_kg()).abs() < 1e-15);
        // Well shaped: no angle under the insertion's minimum.
        let worst = worst_angle(&back.pattern, &back.triangles);
        assert!(worst >= MIN_ANGLE_RAD, "{worst}");
    }

    #[test]
    fn indices_after_the_removed_vertex_move_down_and_creases_follow_their_edges() {
        let sp = flat_sheet();
        let cut = cut_along(&sp, &line(&sp, V2::new(0.001, 0.004), V2::new(0.3, 0.9))).unwrap();
        let mut m = cut.mesh;
        let n0 = sp.num_vertices();
        // A crease on an old edge far from the cut, a singular vertex after the cut's.
        let far = (0..m.num_edges())
            .find(|&e| {
                let [a, b] = m.topo.edges[e].v;
                (a as usize) < n0
                    && (b as usize) < n0
                    && m.pattern[a as usize].x < -0.04
                    && !m.topo.edges[e].is_boundary()
            })
            .unwrap();
        m.edge_rest_angle[far] = 0.03;
        m.edge_damage[far] = 0.5;
        let far_v = m.topo.edges[far].v;
        let last = m.num_vertices() as u32 - 1;
        m.singular.push(last);
        let v = (n0 as u32..last)
            .find(|&v| collapse_vertex(&m, v, 0.01).is_ok())
            .expect("a cut vertex collapses");
        let c = collapse_vertex(&m, v, 0.01).unwrap();
        assert_eq!(c.removed, v);
        assert_eq!(c.new_index(v), None);
        assert_eq!(c.new_index(v - 1), Some(v - 1));
        assert_eq!(c.new_index(last), Some(last - 1));
        assert_eq!(c.mesh.singular, vec![last - 1]);
        assert_eq!(c.mesh.pattern[last as usize - 1], m.pattern[last as usize]);
        assert_eq!(c.mesh.vel[last as usize - 1], m.vel[last as usize]);
        let fe = c.mesh.topo.find_edge(far_v[0], far_v[1]).unwrap() as usize;
        assert_eq!(c.mesh.edge_rest_angle[fe], 0.03);
        assert_eq!(c.mesh.edge_damage[fe], 0.5);
        assert_eq!(c.tri_parent.len(), c.mesh.num_triangles());
        // Singular vertices and lattice corners stay.
        assert_eq!(
            collapse_vertex(&m, last, 0.01).unwrap_err(),
            CollapseError::Singular(last)
        );
        let corner = (0..sp.num_vertices() as u32)
            .min_by(|&a, &b| {
                let s = |i: u32| sp.pattern[i as usize].x + sp.pattern[i as usize].y;
                s(a).total_cmp(&s(b))
            })
            .unwrap();
        assert_eq!(
            collapse_vertex(&sp, corner, 0.01).unwrap_err(),
            CollapseError::Corner(corner)
        );
        assert_eq!(
            collapse_vertex(&m, m.num_vertices() as u32, 0.01).unwrap_err(),
            CollapseError::NoVertex(m.num_vertices() as u32)
        );
    }

    #[test]
    fn a_bent_or_creased_star_is_kept() {
        let sp = flat_sheet();
        let cut = cut_along(&sp, &line(&sp, V2::new(0.002, 0.001), V2::new(1.0, 0.2))).unwrap();
        let n0 = sp.num_vertices() as u32;
        let mut m = cut.mesh;
        let v = (n0..m.num_vertices() as u32)
            .find(|&v| !m.topo.vertex_on_boundary[v as usize])
            .unwrap();
        // Lift the vertex out of the plane: its star is bent.
        m.pos[v as usize].z += 0.002;
        assert!(matches!(
            collapse_vertex(&m, v, 0.01),
            Err(CollapseError::Bent(w, _)) if w == v
        ));
        m.pos[v as usize].z -= 0.002;
        let j = m.topo.neighbours(v)[0];
        let e = m.topo.find_edge(v, j).unwrap() as usize;
        m.edge_damage[e] = 0.1;
        assert_eq!(
            collapse_vertex(&m, v, 0.01).unwrap_err(),
            CollapseError::Creased(v)
        );
        m.edge_damage[e] = 0.0;
        assert!(collapse_vertex(&m, v, 0.01).is_ok());
    }
}
