//! # Parameter values as the engine sees them
//!
//! A plain `Copy` snapshot of every parameter the engine reads, independent of nice-plug: the
//! plugin fills it from its parameters each block ([`crate::params::PapierParams::values`]), the
//! offline renderer from `--set`, scripts and defaults ([`ParamValues::set`]). The table of ids
//! here must match `params.rs`; a unit test there checks both directions.

use sim_core::script::ScriptValue;
use sim_core::{GestureParam, Material, RoomConfig, SheetSize, SimConfig};
use thiserror::Error;

use sim_core::room::{TABLE_HEIGHT_RANGE_CM, WALL_DIST_RANGE_CM};

/// Range of the mix and output gains, dB. The bottom of the range is "off" (silence).
pub const GAIN_RANGE_DB: (f32, f32) = (-60.0, 12.0);

/// Default friction level, dB: friction is linear in slip speed (T 1770), so a fast crumple
/// rubs the table at several times the recording speed; −12 dB keeps the default mix clear of
/// the output's soft clipper with crumple units at 0 dB.
pub const DEFAULT_FRICTION_DB: f32 = -12.0;

/// Default output gain, dB: 6 dB of headroom for the bursts of a fast crumple's release.
pub const DEFAULT_OUTPUT_DB: f32 = -6.0;

/// Range of the listener distance, metres.
pub const LISTENER_DIST_RANGE_M: (f32, f32) = (0.2, 5.0);

/// Largest seed.
pub const MAX_SEED: i32 = 65_535;

/// The sim config a fresh sheet gets from the parameters.
pub fn sim_config(p: &ParamValues) -> SimConfig {
    SimConfig {
        size: p.size,
        material: p.material,
        seed: p.seed,
        room: p.room,
        ..SimConfig::default()
    }
}

/// Why a parameter could not be set.
#[derive(Debug, Error, PartialEq)]
pub enum ParamError {
    /// No parameter has this id.
    #[error("unknown parameter id `{0}` (see the README's parameter table)")]
    UnknownId(String),
    /// The value has the wrong kind or is out of range.
    #[error("bad value {value} for `{id}`: expected {expected}")]
    BadValue {
        /// Parameter id.
        id: String,
        /// The value given.
        value: String,
        /// What is expected.
        expected: String,
    },
}

/// Every engine-relevant parameter value, in plain units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamValues {
    /// Gesture values, indexed by [`GestureParam::index`].
    pub gestures: [f32; GestureParam::COUNT],
    /// Sheet size.
    pub size: SheetSize,
    /// Paper grade.
    pub material: Material,
    /// Seed.
    pub seed: u64,
    /// Table and wall.
    pub room: RoomConfig,
    /// Listener azimuth, degrees.
    pub listener_az_deg: f32,
    /// Listener distance, metres.
    pub listener_dist_m: f32,
    /// Crumple level, dB.
    pub mix_crumple_db: f32,
    /// Friction level, dB.
    pub mix_friction_db: f32,
    /// Tear level, dB.
    pub mix_tear_db: f32,
    /// Output gain, dB.
    pub gain_db: f32,
}

impl Default for ParamValues {
    fn default() -> Self {
        let mut gestures = [0.0; GestureParam::COUNT];
        for g in GestureParam::ALL {
            gestures[g.index()] = g.default_value();
        }
        Self {
            gestures,
            size: SheetSize::A4,
            material: Material::Printer,
            seed: 1,
            room: RoomConfig::default(),
            listener_az_deg: 0.0,
            listener_dist_m: 1.0,
            mix_crumple_db: 0.0,
            mix_friction_db: DEFAULT_FRICTION_DB,
            mix_tear_db: 0.0,
            gain_db: DEFAULT_OUTPUT_DB,
        }
    }
}

/// Every parameter id, in the plugin's order.
pub const PARAM_IDS: [&str; 24] = [
    "crumple",
    "slide",
    "lift",
    "twist",
    "shake_depth",
    "shake_rate_hz",
    "tear_amount",
    "tear_steer",
    "tear_pos",
    "pull_sep",
    "pull_asym",
    "size",
    "material",
    "seed",
    "table",
    "table_height_cm",
    "wall",
    "wall_dist_cm",
    "listener_az_deg",
    "listener_dist_m",
    "mix_crumple_db",
    "mix_friction_db",
    "mix_tear_db",
    "gain_db",
];

fn number(id: &str, v: &ScriptValue, (lo, hi): (f32, f32), unit: &str) -> Result<f32, ParamError> {
    let bad = || ParamError::BadValue {
        id: id.to_string(),
        value: v.to_string(),
        expected: format!("a number from {lo} to {hi}{unit}"),
    };
    let x = match v {
        ScriptValue::Number(x) => *x,
        ScriptValue::Text(s) => s.trim().parse::<f64>().map_err(|_| bad())?,
        ScriptValue::Bool(_) => return Err(bad()),
    };
    if !x.is_finite() || x < f64::from(lo) - 1e-9 || x > f64::from(hi) + 1e-9 {
        return Err(bad());
    }
    Ok((x as f32).clamp(lo, hi))
}

fn boolean(id: &str, v: &ScriptValue) -> Result<bool, ParamError> {
    match v {
        ScriptValue::Bool(b) => Ok(*b),
        ScriptValue::Number(x) if *x == 0.0 || *x == 1.0 => Ok(*x == 1.0),
        ScriptValue::Text(s) => match s.trim().to_ascii_lowercase().as_str() {
            "true" | "on" | "1" | "yes" => Ok(true),
            "false" | "off" | "0" | "no" => Ok(false),
            _ => Err(ParamError::BadValue {
                id: id.into(),
                value: v.to_string(),
                expected: "on/off (true, false, 1, 0)".into(),
            }),
        },
        _ => Err(ParamError::BadValue {
            id: id.into(),
            value: v.to_string(),
            expected: "on/off (true, false, 1, 0)".into(),
        }),
    }
}

impl ParamValues {
    /// Sets one parameter by id from a script / command-line value, with full validation.
    pub fn set(&mut self, id: &str, v: &ScriptValue) -> Result<(), ParamError> {
        if let Some(g) = GestureParam::from_id(id) {
            let unit = if g == GestureParam::ShakeRateHz {
                " Hz"
            } else {
                ""
            };
            self.gestures[g.index()] = number(id, v, g.range(), unit)?;
            return Ok(());
        }
        match id {
            "size" => {
                self.size = match v {
                    ScriptValue::Text(s) => SheetSize::from_id(s.trim()),
                    _ => None,
                }
                .ok_or_else(|| ParamError::BadValue {
                    id: id.into(),
                    value: v.to_string(),
                    expected: "one of a4, a5, a6, sq10".into(),
                })?;
            }
            "material" => {
                self.material = match v {
                    ScriptValue::Text(s) => Material::from_id(s.trim()),
                    _ => None,
                }
                .ok_or_else(|| ParamError::BadValue {
                    id: id.into(),
                    value: v.to_string(),
                    expected: "one of printer, tracing, banknote".into(),
                })?;
            }
            "seed" => {
                let x = number(id, v, (0.0, MAX_SEED as f32), "")?;
                if x.fract() != 0.0 {
                    return Err(ParamError::BadValue {
                        id: id.into(),
                        value: v.to_string(),
                        expected: format!("a whole number from 0 to {MAX_SEED}"),
                    });
                }
                self.seed = x as u64;
            }
            "table" => self.room.table = boolean(id, v)?,
            "table_height_cm" => {
                self.room.table_height_cm = number(id, v, TABLE_HEIGHT_RANGE_CM, " cm")?
            }
            "wall" => self.room.wall = boolean(id, v)?,
            "wall_dist_cm" => self.room.wall_dist_cm = number(id, v, WALL_DIST_RANGE_CM, " cm")?,
            "listener_az_deg" => self.listener_az_deg = number(id, v, (-180.0, 180.0), "°")?,
            "listener_dist_m" => self.listener_dist_m = number(id, v, LISTENER_DIST_RANGE_M, " m")?,
            "mix_crumple_db" => self.mix_crumple_db = number(id, v, GAIN_RANGE_DB, " dB")?,
            "mix_friction_db" => self.mix_friction_db = number(id, v, GAIN_RANGE_DB, " dB")?,
            "mix_tear_db" => self.mix_tear_db = number(id, v, GAIN_RANGE_DB, " dB")?,
            "gain_db" => self.gain_db = number(id, v, GAIN_RANGE_DB, " dB")?,
            _ => return Err(ParamError::UnknownId(id.to_string())),
        }
        Ok(())
    }

    /// Parses a command-line `ID=VALUE` (text values; numbers, booleans and ids are accepted).
    pub fn set_from_arg(&mut self, arg: &str) -> Result<(), ParamError> {
        let Some((id, value)) = arg.split_once('=') else {
            return Err(ParamError::BadValue {
                id: arg.to_string(),
                value: String::new(),
                expected: "ID=VALUE".into(),
            });
        };
        let id = id.trim();
        let value = value.trim();
        let v = if let Ok(x) = value.parse::<f64>() {
            ScriptValue::Number(x)
        } else {
            ScriptValue::Text(value.to_string())
        };
        self.set(id, &v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_id_is_settable() {
        let mut p = ParamValues::default();
        for id in &PARAM_IDS {
            let v = match *id {
                "size" => ScriptValue::Text("a6".into()),
                "material" => ScriptValue::Text("tracing".into()),
                "table" | "wall" => ScriptValue::Bool(true),
                "seed" => ScriptValue::Number(7.0),
                "table_height_cm" => ScriptValue::Number(80.0),
                "wall_dist_cm" => ScriptValue::Number(20.0),
                "listener_az_deg" => ScriptValue::Number(45.0),
                "listener_dist_m" => ScriptValue::Number(2.0),
                "shake_rate_hz" => ScriptValue::Number(4.0),
                id if id.ends_with("_db") => ScriptValue::Number(-6.0),
                _ => ScriptValue::Number(0.5),
            };
            p.set(id, &v).unwrap_or_else(|e| panic!("{id}: {e}"));
        }
        assert_eq!(p.size, SheetSize::A6);
        assert_eq!(p.material, Material::Tracing);
        assert!(p.room.wall);
    }

    #[test]
    fn bad_values_are_clear_errors() {
        let mut p = ParamValues::default();
        let before = p;
        assert!(matches!(
            p.set_from_arg("nonsense=1"),
            Err(ParamError::UnknownId(_))
        ));
        for arg in [
            "size=a3",
            "slide=2",
            "slide=nan",
            "twist=-1.5",
            "table=maybe",
            "seed=1.5",
            "seed=-1",
            "gain_db=100",
            "material=3",
            "crumple",
        ] {
            let e = p.set_from_arg(arg).unwrap_err().to_string();
            assert!(!e.contains('\n'), "{arg}: {e}");
        }
        assert_eq!(p, before, "failed sets leave values unchanged");
        p.set_from_arg("size=A5").unwrap();
        p.set_from_arg("table=off").unwrap();
        assert_eq!(p.size, SheetSize::A5);
        assert!(!p.room.table);
    }
}
