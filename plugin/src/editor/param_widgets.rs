//! # Parameter widgets
//!
//! Small widgets bound to nice-plug parameters. Every change goes through the host's parameter
//! API as one gesture (`begin_set_parameter`, `set_parameter`, `end_set_parameter`), so hosts
//! record it as automation and undo it as one step:
//!
//! - [`slider_row`]: a labelled [`ParamSlider`] (drag, shift-drag for fine steps, double-click
//!   to reset, click the value to type one);
//! - [`choice_row`]: an enum parameter as a row of buttons;
//! - [`toggle_row`]: a bool parameter as a checkbox.

use nice_plug::context::gui::ParamSetter;
use nice_plug::prelude::{BoolParam, Enum, EnumParam, Param};
use nice_plug_egui::widgets::ParamSlider;

/// Width of the sliders, logical pixels.
pub const SLIDER_WIDTH_PX: f32 = 150.0;

/// A grid row: the parameter's name, then a slider.
pub fn slider_row(ui: &mut egui::Ui, param: &impl Param, setter: &ParamSetter) {
    ui.label(param.name());
    ui.add(ParamSlider::for_param(param, setter).with_width(SLIDER_WIDTH_PX));
    ui.end_row();
}

/// A grid row: the parameter's name, then one button per variant.
pub fn choice_row<T: Enum + PartialEq + 'static>(
    ui: &mut egui::Ui,
    param: &EnumParam<T>,
    setter: &ParamSetter,
) {
    ui.label(param.name());
    ui.horizontal_wrapped(|ui| {
        let current = param.value().to_index();
        for (i, name) in T::variants().iter().enumerate() {
            if ui.selectable_label(i == current, *name).clicked() && i != current {
                setter.begin_set_parameter(param);
                setter.set_parameter(param, T::from_index(i));
                setter.end_set_parameter(param);
            }
        }
    });
    ui.end_row();
}

/// A grid row: the parameter's name, then a checkbox.
pub fn toggle_row(ui: &mut egui::Ui, param: &BoolParam, setter: &ParamSetter) {
    ui.label(param.name());
    let mut on = param.value();
    if ui.checkbox(&mut on, "").changed() {
        setter.begin_set_parameter(param);
        setter.set_parameter(param, on);
        setter.end_set_parameter(param);
    }
    ui.end_row();
}
