//! # Building a database from your own recordings
//!
//! `cargo xtask sounddb import --recordings DIR --out DB` calls [`import_dir`]. Record like the
//! seeds did (T 1905–1909, S 210): one microphone about 1 m away, the same room and gain for all
//! takes, one paper type, and for friction one obstacle.
//!
//! ## What to record
//!
//! For a cell, cut a rectangle with a **straight edge** l_r and a **curved edge** l_c/2 (both on
//! the grid {2.5, 5, 7.5, 10, 12.5, 15, 20, 25, 30} cm if you can), and bend it along the curved
//! edge:
//!
//! - **flap**: hold both ends, bent by ~10 % compression (the ends of a 10 cm edge 9 cm apart),
//!   and twist to flip the curvature; several flips per file are fine — the file is cut at
//!   onsets, one unit per flip (up to [`ImportOptions::max_variants`] per cell);
//! - **friction**: keep the curved edges at ~30 % compression and slide the sheet on the obstacle,
//!   20 cm in 2 s (10 cm/s); the spectrum is averaged over the 200 ms in the middle of the
//!   slide (T 1909);
//! - **clac**: crumple a sheet and keep the short dry clicks (constrained sounds, cell (0, 0));
//! - **flat friction**: slide a flat sheet (constrained friction, cell (0, 0)).
//!
//! ## Naming scheme
//!
//! ```text
//! flap_s<straight>_c<curved>[_anything].wav       e.g. flap_s10_c5.wav, flap_s12p5_c7.5_take2.wav
//! friction_s<straight>_c<curved>[_anything].wav   e.g. friction_s20_c15.wav
//! clac[_anything].wav                             e.g. clac_01.wav
//! friction_flat[_anything].wav                    e.g. friction_flat.wav
//! ```
//!
//! Lengths are in cm; `p` may replace the decimal point (`12p5` = 12.5). `curved` is the length
//! of ONE curved edge (l_c/2), `straight` is l_r (see the crate docs for why). Names are
//! case-insensitive. Files that match no pattern are reported and skipped unless annotated.
//!
//! ## Annotation file (optional)
//!
//! `annotations.toml` in the recordings folder overrides or completes the names:
//!
//! ```toml
//! [[recording]]
//! file = "take3.wav"
//! kind = "flap"          # flap | clac | friction | friction_flat
//! straight_cm = 10.0     # flap / friction
//! curved_cm = 5.0        # flap / friction
//! speed_m_s = 0.12       # friction only (default 0.10, the seeds' 10 cm/s)
//! ```
//!
//! ## Processing
//!
//! - Multi-channel files are averaged to mono; every unit is resampled to the database rate
//!   ([`ImportOptions::rate_hz`], 44.1 kHz by default).
//! - **Onsets** (flap, clac): 2 ms RMS frames (1 ms hop); an onset is a frame ≥ 20 dB above the
//!   file's noise floor (10th percentile) and ≥ 12 dB above the minimum of the previous 10 ms, at
//!   least 60 ms (flap) / 15 ms (clac) after the previous onset so that the sub-bursts of one flip
//!   stay in one unit. A unit runs from 1 ms before its onset to the next onset or the maximum
//!   length (0.8 s flap, 0.2 s clac), cut where its envelope stays below max(peak − 60 dB,
//!   floor + 6 dB); 0.5 ms fade-in, 5 ms fade-out; units under 10 ms or quieter than −50 dBFS are
//!   dropped.
//! - **Friction**: the active part of the file is the longest run of frames ≥ 10 dB above the
//!   noise floor; the spectrum is the power average of Hann frames over its middle 200 ms
//!   ([`crate::analysis::band_rms_spectrum`], frames of up to 4096 samples), put onto the
//!   database's 2048 bins. A slide whose active part is shorter than 200 ms is rejected.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::analysis::band_rms_spectrum;
use crate::cell::Cell;
use crate::database::{Database, DbInfo, FrictionSpectrum, Unit};
use crate::resample::{Resampler, spectrum_band_power};
use crate::wav;

/// Name of the optional annotation file.
pub const ANNOTATIONS_FILE: &str = "annotations.toml";
/// Length of the friction analysis window, s (T 1909).
pub const FRICTION_WINDOW_S: f64 = 0.200;

/// What a recording holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RecordingKind {
    /// Flips of a bent sheet (free crumple units).
    Flap,
    /// Constrained clicks (cell (0, 0) crumple units).
    Clac,
    /// A slide of a bent sheet (free friction spectrum).
    Friction,
    /// A slide of a flat sheet (constrained friction spectrum).
    FrictionFlat,
}

/// A recording and its annotation.
#[derive(Clone, Debug, PartialEq)]
pub struct Recording {
    /// The WAV file.
    pub path: PathBuf,
    /// What it holds.
    pub kind: RecordingKind,
    /// Its cell.
    pub cell: Cell,
    /// Slide speed, m/s (friction).
    pub speed_m_s: f32,
}

/// Import settings.
#[derive(Clone, Debug)]
pub struct ImportOptions {
    /// Rate of the database, Hz.
    pub rate_hz: u32,
    /// Database name.
    pub name: String,
    /// Paper type (free text).
    pub material: String,
    /// Obstacle of the friction recordings (free text).
    pub obstacle: String,
    /// Most flap/clac units kept per cell.
    pub max_variants: usize,
}

impl Default for ImportOptions {
    fn default() -> Self {
        Self {
            rate_hz: crate::DEFAULT_SAMPLE_RATE_HZ,
            name: "my paper (recorded)".into(),
            material: String::new(),
            obstacle: String::new(),
            max_variants: 8,
        }
    }
}

/// Why an import failed as a whole.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// The recordings folder cannot be read.
    #[error("cannot read recordings folder {path}: {source}")]
    Io {
        /// The folder.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// `annotations.toml` is malformed.
    #[error("{path}: {message}")]
    Annotations {
        /// The file.
        path: PathBuf,
        /// Parser message.
        message: String,
    },
    /// Nothing usable was found.
    #[error(
        "no usable recording in {path} ({skipped} files skipped; see the notes). Name files like flap_s10_c5.wav, friction_s10_c5.wav, clac.wav, friction_flat.wav or list them in annotations.toml"
    )]
    Nothing {
        /// The folder.
        path: PathBuf,
        /// Files skipped.
        skipped: usize,
    },
}

/// What the import did, file by file.
#[derive(Clone, Debug, Default)]
pub struct ImportReport {
    /// One line per file processed or skipped.
    pub notes: Vec<String>,
    /// Number of files skipped.
    pub skipped: usize,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AnnotationFile {
    #[serde(default)]
    recording: Vec<Annotation>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Annotation {
    file: String,
    kind: RecordingKind,
    straight_cm: Option<f32>,
    curved_cm: Option<f32>,
    speed_m_s: Option<f32>,
}

fn parse_len(s: &str) -> Option<f32> {
    let v: f32 = s.replace('p', ".").parse().ok()?;
    (v.is_finite() && v > 0.0 && v <= crate::database::MAX_LENGTH_CM).then_some(v)
}

/// Parses a file name of the naming scheme (see the module docs) into (kind, cell).
pub fn parse_name(file_name: &str) -> Result<(RecordingKind, Cell), String> {
    let lower = file_name.to_ascii_lowercase();
    let stem = lower
        .strip_suffix(".wav")
        .ok_or_else(|| "not a .wav file".to_string())?;
    let parts: Vec<&str> = stem.split('_').collect();
    let cell_from = |parts: &[&str]| -> Result<Cell, String> {
        let s = parts
            .first()
            .and_then(|p| p.strip_prefix('s'))
            .and_then(parse_len);
        let c = parts
            .get(1)
            .and_then(|p| p.strip_prefix('c'))
            .and_then(parse_len);
        match (s, c) {
            (Some(straight_cm), Some(curved_cm)) => Ok(Cell::Free {
                straight_cm,
                curved_cm,
            }),
            _ => Err(
                "expected _s<straight cm>_c<curved cm> after the kind (e.g. flap_s10_c5.wav)"
                    .into(),
            ),
        }
    };
    match parts.first().copied() {
        Some("clac") => Ok((RecordingKind::Clac, Cell::Constrained)),
        Some("flap") => Ok((RecordingKind::Flap, cell_from(&parts[1..])?)),
        Some("friction") if parts.get(1) == Some(&"flat") => {
            Ok((RecordingKind::FrictionFlat, Cell::Constrained))
        }
        Some("friction") => Ok((RecordingKind::Friction, cell_from(&parts[1..])?)),
        _ => Err("name starts with none of flap_, friction_, clac, friction_flat".into()),
    }
}

/// Lists the recordings of a folder: annotated files first, then files named by the scheme.
pub fn scan(dir: &Path, report: &mut ImportReport) -> Result<Vec<Recording>, ImportError> {
    let io = |e| ImportError::Io {
        path: dir.to_path_buf(),
        source: e,
    };
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map_err(io)?
        .flatten()
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .map(|e| e.file_name().to_string_lossy().to_string())
        .collect();
    names.sort();
    let mut out = Vec::new();
    let ann_path = dir.join(ANNOTATIONS_FILE);
    let mut annotated: Vec<String> = Vec::new();
    if ann_path.is_file() {
        let text = std::fs::read_to_string(&ann_path).map_err(|e| ImportError::Io {
            path: ann_path.clone(),
            source: e,
        })?;
        let file: AnnotationFile = toml::from_str(&text).map_err(|e| ImportError::Annotations {
            path: ann_path.clone(),
            message: e.to_string(),
        })?;
        for (i, a) in file.recording.into_iter().enumerate() {
            let constrained = matches!(a.kind, RecordingKind::Clac | RecordingKind::FrictionFlat);
            let cell = if constrained {
                Cell::Constrained
            } else {
                match (a.straight_cm, a.curved_cm) {
                    (Some(s), Some(c))
                        if parse_len(&s.to_string()).is_some()
                            && parse_len(&c.to_string()).is_some() =>
                    {
                        Cell::Free {
                            straight_cm: s,
                            curved_cm: c,
                        }
                    }
                    _ => {
                        report.notes.push(format!(
                            "annotations.toml recording[{i}] ({}): flap/friction need straight_cm and curved_cm in (0, 100]; skipped",
                            a.file
                        ));
                        report.skipped += 1;
                        annotated.push(a.file.to_ascii_lowercase());
                        continue;
                    }
                }
            };
            let speed = a.speed_m_s.unwrap_or(crate::REFERENCE_SLIDE_SPEED_M_S);
            if !(speed.is_finite() && speed > 0.0 && speed <= 10.0) {
                report.notes.push(format!(
                    "annotations.toml recording[{i}] ({}): speed_m_s = {speed} must be in (0, 10]; skipped",
                    a.file
                ));
                report.skipped += 1;
                annotated.push(a.file.to_ascii_lowercase());
                continue;
            }
            annotated.push(a.file.to_ascii_lowercase());
            out.push(Recording {
                path: dir.join(&a.file),
                kind: a.kind,
                cell,
                speed_m_s: speed,
            });
        }
    }
    for name in names {
        let lower = name.to_ascii_lowercase();
        if lower == ANNOTATIONS_FILE || annotated.contains(&lower) {
            continue;
        }
        if !lower.ends_with(".wav") {
            continue;
        }
        match parse_name(&name) {
            Ok((kind, cell)) => out.push(Recording {
                path: dir.join(&name),
                kind,
                cell,
                speed_m_s: crate::REFERENCE_SLIDE_SPEED_M_S,
            }),
            Err(why) => {
                report.notes.push(format!("{name}: {why}; skipped"));
                report.skipped += 1;
            }
        }
    }
    Ok(out)
}

/// Short-term energy envelope: RMS² of 2 ms frames every 1 ms, in dB, and the frame hop.
fn envelope_db(x: &[f32], rate: f64) -> (Vec<f64>, usize) {
    let hop = ((0.001 * rate) as usize).max(1);
    let len = 2 * hop;
    let mut out = Vec::with_capacity(x.len() / hop + 1);
    let mut start = 0;
    while start < x.len() {
        let end = (start + len).min(x.len());
        let e: f64 = x[start..end]
            .iter()
            .map(|v| f64::from(*v).powi(2))
            .sum::<f64>()
            / (end - start) as f64;
        out.push(10.0 * e.max(1e-20).log10());
        start += hop;
    }
    (out, hop)
}

fn percentile(v: &[f64], p: f64) -> f64 {
    if v.is_empty() {
        return -200.0;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[((s.len() - 1) as f64 * p) as usize]
}

/// Cuts a recording into units at onsets (see the module docs). Returns sample ranges.
pub fn segment_onsets(x: &[f32], rate: f64, kind: RecordingKind) -> Vec<std::ops::Range<usize>> {
    let (env, hop) = envelope_db(x, rate);
    if env.is_empty() {
        return Vec::new();
    }
    let floor = percentile(&env, 0.10);
    let (refractory_ms, max_len_s) = match kind {
        RecordingKind::Clac => (15usize, 0.2),
        _ => (60usize, 0.8),
    };
    let mut onsets = Vec::new();
    let mut last: Option<usize> = None;
    for i in 0..env.len() {
        let lo = i.saturating_sub(10);
        let prev_min = env[lo..i].iter().copied().fold(f64::INFINITY, f64::min);
        let rise = if i == 0 {
            env[0] - floor
        } else {
            env[i] - prev_min
        };
        if env[i] >= floor + 20.0
            && env[i] > -60.0
            && rise >= 12.0
            && last.is_none_or(|l| i >= l + refractory_ms)
        {
            onsets.push(i);
            last = Some(i);
        }
    }
    let max_len = (max_len_s * rate) as usize;
    let mut out = Vec::new();
    for (k, &o) in onsets.iter().enumerate() {
        let start = (o * hop).saturating_sub(hop);
        let next = onsets
            .get(k + 1)
            .map_or(x.len(), |&n| (n * hop).saturating_sub(hop));
        let mut end = next.min(start + max_len).min(x.len());
        let seg = &x[start..end];
        let peak = seg.iter().fold(0.0f32, |m, v| m.max(v.abs()));
        if peak < 10f32.powf(-50.0 / 20.0) {
            continue;
        }
        // Cut where the envelope stays below max(peak − 60 dB, floor + 6 dB).
        let peak_db = 20.0 * f64::from(peak).log10();
        let gate = (peak_db - 60.0).max(floor + 6.0);
        let first_frame = start / hop;
        let last_frame = (end / hop).min(env.len());
        if let Some(lf) = (first_frame..last_frame).rev().find(|&f| env[f] > gate) {
            end = end.min((lf + 2) * hop).max(start + 1);
        }
        if end - start >= (0.010 * rate) as usize {
            out.push(start..end);
        }
    }
    out
}

fn fade(unit: &mut [f32], rate: f64) {
    let n = unit.len();
    let fin = ((0.0005 * rate) as usize).min(n / 2);
    let fout = ((0.005 * rate) as usize).min(n / 2);
    for (i, u) in unit.iter_mut().enumerate().take(fin) {
        *u *= (i as f32 + 0.5) / fin as f32;
    }
    for i in 0..fout {
        let t = (i as f32 + 0.5) / fout as f32;
        unit[n - fout + i] *= 0.5 + 0.5 * (std::f32::consts::PI * t).cos();
    }
}

/// The friction spectrum of a slide recording, on `bins` bins for a database at `db_rate` Hz.
pub fn friction_spectrum(
    x: &[f32],
    rate: f64,
    bins: usize,
    db_rate: f64,
) -> Result<Vec<f32>, String> {
    let (env, hop) = envelope_db(x, rate);
    let floor = percentile(&env, 0.10);
    let gate = floor + 10.0;
    let (mut best, mut run_start) = ((0usize, 0usize), None::<usize>);
    for (i, &e) in env
        .iter()
        .chain(std::iter::once(&f64::NEG_INFINITY))
        .enumerate()
    {
        match (e >= gate && e > -70.0, run_start) {
            (true, None) => run_start = Some(i),
            (false, Some(s)) => {
                if i - s > best.1 - best.0 {
                    best = (s, i);
                }
                run_start = None;
            }
            _ => {}
        }
    }
    let active = (best.0 * hop, (best.1 * hop).min(x.len()));
    let window = (FRICTION_WINDOW_S * rate) as usize;
    if active.1 - active.0 < window {
        return Err(format!(
            "the slide is {:.0} ms long above the noise floor; at least {:.0} ms are needed",
            (active.1 - active.0) as f64 / rate * 1000.0,
            FRICTION_WINDOW_S * 1000.0
        ));
    }
    let mid = (active.0 + active.1) / 2;
    let seg = &x[mid - window / 2..mid - window / 2 + window];
    // Frames of up to 4096 samples that fit the window.
    let mut n = 4096usize;
    while n > window && n > 64 {
        n /= 2;
    }
    let rec_bins = n / 2;
    let spec = band_rms_spectrum(seg, rate, rec_bins);
    let src_df = rate / n as f64;
    let dst_df = db_rate / (2.0 * bins as f64);
    let power = spectrum_band_power(&spec, src_df, bins, dst_df);
    Ok(power.iter().map(|p| p.sqrt() as f32).collect())
}

/// Builds a database from a folder of recordings (see the module docs).
pub fn import_dir(
    dir: &Path,
    opts: &ImportOptions,
) -> Result<(Database, ImportReport), ImportError> {
    let mut report = ImportReport::default();
    let recordings = scan(dir, &mut report)?;
    let mut db = Database::new(
        DbInfo {
            name: opts.name.clone(),
            material: opts.material.clone(),
            obstacle: opts.obstacle.clone(),
            synthesized: false,
            description: format!(
                "Imported by `cargo xtask sounddb import` from {}",
                dir.display()
            ),
            seed: None,
        },
        opts.rate_hz,
    );
    let db_rate = f64::from(opts.rate_hz);
    for rec in recordings {
        let name = rec.path.file_name().map_or_else(
            || rec.path.display().to_string(),
            |n| n.to_string_lossy().to_string(),
        );
        let decoded = match std::fs::read(&rec.path)
            .map_err(|e| e.to_string())
            .and_then(|b| wav::decode(&b))
        {
            Ok(d) => d,
            Err(e) => {
                report
                    .notes
                    .push(format!("{name}: cannot read ({e}); skipped"));
                report.skipped += 1;
                continue;
            }
        };
        let rate = f64::from(decoded.sample_rate_hz);
        match rec.kind {
            RecordingKind::Flap | RecordingKind::Clac => {
                let existing = db
                    .units
                    .iter()
                    .filter(|u| u.cell.same_as(&rec.cell))
                    .count();
                let room = opts.max_variants.saturating_sub(existing);
                let segments = segment_onsets(&decoded.samples, rate, rec.kind);
                let resampler =
                    (decoded.sample_rate_hz != opts.rate_hz).then(|| Resampler::new(rate, db_rate));
                let mut kept = 0;
                for seg in segments.iter().take(room) {
                    let raw = &decoded.samples[seg.clone()];
                    let mut unit = match &resampler {
                        Some(r) => r.process(raw),
                        None => raw.to_vec(),
                    };
                    fade(&mut unit, db_rate);
                    db.units.push(Unit {
                        cell: rec.cell,
                        samples: unit,
                        file: String::new(),
                    });
                    kept += 1;
                }
                if kept == 0 {
                    report.notes.push(format!(
                        "{name}: no onset found (quieter than −50 dBFS or no 20 dB rise above the noise floor); skipped"
                    ));
                    report.skipped += 1;
                } else {
                    report.notes.push(format!(
                        "{name}: {kept} unit(s) for cell {} ({} onsets found)",
                        rec.cell.label(),
                        segments.len()
                    ));
                }
            }
            RecordingKind::Friction | RecordingKind::FrictionFlat => {
                if db.spectra.iter().any(|s| s.cell.same_as(&rec.cell)) {
                    report.notes.push(format!(
                        "{name}: cell {} already has a friction spectrum; skipped",
                        rec.cell.label()
                    ));
                    report.skipped += 1;
                    continue;
                }
                match friction_spectrum(&decoded.samples, rate, db.spectrum_bins, db_rate) {
                    Ok(magnitudes) => {
                        db.spectra.push(FrictionSpectrum {
                            cell: rec.cell,
                            magnitudes,
                            speed_m_s: rec.speed_m_s,
                            file: String::new(),
                        });
                        report.notes.push(format!(
                            "{name}: friction spectrum for cell {} (slide at {} m/s)",
                            rec.cell.label(),
                            rec.speed_m_s
                        ));
                    }
                    Err(e) => {
                        report.notes.push(format!("{name}: {e}; skipped"));
                        report.skipped += 1;
                    }
                }
            }
        }
    }
    if db.units.is_empty() && db.spectra.is_empty() {
        return Err(ImportError::Nothing {
            path: dir.to_path_buf(),
            skipped: report.skipped,
        });
    }
    Ok((db, report))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        assert_eq!(
            parse_name("flap_s10_c5.wav").unwrap(),
            (
                RecordingKind::Flap,
                Cell::Free {
                    straight_cm: 10.0,
                    curved_cm: 5.0
                }
            )
        );
        assert_eq!(
            parse_name("Friction_S12p5_C7.5_take2.WAV").unwrap(),
            (
                RecordingKind::Friction,
                Cell::Free {
                    straight_cm: 12.5,
                    curved_cm: 7.5
                }
            )
        );
        assert_eq!(parse_name("clac_03.wav").unwrap().0, RecordingKind::Clac);
        assert_eq!(
            parse_name("friction_flat.wav").unwrap(),
            (RecordingKind::FrictionFlat, Cell::Constrained)
        );
        assert!(parse_name("flap_10_5.wav").is_err());
        assert!(parse_name("flap_s0_c5.wav").is_err());
        assert!(parse_name("snare.wav").is_err());
        assert!(parse_name("flap_s10_c5.mp3").is_err());
    }

    fn noise(n: usize, seed: &mut u64) -> Vec<f32> {
        (0..n)
            .map(|_| {
                *seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((*seed >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 2.0
            })
            .collect()
    }

    #[test]
    fn onsets_of_three_flips() {
        let rate = 44_100.0;
        let mut seed = 3;
        let mut x: Vec<f32> = noise(3 * 44_100, &mut seed)
            .iter()
            .map(|v| v * 1e-4)
            .collect();
        for &t in &[0.3, 1.1, 2.0] {
            let start = (t * rate) as usize;
            let burst = noise(8000, &mut seed);
            for (i, b) in burst.iter().enumerate() {
                x[start + i] += b * 0.5 * (-(i as f32) / 800.0).exp();
            }
        }
        let segs = segment_onsets(&x, rate, RecordingKind::Flap);
        assert_eq!(segs.len(), 3, "{segs:?}");
        for (s, t) in segs.iter().zip([0.3, 1.1, 2.0]) {
            let onset = (t * rate) as usize;
            assert!(
                s.start <= onset && onset - s.start < 150,
                "{s:?} vs {onset}"
            );
            assert!(s.end - s.start < (0.8 * rate) as usize);
        }
    }

    /// Power of a database spectrum (2048 bins over 0–22.05 kHz) within `±half_width_hz` of
    /// `f_hz`.
    fn band_power(s: &[f32], f_hz: f64, half_width_hz: f64) -> f64 {
        let df = 44_100.0 / (2.0 * s.len() as f64);
        s.iter()
            .enumerate()
            .filter(|(k, _)| (*k as f64 * df - f_hz).abs() <= half_width_hz)
            .map(|(_, v)| f64::from(*v).powi(2))
            .sum()
    }

    /// The friction spectrum is the power average over the 200 ms in the middle of the slide
    /// (T 1909), at the recording's level. A 2 s slide (between silences) whose first 100 ms of
    /// the middle 200 ms is a 1 kHz tone, whose next 100 ms is a 2.5 kHz tone and whose rest is a
    /// 6 kHz tone must give a spectrum peaking at 1 or 2.5 kHz with those two tones equally
    /// strong and almost nothing at 6 kHz. Detects a window not centred on the slide (one tone
    /// would dominate), longer than ~200 ms or over the whole slide (6 kHz would dominate), at
    /// the start or end of the file; a noise slide checks the level and that a slide shorter
    /// than 200 ms is refused.
    #[test]
    fn friction_window_in_the_middle() {
        let rate = 48_000.0;
        // A tone slide: 0.5 s of silence, 2 s of tones, 0.5 s of silence.
        let (f_a, f_b, f_edge) = (1_000.0, 2_500.0, 6_000.0);
        let (start, len) = (24_000usize, 96_000usize);
        let centre = start + len / 2;
        let tenth = 4_800usize; // 100 ms
        let mut tones = vec![0.0f32; 3 * 48_000];
        for (i, v) in tones.iter_mut().enumerate().skip(start).take(len) {
            let f = if (centre - tenth..centre).contains(&i) {
                f_a
            } else if (centre..centre + tenth).contains(&i) {
                f_b
            } else {
                f_edge
            };
            *v = 0.1 * (2.0 * std::f64::consts::PI * f * i as f64 / rate).sin() as f32;
        }
        let s = friction_spectrum(&tones, rate, 2048, 44_100.0).unwrap();
        let total: f64 = s.iter().map(|v| f64::from(*v).powi(2)).sum();
        let (p_a, p_b, p_edge) = (
            band_power(&s, f_a, 100.0),
            band_power(&s, f_b, 100.0),
            band_power(&s, f_edge, 100.0),
        );
        let df = 44_100.0 / 4096.0;
        let peak_hz = s
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .unwrap()
            .0 as f64
            * df;
        eprintln!(
            "tone slide: peak {peak_hz:.0} Hz; power at 1 kHz {:.3}, 2.5 kHz {:.3}, 6 kHz {:.4} \
             of {total:.2e}",
            p_a / total,
            p_b / total,
            p_edge / total
        );
        assert!(
            (peak_hz - f_a).abs() < 30.0 || (peak_hz - f_b).abs() < 30.0,
            "peak at {peak_hz} Hz"
        );
        assert!(
            p_edge < 0.02 * total,
            "the edges of the slide leak in: {:.3} of the power at 6 kHz",
            p_edge / total
        );
        // The Hann frames that fit the window leave its last 8 ms out, so the first half weighs
        // ~1.15 × the second; a window 10 ms off centre moves the ratio out of [0.7, 1.4].
        assert!(
            p_a + p_b > 0.9 * total && p_a < 1.4 * p_b && p_b < 1.4 * p_a,
            "the window is not centred on the middle: 1 kHz {p_a:.3e}, 2.5 kHz {p_b:.3e}"
        );
        // A sine of amplitude 0.1 has power 0.005.
        assert!((total / 0.005 - 1.0).abs() < 0.15, "{total}");

        // A noise slide: the level.
        let mut seed = 9;
        let mut x = vec![0.0f32; 3 * 48_000];
        let slide = noise(2 * 48_000, &mut seed);
        for (i, v) in slide.iter().enumerate() {
            x[24_000 + i] = v * 0.1;
        }
        let s = friction_spectrum(&x, rate, 2048, 44_100.0).unwrap();
        assert_eq!(s.len(), 2048);
        // Uniform noise of amplitude 0.1: variance 0.01/3, spread over 0–24 kHz; the database
        // covers 0–22.05 kHz.
        let total: f64 = s.iter().map(|v| f64::from(*v).powi(2)).sum();
        let expect = 0.01 / 3.0 * 22_050.0 / 24_000.0;
        assert!((total / expect - 1.0).abs() < 0.15, "{total} vs {expect}");
        let short = &x[..24_000 + 4_000];
        assert!(friction_spectrum(short, rate, 2048, 44_100.0).is_err());
    }
}
