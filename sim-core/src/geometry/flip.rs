//! # Finding a compressed flat-region edge to flip (module doc step 2 of [`super`]; thesis T
//! 811–828; the flip itself is [`crate::sheet::refine::flip_edge`]).

use super::*;

impl GeometryLayer {
    /// Step (d), edge flipping in flat regions (digest-crumpling §3.1, T 811–828): among the
    /// interior edges between two flat triangles that are coplanar (|θ| < θ0, so in one flat
    /// region), the most compressed one (c_e > ε_c) whose quad's other diagonal is not
    /// (c ≤ ε_c, its 3D length from the four vertices' positions, its rest length from the
    /// pattern) becomes this frame's pending flip, if the flip is allowed (no rest angle or
    /// damage on the edge, no held or singular vertex in the quad, well-shaped new triangles:
    /// [`crate::sheet::refine::flip_edge`]). The sim flips it at the start of the next step.
    pub(super) fn find_flip(&mut self, sp: &PhysMesh, frame: u64) {
        let topo = &sp.topo;
        let mut best: Option<PendingFlip> = None;
        for (ei, e) in topo.edges.iter().enumerate() {
            if e.is_boundary() || self.out.edge_dihedral_rad[ei].abs() >= THETA0_RAD {
                continue;
            }
            let [h1, h2] = e.he;
            let (f1, f2) = (
                topo.half_edges[h1 as usize].face as usize,
                topo.half_edges[h2 as usize].face as usize,
            );
            if self.curved[f1] || self.curved[f2] {
                continue;
            }
            let rest = sp.edge_rest_len_m[ei];
            let [u, w] = e.v;
            let c = (rest - (sp.pos[u as usize] - sp.pos[w as usize]).norm()) / rest;
            if c.is_nan() || c <= self.eps_c || best.is_some_and(|b| b.compression >= c) {
                continue;
            }
            let (x1, x2) = (topo.opposite(h1), topo.opposite(h2));
            let quad = [u, w, x1, x2];
            if sp.edge_rest_angle[ei] != 0.0
                || sp.edge_damage[ei] != 0.0
                || quad
                    .iter()
                    .any(|&v| self.near_held[v as usize] || self.is_singular[v as usize])
            {
                continue;
            }
            // The quad bends across the other diagonal, not across this edge (Fig. 2.5: the
            // lifted corner folds the quad along x1–x2): a flat quad merely squeezed in its
            // plane, as a whole sheet is at the onset of a crumple, keeps its triangles.
            let th1 = self.out.edge_dihedral_rad[ei].abs();
            let th2 = dihedral(&[x1, x2, u, w].map(|v| sp.pos[v as usize])).abs();
            if !(th2 >= THETA_LOW_RAD && th2 > th1 && th2 < std::f64::consts::FRAC_PI_2) {
                continue;
            }
            let rest2 = (sp.pattern[x1 as usize] - sp.pattern[x2 as usize]).norm();
            let c2 = (rest2 - (sp.pos[x1 as usize] - sp.pos[x2 as usize]).norm()) / rest2;
            if c2.is_nan()
                || c2 > self.eps_c
                || !crate::sheet::refine::flip_is_well_shaped(sp, ei as u32)
            {
                continue;
            }
            best = Some(PendingFlip {
                edge: [u.min(w), u.max(w)],
                compression: c,
                other_compression: c2,
                frame,
            });
        }
        self.pending_flip = best;
    }

    /// The edge found last frame to be flipped, if any (taken: the sim flips it, then calls
    /// [`Self::edge_flipped`] on the layer rebuilt for the new mesh; an undone frame drops it).
    pub fn take_pending_flip(&mut self) -> Option<PendingFlip> {
        self.pending_flip.take()
    }

    /// The edge waiting to be flipped, if any.
    pub fn pending_flip(&self) -> Option<&PendingFlip> {
        self.pending_flip.as_ref()
    }

    /// Reports the flip of `f`'s edge into `diagonal` as this frame's event.
    pub fn edge_flipped(&mut self, f: &PendingFlip, diagonal: [u32; 2]) {
        self.out.push_event(ShapeEvent::EdgeFlipped {
            diagonal,
            compression: f.compression,
        });
    }
}
