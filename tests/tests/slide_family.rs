//! The friction of a family of seeded random slides (issue 52 item 3; thesis §4.4, T 1944–1949:
//! "a general translation of the spectrum towards higher frequencies when the size decreases").
//!
//! Each slide, from its seed: one edge held (back, front, left or right), lifted from 0 to 0.6
//! (a flat slide when 0), slid 0.2–0.9 over 0.8–2.5 s, sometimes pushed back part of the way.
//! The same 20 slides are played on A4, A5 and A6 sheets; each is rendered friction only (no
//! crumple units, air or crackle: the "crumple mix off") from its first sliding frame,
//! and its spectral centroid measured. The median centroid must rise as the sheet shrinks.
//!
//! Not in the family, and not holding: two hands pushing the back and front edges together. An
//! A4 sheet pushed so buckles into a plateau with a fold near each held edge (dihedrals above
//! a_max = 0.5 rad on its 33 mm mesh edges), so the free region that borders the contact is a
//! 4 × 3 cm patch and rubs brighter than the A5's whole arch (docs/decisions.md, "Sound realism").

mod render_common;

use rand::{RngExt, SeedableRng};
use render_common::{anechoic, median, play_script, printer_db, render, renderer};
use sim_core::SheetSize;
use sim_core::script::Script;
use sim_core::sound_input::SoundFrame;

const RATE: f64 = 48_000.0;
const FRAME_RATE: f64 = sim_core::sim::DEFAULT_FRAME_RATE_HZ;
const SLIDES: u64 = 20;

/// The script of slide `seed` (its size is set by the caller).
fn slide(seed: u64) -> String {
    let mut rng = rand_pcg::Pcg32::seed_from_u64(0x511d_e000 ^ seed);
    let slot = ["back", "front", "left", "right"][rng.random_range(0..4)];
    let lift: f64 = if rng.random_bool(0.3) {
        0.0
    } else {
        rng.random_range(0.05..0.6)
    };
    let t0: f64 = rng.random_range(0.6..1.0);
    let t1 = t0 + rng.random_range(0.8..2.5);
    let amount: f64 = rng.random_range(0.2..0.9);
    let back: f64 = if rng.random_bool(0.3) {
        amount * rng.random_range(0.3..0.8)
    } else {
        amount
    };
    let end = t1 + 0.5;
    format!(
        "version = 1\nduration_s = {:.3}\n[set]\nseed = {}\n\
         [[grab]]\nslot = \"{slot}\"\non_s = 0.0\n\
         [[lane]]\nid = \"lift\"\ninterp = \"smooth\"\npoints = [[0.0, 0.0], [0.5, {lift:.3}]]\n\
         [[lane]]\nid = \"slide\"\ninterp = \"smooth\"\n\
         points = [[{t0:.3}, 0.0], [{t1:.3}, {amount:.3}], [{end:.3}, {back:.3}]]\n",
        end + 0.3,
        seed + 1
    )
}

/// Friction only, left channel, from the first frame with a sliding source.
fn friction_render(frames: &[SoundFrame]) -> Vec<f32> {
    friction_render_keep(frames, |_| true)
}

fn friction_render_keep(
    frames: &[SoundFrame],
    keep: impl Fn(&sim_core::sound_input::FrictionSource) -> bool,
) -> Vec<f32> {
    let mut r = renderer(RATE, printer_db(RATE), 5, anechoic());
    let per_frame = (RATE / FRAME_RATE) as usize;
    let first = frames
        .iter()
        .position(|f| !f.friction().is_empty())
        .unwrap_or(frames.len());
    let mut left = Vec::new();
    for (i, f) in frames.iter().enumerate() {
        let mut g = SoundFrame::default();
        g.frame = f.frame;
        g.time_s = f.time_s;
        for s in f.friction().iter().filter(|s| keep(s)) {
            g.push_friction(*s);
        }
        r.set_frame(&g);
        let (l, _) = render(&mut r, per_frame, per_frame);
        if i >= first {
            left.extend_from_slice(&l);
        }
    }
    left
}

fn centroid_hz(x: &[f32]) -> Option<f64> {
    let n = 4096;
    if x.len() < 4 * n || render_common::rms(x) < 1e-6 {
        return None;
    }
    let psd = sounddb::analysis::welch_psd(x, RATE, n);
    Some(sounddb::analysis::centroid_hz(&psd, RATE / n as f64))
}

#[test]
fn the_median_friction_centroid_rises_as_the_sheet_shrinks() {
    let mut medians = Vec::new();
    for size in [SheetSize::A4, SheetSize::A5, SheetSize::A6] {
        let mut cs = Vec::new();
        for seed in 0..SLIDES {
            let script = Script::parse(&slide(seed)).unwrap();
            let frames = play_script(&script, Some(size));
            let constrained = frames
                .iter()
                .flat_map(|f| f.friction())
                .filter(|s| s.resonator.is_constrained())
                .count();
            let all = frames.iter().map(|f| f.friction().len()).sum::<usize>();
            let c = centroid_hz(&friction_render(&frames));
            eprintln!(
                "{size:?} slide {seed}: centroid {}, {constrained}/{all} constrained sources",
                c.map_or("silent".into(), |c| format!("{c:.0} Hz"))
            );
            cs.extend(c);
        }
        assert!(
            cs.len() as u64 >= SLIDES * 3 / 4,
            "{size:?}: only {} of {SLIDES} slides rub",
            cs.len()
        );
        let m = median(cs);
        eprintln!("{size:?}: median centroid {m:.0} Hz");
        medians.push(m);
    }
    assert!(
        medians[0] < medians[1] && medians[1] < medians[2],
        "median friction centroids A4, A5, A6: {medians:?}"
    );
}
