//! # Scripts: automation lanes, grabs and resets in a TOML file
//!
//! A script is the offline twin of a DAW track: parameter values at t = 0, automation lanes
//! (parameter id, breakpoints, interpolation), held grabs (the MIDI notes 48–55 of the plugin)
//! and resets. The seed scenario library (`sim-core/scenarios/*.toml`) is written in it, and
//! `papier-render --script FILE.toml` plays it through the plugin's engine.
//!
//! ```toml
//! version = 1                 # format version (required)
//! duration_s = 3.3            # optional; default: last breakpoint or release + 1 s
//!
//! [set]                       # parameter values at t = 0 (plugin parameter ids)
//! size = "a4"
//! table = true
//!
//! [[lane]]
//! id = "slide"
//! interp = "linear"           # "step" | "linear" | "smooth" (smoothstep between points)
//! points = [[0.0, 0.0], [1.5, 0.6]]   # [time_s, value], times non-decreasing
//!
//! [[grab]]
//! slot = "front"              # back | front | left | right | corners
//! on_s = 0.0
//! off_s = 2.0                 # optional: held to the end
//! velocity = 0.8              # grip speed 0–1 (MIDI velocity / 127); default 0.8
//!
//! [[reset]]
//! at_s = 1.0
//!
//! [phrase]                    # optional: read by the plugin's phrase loader, not by scripts
//! note = 60
//! ```
//!
//! Parsing checks the structure (types, finite and non-negative times, ordering, known slots);
//! parameter ids are checked by the consumer, which knows its parameter set. A lane's value
//! before its first point is its first value; after its last point, its last value.

use std::path::Path;

use serde::Deserialize;
use thiserror::Error;

use crate::control::GrabSlot;

/// The only script format version this build reads.
pub const SCRIPT_VERSION: u32 = 1;

/// Longest script accepted, seconds (one hour).
pub const MAX_SCRIPT_DURATION_S: f64 = 3600.0;

/// Why a script could not be read.
#[derive(Debug, Error)]
pub enum ScriptError {
    /// The file could not be read.
    #[error("cannot read script {path}: {source}")]
    Io {
        /// File path.
        path: String,
        /// Underlying error.
        source: std::io::Error,
    },
    /// The file is empty.
    #[error("script is empty")]
    Empty,
    /// The text is not valid UTF-8 TOML of the expected shape.
    #[error("script is not valid TOML: {0}")]
    Toml(String),
    /// Unsupported `version`.
    #[error("unsupported script version {0} (this build reads version {SCRIPT_VERSION})")]
    Version(u32),
    /// A semantic problem, with its location.
    #[error("{0}")]
    Invalid(String),
}

/// A parameter value in a script: a number, a boolean or a text id (enums such as `size`).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum ScriptValue {
    /// A boolean (`table = true`).
    Bool(bool),
    /// A number in the parameter's plain units.
    Number(f64),
    /// A text id (`size = "a6"`).
    Text(String),
}

impl ScriptValue {
    /// The number, if this is one.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            ScriptValue::Number(v) => Some(*v),
            _ => None,
        }
    }
}

impl std::fmt::Display for ScriptValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ScriptValue::Bool(b) => write!(f, "{b}"),
            ScriptValue::Number(v) => write!(f, "{v}"),
            ScriptValue::Text(s) => write!(f, "{s:?}"),
        }
    }
}

/// Interpolation between lane breakpoints.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Interp {
    /// Hold each value until the next breakpoint.
    Step,
    /// Straight lines.
    #[default]
    Linear,
    /// Smoothstep (zero slope at each breakpoint).
    Smooth,
}

/// An automation lane.
#[derive(Clone, Debug, PartialEq)]
pub struct Lane {
    /// Parameter id.
    pub id: String,
    /// Interpolation.
    pub interp: Interp,
    /// Breakpoints (time in seconds, value), times non-decreasing.
    pub points: Vec<(f64, ScriptValue)>,
}

impl Lane {
    /// Value at time `t_s`. Numbers are interpolated; other values step.
    pub fn value_at(&self, t_s: f64) -> ScriptValue {
        let pts = &self.points;
        let idx = pts.partition_point(|(t, _)| *t <= t_s);
        if idx == 0 {
            return pts[0].1.clone();
        }
        if idx >= pts.len() {
            return pts[pts.len() - 1].1.clone();
        }
        let (t0, v0) = &pts[idx - 1];
        let (t1, v1) = &pts[idx];
        match (self.interp, v0, v1) {
            (Interp::Step, _, _) => v0.clone(),
            (interp, ScriptValue::Number(a), ScriptValue::Number(b)) if t1 > t0 => {
                let mut u = (t_s - t0) / (t1 - t0);
                if interp == Interp::Smooth {
                    u = u * u * (3.0 - 2.0 * u);
                }
                ScriptValue::Number(a + (b - a) * u)
            }
            _ => v0.clone(),
        }
    }

    /// True if the lane only changes at its breakpoints.
    pub fn is_stepwise(&self) -> bool {
        self.interp == Interp::Step
            || self
                .points
                .iter()
                .any(|(_, v)| !matches!(v, ScriptValue::Number(_)))
    }
}

/// A held grab.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrabSpan {
    /// Which points are held.
    pub slot: GrabSlot,
    /// Grab time, seconds.
    pub on_s: f64,
    /// Release time, seconds (`None`: held to the end).
    pub off_s: Option<f64>,
    /// Grip speed 0–1.
    pub velocity: f32,
}

/// A discrete script input, in time order (see [`Script::discrete_inputs`]).
#[derive(Clone, Debug, PartialEq)]
pub enum DiscreteInput {
    /// Reset the sheet.
    Reset,
    /// Grab a slot.
    Grab {
        /// Slot.
        slot: GrabSlot,
        /// Grip speed 0–1.
        velocity: f32,
    },
    /// Release a slot.
    Release {
        /// Slot.
        slot: GrabSlot,
    },
}

/// A parsed, validated script.
#[derive(Clone, Debug, PartialEq)]
pub struct Script {
    /// Total length, seconds.
    pub duration_s: f64,
    /// Parameter values at t = 0, in file order.
    pub set: Vec<(String, ScriptValue)>,
    /// Automation lanes.
    pub lanes: Vec<Lane>,
    /// Grabs.
    pub grabs: Vec<GrabSpan>,
    /// Reset times, seconds.
    pub resets: Vec<f64>,
    /// The `[phrase]` table, untouched: how the plugin binds the script to a MIDI note. A script
    /// played as a script ignores it.
    pub phrase: Option<toml::Table>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScript {
    version: Option<u32>,
    duration_s: Option<f64>,
    #[serde(default)]
    set: toml::Table,
    #[serde(default)]
    lane: Vec<RawLane>,
    #[serde(default)]
    grab: Vec<RawGrab>,
    #[serde(default)]
    reset: Vec<RawReset>,
    phrase: Option<toml::Table>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLane {
    id: String,
    #[serde(default)]
    interp: Interp,
    points: Vec<(f64, ScriptValue)>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGrab {
    slot: String,
    on_s: f64,
    off_s: Option<f64>,
    velocity: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawReset {
    at_s: f64,
}

fn check_time(t: f64, what: &str) -> Result<(), ScriptError> {
    if !t.is_finite() || !(0.0..=MAX_SCRIPT_DURATION_S).contains(&t) {
        return Err(ScriptError::Invalid(format!(
            "{what}: time {t} s is not within 0–{MAX_SCRIPT_DURATION_S} s"
        )));
    }
    Ok(())
}

fn value_from_toml(v: &toml::Value, what: &str) -> Result<ScriptValue, ScriptError> {
    match v {
        toml::Value::Boolean(b) => Ok(ScriptValue::Bool(*b)),
        toml::Value::Integer(i) => Ok(ScriptValue::Number(*i as f64)),
        toml::Value::Float(f) if f.is_finite() => Ok(ScriptValue::Number(*f)),
        toml::Value::Float(f) => Err(ScriptError::Invalid(format!(
            "{what}: value {f} is not finite"
        ))),
        toml::Value::String(s) => Ok(ScriptValue::Text(s.clone())),
        other => Err(ScriptError::Invalid(format!(
            "{what}: expected a number, boolean or text, found {}",
            other.type_str()
        ))),
    }
}

impl Script {
    /// Reads and parses a script file.
    pub fn from_file(path: &Path) -> Result<Self, ScriptError> {
        let bytes = std::fs::read(path).map_err(|source| ScriptError::Io {
            path: path.display().to_string(),
            source,
        })?;
        let text = String::from_utf8(bytes)
            .map_err(|_| ScriptError::Toml("the file is not UTF-8 text".into()))?;
        Self::parse(&text)
    }

    /// Parses script text.
    pub fn parse(text: &str) -> Result<Self, ScriptError> {
        if text.trim().is_empty() {
            return Err(ScriptError::Empty);
        }
        let raw: RawScript = toml::from_str(text).map_err(|e| {
            // One line: the message without the source excerpt.
            let msg = e.message().replace('\n', " ");
            match e.span() {
                Some(span) => {
                    let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
                    ScriptError::Toml(format!("line {line}: {msg}"))
                }
                None => ScriptError::Toml(msg),
            }
        })?;
        let version = raw
            .version
            .ok_or_else(|| ScriptError::Invalid("missing `version = 1`".into()))?;
        if version != SCRIPT_VERSION {
            return Err(ScriptError::Version(version));
        }

        let mut set = Vec::with_capacity(raw.set.len());
        for (k, v) in &raw.set {
            set.push((k.clone(), value_from_toml(v, &format!("[set] {k}"))?));
        }

        let mut last_t: f64 = 0.0;
        let mut lanes = Vec::with_capacity(raw.lane.len());
        for (i, l) in raw.lane.into_iter().enumerate() {
            let what = format!("lane {} ({})", i + 1, l.id);
            if l.id.is_empty() {
                return Err(ScriptError::Invalid(format!("{what}: empty id")));
            }
            if l.points.is_empty() {
                return Err(ScriptError::Invalid(format!("{what}: no points")));
            }
            let mut prev = f64::NEG_INFINITY;
            for (t, v) in &l.points {
                check_time(*t, &what)?;
                if *t < prev {
                    return Err(ScriptError::Invalid(format!(
                        "{what}: times must not decrease ({t} after {prev})"
                    )));
                }
                if let ScriptValue::Number(x) = v
                    && !x.is_finite()
                {
                    return Err(ScriptError::Invalid(format!("{what}: value is not finite")));
                }
                prev = *t;
            }
            let numbers = l
                .points
                .iter()
                .all(|(_, v)| matches!(v, ScriptValue::Number(_)));
            if l.interp != Interp::Step && !numbers {
                return Err(ScriptError::Invalid(format!(
                    "{what}: only numeric lanes can use interp = \"{}\"; use \"step\"",
                    if l.interp == Interp::Linear {
                        "linear"
                    } else {
                        "smooth"
                    }
                )));
            }
            last_t = last_t.max(prev);
            lanes.push(Lane {
                id: l.id,
                interp: l.interp,
                points: l.points,
            });
        }

        let mut grabs = Vec::with_capacity(raw.grab.len());
        for (i, g) in raw.grab.into_iter().enumerate() {
            let what = format!("grab {}", i + 1);
            let slot = GrabSlot::from_id(&g.slot).ok_or_else(|| {
                ScriptError::Invalid(format!(
                    "{what}: unknown slot {:?} (back, front, left, right, corners)",
                    g.slot
                ))
            })?;
            check_time(g.on_s, &what)?;
            if let Some(off) = g.off_s {
                check_time(off, &what)?;
                if off < g.on_s {
                    return Err(ScriptError::Invalid(format!(
                        "{what}: off_s {off} is before on_s {}",
                        g.on_s
                    )));
                }
                last_t = last_t.max(off);
            }
            last_t = last_t.max(g.on_s);
            let velocity = g.velocity.unwrap_or(0.8);
            if !velocity.is_finite() || !(0.0..=1.0).contains(&velocity) {
                return Err(ScriptError::Invalid(format!(
                    "{what}: velocity {velocity} is not within 0–1"
                )));
            }
            grabs.push(GrabSpan {
                slot,
                on_s: g.on_s,
                off_s: g.off_s,
                velocity: velocity as f32,
            });
        }

        let mut resets = Vec::with_capacity(raw.reset.len());
        for (i, r) in raw.reset.into_iter().enumerate() {
            check_time(r.at_s, &format!("reset {}", i + 1))?;
            last_t = last_t.max(r.at_s);
            resets.push(r.at_s);
        }

        let duration_s = match raw.duration_s {
            Some(d) => {
                if !d.is_finite() || d <= 0.0 || d > MAX_SCRIPT_DURATION_S {
                    return Err(ScriptError::Invalid(format!(
                        "duration_s {d} is not within (0, {MAX_SCRIPT_DURATION_S}] s"
                    )));
                }
                d
            }
            None => last_t + 1.0,
        };

        Ok(Self {
            duration_s,
            set,
            lanes,
            grabs,
            resets,
            phrase: raw.phrase,
        })
    }

    /// Every parameter id the script refers to (in `[set]` and lanes).
    pub fn param_ids(&self) -> impl Iterator<Item = &str> {
        self.set
            .iter()
            .map(|(k, _)| k.as_str())
            .chain(self.lanes.iter().map(|l| l.id.as_str()))
    }

    /// The discrete inputs (resets, grabs, releases) sorted by time; at equal times resets come
    /// first, then releases, then grabs, each group in file order.
    pub fn discrete_inputs(&self) -> Vec<(f64, DiscreteInput)> {
        let mut out: Vec<(f64, u8, usize, DiscreteInput)> = Vec::new();
        for (i, t) in self.resets.iter().enumerate() {
            out.push((*t, 0, i, DiscreteInput::Reset));
        }
        for (i, g) in self.grabs.iter().enumerate() {
            out.push((
                g.on_s,
                2,
                i,
                DiscreteInput::Grab {
                    slot: g.slot,
                    velocity: g.velocity,
                },
            ));
            if let Some(off) = g.off_s {
                out.push((off, 1, i, DiscreteInput::Release { slot: g.slot }));
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        out.into_iter().map(|(t, _, _, d)| (t, d)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const OK: &str = r#"
version = 1
[set]
size = "a6"
table = true
table_height_cm = 70
[[lane]]
id = "slide"
points = [[0.0, 0.0], [1.0, 1.0]]
[[lane]]
id = "size"
interp = "step"
points = [[0.0, "a4"], [2.0, "a5"]]
[[grab]]
slot = "front"
on_s = 0.5
off_s = 1.5
[[reset]]
at_s = 0.5
"#;

    #[test]
    fn parses_and_interpolates() {
        let s = Script::parse(OK).unwrap();
        assert_eq!(s.set.len(), 3);
        assert_eq!(s.lanes[0].value_at(0.25), ScriptValue::Number(0.25));
        assert_eq!(s.lanes[0].value_at(-1.0), ScriptValue::Number(0.0));
        assert_eq!(s.lanes[0].value_at(9.0), ScriptValue::Number(1.0));
        assert_eq!(s.lanes[1].value_at(1.9), ScriptValue::Text("a4".into()));
        assert_eq!(s.lanes[1].value_at(2.0), ScriptValue::Text("a5".into()));
        assert!((s.duration_s - 3.0).abs() < 1e-12);
        let d = s.discrete_inputs();
        assert_eq!(d[0], (0.5, DiscreteInput::Reset));
        assert!(matches!(d[1].1, DiscreteInput::Grab { .. }));
        assert!(matches!(d[2], (t, DiscreteInput::Release { .. }) if t == 1.5));
    }

    #[test]
    fn smooth_lane_has_flat_ends() {
        let s = Script::parse(
            "version = 1\n[[lane]]\nid = \"lift\"\ninterp = \"smooth\"\npoints = [[0, 0], [1, 1]]\n",
        )
        .unwrap();
        let v = |t| s.lanes[0].value_at(t).as_f64().unwrap();
        assert!((v(0.5) - 0.5).abs() < 1e-12);
        assert!(v(0.01) < 0.01 * 0.5);
    }

    #[test]
    fn rejects_bad_input_with_clear_errors() {
        let cases = [
            ("", "empty"),
            ("\u{0}\u{1}garbage", "TOML"),
            ("version = 2", "version"),
            ("[set]\nx = 1", "version"),
            (
                "version = 1\n[[lane]]\nid = \"a\"\npoints = []",
                "no points",
            ),
            (
                "version = 1\n[[lane]]\nid = \"a\"\npoints = [[1, 0], [0, 1]]",
                "decrease",
            ),
            (
                "version = 1\n[[lane]]\nid = \"a\"\npoints = [[-1, 0]]",
                "time",
            ),
            (
                "version = 1\n[[lane]]\nid = \"a\"\npoints = [[0, \"x\"]]",
                "step",
            ),
            ("version = 1\n[[grab]]\nslot = \"nose\"\non_s = 0", "slot"),
            (
                "version = 1\n[[grab]]\nslot = \"back\"\non_s = 1\noff_s = 0.5",
                "before",
            ),
            (
                "version = 1\n[[grab]]\nslot = \"back\"\non_s = 1\nvelocity = 3",
                "velocity",
            ),
            ("version = 1\nduration_s = -1", "duration"),
            ("version = 1\nbogus = 3", "TOML"),
            ("version = 1\n[set]\nx = [1, 2]", "expected"),
        ];
        for (text, needle) in cases {
            let err = Script::parse(text).unwrap_err().to_string();
            assert!(
                err.to_lowercase().contains(&needle.to_lowercase()),
                "{text:?} gave {err:?}, expected to mention {needle:?}"
            );
            assert!(!err.contains('\n'), "error must be one line: {err:?}");
        }
    }
}
