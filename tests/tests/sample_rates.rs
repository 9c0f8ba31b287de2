//! One performance, one take at every sample rate: the sheet's timeline does not depend on the
//! audio rate (`papier::offline::timeline`: a lane is read at each frame's exact time, not at
//! its rounded sample; `papier::engine::FrameClock::time_s`). `papier-render` plays a scene at
//! several rates; the OBJ sequence (the sheet) and the sound-frame log (every crumple and
//! friction event with its resonators) must be the same bytes at each.
//!
//! Breakage detected: before the frame times were exact, `s4_crumple` gave other sheets at 22.05
//! and 44.1 kHz, and `c5_full_crumple` three different sheets over 22.05, 44.1, 48 and 96 kHz
//! (a 5 ms frame is 220.5 and 110.25 samples there).

use std::path::Path;
use std::process::Command;

use papier_tests::paths;

/// The sheet (OBJ files at 25 per second, concatenated) and the frame log without its header
/// comments, rendered from `scene` at `rate_hz`.
fn take(dir: &Path, scene: &str, rate_hz: u32) -> (Vec<u8>, String) {
    let tag = format!("{scene}_{rate_hz}");
    let objs = dir.join(format!("obj_{tag}"));
    let log = dir.join(format!("{tag}.jsonl"));
    let out = Command::new(paths::papier_render())
        .args(["--scene", scene, "--sample-rate", &rate_hz.to_string()])
        .args(["--out", dir.join(format!("{tag}.wav")).to_str().unwrap()])
        .args(["--obj-dir", objs.to_str().unwrap(), "--obj-fps", "25"])
        .args(["--write-frames", log.to_str().unwrap(), "--quiet"])
        .output()
        .expect("run papier-render");
    assert!(
        out.status.success(),
        "{tag}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut files: Vec<_> = std::fs::read_dir(&objs)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() > 10, "{tag}: {} OBJ files", files.len());
    let sheet = files
        .iter()
        .flat_map(|f| std::fs::read(f).unwrap())
        .collect();
    let events = std::fs::read_to_string(&log)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n");
    (sheet, events)
}

fn same_at_every_rate(scenes: &[&str], rates: &[u32]) {
    let dir = tempfile_dir();
    for scene in scenes {
        let (sheet, events) = take(&dir, scene, 48_000);
        assert!(events.contains("crumple") || events.contains("friction"));
        for &r in rates.iter().filter(|&&r| r != 48_000) {
            let (s, e) = take(&dir, scene, r);
            assert!(
                s == sheet,
                "{scene}: another sheet at {r} Hz than at 48 kHz"
            );
            assert!(
                e == events,
                "{scene}: other sound events at {r} Hz than at 48 kHz"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn tempfile_dir() -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!(
        "papier-sample-rates-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The two crumples that diverged, at the eight rates of the issue.
#[test]
fn the_crumples_are_the_same_sheet_and_events_at_every_rate() {
    same_at_every_rate(
        &["s4_crumple", "c5_full_crumple"],
        &[
            22_050, 32_000, 44_100, 48_000, 88_200, 96_000, 176_400, 192_000,
        ],
    );
}

/// The other seed scenes at 44.1 and 48 kHz (the project rates most used).
#[test]
fn every_other_seed_scene_is_the_same_at_44_1_and_48_khz() {
    same_at_every_rate(
        &[
            "c1_first_sharp_feature",
            "c2_moebius_twist",
            "c3_unload_after_singularity",
            "c4_double_bend",
            "c6_four_corner_flip",
            "s1_slide_release_pinch",
            "s2_shake",
            "s3_wiggle_near_wall",
            "s5_fold_and_revert",
            "s6_slide_on_table",
        ],
        &[44_100, 48_000],
    );
}
