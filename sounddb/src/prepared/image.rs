//! # A prepared database as one byte string (its run-time layout)
//!
//! Preparing the embedded database for a rate (decoding the pack's WAV files, resampling,
//! quantizing) was most of a render's start-up (docs/benchmarks.md, "Start-up of a render").
//! What takes the time depends only on the **unit rate** ([`SoundDb::unit_rate_hz`]: the host
//! rate, or a half or a quarter of it from 88 kHz on), so the plugin's build script prepares the
//! embedded database's units for the two common unit rates, 44.1 and 48 kHz, and stores each
//! with the database's friction spectra as an **image** ([`SoundDb::image`]). At run time
//! [`SoundDb::from_image`] reads one back for any host rate with that unit rate (44.1, 88.2,
//! 176.4 kHz and 48, 96, 192 kHz): a copy of the 16-bit samples and the spectra moved onto the
//! host rate's friction bins, no WAV decoding, no resampling. The result equals
//! [`SoundDb::prepare`] of the database at that rate (tested). The friction spectra are stored
//! twice: as the database has them, for the rates above the unit rate, and binned for the unit
//! rate itself (binning them took most of what was left of a start-up at 48 kHz).
//!
//! Layout (all little-endian): magic `PAPIERPD`, version u32, unit rate f64, [`DbInfo`] (three
//! strings, a flag, a string, an optional seed), the statistics, the crumple cells (cell, first
//! unit, count), the units (offset, length, scale, peak), the samples (count, i16s), then the
//! spectra's rate u32 and bins u64 and each spectrum (cell, slide speed, magnitudes), and the
//! spectra binned for the unit rate (count, f32s). The
//! cells' reference radii and lookup indexes are derived from the cells, so never stored.
//!
//! Reading never panics and checks what the renderer relies on (units inside the samples with
//! their padding, cells' units in range, finite spectra and speeds, the unit rate of the host
//! rate asked for): a damaged image is a one-line [`DbError::BadImage`].

use super::{
    CrumpleCell, PrepareStats, PreparedUnit, PreparedUnits, SoundDb, UNIT_PAD, friction_cells,
    friction_frame_len, friction_spectra, unit_rate_of,
};
use crate::DbError;
use crate::bytes::{ByteReader, PutLe};
use crate::cell::Cell;
use crate::database::{Database, DbInfo, FrictionSpectrum};

/// Magic bytes at the start of an image.
const MAGIC: &[u8; 8] = b"PAPIERPD";
/// Image layout version.
const IMAGE_VERSION: u32 = 1;

fn put_cell(out: &mut Vec<u8>, cell: &Cell) {
    match *cell {
        Cell::Constrained => out.extend_from_slice(&[0u8; 9]),
        Cell::Free {
            straight_cm,
            curved_cm,
        } => {
            out.push(1);
            out.put_u32(straight_cm.to_bits());
            out.put_u32(curved_cm.to_bits());
        }
    }
}

fn read_cell(r: &mut ByteReader) -> Result<Cell, DbError> {
    let tag = r.u8()?;
    let straight_cm = r.f32()?;
    let curved_cm = r.f32()?;
    match tag {
        0 => Ok(Cell::Constrained),
        1 if straight_cm.is_finite() && curved_cm.is_finite() => Ok(Cell::Free {
            straight_cm,
            curved_cm,
        }),
        _ => Err(r.error(format!(
            "a cell with tag {tag} ({straight_cm}, {curved_cm})"
        ))),
    }
}

fn read_f32s(r: &mut ByteReader, n: usize) -> Result<Vec<f32>, DbError> {
    let bytes = n
        .checked_mul(4)
        .ok_or_else(|| r.error(format!("{n} values overflow")))?;
    let v: Vec<f32> = r
        .take(bytes)?
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    if v.iter().any(|x| !x.is_finite()) {
        return Err(r.error("a value is not finite".into()));
    }
    Ok(v)
}

impl SoundDb {
    /// The image of `db` prepared for `sample_rate_hz`'s unit rate (module docs); allocates and
    /// takes as long as [`SoundDb::prepare`].
    pub fn image(db: &Database, sample_rate_hz: f64) -> Vec<u8> {
        let unit_rate = unit_rate_of(sample_rate_hz);
        let p = SoundDb::prepare(db, unit_rate);
        let mut out = Vec::with_capacity(
            4096 + p.pcm.len() * 2 + db.spectra.len() * (db.spectrum_bins * 4 + 16),
        );
        out.extend_from_slice(MAGIC);
        out.put_u32(IMAGE_VERSION);
        out.put_u64(p.sample_rate_hz.to_bits());
        let info = &p.info;
        out.put_str(&info.name);
        out.put_str(&info.material);
        out.put_str(&info.obstacle);
        out.push(u8::from(info.synthesized));
        out.put_str(&info.description);
        out.push(u8::from(info.seed.is_some()));
        out.put_u64(info.seed.unwrap_or(0));
        out.put_u64(p.stats.trimmed_samples as u64);
        out.put_u64(p.stats.resampled_units as u64);
        out.put_u32(p.crumple_cells.len() as u32);
        for c in &p.crumple_cells {
            put_cell(&mut out, &c.cell);
            out.put_u32(c.first_unit);
            out.put_u32(c.num_units);
        }
        out.put_u32(p.units.len() as u32);
        for u in &p.units {
            out.put_u64(u.offset as u64);
            out.put_u64(u.len as u64);
            out.put_u32(u.scale.to_bits());
            out.put_u32(u.peak.to_bits());
        }
        out.put_u64(p.pcm.len() as u64);
        for q in &p.pcm {
            out.extend_from_slice(&q.to_le_bytes());
        }
        out.put_u32(db.spectrum_rate_hz);
        out.put_u64(db.spectrum_bins as u64);
        out.put_u32(db.spectra.len() as u32);
        for s in &db.spectra {
            put_cell(&mut out, &s.cell);
            out.put_u32(s.speed_m_s.to_bits());
            for m in &s.magnitudes {
                out.put_u32(m.to_bits());
            }
        }
        out.put_u64(p.spectra.len() as u64);
        for v in &p.spectra {
            out.put_u32(v.to_bits());
        }
        out
    }

    /// Reads an image made by [`SoundDb::image`] for `sample_rate_hz`, whose unit rate must be
    /// the image's (allocates: off the audio thread). Equals [`SoundDb::prepare`] of the
    /// database at that rate.
    pub fn from_image(bytes: &[u8], sample_rate_hz: f64) -> Result<SoundDb, DbError> {
        let mut r = ByteReader::new(bytes, DbError::BadImage);
        if r.take(8)? != MAGIC {
            return Err(r.error("missing PAPIERPD magic".into()));
        }
        let version = r.u32()?;
        if version != IMAGE_VERSION {
            return Err(r.error(format!(
                "image version {version}, this build reads {IMAGE_VERSION}"
            )));
        }
        let unit_rate = r.f64()?;
        let rate_ok = sample_rate_hz.is_finite() && sample_rate_hz > 0.0;
        if !rate_ok || unit_rate.to_bits() != unit_rate_of(sample_rate_hz).to_bits() {
            return Err(r.error(format!(
                "units at {unit_rate} Hz, not the unit rate of {sample_rate_hz} Hz"
            )));
        }
        let name = r.str()?;
        let material = r.str()?;
        let obstacle = r.str()?;
        let synthesized = r.u8()? != 0;
        let description = r.str()?;
        let has_seed = r.u8()? != 0;
        let seed = r.u64()?;
        let info = DbInfo {
            name,
            material,
            obstacle,
            synthesized,
            description,
            seed: has_seed.then_some(seed),
        };
        let stats = PrepareStats {
            trimmed_samples: r.len()?,
            resampled_units: r.len()?,
        };

        let n = r.u32()? as usize;
        let mut crumple_cells = Vec::with_capacity(n.min(r.remaining() / 17));
        for _ in 0..n {
            let cell = read_cell(&mut r)?;
            crumple_cells.push(CrumpleCell {
                cell,
                first_unit: r.u32()?,
                num_units: r.u32()?,
                reference_radius_m: cell.reference_radius_m(),
            });
        }
        let n = r.u32()? as usize;
        let mut units = Vec::with_capacity(n.min(r.remaining() / 24));
        for _ in 0..n {
            units.push(PreparedUnit {
                offset: r.len()?,
                len: r.len()?,
                scale: r.f32()?,
                peak: r.f32()?,
            });
        }
        let n = r.len()?;
        let bytes_n = n
            .checked_mul(2)
            .ok_or_else(|| r.error("samples overflow".into()))?;
        let pcm: Vec<i16> = r
            .take(bytes_n)?
            .chunks_exact(2)
            .map(|b| i16::from_le_bytes([b[0], b[1]]))
            .collect();

        let spectrum_rate_hz = r.u32()?;
        let spectrum_bins = r.len()?;
        if spectrum_rate_hz == 0 || spectrum_bins == 0 {
            return Err(r.error(format!(
                "spectra of {spectrum_bins} bins at {spectrum_rate_hz} Hz"
            )));
        }
        let n = r.u32()? as usize;
        let mut sources = Vec::with_capacity(n.min(r.remaining() / (13 + 4 * spectrum_bins)));
        for _ in 0..n {
            let cell = read_cell(&mut r)?;
            let speed_m_s = r.f32()?;
            if !(speed_m_s.is_finite() && speed_m_s > 0.0) {
                return Err(r.error(format!("a spectrum's slide speed is {speed_m_s} m/s")));
            }
            sources.push(FrictionSpectrum {
                cell,
                magnitudes: read_f32s(&mut r, spectrum_bins)?,
                speed_m_s,
                file: String::new(),
            });
        }
        let n = r.len()?;
        let binned = read_f32s(&mut r, n)?;
        if r.remaining() != 0 {
            return Err(r.error(format!("{} trailing bytes", r.remaining())));
        }

        // What the renderer relies on.
        for (i, u) in units.iter().enumerate() {
            let inside = u.offset >= UNIT_PAD
                && u.offset
                    .checked_add(u.len)
                    .and_then(|e| e.checked_add(UNIT_PAD))
                    .is_some_and(|e| e <= pcm.len());
            if !inside || !u.scale.is_finite() || !u.peak.is_finite() {
                return Err(r.error(format!("unit {i} lies outside the samples")));
            }
        }
        for (i, c) in crumple_cells.iter().enumerate() {
            let end = u64::from(c.first_unit) + u64::from(c.num_units);
            if c.num_units == 0 || end > units.len() as u64 {
                return Err(r.error(format!("crumple cell {i}'s units are out of range")));
            }
        }
        let max_cells = usize::from(u16::MAX);
        if crumple_cells.len() > max_cells || sources.len() > max_cells {
            return Err(r.error("too many cells".into()));
        }

        let frame_len = friction_frame_len(sample_rate_hz);
        let bins = frame_len / 2 + 1;
        let (friction_cells, spectra) = if sample_rate_hz.to_bits() == unit_rate.to_bits() {
            if binned.len() != sources.len() * bins {
                return Err(r.error(format!(
                    "{} binned values for {} spectra of {bins} bins",
                    binned.len(),
                    sources.len()
                )));
            }
            (friction_cells(&sources), binned)
        } else {
            friction_spectra(
                &sources,
                spectrum_rate_hz,
                spectrum_bins,
                bins,
                sample_rate_hz / frame_len as f64,
            )
        };
        Ok(SoundDb::assemble(
            sample_rate_hz,
            info,
            PreparedUnits {
                pcm,
                units,
                crumple_cells,
                stats,
            },
            friction_cells,
            spectra,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{Material, generate};

    #[test]
    fn an_image_reads_back_as_the_database_prepared_at_each_rate_of_its_unit_rate() {
        let db = generate(Material::Printer);
        for (image_rate, rates) in [
            (44_100.0, &[44_100.0, 88_200.0, 176_400.0][..]),
            (48_000.0, &[48_000.0, 96_000.0, 192_000.0][..]),
            (22_050.0, &[22_050.0][..]),
        ] {
            let image = SoundDb::image(&db, image_rate);
            for &rate in rates {
                let back = SoundDb::from_image(&image, rate).unwrap();
                assert!(back == SoundDb::prepare(&db, rate), "{image_rate} → {rate}");
            }
            // Another unit rate is refused, by name.
            let e = SoundDb::from_image(&image, image_rate + 1.0).unwrap_err();
            assert!(e.to_string().contains("unit rate"), "{e}");
            assert!(SoundDb::from_image(&image, f64::NAN).is_err());
        }
    }

    #[test]
    fn a_damaged_image_is_an_error_never_a_panic() {
        let image = SoundDb::image(&generate(Material::Printer), 48_000.0);
        // Every truncation in the header and the tables, and a sample of the rest.
        let cuts = (0..4_000).chain((4_000..image.len()).step_by(image.len() / 97));
        for cut in cuts {
            let e = SoundDb::from_image(&image[..cut], 48_000.0).unwrap_err();
            assert!(matches!(e, DbError::BadImage(_)), "{cut}: {e}");
        }
        // Flipped bits in the header and the tables: an error or a database that is whole.
        let mut rng = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..400 {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            let mut bad = image.clone();
            let at = (rng % 6_000) as usize;
            bad[at] ^= 1 << ((rng >> 40) % 8);
            if let Ok(db) = SoundDb::from_image(&bad, 48_000.0) {
                for i in 0..db.num_units() {
                    let _ = db.unit_padded_pcm(i);
                }
                for c in 0..db.friction_cells().len() {
                    let _ = db.friction_spectrum(crate::CellId(c as u16));
                }
            }
        }
        let mut extra = image.clone();
        extra.push(0);
        let e = SoundDb::from_image(&extra, 48_000.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("trailing") && e.contains("image"), "{e}");
    }
}
