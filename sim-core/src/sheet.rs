//! # The sheet: pattern, S_P and S_G together
//!
//! A [`Sheet`] is the simulated sheet of paper in the seeds' double representation
//! (digest-crumpling §1): the physical mesh S_P ([`physical::PhysMesh`], what the physics step
//! moves and the editor draws) and the geometric structure S_G ([`geometric::GeomStructure`],
//! flat and curved regions, singular and junction vertices). The 2D pattern S̄ is the pattern
//! position of every S_P vertex.
//!
//! Sizes: A4, A5, A6 and the seeds' 10 cm validation square ([`SheetSize`]); width along x,
//! length along y, centred on the origin of the pattern.
//!
//! Parts:
//! - [`pattern`]: the initial lattice triangulation of the flat sheet;
//! - [`topology`]: half-edge topology as plain `u32` index data;
//! - [`physical`]: S_P (positions, velocities, masses, rest data, rest angles, damage);
//! - [`measure`]: a triangle's Green strain and a hinge's dihedral angle;
//! - [`walk`]: straight pattern lines traced across S_P, triangle by triangle;
//! - [`geometric`]: S_G (the data model; its operations are [`crate::geometry`]);
//! - [`refine`]: vertex insertion into S_P with state transfer (a singular vertex at its exact
//!   drawn position).
//! - [`cut`]: cutting S_P along a pattern polyline with state transfer (the path becomes a
//!   chain of S_P edges): a building block for tearing, not used by the frame loop.

pub mod cut;
pub mod geometric;
pub mod measure;
pub mod pattern;
pub mod physical;
pub mod refine;
pub mod tear_step;
pub mod topology;
pub mod unzip;
pub mod walk;

use crate::control::SheetSize;
use crate::math::V2;
use geometric::GeomStructure;
use physical::{MeshError, PhysMesh};

/// Mesh density of a new sheet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshConfig {
    /// Target edge length as a fraction of L_paper (the longer side). The default gives about
    /// 140 S_P triangles on A4–A6 and about 200 on the 10 cm square (the seeds' 87–156,
    /// digest §6.2), which keeps a frame inside the per-frame budget.
    pub spacing_frac: f64,
}

impl Default for MeshConfig {
    fn default() -> Self {
        Self {
            spacing_frac: 1.0 / 9.0,
        }
    }
}

impl MeshConfig {
    /// Smallest accepted spacing fraction (≈ 8 000 triangles on the square).
    pub const MIN_SPACING_FRAC: f64 = 1.0 / 64.0;
    /// Largest accepted spacing fraction (a handful of triangles).
    pub const MAX_SPACING_FRAC: f64 = 0.5;

    /// Returns a copy with a finite spacing inside the accepted range.
    pub fn sanitized(self) -> Self {
        let d = Self::default();
        let f = if self.spacing_frac.is_finite() {
            self.spacing_frac
                .clamp(Self::MIN_SPACING_FRAC, Self::MAX_SPACING_FRAC)
        } else {
            d.spacing_frac
        };
        Self { spacing_frac: f }
    }

    /// Target edge length for a sheet size, metres.
    pub fn spacing_m(&self, size: SheetSize) -> f64 {
        let (w, l) = size.dims_m();
        w.max(l) * self.sanitized().spacing_frac
    }
}

/// The simulated sheet.
#[derive(Clone, Debug, PartialEq)]
pub struct Sheet {
    /// Sheet size.
    pub size: SheetSize,
    /// Width (x extent), metres.
    pub width_m: f64,
    /// Length (y extent), metres.
    pub length_m: f64,
    /// The physical mesh S_P.
    pub sp: PhysMesh,
    /// The geometric structure S_G.
    pub sg: GeomStructure,
}

impl Sheet {
    /// A new flat, undamaged sheet at rest at height `z_m`.
    pub fn new_flat(size: SheetSize, mesh: MeshConfig, z_m: f64, areal_density_kg_m2: f64) -> Self {
        let (w, l) = size.dims_m();
        let pattern = pattern::lattice(w, l, mesh.spacing_m(size));
        let sp = PhysMesh::from_pattern(&pattern, z_m, areal_density_kg_m2)
            .expect("the lattice pattern is always a valid mesh");
        let sg = GeomStructure::initial(&sp);
        Self {
            size,
            width_m: w,
            length_m: l,
            sp,
            sg,
        }
    }

    /// A sheet from an explicit pattern (restoring a saved sheet). S_G is the initial
    /// one-flat-region structure (the geometry layer rebuilds richer structures itself).
    pub fn from_pattern(
        size: SheetSize,
        pattern: &pattern::Pattern,
        z_m: f64,
        areal_density_kg_m2: f64,
    ) -> Result<Self, MeshError> {
        let (w, l) = size.dims_m();
        let sp = PhysMesh::from_pattern(pattern, z_m, areal_density_kg_m2)?;
        let sg = GeomStructure::initial(&sp);
        Ok(Self {
            size,
            width_m: w,
            length_m: l,
            sp,
            sg,
        })
    }

    /// L_paper: the longer side, metres.
    pub fn l_paper_m(&self) -> f64 {
        self.width_m.max(self.length_m)
    }

    /// The S_P vertex nearest to a pattern point, restricted to boundary vertices if
    /// `boundary_only`.
    pub fn nearest_vertex(&self, p: V2, boundary_only: bool) -> u32 {
        let mut best = (f64::MAX, 0u32);
        for (i, q) in self.sp.pattern.iter().enumerate() {
            if boundary_only && !self.sp.topo.vertex_on_boundary[i] {
                continue;
            }
            let d = (q - p).norm_squared();
            if d < best.0 {
                best = (d, i as u32);
            }
        }
        best.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_density_gives_seed_like_triangle_counts() {
        for size in SheetSize::ALL {
            let s = Sheet::new_flat(size, MeshConfig::default(), 0.75, 0.1);
            let nt = s.sp.num_triangles();
            assert!((100..=220).contains(&nt), "{size:?}: {nt} triangles");
            s.sg.validate(&s.sp).unwrap();
            s.sp.topo.validate().unwrap();
        }
    }

    #[test]
    fn density_knob_scales_triangle_count() {
        let coarse = Sheet::new_flat(SheetSize::A4, MeshConfig { spacing_frac: 0.2 }, 0.0, 0.1);
        let fine = Sheet::new_flat(SheetSize::A4, MeshConfig { spacing_frac: 0.05 }, 0.0, 0.1);
        assert!(fine.sp.num_triangles() > 8 * coarse.sp.num_triangles());
    }
}
