//! # Singular-vertex generation and fibre damage (module doc steps 5–6 of [`super`]; TOG 2015 §4.3,
//! thesis §2.4.4; digest-crumpling §3.5): placing a persistent singular vertex at s̄, by moving the
//! nearest S_P vertex or, pending, by an inserted one, and the plastic rest angles and damage
//! around it.

use super::*;

impl GeometryLayer {
    pub(super) fn push_singular(
        &mut self,
        sp: &PhysMesh,
        v: u32,
        sampled2: V2,
        frame: u64,
        case: SingularCase,
    ) {
        self.is_singular[v as usize] = true;
        self.out.singular.push(SingularPoint {
            sp_vertex: v,
            sampled2,
            pos2: sp.pattern[v as usize],
            pos3: sp.pos[v as usize],
            created_frame: frame,
            case,
        });
    }

    /// Step 5–6: a singular vertex about `edge`, with fibre damage. Returns false when no
    /// S_P vertex is eligible.
    #[allow(clippy::too_many_arguments)] // the frame loop's state, passed explicitly
    pub(super) fn create_singular(
        &mut self,
        sp: &mut PhysMesh,
        sg: &mut GeomStructure,
        fixed: &[bool],
        edge: u32,
        case: SingularCase,
        compression: f64,
        frame: u64,
    ) -> bool {
        if self.out.singular.len() >= self.out.singular.capacity() {
            return false;
        }
        let topo = &sp.topo;
        let e = topo.edges[edge as usize];
        let (a, b) = (sp.pattern[e.v[0] as usize], sp.pattern[e.v[1] as usize]);
        let pl = placement::sample_near_segment(a, b, self.sigma_m, &mut self.rng);
        // Candidates: the edge's endpoints and wing vertices.
        let mut cand = [NONE; 4];
        cand[0] = e.v[0];
        cand[1] = e.v[1];
        for (k, &h) in e.he.iter().enumerate() {
            if h != NONE {
                cand[2 + k] = topo.opposite(h);
            }
        }
        let mut best: Option<(f64, u32)> = None;
        for &v in &cand {
            if v == NONE {
                continue;
            }
            let vi = v as usize;
            // Interior, not yet singular, and outside a hand's pinch (held or next to held).
            if topo.vertex_on_boundary[vi]
                || self.is_singular[vi]
                || fixed[vi]
                || topo.neighbours(v).iter().any(|&j| fixed[j as usize])
            {
                continue;
            }
            let d = (sp.pattern[vi] - pl.pos).norm_squared();
            if best.is_none_or(|b| d < b.0 || (d == b.0 && v < b.1)) {
                best = Some((d, v));
            }
        }
        let Some((_, v)) = best else {
            return false;
        };
        let dihedral_rad = self.out.edge_dihedral_rad[edge as usize].abs();
        // The d-cone apex goes to the drawn position: the nearest vertex moves there if the
        // triangles around it stay well shaped, else (with insertion on) a new vertex is
        // inserted there after the frame; with insertion off the vertex moves part of the
        // way. Placement resolution σ, not the S_P edge.
        let exact = self.cfg.insert_singular_vertices && self.pending.is_none();
        let fractions: &[f64] = if exact { &[1.0] } else { &[1.0, 0.5, 0.25] };
        if sp.move_pattern_vertex_by(v, pl.pos, fractions) != V2::zeros() {
            self.after_pattern_move(sp, v);
        } else if exact && sp.pattern[v as usize] != pl.pos {
            self.pending = Some(PendingSingular {
                sampled2: pl.pos,
                fallback_vertex: v,
                case,
                compression,
                dihedral_rad,
                frame,
            });
            return true;
        }
        self.make_singular(sp, sg, v, pl.pos, case, compression, dihedral_rad, frame);
        true
    }

    /// Refreshes what the layer caches of S_P's rest shape around `v` after its pattern
    /// position moved.
    pub(super) fn after_pattern_move(&mut self, sp: &PhysMesh, v: u32) {
        let (a, b) = (
            self.vert_tris_start[v as usize] as usize,
            self.vert_tris_start[v as usize + 1] as usize,
        );
        for k in a..b {
            let t = self.vert_tris[k] as usize;
            self.tri_h[t] = (4.0 * sp.tri_rest[t].area_m2 / 3f64.sqrt()).sqrt();
        }
        self.iso.refresh_rest(sp);
        // As `new` reads them, so a sheet restored from the moved pattern matches.
        self.spacing_m = sp.edge_rest_len_m.iter().sum::<f64>() / sp.num_edges().max(1) as f64;
        self.theta_sing = THETA0_RAD * (self.spacing_m * RHO_BOUND_PER_M).max(1.0);
    }

    /// Step 6: vertex `v` becomes singular, with fibre damage (P eq. 1, T eq. 2.1–2.2) on the
    /// edges around it, signed by their fold in this frame's analysis.
    #[allow(clippy::too_many_arguments)] // the singular point's record, passed explicitly
    pub(super) fn make_singular(
        &mut self,
        sp: &mut PhysMesh,
        sg: &mut GeomStructure,
        v: u32,
        sampled2: V2,
        case: SingularCase,
        compression: f64,
        dihedral_rad: f64,
        frame: u64,
    ) {
        let topo = &sp.topo;
        let nbrs = topo.neighbours(v);
        let n = nbrs.len().max(1) as f64;
        let (dtheta, dd) = (THETA_REST_RAD / n, DAMAGE_D / n);
        for &j in nbrs {
            if let Some(ei) = topo.find_edge(v, j) {
                let ei = ei as usize;
                let sign = if self.out.edge_dihedral_rad[ei] < 0.0 {
                    -1.0
                } else {
                    1.0
                };
                sp.edge_rest_angle[ei] += sign * dtheta;
                sp.edge_damage[ei] += dd;
            }
        }
        sp.singular.push(v);
        self.push_singular(sp, v, sampled2, frame, case);
        sg.vertices.push(GVertex::interior_singular(sp, v));
        let idx = self.out.singular.len() as u32 - 1;
        self.out.push_event(ShapeEvent::SingularCreated {
            singular: idx,
            sp_vertex: v,
            case,
            compression,
            dihedral_rad,
        });
    }

    /// The singular vertex drawn this frame that waits for an inserted S_P vertex, if any
    /// (taken: the sim either inserts it, [`Self::singular_at_inserted`], or falls back,
    /// [`Self::singular_by_move`]; a frame that is undone just drops it).
    pub fn take_pending_singular(&mut self) -> Option<PendingSingular> {
        self.pending.take()
    }

    /// Vertex `v` becomes the pending singular vertex `p`.
    pub(super) fn make_pending_singular(
        &mut self,
        sp: &mut PhysMesh,
        sg: &mut GeomStructure,
        v: u32,
        p: &PendingSingular,
    ) {
        let (s2, case, c, d, f) = (p.sampled2, p.case, p.compression, p.dihedral_rad, p.frame);
        self.make_singular(sp, sg, v, s2, case, c, d, f);
    }

    /// The singular vertex waiting for an inserted S_P vertex, if any.
    pub fn pending_singular(&self) -> Option<&PendingSingular> {
        self.pending.as_ref()
    }

    /// Makes the vertex inserted at `p.sampled2` singular (`self` is the layer
    /// [`Self::remeshed`] built for the refined S_P, whose analysis is current).
    pub fn singular_at_inserted(
        &mut self,
        sp: &mut PhysMesh,
        sg: &mut GeomStructure,
        v: u32,
        p: &PendingSingular,
    ) {
        self.make_pending_singular(sp, sg, v, p);
    }

    /// The fallback when no vertex can be inserted at s̄: the nearest vertex moves towards it
    /// as far as its triangles allow (the behaviour with insertion off), if it is still
    /// eligible. Returns whether a singular vertex was made.
    pub fn singular_by_move(
        &mut self,
        sp: &mut PhysMesh,
        sg: &mut GeomStructure,
        fixed: &[bool],
        p: &PendingSingular,
    ) -> bool {
        let v = p.fallback_vertex;
        let vi = v as usize;
        if vi >= sp.num_vertices()
            || self.is_singular[vi]
            || self.out.singular.len() >= self.out.singular.capacity()
            || fixed.get(vi).copied().unwrap_or(true)
            || sp.topo.neighbours(v).iter().any(|&j| fixed[j as usize])
        {
            return false;
        }
        if sp.move_pattern_vertex(v, p.sampled2) != V2::zeros() {
            self.after_pattern_move(sp, v);
        }
        self.make_pending_singular(sp, sg, v, p);
        true
    }
}
