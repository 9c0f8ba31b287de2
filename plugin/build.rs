//! Generates the default sound database (synthesized printer paper, `sounddb::generate`) into
//! `OUT_DIR/printer.papierdb`, and prepares its units for the two common unit rates as run-time
//! images (`printer-44100.papierpd`, `printer-48000.papierpd`; `sounddb::SoundDb::image`), all
//! embedded by `src/render/default_db.rs`. Deterministic; written to run fast even at the
//! build-script default `opt-level = 0` (a few seconds on the 2-core CI machine, the resampling
//! to 48 kHz most of it).

use std::path::{Path, PathBuf};

/// The unit rates prepared at build time (`src/render/default_db.rs`, `IMAGE_UNIT_RATES_HZ`).
const IMAGE_RATES_HZ: [u32; 2] = [44_100, 48_000];

fn write(path: &Path, bytes: &[u8]) {
    std::fs::write(path, bytes).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let start = std::time::Instant::now();
    let db = sounddb::generate::generate(sounddb::generate::Material::Printer);
    let pack = db.to_pack();
    write(&out.join("printer.papierdb"), &pack);
    let generated_s = start.elapsed().as_secs_f64();
    // Prepared from the pack as the run time would (the same loader), not from `db`.
    let (loaded, _) = sounddb::Database::from_pack(&pack, "embedded printer database")
        .unwrap_or_else(|e| panic!("the generated pack does not load: {e}"));
    let mut image_bytes = 0;
    for rate in IMAGE_RATES_HZ {
        let image = sounddb::SoundDb::image(&loaded, f64::from(rate));
        image_bytes += image.len();
        write(&out.join(format!("printer-{rate}.papierpd")), &image);
    }
    // Kept next to the pack for the build-time report (docs/benchmarks.md).
    let _ = std::fs::write(
        out.join("printer.papierdb.txt"),
        format!(
            "bytes {}\ngenerate_and_pack_s {generated_s:.3}\nimage_bytes {image_bytes}\nprepare_images_s {:.3}\n",
            pack.len(),
            start.elapsed().as_secs_f64() - generated_s
        ),
    );
}
