//! The sound database: bad databases (truncated WAV, wrong rate, missing cells, garbage manifest,
//! empty folder …) give precise errors or warnings and never panic; the generated defaults
//! (size, memory: digest-sound §12 test 16); the size trends of the synthetic friction spectra
//! (test 5) and Table 4.1's ordering (test 6); lookup (test 15); importing your own recordings.

mod render_common;

use std::path::{Path, PathBuf};

use render_common::*;
use sounddb::analysis::{centroid_hz, flatness, log_band_histogram, qf_distance};
use sounddb::generate::friction::{constrained_spectrum, free_spectrum};
use sounddb::generate::{Material, clip_rng, generate};
use sounddb::import::{ImportOptions, import_dir};
use sounddb::{Cell, Database, DbError, SoundDb, Warning};

/// A fresh, empty temporary folder.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("papier-render-db-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small valid database folder: 3 flap cells, the clac cell, 2 spectra.
fn small_db(dir: &Path) -> Database {
    let db = papier_tests::small_db::from(&generate(Material::Printer));
    db.write_dir(dir).unwrap();
    db
}

fn warnings_text(w: &[Warning]) -> String {
    w.iter().map(|w| format!("{w}\n")).collect()
}

#[test]
fn empty_folder_and_missing_folder_are_clear_errors() {
    let dir = temp_dir("empty");
    match Database::load(&dir) {
        Err(e @ DbError::MissingManifest(_)) => assert!(e.to_string().contains("no manifest.toml")),
        other => panic!("{other:?}"),
    }
    match Database::load(&dir.join("nope")) {
        Err(e @ DbError::NotAFolder(_)) => assert!(e.to_string().contains("nope")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn garbage_manifest_reports_the_line() {
    let dir = temp_dir("garbage");
    std::fs::write(
        dir.join("manifest.toml"),
        "format = \"papier-sounddb\"\nversion = 1\nname = [oops\n",
    )
    .unwrap();
    match Database::load(&dir) {
        Err(e @ DbError::Manifest { .. }) => {
            let msg = e.to_string();
            assert!(msg.contains("line 3"), "{msg}");
        }
        other => panic!("{other:?}"),
    }
    std::fs::write(dir.join("manifest.toml"), [0xff, 0xfe, 0x00, 0x41]).unwrap();
    assert!(matches!(
        Database::load(&dir),
        Err(DbError::Manifest { .. })
    ));
    std::fs::write(
        dir.join("manifest.toml"),
        "format = \"wav-bank\"\nversion = 7\nname = \"x\"\nsample_rate_hz = 44100\n",
    )
    .unwrap();
    let err = Database::load(&dir).unwrap_err();
    assert!(matches!(err, DbError::UnsupportedFormat { .. }), "{err}");
    std::fs::write(
        dir.join("manifest.toml"),
        "format = \"papier-sounddb\"\nversion = 1\nname = \"x\"\nsample_rate_hz = 5\n",
    )
    .unwrap();
    assert!(
        Database::load(&dir)
            .unwrap_err()
            .to_string()
            .contains("sample_rate_hz = 5")
    );
    // A valid manifest with no entry at all is an empty database.
    std::fs::write(
        dir.join("manifest.toml"),
        "format = \"papier-sounddb\"\nversion = 1\nname = \"x\"\nsample_rate_hz = 44100\n",
    )
    .unwrap();
    assert!(matches!(Database::load(&dir), Err(DbError::Empty { .. })));
}

#[test]
fn truncated_wav_and_wrong_rate_skip_only_their_entry() {
    let dir = temp_dir("truncated");
    let db = small_db(&dir);
    let n_units = db.units.len();
    // Truncate one unit, rewrite another at 48 kHz, delete a third, corrupt a spectrum.
    let files: Vec<PathBuf> = std::fs::read_dir(dir.join("crumple"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    let bytes = std::fs::read(&files[0]).unwrap();
    std::fs::write(&files[0], &bytes[..bytes.len() / 2]).unwrap();
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 48_000,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(&files[1], spec).unwrap();
    for i in 0..4800 {
        w.write_sample(((i as f32 * 0.1).sin() * 10_000.0) as i16)
            .unwrap();
    }
    w.finalize().unwrap();
    std::fs::remove_file(&files[2]).unwrap();
    let spectra: Vec<PathBuf> = std::fs::read_dir(dir.join("friction"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    std::fs::write(&spectra[0], [0u8; 10]).unwrap();
    std::fs::write(dir.join("crumple/stray.wav"), b"RIFF").unwrap();

    let (back, warnings) = Database::load(&dir).unwrap();
    let text = warnings_text(&warnings);
    eprintln!("{text}");
    assert_eq!(back.units.len(), n_units - 3);
    assert_eq!(back.spectra.len(), 1);
    assert!(
        text.contains(&files[0].file_name().unwrap().to_string_lossy().to_string())
            && text.contains("not a readable WAV")
    );
    assert!(text.contains("48000 Hz") && text.contains("44100 Hz"));
    assert!(text.contains("is missing"));
    assert!(text.contains("has 10 bytes, expected 8192"));
    assert!(text.contains("stray.wav is not listed"));
    assert!(warnings.iter().any(|w| matches!(
        w,
        Warning::MissingCells {
            what: "crumple",
            ..
        }
    )));
    // Still usable: prepared and played.
    let prepared = SoundDb::prepare(&back, 48_000.0);
    assert!(prepared.crumple_lookup(12.0, 14.0).is_some());
}

#[test]
fn missing_cells_use_the_nearest_occupied_cell() {
    // digest-sound §12 test 15 on a partial database, with the documented metric.
    let dir = temp_dir("missing");
    small_db(&dir);
    let (db, warnings) = Database::load(&dir).unwrap();
    assert!(warnings.iter().any(|w| matches!(
        w,
        Warning::MissingCells {
            what: "crumple",
            missing: 78,
            ..
        }
    )));
    let p = SoundDb::prepare(&db, 44_100.0);
    let cell =
        |lr: f32, lc: f32| p.crumple_cells()[p.crumple_lookup(lr, lc).unwrap().0 as usize].cell;
    assert_eq!(cell(10.0, 0.0), Cell::Constrained);
    // (l_r, l_c/2) = (11, 6.1) → (10, 5) in log distance.
    assert_eq!(
        cell(11.0, 12.2),
        Cell::Free {
            straight_cm: 10.0,
            curved_cm: 5.0
        }
    );
    // (25, 25) is nearer (20, 20) than (5, 30); (4, 28) goes to (5, 30).
    assert_eq!(
        cell(25.0, 50.0),
        Cell::Free {
            straight_cm: 20.0,
            curved_cm: 20.0
        }
    );
    assert_eq!(
        cell(4.0, 56.0),
        Cell::Free {
            straight_cm: 5.0,
            curved_cm: 30.0
        }
    );
}

#[test]
fn full_database_lookup_uses_half_lc() {
    let p = printer_db(44_100.0);
    let cell =
        |lr: f32, lc: f32| p.crumple_cells()[p.crumple_lookup(lr, lc).unwrap().0 as usize].cell;
    // A 10 × 10 cm sheet bent along one edge has two curved edges: l_c = 20 → cell (10, 10).
    assert_eq!(
        cell(10.0, 20.0),
        Cell::Free {
            straight_cm: 10.0,
            curved_cm: 10.0
        }
    );
    assert_eq!(
        cell(11.0, 12.2),
        Cell::Free {
            straight_cm: 10.0,
            curved_cm: 5.0
        }
    );
    assert_eq!(cell(10.0, 0.0), Cell::Constrained);
    let f = p.friction_cells()[p.friction_lookup(30.0, 60.0).unwrap().0 as usize].cell;
    assert_eq!(
        f,
        Cell::Free {
            straight_cm: 30.0,
            curved_cm: 30.0
        }
    );
}

#[test]
fn the_loader_never_panics_on_corrupted_input() {
    let full = generate(Material::Banknote);
    let mut db = Database::new(full.info.clone(), 44_100);
    db.units = full.units.iter().step_by(25).cloned().collect();
    db.spectra = full.spectra.iter().step_by(20).cloned().collect();
    let mut files = db.to_files();
    let keys: Vec<String> = files.keys().cloned().collect();
    let mut g = Lcg(99);
    for round in 0..400 {
        let mut mutated = files.clone();
        let key = &keys[(g.next() * keys.len() as f32) as usize % keys.len()];
        let data = mutated.get_mut(key).unwrap();
        match round % 4 {
            0 => data.truncate((g.next() * data.len() as f32) as usize),
            1 => {
                for _ in 0..8 {
                    if !data.is_empty() {
                        let i = (g.next() * data.len() as f32) as usize % data.len();
                        data[i] = (g.next() * 255.0) as u8;
                    }
                }
            }
            2 => data.clear(),
            _ => {
                mutated.remove(key);
            }
        }
        let pack = sounddb::pack::pack(&mutated);
        let result = std::panic::catch_unwind(|| {
            let r = Database::from_pack(&pack, "fuzz");
            if let Ok((d, _)) = &r {
                let _ = SoundDb::prepare(d, 48_000.0);
            }
            r.is_ok()
        });
        assert!(result.is_ok(), "panic on round {round} ({key})");
        files = db.to_files();
    }
    // A corrupted pack is an error too.
    let pack = db.to_pack();
    for cut in [0usize, 7, 20, pack.len() / 2] {
        assert!(matches!(
            Database::from_pack(&pack[..cut], "cut"),
            Err(DbError::BadPack(_))
        ));
    }
}

#[test]
fn test16_default_databases_size_and_memory() {
    for m in Material::ALL {
        let db = generate(m);
        let bytes = db.to_pack().len();
        eprintln!("{}: {:.2} MiB packed", m.name(), bytes as f64 / 1_048_576.0);
        assert!(bytes <= 12 * 1024 * 1024, "{}: {bytes} bytes", m.name());
        assert_eq!(db.units.len(), 249);
        assert_eq!(db.spectra.len(), 82);
        // Deterministic.
        assert_eq!(generate(m).to_pack(), db.to_pack());
    }
    let (embedded, warnings) = papier::render::default_db::embedded_database().unwrap();
    assert!(warnings.is_empty());
    assert_eq!(embedded, {
        let (d, _) = Database::from_pack(&generate(Material::Printer).to_pack(), "x").unwrap();
        d
    });
    let mem = printer_db(44_100.0).memory_bytes();
    eprintln!(
        "test 16: printer database prepared at 44.1 kHz: {:.2} MB",
        mem as f64 / 1e6
    );
    assert!(mem <= 10_000_000, "{mem}");
}

fn hist(s: &[f32]) -> Vec<f64> {
    let m: Vec<f64> = s.iter().map(|v| f64::from(*v)).collect();
    log_band_histogram(&m, 44_100.0 / 4096.0)
}

fn power(s: &[f32]) -> Vec<f64> {
    s.iter().map(|v| f64::from(*v).powi(2)).collect()
}

#[test]
fn test5_spectral_centroid_falls_with_size_and_flat_is_flattest() {
    let db = generate(Material::Printer);
    let df = 44_100.0 / 4096.0;
    let spectrum = |s: f32, c: f32| {
        &db.spectra
            .iter()
            .find(|x| {
                x.cell.same_as(&Cell::Free {
                    straight_cm: s,
                    curved_cm: c,
                })
            })
            .unwrap()
            .magnitudes
    };
    // A4 (21 × 29.7 → cell 20 × 30), half-A4 (20 × 15), A5 (10 × 30), A6 (10 × 15).
    let centroid = |s: f32, c: f32| centroid_hz(&power(spectrum(s, c)), df);
    let (a4, half, a5, a6) = (
        centroid(20.0, 30.0),
        centroid(20.0, 15.0),
        centroid(10.0, 30.0),
        centroid(10.0, 15.0),
    );
    eprintln!("test 5: centroids A6 {a6:.0} A5 {a5:.0} half-A4 {half:.0} A4 {a4:.0} Hz");
    assert!(a6 > a5 && half > a4, "decreasing with l_c");
    assert!(a6 > half && a5 > a4, "decreasing with l_r");
    let flat = db.spectra.iter().find(|s| s.cell.is_constrained()).unwrap();
    let f0 = flatness(&power(&flat.magnitudes), df, 50.0, 20_000.0);
    for s in db.spectra.iter().filter(|s| !s.cell.is_constrained()) {
        let f = flatness(&power(&s.magnitudes), df, 50.0, 20_000.0);
        assert!(
            f0 > f,
            "{}: flatness {f} ≥ constrained {f0}",
            s.cell.label()
        );
    }
    // Whole grid: count the pairs of neighbours where the centroid does not fall with size.
    let mut violations = 0;
    let mut pairs = 0;
    for (i, s) in sounddb::GRID_CM.iter().enumerate() {
        for (j, c) in sounddb::GRID_CM.iter().enumerate() {
            let here = centroid(*s, *c);
            if i + 1 < 9 {
                pairs += 1;
                violations += usize::from(centroid(sounddb::GRID_CM[i + 1], *c) >= here);
            }
            if j + 1 < 9 {
                pairs += 1;
                violations += usize::from(centroid(*s, sounddb::GRID_CM[j + 1]) >= here);
            }
        }
    }
    eprintln!(
        "test 5: centroid rises with size for {violations} of {pairs} neighbouring cell pairs"
    );
    assert!(violations * 20 <= pairs, "{violations} of {pairs}");
}

#[test]
fn test6_table_4_1_ordering_of_spectral_distances() {
    let p = Material::Printer.params();
    let spec = |s: f64, c: f64, comp: f64, seed: u64| {
        let mut rng = clip_rng(seed, 3, s as f32, c as f32, 0);
        hist(&free_spectrum(&p, s, c, comp, &mut rng, 44_100.0, 2048))
    };
    let series = |f: &dyn Fn(f64) -> Vec<f64>| [5.0, 10.0, 20.0].map(f);
    // l_r series at l_c/2 = 10 cm, l_c/2 series at l_r = 10 cm, 30 % compression (T 1915).
    let lr = series(&|v| spec(v, 10.0, 0.3, 1));
    let lc = series(&|v| spec(10.0, v, 0.3, 1));
    let comp = [0.2, 0.4, 0.8].map(|k| spec(10.0, 10.0, k, 1));
    // Shape analogues: our panels are rectangles, so "shape" pairs are independent realisations
    // of the 10 × 10 cell (what remains of S1/S2/S3 once l_r and l_c are equal).
    let shape = [1u64, 2, 3].map(|k| spec(10.0, 10.0, 0.3, k));
    let d = |s: &[Vec<f64>; 3], a: usize, b: usize| qf_distance(&s[a], &s[b]);
    let (r510, r1020, r520) = (d(&lr, 0, 1), d(&lr, 1, 2), d(&lr, 0, 2));
    let (c510, c1020, c520) = (d(&lc, 0, 1), d(&lc, 1, 2), d(&lc, 0, 2));
    let others: Vec<f64> = [(0, 1), (1, 2), (0, 2)]
        .iter()
        .flat_map(|&(a, b)| [d(&comp, a, b), d(&shape, a, b)])
        .collect();
    eprintln!(
        "test 6 (seed T 1927–1933 in brackets): l_r 5v10 {r510:.3} [0.10], 10v20 {r1020:.3} [0.07], 5v20 {r520:.3} [0.16]; \
         l_c/2 5v10 {c510:.3} [0.04], 10v20 {c1020:.3} [0.12], 5v20 {c520:.3} [0.13]; \
         compression 20v40 {:.3} [0.03], 40v80 {:.3} [0.05], 20v80 {:.3} [0.03]; realisations {:.3} {:.3} {:.3} [shapes 0.01–0.04]",
        others[0], others[2], others[4], others[1], others[3], others[5]
    );
    assert!(r520 > r510 && r520 > r1020);
    assert!(c520 > c510 && c520 > c1020);
    let floor = r520.min(c520);
    for o in &others {
        assert!(*o < floor, "{o} ≥ {floor}");
    }
}

#[test]
fn constrained_friction_is_quieter() {
    let p = Material::Printer.params();
    let mut rng = clip_rng(1, 4, 0.0, 0.0, 0);
    let flat: f64 = constrained_spectrum(&p, &mut rng, 44_100.0, 2048)
        .iter()
        .map(|v| f64::from(*v).powi(2))
        .sum();
    let mut rng = clip_rng(1, 3, 10.0, 10.0, 0);
    let free: f64 = free_spectrum(&p, 10.0, 10.0, 0.3, &mut rng, 44_100.0, 2048)
        .iter()
        .map(|v| f64::from(*v).powi(2))
        .sum();
    assert!(flat < free);
}

/// Writes a mono 16-bit WAV.
fn write_wav(path: &Path, rate: u32, x: &[f32]) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for v in x {
        w.write_sample((v.clamp(-1.0, 1.0) * 32_767.0) as i16)
            .unwrap();
    }
    w.finalize().unwrap();
}

#[test]
fn importing_recordings_builds_a_loadable_database() {
    // "Recordings" made from the generator's own units and spectra, with a noise floor, gaps,
    // another sample rate, a bad name and an annotation.
    let rec = temp_dir("recordings");
    let src = generate(Material::Printer);
    let mut g = Lcg(5);
    let noise =
        |n: usize, g: &mut Lcg| -> Vec<f32> { (0..n).map(|_| (g.next() - 0.5) * 2e-4).collect() };
    let unit = |s: f32, c: f32, v: usize| {
        src.units
            .iter()
            .filter(|u| {
                u.cell.same_as(&Cell::Free {
                    straight_cm: s,
                    curved_cm: c,
                })
            })
            .nth(v)
            .unwrap()
            .samples
            .clone()
    };
    // Three flips with 0.4 s gaps.
    let mut flips = noise(22_050, &mut g);
    for v in 0..3 {
        flips.extend(unit(10.0, 5.0, v).iter().map(|x| x * 2.0));
        flips.extend(noise(17_640, &mut g));
    }
    write_wav(&rec.join("flap_s10_c5.wav"), 44_100, &flips);
    // Clacks.
    let clacs: Vec<f32> = src
        .units
        .iter()
        .filter(|u| u.cell.is_constrained())
        .flat_map(|u| {
            let mut v = u.samples.clone();
            v.extend(noise(8_000, &mut Lcg(1)));
            v
        })
        .collect();
    write_wav(&rec.join("clac_take1.wav"), 44_100, &clacs);
    // A slide at 48 kHz: 2 s of noise between silences.
    let mut slide = noise(24_000, &mut g);
    slide.extend((0..96_000).map(|_| (g.next() - 0.5) * 0.2));
    slide.extend(noise(24_000, &mut g));
    write_wav(&rec.join("friction_s20_c15.wav"), 48_000, &slide);
    write_wav(&rec.join("friction_flat.wav"), 48_000, &slide);
    // Annotated file and a badly named one.
    write_wav(&rec.join("take3.wav"), 44_100, &flips);
    std::fs::write(
        rec.join("annotations.toml"),
        "[[recording]]\nfile = \"take3.wav\"\nkind = \"flap\"\nstraight_cm = 12.5\ncurved_cm = 7.5\n",
    )
    .unwrap();
    write_wav(&rec.join("snare.wav"), 44_100, &flips[..1000]);

    let (db, report) = import_dir(&rec, &ImportOptions::default()).unwrap();
    let notes = report.notes.join("\n");
    eprintln!("{notes}");
    assert_eq!(report.skipped, 1);
    assert!(notes.contains("snare.wav"));
    let count = |c: Cell| db.units.iter().filter(|u| u.cell.same_as(&c)).count();
    assert_eq!(
        count(Cell::Free {
            straight_cm: 10.0,
            curved_cm: 5.0
        }),
        3
    );
    assert_eq!(
        count(Cell::Free {
            straight_cm: 12.5,
            curved_cm: 7.5
        }),
        3
    );
    assert_eq!(count(Cell::Constrained), 6);
    assert_eq!(db.spectra.len(), 2);
    // The 2 s slide of uniform noise ±0.1: variance 0.01/3 over 0–24 kHz, of which the database
    // keeps 0–22.05 kHz.
    let total: f64 = db.spectra[0]
        .magnitudes
        .iter()
        .map(|v| f64::from(*v).powi(2))
        .sum();
    let expect = 0.01 / 3.0 * 22_050.0 / 24_000.0;
    assert!((total / expect - 1.0).abs() < 0.15, "{total} vs {expect}");
    // Written and read back through the validating loader, then played.
    let out = temp_dir("imported");
    db.write_dir(&out).unwrap();
    let (back, warnings) = Database::load(&out).unwrap();
    assert_eq!(back.units.len(), db.units.len());
    assert!(!back.info.synthesized);
    assert!(
        warnings
            .iter()
            .any(|w| matches!(w, Warning::MissingCells { .. }))
    );
    let prepared = std::sync::Arc::new(SoundDb::prepare(&back, 48_000.0));
    let mut r = renderer(48_000.0, prepared, 1, anechoic());
    r.trigger(&crumple(1.0, resonator(10.0, 10.0)));
    r.set_frame(&frame(0, &[friction(0.1, resonator(20.0, 30.0))], 0.0));
    let (l, _) = render(&mut r, 48_000, 512);
    assert!(rms(&l) > 1e-3);
    // And in papier-render (`--db`): a seed scene plays the imported database.
    let wav = out.join("render.wav");
    let report = papier::offline::render(&papier::offline::cli::RenderOptions {
        db: Some(out.clone()),
        quiet: true,
        ..papier::offline::cli::RenderOptions::new(
            vec![papier::offline::cli::InputSpec::Scene(
                "s1_slide_release_pinch".into(),
            )],
            wav.clone(),
        )
    })
    .expect("papier-render --db with the imported database");
    eprintln!("{report}");
    assert!(
        report.rms > 1e-4,
        "the imported database is heard: {report}"
    );
    assert!(report.peak.is_finite());
    // Nothing usable → an error naming the folder.
    let empty = temp_dir("no-recordings");
    std::fs::write(empty.join("readme.txt"), "x").unwrap();
    let err = import_dir(&empty, &ImportOptions::default()).unwrap_err();
    assert!(err.to_string().contains("no usable recording"));
}

/// Total size of the files under `dir`, bytes.
fn dir_bytes(dir: &Path) -> u64 {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            if e.file_type().unwrap().is_dir() {
                dir_bytes(&e.path())
            } else {
                e.metadata().unwrap().len()
            }
        })
        .sum()
}

/// What `cargo xtask sounddb --material M --out DIR` does (sounddb/src/main.rs: generate
/// with the material's seed, write the folder, load it back through the validating loader), for
/// every material: the folder loads with no warning at all; every (l_r, l_c/2) cell of the grid
/// {2.5, …, 30} cm holds the 3 flap variants and the 1 friction spectrum the generator promises
/// (sounddb::generate) and the (0, 0) cell its 6 clacs and 1 spectrum, nothing else; every unit
/// and spectrum is non-empty and finite; the folder is at most 12 MiB on disk. Detects cells or
/// variants the generator drops, files the writer names differently from the manifest (warnings),
/// and a database that outgrows its budget.
#[test]
fn generated_database_folders_load_without_warnings_with_every_cell() {
    for m in Material::ALL {
        let dir = temp_dir(&format!("generated-{}", m.name()));
        sounddb::generate::generate_with_seed(m, m.seed())
            .write_dir(&dir)
            .unwrap();
        let (db, warnings) = Database::load(&dir).unwrap();
        assert!(
            warnings.is_empty(),
            "{}: {}",
            m.name(),
            warnings_text(&warnings)
        );
        let units = |c: &Cell| db.units.iter().filter(|u| u.cell.same_as(c)).count();
        let spectra = |c: &Cell| db.spectra.iter().filter(|s| s.cell.same_as(c)).count();
        for s in sounddb::GRID_CM {
            for c in sounddb::GRID_CM {
                let cell = Cell::Free {
                    straight_cm: s,
                    curved_cm: c,
                };
                assert_eq!(units(&cell), 3, "{}: flaps of {}", m.name(), cell.label());
                assert_eq!(
                    spectra(&cell),
                    1,
                    "{}: spectra of {}",
                    m.name(),
                    cell.label()
                );
            }
        }
        assert_eq!(units(&Cell::Constrained), 6, "{}: clacs", m.name());
        assert_eq!(spectra(&Cell::Constrained), 1, "{}", m.name());
        assert_eq!(
            (db.units.len(), db.spectra.len()),
            (81 * 3 + 6, 81 + 1),
            "{}: no cell off the grid",
            m.name()
        );
        for u in &db.units {
            assert!(
                !u.samples.is_empty() && u.samples.iter().all(|v| v.is_finite()),
                "{}: unit {}",
                m.name(),
                u.file
            );
            assert!(
                u.samples.iter().any(|v| *v != 0.0),
                "{}: silent {}",
                m.name(),
                u.file
            );
        }
        for s in &db.spectra {
            assert_eq!(s.magnitudes.len(), sounddb::SPECTRUM_BINS);
            assert!(
                s.magnitudes.iter().all(|v| v.is_finite() && *v >= 0.0)
                    && s.magnitudes.iter().any(|v| *v > 0.0),
                "{}: spectrum {}",
                m.name(),
                s.file
            );
        }
        let bytes = dir_bytes(&dir);
        eprintln!(
            "{}: {:.2} MiB on disk",
            m.name(),
            bytes as f64 / 1_048_576.0
        );
        assert!(bytes <= 12 * 1024 * 1024, "{}: {bytes} bytes", m.name());
    }
}

/// A low tone: `f_hz[0]` and, 12 dB down, `f_hz[1]` (two equal partials would beat and the
/// importer would hear an onset at every beat).
fn low_tone(f_hz: [f64; 2], t_s: f64) -> f64 {
    (2.0 * std::f64::consts::PI * f_hz[0] * t_s).sin()
        + 0.25 * (2.0 * std::f64::consts::PI * f_hz[1] * t_s).sin()
}

/// Decaying [`low_tone`] bursts (time constant `tau_s`) of `burst_s` each, every `period_s`,
/// over a −90 dBFS noise floor: "recordings" of flips or clacks.
fn tone_bursts(
    rate: f64,
    partials_hz: [f64; 2],
    count: usize,
    burst_s: f64,
    period_s: f64,
    tau_s: f64,
    g: &mut Lcg,
) -> Vec<f32> {
    let n = ((0.3 + count as f64 * period_s) * rate) as usize;
    let mut x: Vec<f32> = (0..n).map(|_| (g.next() - 0.5) * 6e-5).collect();
    for b in 0..count {
        let start = ((0.3 + b as f64 * period_s) * rate) as usize;
        for i in 0..(burst_s * rate) as usize {
            let t = i as f64 / rate;
            x[start + i] += (0.3 * (-t / tau_s).exp() * low_tone(partials_hz, t)) as f32;
        }
    }
    x
}

/// Share of the power of `x` below `hz`, and the spectral centroid, Hz (Welch, 4096 points).
fn low_share_and_centroid(x: &[f32], rate: f64, hz: f64) -> (f64, f64) {
    let psd = sounddb::analysis::welch_psd(x, rate, 4096);
    let df = rate / 4096.0;
    let total: f64 = psd.iter().sum();
    let low: f64 = psd
        .iter()
        .enumerate()
        .filter(|(k, _)| (*k as f64) * df < hz)
        .map(|(_, p)| p)
        .sum();
    (low / total, centroid_hz(&psd, df))
}

/// A database imported from recordings the test writes (low tones only: 300–600 Hz flaps,
/// clacks and slides, where the synthesized printer paper rings in the kHz) and passed to the
/// `papier-render` binary with `--db` plays a seed scene finitely and audibly, and clearly not
/// with the embedded database: the render with `--db` has ≥ 80 % of its power below 1 kHz and
/// a centroid under 1 kHz, the same scene with the embedded database has less than half of its
/// power below 1 kHz and a centroid at least twice as high. Detects `--db` being ignored, a
/// database that loads but is not played (silence), and an import that loses the recordings'
/// spectra.
#[test]
fn papier_render_plays_an_imported_database() {
    let rec = temp_dir("low-recordings");
    let rate = 44_100.0;
    let mut g = Lcg(17);
    for (name, partials) in [
        ("flap_s10_c5.wav", [300.0, 450.0]),
        ("flap_s20_c20.wav", [320.0, 480.0]),
        ("flap_s5_c30.wav", [350.0, 525.0]),
        ("flap_s30_c2p5.wav", [330.0, 495.0]),
    ] {
        let x = tone_bursts(rate, partials, 3, 0.35, 0.6, 0.08, &mut g);
        write_wav(&rec.join(name), rate as u32, &x);
    }
    let clacs = tone_bursts(rate, [400.0, 600.0], 6, 0.05, 0.15, 0.01, &mut g);
    write_wav(&rec.join("clac_low.wav"), rate as u32, &clacs);
    // Slides: 2 s of steady tones between silences.
    for (name, partials) in [
        ("friction_s20_c15.wav", [310.0, 470.0]),
        ("friction_s5_c5.wav", [360.0, 540.0]),
        ("friction_flat.wav", [380.0, 570.0]),
    ] {
        let n = (3.0 * rate) as usize;
        let x: Vec<f32> = (0..n)
            .map(|i| {
                let t = i as f64 / rate;
                let on = (0.5..2.5).contains(&t);
                let tone = if on {
                    0.15 * low_tone(partials, t)
                } else {
                    0.0
                };
                tone as f32 + (g.next() - 0.5) * 6e-5
            })
            .collect();
        write_wav(&rec.join(name), rate as u32, &x);
    }
    let (db, report) = import_dir(&rec, &ImportOptions::default()).unwrap();
    eprintln!("{}", report.notes.join("\n"));
    assert_eq!(report.skipped, 0, "{:?}", report.notes);
    // One unit per burst, one spectrum per slide.
    assert_eq!((db.units.len(), db.spectra.len()), (4 * 3 + 6, 3));
    let dbdir = temp_dir("low-db");
    db.write_dir(&dbdir).unwrap();

    let out = temp_dir("low-render");
    let scene = "s1_slide_release_pinch";
    let render = |extra: &[&str], tag: &str| -> (Vec<f32>, f64) {
        let wav = out.join(format!("{tag}.wav"));
        let mut args = vec!["--scene", scene, "--out", wav.to_str().unwrap(), "--quiet"];
        args.extend(extra);
        let o = std::process::Command::new(papier_tests::paths::papier_render())
            .args(&args)
            .output()
            .expect("run papier-render");
        assert!(
            o.status.success(),
            "{tag}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let (sr, l, r) = papier_tests::audio::read_stereo(&wav);
        assert!(
            papier_tests::audio::all_finite_normal(&l)
                && papier_tests::audio::all_finite_normal(&r),
            "{tag}"
        );
        let mono: Vec<f32> = l.iter().zip(&r).map(|(a, b)| 0.5 * (a + b)).collect();
        (mono, f64::from(sr))
    };
    let (imported, sr) = render(&["--db", dbdir.to_str().unwrap()], "imported");
    let (default, _) = render(&[], "default");
    assert_eq!(imported.len(), default.len());
    let (rms_i, rms_d) = (rms(&imported), rms(&default));
    let (low_i, centroid_i) = low_share_and_centroid(&imported, sr, 1_000.0);
    let (low_d, centroid_d) = low_share_and_centroid(&default, sr, 1_000.0);
    eprintln!(
        "{scene}: imported database RMS {rms_i:.2e}, {:.0} % below 1 kHz, centroid {centroid_i:.0} Hz; \
         embedded RMS {rms_d:.2e}, {:.0} % below 1 kHz, centroid {centroid_d:.0} Hz",
        100.0 * low_i,
        100.0 * low_d
    );
    assert!(rms_i > 1e-4, "the imported database is heard: RMS {rms_i}");
    assert!(rms_d > 1e-4, "the embedded database is heard: RMS {rms_d}");
    assert!(
        low_i >= 0.8 && centroid_i < 1_000.0,
        "the render with --db does not sound like the low recordings"
    );
    assert!(
        low_d < 0.5 && centroid_d > 2.0 * centroid_i,
        "the embedded database should sound clearly brighter"
    );
}
