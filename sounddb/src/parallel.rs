//! # One function over many items, on the machine's cores, in the items' order
//!
//! Loading and preparing a database does the same work on each of hundreds of units whose
//! lengths differ tenfold; [`map`] runs it on up to four threads (this one included), each taking
//! the next item as it is free, so no core waits on another's long units. Each item is computed on
//! its own, so the result does not depend on the threads. Off the audio thread only (it spawns).

use std::sync::atomic::{AtomicUsize, Ordering};

/// Threads at most (a database's preparation gains little beyond).
const MAX_THREADS: usize = 4;
/// Items per thread at least (fewer run on this thread alone).
const MIN_ITEMS_PER_THREAD: usize = 8;

/// `f` of every item, in the items' order.
pub fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, MAX_THREADS)
        .min(items.len().div_ceil(MIN_ITEMS_PER_THREAD).max(1));
    if threads <= 1 {
        return items.iter().map(&f).collect();
    }
    let next = AtomicUsize::new(0);
    let work = || {
        let mut done = Vec::new();
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(item) = items.get(i) else {
                return done;
            };
            done.push((i, f(item)));
        }
    };
    let mut slots: Vec<Option<R>> = Vec::new();
    slots.resize_with(items.len(), || None);
    std::thread::scope(|s| {
        let helpers: Vec<_> = (1..threads).map(|_| s.spawn(work)).collect();
        let mut parts = vec![work()];
        // A helper that failed (it cannot, short of memory) leaves its items to the loop below.
        parts.extend(helpers.into_iter().filter_map(|h| h.join().ok()));
        for (i, r) in parts.into_iter().flatten() {
            slots[i] = Some(r);
        }
    });
    slots
        .into_iter()
        .zip(items)
        .map(|(r, item)| r.unwrap_or_else(|| f(item)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_item_once_in_order() {
        for n in [0, 1, 7, 8, 9, 100, 1001] {
            let items: Vec<u64> = (0..n).collect();
            let calls = AtomicUsize::new(0);
            let out = map(&items, |x| {
                calls.fetch_add(1, Ordering::Relaxed);
                x * x + 1
            });
            assert_eq!(out, items.iter().map(|x| x * x + 1).collect::<Vec<_>>());
            assert_eq!(calls.load(Ordering::Relaxed), n as usize);
        }
    }
}
