//! # Meters: engine figures for the editor and the renderer's report
//!
//! Plain atomics written by whoever runs the simulation (worker or audio thread) and by the
//! audio thread, read by the editor. Relaxed ordering: these are displays, not synchronisation.

use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};

/// Engine meters.
#[derive(Debug, Default)]
pub struct Meters {
    /// Frames stepped.
    pub frames_stepped: AtomicU64,
    /// Frames skipped because the simulation fell behind real time.
    pub frames_skipped: AtomicU64,
    /// Frames in which the sheet slept.
    pub frames_asleep: AtomicU64,
    /// Last frame's step time, nanoseconds.
    pub last_step_ns: AtomicU64,
    /// Sum of all step times, nanoseconds.
    pub total_step_ns: AtomicU64,
    /// Longest step time, nanoseconds.
    pub max_step_ns: AtomicU64,
    /// Commands lost because the command queue was full.
    pub commands_dropped: AtomicU64,
    /// Events lost because the event queue was full.
    pub events_dropped: AtomicU64,
    /// Crumple events delivered to the render path.
    pub crumple_events: AtomicU64,
    /// Friction sources delivered to the render path, summed over frames.
    pub friction_sources: AtomicU64,
    /// Frames in which the sheet was tearing.
    pub tear_frames: AtomicU64,
    /// Tear onsets (a tip that starts moving after standing still).
    pub tear_onsets: AtomicU64,
    /// Audio-thread load: time in `process()` / block duration (f32 bits; smoothed).
    pub audio_load_bits: AtomicU32,
    /// Interior singular vertices of the current sheet.
    pub num_singular: AtomicU32,
    /// Mean edge compression of the current sheet, % (f32 bits).
    pub c_mean_pct_bits: AtomicU32,
    /// Output peak of the last block (f32 bits).
    pub peak_bits: AtomicU32,
    /// Largest output peak since the editor last took it (f32 bits; see [`Meters::record_peak`]).
    pub peak_hold_bits: AtomicU32,
    /// Phrases started from notes.
    pub phrase_hits: AtomicU64,
    /// Notes whose phrase is playing: bit `n` of word `n / 64`.
    pub phrase_notes: [AtomicU64; 2],
    /// Is the worker thread running?
    pub worker_running: AtomicBool,
    /// Worker threads started since the plugin was created.
    pub workers_started: AtomicU64,
    /// Worker threads joined since the plugin was created.
    pub workers_joined: AtomicU64,
}

impl Meters {
    /// Records one stepped frame.
    pub fn record_step(&self, step_ns: u64, asleep: bool, num_singular: u32, c_mean_pct: f32) {
        self.frames_stepped.fetch_add(1, Ordering::Relaxed);
        if asleep {
            self.frames_asleep.fetch_add(1, Ordering::Relaxed);
        }
        self.last_step_ns.store(step_ns, Ordering::Relaxed);
        self.total_step_ns.fetch_add(step_ns, Ordering::Relaxed);
        self.max_step_ns.fetch_max(step_ns, Ordering::Relaxed);
        self.num_singular.store(num_singular, Ordering::Relaxed);
        self.c_mean_pct_bits
            .store(c_mean_pct.to_bits(), Ordering::Relaxed);
    }

    /// Is the phrase on `note` playing?
    pub fn phrase_playing(&self, note: u8) -> bool {
        let n = usize::from(note.min(127));
        self.phrase_notes[n / 64].load(Ordering::Relaxed) & (1 << (n % 64)) != 0
    }

    /// Mean edge compression of the current sheet, %.
    pub fn c_mean_pct(&self) -> f32 {
        f32::from_bits(self.c_mean_pct_bits.load(Ordering::Relaxed))
    }

    /// Output peak of the last block.
    pub fn peak(&self) -> f32 {
        f32::from_bits(self.peak_bits.load(Ordering::Relaxed))
    }

    /// Records the output peak of a block (audio thread: two lock-free atomic operations). The
    /// editor repaints less often than blocks arrive, so besides the last block's peak the
    /// largest peak since the editor last looked is kept ([`Meters::take_peak_hold`]).
    pub fn record_peak(&self, peak: f32) {
        let peak = if peak.is_finite() { peak.abs() } else { 0.0 };
        self.peak_bits.store(peak.to_bits(), Ordering::Relaxed);
        // Non-negative finite floats order like their bit patterns.
        self.peak_hold_bits
            .fetch_max(peak.to_bits(), Ordering::Relaxed);
    }

    /// The largest output peak since the previous call (editor).
    pub fn take_peak_hold(&self) -> f32 {
        f32::from_bits(self.peak_hold_bits.swap(0, Ordering::Relaxed))
    }

    /// Records one frame's sound input (for the events-per-second meters).
    pub fn record_sound(&self, sound: &sim_core::SoundFrame) {
        self.crumple_events
            .fetch_add(sound.crumple().len() as u64, Ordering::Relaxed);
        self.friction_sources
            .fetch_add(sound.friction().len() as u64, Ordering::Relaxed);
        if sound.tear.speed_m_s > 0.0 {
            self.tear_frames.fetch_add(1, Ordering::Relaxed);
        }
        if sound.tear.onset {
            self.tear_onsets.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Records the audio thread's time for one block (one-pole smoothing over ~10 blocks).
    pub fn record_audio_load(&self, busy_s: f64, block_s: f64) {
        if block_s <= 0.0 {
            return;
        }
        let now = (busy_s / block_s) as f32;
        let old = f32::from_bits(self.audio_load_bits.load(Ordering::Relaxed));
        let new = if old.is_finite() {
            old + 0.1 * (now - old)
        } else {
            now
        };
        self.audio_load_bits.store(new.to_bits(), Ordering::Relaxed);
    }

    /// Smoothed audio-thread load (1.0 = the whole block duration).
    pub fn audio_load(&self) -> f32 {
        f32::from_bits(self.audio_load_bits.load(Ordering::Relaxed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peak_hold_keeps_the_largest_peak_until_taken() {
        let m = Meters::default();
        m.record_peak(0.25);
        m.record_peak(0.5);
        m.record_peak(0.125);
        assert_eq!(m.peak(), 0.125, "the last block's peak");
        assert_eq!(m.take_peak_hold(), 0.5, "the largest since the last look");
        assert_eq!(m.take_peak_hold(), 0.0);
        m.record_peak(f32::NAN);
        assert_eq!(m.take_peak_hold(), 0.0);
    }
}
