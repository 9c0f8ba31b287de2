//! # The voice pool: selection, culling, merging, stealing
//!
//! The seeds play every crumple unit in its own thread and let the OS mix (T 1820, T 1973); a
//! plugin cannot, so units play from a fixed pool of [`MAX_VOICES`] voices (digest-sound §1.2,
//! §11.5). On a trigger:
//!
//! 1. **Selection** (T 1810–1818, S 153): the nearest occupied crumple cell of (l_r, l_c)
//!    (`SoundDb::crumple_lookup`; (0, 0) for constrained resonators), then a random variant of
//!    the cell, never the one the cell played last ("no immediate repeat"). Several triggers of
//!    one cell between two `render()` calls (the resonators of one event) share one variant.
//! 2. **Gain and taps**: event amplitude (linear, T 1820) × the dipole/image taps of each ear
//!    ([`super::dipole`], [`super::unit_player`]).
//! 3. **Culling** (§11.5): not started if its estimated peak is below −90 dBFS, or more than
//!    60 dB below the loudest voice started in the last 50 ms.
//! 4. **Merging** (§11.5): a trigger of the same unit as a voice started in the same batch, whose
//!    taps are within 10 µs of that voice's, is folded into it (gains summed, delays averaged by
//!    gain) — one voice instead of two.
//! 5. **Stealing**: when the pool is full, the voice with the lowest remaining level (peak ×
//!    remaining fraction) is faded out over [`STEAL_FADE_MS`] and replaced — unless the new voice
//!    would be even quieter, in which case the trigger is dropped.
//!
//! Fades are rendered ahead into a small additive ring ([`FADE_RING`] samples per ear) that the
//! next blocks read out; a database swap fades every voice the same way, so no voice outlives
//! the database it reads.

use sim_core::room::Plane;
use sim_core::sound_input::CrumpleEvent;
use sounddb::{MAX_CELLS, SoundDb};

use super::RenderOptions;
use super::counters::RenderCounters;
use super::dipole::{EarPaths, IMAGE_MAX_DELAY_S, Path, resonator_paths, size_factor};
use super::ears::{EAR_HALF_SPACING_M, Ears, SPEED_OF_SOUND_M_S};
use super::rng::NoiseRng;
use super::unit_player::{Voice, VoiceTaps};

/// Voices in the pool.
pub const MAX_VOICES: usize = 64;
/// Fade of a stolen voice, ms.
pub const STEAL_FADE_MS: f64 = 2.0;
/// Size of the fade ring per ear, samples (≥ 2 ms at 192 kHz).
pub const FADE_RING: usize = 512;
/// Absolute culling floor, dBFS.
pub const CULL_FLOOR_DB: f32 = -90.0;
/// Masking culling margin below the loudest recent voice, dB.
pub const CULL_MASK_DB: f32 = -60.0;
/// Window of "recent" voices for masking, ms.
pub const MASK_WINDOW_MS: f64 = 50.0;
/// Largest tap delay difference for merging, s (10 µs: a comb notch from the averaged delays
/// would sit at ≥ 50 kHz).
pub const MERGE_TOLERANCE_S: f64 = 10e-6;
/// Largest block the pool renders at once, samples.
pub const MAX_CHUNK: usize = 256;
/// Largest event amplitude accepted (beyond: clamped).
pub const MAX_AMPLITUDE: f32 = 100.0;

/// What a trigger needs from the renderer.
pub struct TriggerCtx<'a> {
    /// The database.
    pub db: &'a SoundDb,
    /// The listener.
    pub ears: &'a Ears,
    /// Reflecting planes.
    pub reflectors: &'a [Plane],
    /// Renderer clock (samples since reset).
    pub clock: u64,
    /// Current batch (render-call index).
    pub batch: u64,
    /// Options.
    pub opts: &'a RenderOptions,
}

/// The pool.
pub struct VoicePool {
    voices: Vec<Voice>,
    rng: NoiseRng,
    seed: u64,
    /// Last variant played per cell (u16::MAX = none).
    last_variant: Vec<u16>,
    /// (batch + 1, variant) picked for a cell in the current batch.
    batch_pick: Vec<(u64, u16)>,
    ring: [Vec<f32>; 2],
    ring_pos: usize,
    fade_tmp: [Vec<f32>; 2],
    scratch: Vec<f32>,
    fade_len: usize,
    sample_rate_hz: f64,
    max_delay_samples: f64,
    mask_window: u64,
}

impl VoicePool {
    /// Allocates the pool for a sample rate.
    pub fn new(sample_rate_hz: f64, seed: u64) -> Self {
        let max_delay_samples =
            ((IMAGE_MAX_DELAY_S + 2.0 * EAR_HALF_SPACING_M / SPEED_OF_SOUND_M_S) * sample_rate_hz)
                .ceil()
                + 2.0;
        let fade_len =
            ((STEAL_FADE_MS * 1e-3 * sample_rate_hz).round() as usize).clamp(1, FADE_RING / 2);
        Self {
            voices: vec![Voice::default(); MAX_VOICES],
            rng: NoiseRng::new(seed, 1),
            seed,
            last_variant: vec![u16::MAX; MAX_CELLS],
            batch_pick: vec![(0, 0); MAX_CELLS],
            ring: [vec![0.0; FADE_RING], vec![0.0; FADE_RING]],
            ring_pos: 0,
            fade_tmp: [vec![0.0; FADE_RING], vec![0.0; FADE_RING]],
            scratch: vec![0.0; MAX_CHUNK + max_delay_samples as usize + 8],
            fade_len,
            sample_rate_hz,
            max_delay_samples,
            mask_window: (MASK_WINDOW_MS * 1e-3 * sample_rate_hz) as u64,
        }
    }

    /// Stops every voice, clears the fades and per-cell state, reseeds. No allocation.
    pub fn reset(&mut self) {
        for v in &mut self.voices {
            v.active = false;
        }
        self.rng = NoiseRng::new(self.seed, 1);
        self.reset_cells();
        for r in &mut self.ring {
            r.fill(0.0);
        }
        self.ring_pos = 0;
    }

    /// Forgets the per-cell variant history (after a database swap).
    pub fn reset_cells(&mut self) {
        self.last_variant.fill(u16::MAX);
        self.batch_pick.fill((0, 0));
    }

    /// Number of active voices.
    pub fn active(&self) -> usize {
        self.voices.iter().filter(|v| v.active).count()
    }

    /// The voices (for tests).
    pub fn voices(&self) -> &[Voice] {
        &self.voices
    }

    /// Handles a crumple trigger (see the module docs). No allocation.
    pub fn trigger(&mut self, ev: &CrumpleEvent, ctx: &TriggerCtx, counters: &mut RenderCounters) {
        counters.triggers += 1;
        let amp = ev.amplitude;
        if !amp.is_finite() || amp == 0.0 {
            counters.triggers_invalid += 1;
            return;
        }
        let amp = amp.clamp(-MAX_AMPLITUDE, MAX_AMPLITUDE);
        let res = ev.resonator;
        let Some(cell_id) = ctx.db.crumple_lookup(res.lr_cm, res.lc_cm) else {
            counters.triggers_without_unit += 1;
            return;
        };
        let cell = ctx.db.crumple_cells()[cell_id.0 as usize];
        if cell.num_units == 0 {
            counters.triggers_without_unit += 1;
            return;
        }
        let c = cell_id.0 as usize;
        let variant = if self.batch_pick[c].0 == ctx.batch + 1 {
            u32::from(self.batch_pick[c].1)
        } else {
            let n = cell.num_units;
            let last = u32::from(self.last_variant[c]);
            let v = if n <= 1 {
                0
            } else if last < n {
                let r = self.rng.below(n - 1);
                if r >= last { r + 1 } else { r }
            } else {
                self.rng.below(n)
            };
            self.last_variant[c] = v as u16;
            self.batch_pick[c] = (ctx.batch + 1, v as u16);
            v
        };
        let unit_index = cell.first_unit + variant;
        let unit = *ctx.db.unit(unit_index as usize);

        // Spatial taps.
        let strength = f64::from(amp) * size_factor(res.radius_m, cell.reference_radius_m);
        let mut paths = [EarPaths::default(); 2];
        for (e, p) in paths.iter_mut().enumerate() {
            *p = resonator_paths(
                &res,
                strength,
                ctx.ears.ear_m[e],
                ctx.reflectors,
                ctx.opts.cos_floor,
            );
            counters.image_taps_skipped += p.skipped as u64;
            if ctx.opts.force_image_path && p.num_images == 0 {
                // Reference mode: run the image code with a silent tap.
                p.images[0] = Path {
                    gain: 0.0,
                    delay_s: p.direct.delay_s,
                };
                p.num_images = 1;
            }
        }
        let centre = ctx.ears.centre_m;
        let dc = [
            centre[0] - f64::from(res.centre_m[0]),
            centre[1] - f64::from(res.centre_m[1]),
            centre[2] - f64::from(res.centre_m[2]),
        ];
        let ref_delay_s = (dc[0] * dc[0] + dc[1] * dc[1] + dc[2] * dc[2])
            .sqrt()
            .max(super::dipole::MIN_DISTANCE_M)
            / SPEED_OF_SOUND_M_S;
        let base_delay_s = EAR_HALF_SPACING_M / SPEED_OF_SOUND_M_S;
        let mut taps =
            VoiceTaps::from_paths(&paths, ref_delay_s, base_delay_s, self.sample_rate_hz);
        for e in 0..2 {
            for k in 0..taps.num[e] {
                taps.raw[e][k].delay_samples =
                    taps.raw[e][k].delay_samples.min(self.max_delay_samples);
            }
        }
        let est_peak = (taps.peak_gain() * f64::from(unit.peak)) as f32;

        // Culling.
        if ctx.opts.cull {
            if est_peak < db_to_lin(CULL_FLOOR_DB) {
                counters.voices_culled_quiet += 1;
                return;
            }
            let loudest = self
                .voices
                .iter()
                .filter(|v| v.active && ctx.clock.saturating_sub(v.start_clock) <= self.mask_window)
                .fold(0.0f32, |m, v| m.max(v.est_peak));
            if est_peak < loudest * db_to_lin(CULL_MASK_DB) {
                counters.voices_culled_masked += 1;
                return;
            }
        }

        // Merging.
        if ctx.opts.merge
            && let Some(v) = self.voices.iter_mut().find(|v| {
                v.active
                    && v.batch == ctx.batch
                    && v.pos == 0
                    && v.unit == unit_index
                    && v.taps
                        .compatible(&taps, MERGE_TOLERANCE_S * self.sample_rate_hz)
            })
        {
            v.taps.merge(&taps);
            v.est_peak = (v.taps.peak_gain() * f64::from(unit.peak)) as f32;
            v.update_filters(unit.len);
            counters.voices_merged += 1;
            return;
        }

        // A slot.
        let slot = match self.voices.iter().position(|v| !v.active) {
            Some(s) => s,
            None => {
                let (victim, level) = self
                    .voices
                    .iter()
                    .enumerate()
                    .map(|(i, v)| (i, v.remaining_level()))
                    .fold((0, f32::INFINITY), |b, x| if x.1 < b.1 { x } else { b });
                if est_peak <= level {
                    counters.voices_dropped_pool_full += 1;
                    return;
                }
                self.fade_out(victim, ctx.db);
                counters.voices_stolen += 1;
                victim
            }
        };
        let v = &mut self.voices[slot];
        *v = Voice {
            active: true,
            unit: unit_index,
            cell: cell_id.0,
            pos: 0,
            end: 0,
            start_clock: ctx.clock,
            batch: ctx.batch,
            est_peak,
            taps,
            ..Voice::default()
        };
        v.update_filters(unit.len);
        counters.voices_started += 1;
    }

    /// Renders voice `i`'s next fade_len samples into the fade ring with a linear fade-out, then
    /// stops it.
    fn fade_out(&mut self, i: usize, db: &SoundDb) {
        let n = self.fade_len;
        let [tl, tr] = &mut self.fade_tmp;
        tl[..n].fill(0.0);
        tr[..n].fill(0.0);
        let v = &mut self.voices[i];
        if v.active && v.pos < v.end {
            v.render(db, &mut self.scratch, &mut tl[..n], &mut tr[..n]);
        }
        v.active = false;
        for t in 0..n {
            let g = 1.0 - (t as f32 + 0.5) / n as f32;
            let k = (self.ring_pos + t) % FADE_RING;
            self.ring[0][k] += tl[t] * g;
            self.ring[1][k] += tr[t] * g;
        }
    }

    /// Fades every active voice out (database swap).
    pub fn fade_out_all(&mut self, db: &SoundDb) -> u64 {
        let mut n = 0;
        for i in 0..self.voices.len() {
            if self.voices[i].active {
                self.fade_out(i, db);
                n += 1;
            }
        }
        n
    }

    /// Adds the next `out_l.len()` (≤ [`MAX_CHUNK`]) samples of the fades and every voice into
    /// the outputs. Returns (image tap blocks, voices finished).
    pub fn render(&mut self, db: &SoundDb, out_l: &mut [f32], out_r: &mut [f32]) -> (u64, u64) {
        let n = out_l.len().min(out_r.len()).min(MAX_CHUNK);
        for t in 0..n {
            let k = (self.ring_pos + t) % FADE_RING;
            out_l[t] += self.ring[0][k];
            out_r[t] += self.ring[1][k];
            self.ring[0][k] = 0.0;
            self.ring[1][k] = 0.0;
        }
        self.ring_pos = (self.ring_pos + n) % FADE_RING;
        let (mut images, mut finished) = (0, 0);
        for v in self.voices.iter_mut().filter(|v| v.active) {
            let m = (v.end - v.pos).min(n as u64) as usize;
            images += v.render(db, &mut self.scratch, &mut out_l[..m], &mut out_r[..m]);
            if v.pos >= v.end {
                v.active = false;
                finished += 1;
            }
        }
        (images, finished)
    }
}

/// dB → linear.
pub fn db_to_lin(db: f32) -> f32 {
    10f32.powf(db / 20.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sim_core::sound_input::Resonator;
    use sounddb::{Cell, Database, DbInfo, Unit};

    fn db() -> SoundDb {
        let mut db = Database::new(DbInfo::default(), 48_000);
        for v in 0..3 {
            let mut x = vec![0.0f32; 4800];
            for (i, s) in x.iter_mut().enumerate() {
                *s = 0.5 * (i as f32 * 0.05 * (v + 1) as f32).sin() * (-(i as f32) / 1000.0).exp();
            }
            db.units.push(Unit {
                cell: Cell::Free {
                    straight_cm: 10.0,
                    curved_cm: 10.0,
                },
                samples: x,
                file: String::new(),
            });
        }
        SoundDb::prepare(&db, 48_000.0)
    }

    fn event(amplitude: f32) -> CrumpleEvent {
        CrumpleEvent {
            amplitude,
            resonator: Resonator {
                lr_cm: 10.0,
                lc_cm: 20.0,
                centre_m: [0.0, 0.0, 0.76],
                normal: [0.0, 0.0, 1.0],
                radius_m: 0.056,
            },
        }
    }

    struct Fixture {
        db: SoundDb,
        ears: Ears,
        opts: RenderOptions,
        counters: RenderCounters,
    }

    impl Fixture {
        fn new() -> Self {
            Self {
                db: db(),
                ears: Ears::from_scene(&super::super::Scene::default()),
                opts: RenderOptions::default(),
                counters: RenderCounters::default(),
            }
        }

        fn trigger(&mut self, pool: &mut VoicePool, ev: &CrumpleEvent, clock: u64, batch: u64) {
            let ctx = TriggerCtx {
                db: &self.db,
                ears: &self.ears,
                reflectors: &[],
                clock,
                batch,
                opts: &self.opts,
            };
            pool.trigger(ev, &ctx, &mut self.counters);
        }
    }

    #[test]
    fn variants_all_used_never_repeated() {
        // digest-sound §12 test 15: 3 variants, 100 draws, all selected, no immediate repeat.
        let mut f = Fixture::new();
        let mut pool = VoicePool::new(48_000.0, 9);
        let mut seen = [0usize; 3];
        let mut last = u32::MAX;
        for batch in 0..100 {
            for v in &mut pool.voices {
                v.active = false;
            }
            f.trigger(&mut pool, &event(1.0), 0, batch);
            let v = pool.voices().iter().find(|v| v.active).unwrap().unit;
            assert_ne!(v, last, "immediate repeat at draw {batch}");
            seen[v as usize] += 1;
            last = v;
        }
        assert!(seen.iter().all(|&n| n > 10), "{seen:?}");
    }

    #[test]
    fn quiet_and_masked_triggers_are_culled() {
        let mut f = Fixture::new();
        let mut pool = VoicePool::new(48_000.0, 1);
        f.trigger(&mut pool, &event(1e-6), 0, 0);
        assert_eq!(f.counters.voices_culled_quiet, 1);
        f.trigger(&mut pool, &event(1.0), 0, 1);
        // 70 dB below, 10 ms later: masked. 50 dB below: played.
        f.trigger(&mut pool, &event(10f32.powf(-70.0 / 20.0)), 480, 2);
        assert_eq!(f.counters.voices_culled_masked, 1);
        f.trigger(&mut pool, &event(10f32.powf(-50.0 / 20.0)), 480, 3);
        assert_eq!(pool.active(), 2);
        let mut off = Fixture::new();
        off.opts.cull = false;
        let mut pool = VoicePool::new(48_000.0, 1);
        off.trigger(&mut pool, &event(1e-6), 0, 0);
        assert_eq!(pool.active(), 1);
    }

    #[test]
    fn same_batch_duplicates_merge() {
        let mut f = Fixture::new();
        let mut pool = VoicePool::new(48_000.0, 1);
        f.trigger(&mut pool, &event(0.5), 0, 7);
        f.trigger(&mut pool, &event(0.25), 0, 7);
        assert_eq!(pool.active(), 1);
        assert_eq!(f.counters.voices_merged, 1);
        let v = pool.voices().iter().find(|v| v.active).unwrap();
        let single = {
            let mut g = Fixture::new();
            let mut p = VoicePool::new(48_000.0, 1);
            g.trigger(&mut p, &event(0.75), 0, 7);
            *p.voices().iter().find(|v| v.active).unwrap()
        };
        for e in 0..2 {
            assert!((v.taps.raw[e][0].gain - single.taps.raw[e][0].gain).abs() < 1e-12);
        }
        // Next batch: a new voice (and another variant).
        f.trigger(&mut pool, &event(0.5), 0, 8);
        assert_eq!(pool.active(), 2);
    }

    #[test]
    fn full_pool_steals_the_quietest_with_a_fade() {
        let mut f = Fixture::new();
        f.opts.cull = false;
        let mut pool = VoicePool::new(48_000.0, 1);
        for i in 0..MAX_VOICES {
            f.trigger(&mut pool, &event(0.01 + i as f32 * 0.01), 0, i as u64);
        }
        assert_eq!(pool.active(), MAX_VOICES);
        f.trigger(&mut pool, &event(0.001), 0, 100);
        assert_eq!(f.counters.voices_dropped_pool_full, 1);
        f.trigger(&mut pool, &event(2.0), 0, 101);
        assert_eq!(f.counters.voices_stolen, 1);
        assert_eq!(pool.active(), MAX_VOICES);
        // The stolen voice (amplitude 0.01) is in the fade ring: it decays to 0 within 2 ms.
        let ring_energy: f32 = pool.ring[0].iter().map(|v| v * v).sum();
        assert!(ring_energy > 0.0);
        let n = pool.fade_len;
        assert!(pool.ring[0][n..].iter().all(|&v| v == 0.0));
    }
}
