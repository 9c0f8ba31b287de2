//! # Unzipping S_P along a chain of edges: the torn lips
//!
//! A tear separates the sheet along its torn edge (MIG 2015 §3, `003_8cfb4a33a3603fcd.txt`
//! M:85–101; thesis §3.2–3.3, `000_cb4d91e46ec5927f.txt` T:1331, T:1562–1573; tearing-plan §2).
//! Once the torn edge is a chain of S_P edges ([`super::cut::cut_along`] makes a pattern line
//! one), [`unzip`] opens it: each chain vertex the tear has passed gets a twin, the triangles on
//! the chain's right keep the twin and those on its left the vertex, so the two lips are two
//! boundaries with their own vertices at the same pattern point. The chain starts on the sheet's
//! boundary (a tear starts at an edge, M:114); its last vertex is the crack tip and stays one
//! vertex (a slit disc is still a disc), unless it is on the boundary too: then the tear has
//! crossed the sheet and it splits as well, leaving two pieces.
//!
//! Nothing moves: a twin has its vertex's pattern point, 3D position and velocity, every
//! triangle keeps its pattern shape (no overlap, the same area), and every edge keeps its rest
//! angle and damage. Masses are lumped again from the triangles (the total is unchanged).
//! Building a mesh allocates: an unzip is an announced mesh change, like a cut.
//!
//! Decisions, one line each:
//! - The sides are found by turning round each chain vertex through its triangles without
//!   crossing a chain edge (topology, not pattern geometry: a jagged chain has no "side" a
//!   local line test reads reliably).
//! - Left keeps the old index, right gets the twin, appended in chain order: old vertices keep
//!   their indices, so the state that names them (singular vertices, grips) still holds.

use crate::math::V2;
use crate::sheet::pattern::Pattern;
use crate::sheet::physical::{MeshError, PhysMesh};

/// An unzipped S_P.
#[derive(Clone, Debug)]
pub struct Unzip {
    /// The opened mesh (state transferred).
    pub mesh: PhysMesh,
    /// Per twin, in order (their indices follow the old vertices'): the vertex it twins.
    pub twin_of: Vec<u32>,
}

/// Why a chain cannot be unzipped.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum UnzipError {
    /// Fewer than two vertices.
    #[error("a chain needs at least two vertices")]
    Short,
    /// A vertex index beyond the mesh, or twice in the chain.
    #[error("vertex {0} is not a fresh vertex of the mesh")]
    BadVertex(u32),
    /// Two consecutive vertices share no interior edge (an edge already on the boundary is
    /// already open).
    #[error("no interior edge between vertices {0} and {1}")]
    NotAnInteriorEdge(u32, u32),
    /// The chain does not start on the boundary.
    #[error("the chain starts at vertex {0}, inside the sheet")]
    StartsInside(u32),
    /// A vertex's triangles are not separated by the chain (it touches the boundary where the
    /// chain passes through it).
    #[error("the chain does not separate the triangles round vertex {0}")]
    NotSeparated(u32),
    /// The opened mesh is not valid.
    #[error("the opened mesh is invalid: {0}")]
    Mesh(#[from] MeshError),
}

/// Opens `sp` along `chain` (module doc). Errors leave `sp` as it was.
pub fn unzip(sp: &PhysMesh, chain: &[u32]) -> Result<Unzip, UnzipError> {
    if chain.len() < 2 {
        return Err(UnzipError::Short);
    }
    let n0 = sp.num_vertices();
    for (i, &v) in chain.iter().enumerate() {
        if v as usize >= n0 || chain[..i].contains(&v) {
            return Err(UnzipError::BadVertex(v));
        }
    }
    for w in chain.windows(2) {
        let interior = sp
            .topo
            .find_edge(w[0], w[1])
            .is_some_and(|e| !sp.topo.edges[e as usize].is_boundary());
        if !interior {
            return Err(UnzipError::NotAnInteriorEdge(w[0], w[1]));
        }
    }
    let on_boundary = |v: u32| sp.topo.vertex_on_boundary[v as usize];
    if !on_boundary(chain[0]) {
        return Err(UnzipError::StartsInside(chain[0]));
    }
    let last = chain.len() - 1;
    let splits = if on_boundary(chain[last]) {
        last + 1
    } else {
        last
    };
    let mut triangles = sp.triangles.clone();
    let mut twin_of = Vec::with_capacity(splits);
    for i in 0..splits {
        let c = chain[i];
        // The chain edges at c: a triangle crossing none of them is on c's one side.
        let prev = (i > 0).then(|| chain[i - 1]);
        let next = (i < last).then(|| chain[i + 1]);
        let is_chain = |x: u32| Some(x) == prev || Some(x) == next;
        let fan: Vec<usize> = (0..triangles.len())
            .filter(|&t| triangles[t].contains(&c))
            .collect();
        // The left side: the triangle left of the chain's direction at c, and every triangle
        // reached from it round c without crossing a chain edge.
        let seed = fan.iter().copied().find(|&t| match next {
            Some(n) => has_directed(&triangles[t], c, n),
            None => prev.is_some_and(|p| has_directed(&triangles[t], p, c)),
        });
        let Some(seed) = seed else {
            return Err(UnzipError::NotSeparated(c));
        };
        let mut left = vec![seed];
        let mut k = 0;
        while k < left.len() {
            let t = left[k];
            k += 1;
            for &x in &triangles[t] {
                if x == c || is_chain(x) {
                    continue;
                }
                for &u in &fan {
                    if !left.contains(&u) && triangles[u].contains(&x) {
                        left.push(u);
                    }
                }
            }
        }
        if left.len() == fan.len() {
            return Err(UnzipError::NotSeparated(c));
        }
        let twin = (n0 + twin_of.len()) as u32;
        for &t in fan.iter().filter(|t| !left.contains(t)) {
            for v in &mut triangles[t] {
                if *v == c {
                    *v = twin;
                }
            }
        }
        twin_of.push(c);
    }
    let original = |v: u32| {
        if (v as usize) < n0 {
            v
        } else {
            twin_of[v as usize - n0]
        }
    };
    let mut points: Vec<V2> = sp.pattern.clone();
    points.extend(twin_of.iter().map(|&v| sp.pattern[v as usize]));
    let mut mesh =
        PhysMesh::from_pattern(&Pattern { points, triangles }, 0.0, sp.areal_density_kg_m2)?;
    mesh.pos.clone_from(&sp.pos);
    mesh.pos.extend(twin_of.iter().map(|&v| sp.pos[v as usize]));
    mesh.vel.clone_from(&sp.vel);
    mesh.vel.extend(twin_of.iter().map(|&v| sp.vel[v as usize]));
    mesh.inherit_edge_state(sp, |[a, b]| Some([original(a), original(b)]));
    mesh.singular.clone_from(&sp.singular);
    mesh.rest_version = sp.rest_version + 1;
    Ok(Unzip { mesh, twin_of })
}

/// True if triangle `t` has the directed edge a → b (counter-clockwise).
fn has_directed(t: &[u32; 3], a: u32, b: u32) -> bool {
    (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::SheetSize;
    use crate::sheet::cut::{cut_along, line_crossings};
    use crate::sheet::refine::tests::bent_sheet as sheet;
    use crate::sheet::{MeshConfig, Sheet};

    fn area(sp: &PhysMesh) -> f64 {
        sp.tri_rest.iter().map(|r| r.area_m2).sum()
    }

    /// A sheet cut along the pattern line through `o` along `d`, border to border, and the
    /// chain of edges the cut made (`None` if the line runs along edges: nothing to cut).
    fn chain(o: V2, d: V2) -> Option<(PhysMesh, Vec<u32>)> {
        let sp = sheet();
        let crossings = line_crossings(&sp, o, d).unwrap();
        match cut_along(&sp, &crossings) {
            Ok(cut) => Some((cut.mesh, cut.chain)),
            Err(crate::sheet::cut::CutError::NothingToCut) => None,
            Err(e) => panic!("cut: {e}"),
        }
    }

    fn checked(sp: &PhysMesh, u: &Unzip, pieces_expected: usize) {
        u.mesh.topo.validate().unwrap();
        assert_eq!(u.mesh.topo.validate_pieces(), Ok(pieces_expected));
        assert!((area(&u.mesh) - area(sp)).abs() <= 1e-9 * area(sp));
        assert!((u.mesh.total_mass_kg() - sp.total_mass_kg()).abs() <= 1e-12);
        // Same triangles in the pattern, same places in 3D.
        for (a, b) in sp.triangles.iter().zip(&u.mesh.triangles) {
            for k in 0..3 {
                assert_eq!(sp.pattern[a[k] as usize], u.mesh.pattern[b[k] as usize]);
                assert_eq!(sp.pos[a[k] as usize], u.mesh.pos[b[k] as usize]);
            }
        }
        for (e, ed) in u.mesh.topo.edges.iter().enumerate() {
            let orig = |v: u32| {
                if (v as usize) < sp.num_vertices() {
                    v
                } else {
                    u.twin_of[v as usize - sp.num_vertices()]
                }
            };
            let old = sp.topo.find_edge(orig(ed.v[0]), orig(ed.v[1])).unwrap() as usize;
            assert_eq!(u.mesh.edge_rest_angle[e], sp.edge_rest_angle[old]);
            assert_eq!(u.mesh.edge_damage[e], sp.edge_damage[old]);
        }
    }

    /// Chains of lattice edges across a flat sheet: each row of vertices (one pattern y),
    /// where consecutive vertices share an edge, from border to border.
    fn rows(sp: &PhysMesh) -> Vec<Vec<u32>> {
        let mut ys: Vec<f64> = sp.pattern.iter().map(|p| p.y).collect();
        ys.sort_by(f64::total_cmp);
        ys.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        ys.iter()
            .filter_map(|&y| {
                let mut row: Vec<u32> = (0..sp.num_vertices() as u32)
                    .filter(|&v| (sp.pattern[v as usize].y - y).abs() < 1e-9)
                    .collect();
                row.sort_by(|&a, &b| {
                    sp.pattern[a as usize]
                        .x
                        .total_cmp(&sp.pattern[b as usize].x)
                });
                let joined = row
                    .windows(2)
                    .all(|w| sp.topo.find_edge(w[0], w[1]).is_some());
                (joined && row.len() > 2).then_some(row)
            })
            .collect()
    }

    #[test]
    fn a_tear_across_the_sheet_leaves_two_discs_with_the_sheets_area() {
        for size in [SheetSize::Sq10, SheetSize::A6] {
            let mut sp = Sheet::new_flat(size, MeshConfig::default(), 0.0, 0.08).sp;
            // Some state to carry over: a bent, damaged edge and a moving sheet.
            sp.edge_rest_angle[7] = 0.3;
            sp.edge_damage[7] = 1.5;
            for (i, v) in sp.vel.iter_mut().enumerate() {
                v.z = i as f64 * 1e-3;
            }
            let rows = rows(&sp);
            // The rows strictly inside (the outermost run along the border).
            let inner = &rows[1..rows.len() - 1];
            assert!(inner.len() >= 3, "{} rows", inner.len());
            for c in inner {
                let u = unzip(&sp, c).unwrap_or_else(|e| panic!("row {c:?}: {e}"));
                assert_eq!(&u.twin_of, c, "every chain vertex splits");
                checked(&sp, &u, 2);
            }
        }
    }

    #[test]
    fn a_tear_into_the_sheet_opens_a_slit_and_keeps_one_piece() {
        let (sp, c) = chain(V2::new(0.002, 0.001), V2::new(0.9, 0.3)).unwrap();
        let part = &c[..c.len() / 2];
        let u = unzip(&sp, part).unwrap();
        assert_eq!(
            u.twin_of,
            part[..part.len() - 1],
            "the tip stays one vertex"
        );
        checked(&sp, &u, 1);
        // The slit's two lips are boundary edges, the tip a boundary vertex.
        let tip = *part.last().unwrap();
        assert!(u.mesh.topo.vertex_on_boundary[tip as usize]);
        for (i, &v) in part[..part.len() - 1].iter().enumerate() {
            let twin = (sp.num_vertices() + i) as u32;
            assert!(u.mesh.topo.vertex_on_boundary[v as usize]);
            assert!(u.mesh.topo.vertex_on_boundary[twin as usize]);
        }
        // Reversed, the chain starts at the tip, inside the sheet.
        let rev: Vec<u32> = part.iter().rev().copied().collect();
        assert_eq!(unzip(&sp, &rev).unwrap_err(), UnzipError::StartsInside(tip));
    }

    #[test]
    fn chains_that_are_not_tears_are_refused() {
        let sp = sheet();
        assert_eq!(unzip(&sp, &[3]).unwrap_err(), UnzipError::Short);
        let n = sp.num_vertices() as u32;
        assert_eq!(unzip(&sp, &[0, n]).unwrap_err(), UnzipError::BadVertex(n));
        // A boundary edge is open already.
        let b = sp.topo.edges.iter().find(|e| e.is_boundary()).unwrap().v;
        assert_eq!(
            unzip(&sp, &[b[0], b[1]]).unwrap_err(),
            UnzipError::NotAnInteriorEdge(b[0], b[1])
        );
        // Two vertices sharing no edge.
        let far = (0..n)
            .find(|&v| sp.topo.find_edge(0, v).is_none() && v != 0)
            .unwrap();
        assert_eq!(
            unzip(&sp, &[0, far]).unwrap_err(),
            UnzipError::NotAnInteriorEdge(0, far)
        );
    }
}
