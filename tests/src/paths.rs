//! Where the build puts things. The tests use the release bundles made by
//! `cargo xtask bundle papier --release` (the README's test command builds them first).

use std::path::{Path, PathBuf};

/// The workspace root.
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ lives in the workspace")
        .to_path_buf()
}

/// The cargo target directory (honours `CARGO_TARGET_DIR`).
pub fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(d) => {
            let d = PathBuf::from(d);
            if d.is_absolute() {
                d
            } else {
                workspace_root().join(d)
            }
        }
        None => workspace_root().join("target"),
    }
}

fn must_exist(p: PathBuf, how: &str) -> PathBuf {
    assert!(
        p.exists(),
        "{} is missing; build it first with `{how}` (the README's test command does)",
        p.display()
    );
    p
}

/// `target/bundled/Papier.clap`.
pub fn clap_bundle() -> PathBuf {
    must_exist(
        target_dir().join("bundled").join("Papier.clap"),
        "cargo xtask bundle papier --release",
    )
}

/// `target/bundled/Papier.vst3`.
pub fn vst3_bundle() -> PathBuf {
    must_exist(
        target_dir().join("bundled").join("Papier.vst3"),
        "cargo xtask bundle papier --release",
    )
}

/// The release `papier-render` binary.
pub fn papier_render() -> PathBuf {
    must_exist(
        target_dir().join("release").join("papier-render"),
        "cargo xtask bundle papier --release",
    )
}

/// Runs the release `papier-render` with `args` and returns its exit status and output.
pub fn run_papier_render(args: &[&str]) -> std::process::Output {
    std::process::Command::new(papier_render())
        .args(args)
        .output()
        .expect("run papier-render")
}

/// A path as a command-line argument (the tests' paths are UTF-8).
pub fn arg(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 path")
}

/// The release standalone application (`target/release/papier`).
pub fn standalone() -> PathBuf {
    must_exist(
        target_dir().join("release").join("papier"),
        "cargo xtask bundle papier --release",
    )
}

/// A fresh scratch directory under `target/test-scratch/NAME`.
pub fn scratch(name: &str) -> PathBuf {
    let d = target_dir().join("test-scratch").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create scratch dir");
    d
}
