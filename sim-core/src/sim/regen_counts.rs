//! How often S_P was regenerated from S_G, and why each refused regeneration was refused
//! ([`crate::geometry::GeometryConfig::regenerate_sp`], `sheet/regenerate.rs`).
//!
//! The per-frame regeneration of the seeds (TOG 2015 §6, thesis 2.5.3; digest-crumpling §3.7) is
//! refused whenever the rebuilt mesh would be worse than the one it replaces. Counting each
//! reason separately is what tells a measurement of the mode (examples/regen_probe.rs) which of
//! its guards decides how often it runs.

use crate::sheet::regenerate::RegenError;

/// Regenerations of the current sheet: adopted, unchanged, and refused by reason.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RegenCounts {
    /// Regenerations adopted (S_P replaced).
    pub adopted: u64,
    /// Regenerations that rebuilt S_P as it was (nothing to adopt).
    pub unchanged: u64,
    /// Refused: a regenerated triangle was too thin.
    pub thin: u64,
    /// Refused: an added point fell outside the pattern.
    pub outside: u64,
    /// Refused: two kept vertices met at one point.
    pub merged: u64,
    /// Refused: the triangulation or the mesh could not be built.
    pub invalid: u64,
    /// Refused: the mesh exceeds the preallocated capacity.
    pub capacity: u64,
    /// Refused: the regenerated sheet crosses itself where S_P did not.
    pub crossing: u64,
    /// Refused: the state could not be carried over.
    pub adoption: u64,
}

impl RegenCounts {
    /// Counts a regeneration refused by the triangulation.
    pub fn refuse(&mut self, e: &RegenError) {
        match e {
            RegenError::ThinTriangle(_) => self.thin += 1,
            RegenError::Outside => self.outside += 1,
            RegenError::Merged(_) => self.merged += 1,
            RegenError::Mismatch(_) | RegenError::Insertion | RegenError::Mesh(_) => {
                self.invalid += 1
            }
        }
    }

    /// All refusals.
    pub fn refused(&self) -> u64 {
        self.thin
            + self.outside
            + self.merged
            + self.invalid
            + self.capacity
            + self.crossing
            + self.adoption
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_refusal_is_counted_once_under_its_reason() {
        let mut c = RegenCounts::default();
        c.refuse(&RegenError::ThinTriangle(2.0));
        c.refuse(&RegenError::Outside);
        c.refuse(&RegenError::Merged(3));
        c.refuse(&RegenError::Insertion);
        c.capacity += 1;
        assert_eq!((c.thin, c.outside, c.merged, c.invalid), (1, 1, 1, 1));
        assert_eq!(c.refused(), 5);
        assert_eq!(c.adopted, 0);
    }
}
