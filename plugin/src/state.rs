//! # The sheet in the saved project
//!
//! A project must reopen with the same sheet: its shape and its damage (creases, singular
//! points, later tears). The sheet is persisted next to the parameters under the key `sheet` as
//! the JSON of [`sim_core::SavedSheet`] (versioned by sim-core).
//!
//! [`SheetStore`] is the meeting point of three parties:
//! - the simulation (worker thread, or the audio thread in offline lockstep) publishes the sheet
//!   after something happened ([`SheetStore::try_publish`], non-blocking);
//! - the host saves and loads state on the main thread (the `PersistentField` impl);
//! - the engine notices a loaded state by its generation number and restores the sheet from it.
//!
//! A publish carries the generation it is based on and is refused if a state was loaded in the
//! meantime, so a load can never be overwritten by a stale sheet.
//!
//! Data that cannot be read (corrupt, or written by a newer version) is logged, the plugin keeps
//! its current sheet, and the raw JSON is kept and written back unchanged on the next save so
//! no user data is lost by opening a project in an older build.

use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

use nice_plug::params::persist::PersistentField;
use serde::{Deserialize, Serialize};
use sim_core::SavedSheet;

/// What the store holds.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum StoredSheet {
    /// Nothing yet: a fresh flat sheet.
    #[default]
    Empty,
    /// A sheet that can be restored.
    Valid(Box<SavedSheet>),
    /// Data that could not be read (its JSON text); kept verbatim so that saving does not lose
    /// it.
    Unreadable(String),
}

/// The persisted form: any JSON text, kept raw so that a bad sheet never makes the whole plugin
/// state fail to load and unreadable data is written back byte for byte.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(transparent)]
pub struct SheetJson(pub Box<serde_json::value::RawValue>);

impl SheetJson {
    fn from_text(text: String) -> Self {
        match serde_json::value::RawValue::from_string(text) {
            Ok(raw) => Self(raw),
            Err(_) => Self::null(),
        }
    }

    fn null() -> Self {
        Self(
            serde_json::value::RawValue::from_string("null".to_string())
                .expect("null is valid JSON"),
        )
    }
}

/// The shared sheet store (see the module docs).
#[derive(Debug, Default)]
pub struct SheetStore {
    inner: Mutex<StoredSheet>,
    generation: AtomicU64,
    rejected_publishes: AtomicU64,
}

impl SheetStore {
    /// Generation of the last state load (0 = none since creation).
    pub fn generation(&self) -> u64 {
        self.generation.load(Ordering::Acquire)
    }

    /// A copy of what is stored (main thread or worker; may block briefly).
    pub fn get(&self) -> StoredSheet {
        self.inner.lock().map(|g| g.clone()).unwrap_or_default()
    }

    /// Publishes the simulation's sheet if no state was loaded since `based_on_generation` and
    /// the lock is free; never blocks. Returns true if stored.
    pub fn try_publish(&self, sheet: SavedSheet, based_on_generation: u64) -> bool {
        let Ok(mut guard) = self.inner.try_lock() else {
            return false;
        };
        if self.generation() != based_on_generation {
            self.rejected_publishes.fetch_add(1, Ordering::Relaxed);
            return false;
        }
        *guard = StoredSheet::Valid(Box::new(sheet));
        true
    }

    /// Publishes, waiting for the lock (main thread only, e.g. on deactivation).
    pub fn publish(&self, sheet: SavedSheet, based_on_generation: u64) -> bool {
        let Ok(mut guard) = self.inner.lock() else {
            return false;
        };
        if self.generation() != based_on_generation {
            self.rejected_publishes.fetch_add(1, Ordering::Relaxed);
            return false;
        }
        *guard = StoredSheet::Valid(Box::new(sheet));
        true
    }

    /// Number of publishes refused because a state had been loaded.
    pub fn rejected_publishes(&self) -> u64 {
        self.rejected_publishes.load(Ordering::Relaxed)
    }

    /// Interprets loaded JSON text (what the host's state load calls).
    pub fn load_json(&self, text: &str) {
        let stored = parse_stored(text);
        if let Ok(mut guard) = self.inner.lock() {
            *guard = stored;
        }
        self.generation.fetch_add(1, Ordering::AcqRel);
    }

    /// The JSON text to save.
    pub fn to_json(&self) -> String {
        match self.inner.lock() {
            Ok(guard) => match &*guard {
                StoredSheet::Empty => "null".to_string(),
                StoredSheet::Valid(s) => {
                    serde_json::to_string(s).unwrap_or_else(|_| "null".to_string())
                }
                StoredSheet::Unreadable(text) => text.clone(),
            },
            Err(_) => "null".to_string(),
        }
    }
}

/// Parses a persisted sheet, logging why it cannot be used.
pub fn parse_stored(text: &str) -> StoredSheet {
    if text.trim() == "null" {
        return StoredSheet::Empty;
    }
    match serde_json::from_str::<SavedSheet>(text) {
        Ok(s) => StoredSheet::Valid(Box::new(s)),
        Err(e) => {
            nice_plug::nice_warn!(
                "Papier: the saved sheet cannot be read ({e}); keeping a fresh sheet, and keeping \
                 the saved data unchanged for the next save"
            );
            StoredSheet::Unreadable(text.to_string())
        }
    }
}

impl<'a> PersistentField<'a, SheetJson> for std::sync::Arc<SheetStore> {
    fn set(&self, new_value: SheetJson) {
        self.load_json(new_value.0.get());
    }

    fn map<F, R>(&self, f: F) -> R
    where
        F: Fn(&SheetJson) -> R,
    {
        f(&SheetJson::from_text(self.to_json()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sim_core::{Sim, SimConfig};

    #[test]
    fn round_trip_is_byte_identical() {
        let store = SheetStore::default();
        let sheet = Sim::new(SimConfig::default()).save();
        assert!(store.try_publish(sheet, 0));
        let a = store.to_json();
        let other = SheetStore::default();
        other.load_json(&a);
        let b = other.to_json();
        assert_eq!(a, b);
        assert!(matches!(other.get(), StoredSheet::Valid(_)));
    }

    #[test]
    fn load_wins_over_stale_publish() {
        let store = SheetStore::default();
        let g0 = store.generation();
        store.load_json("null");
        let sheet = Sim::new(SimConfig::default()).save();
        assert!(!store.try_publish(sheet.clone(), g0));
        assert_eq!(store.rejected_publishes(), 1);
        assert!(store.try_publish(sheet, store.generation()));
    }

    #[test]
    fn unreadable_data_is_kept_verbatim() {
        let store = SheetStore::default();
        let junk = r#"{"version": 999,  "future": [1, 2, 3]}"#;
        store.load_json(junk);
        assert!(matches!(store.get(), StoredSheet::Unreadable(_)));
        assert_eq!(store.to_json(), junk);
        store.load_json("\"garbage\"");
        assert_eq!(store.to_json(), "\"garbage\"");
    }
}
