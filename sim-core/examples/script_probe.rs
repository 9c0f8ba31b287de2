//! Development probe: plays script files with several seeds and prints the singular counts,
//! c_mean and the self-contact health. `script_probe FILE SEED...`
use sim_core::scenario_run::run_script;
use sim_core::script::{Script, ScriptValue};
use sim_core::sim::SimConfig;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let base = Script::from_file(std::path::Path::new(&args[0])).unwrap();
    for seed in &args[1..] {
        let mut script = base.clone();
        script.set.retain(|(k, _)| k != "seed");
        script
            .set
            .push(("seed".into(), ScriptValue::Number(seed.parse().unwrap())));
        let s = run_script(&script, SimConfig::default(), true).unwrap();
        let mut runner =
            sim_core::script_runner::ScriptRunner::new(&script, 200.0, Default::default()).unwrap();
        let mut sim = runner.start(SimConfig::default());
        let mut out = sim_core::sim::FrameOutput::default();
        let mut squeeze_max = 0.0f64;
        while runner.drive(&mut sim, &mut out) {
            squeeze_max = squeeze_max.max(sim.crumple_squeeze().0);
        }
        println!(
            "seed {seed}: squeeze {squeeze_max:.2} singular {} c_mean {:.4} n_comp {:.2} strain {:.3} med {:.3} geom {:.3} flips {}",
            s.singular_final,
            s.c_mean_pct,
            s.n_comp_pct,
            s.max_strain,
            s.step_ms_quantile(0.5),
            s.geometry_ms_quantile(0.5),
            s.flips
        );
    }
}
