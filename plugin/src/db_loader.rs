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
//! On activation (main thread) the database for the new sample rate is prepared directly; a load
//! still in flight from an earlier request (made at the old rate, for instance by loading a
//! project before the host activates the plugin) is superseded and never reaches the audio
//! thread.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
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
    /// Loader threads still running.
    in_flight: AtomicUsize,
    /// Makes "is this load still the latest request? then publish it" atomic with respect to
    /// activation superseding every load in flight (never taken on the audio thread).
    publish: Mutex<()>,
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
            in_flight: AtomicUsize::new(0),
            publish: Mutex::new(()),
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

    /// True while a loader thread started by [`DbLoader::request`] is still running.
    pub fn is_loading(&self) -> bool {
        self.in_flight.load(Ordering::Acquire) > 0
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
        {
            // Every load in flight was made for another rate (or an older path): supersede it,
            // and drop what already finished.
            let _publishing = self.publish.lock().unwrap_or_else(|e| e.into_inner());
            self.request_serial.fetch_add(1, Ordering::AcqRel);
            while self.ready.pop().is_some() {}
        }
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
        self.in_flight.fetch_add(1, Ordering::AcqRel);
        let spawned = std::thread::Builder::new()
            .name("papier-db-load".into())
            .spawn(move || {
                let result = match &path {
                    None => Ok((crate::render::default_db(rate), DbState::Embedded)),
                    Some(p) => load(p, rate),
                };
                me.publish_result(serial, path, result);
                me.in_flight.fetch_sub(1, Ordering::AcqRel);
            });
        if let Err(e) = spawned {
            self.in_flight.fetch_sub(1, Ordering::AcqRel);
            self.set_state(DbState::Failed {
                path: self.path().unwrap_or_default(),
                error: format!("cannot start the loader thread: {e}"),
            });
        }
    }

    /// Publishes a finished load (loader thread) unless a newer request or an activation has
    /// superseded it.
    fn publish_result(
        &self,
        serial: u64,
        path: Option<PathBuf>,
        result: Result<(Arc<SoundDb>, DbState), String>,
    ) {
        let _publishing = self.publish.lock().unwrap_or_else(|e| e.into_inner());
        if self.request_serial.load(Ordering::Acquire) != serial {
            return;
        }
        match result {
            Ok((db, state)) => {
                while self.ready.pop().is_some() {}
                let _ = self.ready.push(db);
                self.set_state(state);
            }
            Err(error) => {
                let p = path.unwrap_or_default();
                nice_plug::nice_warn!("Papier: sound database {}: {error}", p.display());
                self.set_state(DbState::Failed { path: p, error });
            }
        }
    }
}

/// Loads and prepares a user database ([`crate::render::user_db::load`]); the error is one
/// line.
pub fn load(path: &Path, sample_rate_hz: f64) -> Result<(Arc<SoundDb>, DbState), String> {
    let (db, info) = crate::render::user_db::load(path, sample_rate_hz)?;
    let state = DbState::Ready {
        path: path.to_path_buf(),
        name: info.name,
        units: info.units,
        warnings: info.warnings,
    };
    Ok((db, state))
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

#[cfg(test)]
mod tests {
    use super::*;
    use sounddb::Cell;

    /// A fresh, empty temporary folder.
    fn temp_dir(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("papier-db-loader-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// Writes a small valid user database (the clac cell, three flap cells and two friction
    /// spectra of the embedded one, renamed) into `dir`; returns its unit count.
    fn write_small_db(dir: &Path) -> usize {
        let (full, _) = crate::render::default_db::embedded_database().unwrap();
        let keep = |c: &Cell| {
            c.is_constrained()
                || [(10.0, 5.0), (20.0, 20.0), (5.0, 30.0)]
                    .iter()
                    .any(|&(s, k)| {
                        c.same_as(&Cell::Free {
                            straight_cm: s,
                            curved_cm: k,
                        })
                    })
        };
        let mut db = full.subset(keep, 2);
        db.info.name = "loader test".into();
        db.write_dir(dir).unwrap();
        db.units.len()
    }

    /// A loader whose requests load at `rate` (as after an activation at that rate).
    fn loader_at(rate: f64) -> Arc<DbLoader> {
        let l = Arc::new(DbLoader::default());
        l.sample_rate_bits.store(rate.to_bits(), Ordering::Relaxed);
        l
    }

    /// Waits for every loader thread to finish. Not a timing assertion: the bound only turns a
    /// hung loader into a failure instead of a hung test run.
    fn wait_idle(l: &DbLoader) {
        let mut waited = 0u32;
        while l.is_loading() {
            std::thread::sleep(std::time::Duration::from_millis(2));
            waited += 1;
            assert!(waited < 150_000, "the loader thread never finished");
        }
    }

    /// Detects a `request` that loads on the calling thread (the audio or GUI thread would
    /// stall), or a loaded database that does not reach the ready queue with a `Ready` status.
    #[test]
    fn request_loads_on_its_own_thread_and_queues_the_database() {
        let dir = temp_dir("valid");
        let units = write_small_db(&dir);
        let loader = loader_at(44_100.0);
        // While the test holds the publish lock no loader thread can hand a result over: if
        // `request` did the work itself, the result would already be there when it returns.
        let guard = loader.publish.lock().unwrap();
        loader.request(Some(dir.clone()));
        assert!(loader.ready.is_empty());
        assert!(loader.is_loading());
        assert_eq!(loader.state(), DbState::Loading(dir.clone()));
        assert_eq!(loader.path(), Some(dir.clone()));
        drop(guard);
        wait_idle(&loader);
        match loader.state() {
            DbState::Ready {
                path,
                name,
                units: n,
                ..
            } => {
                assert_eq!(path, dir);
                assert_eq!(name, "loader test");
                assert_eq!(n, units);
            }
            other => panic!("expected Ready, got {other:?}"),
        }
        let db = loader
            .ready
            .pop()
            .expect("the loaded database is queued for the audio thread");
        assert_eq!(db.num_units(), units);
        assert!(db.matches_rate(44_100.0));
        assert!(loader.ready.is_empty(), "one database per request");
        // The audio thread's swap: the old database is retired and dropped off that thread.
        assert!(loader.retired.push(Arc::new(SoundDb::empty())).is_ok());
        loader.drain_retired();
        assert!(loader.retired.is_empty());
    }

    /// Detects a broken folder that replaces the database in use (silence or a crash) or whose
    /// error is lost instead of being shown, and a fallback other than the embedded database
    /// on the next activation.
    #[test]
    fn a_broken_folder_keeps_the_current_database_and_says_why() {
        let good = temp_dir("good");
        let units = write_small_db(&good);
        let loader = loader_at(44_100.0);
        loader.request(Some(good.clone()));
        wait_idle(&loader);
        let current = loader.ready.pop().expect("the good database loads");
        assert_eq!(current.num_units(), units);

        let broken = temp_dir("broken");
        std::fs::write(
            broken.join("manifest.toml"),
            "format = \"papier-sounddb\"\nversion = 1\nname = [oops\n",
        )
        .unwrap();
        let missing = broken.join("does-not-exist");
        for (bad, expect) in [(&broken, "manifest"), (&missing, "does-not-exist")] {
            loader.request(Some(bad.clone()));
            wait_idle(&loader);
            match loader.state() {
                DbState::Failed { path, error } => {
                    assert_eq!(&path, bad);
                    assert!(error.contains(expect), "unhelpful error: {error}");
                    assert!(!error.contains('\n'), "error is one line: {error}");
                }
                other => panic!("{}: expected Failed, got {other:?}", bad.display()),
            }
            assert!(
                loader.ready.is_empty(),
                "nothing replaces the database that plays"
            );
            // The choice is kept (saved with the project, shown with its error).
            assert_eq!(loader.path().as_ref(), Some(bad));
        }

        // On the next activation the broken choice falls back to the embedded database.
        let db = loader.prepare_for_rate(44_100.0);
        let embedded = crate::render::default_db(44_100.0);
        assert_eq!(db.num_units(), embedded.num_units());
        assert_ne!(db.num_units(), units);
        assert!(matches!(loader.state(), DbState::Failed { .. }));
    }

    /// Detects a load requested at the old rate (a project loaded before the host activates
    /// the plugin) that finishes after the activation prepared the database for the new rate
    /// and is then swapped in by the audio thread: units resampled for the wrong rate.
    /// (Before the fix this failed whenever the loader thread finished during the activation's
    /// own load, which is the common timing.)
    #[test]
    fn activation_supersedes_a_load_in_flight_for_another_rate() {
        let dir = temp_dir("superseded");
        let units = write_small_db(&dir);
        for _ in 0..3 {
            let loader = loader_at(48_000.0);
            loader.request(Some(dir.clone()));
            let db = loader.prepare_for_rate(44_100.0);
            wait_idle(&loader);
            assert!(db.matches_rate(44_100.0));
            assert_eq!(db.num_units(), units);
            assert!(
                loader.ready.is_empty(),
                "a database loaded for 48 kHz was queued for the 44.1 kHz engine"
            );
            assert!(
                matches!(loader.state(), DbState::Ready { .. }),
                "{:?}",
                loader.state()
            );
        }
    }

    /// Detects a persisted `db_path` that does not restore the folder (or restores it without
    /// loading it), an empty string that is not the embedded default, and a project reload
    /// with the same folder that reloads it needlessly.
    #[test]
    fn the_persisted_path_round_trips_and_loads_only_on_change() {
        let dir = temp_dir("persisted");
        write_small_db(&dir);
        let loader = loader_at(44_100.0);
        let text = dir.to_string_lossy().into_owned();
        PersistentField::set(&loader, DbPath(Some(text.clone())));
        assert_eq!(loader.path(), Some(dir.clone()));
        assert_eq!(loader.map(|p| p.clone()), DbPath(Some(text.clone())));
        wait_idle(&loader);
        assert!(matches!(loader.state(), DbState::Ready { .. }));
        assert_eq!(loader.ready.len(), 1);

        let serial = loader.request_serial.load(Ordering::Acquire);
        PersistentField::set(&loader, DbPath(Some(text)));
        assert_eq!(
            loader.request_serial.load(Ordering::Acquire),
            serial,
            "the same folder is not loaded again"
        );

        PersistentField::set(&loader, DbPath(Some(String::new())));
        assert_eq!(loader.path(), None);
        assert_eq!(loader.map(|p| p.clone()), DbPath(None));
        wait_idle(&loader);
        assert_eq!(loader.state(), DbState::Embedded);
    }
}
