//! # Carrying the geometry layer over to a changed S_P (a vertex inserted, an edge flipped; the
//! sim's side is `sim/remesh.rs`).

use super::*;

impl GeometryLayer {
    /// This layer carried over to `sp`, S_P refined by [`crate::sheet::refine`] (old vertices
    /// keep their index; `tri_parent` names each new triangle's old triangle): the persistent
    /// state goes through [`Self::save`] / [`Self::restore`] as for a saved sheet, with the
    /// per-triangle state (curved flags, refractory frames) taken from the parent triangle;
    /// this frame's events and counters are kept. Allocates (a connectivity change).
    pub fn remeshed(
        &self,
        sp: &PhysMesh,
        sg: &mut GeomStructure,
        tri_parent: &[u32],
        mat: &PaperMaterial,
        seed: u64,
    ) -> Result<Self, String> {
        let mut saved = self.save();
        // A tear that ran through a singular vertex made it a lip vertex (sim/tear.rs): it
        // leaves the list with the sheet's (no other mesh change drops one).
        saved.singular.retain(|s| sp.singular.contains(&s.0));
        saved.curved = tri_parent
            .iter()
            .map(|&t| self.curved[t as usize])
            .collect();
        saved.refractory_until = tri_parent
            .iter()
            .map(|&t| self.refractory_until[t as usize])
            .collect();
        let mut g = Self::unpublished(sp, self.cfg, mat, seed);
        g.eps_c = self.eps_c;
        g.sigma_m = self.sigma_m;
        // A mesh change in the frame loop partitions the new mesh afresh, promotions included
        // (the live behaviour, unchanged).
        g.restore_with(sp, sg, Some(&saved), Promote::Yes)?;
        for (t, &p) in tri_parent.iter().enumerate() {
            g.prev_curved[t] = self.prev_curved[p as usize];
        }
        for (slot, &j) in g.junction_prev.iter_mut().zip(&self.junction_prev) {
            *slot = j;
        }
        g.out.frame = self.out.frame;
        g.out.events.clone_from(&self.out.events);
        g.out.events_dropped = self.out.events_dropped;
        g.out.max_vertex_jump_m = self.out.max_vertex_jump_m;
        g.out.junction_moves = self.out.junction_moves;
        g.frames_processed = self.frames_processed;
        g.keep_events = self.keep_events;
        Ok(g)
    }
}
