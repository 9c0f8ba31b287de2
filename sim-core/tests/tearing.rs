//! Tearing I in the frame loop (sim/tear.rs): `tear_amount` 0 → 1 tears the sheet in two
//! whatever the steer, the torn mesh keeps its invariants in every frame, the mesh changes
//! are announced, the tear sounds while it moves, and a save mid-tear continues exactly.

mod common;

use sim_core::control::{Command, GestureParam, GrabSlot, SheetSize};
use sim_core::scenario_run::state_hash;
use sim_core::sim::{FrameOutput, Sim, SimConfig};

use common::set_gesture as set;

/// A sheet on the table torn by `tear_amount` ramped 0 → 1 over `ramp_frames` at `steer`,
/// then `hold` frames more; checks the invariants every frame (`common::step_torn`). Returns
/// the sim and the frames in which the tear sounded.
fn tear(
    size: SheetSize,
    steer: f32,
    pos: f32,
    ramp_frames: u32,
    hold: u32,
    seed: u64,
) -> (Sim, Vec<u32>) {
    let (mut sim, _, _) = common::sheet_on_table(size, seed);
    let mut out = FrameOutput::default();
    set(&mut sim, GestureParam::TearSteer, steer);
    set(&mut sim, GestureParam::TearPosition, pos);
    let mut sounding = Vec::new();
    let mut last_length = 0.0f32;
    for k in 1..=ramp_frames + hold {
        let amount = (k as f32 / ramp_frames as f32).min(1.0);
        set(&mut sim, GestureParam::TearAmount, amount);
        common::step_torn(&mut sim, &mut out, k, &mut last_length);
        let t = out.sound.tear;
        if t.speed_m_s > 0.0 {
            sounding.push(k);
            assert!(t.tip_m.iter().all(|c| c.is_finite()));
        }
    }
    (sim, sounding)
}

#[test]
fn a_full_tear_leaves_exactly_two_pieces_with_the_sheets_area_whatever_the_steer() {
    for (size, steer, pos, seed) in [
        (SheetSize::A4, 0.0, 0.5, 1),
        (SheetSize::A4, 0.6, 0.3, 2),
        (SheetSize::A5, -1.0, 0.7, 3),
        (SheetSize::A6, 0.3, 0.5, 4),
        (SheetSize::A4, 1.0, 0.9, 5),
    ] {
        let (sim, sounding) = tear(size, steer, pos, 200, 80, seed);
        assert!(
            sim.tear().separated,
            "{size:?} steer {steer}: not separated {:?}",
            sim.tear()
        );
        assert_eq!(sim.sheet().sp.topo.pieces().len(), 2);
        // It sounded from the first frame the amount rose until the tip stopped.
        assert_eq!(sounding.first(), Some(&1), "{size:?} steer {steer}");
        assert!(
            sounding.len() >= 10,
            "{size:?} steer {steer}: {} frames",
            sounding.len()
        );
        assert_eq!(sim.tear().refused_steps, 0, "{size:?} steer {steer}");
    }
}

#[test]
fn a_held_amount_stops_the_tear_and_the_sheet_comes_to_rest() {
    let mut sim = Sim::new(SimConfig::default());
    let mut out = FrameOutput::default();
    for k in 1..=100 {
        set(&mut sim, GestureParam::TearAmount, k as f32 / 200.0);
        sim.step(&mut out);
    }
    // The hands' rotation catches up with the amount (a 40 ms low-pass), then stops.
    for _ in 0..80 {
        sim.step(&mut out);
    }
    let length = sim.tear().path_length_m;
    assert!(length > 0.1 && !sim.tear().separated);
    for _ in 0..320 {
        sim.step(&mut out);
        assert_eq!(out.sound.tear.speed_m_s, 0.0);
    }
    assert_eq!(sim.tear().path_length_m, length);
    assert_eq!(sim.sheet().sp.topo.pieces().len(), 1);
    assert!(sim.is_asleep(), "a half-torn sheet on the table sleeps");
}

#[test]
fn a_reset_gives_a_whole_sheet_that_tears_again() {
    let (mut sim, _) = tear(SheetSize::A6, 0.0, 0.5, 100, 80, 9);
    assert!(sim.tear().separated);
    sim.apply(Command::Reset);
    let mut out = FrameOutput::default();
    for _ in 0..5 {
        sim.step(&mut out);
    }
    assert_eq!(sim.sheet().sp.topo.pieces().len(), 1);
    assert!(
        !sim.tear().started,
        "the amount held at 1 does not tear the new sheet"
    );
    set(&mut sim, GestureParam::TearAmount, 0.0);
    for k in 1..=150 {
        set(
            &mut sim,
            GestureParam::TearAmount,
            (k as f32 / 100.0).min(1.0),
        );
        sim.step(&mut out);
    }
    assert!(sim.tear().separated);
}

#[test]
fn a_sheet_saved_mid_tear_continues_bit_identically() {
    let mut a = Sim::new(SimConfig {
        size: SheetSize::A5,
        ..SimConfig::default()
    });
    let mut out = FrameOutput::default();
    let drive = |sim: &mut Sim, k: u32| {
        set(
            sim,
            GestureParam::TearSteer,
            if (k / 30).is_multiple_of(2) {
                0.8
            } else {
                -0.8
            },
        );
        set(sim, GestureParam::TearAmount, (k as f32 / 160.0).min(1.0));
    };
    for k in 1..=70 {
        drive(&mut a, k);
        a.step(&mut out);
    }
    assert!(a.tear().mesh_steps > 0);
    let saved = a.save();
    let json = serde_json::to_string(&saved).unwrap();
    let mut b = Sim::restore(SimConfig::default(), &serde_json::from_str(&json).unwrap()).unwrap();
    // Both outputs fresh (a frame's unused event slots keep older frames' events).
    let (mut out, mut out_b) = (FrameOutput::default(), FrameOutput::default());
    for k in 71..=260 {
        drive(&mut a, k);
        drive(&mut b, k);
        a.step(&mut out);
        b.step(&mut out_b);
        assert_eq!(out.sound, out_b.sound, "frame {k}");
        assert_eq!(state_hash(&a), state_hash(&b), "frame {k}");
    }
    assert!(a.tear().separated);
}

/// A seed changed while the sheet tears is the next sheet's: this one keeps its fibres (its
/// lips, the pull's fracture), and a sheet saved after the change, which saves its fibres'
/// seed, continues exactly, lips and all. (Found by the stress sessions over seeds 1000–1019:
/// the restore made the fibres from the new seed, and a restored pull ran elsewhere.)
#[test]
fn a_sheet_saved_after_a_seed_change_mid_tear_continues_bit_identically() {
    let mut a = Sim::new(SimConfig {
        size: SheetSize::A5,
        ..SimConfig::default()
    });
    let mut out = FrameOutput::default();
    let drive = |sim: &mut Sim, k: u32| {
        set(sim, GestureParam::TearAmount, (k as f32 / 160.0).min(1.0));
    };
    for k in 1..=70 {
        drive(&mut a, k);
        if k == 40 {
            a.apply(Command::Seed(0x5eed_0042));
        }
        a.step(&mut out);
    }
    assert!(a.tear().mesh_steps > 0);
    let saved = a.save();
    let json = serde_json::to_string(&saved).unwrap();
    let mut b = Sim::restore(SimConfig::default(), &serde_json::from_str(&json).unwrap()).unwrap();
    let snapshot = || sim_core::mesh_snapshot::MeshSnapshot::with_capacity(4096, 8192);
    let (mut mesh_a, mut mesh_b) = (snapshot(), snapshot());
    let (mut out, mut out_b) = (FrameOutput::default(), FrameOutput::default());
    for k in 71..=260 {
        a.write_mesh(&mut mesh_a);
        b.write_mesh(&mut mesh_b);
        assert!(!mesh_a.lips.is_empty(), "frame {k}: lips drawn");
        assert_eq!(mesh_a, mesh_b, "frame {k}: the meshes and their lips");
        drive(&mut a, k);
        drive(&mut b, k);
        a.step(&mut out);
        b.step(&mut out_b);
        assert_eq!(a.tear(), b.tear(), "frame {k}");
        assert_eq!(state_hash(&a), state_hash(&b), "frame {k}");
    }
    assert!(a.tear().separated);
}

/// A tear step that would leave a vertex joining two triangles by their corner alone (a
/// bow-tie; the stress session of seed 1029 at frame 21 868, a coarse A4 torn twice) is
/// refused: the mesh stays as it was, every piece a disc, and the tear goes on later.
#[test]
fn a_tear_step_that_would_make_a_bow_tie_is_refused() {
    let fixture: sim_core::stress::StressFixture =
        serde_json::from_str(include_str!("fixtures/stress_seed1029_frame21867.json")).unwrap();
    let mut sim = fixture
        .restore(sim_core::stress::StressConfig::test_session(0, 0).sim)
        .unwrap();
    assert!(
        sim.tear().pending,
        "the fixture's next frame makes a tear step"
    );
    let mut out = FrameOutput::default();
    for k in 1..=5 {
        sim.step(&mut out);
        if let Err(e) = sim.sheet().sp.topo.validate_pieces() {
            panic!("frame {k}: {e}");
        }
    }
}

#[test]
fn a_tear_onsets_when_it_starts_and_again_after_a_pause_and_carries_its_flaps() {
    // A6 torn in two pushes: 0 → 0.3 over 0.3 s, held 0.3 s, 0.3 → 0.5 over 0.2 s, held.
    let (mut sim, _, _) = common::sheet_on_table(SheetSize::A6, 11);
    let mut out = FrameOutput::default();
    let mut last_length = 0.0f32;
    let mut onsets = Vec::new();
    let mut moving = 0;
    let mut first_moving = None;
    let mut with_flaps = 0;
    let mut free_flaps = 0;
    let lanes: Vec<f32> = (0..60)
        .map(|k| 0.3 * k as f32 / 60.0)
        .chain(std::iter::repeat_n(0.3, 60))
        .chain((0..40).map(|k| 0.3 + 0.2 * k as f32 / 40.0))
        .chain(std::iter::repeat_n(0.5, 40))
        .collect();
    for (k, &amount) in lanes.iter().enumerate() {
        set(&mut sim, GestureParam::TearAmount, amount);
        common::step_torn(&mut sim, &mut out, k as u32 + 1, &mut last_length);
        let t = out.sound.tear;
        if t.onset {
            assert!(t.speed_m_s > 0.0, "frame {k}: an onset of a still tip");
            onsets.push(k);
        }
        if t.speed_m_s > 0.0 {
            moving += 1;
            first_moving.get_or_insert(k);
            let r = t.resonator;
            if r.radius_m > 0.0 {
                with_flaps += 1;
                assert!(r.lr_cm > 0.0 && r.lr_cm.is_finite(), "frame {k}: {r:?}");
                assert!(r.centre_m.iter().all(|c| c.is_finite()));
                free_flaps += usize::from(!r.is_constrained());
            }
        } else {
            assert!(!t.onset);
        }
    }
    assert_eq!(onsets.len(), 2, "onsets at {onsets:?}");
    assert_eq!(
        Some(onsets[0]),
        first_moving,
        "the first moving frame is an onset"
    );
    assert!((120..=130).contains(&onsets[1]), "onsets at {onsets:?}");
    assert!(moving > 40, "{moving} moving frames");
    assert_eq!(with_flaps, moving, "every moving frame has its flaps");
    // The left flap is lifted (sim/tear_hands.rs): free regions at the tip.
    assert!(free_flaps > moving / 2, "{free_flaps} of {moving} free");
}

/// Distance from `q` to the segment [a, b].
fn segment_distance(q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (abx, aby) = (b[0] - a[0], b[1] - a[1]);
    let l2 = abx * abx + aby * aby;
    let t = if l2 > 0.0 {
        (((q[0] - a[0]) * abx + (q[1] - a[1]) * aby) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (q[0] - a[0] - t * abx).hypot(q[1] - a[1] - t * aby)
}

#[test]
fn the_torn_lips_are_jagged_at_the_millimetre_scale_and_their_teeth_fit() {
    // A family of tears (sizes, steers, places, seeds), none tuned on.
    for (size, steer, pos, seed) in [
        (SheetSize::A6, 0.0, 0.5, 5u64),
        (SheetSize::A5, 0.6, 0.3, 17),
        (SheetSize::A6, -0.8, 0.7, 23),
        (SheetSize::A4, 0.3, 0.45, 31),
    ] {
        let (sim, _) = tear(size, steer, pos, 160, 20, seed);
        let label = format!("{size:?} steer {steer} seed {seed}");
        let runs = sim.lips().runs();
        assert!(runs.len() >= 4, "{label}: {} lip edges", runs.len());
        let sp = &sim.sheet().sp;
        let (mut sum_mm, mut n, mut max_mm, mut lip_length_m) = (0.0, 0usize, 0.0f64, 0.0);
        for r in runs {
            let p = r.points();
            let (a, b) = (
                sp.pattern[r.edge[0] as usize],
                sp.pattern[r.edge[1] as usize],
            );
            assert_eq!(p[0], [a.x, a.y], "{label}: a run starts at its vertex");
            assert_eq!(
                p[p.len() - 1],
                [b.x, b.y],
                "{label}: a run ends at its vertex"
            );
            lip_length_m += (b - a).norm();
            for q in &p[1..p.len() - 1] {
                let d_mm = 1e3 * segment_distance(*q, [a.x, a.y], [b.x, b.y]);
                sum_mm += d_mm;
                max_mm = max_mm.max(d_mm);
                n += 1;
            }
            // The other lip has the same jag, run the other way.
            let twin = runs
                .iter()
                .find(|t| t.edge != r.edge && t.points().iter().rev().eq(p.iter()))
                .unwrap_or_else(|| panic!("{label}: lip edge {:?} has no twin", r.edge));
            assert_ne!(twin.triangle, r.triangle);
        }
        let mean_mm = sum_mm / n as f64;
        eprintln!(
            "{label}: {} lip edges, {:.1} cm of lips, jag mean {mean_mm:.2} mm, max {max_mm:.2} mm",
            runs.len(),
            100.0 * lip_length_m
        );
        assert!((0.1..=1.0).contains(&mean_mm), "{label}: mean {mean_mm} mm");
        assert!(max_mm <= 2.5, "{label}: max {max_mm} mm");
        // Two lips as long as the tear, at least.
        assert!(lip_length_m >= 1.9 * sim.tear().path_length_m, "{label}");

        // The snapshot carries them into 3D, their ends on the vertices.
        let (nv, nt) = sim.mesh_capacity();
        let mut snap = sim_core::mesh_snapshot::MeshSnapshot::with_capacity(nv, nt);
        sim.write_mesh(&mut snap);
        assert_eq!(snap.lips.len(), runs.len());
        for l in &snap.lips {
            let pts = &snap.lip_points_m[l.start as usize..(l.start + l.len) as usize];
            for (end, v) in [(pts[0], l.edge[0]), (pts[pts.len() - 1], l.edge[1])] {
                let want = snap.positions_m[v as usize];
                assert!((0..3).all(|i| (end[i] - want[i]).abs() < 1e-5), "{label}");
            }
        }
    }
    // A whole sheet has none, and a reset makes the sheet whole again.
    let (mut sim, _) = tear(SheetSize::A6, 0.0, 0.5, 100, 10, 9);
    assert!(!sim.lips().runs().is_empty());
    sim.apply(Command::Reset);
    assert!(sim.lips().runs().is_empty());
}

#[test]
fn the_torn_pieces_are_sheets_they_crumple_and_slide_with_their_sounds() {
    // Torn in two, then crumpled by the corners (two on each piece), let go, then the front
    // edge (half of it on each piece) slid toward the back.
    let (mut sim, _) = tear(SheetSize::A5, 0.0, 0.5, 150, 60, 13);
    assert!(sim.tear().separated);
    let mut out = FrameOutput::default();
    let mut last_length = sim.tear().path_length_m as f32;
    let mut k = 1000;
    let mut step = |sim: &mut Sim, out: &mut FrameOutput| {
        k += 1;
        common::step_torn(sim, out, k, &mut last_length);
        assert_eq!(sim.sheet().sp.topo.pieces().len(), 2, "frame {k}");
        assert_eq!(out.stats.num_flipped, 0, "frame {k}");
    };
    sim.apply(Command::Grab {
        slot: GrabSlot::Corners,
        grip: 1.0,
    });
    let (mut crumples, mut rubs) = (0usize, 0usize);
    for i in 1..=200 {
        set(
            &mut sim,
            GestureParam::Crumple,
            0.7 * (i as f32 / 150.0).min(1.0),
        );
        step(&mut sim, &mut out);
        crumples += out.sound.crumple().len();
    }
    set(&mut sim, GestureParam::Crumple, 0.0);
    sim.apply(Command::Release {
        slot: GrabSlot::Corners,
    });
    for _ in 0..200 {
        step(&mut sim, &mut out);
    }
    sim.apply(Command::Grab {
        slot: GrabSlot::Front,
        grip: 1.0,
    });
    for i in 1..=200 {
        set(
            &mut sim,
            GestureParam::Slide,
            0.5 * (i as f32 / 150.0).min(1.0),
        );
        step(&mut sim, &mut out);
        rubs += usize::from(!out.sound.friction().is_empty());
    }
    eprintln!("crumple events {crumples}, frames with friction {rubs}");
    assert!(crumples >= 5, "{crumples} crumple events");
    assert!(rubs >= 20, "{rubs} frames with friction");
}

/// Heading of the tip's motion over the `span` path points ending at `end`, radians.
fn heading(path: &[sim_core::math::V2], end: usize, span: usize) -> f64 {
    let d = path[end] - path[end.saturating_sub(span)];
    d.y.atan2(d.x)
}

#[test]
fn an_alternating_steer_zig_zags_the_tear() {
    // Thesis Fig. 3.10 (T 1374-1392): the balance of the hands' rotations steers the tear; the
    // steer switched +s, −s, +s along the ramp turns the tip one way, back, and the first way
    // again, and the opposite steer mirrors it. A family of sizes, places, strengths and seeds.
    for (size, s, pos, seed) in [
        (SheetSize::A4, 0.8, 0.35, 22u64),
        (SheetSize::A4, -0.8, 0.35, 22),
        (SheetSize::A5, 0.6, 0.5, 41),
        (SheetSize::A6, -1.0, 0.6, 43),
        (SheetSize::A4, 0.5, 0.7, 47),
    ] {
        let label = format!("{size:?} steer {s:+} then {:+} at {pos} seed {seed}", -s);
        let (mut sim, _, _) = common::sheet_on_table(size, seed);
        let mut out = FrameOutput::default();
        set(&mut sim, GestureParam::TearPosition, pos);
        let ramp = 240u32;
        let mut last_length = 0.0f32;
        // The tip's path and, for each third of the ramp, the path index where it ended.
        let (mut path, mut ends) = (Vec::new(), Vec::new());
        for k in 1..=ramp {
            let third = (3 * (k - 1) / ramp) as usize;
            let steer = if third == 1 { -s } else { s };
            set(&mut sim, GestureParam::TearSteer, steer);
            set(&mut sim, GestureParam::TearAmount, k as f32 / ramp as f32);
            common::step_torn(&mut sim, &mut out, k, &mut last_length);
            if sim.tear().started && !sim.tear().separated {
                path.push(sim.tear().tip());
            }
            if k % (ramp / 3) == 0 {
                ends.push(path.len().saturating_sub(1));
            }
        }
        let span = 6;
        assert!(ends[0] > 2 * span, "{label}: {} path points", path.len());
        assert!(ends[2] > ends[1] + span, "{label}: the tear ended early");
        // Heading at the end of each third against straight down the sheet (−y).
        let turns = [0, 1, 2].map(|i| {
            let h = heading(&path, ends[i], span) + std::f64::consts::FRAC_PI_2;
            (h + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
        });
        eprintln!(
            "{label}: headings off the axis {:?} deg",
            turns.map(|t| (t.to_degrees() * 10.0).round() / 10.0)
        );
        for (i, t) in turns.iter().enumerate() {
            assert!(
                t.abs() > 5f64.to_radians(),
                "{label}: third {i} off by {t} rad"
            );
        }
        assert!(
            turns[0].signum() != turns[1].signum() && turns[1].signum() != turns[2].signum(),
            "{label}: no zig-zag {turns:?}"
        );
        // The steer's sign sets the way (the same rule for every sheet).
        assert_eq!(turns[0] > 0.0, s > 0.0, "{label}: {turns:?}");
    }
}

/// Mean pattern length of the mesh's edges, metres.
fn mean_edge_m(sp: &sim_core::sheet::physical::PhysMesh) -> f64 {
    let edges = &sp.topo.edges;
    let sum: f64 = edges
        .iter()
        .map(|e| (sp.pattern[e.v[0] as usize] - sp.pattern[e.v[1] as usize]).norm())
        .sum();
    sum / edges.len() as f64
}

#[test]
fn the_flaps_open_as_a_cone_whose_apex_is_the_tip() {
    // M:87–95, thesis T:1333: the flaps either side of the crack form a cone whose apex is the
    // tip. Half-way through a tear, the two lips' gap (their 3D distance at each pattern point
    // of the cut) grows linearly with the distance from the tip and closes at the tip.
    for (size, steer, pos, seed) in [
        (SheetSize::A4, 0.0, 0.5, 61u64),
        (SheetSize::A5, 0.5, 0.4, 62),
        (SheetSize::A6, -0.4, 0.6, 63),
        (SheetSize::A4, -0.3, 0.3, 64),
    ] {
        let label = format!("{size:?} steer {steer} seed {seed}");
        let (mut sim, _, _) = common::sheet_on_table(size, seed);
        let mut out = FrameOutput::default();
        set(&mut sim, GestureParam::TearSteer, steer);
        set(&mut sim, GestureParam::TearPosition, pos);
        let mut last_length = 0.0f32;
        for k in 1..=160u32 {
            set(
                &mut sim,
                GestureParam::TearAmount,
                (k as f32 / 200.0).min(0.6),
            );
            common::step_torn(&mut sim, &mut out, k, &mut last_length);
        }
        assert!(sim.tear().started && !sim.tear().separated, "{label}");
        let sp = &sim.sheet().sp;
        let tip = sim.tear().tip();
        // Pairs of lip vertices at one pattern point: (distance from the tip, gap).
        let mut vs: Vec<u32> = sim.lips().runs().iter().flat_map(|r| r.edge).collect();
        vs.sort_unstable();
        vs.dedup();
        let mut pairs = Vec::new();
        for (i, &a) in vs.iter().enumerate() {
            for &b in &vs[i + 1..] {
                let (pa, pb) = (sp.pattern[a as usize], sp.pattern[b as usize]);
                if (pa - pb).norm() < 1e-12 {
                    let gap = (sp.pos[a as usize] - sp.pos[b as usize]).norm();
                    pairs.push(((pa - tip).norm(), gap));
                }
            }
        }
        assert!(pairs.len() >= 4, "{label}: {} lip pairs", pairs.len());
        // Least squares gap = a + b·d.
        let n = pairs.len() as f64;
        let (sd, sg) = pairs
            .iter()
            .fold((0.0, 0.0), |(x, y), p| (x + p.0, y + p.1));
        let (md, mg) = (sd / n, sg / n);
        let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
        for &(d, g) in &pairs {
            sxy += (d - md) * (g - mg);
            sxx += (d - md) * (d - md);
            syy += (g - mg) * (g - mg);
        }
        let slope = sxy / sxx;
        let r = sxy / (sxx * syy).sqrt();
        let apex_m = md - mg / slope;
        eprintln!(
            "{label}: {} pairs, gap = {:.1} mm + {:.3}·d, r {r:.3}, gap closes {:.1} mm from the tip, widest {:.1} mm, edges {:.1} mm",
            pairs.len(),
            1e3 * (mg - slope * md),
            slope,
            1e3 * apex_m,
            1e3 * pairs.iter().map(|p| p.1).fold(0.0, f64::max),
            1e3 * mean_edge_m(sp)
        );
        assert!(
            (0.2..=1.0).contains(&slope),
            "{label}: the flaps open by {slope} m a metre"
        );
        assert!(r > 0.95, "{label}: not a cone (r {r})");
        // The apex is the tip at the mesh's resolution: the cut's vertices are an edge apart,
        // and the bent sheet rounds the apex over about an edge.
        let edge_m = mean_edge_m(sp);
        assert!(
            apex_m.abs() < 2.0 * edge_m,
            "{label}: the gap closes {apex_m} m from the tip (edges {edge_m} m)"
        );
    }
}
