//! # Vertex insertion and edge flips in S_P, with state transfer
//!
//! The seeds keep every vertex of S_G a vertex of S_P (P 351–354, T 665; digest-crumpling
//! §1.2 "Invariant"), and a singular vertex is placed at its drawn pattern position s̄ and never
//! moved in 2D (P 63–66, 295–297, 659–668; T 600, 933). They get this by regenerating S_P from
//! S_G every frame (§2.2). Our S_P keeps its connectivity between singular points
//! ([`crate::geometry`], "Implementation decisions"), so a d-cone apex used to be the nearest
//! S_P vertex moved towards s̄ — in full only where the triangles around it stay well shaped.
//! This module is the remeshing step that makes the apex exact everywhere: it **inserts a new
//! S_P vertex at s̄** and transfers the sheet's state to the refined mesh, the seeds' S_G → S_P
//! enrichment (§2.2) applied where S_G changed.
//!
//! ## The refinement
//!
//! 1. **Locate** s̄ in the pattern: the triangle t = (a, b, c) with the largest smallest
//!    barycentric coordinate (exact point location on a valid mesh).
//! 2. **Split.** If s̄ lies well inside t, t becomes (a, b, n), (b, c, n), (c, a, n). If it lies
//!    close to an interior edge (u, w) of t (barycentric coordinate of the opposite vertex below
//!    [`EDGE_SPLIT_BARY`]), that edge is split at s̄ instead and both of its triangles become two,
//!    so no sliver is made. Points close to a vertex ([`NEAR_VERTEX_FRAC`] of the triangle's
//!    shortest edge) or to the sheet boundary are refused: the caller moves that vertex instead
//!    (a singular vertex is interior).
//!
//!    **An edge split across a fold** is made at the foot of s̄ on the edge instead of at s̄,
//!    when split at s̄ the new vertex's edges start strained by more than a limit
//!    ([`SPLIT_START_STRAIN_MAX`], 5 %, after the relaxation below;
//!    `GeometryConfig::insertion_max_start_strain`) and at the foot by less. Off the edge,
//!    the two new triangles on the far side, (w, n, x) and (n, u, x), reach across the old
//!    edge into t: in the pattern they are flat, on the sheet they would have to bend along
//!    the old edge, so where that edge is a sharp fold their edges to x start far too long or
//!    short, and no position of the new vertex fixes all of them at once. On the edge, every
//!    new triangle lies on one side of it and starts with its exact rest shape. Where even
//!    that starts beyond the limit (the foot next to a vertex, a fold along another edge),
//!    [`insert_vertex_near`] tries its nudged points and takes the first within the limit,
//!    else the least strained. Insertions at s̄ whatever their strain started strained by up to
//!    0.78, which the frame's own solve had to relax, or kept where the pass-through guard
//!    undid that frame; with the limit, far fewer crumples pass the health limit and fewer
//!    frames are undone (docs/decisions.md, "Insertion next to s̄"). The price is the law of s̄
//!    (geometry.rs, digest-crumpling §3.5): where the foot is taken, the offset across the edge
//!    (normal with standard deviation σ/√2, 0.7 mm by default; the split is at most
//!    [`EDGE_SPLIT_BARY`] of t's height away, a third of it where the triangle split was
//!    refused) is dropped and only the position along the edge is kept. In the seeds the
//!    problem does not arise, because S_P is rebuilt around s̄ every frame (§2.2). Where every
//!    candidate starts strained, the least strained one may be a sliver whose triangle is
//!    strained beyond its edges (a known approximation, same section).
//! 3. **Lawson flips** restore the Delaunay property around the new vertex in the pattern
//!    (the seeds triangulate flat regions by Delaunay, T 738): an edge opposite the new vertex
//!    whose far vertex lies inside the circumcircle of the new triangle is flipped, and the two
//!    edges behind it are checked in turn. An edge is flipped only if it carries no rest angle
//!    and no fibre damage (a fold or a damaged edge keeps its place: the seeds' creases are S_P
//!    edges too, T 740) and is bent by less than [`FLIP_MAX_DIHEDRAL_RAD`] now (flipping a bent
//!    quad would change the surface's shape).
//! 4. **Quality check**: every triangle around the new vertex keeps an angle of at least
//!    [`MIN_ANGLE_RAD`], else the insertion is refused.
//!
//! ## State transfer (digest §2.2 item 5, impl. choice)
//!
//! Old vertices keep their index, pattern position, 3D position and velocity; the new vertex is
//! appended with the velocity interpolated barycentrically in the old triangle that contained
//! s̄ (no momentum is invented) and the 3D position interpolated there too, then moved to where
//! its new edges have their pattern lengths as nearly as they can (a few Gauss–Newton steps on
//! 3 unknowns, never turning a triangle of its star over): inside a fold, or on the chord of a
//! bent triangle, the interpolated point is closer to some of its new neighbours than the
//! paper between them is long, and its edges would start compressed by up to 15 % (measured
//! in the crumple scenes) — the seeds follow their S_P regeneration with the isometry step for
//! the same reason (§3.8). Edges
//! that exist in both meshes keep their rest angle and damage; the two halves of a split edge
//! inherit the split edge's; new edges start flat and undamaged (they cross what was the inside
//! of a triangle, which had no rest curvature). Rest data, hinges and lumped masses are rebuilt
//! exactly as [`PhysMesh::from_pattern`] builds them; the masses are re-lumped over the new
//! triangles, so the total mass is unchanged while the three (or four) vertices around s̄ hand
//! part of theirs to the new vertex. Unchanged triangles keep their index; each triangle of the
//! refined mesh names the old triangle under its pattern centroid ([`Insertion::tri_parent`]),
//! so per-triangle state (the geometry layer's curved flags) follows.
//!
//! ## Edge flips
//!
//! [`flip_edge`] swaps an interior edge for the other diagonal of its quad (digest-crumpling
//! §3.1, T 811–828; when, is the geometry layer's flip rule, [`crate::geometry`] step 2). The
//! vertices and their state are untouched; the two triangles keep their indices and name
//! their old triangle under the new centroid as parent; rest data, hinges and masses are
//! rebuilt as for an insertion; every other edge keeps its rest angle and damage. Refused: a
//! boundary edge, an edge with a rest angle or damage (a fold keeps its place), and a quad
//! that is not strictly convex in the pattern or whose new triangles would have an angle below
//! [`FLIP_MIN_ANGLE_RAD`].
//!
//! Building a mesh allocates; an insertion or a flip is an event, like a reset, not a
//! steady-state step.

use crate::math::{V2, V3, barycentric2};
use crate::sheet::measure::dihedral;
use crate::sheet::pattern::{Pattern, signed_area};
use crate::sheet::physical::{MeshError, PhysMesh};
use crate::sheet::topology::{Edge, NONE};
use crate::triangle_distance::triangles_intersect;

/// Below this barycentric coordinate of the opposite vertex, a point splits the edge instead of
/// the triangle.
pub const EDGE_SPLIT_BARY: f64 = 0.12;
/// A point closer to a vertex than this fraction of its triangle's shortest edge is refused.
pub const NEAR_VERTEX_FRAC: f64 = 0.25;
/// Smallest angle accepted in the triangles around the new vertex (12°; the lattice's are
/// ≈ 60°, and a sheet of ≈ 30° triangles simulates well).
pub const MIN_ANGLE_RAD: f64 = 12.0 * std::f64::consts::PI / 180.0;
/// Largest current dihedral angle of an edge that may be flipped, radians.
pub const FLIP_MAX_DIHEDRAL_RAD: f64 = 0.2;
/// Above this start strain of the new vertex's edges (largest |l/l̄ − 1|) an edge split at s̄
/// is made at the foot of s̄ on the edge instead, if that starts less strained, and
/// [`insert_vertex_near`] tries its nudged points (module doc, step 2).
pub const SPLIT_START_STRAIN_MAX: f64 = 0.05;
/// Largest number of Lawson flips per insertion.
const MAX_FLIPS: usize = 32;

/// Why a point cannot be inserted.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum InsertError {
    /// The point is outside the pattern (or not finite).
    #[error("the point is outside the sheet's pattern")]
    Outside,
    /// The point is (almost) on an existing vertex.
    #[error("the point is next to vertex {0}")]
    NearVertex(u32),
    /// The point is next to the sheet boundary.
    #[error("the point is next to the sheet boundary")]
    NearBoundary,
    /// The triangles around the new vertex would be poorly shaped.
    #[error("the triangles around the new vertex would be poorly shaped (smallest angle {0:.1}°)")]
    PoorShape(f64),
    /// The refined pattern is not a valid mesh.
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// A refined mesh.
#[derive(Clone, Debug)]
pub struct Insertion {
    /// The refined S_P (state transferred).
    pub mesh: PhysMesh,
    /// Index of the new vertex (the old vertex count).
    pub vertex: u32,
    /// Per triangle of the refined mesh, the old triangle under its pattern centroid.
    pub tri_parent: Vec<u32>,
    /// Lawson flips made.
    pub flips: usize,
}

/// The triangle of `triangles` containing `p` (largest smallest barycentric coordinate), with
/// the coordinates. `None` when `p` is outside by more than a rounding error.
pub(super) fn locate(points: &[V2], triangles: &[[u32; 3]], p: V2) -> Option<(usize, [f64; 3])> {
    let mut best: Option<(usize, [f64; 3], f64)> = None;
    for (t, tri) in triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|i| points[i as usize]);
        let l = barycentric2(a, b, c, p);
        let m = l[0].min(l[1]).min(l[2]);
        if m.is_finite() && best.is_none_or(|(_, _, bm)| m > bm) {
            best = Some((t, l, m));
        }
    }
    best.filter(|&(_, _, m)| m > -1e-9).map(|(t, l, _)| (t, l))
}

/// True if `d` lies strictly inside the circumcircle of the counter-clockwise triangle (a, b, c).
pub(super) fn in_circle(a: V2, b: V2, c: V2, d: V2) -> bool {
    let (ad, bd, cd) = (a - d, b - d, c - d);
    let det = ad.norm_squared() * bd.perp(&cd) - bd.norm_squared() * ad.perp(&cd)
        + cd.norm_squared() * ad.perp(&bd);
    det > 0.0
}

/// Smallest interior angle of the pattern triangle (a, b, c), radians.
pub(super) fn min_angle(a: V2, b: V2, c: V2) -> f64 {
    let ang = |p: V2, q: V2, r: V2| {
        let (u, v) = (q - p, r - p);
        u.perp(&v).abs().atan2(u.dot(&v))
    };
    ang(a, b, c).min(ang(b, c, a)).min(ang(c, a, b))
}

/// Smallest interior angle of the pattern triangle (a, b, c), radians, or 0 if it is not
/// counter-clockwise (a turned-over or degenerate triangle is the worst shape there is).
pub(super) fn ccw_min_angle(a: V2, b: V2, c: V2) -> f64 {
    if signed_area(a, b, c) <= 0.0 {
        0.0
    } else {
        min_angle(a, b, c)
    }
}

/// Moves the new vertex `n` (3D) from its barycentric start to where its edges have their
/// pattern lengths, as far as they can (Gauss–Newton on Σ_j (|x − x_j| − l̄_j)², at most 8
/// steps, each kept only if it lowers the error and turns no triangle of the star over). In
/// a fold, the point interpolated on one side's plane is closer to the far side's vertices
/// than the paper between them is long: left there, its edges start compressed by up to 15 %.
fn relax_new_vertex(points: &[V2], pos: &mut [V3], triangles: &[[u32; 3]], n: u32) {
    let ni = n as usize;
    let mut ring: [(V3, f64); 12] = [(V3::zeros(), 0.0); 12];
    let mut m = 0;
    for tri in triangles.iter().filter(|t| t.contains(&n)) {
        for &j in tri {
            if j != n && m < ring.len() && !ring[..m].iter().any(|r| r.0 == pos[j as usize]) {
                ring[m] = (pos[j as usize], (points[j as usize] - points[ni]).norm());
                m += 1;
            }
        }
    }
    let ring = &ring[..m];
    let star: Vec<[u32; 3]> = triangles
        .iter()
        .filter(|t| t.contains(&n))
        .copied()
        .collect();
    let normals = |x: V3, pos: &[V3]| -> Vec<V3> {
        star.iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| if i == n { x } else { pos[i as usize] });
                (b - a).cross(&(c - a))
            })
            .collect()
    };
    let start_normals = normals(pos[ni], pos);
    // A step must not carry the star through another layer of a fold (a layer 1.4 mm away
    // was crossed in the full crumple, seed 2): every star triangle against every triangle
    // sharing no vertex with it (insertions are rare; this runs at most 8 times each).
    let crosses_another_layer = |x: V3, pos: &[V3]| {
        star.iter().any(|t| {
            let ct = t.map(|i| if i == n { x } else { pos[i as usize] });
            triangles
                .iter()
                .filter(|o| !o.iter().any(|v| t.contains(v)))
                .any(|o| triangles_intersect(ct, o.map(|i| pos[i as usize])))
        })
    };
    let err = |x: V3| -> f64 {
        ring.iter()
            .map(|&(xj, l)| ((x - xj).norm() - l).powi(2))
            .sum()
    };
    let mut x = pos[ni];
    let mut e = err(x);
    for _ in 0..8 {
        let (mut jtj, mut jtr) = (crate::math::M3::zeros(), V3::zeros());
        for &(xj, l) in ring {
            let d = x - xj;
            let dn = d.norm();
            if dn <= 1e-12 {
                continue;
            }
            let g = d / dn;
            jtj += g * g.transpose();
            jtr += g * (dn - l);
        }
        jtj += crate::math::M3::identity() * 1e-9;
        let Some(step) = jtj.try_inverse().map(|inv| inv * jtr) else {
            break;
        };
        let y = x - step;
        let ey = err(y);
        let keeps_side = normals(y, pos)
            .iter()
            .zip(&start_normals)
            .all(|(a, b)| a.dot(b) > 0.0);
        if ey.is_nan()
            || ey >= e
            || !keeps_side
            || !y.iter().all(|c| c.is_finite())
            || crosses_another_layer(y, pos)
        {
            break;
        }
        x = y;
        e = ey;
    }
    pos[ni] = x;
}

/// Index of the triangle holding the directed edge u → w, and the third vertex.
pub(super) fn with_directed_edge(triangles: &[[u32; 3]], u: u32, w: u32) -> Option<(usize, u32)> {
    triangles.iter().enumerate().find_map(|(t, tri)| {
        (0..3)
            .find(|&k| tri[k] == u && tri[(k + 1) % 3] == w)
            .map(|k| (t, tri[(k + 2) % 3]))
    })
}

/// Inserts a vertex at pattern point `p` into `sp` and transfers the state (module doc).
pub fn insert_vertex(sp: &PhysMesh, p: V2) -> Result<Insertion, InsertError> {
    insert_vertex_limited(sp, p, SPLIT_START_STRAIN_MAX)
}

/// [`insert_vertex`] with the start strain above which an edge split at s̄ is made at the foot
/// of s̄ instead (module doc, step 2; infinite: never).
pub fn insert_vertex_limited(
    sp: &PhysMesh,
    p: V2,
    max_start_strain: f64,
) -> Result<Insertion, InsertError> {
    if !(p.x.is_finite() && p.y.is_finite()) {
        return Err(InsertError::Outside);
    }
    let (t, l) = locate(&sp.pattern, &sp.triangles, p).ok_or(InsertError::Outside)?;
    let tri = sp.triangles[t];
    let corners = tri.map(|i| sp.pattern[i as usize]);
    let shortest = (0..3)
        .map(|k| (corners[(k + 1) % 3] - corners[k]).norm())
        .fold(f64::INFINITY, f64::min);
    for (k, &c) in corners.iter().enumerate() {
        if (c - p).norm() < NEAR_VERTEX_FRAC * shortest {
            return Err(InsertError::NearVertex(tri[k]));
        }
    }
    // Near an edge, split the edge; else split the triangle, and if the flips cannot make that
    // well shaped (a bent edge close by), try splitting the nearest edge instead.
    let kmin = (0..3).min_by(|&i, &j| l[i].total_cmp(&l[j])).unwrap_or(0);
    let tries: &[Option<usize>] = if l[kmin] < EDGE_SPLIT_BARY {
        &[Some(kmin)]
    } else {
        &[None, Some(kmin)]
    };
    let mut err = InsertError::Outside;
    for &split in tries {
        let at_p = split_and_flip(sp, p, t, l, split, false);
        // An edge split whose new triangles span a fold starts them strained: then the split
        // at the foot of s̄ on the edge, if it starts them less strained (module doc, step 2).
        let result = match at_p {
            Ok(ins) if split.is_some() && start_strain(&ins) > max_start_strain => {
                match split_and_flip(sp, p, t, l, split, true) {
                    Ok(foot) if start_strain(&foot) < start_strain(&ins) => Ok(foot),
                    _ => Ok(ins),
                }
            }
            r => r,
        };
        match result {
            Ok(ins) => return Ok(ins),
            Err(e) => {
                // Report the better-shaped refusal (or the first other reason).
                err = match (&err, &e) {
                    (InsertError::PoorShape(a), InsertError::PoorShape(b)) if a >= b => err,
                    (InsertError::PoorShape(_) | InsertError::Outside, _) => e,
                    _ => err,
                }
            }
        }
    }
    Err(err)
}

/// [`insert_vertex`] at `p` or, where that is refused for being next to a vertex or for a
/// poorly shaped star, at the nearest of a few points that are accepted: `p` pushed straight
/// away from the vertex it is next to (to 1.25 × the refusal distance), then `p` moved a
/// quarter and a half of the way to the centre of its triangle. The seeds' placement keeps s̄
/// "away from existing vertices" (digest §3.5, impl. choice) and inside well-shaped elements;
/// the nudge is at most half a triangle (≤ 0.3 S_P edge), where the nearest vertex would be
/// up to a whole edge away. Where the insertion at `p` is made but starts the new vertex's
/// edges strained beyond `max_start_strain` (default [`SPLIT_START_STRAIN_MAX`]: a fold next
/// to it that the split at the foot, module doc step 2, does not avoid), the same points are
/// tried: the first whose insertion starts within that strain is taken, else the least
/// strained of all. Returns the insertion and the new vertex's pattern position (the point
/// used, or its foot on a split edge).
pub fn insert_vertex_near(
    sp: &PhysMesh,
    p: V2,
    max_start_strain: f64,
) -> Result<(Insertion, V2), InsertError> {
    let used = |ins: Insertion| {
        let q = ins.mesh.pattern[ins.vertex as usize];
        (ins, q)
    };
    // The least strained insertion so far, if every one starts strained.
    let mut best: Option<(Insertion, f64)> = None;
    let first = match insert_vertex_limited(sp, p, max_start_strain) {
        Ok(ins) => {
            let strain = start_strain(&ins);
            if strain <= max_start_strain {
                return Ok(used(ins));
            }
            best = Some((ins, strain));
            None
        }
        Err(e @ (InsertError::Outside | InsertError::Mesh(_) | InsertError::NearBoundary)) => {
            return Err(e);
        }
        Err(e) => Some(e),
    };
    let (t, _) = locate(&sp.pattern, &sp.triangles, p).ok_or(InsertError::Outside)?;
    let corners = sp.triangles[t].map(|i| sp.pattern[i as usize]);
    let centre = (corners[0] + corners[1] + corners[2]) / 3.0;
    let shortest = (0..3)
        .map(|k| (corners[(k + 1) % 3] - corners[k]).norm())
        .fold(f64::INFINITY, f64::min);
    let mut tries = [p; 3];
    if let Some(InsertError::NearVertex(v)) = first {
        let c = sp.pattern[v as usize];
        let away = (p - c)
            .try_normalize(1e-12)
            .unwrap_or((centre - c).normalize());
        tries[0] = c + away * (1.25 * NEAR_VERTEX_FRAC * shortest);
    }
    tries[1] = p + (centre - p) * 0.25;
    tries[2] = p + (centre - p) * 0.5;
    for q in tries {
        if q != p
            && let Ok(ins) = insert_vertex_limited(sp, q, max_start_strain)
        {
            let strain = start_strain(&ins);
            if strain <= max_start_strain {
                return Ok(used(ins));
            }
            if best.as_ref().is_none_or(|(_, b)| strain < *b) {
                best = Some((ins, strain));
            }
        }
    }
    match (best, first) {
        (Some((ins, _)), _) => Ok(used(ins)),
        (None, Some(e)) => Err(e),
        (None, None) => Err(InsertError::Outside),
    }
}

/// Largest relative length error |l/l̄ − 1| of the new vertex's edges in an insertion (3D
/// length against the pattern's).
pub fn start_strain(ins: &Insertion) -> f64 {
    let (m, n) = (&ins.mesh, ins.vertex as usize);
    m.topo
        .neighbours(ins.vertex)
        .iter()
        .map(|&j| {
            let j = j as usize;
            let rest = (m.pattern[j] - m.pattern[n]).norm();
            ((m.pos[n] - m.pos[j]).norm() / rest - 1.0).abs()
        })
        .fold(0.0, f64::max)
}

/// Splits triangle `t` (barycentric coordinates `l` of `p`) at `p` (`split == None`) or the
/// edge opposite its corner `k` (`Some(k)`), then flips and checks the star.
fn split_and_flip(
    sp: &PhysMesh,
    p: V2,
    t: usize,
    l: [f64; 3],
    split: Option<usize>,
    on_edge: bool,
) -> Result<Insertion, InsertError> {
    let n = sp.num_vertices() as u32;
    let tri = sp.triangles[t];
    // 3D state of the new vertex: barycentric in the containing triangle.
    let mut pos = (0..3).fold(V3::zeros(), |s, k| s + sp.pos[tri[k] as usize] * l[k]);
    let mut vel = (0..3).fold(V3::zeros(), |s, k| s + sp.vel[tri[k] as usize] * l[k]);
    let mut p = p;
    // The edge split on the edge itself, at the foot of s̄ (module doc, step 2).
    if let (Some(kmin), true) = (split, on_edge) {
        let (u, w) = (tri[(kmin + 1) % 3], tri[(kmin + 2) % 3]);
        let (pu, pw) = (sp.pattern[u as usize], sp.pattern[w as usize]);
        let a = ((p - pu).dot(&(pw - pu)) / (pw - pu).norm_squared()).clamp(0.0, 1.0);
        let shortest = (0..3)
            .map(|k| (sp.pattern[tri[(k + 1) % 3] as usize] - sp.pattern[tri[k] as usize]).norm())
            .fold(f64::INFINITY, f64::min);
        let q = pu + (pw - pu) * a;
        for v in [u, w] {
            if (q - sp.pattern[v as usize]).norm() < NEAR_VERTEX_FRAC * shortest {
                return Err(InsertError::NearVertex(v));
            }
        }
        p = q;
        let (xu, xw) = (sp.pos[u as usize], sp.pos[w as usize]);
        pos = xu + (xw - xu) * a;
        let (vu, vw) = (sp.vel[u as usize], sp.vel[w as usize]);
        vel = vu + (vw - vu) * a;
    }
    let mut points = sp.pattern.clone();
    points.push(p);
    let mut pos_all = sp.pos.clone();
    pos_all.push(pos);
    let mut triangles = sp.triangles.clone();
    // Edges of the new mesh that inherit an old edge's rest angle and damage: (new pair, old).
    let mut inherit: [([u32; 2], [u32; 2]); 2] = [([NONE; 2], [NONE; 2]); 2];
    // The edges opposite the new vertex, to check for flips: directed as in their triangle.
    let mut stack: Vec<(u32, u32)> = Vec::with_capacity(2 * MAX_FLIPS + 4);
    if let Some(kmin) = split {
        // Split the edge (u, w) opposite corner kmin: t = (u, w, o), its twin s = (w, u, x).
        let (u, w, o) = (tri[(kmin + 1) % 3], tri[(kmin + 2) % 3], tri[kmin]);
        let Some((s, x)) = with_directed_edge(&triangles, w, u) else {
            return Err(InsertError::NearBoundary);
        };
        triangles[t] = [u, n, o];
        triangles.push([n, w, o]);
        triangles[s] = [w, n, x];
        triangles.push([n, u, x]);
        inherit = [([u, n], [u, w]), ([n, w], [u, w])];
        stack.extend([(o, u), (w, o), (x, w), (u, x)]);
    } else {
        let [a, b, c] = tri;
        triangles[t] = [a, b, n];
        triangles.push([b, c, n]);
        triangles.push([c, a, n]);
        stack.extend([(a, b), (b, c), (c, a)]);
    }
    // Lawson flips about the new vertex.
    let old_edge = |a: u32, b: u32| {
        if a >= n || b >= n {
            return None;
        }
        sp.topo.find_edge(a, b).map(|e| e as usize)
    };
    let mut flips = 0;
    while let Some((u, w)) = stack.pop() {
        if flips >= MAX_FLIPS {
            break;
        }
        let Some((t1, _)) = with_directed_edge(&triangles, u, w) else {
            continue;
        };
        let Some((t2, x)) = with_directed_edge(&triangles, w, u) else {
            continue; // boundary
        };
        let (pu, pw, pn, px) = (
            points[u as usize],
            points[w as usize],
            points[n as usize],
            points[x as usize],
        );
        if !in_circle(pu, pw, pn, px) {
            continue;
        }
        // Convex quad: u and w on opposite sides of the new diagonal n–x.
        if signed_area(pn, px, pu) * signed_area(pn, px, pw) >= 0.0 {
            continue;
        }
        if let Some(e) = old_edge(u, w)
            && (sp.edge_rest_angle[e] != 0.0 || sp.edge_damage[e] != 0.0)
        {
            continue;
        }
        let theta = dihedral(&[u, w, n, x].map(|i| pos_all[i as usize]));
        if theta.abs() > FLIP_MAX_DIHEDRAL_RAD {
            continue;
        }
        triangles[t1] = [n, u, x];
        triangles[t2] = [n, x, w];
        flips += 1;
        stack.push((u, x));
        stack.push((x, w));
    }
    // Quality of the new vertex's star.
    let worst = triangles
        .iter()
        .filter(|tri| tri.contains(&n))
        .map(|tri| {
            let [a, b, c] = tri.map(|i| points[i as usize]);
            ccw_min_angle(a, b, c)
        })
        .fold(f64::INFINITY, f64::min);
    if worst < MIN_ANGLE_RAD {
        return Err(InsertError::PoorShape(worst.to_degrees()));
    }
    relax_new_vertex(&points, &mut pos_all, &triangles, n);
    let tri_parent = triangles
        .iter()
        .enumerate()
        .map(|(i, tri)| {
            if i < sp.triangles.len() && *tri == sp.triangles[i] {
                return i as u32;
            }
            let c = tri.iter().fold(V2::zeros(), |s, &v| s + points[v as usize]) / 3.0;
            locate(&sp.pattern, &sp.triangles, c).map_or(t as u32, |(pt, _)| pt as u32)
        })
        .collect();
    let pattern = Pattern { points, triangles };
    let mut mesh = PhysMesh::from_pattern(&pattern, 0.0, sp.areal_density_kg_m2)?;
    mesh.pos = pos_all;
    mesh.vel.clone_from(&sp.vel);
    mesh.vel.push(vel);
    mesh.inherit_edge_state(sp, |key| {
        let from = inherit
            .iter()
            .find(|(new, _)| [new[0].min(new[1]), new[0].max(new[1])] == key)
            .map(|&(_, old)| old)
            .unwrap_or(key);
        (from[0] < n && from[1] < n).then_some(from)
    });
    mesh.singular.clone_from(&sp.singular);
    mesh.rest_version = sp.rest_version + 1;
    Ok(Insertion {
        mesh,
        vertex: n,
        tri_parent,
        flips,
    })
}

/// Smallest angle accepted in the two triangles of a flipped edge (the lattice's flip gives
/// 30°–30°–120° triangles; a flip is only worth making into shapes the physics handles as well).
pub const FLIP_MIN_ANGLE_RAD: f64 = 20.0 * std::f64::consts::PI / 180.0;

/// Why an edge cannot be flipped.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum FlipError {
    /// The edge does not exist or lies on the sheet boundary.
    #[error("edge {0} is not an interior edge of the sheet")]
    NotInterior(u32),
    /// A fold or a damaged edge keeps its place (its rest angle and damage belong to it).
    #[error("edge {0} carries a rest angle or fibre damage")]
    Creased(u32),
    /// The quad of the edge's two triangles is not strictly convex in the pattern, or the two
    /// new triangles would be poorly shaped.
    #[error("flipping edge {0} would make poorly shaped triangles (smallest angle {1:.1}°)")]
    PoorShape(u32, f64),
    /// The new pattern is not a valid mesh.
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// The two triangles of interior edge `e` = (u, w) and the flip's new ones (u, x2, x1),
/// (w, x1, x2), with the smallest pattern angle among the new ones (0 if one of them is
/// turned over: the quad is not strictly convex).
fn flip_quad(sp: &PhysMesh, e: Edge) -> (usize, usize, [[u32; 3]; 2], f64) {
    let he = |h: u32| sp.topo.half_edges[h as usize];
    let (h1, h2) = (e.he[0], e.he[1]);
    let (t1, t2) = (he(h1).face as usize, he(h2).face as usize);
    let (u, w) = (he(h1).origin, sp.topo.dest(h1));
    let (x1, x2) = (sp.topo.opposite(h1), sp.topo.opposite(h2));
    let new_tris = [[u, x2, x1], [w, x1, x2]];
    let worst = new_tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| sp.pattern[i as usize]);
            ccw_min_angle(a, b, c)
        })
        .fold(f64::INFINITY, f64::min);
    (t1, t2, new_tris, worst)
}

/// True if interior edge `edge` may be flipped into well-shaped triangles (the shape test of
/// [`flip_edge`], without building anything).
pub fn flip_is_well_shaped(sp: &PhysMesh, edge: u32) -> bool {
    sp.topo
        .edges
        .get(edge as usize)
        .is_some_and(|&e| !e.is_boundary() && flip_quad(sp, e).3 >= FLIP_MIN_ANGLE_RAD)
}

/// A mesh with one edge flipped.
#[derive(Clone, Debug)]
pub struct Flip {
    /// The new S_P (state transferred).
    pub mesh: PhysMesh,
    /// The new diagonal's vertices (the old edge's two opposite vertices).
    pub diagonal: [u32; 2],
    /// Per triangle of the new mesh, the old triangle under its pattern centroid (the two
    /// triangles of the flipped quad keep their indices).
    pub tri_parent: Vec<u32>,
}

/// Flips interior edge `edge` of `sp`: its two triangles (u, w, x1) and (w, u, x2) become
/// (u, x2, x1) and (w, x1, x2), the quad's other diagonal x1–x2 replacing u–w (digest-crumpling
/// §3.1, T 811–828). Vertices, their state and masses' total are unchanged; the masses are
/// re-lumped over the two new triangles; every other edge keeps its rest angle and damage, the
/// new diagonal starts flat and undamaged (the old one must be: [`FlipError::Creased`]).
/// Allocates (a connectivity change, an event like an insertion).
pub fn flip_edge(sp: &PhysMesh, edge: u32) -> Result<Flip, FlipError> {
    let Some(&e) = sp.topo.edges.get(edge as usize) else {
        return Err(FlipError::NotInterior(edge));
    };
    if e.is_boundary() {
        return Err(FlipError::NotInterior(edge));
    }
    if sp.edge_rest_angle[edge as usize] != 0.0 || sp.edge_damage[edge as usize] != 0.0 {
        return Err(FlipError::Creased(edge));
    }
    let (t1, t2, new_tris, worst) = flip_quad(sp, e);
    if worst < FLIP_MIN_ANGLE_RAD {
        return Err(FlipError::PoorShape(edge, worst.to_degrees()));
    }
    let p = |i: u32| sp.pattern[i as usize];
    let [x1, x2] = [new_tris[0][2], new_tris[0][1]];
    let mut triangles = sp.triangles.clone();
    triangles[t1] = new_tris[0];
    triangles[t2] = new_tris[1];
    let tri_parent = triangles
        .iter()
        .enumerate()
        .map(|(i, tri)| {
            if i != t1 && i != t2 {
                return i as u32;
            }
            let c = tri.iter().fold(V2::zeros(), |s, &v| s + p(v)) / 3.0;
            locate(&sp.pattern, &sp.triangles, c).map_or(i as u32, |(pt, _)| pt as u32)
        })
        .collect();
    let pattern = Pattern {
        points: sp.pattern.clone(),
        triangles,
    };
    let mut mesh = PhysMesh::from_pattern(&pattern, 0.0, sp.areal_density_kg_m2)?;
    mesh.pos.clone_from(&sp.pos);
    mesh.vel.clone_from(&sp.vel);
    mesh.inherit_edge_state(sp, Some);
    mesh.singular.clone_from(&sp.singular);
    mesh.rest_version = sp.rest_version + 1;
    Ok(Flip {
        mesh,
        diagonal: [x1.min(x2), x1.max(x2)],
        tri_parent,
    })
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::sheet::pattern::lattice;
    use rand::{RngExt, SeedableRng};

    /// A 10 cm lattice sheet, bent into a gentle cylinder (radius 20 cm) and moving (also the
    /// fixture of the cut tests, `sheet/cut.rs`).
    pub(in crate::sheet) fn bent_sheet() -> PhysMesh {
        let p = lattice(0.1, 0.1, 0.1 / 9.0);
        let mut sp = PhysMesh::from_pattern(&p, 0.0, 0.08).unwrap();
        for (i, q) in sp.pattern.iter().enumerate() {
            let r = 0.2;
            let a = q.x / r;
            sp.pos[i] = V3::new(r * a.sin(), q.y, r * (1.0 - a.cos()));
            sp.vel[i] = V3::new(0.1 * q.y, -0.05, 0.3 * q.x);
        }
        sp
    }

    /// [`bent_sheet`] with one damaged and angled edge.
    fn sheet() -> PhysMesh {
        let mut sp = bent_sheet();
        sp.edge_rest_angle[40] = 0.05;
        sp.edge_damage[40] = 1.5;
        sp
    }

    fn total_area(sp: &PhysMesh) -> f64 {
        sp.tri_rest.iter().map(|r| r.area_m2).sum()
    }

    #[test]
    fn a_vertex_inserted_inside_a_triangle_sits_exactly_at_the_point_on_the_surface() {
        let sp = sheet();
        let t = 60;
        let tri = sp.triangles[t];
        let w = [0.3, 0.45, 0.25];
        let p = (0..3).fold(V2::zeros(), |s, k| s + sp.pattern[tri[k] as usize] * w[k]);
        let ins = insert_vertex(&sp, p).unwrap();
        let m = &ins.mesh;
        assert_eq!(ins.vertex as usize, sp.num_vertices());
        assert_eq!(m.num_vertices(), sp.num_vertices() + 1);
        assert_eq!(m.num_triangles(), sp.num_triangles() + 2);
        assert_eq!(m.pattern[ins.vertex as usize], p);
        let x = (0..3).fold(V3::zeros(), |s, k| s + sp.pos[tri[k] as usize] * w[k]);
        let v = (0..3).fold(V3::zeros(), |s, k| s + sp.vel[tri[k] as usize] * w[k]);
        assert!((m.vel[ins.vertex as usize] - v).norm() < 1e-15);
        // The barycentric point lies on the chord of the bent sheet; the new vertex moves
        // from there (by less than a millimetre) until its edges have their pattern lengths.
        let nv = ins.vertex as usize;
        let strain_at = |x: V3| {
            m.topo
                .neighbours(ins.vertex)
                .iter()
                .map(|&j| {
                    ((x - m.pos[j as usize]).norm() / (m.pattern[j as usize] - p).norm() - 1.0)
                        .abs()
                })
                .fold(0.0, f64::max)
        };
        assert!((m.pos[nv] - x).norm() < 1e-3);
        let (before, after) = (strain_at(x), strain_at(m.pos[nv]));
        assert!(after < 0.5 * before && after < 1e-4, "{before} → {after}");
        // Old vertices keep their state; area and mass are conserved.
        assert_eq!(&m.pos[..sp.num_vertices()], &sp.pos[..]);
        assert_eq!(&m.vel[..sp.num_vertices()], &sp.vel[..]);
        assert_eq!(&m.pattern[..sp.num_vertices()], &sp.pattern[..]);
        assert!((total_area(m) - total_area(&sp)).abs() < 1e-15);
        assert!((m.total_mass_kg() - sp.total_mass_kg()).abs() < 1e-15);
        m.topo.validate().unwrap();
        assert_eq!(m.topo.euler_characteristic(), 1);
        // The damaged edge keeps its rest angle and damage.
        let e = sp.topo.edges[40].v;
        let ne = m.topo.find_edge(e[0], e[1]).unwrap() as usize;
        assert_eq!(m.edge_rest_angle[ne], 0.05);
        assert_eq!(m.edge_damage[ne], 1.5);
        assert_eq!(m.rest_version, sp.rest_version + 1);
    }

    #[test]
    fn a_point_near_an_interior_edge_splits_the_edge_and_its_halves_inherit_the_damage() {
        let mut sp = sheet();
        // An interior edge with damage.
        let ei = (0..sp.num_edges())
            .find(|&e| {
                let ed = sp.topo.edges[e];
                !ed.is_boundary()
                    && !sp.topo.vertex_on_boundary[ed.v[0] as usize]
                    && !sp.topo.vertex_on_boundary[ed.v[1] as usize]
            })
            .unwrap();
        sp.edge_rest_angle[ei] = -0.07;
        sp.edge_damage[ei] = 2.0;
        let [a, b] = sp.topo.edges[ei].v;
        let (pa, pb) = (sp.pattern[a as usize], sp.pattern[b as usize]);
        let mid = (pa + pb) * 0.5;
        let normal = V2::new(-(pb - pa).y, (pb - pa).x).normalize();
        let p = mid + normal * 0.02 * (pb - pa).norm();
        let ins = insert_vertex(&sp, p).unwrap();
        let m = &ins.mesh;
        let n = ins.vertex;
        assert_eq!(m.num_triangles(), sp.num_triangles() + 2);
        assert!(m.topo.find_edge(a, b).is_none(), "the edge is split");
        for end in [a, b] {
            let e = m.topo.find_edge(end, n).unwrap() as usize;
            assert_eq!(m.edge_rest_angle[e], -0.07);
            assert_eq!(m.edge_damage[e], 2.0);
        }
        m.topo.validate().unwrap();
        assert!((total_area(m) - total_area(&sp)).abs() < 1e-15);
    }

    /// The sheet folded by 162° along the lattice line of an interior edge (an isometry: no
    /// triangle straddles the line), and that edge.
    fn folded_sheet() -> (PhysMesh, usize) {
        let mut sp = sheet();
        let ei = plain_interior_edge(&sp) as usize;
        let [a, b] = sp.topo.edges[ei].v;
        let (pa, pb) = (sp.pattern[a as usize], sp.pattern[b as usize]);
        let normal = V2::new(-(pb - pa).y, (pb - pa).x).normalize();
        let fold = 0.9 * std::f64::consts::PI;
        for (i, q) in sp.pattern.iter().enumerate() {
            let h = (q - pa).dot(&normal);
            let h = if h.abs() < 1e-12 { 0.0 } else { h.max(0.0) };
            let foot = q - normal * h + normal * (h * fold.cos());
            sp.pos[i] = V3::new(foot.x, foot.y, h * fold.sin());
        }
        let h = sp.edge_hinge[ei];
        let theta = dihedral(&sp.hinges[h as usize].v.map(|i| sp.pos[i as usize]));
        assert!((theta.abs() - fold).abs() < 1e-9, "{theta}");
        (sp, ei)
    }

    /// Points scattered about a sharp fold: every insertion [`insert_vertex_near`] makes
    /// starts within [`SPLIT_START_STRAIN_MAX`] (at s̄ off the fold, at its foot on the fold
    /// edge, or nudged into a triangle), where inserting at s̄ regardless starts many beyond.
    #[test]
    fn insertions_about_a_sharp_fold_start_unstrained() {
        let (sp, ei) = folded_sheet();
        let [a, b] = sp.topo.edges[ei].v;
        let (pa, pb) = (sp.pattern[a as usize], sp.pattern[b as usize]);
        let len = (pb - pa).norm();
        let (dir, normal) = ((pb - pa) / len, V2::new(-(pb - pa).y, (pb - pa).x) / len);
        let mut rng = rand_pcg::Pcg32::seed_from_u64(11);
        let (mut made, mut strained_at_p, mut worst) = (0, 0, 0.0f64);
        for _ in 0..200 {
            let p = pa
                + dir * (len * rng.random_range(-2.0..3.0))
                + normal * (len * rng.random_range(-0.15..0.15));
            let Ok((ins, q)) = insert_vertex_near(&sp, p, SPLIT_START_STRAIN_MAX) else {
                continue;
            };
            made += 1;
            assert_eq!(q, ins.mesh.pattern[ins.vertex as usize]);
            worst = worst.max(start_strain(&ins));
            if let Some((t, l)) = locate(&sp.pattern, &sp.triangles, p) {
                let kmin = (0..3).min_by(|&i, &j| l[i].total_cmp(&l[j])).unwrap();
                if l[kmin] < EDGE_SPLIT_BARY
                    && let Ok(at_p) = split_and_flip(&sp, p, t, l, Some(kmin), false)
                {
                    strained_at_p += usize::from(start_strain(&at_p) > SPLIT_START_STRAIN_MAX);
                }
            }
        }
        println!(
            "{made} insertions, largest start strain {worst:.4}, {strained_at_p} strained at s̄"
        );
        assert!(made >= 100, "{made} insertions");
        assert!(
            strained_at_p >= 10,
            "{strained_at_p} would start strained at s̄"
        );
        assert!(
            worst <= SPLIT_START_STRAIN_MAX,
            "largest start strain {worst}"
        );
    }

    #[test]
    fn a_point_next_to_a_sharply_bent_edge_is_inserted_on_the_edge_unstrained() {
        let (sp, ei) = folded_sheet();
        let [a, b] = sp.topo.edges[ei].v;
        let (pa, pb) = (sp.pattern[a as usize], sp.pattern[b as usize]);
        let normal = V2::new(-(pb - pa).y, (pb - pa).x).normalize();
        for side in [1.0, -1.0] {
            let p = (pa + pb) * 0.5 + normal * (side * 0.1 * (pb - pa).norm());
            // Split at s̄, the triangles across the fold would start strained.
            let (t, l) = locate(&sp.pattern, &sp.triangles, p).unwrap();
            let kmin = (0..3).min_by(|&i, &j| l[i].total_cmp(&l[j])).unwrap();
            let at_p = split_and_flip(&sp, p, t, l, Some(kmin), false).unwrap();
            assert!(
                start_strain(&at_p) > SPLIT_START_STRAIN_MAX,
                "{}",
                start_strain(&at_p)
            );
            let ins = insert_vertex(&sp, p).unwrap();
            let (m, n) = (&ins.mesh, ins.vertex);
            let q = m.pattern[n as usize];
            assert!((q - pa).perp(&(pb - pa)).abs() < 1e-15, "on the edge");
            assert!((q - (pa + pb) * 0.5).norm() < 1e-12, "at the foot of s̄");
            assert!(m.topo.find_edge(a, b).is_none(), "the edge is split");
            // Every edge of the new vertex has its pattern length: no triangle spans the fold.
            assert!(start_strain(&ins) < 1e-12, "{}", start_strain(&ins));
        }
        // An unbent edge is split at s̄ itself.
        let flat = sheet();
        let p = (pa + pb) * 0.5 + normal * (0.05 * (pb - pa).norm());
        assert_eq!(
            insert_vertex_near(&flat, p, SPLIT_START_STRAIN_MAX)
                .unwrap()
                .1,
            p
        );
    }

    #[test]
    fn points_near_a_vertex_or_the_boundary_or_outside_are_refused() {
        let sp = sheet();
        let v = 50usize;
        let p = sp.pattern[v] + V2::new(1e-4, 0.0);
        assert!(matches!(
            insert_vertex(&sp, p),
            Err(InsertError::NearVertex(_))
        ));
        assert_eq!(
            insert_vertex(&sp, V2::new(0.2, 0.0)).unwrap_err(),
            InsertError::Outside
        );
        assert_eq!(
            insert_vertex(&sp, V2::new(f64::NAN, 0.0)).unwrap_err(),
            InsertError::Outside
        );
        // Just inside the bottom edge, between two boundary vertices.
        let ei = (0..sp.num_edges())
            .find(|&e| sp.topo.edges[e].is_boundary())
            .unwrap();
        let [a, b] = sp.topo.edges[ei].v;
        let mid = (sp.pattern[a as usize] + sp.pattern[b as usize]) * 0.5;
        let inward = -mid.normalize() * 1e-4;
        assert_eq!(
            insert_vertex(&sp, mid + inward).unwrap_err(),
            InsertError::NearBoundary
        );
    }

    #[test]
    fn random_insertions_keep_a_valid_well_shaped_mesh_or_are_refused_with_a_reason() {
        let mut rng = rand_pcg::Pcg32::seed_from_u64(7);
        let mut sp = sheet();
        let (mut ok, mut refused) = (0, 0);
        for _ in 0..200 {
            let p = V2::new(rng.random_range(-0.05..0.05), rng.random_range(-0.05..0.05));
            match insert_vertex(&sp, p) {
                Ok(ins) => {
                    ok += 1;
                    let m = &ins.mesh;
                    m.topo.validate().unwrap();
                    assert_eq!(m.topo.euler_characteristic(), 1);
                    assert_eq!(ins.tri_parent.len(), m.num_triangles());
                    assert!(
                        ins.tri_parent
                            .iter()
                            .all(|&t| (t as usize) < sp.num_triangles())
                    );
                    for tri in m.triangles.iter().filter(|t| t.contains(&ins.vertex)) {
                        let [a, b, c] = tri.map(|i| m.pattern[i as usize]);
                        assert!(min_angle(a, b, c) >= MIN_ANGLE_RAD - 1e-12);
                    }
                    assert!((total_area(m) - 0.01).abs() < 1e-12);
                    sp = ins.mesh;
                }
                Err(InsertError::Mesh(e)) => panic!("invalid mesh: {e}"),
                Err(_) => refused += 1,
            }
        }
        assert!(ok >= 40, "{ok} insertions, {refused} refused");
        assert!(refused >= 1);
    }

    #[test]
    fn flips_leave_folded_and_damaged_edges_in_place() {
        // Fold the sheet sharply along x = 0: edges there are bent far beyond the flip limit.
        let mut sp = sheet();
        for (i, q) in sp.pattern.iter().enumerate() {
            sp.pos[i] = V3::new(q.x.min(0.0), q.y, q.x.max(0.0));
        }
        let before: Vec<[u32; 2]> = (0..sp.num_edges())
            .filter(|&e| {
                let h = sp.edge_hinge[e];
                h != NONE
                    && dihedral(&sp.hinges[h as usize].v.map(|i| sp.pos[i as usize])).abs()
                        > FLIP_MAX_DIHEDRAL_RAD
            })
            .map(|e| sp.topo.edges[e].v)
            .collect();
        assert!(!before.is_empty());
        let mut rng = rand_pcg::Pcg32::seed_from_u64(3);
        for _ in 0..60 {
            let p = V2::new(rng.random_range(-0.02..0.02), rng.random_range(-0.04..0.04));
            if let Ok(ins) = insert_vertex(&sp, p) {
                // Every bent edge is still there, or was split (then both halves exist).
                for &[a, b] in &before {
                    let kept = ins.mesh.topo.find_edge(a, b).is_some();
                    let split = ins.mesh.topo.find_edge(a, ins.vertex).is_some()
                        && ins.mesh.topo.find_edge(ins.vertex, b).is_some();
                    assert!(kept || split, "bent edge {a}–{b} was flipped");
                }
            }
        }
    }

    /// An interior lattice edge with interior end points, no rest angle and no damage.
    fn plain_interior_edge(sp: &PhysMesh) -> u32 {
        (0..sp.num_edges() as u32)
            .find(|&e| {
                let ed = sp.topo.edges[e as usize];
                !ed.is_boundary()
                    && ed
                        .v
                        .iter()
                        .all(|&v| !sp.topo.vertex_on_boundary[v as usize])
                    && sp.edge_rest_angle[e as usize] == 0.0
                    && sp.edge_damage[e as usize] == 0.0
                    && e > 60
            })
            .unwrap()
    }

    #[test]
    fn a_flip_swaps_the_diagonal_and_keeps_the_state_mass_and_other_edges() {
        let sp = sheet();
        let e = plain_interior_edge(&sp);
        let [u, w] = sp.topo.edges[e as usize].v;
        let f = flip_edge(&sp, e).unwrap();
        let m = &f.mesh;
        m.topo.validate().unwrap();
        assert_eq!(m.num_vertices(), sp.num_vertices());
        assert_eq!(m.num_triangles(), sp.num_triangles());
        assert!(m.topo.find_edge(u, w).is_none(), "the old diagonal is gone");
        let [x1, x2] = f.diagonal;
        let ne = m.topo.find_edge(x1, x2).expect("the new diagonal") as usize;
        assert_eq!((m.edge_rest_angle[ne], m.edge_damage[ne]), (0.0, 0.0));
        // The new diagonal joins the two vertices opposite the old one.
        for x in [x1, x2] {
            assert!(sp.topo.find_edge(x, u).is_some() && sp.topo.find_edge(x, w).is_some());
        }
        // State, area and mass: unchanged (masses re-lumped, total conserved).
        assert_eq!(m.pos, sp.pos);
        assert_eq!(m.vel, sp.vel);
        assert!((total_area(m) - total_area(&sp)).abs() < 1e-15);
        let mass = |s: &PhysMesh| s.mass_kg.iter().sum::<f64>();
        assert!((mass(m) - mass(&sp)).abs() < 1e-15);
        // Every other edge keeps its rest angle and damage (edge 40 carries both).
        let mut kept = 0;
        for (oe, ed) in sp.topo.edges.iter().enumerate() {
            if oe as u32 == e {
                continue;
            }
            let me = m.topo.find_edge(ed.v[0], ed.v[1]).unwrap() as usize;
            assert_eq!(m.edge_rest_angle[me], sp.edge_rest_angle[oe]);
            assert_eq!(m.edge_damage[me], sp.edge_damage[oe]);
            kept += 1;
        }
        assert_eq!(kept + 1, sp.num_edges());
        // Untouched triangles keep their index; the two new ones name a parent of the quad.
        let quad: Vec<usize> = sp.topo.edges[e as usize]
            .he
            .iter()
            .map(|&h| sp.topo.half_edges[h as usize].face as usize)
            .collect();
        for (t, &p) in f.tri_parent.iter().enumerate() {
            if quad.contains(&t) {
                assert!(quad.contains(&(p as usize)));
            } else {
                assert_eq!(p as usize, t);
                assert_eq!(m.triangles[t], sp.triangles[t]);
            }
        }
        assert_eq!(m.rest_version, sp.rest_version + 1);
        // Flipping the new diagonal back gives the original triangles' vertex sets.
        let back = flip_edge(m, ne as u32).unwrap();
        assert!(back.mesh.topo.find_edge(u, w).is_some());
        assert_eq!(back.diagonal, [u.min(w), u.max(w)]);
    }

    #[test]
    fn boundary_creased_and_badly_shaped_flips_are_refused() {
        let sp = sheet();
        let boundary = (0..sp.num_edges() as u32)
            .find(|&e| sp.topo.edges[e as usize].is_boundary())
            .unwrap();
        assert_eq!(
            flip_edge(&sp, boundary).unwrap_err(),
            FlipError::NotInterior(boundary)
        );
        let n = sp.num_edges() as u32;
        assert_eq!(flip_edge(&sp, n).unwrap_err(), FlipError::NotInterior(n));
        // Edge 40 carries a rest angle and damage (the fixture).
        assert_eq!(flip_edge(&sp, 40).unwrap_err(), FlipError::Creased(40));
        // A dart: the quad (0, 1, 2, 3) is not convex at vertex 3, so its diagonal 1–3 (inside)
        // cannot be swapped for 0–2 (outside).
        let dart = Pattern {
            points: vec![
                V2::new(0.0, 0.0),
                V2::new(1.0, -1.0),
                V2::new(0.3, 0.0),
                V2::new(1.0, 1.0),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        let d = PhysMesh::from_pattern(&dart, 0.0, 0.08).unwrap();
        let e = d.topo.find_edge(0, 2).unwrap();
        assert!(matches!(flip_edge(&d, e), Err(FlipError::PoorShape(..))));
        // A square's diagonal flips (two 45°–45°–90° triangles).
        let square = Pattern {
            points: vec![
                V2::new(0.0, 0.0),
                V2::new(1.0, 0.0),
                V2::new(1.0, 1.0),
                V2::new(0.0, 1.0),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        let q = PhysMesh::from_pattern(&square, 0.0, 0.08).unwrap();
        let f = flip_edge(&q, q.topo.find_edge(0, 2).unwrap()).unwrap();
        assert_eq!(f.diagonal, [1, 3]);
        assert!(f.mesh.topo.find_edge(0, 2).is_none());
    }
}
