//! # sounddb: the sound database
//!
//! Papier's sound is concatenative and data driven, like the seeds' (thesis ch. 4,
//! `000_cb4d91e46ec5927f.txt` §4.3, lines 1800–1967; SCA 2016, `002_9b4a8fc30aee6402.txt` §4,
//! lines 143–210; digest-sound §3): every vibrating patch of the sheet (a *resonator*) is
//! characterised by two lengths,
//!
//! - **l_r**, the mean length of its rulings (the straight direction), and
//! - **l_c**, the total length of its free curved borders (0 = constrained),
//!
//! and the pair picks the nearest entry of a pre-recorded database:
//!
//! - **crumple units**: time-domain clips played once per crumpling event, "flap" sounds for free
//!   resonators and "clac" sounds for constrained ones (T 1704, T 1806);
//! - **friction spectra**: averaged magnitude spectra turned into noise by a random-phase inverse
//!   FFT at run time (T 1822–1830, S 149).
//!
//! ## The index and the l_c vs l_c/2 question (digest-sound §3, §13.5)
//!
//! The seeds recorded, for each grid value, "a rectangular sheet of paper with (l_r, l_c/2) edge
//! length, bent along its edge of length l_c/2" (T 1808, S 151). A rectangle bent that way has
//! **two** curved free edges of length l_c/2 each, i.e. a total free curved border l_c: the
//! sentence is consistent with l_c being the resonator's total free curved border. Table 4.1
//! (T 1927) quotes its sizes as l_c/2 = 5, 10, 20 cm, i.e. grid values, and T 1907's
//! "l_c = L/2" reads as a typo for "l_c/2 = L" (L = the curved edge length). We therefore fix:
//!
//! > **A database cell is keyed by the recorded sheet's edges: `straight_cm` = l_r and
//! > `curved_cm` = l_c/2, the length of ONE curved edge.** A resonator whose total free curved
//! > border is `lc_cm` (what `sim_core::sound_input::Resonator::lc_cm` holds) is looked up at
//! > `curved_cm = lc_cm / 2`.
//!
//! The grid values {2.5, 5, 7.5, 10, 12.5, 15, 20, 25, 30} cm ([`GRID_CM`], T 1905) apply to both
//! `straight_cm` and `curved_cm`; the special cell (0, 0) ([`Cell::Constrained`]) holds the
//! constrained sounds (clac clips and constrained friction, T 1808).
//!
//! ## Lookup metric
//!
//! The seeds select "the closest recorded (l_r, l_c)" without a metric (T 1810). We use the
//! Euclidean distance in (ln l_r, ln(l_c/2)) — the grid is roughly geometric — over the
//! **occupied** cells only, so a partial database still answers every query ([`CellIndex`]).
//! Ties go to the cell listed first. Lookups allocate nothing.
//!
//! ## Two forms of a database
//!
//! - [`Database`]: what is on disk (a folder with `manifest.toml`, WAV units, `.f32` spectra; see
//!   [`manifest`]), loaded and validated at its own sample rate with
//!   [`Database::load`] (errors for what makes it unusable, [`Warning`]s for what was skipped),
//!   built by the generator ([`generate`]) or the importer ([`import`]).
//! - [`SoundDb`]: the same database **prepared for one sample rate** (units resampled, spectra
//!   moved onto the render path's FFT bins) — what a renderer holds in an `Arc`. Prepare it off
//!   the audio thread ([`SoundDb::prepare`]); it is immutable afterwards.
//!
//! ## Modules
//!
//! - [`cell`]: cells, the grid, the nearest-occupied-cell index;
//! - [`manifest`]: the on-disk format;
//! - [`database`]: loading, validation, writing (folder or single-file pack, [`pack`]);
//! - [`prepared`]: the rate-specific form for the render path ([`resample`] does the resampling);
//! - [`generate`]: the synthetic default databases (curved-panel modal model);
//! - [`import`]: building a database from the user's own recordings;
//! - [`analysis`]: spectral measures shared by the importer and the tests (Welch PSD, centroid,
//!   flatness, quadratic-form distance).

#![warn(missing_docs)]

pub mod analysis;
mod bytes;
pub mod cell;
pub mod database;
pub mod error;
pub mod generate;
pub mod import;
pub mod manifest;
pub mod pack;
mod parallel;
pub mod prepared;
pub mod resample;
mod wav;

pub use cell::{Cell, CellIndex, GRID_CM};
pub use database::{Database, DbInfo, FrictionSpectrum, Unit, UnitKind};
pub use error::{DbError, Warning};
pub use prepared::{CellId, PreparedUnit, SoundDb, friction_frame_len, unit_decimation};

/// Sample rate of the seeds' recordings and of the generated databases, Hz (T 1903).
pub const DEFAULT_SAMPLE_RATE_HZ: u32 = 44_100;

/// Number of bins of a stored friction spectrum: 2048 frequencies over 0 … fs/2 (T 1967).
/// Bin `k` is centred on `k · fs / (2 · SPECTRUM_BINS)` Hz (10.77 Hz apart at 44.1 kHz).
pub const SPECTRUM_BINS: usize = 2048;

/// Slide speed of the seeds' friction recordings (20 cm in 2 s, T 1909), m/s. A friction source
/// sliding at this speed plays its spectrum at unity gain (friction amplitude is linear in the
/// relative speed, S 153).
pub const REFERENCE_SLIDE_SPEED_M_S: f32 = 0.10;

/// Largest number of cells (crumple or friction) a database may hold; extra cells are dropped with
/// a warning. Sized so renderers can keep per-cell state in fixed arrays.
pub const MAX_CELLS: usize = 256;

/// Largest number of crumple variants per cell; extra variants are dropped with a warning.
pub const MAX_VARIANTS_PER_CELL: usize = 32;

/// Longest accepted crumple unit, seconds (the seeds' units are 0.2–0.8 s, T 1967); longer clips
/// are truncated with a warning.
pub const MAX_UNIT_S: f32 = 4.0;
