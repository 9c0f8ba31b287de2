//! Prints per-scenario figures with the geometry layer off and on (development probe).
use sim_core::scenario;
use sim_core::scenario_run::run_scenario;
use sim_core::sim::SimConfig;

fn main() {
    let only: Vec<String> = std::env::args().skip(1).collect();
    let factor: Option<f64> = std::env::var("CEF").ok().and_then(|v| v.parse().ok());
    let phys = std::env::var("PHYS").is_ok();
    for name in scenario::names() {
        if !only.is_empty() && !only.iter().any(|o| name.contains(o.as_str())) {
            continue;
        }
        for on in [false, true] {
            if !on && !phys {
                continue;
            }
            let mut cfg = SimConfig::default();
            cfg.geometry.enabled = on;
            if let Some(f) = factor {
                cfg.geometry.curved_eps_factor = f;
            }
            let s = run_scenario(name, cfg, true).unwrap();
            println!(
                "{name:30} geom={on:5} c_mean {:.4} n_comp {:.2} strain {:.3} sing {:2} first {:?} curvedmax {:3} cones {:3} jump {:.2}mm ev {:5} med {:.3} p99 {:.3} flips {} rec {}",
                s.c_mean_pct,
                s.n_comp_pct,
                s.max_strain,
                s.singular_final,
                s.first_singular_frame,
                s.curved_regions_max,
                s.cones_max,
                s.jump_max_m * 1e3,
                s.geometry_events,
                s.step_ms_quantile(0.5),
                s.step_ms_quantile(0.99),
                s.flips,
                s.recoveries
            );
        }
    }
}
