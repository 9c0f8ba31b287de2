//! System prerequisites of the tasks: Debian packages and the Python environment of the VST3
//! host test. On a fresh machine the tasks install what is missing (as root, with apt-get);
//! otherwise they say exactly what to run.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, bail};

/// Packages needed to build the standalone application (ALSA and JACK headers).
pub const STANDALONE_PACKAGES: &[&str] = &["libasound2-dev", "libjack-jackd2-dev", "pkg-config"];

/// Packages needed by the headless GUI tests (X server, window info, screenshots, synthetic
/// mouse input).
pub const GUI_TEST_PACKAGES: &[&str] = &["xvfb", "xauth", "imagemagick", "x11-utils", "xdotool"];

/// Python packages of the VST3 host test.
pub const PYTHON_PACKAGES: &[&str] = &["pedalboard==0.9.26", "numpy", "mido"];

fn installed(pkg: &str) -> bool {
    Command::new("dpkg-query")
        .args(["-W", "-f=${Status}", pkg])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).contains("install ok installed"))
        .unwrap_or(false)
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

/// Makes sure the Debian packages are installed; installs them with apt-get when running as
/// root. Returns an error naming the command to run otherwise.
pub fn ensure_packages(pkgs: &[&str]) -> anyhow::Result<()> {
    let missing: Vec<&str> = pkgs.iter().copied().filter(|p| !installed(p)).collect();
    if missing.is_empty() {
        return Ok(());
    }
    let line = format!(
        "apt-get update && apt-get install -y --no-install-recommends {}",
        missing.join(" ")
    );
    if !is_root() || Command::new("apt-get").arg("--version").output().is_err() {
        bail!("missing system packages {missing:?}; install them with: sudo sh -c '{line}'");
    }
    eprintln!("xtask: installing {}", missing.join(" "));
    let ok = Command::new("sh")
        .arg("-c")
        .arg(format!("DEBIAN_FRONTEND=noninteractive {line}"))
        .status()
        .context("run apt-get")?
        .success();
    if !ok {
        bail!("apt-get could not install {missing:?}");
    }
    Ok(())
}

/// The Python interpreter of `target/venv`, created and filled with [`PYTHON_PACKAGES`] if
/// needed.
pub fn ensure_venv(target_dir: &Path) -> anyhow::Result<PathBuf> {
    let venv = target_dir.join("venv");
    let python = venv.join("bin").join("python");
    let marker = venv.join(".papier-ready");
    if marker.exists() && python.exists() {
        return Ok(python);
    }
    eprintln!(
        "xtask: creating {} with {}",
        venv.display(),
        PYTHON_PACKAGES.join(" ")
    );
    let ok = Command::new("python3")
        .args(["-m", "venv"])
        .arg(&venv)
        .status()
        .context("run python3 -m venv")?
        .success();
    if !ok {
        bail!(
            "python3 -m venv {} failed (is python3-venv installed?)",
            venv.display()
        );
    }
    let ok = Command::new(&python)
        .args([
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
        ])
        .args(PYTHON_PACKAGES)
        .status()
        .context("run pip")?
        .success();
    if !ok {
        bail!("pip could not install {:?}", PYTHON_PACKAGES);
    }
    std::fs::write(&marker, PYTHON_PACKAGES.join("\n"))?;
    Ok(python)
}
