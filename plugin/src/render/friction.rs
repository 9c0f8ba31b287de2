//! # Friction noise: weighted spectra → one random-phase inverse FFT → overlap-add
//!
//! The seeds synthesize friction from averaged magnitude spectra (T 1822–1830,
//! `000_cb4d91e46ec5927f.txt`; S 149–153, `002_9b4a8fc30aee6402.txt`; digest-sound §4.2):
//!
//! ```text
//! S(ω) = Σ_sources amp · |H_spatial(ω)| · DB_spectrum(ω)        (summed BEFORE the iFFT, T 1830)
//! v_k  = S_k · e^{iφ_k},  φ_k ~ U[−π, π] fresh per frame          (T 1826)
//! x    = iFFT(v),  frames of M samples overlapped by M/2           (T 1830, T 1903)
//! ```
//!
//! Our implementation (choices for what the seeds leave open, digest §4.2 notes 1–5):
//!
//! - **Magnitudes** (not powers), as S 149 says and v_k = s_k e^{iφ} implies.
//! - **Real output**: a real inverse FFT of size M (`realfft`) on M/2 + 1 bins; DC and Nyquist
//!   bins are 0 (they must be real). The seeds use M = 2048 and hop 1024 at 44.1 kHz (T 1903);
//!   here M = `sounddb::friction_frame_len`: the even length with factors 2, 3, 5, 7 closest to
//!   fs · 7/150 s, so the frame lasts 46.67 ms and the bins lie 21.43 Hz apart at every common
//!   rate (44.1 kHz → 2058, 48 kHz → 2240, 96 kHz → 4480, 192 kHz → 8960; 8 kHz → 378): the
//!   same frames at the same times at 44.1 and 48 kHz. The database spectra are moved
//!   onto these bins
//!   and scaled at load time (`sounddb::prepared`), never here.
//! - **Window**: successive frames are independent noise, so the overlap uses the
//!   power-complementary sine window w(n) = sin(π(n + ½)/M): w²(n) + w²(n + M/2) = 1, the
//!   variance is constant across the overlap (a Hann window would dip 3 dB mid-overlap, a 43 Hz
//!   flutter). The frame's circular wrap is inside the window's tails.
//! - **Amplitude** of a source: its slip speed relative to the recording speed (10 cm/s, T 1909;
//!   S 153: linear in the relative speed) — folded into the prepared spectra.
//! - **Spatialization**: |H(ω)| of eq. 4.12 per source and per ear ([`super::dipole`]); without
//!   reflectors H is the scalar |g0| and no per-bin work is done (§11.1). With reflectors, |H| is
//!   computed at unit strength and cached per (ear, place): a source that has not moved by more
//!   than 1 mm / turned by more than 0.01 since, in an unchanged scene, reuses it (§11.6; the
//!   approximation is that tolerance). [`CACHE_SLOTS`] slots, least recently used replaced.
//! - **Stereo**: one magnitude sum per ear, **the same random phases** for both ears (the channels
//!   stay correlated as one source heard twice), two inverse FFTs per hop.
//! - **Timing and interpolation**: frame j starts at sample j·hop (absolute, since `reset`) and
//!   uses the *time-weighted mean* of the sources over the previous hop: each `set_frame` closes
//!   the segment of the previous frame's sources, weighted by its duration / hop. A frame rate
//!   above the hop rate (200 Hz vs 43 Hz) is thus averaged, not sampled, and the OLA crossfade
//!   interpolates between hops. Latency: ≤ 1 hop (23 ms) from a `set_frame` to the first sample of
//!   friction it causes (test 4); the seeds' frame is 46 ms.
//! - **Phases**: frame j draws its phases from its own noise stream (seed, j), so a skipped hop
//!   does not shift the phases of later frames: the output with and without the skips is the same.
//! - **Merging** (§11.4–11.5): within a hop, sources of the same cell at the same place (centre
//!   within 5 mm, normal within 0.05, radius within 5 %) share one entry (amplitudes summed).
//!   With [`super::RenderOptions::merge`] and no reflectors, entries of one cell are also summed
//!   into one weight before touching the bins.
//! - **Skips** (§11.2): a hop without sources runs no iFFT; the second half of the last frame
//!   still plays (the tail), then the generator goes silent and costs nothing.
//! - **Silent bins**: the per-bin work (|H|, the weighted sums, the phases) stops at the
//!   database's last non-zero bin (`SoundDb::friction_active_bins`). A database made at
//!   44.1 kHz fills 1 025 of the 2 241 bins at 96 kHz; the bins above are 0, as they would be
//!   anyway, and the phases drawn below are the same, so the output is unchanged.
//!
//! Because frames start at absolute sample positions and depend only on the inputs received
//! before them, the output does not depend on how `render()` calls are split.

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner};
use sim_core::room::Plane;
use sim_core::sound_input::{FrictionSource, MAX_FRICTION_SOURCES, Resonator};
use sounddb::{CellId, SoundDb};

use super::RenderOptions;
use super::counters::RenderCounters;
use super::dipole::{EarPaths, Path, resonator_paths, size_factor};
use super::ears::Ears;
use super::rng::NoiseRng;

/// Most distinct (cell, place) entries per hop.
pub const MAX_ENTRIES: usize = 64;
/// Size of the random phase table (phases quantised to 2π/4096).
const PHASE_TABLE: usize = 4096;
/// First noise stream of the per-hop phase streams.
const PHASE_STREAM_BASE: u64 = 1 << 32;
/// Slip speeds below this are silence, m/s.
pub const MIN_SLIP_SPEED_M_S: f32 = 1e-6;

#[derive(Clone, Copy, Debug, Default)]
struct Source {
    cell: u16,
    amp: f32,
    res: Resonator,
}

#[derive(Clone, Copy, Debug, Default)]
struct Entry {
    cell: u16,
    /// Σ amplitude × duration (samples).
    weight: f32,
    res: Resonator,
}

fn same_place(a: &Resonator, b: &Resonator) -> bool {
    let d2: f32 = (0..3)
        .map(|i| (a.centre_m[i] - b.centre_m[i]).powi(2))
        .sum();
    let n2: f32 = (0..3).map(|i| (a.normal[i] - b.normal[i]).powi(2)).sum();
    let r = (a.radius_m - b.radius_m).abs() <= 0.05 * a.radius_m.abs().max(b.radius_m.abs());
    d2 <= 0.005 * 0.005 && n2 <= 0.05 * 0.05 && r
}

/// Cached |H(ω)| of one source position for one ear (digest-sound §11.6: recompute the spatial
/// terms only when the source moves by more than 1 mm or turns by more than 0.01, or the scene
/// changes).
#[derive(Clone, Copy, Debug, Default)]
struct CombSlot {
    valid: bool,
    ear: u8,
    scene_version: u64,
    centre_m: [f32; 3],
    normal: [f32; 3],
    last_used: u64,
    /// Bins computed (the database's active bins when it was claimed).
    len: usize,
}

/// Fixed-size store of cached comb magnitudes ([`CACHE_SLOTS`] slots × bins).
struct CombCache {
    slots: Vec<CombSlot>,
    data: Vec<f32>,
}

/// Slots of the comb cache (both ears).
pub const CACHE_SLOTS: usize = 2 * MAX_ENTRIES;
/// Position tolerance of the comb cache, m.
pub const CACHE_TOLERANCE_M: f32 = 0.001;
/// Normal tolerance of the comb cache.
pub const CACHE_TOLERANCE_NORMAL: f32 = 0.01;

impl CombCache {
    fn new(bins: usize) -> Self {
        Self {
            slots: vec![CombSlot::default(); CACHE_SLOTS],
            data: vec![0.0; CACHE_SLOTS * bins],
        }
    }

    fn clear(&mut self) {
        for s in &mut self.slots {
            s.valid = false;
        }
    }

    fn find(
        &self,
        res: &Resonator,
        ear: usize,
        version: u64,
        len: usize,
        enabled: bool,
    ) -> Option<usize> {
        if !enabled {
            return None;
        }
        self.slots.iter().position(|s| {
            s.valid
                && s.ear as usize == ear
                && s.len >= len
                && s.scene_version == version
                && (0..3)
                    .map(|i| (s.centre_m[i] - res.centre_m[i]).powi(2))
                    .sum::<f32>()
                    <= CACHE_TOLERANCE_M * CACHE_TOLERANCE_M
                && (0..3)
                    .map(|i| (s.normal[i] - res.normal[i]).powi(2))
                    .sum::<f32>()
                    <= CACHE_TOLERANCE_NORMAL * CACHE_TOLERANCE_NORMAL
        })
    }

    /// The least recently used slot, re-keyed for `res`.
    fn claim(&mut self, res: &Resonator, ear: usize, version: u64, len: usize) -> usize {
        let k = self
            .slots
            .iter()
            .enumerate()
            .min_by_key(|(_, s)| if s.valid { s.last_used + 1 } else { 0 })
            .map_or(0, |(k, _)| k);
        self.slots[k] = CombSlot {
            valid: true,
            ear: ear as u8,
            scene_version: version,
            centre_m: res.centre_m,
            normal: res.normal,
            last_used: 0,
            len,
        };
        k
    }

    fn touch(&mut self, k: usize, hop: u64) {
        self.slots[k].last_used = hop;
    }

    fn magnitude(&self, k: usize, bins: usize) -> &[f32] {
        &self.data[k * bins..(k + 1) * bins]
    }

    fn magnitude_mut(&mut self, k: usize, bins: usize) -> &mut [f32] {
        &mut self.data[k * bins..(k + 1) * bins]
    }
}

/// The friction generator.
pub struct Friction {
    m: usize,
    hop: usize,
    bins: usize,
    sample_rate_hz: f64,
    window: Vec<f32>,
    ifft: Arc<dyn ComplexToReal<f32>>,
    fft_scratch: Vec<Complex<f32>>,
    spec: [Vec<Complex<f32>>; 2],
    frame: Vec<f32>,
    mag: [Vec<f32>; 2],
    /// Output for the next M samples, per ear.
    pending: [Vec<f32>; 2],
    /// Samples output in the current hop (0 … hop).
    hop_pos: usize,
    /// Hops of non-zero output left in `pending`.
    live_hops: u8,
    phase_table: Vec<(f32, f32)>,
    seed: u64,
    /// Hop boundaries since reset (the phases of frame j come from stream j).
    hop_index: u64,
    current: [Source; MAX_FRICTION_SOURCES],
    num_current: usize,
    seg_start: usize,
    entries: [Entry; MAX_ENTRIES],
    num_entries: usize,
    /// Per-cell merged weights for the no-reflector path.
    cell_weight: [Vec<f32>; 2],
    cache: CombCache,
}

impl Friction {
    /// Allocates the generator for a sample rate (plans the FFT).
    pub fn new(sample_rate_hz: f64, seed: u64) -> Self {
        let m = sounddb::friction_frame_len(sample_rate_hz);
        let hop = m / 2;
        let bins = m / 2 + 1;
        let ifft = RealFftPlanner::<f32>::new().plan_fft_inverse(m);
        let window = (0..m)
            .map(|n| (std::f64::consts::PI * (n as f64 + 0.5) / m as f64).sin() as f32)
            .collect();
        let phase_table = (0..PHASE_TABLE)
            .map(|i| {
                let p = 2.0 * std::f64::consts::PI * i as f64 / PHASE_TABLE as f64;
                (p.cos() as f32, p.sin() as f32)
            })
            .collect();
        Self {
            m,
            hop,
            bins,
            sample_rate_hz,
            window,
            fft_scratch: ifft.make_scratch_vec(),
            spec: [ifft.make_input_vec(), ifft.make_input_vec()],
            frame: ifft.make_output_vec(),
            ifft,
            mag: [vec![0.0; bins], vec![0.0; bins]],
            pending: [vec![0.0; m], vec![0.0; m]],
            hop_pos: 0,
            live_hops: 0,
            phase_table,
            seed,
            hop_index: 0,
            current: [Source::default(); MAX_FRICTION_SOURCES],
            num_current: 0,
            seg_start: 0,
            entries: [Entry::default(); MAX_ENTRIES],
            num_entries: 0,
            cell_weight: [vec![0.0; sounddb::MAX_CELLS], vec![0.0; sounddb::MAX_CELLS]],
            cache: CombCache::new(bins),
        }
    }

    /// Frame length M.
    pub fn frame_len(&self) -> usize {
        self.m
    }

    /// Hop M/2.
    pub fn hop(&self) -> usize {
        self.hop
    }

    /// Clears everything and reseeds. No allocation.
    pub fn reset(&mut self) {
        for p in &mut self.pending {
            p.fill(0.0);
        }
        self.hop_pos = 0;
        self.live_hops = 0;
        self.hop_index = 0;
        self.num_current = 0;
        self.seg_start = 0;
        self.num_entries = 0;
        self.cache.clear();
    }

    /// Forgets sources and entries (their cells belong to a database being swapped out); the
    /// tail already synthesized keeps playing.
    pub fn clear_sources(&mut self) {
        self.num_current = 0;
        self.num_entries = 0;
        self.seg_start = self.hop_pos;
    }

    /// The sources of a new simulation frame (closing the previous frame's segment).
    pub fn set_sources(
        &mut self,
        sources: &[FrictionSource],
        db: &SoundDb,
        merge: bool,
        counters: &mut RenderCounters,
    ) {
        let upto = self.hop_pos;
        self.flush(upto, merge, counters);
        self.num_current = 0;
        for s in sources.iter().take(MAX_FRICTION_SOURCES) {
            let v = s.slip_speed_m_s.abs();
            if !v.is_finite() || v < MIN_SLIP_SPEED_M_S {
                continue;
            }
            let Some(cell) = db.friction_lookup(s.resonator.lr_cm, s.resonator.lc_cm) else {
                counters.friction_sources_without_spectrum += 1;
                continue;
            };
            self.current[self.num_current] = Source {
                cell: cell.0,
                amp: v.min(10.0) / sounddb::REFERENCE_SLIDE_SPEED_M_S,
                res: s.resonator,
            };
            self.num_current += 1;
        }
    }

    /// Adds the current sources' contribution from `seg_start` to `upto` into the entries.
    fn flush(&mut self, upto: usize, merge: bool, counters: &mut RenderCounters) {
        let dur = upto.saturating_sub(self.seg_start) as f32;
        self.seg_start = upto;
        if dur <= 0.0 {
            return;
        }
        for s in &self.current[..self.num_current] {
            let w = s.amp * dur;
            if let Some(e) = self.entries[..self.num_entries]
                .iter_mut()
                .find(|e| merge && e.cell == s.cell && same_place(&e.res, &s.res))
            {
                e.weight += w;
                counters.friction_sources_merged += 1;
            } else if self.num_entries < MAX_ENTRIES {
                self.entries[self.num_entries] = Entry {
                    cell: s.cell,
                    weight: w,
                    res: s.res,
                };
                self.num_entries += 1;
            } else {
                counters.friction_sources_dropped += 1;
            }
        }
    }

    /// True when nothing is playing and nothing is pending.
    pub fn is_silent(&self) -> bool {
        self.live_hops == 0 && self.num_current == 0 && self.num_entries == 0
    }

    /// Renders `out_l.len()` samples (overwrites).
    pub fn render(
        &mut self,
        db: &SoundDb,
        ears: &Ears,
        reflectors: &[Plane],
        scene_version: u64,
        opts: &RenderOptions,
        out_l: &mut [f32],
        out_r: &mut [f32],
        counters: &mut RenderCounters,
    ) {
        let n = out_l.len().min(out_r.len());
        let mut done = 0;
        while done < n {
            if self.hop_pos == self.hop {
                self.boundary(db, ears, reflectors, scene_version, opts, counters);
            }
            let m = (n - done).min(self.hop - self.hop_pos);
            let (dl, dr) = (&mut out_l[done..done + m], &mut out_r[done..done + m]);
            if self.live_hops == 0 && opts.skip_silent_friction {
                dl.fill(0.0);
                dr.fill(0.0);
                counters.friction_samples_silent += m as u64;
            } else {
                dl.copy_from_slice(&self.pending[0][self.hop_pos..self.hop_pos + m]);
                dr.copy_from_slice(&self.pending[1][self.hop_pos..self.hop_pos + m]);
            }
            self.hop_pos += m;
            done += m;
        }
    }

    /// A hop boundary: shift the OLA buffers and add the next frame.
    fn boundary(
        &mut self,
        db: &SoundDb,
        ears: &Ears,
        reflectors: &[Plane],
        scene_version: u64,
        opts: &RenderOptions,
        counters: &mut RenderCounters,
    ) {
        counters.friction_hops += 1;
        let hop = self.hop;
        self.flush(hop, opts.merge, counters);
        let hop_index = self.hop_index;
        self.hop_index += 1;
        self.seg_start = 0;
        self.hop_pos = 0;
        if self.live_hops > 0 || !opts.skip_silent_friction {
            for p in &mut self.pending {
                p.copy_within(hop.., 0);
                p[hop..].fill(0.0);
            }
            self.live_hops = self.live_hops.saturating_sub(1);
        }
        let active = self.num_entries > 0
            && db.matches_rate(self.sample_rate_hz)
            && !db.friction_cells().is_empty();
        if !active && opts.skip_silent_friction {
            self.num_entries = 0;
            counters.friction_hops_skipped += 1;
            return;
        }
        self.build_magnitudes(db, ears, reflectors, scene_version, opts, counters);
        self.num_entries = 0;
        // Random phases shared by both ears, from the hop's own stream (so skipping silent hops
        // never shifts later phases); DC and Nyquist stay real (0).
        // Bins from the database's last non-zero one on carry nothing: no phase is drawn there
        // (the draws below it are the same as if it were).
        let mut rng = NoiseRng::new(self.seed, PHASE_STREAM_BASE + hop_index);
        let active = db.friction_active_bins().min(self.bins);
        for e in 0..2 {
            self.spec[e][active..].fill(Complex::new(0.0, 0.0));
        }
        for j in 0..active {
            let (c, s) = if j == 0 || j == self.bins - 1 {
                (0.0, 0.0)
            } else {
                self.phase_table[(rng.next_u32() >> 20) as usize]
            };
            for e in 0..2 {
                let a = self.mag[e][j];
                self.spec[e][j] = Complex::new(a * c, a * s);
            }
        }
        for e in 0..2 {
            // Lengths come from the plan; the first and last bins are real: cannot fail.
            let _ = self.ifft.process_with_scratch(
                &mut self.spec[e],
                &mut self.frame,
                &mut self.fft_scratch,
            );
            for ((p, x), w) in self.pending[e]
                .iter_mut()
                .zip(&self.frame)
                .zip(&self.window)
            {
                *p += x * w;
            }
            counters.friction_ffts += 1;
        }
        self.live_hops = 2;
    }

    fn build_magnitudes(
        &mut self,
        db: &SoundDb,
        ears: &Ears,
        reflectors: &[Plane],
        scene_version: u64,
        opts: &RenderOptions,
        counters: &mut RenderCounters,
    ) {
        for m in &mut self.mag {
            m.fill(0.0);
        }
        if self.num_entries == 0 || !db.matches_rate(self.sample_rate_hz) {
            return;
        }
        let inv_hop = 1.0 / self.hop as f32;
        let d_omega = 2.0 * std::f64::consts::PI * self.sample_rate_hz / self.m as f64;
        let merge_cells = opts.merge && reflectors.is_empty() && !opts.force_image_path;
        if merge_cells {
            for w in &mut self.cell_weight {
                w.fill(0.0);
            }
        }
        let cells = db.friction_cells();
        let bins = self.bins;
        // Per-bin work stops at the database's last non-zero bin (above it every spectrum is 0).
        let active = db.friction_active_bins().min(bins);
        for e in &self.entries[..self.num_entries] {
            let cell = cells[e.cell as usize];
            // Unit-strength paths; the strength (amplitude × duration share × size factor)
            // multiplies |H| afterwards, so a cached |H| serves any strength.
            let strength = ((e.weight * inv_hop) as f64
                * size_factor(e.res.radius_m, cell.reference_radius_m))
                as f32;
            let spectrum = &db.friction_spectrum(CellId(e.cell))[..active];
            for ear in 0..2 {
                let mut paths: EarPaths =
                    resonator_paths(&e.res, 1.0, ears.ear_m[ear], reflectors, opts.cos_floor);
                if opts.force_image_path && paths.num_images == 0 {
                    paths.images[0] = Path {
                        gain: 0.0,
                        delay_s: paths.direct.delay_s,
                    };
                    paths.num_images = 1;
                }
                if paths.num_images > 0 {
                    let slot =
                        self.cache
                            .find(&e.res, ear, scene_version, active, opts.cache_geometry);
                    let slot = match slot {
                        Some(k) => {
                            counters.friction_comb_cache_hits += 1;
                            k
                        }
                        None => {
                            let k = self.cache.claim(&e.res, ear, scene_version, active);
                            counters.friction_comb_bins += super::dipole::comb_magnitude(
                                &paths,
                                d_omega,
                                &mut self.cache.magnitude_mut(k, bins)[..active],
                            );
                            k
                        }
                    };
                    self.cache.touch(slot, self.hop_index);
                    let h = &self.cache.magnitude(slot, bins)[..active];
                    for ((a, hj), s) in self.mag[ear].iter_mut().zip(h).zip(spectrum) {
                        *a += (strength * hj) * s;
                    }
                } else {
                    let ws = strength * (paths.direct.gain as f32).abs();
                    if merge_cells {
                        self.cell_weight[ear][e.cell as usize] += ws;
                    } else {
                        for (a, s) in self.mag[ear].iter_mut().zip(spectrum) {
                            *a += ws * s;
                        }
                    }
                }
            }
        }
        if merge_cells {
            for ear in 0..2 {
                for (c, &w) in self.cell_weight[ear].iter().enumerate().take(cells.len()) {
                    if w != 0.0 {
                        let spectrum = &db.friction_spectrum(CellId(c as u16))[..active];
                        for (a, s) in self.mag[ear].iter_mut().zip(spectrum) {
                            *a += w * s;
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cache_finds_what_it_claimed() {
        let mut c = CombCache::new(8);
        let res = Resonator {
            centre_m: [0.1, 0.0, 0.77],
            normal: [0.0, 0.0, 1.0],
            ..Resonator::default()
        };
        assert!(c.find(&res, 0, 1, 6, true).is_none());
        let k = c.claim(&res, 0, 1, 6);
        c.touch(k, 5);
        assert_eq!(c.find(&res, 0, 1, 6, true), Some(k));
        assert_eq!(c.find(&res, 0, 1, 4, true), Some(k));
        assert!(c.find(&res, 1, 1, 6, true).is_none());
        assert!(c.find(&res, 0, 2, 6, true).is_none());
        // Computed for 6 bins: not enough for a database with sound in 8.
        assert!(c.find(&res, 0, 1, 8, true).is_none());
    }

    #[test]
    fn static_sources_hit_the_cache() {
        let mut db = sounddb::Database::new(sounddb::DbInfo::default(), 44_100);
        db.spectra.push(sounddb::FrictionSpectrum {
            cell: sounddb::Cell::Constrained,
            magnitudes: vec![0.001; 2048],
            speed_m_s: 0.1,
            file: String::new(),
        });
        let db = SoundDb::prepare(&db, 44_100.0);
        let scene = super::super::Scene::default();
        let ears = Ears::from_scene(&scene);
        let reflectors: Vec<Plane> = scene.room.reflectors().collect();
        let mut f = Friction::new(44_100.0, 1);
        let mut counters = RenderCounters::default();
        let src = FrictionSource {
            slip_speed_m_s: 0.1,
            resonator: Resonator {
                centre_m: [0.0, 0.0, 0.77],
                normal: [0.0, 0.0, 1.0],
                ..Resonator::default()
            },
            ..FrictionSource::default()
        };
        let opts = RenderOptions::default();
        let (mut l, mut r) = (vec![0.0f32; 1024], vec![0.0f32; 1024]);
        for _ in 0..10 {
            f.set_sources(&[src], &db, true, &mut counters);
            f.render(
                &db,
                &ears,
                &reflectors,
                1,
                &opts,
                &mut l,
                &mut r,
                &mut counters,
            );
        }
        // The Nyquist bin is always 0, so the comb is computed for the 1 029 bins below it
        // (M = 2058 at 44.1 kHz).
        assert_eq!(db.friction_active_bins(), 1029);
        assert_eq!(counters.friction_comb_bins, 2 * 1029, "{counters:?}");
        assert_eq!(counters.friction_comb_cache_hits, 2 * 8);
    }
}
