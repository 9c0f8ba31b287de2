//! # MIDI volume changes, each at its sample
//!
//! The sheet's commands are stamped with the sample their MIDI message carries and applied at
//! the frame boundary they fall before ([`super::frame_clock`]). The MIDI volume (CC 7, and the
//! reset of all controllers, which sets it back to 1) acts on the render path's mix instead, so
//! it is kept here, stamped the same way, and [`super::Engine::render`] splits its block at each
//! change: the mix's 10 ms glide starts at the message's own sample.
//!
//! A change taking effect at the start of the block that carries it would let the host's block
//! boundaries decide where the glide begins, and a render would depend on the block size
//! (docs/decisions.md, "Smaller rules and the runs that found them").
//!
//! The queue is fixed-size ([`CAPACITY`] changes, no allocation on the audio thread). A block
//! carrying more changes than that gives up on the oldest: it takes effect at once, which is
//! inaudible beside the 10 ms glide of the mix.

/// Volume changes kept at once.
pub const CAPACITY: usize = 64;

/// Pending volume changes, in sample order.
#[derive(Clone, Debug)]
pub struct VolumeChanges {
    at: [u64; CAPACITY],
    gain: [f32; CAPACITY],
    head: usize,
    len: usize,
}

impl Default for VolumeChanges {
    fn default() -> Self {
        Self {
            at: [0; CAPACITY],
            gain: [0.0; CAPACITY],
            head: 0,
            len: 0,
        }
    }
}

impl VolumeChanges {
    /// Queues the linear gain `gain` from sample `at`. A time before the last queued one counts
    /// as that one (MIDI messages come in time order; this keeps the queue ordered whatever
    /// arrives). When the queue is full, the oldest change is taken out and returned: the caller
    /// applies it now. No allocation.
    pub fn push(&mut self, at: u64, gain: f32) -> Option<f32> {
        let early = if self.len == CAPACITY {
            self.pop()
        } else {
            None
        };
        let at = match self.last_at() {
            Some(last) => at.max(last),
            None => at,
        };
        let k = (self.head + self.len) % CAPACITY;
        self.at[k] = at;
        self.gain[k] = gain;
        self.len += 1;
        early
    }

    /// Takes out every change due at or before sample `now`; returns the latest one's gain.
    pub fn take_due(&mut self, now: u64) -> Option<f32> {
        let mut latest = None;
        while self.next_at().is_some_and(|at| at <= now) {
            latest = self.pop();
        }
        latest
    }

    /// The sample of the next pending change.
    pub fn next_at(&self) -> Option<u64> {
        (self.len > 0).then(|| self.at[self.head])
    }

    /// Number of pending changes.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when nothing is pending.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    fn last_at(&self) -> Option<u64> {
        (self.len > 0).then(|| self.at[(self.head + self.len - 1) % CAPACITY])
    }

    fn pop(&mut self) -> Option<f32> {
        if self.len == 0 {
            return None;
        }
        let g = self.gain[self.head];
        self.head = (self.head + 1) % CAPACITY;
        self.len -= 1;
        Some(g)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn changes_come_out_at_their_samples_and_the_latest_due_wins() {
        let mut q = VolumeChanges::default();
        assert_eq!(q.push(100, 0.5), None);
        assert_eq!(q.push(100, 0.25), None);
        assert_eq!(q.push(250, 1.0), None);
        assert_eq!(q.next_at(), Some(100));
        assert_eq!(q.take_due(99), None);
        assert_eq!(q.take_due(100), Some(0.25));
        assert_eq!(q.next_at(), Some(250));
        assert_eq!(q.take_due(1000), Some(1.0));
        assert!(q.is_empty());
        assert_eq!(q.next_at(), None);
    }

    #[test]
    fn an_earlier_time_keeps_the_order_and_a_full_queue_gives_up_the_oldest() {
        let mut q = VolumeChanges::default();
        q.push(500, 0.1);
        q.push(20, 0.2);
        assert_eq!(q.take_due(499), None);
        assert_eq!(q.take_due(500), Some(0.2));
        for k in 0..CAPACITY {
            assert_eq!(q.push(1000 + k as u64, k as f32), None);
        }
        assert_eq!(q.len(), CAPACITY);
        assert_eq!(q.push(5000, 99.0), Some(0.0));
        assert_eq!(q.len(), CAPACITY);
        assert_eq!(q.next_at(), Some(1001));
        assert_eq!(q.take_due(u64::MAX), Some(99.0));
    }
}
