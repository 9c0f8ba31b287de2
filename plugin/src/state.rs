//! # The sheet in the saved project (the persistence adapter)
//!
//! The sheet is persisted next to the parameters under the key `sheet` as the JSON of
//! [`sim_core::SavedSheet`] (versioned by sim-core). The store it lives in between saves, and
//! the rules for when the simulation publishes it, are the engine's
//! ([`crate::engine::sheet_store`]); this module adapts it to nice-plug's persistence: the
//! host's save asks the worker for the sheet as it is now, then writes the store's JSON text;
//! a load hands the text to the store. The text is kept raw ([`SheetJson`]), so a bad sheet
//! never makes the whole plugin state fail to load and unreadable data is written back byte
//! for byte.

use nice_plug::params::persist::PersistentField;
use serde::{Deserialize, Serialize};

use crate::engine::sheet_store::{FRESH_SAVE_PATIENCE, SheetStore};

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

impl<'a> PersistentField<'a, SheetJson> for std::sync::Arc<SheetStore> {
    fn set(&self, new_value: SheetJson) {
        self.load_json(new_value.0.get());
    }

    fn map<F, R>(&self, f: F) -> R
    where
        F: Fn(&SheetJson) -> R,
    {
        // The host saves (main thread): the sheet as it is now, not as last published.
        self.request_fresh(FRESH_SAVE_PATIENCE);
        f(&SheetJson::from_text(self.to_json()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sim_core::{Sim, SimConfig};
    use std::sync::Arc;

    /// What the host saves reloads into a store that saves it again byte for byte, and bad
    /// JSON text becomes the JSON `null` rather than a failed state.
    #[test]
    fn the_persisted_text_round_trips() {
        let store = Arc::new(SheetStore::default());
        assert!(store.try_publish(Sim::new(SimConfig::default()).save(), 0));
        let saved = store.map(|j: &SheetJson| j.0.get().to_string());
        let other = Arc::new(SheetStore::default());
        other.set(SheetJson::from_text(saved.clone()));
        assert_eq!(other.map(|j: &SheetJson| j.0.get().to_string()), saved);
        assert_eq!(SheetJson::from_text("{oops".into()).0.get(), "null");
    }
}
