//! # Generalized-cone fitting of each curved region (module doc step 8 of [`super`]; TOG 2015 §3.7,
//! digest-crumpling §3.7): rulings ordered across the region, segmentation into cones and gap
//! cones with the math of [`super::cone`].

use super::*;

impl GeometryLayer {
    /// Step 8: cone fitting and segmentation of every curved region.
    pub(super) fn fit_cones(&mut self) {
        let eps = EPS_BLASCHKE_FRAC * self.l_paper_m;
        let far = 100.0 * self.l_paper_m;
        for region in 0..self.out.regions.len() {
            let reg = self.out.regions[region];
            if reg.kind != RegionKind::Curved || reg.num_rulings == 0 {
                continue;
            }
            let first = reg.first_ruling as usize;
            let last = first + reg.num_rulings as usize - 1;
            if reg.singular_apex != NONE {
                let s = self.out.singular[reg.singular_apex as usize];
                self.push_cone(ConeInfo {
                    region: region as u32,
                    apex2: Some(s.pos2),
                    apex3: Some(s.pos3),
                    first_ruling: first as u32,
                    last_ruling: last as u32,
                    is_gap: false,
                    rms_m: 0.0,
                });
                continue;
            }
            self.planes.clear();
            let mut prev: Option<V3> = None;
            for r in &self.out.rulings[first..=last] {
                let mut n = r.normal;
                if let Some(p) = prev
                    && p.dot(&n) < 0.0
                {
                    n = -n;
                }
                prev = Some(n);
                let m = (r.a3 + r.b3) * 0.5;
                self.planes.push(RulingPlane {
                    n,
                    w: -n.dot(&m),
                    a2: r.a2,
                    b2: r.b2,
                    a3: r.a3,
                    b3: r.b3,
                });
            }
            let planes = &self.planes;
            let cones = &mut self.out.cones;
            let mut last_seg: Option<usize> = None;
            segment(planes, 0, planes.len() - 1, eps, far, &mut |sg| {
                if cones.len() + 2 > cones.capacity() {
                    return;
                }
                if let Some(pl) = last_seg {
                    let gap = gap_apex(&planes[pl], &planes[sg.first]);
                    cones.push(ConeInfo {
                        region: region as u32,
                        apex2: gap.map(|g| g.0),
                        apex3: gap.map(|g| g.1),
                        first_ruling: (first + pl) as u32,
                        last_ruling: (first + sg.first) as u32,
                        is_gap: true,
                        rms_m: 0.0,
                    });
                }
                let seg_planes = &planes[sg.first..=sg.last];
                cones.push(ConeInfo {
                    region: region as u32,
                    apex2: apex_in_pattern(seg_planes, &sg.fit),
                    apex3: sg.fit.apex3,
                    first_ruling: (first + sg.first) as u32,
                    last_ruling: (first + sg.last) as u32,
                    is_gap: false,
                    rms_m: sg.fit.rms_m,
                });
                last_seg = Some(sg.last);
            });
        }
    }

    pub(super) fn push_cone(&mut self, c: ConeInfo) {
        if self.out.cones.len() < self.out.cones.capacity() {
            self.out.cones.push(c);
        }
    }
}
