//! # The phrase pad: takes played from buttons
//!
//! One button per phrase of the bank ([`crate::phrase`]), labelled with its key and name and lit
//! while it plays. Pressing a button is striking its key (note-on at the pad's velocity),
//! releasing it lets go of the key (note-off): the messages go through the GUI → audio queue
//! like the grab pad's, so a phrase from the pad and one from a keyboard are the same thing.
//! **Reload** reads the user's phrase folder again (off the audio thread; the open editor also
//! does it by itself when the folder changes); files it refused are listed, one line each.

use std::sync::Arc;

use egui::{Color32, RichText, Ui, vec2};

use crate::engine::Meters;
use crate::gesture_map::MidiInput;
use crate::phrase::{PhraseShelf, note_name};

/// Default velocity of the pad (MIDI 100: a phrase as written).
pub const DEFAULT_VELOCITY: f32 = 100.0 / 127.0;

/// How often the open editor looks at the phrase folder, seconds.
const FOLDER_CHECK_S: f64 = 1.0;

/// Buttons per row.
const COLUMNS: usize = 2;

/// The pad's state.
#[derive(Debug)]
pub struct PhrasePad {
    velocity: f32,
    held: Option<u8>,
    /// When the folder was last looked at (editor time, s).
    checked_s: f64,
}

impl Default for PhrasePad {
    fn default() -> Self {
        Self {
            velocity: DEFAULT_VELOCITY,
            held: None,
            checked_s: f64::NEG_INFINITY,
        }
    }
}

impl PhrasePad {
    /// Draws the pad; returns the first button's rectangle (for layout tests), if any.
    pub fn show(
        &mut self,
        ui: &mut Ui,
        shelf: &Arc<PhraseShelf>,
        meters: &Meters,
        sink: &mut impl FnMut(MidiInput),
    ) -> Option<egui::Rect> {
        // While the window is open, a changed folder is read again (once a second at most).
        let now_s = ui.input(|i| i.time);
        if now_s - self.checked_s >= FOLDER_CHECK_S {
            self.checked_s = now_s;
            shelf.reload_if_changed();
        }
        let bank = shelf.current();
        ui.horizontal(|ui| {
            ui.label("Velocity");
            ui.add(egui::Slider::new(&mut self.velocity, 0.05..=1.0).show_value(false))
                .on_hover_text("How hard the pad strikes: amplitude and speed of the phrase");
            ui.weak(format!("{}", (self.velocity * 127.0).round()));
            if ui
                .button("Reload")
                .on_hover_text(match shelf.dir() {
                    Some(d) => format!("Read the phrase folder again: {}", d.display()),
                    None => "No user phrase folder (no home directory)".into(),
                })
                .clicked()
            {
                shelf.reload();
            }
        });
        let mut first = None;
        let mut down_now = None;
        let width = ((ui.available_width() - 12.0) / COLUMNS as f32).max(60.0);
        egui::Grid::new("phrase_pad")
            .num_columns(COLUMNS)
            .spacing([4.0, 3.0])
            .show(ui, |ui| {
                for (i, p) in bank.by_note().enumerate() {
                    let playing = meters.phrase_playing(p.note);
                    let text = RichText::new(format!("{:<4} {}", note_name(p.note), p.name));
                    // A fixed width, long names cut short (the hover text has them whole).
                    let mut button = egui::Button::new(text).truncate();
                    if playing {
                        button = button.fill(Color32::from_rgb(70, 110, 70));
                    }
                    let r = ui
                        .add_sized(vec2(width, 20.0), button)
                        .on_hover_text(format!(
                            "{} · note {} · {:.1} s · {} · {}",
                            p.name,
                            p.note,
                            p.duration_s,
                            match p.start {
                                crate::phrase::PhraseStart::Fresh => "fresh sheet",
                                crate::phrase::PhraseStart::Current => "current sheet",
                            },
                            p.source
                        ));
                    first.get_or_insert(r.rect);
                    if r.is_pointer_button_down_on() {
                        down_now = Some(p.note);
                    }
                    if i % COLUMNS == COLUMNS - 1 {
                        ui.end_row();
                    }
                }
            });
        if down_now != self.held {
            if let Some(key) = self.held {
                sink(MidiInput::NoteOff { key });
            }
            if let Some(key) = down_now {
                sink(MidiInput::NoteOn {
                    key,
                    velocity: self.velocity,
                });
            }
            self.held = down_now;
        }
        for e in &bank.errors {
            ui.colored_label(Color32::from_rgb(230, 160, 80), e);
        }
        first
    }
}
