//! # Presets: paper, room and mix recalled by name
//!
//! A preset is a set of parameter values of one group:
//! - **paper**: `size`, `material`;
//! - **room**: `table`, `table_height_cm`, `wall`, `wall_dist_cm` and the listener
//!   (`listener_az_deg`, `listener_dist_m`);
//! - **mix**: `mix_crumple_db`, `mix_friction_db`, `mix_tear_db`, `gain_db`.
//!
//! Loading one changes only its group, so a paper, a room and a mix combine. It never carries
//! gestures or the seed (those are the performance). In the plugin a preset load is a parameter
//! change through the host's parameter API, one begin/set/end per parameter — the host records it
//! (and can undo it) like a knob turned, and the sheet is kept (a size change makes a new sheet,
//! as turning the size knob does). `papier-render --preset NAME|FILE` applies one at t = 0.
//!
//! A user preset is a TOML file in the user's preset folder (see [`user_preset_dir`]):
//!
//! ```toml
//! version = 1
//! name = "my desk"
//! kind = "room"            # paper | room | mix
//! [set]
//! table = true
//! wall_dist_cm = 25.0
//! ```

use std::path::{Path, PathBuf};

use serde::Deserialize;
use sim_core::script::ScriptValue;
use thiserror::Error;

use crate::engine::ParamValues;

/// The preset file format version this build reads and writes.
pub const PRESET_VERSION: u32 = 1;

/// A preset's group.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PresetKind {
    /// Size and material.
    Paper,
    /// Table, wall and listener.
    Room,
    /// Levels.
    Mix,
}

impl PresetKind {
    /// Every kind.
    pub const ALL: [PresetKind; 3] = [PresetKind::Paper, PresetKind::Room, PresetKind::Mix];

    /// Its id in files.
    pub const fn id(self) -> &'static str {
        match self {
            PresetKind::Paper => "paper",
            PresetKind::Room => "room",
            PresetKind::Mix => "mix",
        }
    }

    /// The parameter ids of the group.
    pub const fn param_ids(self) -> &'static [&'static str] {
        match self {
            PresetKind::Paper => &["size", "material"],
            PresetKind::Room => &[
                "table",
                "table_height_cm",
                "wall",
                "wall_dist_cm",
                "listener_az_deg",
                "listener_dist_m",
            ],
            PresetKind::Mix => &[
                "mix_crumple_db",
                "mix_friction_db",
                "mix_tear_db",
                "gain_db",
            ],
        }
    }

    fn from_id(id: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.id() == id)
    }
}

/// Why a preset could not be read, found or saved (one line).
#[derive(Debug, Error, PartialEq)]
#[error("{0}")]
pub struct PresetError(pub String);

/// A preset.
#[derive(Clone, Debug, PartialEq)]
pub struct Preset {
    /// Name (unique within its kind in a list).
    pub name: String,
    /// Group.
    pub kind: PresetKind,
    /// Values, checked, in file order.
    pub values: Vec<(String, ScriptValue)>,
    /// "factory" or the file path.
    pub source: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPreset {
    version: u32,
    name: String,
    kind: String,
    set: toml::Table,
}

/// The factory presets: (name, kind, `id=value` settings).
const FACTORY: [(&str, PresetKind, &[&str]); 13] = [
    (
        "A4 printer paper",
        PresetKind::Paper,
        &["size=a4", "material=printer"],
    ),
    (
        "A5 printer paper",
        PresetKind::Paper,
        &["size=a5", "material=printer"],
    ),
    (
        "receipt (A6)",
        PresetKind::Paper,
        &["size=a6", "material=printer"],
    ),
    (
        "tracing paper",
        PresetKind::Paper,
        &["size=a4", "material=tracing"],
    ),
    (
        "bank note",
        PresetKind::Paper,
        &["size=sq10", "material=banknote"],
    ),
    (
        "desk",
        PresetKind::Room,
        &[
            "table=on",
            "table_height_cm=75",
            "wall=off",
            "listener_az_deg=0",
            "listener_dist_m=1",
        ],
    ),
    (
        "desk against a wall",
        PresetKind::Room,
        &[
            "table=on",
            "table_height_cm=75",
            "wall=on",
            "wall_dist_cm=25",
            "listener_az_deg=0",
            "listener_dist_m=1",
        ],
    ),
    (
        "held in the air, close mic",
        PresetKind::Room,
        &[
            "table=off",
            "wall=off",
            "listener_az_deg=0",
            "listener_dist_m=0.3",
        ],
    ),
    (
        "across the room",
        PresetKind::Room,
        &[
            "table=on",
            "wall=on",
            "wall_dist_cm=60",
            "listener_az_deg=30",
            "listener_dist_m=3",
        ],
    ),
    (
        "balanced",
        PresetKind::Mix,
        &[
            "mix_crumple_db=0",
            "mix_friction_db=-12",
            "mix_tear_db=0",
            "gain_db=-6",
        ],
    ),
    (
        "crumple only",
        PresetKind::Mix,
        &[
            "mix_crumple_db=0",
            "mix_friction_db=-60",
            "mix_tear_db=-60",
            "gain_db=-6",
        ],
    ),
    (
        "friction forward",
        PresetKind::Mix,
        &[
            "mix_crumple_db=-9",
            "mix_friction_db=0",
            "mix_tear_db=-6",
            "gain_db=-6",
        ],
    ),
    (
        "tear forward",
        PresetKind::Mix,
        &[
            "mix_crumple_db=-9",
            "mix_friction_db=-18",
            "mix_tear_db=3",
            "gain_db=-6",
        ],
    ),
];

fn value_from_arg(v: &str) -> ScriptValue {
    match v.parse::<f64>() {
        Ok(x) => ScriptValue::Number(x),
        Err(_) => ScriptValue::Text(v.to_string()),
    }
}

impl Preset {
    /// The factory presets.
    pub fn factory() -> Vec<Preset> {
        FACTORY
            .iter()
            .map(|(name, kind, sets)| {
                let values = sets
                    .iter()
                    .map(|s| {
                        let (id, v) = s.split_once('=').expect("factory presets are id=value");
                        (id.to_string(), value_from_arg(v))
                    })
                    .collect();
                Preset {
                    name: (*name).to_string(),
                    kind: *kind,
                    values,
                    source: "factory".into(),
                }
            })
            .collect()
    }

    /// Parses a preset file's text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Self, PresetError> {
        let err = |m: String| PresetError(format!("{file}: {m}"));
        let raw: RawPreset = toml::from_str(text).map_err(|e| {
            let msg = e.message().replace('\n', " ");
            match e.span() {
                Some(span) => {
                    let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
                    err(format!("line {line}: {msg}"))
                }
                None => err(msg),
            }
        })?;
        if raw.version != PRESET_VERSION {
            return Err(err(format!(
                "version {} is not {PRESET_VERSION}",
                raw.version
            )));
        }
        let kind = PresetKind::from_id(&raw.kind)
            .ok_or_else(|| err(format!("kind \"{}\" is not paper, room or mix", raw.kind)))?;
        if raw.name.trim().is_empty() {
            return Err(err("the name is empty".into()));
        }
        let mut values = Vec::with_capacity(raw.set.len());
        for (id, v) in &raw.set {
            if !kind.param_ids().contains(&id.as_str()) {
                return Err(err(format!(
                    "`{id}` is not a {} setting ({})",
                    kind.id(),
                    kind.param_ids().join(", ")
                )));
            }
            let v = match v {
                toml::Value::Boolean(b) => ScriptValue::Bool(*b),
                toml::Value::Integer(i) => ScriptValue::Number(*i as f64),
                toml::Value::Float(f) => ScriptValue::Number(*f),
                toml::Value::String(s) => ScriptValue::Text(s.clone()),
                other => {
                    return Err(err(format!(
                        "`{id}`: a {} is not a value",
                        other.type_str()
                    )));
                }
            };
            values.push((id.clone(), v));
        }
        let preset = Preset {
            name: raw.name.trim().to_string(),
            kind,
            values,
            source: file.to_string(),
        };
        preset
            .apply_to(&mut ParamValues::default())
            .map_err(|e| err(e.0))?;
        Ok(preset)
    }

    /// Sets the preset's values on `p` (all or nothing).
    pub fn apply_to(&self, p: &mut ParamValues) -> Result<(), PresetError> {
        let mut q = *p;
        for (id, v) in &self.values {
            q.set(id, v)
                .map_err(|e| PresetError(format!("preset \"{}\": {e}", self.name)))?;
        }
        *p = q;
        Ok(())
    }

    /// A preset of `kind` holding the current values of its group.
    pub fn capture(name: &str, kind: PresetKind, p: &ParamValues) -> Self {
        let values = kind
            .param_ids()
            .iter()
            .map(|id| {
                let v = match *id {
                    "size" => ScriptValue::Text(p.size.id().to_string()),
                    "material" => ScriptValue::Text(p.material.id().to_string()),
                    "table" => ScriptValue::Bool(p.room.table),
                    "wall" => ScriptValue::Bool(p.room.wall),
                    "table_height_cm" => ScriptValue::Number(f64::from(p.room.table_height_cm)),
                    "wall_dist_cm" => ScriptValue::Number(f64::from(p.room.wall_dist_cm)),
                    "listener_az_deg" => ScriptValue::Number(f64::from(p.listener_az_deg)),
                    "listener_dist_m" => ScriptValue::Number(f64::from(p.listener_dist_m)),
                    "mix_crumple_db" => ScriptValue::Number(f64::from(p.mix_crumple_db)),
                    "mix_friction_db" => ScriptValue::Number(f64::from(p.mix_friction_db)),
                    "mix_tear_db" => ScriptValue::Number(f64::from(p.mix_tear_db)),
                    _ => ScriptValue::Number(f64::from(p.gain_db)),
                };
                ((*id).to_string(), v)
            })
            .collect();
        Preset {
            name: name.trim().to_string(),
            kind,
            values,
            source: String::new(),
        }
    }

    /// The preset as a file's text.
    pub fn to_toml(&self) -> String {
        let mut set = toml::Table::new();
        for (id, v) in &self.values {
            let v = match v {
                ScriptValue::Bool(b) => toml::Value::Boolean(*b),
                ScriptValue::Number(x) => toml::Value::Float(*x),
                ScriptValue::Text(s) => toml::Value::String(s.clone()),
            };
            set.insert(id.clone(), v);
        }
        let mut doc = toml::Table::new();
        doc.insert(
            "version".into(),
            toml::Value::Integer(i64::from(PRESET_VERSION)),
        );
        doc.insert("name".into(), toml::Value::String(self.name.clone()));
        doc.insert("kind".into(), toml::Value::String(self.kind.id().into()));
        doc.insert("set".into(), toml::Value::Table(set));
        toml::to_string(&doc).unwrap_or_default()
    }

    /// Saves the preset as `<dir>/<name>.toml` (the folder is created); returns the path.
    pub fn save_in(&self, dir: &Path) -> Result<PathBuf, PresetError> {
        let stem: String = self
            .name
            .chars()
            .map(|c| {
                if c.is_alphanumeric() || c == '-' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        if stem.trim_matches('_').is_empty() {
            return Err(PresetError("give the preset a name".into()));
        }
        let path = dir.join(format!("{}_{stem}.toml", self.kind.id()));
        std::fs::create_dir_all(dir)
            .and_then(|_| std::fs::write(&path, self.to_toml()))
            .map_err(|e| PresetError(format!("cannot save {}: {e}", path.display())))?;
        Ok(path)
    }
}

/// The user's preset folder: `$PAPIER_PRESET_DIR`, else `presets` next to the phrase folder's
/// parent (`~/.config/papier/presets` on Linux).
pub fn user_preset_dir() -> Option<PathBuf> {
    if let Some(d) = std::env::var_os("PAPIER_PRESET_DIR").filter(|v| !v.is_empty()) {
        return Some(PathBuf::from(d));
    }
    crate::phrase::shelf::user_phrase_dir().and_then(|p| p.parent().map(|d| d.join("presets")))
}

/// The presets of a folder (`*.toml`, sorted) and the files refused (one line each). A missing
/// folder is empty.
pub fn load_folder(dir: &Path) -> (Vec<Preset>, Vec<String>) {
    let mut presets = Vec::new();
    let mut errors = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return (presets, errors);
    };
    let files = crate::phrase::bank::toml_files(entries);
    for path in files {
        let shown = path.display().to_string();
        match std::fs::read_to_string(&path) {
            Ok(text) => match Preset::parse(&text, &shown) {
                Ok(p) => presets.push(p),
                Err(e) => errors.push(e.0),
            },
            Err(e) => errors.push(format!("{shown}: {e}")),
        }
    }
    (presets, errors)
}

/// Finds a preset for `papier-render --preset`: a file path, else a factory preset's name
/// (case-insensitive), else a user preset's name.
pub fn find(name_or_path: &str) -> Result<Preset, PresetError> {
    let path = Path::new(name_or_path);
    if path.extension().is_some_and(|x| x == "toml") {
        let text = std::fs::read_to_string(path)
            .map_err(|e| PresetError(format!("--preset {name_or_path}: {e}")))?;
        return Preset::parse(&text, name_or_path);
    }
    let wanted = name_or_path.trim().to_lowercase();
    let user = user_preset_dir()
        .map(|d| load_folder(&d).0)
        .unwrap_or_default();
    Preset::factory()
        .into_iter()
        .chain(user)
        .find(|p| p.name.to_lowercase() == wanted)
        .ok_or_else(|| {
            let names: Vec<String> = Preset::factory().into_iter().map(|p| p.name).collect();
            PresetError(format!(
                "--preset {name_or_path}: no such preset (factory: {}; or a .toml file)",
                names.join(", ")
            ))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factory_presets_apply_and_touch_only_their_group() {
        for p in Preset::factory() {
            let mut v = ParamValues::default();
            p.apply_to(&mut v).unwrap_or_else(|e| panic!("{e}"));
            for (id, _) in &p.values {
                assert!(
                    p.kind.param_ids().contains(&id.as_str()),
                    "{}: {id}",
                    p.name
                );
            }
            assert_eq!(v.gestures, ParamValues::default().gestures);
            assert_eq!(v.seed, ParamValues::default().seed);
        }
        let mut v = ParamValues::default();
        find("Receipt (A6)").unwrap().apply_to(&mut v).unwrap();
        assert_eq!(v.size, sim_core::SheetSize::A6);
    }

    #[test]
    fn presets_round_trip_through_files() {
        let dir = std::env::temp_dir().join(format!("papier-presets-{}", std::process::id()));
        let mut v = ParamValues::default();
        v.room.wall = true;
        v.room.wall_dist_cm = 21.5;
        v.listener_az_deg = -40.0;
        v.mix_tear_db = 4.5;
        v.size = sim_core::SheetSize::Sq10;
        for kind in PresetKind::ALL {
            let p = Preset::capture("my setting", kind, &v);
            let path = p.save_in(&dir).unwrap();
            let back = Preset::parse(&std::fs::read_to_string(&path).unwrap(), "f").unwrap();
            let mut w = ParamValues::default();
            back.apply_to(&mut w).unwrap();
            let mut expected = ParamValues::default();
            p.apply_to(&mut expected).unwrap();
            assert_eq!(w, expected, "{kind:?}");
        }
        let (all, errors) = load_folder(&dir);
        assert_eq!((all.len(), errors.len()), (3, 0));
        std::fs::write(
            dir.join("bad.toml"),
            "version = 1\nname = \"x\"\nkind = \"mix\"\n[set]\nsize = \"a4\"\n",
        )
        .unwrap();
        let (_, errors) = load_folder(&dir);
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(errors.len(), 1);
        assert!(
            errors[0].contains("bad.toml") && errors[0].contains("`size`"),
            "{}",
            errors[0]
        );
    }

    #[test]
    fn damaged_presets_are_one_line_errors() {
        for (text, needle) in [
            (
                "version = 1\nname = \"x\"\nkind = \"mix\"\n[set]\ngain_db = 99\n",
                "gain_db",
            ),
            (
                "version = 2\nname = \"x\"\nkind = \"mix\"\n[set]\n",
                "version",
            ),
            (
                "version = 1\nname = \"x\"\nkind = \"sound\"\n[set]\n",
                "kind",
            ),
            ("version = 1\nname = \"x\"\nkind = \"room\"\n[set\n", "line"),
            (
                "version = 1\nname = \"x\"\nkind = \"room\"\n[set]\ncrumple = 1.0\n",
                "crumple",
            ),
        ] {
            let e = Preset::parse(text, "p.toml").unwrap_err().0;
            assert!(
                e.starts_with("p.toml: ") && e.contains(needle) && !e.contains('\n'),
                "{e}"
            );
        }
        assert!(find("no such thing").unwrap_err().0.contains("factory"));
    }
}
