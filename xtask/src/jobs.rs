//! The README's two commands, and running the workspace's tools through cargo.
//!
//! - `cargo xtask demo`: builds the `Papier.clap` and `Papier.vst3` bundles, the standalone
//!   application and `papier-render` (the ALSA/JACK headers installed first if missing), then
//!   renders the demo scene (`plugin/scenes/demo.toml`) to `out/demo.wav` with the embedded
//!   default sound database, and prints where everything is and how to install it.
//! - `cargo xtask test`: installs what the tests need (Debian packages, the Python environment
//!   of the VST3 host test), builds the bundles, checks formatting and lints, and runs every
//!   test of the workspace, the real-host tests included.
//! - [`cargo_run`]: `cargo xtask sounddb` and `cargo xtask bench-report` run the `sounddb` and
//!   `papier-lab` binaries through cargo, so xtask itself links neither.
//!
//! The plugin crate has one feature set (its standalone wrapper always on), so one cargo
//! invocation — the bundle step, which builds the whole `papier` package — compiles the plugin
//! code once for the bundles, the standalone and `papier-render`.

use std::path::PathBuf;
use std::process::Command;

use anyhow::{Context, bail};

use crate::system;

/// Runs `cargo ARGS` (the cargo running xtask, else the one on the path); an error if it fails.
pub fn cargo(args: &[&str]) -> anyhow::Result<()> {
    eprintln!("xtask: cargo {}", args.join(" "));
    let started = std::time::Instant::now();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let ok = Command::new(cargo)
        .args(args)
        .status()
        .with_context(|| format!("run cargo {}", args.join(" ")))?
        .success();
    eprintln!(
        "xtask: cargo {} took {:.0} s",
        args.first().copied().unwrap_or(""),
        started.elapsed().as_secs_f64()
    );
    if !ok {
        bail!("cargo {} failed", args.join(" "));
    }
    Ok(())
}

/// Runs a workspace binary in release: `cargo run --release TARGET -- ARGS`, where `TARGET`
/// selects it (`-p PACKAGE [--bin NAME]`), in the current directory (relative paths in `ARGS`
/// stay the caller's).
pub fn cargo_run(target: &[&str], args: &[String]) -> anyhow::Result<()> {
    let mut all = vec!["run", "--release"];
    all.extend_from_slice(target);
    all.push("--");
    all.extend(args.iter().map(String::as_str));
    cargo(&all)
}

fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(d) => PathBuf::from(d),
        None => PathBuf::from("target"),
    }
}

/// Builds the `papier` package once (library, standalone, `papier-render`) and bundles the
/// plugin and the standalone into `target/bundled/`.
fn bundle() -> anyhow::Result<()> {
    // The standalone's audio backends need the ALSA/JACK headers to build.
    system::ensure_packages(system::STANDALONE_PACKAGES)?;
    eprintln!("xtask: cargo xtask bundle papier --release");
    let started = std::time::Instant::now();
    nice_plug_xtask::main_with_args(
        "cargo xtask",
        ["bundle", "papier", "--release"].map(String::from),
    )?;
    eprintln!(
        "xtask: the bundle step took {:.0} s",
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The main job.
pub fn demo(args: &[String]) -> anyhow::Result<()> {
    if let Some(a) = args.first() {
        bail!("`cargo xtask demo` takes no arguments (got {a:?})");
    }
    nice_plug_xtask::chdir_workspace_root()?;
    let target = target_dir();
    bundle()?;

    std::fs::create_dir_all("out")?;
    let render = target.join("release").join("papier-render");
    eprintln!("xtask: rendering the demo scene");
    let ok = Command::new(&render)
        .args([
            "--script",
            "plugin/scenes/demo.toml",
            "--out",
            "out/demo.wav",
            "--obj-dir",
            "out/demo_obj",
            "--obj-fps",
            "25",
        ])
        .status()
        .with_context(|| format!("run {}", render.display()))?
        .success();
    if !ok {
        bail!("the demo render failed");
    }

    let bundled = std::fs::canonicalize(target.join("bundled"))?;
    let wav = std::fs::canonicalize("out/demo.wav")?;
    println!();
    println!("Papier is built.");
    println!("  demo render:  {}", wav.display());
    println!(
        "  sheet (OBJ):  {}",
        wav.with_file_name("demo_obj").display()
    );
    println!("  CLAP plugin:  {}", bundled.join("Papier.clap").display());
    println!("  VST3 plugin:  {}", bundled.join("Papier.vst3").display());
    println!("  standalone:   {}", bundled.join("Papier").display());
    println!(
        "  renderer:     {}",
        std::fs::canonicalize(&render)?.display()
    );
    println!();
    println!("Install in a DAW (Linux): copy the bundles to your plugin folders, e.g.");
    println!(
        "  mkdir -p ~/.clap ~/.vst3 && cp -r {0}/Papier.clap ~/.clap/ && cp -r {0}/Papier.vst3 ~/.vst3/",
        bundled.display()
    );
    println!(
        "then rescan plugins in the DAW and load \"Papier\" as an instrument on a MIDI track."
    );
    Ok(())
}

/// True if `cargo nextest` runs here.
fn nextest_available() -> bool {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    Command::new(cargo)
        .args(["nextest", "--version"])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// The full test run.
pub fn test(args: &[String]) -> anyhow::Result<()> {
    if let Some(a) = args.first() {
        bail!("`cargo xtask test` takes no arguments (got {a:?})");
    }
    nice_plug_xtask::chdir_workspace_root()?;
    let target = target_dir();
    system::ensure_packages(system::GUI_TEST_PACKAGES)?;
    system::ensure_venv(&std::env::current_dir()?.join(&target))?;
    bundle()?;
    cargo(&["fmt", "--all", "--", "--check"])?;
    cargo(&[
        "clippy",
        "--workspace",
        "--all-targets",
        "--",
        "-D",
        "warnings",
    ])?;
    // cargo-nextest runs the test binaries side by side (cargo test runs them one after the
    // other, and a binary with one long test leaves a core idle); doctests it does not run.
    if nextest_available() {
        cargo(&[
            "nextest",
            "run",
            "--workspace",
            "--no-fail-fast",
            "--failure-output",
            "final",
        ])?;
        cargo(&["test", "--workspace", "--doc"])?;
    } else {
        eprintln!("xtask: cargo-nextest is not installed; running the tests with cargo test");
        cargo(&["test", "--workspace", "--no-fail-fast"])?;
    }
    // The render path's allocation proof needs its own global allocator, which debug builds
    // cannot have (nice-plug's allocation checker is theirs): run it in release.
    cargo(&[
        "test",
        "--release",
        "-p",
        "papier-tests",
        "--test",
        "render_no_alloc",
    ])?;
    println!("xtask: all tests passed");
    Ok(())
}
