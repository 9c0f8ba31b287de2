//! # The sound database picker
//!
//! Chooses where the sound comes from: the embedded default database, or a user database
//! folder (made with `cargo xtask sounddb import`). There is no native folder dialog (it would
//! need GTK or a desktop portal); the folder is typed or pasted into a text field, and the
//! folders loaded successfully in this session are offered again as buttons.
//!
//! Loading happens on the loader's own thread ([`crate::db_loader`]): **Load** calls
//! `DbLoader::request(Some(folder))`, **Use embedded** `request(None)`; the picker shows the
//! loader's state every frame — loading, the database's name and unit count with any
//! warnings, or why the folder could not be used (the previous database plays on).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use egui::{Color32, RichText, Ui};

use crate::db_loader::{DbLoader, DbState};

/// How many recent folders are offered.
pub const MAX_RECENT: usize = 5;

/// The picker's own state (the text being edited, recent folders).
#[derive(Debug, Default)]
pub struct DbPicker {
    text: String,
    initialized: bool,
    recent: Vec<PathBuf>,
    hint: Option<String>,
}

/// What is wrong with a typed folder before asking the loader, if anything obvious.
pub fn check_folder(text: &str) -> Result<PathBuf, String> {
    let t = text.trim();
    if t.is_empty() {
        return Err("type or paste a folder path".into());
    }
    let p = Path::new(t);
    if !p.is_dir() {
        return Err(format!("{t} is not a folder"));
    }
    Ok(p.to_path_buf())
}

/// Adds `path` at the front of the recent list (no duplicates, at most [`MAX_RECENT`]).
pub fn remember(recent: &mut Vec<PathBuf>, path: &Path) {
    recent.retain(|p| p != path);
    recent.insert(0, path.to_path_buf());
    recent.truncate(MAX_RECENT);
}

impl DbPicker {
    /// Draws the picker for `loader`.
    pub fn show(&mut self, ui: &mut Ui, loader: &Arc<DbLoader>) {
        let state = loader.state();
        if !self.initialized {
            self.initialized = true;
            if let Some(p) = loader.path() {
                self.text = p.to_string_lossy().into_owned();
            }
        }
        if let DbState::Ready { path, .. } = &state
            && self.recent.first() != Some(path)
        {
            remember(&mut self.recent, path);
        }

        let edit = ui.add(
            egui::TextEdit::singleline(&mut self.text)
                .hint_text("folder of a user sound database")
                .desired_width(f32::INFINITY),
        );
        if edit.changed() {
            self.hint = None;
        }
        let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        ui.horizontal(|ui| {
            if ui.button("Load").clicked() || enter {
                match check_folder(&self.text) {
                    Ok(p) => loader.request(Some(p)),
                    Err(e) => self.hint = Some(e),
                }
            }
            if ui
                .add_enabled(
                    !matches!(state, DbState::Embedded),
                    egui::Button::new("Use embedded"),
                )
                .clicked()
            {
                loader.request(None);
                self.hint = None;
            }
        });
        if let Some(h) = &self.hint {
            ui.colored_label(Color32::from_rgb(230, 160, 80), h);
        }

        match &state {
            DbState::Embedded => {
                ui.label("Playing the embedded default database (synthesized printer paper).");
            }
            DbState::Loading(p) => {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label(format!("Loading {} …", p.display()));
                });
            }
            DbState::Ready {
                path,
                name,
                units,
                warnings,
            } => {
                ui.label(
                    RichText::new(format!("✔ {name}: {units} units"))
                        .color(Color32::from_rgb(110, 200, 130)),
                )
                .on_hover_text(path.display().to_string());
                if !warnings.is_empty() {
                    egui::CollapsingHeader::new(format!("{} warnings", warnings.len()))
                        .id_salt("db_warnings")
                        .show(ui, |ui| {
                            for w in warnings {
                                ui.colored_label(Color32::from_rgb(230, 200, 90), w);
                            }
                        });
                }
            }
            DbState::Failed { path, error } => {
                ui.colored_label(
                    Color32::from_rgb(235, 90, 80),
                    format!("✖ {}: {error}", path.display()),
                );
                ui.label("The previous database plays on.");
            }
        }

        if !self.recent.is_empty() {
            ui.horizontal_wrapped(|ui| {
                ui.weak("Recent:");
                let mut chosen = None;
                for p in &self.recent {
                    let name = p
                        .file_name()
                        .map(|n| n.to_string_lossy().into_owned())
                        .unwrap_or_else(|| p.display().to_string());
                    if ui
                        .small_button(name)
                        .on_hover_text(p.display().to_string())
                        .clicked()
                    {
                        chosen = Some(p.clone());
                    }
                }
                if let Some(p) = chosen {
                    self.text = p.to_string_lossy().into_owned();
                    loader.request(Some(p));
                }
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obvious_mistakes_are_caught_before_loading() {
        assert!(check_folder("   ").is_err());
        let missing = check_folder("/definitely/not/a/folder/papier").unwrap_err();
        assert!(missing.contains("not a folder"));
        let file = std::env::current_exe().unwrap();
        assert!(check_folder(&file.to_string_lossy()).is_err());
        let dir = std::env::temp_dir();
        assert_eq!(check_folder(&format!(" {} ", dir.display())).unwrap(), dir);
    }

    #[test]
    fn recent_list_is_most_recent_first_without_duplicates() {
        let mut r = Vec::new();
        for p in ["/a", "/b", "/a", "/c", "/d", "/e", "/f"] {
            remember(&mut r, Path::new(p));
        }
        let names: Vec<_> = r.iter().map(|p| p.to_string_lossy().into_owned()).collect();
        assert_eq!(names, vec!["/f", "/e", "/d", "/c", "/a"]);
    }
}
