//! `papier-render --batch` as a user runs it: a job file of takes rendered on two threads, each
//! take's WAV (and OBJ sequence) byte-identical to its single render, a damaged input reported
//! as one failed take while the others render, and a shard rendering exactly its share.

use std::path::{Path, PathBuf};

use papier_tests::paths;
use papier_tests::paths::arg as s;
use papier_tests::paths::run_papier_render as run;

const JOBS: &str = r#"
[defaults]
out_dir = "takes"
block = 256

[[job]]
name = "shake"
scene = "s2_shake"
seeds = [3, 4]

[[job]]
name = "pull"
scene = "t3_pull_equal"
sizes = ["a6"]
obj = true

[[job]]
name = "broken"
midi = "broken.mid"
"#;

/// The files of an OBJ directory, sorted, with their bytes.
fn objs(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    v.sort();
    v.into_iter()
        .map(|p| {
            let b = std::fs::read(&p).unwrap();
            (p.file_name().unwrap().into(), b)
        })
        .collect()
}

#[test]
fn a_batch_renders_every_take_as_its_single_render_and_reports_the_failed_one() {
    let dir = paths::scratch("batch_render");
    let file = dir.join("jobs.toml");
    std::fs::write(&file, JOBS).unwrap();
    // A MIDI file that is not one: the take fails when it renders, the others go on.
    std::fs::write(dir.join("broken.mid"), b"MThd not really").unwrap();
    let out = run(&["--batch", s(&file), "--jobs", "2"]);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert_eq!(out.status.code(), Some(1), "{stdout}\n{stderr}");
    assert!(
        stdout.contains("batch of 4 takes, shard 0/1: 3 rendered, 1 failed, 2 threads"),
        "{stdout}"
    );
    let failed: Vec<&str> = stderr.lines().filter(|l| l.contains("error")).collect();
    assert_eq!(failed.len(), 1, "{stderr}");
    assert!(failed[0].contains("take broken:"), "{stderr}");

    // Each take equals its single render.
    let takes = dir.join("takes");
    let singles = [
        ("shake_s3", vec!["--scene", "s2_shake", "--seed", "3"]),
        ("shake_s4", vec!["--scene", "s2_shake", "--seed", "4"]),
        (
            "pull_a6",
            vec!["--scene", "t3_pull_equal", "--set", "size=a6"],
        ),
    ];
    for (stem, args) in singles {
        let wav = dir.join(format!("single_{stem}.wav"));
        let obj = dir.join(format!("single_{stem}_obj"));
        let mut a = args.clone();
        a.extend(["--block", "256", "--quiet", "--out", s(&wav)]);
        if stem == "pull_a6" {
            a.extend(["--obj-dir", s(&obj)]);
        }
        let o = run(&a);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let batch_wav = std::fs::read(takes.join(format!("{stem}.wav"))).unwrap();
        assert!(
            batch_wav == std::fs::read(&wav).unwrap(),
            "{stem}: WAV differs"
        );
        if stem == "pull_a6" {
            let b = objs(&takes.join("pull_a6_obj"));
            assert!(!b.is_empty());
            assert!(b == objs(&obj), "{stem}: OBJ sequence differs");
        }
    }
    assert!(!takes.join("broken.wav").exists());

    // A shard renders its share only (takes 1 and 3 of 0..4).
    std::fs::remove_dir_all(&takes).unwrap();
    let out = run(&["--batch", s(&file), "--shard", "1/2", "--quiet"]);
    assert_eq!(out.status.code(), Some(1), "the broken take is take 3");
    let mut made: Vec<String> = std::fs::read_dir(&takes)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    made.sort();
    assert_eq!(made, vec!["shake_s4.wav"]);
}

#[test]
fn a_bad_job_file_is_refused_with_one_line_before_anything_renders() {
    let dir = paths::scratch("batch_render_bad");
    let file = dir.join("jobs.toml");
    std::fs::write(&file, JOBS.replace("t3_pull_equal", "t9_nothing")).unwrap();
    std::fs::write(dir.join("broken.mid"), b"x").unwrap();
    let out = run(&["--batch", s(&file)]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("job 2 (\"pull\"): unknown scene"),
        "{stderr}"
    );
    assert!(!dir.join("takes").exists(), "nothing rendered");
    for (args, want) in [
        (vec!["--batch", s(&file), "--shard", "3/3"], "--shard 3/3"),
        (
            vec!["--batch", s(&file), "--scene", "s2_shake"],
            "--batch takes",
        ),
        (
            vec!["--scene", "s2_shake", "--jobs", "2"],
            "go with --batch",
        ),
        (vec!["--batch", "/nonexistent/jobs.toml"], "cannot read"),
    ] {
        let out = run(&args);
        let e = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(e.contains(want), "{e:?} lacks {want:?}");
    }
}
