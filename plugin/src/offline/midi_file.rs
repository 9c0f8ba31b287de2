//! # Standard MIDI files for the offline renderer
//!
//! Reads a `.mid` file (format 0 or 1; metrical time with tempo changes, or SMPTE time) into
//! time-stamped [`MidiInput`]s in seconds. Before parsing, the chunk structure is checked
//! against the file length, so a truncated file is an error rather than a silently shortened
//! render. Only note on/off and control changes matter to Papier; everything else is skipped.

use std::path::Path;

use midly::{MetaMessage, MidiMessage, Smf, Timing, TrackEventKind};

use crate::gesture_map::MidiInput;

/// Default tempo of a metrical file without tempo events, µs per quarter note (120 BPM).
const DEFAULT_TEMPO_US: u32 = 500_000;

/// A time-stamped MIDI input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimedMidi {
    /// Time, seconds.
    pub time_s: f64,
    /// The message.
    pub input: MidiInput,
}

/// A parsed MIDI file.
#[derive(Clone, Debug, PartialEq)]
pub struct MidiFile {
    /// Messages in time order (stable for equal times).
    pub events: Vec<TimedMidi>,
    /// Length of the file (its last event, end-of-track included), seconds.
    pub length_s: f64,
}

fn be_u32(b: &[u8]) -> u32 {
    u32::from_be_bytes([b[0], b[1], b[2], b[3]])
}

/// Checks the chunk layout: header chunk, then as many track chunks as declared, each within the
/// file.
fn check_chunks(bytes: &[u8]) -> Result<(), String> {
    if bytes.is_empty() {
        return Err("the file is empty".into());
    }
    if bytes.len() < 14 || &bytes[0..4] != b"MThd" {
        return Err("not a Standard MIDI File (no MThd header)".into());
    }
    let header_len = be_u32(&bytes[4..8]) as usize;
    if header_len < 6 || 8 + header_len > bytes.len() {
        return Err("truncated or malformed MIDI header".into());
    }
    let ntracks = u16::from_be_bytes([bytes[10], bytes[11]]) as usize;
    let mut pos = 8 + header_len;
    let mut found = 0;
    while found < ntracks {
        if pos + 8 > bytes.len() {
            return Err(format!(
                "truncated MIDI file: {ntracks} tracks declared, only {found} present"
            ));
        }
        let len = be_u32(&bytes[pos + 4..pos + 8]) as usize;
        if pos + 8 + len > bytes.len() {
            return Err(format!(
                "truncated MIDI file: track {} declares {len} bytes, only {} remain",
                found + 1,
                bytes.len() - pos - 8
            ));
        }
        if &bytes[pos..pos + 4] == b"MTrk" {
            found += 1;
        }
        pos += 8 + len;
    }
    Ok(())
}

impl MidiFile {
    /// Reads and parses a MIDI file; the error is one line.
    pub fn from_file(path: &Path) -> Result<Self, String> {
        let bytes =
            std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        Self::parse(&bytes)
    }

    /// Parses MIDI file bytes.
    pub fn parse(bytes: &[u8]) -> Result<Self, String> {
        check_chunks(bytes)?;
        let smf = Smf::parse(bytes).map_err(|e| format!("invalid MIDI file: {e}"))?;

        // Absolute ticks for every event of every track, then one tempo map.
        struct Ev {
            tick: u64,
            track: usize,
            idx: usize,
            kind: Kind,
        }
        enum Kind {
            Tempo(u32),
            Midi(MidiInput),
            End,
        }
        let mut evs: Vec<Ev> = Vec::new();
        for (ti, track) in smf.tracks.iter().enumerate() {
            let mut tick = 0u64;
            for (ei, e) in track.iter().enumerate() {
                tick += u64::from(u32::from(e.delta));
                let kind = match e.kind {
                    TrackEventKind::Meta(MetaMessage::Tempo(t)) => Kind::Tempo(u32::from(t)),
                    TrackEventKind::Meta(MetaMessage::EndOfTrack) => Kind::End,
                    TrackEventKind::Midi { message, .. } => match message {
                        MidiMessage::NoteOn { key, vel } if u8::from(vel) > 0 => {
                            Kind::Midi(MidiInput::NoteOn {
                                key: key.into(),
                                velocity: f32::from(u8::from(vel)) / 127.0,
                            })
                        }
                        MidiMessage::NoteOn { key, .. } | MidiMessage::NoteOff { key, .. } => {
                            Kind::Midi(MidiInput::NoteOff { key: key.into() })
                        }
                        MidiMessage::Controller { controller, value } => {
                            Kind::Midi(MidiInput::Cc {
                                cc: controller.into(),
                                value: f32::from(u8::from(value)) / 127.0,
                            })
                        }
                        _ => continue,
                    },
                    _ => continue,
                };
                evs.push(Ev {
                    tick,
                    track: ti,
                    idx: ei,
                    kind,
                });
            }
        }
        evs.sort_by_key(|e| (e.tick, e.track, e.idx));

        // Metrical: seconds = ticks · tempo / ticks-per-quarter; SMPTE: ticks / (fps · subframes).
        let (divisor, smpte) = match smf.header.timing {
            Timing::Metrical(tpq) => {
                let tpq = u16::from(tpq);
                if tpq == 0 {
                    return Err("invalid MIDI file: 0 ticks per quarter note".into());
                }
                (f64::from(tpq), false)
            }
            Timing::Timecode(fps, sub) => {
                if sub == 0 {
                    return Err("invalid MIDI file: 0 subframes per frame".into());
                }
                (f64::from(fps.as_f32()) * f64::from(sub), true)
            }
        };

        let mut tempo_us = DEFAULT_TEMPO_US;
        let mut last_tick = 0u64;
        let mut t_s = 0.0f64;
        let mut events = Vec::new();
        for e in evs {
            let dt_ticks = (e.tick - last_tick) as f64;
            t_s += if smpte {
                dt_ticks / divisor
            } else {
                dt_ticks * f64::from(tempo_us) * 1e-6 / divisor
            };
            last_tick = e.tick;
            if !t_s.is_finite() || t_s > crate::offline::MAX_RENDER_S {
                return Err(format!(
                    "MIDI file is longer than the {} s limit",
                    crate::offline::MAX_RENDER_S
                ));
            }
            match e.kind {
                Kind::Tempo(t) => tempo_us = t.max(1),
                Kind::Midi(input) => events.push(TimedMidi { time_s: t_s, input }),
                Kind::End => {}
            }
        }
        Ok(Self {
            events,
            length_s: t_s,
        })
    }
}

/// Writes a format-0 MIDI file (480 ticks per quarter, 120 BPM) from time-stamped inputs.
/// Used by tests and examples to produce input for `papier-render`.
pub fn write_smf(events: &[TimedMidi], length_s: f64) -> Vec<u8> {
    use midly::num::{u4, u7, u28};
    use midly::{Format, Header, TrackEvent};
    let tpq = 480u16;
    let ticks_per_s = f64::from(tpq) * 2.0; // 120 BPM
    let mut sorted: Vec<&TimedMidi> = events.iter().collect();
    sorted.sort_by(|a, b| a.time_s.total_cmp(&b.time_s));
    let mut track = Vec::new();
    let mut last = 0u64;
    let mut push = |tick: u64, kind: TrackEventKind<'static>| {
        let delta = tick.saturating_sub(last);
        last = last.max(tick);
        track.push(TrackEvent {
            delta: u28::new(delta.min(0x0FFF_FFFF) as u32),
            kind,
        });
    };
    push(
        0,
        TrackEventKind::Meta(MetaMessage::Tempo(midly::num::u24::new(500_000))),
    );
    for e in sorted {
        let tick = (e.time_s.max(0.0) * ticks_per_s).round() as u64;
        let message = match e.input {
            MidiInput::NoteOn { key, velocity } => MidiMessage::NoteOn {
                key: u7::new(key.min(127)),
                vel: u7::new(((velocity.clamp(0.0, 1.0) * 127.0).round() as u8).max(1)),
            },
            MidiInput::NoteOff { key } => MidiMessage::NoteOff {
                key: u7::new(key.min(127)),
                vel: u7::new(0),
            },
            MidiInput::AllNotesOff => MidiMessage::Controller {
                controller: u7::new(123),
                value: u7::new(0),
            },
            MidiInput::Cc { cc, value } => MidiMessage::Controller {
                controller: u7::new(cc.min(127)),
                value: u7::new((value.clamp(0.0, 1.0) * 127.0).round() as u8),
            },
        };
        push(
            tick,
            TrackEventKind::Midi {
                channel: u4::new(0),
                message,
            },
        );
    }
    let end = (length_s.max(0.0) * ticks_per_s).round() as u64;
    push(end, TrackEventKind::Meta(MetaMessage::EndOfTrack));
    let smf = Smf {
        header: Header::new(
            Format::SingleTrack,
            Timing::Metrical(midly::num::u15::new(tpq)),
        ),
        tracks: vec![track],
    };
    let mut out = Vec::new();
    // Writing to a Vec cannot fail.
    let _ = smf.write_std(&mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn write_then_parse_round_trips_times_and_messages() {
        let evs = vec![
            TimedMidi {
                time_s: 0.0,
                input: MidiInput::NoteOn {
                    key: 48,
                    velocity: 1.0,
                },
            },
            TimedMidi {
                time_s: 0.5,
                input: MidiInput::Cc { cc: 21, value: 1.0 },
            },
            TimedMidi {
                time_s: 2.25,
                input: MidiInput::NoteOff { key: 48 },
            },
        ];
        let bytes = write_smf(&evs, 10.0);
        let f = MidiFile::parse(&bytes).unwrap();
        assert_eq!(f.events.len(), 3);
        assert!((f.events[1].time_s - 0.5).abs() < 1e-9);
        assert!((f.events[2].time_s - 2.25).abs() < 1e-9);
        assert_eq!(f.events[2].input, MidiInput::NoteOff { key: 48 });
        assert!((f.length_s - 10.0).abs() < 1e-9);
    }

    #[test]
    fn bad_files_give_one_line_errors() {
        let good = write_smf(
            &[TimedMidi {
                time_s: 1.0,
                input: MidiInput::NoteOn {
                    key: 50,
                    velocity: 0.5,
                },
            }],
            2.0,
        );
        let mut cases: Vec<Vec<u8>> = vec![
            vec![],
            b"hello world, not midi at all".to_vec(),
            good[..good.len() - 3].to_vec(),
            good[..20].to_vec(),
        ];
        let mut x = 12345u32;
        cases.push(
            (0..4096)
                .map(|_| {
                    x ^= x << 13;
                    x ^= x >> 17;
                    x ^= x << 5;
                    x as u8
                })
                .collect(),
        );
        // A valid header and chunk layout around random track bytes: a lenient parser would
        // cut the track short and render silence.
        for seed in 1..=8u32 {
            let mut bytes = good[..14].to_vec();
            bytes.extend_from_slice(b"MTrk");
            bytes.extend_from_slice(&512u32.to_be_bytes());
            let mut x = seed.wrapping_mul(2_654_435_761);
            bytes.extend((0..512).map(|_| {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                x as u8
            }));
            cases.push(bytes);
        }
        for c in cases {
            let e = MidiFile::parse(&c).unwrap_err();
            assert!(!e.contains('\n') && !e.is_empty(), "{e}");
        }
    }
}
