//! The README's main command renders `plugin/scenes/demo.toml` (slide-release-pinch, crumple,
//! shake) with the embedded database: the result must be audible, finite and clear of the
//! output's soft clipper (issue 6 acceptance), and every part of the scene must sound.

use papier::offline::cli::{InputSpec, RenderOptions};

#[test]
fn the_demo_is_audible_finite_and_unclipped() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = std::env::temp_dir().join(format!("papier_demo_{}.wav", std::process::id()));
    let opts = RenderOptions {
        quiet: true,
        ..RenderOptions::new(
            vec![InputSpec::Script(root.join("plugin/scenes/demo.toml"))],
            out.clone(),
        )
    };
    let report = papier::offline::render(&opts).expect("demo renders");
    let mut reader = hound::WavReader::open(&out).unwrap();
    let x: Vec<f32> = reader.samples::<f32>().map(Result::unwrap).collect();
    let _ = std::fs::remove_file(&out);
    assert!(x.iter().all(|v| v.is_finite()), "finite");
    let peak = x.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    let knee = papier::render::output_stage::CLIP_KNEE;
    eprintln!("{report}");
    assert!(peak < knee, "peak {peak} reaches the soft clipper ({knee})");
    assert!(report.crumple_events > 0, "the crumple is heard");
    // Every second of each part has sound: the slide (0.2–2 s), the crumple (4–6 s) and the
    // shake (8.2–10 s); RMS of each part above −60 dBFS.
    let rate = 48_000usize;
    for (a, b) in [(0.2, 2.0), (4.0, 6.0), (8.2, 10.0)] {
        let s = &x[(a * rate as f64) as usize * 2..(b * rate as f64) as usize * 2];
        let rms = (s.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>() / s.len() as f64).sqrt();
        let db = 20.0 * rms.log10();
        eprintln!("{a}–{b} s: {db:.1} dBFS RMS");
        assert!(db > -60.0, "{a}–{b} s is silent ({db:.1} dBFS)");
    }
}
