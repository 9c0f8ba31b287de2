//! # The sheet store: where the simulation publishes the sheet a saved project holds
//!
//! A project must reopen with the same sheet: its shape and its damage (creases, singular
//! points, later tears). [`SheetStore`] is the meeting point of three parties:
//! - the simulation (worker thread, or the audio thread in offline lockstep) publishes the sheet
//!   after something happened ([`SheetStore::try_publish`], non-blocking);
//! - the host saves and loads state on the main thread (the plugin face's persistence adapter,
//!   `crate::state`, reads and writes the JSON text through [`SheetStore::to_json`] and
//!   [`SheetStore::load_json`]);
//! - the engine notices a loaded state by its generation number and restores the sheet from it.
//!
//! A publish carries the generation it is based on and is refused if a state was loaded in the
//! meantime, so a load can never be overwritten by a stale sheet.
//!
//! ## A save holds the sheet as it is now
//!
//! Publishing a moving sheet every frame would allocate on the worker 200 times a second, so the
//! worker publishes on its own only when the sheet comes to rest and every
//! [`super::frame_loop::PUBLISH_INTERVAL_FRAMES`] frames while it moves. A project saved between
//! those would store a sheet up to 2 s old. So the host's save asks for the sheet as it is:
//! while a worker thread runs ([`SheetStore::set_worker_live`]), the save counts a request and
//! waits (on the main thread, at most [`FRESH_SAVE_PATIENCE`]) until the worker has served it
//! ([`SheetStore::serve_save_request`]), between frames, once it has stepped every frame the
//! audio clock has reached: the saved sheet is the one whose sound was last heard. If the worker
//! does not answer in time (an overloaded machine), the save stores what was published last.
//! The offline (lockstep) path runs the sheet on the audio thread, which a save must not wait
//! for; it publishes at the end of every block in which the sheet moved instead.
//!
//! Data that cannot be read (corrupt, or written by a newer version) is logged, the current
//! sheet is kept, and the raw JSON is kept and written back unchanged on the next save so no
//! user data is lost by opening a project in an older build.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

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

/// How long a host's save waits for the worker to publish the sheet as it is now.
pub const FRESH_SAVE_PATIENCE: Duration = Duration::from_millis(200);

/// The shared sheet store (see the module docs).
#[derive(Debug, Default)]
pub struct SheetStore {
    inner: Mutex<StoredSheet>,
    generation: AtomicU64,
    rejected_publishes: AtomicU64,
    /// A worker thread runs and serves save requests.
    worker_live: AtomicBool,
    /// Save requests made (a counter) and the last one served.
    save_requested: AtomicU64,
    save_served: AtomicU64,
    /// Signalled when a request is served or the worker stops.
    served: Condvar,
    /// Saves that stored an older sheet because the worker did not answer in time.
    stale_saves: AtomicU64,
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

    /// Worker thread: whether it runs (and serves save requests). On stop, a save waiting for
    /// it is released.
    pub fn set_worker_live(&self, live: bool) {
        self.worker_live.store(live, Ordering::Release);
        if !live {
            // Taking the lock orders the store before a waiting save's next check.
            drop(self.inner.lock());
            self.served.notify_all();
        }
    }

    /// Worker thread: publishes the sheet (`save` makes it) if the host asked for it since the
    /// last request served; never blocks (a busy lock leaves the request for the next call).
    /// Returns true if a request was served.
    pub fn serve_save_request(
        &self,
        based_on_generation: u64,
        save: impl FnOnce() -> SavedSheet,
    ) -> bool {
        let requested = self.save_requested.load(Ordering::Acquire);
        if requested <= self.save_served.load(Ordering::Acquire) {
            return false;
        }
        let Ok(mut guard) = self.inner.try_lock() else {
            return false;
        };
        if self.generation() == based_on_generation {
            *guard = StoredSheet::Valid(Box::new(save()));
        } else {
            // A state was loaded since: the save stores the loaded one.
            self.rejected_publishes.fetch_add(1, Ordering::Relaxed);
        }
        self.save_served.store(requested, Ordering::Release);
        drop(guard);
        self.served.notify_all();
        true
    }

    /// Main thread, before saving: while a worker runs, asks it for the sheet as it is now and
    /// waits up to `patience`. Returns false if the worker did not answer in time.
    pub fn request_fresh(&self, patience: Duration) -> bool {
        if !self.worker_live.load(Ordering::Acquire) {
            return true;
        }
        let request = self.save_requested.fetch_add(1, Ordering::AcqRel) + 1;
        let Ok(guard) = self.inner.lock() else {
            return false;
        };
        let waiting = |_: &mut StoredSheet| {
            self.worker_live.load(Ordering::Acquire)
                && self.save_served.load(Ordering::Acquire) < request
        };
        let answered = match self.served.wait_timeout_while(guard, patience, waiting) {
            Ok((_, timeout)) => !timeout.timed_out(),
            Err(_) => false,
        };
        if !answered {
            self.stale_saves.fetch_add(1, Ordering::Relaxed);
        }
        answered
    }

    /// Saves that stored the last published sheet because the worker did not answer in time.
    pub fn stale_saves(&self) -> u64 {
        self.stale_saves.load(Ordering::Relaxed)
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
            tracing::warn!(
                "Papier: the saved sheet cannot be read ({e}); keeping a fresh sheet, and keeping \
                 the saved data unchanged for the next save"
            );
            StoredSheet::Unreadable(text.to_string())
        }
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

    /// A worker stand-in: serves requests until told to stop, publishing a sheet whose frame
    /// counter it advances each round.
    fn serving_worker(
        store: &SheetStore,
        stop: &std::sync::atomic::AtomicBool,
        generation: u64,
    ) -> u64 {
        store.set_worker_live(true);
        let mut frame = 0u64;
        let mut served = 0;
        while !stop.load(Ordering::Acquire) {
            frame += 1;
            let sheet = || {
                let mut s = Sim::new(SimConfig::default()).save();
                s.frame = frame;
                s
            };
            if store.serve_save_request(generation, sheet) {
                served += 1;
            }
            std::thread::sleep(Duration::from_micros(200));
        }
        store.set_worker_live(false);
        served
    }

    fn stored_frame(store: &SheetStore) -> Option<u64> {
        match store.get() {
            StoredSheet::Valid(s) => Some(s.frame),
            _ => None,
        }
    }

    #[test]
    fn a_save_waits_for_the_worker_to_publish_the_sheet_as_it_is() {
        let store = SheetStore::default();
        let stop = std::sync::atomic::AtomicBool::new(false);
        std::thread::scope(|s| {
            let worker = s.spawn(|| serving_worker(&store, &stop, 0));
            while !store.worker_live.load(Ordering::Acquire) {
                std::thread::yield_now();
            }
            // Nothing published yet: the save gets the worker's sheet of the moment.
            assert_eq!(stored_frame(&store), None);
            assert!(store.request_fresh(Duration::from_secs(10)));
            let first = stored_frame(&store).expect("the worker published");
            // A later save gets a later sheet, not the first one again.
            std::thread::sleep(Duration::from_millis(5));
            assert!(store.request_fresh(Duration::from_secs(10)));
            let second = stored_frame(&store).expect("the worker published");
            assert!(second > first, "{second} after {first}");
            stop.store(true, Ordering::Release);
            assert_eq!(worker.join().unwrap(), 2, "one publish per save");
        });
        assert_eq!(store.stale_saves(), 0);
        // No worker: the save does not wait and keeps what is stored.
        assert!(store.request_fresh(Duration::from_secs(10)));
    }

    #[test]
    fn a_save_the_worker_does_not_answer_keeps_the_last_sheet() {
        let store = SheetStore::default();
        assert!(store.try_publish(Sim::new(SimConfig::default()).save(), 0));
        // A worker that is live but never serves (an overloaded machine).
        store.set_worker_live(true);
        assert!(!store.request_fresh(Duration::from_millis(20)));
        assert_eq!(store.stale_saves(), 1);
        assert_eq!(stored_frame(&store), Some(0));
        // A worker that stops releases the save at once.
        std::thread::scope(|s| {
            s.spawn(|| {
                std::thread::sleep(Duration::from_millis(20));
                store.set_worker_live(false);
            });
            assert!(store.request_fresh(Duration::from_secs(60)));
        });
    }

    #[test]
    fn a_request_served_after_a_load_keeps_the_loaded_sheet() {
        let store = SheetStore::default();
        let g0 = store.generation();
        store.set_worker_live(true);
        store.save_requested.fetch_add(1, Ordering::AcqRel);
        store.load_json("null");
        // The worker still runs on the old sheet: served, but not stored.
        assert!(store.serve_save_request(g0, || Sim::new(SimConfig::default()).save()));
        assert_eq!(store.get(), StoredSheet::Empty);
        assert_eq!(store.rejected_publishes(), 1);
        // Served once: nothing more to do.
        assert!(!store.serve_save_request(g0, || unreachable!("no request is pending")));
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
