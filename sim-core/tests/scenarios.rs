//! The seed scenario library played through the simulation: every scenario stays healthy and
//! near-isometric, and the behaviours the scenarios are about actually happen (the sheet
//! curves up when two edges approach, slides rub on the table, the wall is touched, a room
//! change lifts the sheet smoothly, a sheet at rest costs nothing).

use sim_core::control::{Command, GestureParam, GrabSlot};
use sim_core::room::RoomConfig;
use sim_core::scenario;
use sim_core::scenario_run::run_scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, Sim, SimConfig};
use sim_core::sound_input::Obstacle;

/// Plays a scenario, calling `each(sim)` after every frame.
fn play(name: &str, mut each: impl FnMut(&Sim)) {
    let script = scenario::get(name).unwrap();
    let base = SimConfig::default();
    let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
    let mut sim = runner.start(base);
    let mut out = FrameOutput::default();
    while runner.drive(&mut sim, &mut out) {
        each(&sim);
    }
}

#[test]
fn every_scenario_is_healthy_and_near_isometric() {
    for name in scenario::names() {
        let s = run_scenario(name, SimConfig::default(), false).unwrap();
        assert_eq!((s.flips, s.recoveries), (0, 0), "{name}");
        // Regression guards (measured values are in docs/benchmarks.md): the whole frame
        // (physics + geometry layer) keeps the length error of these scripts well under the
        // seeds' post-isometry figures.
        assert!(s.c_mean_pct < 0.5, "{name}: c_mean {}", s.c_mean_pct);
        assert!(s.n_comp_pct < 10.0, "{name}: n_comp {}", s.n_comp_pct);
        // Largest Green strain over the scene: 0.049 at most (c2_moebius_twist; every scene's
        // figure is in docs/benchmarks.md), the solver run to convergence. Twice that means
        // the membrane gave way somewhere.
        assert!(s.max_strain < 0.1, "{name}: strain {}", s.max_strain);
        assert!(s.max_speed_m_s < 10.0, "{name}: speed {}", s.max_speed_m_s);
        assert!(
            (100.0..=220.0).contains(&s.triangles_avg),
            "{name}: {} triangles",
            s.triangles_avg
        );
    }
}

#[test]
fn the_seed_scenes_never_engage_the_tear() {
    // The tear and pull gestures at their defaults: no tear starts, no lip exists, the tear is
    // silent and the mesh stays one piece (so the tearing code cannot change their renders).
    for name in scenario::names().filter(|n| !n.starts_with('t')) {
        let mut engaged = 0usize;
        play(name, |sim| {
            let t = sim.tear();
            engaged += usize::from(
                t.started
                    || t.pending
                    || t.pulling
                    || t.path_length_m > 0.0
                    || !sim.lips().runs().is_empty(),
            );
        });
        assert_eq!(engaged, 0, "{name}: the tear engaged in {engaged} frames");
    }
}

#[test]
fn approaching_edges_curve_the_sheet_up() {
    // S1: back and front edges slide together: the middle rises well above the table.
    let mut z_max: f64 = 0.0;
    play("s1_slide_release_pinch", |sim| {
        if sim.time_s() < 1.5 {
            let z = sim.sheet().sp.pos.iter().map(|p| p.z).fold(0.0, f64::max);
            z_max = z_max.max(z);
        }
    });
    assert!(z_max > 0.75 + 0.03, "the sheet bows up: top at {z_max}");
}

#[test]
fn sliding_rubs_on_the_table_and_pushing_reaches_the_wall() {
    let (mut sliding, mut touching) = (0usize, 0usize);
    play("s6_slide_on_table", |sim| {
        sliding += sim
            .contacts()
            .iter()
            .filter(|c| c.in_contact && c.obstacle == Obstacle::Table && c.slip_speed_m_s > 0.01)
            .count();
    });
    assert!(sliding > 100, "vertices slide on the table: {sliding}");
    play("s3_wiggle_near_wall", |sim| {
        touching += sim
            .contacts()
            .iter()
            .filter(|c| c.in_contact && c.obstacle == Obstacle::Wall)
            .count();
    });
    assert!(touching > 0, "the sheet touches the wall");
}

#[test]
fn a_sheet_at_rest_sleeps_and_does_no_work() {
    let mut sim = Sim::new(SimConfig::default());
    let mut out = FrameOutput::default();
    assert!(sim.is_asleep());
    let work = sim.work_counter();
    let before = sim.save();
    for _ in 0..1000 {
        sim.step(&mut out);
        assert!(out.stats.asleep);
    }
    assert_eq!(sim.work_counter(), work, "no substep while asleep");
    assert_eq!(sim.save().positions_m, before.positions_m);
    // A hand moving wakes it; once the hand has arrived and the sheet settled, it sleeps again.
    sim.apply(Command::Grab {
        slot: GrabSlot::Front,
        grip: 1.0,
    });
    sim.apply(Command::Gesture {
        param: GestureParam::Lift,
        value: 0.3,
    });
    assert!(!sim.is_asleep());
    let mut frames = 0;
    while !sim.is_asleep() {
        sim.step(&mut out);
        frames += 1;
        assert!(frames < 4000, "never fell asleep");
    }
    let work = sim.work_counter();
    for _ in 0..500 {
        sim.step(&mut out);
    }
    assert_eq!(sim.work_counter(), work);
    // A command that changes nothing does not wake it.
    sim.apply(Command::Gesture {
        param: GestureParam::Lift,
        value: 0.3,
    });
    sim.apply(Command::Release {
        slot: GrabSlot::Back,
    });
    assert!(sim.is_asleep());
}

#[test]
fn raising_the_table_lifts_the_sheet_smoothly() {
    let mut sim = Sim::new(SimConfig::default());
    let mut out = FrameOutput::default();
    sim.apply(Command::Room(RoomConfig {
        table_height_cm: 100.0,
        ..RoomConfig::default()
    }));
    let mut vmax: f32 = 0.0;
    for _ in 0..400 {
        sim.step(&mut out);
        vmax = vmax.max(out.stats.max_speed_m_s);
        assert_eq!(out.stats.num_flipped, 0);
    }
    let z: Vec<f64> = sim.sheet().sp.pos.iter().map(|p| p.z).collect();
    assert!(
        z.iter().all(|&z| (z - 1.0).abs() < 1e-3),
        "the sheet rode up with the table"
    );
    assert!(vmax < 1.0, "no explosion: {vmax} m/s");
    // Switching the table off drops the sheet to the floor.
    sim.apply(Command::Room(RoomConfig {
        table: false,
        ..RoomConfig::default()
    }));
    for _ in 0..600 {
        sim.step(&mut out);
    }
    let zmax = sim.sheet().sp.pos.iter().map(|p| p.z).fold(0.0, f64::max);
    assert!(zmax < 0.05, "on the floor: {zmax}");
}

/// A table raised into a crumpled sheet held by two hands and the crumple hands lifts it
/// whole: the hands yield to the table together. When only the hands whose patch the table
/// touched were carried, their vertices rode on the table top under the layers the table
/// pushed up through the ball, the sheet between was pulled apart and held vertices slipped
/// into the table (here 1.2 cm inside it at the end; in the long stress runs, seeds 17 and 24,
/// strain above 1 and a degenerate triangle).
#[test]
fn a_table_raised_into_a_held_crumpled_sheet_lifts_it_whole() {
    let mut sim = Sim::new(SimConfig::default());
    let mut out = FrameOutput::default();
    for slot in [GrabSlot::Left, GrabSlot::Right] {
        sim.apply(Command::Grab { slot, grip: 0.5 });
    }
    sim.apply(Command::Gesture {
        param: GestureParam::Crumple,
        value: 0.6,
    });
    for _ in 0..300 {
        sim.step(&mut out);
    }
    sim.apply(Command::Room(RoomConfig {
        table_height_cm: 120.0,
        ..RoomConfig::default()
    }));
    let mut strain: f32 = 0.0;
    for _ in 0..400 {
        sim.step(&mut out);
        strain = strain.max(out.stats.max_strain);
        assert_eq!(out.stats.num_flipped, 0);
    }
    let zmin = sim.sheet().sp.pos.iter().map(|p| p.z).fold(9.0, f64::min);
    assert!(
        zmin > 1.2 - 1e-3,
        "sheet pressed into the table: z {zmin} m"
    );
    assert!(strain < 0.5, "strain {strain}");
}

#[test]
fn reset_keeps_held_slots_and_size_changes_rebuild() {
    let mut sim = Sim::new(SimConfig::default());
    let mut out = FrameOutput::default();
    sim.apply(Command::Grab {
        slot: GrabSlot::Back,
        grip: 0.5,
    });
    sim.apply(Command::Gesture {
        param: GestureParam::Slide,
        value: 0.4,
    });
    for _ in 0..100 {
        sim.step(&mut out);
    }
    let nt = sim.sheet().sp.num_triangles();
    sim.apply(Command::Reset);
    assert_eq!(sim.frame(), 0);
    assert!(
        sim.rig().state.held[GrabSlot::Back.index()].is_some(),
        "still held"
    );
    assert!(
        sim.sheet()
            .sp
            .pos
            .iter()
            .all(|p| (p.z - 0.75).abs() < 1e-12),
        "flat again"
    );
    sim.step(&mut out);
    assert!(out.stats.num_held > 0);
    sim.apply(Command::Size(sim_core::SheetSize::Sq10));
    assert_ne!(sim.sheet().sp.num_triangles(), nt);
    let (nv, ntc) = sim.mesh_capacity();
    assert!(nv >= sim.sheet().sp.num_vertices() && ntc >= sim.sheet().sp.num_triangles());
    for _ in 0..50 {
        sim.step(&mut out);
    }
    assert_eq!(out.stats.recoveries, 0);
}
