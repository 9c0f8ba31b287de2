//! # The audio render path
//!
//! Turns per-frame sound input from the simulation ([`sim_core::SoundFrame`],
//! [`sim_core::sound_input::CrumpleEvent`]) into stereo audio, following the seeds' data-driven
//! method (thesis ch. 4, `000_cb4d91e46ec5927f.txt` T 1633–2060; SCA 2016,
//! `002_9b4a8fc30aee6402.txt`; tearing: MIG 2015, `003_8cfb4a33a3603fcd.txt` §5; digest-sound,
//! digest-tearing §3):
//!
//! ```text
//!  trigger(CrumpleEvent) ─► voice_pool: nearest cell, variant, cull/merge/steal ─► unit_player:
//!                            unit × amplitude, dipole + image taps per ear (frac_delay) ──┐
//!  set_frame(SoundFrame) ─► friction: Σ amp·|H(ω)|·spectrum per ear → random phase →      ├─► mix ─► safety ─► L/R
//!                            real iFFT (M ≈ 46 ms) → sine-window overlap-add (hop M/2) ───┤   (smoothed levels)
//!                        └► tearing: w·r^α, amplitude and grain rate ∝ speed (ramped), ───┘
//!                            onset burst → tear_tone: coloured by the flaps' friction spectrum
//! ```
//!
//! One concept per module: [`voice_pool`] (selection, culling, merging, stealing),
//! [`unit_player`] (one voice), [`frac_delay`] (Lagrange taps), [`dipole`] (eq. 4.1–4.12, images,
//! comb), [`ears`] (stereo listener), [`friction`] (iFFT OLA), [`tearing`] (crackle noise), [`tear_tone`] (its colour from the flaps),
//! [`smoothing`] (mix and per-frame interpolation), [`output_stage`] (safety clip), [`counters`]
//! (proof of the skips), [`rng`] (seeded noise), [`mod@default_db`] (the embedded database),
//! [`user_db`] (a user's database folder, loaded and prepared).
//!
//! ## Real-time contract
//!
//! [`Renderer::new`] allocates everything. [`Renderer::set_frame`], [`Renderer::trigger`],
//! [`Renderer::render`], [`Renderer::reset`], [`Renderer::set_mix`], [`Renderer::set_scene`],
//! [`Renderer::set_options`] and [`Renderer::swap_db`] never allocate, lock or block (proved by
//! `tests/tests/render_no_alloc.rs` with a counting global allocator). `render` accepts any
//! length (it works in internal chunks of 256 samples, 512 or 1024 above 88 kHz: 256 at the
//! voices' unit rate, [`voice_bus`]), any rate from 8 to 192 kHz, and its output
//! is never NaN, infinite or denormal.
//!
//! ## Determinism
//!
//! Same database, seed and calls at the same sample positions → bit-identical output, however
//! the caller splits `render` calls: every process runs on absolute sample positions (friction
//! frames start at multiples of the hop since `reset`, smoothers and ramps advance per sample,
//! voices start at the first sample of the `render` call after their `trigger`). The three noise
//! consumers (variant choice, friction phases, tear grains) have independent streams, so a skipped
//! process never shifts another's noise.
//!
//! ## Levels
//!
//! A unit plays at its stored level × event amplitude × dipole gain normalised to 1 m (facing the
//! sheet, a unit-amplitude event of a resonator the size of its database cell sounds at the
//! database level). Friction at the recording slide speed (10 cm/s) plays its spectrum's level.
//! Tear grains reach ±1 at 0.1 m/s. Then the four [`MixLevels`] (smoothed, 10 ms).

pub mod air;
pub mod counters;
pub mod crackle;
pub mod default_db;
pub mod dipole;
pub mod ears;
pub mod frac_delay;
pub mod friction;
pub mod output_stage;
pub mod rng;
pub mod smoothing;
pub mod tear_tone;
pub mod tearing;
pub mod unit_player;
pub mod user_db;
pub mod voice_bus;
pub mod voice_pool;

/// Helpers for the render path's unit tests.
#[cfg(test)]
pub(crate) mod test_support {
    /// RMS of a signal.
    pub fn rms(x: &[f32]) -> f64 {
        (x.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>() / x.len() as f64).sqrt()
    }
}

use std::sync::Arc;

use sim_core::RoomConfig;
use sim_core::room::Plane;
use sim_core::sound_input::{CrumpleEvent, SoundFrame};
use sounddb::SoundDb;

use self::air::AirNoise;
pub use self::counters::RenderCounters;
use self::crackle::Crackle;
pub use self::default_db::default_db;
use self::dipole::{COS_FLOOR, MAX_REFLECTORS};
use self::ears::Ears;
use self::friction::Friction;
use self::smoothing::GainSmoother;
use self::tear_tone::TearTone;
use self::tearing::{TearNoise, TearSettings};
use self::voice_bus::VoiceBus;
use self::voice_pool::{MAX_CHUNK, TriggerCtx, VoicePool};

/// Largest block the plugin is guaranteed to get processed without internal splitting concerns;
/// `render` accepts any length (it chunks internally), this is only the documented host maximum.
pub const MAX_BLOCK: usize = 16_384;

/// Supported sample rates, Hz.
pub const SAMPLE_RATE_RANGE_HZ: (f64, f64) = (8_000.0, 192_000.0);

/// Mix levels, in dB.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MixLevels {
    /// Crumple units level, dB.
    pub crumple_db: f32,
    /// Friction noise level, dB.
    pub friction_db: f32,
    /// Tearing noise level, dB.
    pub tear_db: f32,
    /// Output gain, dB (includes MIDI volume).
    pub output_db: f32,
}

impl Default for MixLevels {
    fn default() -> Self {
        Self {
            crumple_db: 0.0,
            friction_db: 0.0,
            tear_db: 0.0,
            output_db: 0.0,
        }
    }
}

/// Listener and reflectors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scene {
    /// Table and wall.
    pub room: RoomConfig,
    /// Listener azimuth, degrees (0 = in front of the front edge, +90 = right).
    pub listener_az_deg: f32,
    /// Listener distance from the sheet's home centre, metres.
    pub listener_dist_m: f32,
}

impl Default for Scene {
    fn default() -> Self {
        Self {
            room: RoomConfig::default(),
            listener_az_deg: 0.0,
            listener_dist_m: 1.0,
        }
    }
}

impl Scene {
    /// A copy with every value finite and in range (distance 0.1–20 m).
    pub fn sanitized(self) -> Self {
        Self {
            room: self.room.sanitized(),
            listener_az_deg: if self.listener_az_deg.is_finite() {
                self.listener_az_deg
            } else {
                0.0
            },
            listener_dist_m: if self.listener_dist_m.is_finite() {
                self.listener_dist_m.clamp(0.1, 20.0)
            } else {
                1.0
            },
        }
    }
}

/// Switches of the shortcuts (digest-sound §11). The default takes them all; [`Self::reference`]
/// takes none (the "no-skip reference" the tests compare against).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Cull inaudible triggers (−90 dBFS floor, −60 dB masking).
    pub cull: bool,
    /// Merge same-unit triggers of one batch and same-cell friction entries.
    pub merge: bool,
    /// Skip the friction iFFT when there is no source (and go silent after the tail).
    pub skip_silent_friction: bool,
    /// Do not run the tear generator while the speed is 0.
    pub skip_idle_tear: bool,
    /// Do not run the air and crackle generators while the sheet moves no air and no bend.
    pub skip_idle_air: bool,
    /// Reference mode: run the image code even without a reflector, with silent taps.
    pub force_image_path: bool,
    /// Reuse a friction source's |H(ω)| while it stays within 1 mm / 0.01 of where it was
    /// computed, in the same scene (§11.6).
    pub cache_geometry: bool,
    /// Floor of |cos θ| of the dipole.
    pub cos_floor: f64,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            cull: true,
            merge: true,
            skip_silent_friction: true,
            skip_idle_tear: true,
            skip_idle_air: true,
            force_image_path: false,
            cache_geometry: true,
            cos_floor: COS_FLOOR,
        }
    }
}

impl RenderOptions {
    /// Every shortcut off.
    pub fn reference() -> Self {
        Self {
            cull: false,
            merge: false,
            skip_silent_friction: false,
            skip_idle_tear: false,
            skip_idle_air: false,
            force_image_path: true,
            cache_geometry: false,
            cos_floor: COS_FLOOR,
        }
    }
}

/// Mix and output levels at or below this are off (the bottom of the parameters' range).
pub const MUTE_DB: f32 = -60.0;

fn db_to_gain(db: f32) -> f32 {
    if !db.is_finite() || db <= MUTE_DB {
        0.0
    } else {
        10f32.powf(db.min(24.0) / 20.0)
    }
}

/// Index of the mix gains.
const CRUMPLE: usize = 0;
const FRICTION: usize = 1;
const TEAR: usize = 2;
const OUTPUT: usize = 3;

/// The render path.
pub struct Renderer {
    sample_rate_hz: f64,
    db: Arc<SoundDb>,
    db_usable: bool,
    empty: SoundDb,
    scene: Scene,
    ears: Ears,
    reflectors: [Plane; MAX_REFLECTORS],
    num_reflectors: usize,
    /// Incremented by every `set_scene` (invalidates cached spatial terms).
    scene_version: u64,
    mix: MixLevels,
    gains: [GainSmoother; 4],
    tear_ear_gain: [GainSmoother; 2],
    tear_tip: [f32; 3],
    air_ear_gain: [GainSmoother; 2],
    air: AirNoise,
    crackle_ear_gain: [GainSmoother; 2],
    crackle: Crackle,
    opts: RenderOptions,
    voices: VoicePool,
    /// The voices' bus at the unit rate (above 88 kHz), [`voice_bus`].
    voice_bus: VoiceBus,
    friction: Friction,
    tear: TearNoise,
    tear_tone: TearTone,
    bus: [Vec<f32>; 7],
    clock: u64,
    batch: u64,
    last_frame_clock: Option<u64>,
    counters: RenderCounters,
}

impl Renderer {
    /// Builds a renderer (allocates everything it will ever need). `db` must be prepared for
    /// `sample_rate_hz` ([`SoundDb::prepare`], [`default_db()`]) or be the empty database; a
    /// database prepared for another rate is kept but not played (triggers are counted as
    /// `triggers_without_unit`). The rate is clamped to 8–192 kHz.
    pub fn new(sample_rate_hz: f64, db: Arc<SoundDb>, seed: u64) -> Self {
        let rate = if sample_rate_hz.is_finite() {
            sample_rate_hz.clamp(SAMPLE_RATE_RANGE_HZ.0, SAMPLE_RATE_RANGE_HZ.1)
        } else {
            48_000.0
        };
        let scene = Scene::default();
        let mix = MixLevels::default();
        // Above 88 kHz the voices play at a half or a quarter of the rate (`voice_bus`).
        let decimation = sounddb::unit_decimation(rate);
        let mut r = Self {
            sample_rate_hz: rate,
            db_usable: db.matches_rate(rate),
            db,
            empty: SoundDb::empty(),
            scene,
            ears: Ears::from_scene(&scene),
            reflectors: [Plane {
                point_m: [0.0; 3],
                normal: [0.0, 0.0, 1.0],
            }; MAX_REFLECTORS],
            num_reflectors: 0,
            scene_version: 0,
            mix,
            gains: [GainSmoother::new(1.0, rate); 4],
            tear_ear_gain: [GainSmoother::new(1.0, rate); 2],
            tear_tip: [0.0; 3],
            air_ear_gain: [GainSmoother::new(0.0, rate); 2],
            air: AirNoise::new(rate, seed),
            crackle_ear_gain: [GainSmoother::new(0.0, rate); 2],
            crackle: Crackle::new(rate, seed),
            opts: RenderOptions::default(),
            voices: VoicePool::new(rate / decimation as f64, seed),
            voice_bus: VoiceBus::new(decimation),
            friction: Friction::new(rate, seed),
            tear: TearNoise::new(rate, seed, TearSettings::default()),
            tear_tone: TearTone::new(rate, MAX_CHUNK * decimation),
            bus: std::array::from_fn(|_| vec![0.0; MAX_CHUNK * decimation]),
            clock: 0,
            batch: 0,
            last_frame_clock: None,
            counters: RenderCounters::default(),
        };
        r.set_scene(scene);
        r.set_mix(mix);
        r.snap_gains();
        r
    }

    /// Jumps the mix gains to their targets (set with [`Self::set_mix`] and the scene) instead
    /// of gliding there: for a renderer just built, so its first samples already play at the
    /// mix it was set up with rather than fading from 0 dB. No allocation.
    pub fn snap_gains(&mut self) {
        for g in self.gains.iter_mut().chain(self.tear_ear_gain.iter_mut()) {
            g.snap();
        }
    }

    /// Clears voices, noise state, smoothers (snapped to their targets) and counters, and
    /// reseeds the noise: the renderer is as after `new()` with the current mix and scene.
    /// No allocation.
    pub fn reset(&mut self) {
        self.voices.reset();
        self.voice_bus.reset();
        self.friction.reset();
        self.tear.reset();
        self.tear_tone.reset();
        self.air.reset();
        self.crackle.reset();
        for g in self
            .air_ear_gain
            .iter_mut()
            .chain(self.crackle_ear_gain.iter_mut())
        {
            g.set_target(0.0);
            g.snap();
        }
        self.tear_tip = [0.0; 3];
        self.update_tear_gains();
        self.snap_gains();
        self.clock = 0;
        self.batch = 0;
        self.last_frame_clock = None;
        self.counters = RenderCounters::default();
    }

    /// New mix levels (smoothed internally, 10 ms). No allocation.
    pub fn set_mix(&mut self, mix: MixLevels) {
        self.mix = mix;
        self.gains[CRUMPLE].set_target(db_to_gain(mix.crumple_db));
        self.gains[FRICTION].set_target(db_to_gain(mix.friction_db));
        self.gains[TEAR].set_target(db_to_gain(mix.tear_db));
        self.gains[OUTPUT].set_target(db_to_gain(mix.output_db));
    }

    /// New listener / room geometry (sanitized). Units already playing keep the geometry of their
    /// trigger; friction and tearing follow from the next hop / frame. No allocation.
    pub fn set_scene(&mut self, scene: Scene) {
        let scene = scene.sanitized();
        self.scene = scene;
        self.scene_version += 1;
        self.ears = Ears::from_scene(&scene);
        self.num_reflectors = 0;
        for p in scene.room.reflectors().take(MAX_REFLECTORS) {
            self.reflectors[self.num_reflectors] = p;
            self.num_reflectors += 1;
        }
        self.update_tear_gains();
    }

    /// Switches shortcuts on or off (tests and the reference render). No allocation.
    pub fn set_options(&mut self, opts: RenderOptions) {
        self.opts = opts;
    }

    /// The options.
    pub fn options(&self) -> RenderOptions {
        self.opts
    }

    fn update_tear_gains(&mut self) {
        let tip = self.tear_tip;
        let tip = if tip.iter().all(|v| v.is_finite()) && tip != [0.0; 3] {
            [f64::from(tip[0]), f64::from(tip[1]), f64::from(tip[2])]
        } else {
            self.scene.room.home_centre_m()
        };
        for e in 0..2 {
            let ear = self.ears.ear_m[e];
            let d =
                ((ear[0] - tip[0]).powi(2) + (ear[1] - tip[1]).powi(2) + (ear[2] - tip[2]).powi(2))
                    .sqrt()
                    .max(0.1);
            self.tear_ear_gain[e].set_target((1.0 / d) as f32);
        }
    }

    /// Continuous input of a new simulation frame: friction sources and the tear. Call once per
    /// simulation frame, between `render` calls; values are interpolated across the frame (tear
    /// speed: linear ramp over the measured frame interval; friction: time-weighted within each
    /// hop). Crumple events of the frame are NOT triggered here — call [`Self::trigger`] for
    /// them. No allocation.
    pub fn set_frame(&mut self, frame: &SoundFrame) {
        self.counters.frames += 1;
        let interval = match self.last_frame_clock {
            Some(c) => self.clock - c,
            None => (0.005 * self.sample_rate_hz) as u64,
        };
        let lo = (0.001 * self.sample_rate_hz) as u64;
        let hi = (0.050 * self.sample_rate_hz) as u64;
        let ramp = interval.clamp(lo.max(1), hi) as u32;
        self.last_frame_clock = Some(self.clock);
        let db: &SoundDb = if self.db_usable {
            &self.db
        } else {
            &self.empty
        };
        self.friction
            .set_sources(frame.friction(), db, self.opts.merge, &mut self.counters);
        self.tear.set_speed(frame.tear.speed_m_s, ramp);
        if frame.tear.onset {
            self.tear.onset();
            self.counters.tear_onsets += 1;
        }
        let designs = self.tear_tone.designs();
        self.tear_tone
            .set_resonator(&frame.tear.resonator, db, self.db_usable);
        self.counters.tear_tone_kernels += self.tear_tone.designs() - designs;
        self.tear_tip = frame.tear.tip_m;
        self.update_tear_gains();
        self.air.set_strength(frame.air.strength_m3_s2, ramp);
        self.update_air_gains(&frame.air);
        self.crackle.set_rate(frame.crackle.rate_m_rad_s, ramp);
        if frame.crackle.rate_m_rad_s > 0.0 {
            let c = frame.crackle.centre_m.map(f64::from);
            if c.iter().all(|v| v.is_finite()) {
                for e in 0..2 {
                    let ear = self.ears.ear_m[e];
                    let d = ((ear[0] - c[0]).powi(2)
                        + (ear[1] - c[1]).powi(2)
                        + (ear[2] - c[2]).powi(2))
                    .sqrt()
                    .max(0.1);
                    self.crackle_ear_gain[e].set_target((1.0 / d) as f32);
                }
            }
        }
    }

    /// The air's gain to each ear: 1/d from the moving area's centre (≥ 10 cm) times a dipole
    /// pattern with a floor, 0.25 + 0.75 |n · r̂| ([`air`]).
    fn update_air_gains(&mut self, air: &sim_core::sound_input::AirState) {
        if air.strength_m3_s2.is_nan() || air.strength_m3_s2 <= 0.0 {
            return;
        }
        let c = air.centre_m.map(f64::from);
        let n = air.normal.map(f64::from);
        if !c.iter().chain(&n).all(|v| v.is_finite()) {
            return;
        }
        for e in 0..2 {
            let ear = self.ears.ear_m[e];
            let r = [ear[0] - c[0], ear[1] - c[1], ear[2] - c[2]];
            let d = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt().max(0.1);
            let cos = ((r[0] * n[0] + r[1] * n[1] + r[2] * n[2]) / d)
                .abs()
                .min(1.0);
            self.air_ear_gain[e].set_target(((0.25 + 0.75 * cos) / d) as f32);
        }
    }

    /// Starts a crumple unit at the first sample of the next [`Self::render`] call. No allocation.
    pub fn trigger(&mut self, event: &CrumpleEvent) {
        let db: &SoundDb = if self.db_usable {
            &self.db
        } else {
            &self.empty
        };
        let ctx = TriggerCtx {
            db,
            ears: &self.ears,
            reflectors: &self.reflectors[..self.num_reflectors],
            clock: self.voice_bus.voice_clock(),
            batch: self.batch,
            opts: &self.opts,
        };
        self.voices.trigger(event, &ctx, &mut self.counters);
    }

    /// Renders `left.len()` samples (any length; `right` must be as long, extra samples of the
    /// longer one are zeroed) into the two channels, overwriting them. No allocation.
    pub fn render(&mut self, left: &mut [f32], right: &mut [f32]) {
        let n = left.len().min(right.len());
        left[n..].fill(0.0);
        right[n..].fill(0.0);
        self.counters.render_calls += 1;
        let mut done = 0;
        while done < n {
            let m = (n - done).min(self.voice_bus.max_chunk());
            self.render_chunk(&mut left[done..done + m], &mut right[done..done + m]);
            done += m;
        }
        self.batch += 1;
    }

    fn render_chunk(&mut self, left: &mut [f32], right: &mut [f32]) {
        let n = left.len();
        let [cl, cr, fl, fr, tm, am, km] = &mut self.bus;
        let (cl, cr, fl, fr, tm, am, km) = (
            &mut cl[..n],
            &mut cr[..n],
            &mut fl[..n],
            &mut fr[..n],
            &mut tm[..n],
            &mut am[..n],
            &mut km[..n],
        );
        let db: &SoundDb = if self.db_usable {
            &self.db
        } else {
            &self.empty
        };
        let (mut images, mut finished) = (0, 0);
        let voices = &mut self.voices;
        self.voice_bus.render(cl, cr, |l, r| {
            let (i, f) = voices.render(db, l, r);
            images += i;
            finished += f;
        });
        self.counters.unit_image_tap_blocks += images;
        self.counters.voices_finished += finished;
        self.friction.render(
            db,
            &self.ears,
            &self.reflectors[..self.num_reflectors],
            self.scene_version,
            &self.opts,
            fl,
            fr,
            &mut self.counters,
        );
        let ran = self.tear.render(tm, self.opts.skip_idle_tear) as u64;
        self.tear_tone.process(tm, ran == 0);
        self.counters.tear_samples += ran;
        self.counters.tear_samples_skipped += n as u64 - ran;
        let ran = self.air.render(am, self.opts.skip_idle_air) as u64;
        self.counters.air_samples += ran;
        self.counters.air_samples_skipped += n as u64 - ran;
        let ran = self.crackle.render(km, self.opts.skip_idle_air) as u64;
        self.counters.crackle_samples += ran;
        self.counters.crackle_samples_skipped += n as u64 - ran;
        let [gc, gf, gt, go] = &mut self.gains;
        let [tl, tr] = &mut self.tear_ear_gain;
        let [al, ar] = &mut self.air_ear_gain;
        let [kl, kr] = &mut self.crackle_ear_gain;
        let (mut clipped, mut nonfinite) = (0u64, 0u64);
        for t in 0..n {
            let (c, f, te, o) = (gc.tick(), gf.tick(), gt.tick(), go.tick());
            let (el, er) = (tl.tick(), tr.tick());
            let (ql, qr) = (al.tick(), ar.tick());
            let (xl, xr) = (kl.tick(), kr.tick());
            let l = o * (c * (cl[t] + ql * am[t] + xl * km[t]) + f * fl[t] + te * el * tm[t]);
            let r = o * (c * (cr[t] + qr * am[t] + xr * km[t]) + f * fr[t] + te * er * tm[t]);
            let (l, lc, ln) = output_stage::safety(l);
            let (r, rc, rn) = output_stage::safety(r);
            left[t] = l;
            right[t] = r;
            clipped += u64::from(lc) + u64::from(rc);
            nonfinite += u64::from(ln) + u64::from(rn);
        }
        self.counters.clipped_samples += clipped;
        self.counters.nonfinite_samples += nonfinite;
        self.counters.samples += n as u64;
        self.clock += n as u64;
    }

    /// Replaces the database; returns the one to drop **off the audio thread**. Playing units are
    /// faded out over 2 ms (rendered ahead from the old database, so nothing keeps a reference to
    /// it), friction sources are re-selected at the next `set_frame` (the synthesized tail plays
    /// on). A database prepared for another sample rate is rejected: it is returned unchanged and
    /// `db_swaps_rejected` counts it (check with `Arc::ptr_eq`). No allocation.
    pub fn swap_db(&mut self, db: Arc<SoundDb>) -> Arc<SoundDb> {
        if !db.matches_rate(self.sample_rate_hz) {
            self.counters.db_swaps_rejected += 1;
            return db;
        }
        if self.db_usable {
            let old: &SoundDb = &self.db;
            self.voices.fade_out_all(old);
        }
        self.voices.reset_cells();
        self.friction.clear_sources();
        self.db_usable = true;
        self.counters.db_swaps += 1;
        std::mem::replace(&mut self.db, db)
    }

    /// The counters.
    pub fn counters(&self) -> &RenderCounters {
        &self.counters
    }

    /// The sample rate, Hz.
    pub fn sample_rate_hz(&self) -> f64 {
        self.sample_rate_hz
    }

    /// The database in use.
    pub fn db_arc(&self) -> &Arc<SoundDb> {
        &self.db
    }

    /// True when the database matches the renderer's rate.
    pub fn db_usable(&self) -> bool {
        self.db_usable
    }

    /// Number of playing crumple voices.
    pub fn active_voices(&self) -> usize {
        self.voices.active()
    }

    /// The friction frame length M and hop.
    pub fn friction_frame(&self) -> (usize, usize) {
        (self.friction.frame_len(), self.friction.hop())
    }

    /// The listener's ears.
    pub fn ears(&self) -> &Ears {
        &self.ears
    }

    /// The current scene.
    pub fn scene(&self) -> Scene {
        self.scene
    }

    /// The current mix.
    pub fn mix(&self) -> MixLevels {
        self.mix
    }
}
