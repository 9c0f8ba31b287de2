//! # Outliving the editor's window threads
//!
//! On Linux the editor's window runs on a thread of its own (baseview's X11 backend), started
//! when the host creates the GUI. When the host destroys the GUI, baseview 0.4.2 stops that
//! thread's event loop and then, before joining the thread, asks the window to show itself;
//! when the loop has already ended, that request fails and the join is skipped. The thread then
//! finishes on its own: it tears its GL context down (EGL unloading the Mesa driver), which
//! takes milliseconds. Seen in the test host (`tests/src/clap_gui.rs`, `close_editor`): a test
//! process that exited meanwhile crashed in that teardown. A host that destroys the plugin and
//! unloads its library right away would pull the code from under the thread the same way.
//!
//! So each window thread counts itself here while it runs ([`WindowThreads::enter`], from the
//! editor's `build`, which runs on it), through a thread-local guard whose destructor runs when
//! the thread exits — after the window, its GL context and everything else the thread owned
//! are gone. The plugin's destructor waits (bounded) until its window threads are gone
//! ([`WindowThreads::wait_until_ended`]); with no window, or after a proper join, it does not
//! wait at all. Only the host's main thread ever waits here, never the audio thread.

use std::cell::RefCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// One plugin instance's editor window threads that are still running.
#[derive(Debug, Default)]
pub struct WindowThreads {
    live: AtomicUsize,
}

/// Counts its thread until the thread exits.
struct Guard(Arc<WindowThreads>);

impl Drop for Guard {
    fn drop(&mut self) {
        self.0.live.fetch_sub(1, Ordering::AcqRel);
    }
}

thread_local! {
    /// The guard of the window thread this is (none on other threads).
    static GUARD: RefCell<Option<Guard>> = const { RefCell::new(None) };
}

impl WindowThreads {
    /// Counts the calling thread as a window thread of this instance until it exits (once per
    /// thread; a thread already counted is not counted again).
    pub fn enter(self: &Arc<Self>) {
        GUARD.with(|g| {
            let mut g = g.borrow_mut();
            if g.is_none() {
                self.live.fetch_add(1, Ordering::AcqRel);
                *g = Some(Guard(Arc::clone(self)));
            }
        });
    }

    /// Window threads still running.
    pub fn live(&self) -> usize {
        self.live.load(Ordering::Acquire)
    }

    /// Waits, polling, until no window thread runs or `patience` has passed; returns whether
    /// none runs.
    pub fn wait_until_ended(&self, patience: Duration) -> bool {
        let t0 = Instant::now();
        while self.live() > 0 {
            if t0.elapsed() >= patience {
                return false;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_thread_counts_until_it_has_exited() {
        let threads = Arc::new(WindowThreads::default());
        assert!(
            threads.wait_until_ended(Duration::ZERO),
            "nothing to wait for"
        );
        let (entered_tx, entered_rx) = std::sync::mpsc::channel();
        let (go_tx, go_rx) = std::sync::mpsc::channel::<()>();
        let t = Arc::clone(&threads);
        let handle = std::thread::spawn(move || {
            t.enter();
            t.enter(); // counted once
            entered_tx.send(()).unwrap();
            go_rx.recv().unwrap();
        });
        entered_rx.recv().unwrap();
        assert_eq!(threads.live(), 1);
        assert!(
            !threads.wait_until_ended(Duration::from_millis(20)),
            "the thread still runs"
        );
        go_tx.send(()).unwrap();
        // Not joined: the count alone tells when the thread has gone.
        assert!(threads.wait_until_ended(Duration::from_secs(10)));
        assert_eq!(threads.live(), 0);
        handle.join().unwrap();
    }

    #[test]
    fn threads_of_other_instances_are_not_waited_for() {
        let (mine, other) = (
            Arc::new(WindowThreads::default()),
            Arc::new(WindowThreads::default()),
        );
        let (tx, rx) = std::sync::mpsc::channel::<()>();
        let o = Arc::clone(&other);
        let handle = std::thread::spawn(move || {
            o.enter();
            rx.recv().unwrap();
        });
        while other.live() == 0 {
            std::thread::yield_now();
        }
        assert!(mine.wait_until_ended(Duration::ZERO));
        tx.send(()).unwrap();
        handle.join().unwrap();
        assert_eq!(other.live(), 0);
    }
}
