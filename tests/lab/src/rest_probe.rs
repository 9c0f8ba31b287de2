//! Does a held sheet come to rest, and if not, what keeps it moving? Plays a scene and prints,
//! per window of 50 frames (0.25 s), what could keep a sheet that nothing drives from settling:
//! the awake frames, the step time, the largest strain and vertex speed, the kinetic energy,
//! the crumple events and flipped curvature points the sound analysis saw, the frames in which
//! a hand slipped (and which hands), the crumple squeeze against its limit, the frames undone by
//! the pass-through guard, the substeps solved again or split, and the Newton solves that ended
//! at the iteration cap.
//!
//! `cargo run --release -p papier-lab -- rest-probe [NAME[@SEED]|FILE.toml]`
//! (default `sim-core/tests/fixtures/rest_front_slide_lift_crumple.toml`).

use std::time::Instant;

use sim_core::gesture_rig::NUM_HANDS;
use sim_core::sim::SimConfig;

use crate::args::at_most;
use crate::play::Play;

pub const USAGE: &str = "[NAME[@SEED]|FILE.toml]";

/// Frames per printed window.
const WINDOW: u64 = 50;

#[derive(Clone, Copy, Default)]
struct Window {
    frames: u64,
    awake: u64,
    step_ns: u128,
    max_step_ns: u128,
    strain: f32,
    speed: f32,
    ke: f32,
    crumple: u64,
    flipped: u64,
    slip_frames: u64,
    slip_hands: u32,
    undone: u64,
    held_back: u64,
    split: u64,
    capped: u64,
    squeeze: f64,
    limit: f64,
}

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 1)?;
    let default = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../sim-core/tests/fixtures/rest_front_slide_lift_crumple.toml"
    );
    let name = args.first().map_or(default, String::as_str);
    let mut p = Play::scene(name, SimConfig::default())?;
    let mut windows: Vec<Window> = Vec::new();
    loop {
        let t0 = Instant::now();
        if !p.frame() {
            break;
        }
        let step_ns = t0.elapsed().as_nanos();
        let k = ((p.out.sound.frame.max(1) - 1) / WINDOW) as usize;
        if windows.len() <= k {
            windows.resize(k + 1, Window::default());
        }
        let w = &mut windows[k];
        let s = &p.out.stats;
        w.frames += 1;
        w.awake += u64::from(!s.asleep);
        w.step_ns += step_ns;
        w.max_step_ns = w.max_step_ns.max(step_ns);
        w.strain = w.strain.max(s.max_strain);
        w.speed = w.speed.max(s.max_speed_m_s);
        w.ke = w.ke.max(s.kinetic_energy_j);
        let a = p.sim.analysis_stats();
        w.crumple += u64::from(a.crumple_events + a.clac_events + a.impact_events);
        w.flipped += u64::from(a.flipped_points);
        let hands = &p.sim.rig().state.hands;
        let mut slipped = false;
        for (h, hand) in hands.iter().enumerate().take(NUM_HANDS) {
            if hand.active && hand.slipping {
                w.slip_hands |= 1 << h;
                slipped = true;
            }
        }
        w.slip_frames += u64::from(slipped);
        w.undone += u64::from(s.undo_streak > 0);
        w.held_back += u64::from(s.held_back_substeps);
        w.split += u64::from(s.split_substeps);
        w.capped += u64::from(s.capped_substeps);
        if std::env::var("DBG").is_ok() && (1100..1103).contains(&p.out.sound.frame) {
            let mut line = format!(
                "f{} strain {:.4} vmax {:.4} it {} cap {} iso {:.2e} it1 {} contacts {} pairs {} ke {:.2e}",
                p.out.sound.frame,
                s.max_strain,
                s.max_speed_m_s,
                s.iterations,
                s.capped_substeps,
                p.sim.geometry().isometry.max_disp_m,
                p.sim.geometry().isometry.phase1_iters,
                s.num_contacts,
                0,
                s.kinetic_energy_j
            );
            line += &format!(
                " moving {} pend {} flips {} ins {} sing {}",
                p.sim.rig().is_moving(),
                p.sim.refinement_pending(),
                p.sim.flipped_edges(),
                p.sim.inserted_vertices(),
                s.num_singular
            );
            for (h, hand) in hands.iter().enumerate() {
                if hand.active {
                    line += &format!(" d{:.1e}", (hand.pose.pos() - hand.prev_pose.pos()).norm());
                    let q = hand.pose.pos();
                    line += &format!(
                        " | h{h}{} ({:.4},{:.4},{:.4}){}",
                        if hand.slipping { "*" } else { "" },
                        q.x,
                        q.y,
                        q.z,
                        if hand.yielded_to.is_some() { "y" } else { "" }
                    );
                }
            }
            println!("{line}");
        }
        let (squeeze, limit) = p.sim.crumple_squeeze();
        w.squeeze = squeeze;
        w.limit = limit;
    }
    println!(
        "{:>6} {:>5} {:>7} {:>7} {:>6} {:>6} {:>9} {:>5} {:>6} {:>5} {:>6} {:>4} {:>4} {:>4} {:>4} {:>13}",
        "t_s",
        "awake",
        "step",
        "max",
        "strain",
        "v_m_s",
        "KE_J",
        "crmp",
        "flips",
        "slip",
        "hands",
        "undo",
        "hold",
        "splt",
        "cap",
        "squeeze/limit"
    );
    for (k, w) in windows.iter().enumerate() {
        let n = w.frames.max(1) as f64;
        println!(
            "{:6.2} {:5} {:6.2}ms {:6.1}ms {:6.3} {:6.3} {:9.2e} {:5} {:6} {:5} {:6x} {:4} {:4} {:4} {:4} {:6.3}/{:6.3}",
            (k as u64 * WINDOW) as f64 / 200.0,
            w.awake,
            w.step_ns as f64 / n / 1e6,
            w.max_step_ns as f64 / 1e6,
            w.strain,
            w.speed,
            w.ke,
            w.crumple,
            w.flipped,
            w.slip_frames,
            w.slip_hands,
            w.undone,
            w.held_back,
            w.split,
            w.capped,
            w.squeeze,
            w.limit
        );
    }
    Ok(())
}
