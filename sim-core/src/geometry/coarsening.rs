//! # Finding a cut vertex to take out again (module doc step 11 of [`super`]; the collapse itself is
//! [`crate::sheet::coarsen`]).

use super::*;

impl GeometryLayer {
    /// Step 10, coarsening (module doc, "Coarsening"): the last vertex beyond the initial
    /// lattice that is not singular, not held or next to a held vertex, whose triangles are
    /// all flat-region triangles, whose edges are uncreased and bent by less than θ0, which
    /// moves with its neighbours (relative speed below [`COARSEN_MAX_REL_SPEED_M_S`]) and which
    /// a neighbour can take the place of ([`crate::sheet::coarsen::collapse_target`]) becomes
    /// the pending coarsening. Only when no other mesh change is pending (the others name
    /// vertices by index). Allocation-free.
    pub(super) fn find_coarsening(&mut self, sp: &PhysMesh, frame: u64) {
        if self.pending_coarsen.is_some()
            || self.pending.is_some()
            || self.pending_flip.is_some()
            || self.pending_cut_frame.is_some()
        {
            return;
        }
        let topo = &sp.topo;
        for v in (self.coarsen_from..sp.num_vertices()).rev() {
            if self.is_singular[v] || self.near_held[v] {
                continue;
            }
            let (a, b) = (
                self.vert_tris_start[v] as usize,
                self.vert_tris_start[v + 1] as usize,
            );
            if self.vert_tris[a..b]
                .iter()
                .any(|&t| self.curved[t as usize])
            {
                continue;
            }
            let still = topo.neighbours(v as u32).iter().all(|&j| {
                let e = topo.find_edge(v as u32, j).map_or(0, |e| e as usize);
                self.out.edge_dihedral_rad[e].abs() < THETA0_RAD
                    && sp.edge_rest_angle[e] == 0.0
                    && sp.edge_damage[e] == 0.0
                    && (sp.vel[v] - sp.vel[j as usize]).norm() < COARSEN_MAX_REL_SPEED_M_S
            });
            if still
                && crate::sheet::coarsen::collapse_target(sp, v as u32, &self.vert_tris[a..b])
                    .is_some()
            {
                self.pending_coarsen = Some((v as u32, frame));
                return;
            }
        }
    }

    /// The vertex found to be taken out of a flat region, if any (taken: the sim collapses it,
    /// [`crate::sheet::coarsen::collapse_vertex`], then calls [`Self::vertex_collapsed`] on
    /// the layer rebuilt for the new mesh; an undone frame drops it).
    pub fn take_pending_coarsen(&mut self) -> Option<u32> {
        self.pending_coarsen.take().map(|(v, _)| v)
    }

    /// The vertex waiting to be taken out of a flat region, if any.
    pub fn pending_coarsen(&self) -> Option<u32> {
        self.pending_coarsen.map(|(v, _)| v)
    }

    /// Reports that vertex `removed` (its index before) was merged into `into` (its index
    /// now) as this frame's event.
    pub fn vertex_collapsed(&mut self, removed: u32, into: u32) {
        self.out
            .push_event(ShapeEvent::VertexCollapsed { removed, into });
    }
}
