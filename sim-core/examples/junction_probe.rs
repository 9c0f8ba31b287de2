//! Development probe: a gently slid A5 sheet.
use sim_core::control::{Command, GestureParam, GrabSlot, SheetSize};
use sim_core::sim::{FrameOutput, Sim, SimConfig};
fn main() {
    let cfg = SimConfig {
        size: SheetSize::A5,
        ..SimConfig::default()
    };
    let mut sim = Sim::new(cfg);
    for slot in [GrabSlot::Back, GrabSlot::Front] {
        sim.apply(Command::Grab { slot, grip: 1.0 });
    }
    sim.apply(Command::Gesture {
        param: GestureParam::Slide,
        value: 0.25,
    });
    let mut out = FrameOutput::default();
    for f in 0..150 {
        sim.step(&mut out);
        for e in &sim.geometry().events {
            if matches!(e, sim_core::geometry::ShapeEvent::SingularCreated { .. }) {
                println!("f{f} {e:?} flatc {}", sim.geometry().max_flat_compression);
            }
        }
    }
}
