//! # The meters strip
//!
//! What the engine is doing, read from [`Meters`] (relaxed atomics written by the audio thread
//! and the simulation) and from the frame on display:
//!
//! - output level: the largest peak since the last repaint, with release and a held marker
//!   ([`super::ballistics::PeakMeter`]);
//! - events per second by kind: crumple events, friction sources (summed over frames) and
//!   tearing frames, each a counter differentiated over time ([`super::ballistics::RateMeter`]);
//! - simulation step time (last and longest) against the frame budget, and the audio thread's
//!   load (time in `process()` / block duration);
//! - singular-vertex count and mean edge compression `c_mean` of the sheet;
//! - the view's own refresh rate, and whether the simulation runs, skips or drops anything.

use std::sync::atomic::Ordering;

use egui::{Color32, Rect, Sense, Stroke, StrokeKind, Ui, pos2, vec2};
use sim_core::sim::{DEFAULT_FRAME_RATE_HZ, FrameStats};

use super::ballistics::{METER_FLOOR_DB, PeakMeter, RateMeter};
use crate::engine::Meters;

/// Top of the level meter scale, dBFS.
pub const METER_TOP_DB: f32 = 6.0;

/// The meters' display state.
#[derive(Debug, Default)]
pub struct MetersPanel {
    level: PeakMeter,
    crumple: RateMeter,
    friction: RateMeter,
    tear: RateMeter,
    view_fps: RateMeter,
    last_time_s: Option<f64>,
}

/// Draws a horizontal bar filled to `fraction` (0–1), with an optional marker.
fn bar(ui: &mut Ui, width: f32, fraction: f32, fill: Color32, marker: Option<f32>) -> Rect {
    let (rect, _) = ui.allocate_exact_size(vec2(width, 10.0), Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, ui.visuals().extreme_bg_color);
    let f = if fraction.is_finite() {
        fraction.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let filled = Rect::from_min_size(rect.min, vec2(rect.width() * f, rect.height()));
    painter.rect_filled(filled, 2.0, fill);
    if let Some(m) = marker.filter(|m| m.is_finite()) {
        let x = rect.left() + rect.width() * m.clamp(0.0, 1.0);
        painter.line_segment(
            [pos2(x, rect.top()), pos2(x, rect.bottom())],
            Stroke::new(2.0, Color32::WHITE),
        );
    }
    painter.rect_stroke(
        rect,
        2.0,
        Stroke::new(1.0, ui.visuals().widgets.noninteractive.bg_stroke.color),
        StrokeKind::Inside,
    );
    rect
}

/// Position of a level on the meter scale (0–1).
pub fn level_fraction(db: f32) -> f32 {
    ((db - METER_FLOOR_DB) / (METER_TOP_DB - METER_FLOOR_DB)).clamp(0.0, 1.0)
}

fn level_colour(db: f32) -> Color32 {
    if db > -0.1 {
        Color32::from_rgb(230, 70, 60)
    } else if db > -12.0 {
        Color32::from_rgb(230, 200, 70)
    } else {
        Color32::from_rgb(80, 200, 120)
    }
}

fn load_colour(fraction: f32) -> Color32 {
    if fraction > 0.8 {
        Color32::from_rgb(230, 70, 60)
    } else if fraction > 0.5 {
        Color32::from_rgb(230, 200, 70)
    } else {
        Color32::from_rgb(90, 160, 230)
    }
}

impl MetersPanel {
    /// Reads the meters and draws the strip. `stats` are the statistics of the frame on
    /// display, if any; `frames_written` the view buffer's frame counter; `now_s` the GUI clock.
    pub fn show(
        &mut self,
        ui: &mut Ui,
        meters: &Meters,
        stats: Option<&FrameStats>,
        frames_written: u64,
        now_s: f64,
    ) {
        let dt = self.last_time_s.map_or(0.0, |t| (now_s - t) as f32);
        self.last_time_s = Some(now_s);
        self.level.update(meters.take_peak_hold(), dt);
        let crumple = self
            .crumple
            .update(meters.crumple_events.load(Ordering::Relaxed), now_s);
        let friction = self
            .friction
            .update(meters.friction_sources.load(Ordering::Relaxed), now_s);
        let tear = self
            .tear
            .update(meters.tear_frames.load(Ordering::Relaxed), now_s);
        let onsets = meters.tear_onsets.load(Ordering::Relaxed);
        let fps = self.view_fps.update(frames_written, now_s);

        let budget_ms = 1e3 / DEFAULT_FRAME_RATE_HZ;
        let step_ms = meters.last_step_ns.load(Ordering::Relaxed) as f64 * 1e-6;
        let max_step_ms = meters.max_step_ns.load(Ordering::Relaxed) as f64 * 1e-6;
        let load = meters.audio_load();
        let (singular, c_mean) = match stats {
            Some(s) => (s.num_singular, s.c_mean_pct),
            None => (
                meters.num_singular.load(Ordering::Relaxed),
                meters.c_mean_pct(),
            ),
        };

        egui::Grid::new("meters")
            .num_columns(6)
            .spacing([8.0, 5.0])
            .show(ui, |ui| {
                ui.label("Output");
                bar(
                    ui,
                    150.0,
                    level_fraction(self.level.level_db),
                    level_colour(self.level.level_db),
                    Some(level_fraction(self.level.hold_db)),
                );
                ui.monospace(if self.level.hold_db <= METER_FLOOR_DB {
                    "   −∞ dB".to_owned()
                } else {
                    format!("{:5.1} dB", self.level.hold_db)
                });
                ui.label("Sim step");
                bar(
                    ui,
                    120.0,
                    (step_ms / budget_ms) as f32,
                    load_colour((step_ms / budget_ms) as f32),
                    Some((max_step_ms / budget_ms) as f32),
                );
                ui.monospace(format!(
                    "{step_ms:5.2} ms (max {max_step_ms:.2}) of {budget_ms:.1} ms"
                ));
                ui.end_row();

                ui.label("Events/s");
                ui.monospace(format!(
                    "crumple {crumple:5.0}  friction {friction:6.0}  tear {tear:4.0} ({onsets} onsets)"
                ))
                .on_hover_text(
                    "crumple events, friction sources (summed over simulation frames) and \
                     tearing frames, per second",
                );
                ui.label("");
                ui.label("Audio load");
                bar(ui, 120.0, load, load_colour(load), None);
                ui.monospace(format!("{:5.1} %", 100.0 * load));
                ui.end_row();

                ui.label("Sheet");
                let playing: u32 = meters
                    .phrase_notes
                    .iter()
                    .map(|w| w.load(Ordering::Relaxed).count_ones())
                    .sum();
                let hits = meters.phrase_hits.load(Ordering::Relaxed);
                ui.monospace(format!(
                    "singular vertices {singular:3}   c_mean {c_mean:5.2} %   phrases {playing} ({hits} hits)"
                ))
                .on_hover_text("Persistent singular vertices (d-cone apexes), the mean edge compression against the flat pattern, the phrases playing now and the phrase notes struck so far");
                ui.label("");
                ui.label("Engine");
                let running = meters.worker_running.load(Ordering::Relaxed);
                let skipped = meters.frames_skipped.load(Ordering::Relaxed);
                let dropped = meters.commands_dropped.load(Ordering::Relaxed)
                    + meters.events_dropped.load(Ordering::Relaxed);
                ui.label(if running { "sim running" } else { "sim idle" });
                let mut s = format!("view {fps:3.0} fps");
                if skipped > 0 {
                    s.push_str(&format!(" · {skipped} frames skipped"));
                }
                if dropped > 0 {
                    s.push_str(&format!(" · {dropped} dropped"));
                }
                ui.monospace(s);
                ui.end_row();
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_scale_spans_floor_to_top() {
        assert_eq!(level_fraction(METER_FLOOR_DB), 0.0);
        assert_eq!(level_fraction(METER_TOP_DB), 1.0);
        assert_eq!(level_fraction(100.0), 1.0);
        let zero = level_fraction(0.0);
        assert!(zero > 0.9 && zero < 1.0);
    }

    #[test]
    fn colours_warn_as_levels_rise() {
        assert_ne!(level_colour(-30.0), level_colour(-6.0));
        assert_ne!(level_colour(-6.0), level_colour(0.5));
        assert_ne!(load_colour(0.1), load_colour(0.9));
    }
}
