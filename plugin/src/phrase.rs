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
//! - [`player`]: the voices playing, on the thread that calls the engine (allocation-free).
//!
//! This goes beyond the seeds, which drive the sheet from a mouse or scripted handles only.
//! Phrases are parsed off the audio thread; the engine swaps a new bank in like a database.

pub mod bank;
pub mod player;
pub mod spec;

pub use bank::PhraseBank;
pub use player::PhrasePlayer;
pub use spec::{FIRST_PHRASE_NOTE, NoteOffRule, Phrase, PhraseError, PhraseStart};
