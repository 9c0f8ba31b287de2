//! Helpers shared by the `render_*` test files (included with `mod render_common;`).

#![allow(dead_code)]

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use papier::render::{MixLevels, Renderer, Scene};
use sim_core::script::Script;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{DEFAULT_FRAME_RATE_HZ, FrameOutput, SimConfig};
use sim_core::sound_analysis::AnalysisStats;
use sim_core::sound_input::{CrumpleEvent, FrictionSource, Obstacle, Resonator, SoundFrame};
use sim_core::{Command, RoomConfig, SheetSize};
use sounddb::SoundDb;

/// The embedded printer database prepared for a rate, cached per test binary.
pub fn printer_db(rate: f64) -> Arc<SoundDb> {
    static CACHE: OnceLock<Mutex<HashMap<u64, Arc<SoundDb>>>> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    let mut map = cache.lock().unwrap();
    map.entry(rate.to_bits())
        .or_insert_with(|| papier::render::default_db(rate))
        .clone()
}

/// Height of the default table top, m.
pub const TABLE_Z: f32 = 0.75;

/// A resonator lying on the table, centred near the sheet's home centre.
pub fn resonator(lr_cm: f32, lc_cm: f32) -> Resonator {
    Resonator {
        lr_cm,
        lc_cm,
        centre_m: [0.0, 0.0, TABLE_Z + 0.02],
        normal: [0.0, 0.0, 1.0],
        radius_m: ((lr_cm * 0.5 * lc_cm).max(1.0) * 1e-4 / std::f32::consts::PI).sqrt(),
    }
}

pub fn crumple(amplitude: f32, res: Resonator) -> CrumpleEvent {
    CrumpleEvent {
        amplitude,
        resonator: res,
    }
}

pub fn friction(speed: f32, res: Resonator) -> FrictionSource {
    FrictionSource {
        slip_speed_m_s: speed,
        obstacle: Obstacle::Table,
        resonator: res,
    }
}

/// A frame with the given sources and tear speed.
pub fn frame(index: u64, friction: &[FrictionSource], tear_speed: f32) -> SoundFrame {
    let mut f = SoundFrame::default();
    f.frame = index;
    f.time_s = index as f64 * 0.005;
    for s in friction {
        f.push_friction(*s);
    }
    f.tear.speed_m_s = tear_speed;
    f.tear.tip_m = [0.05, 0.0, TABLE_Z + 0.01];
    f
}

/// Scene without any reflector.
pub fn anechoic() -> Scene {
    Scene {
        room: RoomConfig {
            table: false,
            wall: false,
            ..RoomConfig::default()
        },
        ..Scene::default()
    }
}

/// Scene with table and wall.
pub fn table_and_wall() -> Scene {
    Scene {
        room: RoomConfig {
            table: true,
            wall: true,
            ..RoomConfig::default()
        },
        listener_az_deg: 30.0,
        listener_dist_m: 1.0,
    }
}

/// A renderer with unity mix.
pub fn renderer(rate: f64, db: Arc<SoundDb>, seed: u64, scene: Scene) -> Renderer {
    let mut r = Renderer::new(rate, db, seed);
    r.set_mix(MixLevels::default());
    r.set_scene(scene);
    r
}

/// Renders `n` samples in blocks of `block`.
pub fn render(r: &mut Renderer, n: usize, block: usize) -> (Vec<f32>, Vec<f32>) {
    let mut l = vec![0.0f32; n];
    let mut rr = vec![0.0f32; n];
    let mut pos = 0;
    while pos < n {
        let m = block.min(n - pos);
        r.render(&mut l[pos..pos + m], &mut rr[pos..pos + m]);
        pos += m;
    }
    (l, rr)
}

/// True for a subnormal f32.
pub fn is_denormal(x: f32) -> bool {
    x != 0.0 && x.abs() < f32::MIN_POSITIVE
}

pub fn rms(x: &[f32]) -> f64 {
    (x.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>() / x.len().max(1) as f64).sqrt()
}

/// FNV-1a over the bit patterns.
pub fn hash(l: &[f32], r: &[f32]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for v in l.iter().chain(r) {
        for b in v.to_bits().to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

/// A small deterministic generator for test scripts.
pub struct Lcg(pub u64);

impl Lcg {
    pub fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// One step of a scripted scene: a frame plus the crumple events to trigger with it.
pub struct Step {
    pub frame: SoundFrame,
    pub events: Vec<CrumpleEvent>,
}

/// Drives a renderer through steps of `frame_len` samples each, splitting every frame's samples
/// with `split` (sizes cycled). Returns the output.
pub fn drive(
    r: &mut Renderer,
    steps: &[Step],
    frame_len: usize,
    split: &[usize],
) -> (Vec<f32>, Vec<f32>) {
    let n = steps.len() * frame_len;
    let mut l = vec![0.0f32; n];
    let mut rr = vec![0.0f32; n];
    let mut k = 0;
    for (i, s) in steps.iter().enumerate() {
        r.set_frame(&s.frame);
        for e in &s.events {
            r.trigger(e);
        }
        let mut pos = i * frame_len;
        let end = pos + frame_len;
        while pos < end {
            let m = split[k % split.len()].max(1).min(end - pos);
            k += 1;
            r.render(&mut l[pos..pos + m], &mut rr[pos..pos + m]);
            pos += m;
        }
    }
    (l, rr)
}

/// A busy scene: crumple events of many sizes, 16 friction sources, a tear, for `frames` frames.
pub fn busy_steps(frames: usize, seed: u64) -> Vec<Step> {
    let mut g = Lcg(seed);
    let sizes = [2.5f32, 5.0, 10.0, 15.0, 20.0, 30.0];
    (0..frames)
        .map(|i| {
            let mut fr = Vec::new();
            for k in 0..16 {
                let mut res = resonator(sizes[k % 6], 2.0 * sizes[(k + 2) % 6]);
                res.centre_m[0] = -0.1 + 0.013 * k as f32;
                res.centre_m[1] = 0.05 * (k % 3) as f32;
                fr.push(friction(0.02 + 0.1 * g.next(), res));
            }
            let mut events = Vec::new();
            if i % 3 == 0 {
                for _ in 0..4 {
                    let lc = if g.next() < 0.2 {
                        0.0
                    } else {
                        2.0 * sizes[(g.next() * 6.0) as usize % 6]
                    };
                    let mut res = resonator(sizes[(g.next() * 6.0) as usize % 6], lc);
                    res.centre_m[0] = 0.2 * g.next() - 0.1;
                    res.normal = [g.next() - 0.5, g.next() - 0.5, 1.0];
                    events.push(crumple(0.2 + g.next(), res));
                }
            }
            // The tear starts every 40 frames (an onset) and its flaps change every 5.
            let mut frame = frame(i as u64, &fr, if i % 40 < 20 { 0.08 } else { 0.0 });
            frame.tear.onset = i % 40 == 0;
            if i % 40 < 20 {
                frame.tear.resonator = resonator(sizes[(i / 5) % 6], sizes[(i / 10) % 6]);
            }
            // The air and the crackle come and go (render/air.rs, render/crackle.rs).
            if i % 50 < 30 {
                frame.air.strength_m3_s2 = 0.05 + 0.5 * g.next();
                frame.air.centre_m = [0.1 * g.next(), 0.0, 0.8];
                frame.air.normal = [0.0, g.next() - 0.5, 1.0];
            }
            if i % 30 < 20 {
                frame.crackle.rate_m_rad_s = 20.0 * g.next();
                frame.crackle.centre_m = [0.0, 0.1 * g.next(), 0.78];
            }
            Step { frame, events }
        })
        .collect()
}

/// Asserts bit-identical stereo outputs, reporting the first difference (not the vectors).
pub fn assert_same(a: &(Vec<f32>, Vec<f32>), b: &(Vec<f32>, Vec<f32>)) {
    assert_eq!(a.0.len(), b.0.len(), "lengths differ");
    for (ch, (x, y)) in [(&a.0, &b.0), (&a.1, &b.1)].into_iter().enumerate() {
        if let Some(i) = (0..x.len()).find(|&i| x[i].to_bits() != y[i].to_bits()) {
            panic!(
                "channel {ch} differs first at sample {i}: {} vs {} ({} samples)",
                x[i],
                y[i],
                x.len()
            );
        }
    }
}

/// Plays a script on a fresh sheet (optionally resized first) at the default frame rate and
/// records every frame's sound input.
pub fn play_script(script: &Script, size: Option<SheetSize>) -> Vec<SoundFrame> {
    play_script_with_stats(script, size).0
}

/// [`play_script`], with each frame's sound-analysis counts.
pub fn play_script_with_stats(
    script: &Script,
    size: Option<SheetSize>,
) -> (Vec<SoundFrame>, Vec<AnalysisStats>) {
    let base = SimConfig::default();
    let mut runner = ScriptRunner::new(script, DEFAULT_FRAME_RATE_HZ, base.room).unwrap();
    let mut sim = runner.start(base);
    if let Some(s) = size {
        sim.apply(Command::Size(s));
    }
    let mut out = FrameOutput::default();
    let (mut frames, mut stats) = (Vec::new(), Vec::new());
    while runner.drive(&mut sim, &mut out) {
        frames.push(out.sound);
        stats.push(*sim.analysis_stats());
    }
    (frames, stats)
}

/// The median of `v` (the mean of the two middle values for an even count); NaN-safe ordering.
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    0.5 * (v[(n - 1) / 2] + v[n / 2])
}

/// Renders script text as `papier-render --script` does (the engine in lockstep, the embedded
/// database, the default mix, 48 kHz) through a temporary file; both channels averaged.
/// `tag` names the test's temporary folder.
pub fn render_script_mono(tag: &str, name: &str, script: &str) -> Vec<f32> {
    use papier::offline::cli::{InputSpec, RenderOptions};
    let dir = std::env::temp_dir().join(format!("papier_{tag}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let toml = dir.join(format!("{name}.toml"));
    let wav = dir.join(format!("{name}.wav"));
    std::fs::write(&toml, script).unwrap();
    let opts = RenderOptions {
        quiet: true,
        ..RenderOptions::new(vec![InputSpec::Script(toml.clone())], wav.clone())
    };
    papier::offline::render(&opts).expect("the script renders");
    let mut reader = hound::WavReader::open(&wav).unwrap();
    let x: Vec<f32> = reader.samples::<f32>().map(Result::unwrap).collect();
    let _ = std::fs::remove_file(&toml);
    let _ = std::fs::remove_file(&wav);
    x.chunks_exact(2).map(|c| 0.5 * (c[0] + c[1])).collect()
}
