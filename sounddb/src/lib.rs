//! # sounddb: the sound database
//!
//! Crumple units (time-domain clips) and friction spectra (magnitude spectra), indexed like the
//! seeds by resonator size (l_r, l_c) (thesis §4.3.4, `000_cb4d91e46ec5927f.txt` T 1804–1909;
//! SCA 2016 §4; digest-sound §3).
//!
//! **Current state:** only the empty database exists; the format, loader, generator and importer
//! are built in the sound issue.

#![warn(missing_docs)]

/// A loaded, immutable sound database.
#[derive(Debug, Default)]
pub struct SoundDb {
    _private: (),
}

impl SoundDb {
    /// A database with no units (renders silence).
    pub fn empty() -> Self {
        Self::default()
    }
}
