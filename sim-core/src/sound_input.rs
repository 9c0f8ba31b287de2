//! # Sound input: what the sheet tells the sound engine each frame
//!
//! The sound model of the seeds (thesis ch. 4, `000_cb4d91e46ec5927f.txt` §4.3; SCA 2016,
//! `002_9b4a8fc30aee6402.txt` §3–5; digest-sound §1–2) turns geometry into sound in four stages:
//! event detection → resonators → database units → spatialization. This module holds the
//! hand-over between the first two stages (computed from the sheet, here in sim-core) and the last
//! two (the render path, in the plugin):
//!
//! - a [`Resonator`] is a patch of the sheet that vibrates as one: its mean ruling length `l_r`,
//!   its total free curved border length `l_c` (0 = constrained: a "clac" or constrained friction),
//!   and a compact disk (centre, normal, radius) for the dipole radiation model (eq. 4.1–4.6);
//! - a [`CrumpleEvent`] is one crumpling sound to start now: an amplitude (linear gain, the sum of
//!   curvature changes ΣΔ_v of its event, T 1772) and the resonator that selects the unit;
//! - a [`FrictionSource`] is a contact region that is sliding: its resonator and its slip speed
//!   (the friction amplitude is linear in the mean relative speed, T 1770, S 153);
//! - [`TearState`] carries the tear speed |t| (linear amplitude and "pitch", T 2042), the tip,
//!   its onsets and the flaps' resonator that colours the noise (beyond the seeds).
//!
//! A [`SoundFrame`] gathers one frame of these with fixed capacity and no heap data, so it can be
//! copied into a triple buffer and read by the audio thread without allocation. Crumple events are
//! discrete: the plugin's worker sends them through a queue (a triple buffer may drop frames);
//! the frame record keeps them too, for logs and lockstep rendering.

/// Maximal number of crumple events (event × resonator pairs) in one frame.
pub const MAX_CRUMPLE_EVENTS: usize = 32;
/// Maximal number of sliding friction sources in one frame.
pub const MAX_FRICTION_SOURCES: usize = 32;

/// A vibrating patch of the sheet (digest-sound §2.3–2.4).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Resonator {
    /// Mean length of the rulings of the patch, cm.
    pub lr_cm: f32,
    /// Total length of the patch's free curved borders, cm; 0 means constrained.
    pub lc_cm: f32,
    /// Centre of the equivalent vibrating disk, world metres.
    pub centre_m: [f32; 3],
    /// Unit normal of the disk (dipole axis).
    pub normal: [f32; 3],
    /// Radius of the equivalent disk, metres (√(area/π)).
    pub radius_m: f32,
}

impl Resonator {
    /// A constrained resonator has no free curved border (seeds: l_c = 0, database cell (0, 0)).
    pub fn is_constrained(&self) -> bool {
        self.lc_cm <= 0.0
    }
}

/// One crumpling sound to start (one resonator of one crumpling event).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CrumpleEvent {
    /// Linear gain of the unit: the event amplitude (sum of curvature changes, T 1772),
    /// scaled so that 1.0 is a full curvature flip (±10 m⁻¹) over a 5 × 5 cm patch.
    pub amplitude: f32,
    /// The patch that rings.
    pub resonator: Resonator,
}

/// What a friction contact slides on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Obstacle {
    /// The table top.
    #[default]
    Table,
    /// The wall.
    Wall,
    /// The floor (only reachable with the table off).
    Floor,
    /// The sheet against itself.
    SelfContact,
}

/// A sliding contact region (one friction event and one of its resonators).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrictionSource {
    /// Mean tangential speed of the contact vertices relative to the obstacle, m/s.
    pub slip_speed_m_s: f32,
    /// What the sheet slides on.
    pub obstacle: Obstacle,
    /// The patch whose spectrum is selected.
    pub resonator: Resonator,
}

/// State of the tear, if any.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TearState {
    /// Tear tip speed |t|, m/s; 0 when the tip does not move.
    pub speed_m_s: f32,
    /// Tip position, world metres.
    pub tip_m: [f32; 3],
    /// Length torn so far, metres (0 before a tear; never decreases until a reset).
    pub length_m: f32,
    /// The tip started moving this frame after standing still (a tear onset).
    pub onset: bool,
    /// The flaps at the tip, which colour the tear noise (beyond the seeds); a radius of 0
    /// means none (the noise stays white, as the seeds').
    pub resonator: Resonator,
}

/// The air the sheet moves (beyond the seeds; [`crate::sound_analysis::air`]): how hard the
/// sheet's free parts accelerate through the air this frame, and where.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AirState {
    /// Σ A |a_n| over the free triangles (area × normal acceleration), m³/s²; 0 when the
    /// sheet moves no air.
    pub strength_m3_s2: f32,
    /// Centre of the moving area (weighted by A |a_n|), world metres.
    pub centre_m: [f32; 3],
    /// Mean normal of the moving area (weighted by A |a_n|, unit; the dipole's axis).
    pub normal: [f32; 3],
}

/// The crackle of the sheet being deformed (beyond the seeds;
/// [`crate::sound_analysis::crackle`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CrackleState {
    /// D = Σ ℓ |θ̇| weighted by how bent each hinge is, m·rad/s; 0 when nothing bent moves.
    pub rate_m_rad_s: f32,
    /// Where it comes from (weighted centroid), world metres.
    pub centre_m: [f32; 3],
}

/// One frame of sound input, fixed capacity, no heap data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoundFrame {
    /// Frame index since the sheet's simulation started.
    pub frame: u64,
    /// Simulated time at the end of the frame, seconds.
    pub time_s: f64,
    num_crumple: u32,
    crumple: [CrumpleEvent; MAX_CRUMPLE_EVENTS],
    num_friction: u32,
    friction: [FrictionSource; MAX_FRICTION_SOURCES],
    /// The tear.
    pub tear: TearState,
    /// The air the sheet moves.
    pub air: AirState,
    /// The crackle of the sheet being deformed.
    pub crackle: CrackleState,
    /// Number of crumple events that did not fit (counted, not lost silently).
    pub dropped_crumple: u32,
    /// Number of friction sources that did not fit.
    pub dropped_friction: u32,
}

impl Default for SoundFrame {
    fn default() -> Self {
        Self {
            frame: 0,
            time_s: 0.0,
            num_crumple: 0,
            crumple: [CrumpleEvent::default(); MAX_CRUMPLE_EVENTS],
            num_friction: 0,
            friction: [FrictionSource::default(); MAX_FRICTION_SOURCES],
            tear: TearState::default(),
            air: AirState::default(),
            crackle: CrackleState::default(),
            dropped_crumple: 0,
            dropped_friction: 0,
        }
    }
}

impl SoundFrame {
    /// Empties the frame (keeps nothing), without touching the storage.
    pub fn clear(&mut self) {
        self.num_crumple = 0;
        self.num_friction = 0;
        self.tear = TearState::default();
        self.air = AirState::default();
        self.crackle = CrackleState::default();
        self.dropped_crumple = 0;
        self.dropped_friction = 0;
    }

    /// Crumple events of this frame.
    pub fn crumple(&self) -> &[CrumpleEvent] {
        &self.crumple[..self.num_crumple as usize]
    }

    /// Friction sources of this frame.
    pub fn friction(&self) -> &[FrictionSource] {
        &self.friction[..self.num_friction as usize]
    }

    /// Adds a crumple event; returns false (and counts it) when the frame is full or the event
    /// is not finite.
    pub fn push_crumple(&mut self, e: CrumpleEvent) -> bool {
        if !e.amplitude.is_finite() || (self.num_crumple as usize) >= MAX_CRUMPLE_EVENTS {
            self.dropped_crumple = self.dropped_crumple.saturating_add(1);
            return false;
        }
        self.crumple[self.num_crumple as usize] = e;
        self.num_crumple += 1;
        true
    }

    /// Adds a friction source; returns false (and counts it) when the frame is full or the
    /// source is not finite.
    pub fn push_friction(&mut self, f: FrictionSource) -> bool {
        if !f.slip_speed_m_s.is_finite() || (self.num_friction as usize) >= MAX_FRICTION_SOURCES {
            self.dropped_friction = self.dropped_friction.saturating_add(1);
            return false;
        }
        self.friction[self.num_friction as usize] = f;
        self.num_friction += 1;
        true
    }

    /// Removes the crumple events (after they were sent through the event queue).
    pub fn take_crumple_count(&mut self) -> usize {
        let n = self.num_crumple as usize;
        self.num_crumple = 0;
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capacity_is_enforced_and_counted() {
        let mut f = SoundFrame::default();
        for _ in 0..MAX_CRUMPLE_EVENTS + 3 {
            f.push_crumple(CrumpleEvent {
                amplitude: 1.0,
                ..Default::default()
            });
        }
        assert_eq!(f.crumple().len(), MAX_CRUMPLE_EVENTS);
        assert_eq!(f.dropped_crumple, 3);
        assert!(!f.push_friction(FrictionSource {
            slip_speed_m_s: f32::NAN,
            ..Default::default()
        }));
        assert_eq!(f.friction().len(), 0);
        f.clear();
        assert_eq!(f.crumple().len(), 0);
        assert_eq!(f.dropped_crumple, 0);
    }
}
