//! How loud and how often do the layers of a crumpling sheet rub on each other? Per 0.25 s of a
//! scene: friction sources on the obstacles and on the sheet's own layers, the layers' mean and
//! largest slip speed and mean resonator radius.
//!
//! `cargo run --release -p papier-lab -- layer-probe [NAME[@SEED]|FILE.toml ...]`.

use sim_core::sim::SimConfig;
use sim_core::sound_input::Obstacle;

use crate::play::{self, Play};

pub const USAGE: &str = "[NAME[@SEED]|FILE.toml ...]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    for name in play::scenes_or_all(args) {
        let mut p = Play::scene(&name, SimConfig::default())?;
        println!("{name}");
        let (mut frames, mut table, mut layers) = (0u32, 0u32, 0u32);
        let (mut slip_sum, mut slip_max, mut radius_sum) = (0.0f64, 0.0f32, 0.0f64);
        let mut layer_frames = 0u32;
        while p.frame() {
            frames += 1;
            let mut any = false;
            for f in p.out.sound.friction() {
                if f.obstacle == Obstacle::SelfContact {
                    layers += 1;
                    any = true;
                    slip_sum += f64::from(f.slip_speed_m_s);
                    slip_max = slip_max.max(f.slip_speed_m_s);
                    radius_sum += f64::from(f.resonator.radius_m);
                } else {
                    table += 1;
                }
            }
            layer_frames += u32::from(any);
            if frames % 50 == 0 {
                let n = f64::from(layers.max(1));
                println!(
                    "  t {:5.2} s  table sources {table:4}  layer sources {layers:4} in {layer_frames:3} frames  slip mean {:6.3} max {:6.3} m/s  radius {:5.1} cm",
                    f64::from(frames) * 0.005,
                    slip_sum / n,
                    slip_max,
                    100.0 * radius_sum / n
                );
                (table, layers, layer_frames, slip_sum, slip_max, radius_sum) =
                    (0, 0, 0, 0.0, 0.0, 0.0);
            }
        }
    }
    Ok(())
}
