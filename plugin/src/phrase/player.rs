//! Phrases playing: note-ons start prepared phrases, each frame start gets their lanes' values,
//! their grabs and resets land at their samples. Allocation-free (a fixed set of voices).
//!
//! - **Velocity** scales intensity: the amplitude of the intensity gestures (crumple, slide,
//!   lift, twist, shake depth, pull separation) about their neutral values by
//!   `a = 1 + 0.85·(v − 100/127)` and the phrase's speed (its time axis, the shake rate and the
//!   grips) by `s = 1 + 0.6·(v − 100/127)`: velocity 100 plays the phrase as written, 30 at 0.53
//!   of its amplitude and 0.67 of its speed, 127 at 1.18 and 1.13. Positions (tear position,
//!   steer, asymmetry) and the tear's extent are never scaled: a soft "quick tear" still tears
//!   through, only slower.
//! - **Round-robin**: hit `n` of an instance gets seed `mix(instance seed, phrase seed, n)`; a
//!   fresh phrase builds its sheet with it (new singular points, another crumple), and every
//!   phrase varies its amplitude by ±8 % and speed by ±5 % with it. The same performance gives
//!   the same hits, so the same bits.
//! - **Timing**: lane values are sent at the frame starts (the sheet reads gestures once per
//!   frame) whenever they change, as the offline timeline does for scripts; steps land at their
//!   samples. Commands leave in sample order across voices, so the engine's FIFO applies each in
//!   its frame.
//! - A phrase's end lets go of the hands it still holds; with `note_off = "release"` they hold
//!   (lanes at their last values) until the note-off. A reset (note 36), CC 121 and all-notes-off
//!   stop every phrase; a note struck again restarts its phrase; a ninth voice takes the oldest.

use std::sync::Arc;

use sim_core::{Command, GestureParam, GrabSlot};

use super::bank::PhraseBank;
use super::spec::{NoteOffRule, Phrase, PhraseEvent, PhraseStart};
use crate::engine::{FrameClock, ParamValues};

/// Phrases that can play at once.
pub const MAX_PHRASE_VOICES: usize = 8;

/// Velocity that plays a phrase as written (MIDI 100).
const REFERENCE_VELOCITY: f32 = 100.0 / 127.0;

/// Amplitude change per unit of velocity.
const AMPLITUDE_PER_VELOCITY: f32 = 0.85;

/// Speed change per unit of velocity.
const SPEED_PER_VELOCITY: f32 = 0.6;

/// Round-robin variation of the amplitude (±) and the speed (±).
const HIT_AMPLITUDE_SPREAD: f32 = 0.08;
const HIT_SPEED_SPREAD: f32 = 0.05;

/// The slowest a phrase plays (velocity 0, the slowest hit): its length is at most its written
/// length divided by this.
pub const SLOWEST_SPEED: f32 =
    (1.0 - SPEED_PER_VELOCITY * REFERENCE_VELOCITY) * (1.0 - HIT_SPEED_SPREAD);

/// The gestures whose amplitude velocity scales.
const fn is_intensity(g: GestureParam) -> bool {
    matches!(
        g,
        GestureParam::Crumple
            | GestureParam::Slide
            | GestureParam::Lift
            | GestureParam::Twist
            | GestureParam::ShakeDepth
            | GestureParam::PullSeparation
    )
}

/// The speed factor a velocity (0–1) gives, before the hit's variation.
pub fn speed_for_velocity(velocity: f32) -> f32 {
    1.0 + SPEED_PER_VELOCITY * (velocity.clamp(0.0, 1.0) - REFERENCE_VELOCITY)
}

/// The amplitude factor a velocity (0–1) gives, before the hit's variation.
pub fn amplitude_for_velocity(velocity: f32) -> f32 {
    1.0 + AMPLITUDE_PER_VELOCITY * (velocity.clamp(0.0, 1.0) - REFERENCE_VELOCITY)
}

/// SplitMix64: one well-mixed word from a counter.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A uniform number in [−1, 1) from a word.
fn unit(z: u64) -> f32 {
    ((z >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
}

#[derive(Clone, Copy, Debug)]
struct Voice {
    /// Index into the bank.
    phrase: usize,
    note: u8,
    /// Sample of the note-on.
    start: u64,
    /// Amplitude and speed factors.
    amp: f32,
    speed: f64,
    /// This hit's seed.
    seed: u64,
    /// Next event to send.
    next_event: usize,
    /// Initial commands sent.
    started: bool,
    /// Values last sent per gesture (bits), or `u32::MAX` for none.
    sent: [u32; GestureParam::COUNT],
    /// Slots this phrase holds (bit per [`GrabSlot::ALL`] index).
    held: u8,
    /// Start order (the oldest voice is taken when all are busy).
    age: u64,
}

fn slot_bit(slot: GrabSlot) -> u8 {
    1 << GrabSlot::ALL.iter().position(|s| *s == slot).unwrap_or(0)
}

/// The voices playing phrases.
pub struct PhrasePlayer {
    bank: Arc<PhraseBank>,
    voices: [Option<Voice>; MAX_PHRASE_VOICES],
    /// Commands are sent for samples below this.
    sent_until: u64,
    /// Hits so far (the round-robin counter).
    hits: u64,
    /// Voices started so far (their age order).
    started: u64,
}

impl PhrasePlayer {
    /// A player with a bank.
    pub fn new(bank: Arc<PhraseBank>) -> Self {
        Self {
            bank,
            voices: [None; MAX_PHRASE_VOICES],
            sent_until: 0,
            hits: 0,
            started: 0,
        }
    }

    /// The bank.
    pub fn bank(&self) -> &Arc<PhraseBank> {
        &self.bank
    }

    /// Replaces the bank (every phrase stops); returns the old one, to be dropped off the audio
    /// thread.
    pub fn swap_bank(&mut self, bank: Arc<PhraseBank>) -> Arc<PhraseBank> {
        self.voices = [None; MAX_PHRASE_VOICES];
        std::mem::replace(&mut self.bank, bank)
    }

    /// Phrases playing now.
    pub fn playing(&self) -> usize {
        self.voices.iter().flatten().count()
    }

    /// Hits so far.
    pub fn hits(&self) -> u64 {
        self.hits
    }

    /// The notes whose phrase is playing: bit `n` of word `n / 64`.
    pub fn notes_playing(&self) -> [u64; 2] {
        let mut bits = [0u64; 2];
        for v in self.voices.iter().flatten() {
            let n = usize::from(v.note.min(127));
            bits[n / 64] |= 1 << (n % 64);
        }
        bits
    }

    /// A note-on at sample `at`: starts the note's phrase, if any. True if one started.
    pub fn note_on(&mut self, at: u64, note: u8, velocity: f32, instance_seed: u64) -> bool {
        let Some(index) = self.bank.index_of(note) else {
            return false;
        };
        let phrase = &self.bank.phrases()[index];
        let v = if velocity.is_finite() {
            velocity.clamp(0.0, 1.0)
        } else {
            REFERENCE_VELOCITY
        };
        self.hits += 1;
        let seed = mix(instance_seed ^ mix(phrase.seed) ^ mix(self.hits.wrapping_mul(0x2545_f491)));
        let amp = amplitude_for_velocity(v) * (1.0 + HIT_AMPLITUDE_SPREAD * unit(mix(seed ^ 1)));
        let speed = speed_for_velocity(v) * (1.0 + HIT_SPEED_SPREAD * unit(mix(seed ^ 2)));
        let voice = Voice {
            phrase: index,
            note,
            start: at.max(self.sent_until),
            amp: amp.max(0.05),
            speed: f64::from(speed.max(SLOWEST_SPEED)),
            seed,
            next_event: 0,
            started: false,
            sent: [u32::MAX; GestureParam::COUNT],
            held: 0,
            age: self.started,
        };
        self.started += 1;
        // The same note restarts; else a free voice; else the oldest.
        let slot = self
            .voices
            .iter()
            .position(|v| v.is_some_and(|v| v.note == note))
            .or_else(|| self.voices.iter().position(Option::is_none))
            .unwrap_or_else(|| {
                (0..MAX_PHRASE_VOICES)
                    .min_by_key(|&i| self.voices[i].map_or(0, |v| v.age))
                    .unwrap_or(0)
            });
        self.voices[slot] = Some(voice);
        true
    }

    /// A note-off at sample `at`: a release-rule phrase lets go of its hands and stops.
    pub fn note_off(&mut self, at: u64, note: u8, mut send: impl FnMut(u64, Command)) {
        for slot in &mut self.voices {
            let Some(v) = slot else { continue };
            if v.note != note || self.bank.phrases()[v.phrase].note_off != NoteOffRule::Release {
                continue;
            }
            release_held(v, at.max(self.sent_until), &mut send);
            *slot = None;
        }
    }

    /// Stops every phrase (its hands are left to the caller's reset or release).
    pub fn stop_all(&mut self) {
        self.voices = [None; MAX_PHRASE_VOICES];
    }

    /// Sends every phrase command stamped before sample `to`, in sample order.
    pub fn advance(
        &mut self,
        to: u64,
        frames: &FrameClock,
        params: &ParamValues,
        mut send: impl FnMut(u64, Command),
    ) {
        let from = self.sent_until;
        if to <= from {
            return;
        }
        self.sent_until = to;
        if self.voices.iter().all(Option::is_none) {
            return;
        }
        let rate = frames.sample_rate_hz();
        let phrases = self.bank.phrases();
        // The frame holding `from`.
        let mut k = (from as f64 / frames.samples_per_frame()).floor() as u64;
        while k > 0 && frames.start(k) > from {
            k -= 1;
        }
        while frames.start(k + 1) <= from {
            k += 1;
        }
        loop {
            let seg_start = from.max(frames.start(k));
            let seg_end = to.min(frames.start(k + 1));
            if seg_start >= to {
                break;
            }
            let frame_start = frames.start(k);
            for slot in &mut self.voices {
                let Some(v) = slot else { continue };
                let p = &phrases[v.phrase];
                // The note-on: the fresh sheet and the initial gestures.
                if !v.started && (seg_start..seg_end).contains(&v.start) {
                    v.started = true;
                    start_commands(v, p, params, &mut send);
                }
                if !v.started {
                    continue;
                }
                // Lane values at the frame start.
                if frame_start > v.start && (seg_start..seg_end).contains(&frame_start) {
                    let t = (frame_start - v.start) as f64 / rate * v.speed;
                    send_lanes(v, p, t, frame_start, &mut send);
                }
                // Steps due in this segment.
                while let Some(&(t, e)) = p.events.get(v.next_event) {
                    let at = v.start + (t / v.speed * rate).round() as u64;
                    if at >= seg_end {
                        break;
                    }
                    v.next_event += 1;
                    match e {
                        PhraseEvent::Reset => send(at, Command::Reset),
                        PhraseEvent::Grab(s, grip) => {
                            v.held |= slot_bit(s);
                            let grip = (grip * v.speed as f32).clamp(0.0, 1.0);
                            send(at, Command::Grab { slot: s, grip });
                        }
                        PhraseEvent::Release(s) => {
                            v.held &= !slot_bit(s);
                            send(at, Command::Release { slot: s });
                        }
                        PhraseEvent::Material(m) => send(at, Command::Material(m)),
                        PhraseEvent::Size(z) => send(at, Command::Size(z)),
                    }
                }
                // The end.
                let end = v.start + (p.duration_s / v.speed * rate).round() as u64;
                if p.note_off == NoteOffRule::Finish
                    && v.next_event >= p.events.len()
                    && end < seg_end
                {
                    release_held(v, end.max(seg_start), &mut send);
                    *slot = None;
                }
            }
            if seg_end >= to {
                break;
            }
            k += 1;
        }
    }
}

fn release_held(v: &mut Voice, at: u64, send: &mut impl FnMut(u64, Command)) {
    for s in GrabSlot::ALL {
        if v.held & slot_bit(s) != 0 {
            send(at, Command::Release { slot: s });
        }
    }
    v.held = 0;
}

/// The note-on's commands: a fresh sheet (fresh phrases), the material, the gestures' start.
fn start_commands(
    v: &mut Voice,
    p: &Phrase,
    params: &ParamValues,
    send: &mut impl FnMut(u64, Command),
) {
    let at = v.start;
    if let Some(m) = p.material {
        send(at, Command::Material(m));
    }
    if p.start == PhraseStart::Fresh {
        send(at, Command::ReleaseAll);
        send(at, Command::Seed(v.seed));
        send(at, Command::Size(p.size.unwrap_or(params.size)));
        send(at, Command::Reset);
        // Gestures the phrase does not set start from the instance's parameter values.
        for g in GestureParam::ALL {
            let set =
                p.initial.iter().any(|(h, _)| *h == g) || p.lanes.iter().any(|l| l.gesture == g);
            if !set {
                send(
                    at,
                    Command::Gesture {
                        param: g,
                        value: params.gestures[g.index()],
                    },
                );
            }
        }
    }
    for &(g, x) in &p.initial {
        if !p.lanes.iter().any(|l| l.gesture == g) {
            let value = scaled(g, x, v);
            v.sent[g.index()] = value.to_bits();
            send(at, Command::Gesture { param: g, value });
        }
    }
    send_lanes(v, p, 0.0, at, send);
}

/// Sends the lanes' values at phrase time `t_s` where they changed.
fn send_lanes(v: &mut Voice, p: &Phrase, t_s: f64, at: u64, send: &mut impl FnMut(u64, Command)) {
    for lane in &p.lanes {
        let value = scaled(lane.gesture, lane.value_at(t_s), v);
        let i = lane.gesture.index();
        if v.sent[i] != value.to_bits() {
            v.sent[i] = value.to_bits();
            send(
                at,
                Command::Gesture {
                    param: lane.gesture,
                    value,
                },
            );
        }
    }
}

/// A gesture value scaled by the hit's amplitude (intensity gestures, about their neutral
/// value) or speed (the shake rate), clamped to its range.
fn scaled(g: GestureParam, x: f32, v: &Voice) -> f32 {
    let (lo, hi) = g.range();
    let y = if is_intensity(g) {
        let n = g.default_value();
        n + (x - n) * v.amp
    } else if g == GestureParam::ShakeRateHz {
        x * v.speed as f32
    } else {
        x
    };
    y.clamp(lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::phrase::spec::Phrase;

    fn bank(text: &str) -> Arc<PhraseBank> {
        Arc::new(PhraseBank::from_phrases(vec![
            Phrase::parse(text, "t.toml", "t").unwrap(),
        ]))
    }

    const CRUMPLE: &str = r#"
version = 1
duration_s = 1.0
[phrase]
note = 60
[[lane]]
id = "crumple"
points = [[0.0, 0.0], [0.5, 0.6]]
[[grab]]
slot = "back"
on_s = 0.1
"#;

    fn play(p: &mut PhrasePlayer, to: u64, block: u64) -> Vec<(u64, Command)> {
        let frames = FrameClock::new(48_000.0, 200.0);
        let params = ParamValues::default();
        let mut out = Vec::new();
        let mut at = p.sent_until;
        while at < to {
            at = (at + block).min(to);
            p.advance(at, &frames, &params, |s, c| out.push((s, c)));
        }
        out
    }

    #[test]
    fn a_phrase_sends_its_lanes_at_frame_starts_in_order_at_any_block_size() {
        let mut runs = Vec::new();
        for block in [1, 64, 480, 4096, 48_000] {
            let mut p = PhrasePlayer::new(bank(CRUMPLE));
            assert!(p.note_on(100, 60, REFERENCE_VELOCITY, 1));
            let out = play(&mut p, 72_000, block);
            assert!(out.windows(2).all(|w| w[0].0 <= w[1].0), "sample order");
            assert_eq!(p.playing(), 0, "the phrase ended");
            runs.push(out);
        }
        assert!(
            runs.windows(2).all(|w| w[0] == w[1]),
            "block size changes nothing"
        );
        let out = &runs[0];
        // Grab, then the release at the end (the phrase's hands let go).
        let grabs: Vec<_> = out
            .iter()
            .filter(|(_, c)| matches!(c, Command::Grab { .. }))
            .collect();
        let releases: Vec<_> = out
            .iter()
            .filter(|(_, c)| matches!(c, Command::Release { .. }))
            .collect();
        assert_eq!((grabs.len(), releases.len()), (1, 1));
        assert!(releases[0].0 > grabs[0].0);
        // Crumple rises to about 0.6 (the hit's ±8 % variation).
        let last = out
            .iter()
            .rev()
            .find_map(|(_, c)| match c {
                Command::Gesture {
                    param: GestureParam::Crumple,
                    value,
                } => Some(*value),
                _ => None,
            })
            .unwrap();
        assert!((last - 0.6).abs() < 0.06, "{last}");
    }

    #[test]
    fn velocity_scales_amplitude_and_speed_and_hits_differ() {
        let peak_and_end = |velocity: f32, hits: usize| {
            let mut p = PhrasePlayer::new(bank(CRUMPLE));
            let mut r = (0.0f32, 0u64);
            for h in 0..hits {
                let t0 = p.sent_until;
                p.note_on(t0, 60, velocity, 1);
                let out = play(&mut p, t0 + 96_000, 512);
                if h + 1 == hits {
                    for (at, c) in out {
                        match c {
                            Command::Gesture {
                                param: GestureParam::Crumple,
                                value,
                            } => r.0 = r.0.max(value),
                            Command::Release { .. } => r.1 = at - t0,
                            _ => {}
                        }
                    }
                }
            }
            r
        };
        let (soft, soft_end) = peak_and_end(30.0 / 127.0, 1);
        let (hard, hard_end) = peak_and_end(120.0 / 127.0, 1);
        assert!(hard > soft * 1.5, "{soft} {hard}");
        assert!(
            hard_end < soft_end,
            "harder is faster: {soft_end} {hard_end}"
        );
        assert_ne!(
            peak_and_end(0.8, 1),
            peak_and_end(0.8, 2),
            "two hits differ"
        );
        assert_eq!(peak_and_end(0.8, 2), peak_and_end(0.8, 2), "and repeat");
    }

    #[test]
    fn release_phrases_hold_until_the_note_off_and_resets_stop_everything() {
        let text = CRUMPLE.replace("note = 60", "note = 61\nnote_off = \"release\"");
        let mut p = PhrasePlayer::new(bank(&text));
        p.note_on(0, 61, 0.8, 1);
        let out = play(&mut p, 96_000, 256);
        assert!(
            !out.iter()
                .any(|(_, c)| matches!(c, Command::Release { .. }))
        );
        assert_eq!(p.playing(), 1, "held past its end");
        let mut released = Vec::new();
        p.note_off(96_000, 61, |s, c| released.push((s, c)));
        assert_eq!(
            released,
            vec![(
                96_000,
                Command::Release {
                    slot: GrabSlot::Back
                }
            )]
        );
        assert_eq!(p.playing(), 0);
        assert!(!p.note_on(0, 62, 0.8, 1), "no phrase on 62");
        p.note_on(96_000, 61, 0.8, 1);
        p.stop_all();
        assert_eq!(p.playing(), 0);
    }
}
