//! Render-path benchmarks (digest-sound §12 tests 1 and 2; digest-tearing S-6).
//!
//! `cargo bench -p papier --bench render -- --warm-up-time 1 --measurement-time 3`
//!
//! 1. **full scene** (test 2): 64 crumple voices kept playing (32 new distinct events every
//!    100 ms, the pool steals), 16 friction sources, tearing (coloured by flaps), the air and the crackle,
//!    table + wall reflectors, frames every
//!    5 ms — at 44.1 / 48 / 96 / 192 kHz with blocks of 64 / 256 / 1024. Criterion measures the time to
//!    render one second of audio (the ratio to real time is time / 1 s).
//! 2. **friction only** (test 1): one friction stream summing 16 sources with table + wall, 60 s
//!    at 44.1 kHz, static (the comb of each source is cached) and sliding (2 mm per hop: every
//!    comb recomputed) (seeds: 4 ms per 1024-sample hop, real-time factor ≈ 0.18–0.2, T 1973).
//! 3. After criterion, a **block-time table**: 10 s of the full scene per configuration, every
//!    `render()` call timed; prints the mean real-time ratio and the p99 / max block time as a
//!    fraction of the block deadline (block / fs), as a Markdown table for docs/benchmarks.md.
//!    Skipped in criterion's `--test` mode; `RENDER_TABLE=96:64` (kHz:block) runs one row only.

use std::hint::black_box;
use std::sync::Arc;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion};
use papier::render::{MixLevels, Renderer, Scene, default_db};
use sim_core::RoomConfig;
use sim_core::sound_input::{CrumpleEvent, FrictionSource, Obstacle, Resonator, SoundFrame};
use sounddb::SoundDb;

const RATES: [f64; 4] = [44_100.0, 48_000.0, 96_000.0, 192_000.0];
const BLOCKS: [usize; 3] = [64, 256, 1024];

fn resonator(lr_cm: f32, lc_cm: f32, x: f32, y: f32) -> Resonator {
    Resonator {
        lr_cm,
        lc_cm,
        centre_m: [x, y, 0.77],
        normal: [0.1 * x, 0.1 * y, 1.0],
        radius_m: ((lr_cm * 0.5 * lc_cm).max(1.0) * 1e-4 / std::f32::consts::PI).sqrt(),
    }
}

/// The full scene: keeps 64 voices busy, 16 friction sources, tearing, table + wall.
struct Scenario {
    renderer: Renderer,
    frame: SoundFrame,
    events: Vec<CrumpleEvent>,
    frame_len: usize,
    since_frame: usize,
    frames: u64,
}

impl Scenario {
    fn new(rate: f64, db: Arc<SoundDb>) -> Self {
        let mut renderer = Renderer::new(rate, db, 1);
        renderer.set_mix(MixLevels::default());
        renderer.set_scene(Scene {
            room: RoomConfig {
                table: true,
                wall: true,
                ..RoomConfig::default()
            },
            listener_az_deg: 30.0,
            listener_dist_m: 1.0,
        });
        let sizes = [2.5f32, 5.0, 10.0, 15.0, 20.0, 30.0];
        let mut frame = SoundFrame::default();
        for k in 0..16 {
            frame.push_friction(FrictionSource {
                slip_speed_m_s: 0.05 + 0.01 * k as f32,
                obstacle: Obstacle::Table,
                resonator: resonator(
                    sizes[k % 6],
                    2.0 * sizes[(k + 3) % 6],
                    -0.1 + 0.013 * k as f32,
                    0.02 * (k % 4) as f32,
                ),
            });
        }
        frame.tear.speed_m_s = 0.08;
        frame.tear.tip_m = [0.05, 0.0, 0.76];
        // Flaps at the tip: the tear is coloured by a full kernel (the worst case).
        frame.tear.resonator = resonator(10.0, 20.0, 0.05, 0.0);
        // The air a moving sheet pushes and the crackle of its bends, both playing.
        frame.air.strength_m3_s2 = 0.3;
        frame.air.centre_m = [0.0, 0.0, 0.85];
        frame.air.normal = [0.0, -0.5, 0.8];
        frame.crackle.rate_m_rad_s = 10.0;
        frame.crackle.centre_m = [0.02, 0.0, 0.78];
        let events = (0..64)
            .map(|k| CrumpleEvent {
                amplitude: 0.3 + 0.01 * k as f32,
                resonator: resonator(
                    sizes[k % 6],
                    if k % 5 == 0 {
                        0.0
                    } else {
                        2.0 * sizes[(k / 6) % 6]
                    },
                    -0.15 + 0.005 * k as f32,
                    0.1 * ((k % 3) as f32 - 1.0),
                ),
            })
            .collect();
        let mut s = Self {
            renderer,
            frame,
            events,
            frame_len: (rate * 0.005).round() as usize,
            since_frame: 0,
            frames: 0,
        };
        s.renderer.set_frame(&s.frame);
        for e in &s.events {
            s.renderer.trigger(e);
        }
        s
    }

    /// One host block: a frame every 5 ms (16 new events every 100 ms), then render.
    fn block(&mut self, l: &mut [f32], r: &mut [f32]) {
        while self.since_frame >= self.frame_len {
            self.since_frame -= self.frame_len;
            self.frames += 1;
            self.frame.frame = self.frames;
            self.renderer.set_frame(&self.frame);
            if self.frames.is_multiple_of(20) {
                let start = (self.frames / 20 * 32) as usize % 64;
                for e in self.events.iter().cycle().skip(start).take(32) {
                    self.renderer.trigger(e);
                }
            }
        }
        self.renderer.render(l, r);
        self.since_frame += l.len();
    }
}

fn full_scene(c: &mut Criterion) {
    let mut group = c.benchmark_group("full_scene_1s");
    for rate in RATES {
        let db = default_db(rate);
        for block in BLOCKS {
            let mut s = Scenario::new(rate, db.clone());
            let mut l = vec![0.0f32; block];
            let mut r = vec![0.0f32; block];
            let blocks_per_s = (rate as usize).div_ceil(block);
            group.bench_with_input(
                BenchmarkId::new(format!("{}k", rate / 1000.0), block),
                &block,
                |b, _| {
                    b.iter(|| {
                        for _ in 0..blocks_per_s {
                            s.block(&mut l, &mut r);
                        }
                        black_box(l[0])
                    })
                },
            );
        }
    }
    group.finish();
}

fn friction_only(c: &mut Criterion) {
    let rate = 44_100.0;
    let db = default_db(rate);
    let mut renderer = Renderer::new(rate, db, 1);
    renderer.set_scene(Scene {
        room: RoomConfig {
            table: true,
            wall: true,
            ..RoomConfig::default()
        },
        ..Scene::default()
    });
    let mut frame = SoundFrame::default();
    let sizes = [2.5f32, 5.0, 10.0, 15.0, 20.0, 30.0];
    for k in 0..16 {
        frame.push_friction(FrictionSource {
            slip_speed_m_s: 0.1,
            obstacle: Obstacle::Table,
            resonator: resonator(sizes[k % 6], 2.0 * sizes[(k + 2) % 6], 0.01 * k as f32, 0.0),
        });
    }
    renderer.set_frame(&frame);
    let mut l = vec![0.0f32; 1024];
    let mut r = vec![0.0f32; 1024];
    let mut group = c.benchmark_group("friction_16_sources");
    group.sample_size(10);
    group.bench_function("60s_44k1_block1024_static", |b| {
        b.iter(|| {
            for _ in 0..(60 * 44_100 / 1024) {
                renderer.set_frame(&frame);
                renderer.render(&mut l, &mut r);
            }
            black_box(l[0])
        })
    });
    // Sliding sources: every frame moves them by 2 mm, so the geometry cache (1 mm) never hits
    // and every hop recomputes 16 × 2 combs.
    let mut moving = frame;
    let mut k = 0u64;
    group.bench_function("60s_44k1_block1024_moving", |b| {
        b.iter(|| {
            for _ in 0..(60 * 44_100 / 1024) {
                k += 1;
                moving.clear();
                for s in frame.friction() {
                    let mut s = *s;
                    s.resonator.centre_m[0] += 0.002 * (k % 100) as f32;
                    moving.push_friction(s);
                }
                renderer.set_frame(&moving);
                renderer.render(&mut l, &mut r);
            }
            black_box(l[0])
        })
    });
    group.finish();
}

/// CPU time consumed by this thread, ns (Linux `/proc/thread-self/schedstat`), if available.
fn thread_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

fn block_time_table() {
    println!();
    println!(
        "| rate | block | wall cost (× real time) | CPU cost (× real time) | p99 block / deadline | max block / deadline | voices (mean) |"
    );
    println!("|---|---|---|---|---|---|---|");
    // `RENDER_TABLE=96:64` measures one configuration only (kHz:block), e.g. under `perf`.
    let only = std::env::var("RENDER_TABLE").ok();
    let wanted = |rate: f64, block: usize| {
        only.as_deref()
            .is_none_or(|o| o == format!("{}:{block}", rate / 1000.0))
    };
    for rate in RATES {
        if !BLOCKS.iter().any(|&b| wanted(rate, b)) {
            continue;
        }
        let db = default_db(rate);
        for block in BLOCKS {
            if !wanted(rate, block) {
                continue;
            }
            let mut s = Scenario::new(rate, db.clone());
            let mut l = vec![0.0f32; block];
            let mut r = vec![0.0f32; block];
            // Warm up 1 s, measure 10 s.
            let n = (rate as usize).div_ceil(block);
            for _ in 0..n {
                s.block(&mut l, &mut r);
            }
            let mut times = Vec::with_capacity(10 * n);
            let mut voices = 0usize;
            let cpu0 = thread_cpu_ns();
            for _ in 0..10 * n {
                let t = Instant::now();
                s.block(&mut l, &mut r);
                times.push(t.elapsed());
                voices += s.renderer.active_voices();
            }
            let cpu = thread_cpu_ns()
                .zip(cpu0)
                .map(|(b, a)| (b - a) as f64 * 1e-9);
            let total: Duration = times.iter().sum();
            let audio_s = (10 * n * block) as f64 / rate;
            let deadline = block as f64 / rate;
            times.sort();
            let p99 = times[times.len() * 99 / 100].as_secs_f64();
            let max = times[times.len() - 1].as_secs_f64();
            println!(
                "| {} kHz | {block} | {:.4} | {} | {:.3} | {:.3} | {:.0} |",
                rate / 1000.0,
                total.as_secs_f64() / audio_s,
                cpu.map_or("n/a".to_string(), |c| format!("{:.4}", c / audio_s)),
                p99 / deadline,
                max / deadline,
                voices as f64 / times.len() as f64
            );
        }
    }
}

fn main() {
    let test_mode = std::env::args().any(|a| a == "--test" || a == "--list");
    let mut c = Criterion::default().configure_from_args();
    full_scene(&mut c);
    friction_only(&mut c);
    c.final_summary();
    if !test_mode {
        block_time_table();
    }
}
