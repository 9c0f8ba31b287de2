//! # Saving and restoring the geometry layer's persistent state with a sheet ([`SavedGeometry`]):
//! curved flags, refractory frames, singular points with their sampled positions, the generator
//! and every pending mesh change; a restore validates every field.

use super::*;

/// The persistent state of the layer as saved with a sheet.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SavedGeometry {
    /// Curved flag per S_P triangle.
    pub curved: Vec<bool>,
    /// Refractory end frame per S_P triangle.
    pub refractory_until: Vec<u64>,
    /// Singular points: (S_P vertex, sampled pattern position, creation frame, case 0/1/2).
    pub singular: Vec<(u32, [f64; 2], u64, u8)>,
    /// The layer's random number generator.
    pub rng: rand_pcg::Pcg32,
    /// Largest edge compression when the isometry step last ran in an undriven frame (0 =
    /// none since the sheet was last driven; see the isometry step, module doc step 9). Saves
    /// from before this field load as 0.
    #[serde(default)]
    pub iso_undriven_compression: f64,
    /// A singular vertex waiting for its inserted S_P vertex: (s̄, fallback vertex, case,
    /// compression, dihedral, frame drawn). Absent when none (and in saves from before it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pending_singular: Option<([f64; 2], u32, u8, f64, f64, u64)>,
    /// An edge waiting to be flipped: (its vertices, compression, other diagonal's
    /// compression, frame found). Absent when none (and in saves from before it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pending_flip: Option<([u32; 2], f64, f64, u64)>,
}

impl GeometryLayer {
    /// The persistent state, for saving.
    pub fn save(&self) -> SavedGeometry {
        SavedGeometry {
            curved: self.curved.clone(),
            refractory_until: self.refractory_until.clone(),
            singular: self
                .out
                .singular
                .iter()
                .map(|s| {
                    (
                        s.sp_vertex,
                        [s.sampled2.x, s.sampled2.y],
                        s.created_frame,
                        s.case.code(),
                    )
                })
                .collect(),
            rng: self.rng.clone(),
            iso_undriven_compression: self.iso_undriven_compression,
            pending_singular: self.pending.map(|p| {
                (
                    [p.sampled2.x, p.sampled2.y],
                    p.fallback_vertex,
                    p.case.code(),
                    p.compression,
                    p.dihedral_rad,
                    p.frame,
                )
            }),
            pending_flip: self
                .pending_flip
                .map(|f| (f.edge, f.compression, f.other_compression, f.frame)),
        }
    }

    /// Restores the persistent state (after `new` on the restored S_P). Without saved state
    /// (a version-2 sheet) the singular vertices are taken from `sp.singular` and everything
    /// else starts fresh. Errors name the inconsistent field.
    ///
    /// The saved flat/curved flags are kept exactly as saved: they are the flags the frame's
    /// partition left (its promotion of lone flat facets beside curved triangles included),
    /// judged on the shape the partition saw, before the isometry step and the end of the frame
    /// moved the sheet. Partitioning the restored sheet again promoted facets by the moved
    /// shape, and the restored sheet then judged its next frame from other flags than the
    /// uninterrupted one (docs/decisions.md, "Smaller rules and the runs that found them").
    pub fn restore(
        &mut self,
        sp: &PhysMesh,
        sg: &mut GeomStructure,
        saved: Option<&SavedGeometry>,
    ) -> Result<(), String> {
        self.restore_with(sp, sg, saved, Promote::No)
    }

    pub(super) fn restore_with(
        &mut self,
        sp: &PhysMesh,
        sg: &mut GeomStructure,
        saved: Option<&SavedGeometry>,
        promote: Promote,
    ) -> Result<(), String> {
        let (nt, nv) = (sp.num_triangles(), sp.num_vertices());
        self.out.singular.clear();
        for f in &mut self.is_singular {
            *f = false;
        }
        match saved {
            Some(g) => {
                if g.curved.len() != nt || g.refractory_until.len() != nt {
                    return Err("geometry state does not match the mesh".into());
                }
                if g.singular.len() != sp.singular.len()
                    || g.singular.iter().zip(&sp.singular).any(|(a, &b)| a.0 != b)
                {
                    return Err("geometry singular list does not match the sheet's".into());
                }
                self.curved.copy_from_slice(&g.curved);
                self.refractory_until.copy_from_slice(&g.refractory_until);
                self.rng = g.rng.clone();
                self.iso_undriven_compression = if g.iso_undriven_compression.is_finite() {
                    g.iso_undriven_compression.clamp(0.0, 1.0)
                } else {
                    0.0
                };
                for &(v, s2, f, c) in &g.singular {
                    if v as usize >= nv || !(s2[0].is_finite() && s2[1].is_finite()) || c > 3 {
                        return Err("bad geometry singular entry".into());
                    }
                    self.push_singular(sp, v, V2::new(s2[0], s2[1]), f, SingularCase::of_code(c));
                }
                self.pending = match g.pending_singular {
                    None => None,
                    Some((s2, v, c, comp, dih, f)) => {
                        if v as usize >= nv
                            || !(s2[0].is_finite() && s2[1].is_finite())
                            || c > 3
                            || !(comp.is_finite() && dih.is_finite())
                        {
                            return Err("bad pending singular entry".into());
                        }
                        Some(PendingSingular {
                            sampled2: V2::new(s2[0], s2[1]),
                            fallback_vertex: v,
                            case: SingularCase::of_code(c),
                            compression: comp,
                            dihedral_rad: dih,
                            frame: f,
                        })
                    }
                };
                self.pending_flip = match g.pending_flip {
                    None => None,
                    Some(([a, b], c, o, f)) => {
                        if a >= b || b as usize >= nv || !(c.is_finite() && o.is_finite()) {
                            return Err("bad pending flip entry".into());
                        }
                        Some(PendingFlip {
                            edge: [a, b],
                            compression: c,
                            other_compression: o,
                            frame: f,
                        })
                    }
                };
            }
            None => {
                self.iso_undriven_compression = 0.0;
                self.pending = None;
                self.pending_flip = None;
                for &v in &sp.singular {
                    self.push_singular(sp, v, sp.pattern[v as usize], 0, SingularCase::Restored);
                }
            }
        }
        self.prev_curved.copy_from_slice(&self.curved);
        sync_sg_singular(sg, sp);
        self.refresh(sp, promote);
        Ok(())
    }
}
