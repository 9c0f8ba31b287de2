//! # What the geometry layer publishes per frame ([`GeometryFrame`], module doc steps 7–10 of
//! [`super`]): the region partition, rulings with their dihedral angles, free curved borders,
//! singular points, cones and the frame's sudden shape changes, for sound and tearing.

use super::*;

/// Kind of an S_P triangle in the partition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TriKind {
    /// Part of a flat region (coplanar with its flat neighbours).
    #[default]
    Flat,
    /// Part of a curved region (a generalized cone).
    Curved,
    /// Incident to an interior singular vertex (a d-cone's neighbourhood); its region is
    /// still given by `tri_region`.
    SingularFan,
}

/// Kind of a region.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RegionKind {
    /// A flat region: a *constrained* resonator for the sound model (T 1768).
    #[default]
    Flat,
    /// A curved region: an *unconstrained* resonator with free curved borders.
    Curved,
    /// A crease between two flat regions: the seeds' degenerate curved region with one
    /// ruling (T 740); here the chain of S_P edges between the two regions, one ruling each,
    /// `mean_ruling_len_m` the crease's whole length.
    Crease,
}

/// One region of the partition.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Region {
    /// Kind.
    pub kind: RegionKind,
    /// S_P triangles in it (0 for a crease).
    pub num_triangles: u32,
    /// Pattern area, m².
    pub area_m2: f64,
    /// l_c: total pattern length of its free curved border edges (curved regions), metres.
    pub free_border_len_m: f64,
    /// Free border edges (entries of [`GeometryFrame::free_borders`]).
    pub num_free_border_edges: u32,
    /// Its rulings are `rulings[first_ruling .. first_ruling + num_rulings]`, ordered across
    /// the region.
    pub first_ruling: u32,
    /// Number of rulings.
    pub num_rulings: u32,
    /// l_r: mean pattern length of its rulings, metres (0 without rulings).
    pub mean_ruling_len_m: f64,
    /// Largest |dihedral| of its rulings, radians.
    pub max_abs_dihedral_rad: f64,
    /// Index into [`GeometryFrame::singular`] of an interior singular vertex in it (the
    /// region is then one cone with that apex), `u32::MAX` if none.
    pub singular_apex: u32,
}

/// One ruling: a straight line of the pattern, isometric to a straight segment in 3D.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RulingInfo {
    /// Region it belongs to.
    pub region: u32,
    /// Pattern endpoints, metres.
    pub a2: V2,
    /// Pattern endpoints, metres.
    pub b2: V2,
    /// 3D endpoints (interpolated on S_P), metres.
    pub a3: V3,
    /// 3D endpoints, metres.
    pub b3: V3,
    /// Pattern length, metres.
    pub length_m: f64,
    /// Signed dihedral angle across the ruling, radians (ridges: |·| > [`RIDGE_RAD`]): the
    /// mean curvature along it × its strip width (half the distance to its neighbours; the
    /// angle between the tangent planes of neighbouring rulings, as the seeds' quads have);
    /// a crease's own S_P edge angle.
    pub dihedral_rad: f64,
    /// Mean signed normal curvature across the ruling along its length, 1/m (0 for a crease).
    pub curvature_per_m: f64,
    /// Unit tangent-plane normal along the ruling (the cone fit's n_i).
    pub normal: V3,
    /// The S_P edge for a crease ruling, `u32::MAX` for a traced one.
    pub sp_edge: u32,
    /// The pattern point the ruling was traced through (its seed; realignment turns the line
    /// about it, [`realign`]).
    pub anchor2: V2,
    /// The S_P triangle holding `anchor2`, `u32::MAX` for crease and resampled rulings.
    pub anchor_tri: u32,
    /// Added by boundary resampling ([`realign`]): endpoints on the chords between its
    /// neighbours' endpoints, 3D by cubic interpolation along them, not traced on S_P.
    pub resampled: bool,
}

/// A free curved border edge (an S_P boundary edge of a curved region, T 1704, 1721).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FreeBorderEdge {
    /// Region.
    pub region: u32,
    /// S_P edge.
    pub edge: u32,
    /// Pattern length, metres.
    pub length_m: f64,
}

/// How a singular vertex was born (§3.5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SingularCase {
    /// Case B: the propagation hit a crease between flat regions (Fig. 6c).
    #[default]
    Crease,
    /// Case A: the propagation met conflicting rulings of a curved region (Fig. 6d).
    CurvedRegion,
    /// Restored from a saved sheet of version 2, which did not record the case.
    Restored,
    /// A vertex whose 1-ring is bent in two directions (ruling families meeting at an
    /// angle, P 685–704); impl. choice, see the module doc.
    NonDevelopable,
}

impl SingularCase {
    /// The case's number in a saved sheet.
    pub(super) fn code(self) -> u8 {
        match self {
            SingularCase::Crease => 0,
            SingularCase::CurvedRegion => 1,
            SingularCase::Restored => 2,
            SingularCase::NonDevelopable => 3,
        }
    }

    /// The case of a saved number (unknown numbers: restored).
    pub(super) fn of_code(c: u8) -> Self {
        match c {
            0 => SingularCase::Crease,
            1 => SingularCase::CurvedRegion,
            3 => SingularCase::NonDevelopable,
            _ => SingularCase::Restored,
        }
    }
}

/// A singular vertex drawn in a frame whose nearest S_P vertex could not move to s̄ in full:
/// the sim inserts a vertex at s̄ after the frame and makes it singular
/// ([`GeometryLayer::take_pending_singular`], [`crate::sheet::refine`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PendingSingular {
    /// The drawn pattern position s̄, metres.
    pub sampled2: V2,
    /// The nearest eligible S_P vertex: moved towards s̄ instead if the insertion is refused.
    pub fallback_vertex: u32,
    /// How it was born.
    pub case: SingularCase,
    /// Compression that started the pass (for the event).
    pub compression: f64,
    /// |θ| of the edge the point was drawn about, radians (for the event).
    pub dihedral_rad: f64,
    /// Frame in which it was drawn.
    pub frame: u64,
}

/// A compressed flat-region edge to flip (digest-crumpling §3.1, T 811–828): found by the
/// layer, flipped by the sim at the start of the next step ([`GeometryLayer::take_pending_flip`],
/// [`crate::sheet::refine::flip_edge`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PendingFlip {
    /// The edge's vertices, ascending.
    pub edge: [u32; 2],
    /// Its compression c_e = (l̄ − l)/l̄ (> ε_c).
    pub compression: f64,
    /// The compression of the quad's other diagonal (≤ ε_c).
    pub other_compression: f64,
    /// Frame in which it was found.
    pub frame: u64,
}

/// A persistent interior singular vertex (d-cone apex).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SingularPoint {
    /// Its S_P vertex.
    pub sp_vertex: u32,
    /// The position drawn by the placement law, metres (pattern).
    pub sampled2: V2,
    /// Pattern position of the vertex (fixed forever), metres.
    pub pos2: V2,
    /// Current 3D position, metres.
    pub pos3: V3,
    /// Frame it was created in.
    pub created_frame: u64,
    /// Case.
    pub case: SingularCase,
}

/// A generalized cone (or gap cone) of a curved region.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ConeInfo {
    /// Region.
    pub region: u32,
    /// Apex in the pattern, `None` at infinity (generalized cylinder).
    pub apex2: Option<V2>,
    /// Apex in 3D, `None` at infinity.
    pub apex3: Option<V3>,
    /// First ruling (index into [`GeometryFrame::rulings`]).
    pub first_ruling: u32,
    /// Last ruling (inclusive).
    pub last_ruling: u32,
    /// Gap (junction) cone between two fitted cones (P 895–901).
    pub is_gap: bool,
    /// RMS plane–apex distance of the fit, metres.
    pub rms_m: f64,
}

/// A sudden shape change of this frame (a "clac" candidate, T 1261).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShapeEvent {
    /// A new interior singular vertex.
    SingularCreated {
        /// Index into [`GeometryFrame::singular`].
        singular: u32,
        /// Its S_P vertex.
        sp_vertex: u32,
        /// How.
        case: SingularCase,
        /// Compression c_t of the triangle that started the propagation.
        compression: f64,
        /// |dihedral| of ē_sing, radians.
        dihedral_rad: f64,
    },
    /// A compressed flat strip became curved (a new curved region, or a grown one).
    StripCurved {
        /// Triangles in the strip.
        num_triangles: u32,
        /// Compression c_t of T_comp.
        compression: f64,
        /// True when both borders were free (a new generalized cylinder).
        cylinder: bool,
    },
    /// Curved triangles turned flat (regions flattened or shrunk).
    Flattened {
        /// Triangles that turned flat.
        num_triangles: u32,
    },
    /// The number of flat regions grew (a flat region split along a bent edge).
    FlatRegionSplit {
        /// Flat regions before.
        before: u32,
        /// Flat regions after.
        after: u32,
    },
    /// Junction points appeared or disappeared.
    JunctionsMoved {
        /// Boundary vertices whose junction status changed.
        count: u32,
    },
    /// A compressed flat-region edge was flipped (digest-crumpling §3.1): the sheet's
    /// triangles changed, not its shape.
    EdgeFlipped {
        /// The new edge's vertices (the old edge's opposite vertices), ascending.
        diagonal: [u32; 2],
        /// Compression of the old edge.
        compression: f64,
    },
    /// The geometry layer moved a vertex by more than [`JUMP_EVENT_M`].
    VertexJump {
        /// S_P vertex.
        vertex: u32,
        /// Distance, metres.
        jump_m: f64,
    },
}

/// Per-frame output of the geometry layer (read with `Sim::geometry`).
///
/// All per-triangle arrays are indexed like S_P triangles, vertex indices are S_P vertices
/// (the same indexing as `Sim::contacts`, which gives the contact vertices and their slip
/// speeds). Sound: per region, `mean_ruling_len_m` is l_r and `free_border_len_m` is l_c;
/// ridges are rulings with |dihedral| > [`RIDGE_RAD`]; `events` are this frame's sudden
/// changes. The lists are cleared and refilled every awake frame; `singular` only grows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GeometryFrame {
    /// Frame these outputs belong to.
    pub frame: u64,
    /// Region of every S_P triangle (index into `regions`).
    pub tri_region: Vec<u32>,
    /// Kind of every S_P triangle.
    pub tri_kind: Vec<TriKind>,
    /// Regions: flat and curved ones first (in order of their lowest triangle), then creases.
    pub regions: Vec<Region>,
    /// Rulings, contiguous per region.
    pub rulings: Vec<RulingInfo>,
    /// Free curved border edges.
    pub free_borders: Vec<FreeBorderEdge>,
    /// Persistent interior singular vertices, in creation order (never shrinks).
    pub singular: Vec<SingularPoint>,
    /// Cones and gap cones of the curved regions.
    pub cones: Vec<ConeInfo>,
    /// Junction points (boundary S_P vertices between a flat and a curved triangle).
    pub junctions: Vec<u32>,
    /// Held S_P vertices this frame (each handle's vertex and its tangent-plane neighbours,
    /// [`crate::handles`]): S_G's handle vertices (P 388–394).
    pub held: Vec<u32>,
    /// Signed dihedral angle of every S_P edge, radians (0 on the boundary).
    pub edge_dihedral_rad: Vec<f64>,
    /// This frame's sudden shape changes (at most [`MAX_EVENTS`]; `events_dropped` counts
    /// the rest).
    pub events: Vec<ShapeEvent>,
    /// Events that did not fit.
    pub events_dropped: u32,
    /// Number of flat regions.
    pub num_flat_regions: u32,
    /// Number of curved regions (creases not counted).
    pub num_curved_regions: u32,
    /// Number of crease regions.
    pub num_creases: u32,
    /// Largest compression c_t over flat triangles this frame.
    pub max_flat_compression: f64,
    /// Largest compression c_t over curved triangles compressed along their rulings.
    pub max_curved_compression: f64,
    /// Largest vertex displacement made by the layer this frame, metres.
    pub max_vertex_jump_m: f64,
    /// Boundary vertices whose junction status changed this frame.
    pub junction_moves: u32,
    /// The isometry optimizer's report.
    pub isometry: IsometryReport,
    /// The isometry result was discarded this frame because it would have turned a triangle
    /// over.
    pub isometry_reverted: bool,
}

impl GeometryFrame {
    pub(super) fn push_event(&mut self, e: ShapeEvent) {
        if self.events.len() < MAX_EVENTS {
            self.events.push(e);
        } else {
            self.events_dropped += 1;
        }
    }

    /// Mean ruling length l_r and free-border length l_c of a region (sound model, T 1800).
    pub fn resonator_sizes(&self, region: u32) -> Option<(f64, f64)> {
        let r = self.regions.get(region as usize)?;
        Some((r.mean_ruling_len_m, r.free_border_len_m))
    }

    /// Rulings of a region.
    pub fn region_rulings(&self, region: u32) -> &[RulingInfo] {
        match self.regions.get(region as usize) {
            Some(r) => {
                let a = r.first_ruling as usize;
                &self.rulings[a..a + r.num_rulings as usize]
            }
            None => &[],
        }
    }

    /// The whole S_G vertex set of this frame (see [`crate::sheet::geometric`]): the
    /// persistent corners, boundary samples and interior singular vertices of `sg`, then the
    /// junction points and the held (handle) vertices, each with its pattern and current 3D
    /// position from `sp`. Allocation-free.
    pub fn sg_vertices<'a>(
        &'a self,
        sg: &'a GeomStructure,
        sp: &'a PhysMesh,
    ) -> impl Iterator<Item = GVertex> + 'a {
        let per_frame = |kind: VKind| {
            move |&v: &u32| GVertex {
                p2: sp.pattern[v as usize],
                p3: sp.pos[v as usize],
                kind,
                bound_s_m: None,
                sp_index: v,
            }
        };
        sg.vertices
            .iter()
            .map(|g| GVertex {
                p3: sp.pos[g.sp_index as usize],
                ..*g
            })
            .chain(self.junctions.iter().map(per_frame(VKind::Junction)))
            .chain(self.held.iter().map(per_frame(VKind::Handle)))
    }

    /// Ridges: rulings bent beyond [`RIDGE_RAD`].
    pub fn ridges(&self) -> impl Iterator<Item = &RulingInfo> {
        self.rulings
            .iter()
            .filter(|r| r.dihedral_rad.abs() > RIDGE_RAD)
    }
}
