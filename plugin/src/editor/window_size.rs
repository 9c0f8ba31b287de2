//! # The editor's window size, saved with the project
//!
//! nice-plug-egui 0.6's `EguiEditorState` is not a persistable field, so the size lives here:
//! [`EditorSize`] is the persisted field `editor_size` of [`crate::params::PapierParams`]
//! (logical pixels, so it scales with the display's DPI), serialized as
//! `{"width":…,"height":…}`. The window writes it when it is resized
//! ([`super::PapierEditor`]'s `resized`); the editor shell ([`super::shell`]) opens the next
//! window at that size.
//!
//! A loaded value is kept exactly as loaded (re-saving a loaded state gives identical bytes);
//! it is clamped to [`MIN_SIZE`]–[`MAX_SIZE`] only when a window is opened.

use std::sync::atomic::{AtomicU64, Ordering};

use nice_plug::params::persist::PersistentField;
use serde::{Deserialize, Serialize};

/// Initial window size, logical pixels.
pub const DEFAULT_SIZE: (u32, u32) = (1060, 720);
/// Smallest window, logical pixels.
pub const MIN_SIZE: (u32, u32) = (860, 600);
/// Largest window, logical pixels.
pub const MAX_SIZE: (u32, u32) = (4096, 4096);

/// The persisted form.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SavedEditorSize {
    /// Width, logical pixels.
    pub width: u32,
    /// Height, logical pixels.
    pub height: u32,
}

/// The window size, shared by the plugin state, the editor shell and the window (both halves
/// in one atomic, so a reader never sees the width of one size and the height of another).
#[derive(Debug)]
pub struct EditorSize(AtomicU64);

impl Default for EditorSize {
    fn default() -> Self {
        Self(AtomicU64::new(pack(DEFAULT_SIZE)))
    }
}

fn pack((w, h): (u32, u32)) -> u64 {
    (u64::from(w) << 32) | u64::from(h)
}

fn unpack(v: u64) -> (u32, u32) {
    ((v >> 32) as u32, v as u32)
}

impl EditorSize {
    /// The size as stored (as saved or loaded).
    pub fn get(&self) -> (u32, u32) {
        unpack(self.0.load(Ordering::Relaxed))
    }

    /// Stores a size.
    pub fn set(&self, size: (u32, u32)) {
        self.0.store(pack(size), Ordering::Relaxed);
    }

    /// Stores a window's logical size (rounded).
    pub fn set_logical(&self, width: f64, height: f64) {
        let r = |v: f64| {
            if v.is_finite() {
                v.round().clamp(1.0, f64::from(u32::MAX)) as u32
            } else {
                1
            }
        };
        self.set((r(width), r(height)));
    }

    /// The size a window opens at: the stored size within [`MIN_SIZE`]–[`MAX_SIZE`].
    pub fn clamped(&self) -> (u32, u32) {
        let (w, h) = self.get();
        (
            w.clamp(MIN_SIZE.0, MAX_SIZE.0),
            h.clamp(MIN_SIZE.1, MAX_SIZE.1),
        )
    }
}

impl<'a> PersistentField<'a, SavedEditorSize> for std::sync::Arc<EditorSize> {
    fn set(&self, new_value: SavedEditorSize) {
        EditorSize::set(self, (new_value.width, new_value.height));
    }

    fn map<F, R>(&self, f: F) -> R
    where
        F: Fn(&SavedEditorSize) -> R,
    {
        let (width, height) = self.get();
        f(&SavedEditorSize { width, height })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stores_and_clamps() {
        let s = EditorSize::default();
        assert_eq!(s.get(), DEFAULT_SIZE);
        assert_eq!(s.clamped(), DEFAULT_SIZE);
        s.set((10, 100_000));
        assert_eq!(s.get(), (10, 100_000), "kept as stored");
        assert_eq!(s.clamped(), (MIN_SIZE.0, MAX_SIZE.1));
        s.set_logical(1000.4, 700.6);
        assert_eq!(s.get(), (1000, 701));
        s.set_logical(f64::NAN, -5.0);
        assert_eq!(s.get(), (1, 1));
    }

    #[test]
    fn persisted_form_round_trips_byte_identically() {
        use std::sync::Arc;
        let field = Arc::new(EditorSize::default());
        let json = r#"{"width":1234,"height":5}"#;
        let loaded: SavedEditorSize = serde_json::from_str(json).unwrap();
        PersistentField::set(&field, loaded);
        let saved = field.map(|v| serde_json::to_string(v).unwrap());
        assert_eq!(saved, json);
    }
}
