//! Prints the Table 4.1 analogues (quadratic-form distances between friction spectra of the
//! generated printer model) and the spectral centroids of the A4/A5/A6 analogue cells:
//! `cargo run -p sounddb --example table41`.
use sounddb::analysis::{centroid_hz, flatness, log_band_histogram, qf_distance};
use sounddb::generate::{
    Material, clip_rng, friction::constrained_spectrum, friction::free_spectrum,
};

fn hist(s: &[f32]) -> Vec<f64> {
    let m: Vec<f64> = s.iter().map(|v| f64::from(*v)).collect();
    log_band_histogram(&m, 44_100.0 / 4096.0)
}

fn main() {
    let p = Material::Printer.params();
    let spec = |s: f64, c: f64, comp: f64, seed: u64| {
        let mut rng = clip_rng(seed, 3, s as f32, c as f32, 0);
        free_spectrum(&p, s, c, comp, &mut rng, 44_100.0, 2048)
    };
    let lr: Vec<Vec<f64>> = [5.0, 10.0, 20.0]
        .iter()
        .map(|&s| hist(&spec(s, 10.0, 0.3, 1)))
        .collect();
    let lc: Vec<Vec<f64>> = [5.0, 10.0, 20.0]
        .iter()
        .map(|&c| hist(&spec(10.0, c, 0.3, 1)))
        .collect();
    let comp: Vec<Vec<f64>> = [0.2, 0.4, 0.8]
        .iter()
        .map(|&k| hist(&spec(10.0, 10.0, k, 1)))
        .collect();
    let shape: Vec<Vec<f64>> = [1u64, 2, 3]
        .iter()
        .map(|&k| hist(&spec(10.0, 10.0, 0.3, k)))
        .collect();
    let pairs = [(0, 1), (1, 2), (0, 2)];
    for (name, set) in [
        ("l_r", &lr),
        ("l_c/2", &lc),
        ("compression", &comp),
        ("realization", &shape),
    ] {
        for (a, b) in pairs {
            println!("{name} {a} vs {b}: {:.4}", qf_distance(&set[a], &set[b]));
        }
    }
    let df = 44_100.0 / 4096.0;
    let pw = |s: &[f32]| {
        s.iter()
            .map(|v| f64::from(*v).powi(2))
            .collect::<Vec<f64>>()
    };
    for (s, c) in [(10.0, 15.0), (10.0, 30.0), (20.0, 15.0), (20.0, 30.0)] {
        let x = pw(&spec(s, c, 0.3, 1));
        println!(
            "centroid s{s} c{c}: {:.1} Hz flat {:.3}",
            centroid_hz(&x, df),
            flatness(&x, df, 50.0, 20000.0)
        );
    }
    let mut rng = clip_rng(1, 4, 0.0, 0.0, 0);
    let x = pw(&constrained_spectrum(&p, &mut rng, 44_100.0, 2048));
    println!(
        "constrained centroid {:.1} flat {:.3}",
        centroid_hz(&x, df),
        flatness(&x, df, 50.0, 20000.0)
    );
    // Centroid over the whole grid (rows: l_r, columns: l_c/2).
    let db = sounddb::generate::generate(Material::Printer);
    let mut violations = 0;
    for (i, s) in db.spectra.iter().enumerate() {
        if let sounddb::Cell::Free { .. } = s.cell {
            let c = centroid_hz(&pw(&s.magnitudes), df);
            // Next along curved (same row) and along straight (+9).
            for j in [i + 1, i + 9] {
                if j < 81 && (j != i + 1 || (i + 1) % 9 != 0) {
                    let d = centroid_hz(&pw(&db.spectra[j].magnitudes), df);
                    if d >= c {
                        violations += 1;
                        println!(
                            "not decreasing: {} {c:.0} -> {} {d:.0}",
                            s.cell.label(),
                            db.spectra[j].cell.label()
                        );
                    }
                }
            }
        }
    }
    println!("grid centroid violations: {violations}");
}
