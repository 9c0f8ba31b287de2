//! # Batch renders: many takes from one job file, on every core, sharded over machines
//!
//! `papier-render --batch FILE.toml [--shard I/N] [--jobs N] [--quiet]` renders a list of jobs.
//! A job names one input (a built-in scene, a script or a MIDI file) and the variations to
//! render it with; every combination is one take, rendered exactly as the single render with
//! the same options would render it ([`super::render`], so its bytes are the same):
//!
//! ```toml
//! [defaults]              # optional; every key optional
//! out_dir = "takes"       # relative to the job file (default: the job file's folder)
//! sample_rate = 48000     # 8000–192000
//! block = 512             # 1–16384
//! obj_fps = 30
//!
//! [rooms]                 # optional: named sets of parameter settings (README ids)
//! near_wall = ["wall=on", "wall_dist_cm=20"]
//! dry = ["table=off"]
//!
//! [[job]]
//! name = "crumple"        # output stem: letters, digits, '-' and '_'
//! scene = "s4_crumple"    # or script = "x.toml", or midi = "x.mid" (relative to the job file)
//! seeds = [1, 2, 3]       # each optional: one take per value, all combinations
//! sizes = ["a4", "a6"]
//! materials = ["printer", "banknote"]
//! rooms = ["near_wall", "dry"]
//! set = ["mix_tear_db=-6"] # applied to every take of the job
//! obj = true              # also the OBJ sequence, in out_dir/STEM_obj/
//! ```
//!
//! A take's output is `out_dir/STEM.wav` with STEM = name, then `_s{seed}`, `_{size}`,
//! `_{material}`, `_{room}` for the lists the job has. Decisions, one line each:
//! - **Checked before anything renders**: an unknown key, scene, room, size, material or
//!   parameter setting, a missing input file or two takes with one output name stop the batch
//!   with one line naming the job; a take that fails while rendering (a damaged MIDI file) is
//!   reported in the summary and the others go on.
//! - **One take per worker thread** (`--jobs`, default: the cores): a take is one sheet in
//!   lockstep with its audio, so takes are independent and their bytes do not depend on the
//!   thread they ran on; workers take the next take from a shared counter. The embedded
//!   database is prepared once per sample rate for the whole batch.
//! - **`--shard I/N`** renders the takes whose index (in file order, combinations expanded) is
//!   I modulo N, so N machines of a job array each render their share (the README shows a
//!   Slurm array and a Kubernetes indexed Job).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use serde::Deserialize;

use super::cli::{InputSpec, MAX_BLOCK, MAX_SAMPLE_RATE_HZ, MIN_SAMPLE_RATE_HZ, RenderOptions};
use super::render::render;
use crate::engine::param_values::{MAX_SEED, ParamValues};

/// The sheet sizes a job may list.
pub const SIZES: [&str; 4] = ["a4", "a5", "a6", "sq10"];
/// The materials a job may list.
pub const MATERIALS: [&str; 3] = ["printer", "tracing", "banknote"];

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct Defaults {
    out_dir: Option<PathBuf>,
    sample_rate: Option<u32>,
    block: Option<usize>,
    obj_fps: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct JobSpec {
    name: String,
    scene: Option<String>,
    script: Option<PathBuf>,
    midi: Option<PathBuf>,
    #[serde(default)]
    seeds: Vec<u64>,
    #[serde(default)]
    sizes: Vec<String>,
    #[serde(default)]
    materials: Vec<String>,
    #[serde(default)]
    rooms: Vec<String>,
    #[serde(default)]
    set: Vec<String>,
    #[serde(default)]
    obj: bool,
    sample_rate: Option<u32>,
    block: Option<usize>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BatchFile {
    #[serde(default)]
    defaults: Defaults,
    #[serde(default)]
    rooms: BTreeMap<String, Vec<String>>,
    #[serde(default)]
    job: Vec<JobSpec>,
}

/// One take: its name and the options of its single render.
#[derive(Clone, Debug, PartialEq)]
pub struct Take {
    /// The job's name.
    pub job: String,
    /// The output stem (name and variations).
    pub stem: String,
    /// The single render's options.
    pub opts: RenderOptions,
}

/// Which share of the takes to render: those whose index is `index` modulo `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 0 ≤ index < count.
    pub index: usize,
    /// Machines sharing the batch, ≥ 1.
    pub count: usize,
}

impl Shard {
    /// The whole batch.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `I/N`. The error is one line.
    pub fn parse(s: &str) -> Result<Self, String> {
        let bad = || format!("--shard {s}: expected I/N with 0 <= I < N, e.g. 0/4");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            i.trim().parse::<usize>().map_err(|_| bad())?,
            n.trim().parse::<usize>().map_err(|_| bad())?,
        );
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Self { index, count })
    }

    /// True if the take of index `i` is in this shard.
    pub fn holds(&self, i: usize) -> bool {
        i % self.count == self.index
    }
}

/// The line and column (1-based) of byte `offset` in `text`.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before
        .rfind('\n')
        .map_or(before.len(), |i| before.len() - i - 1)
        + 1;
    (line, col)
}

/// True for a usable output stem.
fn valid_name(name: &str) -> bool {
    !name.is_empty()
        && name.len() <= 100
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
}

/// Reads a job file and expands it into takes, checking everything that can be checked
/// without rendering. The error is one line naming the file and, where it is one job's, the
/// job.
pub fn read(path: &Path) -> Result<Vec<Take>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("--batch {}: cannot read it: {e}", path.display()))?;
    parse(&text, path)
}

/// [`read`] for the text of a job file at `path` (relative paths are relative to its folder).
pub fn parse(text: &str, path: &Path) -> Result<Vec<Take>, String> {
    let file: BatchFile = toml::from_str(text).map_err(|e| {
        let at = e.span().map(|s| {
            let (l, c) = line_col(text, s.start);
            format!(" at line {l}, column {c}")
        });
        format!(
            "--batch {}{}: {}",
            path.display(),
            at.unwrap_or_default(),
            e.message().lines().next().unwrap_or("not a job file")
        )
    })?;
    let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let at_base = |p: &Path| {
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            base.join(p)
        }
    };
    let d = &file.defaults;
    let out_dir = d.out_dir.as_deref().map_or(base.clone(), at_base);
    let scenes = super::scene_names();
    let mut takes = Vec::new();
    if file.job.is_empty() {
        return Err(format!("--batch {}: no [[job]]", path.display()));
    }
    for (k, j) in file.job.iter().enumerate() {
        let err = |msg: String| {
            format!(
                "--batch {}: job {} ({:?}): {msg}",
                path.display(),
                k + 1,
                j.name
            )
        };
        if !valid_name(&j.name) {
            return Err(err(
                "name: letters, digits, '-' and '_' only (1 to 100)".into()
            ));
        }
        let input = match (&j.scene, &j.script, &j.midi) {
            (Some(s), None, None) => {
                if !scenes.contains(&s.as_str()) {
                    return Err(err(format!(
                        "unknown scene {s:?} (papier-render --list-scenes)"
                    )));
                }
                InputSpec::Scene(s.clone())
            }
            (None, Some(p), None) | (None, None, Some(p)) => {
                let p = at_base(p);
                if !p.is_file() {
                    return Err(err(format!("no such file {}", p.display())));
                }
                if j.script.is_some() {
                    InputSpec::Script(p)
                } else {
                    InputSpec::Midi(p)
                }
            }
            _ => return Err(err("give exactly one of scene, script or midi".into())),
        };
        let sample_rate_hz = j.sample_rate.or(d.sample_rate).unwrap_or(48_000);
        if !(MIN_SAMPLE_RATE_HZ..=MAX_SAMPLE_RATE_HZ).contains(&sample_rate_hz) {
            return Err(err(format!(
                "sample_rate {sample_rate_hz}: expected {MIN_SAMPLE_RATE_HZ} to {MAX_SAMPLE_RATE_HZ}"
            )));
        }
        let block = j.block.or(d.block).unwrap_or(512);
        if !(1..=MAX_BLOCK).contains(&block) {
            return Err(err(format!("block {block}: expected 1 to {MAX_BLOCK}")));
        }
        let obj_fps = d.obj_fps.unwrap_or(30.0);
        if !(obj_fps.is_finite() && (1.0..=1000.0).contains(&obj_fps)) {
            return Err(format!(
                "--batch {}: defaults.obj_fps {obj_fps}: expected 1 to 1000",
                path.display()
            ));
        }
        if let Some(s) = j.seeds.iter().find(|&&s| s > MAX_SEED as u64) {
            return Err(err(format!("seed {s}: expected 0 to {MAX_SEED}")));
        }
        if let Some(s) = j.sizes.iter().find(|s| !SIZES.contains(&s.as_str())) {
            return Err(err(format!(
                "size {s:?}: expected one of {}",
                SIZES.join(", ")
            )));
        }
        if let Some(m) = j
            .materials
            .iter()
            .find(|m| !MATERIALS.contains(&m.as_str()))
        {
            return Err(err(format!(
                "material {m:?}: expected one of {}",
                MATERIALS.join(", ")
            )));
        }
        if let Some(r) = j.rooms.iter().find(|r| !file.rooms.contains_key(*r)) {
            return Err(err(format!("room {r:?} is not in [rooms]")));
        }
        let mut probe = ParamValues::default();
        for s in j
            .set
            .iter()
            .chain(j.rooms.iter().flat_map(|r| &file.rooms[r]))
        {
            probe
                .set_from_arg(s)
                .map_err(|e| err(format!("set {s:?}: {e}")))?;
        }
        // Every combination; an absent list is one take without that variation.
        let opt = |v: &[String]| -> Vec<Option<String>> {
            if v.is_empty() {
                vec![None]
            } else {
                v.iter().cloned().map(Some).collect()
            }
        };
        let seeds: Vec<Option<u64>> = if j.seeds.is_empty() {
            vec![None]
        } else {
            j.seeds.iter().copied().map(Some).collect()
        };
        for seed in &seeds {
            for size in opt(&j.sizes) {
                for material in opt(&j.materials) {
                    for room in opt(&j.rooms) {
                        let mut stem = j.name.clone();
                        let mut sets = j.set.clone();
                        if let Some(s) = seed {
                            stem.push_str(&format!("_s{s}"));
                        }
                        if let Some(s) = &size {
                            stem.push_str(&format!("_{s}"));
                            sets.push(format!("size={s}"));
                        }
                        if let Some(m) = &material {
                            stem.push_str(&format!("_{m}"));
                            sets.push(format!("material={m}"));
                        }
                        if let Some(r) = &room {
                            stem.push_str(&format!("_{r}"));
                            sets.extend(file.rooms[r].iter().cloned());
                        }
                        let mut opts = RenderOptions::new(
                            vec![input.clone()],
                            out_dir.join(format!("{stem}.wav")),
                        );
                        opts.sample_rate_hz = sample_rate_hz;
                        opts.block = block;
                        opts.seed = *seed;
                        opts.sets = sets;
                        opts.obj_fps = obj_fps;
                        opts.obj_dir = j.obj.then(|| out_dir.join(format!("{stem}_obj")));
                        opts.quiet = true;
                        if let Some(other) = takes.iter().find(|t: &&Take| t.stem == stem) {
                            return Err(err(format!(
                                "its take {stem} has the output name of a take of job {:?}",
                                other.job
                            )));
                        }
                        takes.push(Take {
                            job: j.name.clone(),
                            stem,
                            opts,
                        });
                    }
                }
            }
        }
    }
    Ok(takes)
}

/// How one take went.
#[derive(Clone, Debug)]
pub struct TakeResult {
    /// Index of the take in the batch.
    pub index: usize,
    /// The take's stem.
    pub stem: String,
    /// Its length (s) and the render's wall time (s), or the one-line error.
    pub outcome: Result<(f64, f64), String>,
}

/// What a batch did.
#[derive(Clone, Debug)]
pub struct BatchSummary {
    /// Takes in the file.
    pub takes: usize,
    /// The shard rendered.
    pub shard: Shard,
    /// Worker threads.
    pub threads: usize,
    /// Each rendered take, in batch order.
    pub results: Vec<TakeResult>,
    /// Wall time of the whole batch, s.
    pub took_s: f64,
}

impl BatchSummary {
    /// Takes that failed.
    pub fn failed(&self) -> usize {
        self.results.iter().filter(|r| r.outcome.is_err()).count()
    }
}

impl std::fmt::Display for BatchSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let audio_s: f64 = self
            .results
            .iter()
            .filter_map(|r| r.outcome.as_ref().ok().map(|o| o.0))
            .sum();
        writeln!(
            f,
            "papier-render: batch of {} takes, shard {}/{}: {} rendered, {} failed, {} threads, \
             {:.1} s of audio in {:.1} s ({:.1}x real time)",
            self.takes,
            self.shard.index,
            self.shard.count,
            self.results.len() - self.failed(),
            self.failed(),
            self.threads,
            audio_s,
            self.took_s,
            audio_s / self.took_s.max(1e-9)
        )?;
        writeln!(
            f,
            "  {:<40} {:>8} {:>8} {:>8}",
            "take", "audio s", "took s", "x rt"
        )?;
        for r in &self.results {
            match &r.outcome {
                Ok((len, took)) => writeln!(
                    f,
                    "  {:<40} {:>8.2} {:>8.2} {:>8.1}",
                    r.stem,
                    len,
                    took,
                    len / took.max(1e-9)
                )?,
                Err(e) => writeln!(f, "  {:<40} FAILED: {e}", r.stem)?,
            }
        }
        Ok(())
    }
}

/// Renders the takes of `shard` on `threads` worker threads (at least 1), with one progress bar
/// over the takes (hidden when `quiet` or not on a terminal). Never stops at a failed take.
pub fn run(takes: &[Take], shard: Shard, threads: usize, quiet: bool) -> BatchSummary {
    let started = Instant::now();
    let mine: Vec<usize> = (0..takes.len()).filter(|&i| shard.holds(i)).collect();
    let threads = threads.clamp(1, mine.len().max(1));
    // One prepared embedded database per rate for the whole batch (it is shared while alive;
    // else every take would prepare it again, ~0.2 s each).
    let mut rates: Vec<u32> = mine
        .iter()
        .map(|&i| &takes[i].opts)
        .filter(|o| o.db.is_none())
        .map(|o| o.sample_rate_hz)
        .collect();
    rates.sort_unstable();
    rates.dedup();
    let _dbs: Vec<_> = rates
        .iter()
        .map(|&r| crate::render::default_db(f64::from(r)))
        .collect();
    let bar = super::progress::progress_bar(mine.len() as u64, quiet);
    let next = AtomicUsize::new(0);
    let results = Mutex::new(Vec::with_capacity(mine.len()));
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&i) = mine.get(k) else { break };
                    let take = &takes[i];
                    let t0 = Instant::now();
                    let outcome = render(&take.opts)
                        .map(|r| (r.length_s, t0.elapsed().as_secs_f64()))
                        .map_err(|e| e.to_string());
                    if let Ok(mut v) = results.lock() {
                        v.push(TakeResult {
                            index: i,
                            stem: take.stem.clone(),
                            outcome,
                        });
                    }
                    bar.inc(1);
                }
            });
        }
    });
    bar.finish_and_clear();
    let mut results = results.into_inner().unwrap_or_default();
    results.sort_by_key(|r| r.index);
    BatchSummary {
        takes: takes.len(),
        shard,
        threads,
        results,
        took_s: started.elapsed().as_secs_f64(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILE: &str = r#"
[defaults]
out_dir = "out"
block = 256

[rooms]
near = ["wall=on", "wall_dist_cm=20"]
dry = ["table=off"]

[[job]]
name = "crumple"
scene = "s4_crumple"
seeds = [1, 2]
sizes = ["a5", "a6"]
rooms = ["near", "dry"]

[[job]]
name = "shake"
scene = "s2_shake"
set = ["mix_friction_db=-6"]
obj = true
sample_rate = 44100
"#;

    #[test]
    fn every_combination_is_a_take_with_its_name_and_settings() {
        let takes = parse(FILE, Path::new("/b/jobs.toml")).unwrap();
        assert_eq!(takes.len(), 2 * 2 * 2 + 1);
        let t = &takes[0];
        assert_eq!(t.stem, "crumple_s1_a5_near");
        assert_eq!(t.opts.out, PathBuf::from("/b/out/crumple_s1_a5_near.wav"));
        assert_eq!(t.opts.seed, Some(1));
        assert_eq!(t.opts.block, 256);
        assert_eq!(t.opts.sets, vec!["size=a5", "wall=on", "wall_dist_cm=20"]);
        assert_eq!(t.opts.obj_dir, None);
        let s = takes.last().unwrap();
        assert_eq!(s.stem, "shake");
        assert_eq!(s.opts.sample_rate_hz, 44_100);
        assert_eq!(s.opts.obj_dir, Some(PathBuf::from("/b/out/shake_obj")));
        assert_eq!(s.opts.sets, vec!["mix_friction_db=-6"]);
    }

    #[test]
    fn the_shards_cover_every_take_exactly_once() {
        let takes = parse(FILE, Path::new("/b/jobs.toml")).unwrap();
        for n in 1..=5 {
            let mut seen = vec![0; takes.len()];
            for i in 0..n {
                let sh = Shard::parse(&format!("{i}/{n}")).unwrap();
                for (k, c) in seen.iter_mut().enumerate() {
                    *c += usize::from(sh.holds(k));
                }
            }
            assert!(seen.iter().all(|&c| c == 1), "{n} shards: {seen:?}");
        }
        for bad in ["", "1", "2/2", "a/3", "0/0", "-1/2"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn a_bad_job_file_is_one_line_naming_the_job() {
        let p = Path::new("/b/jobs.toml");
        let cases = [
            (
                FILE.replace("s2_shake", "s9_nope"),
                "job 2 (\"shake\"): unknown scene",
            ),
            (
                FILE.replace("\"dry\"]\n", "\"wet\"]\n"),
                "job 1 (\"crumple\"): room \"wet\"",
            ),
            (
                FILE.replace("\"a6\"", "\"a3\""),
                "job 1 (\"crumple\"): size \"a3\"",
            ),
            (
                FILE.replace("mix_friction_db=-6", "mix_friction_db=loud"),
                "job 2 (\"shake\"): set",
            ),
            (FILE.replace("obj = true", "objs = true"), "at line"),
            (
                FILE.replace("scene = \"s2_shake\"", ""),
                "job 2 (\"shake\"): give exactly one",
            ),
            (
                FILE.replace("name = \"shake\"", "name = \"crumple_s1_a5_near\""),
                "output name",
            ),
            (FILE.replace("name = \"shake\"", "name = \"a b\""), "name:"),
            (
                FILE.replace("scene = \"s2_shake\"", "midi = \"none.mid\""),
                "no such file",
            ),
            ("[defaults]\n".to_string(), "no [[job]]"),
        ];
        for (text, want) in cases {
            let e = parse(&text, p).unwrap_err();
            assert!(!e.contains('\n'), "{e}");
            assert!(e.contains(want), "{e:?} lacks {want:?}");
        }
    }
}
