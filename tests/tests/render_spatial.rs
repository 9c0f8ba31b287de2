//! Dipole and image-source spatialization (thesis eq. 4.11 / 4.12; digest-sound §5, §12 tests 9,
//! 10, 11): delays and gains of the direct and image taps of a unit, the comb of a friction
//! spectrum near the table, and the no-reflector shortcut.

mod render_common;

use std::sync::Arc;

use papier::render::dipole::{COS_FLOOR, comb_magnitude, ear_paths};
use papier::render::ears::{EAR_HALF_SPACING_M, SPEED_OF_SOUND_M_S};
use papier::render::{RenderOptions, Scene};
use render_common::*;
use sim_core::RoomConfig;
use sim_core::room::Plane;
use sim_core::sound_input::Resonator;
use sounddb::{Cell, Database, DbInfo, FrictionSpectrum, SoundDb, Unit};

const RATE: f64 = 44_100.0;

/// A database whose only unit is a unit impulse and whose only spectrum is white.
fn impulse_db() -> Arc<SoundDb> {
    let mut db = Database::new(DbInfo::default(), 44_100);
    let mut x = vec![0.0f32; 32];
    x[0] = 1.0;
    db.units.push(Unit {
        cell: Cell::Constrained,
        samples: x,
        file: String::new(),
    });
    db.spectra.push(FrictionSpectrum {
        cell: Cell::Constrained,
        magnitudes: vec![0.001; 2048],
        speed_m_s: 0.1,
        file: String::new(),
    });
    Arc::new(SoundDb::prepare(&db, RATE))
}

/// Listener to the right of the table (az 90°, 1 m), table top at 40 cm: head at (1, 0, 0.85),
/// ears at y = ∓0.085.
fn side_scene(table: bool) -> Scene {
    Scene {
        room: RoomConfig {
            table,
            table_height_cm: 40.0,
            wall: false,
            wall_dist_cm: 40.0,
        },
        listener_az_deg: 90.0,
        listener_dist_m: 1.0,
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Sum and first moment of x over [lo, hi].
fn cluster(x: &[f32], lo: usize, hi: usize) -> (f64, f64) {
    let s: f64 = x[lo..=hi].iter().map(|v| f64::from(*v)).sum();
    let m: f64 = x[lo..=hi]
        .iter()
        .enumerate()
        .map(|(i, v)| (lo + i) as f64 * f64::from(*v))
        .sum();
    (s, m / s)
}

#[test]
fn test9_direct_and_image_taps_of_a_unit() {
    let mut r = renderer(RATE, impulse_db(), 1, side_scene(true));
    let y = [0.0, 0.0, 0.45]; // 5 cm above the table top (z = 0.40)
    let res = Resonator {
        lr_cm: 10.0,
        lc_cm: 0.0,
        centre_m: [0.0, 0.0, 0.45],
        normal: [0.0, 0.0, 1.0],
        radius_m: 0.05,
    };
    r.trigger(&crumple(1.0, res));
    let (l, rr) = render(&mut r, 64, 64);
    let centre = [1.0, 0.0, 0.85];
    let y_img = [0.0, 0.0, 0.35];
    let c = SPEED_OF_SOUND_M_S;
    for (ear_y, out) in [(-EAR_HALF_SPACING_M, &l), (EAR_HALF_SPACING_M, &rr)] {
        let ear = [1.0, ear_y, 0.85];
        let (d, di, dc) = (dist(ear, y), dist(ear, y_img), dist(centre, y));
        let g0 = ((ear[2] - y[2]) / d) / d;
        let g1 = (-(ear[2] - y_img[2]) / di) / di;
        let base = EAR_HALF_SPACING_M / c;
        let d0 = ((d - dc) / c + base) * RATE;
        let d1 = ((di - dc) / c + base) * RATE;
        let (i0, i1) = (d0.floor() as usize, d1.floor() as usize);
        assert!(i0 + 2 < i1 - 1, "clusters overlap");
        let (s0, m0) = cluster(out, i0 - 1, i0 + 2);
        let (s1, m1) = cluster(out, i1 - 1, i1 + 2);
        // Nothing outside the two clusters.
        let outside: f64 = out
            .iter()
            .enumerate()
            .filter(|(i, _)| !((i0 - 1..=i0 + 2).contains(i) || (i1 - 1..=i1 + 2).contains(i)))
            .map(|(_, v)| f64::from(v.abs()))
            .sum();
        assert_eq!(outside, 0.0);
        // Two peaks.
        let peak = out.iter().fold(0.0f32, |m, v| m.max(v.abs()));
        let peaks = (1..63)
            .filter(|&i| {
                out[i].abs() > 0.2 * peak
                    && out[i].abs() >= out[i - 1].abs()
                    && out[i].abs() > out[i + 1].abs()
            })
            .count();
        assert_eq!(peaks, 2);
        let expected_delay = (di - d) / c * RATE;
        eprintln!(
            "test 9 ear {ear_y:+}: image delay {:.4} (expected {expected_delay:.4}) samples, ratio {:.5} (expected {:.5})",
            m1 - m0,
            s1 / s0,
            g1 / g0
        );
        assert!((m0 - d0).abs() <= 0.05, "direct at {m0}, expected {d0}");
        assert!((m1 - d1).abs() <= 0.05, "image at {m1}, expected {d1}");
        assert!(((m1 - m0) - expected_delay).abs() <= 0.05);
        assert!(
            ((s1 / s0) / (g1 / g0) - 1.0).abs() <= 1e-3,
            "{} vs {}",
            s1 / s0,
            g1 / g0
        );
        assert!((s0 / g0 - 1.0).abs() <= 1e-3, "direct gain {s0} vs {g0}");
    }
}

#[test]
fn test9_listener_in_the_sheet_plane_hears_the_floor() {
    // No table; the sheet at ear height with its normal vertical: cos θ = 0 at both ears.
    let mut r = renderer(RATE, impulse_db(), 1, side_scene(false));
    let res = Resonator {
        lr_cm: 10.0,
        lc_cm: 0.0,
        centre_m: [0.0, 0.0, 0.85],
        normal: [0.0, 0.0, 1.0],
        radius_m: 0.05,
    };
    r.trigger(&crumple(1.0, res));
    let (l, _) = render(&mut r, 64, 64);
    // cos θ is ±0 up to rounding (f32 centre vs f64 ear): either polarity of the floor.
    let sum: f64 = l.iter().map(|v| f64::from(*v)).sum::<f64>().abs();
    let d = (1.0f64 + EAR_HALF_SPACING_M * EAR_HALF_SPACING_M).sqrt();
    assert!(sum <= COS_FLOOR / d * (1.0 + 1e-3), "{sum}");
    assert!((sum / (COS_FLOOR / d) - 1.0).abs() < 1e-3);
    // Facing the same listener, the same source is ≥ 10 × louder.
    let mut r = renderer(RATE, impulse_db(), 1, side_scene(false));
    r.trigger(&crumple(
        1.0,
        Resonator {
            normal: [1.0, 0.0, 0.0],
            ..res
        },
    ));
    let (l, _) = render(&mut r, 64, 64);
    let facing: f64 = l.iter().map(|v| f64::from(*v)).sum();
    assert!(facing > 9.9 * sum);
}

/// First local minimum of |H| (bins j·df) above 1 bin.
fn first_notch_hz(mag: &[f32], df: f64) -> f64 {
    let j = (2..mag.len() - 1)
        .find(|&j| mag[j] < mag[j - 1] && mag[j] <= mag[j + 1])
        .unwrap();
    j as f64 * df
}

#[test]
fn test10_comb_of_the_table_image_in_frequency() {
    // Tangential dipole (n = +x, towards the listener): image and direct have the same sign, the
    // first notch is at c / (2 (R̃ − R)).
    let table = Plane {
        point_m: [0.0, 0.0, 0.0],
        normal: [0.0, 0.0, 1.0],
    };
    let ear = [1.0, 0.0, 0.3];
    let m = 2048usize;
    let df = RATE / m as f64;
    let mut notch = Vec::new();
    for d in [0.02, 0.06] {
        let p = ear_paths(
            [0.0, 0.0, d],
            [1.0, 0.0, 0.0],
            1.0,
            ear,
            &[table],
            COS_FLOOR,
        );
        assert_eq!(p.num_images, 1);
        assert!(p.images[0].gain > 0.0 && p.direct.gain > 0.0);
        let mut mag = vec![0.0f32; m / 2 + 1];
        comb_magnitude(&p, 2.0 * std::f64::consts::PI * df, &mut mag);
        let expected = SPEED_OF_SOUND_M_S
            / (2.0 * (p.images[0].delay_s - p.direct.delay_s) * SPEED_OF_SOUND_M_S);
        let found = first_notch_hz(&mag, df);
        eprintln!("test 10: d = {d} m: notch {found:.0} Hz, expected {expected:.0} Hz");
        assert!((found - expected).abs() <= df, "{found} vs {expected}");
        notch.push(found);
    }
    let ratio = notch[0] / notch[1];
    assert!(
        (ratio / 3.0 - 1.0).abs() <= 0.05,
        "notch moves by {ratio}, expected 3"
    );
}

#[test]
fn test10_the_renderer_synthesizes_the_comb() {
    // End to end: a white friction spectrum from a sheet 2 or 6 cm above the table, facing the
    // listener; the notch of the left channel's spectrum is where eq. 4.12 puts it.
    let mut found = Vec::new();
    for d in [0.02f32, 0.06] {
        let mut r = renderer(RATE, impulse_db(), 3, side_scene(true));
        let res = Resonator {
            lr_cm: 10.0,
            lc_cm: 0.0,
            centre_m: [0.0, 0.0, 0.40 + d],
            normal: [1.0, 0.0, 0.0],
            radius_m: 0.05,
        };
        r.set_frame(&frame(0, &[friction(0.1, res)], 0.0));
        let (l, _) = render(&mut r, (6.0 * RATE) as usize, 4096);
        let psd = sounddb::analysis::welch_psd(&l[8192..], RATE, 4096);
        let dfw = RATE / 4096.0;
        let ear = r.ears().ear_m[0];
        let y = [0.0, 0.0, 0.40 + f64::from(d)];
        let yi = [0.0, 0.0, 0.40 - f64::from(d)];
        let expected = SPEED_OF_SOUND_M_S / (2.0 * (dist(ear, yi) - dist(ear, y)));
        // The deepest point within ±30 % of the expectation.
        let (lo, hi) = (
            (0.7 * expected / dfw) as usize,
            (1.3 * expected / dfw) as usize,
        );
        let k = (lo..hi).min_by(|&a, &b| psd[a].total_cmp(&psd[b])).unwrap();
        let notch = k as f64 * dfw;
        let depth = 10.0 * (psd[k] / psd[(0.5 * expected / dfw) as usize]).log10();
        eprintln!(
            "test 10 (renderer): d = {d}: notch {notch:.0} Hz (expected {expected:.0}), depth {depth:.1} dB"
        );
        assert!(
            (notch - expected).abs() <= 2.0 * RATE / 2048.0,
            "{notch} vs {expected}"
        );
        assert!(depth < -15.0);
        found.push(notch);
    }
    assert!((found[0] / found[1] / 3.0 - 1.0).abs() <= 0.05);
}

#[test]
fn test11_no_reflector_means_no_image_path_and_the_same_output() {
    let db = printer_db(RATE);
    let steps = busy_steps(300, 21);
    // Merging is another shortcut (tested in render_engine); it is off in both so that the only
    // difference is the image path.
    let base = RenderOptions {
        merge: false,
        ..RenderOptions::default()
    };
    let mut fast = renderer(RATE, db.clone(), 4, anechoic());
    fast.set_options(base);
    let mut forced = renderer(RATE, db, 4, anechoic());
    forced.set_options(RenderOptions {
        force_image_path: true,
        ..base
    });
    let a = drive(&mut fast, &steps, 220, &[220]);
    let b = drive(&mut forced, &steps, 220, &[220]);
    assert_same(&a, &b);
    assert!(rms(&a.0) > 1e-3);
    let (cf, cr) = (fast.counters(), forced.counters());
    assert_eq!(cf.unit_image_tap_blocks, 0);
    assert_eq!(cf.friction_comb_bins, 0);
    assert!(cr.unit_image_tap_blocks > 0 && cr.friction_comb_bins > 0);
    // With the table, the image path runs.
    let mut table = renderer(RATE, printer_db(RATE), 4, Scene::default());
    let _ = drive(&mut table, &steps[..50], 220, &[220]);
    assert!(table.counters().unit_image_tap_blocks > 0);
    assert!(table.counters().friction_comb_bins > 0);
}
