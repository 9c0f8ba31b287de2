//! Prints the per-frame statistics of one scenario (debugging aid).
//!
//! `cargo run --release -p sim-core --example scenario_trace -- NAME|FILE.toml [newton|xpbd] SUBSTEPS ITERS`
//! (`PAPIER_NO_GEOMETRY=1` turns the geometry layer off).

use sim_core::physics::SolverKind;
use sim_core::room::RoomConfig;
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().expect("scenario name");
    let mut cfg = SimConfig::default();
    if let Some(k) = args.get(1) {
        cfg.solver.kind = if k == "xpbd" {
            SolverKind::Xpbd
        } else {
            SolverKind::Newton
        };
    }
    if let Some(s) = args.get(2) {
        cfg.solver.substeps = s.parse().expect("substeps");
    }
    if let Some(s) = args.get(3) {
        cfg.solver.iterations = s.parse().expect("iterations");
    }
    if std::env::var_os("PAPIER_NO_GEOMETRY").is_some() {
        cfg.geometry.enabled = false;
    }
    let script = if name.ends_with(".toml") {
        let text = std::fs::read_to_string(name).expect("script file");
        sim_core::script::Script::parse(&text).expect("script")
    } else {
        scenario::get(name).expect("scenario")
    };
    let mut runner =
        ScriptRunner::new(&script, cfg.frame_rate_hz, RoomConfig::default()).expect("runner");
    let mut sim = runner.start(cfg);
    let mut out = FrameOutput::default();
    let mut cmds = Vec::new();
    while {
        cmds.clear();
        runner.next_frame(&mut cmds)
    } {
        for c in cmds.drain(..) {
            println!("  cmd {c:?}");
            sim.apply(c);
        }
        sim.step(&mut out);
        let s = out.stats;
        println!(
            "f {:4} t {:5.3} sleep {} it {:2} c {:6.3} nc {:5.1} strain {:6.3} vmax {:6.3} ke {:.2e} held {:2} cont {:3} flip {} rec {} sing {} ev {}",
            sim.frame(),
            sim.time_s(),
            s.asleep as u8,
            s.iterations,
            s.c_mean_pct,
            s.n_comp_pct,
            s.max_strain,
            s.max_speed_m_s,
            s.kinetic_energy_j,
            s.num_held,
            s.num_contacts,
            s.num_flipped,
            s.recoveries,
            s.num_singular,
            out.sound.crumple().len()
        );
    }
}
