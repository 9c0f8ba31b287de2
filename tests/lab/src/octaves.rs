//! The octave profile of rendered takes (issue 52 item 4): each WAV's power per octave
//! (125 Hz … 16 kHz) relative to its loudest octave and its spectral centroid, printed as a
//! Markdown table and drawn as one line per take over the band real crumple recordings occupy
//! (125–500 Hz octaves 8–15 dB under the loudest). The measure is `sounddb::analysis`'s, the one
//! `tests/tests/crumple_body.rs` asserts.
//!
//! `cargo run --release -p papier-lab -- octaves OUT.png LABEL=FILE.wav ...`

use std::path::Path;

use anyhow::Context;
use sounddb::analysis;

use crate::args::bad;

pub const USAGE: &str = "OUT.png LABEL=FILE.wav ...";

/// Welch segment length, samples.
const SEGMENT: usize = 8192;

pub fn run(args: &[String]) -> anyhow::Result<()> {
    let Some((png, takes)) = args.split_first() else {
        return Err(bad("no output PNG"));
    };
    if takes.is_empty() {
        return Err(bad("no LABEL=FILE.wav"));
    }
    let mut rows = Vec::new();
    for t in takes {
        let (label, file) = t
            .split_once('=')
            .ok_or_else(|| bad(format!("{t:?} is not LABEL=FILE.wav")))?;
        let (profile, centroid) = measure(Path::new(file))?;
        rows.push((label.to_string(), profile, centroid));
    }
    println!(
        "| take | centroid Hz | {} |",
        analysis::OCTAVE_CENTRES_HZ
            .map(|c| format!("{c:.0}"))
            .join(" | ")
    );
    println!("|---|---|{}", "---|".repeat(8));
    for (label, p, c) in &rows {
        println!(
            "| {label} | {c:.0} | {} |",
            p.map(|v| format!("{v:.1}")).join(" | ")
        );
    }
    plot(Path::new(png), &rows)
}

/// The octave profile (dB re the loudest) and centroid of a WAV's channels averaged.
fn measure(file: &Path) -> anyhow::Result<([f64; 8], f64)> {
    let mut r =
        hound::WavReader::open(file).with_context(|| format!("cannot read {}", file.display()))?;
    let spec = r.spec();
    let ch = usize::from(spec.channels.max(1));
    let x: Vec<f32> = match spec.sample_format {
        hound::SampleFormat::Float => r.samples::<f32>().collect::<Result<_, _>>()?,
        hound::SampleFormat::Int => {
            let scale = 1.0 / (1u64 << (spec.bits_per_sample - 1)) as f32;
            r.samples::<i32>()
                .map(|s| s.map(|v| v as f32 * scale))
                .collect::<Result<_, _>>()?
        }
    };
    let mono: Vec<f32> = x
        .chunks_exact(ch)
        .map(|c| c.iter().sum::<f32>() / ch as f32)
        .collect();
    if mono.len() < SEGMENT {
        return Err(bad(format!(
            "{} is shorter than {SEGMENT} samples",
            file.display()
        )));
    }
    let rate = f64::from(spec.sample_rate);
    let psd = analysis::welch_psd(&mono, rate, SEGMENT);
    let df = rate / SEGMENT as f64;
    Ok((
        analysis::octave_profile_db(&psd, df),
        analysis::centroid_hz(&psd, df),
    ))
}

fn plot(png: &Path, rows: &[(String, [f64; 8], f64)]) -> anyhow::Result<()> {
    use plotters::prelude::*;
    let root = BitMapBackend::new(png, (900, 520)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Octave profile re the loudest octave (grey: real crumples' 125–500 Hz band)",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(-0.5f64..7.5f64, -30.0f64..2.0f64)?;
    chart
        .configure_mesh()
        .x_labels(8)
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && (0.0..8.0).contains(&i) {
                let c = analysis::OCTAVE_CENTRES_HZ[i as usize];
                if c >= 1e3 {
                    format!("{:.0}k", c / 1e3)
                } else {
                    format!("{c:.0}")
                }
            } else {
                String::new()
            }
        })
        .x_desc("octave centre, Hz")
        .y_desc("dB re loudest octave")
        .draw()?;
    chart.draw_series(std::iter::once(Rectangle::new(
        [(-0.3, -15.0), (2.3, -8.0)],
        RGBColor(210, 210, 210).filled(),
    )))?;
    let colours = [
        BLUE,
        RED,
        GREEN,
        MAGENTA,
        CYAN,
        BLACK,
        RGBColor(200, 120, 0),
    ];
    for (k, (label, p, c)) in rows.iter().enumerate() {
        let colour = colours[k % colours.len()];
        chart
            .draw_series(LineSeries::new(
                p.iter().enumerate().map(|(i, v)| (i as f64, v.max(-30.0))),
                colour.stroke_width(2),
            ))?
            .label(format!("{label} ({c:.0} Hz)"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], colour.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
