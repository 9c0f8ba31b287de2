//! # Papier's parameters
//!
//! Every parameter is automatable and has a short, stable id with its unit in the name (these
//! ids are a contract with saved projects, host automation, scripts and `papier-render --set`;
//! never rename one). They are grouped like the instrument's face:
//!
//! | group | ids |
//! |---|---|
//! | Gestures | `crumple`, `slide`, `lift`, `twist`, `shake_depth`, `shake_rate_hz`, `tear_amount`, `tear_steer`, `tear_pos`, `pull_sep`, `pull_asym` |
//! | Sheet | `size` (a4 · a5 · a6 · sq10), `material` (printer · tracing · banknote), `seed` |
//! | Room | `table`, `table_height_cm`, `wall`, `wall_dist_cm` |
//! | Listener | `listener_az_deg`, `listener_dist_m` |
//! | Mix | `mix_crumple_db`, `mix_friction_db`, `mix_tear_db` |
//! | Output | `gain_db` |
//!
//! Gesture ranges are linear so that a MIDI CC, a host's normalized value and a script's plain
//! value all land on the same number (see [`sim_core::GestureParam::range`]).
//!
//! Besides the parameters, the saved state carries the sheet itself ([`crate::state`]) under the
//! persisted key `sheet`, the user sound database folder ([`crate::db_loader`]) under
//! `db_path`, the editor window's size ([`crate::editor::window_size`]) under `editor_size`, and
//! a state format version under `state_version`.

use std::sync::Arc;
use std::sync::atomic::AtomicU32;

use nice_plug::prelude::*;
use sim_core::room::{TABLE_HEIGHT_RANGE_CM, WALL_DIST_RANGE_CM};
use sim_core::{GestureParam, Material, RoomConfig, SheetSize};

use crate::db_loader::DbLoader;
use crate::editor::window_size::EditorSize;
use crate::engine::ParamValues;
use crate::engine::param_values::{
    DEFAULT_FRICTION_DB, DEFAULT_OUTPUT_DB, GAIN_RANGE_DB, LISTENER_DIST_RANGE_M, MAX_SEED,
};
use crate::engine::sheet_store::SheetStore;

/// Version of the plugin state layout (parameters + persisted fields). Bumped on any change
/// that needs a migration in `Plugin::filter_state`.
pub const STATE_VERSION: u32 = 1;

/// Sheet size choice.
#[derive(Enum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum SizeChoice {
    /// A4.
    #[id = "a4"]
    #[name = "A4"]
    A4,
    /// A5.
    #[id = "a5"]
    #[name = "A5"]
    A5,
    /// A6.
    #[id = "a6"]
    #[name = "A6"]
    A6,
    /// 10 cm square.
    #[id = "sq10"]
    #[name = "10 cm square"]
    Sq10,
}

impl From<SizeChoice> for SheetSize {
    fn from(s: SizeChoice) -> Self {
        match s {
            SizeChoice::A4 => SheetSize::A4,
            SizeChoice::A5 => SheetSize::A5,
            SizeChoice::A6 => SheetSize::A6,
            SizeChoice::Sq10 => SheetSize::Sq10,
        }
    }
}

/// Paper grade choice.
#[derive(Enum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum MaterialChoice {
    /// Printer paper.
    #[id = "printer"]
    #[name = "Printer paper"]
    Printer,
    /// Tracing paper.
    #[id = "tracing"]
    #[name = "Tracing paper"]
    Tracing,
    /// Bank-note paper.
    #[id = "banknote"]
    #[name = "Bank note"]
    Banknote,
}

impl From<MaterialChoice> for Material {
    fn from(m: MaterialChoice) -> Self {
        match m {
            MaterialChoice::Printer => Material::Printer,
            MaterialChoice::Tracing => Material::Tracing,
            MaterialChoice::Banknote => Material::Banknote,
        }
    }
}

/// Gesture parameters.
#[derive(Params)]
pub struct GestureParams {
    /// Crumple 0–1.
    #[id = "crumple"]
    pub crumple: FloatParam,
    /// Slide 0–1.
    #[id = "slide"]
    pub slide: FloatParam,
    /// Lift 0–1.
    #[id = "lift"]
    pub lift: FloatParam,
    /// Twist −1–1.
    #[id = "twist"]
    pub twist: FloatParam,
    /// Shake depth 0–1.
    #[id = "shake_depth"]
    pub shake_depth: FloatParam,
    /// Shake rate, Hz.
    #[id = "shake_rate_hz"]
    pub shake_rate_hz: FloatParam,
    /// Tear amount 0–1.
    #[id = "tear_amount"]
    pub tear_amount: FloatParam,
    /// Tear steering −1–1.
    #[id = "tear_steer"]
    pub tear_steer: FloatParam,
    /// Tear position 0–1.
    #[id = "tear_pos"]
    pub tear_pos: FloatParam,
    /// Pull separation 0–1.
    #[id = "pull_sep"]
    pub pull_sep: FloatParam,
    /// Pull asymmetry −1–1.
    #[id = "pull_asym"]
    pub pull_asym: FloatParam,
}

fn gesture_param(g: GestureParam) -> FloatParam {
    let (min, max) = g.range();
    let p = FloatParam::new(g.name(), g.default_value(), FloatRange::Linear { min, max });
    match g {
        GestureParam::ShakeRateHz => p
            .with_unit(" Hz")
            .with_value_to_string(formatters::v2s_f32_rounded(2)),
        _ => p.with_value_to_string(formatters::v2s_f32_rounded(3)),
    }
}

impl Default for GestureParams {
    fn default() -> Self {
        Self {
            crumple: gesture_param(GestureParam::Crumple),
            slide: gesture_param(GestureParam::Slide),
            lift: gesture_param(GestureParam::Lift),
            twist: gesture_param(GestureParam::Twist),
            shake_depth: gesture_param(GestureParam::ShakeDepth),
            shake_rate_hz: gesture_param(GestureParam::ShakeRateHz),
            tear_amount: gesture_param(GestureParam::TearAmount),
            tear_steer: gesture_param(GestureParam::TearSteer),
            tear_pos: gesture_param(GestureParam::TearPosition),
            pull_sep: gesture_param(GestureParam::PullSeparation),
            pull_asym: gesture_param(GestureParam::PullAsymmetry),
        }
    }
}

impl GestureParams {
    /// The parameter of a gesture.
    pub fn get(&self, g: GestureParam) -> &FloatParam {
        match g {
            GestureParam::Crumple => &self.crumple,
            GestureParam::Slide => &self.slide,
            GestureParam::Lift => &self.lift,
            GestureParam::Twist => &self.twist,
            GestureParam::ShakeDepth => &self.shake_depth,
            GestureParam::ShakeRateHz => &self.shake_rate_hz,
            GestureParam::TearAmount => &self.tear_amount,
            GestureParam::TearSteer => &self.tear_steer,
            GestureParam::TearPosition => &self.tear_pos,
            GestureParam::PullSeparation => &self.pull_sep,
            GestureParam::PullAsymmetry => &self.pull_asym,
        }
    }
}

/// Sheet parameters.
#[derive(Params)]
pub struct SheetParams {
    /// Sheet size (changing it replaces the sheet by a fresh one).
    #[id = "size"]
    pub size: EnumParam<SizeChoice>,
    /// Paper grade.
    #[id = "material"]
    pub material: EnumParam<MaterialChoice>,
    /// Random seed of new sheets (used from the next reset).
    #[id = "seed"]
    pub seed: IntParam,
}

impl Default for SheetParams {
    fn default() -> Self {
        Self {
            size: EnumParam::new("Size", SizeChoice::A4),
            material: EnumParam::new("Material", MaterialChoice::Printer),
            seed: IntParam::new(
                "Seed",
                1,
                IntRange::Linear {
                    min: 0,
                    max: MAX_SEED,
                },
            ),
        }
    }
}

/// Room parameters.
#[derive(Params)]
pub struct RoomParams {
    /// Table on/off.
    #[id = "table"]
    pub table: BoolParam,
    /// Table top height, cm.
    #[id = "table_height_cm"]
    pub table_height_cm: FloatParam,
    /// Wall on/off.
    #[id = "wall"]
    pub wall: BoolParam,
    /// Wall distance from the sheet's home centre, cm.
    #[id = "wall_dist_cm"]
    pub wall_dist_cm: FloatParam,
}

impl Default for RoomParams {
    fn default() -> Self {
        let d = RoomConfig::default();
        Self {
            table: BoolParam::new("Table", d.table),
            table_height_cm: FloatParam::new(
                "Table Height",
                d.table_height_cm,
                FloatRange::Linear {
                    min: TABLE_HEIGHT_RANGE_CM.0,
                    max: TABLE_HEIGHT_RANGE_CM.1,
                },
            )
            .with_unit(" cm")
            .with_value_to_string(formatters::v2s_f32_rounded(1)),
            wall: BoolParam::new("Wall", d.wall),
            wall_dist_cm: FloatParam::new(
                "Wall Distance",
                d.wall_dist_cm,
                FloatRange::Skewed {
                    min: WALL_DIST_RANGE_CM.0,
                    max: WALL_DIST_RANGE_CM.1,
                    factor: FloatRange::skew_factor(-1.5),
                },
            )
            .with_unit(" cm")
            .with_value_to_string(formatters::v2s_f32_rounded(1)),
        }
    }
}

/// Listener parameters.
#[derive(Params)]
pub struct ListenerParams {
    /// Listener azimuth, degrees (0 = in front of the front edge, +90 = to the right).
    #[id = "listener_az_deg"]
    pub listener_az_deg: FloatParam,
    /// Listener distance from the sheet's home centre, metres.
    #[id = "listener_dist_m"]
    pub listener_dist_m: FloatParam,
}

impl Default for ListenerParams {
    fn default() -> Self {
        Self {
            listener_az_deg: FloatParam::new(
                "Listener Azimuth",
                0.0,
                FloatRange::Linear {
                    min: -180.0,
                    max: 180.0,
                },
            )
            .with_unit("°")
            .with_value_to_string(formatters::v2s_f32_rounded(1)),
            listener_dist_m: FloatParam::new(
                "Listener Distance",
                1.0,
                FloatRange::Skewed {
                    min: LISTENER_DIST_RANGE_M.0,
                    max: LISTENER_DIST_RANGE_M.1,
                    factor: FloatRange::skew_factor(-1.0),
                },
            )
            .with_unit(" m")
            .with_value_to_string(formatters::v2s_f32_rounded(2)),
        }
    }
}

fn gain_param(name: &str, default_db: f32) -> FloatParam {
    FloatParam::new(
        name,
        default_db,
        FloatRange::Linear {
            min: GAIN_RANGE_DB.0,
            max: GAIN_RANGE_DB.1,
        },
    )
    .with_unit(" dB")
    .with_value_to_string(formatters::v2s_f32_rounded(1))
}

/// Mix parameters.
#[derive(Params)]
pub struct MixParams {
    /// Crumple units level, dB.
    #[id = "mix_crumple_db"]
    pub crumple_db: FloatParam,
    /// Friction noise level, dB.
    #[id = "mix_friction_db"]
    pub friction_db: FloatParam,
    /// Tearing noise level, dB.
    #[id = "mix_tear_db"]
    pub tear_db: FloatParam,
}

impl Default for MixParams {
    fn default() -> Self {
        Self {
            crumple_db: gain_param("Crumple Level", 0.0),
            friction_db: gain_param("Friction Level", DEFAULT_FRICTION_DB),
            tear_db: gain_param("Tear Level", 0.0),
        }
    }
}

/// All of Papier's parameters and persisted fields.
#[derive(Params)]
pub struct PapierParams {
    /// Gestures.
    #[nested(group = "Gestures")]
    pub gestures: GestureParams,
    /// Sheet.
    #[nested(group = "Sheet")]
    pub sheet: SheetParams,
    /// Room.
    #[nested(group = "Room")]
    pub room: RoomParams,
    /// Listener.
    #[nested(group = "Listener")]
    pub listener: ListenerParams,
    /// Mix.
    #[nested(group = "Mix")]
    pub mix: MixParams,
    /// Output gain, dB.
    #[id = "gain_db"]
    pub gain_db: FloatParam,

    /// Version of the saved state layout.
    #[persist = "state_version"]
    pub state_version: Arc<AtomicU32>,
    /// The sheet (shape and damage), saved with the project.
    #[persist = "sheet"]
    pub sheet_store: Arc<SheetStore>,
    /// The user sound database folder (`null` = the embedded default), and its loader.
    #[persist = "db_path"]
    pub db: Arc<DbLoader>,
    /// The editor window's size, logical pixels ([`crate::editor::window_size`]).
    #[persist = "editor_size"]
    pub editor_size: Arc<EditorSize>,
}

impl Default for PapierParams {
    fn default() -> Self {
        Self {
            gestures: GestureParams::default(),
            sheet: SheetParams::default(),
            room: RoomParams::default(),
            listener: ListenerParams::default(),
            mix: MixParams::default(),
            gain_db: gain_param("Output Gain", DEFAULT_OUTPUT_DB),
            state_version: Arc::new(AtomicU32::new(STATE_VERSION)),
            sheet_store: Arc::new(SheetStore::default()),
            db: Arc::new(DbLoader::default()),
            editor_size: Arc::new(EditorSize::default()),
        }
    }
}

impl PapierParams {
    /// Reads the current (unsmoothed) values of every parameter the engine uses. Allocation-free.
    pub fn values(&self) -> ParamValues {
        let mut gestures = [0.0; GestureParam::COUNT];
        for g in GestureParam::ALL {
            gestures[g.index()] = self.gestures.get(g).value();
        }
        ParamValues {
            gestures,
            size: self.sheet.size.value().into(),
            material: self.sheet.material.value().into(),
            seed: self.sheet.seed.value().clamp(0, MAX_SEED) as u64,
            room: RoomConfig {
                table: self.room.table.value(),
                table_height_cm: self.room.table_height_cm.value(),
                wall: self.room.wall.value(),
                wall_dist_cm: self.room.wall_dist_cm.value(),
            },
            listener_az_deg: self.listener.listener_az_deg.value(),
            listener_dist_m: self.listener.listener_dist_m.value(),
            mix_crumple_db: self.mix.crumple_db.value(),
            mix_friction_db: self.mix.friction_db.value(),
            mix_tear_db: self.mix.tear_db.value(),
            gain_db: self.gain_db.value(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `PARAM_IDS` is written by hand; the plugin's parameter list comes from the `#[id]`s of
    /// `params.rs` through the `Params` derive. Same ids, same order (the order hosts list them
    /// in), so neither can change without the other.
    #[test]
    fn param_ids_match_the_plugin_parameters() {
        use nice_plug::prelude::Params;
        let params = PapierParams::default();
        let plugin: Vec<String> = params
            .param_map()
            .into_iter()
            .map(|(id, _, _)| id)
            .collect();
        let table: Vec<String> = crate::engine::param_values::PARAM_IDS
            .iter()
            .map(|s| s.to_string())
            .collect();
        for id in &plugin {
            assert!(
                table.contains(id),
                "parameter `{id}` of params.rs is missing from PARAM_IDS"
            );
        }
        for id in &table {
            assert!(
                plugin.contains(id),
                "PARAM_IDS lists `{id}`, which params.rs does not declare"
            );
        }
        assert_eq!(plugin, table, "PARAM_IDS is not in the plugin's order");
    }
}
