//! # Regenerating S_P from S_G (the seeds' step (g), opt-in every frame), with state transfer
//!
//! The seeds rebuild the physical mesh S_P from the geometric structure S_G at the end of
//! every frame (TOG 2015 §4.1 and §5, `001_44bc28f7c5e9f81f.txt` P 351–354 and the frame loop's
//! step (g); thesis §2.4, `000_cb4d91e46ec5927f.txt` T 734–744; digest-crumpling §2.2, §3.8):
//! flat regions are sampled and Delaunay-triangulated, crease edges stay S_P edges, and every
//! curved region becomes quads between neighbouring rulings, each split into four triangles
//! about its barycentre, with the rulings as S_P edges; cone fans stay as they are; new
//! vertices take their 3D position and velocity from the previous S_P. Papier's default S_P
//! changes only at S_G's events ([`crate::geometry`], "Simplifications"; the reason, measured,
//! is `docs/sp-regeneration-plan.md`). This module is the per-frame regeneration itself
//! ([`regenerate`]); the sim runs it after every awake frame when
//! [`crate::geometry::GeometryConfig::regenerate_sp`] is on (`sim/remesh.rs`).
//!
//! ## What is regenerated, and what is kept
//!
//! S_G here is the persistent part ([`super::geometric::GeomStructure`]: corners, boundary
//! samples, singular vertices) and the layer's frame (regions as S_P triangle sets, rulings with
//! pattern and 3D endpoints). The regenerated S_P is a **constrained Delaunay triangulation**
//! (spade) of the pattern:
//!
//! - **Vertices kept** (index map old → new, old order, state copied exactly): every S_G
//!   vertex, every held vertex and every vertex of a holding hand (the sim's `must_keep`),
//!   every vertex of a flat or singular-fan triangle (the flat regions' samples are S_P's own:
//!   impl. choice, where the seeds draw new interior samples at ρ_int, digest §9 — our lattice
//!   already is a Delaunay triangulation of such samples), and every vertex of an edge with a
//!   rest angle or fibre damage.
//! - **Vertices dropped**: the rest, i.e. the vertices all of whose triangles are curved — a
//!   curved region's interior is rebuilt from its rulings each frame, as in the seeds.
//! - **Vertices added**: points along the rulings of each curved region and a barycentre per
//!   piece of each quad between neighbouring rulings (next section). A point within
//!   [`SNAP_FRAC`] of the lattice spacing h of a point already placed is that point; one within
//!   [`GAP_FRAC`] · h of a placed point, or within [`SNAP_FRAC`] · h of a kept edge, is left
//!   out (no sliver, and S_P stays about as fine as the lattice); a point near the sheet's
//!   border is put exactly on it.
//! - **Constraints** (edges the triangulation must have): every old edge between kept vertices
//!   that borders a flat or fan triangle or carries a rest angle or damage — so flat regions,
//!   creases and cone fans keep their triangles — then each ruling as the chain of its points
//!   (piece by piece, so the triangulation cannot slip a sliver between a piece and a point on
//!   it), each piece that crosses no constraint already in.
//!
//! ## Rulings used, and long rulings (impl. choices)
//!
//! The layer traces rulings about 1/ρ_bound = 0.83 cm apart (Table VI), a quarter of our
//! lattice spacing: taking all of them would make S_P four times as fine across the rulings as
//! along them. In each region the first ruling is used, then each one at least
//! [`RULING_SPACING_FRAC`] · h from the last one used (at its farther end). The seeds' quad
//! between two neighbouring rulings, split about its barycentre, has angles of about atan(w / L)
//! (5° for rulings 0.83 cm apart and 10 cm long) and its bending hinge is the whole ruling.
//! Here a ruling longer than h is cut into ⌈L / h⌉ equal pieces (points on the ruling, which
//! stays one straight chain of edges), and the quad into as many sub-quads, each with its own
//! barycentre (the midpoint of the pieces' midpoints), so the curved region's triangles are as
//! fine along the rulings as the lattice.
//!
//! ## State transfer
//!
//! A kept vertex keeps its 3D position and velocity. An added vertex takes both interpolated
//! (barycentric) in the old triangle under its pattern point (digest §2.2 item 5): on a curved
//! region that is the chord of the old triangle, within its sag of the surface. A point on a
//! ruling whose 3D length matches its pattern length within [`RULING_ISOMETRY_TOL`] is put on
//! the ruling's straight 3D segment instead — a developable surface is straight along its
//! rulings, so there the point is on the surface, not on a chord — unless that is more than
//! [`RULING_POINT_FRAC`] · h from the interpolated point (a ruling traced across a fold:
//! measured, unguarded placement on the rulings' segments gave one C1 edge 335 % longer than
//! its rest length). Rest data, hinges and lumped masses are rebuilt from the new pattern
//! ([`PhysMesh::from_pattern`]: the total mass is unchanged). An edge present in both meshes
//! keeps its rest angle and damage; a new edge starts flat and undamaged (the dropped region had
//! neither, by the rule above). Each triangle names the old triangle under its pattern centroid
//! ([`Regeneration::tri_parent`]). The sim then runs the isometry step on the new S_P (step
//! (h) after (g), as in the seeds' frame loop, digest §3.0).
//!
//! ## Refusals
//!
//! A triangle with an angle below [`REGEN_MIN_ANGLE_RAD`] has the added point at its widest
//! angle taken out and the triangulation redone (at most [`MAX_PASSES`] times); a thin
//! triangle of kept vertices only, a point outside the sheet, or a mesh that fails to build
//! refuses the regeneration ([`RegenError`]): S_P stays as it is that frame. The angle limit
//! is lower than an insertion's 12° ([`super::refine::MIN_ANGLE_RAD`]) because the seeds' own
//! barycentre split of a quad 0.8 cm wide and 5 cm long has angles of about 10°.
//!
//! Building a mesh allocates: the per-frame regeneration is an opt-in mode for offline study
//! (accuracy and cost against the default event-driven S_P, `sim-core/examples/regen_probe.rs`,
//! figures in `docs/sp-regeneration-plan.md`), not the plugin's steady state.

use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::refine::{locate, min_angle};
use crate::math::{V2, V3};
use crate::sheet::pattern::Pattern;
use crate::sheet::physical::{MeshError, PhysMesh};
use crate::sheet::topology::NONE;

/// A new point within this fraction of the lattice spacing of a vertex already placed is that
/// vertex.
pub const SNAP_FRAC: f64 = 0.25;

/// A new point farther than the snap distance but within this fraction of the lattice spacing
/// of a point already placed is left out: the regenerated S_P is about as fine as the lattice.
pub const GAP_FRAC: f64 = 0.6;

/// Most pieces a ruling is cut into.
const MAX_PIECES: usize = 64;

/// Rulings of one region closer than this fraction of the lattice spacing to the last one used
/// are not used (module doc, "Long rulings").
pub const RULING_SPACING_FRAC: f64 = 1.0;

/// A ruling whose 3D length is within this fraction of its pattern length is isometric: its new
/// points are put on its 3D segment (module doc, "State transfer").
pub const RULING_ISOMETRY_TOL: f64 = 0.01;

/// A point put on its ruling must lie within this fraction of the lattice spacing of the point
/// interpolated in the old S_P, or the interpolated one is used.
pub const RULING_POINT_FRAC: f64 = 0.1;

/// Most times a thin triangle's added point is taken out and the triangulation redone.
pub const MAX_PASSES: usize = 8;

/// Smallest pattern angle a regenerated triangle may have, radians (5°; module doc).
pub const REGEN_MIN_ANGLE_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// A ruling of a curved region, as the regeneration needs it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RulingLine {
    /// Region it belongs to (neighbouring rulings of one region come one after the other).
    pub region: u32,
    /// Pattern endpoints, metres.
    pub a2: V2,
    /// Pattern endpoints, metres.
    pub b2: V2,
    /// 3D endpoints, metres (interpolated on S_P).
    pub a3: V3,
    /// 3D endpoints, metres.
    pub b3: V3,
}

/// Why S_P was not regenerated.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum RegenError {
    /// The inputs do not match the mesh.
    #[error("regeneration inputs do not match S_P: {0}")]
    Mismatch(&'static str),
    /// A point could not be triangulated (not finite).
    #[error("a pattern point could not be triangulated")]
    Insertion,
    /// The triangulation has a thin triangle.
    #[error("a regenerated triangle has a {0:.1}° angle")]
    ThinTriangle(f64),
    /// An added point lies outside the old pattern.
    #[error("an added point lies outside the sheet")]
    Outside,
    /// The triangulation lost a kept vertex (two kept vertices at one point).
    #[error("vertex {0} was merged into another")]
    Merged(u32),
    /// The mesh could not be built.
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// A regenerated S_P.
#[derive(Clone, Debug)]
pub struct Regeneration {
    /// The new mesh, with its state.
    pub mesh: PhysMesh,
    /// For each old vertex, its new index, or [`NONE`] if it was dropped.
    pub old_to_new: Vec<u32>,
    /// For each new triangle, the old triangle under its pattern centroid.
    pub tri_parent: Vec<u32>,
    /// Vertices added (ruling endpoints and quad barycentres).
    pub added: u32,
    /// Old vertices dropped.
    pub dropped: u32,
    /// Rulings that are chains of S_P edges in the new mesh.
    pub rulings_as_edges: u32,
}

impl Regeneration {
    /// True if the new mesh is the old one (same vertices, same triangles as sets).
    pub fn unchanged(&self, old: &PhysMesh) -> bool {
        if self.added > 0 || self.dropped > 0 || self.mesh.num_triangles() != old.num_triangles() {
            return false;
        }
        let norm = |t: [u32; 3]| {
            let mut t = t;
            t.sort_unstable();
            t
        };
        let mut a: Vec<[u32; 3]> = old.triangles.iter().map(|&t| norm(t)).collect();
        let mut b: Vec<[u32; 3]> = self.mesh.triangles.iter().map(|&t| norm(t)).collect();
        // Kept vertices keep their order, so old and new indices agree when nothing is dropped.
        a.sort_unstable();
        b.sort_unstable();
        a == b
    }
}

/// Regenerates S_P (module doc). `tri_curved[t]`: old triangle t is in a curved region (not a
/// flat region, not a singular fan). `must_keep[v]`: old vertex v is an S_G vertex or held.
/// `rulings`: the traced rulings of the curved regions, ordered across each region.
/// `spacing_m`: the lattice spacing (sets the snap distance).
pub fn regenerate(
    sp: &PhysMesh,
    tri_curved: &[bool],
    must_keep: &[bool],
    rulings: &[RulingLine],
    spacing_m: f64,
) -> Result<Regeneration, RegenError> {
    let n_old = sp.num_vertices();
    if tri_curved.len() != sp.num_triangles() || must_keep.len() != n_old {
        return Err(RegenError::Mismatch("per-triangle or per-vertex lengths"));
    }
    // Which old vertices stay: those with a non-curved triangle, S_G and held vertices, and the
    // ends of creased or damaged edges.
    let mut keep = must_keep.to_vec();
    for (t, tri) in sp.triangles.iter().enumerate() {
        if !tri_curved[t] {
            for &v in tri {
                keep[v as usize] = true;
            }
        }
    }
    for &s in &sp.singular {
        keep[s as usize] = true;
    }
    for (e, edge) in sp.topo.edges.iter().enumerate() {
        if sp.edge_rest_angle[e] != 0.0 || sp.edge_damage[e] != 0.0 {
            keep[edge.v[0] as usize] = true;
            keep[edge.v[1] as usize] = true;
        }
    }
    let mut old_to_new = vec![NONE; n_old];
    let mut points: Vec<V2> = Vec::with_capacity(n_old + 3 * rulings.len());
    for v in 0..n_old {
        if keep[v] {
            old_to_new[v] = points.len() as u32;
            points.push(sp.pattern[v]);
        }
    }
    let n_kept = points.len();
    // The kept structure's edges (constraints below): flat-region, fan and creased edges.
    let kept_edges: Vec<(usize, [u32; 2])> = sp
        .topo
        .edges
        .iter()
        .enumerate()
        .filter(|&(e, edge)| {
            let flat_side = edge
                .he
                .iter()
                .filter(|&&h| h != NONE)
                .any(|&h| !tri_curved[sp.topo.half_edges[h as usize].face as usize]);
            let creased = sp.edge_rest_angle[e] != 0.0 || sp.edge_damage[e] != 0.0;
            flat_side || creased
        })
        .map(|(e, edge)| (e, edge.v.map(|v| old_to_new[v as usize])))
        .collect();
    let snap_m = SNAP_FRAC * spacing_m;
    let snap2 = snap_m * snap_m;
    let gap2 = (GAP_FRAC * spacing_m).powi(2);
    let border = BorderBox::of(sp);
    // A point within the snap distance of a kept vertex or a point already added is that point;
    // one that close to a kept edge (but not its ends) would make a sliver and is not added.
    let near_kept_edge = |p: V2, points: &[V2]| {
        kept_edges.iter().any(|&(_, [a, b])| {
            let (pa, pb) = (points[a as usize], points[b as usize]);
            let d = pb - pa;
            let t = ((p - pa).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
            (pa + d * t - p).norm_squared() < snap2
        })
    };
    // The old vertex each point is, NONE for a new point.
    let mut origin: Vec<u32> = (0..n_old as u32).filter(|&v| keep[v as usize]).collect();
    let nearest = |p: V2, points: &[V2]| {
        points
            .iter()
            .map(|q| (q - p).norm_squared())
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(&b.1))
    };
    let fits = |p: V2, points: &[V2]| {
        nearest(p, points).is_none_or(|(_, d2)| d2 >= gap2) && !near_kept_edge(p, &points[..n_kept])
    };
    // The 3D point of each new point on a ruling, where the ruling is straight and isometric
    // (module doc, "State transfer").
    let mut on_ruling: Vec<Option<V3>> = Vec::with_capacity(points.capacity());
    let mut add = |p: V2, p3: Option<V3>, points: &mut Vec<V2>| -> u32 {
        let p = border.onto(p, snap_m);
        if let Some((i, d2)) = nearest(p, points)
            && d2 < snap2
        {
            return i as u32;
        }
        if !fits(p, points) {
            return NONE;
        }
        points.push(p);
        origin.push(NONE);
        on_ruling.push(p3);
        (points.len() - 1) as u32
    };
    // Segments per ruling: rulings are cut into pieces no longer than the lattice spacing
    // (module doc, "Long rulings").
    let pieces = |len: f64| ((len / spacing_m).ceil() as usize).clamp(1, MAX_PIECES);
    // Each ruling as the chain of its points in order, ends first: a point snapped onto another
    // is that one, a point left out is skipped.
    let rulings = &spaced(rulings, RULING_SPACING_FRAC * spacing_m);
    let mut chains: Vec<Vec<u32>> = Vec::with_capacity(rulings.len());
    for r in rulings {
        if !(r.a2.x.is_finite() && r.a2.y.is_finite() && r.b2.x.is_finite() && r.b2.y.is_finite()) {
            return Err(RegenError::Insertion);
        }
        let k = pieces((r.b2 - r.a2).norm());
        let mut chain = Vec::with_capacity(k + 1);
        for j in 0..=k {
            let f = j as f64 / k as f64;
            let isometric =
                ((r.b3 - r.a3).norm() / (r.b2 - r.a2).norm() - 1.0).abs() < RULING_ISOMETRY_TOL;
            let p3 = isometric.then(|| r.a3 + (r.b3 - r.a3) * f);
            let v = add(r.a2 + (r.b2 - r.a2) * f, p3, &mut points);
            if v != NONE && chain.last() != Some(&v) {
                chain.push(v);
            }
        }
        chains.push(chain);
    }
    for i in 1..rulings.len() {
        let (r0, r1) = (&rulings[i - 1], &rulings[i]);
        if r0.region != r1.region {
            continue;
        }
        // The quad's corners in order (the second ruling may run the other way).
        let (p, q) = if (r0.a2 - r1.a2).norm_squared() <= (r0.a2 - r1.b2).norm_squared() {
            (r1.a2, r1.b2)
        } else {
            (r1.b2, r1.a2)
        };
        let k = pieces((r0.b2 - r0.a2).norm().max((q - p).norm()));
        for j in 0..k {
            let f = (j as f64 + 0.5) / k as f64;
            let c = (r0.a2 + (r0.b2 - r0.a2) * f + p + (q - p) * f) / 2.0;
            add(c, None, &mut points);
        }
    }

    // Triangulate; an added point at the widest angle of a thin triangle is taken out and the
    // triangulation redone (module doc, "Refusals").
    let mut alive = vec![true; points.len()];
    let mut triangles;
    let mut pass = 0;
    loop {
        triangles = triangulate(&points, &alive, n_kept, &kept_edges, &chains)?;
        let mut thinnest = f64::MAX;
        let mut taken_out = false;
        for t in &triangles {
            let c = t.map(|i| points[i as usize]);
            let ang = min_angle(c[0], c[1], c[2]);
            if ang >= REGEN_MIN_ANGLE_RAD {
                continue;
            }
            thinnest = thinnest.min(ang);
            let widest = (0..3)
                .filter(|&k| t[k] as usize >= n_kept && alive[t[k] as usize])
                .max_by(|&i, &j| {
                    corner_angle(&c, i)
                        .total_cmp(&corner_angle(&c, j))
                        .then(j.cmp(&i))
                });
            if let Some(k) = widest {
                alive[t[k] as usize] = false;
                taken_out = true;
            }
        }
        if thinnest == f64::MAX {
            break;
        }
        if !taken_out || pass == MAX_PASSES {
            return Err(RegenError::ThinTriangle(thinnest.to_degrees()));
        }
        pass += 1;
    }
    // The points left, renumbered: old vertices first, in their old order (so a regeneration
    // that changes nothing gives S_P back, index for index), then the new points.
    let mut order: Vec<usize> = (0..points.len()).filter(|&i| alive[i]).collect();
    order.sort_by_key(|&i| (origin[i] == NONE, origin[i], i));
    let mut renumber = vec![NONE; points.len()];
    for (rank, &i) in order.iter().enumerate() {
        renumber[i] = rank as u32;
    }
    old_to_new.fill(NONE);
    for &i in &order {
        if origin[i] != NONE {
            old_to_new[origin[i] as usize] = renumber[i];
        }
    }
    let on_ruling: Vec<Option<V3>> = order
        .iter()
        .map(|&i| i.checked_sub(n_kept).and_then(|k| on_ruling[k]))
        .collect();
    let origin: Vec<u32> = order.iter().map(|&i| origin[i]).collect();
    let points: Vec<V2> = order.iter().map(|&i| points[i]).collect();
    for t in &mut triangles {
        *t = t.map(|i| renumber[i as usize]);
    }
    let ends: Vec<[u32; 2]> = chains
        .iter()
        .map(|c| match (c.first(), c.last()) {
            (Some(&a), Some(&b)) if c.len() > 1 => [renumber[a as usize], renumber[b as usize]],
            _ => [NONE, NONE],
        })
        .collect();
    let n_old_left = origin.iter().filter(|&&o| o != NONE).count();
    let added = points.len() - n_old_left;

    // State: old vertices copied, new ones interpolated in the old triangle under them.
    let mut pos: Vec<V3> = Vec::with_capacity(points.len());
    let mut vel: Vec<V3> = Vec::with_capacity(points.len());
    let near_m = RULING_POINT_FRAC * spacing_m;
    for ((p, &o), p3) in points.iter().zip(&origin).zip(&on_ruling) {
        if o != NONE {
            pos.push(sp.pos[o as usize]);
            vel.push(sp.vel[o as usize]);
            continue;
        }
        let (t, l) = locate(&sp.pattern, &sp.triangles, *p).ok_or(RegenError::Outside)?;
        let tri = sp.triangles[t];
        let lerp = |x: &[V3]| {
            tri.iter()
                .zip(l)
                .fold(V3::zeros(), |s, (&i, w)| s + x[i as usize] * w)
        };
        let chord = lerp(&sp.pos);
        pos.push(
            p3.filter(|q| q.iter().all(|c| c.is_finite()) && (q - chord).norm() < near_m)
                .unwrap_or(chord),
        );
        vel.push(lerp(&sp.vel));
    }
    let tri_parent: Vec<u32> = triangles
        .iter()
        .map(|t| {
            let c = t.iter().fold(V2::zeros(), |s, &i| s + points[i as usize]) / 3.0;
            locate(&sp.pattern, &sp.triangles, c).map_or(0, |(pt, _)| pt as u32)
        })
        .collect();
    let mut new_to_old = vec![NONE; points.len()];
    for (o, &n) in old_to_new.iter().enumerate() {
        if n != NONE {
            new_to_old[n as usize] = o as u32;
        }
    }
    let pattern = Pattern { points, triangles };
    let mut mesh = PhysMesh::from_pattern(&pattern, 0.0, sp.areal_density_kg_m2)?;
    mesh.pos = pos;
    mesh.vel = vel;
    mesh.inherit_edge_state(sp, |v| {
        let [a, b] = v.map(|v| new_to_old[v as usize]);
        (a != NONE && b != NONE).then_some([a, b])
    });
    mesh.singular = sp
        .singular
        .iter()
        .map(|&s| old_to_new[s as usize])
        .collect();
    mesh.rest_version = sp.rest_version + 1;
    let rulings_as_edges = ends
        .iter()
        .filter(|&&[a, b]| a != b && a != NONE && b != NONE && is_edge_chain(&mesh, a, b))
        .count() as u32;
    Ok(Regeneration {
        mesh,
        old_to_new,
        tri_parent,
        added: added as u32,
        dropped: (n_old - n_old_left) as u32,
        rulings_as_edges,
    })
}

/// The rulings used: in each region (rulings come region by region, in order across it), the
/// first, then each one whose farther end is at least `min_m` from the corresponding end of the
/// last one used.
fn spaced(rulings: &[RulingLine], min_m: f64) -> Vec<RulingLine> {
    let mut used: Vec<RulingLine> = Vec::with_capacity(rulings.len());
    for r in rulings {
        let far = used
            .last()
            .filter(|l| l.region == r.region)
            .is_none_or(|l| {
                let same = (l.a2 - r.a2).norm().max((l.b2 - r.b2).norm());
                let reversed = (l.a2 - r.b2).norm().max((l.b2 - r.a2).norm());
                same.min(reversed) >= min_m
            });
        if far {
            used.push(*r);
        }
    }
    used
}

/// The constrained Delaunay triangulation of the live `points` (kept ones first: `n_kept`),
/// with the kept edges and the rulings' chains (between live points) as constraints; triangles
/// in `points` indices.
fn triangulate(
    points: &[V2],
    alive: &[bool],
    n_kept: usize,
    kept_edges: &[(usize, [u32; 2])],
    chains: &[Vec<u32>],
) -> Result<Vec<[u32; 3]>, RegenError> {
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::new();
    let mut handles = vec![None; points.len()];
    let mut point_of = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate().filter(|&(i, _)| alive[i]) {
        let h = cdt
            .insert(Point2::new(p.x, p.y))
            .map_err(|_| RegenError::Insertion)?;
        // Two points on one position are one vertex to spade: each point must stay its own.
        if h.index() != point_of.len() {
            return Err(RegenError::Merged(if i < n_kept { i as u32 } else { NONE }));
        }
        point_of.push(i as u32);
        handles[i] = Some(h);
    }
    // Constraints: the kept structure first, then the rulings' pieces that fit.
    let pairs = kept_edges
        .iter()
        .map(|&(_, e)| e)
        .chain(chains.iter().flat_map(|c| {
            let live: Vec<u32> = c.iter().copied().filter(|&v| alive[v as usize]).collect();
            live.windows(2).map(|w| [w[0], w[1]]).collect::<Vec<_>>()
        }));
    for [a, b] in pairs {
        if let (Some(ha), Some(hb)) = (handles[a as usize], handles[b as usize])
            && ha != hb
            && cdt.can_add_constraint(ha, hb)
        {
            cdt.add_constraint(ha, hb);
        }
    }
    Ok(cdt
        .inner_faces()
        .map(|f| f.vertices().map(|v| point_of[v.fix().index()]))
        .collect())
}

/// The angle of triangle `c` at corner `k`, radians.
fn corner_angle(c: &[V2; 3], k: usize) -> f64 {
    let (u, w) = (c[(k + 1) % 3] - c[k], c[(k + 2) % 3] - c[k]);
    u.perp(&w).abs().atan2(u.dot(&w))
}

/// True if the straight pattern segment from vertex `a` to vertex `b` of `mesh` is a chain of
/// its edges (each step an edge to a vertex on the segment, closer to `b`).
pub fn is_edge_chain(mesh: &PhysMesh, a: u32, b: u32) -> bool {
    let (pa, pb) = (mesh.pattern[a as usize], mesh.pattern[b as usize]);
    let d = pb - pa;
    let len2 = d.norm_squared();
    if len2 <= 0.0 {
        return false;
    }
    let tol = 1e-9 * len2.sqrt();
    let mut at = a;
    for _ in 0..mesh.num_vertices() {
        if at == b {
            return true;
        }
        let t_at = (mesh.pattern[at as usize] - pa).dot(&d) / len2;
        let next = mesh.topo.neighbours(at).iter().copied().find(|&w| {
            let q = mesh.pattern[w as usize] - pa;
            (d.perp(&q) / len2.sqrt()).abs() < tol && q.dot(&d) / len2 > t_at
        });
        match next {
            Some(w) => at = w,
            None => return false,
        }
    }
    false
}

/// The sheet's rectangular outline in the pattern (its boundary vertices' bounding box): points
/// near it are put exactly on it.
struct BorderBox {
    lo: V2,
    hi: V2,
}

impl BorderBox {
    fn of(sp: &PhysMesh) -> Self {
        let (mut lo, mut hi) = (V2::repeat(f64::MAX), V2::repeat(f64::MIN));
        for q in &sp.pattern {
            lo = lo.inf(q);
            hi = hi.sup(q);
        }
        Self { lo, hi }
    }

    /// `p` clamped into the box, and put on a side it is within `snap_m` of.
    fn onto(&self, p: V2, snap_m: f64) -> V2 {
        let mut p = p.sup(&self.lo).inf(&self.hi);
        for k in 0..2 {
            if p[k] - self.lo[k] < snap_m * 1e-3 {
                p[k] = self.lo[k];
            } else if self.hi[k] - p[k] < snap_m * 1e-3 {
                p[k] = self.hi[k];
            }
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::pattern::lattice;

    fn sheet() -> PhysMesh {
        PhysMesh::from_pattern(&lattice(0.1, 0.1, 0.1 / 9.0), 0.0, 0.08).unwrap()
    }

    /// Nothing curved: the regenerated mesh is S_P itself, state and all.
    #[test]
    fn a_flat_sheet_regenerates_to_itself() {
        let sp = sheet();
        let r = regenerate(
            &sp,
            &vec![false; sp.num_triangles()],
            &vec![false; sp.num_vertices()],
            &[],
            0.1 / 9.0,
        )
        .unwrap();
        assert!(r.unchanged(&sp));
        assert_eq!(
            r.old_to_new,
            (0..sp.num_vertices() as u32).collect::<Vec<_>>()
        );
        assert_eq!(r.added, 0);
        assert_eq!(r.dropped, 0);
    }

    /// A curved band across the sheet with rulings across it: its interior vertices go, the
    /// rulings become edge chains with barycentres between them, the state is interpolated and
    /// the mass kept; a creased edge and a singular vertex survive.
    #[test]
    fn a_curved_band_is_rebuilt_from_its_rulings() {
        let mut sp = sheet();
        // Bend the sheet along x (a cylinder about the y axis), moving at 1 m/s in z.
        let radius_m = 0.05;
        let on_cylinder = |q: V2| {
            let (s, c) = (q.x / radius_m).sin_cos();
            V3::new(radius_m * s, q.y, radius_m * (1.0 - c))
        };
        for (p, q) in sp.pos.iter_mut().zip(&sp.pattern) {
            *p = on_cylinder(*q);
        }
        for v in &mut sp.vel {
            *v = V3::new(0.0, 0.0, 1.0);
        }
        let tri_curved: Vec<bool> = sp
            .triangles
            .iter()
            .map(|t| t.iter().all(|&v| sp.pattern[v as usize].x.abs() < 0.03))
            .collect();
        // A creased edge inside the band keeps its ends.
        let crease = (0..sp.num_edges())
            .find(|&e| {
                let [a, b] = sp.topo.edges[e].v;
                let (pa, pb) = (sp.pattern[a as usize], sp.pattern[b as usize]);
                pa.x.abs() < 0.006 && pb.x.abs() < 0.006 && pa.y.abs() < 0.02
            })
            .unwrap();
        sp.edge_damage[crease] = 0.5;
        // Rulings 0.68 h apart: every other one is used (RULING_SPACING_FRAC).
        let ruling_x = |i: i32| -0.015 + 0.0075 * f64::from(i);
        let rulings: Vec<RulingLine> = (0..5)
            .map(|i| {
                let (a2, b2) = (V2::new(ruling_x(i), -0.05), V2::new(ruling_x(i), 0.05));
                RulingLine {
                    region: 0,
                    a2,
                    b2,
                    a3: on_cylinder(a2),
                    b3: on_cylinder(b2),
                }
            })
            .collect();
        let mass0 = sp.total_mass_kg();
        let r = regenerate(
            &sp,
            &tri_curved,
            &vec![false; sp.num_vertices()],
            &rulings,
            0.1 / 9.0,
        )
        .unwrap();
        assert!(
            r.dropped > 0 && r.added > 0,
            "{} dropped, {} added",
            r.dropped,
            r.added
        );
        assert!(!r.unchanged(&sp));
        r.mesh.topo.validate().unwrap();
        assert_eq!(r.mesh.topo.euler_characteristic(), 1);
        assert!((r.mesh.total_mass_kg() - mass0).abs() < 1e-12 * mass0);
        // The rulings used (x = −1.5, 0, 1.5 cm) are edge chains, but perhaps the one through
        // the crease.
        assert!(
            r.rulings_as_edges >= 2,
            "{} rulings are edges",
            r.rulings_as_edges
        );
        // Transferred state: moving as it did, on the old surface.
        let mut on_rulings = 0;
        for ((p, v), q) in r.mesh.pos.iter().zip(&r.mesh.vel).zip(&r.mesh.pattern) {
            assert!((v - V3::new(0.0, 0.0, 1.0)).norm() < 1e-12);
            assert!(p.iter().all(|c| c.is_finite()));
            // On the cylinder where a ruling (straight, isometric) carries the point, else on
            // a chord of the lattice's triangles (sagging by at most h² / 8r = 0.3 mm).
            let radial = (p.x * p.x + (p.z - radius_m).powi(2)).sqrt();
            assert!(
                radial <= radius_m + 1e-12 && radial >= radius_m - 4e-4,
                "{p:?} at {q:?}"
            );
            if [0, 4].iter().any(|&i| (q.x - ruling_x(i)).abs() < 1e-12) {
                assert!((p - on_cylinder(*q)).norm() < 1e-12, "{p:?} at {q:?}");
                on_rulings += 1;
            }
        }
        assert!(on_rulings >= 2 * 9, "{on_rulings} vertices on the rulings");
        let [a, b] = sp.topo.edges[crease].v;
        let (na, nb) = (r.old_to_new[a as usize], r.old_to_new[b as usize]);
        let ne = r.mesh.topo.find_edge(na, nb).expect("the crease is kept") as usize;
        assert_eq!(r.mesh.edge_damage[ne], 0.5);
        assert_eq!(r.tri_parent.len(), r.mesh.num_triangles());
    }

    /// The same inputs give the same mesh, bit for bit.
    #[test]
    fn regeneration_is_deterministic() {
        let sp = sheet();
        let tri_curved: Vec<bool> = (0..sp.num_triangles()).map(|t| t % 3 == 0).collect();
        let rulings = [RulingLine {
            region: 0,
            a2: V2::new(-0.01, -0.05),
            b2: V2::new(0.012, 0.05),
            a3: V3::new(-0.01, -0.05, 0.0),
            b3: V3::new(0.012, 0.05, 0.0),
        }];
        let go = || {
            regenerate(
                &sp,
                &tri_curved,
                &vec![false; sp.num_vertices()],
                &rulings,
                0.1 / 9.0,
            )
        };
        match (go(), go()) {
            (Ok(a), Ok(b)) => {
                assert_eq!(a.mesh.triangles, b.mesh.triangles);
                assert_eq!(a.mesh.pattern, b.mesh.pattern);
                assert_eq!(a.old_to_new, b.old_to_new);
            }
            (Err(a), Err(b)) => assert_eq!(a, b),
            (a, b) => panic!("{a:?} / {b:?}"),
        }
    }
}
