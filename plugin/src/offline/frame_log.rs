//! # Frame logs: the sound input recorded as JSON lines
//!
//! The seeds note that the per-frame sound parameters (events, amplitudes, resonator sizes) can be
//! logged and replayed offline at a fixed frame rate (T 1832). `papier-render` can render from such
//! a log instead of simulating; the render tests use logs as fixtures. One
//! [`SoundFrame`] per line, UTF-8, `\n`-separated:
//!
//! ```json
//! {"frame":12,"time_s":0.06,
//!  "crumple":[{"amplitude":0.5,"resonator":{"lr_cm":10,"lc_cm":20,"centre_m":[0,0,0.76],"normal":[0,0,1],"radius_m":0.05}}],
//!  "friction":[{"slip_speed_m_s":0.1,"obstacle":"table","resonator":{"lr_cm":20,"lc_cm":30,"centre_m":[0,0,0.75],"normal":[0,0,1],"radius_m":0.1}}],
//!  "tear":{"speed_m_s":0.0,"tip_m":[0,0,0]}}
//! ```
//!
//! (shown wrapped; a record is one line). Fields:
//!
//! | key | type | meaning |
//! |---|---|---|
//! | `frame` | u64 | frame index, strictly increasing through the file |
//! | `time_s` | f64 | simulated time at the end of the frame, s, finite, non-decreasing |
//! | `crumple` | array (optional, ≤ 32) | crumple events: `amplitude` (finite) and `resonator` |
//! | `friction` | array (optional, ≤ 32) | friction sources: `slip_speed_m_s` (≥ 0), `obstacle` (`table`, `wall`, `floor`, `self_contact`; default `table`) and `resonator` |
//! | `tear` | object (optional) | `speed_m_s` (≥ 0), `tip_m`, `length_m` (optional), `onset` (optional, default false) and `resonator` (optional: the flaps that colour the noise) |
//! | `air` | object (optional) | the air the sheet moves: `strength_m3_s2` (≥ 0), `centre_m`, `normal` |
//! | `crackle` | object (optional) | the crackle of the sheet being deformed: `rate_m_rad_s` (≥ 0), `centre_m` |
//! | `dropped_crumple`, `dropped_friction` | u32 (optional) | events the simulation could not fit |
//!
//! A `resonator` has `lr_cm` and `lc_cm` (≥ 0; `lc_cm` = 0 is constrained; `lc_cm` is the TOTAL
//! free curved border, see `sounddb`), `centre_m` and `normal` (3 finite numbers each) and
//! `radius_m` (≥ 0). Empty lines and lines starting with `#` are skipped. Any other problem stops
//! the reader with the line number and the reason ([`FrameLogError`]); nothing is silently
//! truncated or clamped.

use std::io::{BufRead, Write};

use serde::{Deserialize, Serialize};
use sim_core::sound_input::{
    AirState, CrackleState, CrumpleEvent, FrictionSource, MAX_CRUMPLE_EVENTS, MAX_FRICTION_SOURCES,
    Obstacle, Resonator, SoundFrame, TearState,
};

/// Why a log could not be read.
#[derive(Debug, thiserror::Error)]
pub enum FrameLogError {
    /// Reading failed.
    #[error("frame log: read error after line {line}: {source}")]
    Io {
        /// Last line read.
        line: usize,
        /// The error.
        source: std::io::Error,
    },
    /// A line is not a valid record (JSON syntax, missing or mistyped key).
    #[error("frame log line {line}: {message}")]
    Parse {
        /// 1-based line number.
        line: usize,
        /// Parser message.
        message: String,
    },
    /// A record is well-formed but invalid (non-finite number, too many events, out of order).
    #[error("frame log line {line}: {message}")]
    Invalid {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
}

/// `resonator` record.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResonatorRecord {
    /// l_r, cm.
    pub lr_cm: f32,
    /// l_c (total free curved border), cm; 0 = constrained.
    pub lc_cm: f32,
    /// Disk centre, m.
    pub centre_m: [f32; 3],
    /// Disk normal.
    pub normal: [f32; 3],
    /// Disk radius, m.
    pub radius_m: f32,
}

/// A crumple event record.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrumpleRecord {
    /// Linear gain.
    pub amplitude: f32,
    /// The resonator.
    pub resonator: ResonatorRecord,
}

/// Obstacle names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ObstacleRecord {
    /// Table.
    #[default]
    Table,
    /// Wall.
    Wall,
    /// Floor.
    Floor,
    /// The sheet itself.
    SelfContact,
}

/// A friction source record.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionRecord {
    /// Slip speed, m/s.
    pub slip_speed_m_s: f32,
    /// Obstacle.
    #[serde(default)]
    pub obstacle: ObstacleRecord,
    /// The resonator.
    pub resonator: ResonatorRecord,
}

/// The tear record.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct TearRecord {
    /// Tear speed, m/s.
    pub speed_m_s: f32,
    /// Tip position, m.
    #[serde(default)]
    pub tip_m: [f32; 3],
    /// Length torn so far, m (absent while nothing is torn).
    #[serde(default, skip_serializing_if = "is_zero_f32")]
    pub length_m: f32,
    /// A tear onset in this frame (absent: none).
    #[serde(default, skip_serializing_if = "is_false")]
    pub onset: bool,
    /// The flaps at the tip that colour the noise (absent: none, white noise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resonator: Option<ResonatorRecord>,
}

/// The air record (absent: the sheet moved no air).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct AirRecord {
    /// Σ A |a_n|, m³/s².
    pub strength_m3_s2: f32,
    /// Centre, m.
    #[serde(default)]
    pub centre_m: [f32; 3],
    /// Mean normal.
    #[serde(default)]
    pub normal: [f32; 3],
}

/// The crackle record (absent: nothing bent moved).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct CrackleRecord {
    /// D, m·rad/s.
    pub rate_m_rad_s: f32,
    /// Centre, m.
    #[serde(default)]
    pub centre_m: [f32; 3],
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn is_zero_f32(x: &f32) -> bool {
    *x == 0.0
}

/// One line of a frame log.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameRecord {
    /// Frame index.
    pub frame: u64,
    /// Time at the end of the frame, s.
    pub time_s: f64,
    /// Crumple events.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub crumple: Vec<CrumpleRecord>,
    /// Friction sources.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub friction: Vec<FrictionRecord>,
    /// Tear.
    #[serde(default)]
    pub tear: TearRecord,
    /// Air.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub air: Option<AirRecord>,
    /// Crackle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crackle: Option<CrackleRecord>,
    /// Dropped crumple events.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub dropped_crumple: u32,
    /// Dropped friction sources.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub dropped_friction: u32,
}

fn is_zero(v: &u32) -> bool {
    *v == 0
}

fn res_record(r: &Resonator) -> ResonatorRecord {
    ResonatorRecord {
        lr_cm: r.lr_cm,
        lc_cm: r.lc_cm,
        centre_m: r.centre_m,
        normal: r.normal,
        radius_m: r.radius_m,
    }
}

fn res_from(r: &ResonatorRecord, what: &str) -> Result<Resonator, String> {
    let finite3 = |v: [f32; 3]| v.iter().all(|x| x.is_finite());
    if !(r.lr_cm.is_finite() && r.lr_cm >= 0.0) {
        return Err(format!(
            "{what}: lr_cm = {} must be finite and ≥ 0",
            r.lr_cm
        ));
    }
    if !(r.lc_cm.is_finite() && r.lc_cm >= 0.0) {
        return Err(format!(
            "{what}: lc_cm = {} must be finite and ≥ 0",
            r.lc_cm
        ));
    }
    if !(r.radius_m.is_finite() && r.radius_m >= 0.0) {
        return Err(format!(
            "{what}: radius_m = {} must be finite and ≥ 0",
            r.radius_m
        ));
    }
    if !finite3(r.centre_m) || !finite3(r.normal) {
        return Err(format!("{what}: centre_m and normal must be finite"));
    }
    Ok(Resonator {
        lr_cm: r.lr_cm,
        lc_cm: r.lc_cm,
        centre_m: r.centre_m,
        normal: r.normal,
        radius_m: r.radius_m,
    })
}

impl From<&SoundFrame> for FrameRecord {
    fn from(f: &SoundFrame) -> Self {
        Self {
            frame: f.frame,
            time_s: f.time_s,
            crumple: f
                .crumple()
                .iter()
                .map(|e| CrumpleRecord {
                    amplitude: e.amplitude,
                    resonator: res_record(&e.resonator),
                })
                .collect(),
            friction: f
                .friction()
                .iter()
                .map(|s| FrictionRecord {
                    slip_speed_m_s: s.slip_speed_m_s,
                    obstacle: match s.obstacle {
                        Obstacle::Table => ObstacleRecord::Table,
                        Obstacle::Wall => ObstacleRecord::Wall,
                        Obstacle::Floor => ObstacleRecord::Floor,
                        Obstacle::SelfContact => ObstacleRecord::SelfContact,
                    },
                    resonator: res_record(&s.resonator),
                })
                .collect(),
            tear: TearRecord {
                speed_m_s: f.tear.speed_m_s,
                tip_m: f.tear.tip_m,
                length_m: f.tear.length_m,
                onset: f.tear.onset,
                resonator: (f.tear.resonator.radius_m > 0.0).then(|| res_record(&f.tear.resonator)),
            },
            air: (f.air.strength_m3_s2 > 0.0).then_some(AirRecord {
                strength_m3_s2: f.air.strength_m3_s2,
                centre_m: f.air.centre_m,
                normal: f.air.normal,
            }),
            crackle: (f.crackle.rate_m_rad_s > 0.0).then_some(CrackleRecord {
                rate_m_rad_s: f.crackle.rate_m_rad_s,
                centre_m: f.crackle.centre_m,
            }),
            dropped_crumple: f.dropped_crumple,
            dropped_friction: f.dropped_friction,
        }
    }
}

impl FrameRecord {
    /// Validates the record and converts it (the message names the offending field).
    pub fn to_frame(&self) -> Result<SoundFrame, String> {
        if !self.time_s.is_finite() {
            return Err(format!("time_s = {} must be finite", self.time_s));
        }
        if self.crumple.len() > MAX_CRUMPLE_EVENTS {
            return Err(format!(
                "{} crumple events, at most {MAX_CRUMPLE_EVENTS} per frame",
                self.crumple.len()
            ));
        }
        if self.friction.len() > MAX_FRICTION_SOURCES {
            return Err(format!(
                "{} friction sources, at most {MAX_FRICTION_SOURCES} per frame",
                self.friction.len()
            ));
        }
        let mut f = SoundFrame::default();
        f.frame = self.frame;
        f.time_s = self.time_s;
        for (i, c) in self.crumple.iter().enumerate() {
            if !c.amplitude.is_finite() {
                return Err(format!(
                    "crumple[{i}].amplitude = {} must be finite",
                    c.amplitude
                ));
            }
            let resonator = res_from(&c.resonator, &format!("crumple[{i}].resonator"))?;
            f.push_crumple(CrumpleEvent {
                amplitude: c.amplitude,
                resonator,
            });
        }
        for (i, s) in self.friction.iter().enumerate() {
            if !(s.slip_speed_m_s.is_finite() && s.slip_speed_m_s >= 0.0) {
                return Err(format!(
                    "friction[{i}].slip_speed_m_s = {} must be finite and ≥ 0",
                    s.slip_speed_m_s
                ));
            }
            let resonator = res_from(&s.resonator, &format!("friction[{i}].resonator"))?;
            f.push_friction(FrictionSource {
                slip_speed_m_s: s.slip_speed_m_s,
                obstacle: match s.obstacle {
                    ObstacleRecord::Table => Obstacle::Table,
                    ObstacleRecord::Wall => Obstacle::Wall,
                    ObstacleRecord::Floor => Obstacle::Floor,
                    ObstacleRecord::SelfContact => Obstacle::SelfContact,
                },
                resonator,
            });
        }
        if !(self.tear.speed_m_s.is_finite() && self.tear.speed_m_s >= 0.0) {
            return Err(format!(
                "tear.speed_m_s = {} must be finite and ≥ 0",
                self.tear.speed_m_s
            ));
        }
        if !self.tear.tip_m.iter().all(|v| v.is_finite()) {
            return Err("tear.tip_m must be finite".into());
        }
        let resonator = match &self.tear.resonator {
            Some(r) => res_from(r, "tear.resonator")?,
            None => Resonator::default(),
        };
        f.tear = TearState {
            speed_m_s: self.tear.speed_m_s,
            tip_m: self.tear.tip_m,
            length_m: self.tear.length_m,
            onset: self.tear.onset,
            resonator,
        };
        if let Some(a) = &self.air {
            if !(a.strength_m3_s2.is_finite() && a.strength_m3_s2 >= 0.0) {
                return Err(format!(
                    "air.strength_m3_s2 = {} must be finite and ≥ 0",
                    a.strength_m3_s2
                ));
            }
            if !a.centre_m.iter().chain(&a.normal).all(|v| v.is_finite()) {
                return Err("air.centre_m and air.normal must be finite".into());
            }
            f.air = AirState {
                strength_m3_s2: a.strength_m3_s2,
                centre_m: a.centre_m,
                normal: a.normal,
            };
        }
        if let Some(c) = &self.crackle {
            if !(c.rate_m_rad_s.is_finite() && c.rate_m_rad_s >= 0.0) {
                return Err(format!(
                    "crackle.rate_m_rad_s = {} must be finite and ≥ 0",
                    c.rate_m_rad_s
                ));
            }
            if !c.centre_m.iter().all(|v| v.is_finite()) {
                return Err("crackle.centre_m must be finite".into());
            }
            f.crackle = CrackleState {
                rate_m_rad_s: c.rate_m_rad_s,
                centre_m: c.centre_m,
            };
        }
        f.dropped_crumple = self.dropped_crumple;
        f.dropped_friction = self.dropped_friction;
        Ok(f)
    }
}

/// Reads frames from a JSON-lines stream, validating as it goes.
pub struct FrameLogReader<R: BufRead> {
    reader: R,
    line: usize,
    buf: String,
    last: Option<(u64, f64)>,
    failed: bool,
}

impl<R: BufRead> FrameLogReader<R> {
    /// A reader over `reader`.
    pub fn new(reader: R) -> Self {
        Self {
            reader,
            line: 0,
            buf: String::new(),
            last: None,
            failed: false,
        }
    }
}

impl<R: BufRead> Iterator for FrameLogReader<R> {
    type Item = Result<SoundFrame, FrameLogError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        loop {
            self.buf.clear();
            match self.reader.read_line(&mut self.buf) {
                Ok(0) => return None,
                Ok(_) => {}
                Err(source) => {
                    self.failed = true;
                    return Some(Err(FrameLogError::Io {
                        line: self.line,
                        source,
                    }));
                }
            }
            self.line += 1;
            let text = self.buf.trim();
            if text.is_empty() || text.starts_with('#') {
                continue;
            }
            let line = self.line;
            let record: FrameRecord = match serde_json::from_str(text) {
                Ok(r) => r,
                Err(e) => {
                    self.failed = true;
                    return Some(Err(FrameLogError::Parse {
                        line,
                        message: e.to_string(),
                    }));
                }
            };
            let frame = match record.to_frame() {
                Ok(f) => f,
                Err(message) => {
                    self.failed = true;
                    return Some(Err(FrameLogError::Invalid { line, message }));
                }
            };
            if let Some((f, t)) = self.last {
                if frame.frame <= f {
                    self.failed = true;
                    return Some(Err(FrameLogError::Invalid {
                        line,
                        message: format!(
                            "frame {} does not follow frame {f} (indices must increase)",
                            frame.frame
                        ),
                    }));
                }
                if frame.time_s < t {
                    self.failed = true;
                    return Some(Err(FrameLogError::Invalid {
                        line,
                        message: format!(
                            "time_s {} is before the previous frame's {t}",
                            frame.time_s
                        ),
                    }));
                }
            }
            self.last = Some((frame.frame, frame.time_s));
            return Some(Ok(frame));
        }
    }
}

/// Parses a whole log held in memory.
pub fn parse_frame_log(text: &str) -> Result<Vec<SoundFrame>, FrameLogError> {
    FrameLogReader::new(text.as_bytes()).collect()
}

/// Reads a whole log file.
pub fn read_frame_log(path: &std::path::Path) -> Result<Vec<SoundFrame>, FrameLogError> {
    let file = std::fs::File::open(path).map_err(|source| FrameLogError::Io { line: 0, source })?;
    FrameLogReader::new(std::io::BufReader::new(file)).collect()
}

/// Writes one frame as one line.
pub fn write_frame<W: Write>(w: &mut W, frame: &SoundFrame) -> std::io::Result<()> {
    let record = FrameRecord::from(frame);
    serde_json::to_writer(&mut *w, &record).map_err(std::io::Error::other)?;
    w.write_all(b"\n")
}

/// Writes frames to a JSON-lines string.
pub fn frames_to_string(frames: &[SoundFrame]) -> String {
    let mut out = Vec::new();
    for f in frames {
        // Writing to a Vec cannot fail.
        let _ = write_frame(&mut out, f);
    }
    String::from_utf8(out).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_frame(i: u64) -> SoundFrame {
        let mut f = SoundFrame::default();
        f.frame = i;
        f.time_s = i as f64 * 0.005;
        let res = Resonator {
            lr_cm: 10.0,
            lc_cm: 20.0,
            centre_m: [0.01, -0.02, 0.76],
            normal: [0.0, 0.0, 1.0],
            radius_m: 0.05,
        };
        f.push_crumple(CrumpleEvent {
            amplitude: 0.7,
            resonator: res,
        });
        f.push_friction(FrictionSource {
            slip_speed_m_s: 0.12,
            obstacle: Obstacle::Wall,
            resonator: res,
        });
        f.tear = TearState {
            speed_m_s: 0.05,
            tip_m: [0.1, 0.0, 0.75],
            length_m: 0.02,
            onset: i == 1,
            resonator: if i.is_multiple_of(2) {
                res
            } else {
                Resonator::default()
            },
        };
        f
    }

    #[test]
    fn round_trip() {
        let frames: Vec<SoundFrame> = (0..5).map(sample_frame).collect();
        let text = frames_to_string(&frames);
        assert_eq!(text.lines().count(), 5);
        let back = parse_frame_log(&text).unwrap();
        assert_eq!(back, frames);
        // Comments and blank lines are fine; minimal records too.
        let text = "# a comment\n\n{\"frame\":0,\"time_s\":0.0}\n";
        let f = parse_frame_log(text).unwrap();
        assert_eq!(f.len(), 1);
        assert!(f[0].crumple().is_empty());
    }

    #[test]
    fn bad_lines_are_reported_with_their_number() {
        let good = frames_to_string(&[sample_frame(0)]);
        let cases = [
            (format!("{good}{{\"frame\":1,\"time_s\":0.1,\n"), 2, "EOF"),
            (format!("{good}{{\"frame\":0,\"time_s\":0.1}}\n"), 2, "increase"),
            (format!("{good}\n{{\"frame\":2,\"time_s\":-0.1}}\n"), 3, "before"),
            (
                format!("{good}{{\"frame\":1,\"time_s\":0.1,\"tear\":{{\"speed_m_s\":-1}}}}\n"),
                2,
                "tear.speed_m_s",
            ),
            ("{\"frame\":0,\"time_s\":0.0,\"bogus\":1}\n".to_string(), 1, "bogus"),
            (
                "{\"frame\":0,\"time_s\":0.0,\"crumple\":[{\"amplitude\":1,\"resonator\":{\"lr_cm\":-1,\"lc_cm\":0,\"centre_m\":[0,0,0],\"normal\":[0,0,1],\"radius_m\":0}}]}\n"
                    .to_string(),
                1,
                "crumple[0].resonator: lr_cm",
            ),
        ];
        for (text, line, needle) in cases {
            let err = parse_frame_log(&text).unwrap_err();
            let msg = err.to_string();
            assert!(msg.contains(&format!("line {line}")), "{msg}");
            assert!(msg.contains(needle), "{msg} lacks {needle}");
        }
        let mut many = FrameRecord::from(&SoundFrame::default());
        many.crumple = vec![
            CrumpleRecord {
                amplitude: 1.0,
                resonator: res_record(&Resonator::default()),
            };
            MAX_CRUMPLE_EVENTS + 1
        ];
        let text = serde_json::to_string(&many).unwrap();
        assert!(
            parse_frame_log(&text)
                .unwrap_err()
                .to_string()
                .contains("at most")
        );
    }
}
