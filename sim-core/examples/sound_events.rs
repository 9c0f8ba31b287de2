//! Prints what the sound analysis hears in every seed scenario: crumple events per second
//! (curvature flips and clacs), sliding-contact frames, and the mean resonator (l_r, l_c).
//!
//! `cargo run --release -p sim-core --example sound_events [SCENARIO | FILE.toml ...]`

use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<&str> = if args.is_empty() {
        scenario::names().collect()
    } else {
        args.iter().map(String::as_str).collect()
    };
    println!(
        "{:30} {:>6} {:>8} {:>8} {:>6} {:>9} {:>8} {:>8} {:>8} {:>8}",
        "scenario",
        "secs",
        "crumple",
        "per_s",
        "clac",
        "fric_frm",
        "amp_mean",
        "lr_cm",
        "lc_cm",
        "constr%"
    );
    for name in names {
        let loaded = if name.ends_with(".toml") {
            std::fs::read_to_string(name)
                .map_err(|e| e.to_string())
                .and_then(|t| sim_core::script::Script::parse(&t).map_err(|e| e.to_string()))
        } else {
            scenario::get(name).map_err(|e| e.to_string())
        };
        let script = match loaded {
            Ok(s) => s,
            Err(e) => {
                eprintln!("{name}: {e}");
                continue;
            }
        };
        let base = SimConfig::default();
        let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
        let mut sim = runner.start(base);
        let mut out = FrameOutput::default();
        let (mut crumple, mut clac, mut fric_frames) = (0u64, 0u64, 0u64);
        let (mut amp, mut lr, mut lc, mut constrained, mut nres) = (0.0, 0.0, 0.0, 0u64, 0u64);
        let mut frames = 0u64;
        let mut hmax = 0.0f32;
        let mut flips = 0u64;
        while runner.drive(&mut sim, &mut out) {
            frames += 1;
            let st = sim.analysis_stats();
            flips += u64::from(st.flipped_points);
            hmax = sim
                .sound_analysis()
                .grid_curvature()
                .iter()
                .fold(hmax, |m, h| m.max(h.abs()));
            crumple += u64::from(st.crumple_events);
            clac += u64::from(st.clac_events);
            fric_frames += u64::from(!out.sound.friction().is_empty());
            for e in out.sound.crumple() {
                amp += f64::from(e.amplitude);
                lr += f64::from(e.resonator.lr_cm);
                lc += f64::from(e.resonator.lc_cm);
                constrained += u64::from(e.resonator.is_constrained());
                nres += 1;
            }
        }
        let secs = frames as f64 / base.frame_rate_hz;
        let d = nres.max(1) as f64;
        println!(
            "{:30} {:6.2} {:8} {:8.1} {:6} {:9} {:8.3} {:8.1} {:8.1} {:8.0}",
            name,
            secs,
            crumple,
            crumple as f64 / secs,
            clac,
            fric_frames,
            amp / d,
            lr / d,
            lc / d,
            100.0 * constrained as f64 / d
        );
        println!("    max |H| {hmax:.1} /m, flipped points {flips}");
    }
}
