//! # The editor: Papier's face
//!
//! An egui window (nice-plug-egui) in the plugin and in the standalone application:
//!
//! ```text
//! ┌ Papier ─────────────────────────────────────────────── status ┐
//! │                                            │ Gestures         │
//! │   3D view of the sheet (sheet_view):       │  XY pad  grab pad │
//! │   region colours, handles, table, wall,    │  11 gesture knobs │
//! │   listener; drag = orbit, scroll = zoom    │ Phrases (pad)     │
//! │                                            │ Sheet · Room ·    │
//! │                                            │ Listener · Mix ·  │
//! │                                            │ Sound database    │
//! ├────────────────────────────────────────────┴──────────────────┤
//! │ meters: output level, events/s, sim step, audio load, sheet    │
//! └────────────────────────────────────────────────────────────────┘
//! ```
//!
//! | part | file |
//! |---|---|
//! | the 3D view | [`sheet_view`] ([`projection`], [`shading`], [`region`], [`room_scene`], [`room_map`], [`vec3`]) |
//! | XY pad (slide × lift) | [`xy_pad`] |
//! | grab pad, Reset, Let go | [`grab_pad`] |
//! | phrase pad (takes from notes C4 up), Reload | [`phrase_pad`] |
//! | preset menus (paper, room, mix), Save | [`preset_menu`] |
//! | parameter rows | [`param_widgets`] |
//! | meters | [`meters_panel`] ([`ballistics`]) |
//! | sound database folder | [`db_picker`] |
//! | window size, saved with the project | [`window_size`] |
//! | the editor as the host sees it (size, close) | [`shell`] |
//! | control positions for GUI tests | [`layout_probe`] |
//!
//! ## What the editor may touch (real-time safety by construction)
//!
//! The editor runs on its window's thread. It is built from an [`EditorParts`], and that is all
//! it can reach of the plugin:
//!
//! - [`PapierParams`]: parameters are read with atomic loads and changed only through the host's
//!   parameter API (`ParamSetter`: begin / set / end), which queues the change for the audio
//!   thread the way host automation does; the user sound database goes through
//!   [`crate::db_loader::DbLoader`], whose locks are shared with its loader thread and the main
//!   thread, never with the audio thread (that one only pops and pushes lock-free queues);
//! - [`Meters`]: relaxed atomics, read-only except for taking the held output peak (an atomic
//!   swap);
//! - [`ViewShared`], its triple buffer: the editor's own, filled only while the window is open
//!   by whoever steps the sheet (the simulation worker; in the host's offline mode the audio
//!   thread itself, copying into preallocated storage without waiting). Its consumer end is
//!   behind a mutex that only the GUI thread and `activate()` take, never the audio thread or
//!   the simulation worker;
//! - [`ViewShared`], its queue `gui_midi`: bounded and lock-free; the audio thread drains it at
//!   the start of each block and feeds it to the engine exactly like MIDI notes (grab, release,
//!   reset).
//!
//! Nothing else of the engine is reachable from here, so the editor cannot block, lock or
//! allocate on behalf of the audio thread. The gesture controls follow the same rule: the XY pad
//! and every slider, switch and choice go through the `ParamSetter` (so the host records them as
//! automation), and the grab pad and the Reset / Let go buttons push messages into `gui_midi`
//! (the command path of MIDI notes).
//!
//! Tested in real hosts under Xvfb: `tests/tests/editor_open_close.rs` opens and closes the
//! window 100 times while audio runs (threads, file descriptors, heap and RSS, audio going on),
//! `tests/tests/editor_audio_unchanged.rs` checks that audio and sheet are bit-identical with
//! and without windows opening and closing (offline mode), `tests/tests/editor_screenshot.rs`
//! checks the window's content while a gesture is played on its controls, and
//! `tests/tests/editor_window_size.rs` the window's size.
//!
//! ## Text, size and scale
//!
//! Text renders on every host because egui's default fonts are enabled in the workspace
//! (`default_fonts`). The window is resizable (by the host, or by the corner handle); its size
//! is kept in logical pixels and saved with the project ([`window_size`]), and it is drawn at the
//! display's scale (e.g. `Xft.dpi` on X11): on a 2× display the same logical size is twice the
//! pixels, and the size reported to the host says so ([`shell`]).

pub mod ballistics;
pub mod db_picker;
pub mod grab_pad;
pub mod layout_probe;
pub mod meters_panel;
pub mod palette;
pub mod param_widgets;
pub mod phrase_pad;
pub mod preset_menu;
pub mod projection;
pub mod region;
pub mod room_map;
pub mod room_scene;
pub mod shading;
pub mod sheet_view;
pub mod shell;
pub mod vec3;
pub mod window_size;
pub mod window_threads;
pub mod xy_pad;

use std::sync::Arc;
use std::sync::atomic::Ordering;

use egui::{Color32, RichText, vec2};
use nice_plug::context::gui::{GuiContext, ParamSetter};
use nice_plug_egui::NiceEguiApp;
use nice_plug_egui::baseview::WindowSize;
use nice_plug_egui::resizable_window::ResizableWindow;
use sim_core::GestureParam;

use self::db_picker::DbPicker;
use self::grab_pad::{GrabPad, GrabTarget, zones};
use self::layout_probe::LayoutProbe;
use self::meters_panel::MetersPanel;
use self::param_widgets::{choice_row, slider_row, toggle_row};
use self::phrase_pad::PhrasePad;
use self::preset_menu::PresetMenu;
use self::sheet_view::SheetView;
use self::shell::Session;
use self::window_size::MIN_SIZE;
use self::window_threads::WindowThreads;
use self::xy_pad::XyPad;
use crate::db_loader::DbState;
use crate::engine::{Meters, ViewShared};
use crate::gesture_map::MidiInput;
use crate::params::PapierParams;
use crate::phrase::PhraseShelf;

pub use self::shell::EditorShell;

/// Width of the controls column, logical pixels.
pub const CONTROLS_WIDTH_PX: f32 = 400.0;
/// Side of the XY pad, logical pixels.
pub const XY_PAD_PX: f32 = 150.0;
/// Size of the grab pad diagram, logical pixels.
pub const GRAB_PAD_PX: [f32; 2] = [130.0, 150.0];
/// Everything of the plugin the editor may touch (see the module docs).
#[derive(Clone)]
pub struct EditorParts {
    /// Parameters and persisted fields.
    pub params: Arc<PapierParams>,
    /// Engine meters.
    pub meters: Arc<Meters>,
    /// The view buffer and the GUI → audio message queue.
    pub view: Arc<ViewShared>,
    /// The instance's window threads still running ([`window_threads`]).
    pub window_threads: Arc<WindowThreads>,
    /// The phrase bank (read; Reload builds a new one off the audio thread).
    pub phrases: Arc<PhraseShelf>,
}

/// Builds the editor.
pub fn create(
    params: Arc<PapierParams>,
    meters: Arc<Meters>,
    view: Arc<ViewShared>,
    window_threads: Arc<WindowThreads>,
    phrases: Arc<PhraseShelf>,
) -> Option<EditorShell> {
    Some(EditorShell::new(EditorParts {
        params,
        meters,
        view,
        window_threads,
        phrases,
    }))
}

/// The window's app.
pub struct PapierEditor {
    parts: EditorParts,
    session: Arc<Session>,
    sheet_view: SheetView,
    grab_pad: GrabPad,
    meters_panel: MetersPanel,
    db_picker: DbPicker,
    phrase_pad: PhrasePad,
    preset_menu: PresetMenu,
    probe: LayoutProbe,
    /// Gesture messages lost because the GUI → audio queue was full.
    messages_lost: u64,
}

impl PapierEditor {
    fn new(parts: EditorParts, session: Arc<Session>) -> Self {
        Self {
            parts,
            session,
            sheet_view: SheetView::default(),
            grab_pad: GrabPad::default(),
            meters_panel: MetersPanel::default(),
            db_picker: DbPicker::default(),
            phrase_pad: PhrasePad::default(),
            preset_menu: PresetMenu::default(),
            probe: LayoutProbe::default(),
            messages_lost: 0,
        }
    }

    fn section(ui: &mut egui::Ui, title: &str, id: &str, body: impl FnOnce(&mut egui::Ui)) {
        egui::CollapsingHeader::new(RichText::new(title).strong())
            .id_salt(id)
            .default_open(true)
            .show(ui, |ui| {
                egui::Grid::new(id)
                    .num_columns(2)
                    .spacing([10.0, 4.0])
                    .show(ui, body);
            });
    }

    fn title_bar(&mut self, ui: &mut egui::Ui, gui: &GuiContext) {
        ui.horizontal(|ui| {
            let title = ui.heading("Papier");
            self.probe.record("title", title.rect);
            ui.label("a sheet of paper to play");
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                ui.weak(format!("{:?}", gui.plugin_api()));
                let db = match self.parts.params.db.state() {
                    DbState::Embedded => "embedded sounds".to_owned(),
                    DbState::Loading(_) => "loading sounds…".to_owned(),
                    DbState::Ready { name, .. } => format!("sounds: {name}"),
                    DbState::Failed { .. } => "sound database failed".to_owned(),
                };
                ui.weak(db);
                if self.messages_lost > 0 {
                    ui.colored_label(
                        Color32::from_rgb(230, 160, 80),
                        format!(
                            "{} gesture messages lost (is the plugin processing?)",
                            self.messages_lost
                        ),
                    );
                }
            });
        });
    }

    fn gestures(
        &mut self,
        ui: &mut egui::Ui,
        setter: &ParamSetter,
        sink: &mut impl FnMut(MidiInput),
    ) {
        let p = self.parts.params.clone();
        egui::CollapsingHeader::new(RichText::new("Gestures").strong())
            .id_salt("gestures_header")
            .default_open(true)
            .show(ui, |ui| {
                ui.horizontal_top(|ui| {
                    let xy = XyPad::new(
                        &p.gestures.slide,
                        &p.gestures.lift,
                        setter,
                        vec2(XY_PAD_PX, XY_PAD_PX),
                    )
                    .show(ui)
                    .on_hover_text("Left to right: slide the held edges; bottom to top: lift them");
                    self.probe.record("xy_pad", xy.rect);
                    ui.add_space(6.0);
                    let pad = self
                        .grab_pad
                        .pad(ui, vec2(GRAB_PAD_PX[0], GRAB_PAD_PX[1]), sink);
                    self.probe.record("grab_pad", pad);
                    for (t, z) in zones(pad) {
                        let name = match t {
                            GrabTarget::Back => "grab_back",
                            GrabTarget::Front => "grab_front",
                            GrabTarget::Left => "grab_left",
                            GrabTarget::Right => "grab_right",
                            GrabTarget::Corners => "grab_corners",
                        };
                        self.probe.record(name, z);
                    }
                });
                let b = self.grab_pad.buttons(ui, sink);
                self.probe.record("hold", b.hold);
                self.probe.record("reset", b.reset);
                self.probe.record("let_go", b.let_go);
                ui.add_space(4.0);
                egui::Grid::new("gesture_params")
                    .num_columns(2)
                    .spacing([10.0, 4.0])
                    .show(ui, |ui| {
                        for g in GestureParam::ALL {
                            slider_row(ui, p.gestures.get(g), setter);
                        }
                    });
            });
    }

    fn controls(
        &mut self,
        ui: &mut egui::Ui,
        setter: &ParamSetter,
        sink: &mut impl FnMut(MidiInput),
    ) {
        let p = self.parts.params.clone();
        egui::ScrollArea::vertical()
            .auto_shrink([false, false])
            .show(ui, |ui| {
                self.gestures(ui, setter, sink);
                let (shelf, meters) = (self.parts.phrases.clone(), self.parts.meters.clone());
                egui::CollapsingHeader::new(RichText::new("Phrases").strong())
                    .id_salt("phrases_header")
                    .default_open(true)
                    .show(ui, |ui| {
                        if let Some(r) = self.phrase_pad.show(ui, &shelf, &meters, sink) {
                            self.probe.record("phrase_first", r);
                        }
                    });
                egui::CollapsingHeader::new(RichText::new("Presets").strong())
                    .id_salt("presets_header")
                    .default_open(true)
                    .show(ui, |ui| self.preset_menu.show(ui, &p, setter));
                Self::section(ui, "Sheet", "sheet", |ui| {
                    choice_row(ui, &p.sheet.size, setter);
                    choice_row(ui, &p.sheet.material, setter);
                    slider_row(ui, &p.sheet.seed, setter);
                });
                Self::section(ui, "Room", "room", |ui| {
                    toggle_row(ui, &p.room.table, setter);
                    slider_row(ui, &p.room.table_height_cm, setter);
                    toggle_row(ui, &p.room.wall, setter);
                    slider_row(ui, &p.room.wall_dist_cm, setter);
                });
                Self::section(ui, "Listener", "listener", |ui| {
                    slider_row(ui, &p.listener.listener_az_deg, setter);
                    slider_row(ui, &p.listener.listener_dist_m, setter);
                });
                Self::section(ui, "Mix", "mix", |ui| {
                    slider_row(ui, &p.mix.crumple_db, setter);
                    slider_row(ui, &p.mix.friction_db, setter);
                    slider_row(ui, &p.mix.tear_db, setter);
                    slider_row(ui, &p.gain_db, setter);
                });
                egui::CollapsingHeader::new(RichText::new("Sound database").strong())
                    .id_salt("db_header")
                    .default_open(true)
                    .show(ui, |ui| self.db_picker.show(ui, &p.db));
            });
    }
}

impl NiceEguiApp for PapierEditor {
    fn build(
        &mut self,
        egui_ctx: egui::Context,
        nice_gui_ctx: GuiContext,
        _frame: &mut nice_plug_egui::Frame,
    ) -> Result<(), nice_plug_egui::baseview::HandlerError> {
        // This runs on the window's thread: the plugin outlives it (window_threads.rs).
        self.parts.window_threads.enter();
        egui_ctx.set_visuals(egui::Visuals::dark());
        // The saved size is in logical pixels at zoom 1; keyboard zoom would break that.
        egui_ctx.options_mut(|o| o.zoom_with_keyboard = false);
        if let Ok(mut g) = self.session.gui.lock() {
            *g = Some(nice_gui_ctx);
        }
        self.probe = LayoutProbe::from_env();
        self.parts.view.open.store(true, Ordering::Relaxed);
        Ok(())
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut nice_plug_egui::Frame) {
        // The host's context is gone once the window is closing.
        let Some(gui) = self.session.gui() else {
            return;
        };
        let setter = gui.param_setter();
        if let Some(scale) = ui.ctx().native_pixels_per_point() {
            self.session.set_display_scale(scale);
        }
        let now_s = ui.input(|i| i.time);
        self.probe.begin();
        self.sheet_view.refresh(&self.parts.view);

        let view = self.parts.view.clone();
        let mut lost = 0u64;
        let mut sink = |m: MidiInput| {
            if view.gui_midi.push(m).is_err() {
                lost += 1;
            }
        };
        let p = self.parts.params.clone();
        let window = ResizableWindow::new("papier_window")
            .min_size(vec2(MIN_SIZE.0 as f32, MIN_SIZE.1 as f32));
        window.show(ui, |ui| {
            self.probe.record("window", ui.max_rect());
            egui::Panel::top("title_bar").show(ui, |ui| self.title_bar(ui, &gui));
            egui::Panel::bottom("meters").show(ui, |ui| {
                ui.add_space(4.0);
                let stats = self
                    .sheet_view
                    .frame()
                    .valid
                    .then_some(self.sheet_view.frame().stats);
                self.meters_panel.show(
                    ui,
                    &self.parts.meters,
                    stats.as_ref(),
                    self.parts.view.frames_written.load(Ordering::Relaxed),
                    now_s,
                );
                self.probe.record("meters", ui.min_rect());
                ui.add_space(2.0);
            });
            egui::Panel::right("controls")
                .exact_size(CONTROLS_WIDTH_PX)
                .show(ui, |ui| self.controls(ui, &setter, &mut sink));
            egui::CentralPanel::default().show(ui, |ui| {
                let values = p.values();
                let r = self.sheet_view.show(
                    ui,
                    values.room,
                    values.listener_az_deg,
                    values.listener_dist_m,
                );
                self.probe.record("view", r.rect);
                // The phrases playing, named at the top of the view.
                let bank = self.parts.phrases.current();
                let playing: Vec<String> = bank
                    .by_note()
                    .filter(|ph| self.parts.meters.phrase_playing(ph.note))
                    .map(|ph| format!("{} {}", crate::phrase::note_name(ph.note), ph.name))
                    .collect();
                if !playing.is_empty() {
                    ui.painter().text(
                        r.rect.center_top() + vec2(0.0, 12.0),
                        egui::Align2::CENTER_TOP,
                        format!("playing: {}", playing.join(" · ")),
                        egui::FontId::proportional(15.0),
                        Color32::from_rgb(150, 220, 150),
                    );
                }
                let overlays = self.sheet_view.overlays();
                self.probe.record("view_legend", overlays.legend);
                self.probe.record("view_map", overlays.map);
            });
        });
        self.messages_lost += lost;
        self.probe.end(ui.ctx().pixels_per_point());
        // Repaint at the display's rate (baseview paces redraws on presentation).
        ui.ctx().request_repaint();
    }

    fn resized(&mut self, new_size: WindowSize) {
        self.parts
            .params
            .editor_size
            .set_logical(new_size.logical.width, new_size.logical.height);
    }

    fn editor_closed(&mut self) {
        // nice-plug-egui 0.6 does not call this; the shell's handle does the same on close.
        self.parts.view.open.store(false, Ordering::Relaxed);
        self.session.close();
    }
}
