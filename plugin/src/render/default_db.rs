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
//!
//! ## Prepared at build time for the common rates
//!
//! Decoding the pack and preparing it (resampling to 48 kHz, quantizing) was most of a render's
//! start-up. The build script also prepares the units for the two common unit rates, 44.1 and 48
//! kHz, and embeds each as an image in its run-time layout ([`sounddb::SoundDb::image`]): at
//! 44.1, 48, 88.2, 96, 176.4 and 192 kHz [`default_db`] only copies the samples out of an image
//! and bins the friction spectra. The prepared database is a pure function of the pack and the
//! rate, and the preparation is exact arithmetic in a fixed order at every optimisation level,
//! so a database read from an image equals one prepared at run time (tested here). Other rates
//! are prepared from the pack. Decision: two images (≈ 16 MB more in each binary) rather than
//! one, because at 44.1 kHz decoding and quantizing took as long as resampling did at 48 kHz.
//!
//! ## One prepared copy per sample rate in a process
//!
//! Preparing the database for a rate takes a moment (milliseconds from an image, tens of them
//! from the pack) and the prepared database holds megabytes of samples.
//! A host that runs several Papier instances loads the plugin's library once, so
//! [`default_db`] keeps the prepared database of each rate while any instance (or renderer)
//! still holds it — a weak reference in a process-wide table — and hands the same `Arc` to
//! every instance at that rate: the second and later instances start at once and share the
//! memory. The database is a pure function of the pack and the rate, so sharing it changes no
//! sample. The most recently prepared copy is also held by the process itself ([`RECENT`]), so a
//! host that closes an instance and opens a new one at the same rate — pedalboard re-creates the
//! plugin on every render call — does not prepare it again; a copy of any other
//! rate is prepared again once its last holder drops it. The tables are locked only here, never
//! on the audio thread.

use std::sync::{Arc, Mutex, Weak};

use sounddb::{Database, DbError, SoundDb, Warning};

static PACK: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/printer.papierdb"));

/// The unit rates with an embedded prepared image, and the images (module docs).
const IMAGE_UNIT_RATES_HZ: [f64; 2] = [44_100.0, 48_000.0];
static IMAGES: [&[u8]; 2] = [
    include_bytes!(concat!(env!("OUT_DIR"), "/printer-44100.papierpd")),
    include_bytes!(concat!(env!("OUT_DIR"), "/printer-48000.papierpd")),
];

/// The embedded database prepared for `sample_rate_hz`: read from the image of its unit rate
/// where there is one, prepared from the pack otherwise.
fn prepare_embedded(sample_rate_hz: f64) -> Result<SoundDb, DbError> {
    let unit_rate = sounddb::prepared::unit_rate_of(sample_rate_hz);
    let image = IMAGE_UNIT_RATES_HZ
        .iter()
        .position(|r| r.to_bits() == unit_rate.to_bits())
        .map(|i| IMAGES[i]);
    match image {
        Some(image) => SoundDb::from_image(image, sample_rate_hz),
        None => embedded_database().map(|(db, _)| SoundDb::prepare(&db, sample_rate_hz)),
    }
}

/// Loads the embedded database at its own rate (44.1 kHz), with the loader's warnings.
pub fn embedded_database() -> Result<(Database, Vec<Warning>), DbError> {
    Database::from_pack(PACK, "embedded printer database")
}

/// The embedded printer database prepared for `sample_rate_hz`. Allocates and takes milliseconds
/// (tens of them at a rate without an image): call it off the audio thread. If
/// the embedded pack could not be read (it is validated by the tests, so this should not happen)
/// the empty database is returned and the plugin stays silent rather than failing.
///
/// The same `Arc` is returned for the same rate while one is alive (module doc, "One prepared
/// copy per sample rate in a process").
pub fn default_db(sample_rate_hz: f64) -> Arc<SoundDb> {
    /// Prepared databases by the bits of their rate, held weakly.
    static PREPARED: Mutex<Vec<(u64, Weak<SoundDb>)>> = Mutex::new(Vec::new());
    let key = sample_rate_hz.to_bits();
    // The table is locked only to look up and to insert, not while preparing, so that two
    // rates never wait for each other. A panic elsewhere while it was held leaves it usable.
    let lookup = |table: &mut Vec<(u64, Weak<SoundDb>)>| {
        table.retain(|(_, w)| w.strong_count() > 0);
        table
            .iter()
            .find(|(k, _)| *k == key)
            .and_then(|(_, w)| w.upgrade())
    };
    if let Some(db) = lookup(&mut PREPARED.lock().unwrap_or_else(|e| e.into_inner())) {
        keep_recent(&db);
        return db;
    }
    let db = Arc::new(prepare_embedded(sample_rate_hz).unwrap_or_else(|_| SoundDb::empty()));
    let mut table = PREPARED.lock().unwrap_or_else(|e| e.into_inner());
    // Another caller may have prepared the same rate meanwhile: theirs is kept, equal to ours.
    if let Some(shared) = lookup(&mut table) {
        return shared;
    }
    table.push((key, Arc::downgrade(&db)));
    drop(table);
    keep_recent(&db);
    db
}

/// The prepared database the process keeps alive: the one most recently asked for.
static RECENT: Mutex<Option<Arc<SoundDb>>> = Mutex::new(None);

fn keep_recent(db: &Arc<SoundDb>) {
    let old = RECENT
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .replace(db.clone());
    // Dropped outside the lock.
    drop(old);
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

    #[test]
    fn the_embedded_images_equal_a_preparation_at_run_time() {
        let (db, _) = embedded_database().unwrap();
        for rate in [44_100.0, 48_000.0, 96_000.0] {
            let read = prepare_embedded(rate).unwrap();
            assert!(read.matches_rate(rate));
            assert!(
                read == SoundDb::prepare(&db, rate),
                "{rate} Hz: image ≠ preparation"
            );
        }
        // The images are what the build script made of this build's pack.
        for (rate, image) in IMAGE_UNIT_RATES_HZ.iter().zip(IMAGES) {
            assert!(
                SoundDb::image(&db, *rate) == image,
                "{rate} Hz image is stale"
            );
        }
        // A rate next to one with an image is prepared from the pack.
        let near = prepare_embedded(48_000.5).unwrap();
        assert!(near.matches_rate(48_000.5) && near == SoundDb::prepare(&db, 48_000.5));
    }

    #[test]
    fn instances_at_one_rate_share_the_prepared_database_while_it_is_held() {
        // A rate no other test of this binary uses, so the shared table starts without it.
        let rate = 47_999.0;
        let a = default_db(rate);
        let b = default_db(rate);
        assert!(Arc::ptr_eq(&a, &b), "the same rate shares one copy");
        assert!(a.matches_rate(rate));
        let other = default_db(44_101.0);
        assert!(!Arc::ptr_eq(&a, &other), "another rate has its own");
        assert!(other.matches_rate(44_101.0));
        // The process keeps only the most recent copy (other tests of this binary may ask for
        // other rates meanwhile, so which one that is is not checked here); `a`'s rate is not it.
        drop(other);
        // Any other copy dropped by every holder is prepared again, equal to the first.
        let weak = Arc::downgrade(&a);
        let (units, bytes) = (a.num_units(), a.memory_bytes());
        drop((a, b));
        assert!(
            weak.upgrade().is_none(),
            "nothing but the most recent copy is kept alive"
        );
        let c = default_db(rate);
        assert_eq!((c.num_units(), c.memory_bytes()), (units, bytes));
    }
}
