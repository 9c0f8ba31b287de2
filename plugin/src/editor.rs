//! # The editor window
//!
//! An egui window (nice-plug-egui) showing every parameter, grouped like the parameter list,
//! and a status line from the engine's meters. Parameter widgets go through the host's parameter
//! API (`ParamSetter`), so moving them records automation. egui's default fonts are enabled in
//! the workspace (`default_fonts`), so text renders on every host.

use std::sync::Arc;
use std::sync::atomic::Ordering;

use nice_plug::context::gui::{GuiContext, ParamSetter};
use nice_plug::editor::dpi::LogicalSize;
use nice_plug::prelude::Param;
use nice_plug_egui::widgets::ParamSlider;
use nice_plug_egui::{
    EguiEditor, EguiEditorState, EguiNiceSettings, NiceEguiApp, RepaintNotifier, create_egui_editor,
};
use sim_core::GestureParam;

use crate::engine::{Meters, ViewShared};
use crate::params::PapierParams;

/// Initial window size, logical pixels.
pub const DEFAULT_SIZE: (f32, f32) = (760.0, 560.0);

/// The editor's initial state.
pub fn default_state() -> Arc<EguiEditorState> {
    EguiEditorState::from_size(LogicalSize::new(DEFAULT_SIZE.0, DEFAULT_SIZE.1), 1.0)
}

/// Builds the editor.
pub fn create(
    params: Arc<PapierParams>,
    meters: Arc<Meters>,
    view: Arc<ViewShared>,
    state: Arc<EguiEditorState>,
) -> Option<EguiEditor<PapierEditor>> {
    create_egui_editor(
        state,
        RepaintNotifier::new(),
        EguiNiceSettings::new().with_tile("Papier"),
        PapierEditor {
            params,
            meters,
            view,
            gui: None,
        },
    )
}

/// The editor app.
pub struct PapierEditor {
    params: Arc<PapierParams>,
    meters: Arc<Meters>,
    view: Arc<ViewShared>,
    gui: Option<GuiContext>,
}

fn row(ui: &mut egui::Ui, param: &impl Param, setter: &ParamSetter) {
    ui.label(param.name());
    ui.add(ParamSlider::for_param(param, setter).with_width(150.0));
    ui.end_row();
}

impl PapierEditor {
    fn group(ui: &mut egui::Ui, title: &str, id: &str, body: impl FnOnce(&mut egui::Ui)) {
        ui.group(|ui| {
            ui.strong(title);
            egui::Grid::new(id)
                .num_columns(2)
                .spacing([10.0, 4.0])
                .show(ui, body);
        });
    }
}

impl NiceEguiApp for PapierEditor {
    fn build(
        &mut self,
        _egui_ctx: egui::Context,
        nice_gui_ctx: GuiContext,
        _frame: &mut nice_plug_egui::Frame,
    ) -> Result<(), nice_plug_egui::baseview::HandlerError> {
        self.gui = Some(nice_gui_ctx);
        self.view.open.store(true, Ordering::Relaxed);
        Ok(())
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut nice_plug_egui::Frame) {
        let Some(gui) = self.gui.as_ref() else {
            return;
        };
        let setter = gui.param_setter();
        let p = &self.params;
        ui.horizontal(|ui| {
            ui.heading("Papier");
            ui.label("a sheet of paper");
        });
        ui.separator();
        egui::ScrollArea::vertical()
            .auto_shrink([false, false])
            .show(ui, |ui| {
                ui.horizontal_top(|ui| {
                    ui.vertical(|ui| {
                        Self::group(ui, "Gestures", "gestures", |ui| {
                            for g in GestureParam::ALL {
                                row(ui, p.gestures.get(g), &setter);
                            }
                        });
                    });
                    ui.vertical(|ui| {
                        Self::group(ui, "Sheet", "sheet", |ui| {
                            row(ui, &p.sheet.size, &setter);
                            row(ui, &p.sheet.material, &setter);
                            row(ui, &p.sheet.seed, &setter);
                        });
                        Self::group(ui, "Room", "room", |ui| {
                            row(ui, &p.room.table, &setter);
                            row(ui, &p.room.table_height_cm, &setter);
                            row(ui, &p.room.wall, &setter);
                            row(ui, &p.room.wall_dist_cm, &setter);
                        });
                        Self::group(ui, "Listener", "listener", |ui| {
                            row(ui, &p.listener.listener_az_deg, &setter);
                            row(ui, &p.listener.listener_dist_m, &setter);
                        });
                        Self::group(ui, "Mix", "mix", |ui| {
                            row(ui, &p.mix.crumple_db, &setter);
                            row(ui, &p.mix.friction_db, &setter);
                            row(ui, &p.mix.tear_db, &setter);
                            row(ui, &p.gain_db, &setter);
                        });
                    });
                });
            });
        ui.separator();
        let m = &self.meters;
        ui.label(format!(
            "sim: {} · frames {} · step {:.3} ms · singular points {} · c_mean {:.2} % · peak {:.3}",
            if m.worker_running.load(Ordering::Relaxed) {
                "running"
            } else {
                "stopped"
            },
            m.frames_stepped.load(Ordering::Relaxed),
            m.last_step_ns.load(Ordering::Relaxed) as f64 * 1e-6,
            m.num_singular.load(Ordering::Relaxed),
            m.c_mean_pct(),
            m.peak(),
        ));
        ui.ctx().request_repaint();
    }

    fn editor_closed(&mut self) {
        self.view.open.store(false, Ordering::Relaxed);
        self.gui = None;
    }
}
