//! # Control vocabulary: what can be asked of the sheet
//!
//! Everything that drives the simulation arrives as a [`Command`]: a grab or release of a
//! group of boundary points ("hands"), a new value of a continuous gesture (crumple, slide, …),
//! a change of sheet size, material, seed or room, or a reset to a fresh flat sheet.
//!
//! The gesture set follows the interaction model of the seeds: handles are hard positional
//! constraints on boundary points with a controlled tangent plane (thesis §2.3.1, T 714/730;
//! TOG 2015 P 388–394, 450), driven here by absolute gesture values so that host automation and
//! offline renders are reproducible (digest-tearing §4.3). Every gesture value is given in the
//! plain units of the plugin parameter of the same id ([`GestureParam::id`]); the ranges are
//! linear so that a MIDI CC maps onto them exactly as the host's normalised value does.
//!
//! Commands are `Copy`, carry no heap data and are safe to send through a lock-free queue.

use serde::{Deserialize, Serialize};

use crate::room::RoomConfig as Room;

/// Default number of simulation frames per second of simulated time.
pub const DEFAULT_FRAME_RATE_HZ: f64 = 200.0;

pub use crate::room::RoomConfig;

/// Standard sheet sizes, portrait orientation (width along x, length along y).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SheetSize {
    /// ISO A4, 21.0 × 29.7 cm.
    #[default]
    A4,
    /// ISO A5, 14.8 × 21.0 cm.
    A5,
    /// ISO A6, 10.5 × 14.8 cm.
    A6,
    /// A 10 cm square, the seeds' validation sheet (L_paper = 10 cm, P 1054).
    Sq10,
}

impl SheetSize {
    /// All sizes, in parameter order.
    pub const ALL: [SheetSize; 4] = [SheetSize::A4, SheetSize::A5, SheetSize::A6, SheetSize::Sq10];

    /// Stable id used by the plugin parameter, scripts and `--set size=…`.
    pub const fn id(self) -> &'static str {
        match self {
            SheetSize::A4 => "a4",
            SheetSize::A5 => "a5",
            SheetSize::A6 => "a6",
            SheetSize::Sq10 => "sq10",
        }
    }

    /// Parses a stable id (case-insensitive).
    pub fn from_id(id: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|s| s.id().eq_ignore_ascii_case(id))
    }

    /// (width, length) in centimetres.
    pub const fn dims_cm(self) -> (f64, f64) {
        match self {
            SheetSize::A4 => (21.0, 29.7),
            SheetSize::A5 => (14.8, 21.0),
            SheetSize::A6 => (10.5, 14.8),
            SheetSize::Sq10 => (10.0, 10.0),
        }
    }

    /// (width, length) in metres.
    pub fn dims_m(self) -> (f64, f64) {
        let (w, l) = self.dims_cm();
        (w * 0.01, l * 0.01)
    }

    /// The largest dimension in cm: the seeds' L_paper, which scales several thresholds.
    pub fn l_paper_cm(self) -> f64 {
        let (w, l) = self.dims_cm();
        w.max(l)
    }
}

/// Paper grades. The seeds tie thicker paper to a larger compression limit ε_c and fewer
/// singular points (P 1309–1314; T 1184, 1202) and recorded one sound database per grade
/// (T 1804).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Material {
    /// 80 g/m² printer paper, the seeds' reference.
    #[default]
    Printer,
    /// Thin, stiff-ish tracing paper.
    Tracing,
    /// Bank-note paper: tough, cloth-like.
    Banknote,
}

impl Material {
    /// All materials, in parameter order.
    pub const ALL: [Material; 3] = [Material::Printer, Material::Tracing, Material::Banknote];

    /// Stable id used by the plugin parameter, scripts and `--set material=…`.
    pub const fn id(self) -> &'static str {
        match self {
            Material::Printer => "printer",
            Material::Tracing => "tracing",
            Material::Banknote => "banknote",
        }
    }

    /// Parses a stable id (case-insensitive).
    pub fn from_id(id: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.id().eq_ignore_ascii_case(id))
    }
}

/// Groups of boundary points that a "hand" can hold (MIDI notes 48–55 in the plugin).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GrabSlot {
    /// The back edge (+y, far from a listener at azimuth 0).
    Back,
    /// The front edge (−y).
    Front,
    /// The left edge (−x).
    Left,
    /// The right edge (+x).
    Right,
    /// All four corners.
    Corners,
}

impl GrabSlot {
    /// All slots.
    pub const ALL: [GrabSlot; 5] = [
        GrabSlot::Back,
        GrabSlot::Front,
        GrabSlot::Left,
        GrabSlot::Right,
        GrabSlot::Corners,
    ];

    /// Stable id used in scripts.
    pub const fn id(self) -> &'static str {
        match self {
            GrabSlot::Back => "back",
            GrabSlot::Front => "front",
            GrabSlot::Left => "left",
            GrabSlot::Right => "right",
            GrabSlot::Corners => "corners",
        }
    }

    /// Parses a stable id (case-insensitive).
    pub fn from_id(id: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|s| s.id().eq_ignore_ascii_case(id))
    }

    /// Index into per-slot arrays.
    pub const fn index(self) -> usize {
        self as usize
    }
}

/// The continuous gestures. Each is also a plugin parameter with the same [`id`](Self::id).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum GestureParam {
    /// Squeeze the sheet towards its centre, 0–1.
    Crumple,
    /// Front edge travel towards the back edge in the table plane, 0–1 of half the length.
    Slide,
    /// Height of the held edges, 0–1 of half the length.
    Lift,
    /// Rotation of the held edges' tangent frames about the long axis, −1–1 (±π); 0 = none.
    Twist,
    /// Shake depth, 0–1 of the maximal depth (5 % of the length).
    ShakeDepth,
    /// Shake rate in Hz.
    ShakeRateHz,
    /// Tear opening, 0–1.
    TearAmount,
    /// Tear steering between the two hands, −1–1; 0 = straight.
    TearSteer,
    /// Where along the top edge a tear starts, 0–1.
    TearPosition,
    /// Separation of the two pull points, 0–1.
    PullSeparation,
    /// Asymmetry of the pull, −1–1; 0 = symmetric.
    PullAsymmetry,
}

impl GestureParam {
    /// Number of gestures.
    pub const COUNT: usize = 11;

    /// All gestures, in parameter order.
    pub const ALL: [GestureParam; Self::COUNT] = [
        GestureParam::Crumple,
        GestureParam::Slide,
        GestureParam::Lift,
        GestureParam::Twist,
        GestureParam::ShakeDepth,
        GestureParam::ShakeRateHz,
        GestureParam::TearAmount,
        GestureParam::TearSteer,
        GestureParam::TearPosition,
        GestureParam::PullSeparation,
        GestureParam::PullAsymmetry,
    ];

    /// Stable parameter id (never change these: saved projects and automation refer to them).
    pub const fn id(self) -> &'static str {
        match self {
            GestureParam::Crumple => "crumple",
            GestureParam::Slide => "slide",
            GestureParam::Lift => "lift",
            GestureParam::Twist => "twist",
            GestureParam::ShakeDepth => "shake_depth",
            GestureParam::ShakeRateHz => "shake_rate_hz",
            GestureParam::TearAmount => "tear_amount",
            GestureParam::TearSteer => "tear_steer",
            GestureParam::TearPosition => "tear_pos",
            GestureParam::PullSeparation => "pull_sep",
            GestureParam::PullAsymmetry => "pull_asym",
        }
    }

    /// Human-readable name.
    pub const fn name(self) -> &'static str {
        match self {
            GestureParam::Crumple => "Crumple",
            GestureParam::Slide => "Slide",
            GestureParam::Lift => "Lift",
            GestureParam::Twist => "Twist",
            GestureParam::ShakeDepth => "Shake Depth",
            GestureParam::ShakeRateHz => "Shake Rate",
            GestureParam::TearAmount => "Tear Amount",
            GestureParam::TearSteer => "Tear Steer",
            GestureParam::TearPosition => "Tear Position",
            GestureParam::PullSeparation => "Pull Separation",
            GestureParam::PullAsymmetry => "Pull Asymmetry",
        }
    }

    /// Parses a stable id.
    pub fn from_id(id: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|g| g.id() == id)
    }

    /// Index into per-gesture arrays.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Linear plain range (min, max).
    pub const fn range(self) -> (f32, f32) {
        match self {
            GestureParam::Twist | GestureParam::TearSteer | GestureParam::PullAsymmetry => {
                (-1.0, 1.0)
            }
            GestureParam::ShakeRateHz => (0.5, 8.0),
            _ => (0.0, 1.0),
        }
    }

    /// Default plain value.
    pub const fn default_value(self) -> f32 {
        match self {
            GestureParam::ShakeRateHz => 3.0,
            GestureParam::TearPosition => 0.5,
            _ => 0.0,
        }
    }

    /// True for the bipolar gestures whose MIDI CC value 64 means "centre".
    pub const fn is_bipolar(self) -> bool {
        matches!(
            self,
            GestureParam::Twist | GestureParam::TearSteer | GestureParam::PullAsymmetry
        )
    }

    /// Clamps a value into range; a non-finite value yields `None` (the command is ignored).
    pub fn sanitize(self, value: f32) -> Option<f32> {
        if !value.is_finite() {
            return None;
        }
        let (lo, hi) = self.range();
        Some(value.clamp(lo, hi))
    }
}

/// One input to the simulation. Applied at the start of the frame whose time span contains the
/// command's timestamp (the caller does the scheduling).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Command {
    /// Replace the sheet by a new flat, undamaged sheet (same size, material and seed).
    Reset,
    /// A hand takes hold of a slot. `grip` ∈ [0, 1] (MIDI velocity) sets how fast the held
    /// points travel to their targets.
    Grab {
        /// Which points are held.
        slot: GrabSlot,
        /// Grip speed, 0–1.
        grip: f32,
    },
    /// The hand holding `slot` lets go.
    Release {
        /// Which points are released.
        slot: GrabSlot,
    },
    /// Every hand lets go.
    ReleaseAll,
    /// A new value of a continuous gesture, in the gesture's plain units.
    Gesture {
        /// Which gesture.
        param: GestureParam,
        /// New value (clamped to the gesture's range; non-finite values are ignored).
        value: f32,
    },
    /// A new sheet size: the sheet is replaced by a fresh flat sheet of that size.
    Size(SheetSize),
    /// A new paper grade: stiffness and damage thresholds change, damage is kept.
    Material(Material),
    /// A new random seed, used from the next reset on.
    Seed(u64),
    /// New room geometry (table and wall).
    Room(Room),
}
