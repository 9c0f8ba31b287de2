//! A phrase file read and prepared: a script ([`sim_core::script`]) plus a `[phrase]` table,
//! turned into numbers the audio thread can play without allocating.
//!
//! ```toml
//! version = 1
//! [phrase]
//! name = "page turn"     # shown on the editor's pad; default: the file name
//! note = 60              # C4 = 60 … 127 (below 60 is the gesture map's)
//! start = "current"      # "current": play on the sheet as it is; "fresh": a new flat sheet
//! note_off = "finish"    # "finish": play to the end; "release": hold until the note-off
//! [set]                  # size, material, seed and gesture values at the phrase's start
//! [[lane]] / [[grab]] / [[reset]]   # as in a script; lanes drive gestures only
//! ```
//!
//! A phrase shapes the sheet, not the room, the listener or the mix: those belong to the
//! instance, so a phrase that sets them is refused (the seed scenes' room and listener settings
//! are dropped when they become factory phrases). `seed` in `[set]` is the phrase's base seed,
//! varied on every hit ([`super::player`]).

use sim_core::script::{Interp, Script, ScriptValue};
use sim_core::{GestureParam, GrabSlot, Material, SheetSize};
use thiserror::Error;

/// Lowest note a phrase may use (C4): the gesture map uses the notes below.
pub const FIRST_PHRASE_NOTE: u8 = 60;

/// Why a phrase file was refused (one line, naming the file).
#[derive(Debug, Error, PartialEq)]
#[error("{file}: {message}")]
pub struct PhraseError {
    /// File name (or factory phrase name).
    pub file: String,
    /// What is wrong, with its line where the TOML parser knows it.
    pub message: String,
}

/// Where a phrase starts from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhraseStart {
    /// The sheet as it is.
    Current,
    /// A new flat sheet (the hit's seed, the phrase's size and material).
    Fresh,
}

/// What a note-off does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoteOffRule {
    /// Nothing: the phrase plays to its end, where its hands let go.
    Finish,
    /// The phrase's hands hold until the note-off, which lets them go and stops the phrase.
    Release,
}

/// A gesture lane, in plain gesture units.
#[derive(Clone, Debug, PartialEq)]
pub struct PhraseLane {
    /// The gesture it drives.
    pub gesture: GestureParam,
    /// Interpolation.
    pub interp: Interp,
    /// Breakpoints (phrase time, s; value), times non-decreasing, at least one.
    pub points: Vec<(f64, f32)>,
}

impl PhraseLane {
    /// Value at phrase time `t_s` (the first value before the first point, the last after the
    /// last). Allocation-free.
    pub fn value_at(&self, t_s: f64) -> f32 {
        let pts = &self.points;
        let idx = pts.partition_point(|(t, _)| *t <= t_s);
        if idx == 0 {
            return pts[0].1;
        }
        if idx >= pts.len() {
            return pts[pts.len() - 1].1;
        }
        let (t0, a) = pts[idx - 1];
        let (t1, b) = pts[idx];
        if self.interp == Interp::Step || t1 <= t0 {
            return a;
        }
        let mut u = (t_s - t0) / (t1 - t0);
        if self.interp == Interp::Smooth {
            u = u * u * (3.0 - 2.0 * u);
        }
        a + (b - a) * u as f32
    }
}

/// A discrete step of a phrase.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhraseEvent {
    /// A new flat sheet.
    Reset,
    /// A hand takes a slot (grip speed 0–1).
    Grab(GrabSlot, f32),
    /// The hand on a slot lets go.
    Release(GrabSlot),
    /// A new paper grade (a `material` lane).
    Material(Material),
    /// A new flat sheet of this size (a `size` lane).
    Size(SheetSize),
}

/// A phrase ready to play.
#[derive(Clone, Debug, PartialEq)]
pub struct Phrase {
    /// Name shown on the pad.
    pub name: String,
    /// Its note.
    pub note: u8,
    /// Where it starts from.
    pub start: PhraseStart,
    /// What a note-off does.
    pub note_off: NoteOffRule,
    /// Length, seconds (at velocity 100).
    pub duration_s: f64,
    /// Sheet size for a fresh start (`None`: the instance's).
    pub size: Option<SheetSize>,
    /// Paper grade, applied at the start (`None`: unchanged).
    pub material: Option<Material>,
    /// Base seed, varied per hit.
    pub seed: u64,
    /// Gesture values at the start.
    pub initial: Vec<(GestureParam, f32)>,
    /// Gesture lanes.
    pub lanes: Vec<PhraseLane>,
    /// Discrete steps, in time order (sheet changes, resets, releases, grabs at equal times).
    pub events: Vec<(f64, PhraseEvent)>,
    /// Where it came from ("factory" or the file path).
    pub source: String,
}

fn text<'a>(t: &'a toml::Table, key: &str) -> Result<Option<&'a str>, String> {
    match t.get(key) {
        None => Ok(None),
        Some(toml::Value::String(s)) => Ok(Some(s.as_str())),
        Some(v) => Err(format!(
            "[phrase] {key}: expected text, found {}",
            v.type_str()
        )),
    }
}

/// Is `id` the instance's to set (the room, the listener and the mix: the preset groups of
/// [`crate::preset`] a phrase does not touch)?
fn is_instance_id(id: &str) -> bool {
    use crate::preset::PresetKind;
    PresetKind::Room.param_ids().contains(&id) || PresetKind::Mix.param_ids().contains(&id)
}

fn number(id: &str, v: &ScriptValue) -> Result<f64, String> {
    match v {
        ScriptValue::Number(x) if x.is_finite() => Ok(*x),
        other => Err(format!("`{id}`: expected a number, found {other}")),
    }
}

impl Phrase {
    /// Parses a phrase file's text. `file` names it in errors; `default_name` is used when the
    /// `[phrase]` table has no name.
    pub fn parse(text: &str, file: &str, default_name: &str) -> Result<Self, PhraseError> {
        let err = |message: String| PhraseError {
            file: file.to_string(),
            message,
        };
        let script = Script::parse(text).map_err(|e| err(e.to_string().replace('\n', " ")))?;
        let header = script
            .phrase
            .clone()
            .ok_or_else(|| err("no [phrase] table (it names the note: note = 60)".into()))?;
        Self::from_script(&script, &header, file, default_name, false).map_err(err)
    }

    /// Builds a phrase from a parsed script and its `[phrase]` table. With `drop_instance_ids`
    /// the room, listener and mix settings and lanes are dropped instead of refused (the seed
    /// scenes as factory phrases).
    pub fn from_script(
        script: &Script,
        header: &toml::Table,
        source: &str,
        default_name: &str,
        drop_instance_ids: bool,
    ) -> Result<Self, String> {
        for key in header.keys() {
            if !["name", "note", "start", "note_off"].contains(&key.as_str()) {
                return Err(format!(
                    "[phrase] unknown key `{key}` (name, note, start, note_off)"
                ));
            }
        }
        let note = match header.get("note") {
            Some(toml::Value::Integer(n)) if (i64::from(FIRST_PHRASE_NOTE)..=127).contains(n) => {
                *n as u8
            }
            Some(v) => {
                return Err(format!(
                    "[phrase] note: expected a note number from {FIRST_PHRASE_NOTE} (C4) to \
                     127, found {v}"
                ));
            }
            None => return Err("[phrase] note is missing".into()),
        };
        let name = text(header, "name")?.unwrap_or(default_name).to_string();
        let start = match text(header, "start")? {
            None | Some("current") => PhraseStart::Current,
            Some("fresh") => PhraseStart::Fresh,
            Some(s) => return Err(format!("[phrase] start: \"{s}\" is not current or fresh")),
        };
        let note_off = match text(header, "note_off")? {
            None | Some("finish") => NoteOffRule::Finish,
            Some("release") => NoteOffRule::Release,
            Some(s) => {
                return Err(format!(
                    "[phrase] note_off: \"{s}\" is not finish or release"
                ));
            }
        };
        let mut phrase = Phrase {
            name,
            note,
            start,
            note_off,
            duration_s: script.duration_s,
            size: None,
            material: None,
            seed: 1,
            initial: Vec::new(),
            lanes: Vec::new(),
            events: Vec::new(),
            source: source.to_string(),
        };
        for (id, v) in &script.set {
            if is_instance_id(id) {
                if drop_instance_ids {
                    continue;
                }
                return Err(format!(
                    "[set] `{id}` belongs to the instance (room, listener, mix), not to a phrase"
                ));
            }
            match id.as_str() {
                "size" => {
                    phrase.size = Some(
                        match v {
                            ScriptValue::Text(s) => SheetSize::from_id(s.trim()),
                            _ => None,
                        }
                        .ok_or_else(|| format!("[set] size: {v} is not a4, a5, a6 or sq10"))?,
                    );
                }
                "material" => {
                    phrase.material = Some(
                        match v {
                            ScriptValue::Text(s) => Material::from_id(s.trim()),
                            _ => None,
                        }
                        .ok_or_else(|| {
                            format!("[set] material: {v} is not printer, tracing or banknote")
                        })?,
                    );
                }
                "seed" => {
                    let x = number(id, v).map_err(|e| format!("[set] {e}"))?;
                    if x < 0.0 || x.fract() != 0.0 {
                        return Err(format!("[set] seed: {x} is not a whole number ≥ 0"));
                    }
                    phrase.seed = x as u64;
                }
                _ => {
                    let g = GestureParam::from_id(id)
                        .ok_or_else(|| format!("[set] unknown parameter id `{id}`"))?;
                    let x = number(id, v).map_err(|e| format!("[set] {e}"))?;
                    phrase.initial.push((g, gesture_value(g, x, "[set]")?));
                }
            }
        }
        // Sheet changes first at equal times, then the script's resets, releases and grabs.
        let mut steps = Vec::new();
        for (i, lane) in script.lanes.iter().enumerate() {
            let what = format!("lane {} ({})", i + 1, lane.id);
            if drop_instance_ids && is_instance_id(&lane.id) {
                continue;
            }
            if lane.id == "material" || lane.id == "size" {
                for (t, v) in &lane.points {
                    let e = match (lane.id.as_str(), v) {
                        ("material", ScriptValue::Text(m)) => {
                            Material::from_id(m.trim()).map(PhraseEvent::Material)
                        }
                        ("size", ScriptValue::Text(z)) => {
                            SheetSize::from_id(z.trim()).map(PhraseEvent::Size)
                        }
                        _ => None,
                    }
                    .ok_or_else(|| format!("{what}: {v} is not a {}", lane.id))?;
                    steps.push((*t, e));
                }
                continue;
            }
            let g = GestureParam::from_id(&lane.id).ok_or_else(|| {
                format!("{what}: a phrase's lanes drive gestures, size and material only")
            })?;
            let mut points = Vec::with_capacity(lane.points.len());
            for (t, v) in &lane.points {
                let x = number(&lane.id, v).map_err(|e| format!("{what}: {e}"))?;
                points.push((*t, gesture_value(g, x, &what)?));
            }
            phrase.lanes.push(PhraseLane {
                gesture: g,
                interp: lane.interp,
                points,
            });
        }
        for (t, d) in script.discrete_inputs() {
            use sim_core::script::DiscreteInput;
            let e = match d {
                DiscreteInput::Reset => PhraseEvent::Reset,
                DiscreteInput::Grab { slot, velocity } => PhraseEvent::Grab(slot, velocity),
                DiscreteInput::Release { slot } => PhraseEvent::Release(slot),
            };
            steps.push((t, e));
        }
        steps.sort_by(|a, b| a.0.total_cmp(&b.0));
        phrase.events = steps;
        Ok(phrase)
    }
}

/// A gesture value checked against its range.
fn gesture_value(g: GestureParam, x: f64, what: &str) -> Result<f32, String> {
    let (lo, hi) = g.range();
    if x < f64::from(lo) - 1e-9 || x > f64::from(hi) + 1e-9 {
        return Err(format!("{what}: {} = {x} is outside {lo}…{hi}", g.id()));
    }
    Ok((x as f32).clamp(lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    const OK: &str = r#"
version = 1
duration_s = 2.0
[phrase]
name = "test"
note = 64
start = "fresh"
note_off = "release"
[set]
size = "a6"
crumple = 0.1
[[lane]]
id = "crumple"
interp = "smooth"
points = [[0.0, 0.1], [1.0, 0.9]]
[[grab]]
slot = "back"
on_s = 0.5
off_s = 1.5
"#;

    #[test]
    fn a_phrase_file_is_prepared() {
        let p = Phrase::parse(OK, "t.toml", "t").unwrap();
        assert_eq!(
            (p.note, p.start, p.note_off),
            (64, PhraseStart::Fresh, NoteOffRule::Release)
        );
        assert_eq!(p.size, Some(SheetSize::A6));
        assert_eq!(p.initial, vec![(GestureParam::Crumple, 0.1)]);
        assert!((p.lanes[0].value_at(0.5) - 0.5).abs() < 1e-6);
        assert_eq!(p.lanes[0].value_at(-1.0), 0.1);
        assert_eq!(p.lanes[0].value_at(9.0), 0.9);
        assert_eq!(
            p.events,
            vec![
                (0.5, PhraseEvent::Grab(GrabSlot::Back, 0.8)),
                (1.5, PhraseEvent::Release(GrabSlot::Back))
            ]
        );
    }

    #[test]
    fn a_damaged_phrase_is_refused_in_one_line_naming_file_and_line() {
        let cases = [
            (OK.replace("note = 64", "note = 40"), "note"),
            (OK.replace("note = 64", "note = \"C4\""), "note"),
            (OK.replace("[phrase]", "[phrasse]"), "line"),
            (OK.replace("start = \"fresh\"", "start = \"new\""), "start"),
            (OK.replace("size = \"a6\"", "wall = true"), "wall"),
            (OK.replace("id = \"crumple\"", "id = \"gain_db\""), "gain_db"),
            (OK.replace("[0.0, 0.1]", "[0.0, 7.0]"), "outside"),
            (OK.replace("[phrase]\nname = \"test\"\nnote = 64\nstart = \"fresh\"\nnote_off = \"release\"\n", ""), "[phrase]"),
            ("version = 1\n[phrase]\nnote = 61\nvelocity = 3\n".into(), "velocity"),
            ("version = 1\n[phrase\nnote = 61\n".into(), "line 2"),
        ];
        for (text, needle) in cases {
            let e = Phrase::parse(&text, "bad.toml", "bad")
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("bad.toml: "), "{e}");
            assert!(e.contains(needle), "{needle}: {e}");
            assert!(!e.contains('\n'), "{e}");
        }
    }
}
