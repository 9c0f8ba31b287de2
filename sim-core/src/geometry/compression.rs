//! # Compression analysis and imaginary-ruling propagation (module doc steps 3–4 of [`super`];
//! TOG 2015 §4.2 and Appendix A, thesis §2.4.3; digest-crumpling §3.2–3.4): the most compressed
//! flat triangle starts a pass, the walk along v⊥ ends at two borders, the strip becomes curved.

use super::*;

impl GeometryLayer {
    /// Steps 3–6: compression analysis, propagation, singular vertices, fibre damage.
    pub(super) fn treat_compression(
        &mut self,
        sp: &mut PhysMesh,
        sg: &mut GeomStructure,
        fixed: &[bool],
        frame: u64,
    ) -> u32 {
        let mut new_singular = 0u32;
        self.out.max_flat_compression = 0.0;
        let cos_along = CONFLICT_RAD.cos();
        self.out.max_curved_compression = 0.0;
        for pass in 0..self.cfg.max_passes {
            // Most compressed flat triangle, or curved triangle compressed along its own
            // rulings (a conflict with its ruling family, case A).
            let mut best: Option<(f64, usize, stretch::Stretch)> = None;
            for t in 0..sp.num_triangles() {
                let x = sp.triangles[t].map(|i| sp.pos[i as usize]);
                let s = stretch::stretch_tensor(&x, &sp.tri_rest[t].dm_inv);
                let c = s.compression();
                if !c.is_finite() {
                    continue;
                }
                // Triangles in a hand's pinch (touching a held vertex or one of its
                // neighbours) are strained by the hard constraint itself.
                if sp.triangles[t].iter().any(|&v| self.near_held[v as usize]) {
                    continue;
                }
                if self.curved[t] {
                    // Compression along a well-defined ruling direction (v ∥ r̄_t).
                    if self.tri_aniso[t] > ANISO_MAX
                        || s.v.dot(&self.tri_ruling[t]).abs() < cos_along
                    {
                        continue;
                    }
                    if pass == 0 {
                        self.out.max_curved_compression = self.out.max_curved_compression.max(c);
                    }
                    if c <= self.eps_c * self.cfg.curved_eps_factor {
                        continue;
                    }
                } else if pass == 0 {
                    self.out.max_flat_compression = self.out.max_flat_compression.max(c);
                }
                if c > self.eps_c
                    && self.refractory_until[t] <= frame
                    && best.is_none_or(|b| c > b.0)
                {
                    best = Some((c, t, s));
                }
            }
            let Some((c_t, t_comp, s)) = best else {
                break;
            };
            let borders = if self.curved[t_comp] {
                // Compression along the rulings of a curved region: the singular point goes
                // about its most bent edge (the first strongly bent ruling, P 700–704).
                self.strip.clear();
                self.strip.push(t_comp as u32);
                let mut e_best: Option<(f64, u32)> = None;
                for k in 0..3 {
                    let e = sp.topo.he_edge[3 * t_comp + k];
                    let th = self.out.edge_dihedral_rad[e as usize].abs();
                    if !sp.topo.edges[e as usize].is_boundary() && e_best.is_none_or(|b| th > b.0) {
                        e_best = Some((th, e));
                    }
                }
                match e_best {
                    Some((th, e)) if th > self.theta_sing => [Border::InCurved(e), Border::None],
                    _ => [Border::None, Border::None],
                }
            } else {
                self.propagate(sp, t_comp as u32, s.v_perp)
            };
            let mut made = 0;
            for b in borders {
                let (edge, case) = match b {
                    Border::Crease(e) => (e, SingularCase::Crease),
                    Border::InCurved(e) => (e, SingularCase::CurvedRegion),
                    _ => continue,
                };
                if new_singular >= self.cfg.max_new_singular_per_frame {
                    continue;
                }
                if self.create_singular(sp, sg, fixed, edge, case, c_t, frame) {
                    new_singular += 1;
                    made += 1;
                }
            }
            let cylinder = borders.iter().all(|b| *b == Border::Free);
            let was_curved = self.curved[t_comp];
            for &t in &self.strip {
                self.curved[t as usize] = true;
                self.refractory_until[t as usize] = frame + REFRACTORY_FRAMES;
            }
            if made == 0 && !was_curved {
                let n = self.strip.len() as u32;
                self.out.push_event(ShapeEvent::StripCurved {
                    num_triangles: n,
                    compression: c_t,
                    cylinder,
                });
            }
        }
        new_singular
    }

    /// Step 4: imaginary-ruling propagation from `t_comp` along ±`v_perp`; fills `strip`.
    pub(super) fn propagate(&mut self, sp: &PhysMesh, t_comp: u32, v_perp: V2) -> [Border; 2] {
        self.strip.clear();
        self.strip.push(t_comp);
        let tri = sp.triangles[t_comp as usize];
        let centroid = (sp.pattern[tri[0] as usize]
            + sp.pattern[tri[1] as usize]
            + sp.pattern[tri[2] as usize])
            / 3.0
            + off_line(v_perp, self.tri_h[t_comp as usize]);
        let cos_conflict = CONFLICT_RAD.cos();
        let theta_sing = self.theta_sing;
        let mut borders = [Border::None; 2];
        for (side, dir) in [v_perp, -v_perp].into_iter().enumerate() {
            let mut border = Border::None;
            let mut in_curved: Option<(u32, u32)> = None; // (last edge crossed, steps inside)
            let th = &self.out.edge_dihedral_rad;
            let curved = &self.curved;
            let ruling = &self.tri_ruling;
            let aniso = &self.tri_aniso;
            let bend = &self.tri_bend;
            let strip = &mut self.strip;
            walk::walk(sp, t_comp, centroid, dir, MAX_WALK, |c| {
                if let Some((_, steps)) = in_curved {
                    if c.to == NONE || steps >= 4 {
                        // No strongly bent ruling right behind the border: the curved region
                        // absorbs the new rulings (no singular point).
                        border = Border::Compatible;
                        return false;
                    }
                    if th[c.edge as usize].abs() > theta_sing {
                        border = Border::InCurved(c.edge);
                        return false;
                    }
                    in_curved = Some((c.edge, steps + 1));
                    return true;
                }
                if c.to == NONE {
                    border = Border::Free;
                    return false;
                }
                let to = c.to as usize;
                if !curved[to] {
                    if th[c.edge as usize].abs() < THETA0_RAD {
                        if strip.len() < strip.capacity() {
                            strip.push(c.to);
                        }
                        true
                    } else {
                        border = Border::Crease(c.edge);
                        false
                    }
                } else if ruling[to].dot(&dir).abs() >= cos_conflict
                    || aniso[to] > ANISO_MAX
                    || bend[to] <= theta_sing
                {
                    // Compatible, or not a clear, strongly bent ruling family: it grows.
                    border = Border::Compatible;
                    false
                } else {
                    in_curved = Some((c.edge, 0));
                    true
                }
            });
            borders[side] = border;
        }
        borders
    }
}
