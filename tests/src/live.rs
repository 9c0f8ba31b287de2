//! A host's audio thread for tests that keep audio running while something else happens (the
//! editor opening and closing): `process()` at real-time pace until told to stop, with a
//! repeating gesture, every sample checked and, if asked, recorded.
//!
//! Pacing is what a host does, not a check: a block that comes late is counted and reported,
//! never asserted on (the tests run on shared machines).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use clack_host::prelude::*;

use crate::clap::{HostEvent, TestHost};

/// Block size of the live audio thread, samples.
pub const LIVE_BLOCK: usize = 256;

/// A gesture that repeats every `period` samples.
#[derive(Clone, Debug)]
pub struct Gesture {
    /// Length of one repetition, samples.
    pub period: u64,
    /// The events of one repetition (positions within it, sorted).
    pub events: Vec<HostEvent>,
}

impl Gesture {
    /// Every 2 s at 48 kHz: a fresh sheet, held by its four corners, lifted and shaken, a
    /// crumple wave in the middle, then calm. The sheet keeps moving and sounding, so an
    /// editor has something to show and a glitch something to break.
    pub fn shake_and_crumple() -> Self {
        let block = LIVE_BLOCK as u64;
        let cc = |at: u64, c: u8, v: u8| HostEvent::Midi {
            at: at * block,
            data: [0xB0, c, v],
        };
        let note = |at: u64, key: u8, velocity: f64| HostEvent::NoteOn {
            at: at * block,
            key,
            velocity,
        };
        Self {
            period: 375 * block,
            events: vec![
                note(0, 36, 1.0),
                note(5, 55, 0.8),
                cc(10, 24, 100),
                cc(10, 22, 60),
                cc(150, 20, 90),
                cc(300, 20, 0),
                cc(300, 24, 0),
            ],
        }
    }

    /// Adds the events that fall in `[pos, pos + n)` to `ev`.
    pub fn push_block(&self, ev: &mut EventBuffer, pos: u64, n: u64) {
        let base = pos - pos % self.period;
        for rep in [base, base + self.period] {
            for e in &self.events {
                let at = rep + e.at();
                if (pos..pos + n).contains(&at) {
                    e.push_to(ev, (at - pos) as u32);
                }
            }
        }
    }

    /// The same events as a flat list over `[0, total)` (for [`crate::clap::Instance::render`]).
    pub fn unrolled(&self, total: u64) -> Vec<HostEvent> {
        let mut out = Vec::new();
        let mut rep = 0;
        while rep < total {
            for e in &self.events {
                let mut e = *e;
                let at = rep + e.at();
                if at >= total {
                    continue;
                }
                match &mut e {
                    HostEvent::Midi { at: a, .. }
                    | HostEvent::NoteOn { at: a, .. }
                    | HostEvent::NoteOff { at: a, .. }
                    | HostEvent::Note { at: a, .. }
                    | HostEvent::Param { at: a, .. } => *a = at,
                }
                out.push(e);
            }
            rep += self.period;
        }
        out
    }
}

/// Shared between the live audio thread and the test's main thread.
#[derive(Debug, Default)]
pub struct Live {
    /// Set to stop the audio thread.
    pub stop: AtomicBool,
    /// Blocks processed so far.
    pub blocks: AtomicU64,
}

impl Live {
    /// Waits (polling, up to `timeout`) until at least `n` more blocks than `since` were
    /// processed. Returns whether they were.
    pub fn wait_for_blocks(&self, since: u64, n: u64, timeout: Duration) -> bool {
        let t0 = Instant::now();
        while self.blocks.load(Ordering::Acquire) < since + n {
            if t0.elapsed() > timeout {
                return false;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        true
    }
}

/// Stops a live audio thread however a scope is left (a failed assertion included).
pub struct StopOnDrop<'a>(pub &'a Live);

impl Drop for StopOnDrop<'_> {
    fn drop(&mut self) {
        self.0.stop.store(true, Ordering::Relaxed);
    }
}

/// What the live audio thread saw.
#[derive(Debug, Default)]
pub struct LiveStats {
    /// Whether the thread got real-time scheduling (SCHED_FIFO).
    pub realtime: bool,
    /// Blocks processed.
    pub blocks: u64,
    /// `process()` calls that failed.
    pub errors: u64,
    /// Non-finite output samples.
    pub non_finite: u64,
    /// Largest absolute output sample.
    pub peak: f32,
    /// Longest `process()` call (reported only).
    pub max_process: Duration,
    /// Blocks delivered more than a block late (reported only).
    pub late_blocks: u64,
    /// Wall time of the run.
    pub elapsed: Duration,
    /// The output (left, right) if recording was asked for.
    pub output: Option<(Vec<f32>, Vec<f32>)>,
}

/// Asks for real-time scheduling of the calling thread, as audio hosts do (SCHED_FIFO,
/// priority 20). Returns whether it was granted (it needs CAP_SYS_NICE or an rtprio limit).
fn make_realtime() -> bool {
    #[repr(C)]
    struct SchedParam {
        sched_priority: i32,
    }
    unsafe extern "C" {
        fn pthread_self() -> usize;
        fn pthread_setschedparam(thread: usize, policy: i32, param: *const SchedParam) -> i32;
    }
    const SCHED_FIFO: i32 = 1;
    let param = SchedParam { sched_priority: 20 };
    // SAFETY: plain libc calls on the current thread with a valid parameter block.
    unsafe { pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0 }
}

/// How the live audio thread runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LiveMode {
    /// As a host's real-time audio thread: real-time scheduling if the system grants it.
    RealTime,
    /// As a host rendering offline while the user watches: ordinary scheduling (the plugin
    /// then steps the sheet on this thread, which may take longer than a block), output kept.
    OfflineRecorded,
}

/// The audio thread: blocks of [`LIVE_BLOCK`] samples at `sample_rate` pace with `gesture`,
/// until `live.stop`. Call it on a thread of its own.
pub fn run(
    stopped: StoppedPluginAudioProcessor<TestHost>,
    sample_rate: f64,
    gesture: &Gesture,
    mode: LiveMode,
    live: &Live,
) -> (StoppedPluginAudioProcessor<TestHost>, LiveStats) {
    let record = mode == LiveMode::OfflineRecorded;
    let mut stats = LiveStats {
        realtime: mode == LiveMode::RealTime && make_realtime(),
        ..LiveStats::default()
    };
    let mut proc = stopped.start_processing().expect("start_processing");
    let block_time = Duration::from_secs_f64(LIVE_BLOCK as f64 / sample_rate);
    let (mut l, mut r) = (vec![0.0f32; LIVE_BLOCK], vec![0.0f32; LIVE_BLOCK]);
    let (mut left, mut right) = (Vec::new(), Vec::new());
    if record {
        let minute = (60.0 * sample_rate) as usize;
        left.reserve(minute);
        right.reserve(minute);
    }
    let mut ports = AudioPorts::with_capacity(2, 1);
    let mut ev = EventBuffer::with_capacity(16);
    let mut out_ev = EventBuffer::with_capacity(16);
    let start = Instant::now();
    let mut pos = 0u64;
    while !live.stop.load(Ordering::Relaxed) {
        ev.clear();
        out_ev.clear();
        gesture.push_block(&mut ev, pos, LIVE_BLOCK as u64);
        let t = Instant::now();
        let result = {
            let mut outputs = ports.with_output_buffers([AudioPortBuffer {
                latency: 0,
                channels: AudioPortBufferType::f32_output_only(
                    [&mut l[..], &mut r[..]].into_iter(),
                ),
            }]);
            proc.process(
                &InputAudioBuffers::empty(),
                &mut outputs,
                &ev.as_input(),
                &mut out_ev.as_output(),
                Some(pos),
                None,
            )
        };
        stats.max_process = stats.max_process.max(t.elapsed());
        if result.is_err() {
            stats.errors += 1;
        }
        for s in l.iter().chain(&r) {
            if s.is_finite() {
                stats.peak = stats.peak.max(s.abs());
            } else {
                stats.non_finite += 1;
            }
        }
        if record {
            left.extend_from_slice(&l);
            right.extend_from_slice(&r);
        }
        stats.blocks += 1;
        live.blocks.store(stats.blocks, Ordering::Release);
        pos += LIVE_BLOCK as u64;
        let deadline = start + block_time * stats.blocks as u32;
        let now = Instant::now();
        if now > deadline + block_time {
            stats.late_blocks += 1;
        }
        if deadline > now {
            std::thread::sleep(deadline - now);
        }
    }
    stats.elapsed = start.elapsed();
    if record {
        stats.output = Some((left, right));
    }
    (proc.stop_processing(), stats)
}
