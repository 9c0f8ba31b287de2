//! Compression strips per scene (digest-crumpling §3.3–3.4; `ShapeEvent::StripCurved`): how
//! many strips a run makes, in how many frames, how many are generalized cylinders (both
//! borders free), their size in S_P triangles and the mesh at the end. The figures of
//! `docs/sp-regeneration-plan.md` ("Strips are rare") come from it:
//! `cargo run --release -p sim-core --example strip_probe [-- NAME[@SEED]...]` (default: every
//! seed scenario).
use sim_core::geometry::ShapeEvent;
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, SimConfig};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<String> = if args.is_empty() {
        scenario::names().map(str::to_string).collect()
    } else {
        args
    };
    println!(
        "| scene | strips | cylinders | frames with strips | most in one frame | triangles per strip | S_P triangles at the end |"
    );
    println!("|---|---|---|---|---|---|---|");
    for arg in names {
        // `NAME@SEED` plays the scene with another seed.
        let script = scenario::get_seeded(&arg).expect("scene");
        let base = SimConfig::default();
        let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).expect("script");
        let mut sim = runner.start(base);
        let mut out = FrameOutput::default();
        let mut cmds = Vec::new();
        let (mut strips, mut cylinders, mut triangles, mut frames) = (0u64, 0u64, 0u64, 0u64);
        let mut most = 0u64;
        while {
            cmds.clear();
            runner.next_frame(&mut cmds)
        } {
            for c in cmds.drain(..) {
                sim.apply(c);
            }
            sim.step(&mut out);
            let mut n = 0;
            for e in &sim.geometry().events {
                if let ShapeEvent::StripCurved {
                    num_triangles,
                    cylinder,
                    ..
                } = e
                {
                    n += 1;
                    triangles += u64::from(*num_triangles);
                    cylinders += u64::from(*cylinder);
                }
            }
            strips += n;
            frames += u64::from(n > 0);
            most = most.max(n);
        }
        println!(
            "| {arg} | {strips} | {cylinders} | {frames} | {most} | {:.1} | {} |",
            triangles as f64 / strips.max(1) as f64,
            sim.sheet().sp.num_triangles()
        );
    }
}
