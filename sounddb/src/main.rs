//! The `sounddb` tool: generate, import or check a sound database (format: `sounddb::manifest`).
//! Run it as `cargo xtask sounddb ARGS`, which runs `cargo run --release -p sounddb --bin sounddb
//! -- ARGS` (the xtask binary itself links none of the workspace's crates).
//!
//! ```text
//! cargo xtask sounddb --material printer|tracing|banknote --out DIR [--seed N]
//!     Synthesizes a default database with the curved-panel modal model (sounddb::generate;
//!     deterministic, ≤ 12 MiB). The units are SYNTHESIZED, not recorded.
//! cargo xtask sounddb import --recordings DIR --out DB [--name TEXT] [--material TEXT]
//!                            [--obstacle TEXT] [--rate HZ] [--max-variants N]
//!     Builds a database from your own WAV recordings (naming scheme and annotations.toml:
//!     sounddb::import): flap/clac files are cut at onsets, friction spectra are averaged over
//!     the 200 ms in the middle of each slide.
//! cargo xtask sounddb check DB
//!     Loads a database folder through the validating loader and prints what it holds and every
//!     warning.
//! ```
//!
//! Every database written is loaded back through the same validating loader the plugin uses, and
//! its warnings are printed. An error is printed on one line; the exit status is then 1.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use sounddb::generate::Material;
use sounddb::import::{ImportOptions, import_dir};
use sounddb::{Database, Warning};

const USAGE: &str = "usage:
  cargo xtask sounddb --material printer|tracing|banknote --out DIR [--seed N]
  cargo xtask sounddb import --recordings DIR --out DB [--name TEXT] [--material TEXT] [--obstacle TEXT] [--rate HZ] [--max-variants N]
  cargo xtask sounddb check DB";

/// Any error of the tool, printed as it is.
type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("sounddb: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &[String]) -> Result<()> {
    match args.first().map(String::as_str) {
        Some("import") => import(&args[1..]),
        Some("check") => match args.get(1) {
            Some(dir) if args.len() == 2 => check(Path::new(dir)),
            _ => Err(USAGE.into()),
        },
        Some("-h" | "--help") | None => {
            println!("{USAGE}");
            Ok(())
        }
        Some(_) => generate(args),
    }
}

/// Parses `--key value` pairs; unknown keys are errors.
fn options(args: &[String], known: &[&str]) -> Result<Vec<(String, String)>> {
    let mut out = Vec::new();
    let mut it = args.iter();
    while let Some(k) = it.next() {
        if !known.contains(&k.as_str()) {
            return Err(format!("unknown option {k:?}\n{USAGE}").into());
        }
        let v = it
            .next()
            .ok_or_else(|| format!("{k} needs a value\n{USAGE}"))?;
        out.push((k.clone(), v.clone()));
    }
    Ok(out)
}

fn get<'a>(opts: &'a [(String, String)], key: &str) -> Option<&'a str> {
    opts.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

fn generate(args: &[String]) -> Result<()> {
    let opts = options(args, &["--material", "--out", "--seed"])?;
    let material_name = get(&opts, "--material").ok_or(USAGE)?;
    let material = Material::from_name(material_name).ok_or_else(|| {
        format!("unknown material {material_name:?} (printer, tracing, banknote)")
    })?;
    let out = PathBuf::from(get(&opts, "--out").ok_or(USAGE)?);
    let seed = match get(&opts, "--seed") {
        Some(s) => s.parse::<u64>().map_err(|_| "--seed must be an integer")?,
        None => material.seed(),
    };
    let start = std::time::Instant::now();
    let db = sounddb::generate::generate_with_seed(material, seed);
    let secs = start.elapsed().as_secs_f64();
    db.write_dir(&out)?;
    println!(
        "generated the {} database (seed {seed}) in {secs:.2} s: SYNTHESIZED units, not recordings",
        material.name()
    );
    report_written(&out)
}

fn import(args: &[String]) -> Result<()> {
    let opts = options(
        args,
        &[
            "--recordings",
            "--out",
            "--name",
            "--material",
            "--obstacle",
            "--rate",
            "--max-variants",
        ],
    )?;
    let recordings = PathBuf::from(get(&opts, "--recordings").ok_or(USAGE)?);
    let out = PathBuf::from(get(&opts, "--out").ok_or(USAGE)?);
    let mut o = ImportOptions::default();
    if let Some(v) = get(&opts, "--name") {
        o.name = v.to_string();
    }
    if let Some(v) = get(&opts, "--material") {
        o.material = v.to_string();
    }
    if let Some(v) = get(&opts, "--obstacle") {
        o.obstacle = v.to_string();
    }
    if let Some(v) = get(&opts, "--rate") {
        o.rate_hz = v.parse().map_err(|_| "--rate must be an integer (Hz)")?;
        if !(8_000..=192_000).contains(&o.rate_hz) {
            return Err("--rate must be within 8000..=192000 Hz".into());
        }
    }
    if let Some(v) = get(&opts, "--max-variants") {
        o.max_variants = v.parse().map_err(|_| "--max-variants must be an integer")?;
    }
    let (db, report) = import_dir(&recordings, &o)?;
    for note in &report.notes {
        println!("  {note}");
    }
    if report.skipped > 0 {
        println!("{} file(s) skipped (see above)", report.skipped);
    }
    db.write_dir(&out)?;
    report_written(&out)
}

fn check(dir: &Path) -> Result<()> {
    let (db, warnings) = Database::load(dir)?;
    summary(&db, dir);
    print_warnings(&warnings);
    Ok(())
}

fn report_written(out: &Path) -> Result<()> {
    let (db, warnings) = Database::load(out).map_err(|e| {
        format!(
            "the database written to {} does not load: {e}",
            out.display()
        )
    })?;
    summary(&db, out);
    print_warnings(&warnings);
    Ok(())
}

fn summary(db: &Database, dir: &Path) {
    let unit_s: f64 = db
        .units
        .iter()
        .map(|u| u.samples.len() as f64 / f64::from(db.sample_rate_hz))
        .sum();
    let clac = db.units.iter().filter(|u| u.cell.is_constrained()).count();
    let bytes = dir_size(dir);
    println!(
        "{}: \"{}\" ({}), {} Hz; {} crumple units ({} flap, {} clac, {:.1} s of audio), {} friction spectra of {} bins; {:.2} MiB on disk",
        dir.display(),
        db.info.name,
        if db.info.synthesized {
            "synthesized"
        } else {
            "recorded"
        },
        db.sample_rate_hz,
        db.units.len(),
        db.units.len() - clac,
        clac,
        unit_s,
        db.spectra.len(),
        db.spectrum_bins,
        bytes as f64 / (1024.0 * 1024.0)
    );
}

fn print_warnings(warnings: &[Warning]) {
    if warnings.is_empty() {
        println!("no warnings");
    } else {
        println!("{} warning(s):", warnings.len());
        for w in warnings {
            println!("  warning: {w}");
        }
    }
}

fn dir_size(dir: &Path) -> u64 {
    let mut total = 0;
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            match e.file_type() {
                Ok(t) if t.is_dir() => total += dir_size(&e.path()),
                Ok(_) => total += e.metadata().map(|m| m.len()).unwrap_or(0),
                Err(_) => {}
            }
        }
    }
    total
}
