//! # The on-disk format
//!
//! A database is a folder:
//!
//! ```text
//! my-paper/
//!   manifest.toml
//!   crumple/flap_s10_c5_v0.wav      crumple units: mono WAV (16/24/32-bit PCM or 32-bit float)
//!   crumple/clac_v0.wav
//!   friction/s10_c5.f32              friction spectra: SPECTRUM_BINS little-endian f32 magnitudes
//!   friction/flat.f32
//! ```
//!
//! File names are free (the manifest lists every file); the ones above are what the generator and
//! the importer write. The manifest:
//!
//! ```toml
//! format = "papier-sounddb"
//! version = 1
//! name = "Printer paper (synthesized)"
//! material = "printer"            # free text
//! obstacle = "wooden table"       # what the friction spectra slide on
//! synthesized = true              # false for recordings
//! description = "..."             # free text (optional)
//! sample_rate_hz = 44100          # rate of every WAV unit
//! spectrum_bins = 2048            # length of every .f32 spectrum (optional, default 2048)
//! spectrum_rate_hz = 44100        # bin k is at k·spectrum_rate_hz/(2·spectrum_bins) Hz (optional,
//!                                 # default sample_rate_hz)
//!
//! [[crumple]]
//! kind = "flap"                   # "flap" (free) or "clac" (constrained, cell (0,0))
//! straight_cm = 10.0              # l_r            (flap only)
//! curved_cm = 5.0                 # l_c/2 = one curved edge of the recorded rectangle (flap only)
//! file = "crumple/flap_s10_c5_v0.wav"
//! gain_db = 0.0                   # optional level trim
//!
//! [[friction]]
//! kind = "free"                   # "free" or "flat" (constrained, cell (0,0))
//! straight_cm = 10.0
//! curved_cm = 5.0
//! file = "friction/s10_c5.f32"
//! speed_m_s = 0.10                # slide speed of the recording (optional, default 0.10)
//! ```
//!
//! **Spectrum convention.** Value `s_k` (k = 0 … bins−1) is the RMS amplitude of the recorded
//! friction noise in the band of width Δf = spectrum_rate_hz/(2·bins) around f_k = k·Δf, i.e.
//! the one-sided power spectral density is s_k²/Δf. This is the seeds' "average magnitude
//! spectrum" (S 149, T 1909) with an explicit normalisation so that spectra from different FFT
//! sizes and rates mean the same thing; the importer computes it from the middle 200 ms of a slide
//! ([`crate::import`]).
//!
//! **Units.** Crumple units are played once at a gain linear in the event amplitude (T 1820);
//! their stored level is the level heard at 1 m for a unit-amplitude event (the seeds' 1 m
//! microphone, T 1905).

use serde::{Deserialize, Serialize};

/// The `format` string of a manifest.
pub const FORMAT: &str = "papier-sounddb";
/// The manifest version this build reads and writes.
pub const VERSION: u32 = 1;
/// Name of the manifest file inside a database folder.
pub const MANIFEST_FILE: &str = "manifest.toml";

/// The header of a manifest (the entry tables are parsed one by one so that a bad entry only
/// skips itself).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Header {
    /// Always [`FORMAT`].
    pub format: String,
    /// Format version ([`VERSION`]).
    pub version: u32,
    /// Display name.
    pub name: String,
    /// Paper type (free text).
    #[serde(default)]
    pub material: String,
    /// What friction spectra slide on (free text).
    #[serde(default)]
    pub obstacle: String,
    /// True when the units were synthesized rather than recorded.
    #[serde(default)]
    pub synthesized: bool,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// Sample rate of every WAV unit, Hz.
    pub sample_rate_hz: u32,
    /// Number of bins of every spectrum file.
    #[serde(default = "default_bins")]
    pub spectrum_bins: usize,
    /// Rate the spectra refer to (bin k at k·rate/(2·bins) Hz); defaults to `sample_rate_hz`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spectrum_rate_hz: Option<u32>,
    /// Generator seed, if generated.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Crumple entries (parsed individually).
    #[serde(default, skip_serializing)]
    pub crumple: Vec<toml::Value>,
    /// Friction entries (parsed individually).
    #[serde(default, skip_serializing)]
    pub friction: Vec<toml::Value>,
}

fn default_bins() -> usize {
    crate::SPECTRUM_BINS
}

/// Kind of a crumple entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CrumpleKind {
    /// Free resonator ("flap", l_c > 0).
    Flap,
    /// Constrained resonator ("clac", cell (0, 0)).
    Clac,
}

/// Kind of a friction entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FrictionKind {
    /// Free resonator (unconstrained friction).
    Free,
    /// Constrained friction (flat sheet, cell (0, 0)).
    Flat,
}

/// One `[[crumple]]` entry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrumpleEntry {
    /// flap or clac.
    pub kind: CrumpleKind,
    /// l_r, cm (flap only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub straight_cm: Option<f32>,
    /// l_c/2, cm (flap only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curved_cm: Option<f32>,
    /// Path relative to the database folder, `/`-separated.
    pub file: String,
    /// Level trim, dB.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub gain_db: f32,
}

/// One `[[friction]]` entry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionEntry {
    /// free or flat.
    pub kind: FrictionKind,
    /// l_r, cm (free only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub straight_cm: Option<f32>,
    /// l_c/2, cm (free only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curved_cm: Option<f32>,
    /// Path relative to the database folder, `/`-separated.
    pub file: String,
    /// Slide speed of the recording, m/s.
    #[serde(default = "default_speed")]
    pub speed_m_s: f32,
}

fn default_speed() -> f32 {
    crate::REFERENCE_SLIDE_SPEED_M_S
}

fn is_zero(v: &f32) -> bool {
    *v == 0.0
}

/// The full manifest as written (header + entries).
#[derive(Clone, Debug, Serialize)]
pub struct ManifestOut<'a> {
    /// Header fields.
    #[serde(flatten)]
    pub header: &'a Header,
    /// Crumple entries.
    pub crumple: Vec<CrumpleEntry>,
    /// Friction entries.
    pub friction: Vec<FrictionEntry>,
}
