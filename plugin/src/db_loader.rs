//! # The sound database in use: the embedded default, or the user's own recordings
//!
//! A user database (a folder made by `cargo xtask sounddb import`, see the README) is chosen in
//! the editor or restored with a project; its path is saved with the state under the persisted
//! key `db_path` (`null` = the embedded default). Loading, validating and resampling it to the
//! host's rate take time and allocate, so they happen on a short-lived loader thread, never on
//! the audio thread:
//!
//! ```text
//!  editor / state load ──request(path)──► loader thread: SoundDb::load(path, rate)
//!                                              │ ok: ready queue ──► audio thread swaps it in
//!                                              │ error: status says why, the current one plays on
//!  audio thread ──old database──► retired queue ──► dropped on the main/GUI thread
//! ```
//!
//! On activation (main thread) the database for the new sample rate is prepared directly.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use crossbeam_queue::ArrayQueue;
use nice_plug::params::persist::PersistentField;
use sounddb::SoundDb;

/// Where the sound comes from and how loading went.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum DbState {
    /// The embedded, synthesized default database.
    #[default]
    Embedded,
    /// A user database is being loaded.
    Loading(PathBuf),
    /// A user database is playing.
    Ready {
        /// Its folder.
        path: PathBuf,
        /// Its display name.
        name: String,
        /// Units it holds.
        units: usize,
        /// What the loader warned about (a partial database still plays).
        warnings: Vec<String>,
    },
    /// The requested database could not be used; the previous one plays on.
    Failed {
        /// The folder.
        path: PathBuf,
        /// Why.
        error: String,
    },
}

/// Shared between the plugin, the editor and loader threads.
pub struct DbLoader {
    path: Mutex<Option<PathBuf>>,
    state: Mutex<DbState>,
    sample_rate_bits: AtomicU64,
    request_serial: AtomicU64,
    /// Databases ready to be swapped in by the audio thread.
    pub ready: ArrayQueue<Arc<SoundDb>>,
    /// Databases the audio thread swapped out, to be dropped elsewhere.
    pub retired: ArrayQueue<Arc<SoundDb>>,
}

impl Default for DbLoader {
    fn default() -> Self {
        Self {
            path: Mutex::new(None),
            state: Mutex::new(DbState::Embedded),
            sample_rate_bits: AtomicU64::new(48_000f64.to_bits()),
            request_serial: AtomicU64::new(0),
            ready: ArrayQueue::new(2),
            retired: ArrayQueue::new(8),
        }
    }
}

impl DbLoader {
    /// The user database folder in use or requested (`None` = embedded default).
    pub fn path(&self) -> Option<PathBuf> {
        self.path.lock().ok().and_then(|p| p.clone())
    }

    /// What the editor shows.
    pub fn state(&self) -> DbState {
        self.state.lock().map(|s| s.clone()).unwrap_or_default()
    }

    fn set_state(&self, s: DbState) {
        if let Ok(mut g) = self.state.lock() {
            *g = s;
        }
    }

    /// Drops databases the audio thread has swapped out (call off the audio thread).
    pub fn drain_retired(&self) {
        while self.retired.pop().is_some() {}
    }

    /// The database to use at `sample_rate_hz`, prepared now (main thread, in `activate()`).
    /// A user database that fails to load falls back to the embedded one and says why.
    pub fn prepare_for_rate(&self, sample_rate_hz: f64) -> Arc<SoundDb> {
        self.sample_rate_bits
            .store(sample_rate_hz.to_bits(), Ordering::Relaxed);
        self.drain_retired();
        while self.ready.pop().is_some() {}
        match self.path() {
            None => {
                self.set_state(DbState::Embedded);
                crate::render::default_db(sample_rate_hz)
            }
            Some(path) => match load(&path, sample_rate_hz) {
                Ok((db, state)) => {
                    self.set_state(state);
                    db
                }
                Err(error) => {
                    nice_plug::nice_warn!("Papier: sound database {}: {error}", path.display());
                    self.set_state(DbState::Failed { path, error });
                    crate::render::default_db(sample_rate_hz)
                }
            },
        }
    }

    /// Asks for a user database (`None` = back to the embedded default). Loads on a separate
    /// thread; the audio thread picks the result up from [`DbLoader::ready`].
    pub fn request(self: &Arc<Self>, path: Option<PathBuf>) {
        self.drain_retired();
        let serial = self.request_serial.fetch_add(1, Ordering::AcqRel) + 1;
        if let Ok(mut p) = self.path.lock() {
            p.clone_from(&path);
        }
        let me = self.clone();
        let rate = f64::from_bits(self.sample_rate_bits.load(Ordering::Relaxed));
        if let Some(p) = &path {
            self.set_state(DbState::Loading(p.clone()));
        }
        let spawned = std::thread::Builder::new()
            .name("papier-db-load".into())
            .spawn(move || {
                let result = match &path {
                    None => Ok((crate::render::default_db(rate), DbState::Embedded)),
                    Some(p) => load(p, rate),
                };
                // A newer request supersedes this one.
                if me.request_serial.load(Ordering::Acquire) != serial {
                    return;
                }
                match result {
                    Ok((db, state)) => {
                        while me.ready.pop().is_some() {}
                        let _ = me.ready.push(db);
                        me.set_state(state);
                    }
                    Err(error) => {
                        let p = path.unwrap_or_default();
                        nice_plug::nice_warn!("Papier: sound database {}: {error}", p.display());
                        me.set_state(DbState::Failed { path: p, error });
                    }
                }
            });
        if let Err(e) = spawned {
            self.set_state(DbState::Failed {
                path: self.path().unwrap_or_default(),
                error: format!("cannot start the loader thread: {e}"),
            });
        }
    }
}

/// Loads and prepares a user database; the error is one line.
pub fn load(path: &Path, sample_rate_hz: f64) -> Result<(Arc<SoundDb>, DbState), String> {
    let (db, warnings) = SoundDb::load(path, sample_rate_hz).map_err(|e| e.to_string())?;
    if db.num_units() == 0 {
        return Err("the database holds no usable units".into());
    }
    let state = DbState::Ready {
        path: path.to_path_buf(),
        name: db.info().name.clone(),
        units: db.num_units(),
        warnings: warnings.iter().map(|w| w.to_string()).collect(),
    };
    Ok((Arc::new(db), state))
}

/// The persisted form of the user database folder (`null` = embedded default).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(transparent)]
pub struct DbPath(pub Option<String>);

impl<'a> PersistentField<'a, DbPath> for Arc<DbLoader> {
    fn set(&self, new_value: DbPath) {
        let path = new_value.0.filter(|s| !s.is_empty()).map(PathBuf::from);
        if path != self.path() {
            self.request(path);
        }
    }

    fn map<F, R>(&self, f: F) -> R
    where
        F: Fn(&DbPath) -> R,
    {
        f(&DbPath(
            self.path().map(|p| p.to_string_lossy().into_owned()),
        ))
    }
}
