//! # Phrases: gesture scripts played from MIDI notes
//!
//! A Foley artist plays takes from a keyboard: one key, one crumple; the next, a page turn. A
//! phrase is a gesture script (the lanes, grabs and resets `papier-render --script` reads,
//! [`sim_core::script`]) bound to a note from C4 (60) up, the range the gesture map leaves free
//! ([`crate::gesture_map`]). Note-on plays it from a fresh or the current sheet, velocity scales
//! its intensity, note-off lets it finish or releases its hands, and each hit draws a new seed
//! (round-robin variation, deterministic for a given performance).
//!
//! - [`spec`]: a phrase file read, checked and prepared (numbers only, no ids);
//! - [`bank`]: the factory phrases and the user's folder, at most one phrase per note;
//! - [`player`]: the voices playing, on the thread that calls the engine (allocation-free);
//! - [`shelf`]: the plugin's bank, the user's folder, the hand-off to the audio thread.
//!
//! This goes beyond the seeds, which drive the sheet from a mouse or scripted handles only.
//! Phrases are parsed off the audio thread; the engine swaps a new bank in like a database.

pub mod bank;
pub mod player;
pub mod shelf;
pub mod spec;

pub use bank::PhraseBank;
pub use player::PhrasePlayer;
pub use shelf::PhraseShelf;
pub use spec::{FIRST_PHRASE_NOTE, NoteOffRule, Phrase, PhraseError, PhraseStart};

/// A note's name, C4 = 60.
pub fn note_name(note: u8) -> String {
    const NAMES: [&str; 12] = [
        "C", "C#", "D", "D#", "E", "F", "F#", "G", "G#", "A", "A#", "B",
    ];
    format!(
        "{}{}",
        NAMES[usize::from(note % 12)],
        i32::from(note / 12) - 1
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn note_names() {
        assert_eq!(super::note_name(60), "C4");
        assert_eq!(super::note_name(66), "F#4");
        assert_eq!(super::note_name(81), "A5");
        assert_eq!(super::note_name(0), "C-1");
    }
}
