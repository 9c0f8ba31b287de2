//! The full pipeline benchmark (issue 6 item 6): every seed scene rendered by `papier-render`'s
//! engine (simulation + sound analysis + render path, lockstep, 48 kHz, block 512) as a
//! real-time factor on one core; an idle sheet's cost; and the sound analysis alone per frame.
//!
//! ```text
//! cargo run --release -p papier --example pipeline_report -- [--write docs/benchmarks.md] [--reps N]
//! ```
//!
//! With `--write`, the tables replace the `<!-- pipeline-report:begin -->` … `end` section of
//! the file (appended if missing). Times are wall-clock on a shared machine; each figure is the
//! best of `--reps` runs (default 3).

use std::path::{Path, PathBuf};
use std::time::Instant;

use papier::offline::cli::{InputSpec, RenderOptions};
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sheet::MeshConfig;
use sim_core::sim::{FrameOutput, SimConfig};
use sim_core::sound_analysis::{AnalysisConfig, AnalysisInput, SoundAnalysis};
use sim_core::sound_input::SoundFrame;

const BEGIN: &str = "<!-- pipeline-report:begin -->";
const END: &str = "<!-- pipeline-report:end -->";

fn render_rtf(inputs: Vec<InputSpec>, out: &Path, reps: usize) -> (f64, f64, u64) {
    let mut best = f64::MAX;
    let mut length = 0.0;
    let mut events = 0;
    for _ in 0..reps {
        let opts = RenderOptions {
            quiet: true,
            ..RenderOptions::new(inputs.clone(), out.to_path_buf())
        };
        let r = papier::offline::render(&opts).expect("render");
        best = best.min(r.wall_s);
        length = r.length_s;
        events = r.crumple_events;
    }
    (length, best, events)
}

/// Median and p99 of the analysis alone, microseconds, over the scene's awake frames, with S_P
/// meshed at `spacing_frac` of the sheet's longer side; also the S_P triangle count at the end.
fn analysis_us(name: &str, spacing_frac: f64) -> (f64, f64, usize, usize) {
    let script = scenario::get(name).unwrap();
    let mut base = SimConfig::default();
    base.mesh.spacing_frac = spacing_frac;
    let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
    let mut sim = runner.start(base);
    let (v, t) = sim.mesh_capacity();
    let sheet = sim.sheet();
    let mut an = SoundAnalysis::new(
        AnalysisConfig::default(),
        v,
        t,
        (0.21, 0.297),
        (sheet.width_m, sheet.length_m),
    );
    let mut out = FrameOutput::default();
    let mut held = vec![false; v];
    let mut sound = SoundFrame::default();
    let mut times = Vec::new();
    while runner.drive(&mut sim, &mut out) {
        if out.stats.asleep {
            continue;
        }
        let sheet = sim.sheet();
        held.clear();
        held.resize(sheet.sp.num_vertices(), false);
        for k in sim.rig().held_vertices() {
            held[k as usize] = true;
        }
        sound.clear();
        let t0 = Instant::now();
        an.analyze(
            &AnalysisInput {
                sp: &sheet.sp,
                contacts: sim.contacts(),
                held: &held,
                time_s: sim.time_s(),
                vel_start: &sheet.sp.vel,
                dt_s: 0.005,
                planes: &sim.obstacles().planes,
                pressed_m: 0.0,
                layer_slip: sim.layer_slip(),
            },
            &mut sound,
        );
        times.push(t0.elapsed().as_secs_f64() * 1e6);
    }
    times.sort_by(f64::total_cmp);
    let q = |p: f64| times[((times.len() - 1) as f64 * p).round() as usize];
    (q(0.5), q(0.99), times.len(), sim.sheet().sp.num_triangles())
}

fn main() {
    let mut write: Option<PathBuf> = None;
    let mut reps = 3usize;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--write" => write = args.next().map(PathBuf::from),
            "--reps" => reps = args.next().and_then(|v| v.parse().ok()).unwrap_or(3),
            other => {
                eprintln!("pipeline_report: unknown argument {other}");
                std::process::exit(2);
            }
        }
    }
    let tmp = std::env::temp_dir().join("papier_pipeline_report.wav");
    let mut md = String::new();
    md.push_str(&format!(
        "## Full pipeline (simulation + sound analysis + render)\n\nProduced by `cargo run --release -p papier --example pipeline_report -- --write docs/benchmarks.md` \
         (best of {reps} runs per scene; 48 kHz, block 512, lockstep on one thread as in `papier-render`, WAV writing included). \
         Real-time factor = audio length / wall time; \"without the start-up\" subtracts the fixed start-up cost measured on the idle sheet below. Target: ≥ 50× for every seed scene; analysis ≤ 0.2 ms per frame \
         (seeds: 5–75 ms per frame, T 1976–1980).\n\n"
    ));
    // An idle sheet: 10 s and 40 s of nothing (the sheet sleeps on the table). The difference
    // is the steady cost of idling; the rest is the fixed start-up (database, sheet, solver).
    let idle = std::env::temp_dir().join("papier_idle.toml");
    let idle_wall = |seconds: f64| {
        std::fs::write(&idle, format!("version = 1\nduration_s = {seconds}\n")).unwrap();
        render_rtf(vec![InputSpec::Script(idle.clone())], &tmp, reps)
    };
    let (len_short, wall_short, _) = idle_wall(10.0);
    let (len_long, wall_long, _) = idle_wall(40.0);
    let per_s = ((wall_long - wall_short) / (len_long - len_short)).max(0.0);
    let startup = (wall_short - per_s * len_short).max(0.0);
    md.push_str("| scene | length s | wall ms | real-time factor | without the start-up | crumple events | analysis median µs | analysis p99 µs |\n|---|---|---|---|---|---|---|---|\n");
    let mut worst = f64::MAX;
    for name in scenario::names() {
        let (len, wall, events) = render_rtf(vec![InputSpec::Scene(name.into())], &tmp, reps);
        let (med, p99, _, _) = analysis_us(name, MeshConfig::default().spacing_frac);
        let rtf = len / wall;
        let steady = len / (wall - startup).max(1e-9);
        worst = worst.min(rtf);
        eprintln!("{name}: {rtf:.0}x, analysis {med:.1}/{p99:.1} us");
        md.push_str(&format!(
            "| {name} | {len:.2} | {:.1} | {rtf:.0}× | {steady:.0}× | {events} | {med:.1} | {p99:.1} |\n",
            wall * 1e3
        ));
    }
    md.push_str(&format!(
        "\nIdle sheet (no gesture; the sheet sleeps, no friction, no voices): 10 s take {:.1} ms and 40 s \
         {:.1} ms wall, i.e. a fixed start-up of {:.1} ms (database, sheet, solver set-up, WAV file) and \
         **{:.2} ms per second of audio ({:.2} % of a core)** while idle.\n\
         Slowest seed scene: **{worst:.0}× real time**.\n",
        wall_short * 1e3,
        wall_long * 1e3,
        startup * 1e3,
        per_s * 1e3,
        per_s * 100.0
    ));
    // Digest-sound §12 test 3: the per-frame control cost against mesh size (seeds: 5–6 ms at
    // ~200 triangles, 17 ms at ~450, 75 ms at ~1333; T 1976–1980).
    md.push_str(
        "\nSound analysis alone against S_P size (c5_full_crumple, meshed finer than the default; \
         digest-sound §12 test 3; seeds: 5–6 ms per frame at ~200 triangles, 17 ms at ~450, 75 ms \
         at ~1333):\n\n| spacing | S_P triangles | analysis median µs | analysis p99 µs | frames |\n|---|---|---|---|---|\n",
    );
    let mut prev: Option<(usize, f64)> = None;
    let mut exps = Vec::new();
    for div in [9.0, 16.0, 24.0, 30.0] {
        let (med, p99, n, tris) = analysis_us("c5_full_crumple", 1.0 / div);
        eprintln!("analysis at L/{div}: {tris} triangles, {med:.1}/{p99:.1} us");
        if let Some((t0, m0)) = prev {
            exps.push((med / m0).ln() / (tris as f64 / t0 as f64).ln());
        }
        prev = Some((tris, med));
        md.push_str(&format!(
            "| L/{div} | {tris} | {med:.1} | {p99:.1} | {n} |\n"
        ));
    }
    md.push_str(&format!(
        "\nLocal growth exponents of the median (cost ∝ N^k between successive rows): {}.\n",
        exps.iter()
            .map(|k| format!("{k:.2}"))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    print!("{md}");
    if let Some(path) = write {
        let old = std::fs::read_to_string(&path).unwrap_or_default();
        let section = format!("{BEGIN}\n{md}{END}");
        let new = match (old.find(BEGIN), old.find(END)) {
            (Some(a), Some(b)) if b > a => {
                format!("{}{}{}", &old[..a], section, &old[b + END.len()..])
            }
            _ => format!("{old}\n\n{section}\n"),
        };
        std::fs::write(&path, new).unwrap();
        eprintln!("wrote {}", path.display());
    }
    let _ = std::fs::remove_file(&tmp);
    let _ = std::fs::remove_file(&idle);
}
