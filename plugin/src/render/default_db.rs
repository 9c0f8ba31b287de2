//! # The embedded default database (synthesized printer paper)
//!
//! `plugin/build.rs` runs `sounddb::generate::generate(Material::Printer)` at build time and packs
//! the result ([`sounddb::pack`]) into `OUT_DIR/printer.papierdb`, which is embedded here with
//! `include_bytes!`: the plugin works on a fresh machine with no files. The pack goes through the
//! same validating loader as a user's folder. The units are **synthesized, not recorded**
//! (digest-sound §10; see `sounddb::generate` for what that loses).
//!
//! The generator is deterministic and fast without optimisation (about 1.2 s at `opt-level = 0`
//! on the 2-core CI machine), so the build script costs the same in every profile.

use std::sync::Arc;

use sounddb::{Database, DbError, SoundDb, Warning};

static PACK: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/printer.papierdb"));

/// The embedded pack (the generated printer database).
pub fn embedded_pack() -> &'static [u8] {
    PACK
}

/// Loads the embedded database at its own rate (44.1 kHz), with the loader's warnings.
pub fn embedded_database() -> Result<(Database, Vec<Warning>), DbError> {
    Database::from_pack(PACK, "embedded printer database")
}

/// The embedded printer database prepared for `sample_rate_hz`. Allocates and takes a few tens
/// of milliseconds (resampling when the rate is not 44.1 kHz): call it off the audio thread. If
/// the embedded pack could not be read (it is validated by the tests, so this should not happen)
/// the empty database is returned and the plugin stays silent rather than failing.
pub fn default_db(sample_rate_hz: f64) -> Arc<SoundDb> {
    match embedded_database() {
        Ok((db, _warnings)) => Arc::new(SoundDb::prepare(&db, sample_rate_hz)),
        Err(_) => Arc::new(SoundDb::empty()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_database_is_complete_and_clean() {
        let (db, warnings) = embedded_database().unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        assert!(db.info.synthesized);
        assert_eq!(db.units.len(), 249);
        assert_eq!(db.spectra.len(), 82);
        assert!(PACK.len() <= 12 * 1024 * 1024);
    }
}
