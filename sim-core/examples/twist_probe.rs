//! Development probe: gestures on the 10 cm sheet (twist only; slide then lift).
use sim_core::control::{Command, GestureParam, GrabSlot, SheetSize};
use sim_core::sim::{FrameOutput, Sim, SimConfig};
fn main() {
    let mode = std::env::args().nth(1).unwrap_or("twist".into());
    for seed in 1..=4u64 {
        let cfg = SimConfig {
            size: SheetSize::Sq10,
            seed,
            ..SimConfig::default()
        };
        let mut sim = Sim::new(cfg);
        for slot in [GrabSlot::Back, GrabSlot::Front] {
            sim.apply(Command::Grab { slot, grip: 0.8 });
        }
        let mut out = FrameOutput::default();
        let (mut cm, mut nc, mut n, mut cones) = (0.0, 0.0, 0.0, 0usize);
        let mut first = None;
        for f in 0..800 {
            let t = f as f32 / 200.0;
            match mode.as_str() {
                "twist" => sim.apply(Command::Gesture {
                    param: GestureParam::Twist,
                    value: (t / 2.0).min(1.0) * 0.5,
                }),
                _ => {
                    sim.apply(Command::Gesture {
                        param: GestureParam::Slide,
                        value: (t / 0.6).min(1.0) * 0.2,
                    });
                    if t > 0.8 {
                        sim.apply(Command::Gesture {
                            param: GestureParam::Lift,
                            value: ((t - 0.8) / 2.0).min(1.0),
                        });
                    }
                }
            }
            sim.step(&mut out);
            if seed == 1 {
                for e in &sim.geometry().events {
                    if matches!(e, sim_core::geometry::ShapeEvent::SingularCreated { .. })
                        && f < 200
                    {
                        println!("  f{f} {e:?} held {}", out.stats.num_held);
                    }
                }
            }
            cm += out.stats.c_mean_pct as f64;
            nc += out.stats.n_comp_pct as f64;
            n += 1.0;
            cones = cones.max(sim.geometry().cones.iter().filter(|c| !c.is_gap).count());
            if first.is_none() && out.stats.num_singular > 0 {
                first = Some((f, out.stats.num_singular, sim.geometry().singular[0].pos2));
            }
        }
        println!(
            "{mode} seed {seed}: sing {} first {:?} cones {} c_mean {:.4} n_comp {:.3}",
            out.stats.num_singular,
            first,
            cones,
            cm / n,
            nc / n
        );
    }
}
