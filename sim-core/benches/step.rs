//! Criterion benches of `Sim::step` on states taken from the seed scenarios.
//!
//! Each bench restores a saved mid-scenario state (so every sample starts from the same sheet,
//! hands and gestures) and steps 10 frames while the scenario's gestures keep the hands moving.
//! Groups: the default solver on four scenarios and at several mesh densities (cost against
//! size); the rebuild of everything sized by the mesh, which each vertex insertion or edge flip
//! pays, and a cut along a pattern line (the mesh operation tearing builds on); and the two
//! contact queries
//! of a crumpled sheet (the crumple cap's closest approach, the sheet–sheet contact pairs of a
//! substep). The full run-time-against-error report
//! (all scenarios, sweeps, percentiles, plot) is `cargo xtask bench-report`.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sheet::MeshConfig;
use sim_core::sim::{FrameOutput, SavedSheet, Sim, SimConfig};

/// Plays `name` for `frames` frames; returns the config, the saved state and the commands of
/// the next 10 frames.
fn snapshot(
    name: &str,
    frames: u64,
    base: SimConfig,
) -> (SimConfig, SavedSheet, Vec<Vec<sim_core::Command>>) {
    let script = scenario::get(name).expect("scenario");
    let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).expect("runner");
    let cfg = runner.config(base);
    let mut sim = runner.start(base);
    let mut out = FrameOutput::default();
    for _ in 0..frames {
        runner.drive(&mut sim, &mut out);
    }
    let saved = sim.save();
    let mut next = Vec::new();
    for _ in 0..10 {
        let mut v = Vec::new();
        runner.next_frame(&mut v);
        next.push(v);
    }
    (cfg, saved, next)
}

fn bench_state(c: &mut Criterion, id: &str, name: &str, frames: u64, base: SimConfig) {
    let (cfg, saved, next) = snapshot(name, frames, base);
    c.bench_function(id, |b| {
        b.iter_batched(
            || Sim::restore(cfg, &saved).expect("restore"),
            |mut sim| {
                let mut out = FrameOutput::default();
                for cmds in &next {
                    for c in cmds {
                        sim.apply(*c);
                    }
                    sim.step(&mut out);
                }
                sim
            },
            BatchSize::SmallInput,
        )
    });
}

fn default_solver(c: &mut Criterion) {
    for (name, frames) in [
        ("c1_first_sharp_feature", 300),
        ("c5_full_crumple", 400),
        ("s1_slide_release_pinch", 250),
        ("s6_slide_on_table", 200),
    ] {
        bench_state(
            c,
            &format!("newton_default/{name}/10_frames"),
            name,
            frames,
            SimConfig::default(),
        );
    }
}

fn density(c: &mut Criterion) {
    for k in [5.0, 9.0, 18.0, 31.0] {
        let base = SimConfig {
            mesh: MeshConfig {
                spacing_frac: 1.0 / k,
            },
            ..SimConfig::default()
        };
        bench_state(
            c,
            &format!("density/L_over_{k}/s1/10_frames"),
            "s1_slide_release_pinch",
            250,
            base,
        );
    }
}

/// Rebuilding everything sized by the mesh — what a vertex insertion or an edge flip costs on
/// top of its frame (`sim/remesh.rs` adopts the new mesh the way a saved sheet is restored): a
/// crumpled C5 state with its inserted vertices, restored; and a cut along a pattern line.
fn rebuild(c: &mut Criterion) {
    let (cfg, saved, _) = snapshot("c5_full_crumple", 400, SimConfig::default());
    c.bench_function("rebuild/c5_frame_400/restore", |b| {
        b.iter(|| Sim::restore(cfg, &saved).expect("restore"))
    });
    // The cut's own part (`sheet/cut.rs`): a flat A4 lattice cut along an oblique line (the new
    // mesh with its state; the adoption after it costs what the restore above measures).
    let sp = Sim::new(SimConfig::default()).sheet().sp.clone();
    let (o, d) = (
        sim_core::math::V2::new(0.003, -0.002),
        sim_core::math::V2::new(0.8, 0.35),
    );
    let line = sim_core::sheet::cut::line_crossings(&sp, o, d).expect("a point on the sheet");
    c.bench_function("rebuild/a4/cut_along", |b| {
        b.iter(|| sim_core::sheet::cut::cut_along(&sp, &line).expect("cut"))
    });
}

/// The contact queries on the crumpled C5 state of [`rebuild`]: the crumple cap's closest
/// approach (`self_proximity.rs`, at the squeeze's reach), its crossing test (the pass-through
/// guard's and the isometry step's) and the sheet–sheet contact pairs of a substep
/// (`physics/sheet_contact.rs`) at the smallest and the largest reach.
fn contact(c: &mut Criterion) {
    let (cfg, saved, _) = snapshot("c5_full_crumple", 400, SimConfig::default());
    let sim = Sim::restore(cfg, &saved).expect("restore");
    let sp = &sim.sheet().sp;
    let mut proximity = sim_core::self_proximity::SelfProximity::with_capacity(sp.num_triangles());
    proximity.set_min_pattern_gap_m(0.75 * cfg.mesh.spacing_m(cfg.size));
    c.bench_function("contact/c5_frame_400/closest_approach", |b| {
        b.iter(|| proximity.closest_approach_m(sp, sim_core::gesture_rig::SQUEEZE_REACH_M))
    });
    c.bench_function("contact/c5_frame_400/any_crossing", |b| {
        b.iter(|| proximity.any_crossing(sp))
    });
    let mut pairs = sim_core::physics::sheet_contact::SheetContact::new(sp);
    for (label, reach_m) in [
        ("min", sim_core::physics::sheet_contact::MIN_REACH_M),
        ("max", sim_core::physics::sheet_contact::MAX_REACH_M),
    ] {
        c.bench_function(
            &format!("contact/c5_frame_400/sheet_pairs_{label}_reach"),
            |b| {
                b.iter(|| {
                    pairs.find(sp, reach_m);
                    pairs.pairs().len()
                })
            },
        );
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = default_solver, density, rebuild, contact
}
criterion_main!(benches);
