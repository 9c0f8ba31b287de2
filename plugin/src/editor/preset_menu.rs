//! # The preset menu: paper, room and mix by name
//!
//! One menu per group ([`crate::preset`]): factory presets, then the user's from the preset
//! folder (read when the menu opens). Choosing one sets its parameters through the host's
//! parameter API, one begin/set/end per parameter — the host records and can undo it like a
//! knob turned, and the sheet is kept. **Save** writes the current values of a group as a user
//! preset file.

use egui::{Color32, Ui};
use nice_plug::prelude::{Param, ParamSetter};
use sim_core::{Material, SheetSize};

use crate::engine::ParamValues;
use crate::params::{MaterialChoice, PapierParams, SizeChoice};
use crate::preset::{self, Preset, PresetKind};

/// The menu's state.
#[derive(Debug, Default)]
pub struct PresetMenu {
    user: Vec<Preset>,
    errors: Vec<String>,
    scanned: bool,
    name: String,
    kind_to_save: usize,
    message: Option<(bool, String)>,
}

/// Sets one parameter through the host, if its value differs.
fn set<P: Param>(setter: &ParamSetter, param: &P, value: P::Plain)
where
    P::Plain: PartialEq,
{
    if param.modulated_plain_value() != value {
        setter.begin_set_parameter(param);
        setter.set_parameter(param, value);
        setter.end_set_parameter(param);
    }
}

/// Sets the parameters of `kind` to their values in `v`, through the host.
pub fn apply(params: &PapierParams, setter: &ParamSetter, kind: PresetKind, v: &ParamValues) {
    match kind {
        PresetKind::Paper => {
            let size = match v.size {
                SheetSize::A4 => SizeChoice::A4,
                SheetSize::A5 => SizeChoice::A5,
                SheetSize::A6 => SizeChoice::A6,
                SheetSize::Sq10 => SizeChoice::Sq10,
            };
            let material = match v.material {
                Material::Printer => MaterialChoice::Printer,
                Material::Tracing => MaterialChoice::Tracing,
                Material::Banknote => MaterialChoice::Banknote,
            };
            set(setter, &params.sheet.size, size);
            set(setter, &params.sheet.material, material);
        }
        PresetKind::Room => {
            set(setter, &params.room.table, v.room.table);
            set(setter, &params.room.table_height_cm, v.room.table_height_cm);
            set(setter, &params.room.wall, v.room.wall);
            set(setter, &params.room.wall_dist_cm, v.room.wall_dist_cm);
            set(setter, &params.listener.listener_az_deg, v.listener_az_deg);
            set(setter, &params.listener.listener_dist_m, v.listener_dist_m);
        }
        PresetKind::Mix => {
            set(setter, &params.mix.crumple_db, v.mix_crumple_db);
            set(setter, &params.mix.friction_db, v.mix_friction_db);
            set(setter, &params.mix.tear_db, v.mix_tear_db);
            set(setter, &params.gain_db, v.gain_db);
        }
    }
}

impl PresetMenu {
    fn rescan(&mut self) {
        let (user, errors) = preset::user_preset_dir()
            .map(|d| preset::load_folder(&d))
            .unwrap_or_default();
        self.user = user;
        self.errors = errors;
        self.scanned = true;
    }

    /// Draws the menus and the save row.
    pub fn show(&mut self, ui: &mut Ui, params: &PapierParams, setter: &ParamSetter) {
        if !self.scanned {
            self.rescan();
        }
        let factory = Preset::factory();
        let mut chosen: Option<Preset> = None;
        ui.horizontal(|ui| {
            for kind in PresetKind::ALL {
                egui::ComboBox::from_id_salt(("preset", kind.id()))
                    .selected_text(kind.id())
                    .width(110.0)
                    .show_ui(ui, |ui| {
                        for p in factory.iter().chain(&self.user).filter(|p| p.kind == kind) {
                            let label = if p.source == "factory" {
                                p.name.clone()
                            } else {
                                format!("{} (user)", p.name)
                            };
                            if ui.selectable_label(false, label).clicked() {
                                chosen = Some(p.clone());
                            }
                        }
                    });
            }
        });
        if let Some(p) = chosen {
            let mut v = params.values();
            match p.apply_to(&mut v) {
                Ok(()) => {
                    apply(params, setter, p.kind, &v);
                    self.message = Some((true, format!("{} preset \"{}\"", p.kind.id(), p.name)));
                }
                Err(e) => self.message = Some((false, e.0)),
            }
        }
        ui.horizontal(|ui| {
            ui.add(
                egui::TextEdit::singleline(&mut self.name)
                    .hint_text("preset name")
                    .desired_width(120.0),
            );
            egui::ComboBox::from_id_salt("preset_save_kind")
                .selected_text(PresetKind::ALL[self.kind_to_save].id())
                .width(60.0)
                .show_index(ui, &mut self.kind_to_save, PresetKind::ALL.len(), |i| {
                    PresetKind::ALL[i].id()
                });
            if ui.button("Save").clicked() {
                let kind = PresetKind::ALL[self.kind_to_save];
                let p = Preset::capture(&self.name, kind, &params.values());
                self.message = Some(match preset::user_preset_dir() {
                    Some(dir) => match p.save_in(&dir) {
                        Ok(path) => (true, format!("saved {}", path.display())),
                        Err(e) => (false, e.0),
                    },
                    None => (false, "no preset folder (no home directory)".into()),
                });
                self.rescan();
            }
        });
        if let Some((ok, m)) = &self.message {
            let colour = if *ok {
                ui.visuals().weak_text_color()
            } else {
                Color32::from_rgb(230, 160, 80)
            };
            ui.colored_label(colour, m);
        }
        for e in &self.errors {
            ui.colored_label(Color32::from_rgb(230, 160, 80), e);
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::{Arc, Mutex};

    use nice_plug::prelude::{GuiContextInner, ParamPtr, Params, PluginApi, PluginState};

    use super::*;

    /// A host that records what the editor asks of it.
    #[derive(Default)]
    struct Recorder {
        calls: Mutex<Vec<(&'static str, ParamPtr, f32)>>,
        state_swaps: Mutex<u32>,
    }

    impl GuiContextInner for Recorder {
        fn plugin_api(&self) -> PluginApi {
            PluginApi::Clap
        }
        unsafe fn raw_begin_set_parameter(&self, param: ParamPtr) {
            self.calls.lock().unwrap().push(("begin", param, f32::NAN));
        }
        unsafe fn raw_set_parameter_normalized(&self, param: ParamPtr, normalized: f32) {
            self.calls.lock().unwrap().push(("set", param, normalized));
        }
        unsafe fn raw_end_set_parameter(&self, param: ParamPtr) {
            self.calls.lock().unwrap().push(("end", param, f32::NAN));
        }
        fn get_state(&self) -> PluginState {
            unreachable!("a preset load never reads the state")
        }
        fn set_state(&self, _state: PluginState) {
            *self.state_swaps.lock().unwrap() += 1;
        }
        fn request_restart(&self) {}
    }

    #[test]
    fn a_preset_load_is_one_host_parameter_gesture_per_changed_parameter() {
        let params = PapierParams::default();
        let ids: Vec<(String, ParamPtr)> = params
            .param_map()
            .into_iter()
            .map(|(id, ptr, _)| (id, ptr))
            .collect();
        let id_of = |ptr: ParamPtr| ids.iter().find(|(_, p)| *p == ptr).unwrap().0.clone();
        for p in Preset::factory() {
            let host = Arc::new(Recorder::default());
            let setter = ParamSetter::new(host.as_ref());
            let mut v = params.values();
            p.apply_to(&mut v).unwrap();
            apply(&params, &setter, p.kind, &v);
            let calls = host.calls.lock().unwrap();
            assert_eq!(*host.state_swaps.lock().unwrap(), 0, "never a state swap");
            assert_eq!(calls.len() % 3, 0);
            for c in calls.chunks(3) {
                assert_eq!([c[0].0, c[1].0, c[2].0], ["begin", "set", "end"]);
                assert!(c[0].1 == c[1].1 && c[1].1 == c[2].1);
                let id = id_of(c[1].1);
                assert!(
                    p.kind.param_ids().contains(&id.as_str()),
                    "{}: {id}",
                    p.name
                );
            }
            // Exactly the parameters whose value the preset changes.
            let changed = p
                .values
                .iter()
                .filter(|(id, x)| {
                    let mut one = params.values();
                    one.set(id, x).unwrap();
                    one != params.values()
                })
                .count();
            assert_eq!(calls.len() / 3, changed, "{}", p.name);
        }
    }
}
