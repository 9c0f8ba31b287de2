//! # Loading, validating and writing a database
//!
//! [`Database::load`] reads a folder (format: [`crate::manifest`]), [`Database::from_pack`] the
//! same content packed into one byte string ([`crate::pack`]); both go through one validation
//! path. The rules:
//!
//! - **fatal** ([`DbError`]): no folder, no or unparsable manifest (the TOML parser's line and
//!   column are in the message), another format or version, an invalid sample rate or bin count,
//!   or nothing usable left at the end;
//! - **skipped with a [`Warning`]**: a bad entry (bad keys, lengths ≤ 0 or > 100 cm), a missing
//!   file, a WAV that does not decode (truncated, not a WAV, unsupported encoding), a unit at
//!   another sample rate, an empty / silent / non-finite unit, a spectrum of the wrong size or
//!   with negative or non-finite values, a duplicate spectrum, more than [`crate::MAX_CELLS`]
//!   cells or [`crate::MAX_VARIANTS_PER_CELL`] variants;
//! - **kept with a [`Warning`]**: multi-channel units (mixed to mono), units longer than
//!   [`crate::MAX_UNIT_S`] (truncated), cells off the size grid, missing grid cells (lookups use
//!   the nearest occupied cell), no (0, 0) entry, a missing part (no friction or no crumple
//!   entries), files the manifest does not list.
//!
//! Nothing here panics on bad input.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::cell::{Cell, GRID_CM, fmt_cm};
use crate::manifest::{
    self, CrumpleEntry, CrumpleKind, FrictionEntry, FrictionKind, Header, MANIFEST_FILE,
};
use crate::pack::{DirSource, FileSource, MemSource};
use crate::{DbError, MAX_CELLS, MAX_UNIT_S, MAX_VARIANTS_PER_CELL, Warning, wav};

/// Longest accepted cell length, cm.
pub const MAX_LENGTH_CM: f32 = 100.0;
/// Accepted sample rates of a database, Hz.
pub const SAMPLE_RATE_RANGE_HZ: (u32, u32) = (8_000, 384_000);

/// Descriptive fields of a database.
#[derive(Clone, Debug, PartialEq)]
pub struct DbInfo {
    /// Display name.
    pub name: String,
    /// Paper type.
    pub material: String,
    /// What the friction spectra slide on.
    pub obstacle: String,
    /// True when the units were synthesized rather than recorded.
    pub synthesized: bool,
    /// Free text.
    pub description: String,
    /// Generator seed, if generated.
    pub seed: Option<u64>,
}

impl Default for DbInfo {
    fn default() -> Self {
        Self {
            name: "unnamed".into(),
            material: String::new(),
            obstacle: String::new(),
            synthesized: false,
            description: String::new(),
            seed: None,
        }
    }
}

/// Kind of a crumple unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitKind {
    /// Free resonator.
    Flap,
    /// Constrained resonator.
    Clac,
}

/// A crumple unit.
#[derive(Clone, Debug, PartialEq)]
pub struct Unit {
    /// Its cell ((0, 0) for clac).
    pub cell: Cell,
    /// Mono samples at the database rate (level trim applied).
    pub samples: Vec<f32>,
    /// File it came from (relative path), or where it will be written.
    pub file: String,
}

impl Unit {
    /// flap or clac.
    pub fn kind(&self) -> UnitKind {
        if self.cell.is_constrained() {
            UnitKind::Clac
        } else {
            UnitKind::Flap
        }
    }
}

/// A friction spectrum.
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionSpectrum {
    /// Its cell ((0, 0) for constrained friction).
    pub cell: Cell,
    /// Magnitudes (see the spectrum convention in [`crate::manifest`]).
    pub magnitudes: Vec<f32>,
    /// Slide speed of the recording, m/s.
    pub speed_m_s: f32,
    /// File it came from (relative path), or where it will be written.
    pub file: String,
}

/// A database at its own sample rate: what is on disk, validated.
#[derive(Clone, Debug, PartialEq)]
pub struct Database {
    /// Descriptive fields.
    pub info: DbInfo,
    /// Rate of the units, Hz.
    pub sample_rate_hz: u32,
    /// Rate the spectra refer to, Hz (bin k at k·rate/(2·bins)).
    pub spectrum_rate_hz: u32,
    /// Bins per spectrum.
    pub spectrum_bins: usize,
    /// Crumple units, in manifest order.
    pub units: Vec<Unit>,
    /// Friction spectra, in manifest order.
    pub spectra: Vec<FrictionSpectrum>,
}

impl Database {
    /// An empty database at `sample_rate_hz` with 2048-bin spectra.
    pub fn new(info: DbInfo, sample_rate_hz: u32) -> Self {
        Self {
            info,
            sample_rate_hz,
            spectrum_rate_hz: sample_rate_hz,
            spectrum_bins: crate::SPECTRUM_BINS,
            units: Vec::new(),
            spectra: Vec::new(),
        }
    }

    /// A smaller database with the same description and rate: the units of the cells `keep`
    /// accepts and the first `max_spectra` of their friction spectra, in manifest order.
    pub fn subset(&self, keep: impl Fn(&Cell) -> bool, max_spectra: usize) -> Database {
        let mut db = Database::new(self.info.clone(), self.sample_rate_hz);
        db.units = self
            .units
            .iter()
            .filter(|u| keep(&u.cell))
            .cloned()
            .collect();
        db.spectra = self
            .spectra
            .iter()
            .filter(|s| keep(&s.cell))
            .take(max_spectra)
            .cloned()
            .collect();
        db
    }

    /// Loads and validates a database folder.
    pub fn load(dir: &Path) -> Result<(Database, Vec<Warning>), DbError> {
        if !dir.is_dir() {
            return Err(DbError::NotAFolder(dir.to_path_buf()));
        }
        if !dir.join(MANIFEST_FILE).is_file() {
            return Err(DbError::MissingManifest(dir.to_path_buf()));
        }
        let src = DirSource {
            root: dir.to_path_buf(),
        };
        load_from(&src, dir)
    }

    /// Loads and validates a database packed with [`Database::to_pack`].
    pub fn from_pack(bytes: &[u8], label: &str) -> Result<(Database, Vec<Warning>), DbError> {
        let src = crate::pack::unpack(bytes, label)?;
        if !src.files.contains_key(MANIFEST_FILE) {
            return Err(DbError::MissingManifest(PathBuf::from(label)));
        }
        load_from(&src, Path::new(label))
    }

    /// The files of this database (manifest, WAV units, spectra) by relative path. Units are
    /// written as 16-bit PCM; file names are regenerated from the cells.
    pub fn to_files(&self) -> BTreeMap<String, Vec<u8>> {
        let mut files = BTreeMap::new();
        let mut crumple = Vec::new();
        let mut variant: BTreeMap<String, usize> = BTreeMap::new();
        for u in &self.units {
            let label = match u.cell {
                Cell::Constrained => "clac".to_string(),
                Cell::Free {
                    straight_cm,
                    curved_cm,
                } => format!("flap_s{}_c{}", fmt_cm(straight_cm), fmt_cm(curved_cm)),
            };
            let v = variant.entry(label.clone()).or_insert(0);
            let file = format!("crumple/{label}_v{v}.wav");
            *v += 1;
            files.insert(
                file.clone(),
                wav::encode_i16(&u.samples, self.sample_rate_hz),
            );
            let (straight_cm, curved_cm) = lengths(&u.cell);
            crumple.push(CrumpleEntry {
                kind: if u.cell.is_constrained() {
                    CrumpleKind::Clac
                } else {
                    CrumpleKind::Flap
                },
                straight_cm,
                curved_cm,
                file,
                gain_db: 0.0,
            });
        }
        let mut friction = Vec::new();
        for s in &self.spectra {
            let file = match s.cell {
                Cell::Constrained => "friction/flat.f32".to_string(),
                Cell::Free {
                    straight_cm,
                    curved_cm,
                } => format!(
                    "friction/s{}_c{}.f32",
                    fmt_cm(straight_cm),
                    fmt_cm(curved_cm)
                ),
            };
            let mut bytes = Vec::with_capacity(4 * s.magnitudes.len());
            for m in &s.magnitudes {
                bytes.extend_from_slice(&m.to_le_bytes());
            }
            files.insert(file.clone(), bytes);
            let (straight_cm, curved_cm) = lengths(&s.cell);
            friction.push(FrictionEntry {
                kind: if s.cell.is_constrained() {
                    FrictionKind::Flat
                } else {
                    FrictionKind::Free
                },
                straight_cm,
                curved_cm,
                file,
                speed_m_s: s.speed_m_s,
            });
        }
        let header = Header {
            format: manifest::FORMAT.into(),
            version: manifest::VERSION,
            name: self.info.name.clone(),
            material: self.info.material.clone(),
            obstacle: self.info.obstacle.clone(),
            synthesized: self.info.synthesized,
            description: self.info.description.clone(),
            sample_rate_hz: self.sample_rate_hz,
            spectrum_bins: self.spectrum_bins,
            spectrum_rate_hz: (self.spectrum_rate_hz != self.sample_rate_hz)
                .then_some(self.spectrum_rate_hz),
            seed: self.info.seed,
            crumple: Vec::new(),
            friction: Vec::new(),
        };
        let text = toml::to_string(&manifest::ManifestOut {
            header: &header,
            crumple,
            friction,
        })
        .unwrap_or_else(|e| format!("# manifest serialization failed: {e}\n"));
        files.insert(MANIFEST_FILE.to_string(), text.into_bytes());
        files
    }

    /// Writes the database as a folder (created if needed; existing files with the same names are
    /// overwritten, other files are left alone).
    pub fn write_dir(&self, dir: &Path) -> Result<(), DbError> {
        for (rel, data) in self.to_files() {
            let path = dir.join(&rel);
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent).map_err(|e| DbError::Write {
                    path: parent.to_path_buf(),
                    message: e.to_string(),
                })?;
            }
            std::fs::write(&path, data).map_err(|e| DbError::Write {
                path: path.clone(),
                message: e.to_string(),
            })?;
        }
        Ok(())
    }

    /// The database packed into one byte string ([`crate::pack`]).
    pub fn to_pack(&self) -> Vec<u8> {
        crate::pack::pack(&self.to_files())
    }

    /// Total size of the files ([`Database::to_files`]), bytes.
    pub fn file_bytes(&self) -> usize {
        self.to_files().values().map(Vec::len).sum()
    }
}

fn lengths(cell: &Cell) -> (Option<f32>, Option<f32>) {
    match *cell {
        Cell::Constrained => (None, None),
        Cell::Free {
            straight_cm,
            curved_cm,
        } => (Some(straight_cm), Some(curved_cm)),
    }
}

fn load_from(src: &dyn FileSource, root: &Path) -> Result<(Database, Vec<Warning>), DbError> {
    let manifest_path = src.display_path(MANIFEST_FILE);
    let bytes = src.read(MANIFEST_FILE).map_err(|e| DbError::Io {
        path: manifest_path.clone(),
        source: e,
    })?;
    let text = std::str::from_utf8(&bytes).map_err(|e| DbError::Manifest {
        path: manifest_path.clone(),
        message: format!("not UTF-8 text ({e})"),
    })?;
    let header: Header = toml::from_str(text).map_err(|e| DbError::Manifest {
        path: manifest_path.clone(),
        message: e.to_string().trim().to_string(),
    })?;
    if header.format != manifest::FORMAT || header.version != manifest::VERSION {
        return Err(DbError::UnsupportedFormat {
            path: manifest_path,
            format: header.format,
            version: header.version,
            expected: manifest::FORMAT,
            expected_version: manifest::VERSION,
        });
    }
    let rate = header.sample_rate_hz;
    let rate_ok = |r: u32| (SAMPLE_RATE_RANGE_HZ.0..=SAMPLE_RATE_RANGE_HZ.1).contains(&r);
    if !rate_ok(rate) {
        return Err(DbError::Manifest {
            path: manifest_path,
            message: format!(
                "sample_rate_hz = {rate} is outside {}..={} Hz",
                SAMPLE_RATE_RANGE_HZ.0, SAMPLE_RATE_RANGE_HZ.1
            ),
        });
    }
    let spectrum_rate = header.spectrum_rate_hz.unwrap_or(rate);
    if !rate_ok(spectrum_rate) {
        return Err(DbError::Manifest {
            path: manifest_path,
            message: format!("spectrum_rate_hz = {spectrum_rate} is out of range"),
        });
    }
    let bins = header.spectrum_bins;
    if !(16..=65_536).contains(&bins) {
        return Err(DbError::Manifest {
            path: manifest_path,
            message: format!("spectrum_bins = {bins} is outside 16..=65536"),
        });
    }

    let mut warnings = Vec::new();
    let mut skipped = 0usize;
    let mut db = Database {
        info: DbInfo {
            name: header.name.clone(),
            material: header.material.clone(),
            obstacle: header.obstacle.clone(),
            synthesized: header.synthesized,
            description: header.description.clone(),
            seed: header.seed,
        },
        sample_rate_hz: rate,
        spectrum_rate_hz: spectrum_rate,
        spectrum_bins: bins,
        units: Vec::new(),
        spectra: Vec::new(),
    };
    let mut referenced: Vec<String> = vec![MANIFEST_FILE.to_string()];

    // Crumple units.
    let mut crumple_cells: Vec<(Cell, usize)> = Vec::new();
    for (i, value) in header.crumple.iter().enumerate() {
        let entry_label = format!("crumple[{i}]");
        match load_unit(src, value, &entry_label, rate, &mut warnings) {
            Ok(Some((unit, file))) => {
                referenced.push(file);
                let num_cells = crumple_cells.len();
                match crumple_cells
                    .iter_mut()
                    .find(|(c, _)| c.same_as(&unit.cell))
                {
                    Some((_, n)) if *n >= MAX_VARIANTS_PER_CELL => {
                        warnings.push(Warning::Capacity {
                            entry: entry_label,
                            problem: format!(
                                "cell {} already has {MAX_VARIANTS_PER_CELL} variants",
                                unit.cell.label()
                            ),
                        });
                        skipped += 1;
                    }
                    Some((_, n)) => {
                        *n += 1;
                        db.units.push(unit);
                    }
                    None if num_cells >= MAX_CELLS => {
                        warnings.push(Warning::Capacity {
                            entry: entry_label,
                            problem: format!("more than {MAX_CELLS} crumple cells"),
                        });
                        skipped += 1;
                    }
                    None => {
                        crumple_cells.push((unit.cell, 1));
                        db.units.push(unit);
                    }
                }
            }
            Ok(None) => skipped += 1,
            Err(file) => {
                referenced.extend(file);
                skipped += 1;
            }
        }
    }

    // Friction spectra.
    for (i, value) in header.friction.iter().enumerate() {
        let entry_label = format!("friction[{i}]");
        match load_spectrum(src, value, &entry_label, bins, &mut warnings) {
            Ok(Some((spectrum, file))) => {
                referenced.push(file);
                if db.spectra.iter().any(|s| s.cell.same_as(&spectrum.cell)) {
                    warnings.push(Warning::DuplicateSpectrum {
                        entry: entry_label,
                        cell: spectrum.cell.label(),
                    });
                    skipped += 1;
                } else if db.spectra.len() >= MAX_CELLS {
                    warnings.push(Warning::Capacity {
                        entry: entry_label,
                        problem: format!("more than {MAX_CELLS} friction cells"),
                    });
                    skipped += 1;
                } else {
                    db.spectra.push(spectrum);
                }
            }
            Ok(None) => skipped += 1,
            Err(file) => {
                referenced.extend(file);
                skipped += 1;
            }
        }
    }

    if db.units.is_empty() && db.spectra.is_empty() {
        return Err(DbError::Empty {
            path: root.to_path_buf(),
            skipped,
        });
    }
    coverage_warnings(&db, &mut warnings);
    for f in src.list() {
        let hidden = f.split('/').any(|c| c.starts_with('.'));
        let doc = f.ends_with(".md") || f.ends_with(".txt");
        if !hidden && !doc && !referenced.contains(&f) {
            warnings.push(Warning::Unreferenced {
                path: src.display_path(&f),
            });
        }
    }
    Ok((db, warnings))
}

/// Checks the lengths of an entry and builds its cell.
fn entry_cell(
    constrained: bool,
    straight_cm: Option<f32>,
    curved_cm: Option<f32>,
) -> Result<Cell, String> {
    if constrained {
        return match (straight_cm, curved_cm) {
            (None, None) => Ok(Cell::Constrained),
            _ => Err("constrained entries (clac / flat) are the (0,0) cell and take no straight_cm / curved_cm".into()),
        };
    }
    let (Some(s), Some(c)) = (straight_cm, curved_cm) else {
        return Err(
            "free entries (flap / free) need straight_cm (l_r) and curved_cm (l_c/2)".into(),
        );
    };
    let ok = |v: f32| v.is_finite() && v > 0.0 && v <= MAX_LENGTH_CM;
    if !ok(s) || !ok(c) {
        return Err(format!(
            "straight_cm = {s}, curved_cm = {c}: lengths must be in (0, {MAX_LENGTH_CM}] cm"
        ));
    }
    Ok(Cell::Free {
        straight_cm: s,
        curved_cm: c,
    })
}

/// Reads one crumple entry. `Ok(None)`: skipped, nothing referenced; `Err(file)`: skipped after
/// the file was identified.
fn load_unit(
    src: &dyn FileSource,
    value: &toml::Value,
    label: &str,
    rate: u32,
    warnings: &mut Vec<Warning>,
) -> Result<Option<(Unit, String)>, Option<String>> {
    let entry: CrumpleEntry = match value.clone().try_into() {
        Ok(e) => e,
        Err(e) => {
            warnings.push(Warning::BadEntry {
                entry: label.into(),
                problem: e.to_string().trim().to_string(),
            });
            return Ok(None);
        }
    };
    let cell = match entry_cell(
        entry.kind == CrumpleKind::Clac,
        entry.straight_cm,
        entry.curved_cm,
    ) {
        Ok(c) => c,
        Err(problem) => {
            warnings.push(Warning::BadEntry {
                entry: label.into(),
                problem,
            });
            return Ok(None);
        }
    };
    if !entry.gain_db.is_finite() || entry.gain_db.abs() > 60.0 {
        warnings.push(Warning::BadEntry {
            entry: label.into(),
            problem: format!("gain_db = {} is outside ±60 dB", entry.gain_db),
        });
        return Ok(None);
    }
    if !cell.is_on_grid() {
        warnings.push(Warning::OffGrid {
            entry: label.into(),
            cell: cell.label(),
        });
    }
    let path = src.display_path(&entry.file);
    let bytes = match src.read(&entry.file) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            warnings.push(Warning::MissingFile {
                entry: label.into(),
                path,
            });
            return Err(None);
        }
        Err(e) => {
            warnings.push(Warning::BadWav {
                entry: label.into(),
                path,
                message: e.to_string(),
            });
            return Err(Some(entry.file));
        }
    };
    let decoded = match wav::decode(&bytes) {
        Ok(d) => d,
        Err(message) => {
            warnings.push(Warning::BadWav {
                entry: label.into(),
                path,
                message,
            });
            return Err(Some(entry.file));
        }
    };
    if decoded.sample_rate_hz != rate {
        warnings.push(Warning::WrongSampleRate {
            entry: label.into(),
            path,
            found_hz: decoded.sample_rate_hz,
            expected_hz: rate,
        });
        return Err(Some(entry.file));
    }
    if decoded.channels > 1 {
        warnings.push(Warning::MixedDown {
            entry: label.into(),
            path: path.clone(),
            channels: decoded.channels,
        });
    }
    let mut samples = decoded.samples;
    let bad = |problem: &str, warnings: &mut Vec<Warning>| {
        warnings.push(Warning::BadUnit {
            entry: label.into(),
            path: path.clone(),
            problem: problem.into(),
        });
    };
    if samples.is_empty() {
        bad("has no samples", warnings);
        return Err(Some(entry.file));
    }
    if samples.iter().any(|s| !s.is_finite()) {
        bad("contains NaN or infinite samples", warnings);
        return Err(Some(entry.file));
    }
    if samples.iter().all(|s| s.abs() < 1e-6) {
        bad("is silent", warnings);
        return Err(Some(entry.file));
    }
    let max_len = (MAX_UNIT_S * rate as f32) as usize;
    if samples.len() > max_len {
        warnings.push(Warning::Truncated {
            entry: label.into(),
            path: path.clone(),
            seconds: samples.len() as f32 / rate as f32,
            max_s: MAX_UNIT_S,
        });
        samples.truncate(max_len);
    }
    if entry.gain_db != 0.0 {
        let g = 10f32.powf(entry.gain_db / 20.0);
        samples.iter_mut().for_each(|s| *s *= g);
    }
    Ok(Some((
        Unit {
            cell,
            samples,
            file: entry.file.clone(),
        },
        entry.file,
    )))
}

/// Reads one friction entry (same conventions as [`load_unit`]).
fn load_spectrum(
    src: &dyn FileSource,
    value: &toml::Value,
    label: &str,
    bins: usize,
    warnings: &mut Vec<Warning>,
) -> Result<Option<(FrictionSpectrum, String)>, Option<String>> {
    let entry: FrictionEntry = match value.clone().try_into() {
        Ok(e) => e,
        Err(e) => {
            warnings.push(Warning::BadEntry {
                entry: label.into(),
                problem: e.to_string().trim().to_string(),
            });
            return Ok(None);
        }
    };
    let cell = match entry_cell(
        entry.kind == FrictionKind::Flat,
        entry.straight_cm,
        entry.curved_cm,
    ) {
        Ok(c) => c,
        Err(problem) => {
            warnings.push(Warning::BadEntry {
                entry: label.into(),
                problem,
            });
            return Ok(None);
        }
    };
    if !(entry.speed_m_s.is_finite() && entry.speed_m_s > 0.0 && entry.speed_m_s <= 10.0) {
        warnings.push(Warning::BadEntry {
            entry: label.into(),
            problem: format!("speed_m_s = {} must be in (0, 10] m/s", entry.speed_m_s),
        });
        return Ok(None);
    }
    if !cell.is_on_grid() {
        warnings.push(Warning::OffGrid {
            entry: label.into(),
            cell: cell.label(),
        });
    }
    let path = src.display_path(&entry.file);
    let bytes = match src.read(&entry.file) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            warnings.push(Warning::MissingFile {
                entry: label.into(),
                path,
            });
            return Err(None);
        }
        Err(e) => {
            warnings.push(Warning::BadSpectrum {
                entry: label.into(),
                path,
                problem: format!("cannot be read ({e})"),
            });
            return Err(Some(entry.file));
        }
    };
    if bytes.len() != 4 * bins {
        warnings.push(Warning::BadSpectrum {
            entry: label.into(),
            path,
            problem: format!(
                "has {} bytes, expected {} ({bins} little-endian f32 bins)",
                bytes.len(),
                4 * bins
            ),
        });
        return Err(Some(entry.file));
    }
    let magnitudes: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    if let Some(k) = magnitudes.iter().position(|m| !m.is_finite() || *m < 0.0) {
        warnings.push(Warning::BadSpectrum {
            entry: label.into(),
            path,
            problem: format!(
                "bin {k} is {} (magnitudes must be finite and ≥ 0)",
                magnitudes[k]
            ),
        });
        return Err(Some(entry.file));
    }
    if magnitudes.iter().all(|m| *m == 0.0) {
        warnings.push(Warning::BadSpectrum {
            entry: label.into(),
            path,
            problem: "is all zeros".into(),
        });
        return Err(Some(entry.file));
    }
    Ok(Some((
        FrictionSpectrum {
            cell,
            magnitudes,
            speed_m_s: entry.speed_m_s,
            file: entry.file.clone(),
        },
        entry.file,
    )))
}

fn coverage_warnings(db: &Database, warnings: &mut Vec<Warning>) {
    let parts: [(&'static str, Vec<Cell>, &'static str); 2] = [
        (
            "crumple",
            db.units.iter().map(|u| u.cell).collect(),
            "crumpling events will be silent",
        ),
        (
            "friction",
            db.spectra.iter().map(|s| s.cell).collect(),
            "sliding will be silent",
        ),
    ];
    for (what, cells, consequence) in parts {
        if cells.is_empty() {
            warnings.push(Warning::PartMissing { what, consequence });
            continue;
        }
        let mut missing = Vec::new();
        for s in GRID_CM {
            for c in GRID_CM {
                let cell = Cell::Free {
                    straight_cm: s,
                    curved_cm: c,
                };
                if !cells.iter().any(|x| x.same_as(&cell)) {
                    missing.push(cell.label());
                }
            }
        }
        if !missing.is_empty() {
            warnings.push(Warning::MissingCells {
                what,
                missing: missing.len(),
                examples: missing[..missing.len().min(5)].join(", "),
            });
        }
        if !cells.iter().any(Cell::is_constrained) {
            warnings.push(Warning::NoConstrained { what });
        }
    }
}

/// A database assembled in memory, loaded back through the validating loader (used by tests and
/// tools to check that what they write is readable).
pub fn reload(db: &Database) -> Result<(Database, Vec<Warning>), DbError> {
    let src = MemSource {
        label: db.info.name.clone(),
        files: db.to_files(),
    };
    load_from(&src, Path::new(&db.info.name))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Breakage detected: a subset that keeps units or spectra of rejected cells, drops those
    /// of accepted ones, ignores the spectrum cap, or loses the rate and description.
    #[test]
    fn subset_keeps_the_accepted_cells_only() {
        let full = crate::generate::generate(crate::generate::Material::Printer);
        let clac = |c: &Cell| c.is_constrained();
        let sub = full.subset(clac, 1);
        assert_eq!(sub.sample_rate_hz, full.sample_rate_hz);
        assert_eq!(sub.info.name, full.info.name);
        let clacs = full
            .units
            .iter()
            .filter(|u| u.cell.is_constrained())
            .count();
        assert!(clacs > 0 && clacs < full.units.len());
        assert_eq!(sub.units.len(), clacs);
        assert!(sub.units.iter().all(|u| u.cell.is_constrained()));
        assert_eq!(sub.spectra.len(), 1);
        assert!(sub.spectra[0].cell.is_constrained());
        assert_eq!(
            full.subset(|_| true, usize::MAX).spectra.len(),
            full.spectra.len()
        );
    }

    fn small_db() -> Database {
        let mut db = Database::new(
            DbInfo {
                name: "t".into(),
                ..DbInfo::default()
            },
            44_100,
        );
        let tone: Vec<f32> = (0..2000).map(|i| (i as f32 * 0.05).sin() * 0.3).collect();
        db.units.push(Unit {
            cell: Cell::Free {
                straight_cm: 10.0,
                curved_cm: 5.0,
            },
            samples: tone.clone(),
            file: String::new(),
        });
        db.units.push(Unit {
            cell: Cell::Constrained,
            samples: tone[..300].to_vec(),
            file: String::new(),
        });
        db.spectra.push(FrictionSpectrum {
            cell: Cell::Constrained,
            magnitudes: vec![0.01; crate::SPECTRUM_BINS],
            speed_m_s: 0.1,
            file: String::new(),
        });
        db
    }

    #[test]
    fn write_and_reload_round_trip() {
        let db = small_db();
        let (back, warnings) = reload(&db).unwrap();
        assert_eq!(back.units.len(), 2);
        assert_eq!(back.spectra.len(), 1);
        assert_eq!(back.spectra[0].magnitudes, db.spectra[0].magnitudes);
        for (a, b) in back.units[0].samples.iter().zip(&db.units[0].samples) {
            assert!((a - b).abs() <= 1.0 / 32767.0);
        }
        // The small database misses 80 crumple cells and 81 friction cells.
        assert!(warnings.iter().any(|w| matches!(
            w,
            Warning::MissingCells {
                what: "crumple",
                missing: 80,
                ..
            }
        )));
        assert!(warnings.iter().any(|w| matches!(
            w,
            Warning::MissingCells {
                what: "friction",
                missing: 81,
                ..
            }
        )));
        let packed = db.to_pack();
        let (p, _) = Database::from_pack(&packed, "pack").unwrap();
        assert_eq!(p.units.len(), 2);
    }

    #[test]
    fn bad_entries_are_skipped_with_precise_warnings() {
        let db = small_db();
        let mut files = db.to_files();
        let manifest = String::from_utf8(files["manifest.toml"].clone()).unwrap();
        let manifest = manifest
            + "\n[[crumple]]\nkind = \"flap\"\nstraight_cm = -3.0\ncurved_cm = 5.0\nfile = \"x.wav\"\n"
            + "\n[[crumple]]\nkind = \"flap\"\nfile = \"y.wav\"\n"
            + "\n[[crumple]]\nkind = \"wobble\"\nfile = \"z.wav\"\n"
            + "\n[[friction]]\nkind = \"free\"\nstraight_cm = 5.0\ncurved_cm = 5.0\nfile = \"friction/short.f32\"\n";
        files.insert("manifest.toml".into(), manifest.into_bytes());
        files.insert("friction/short.f32".into(), vec![0u8; 100]);
        let src = MemSource {
            label: "t".into(),
            files,
        };
        let (back, warnings) = load_from(&src, Path::new("t")).unwrap();
        assert_eq!(back.units.len(), 2);
        let text: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
        assert!(
            text.iter()
                .any(|t| t.contains("crumple[2]") && t.contains("-3"))
        );
        assert!(
            text.iter()
                .any(|t| t.contains("crumple[3]") && t.contains("straight_cm"))
        );
        assert!(
            text.iter()
                .any(|t| t.contains("crumple[4]") && t.contains("wobble"))
        );
        assert!(
            text.iter()
                .any(|t| t.contains("friction[1]") && t.contains("100 bytes"))
        );
    }
}
