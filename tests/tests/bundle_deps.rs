//! The bundles load without the standalone app's audio libraries.
//!
//! The plugin crate is built with one feature set, its standalone wrapper (JACK/ALSA audio and
//! MIDI) always on, so the bundles, the standalone and `papier-render` share one compile. The
//! bundles must still load on a machine without ALSA or JACK (a render server running
//! pedalboard): nothing in the library reaches the standalone's backends, so the linker drops
//! them and the shared object does not name their libraries. The standalone app does need ALSA.
//!
//! Breakage detected: library code that starts to call into the standalone wrapper (or a
//! build change that keeps its sections), which would make `Papier.clap`/`Papier.vst3` fail to
//! load where `libasound.so.2` is missing.

use std::path::Path;
use std::process::Command;

use papier_tests::paths;

/// The `NEEDED` entries of an ELF file's dynamic section (`readelf -d`, from binutils, which the
/// Rust toolchain's linker needs anyway).
fn needed(file: &Path) -> Vec<String> {
    let out = Command::new("readelf")
        .arg("-d")
        .arg(file)
        .output()
        .expect("run readelf (binutils)");
    assert!(out.status.success(), "readelf -d {}", file.display());
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter(|l| l.contains("(NEEDED)"))
        .filter_map(|l| {
            let a = l.find('[')?;
            let b = l.rfind(']')?;
            Some(l[a + 1..b].to_string())
        })
        .collect()
}

fn audio_libraries(libs: &[String]) -> Vec<&String> {
    libs.iter()
        .filter(|l| l.starts_with("libasound") || l.starts_with("libjack"))
        .collect()
}

#[test]
fn the_bundles_do_not_need_the_standalone_audio_libraries() {
    let clap = paths::clap_bundle();
    let vst3 = paths::vst3_bundle()
        .join("Contents")
        .join("x86_64-linux")
        .join("Papier.so");
    for file in [clap, vst3] {
        let libs = needed(&file);
        assert!(
            libs.iter().any(|l| l.starts_with("libc.so")),
            "{}: no NEEDED entries read ({libs:?})",
            file.display()
        );
        assert!(
            audio_libraries(&libs).is_empty(),
            "{} needs {:?}",
            file.display(),
            audio_libraries(&libs)
        );
    }
    // The check can fail: the standalone, built from the same compile, does name ALSA.
    let standalone = needed(&paths::standalone());
    assert!(
        !audio_libraries(&standalone).is_empty(),
        "the standalone names no audio library: {standalone:?}"
    );
}
