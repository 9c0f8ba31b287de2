//! # Carrying the geometry layer over to a changed S_P (a vertex inserted, an edge flipped, a strip
//! cut, a vertex taken out; the sim's side is `sim/remesh.rs`).

use super::*;

impl GeometryLayer {
    /// This layer carried over to `sp`, S_P refined by [`crate::sheet::refine`] (old vertices
    /// keep their index; `tri_parent` names each new triangle's old triangle): the persistent
    /// state goes through [`Self::save`] / [`Self::restore`] as for a saved sheet, with the
    /// per-triangle state (curved flags, refractory frames) taken from the parent triangle;
    /// this frame's events and counters are kept. After a coarsening ([`crate::sheet::coarsen`])
    /// or a regeneration ([`crate::sheet::regenerate`]) `old_to_new` maps every old vertex to
    /// its new index ([`crate::sheet::topology::NONE`]: gone), in the saved state as in the
    /// mesh; a saved state naming a vertex that is gone is an error. Allocates (a connectivity
    /// change).
    pub fn remeshed(
        &self,
        sp: &PhysMesh,
        sg: &mut GeomStructure,
        tri_parent: &[u32],
        old_to_new: Option<&[u32]>,
        mat: &PaperMaterial,
        seed: u64,
    ) -> Result<Self, String> {
        let mut saved = self.save();
        if let Some(m) = old_to_new {
            let map = |v: u32| {
                m.get(v as usize)
                    .copied()
                    .filter(|&n| n != crate::sheet::topology::NONE)
                    .ok_or("a removed vertex is named")
            };
            for s in &mut saved.singular {
                s.0 = map(s.0)?;
            }
            if let Some(p) = &mut saved.pending_singular {
                p.1 = map(p.1)?;
            }
            if let Some(f) = &mut saved.pending_flip {
                f.0 = [map(f.0[0])?, map(f.0[1])?];
            }
            if let Some((line, _)) = &mut saved.pending_cut {
                for c in line {
                    c.0 = [map(c.0[0])?, map(c.0[1])?];
                }
            }
            if let Some(c) = &mut saved.pending_coarsen {
                c.0 = map(c.0)?;
            }
            // Old vertices keep their order: the lattice's survivors are still the first ones.
            if let Some(c) = &mut saved.coarsen_from {
                *c = m
                    .iter()
                    .take(*c as usize)
                    .filter(|&&n| n != crate::sheet::topology::NONE)
                    .count() as u32;
            }
        }
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
        match old_to_new {
            None => {
                for (slot, &j) in g.junction_prev.iter_mut().zip(&self.junction_prev) {
                    *slot = j;
                }
            }
            Some(m) => {
                for (&n, &j) in m.iter().zip(&self.junction_prev) {
                    if let Some(slot) = g.junction_prev.get_mut(n as usize) {
                        *slot = j;
                    }
                }
            }
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
