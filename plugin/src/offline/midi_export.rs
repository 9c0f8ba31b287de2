//! # Scenes and scripts as MIDI performances
//!
//! `papier-render --scene NAME --write-midi FILE.mid` writes what a player would have to send
//! Papier to perform a scene, using the README's MIDI map
//! ([`crate::gesture_map`]): grabs become the slot notes (48 back, 50 front, 52 left, 53 right,
//! 55 corners; velocity = grip), resets note 36, and every gesture lane a control change
//! (CC 20 crumple, 21 slide, … 30 pull asymmetry). The file can be played by a DAW into the
//! plugin, or rendered back with `papier-render --midi FILE.mid` plus the `--set` options the
//! export prints (sheet size, material, seed, room: a MIDI file carries no such settings).
//!
//! The export goes through the same [`Timeline`] as a render, so a lane is sampled exactly where
//! the render samples it (every simulation frame start and every breakpoint); a CC is written
//! only when its 7-bit step changes, and a gesture that is on at all is never rounded to its
//! off step (the crumple hands take hold at the first non-zero value). What a MIDI file cannot carry is reported, not dropped
//! silently: non-gesture lanes that change after t = 0 (output gain, room automation).
//!
//! **Approximation:** a CC has 128 steps, so a gesture performed from MIDI follows the script's
//! value to within half a step (0.4 % of the gesture's range); the sheet's motion, and with it
//! every event, can therefore differ in detail from the script render — as it would for a player.

use std::collections::BTreeMap;

use sim_core::control::GestureParam;
use sim_core::script::ScriptValue;

use super::midi_file::{TimedMidi, write_smf};
use super::timeline::{HostEvent, Timeline};
use crate::gesture_map::{MidiInput, cc_for_gesture, cc_for_gesture_value};

/// A MIDI performance of a timeline.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MidiExport {
    /// Messages in time order.
    pub events: Vec<TimedMidi>,
    /// Length, seconds.
    pub length_s: f64,
    /// `ID=VALUE` settings (for `--set`) of non-gesture parameters at t = 0.
    pub sets: Vec<String>,
    /// Non-gesture parameters that change after t = 0 (not representable).
    pub dropped: Vec<String>,
}

impl MidiExport {
    /// The standard MIDI file.
    pub fn to_smf(&self) -> Vec<u8> {
        write_smf(&self.events, self.length_s)
    }
}

/// One `--set` value, in the form `set_from_arg` reads.
fn arg_value(v: &ScriptValue) -> String {
    match v {
        ScriptValue::Bool(true) => "on".into(),
        ScriptValue::Bool(false) => "off".into(),
        ScriptValue::Number(x) => format!("{x}"),
        ScriptValue::Text(s) => s.clone(),
    }
}

/// Converts a finished timeline (built at `sample_rate_hz`) to a MIDI performance.
pub fn export(tl: &Timeline, sample_rate_hz: f64) -> MidiExport {
    let mut out = MidiExport {
        length_s: tl.length_s,
        ..MidiExport::default()
    };
    // Last value per setting and per CC, so that only changes are written.
    let mut settings: BTreeMap<String, String> = BTreeMap::new();
    let mut last_step: BTreeMap<u8, u8> = BTreeMap::new();
    let mut gesture = |time_s: f64, g: GestureParam, v: f64, events: &mut Vec<TimedMidi>| {
        let cc = cc_for_gesture(g);
        let mut step = cc_for_gesture_value(g, v as f32);
        // A gesture that is on at all must not round to "off": the crumple hands, for one,
        // take hold at the first non-zero value, and the sheet's path depends on when.
        if step == 0 && !g.is_bipolar() && v as f32 > g.range().0 {
            step = 1;
        }
        if last_step.insert(cc, step) != Some(step) {
            events.push(TimedMidi {
                time_s,
                input: MidiInput::Cc {
                    cc,
                    value: f32::from(step) / 127.0,
                },
            });
        }
    };
    for (id, v) in &tl.initial {
        match (GestureParam::from_id(id), v.as_f64()) {
            (Some(g), Some(x)) => gesture(0.0, g, x, &mut out.events),
            _ => {
                settings.insert(id.clone(), arg_value(v));
            }
        }
    }
    for (at, e) in &tl.events {
        let time_s = *at as f64 / sample_rate_hz;
        match e {
            HostEvent::Midi(input) => out.events.push(TimedMidi {
                time_s,
                input: *input,
            }),
            HostEvent::Param { id, value } => match (GestureParam::from_id(id), value.as_f64()) {
                (Some(g), Some(x)) => gesture(time_s, g, x, &mut out.events),
                _ if *at == 0 => {
                    settings.insert(id.clone(), arg_value(value));
                }
                _ => {
                    if !out.dropped.contains(id) {
                        out.dropped.push(id.clone());
                    }
                }
            },
        }
    }
    out.sets = settings
        .into_iter()
        .map(|(id, v)| format!("{id}={v}"))
        .collect();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::{FrameClock, ParamValues};
    use crate::gesture_map::{Action, map};
    use crate::offline::midi_file::MidiFile;
    use sim_core::control::Command;
    use sim_core::script::Script;

    fn timeline(text: &str) -> Timeline {
        let sr = 48_000.0;
        let mut tl = Timeline::default();
        let mut scratch = ParamValues::default();
        tl.add_script(
            "test",
            &Script::parse(text).unwrap(),
            sr,
            FrameClock::new(sr, sim_core::sim::DEFAULT_FRAME_RATE_HZ),
            &mut scratch,
        )
        .unwrap();
        tl.finish();
        tl
    }

    #[test]
    fn grabs_lanes_and_settings_become_notes_ccs_and_set_options() {
        let tl = timeline(
            r#"
version = 1
duration_s = 2.0
[set]
size = "a6"
table = false
seed = 4
[[grab]]
slot = "front"
on_s = 0.1
off_s = 1.5
velocity = 0.5
[[lane]]
id = "twist"
interp = "linear"
points = [[0.0, 0.0], [1.0, -1.0]]
[[lane]]
id = "gain_db"
interp = "linear"
points = [[0.0, -6.0], [1.0, -12.0]]
"#,
        );
        let x = export(&tl, 48_000.0);
        // The output gain starts as a setting; its later automation has no MIDI control.
        assert_eq!(x.sets, vec!["gain_db=-6", "seed=4", "size=a6", "table=off"]);
        assert_eq!(x.dropped, vec!["gain_db"]);
        assert!((x.length_s - 2.0).abs() < 1e-9);
        // The grab: note 50 on at 0.1 s with velocity 0.5, off at 1.5 s.
        let notes: Vec<&TimedMidi> = x
            .events
            .iter()
            .filter(|e| !matches!(e.input, MidiInput::Cc { .. }))
            .collect();
        assert_eq!(notes.len(), 2, "{notes:?}");
        assert!((notes[0].time_s - 0.1).abs() < 1e-4);
        assert!(
            matches!(notes[0].input, MidiInput::NoteOn { key: 50, velocity } if velocity == 0.5)
        );
        assert!(matches!(notes[1].input, MidiInput::NoteOff { key: 50 }));
        // The twist: CC 23 from the centre (64) down to 0, monotone, each step once, and the
        // map turns every message back into the lane's value within half a step.
        let twist: Vec<&TimedMidi> = x
            .events
            .iter()
            .filter(|e| matches!(e.input, MidiInput::Cc { cc: 23, .. }))
            .collect();
        assert!(twist.len() > 30 && twist.len() <= 65, "{}", twist.len());
        let mut prev = f32::MAX;
        for e in &twist {
            let MidiInput::Cc { value, .. } = e.input else {
                unreachable!()
            };
            assert!(value < prev);
            prev = value;
            let Action::Sim(Command::Gesture { value: got, .. }) = map(e.input) else {
                panic!("CC 23 does not map to a gesture")
            };
            let want = -(e.time_s.min(1.0)) as f32;
            assert!((got - want).abs() <= 1.0 / 63.0 + 1e-3, "{got} vs {want}");
        }
        assert_eq!(prev, 0.0);
        // And the file reads back to the same messages.
        let back = MidiFile::parse(&x.to_smf()).unwrap();
        assert_eq!(back.events.len(), x.events.len());
    }
}
