//! # The XY pad: two gesture parameters under one finger
//!
//! A square where the horizontal position sets one parameter and the vertical position another
//! (slide × lift in Papier's face: pushing to the right slides the held edge further, pushing
//! up lifts it). Dragging goes through the host's parameter API like any knob: `begin` when the
//! pointer goes down, `set` (normalized) while it moves, `end` when it is released, for both
//! parameters — so the host records the drag as automation and shows the values.
//!
//! Positions map linearly to normalized values inside the pad's inner area (inset by
//! [`INSET_PX`] so the handle stays visible at the limits); y grows upwards.

use egui::{
    Align2, Color32, FontId, Pos2, Rect, Response, Sense, Stroke, StrokeKind, Ui, Vec2, pos2, vec2,
};
use nice_plug::context::gui::ParamSetter;
use nice_plug::prelude::{FloatParam, Param};

/// Inset of the value area inside the pad, logical pixels.
pub const INSET_PX: f32 = 8.0;
/// Background of the pad (distinct, so the pad is easy to find on a screenshot).
pub const PAD_COLOUR: Color32 = Color32::from_rgb(28, 46, 64);

/// The value area of a pad occupying `rect`.
pub fn value_rect(rect: Rect) -> Rect {
    rect.shrink(INSET_PX.min(0.25 * rect.width().min(rect.height())))
}

/// Normalized (x, y) for a pointer position, clamped to 0–1 (y up).
pub fn normalized_at(rect: Rect, pos: Pos2) -> (f32, f32) {
    let r = value_rect(rect);
    let x = (pos.x - r.left()) / r.width().max(1e-6);
    let y = (r.bottom() - pos.y) / r.height().max(1e-6);
    let c = |v: f32| {
        if v.is_finite() {
            v.clamp(0.0, 1.0)
        } else {
            0.0
        }
    };
    (c(x), c(y))
}

/// Where normalized (x, y) is drawn.
pub fn position_of(rect: Rect, x: f32, y: f32) -> Pos2 {
    let r = value_rect(rect);
    pos2(
        r.left() + x.clamp(0.0, 1.0) * r.width(),
        r.bottom() - y.clamp(0.0, 1.0) * r.height(),
    )
}

/// An XY pad bound to two parameters.
pub struct XyPad<'a> {
    x: &'a FloatParam,
    y: &'a FloatParam,
    setter: &'a ParamSetter<'a>,
    size: Vec2,
}

impl<'a> XyPad<'a> {
    /// A pad of `size` logical pixels for parameters `x` (horizontal) and `y` (vertical).
    pub fn new(
        x: &'a FloatParam,
        y: &'a FloatParam,
        setter: &'a ParamSetter<'a>,
        size: Vec2,
    ) -> Self {
        Self { x, y, setter, size }
    }

    /// Draws the pad and handles the pointer.
    pub fn show(self, ui: &mut Ui) -> Response {
        let (rect, response) = ui.allocate_exact_size(self.size, Sense::click_and_drag());
        let id = response.id;
        let was_down = ui.data(|d| d.get_temp::<bool>(id).unwrap_or(false));
        let down = response.is_pointer_button_down_on();
        if down && !was_down {
            self.setter.begin_set_parameter(self.x);
            self.setter.begin_set_parameter(self.y);
        }
        if down && let Some(p) = response.interact_pointer_pos() {
            let (nx, ny) = normalized_at(rect, p);
            if (nx - self.x.unmodulated_normalized_value()).abs() > 1e-6 {
                self.setter.set_parameter_normalized(self.x, nx);
            }
            if (ny - self.y.unmodulated_normalized_value()).abs() > 1e-6 {
                self.setter.set_parameter_normalized(self.y, ny);
            }
        }
        if !down && was_down {
            self.setter.end_set_parameter(self.x);
            self.setter.end_set_parameter(self.y);
        }
        // A click shorter than a frame never shows the button down: set the values anyway.
        if !down
            && !was_down
            && response.clicked()
            && let Some(p) = response.interact_pointer_pos()
        {
            let (nx, ny) = normalized_at(rect, p);
            for (param, v) in [(self.x, nx), (self.y, ny)] {
                self.setter.begin_set_parameter(param);
                self.setter.set_parameter_normalized(param, v);
                self.setter.end_set_parameter(param);
            }
        }
        if down != was_down {
            ui.data_mut(|d| d.insert_temp(id, down));
        }
        self.paint(ui, rect, down);
        response
    }

    fn paint(&self, ui: &Ui, rect: Rect, active: bool) {
        let painter = ui.painter_at(rect.expand(1.0));
        let visuals = ui.visuals();
        painter.rect_filled(rect, 4.0, PAD_COLOUR);
        let inner = value_rect(rect);
        let grid = Stroke::new(1.0, Color32::from_rgb(44, 66, 88));
        for i in 1..4 {
            let f = i as f32 / 4.0;
            let x = inner.left() + f * inner.width();
            let y = inner.top() + f * inner.height();
            painter.line_segment([pos2(x, inner.top()), pos2(x, inner.bottom())], grid);
            painter.line_segment([pos2(inner.left(), y), pos2(inner.right(), y)], grid);
        }
        painter.rect_stroke(
            rect,
            4.0,
            Stroke::new(1.0, visuals.widgets.inactive.bg_stroke.color),
            StrokeKind::Inside,
        );
        let nx = self.x.modulated_normalized_value();
        let ny = self.y.modulated_normalized_value();
        let p = position_of(rect, nx, ny);
        let cross = Stroke::new(1.0, Color32::from_rgb(120, 170, 220));
        painter.line_segment([pos2(p.x, inner.top()), pos2(p.x, inner.bottom())], cross);
        painter.line_segment([pos2(inner.left(), p.y), pos2(inner.right(), p.y)], cross);
        painter.circle_filled(
            p,
            if active { 8.0 } else { 6.5 },
            Color32::from_rgb(250, 200, 90),
        );
        let font = FontId::proportional(11.0);
        let text = Color32::from_gray(200);
        let axis = Stroke::new(1.5, Color32::from_gray(170));
        let origin = inner.left_bottom() + vec2(3.0, -3.0);
        painter.arrow(origin, vec2(18.0, 0.0), axis);
        painter.arrow(origin, vec2(0.0, -18.0), axis);
        painter.text(
            pos2(inner.right(), inner.bottom()),
            Align2::RIGHT_BOTTOM,
            format!("{} {}", self.x.name(), self.x),
            font.clone(),
            text,
        );
        painter.text(
            pos2(inner.left(), inner.top()),
            Align2::LEFT_TOP,
            format!("{} {}", self.y.name(), self.y),
            font,
            text,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect() -> Rect {
        Rect::from_min_size(pos2(20.0, 40.0), vec2(116.0, 116.0))
    }

    #[test]
    fn corners_map_to_the_value_range_with_y_up() {
        let r = rect();
        let inner = value_rect(r);
        assert_eq!(normalized_at(r, inner.left_bottom()), (0.0, 0.0));
        assert_eq!(normalized_at(r, inner.right_top()), (1.0, 1.0));
        let (x, y) = normalized_at(r, inner.center());
        assert!((x - 0.5).abs() < 1e-6 && (y - 0.5).abs() < 1e-6);
    }

    #[test]
    fn outside_the_pad_clamps() {
        let r = rect();
        assert_eq!(normalized_at(r, pos2(-1000.0, 1000.0)), (0.0, 0.0));
        assert_eq!(normalized_at(r, pos2(1000.0, -1000.0)), (1.0, 1.0));
        assert_eq!(normalized_at(r, pos2(f32::NAN, f32::NAN)), (0.0, 0.0));
    }

    #[test]
    fn position_and_value_round_trip() {
        let r = rect();
        for (x, y) in [(0.0, 0.0), (0.25, 0.8), (1.0, 0.5)] {
            let (bx, by) = normalized_at(r, position_of(r, x, y));
            assert!((bx - x).abs() < 1e-5 && (by - y).abs() < 1e-5, "{x} {y}");
        }
    }
}
