//! The plugin's phrase bank and its hand-off to the audio thread.
//!
//! The bank is built off the audio thread: when the plugin is created, at each activation if the
//! user's folder changed, and when the editor asks (**Reload**). A new bank goes to the audio
//! thread through a one-slot lock-free queue, and the bank it replaces comes back through another
//! to be dropped here; the mutex that holds the bank the editor shows is never taken by the audio
//! thread.
//!
//! The user's folder: `$PAPIER_PHRASE_DIR` if set; else `$XDG_CONFIG_HOME/papier/phrases` or
//! `~/.config/papier/phrases` (Linux), `~/Library/Application Support/Papier/phrases` (macOS),
//! `%APPDATA%\Papier\phrases` (Windows).

use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::SystemTime;

use crossbeam_queue::ArrayQueue;

use super::bank::PhraseBank;

/// The user's phrase folder (see the module docs); `None` when no home is known.
pub fn user_phrase_dir() -> Option<PathBuf> {
    let var = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    if let Some(d) = var("PAPIER_PHRASE_DIR") {
        return Some(d);
    }
    if cfg!(target_os = "windows") {
        return var("APPDATA").map(|d| d.join("Papier").join("phrases"));
    }
    if cfg!(target_os = "macos") {
        return var("HOME").map(|h| {
            h.join("Library")
                .join("Application Support")
                .join("Papier")
                .join("phrases")
        });
    }
    var("XDG_CONFIG_HOME")
        .or_else(|| var("HOME").map(|h| h.join(".config")))
        .map(|c| c.join("papier").join("phrases"))
}

/// The newest modification time in a folder (itself and its `.toml` files), if readable.
fn folder_stamp(dir: &std::path::Path) -> Option<SystemTime> {
    let mut newest = std::fs::metadata(dir).and_then(|m| m.modified()).ok()?;
    for e in std::fs::read_dir(dir).ok()?.flatten() {
        if let Ok(t) = e.metadata().and_then(|m| m.modified()) {
            newest = newest.max(t);
        }
    }
    Some(newest)
}

/// The phrase bank shared by the editor, `activate()` and the audio thread.
pub struct PhraseShelf {
    dir: Option<PathBuf>,
    /// The bank the editor shows and an activation starts with, and the folder's stamp then.
    current: Mutex<(Arc<PhraseBank>, Option<SystemTime>)>,
    /// A new bank for the audio thread.
    pub ready: ArrayQueue<Arc<PhraseBank>>,
    /// Banks the audio thread let go of, to be dropped off it.
    pub retired: ArrayQueue<Arc<PhraseBank>>,
}

impl PhraseShelf {
    /// A shelf over a user folder (`None`: the factory phrases only), loaded now.
    pub fn new(dir: Option<PathBuf>) -> Self {
        let shelf = Self {
            dir,
            current: Mutex::new((Arc::new(PhraseBank::default()), None)),
            ready: ArrayQueue::new(1),
            retired: ArrayQueue::new(4),
        };
        shelf.load();
        shelf
    }

    /// The user's folder.
    pub fn dir(&self) -> Option<&std::path::Path> {
        self.dir.as_deref()
    }

    /// The bank in use.
    pub fn current(&self) -> Arc<PhraseBank> {
        self.current
            .lock()
            .map(|c| c.0.clone())
            .unwrap_or_else(|p| p.into_inner().0.clone())
    }

    fn load(&self) -> Arc<PhraseBank> {
        let stamp = self.dir.as_deref().and_then(folder_stamp);
        let bank = Arc::new(match &self.dir {
            Some(d) => PhraseBank::with_folder(d),
            None => PhraseBank::factory(),
        });
        let mut c = self.current.lock().unwrap_or_else(|p| p.into_inner());
        *c = (bank.clone(), stamp);
        bank
    }

    /// Reads the folder again and sends the new bank to the audio thread (replacing one it has
    /// not taken yet). Not on the audio thread.
    pub fn reload(&self) {
        let bank = self.load();
        while self.retired.pop().is_some() {}
        let _ = self.ready.force_push(bank);
    }

    /// [`Self::reload`] if the folder changed since the last load; true if it did.
    pub fn reload_if_changed(&self) -> bool {
        let stamp = self.dir.as_deref().and_then(folder_stamp);
        let old = self.current.lock().map(|c| c.1).unwrap_or(None);
        if stamp != old {
            self.reload();
            true
        } else {
            false
        }
    }

    /// Drops the banks the audio thread gave back (call off the audio thread).
    pub fn drain_retired(&self) {
        while self.retired.pop().is_some() {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_changed_folder_is_reloaded_and_handed_over() {
        let dir = std::env::temp_dir().join(format!("papier-shelf-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let shelf = PhraseShelf::new(Some(dir.clone()));
        assert!(
            shelf
                .current()
                .get(60)
                .is_some_and(|p| p.name == "page turn")
        );
        assert!(!shelf.reload_if_changed(), "nothing changed");
        std::thread::sleep(std::time::Duration::from_millis(20));
        std::fs::write(
            dir.join("mine.toml"),
            "version = 1\n[phrase]\nnote = 100\n[[lane]]\nid = \"lift\"\npoints = [[0, 0.5]]\n",
        )
        .unwrap();
        assert!(shelf.reload_if_changed());
        let handed = shelf.ready.pop().expect("a bank for the audio thread");
        assert_eq!(handed.get(100).map(|p| p.name.as_str()), Some("mine"));
        assert!(Arc::ptr_eq(&handed, &shelf.current()));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
