//! # Half-edge topology of a triangle mesh, as plain index data
//!
//! The representation of parry's `TriMesh` topology (`TopoHalfEdge { next, twin, vertex, face }`,
//! all `u32`, `u32::MAX` for "none"), which the house style adopts (style.md §4.4). Half-edge
//! `3t + k` of triangle `t = [a, b, c]` runs from corner `k` to corner `k+1 (mod 3)`, so `next`
//! is implicit but stored anyway for clarity. A half-edge on the sheet boundary has
//! `twin == NONE`.
//!
//! On top of the half-edges the module lists the undirected **edges** in a canonical order
//! (sorted by `(min vertex, max vertex)`), which is the order of every per-edge array of the
//! simulation (rest lengths, rest dihedral angles, damage), and the **hinges**: interior edges
//! with their two opposite ("wing") vertices, the stencil of the discrete bending energy.
//!
//! Building never uses hash maps, so the order of everything is a pure function of the
//! triangle list (determinism, digest-crumpling §8 test 18).

use thiserror::Error;

/// "No index": a boundary twin, a missing wing vertex.
pub const NONE: u32 = u32::MAX;

/// One half-edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[repr(C)]
pub struct HalfEdge {
    /// Next half-edge around the same face.
    pub next: u32,
    /// Opposite half-edge of the neighbouring face, or [`NONE`] on the boundary.
    pub twin: u32,
    /// Vertex the half-edge starts at.
    pub origin: u32,
    /// Face the half-edge belongs to.
    pub face: u32,
}

/// An undirected edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Edge {
    /// End vertices, `v[0] < v[1]`.
    pub v: [u32; 2],
    /// The half-edge(s) of the edge: `he[1] == NONE` on the boundary.
    pub he: [u32; 2],
}

impl Edge {
    /// True if the edge lies on the sheet boundary.
    pub fn is_boundary(&self) -> bool {
        self.he[1] == NONE
    }
}

/// Why a triangle list is not a valid sheet mesh.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum TopologyError {
    /// A triangle refers to a vertex that does not exist.
    ///
    /// When this occurs: corrupted saved data or a bug in a remeshing step.
    #[error("triangle {0} has a vertex index out of range")]
    BadIndex(u32),
    /// A triangle repeats a vertex.
    #[error("triangle {0} is degenerate (repeated vertex)")]
    Degenerate(u32),
    /// More than two triangles share an edge.
    #[error("edge ({0}, {1}) is shared by more than two triangles")]
    NonManifoldEdge(u32, u32),
    /// Two triangles share an edge with the same direction (inconsistent orientation).
    #[error("edge ({0}, {1}) is used twice in the same direction (orientation flip)")]
    Orientation(u32, u32),
    /// A vertex is not used by any triangle.
    #[error("vertex {0} belongs to no triangle")]
    IsolatedVertex(u32),
    /// The mesh has no triangle.
    #[error("the mesh has no triangle")]
    Empty,
}

/// Half-edge topology, edges, hinges and vertex adjacency of a triangle mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Topology {
    /// Half-edges, `3 × num_triangles`.
    pub half_edges: Vec<HalfEdge>,
    /// Undirected edges in canonical order.
    pub edges: Vec<Edge>,
    /// Edge index of each half-edge.
    pub he_edge: Vec<u32>,
    /// One outgoing half-edge per vertex (the boundary one for boundary vertices).
    pub vertex_he: Vec<u32>,
    /// True for vertices on the sheet boundary.
    pub vertex_on_boundary: Vec<bool>,
    /// CSR offsets into [`Self::adjacency`] (`num_vertices + 1`).
    pub adjacency_offsets: Vec<u32>,
    /// Neighbouring vertices of each vertex, sorted ascending.
    pub adjacency: Vec<u32>,
}

impl Topology {
    /// Builds the topology of `triangles` over `num_vertices` vertices, checking that the mesh
    /// is a consistently oriented 2-manifold with boundary.
    pub fn build(num_vertices: usize, triangles: &[[u32; 3]]) -> Result<Self, TopologyError> {
        if triangles.is_empty() {
            return Err(TopologyError::Empty);
        }
        let nv = num_vertices as u32;
        let mut half_edges = Vec::with_capacity(triangles.len() * 3);
        for (t, tri) in triangles.iter().enumerate() {
            let t = t as u32;
            if tri.iter().any(|&v| v >= nv) {
                return Err(TopologyError::BadIndex(t));
            }
            if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
                return Err(TopologyError::Degenerate(t));
            }
            for k in 0..3u32 {
                half_edges.push(HalfEdge {
                    next: 3 * t + (k + 1) % 3,
                    twin: NONE,
                    origin: tri[k as usize],
                    face: t,
                });
            }
        }
        let dest = |h: &HalfEdge, hes: &[HalfEdge]| hes[h.next as usize].origin;
        // Sort half-edges by undirected key; pairs become twins.
        let mut keyed: Vec<(u32, u32, u32)> = half_edges
            .iter()
            .enumerate()
            .map(|(i, h)| {
                let (a, b) = (h.origin, dest(h, &half_edges));
                (a.min(b), a.max(b), i as u32)
            })
            .collect();
        keyed.sort_unstable();
        let mut edges = Vec::with_capacity(keyed.len() / 2 + 8);
        let mut he_edge = vec![NONE; half_edges.len()];
        let mut i = 0;
        while i < keyed.len() {
            let (a, b, h0) = keyed[i];
            let mut j = i + 1;
            while j < keyed.len() && keyed[j].0 == a && keyed[j].1 == b {
                j += 1;
            }
            let e = edges.len() as u32;
            match j - i {
                1 => {
                    edges.push(Edge {
                        v: [a, b],
                        he: [h0, NONE],
                    });
                    he_edge[h0 as usize] = e;
                }
                2 => {
                    let h1 = keyed[i + 1].2;
                    if half_edges[h0 as usize].origin == half_edges[h1 as usize].origin {
                        return Err(TopologyError::Orientation(a, b));
                    }
                    half_edges[h0 as usize].twin = h1;
                    half_edges[h1 as usize].twin = h0;
                    edges.push(Edge {
                        v: [a, b],
                        he: [h0, h1],
                    });
                    he_edge[h0 as usize] = e;
                    he_edge[h1 as usize] = e;
                }
                _ => return Err(TopologyError::NonManifoldEdge(a, b)),
            }
            i = j;
        }

        let mut vertex_he = vec![NONE; num_vertices];
        let mut vertex_on_boundary = vec![false; num_vertices];
        for (h, he) in half_edges.iter().enumerate() {
            let v = he.origin as usize;
            if he.twin == NONE {
                vertex_on_boundary[v] = true;
                vertex_on_boundary[dest(he, &half_edges) as usize] = true;
                vertex_he[v] = h as u32;
            } else if vertex_he[v] == NONE {
                vertex_he[v] = h as u32;
            }
        }
        if let Some(v) = vertex_he.iter().position(|&h| h == NONE) {
            return Err(TopologyError::IsolatedVertex(v as u32));
        }

        // Vertex adjacency (CSR) from the edge list.
        let mut deg = vec![0u32; num_vertices];
        for e in &edges {
            deg[e.v[0] as usize] += 1;
            deg[e.v[1] as usize] += 1;
        }
        let mut adjacency_offsets = Vec::with_capacity(num_vertices + 1);
        let mut acc = 0u32;
        adjacency_offsets.push(0);
        for d in &deg {
            acc += d;
            adjacency_offsets.push(acc);
        }
        let mut fill = adjacency_offsets.clone();
        let mut adjacency = vec![0u32; acc as usize];
        for e in &edges {
            let (a, b) = (e.v[0] as usize, e.v[1] as usize);
            adjacency[fill[a] as usize] = b as u32;
            fill[a] += 1;
            adjacency[fill[b] as usize] = a as u32;
            fill[b] += 1;
        }
        for v in 0..num_vertices {
            let (s, t) = (
                adjacency_offsets[v] as usize,
                adjacency_offsets[v + 1] as usize,
            );
            adjacency[s..t].sort_unstable();
        }

        Ok(Self {
            half_edges,
            edges,
            he_edge,
            vertex_he,
            vertex_on_boundary,
            adjacency_offsets,
            adjacency,
        })
    }

    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.vertex_he.len()
    }

    /// Number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.half_edges.len() / 3
    }

    /// Destination vertex of half-edge `h`.
    pub fn dest(&self, h: u32) -> u32 {
        self.half_edges[self.half_edges[h as usize].next as usize].origin
    }

    /// The vertex of `h`'s face opposite to `h`.
    pub fn opposite(&self, h: u32) -> u32 {
        let n = self.half_edges[h as usize].next;
        self.dest(n)
    }

    /// Neighbours of vertex `v`, ascending.
    pub fn neighbours(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.adjacency[self.adjacency_offsets[v] as usize..self.adjacency_offsets[v + 1] as usize]
    }

    /// Valence (number of incident edges) of `v`.
    pub fn valence(&self, v: u32) -> usize {
        self.neighbours(v).len()
    }

    /// Index of the edge `(a, b)`, if it exists (binary search in the canonical order).
    pub fn find_edge(&self, a: u32, b: u32) -> Option<u32> {
        let key = [a.min(b), a.max(b)];
        self.edges
            .binary_search_by(|e| e.v.cmp(&key))
            .ok()
            .map(|i| i as u32)
    }

    /// The connected pieces (triangles sharing an edge), each as its triangles in ascending
    /// order, the pieces ordered by their first triangle: one until a tear separates the sheet.
    pub fn pieces(&self) -> Vec<Vec<u32>> {
        let nt = self.num_triangles();
        let mut seen = vec![false; nt];
        let mut out = Vec::new();
        for start in 0..nt {
            if seen[start] {
                continue;
            }
            seen[start] = true;
            let mut stack = vec![start];
            let mut members = Vec::new();
            while let Some(t) = stack.pop() {
                members.push(t as u32);
                for k in 0..3 {
                    for &he in &self.edges[self.he_edge[3 * t + k] as usize].he {
                        let u = (he / 3) as usize;
                        if he != NONE && !seen[u] {
                            seen[u] = true;
                            stack.push(u);
                        }
                    }
                }
            }
            members.sort_unstable();
            out.push(members);
        }
        out
    }

    /// The piece of each vertex (its index in [`Self::pieces`]; 0 for a vertex on no
    /// triangle) and the number of pieces.
    pub fn vertex_pieces(&self) -> (Vec<u32>, usize) {
        let pieces = self.pieces();
        let mut of_triangle = vec![0u32; self.num_triangles()];
        for (k, p) in pieces.iter().enumerate() {
            for &t in p {
                of_triangle[t as usize] = k as u32;
            }
        }
        let of_vertex = self
            .vertex_he
            .iter()
            .map(|&h| {
                if h == NONE {
                    0
                } else {
                    of_triangle[(h / 3) as usize]
                }
            })
            .collect();
        (of_vertex, pieces.len())
    }

    /// Checks what a torn sheet keeps: every vertex's triangles form one fan (no bow-tie
    /// vertex) and every piece is a disc (χ = V − E + F = 1). Returns the number of pieces.
    pub fn validate_pieces(&self) -> Result<usize, String> {
        let nv = self.num_vertices();
        let mut incident = vec![0u32; nv];
        for h in &self.half_edges {
            incident[h.origin as usize] += 1;
        }
        for (v, (&start, &count)) in self.vertex_he.iter().zip(&incident).enumerate() {
            if start == NONE {
                continue;
            }
            // Around v through the twins from its (boundary-preferred) outgoing half-edge.
            let (mut h, mut walked) = (start, 0u32);
            loop {
                walked += 1;
                let prev = self.half_edges[self.half_edges[h as usize].next as usize].next;
                let twin = self.half_edges[prev as usize].twin;
                if twin == NONE || twin == start || walked > count {
                    break;
                }
                h = twin;
            }
            if walked != count {
                return Err(format!(
                    "vertex {v} has {count} triangles, {walked} in one fan"
                ));
            }
        }
        let pieces = self.pieces();
        let mut piece_of = vec![0usize; self.num_triangles()];
        for (k, p) in pieces.iter().enumerate() {
            for &t in p {
                piece_of[t as usize] = k;
            }
        }
        let mut chi = vec![0i64; pieces.len()];
        for (k, p) in pieces.iter().enumerate() {
            chi[k] += p.len() as i64;
        }
        for e in &self.edges {
            chi[piece_of[(e.he[0] / 3) as usize]] -= 1;
        }
        for v in 0..nv {
            if self.vertex_he[v] != NONE {
                chi[piece_of[(self.vertex_he[v] / 3) as usize]] += 1;
            }
        }
        if let Some(k) = chi.iter().position(|&c| c != 1) {
            return Err(format!("piece {k} has χ = {}, not a disc", chi[k]));
        }
        Ok(pieces.len())
    }

    /// Euler characteristic V − E + F (1 for a disc-like sheet).
    pub fn euler_characteristic(&self) -> i64 {
        self.num_vertices() as i64 - self.edges.len() as i64 + self.num_triangles() as i64
    }

    /// Checks the internal consistency of the structure (twins, next cycles, edge lists).
    pub fn validate(&self) -> Result<(), String> {
        let nh = self.half_edges.len() as u32;
        for (i, h) in self.half_edges.iter().enumerate() {
            let i = i as u32;
            if h.next >= nh || h.face != i / 3 || h.origin as usize >= self.num_vertices() {
                return Err(format!("half-edge {i} has bad indices"));
            }
            let n = &self.half_edges[h.next as usize];
            if self.half_edges[n.next as usize].next != i {
                return Err(format!("half-edge {i}: next cycle is not a triangle"));
            }
            if h.twin != NONE {
                let t = &self.half_edges[h.twin as usize];
                if t.twin != i || t.origin != self.dest(i) || self.dest(h.twin) != h.origin {
                    return Err(format!("half-edge {i}: inconsistent twin"));
                }
            }
            let e = &self.edges[self.he_edge[i as usize] as usize];
            if !e.he.contains(&i) {
                return Err(format!("half-edge {i}: not listed by its edge"));
            }
        }
        for w in self.edges.windows(2) {
            if w[0].v >= w[1].v {
                return Err("edges are not in canonical order".into());
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Vec<[u32; 3]> {
        vec![[0, 1, 2], [0, 2, 3]]
    }

    #[test]
    fn square_has_five_edges_one_hinge() {
        let t = Topology::build(4, &square()).unwrap();
        assert_eq!(t.edges.len(), 5);
        assert_eq!(t.edges.iter().filter(|e| !e.is_boundary()).count(), 1);
        assert_eq!(t.euler_characteristic(), 1);
        assert!(t.vertex_on_boundary.iter().all(|&b| b));
        let e = t.find_edge(2, 0).unwrap();
        let edge = t.edges[e as usize];
        let wings = [t.opposite(edge.he[0]), t.opposite(edge.he[1])];
        assert!(wings.contains(&1) && wings.contains(&3));
        t.validate().unwrap();
    }

    #[test]
    fn rejects_bad_meshes() {
        assert_eq!(
            Topology::build(3, &[[0, 1, 5]]),
            Err(TopologyError::BadIndex(0))
        );
        assert_eq!(
            Topology::build(3, &[[0, 1, 1]]),
            Err(TopologyError::Degenerate(0))
        );
        assert_eq!(
            Topology::build(4, &[[0, 1, 2], [0, 1, 3]]),
            Err(TopologyError::Orientation(0, 1))
        );
        assert_eq!(
            Topology::build(5, &[[0, 1, 2], [1, 0, 3], [0, 1, 4]]),
            Err(TopologyError::NonManifoldEdge(0, 1))
        );
        assert_eq!(
            Topology::build(5, &square()),
            Err(TopologyError::IsolatedVertex(4))
        );
    }

    #[test]
    fn pieces_are_counted_and_bow_ties_refused() {
        // Two squares apart: two discs.
        let two = [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
        let t = Topology::build(8, &two).unwrap();
        assert_eq!(t.pieces(), vec![vec![0, 1], vec![2, 3]]);
        assert_eq!(t.vertex_pieces().1, 2);
        assert_eq!(t.validate_pieces(), Ok(2));
        // Two triangles meeting only at vertex 0: one vertex, two fans.
        let bow_tie = [[0, 1, 2], [0, 3, 4]];
        let t = Topology::build(5, &bow_tie).unwrap();
        assert!(t.validate_pieces().unwrap_err().contains("vertex 0"));
        // A fan all round an inner vertex (a closed fan) is one fan.
        let hexagon: Vec<[u32; 3]> = (0..6).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
        assert_eq!(
            Topology::build(7, &hexagon).unwrap().validate_pieces(),
            Ok(1)
        );
    }
}
