//! # Errors and warnings of the loader
//!
//! A database that cannot be used at all is a [`DbError`]; everything else — a missing or
//! truncated file, a unit at the wrong sample rate, a bad spectrum, missing grid cells — is a
//! [`Warning`]: the entry is skipped and the rest stays usable. The loader never panics on bad
//! input (the bad-database tests of `tests/tests/render_db.rs` and this crate's unit tests feed it
//! truncated WAVs, wrong rates, garbage manifests and empty folders).

use std::path::PathBuf;

/// Why a database could not be loaded at all.
#[derive(Debug, thiserror::Error)]
pub enum DbError {
    /// The database folder does not exist or is not a folder.
    #[error("sound database folder {0} does not exist or is not a folder")]
    NotAFolder(PathBuf),
    /// The folder has no `manifest.toml`.
    #[error(
        "{0} has no manifest.toml (is this a Papier sound database? `cargo xtask sounddb` builds one)"
    )]
    MissingManifest(PathBuf),
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The manifest is not valid TOML or misses required keys.
    #[error("manifest {path} is not a valid sound database manifest: {message}")]
    Manifest {
        /// The manifest file.
        path: PathBuf,
        /// What is wrong (TOML parser message with line/column, or the offending key).
        message: String,
    },
    /// The manifest declares another format or a newer version.
    #[error(
        "manifest {path}: unsupported format {format:?} version {version} (this build reads {expected:?} version {expected_version})"
    )]
    UnsupportedFormat {
        /// The manifest file.
        path: PathBuf,
        /// Declared format.
        format: String,
        /// Declared version.
        version: u32,
        /// The format this build reads.
        expected: &'static str,
        /// The version this build reads.
        expected_version: u32,
    },
    /// The single-file pack is malformed.
    #[error("sound database pack is malformed: {0}")]
    BadPack(String),
    /// A prepared database image is malformed.
    #[error("prepared sound database image is malformed: {0}")]
    BadImage(String),
    /// Nothing usable was left after validation.
    #[error(
        "sound database {path} has no usable crumple unit and no usable friction spectrum ({skipped} entries skipped; see the warnings)"
    )]
    Empty {
        /// The database.
        path: PathBuf,
        /// Number of entries skipped.
        skipped: usize,
    },
    /// Writing a database failed.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file or folder.
        path: PathBuf,
        /// What failed.
        message: String,
    },
}

/// Something the loader skipped or found suspicious; the database stays usable.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Warning {
    /// A file named in the manifest is missing.
    #[error("{entry}: file {path} is missing; entry skipped")]
    MissingFile {
        /// Which manifest entry (e.g. `crumple[3]`).
        entry: String,
        /// The file.
        path: PathBuf,
    },
    /// A WAV file could not be decoded (truncated, not a WAV, unsupported encoding).
    #[error("{entry}: {path} is not a readable WAV file ({message}); entry skipped")]
    BadWav {
        /// Which manifest entry.
        entry: String,
        /// The file.
        path: PathBuf,
        /// Decoder message.
        message: String,
    },
    /// A unit's sample rate differs from the manifest's.
    #[error(
        "{entry}: {path} is at {found_hz} Hz but the database is at {expected_hz} Hz; entry skipped (re-import or resample it)"
    )]
    WrongSampleRate {
        /// Which manifest entry.
        entry: String,
        /// The file.
        path: PathBuf,
        /// Rate found in the file.
        found_hz: u32,
        /// Rate of the database.
        expected_hz: u32,
    },
    /// A multi-channel unit was mixed down to mono.
    #[error("{entry}: {path} has {channels} channels; mixed down to mono")]
    MixedDown {
        /// Which manifest entry.
        entry: String,
        /// The file.
        path: PathBuf,
        /// Channel count found.
        channels: u16,
    },
    /// A unit has no samples, only silence, or non-finite samples.
    #[error("{entry}: {path} {problem}; entry skipped")]
    BadUnit {
        /// Which manifest entry.
        entry: String,
        /// The file.
        path: PathBuf,
        /// What is wrong.
        problem: String,
    },
    /// A unit longer than [`crate::MAX_UNIT_S`] was truncated.
    #[error("{entry}: {path} is {seconds:.2} s long; truncated to {max_s} s")]
    Truncated {
        /// Which manifest entry.
        entry: String,
        /// The file.
        path: PathBuf,
        /// Original length, s.
        seconds: f32,
        /// Limit, s.
        max_s: f32,
    },
    /// A friction spectrum file has the wrong size or bad values.
    #[error("{entry}: spectrum {path} {problem}; entry skipped")]
    BadSpectrum {
        /// Which manifest entry.
        entry: String,
        /// The file.
        path: PathBuf,
        /// What is wrong.
        problem: String,
    },
    /// A manifest entry is malformed (bad keys or values).
    #[error("{entry}: {problem}; entry skipped")]
    BadEntry {
        /// Which manifest entry.
        entry: String,
        /// What is wrong.
        problem: String,
    },
    /// Two friction spectra for the same cell; the first is kept.
    #[error("{entry}: a friction spectrum for cell {cell} already exists; entry skipped")]
    DuplicateSpectrum {
        /// Which manifest entry.
        entry: String,
        /// The cell.
        cell: String,
    },
    /// Too many cells or variants; extra entries dropped.
    #[error("{entry}: {problem}; entry skipped")]
    Capacity {
        /// Which manifest entry.
        entry: String,
        /// What limit was hit.
        problem: String,
    },
    /// A cell is not on the seeds' size grid (allowed; lookups still work).
    #[error(
        "{entry}: cell {cell} is not on the size grid {{2.5, 5, 7.5, 10, 12.5, 15, 20, 25, 30}} cm (kept)"
    )]
    OffGrid {
        /// Which manifest entry.
        entry: String,
        /// The cell.
        cell: String,
    },
    /// Grid cells without any entry (lookups go to the nearest occupied cell).
    #[error(
        "{what}: {missing} of 81 grid cells have no entry (e.g. {examples}); their resonators use the nearest occupied cell"
    )]
    MissingCells {
        /// `crumple` or `friction`.
        what: &'static str,
        /// Number of grid cells without an entry.
        missing: usize,
        /// Up to 5 missing cells.
        examples: String,
    },
    /// No (0, 0) entry of a kind.
    #[error(
        "{what}: no constrained (0,0) entry; constrained resonators use the smallest free cell"
    )]
    NoConstrained {
        /// `crumple` or `friction`.
        what: &'static str,
    },
    /// One of the two parts is entirely missing.
    #[error("no usable {what} entries: {consequence}")]
    PartMissing {
        /// `crumple` or `friction`.
        what: &'static str,
        /// What the user will hear.
        consequence: &'static str,
    },
    /// A file in the folder is not referenced by the manifest.
    #[error("{path} is not listed in manifest.toml (ignored)")]
    Unreferenced {
        /// The file.
        path: PathBuf,
    },
}
