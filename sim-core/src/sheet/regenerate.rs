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
//! pattern endpoints). The regenerated S_P is a **constrained Delaunay triangulation** (spade)
//! of the pattern:
//!
//! - **Vertices kept** (index map old → new, state copied exactly): every S_G vertex, every
//!   held vertex, every vertex of a flat or singular-fan triangle (the flat regions' samples are
//!   S_P's own: impl. choice, where the seeds draw new interior samples at ρ_int, digest §9 —
//!   our lattice already is a Delaunay triangulation of such samples), and every vertex of an
//!   edge with a rest angle or fibre damage.
//! - **Vertices dropped**: the rest, i.e. the vertices all of whose triangles are curved — a
//!   curved region's interior is rebuilt from its rulings each frame, as in the seeds.
//! - **Vertices added**: both pattern endpoints of every traced ruling of a curved region and
//!   the barycentre of every quad between neighbouring rulings of one region. A point within
//!   [`SNAP_FRAC`] of the lattice spacing of a vertex already placed is that vertex (no sliver);
//!   an endpoint on the sheet's border is put exactly on it; a point that close to a kept
//!   edge (below) is left out, and a ruling with an end left out is not made an edge chain.
//! - **Constraints** (edges the triangulation must have): every old edge between kept vertices
//!   that borders a flat or fan triangle or carries a rest angle or damage — so flat regions,
//!   creases and cone fans keep their triangles — then every ruling (from endpoint to endpoint)
//!   that crosses no constraint already in.
//!
//! ## Long rulings (impl. choice)
//!
//! The seeds' quad between two neighbouring rulings, split about its barycentre, has angles of
//! about atan(w / L): 5° for rulings 0.83 cm apart (the resampling's 1/ρ_bound, Table VI) and
//! 10 cm long, and its bending hinge is the whole ruling. Here a ruling longer than the lattice
//! spacing h is cut into ⌈L / h⌉ equal pieces (points on the ruling, which stays one straight
//! chain of edges), and the quad into as many sub-quads, each with its own barycentre (the
//! midpoint of the pieces' midpoints), so the curved region's triangles are as fine along the
//! rulings as the lattice and about as wide as the ruling spacing.
//!
//! ## State transfer
//!
//! A kept vertex keeps its 3D position and velocity. An added vertex takes both interpolated
//! (barycentric) in the old triangle under its pattern point: on a curved region that is the
//! chord of the old triangle, within its sag of the surface. Rest data, hinges and lumped masses
//! are rebuilt from the new pattern ([`PhysMesh::from_pattern`]: the total mass is unchanged).
//! An edge present in both meshes keeps its rest angle and damage; a new edge starts flat and
//! undamaged (the dropped region had neither, by the rule above). Each triangle names the old
//! triangle under its pattern centroid ([`Regeneration::tri_parent`]).
//!
//! ## Refusals
//!
//! A regeneration whose triangulation has a triangle with an angle below
//! [`REGEN_MIN_ANGLE_RAD`] (long rulings close together make thin quads), misses a point, or
//! fails to build is refused ([`RegenError`]): S_P stays as it is that frame. The angle limit
//! is lower than an insertion's 12° ([`super::refine::MIN_ANGLE_RAD`]) because the seeds' own
//! barycentre split of a quad 0.8 cm wide and 5 cm long has angles of about 10°.
//!
//! Building a mesh allocates: the per-frame regeneration is an opt-in mode for offline study
//! (accuracy and cost against the default event-driven S_P), not the plugin's steady state.

use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::refine::{locate, min_angle};
use crate::math::{V2, V3};
use crate::sheet::pattern::Pattern;
use crate::sheet::physical::{MeshError, PhysMesh};
use crate::sheet::topology::NONE;

/// A new point within this fraction of the lattice spacing of a vertex already placed is that
/// vertex.
pub const SNAP_FRAC: f64 = 0.25;

/// Most pieces a ruling is cut into.
const MAX_PIECES: usize = 64;

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
    let add = |p: V2, points: &mut Vec<V2>| -> u32 {
        let p = border.onto(p, snap_m);
        match points.iter().position(|q| (q - p).norm_squared() < snap2) {
            Some(i) => i as u32,
            None if near_kept_edge(p, &points[..n_kept]) => NONE,
            None => {
                points.push(p);
                (points.len() - 1) as u32
            }
        }
    };
    // Segments per ruling: rulings are cut into pieces no longer than the lattice spacing
    // (module doc, "Long rulings").
    let pieces = |len: f64| ((len / spacing_m).ceil() as usize).clamp(1, MAX_PIECES);
    let mut ends: Vec<[u32; 2]> = Vec::with_capacity(rulings.len());
    for r in rulings {
        if !(r.a2.x.is_finite() && r.a2.y.is_finite() && r.b2.x.is_finite() && r.b2.y.is_finite()) {
            return Err(RegenError::Insertion);
        }
        let a = add(r.a2, &mut points);
        let b = add(r.b2, &mut points);
        let k = pieces((r.b2 - r.a2).norm());
        for j in 1..k {
            add(r.a2 + (r.b2 - r.a2) * (j as f64 / k as f64), &mut points);
        }
        ends.push([a, b]);
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
            add(c, &mut points);
        }
    }
    let added = points.len() - n_kept;

    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::new();
    let mut handles = Vec::with_capacity(points.len());
    for p in &points {
        let h = cdt
            .insert(Point2::new(p.x, p.y))
            .map_err(|_| RegenError::Insertion)?;
        handles.push(h);
    }
    // Two points on one position are one vertex to spade: a kept vertex must stay its own.
    for (i, h) in handles.iter().enumerate().take(n_kept) {
        if h.index() != i {
            return Err(RegenError::Merged(i as u32));
        }
    }
    if cdt.num_vertices() != points.len() {
        return Err(RegenError::Merged(NONE));
    }
    // Constraints: the kept structure first, then the rulings that fit.
    for &(_, [a, b]) in &kept_edges {
        if cdt.can_add_constraint(handles[a as usize], handles[b as usize]) {
            cdt.add_constraint(handles[a as usize], handles[b as usize]);
        }
    }
    for &[a, b] in &ends {
        if a != b
            && a != NONE
            && b != NONE
            && cdt.can_add_constraint(handles[a as usize], handles[b as usize])
        {
            cdt.add_constraint(handles[a as usize], handles[b as usize]);
        }
    }
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(cdt.num_inner_faces());
    for f in cdt.inner_faces() {
        let t = f.vertices().map(|v| v.fix().index() as u32);
        let [a, b, c] = t.map(|i| points[i as usize]);
        let ang = min_angle(a, b, c);
        if ang < REGEN_MIN_ANGLE_RAD {
            return Err(RegenError::ThinTriangle(ang.to_degrees()));
        }
        triangles.push(t);
    }
    // State: kept vertices copied, added ones interpolated in the old triangle under them.
    let mut pos: Vec<V3> = Vec::with_capacity(points.len());
    let mut vel: Vec<V3> = Vec::with_capacity(points.len());
    for v in (0..n_old).filter(|&v| keep[v]) {
        pos.push(sp.pos[v]);
        vel.push(sp.vel[v]);
    }
    for p in &points[n_kept..] {
        let (t, l) = locate(&sp.pattern, &sp.triangles, *p).ok_or(RegenError::Outside)?;
        let tri = sp.triangles[t];
        let lerp = |x: &[V3]| {
            tri.iter()
                .zip(l)
                .fold(V3::zeros(), |s, (&i, w)| s + x[i as usize] * w)
        };
        pos.push(lerp(&sp.pos));
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
    for (ei, e) in mesh.topo.edges.iter().enumerate() {
        let [a, b] = e.v.map(|v| new_to_old[v as usize]);
        if a == NONE || b == NONE {
            continue;
        }
        if let Some(oe) = sp.topo.find_edge(a, b) {
            mesh.edge_rest_angle[ei] = sp.edge_rest_angle[oe as usize];
            mesh.edge_damage[ei] = sp.edge_damage[oe as usize];
        }
    }
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
        dropped: (n_old - n_kept) as u32,
        rulings_as_edges,
    })
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
        for (p, q) in sp.pos.iter_mut().zip(&sp.pattern) {
            let r = 0.05;
            *p = V3::new(r * (q.x / r).sin(), q.y, r * (1.0 - (q.x / r).cos()));
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
        let rulings: Vec<RulingLine> = (0..7)
            .map(|i| {
                let x = -0.024 + 0.008 * f64::from(i);
                RulingLine {
                    region: 0,
                    a2: V2::new(x, -0.05),
                    b2: V2::new(x, 0.05),
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
        // Rulings that do not run into the crease are edges.
        assert!(
            r.rulings_as_edges >= 5,
            "{} rulings are edges",
            r.rulings_as_edges
        );
        // Interpolated state: on the chord of the old surface, moving as it did.
        for (p, v) in r.mesh.pos.iter().zip(&r.mesh.vel) {
            assert!((v - V3::new(0.0, 0.0, 1.0)).norm() < 1e-12);
            assert!(p.iter().all(|c| c.is_finite()));
        }
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
