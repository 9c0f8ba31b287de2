//! # Where a frame's time goes: per-phase wall time of `Sim::step` (benchmarks only)
//!
//! The speed targets are per step — the whole frame, and the geometry layer's own
//! cost (the seeds time remeshing and isometry separately: TOG Table V; digest-crumpling §7).
//! Subtracting the median frame time of a physics-only run from that of a run with the
//! geometry layer on does not measure the layer: once the layer acts, the two runs play
//! different trajectories and the solver's iteration counts differ. So the step reads the
//! clock between its phases when asked to ([`crate::sim::Sim::set_phase_timing`]; off by
//! default — a reading costs ~20 ns and nothing else depends on it, so timing on or off gives
//! the same simulation bit for bit).

use std::time::Instant;

/// Wall time of the phases of the last awake frame, nanoseconds (all 0 unless phase timing is
/// on). Their sum is the frame minus the bookkeeping between phases.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PhaseTimes {
    /// Self-contact: the crumple cap's closest-approach query and the pass-through guard
    /// (only while the crumple hands squeeze).
    pub self_contact_ns: u64,
    /// Gesture rig, implicit substeps, contact depth limit and hand slip.
    pub physics_ns: u64,
    /// The developable-geometry layer, steps (d)–(h) of the frame loop.
    pub geometry_ns: u64,
    /// Contacts, length-error metrics and the sound analysis.
    pub analysis_ns: u64,
    /// The tear's macro tip and sound input (sim/tear.rs; its mesh steps run before the
    /// phases, with the other mesh changes).
    pub tear_ns: u64,
}

impl PhaseTimes {
    /// The sum of the phases, nanoseconds.
    pub fn total_ns(&self) -> u64 {
        self.self_contact_ns + self.physics_ns + self.geometry_ns + self.analysis_ns + self.tear_ns
    }
}

/// Lap timer over the phases of one frame; reads no clock while off.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Stopwatch {
    last: Option<Instant>,
}

impl Stopwatch {
    /// Starts a frame's laps if `on`, else turns the watch off.
    pub(crate) fn start(&mut self, on: bool) {
        self.last = on.then(Instant::now);
    }

    /// Nanoseconds since the previous lap (or the start); 0 when off.
    pub(crate) fn lap_ns(&mut self) -> u64 {
        let Some(t) = self.last else {
            return 0;
        };
        let now = Instant::now();
        self.last = Some(now);
        u64::try_from(now.duration_since(t).as_nanos()).unwrap_or(u64::MAX)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_idle_watch_reads_zero_and_a_running_one_counts() {
        let mut w = Stopwatch::default();
        w.start(false);
        std::thread::sleep(std::time::Duration::from_millis(2));
        assert_eq!(w.lap_ns(), 0);
        w.start(true);
        std::thread::sleep(std::time::Duration::from_millis(2));
        assert!(w.lap_ns() >= 2_000_000);
    }
}
