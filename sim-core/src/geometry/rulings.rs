//! # Tracing each curved region's rulings on S_P (module doc step 7 of [`super`]): straight pattern
//! lines along the region-scale ruling direction, with 2D/3D ends, tangent-plane normal and
//! dihedral angle.

use super::*;

impl GeometryLayer {
    /// Step 7b: rulings of the curved regions (contiguous per region, ordered across it), then
    /// one ruling per crease.
    pub(super) fn trace_rulings(&mut self, sp: &PhysMesh) {
        let nt = sp.num_triangles();
        self.covered[..nt].fill(false);
        // The curved triangles, most bent first (the partition grew its regions in that
        // order: `grow_order`, the same set and key), bucketed by region by a stable counting
        // sort, so each region visits its own in that order.
        let nreg = self.out.regions.len();
        self.region_end.clear();
        self.region_end.resize(nreg + 1, 0);
        for &t in &self.grow_order {
            let r = self.out.tri_region[t as usize] as usize;
            if r < nreg {
                self.region_end[r + 1] += 1;
            }
        }
        for r in 0..nreg {
            self.region_end[r + 1] += self.region_end[r];
        }
        self.order.clear();
        self.order.resize(self.region_end[nreg] as usize, 0);
        for &t in &self.grow_order {
            let r = self.out.tri_region[t as usize] as usize;
            if r < nreg {
                self.order[self.region_end[r] as usize] = t;
                self.region_end[r] += 1;
            }
        }
        // Each region's bucket now ends where the next one's began.
        for region in 0..nreg {
            if self.out.regions[region].kind != RegionKind::Curved {
                continue;
            }
            let first = self.out.rulings.len();
            let bucket_start = if region == 0 {
                0
            } else {
                self.region_end[region - 1] as usize
            };
            for oi in bucket_start..self.region_end[region] as usize {
                let t = self.order[oi] as usize;
                if self.covered[t] {
                    continue;
                }
                if self.out.rulings.len() >= self.out.rulings.capacity() {
                    break;
                }
                let dir = self.tri_ruling_smooth[t];
                let tri = sp.triangles[t];
                let c0 = (sp.pattern[tri[0] as usize]
                    + sp.pattern[tri[1] as usize]
                    + sp.pattern[tri[2] as usize])
                    / 3.0
                    + off_line(dir, self.tri_h[t]);
                let r = self.trace_line(sp, region as u32, t as u32, c0, dir, None);
                for &rt in &self.ruling_tris {
                    self.covered[rt as usize] = true;
                }
                self.out.rulings.push(r);
            }
            let n = self.out.rulings.len() - first;
            // Order across the region: by the midpoint's coordinate along the mean bending
            // direction (perpendicular to the doubled-angle mean ruling direction).
            let rs = &mut self.out.rulings[first..];
            let (mut c2, mut s2) = (0.0, 0.0);
            for r in rs.iter() {
                let d = (r.b2 - r.a2).try_normalize(0.0).unwrap_or_else(V2::x);
                c2 += d.x * d.x - d.y * d.y;
                s2 += 2.0 * d.x * d.y;
            }
            let ang = 0.5 * s2.atan2(c2);
            let across = V2::new(-ang.sin(), ang.cos());
            rs.sort_unstable_by(|p, q| {
                let kp = ((p.a2 + p.b2) * 0.5).dot(&across);
                let kq = ((q.a2 + q.b2) * 0.5).dot(&across);
                kp.total_cmp(&kq)
                    .then(p.a2.x.total_cmp(&q.a2.x))
                    .then(p.a2.y.total_cmp(&q.a2.y))
            });
            let reg = &mut self.out.regions[region];
            reg.first_ruling = first as u32;
            reg.num_rulings = n as u32;
            if n > 0 {
                let rs = &self.out.rulings[first..];
                reg.mean_ruling_len_m = rs.iter().map(|r| r.length_m).sum::<f64>() / n as f64;
                reg.max_abs_dihedral_rad =
                    rs.iter().map(|r| r.dihedral_rad.abs()).fold(0.0, f64::max);
            }
        }
        // Creases: edges with |θ| ≥ θ0 between two different flat regions, one crease
        // region per pair of flat regions (the seeds' crease is one line between two flat
        // regions, T 740; on the lattice it is a chain of S_P edges, one ruling each).
        let topo = &sp.topo;
        self.crease_edges.clear();
        for (ei, e) in topo.edges.iter().enumerate() {
            if e.is_boundary() {
                continue;
            }
            let fa = topo.half_edges[e.he[0] as usize].face as usize;
            let fb = topo.half_edges[e.he[1] as usize].face as usize;
            let th = self.out.edge_dihedral_rad[ei];
            let (ra, rb) = (self.out.tri_region[fa], self.out.tri_region[fb]);
            if self.curved[fa] || self.curved[fb] || th.abs() < THETA0_RAD || ra == rb {
                continue;
            }
            self.crease_edges.push((ra.min(rb), ra.max(rb), ei as u32));
        }
        self.crease_edges.sort_unstable();
        let mut i = 0;
        while i < self.crease_edges.len() {
            let key = (self.crease_edges[i].0, self.crease_edges[i].1);
            let mut j = i;
            while j < self.crease_edges.len()
                && (self.crease_edges[j].0, self.crease_edges[j].1) == key
            {
                j += 1;
            }
            if self.out.regions.len() >= self.out.regions.capacity()
                || self.out.rulings.len() + (j - i) > self.out.rulings.capacity()
            {
                break;
            }
            let region = self.out.regions.len() as u32;
            let first = self.out.rulings.len() as u32;
            let (mut len_sum, mut th_max) = (0.0f64, 0.0f64);
            for &(_, _, ei) in &self.crease_edges[i..j] {
                let ei = ei as usize;
                let e = topo.edges[ei];
                let fa = topo.half_edges[e.he[0] as usize].face as usize;
                let fb = topo.half_edges[e.he[1] as usize].face as usize;
                let th = self.out.edge_dihedral_rad[ei];
                let (v0, v1) = (e.v[0] as usize, e.v[1] as usize);
                let len = sp.edge_rest_len_m[ei];
                let n = self.tri_normal[fa] + self.tri_normal[fb];
                self.out.rulings.push(RulingInfo {
                    region,
                    a2: sp.pattern[v0],
                    b2: sp.pattern[v1],
                    a3: sp.pos[v0],
                    b3: sp.pos[v1],
                    length_m: len,
                    dihedral_rad: th,
                    normal: n.try_normalize(0.0).unwrap_or_else(V3::z),
                    sp_edge: ei as u32,
                    anchor2: (sp.pattern[v0] + sp.pattern[v1]) * 0.5,
                    anchor_tri: NONE,
                    ..RulingInfo::default()
                });
                len_sum += len;
                th_max = th_max.max(th.abs());
            }
            let n = (j - i) as u32;
            self.out.regions.push(Region {
                kind: RegionKind::Crease,
                first_ruling: first,
                num_rulings: n,
                // The crease is one ruling of the seeds' degenerate region: its whole length.
                mean_ruling_len_m: len_sum,
                max_abs_dihedral_rad: th_max,
                singular_apex: NONE,
                ..Region::default()
            });
            self.out.num_creases += 1;
            i = j;
        }
    }

    /// Traces the straight pattern line through `c0` (inside triangle `t`) along ∓`dir` across
    /// the triangles of `region` and returns it as a ruling: a end along −`dir`, b end along
    /// +`dir`, each where the line leaves the region (3D: interpolated on the S_P edge it
    /// crosses), the mean signed curvature κ of the triangles crossed (left in
    /// `self.ruling_tris`) and their mean normal. `apex`: a cone apex (pattern, 3D) on the
    /// line behind the a end, which the a end does not pass (a d-cone's generators end at
    /// its tip). The dihedral is κ × the default ruling spacing until the rulings are final.
    pub(super) fn trace_line(
        &mut self,
        sp: &PhysMesh,
        region: u32,
        t: u32,
        c0: V2,
        dir: V2,
        apex: Option<(V2, V3)>,
    ) -> RulingInfo {
        let tri = sp.triangles[t as usize];
        let x0 =
            (sp.pos[tri[0] as usize] + sp.pos[tri[1] as usize] + sp.pos[tri[2] as usize]) / 3.0;
        self.ruling_tris.clear();
        self.ruling_tris.push(t);
        let mut ends = [(c0, x0); 2];
        for (side, d) in [-dir, dir].into_iter().enumerate() {
            let tri_region = &self.out.tri_region;
            let rt = &mut self.ruling_tris;
            let stop = if side == 0 { apex } else { None };
            let mut at_apex = false;
            let last = walk::walk(sp, t, c0, d, MAX_WALK, |c| {
                if let Some((a2, _)) = stop
                    && (c.point - a2).dot(&dir) <= 0.0
                {
                    at_apex = true;
                    return false;
                }
                c.to != NONE && tri_region[c.to as usize] == region && {
                    if rt.len() < rt.capacity() {
                        rt.push(c.to);
                    }
                    true
                }
            });
            if let (true, Some(a)) = (at_apex, stop) {
                ends[side] = a;
            } else if let Some(c) = last {
                let h = c.half_edge;
                let o = sp.topo.half_edges[h as usize].origin as usize;
                let de = sp.topo.dest(h) as usize;
                ends[side] = (c.point, sp.pos[o] + (sp.pos[de] - sp.pos[o]) * c.u);
            }
        }
        let (mut ksum, mut nsum) = (0.0, V3::zeros());
        for &rt in &self.ruling_tris {
            let r = rt as usize;
            ksum += self.tri_kappa[r];
            let n = self.tri_normal[r];
            nsum += if nsum.dot(&n) < 0.0 { -n } else { n };
        }
        let kappa = ksum / self.ruling_tris.len() as f64;
        let (a2, a3) = ends[0];
        let (b2, b3) = ends[1];
        RulingInfo {
            region,
            a2,
            b2,
            a3,
            b3,
            length_m: (b2 - a2).norm(),
            curvature_per_m: kappa,
            dihedral_rad: kappa * self.ruling_w(),
            normal: nsum.try_normalize(0.0).unwrap_or_else(V3::z),
            sp_edge: NONE,
            anchor2: c0,
            anchor_tri: t,
            resampled: false,
        }
    }

    /// Default spacing of traced rulings, metres: the S_P edge, at least 1/ρ_bound.
    pub(super) fn ruling_w(&self) -> f64 {
        (1.0 / RHO_BOUND_PER_M).max(self.spacing_m)
    }
}
