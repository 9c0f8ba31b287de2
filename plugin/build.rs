//! Generates the default sound database (synthesized printer paper, `sounddb::generate`) into
//! `OUT_DIR/printer.papierdb`, embedded by `src/render/default_db.rs`. Deterministic; written to
//! run fast even at the build-script default `opt-level = 0` (≈ 1.2 s on the 2-core CI machine).

use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let start = std::time::Instant::now();
    let db = sounddb::generate::generate(sounddb::generate::Material::Printer);
    let pack = db.to_pack();
    let path = out.join("printer.papierdb");
    std::fs::write(&path, &pack).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
    // Kept next to the pack for the build-time report (docs/benchmarks.md).
    let _ = std::fs::write(
        out.join("printer.papierdb.txt"),
        format!(
            "bytes {}\ngenerate_and_pack_s {:.3}\n",
            pack.len(),
            start.elapsed().as_secs_f64()
        ),
    );
}
