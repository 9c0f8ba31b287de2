//! The small user sound database the tests build from a full one: the clac cell, three flap
//! cells far apart on the grid and two friction spectra, so it loads fast and sounds clearly
//! different from the default.

use sounddb::{Cell, Database};

/// The flap cells kept, (l_r, l_c) in cm.
pub const FLAP_CELLS_CM: [(f32, f32); 3] = [(10.0, 5.0), (20.0, 20.0), (5.0, 30.0)];

/// Is this cell one the small database keeps?
pub fn keeps(c: &Cell) -> bool {
    c.is_constrained()
        || FLAP_CELLS_CM.iter().any(|&(s, k)| {
            c.same_as(&Cell::Free {
                straight_cm: s,
                curved_cm: k,
            })
        })
}

/// The small database cut from `full` (two friction spectra at most).
pub fn from(full: &Database) -> Database {
    full.subset(keeps, 2)
}
