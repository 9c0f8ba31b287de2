//! # Shape measures of S_P's elements: a triangle's Green strain against its rest shape and a
//! hinge's signed dihedral angle
//!
//! Geometry of the sheet's data, used by the physics (membrane and bending energies), the
//! metrics, the geometry layer and the mesh operations alike; they live with the data, not in
//! the physics, so the data layer never reaches up into the solver.

use crate::math::{M2, V3};
use crate::sheet::physical::TriRest;

/// Green strain of a triangle at positions `x`.
#[inline]
pub fn green_strain(x: [V3; 3], rest: &TriRest) -> (M2, [V3; 2]) {
    let d1 = x[1] - x[0];
    let d2 = x[2] - x[0];
    let b = &rest.dm_inv;
    // F = [d1 d2] · B  (3×2), stored as its two columns.
    let f0 = d1 * b[(0, 0)] + d2 * b[(1, 0)];
    let f1 = d1 * b[(0, 1)] + d2 * b[(1, 1)];
    let c00 = f0.dot(&f0);
    let c01 = f0.dot(&f1);
    let c11 = f1.dot(&f1);
    let g = M2::new(0.5 * (c00 - 1.0), 0.5 * c01, 0.5 * c01, 0.5 * (c11 - 1.0));
    (g, [f0, f1])
}

/// Signed dihedral angle of a hinge, radians.
#[inline]
pub fn dihedral(x: &[V3; 4]) -> f64 {
    let e = x[1] - x[0];
    let na = e.cross(&(x[2] - x[0]));
    let nb = (x[3] - x[0]).cross(&e);
    let en = e.norm();
    if en <= 0.0 {
        return 0.0;
    }
    let s = na.cross(&nb).dot(&e) / en;
    let c = na.dot(&nb);
    s.atan2(c)
}
