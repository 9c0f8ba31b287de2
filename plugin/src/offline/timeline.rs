//! # The offline timeline: every input as sample-stamped host events
//!
//! `papier-render` plays its inputs the way a host plays a track: parameter changes
//! (automation) and MIDI messages at sample positions. This module turns MIDI files, scripts and
//! scenes into one sorted list of such events:
//! - MIDI messages at their times (every input's sample is kept within the frame its time falls
//!   in, `FrameClock::input_sample`, so it reaches the same frame at every sample rate);
//! - a script's `[set]` values at t = 0 (the initial parameter state);
//! - grabs as the MIDI notes of the README's map (note on with the velocity, note off), resets as
//!   note 36;
//! - step lanes as parameter changes at their breakpoints; linear and smooth lanes as parameter
//!   changes at every simulation frame start (the sheet reads gestures once per frame) and at
//!   their breakpoints, whenever the value changes. A frame start's value is the lane's at the
//!   frame's exact time k / f_frame, not at its rounded sample: at 44.1 kHz a 5 ms frame is
//!   220.5 samples, and the rounded times gave the sheet other gestures in their last bits, so
//!   another crumple than at 48 kHz.
//!
//! At equal sample positions, parameter changes come before MIDI messages, as in the plugin
//! (parameters are read at the start of a (sub-)block, then its events are handled).

use sim_core::script::{DiscreteInput, Script, ScriptValue};

use super::midi_file::MidiFile;
use crate::engine::{FrameClock, ParamValues};
use crate::gesture_map::{MidiInput, NOTE_RESET, note_for_slot};

/// What happens at a sample.
#[derive(Clone, Debug, PartialEq)]
pub enum HostEvent {
    /// A parameter takes a new value.
    Param {
        /// Parameter id.
        id: String,
        /// New value.
        value: ScriptValue,
    },
    /// A MIDI message.
    Midi(MidiInput),
}

/// Events sorted by sample (parameters first at equal samples, then input order).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Timeline {
    /// (sample, event).
    pub events: Vec<(u64, HostEvent)>,
    /// Parameter values at t = 0 from the scripts' `[set]` tables, in order.
    pub initial: Vec<(String, ScriptValue)>,
    /// Length, seconds.
    pub length_s: f64,
}

impl Timeline {
    /// Adds a MIDI file (its length plus a 1 s tail for ringing sounds).
    pub fn add_midi(&mut self, f: &MidiFile, sample_rate_hz: f64, frames: FrameClock) {
        for e in &f.events {
            self.events.push((
                frames.input_sample(e.time_s, sample_rate_hz),
                HostEvent::Midi(e.input),
            ));
        }
        self.length_s = self.length_s.max(f.length_s + 1.0);
    }

    /// Adds a script. Parameter ids and values are validated against `scratch` (a copy of the
    /// parameter values, changed by the validation); errors name the script.
    pub fn add_script(
        &mut self,
        name: &str,
        s: &Script,
        sample_rate_hz: f64,
        frames: FrameClock,
        scratch: &mut ParamValues,
    ) -> Result<(), String> {
        for (id, v) in &s.set {
            scratch
                .set(id, v)
                .map_err(|e| format!("{name}: [set] {e}"))?;
            self.initial.push((id.clone(), v.clone()));
        }
        for lane in &s.lanes {
            for (_, v) in &lane.points {
                scratch
                    .set(&lane.id, v)
                    .map_err(|e| format!("{name}: lane {}: {e}", lane.id))?;
            }
        }
        for (t, d) in s.discrete_inputs() {
            let at = frames.input_sample(t, sample_rate_hz);
            let input = match d {
                DiscreteInput::Reset => MidiInput::NoteOn {
                    key: NOTE_RESET,
                    velocity: 1.0,
                },
                DiscreteInput::Grab { slot, velocity } => MidiInput::NoteOn {
                    key: note_for_slot(slot),
                    velocity,
                },
                DiscreteInput::Release { slot } => MidiInput::NoteOff {
                    key: note_for_slot(slot),
                },
            };
            self.events.push((at, HostEvent::Midi(input)));
        }
        for lane in &s.lanes {
            let first_t = lane.points[0].0;
            let last_t = lane.points[lane.points.len() - 1].0;
            let mut last: Option<ScriptValue> = None;
            let mut emit = |at: u64, v: ScriptValue, events: &mut Vec<(u64, HostEvent)>| {
                if last.as_ref() != Some(&v) {
                    events.push((
                        at,
                        HostEvent::Param {
                            id: lane.id.clone(),
                            value: v.clone(),
                        },
                    ));
                    last = Some(v);
                }
            };
            if lane.is_stepwise() {
                for (t, v) in &lane.points {
                    emit(
                        frames.input_sample(*t, sample_rate_hz),
                        v.clone(),
                        &mut self.events,
                    );
                }
            } else {
                // Frame starts from the lane's start to its end, each read at its frame's exact
                // time (the same at every sample rate), plus the breakpoints at theirs; a
                // breakpoint on a frame start's sample gives way to the frame start.
                let mut times: Vec<(u64, f64, bool)> = lane
                    .points
                    .iter()
                    .map(|(t, _)| (frames.input_sample(*t, sample_rate_hz), *t, false))
                    .collect();
                let first = frames.input_sample(first_t, sample_rate_hz);
                let last_s = frames.input_sample(last_t, sample_rate_hz);
                let mut k = (first as f64 / frames.samples_per_frame()).floor() as u64;
                loop {
                    let s = frames.start(k);
                    if s > last_s {
                        break;
                    }
                    if s >= first {
                        times.push((s, frames.time_s(k), true));
                    }
                    k += 1;
                }
                times.sort_by(|a, b| a.0.cmp(&b.0).then(b.2.cmp(&a.2)));
                times.dedup_by_key(|x| x.0);
                for (at, t, _) in times {
                    let v = lane.value_at(t);
                    emit(at, v, &mut self.events);
                }
            }
        }
        self.length_s = self.length_s.max(s.duration_s);
        Ok(())
    }

    /// Sorts the events: by sample, parameters before MIDI, otherwise stable.
    pub fn finish(&mut self) {
        self.events
            .sort_by_key(|(at, e)| (*at, matches!(e, HostEvent::Midi(_))));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn script_becomes_host_events() {
        let s = Script::parse(
            r#"
version = 1
duration_s = 2.0
[set]
size = "a5"
[[lane]]
id = "slide"
points = [[0.0, 0.0], [0.1, 1.0]]
[[lane]]
id = "table"
interp = "step"
points = [[0.05, false]]
[[grab]]
slot = "front"
on_s = 0.0
off_s = 1.0
velocity = 0.5
"#,
        )
        .unwrap();
        let mut tl = Timeline::default();
        let frames = FrameClock::new(48_000.0, 200.0);
        let mut scratch = ParamValues::default();
        tl.add_script("t", &s, 48_000.0, frames, &mut scratch)
            .unwrap();
        tl.finish();
        assert_eq!(tl.initial.len(), 1);
        assert_eq!(tl.length_s, 2.0);
        // 21 frame starts in [0, 0.1 s] at 240 samples per frame, all different values.
        let slide: Vec<_> = tl
            .events
            .iter()
            .filter(|(_, e)| matches!(e, HostEvent::Param { id, .. } if id == "slide"))
            .collect();
        assert_eq!(slide.len(), 21);
        assert!(tl.events.iter().any(|(at, e)| *at == 2400
            && matches!(e, HostEvent::Param { id, value: ScriptValue::Bool(false) } if id == "table")));
        // Grab at 0 comes after the parameter change at 0.
        let first_midi = tl
            .events
            .iter()
            .position(|(_, e)| matches!(e, HostEvent::Midi(_)))
            .unwrap();
        assert!(tl.events[..first_midi].iter().all(|(at, _)| *at == 0));
        assert!(
            tl.events
                .iter()
                .any(|(at, e)| *at == 48_000
                    && *e == HostEvent::Midi(MidiInput::NoteOff { key: 50 }))
        );
    }

    #[test]
    fn invalid_ids_and_values_are_reported_with_the_script_name() {
        let frames = FrameClock::new(48_000.0, 200.0);
        for (text, needle) in [
            ("version = 1\n[set]\nbogus = 1\n", "bogus"),
            (
                "version = 1\n[[lane]]\nid = \"slide\"\npoints = [[0, 5]]\n",
                "slide",
            ),
            ("version = 1\n[set]\nsize = \"a3\"\n", "size"),
        ] {
            let s = Script::parse(text).unwrap();
            let e = Timeline::default()
                .add_script("my.toml", &s, 48_000.0, frames, &mut ParamValues::default())
                .unwrap_err();
            assert!(e.starts_with("my.toml") && e.contains(needle), "{e}");
        }
    }
}
