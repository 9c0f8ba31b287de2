//! # A database prepared for one sample rate
//!
//! [`SoundDb`] is what a renderer holds (in an `Arc`): immutable, at the host rate, indexed for
//! allocation-free lookups. Preparing it ([`SoundDb::prepare`]) allocates and may take a fraction
//! of a second (resampling), so it runs off the audio thread — at plugin activation, on a loader
//! thread, or in offline tools.
//!
//! What preparation does:
//!
//! - **Units** are resampled to the unit rate ([`crate::resample`]): the host rate up to 88 kHz,
//!   half of it up to 176 kHz and a quarter above ([`unit_decimation`], next section); their
//!   trailing samples below
//!   −90 dB of the unit's peak are trimmed (digest-sound §11.9: "free clac voices as soon as the
//!   envelope is below −90 dB"), and they are stored as **16-bit integers with a per-unit scale**
//!   (2 bytes/sample: the printer database takes ≈ 8 MB at 44.1 kHz instead of 16 MB as f32;
//!   quantisation noise is 96 dB under each unit's peak). Each unit is surrounded by
//!   [`UNIT_PAD`] zeros so that 4-tap fractional-delay reads need no bounds checks near its ends.
//! - **Friction spectra** are moved onto the bins of the render path's real inverse FFT of size
//!   M = [`friction_frame_len`] (M/2 + 1 bins at j·fs/M), as `sqrt(P_j / 2)` where P_j is the
//!   power of the band (see [`crate::resample::spectrum_band_power`]). With random phases, the
//!   un-normalised real iFFT then has per-sample variance 2·Σ_j |X_j|² = Σ_j P_j, i.e. exactly the
//!   database's power spectral density, independent of M and fs. The DC and Nyquist bins are 0
//!   (they must be real; friction has no content there). Each spectrum is divided by its slide
//!   speed so that a source sliding at speed v is weighted v / v_recorded (S 153, T 1909).
//!
//! ## Friction frame length at other rates
//!
//! The seeds use M = 2048 samples (≈ 46 ms) with hop 1024 at 44.1 kHz (T 1903, T 1830). We keep
//! the frame at 7/150 s = 46.67 ms ± 2 % at every rate — the even length closest to fs · 7/150
//! whose only prime factors are 2, 3, 5, 7 (mixed-radix FFTs stay fast): 44.1 kHz → 2058,
//! 48 kHz → 2240, 88.2 kHz → 4116, 96 kHz → 4480, 176.4 kHz → 8232, 192 kHz → 8960, all exactly
//! 46.67 ms; 8 kHz → 378 (47.3 ms; hop 189), 22.05 kHz → 1024 (46.4 ms). The hop is M/2.
//! Decision: 7/150 s and not the seeds' 2048/44 100 s (0.5 % shorter), because at the common
//! rates the frames then have the same duration, their bins the same frequencies (21.43 Hz
//! apart) and their hops the same times: a friction source gets the same random-phase frames at
//! 44.1 and 48 kHz, so the two renders agree band by band (with 2048 at 44.1 kHz the hop grid
//! drifted 0.5 % against 48 kHz's and the short friction bursts of a crumple differed by up to
//! 1.5 dB in the 80 Hz band: docs/decisions.md, "One take at every sample rate").
//!
//! ## Units at a reduced rate above 88 kHz
//!
//! A crumple voice costs a few multiply-adds per tap and output sample, so at 96 kHz the voices
//! cost twice what they cost at 48 kHz for sound that has nothing above 22 kHz: the embedded
//! database is recorded at 44.1 kHz (and an imported one rarely has anything audible above
//! 20 kHz). So from 88 kHz on, units are stored at fs/2, from 176 kHz on at fs/4
//! ([`unit_decimation`]; 88.2 → 44.1, 96 → 48, 176.4 → 44.1, 192 → 48 kHz), the renderer plays
//! its voices at that rate and interpolates their sum to the host rate once (the renderer's
//! `voice_bus`). Content of an imported database above the unit rate's Nyquist frequency is
//! dropped (a band limit of ≈ 20 kHz, said in the README). Friction spectra stay at the host
//! rate: the friction noise is made at the host rate directly.

mod image;

use crate::cell::{Cell, CellIndex};
use crate::database::{Database, DbInfo, FrictionSpectrum};
use crate::resample::{Resampler, spectrum_band_power};
use crate::{DbError, Warning};

/// Duration of a friction iFFT frame, seconds (module docs: the same at 44.1 and 48 kHz).
pub const FRICTION_FRAME_S: f64 = 7.0 / 150.0;

/// Zeros stored before and after each prepared unit.
pub const UNIT_PAD: usize = 4;

/// Friction iFFT frame length M for a sample rate (see the module docs): the even, 7-smooth
/// (factors 2, 3, 5, 7 only — fast mixed-radix FFTs) length closest to fs · 7/150 s.
pub fn friction_frame_len(sample_rate_hz: f64) -> usize {
    let rate = if sample_rate_hz.is_finite() && sample_rate_hz > 0.0 {
        sample_rate_hz
    } else {
        44_100.0
    };
    let target = (rate * FRICTION_FRAME_S).clamp(256.0, 16_384.0);
    let smooth = |mut n: usize| {
        for p in [2, 3, 5, 7] {
            while n.is_multiple_of(p) {
                n /= p;
            }
        }
        n == 1
    };
    let mut best = 2048usize;
    let mut best_err = f64::INFINITY;
    let lo = (target * 0.9) as usize & !1;
    let hi = (target * 1.1) as usize + 2;
    for n in (lo.max(2)..=hi).step_by(2) {
        let err = (n as f64 / target).ln().abs();
        if smooth(n) && err < best_err {
            best = n;
            best_err = err;
        }
    }
    best
}

/// Below this host rate units are stored at the host rate; [`unit_decimation`].
pub const HALF_RATE_UNITS_FROM_HZ: f64 = 88_000.0;

/// By how much units are stored below the host rate (1, 2 or 4; see the module docs): 1 below
/// 88 kHz, 2 below 176 kHz, 4 from there on. Non-finite or non-positive rates give 1.
pub fn unit_decimation(sample_rate_hz: f64) -> usize {
    if !(sample_rate_hz.is_finite() && sample_rate_hz >= HALF_RATE_UNITS_FROM_HZ) {
        1
    } else if sample_rate_hz < 2.0 * HALF_RATE_UNITS_FROM_HZ {
        2
    } else {
        4
    }
}

/// The unit rate of a host rate: the rate a prepared database's units are stored and played at
/// (the host rate / [`unit_decimation`]).
pub fn unit_rate_of(sample_rate_hz: f64) -> f64 {
    sample_rate_hz / unit_decimation(sample_rate_hz) as f64
}

/// Index of a cell in a prepared database (crumple or friction list).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CellId(pub u16);

/// A crumple unit at the unit rate ([`SoundDb::unit_rate_hz`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreparedUnit {
    /// Index in the PCM store of the first real sample ([`UNIT_PAD`] zeros precede it).
    pub offset: usize,
    /// Number of samples (after trimming).
    pub len: usize,
    /// f32 value = i16 value × scale.
    pub scale: f32,
    /// Peak absolute value (f32 units).
    pub peak: f32,
}

/// A crumple cell and its variants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrumpleCell {
    /// The cell.
    pub cell: Cell,
    /// First unit of the cell in [`SoundDb::unit`] numbering.
    pub first_unit: u32,
    /// Number of variants.
    pub num_units: u32,
    /// Radius of the recorded sheet's equivalent disk (a_ref), metres; `None` for (0, 0).
    pub reference_radius_m: Option<f32>,
}

/// A friction cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionCell {
    /// The cell.
    pub cell: Cell,
    /// a_ref, metres; `None` for (0, 0).
    pub reference_radius_m: Option<f32>,
}

/// Statistics of a preparation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PrepareStats {
    /// Samples removed by the −90 dB tail trim.
    pub trimmed_samples: usize,
    /// Units whose rate was converted.
    pub resampled_units: usize,
}

/// The units of a prepared database: what depends on the unit rate only
/// ([`SoundDb::unit_rate_hz`]), not on the host rate.
#[derive(Clone, Debug, Default, PartialEq)]
struct PreparedUnits {
    pcm: Vec<i16>,
    units: Vec<PreparedUnit>,
    crumple_cells: Vec<CrumpleCell>,
    stats: PrepareStats,
}

/// A database prepared for one sample rate (see the module docs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SoundDb {
    /// 0 for the empty database (usable at any rate).
    sample_rate_hz: f64,
    frame_len: usize,
    info: DbInfo,
    pcm: Vec<i16>,
    units: Vec<PreparedUnit>,
    crumple_cells: Vec<CrumpleCell>,
    crumple_index: CellIndex,
    friction_cells: Vec<FrictionCell>,
    friction_index: CellIndex,
    /// friction_cells.len() × bins, already scaled for the un-normalised real iFFT.
    spectra: Vec<f32>,
    /// Bins below the highest non-zero bin of any spectrum, + 1.
    spectra_active_bins: usize,
    stats: PrepareStats,
}

impl SoundDb {
    /// A database with no units and no spectra (renders silence at any rate).
    pub fn empty() -> Self {
        Self::default()
    }

    /// Loads a database folder and prepares it for `sample_rate_hz` (allocates; off the audio
    /// thread).
    pub fn load(
        dir: &std::path::Path,
        sample_rate_hz: f64,
    ) -> Result<(SoundDb, Vec<Warning>), DbError> {
        let (db, warnings) = Database::load(dir)?;
        Ok((Self::prepare(&db, sample_rate_hz), warnings))
    }

    /// Prepares `db` for `sample_rate_hz` (see the module docs).
    pub fn prepare(db: &Database, sample_rate_hz: f64) -> SoundDb {
        let rate = if sample_rate_hz.is_finite() && sample_rate_hz > 0.0 {
            sample_rate_hz
        } else {
            44_100.0
        };
        let frame_len = friction_frame_len(rate);
        let bins = frame_len / 2 + 1;
        let mut stats = PrepareStats::default();

        // Units grouped by cell, cells in order of first appearance.
        let mut crumple_cells: Vec<CrumpleCell> = Vec::new();
        let mut order: Vec<Vec<usize>> = Vec::new();
        for (i, u) in db.units.iter().enumerate() {
            match crumple_cells.iter().position(|c| c.cell.same_as(&u.cell)) {
                Some(k) => order[k].push(i),
                None => {
                    crumple_cells.push(CrumpleCell {
                        cell: u.cell,
                        first_unit: 0,
                        num_units: 0,
                        reference_radius_m: u.cell.reference_radius_m(),
                    });
                    order.push(vec![i]);
                }
            }
        }
        let unit_rate = rate / unit_decimation(rate) as f64;
        let resampler = (f64::from(db.sample_rate_hz) != unit_rate)
            .then(|| Resampler::new(f64::from(db.sample_rate_hz), unit_rate));
        // Spectra on one thread, the units on the others (each unit on its own: the same
        // result whatever the threads).
        let (quantized, (friction_cells, spectra)) = std::thread::scope(|scope| {
            let spectra = || {
                friction_spectra(
                    &db.spectra,
                    db.spectrum_rate_hz,
                    db.spectrum_bins,
                    bins,
                    rate / frame_len as f64,
                )
            };
            let handle = scope.spawn(spectra);
            let quantized = quantize_units(resampler.as_ref(), &db.units);
            let spectra = handle.join().unwrap_or_else(|_| spectra());
            (quantized, spectra)
        });
        let mut quantized: Vec<Option<QuantizedUnit>> = quantized.into_iter().map(Some).collect();
        let mut pcm: Vec<i16> = Vec::new();
        let mut units = Vec::with_capacity(db.units.len());
        for (k, members) in order.iter().enumerate() {
            crumple_cells[k].first_unit = units.len() as u32;
            crumple_cells[k].num_units = members.len() as u32;
            for &i in members {
                let Some(u) = quantized[i].take() else {
                    continue;
                };
                if resampler.is_some() {
                    stats.resampled_units += 1;
                }
                stats.trimmed_samples += u.trimmed;
                pcm.extend(std::iter::repeat_n(0, UNIT_PAD));
                let offset = pcm.len();
                pcm.extend_from_slice(&u.q[..u.len]);
                pcm.extend(std::iter::repeat_n(0, UNIT_PAD));
                units.push(PreparedUnit {
                    offset,
                    len: u.len,
                    scale: u.scale,
                    peak: u.peak,
                });
            }
        }
        pcm.shrink_to_fit();
        SoundDb::assemble(
            rate,
            db.info.clone(),
            PreparedUnits {
                pcm,
                units,
                crumple_cells,
                stats,
            },
            friction_cells,
            spectra,
        )
    }

    /// A prepared database from its parts: the lookup indexes and the active bins derived.
    fn assemble(
        rate: f64,
        info: DbInfo,
        prepared: PreparedUnits,
        friction_cells: Vec<FrictionCell>,
        spectra: Vec<f32>,
    ) -> SoundDb {
        let frame_len = friction_frame_len(rate);
        let bins = frame_len / 2 + 1;
        let PreparedUnits {
            pcm,
            units,
            crumple_cells,
            stats,
        } = prepared;
        let crumple_index =
            CellIndex::new(&crumple_cells.iter().map(|c| c.cell).collect::<Vec<_>>());
        let friction_index =
            CellIndex::new(&friction_cells.iter().map(|c| c.cell).collect::<Vec<_>>());
        let spectra_active_bins = spectra
            .chunks(bins.max(1))
            .map(|s| s.iter().rposition(|v| *v != 0.0).map_or(0, |j| j + 1))
            .max()
            .unwrap_or(0);
        SoundDb {
            sample_rate_hz: rate,
            frame_len,
            info,
            pcm,
            units,
            crumple_cells,
            crumple_index,
            friction_cells,
            friction_index,
            spectra,
            spectra_active_bins,
            stats,
        }
    }

    /// The rate this database was prepared for; `None` for the empty database (any rate).
    pub fn sample_rate_hz(&self) -> Option<f64> {
        (self.sample_rate_hz > 0.0).then_some(self.sample_rate_hz)
    }

    /// The rate the units are stored and played at: the host rate / [`unit_decimation`]; 0 for
    /// the empty database.
    pub fn unit_rate_hz(&self) -> f64 {
        unit_rate_of(self.sample_rate_hz)
    }

    /// True if a renderer at `sample_rate_hz` can use this database.
    pub fn matches_rate(&self, sample_rate_hz: f64) -> bool {
        match self.sample_rate_hz() {
            None => true,
            Some(r) => (r - sample_rate_hz).abs() < 1e-6 * r,
        }
    }

    /// True without units and spectra.
    pub fn is_empty(&self) -> bool {
        self.units.is_empty() && self.friction_cells.is_empty()
    }

    /// Descriptive fields.
    pub fn info(&self) -> &DbInfo {
        &self.info
    }

    /// Friction iFFT frame length M this database's spectra are binned for (0 when empty).
    pub fn frame_len(&self) -> usize {
        if self.friction_cells.is_empty() && self.units.is_empty() {
            0
        } else {
            self.frame_len
        }
    }

    /// Number of bins of each prepared spectrum (M/2 + 1).
    pub fn spectrum_bins(&self) -> usize {
        self.frame_len / 2 + 1
    }

    /// The friction spectra are zero from this bin on (every cell's): a database recorded at
    /// 44.1 kHz has nothing above 22.05 kHz, so at 96 kHz 1 025 of the 2 241 bins carry sound.
    /// The render path does no per-bin work beyond it. 0 without spectra.
    pub fn friction_active_bins(&self) -> usize {
        self.spectra_active_bins.min(self.spectrum_bins())
    }

    /// Preparation statistics.
    pub fn stats(&self) -> PrepareStats {
        self.stats
    }

    /// Crumple cells.
    pub fn crumple_cells(&self) -> &[CrumpleCell] {
        &self.crumple_cells
    }

    /// Friction cells.
    pub fn friction_cells(&self) -> &[FrictionCell] {
        &self.friction_cells
    }

    /// Number of units.
    pub fn num_units(&self) -> usize {
        self.units.len()
    }

    /// A unit's description.
    pub fn unit(&self, index: usize) -> &PreparedUnit {
        &self.units[index]
    }

    /// A unit's samples **with** [`UNIT_PAD`] zeros on both sides (length len + 2·UNIT_PAD).
    pub fn unit_padded_pcm(&self, index: usize) -> &[i16] {
        let u = &self.units[index];
        &self.pcm[u.offset - UNIT_PAD..u.offset + u.len + UNIT_PAD]
    }

    /// A unit's samples as f32 (allocates; for tests and tools).
    pub fn unit_samples(&self, index: usize) -> Vec<f32> {
        let u = &self.units[index];
        self.pcm[u.offset..u.offset + u.len]
            .iter()
            .map(|&q| f32::from(q) * u.scale)
            .collect()
    }

    /// The crumple cell for a resonator (l_r, total free curved border l_c; l_c ≤ 0 =
    /// constrained). No allocation.
    pub fn crumple_lookup(&self, lr_cm: f32, lc_cm: f32) -> Option<CellId> {
        self.crumple_index
            .lookup(lr_cm, lc_cm)
            .map(|l| CellId(l.index as u16))
    }

    /// The friction cell for a resonator. No allocation.
    pub fn friction_lookup(&self, lr_cm: f32, lc_cm: f32) -> Option<CellId> {
        self.friction_index
            .lookup(lr_cm, lc_cm)
            .map(|l| CellId(l.index as u16))
    }

    /// A friction cell's prepared spectrum (M/2 + 1 bins, iFFT-scaled, per unit speed ratio).
    pub fn friction_spectrum(&self, id: CellId) -> &[f32] {
        let bins = self.spectrum_bins();
        let i = id.0 as usize;
        &self.spectra[i * bins..(i + 1) * bins]
    }

    /// Heap memory held, bytes.
    pub fn memory_bytes(&self) -> usize {
        self.pcm.capacity() * 2
            + self.spectra.capacity() * 4
            + self.units.capacity() * std::mem::size_of::<PreparedUnit>()
            + self.crumple_cells.capacity() * std::mem::size_of::<CrumpleCell>()
            + self.friction_cells.capacity() * std::mem::size_of::<FrictionCell>()
            + 2 * std::mem::size_of::<CellIndex>()
            + (self.crumple_index.len() + self.friction_index.len()) * 12
    }
}

/// A unit in the prepared layout: 16 bits at its own peak, trailing samples under −90 dB of the
/// peak trimmed.
struct QuantizedUnit {
    q: Vec<i16>,
    /// Samples kept.
    len: usize,
    /// Samples trimmed.
    trimmed: usize,
    scale: f32,
    peak: f32,
}

/// `x` rounded half away from zero, as `f32::round` (which is a library call without SSE4.1):
/// exact for |x| < 2²³, where the fractional part x − trunc(x) is exact; larger, infinite or NaN
/// values are returned as they are, as `round` returns them.
#[inline]
fn round_half_away(x: f32) -> f32 {
    if x.is_nan() || x.abs() >= 8_388_608.0 {
        return x;
    }
    let t = x as i32 as f32;
    let d = x - t;
    if d >= 0.5 {
        t + 1.0
    } else if d <= -0.5 {
        t - 1.0
    } else {
        t
    }
}

fn quantize_unit(samples: &[f32]) -> QuantizedUnit {
    let peak = samples.iter().fold(0.0f32, |m, s| m.max(s.abs()));
    let scale = if peak > 0.0 { peak / 32767.0 } else { 1.0 };
    let q: Vec<i16> = samples
        .iter()
        .map(|s| round_half_away(s / scale).clamp(-32767.0, 32767.0) as i16)
        .collect();
    // −90 dB of the peak is 1.04 LSB: keep up to the last sample of magnitude ≥ 2.
    let len = q
        .iter()
        .rposition(|v| v.unsigned_abs() >= 2)
        .map_or(1, |p| p + 1);
    QuantizedUnit {
        trimmed: q.len() - len,
        q,
        len,
        scale,
        peak,
    }
}

/// One unit resampled (when the rates differ) and quantized.
fn prepare_unit(r: Option<&Resampler>, u: &crate::database::Unit) -> QuantizedUnit {
    match r {
        Some(r) => quantize_unit(&r.process(&u.samples)),
        None => quantize_unit(&u.samples),
    }
}

/// Every unit resampled and quantized, in the units' order, on the machine's cores
/// ([`crate::parallel::map`]: the same result whatever the threads; the resampling was most of
/// a render's start-up at 48 kHz, docs/benchmarks.md, "Start-up of a render").
fn quantize_units(r: Option<&Resampler>, units: &[crate::database::Unit]) -> Vec<QuantizedUnit> {
    crate::parallel::map(units, |u| prepare_unit(r, u))
}

/// A database's friction spectra (`sources`, of `spectrum_bins` bins referring to
/// `spectrum_rate_hz`) moved onto the render's `bins` bins of `dst_df` Hz, as magnitudes at the
/// reference slide speed, and their cells.
fn friction_spectra(
    sources: &[FrictionSpectrum],
    spectrum_rate_hz: u32,
    spectrum_bins: usize,
    bins: usize,
    dst_df: f64,
) -> (Vec<FrictionCell>, Vec<f32>) {
    let src_df = f64::from(spectrum_rate_hz) / (2.0 * spectrum_bins as f64);
    // Each spectrum on its own, on the machine's cores (the same values whatever the threads).
    let binned = crate::parallel::map(sources, |s| {
        let power = spectrum_band_power(&s.magnitudes, src_df, bins, dst_df);
        let inv_speed = 1.0 / f64::from(s.speed_m_s);
        power
            .iter()
            .enumerate()
            .map(|(j, p)| {
                if j == 0 || j == bins - 1 {
                    0.0
                } else {
                    ((p / 2.0).sqrt() * inv_speed * f64::from(crate::REFERENCE_SLIDE_SPEED_M_S))
                        as f32
                }
            })
            .collect::<Vec<f32>>()
    });
    (friction_cells(sources), binned.concat())
}

/// The friction cells of a database's spectra, in their order.
fn friction_cells(sources: &[FrictionSpectrum]) -> Vec<FrictionCell> {
    sources
        .iter()
        .map(|s| FrictionCell {
            cell: s.cell,
            reference_radius_m: s.cell.reference_radius_m(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The inline rounding gives what `f32::round` gives (a sign of zero aside, which the cast
    /// to 16 bits drops), so the prepared units keep their bits.
    #[test]
    fn rounding_half_away_is_f32_round() {
        let mut x = -40_000.0f32;
        while x < 40_000.0 {
            for v in [
                x,
                x + 0.5,
                x - 0.5,
                x + 0.499_999_97,
                x + 0.500_000_06,
                x + 0.25,
            ] {
                assert!(round_half_away(v) == v.round(), "{v}");
                assert_eq!(round_half_away(v) as i16, v.round() as i16, "{v}");
            }
            x += 0.731;
        }
        for v in [-0.4, -0.5, 0.5, 8_388_607.5, 1e9, -1e9, f32::INFINITY] {
            assert!(round_half_away(v) == v.round(), "{v}");
        }
        assert!(round_half_away(f32::NAN).is_nan());
    }
    use crate::database::{FrictionSpectrum, Unit};

    #[test]
    fn frame_lengths_stay_near_46_ms() {
        for (rate, m) in [
            (22_050.0, 1024),
            (44_100.0, 2058),
            (48_000.0, 2240),
            (88_200.0, 4116),
            (96_000.0, 4480),
            (176_400.0, 8232),
            (192_000.0, 8960),
        ] {
            assert_eq!(friction_frame_len(rate), m, "{rate}");
        }
        // The common rates' frames last exactly the same (their hops fall at the same times).
        for rate in [44_100.0, 48_000.0, 88_200.0, 96_000.0, 176_400.0, 192_000.0] {
            let m = friction_frame_len(rate) as f64;
            assert!((m / rate - FRICTION_FRAME_S).abs() < 1e-12, "{rate}");
        }
        for rate in [
            8_000.0, 11_025.0, 16_000.0, 32_000.0, 44_100.0, 48_000.0, 176_400.0, 192_000.0,
        ] {
            let m = friction_frame_len(rate);
            let ms = 1000.0 * m as f64 / rate;
            assert!(
                m.is_multiple_of(2) && (45.4..=47.4).contains(&ms),
                "{rate}: {m} = {ms} ms"
            );
        }
    }

    fn db() -> Database {
        let mut db = Database::new(DbInfo::default(), 44_100);
        let mut clip = vec![0.0f32; 1000];
        clip[10] = 0.5;
        clip[11] = -0.25;
        db.units.push(Unit {
            cell: Cell::Constrained,
            samples: clip,
            file: String::new(),
        });
        db.spectra.push(FrictionSpectrum {
            cell: Cell::Constrained,
            magnitudes: vec![0.001; 2048],
            speed_m_s: 0.05,
            file: String::new(),
        });
        db
    }

    #[test]
    fn units_are_trimmed_and_padded() {
        let p = SoundDb::prepare(&db(), 44_100.0);
        let u = *p.unit(0);
        assert_eq!(u.len, 12);
        assert!((u.peak - 0.5).abs() < 1e-6);
        let padded = p.unit_padded_pcm(0);
        assert_eq!(padded.len(), 12 + 2 * UNIT_PAD);
        assert!(padded[..UNIT_PAD].iter().all(|&v| v == 0));
        let s = p.unit_samples(0);
        assert!((s[10] - 0.5).abs() < 1e-4 && (s[11] + 0.25).abs() < 1e-4);
        assert!(p.memory_bytes() > 0);
    }

    #[test]
    fn spectrum_power_matches_at_any_rate() {
        // Source power: 2048 bins × 0.001² = 2.048e-3 over 0–22 kHz, speed 0.05 → ×2 amplitude.
        for rate in [44_100.0, 48_000.0, 96_000.0] {
            let p = SoundDb::prepare(&db(), rate);
            let s = p.friction_spectrum(CellId(0));
            assert_eq!(s.len(), friction_frame_len(rate) / 2 + 1);
            let var: f64 = s.iter().map(|v| 2.0 * f64::from(*v).powi(2)).sum();
            let expect = 2048.0 * 1e-6 * 4.0;
            assert!(
                (var / expect - 1.0).abs() < 0.02,
                "{rate}: {var} vs {expect}"
            );
        }
    }

    #[test]
    fn units_are_stored_at_a_half_or_a_quarter_of_high_host_rates() {
        for (rate, d) in [
            (8_000.0, 1),
            (48_000.0, 1),
            (87_999.0, 1),
            (88_200.0, 2),
            (96_000.0, 2),
            (176_400.0, 4),
            (192_000.0, 4),
            (f64::NAN, 1),
        ] {
            assert_eq!(unit_decimation(rate), d, "{rate}");
        }
        // A 44.1 kHz unit at 88.2 kHz needs no conversion; at 96 kHz it is stored at 48 kHz.
        let p = SoundDb::prepare(&db(), 88_200.0);
        assert_eq!((p.unit_rate_hz(), p.stats.resampled_units), (44_100.0, 0));
        assert_eq!(p.unit(0).len, 12);
        let p = SoundDb::prepare(&db(), 96_000.0);
        assert_eq!((p.unit_rate_hz(), p.stats.resampled_units), (48_000.0, 1));
        assert!(p.matches_rate(96_000.0) && !p.matches_rate(48_000.0));
        // Friction spectra stay on the host rate's bins; those above 22.05 kHz are silent.
        let s = p.friction_spectrum(CellId(0));
        assert_eq!(s.len(), friction_frame_len(96_000.0) / 2 + 1);
        let active = p.friction_active_bins();
        let df = 96_000.0 / friction_frame_len(96_000.0) as f64;
        assert!(s[..active].last().is_some_and(|v| *v > 0.0));
        assert!(s[active..].iter().all(|v| *v == 0.0));
        assert!((active as f64 * df - 22_050.0).abs() < 2.0 * df, "{active}");
        assert_eq!(SoundDb::empty().friction_active_bins(), 0);
        assert_eq!(SoundDb::empty().unit_rate_hz(), 0.0);
    }

    #[test]
    fn empty_matches_any_rate() {
        let e = SoundDb::empty();
        assert!(e.is_empty() && e.matches_rate(12_345.0));
        assert!(e.crumple_lookup(1.0, 1.0).is_none());
        let p = SoundDb::prepare(&db(), 48_000.0);
        assert!(p.matches_rate(48_000.0) && !p.matches_rate(44_100.0));
    }
}
