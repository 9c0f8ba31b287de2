//! # The region partition (module doc step 7 of [`super`]; TOG 2015 §5.1): flat regions of coplanar
//! triangles, curved regions of one ruling family, crease regions, junction points.

use super::*;

impl GeometryLayer {
    /// Step 7a: regions, creases, kinds, free borders, junctions. `promote`: whether lone flat
    /// facets beside curved triangles turn curved (not when the flags are a saved frame's,
    /// [`Self::restore`]).
    pub(super) fn partition(&mut self, sp: &PhysMesh, promote: Promote) {
        let topo = &sp.topo;
        let nt = sp.num_triangles();
        for (i, p) in self.uf.iter_mut().enumerate() {
            *p = i as u32;
        }
        let cos45 = std::f64::consts::FRAC_1_SQRT_2;
        // A flat triangle with no coplanar flat neighbour (each of its edges is either bent
        // by θ0 or more or shared with a curved triangle) is no flat region of the seeds but
        // a facet of the curved region or fold beside it: when it touches a curved triangle
        // it turns curved (and keeps the hysteresis), so a fold running across the lattice
        // is one strip of curved triangles instead of a chain of one-triangle flat regions.
        for t in 0..nt {
            if self.curved[t] || promote == Promote::No {
                continue;
            }
            let (mut coplanar_flat, mut by_curved) = (false, false);
            for k in 0..3 {
                let tw = topo.half_edges[3 * t + k].twin;
                if tw == NONE {
                    continue;
                }
                let n = topo.half_edges[tw as usize].face as usize;
                let e = topo.he_edge[3 * t + k] as usize;
                if self.curved[n] {
                    by_curved = true;
                } else if self.out.edge_dihedral_rad[e].abs() < THETA0_RAD {
                    coplanar_flat = true;
                }
            }
            if by_curved && !coplanar_flat {
                self.curved[t] = true;
            }
        }
        for (ei, e) in topo.edges.iter().enumerate() {
            if e.is_boundary() {
                continue;
            }
            let fa = topo.half_edges[e.he[0] as usize].face;
            let fb = topo.half_edges[e.he[1] as usize].face;
            let (ca, cb) = (self.curved[fa as usize], self.curved[fb as usize]);
            let th = self.out.edge_dihedral_rad[ei].abs();
            // Flat triangles join across coplanar edges; curved ones grow below.
            let join = !ca && !cb && th < THETA0_RAD;
            if join {
                union(&mut self.uf, fa, fb);
            }
        }
        // Curved regions grow from their most bent triangle: a curved neighbour (sharing an
        // edge or, for a fold across the lattice's diagonals whose curved triangles touch at
        // vertices only, a vertex) joins when its region-scale ruling is within 45° of the
        // seed's. Comparing with the seed, not pairwise, keeps a region one family of
        // rulings that fan by at most 90° (a generalized cone); pairwise chaining would let
        // the direction turn step by step across a whole crumpled sheet.
        self.grow_order.clear();
        self.grow_order
            .extend((0..nt as u32).filter(|&t| self.curved[t as usize]));
        let bend = &self.tri_bend;
        self.grow_order.sort_unstable_by(|&x, &y| {
            bend[y as usize]
                .total_cmp(&bend[x as usize])
                .then(x.cmp(&y))
        });
        for f in &mut self.grown {
            *f = false;
        }
        for oi in 0..self.grow_order.len() {
            let seed = self.grow_order[oi];
            if self.grown[seed as usize] {
                continue;
            }
            let d = self.tri_ruling_smooth[seed as usize];
            self.grown[seed as usize] = true;
            self.grow_stack.clear();
            self.grow_stack.push(seed);
            while let Some(t) = self.grow_stack.pop() {
                for &v in &sp.triangles[t as usize] {
                    let (a, b) = (
                        self.vert_tris_start[v as usize] as usize,
                        self.vert_tris_start[v as usize + 1] as usize,
                    );
                    for k in a..b {
                        let n = self.vert_tris[k];
                        let ni = n as usize;
                        if self.grown[ni]
                            || !self.curved[ni]
                            || self.tri_ruling_smooth[ni].dot(&d).abs() <= cos45
                        {
                            continue;
                        }
                        self.grown[ni] = true;
                        union(&mut self.uf, seed, n);
                        if self.grow_stack.len() < self.grow_stack.capacity() {
                            self.grow_stack.push(n);
                        }
                    }
                }
            }
        }
        let out = &mut self.out;
        out.regions.clear();
        out.rulings.clear();
        out.free_borders.clear();
        out.cones.clear();
        out.junctions.clear();
        out.num_flat_regions = 0;
        out.num_curved_regions = 0;
        out.num_creases = 0;
        for r in &mut self.root_region {
            *r = NONE;
        }
        for t in 0..nt {
            let root = find(&mut self.uf, t as u32) as usize;
            if self.root_region[root] == NONE {
                self.root_region[root] = out.regions.len() as u32;
                let kind = if self.curved[t] {
                    out.num_curved_regions += 1;
                    RegionKind::Curved
                } else {
                    out.num_flat_regions += 1;
                    RegionKind::Flat
                };
                out.regions.push(Region {
                    kind,
                    singular_apex: NONE,
                    ..Region::default()
                });
            }
            let id = self.root_region[root];
            out.tri_region[t] = id;
            let reg = &mut out.regions[id as usize];
            reg.num_triangles += 1;
            reg.area_m2 += sp.tri_rest[t].area_m2;
            let tri = sp.triangles[t];
            let sing = tri.iter().position(|&v| self.is_singular[v as usize]);
            out.tri_kind[t] = match sing {
                Some(_) => TriKind::SingularFan,
                None if self.curved[t] => TriKind::Curved,
                None => TriKind::Flat,
            };
            if let Some(k) = sing
                && reg.kind == RegionKind::Curved
                && reg.singular_apex == NONE
            {
                let v = tri[k];
                reg.singular_apex = out
                    .singular
                    .iter()
                    .position(|s| s.sp_vertex == v)
                    .map_or(NONE, |i| i as u32);
            }
        }
        // Free curved borders.
        for (ei, e) in topo.edges.iter().enumerate() {
            if !e.is_boundary() {
                continue;
            }
            let f = topo.half_edges[e.he[0] as usize].face as usize;
            if !self.curved[f] {
                continue;
            }
            let region = out.tri_region[f];
            let len = sp.edge_rest_len_m[ei];
            out.free_borders.push(FreeBorderEdge {
                region,
                edge: ei as u32,
                length_m: len,
            });
            let r = &mut out.regions[region as usize];
            r.free_border_len_m += len;
            r.num_free_border_edges += 1;
        }
        // Junctions.
        for v in 0..self.vflat.len() {
            self.vflat[v] = false;
            self.vcurved[v] = false;
        }
        for t in 0..nt {
            for &v in &sp.triangles[t] {
                if self.curved[t] {
                    self.vcurved[v as usize] = true;
                } else {
                    self.vflat[v as usize] = true;
                }
            }
        }
        let mut moves = 0u32;
        for v in 0..self.vflat.len() {
            let j = topo.vertex_on_boundary[v] && self.vflat[v] && self.vcurved[v];
            if j {
                out.junctions.push(v as u32);
            }
            if j != self.junction_prev[v] {
                moves += 1;
            }
            self.junction_prev[v] = j;
        }
        out.junction_moves = moves;
        if moves > 0 {
            out.push_event(ShapeEvent::JunctionsMoved { count: moves });
        }
        let flattened = self
            .curved
            .iter()
            .zip(&self.prev_curved)
            .filter(|(c, p)| **p && !**c)
            .count() as u32;
        if flattened > 0 {
            out.push_event(ShapeEvent::Flattened {
                num_triangles: flattened,
            });
        }
    }
}
