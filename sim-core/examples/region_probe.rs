//! Development probe: the geometry layer's regions and rulings at a given time of a script.
//!
//! `cargo run --release -p sim-core --example region_probe -- NAME|FILE.toml TIME_S`
use sim_core::room::RoomConfig;
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let mut args = std::env::args().skip(1);
    let name = args.next().expect("scenario name or script file");
    let at_s: f64 = args.next().and_then(|v| v.parse().ok()).unwrap_or(1.0);
    let script = if name.ends_with(".toml") {
        sim_core::script::Script::parse(&std::fs::read_to_string(&name).expect("file"))
            .expect("script")
    } else {
        scenario::get(&name).expect("scenario")
    };
    let cfg = SimConfig::default();
    let mut runner =
        ScriptRunner::new(&script, cfg.frame_rate_hz, RoomConfig::default()).expect("runner");
    let mut sim = runner.start(cfg);
    let mut out = FrameOutput::default();
    while sim.time_s() < at_s && runner.drive(&mut sim, &mut out) {}
    let g = sim.geometry();
    println!("t {:.3} s: {} regions", sim.time_s(), g.regions.len());
    for (i, r) in g.regions.iter().enumerate() {
        println!(
            "  region {i}: {:?} tris {} area {:.4} m² rulings {} mean len {:.3} m free border {:.3} m",
            r.kind,
            r.num_triangles,
            r.area_m2,
            r.num_rulings,
            r.mean_ruling_len_m,
            r.free_border_len_m
        );
    }
    for (k, f) in out.sound.friction().iter().enumerate() {
        println!("  friction {k}: {:?}", f);
    }
}
