//! # MIDI → gestures
//!
//! The one mapping from MIDI input to simulation commands, shared by the plugin's `process()` and
//! the offline renderer. Pure and allocation-free: a MIDI message in, at most one action out.
//!
//! | MIDI (any channel) | action |
//! |---|---|
//! | note 36 | reset to a new flat sheet |
//! | note 48 held | grab the back edge (velocity = grip speed) |
//! | note 50 held | grab the front edge |
//! | note 52 held | grab the left edge |
//! | note 53 held | grab the right edge |
//! | note 55 held | grab all four corners |
//! | note 59 | release every hand |
//! | CC 1, CC 20 | crumple |
//! | CC 21 | slide |
//! | CC 22 | lift |
//! | CC 23 | twist (64 = none) |
//! | CC 24 | shake depth |
//! | CC 25 | shake rate |
//! | CC 26 | tear amount |
//! | CC 27 | tear steer (64 = centre) |
//! | CC 28 | tear position |
//! | CC 29 | pull separation |
//! | CC 30 | pull asymmetry (64 = symmetric) |
//! | CC 7 | volume (gain = (value/127)², the General MIDI curve: 40·log10(v/127) dB) |
//! | CC 121 | reset all controllers: gestures back to their parameter values, volume to unity |
//! | CC 120, CC 123 | all sound off / all notes off: every hand lets go |
//!
//! A CC sets its gesture to `min + (max − min)·v/127`; a bipolar gesture (twist, tear steer,
//! pull asymmetry) maps 64 exactly to 0, 0 to −1 and 127 to +1. A CC and the host's automation of
//! the same gesture parameter both write the gesture: the latest change wins.

use sim_core::{Command, GestureParam, GrabSlot};

/// MIDI note that resets the sheet.
pub const NOTE_RESET: u8 = 36;
/// MIDI note that releases every hand.
pub const NOTE_RELEASE_ALL: u8 = 59;

/// A MIDI message, as the engine sees it (velocities and CC values normalized to 0–1, as
/// nice-plug delivers them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MidiInput {
    /// Note on (a note on with velocity 0 must be passed as [`MidiInput::NoteOff`]).
    NoteOn {
        /// Key number.
        key: u8,
        /// Velocity 0–1.
        velocity: f32,
    },
    /// Note off.
    NoteOff {
        /// Key number.
        key: u8,
    },
    /// All notes off (a note off for every key, e.g. a CLAP wildcard note off).
    AllNotesOff,
    /// Control change.
    Cc {
        /// Controller number.
        cc: u8,
        /// Value 0–1 (value / 127).
        value: f32,
    },
}

/// What a MIDI message asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    /// Nothing (unmapped message).
    None,
    /// A simulation command.
    Sim(Command),
    /// New MIDI volume, as a linear gain.
    Volume(f32),
    /// Reset all controllers.
    ResetControllers,
}

/// The slot a note grabs, if any.
pub const fn slot_for_note(key: u8) -> Option<GrabSlot> {
    match key {
        48 => Some(GrabSlot::Back),
        50 => Some(GrabSlot::Front),
        52 => Some(GrabSlot::Left),
        53 => Some(GrabSlot::Right),
        55 => Some(GrabSlot::Corners),
        _ => None,
    }
}

/// The note that grabs a slot.
pub const fn note_for_slot(slot: GrabSlot) -> u8 {
    match slot {
        GrabSlot::Back => 48,
        GrabSlot::Front => 50,
        GrabSlot::Left => 52,
        GrabSlot::Right => 53,
        GrabSlot::Corners => 55,
    }
}

/// The gesture a controller drives, if any.
pub const fn gesture_for_cc(cc: u8) -> Option<GestureParam> {
    match cc {
        1 | 20 => Some(GestureParam::Crumple),
        21 => Some(GestureParam::Slide),
        22 => Some(GestureParam::Lift),
        23 => Some(GestureParam::Twist),
        24 => Some(GestureParam::ShakeDepth),
        25 => Some(GestureParam::ShakeRateHz),
        26 => Some(GestureParam::TearAmount),
        27 => Some(GestureParam::TearSteer),
        28 => Some(GestureParam::TearPosition),
        29 => Some(GestureParam::PullSeparation),
        30 => Some(GestureParam::PullAsymmetry),
        _ => None,
    }
}

/// The controller that drives a gesture (the first one, for CC 1/20 that is CC 20).
pub const fn cc_for_gesture(g: GestureParam) -> u8 {
    match g {
        GestureParam::Crumple => 20,
        GestureParam::Slide => 21,
        GestureParam::Lift => 22,
        GestureParam::Twist => 23,
        GestureParam::ShakeDepth => 24,
        GestureParam::ShakeRateHz => 25,
        GestureParam::TearAmount => 26,
        GestureParam::TearSteer => 27,
        GestureParam::TearPosition => 28,
        GestureParam::PullSeparation => 29,
        GestureParam::PullAsymmetry => 30,
    }
}

/// Converts a normalized CC value back to its 7-bit step (non-finite → 0).
fn cc_step(value: f32) -> u8 {
    if value.is_finite() {
        (value.clamp(0.0, 1.0) * 127.0).round() as u8
    } else {
        0
    }
}

/// The gesture value a 7-bit CC step means.
pub fn gesture_value_for_cc(g: GestureParam, step: u8) -> f32 {
    let step = step.min(127);
    let (min, max) = g.range();
    if g.is_bipolar() {
        let centre = 0.5 * (min + max);
        let half = 0.5 * (max - min);
        if step >= 64 {
            centre + half * f32::from(step - 64) / 63.0
        } else {
            centre - half * f32::from(64 - step) / 64.0
        }
    } else {
        min + (max - min) * f32::from(step) / 127.0
    }
}

/// The 7-bit CC step whose value is closest to a gesture value (for writing MIDI files).
pub fn cc_for_gesture_value(g: GestureParam, value: f32) -> u8 {
    (0..=127u8)
        .min_by(|a, b| {
            let da = (gesture_value_for_cc(g, *a) - value).abs();
            let db = (gesture_value_for_cc(g, *b) - value).abs();
            da.total_cmp(&db)
        })
        .unwrap_or(0)
}

/// Maps one MIDI message.
pub fn map(input: MidiInput) -> Action {
    match input {
        MidiInput::NoteOn { key, velocity } => {
            if key == NOTE_RESET {
                return Action::Sim(Command::Reset);
            }
            if key == NOTE_RELEASE_ALL {
                return Action::Sim(Command::ReleaseAll);
            }
            match slot_for_note(key) {
                Some(slot) => Action::Sim(Command::Grab {
                    slot,
                    grip: if velocity.is_finite() {
                        velocity.clamp(0.0, 1.0)
                    } else {
                        0.5
                    },
                }),
                None => Action::None,
            }
        }
        MidiInput::AllNotesOff => Action::Sim(Command::ReleaseAll),
        MidiInput::NoteOff { key } => match slot_for_note(key) {
            Some(slot) => Action::Sim(Command::Release { slot }),
            None => Action::None,
        },
        MidiInput::Cc { cc, value } => {
            let step = cc_step(value);
            if let Some(g) = gesture_for_cc(cc) {
                return Action::Sim(Command::Gesture {
                    param: g,
                    value: gesture_value_for_cc(g, step),
                });
            }
            match cc {
                7 => {
                    let v = f32::from(step) / 127.0;
                    Action::Volume(v * v)
                }
                120 | 123 => Action::Sim(Command::ReleaseAll),
                121 => Action::ResetControllers,
                _ => Action::None,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notes_grab_release_and_reset() {
        assert_eq!(
            map(MidiInput::NoteOn {
                key: 36,
                velocity: 1.0
            }),
            Action::Sim(Command::Reset)
        );
        for (key, slot) in [
            (48, GrabSlot::Back),
            (50, GrabSlot::Front),
            (52, GrabSlot::Left),
            (53, GrabSlot::Right),
            (55, GrabSlot::Corners),
        ] {
            assert_eq!(
                map(MidiInput::NoteOn {
                    key,
                    velocity: 0.25
                }),
                Action::Sim(Command::Grab { slot, grip: 0.25 })
            );
            assert_eq!(
                map(MidiInput::NoteOff { key }),
                Action::Sim(Command::Release { slot })
            );
            assert_eq!(note_for_slot(slot), key);
        }
        assert_eq!(
            map(MidiInput::NoteOn {
                key: 60,
                velocity: 1.0
            }),
            Action::None
        );
        // A NaN velocity never reaches the simulation as NaN.
        assert!(matches!(
            map(MidiInput::NoteOn { key: 48, velocity: f32::NAN }),
            Action::Sim(Command::Grab { grip, .. }) if grip == 0.5
        ));
    }

    #[test]
    fn ccs_map_to_gestures_with_exact_centres() {
        let g = |cc, v: u8| match map(MidiInput::Cc {
            cc,
            value: f32::from(v) / 127.0,
        }) {
            Action::Sim(Command::Gesture { param, value }) => (param, value),
            other => panic!("CC {cc} gave {other:?}"),
        };
        assert_eq!(g(1, 127), (GestureParam::Crumple, 1.0));
        assert_eq!(g(20, 0), (GestureParam::Crumple, 0.0));
        assert_eq!(g(23, 64), (GestureParam::Twist, 0.0));
        assert_eq!(g(23, 0), (GestureParam::Twist, -1.0));
        assert_eq!(g(23, 127), (GestureParam::Twist, 1.0));
        assert_eq!(g(27, 64), (GestureParam::TearSteer, 0.0));
        assert_eq!(g(30, 64), (GestureParam::PullAsymmetry, 0.0));
        assert_eq!(g(25, 127), (GestureParam::ShakeRateHz, 8.0));
        assert_eq!(g(25, 0), (GestureParam::ShakeRateHz, 0.5));
        for cc in 20..=30 {
            let (p, _) = g(cc, 10);
            assert_eq!(gesture_for_cc(cc_for_gesture(p)), Some(p));
        }
    }

    #[test]
    fn volume_and_channel_mode_messages() {
        assert_eq!(
            map(MidiInput::Cc { cc: 7, value: 1.0 }),
            Action::Volume(1.0)
        );
        assert_eq!(
            map(MidiInput::Cc { cc: 7, value: 0.0 }),
            Action::Volume(0.0)
        );
        assert_eq!(
            map(MidiInput::Cc {
                cc: 123,
                value: 0.0
            }),
            Action::Sim(Command::ReleaseAll)
        );
        assert_eq!(
            map(MidiInput::Cc {
                cc: 121,
                value: 0.0
            }),
            Action::ResetControllers
        );
        assert_eq!(map(MidiInput::Cc { cc: 74, value: 0.3 }), Action::None);
        // Garbage values are clamped, never NaN.
        assert!(matches!(
            map(MidiInput::Cc { cc: 21, value: f32::INFINITY }),
            Action::Sim(Command::Gesture { value, .. }) if value == 0.0
        ));
    }

    #[test]
    fn cc_value_inverse_round_trips() {
        for g in GestureParam::ALL {
            for step in 0..=127u8 {
                assert_eq!(cc_for_gesture_value(g, gesture_value_for_cc(g, step)), step);
            }
        }
    }
}
