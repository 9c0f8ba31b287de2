//! The pull (sim/tear.rs, "Pull"; thesis §3.3): `pull_sep` pulls the back edge apart with two
//! hands either side of `tear_pos`, and the sheet tears where Griffith's criterion with
//! Roman's energy release says — straight for an equal pull, along the hyperbola whose foci
//! are the hands for an unequal one — and not at all for a gentle pull.

mod common;

use sim_core::control::{Command, GestureParam, SheetSize};
use sim_core::math::V2;
use sim_core::sim::{FrameOutput, Sim};

use common::set_gesture as set;

/// A sheet on the table pulled with `pull_sep` ramped 0 → `sep` over `ramp` frames at
/// `asym`, then held for `hold` frames; checks the torn mesh every frame
/// (`common::step_torn`). Returns the sim and the macro tip's pattern positions, frame by
/// frame, once the tear runs.
fn pull(
    size: SheetSize,
    sep: f32,
    asym: f32,
    pos: f32,
    ramp: u32,
    hold: u32,
    seed: u64,
) -> (Sim, Vec<V2>) {
    let (mut sim, _, _) = common::sheet_on_table(size, seed);
    let mut out = FrameOutput::default();
    set(&mut sim, GestureParam::PullAsymmetry, asym);
    set(&mut sim, GestureParam::TearPosition, pos);
    let mut path = Vec::new();
    let mut last_length = 0.0f32;
    for k in 1..=ramp + hold {
        set(
            &mut sim,
            GestureParam::PullSeparation,
            sep * (k as f32 / ramp as f32).min(1.0),
        );
        common::step_torn(&mut sim, &mut out, k, &mut last_length);
        if sim.tear().started {
            path.push(sim.tear().tip());
        }
    }
    (sim, path)
}

/// The pattern positions of the cut's vertices (the ends of every lip edge), each once.
fn lip_vertices(sim: &Sim) -> Vec<V2> {
    let mut vs: Vec<u32> = sim.lips().runs().iter().flat_map(|r| r.edge).collect();
    vs.sort_unstable();
    vs.dedup();
    let sp = &sim.sheet().sp;
    let mut ps: Vec<V2> = vs.iter().map(|&v| sp.pattern[v as usize]).collect();
    ps.dedup_by(|a, b| a == b);
    ps
}

#[test]
fn an_equal_pull_tears_straight_into_two_pieces() {
    for (size, pos, seed) in [
        (SheetSize::A4, 0.5, 1),
        (SheetSize::A5, 0.3, 2),
        (SheetSize::A6, 0.6, 3),
    ] {
        let (sim, path) = pull(size, 1.0, 0.0, pos, 60, 300, seed);
        let w = sim.sheet().width_m;
        assert!(sim.tear().separated, "{size:?}: {:?}", sim.tear());
        assert_eq!(sim.sheet().sp.topo.pieces().len(), 2);
        assert_eq!(sim.tear().refused_steps, 0);
        let x0 = sim.tear().start_m[0];
        let worst = path.iter().map(|p| (p.x - x0).abs()).fold(0.0, f64::max);
        assert!(
            worst < 0.02 * w,
            "{size:?}: {worst} m off the straight line"
        );
        // The mesh's cut follows at the lattice's resolution: a crossing within a third of an
        // edge of a vertex tears through that vertex (sheet/cut.rs), so the lips zig-zag up to
        // a third of an edge (2.8–4.0 mm, 1.9–2.7 % of the width) about the tip's line.
        let lips = lip_vertices(&sim);
        assert!(lips.len() >= 8, "{size:?}: {} lip vertices", lips.len());
        let worst = lips.iter().map(|p| (p.x - x0).abs()).fold(0.0, f64::max);
        eprintln!(
            "{size:?}: lip vertices within {:.2} mm of the line",
            1e3 * worst
        );
        assert!(
            worst < 0.03 * w,
            "{size:?}: a lip vertex {worst} m off the line"
        );
        // It ran from the back edge to the front edge (the mesh separates the pieces once
        // the tip is within an edge of the border).
        let l = sim.sheet().length_m;
        assert!(sim.tear().start_m[1] >= 0.5 * l - 1e-9, "{:?}", sim.tear());
        assert!(path.last().unwrap().y <= -0.45 * l, "{:?}", path.last());
    }
}

#[test]
fn an_unequal_pull_tears_along_the_hyperbola_of_the_hands() {
    for (asym, pos, seed) in [(0.5, 0.5, 4), (1.0, 0.4, 5), (-0.7, 0.6, 6)] {
        let (sim, path) = pull(SheetSize::A4, 1.0, asym, pos, 60, 300, seed);
        assert!(sim.tear().separated, "asym {asym}: {:?}", sim.tear());
        let [a, b] = sim.tear().foci_m.map(|f| V2::new(f[0], f[1]));
        let ab = (b - a).norm();
        // |SA| − |SB| is constant on a hyperbola with foci A and B.
        let std = |points: &[V2]| {
            let diffs: Vec<f64> = points
                .iter()
                .map(|s| (s - a).norm() - (s - b).norm())
                .collect();
            let mean = diffs.iter().sum::<f64>() / diffs.len() as f64;
            (diffs.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / diffs.len() as f64).sqrt()
        };
        let tip = std(&path);
        assert!(tip < 0.02 * ab, "asym {asym}: std {tip} of |AB| {ab}");
        // The mesh's cut on the same hyperbola, at the lattice's resolution (a third of an
        // edge, above): 4.3–6.9 mm of spread in |SA| − |SB|, 2–3.5 mm from the curve.
        let lips = lip_vertices(&sim);
        assert!(lips.len() >= 8, "asym {asym}: {} lip vertices", lips.len());
        let cut = std(&lips);
        eprintln!(
            "asym {asym}: |SA| − |SB| spread {:.2} mm on the tip, {:.2} mm on the lips",
            1e3 * tip,
            1e3 * cut
        );
        assert!(cut < 0.05 * ab, "asym {asym}: lips' std {cut} of |AB| {ab}");
        // It curves: the tear ends off the straight line from its start, towards the nearer hand.
        let (s0, s1) = (path[0], *path.last().unwrap());
        let nearer_left = (s0 - a).norm() < (s0 - b).norm();
        assert_eq!(s1.x < s0.x, nearer_left, "asym {asym}: {s0:?} → {s1:?}");
        assert!((s1.x - s0.x).abs() > 0.01, "asym {asym}: {s0:?} → {s1:?}");
    }
}

#[test]
fn a_gentle_pull_tears_nothing_and_the_hands_let_go() {
    let (mut sim, path) = pull(SheetSize::A4, 0.2, 0.0, 0.5, 60, 200, 7);
    assert!(path.is_empty(), "a gentle pull tore: {:?}", sim.tear());
    assert!(sim.tear().release_n > 0.0, "it pulls");
    let mut out = FrameOutput::default();
    set(&mut sim, GestureParam::PullSeparation, 0.0);
    let mut frames = 0;
    while !sim.is_asleep() && frames < 400 {
        sim.step(&mut out);
        frames += 1;
    }
    assert!(sim.is_asleep(), "awake {frames} frames after letting go");
    assert!(!sim.tear().hands.active && !sim.tear().pulling);
    assert_eq!(sim.sheet().sp.topo.pieces().len(), 1);
}

#[test]
fn a_pull_held_through_a_reset_tears_again_only_when_it_rises() {
    let (mut sim, _) = pull(SheetSize::A5, 1.0, 0.0, 0.5, 40, 300, 8);
    assert!(sim.tear().separated);
    let mut out = FrameOutput::default();
    sim.apply(Command::Reset);
    for _ in 0..200 {
        sim.step(&mut out);
    }
    assert!(!sim.tear().started, "the held pull tore the new sheet");
    set(&mut sim, GestureParam::PullSeparation, 0.0);
    for _ in 0..60 {
        sim.step(&mut out);
    }
    assert_eq!(
        sim.tear().pull_floor,
        0.0,
        "the floor follows the pull down"
    );
    set(&mut sim, GestureParam::PullSeparation, 1.0);
    for _ in 0..400 {
        sim.step(&mut out);
    }
    assert!(sim.tear().separated, "{:?}", sim.tear());
}
