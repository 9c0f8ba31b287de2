//! # Playing one crumple unit (a voice)
//!
//! A crumple unit is played once, to its end, at a gain linear in the event amplitude (T 1820,
//! S 153). Its spatialization (eq. 4.11) is a handful of taps per ear: the direct path (with the
//! interaural delay) and one image per reflector, each a gain and a fractional delay
//! ([`super::frac_delay`]). Because the whole unit is in memory, a delayed copy is just a read at
//! an earlier position — no delay line. The taps are fixed at the trigger: a unit is heard from
//! where its resonator was when the event happened, with the listener and room of that moment
//! (units last ≤ 0.8 s; later scene changes affect later units).
//!
//! Per block, a voice converts the 16-bit samples it needs (block + longest delay + 3) to f32
//! once, then every tap is a 4-tap FIR over that scratch — a loop the compiler vectorises.

use sounddb::SoundDb;
use sounddb::prepared::UNIT_PAD;

use super::dipole::{EarPaths, MAX_REFLECTORS};
use super::frac_delay::FracTap;

/// Taps per ear: direct + images.
pub const MAX_TAPS: usize = 1 + MAX_REFLECTORS;

/// A tap before conversion to filter coefficients (kept for merging).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RawTap {
    /// Delay, samples (≥ 0).
    pub delay_samples: f64,
    /// Gain.
    pub gain: f64,
}

/// A voice's taps for both ears.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VoiceTaps {
    /// Raw taps per ear (direct first).
    pub raw: [[RawTap; MAX_TAPS]; 2],
    /// Number of taps per ear.
    pub num: [usize; 2],
}

impl VoiceTaps {
    /// Builds taps from the paths to both ears; delays are (R − R_ref)/c + `base_delay_s`, in
    /// samples.
    pub fn from_paths(
        paths: &[EarPaths; 2],
        ref_delay_s: f64,
        base_delay_s: f64,
        sample_rate_hz: f64,
    ) -> Self {
        let mut taps = Self::default();
        for (ear, p) in paths.iter().enumerate() {
            for (k, path) in p.paths().enumerate() {
                taps.raw[ear][k] = RawTap {
                    delay_samples: ((path.delay_s - ref_delay_s + base_delay_s) * sample_rate_hz)
                        .max(0.0),
                    gain: path.gain,
                };
                taps.num[ear] = k + 1;
            }
        }
        taps
    }

    /// Sum of |gain| of the louder ear.
    pub fn peak_gain(&self) -> f64 {
        (0..2)
            .map(|e| {
                self.raw[e][..self.num[e]]
                    .iter()
                    .map(|t| t.gain.abs())
                    .sum::<f64>()
            })
            .fold(0.0, f64::max)
    }

    /// Largest delay, samples.
    pub fn max_delay(&self) -> f64 {
        (0..2)
            .flat_map(|e| self.raw[e][..self.num[e]].iter().map(|t| t.delay_samples))
            .fold(0.0, f64::max)
    }

    /// Number of image taps (both ears).
    pub fn num_images(&self) -> usize {
        self.num[0].saturating_sub(1) + self.num[1].saturating_sub(1)
    }

    /// True when both tap sets have the same structure and every delay is within `tol` samples.
    pub fn compatible(&self, other: &VoiceTaps, tol: f64) -> bool {
        self.num == other.num
            && (0..2).all(|e| {
                (0..self.num[e]).all(|k| {
                    (self.raw[e][k].delay_samples - other.raw[e][k].delay_samples).abs() <= tol
                })
            })
    }

    /// Adds `other`'s gains (delays: gain-weighted mean). Call only when [`Self::compatible`].
    pub fn merge(&mut self, other: &VoiceTaps) {
        for e in 0..2 {
            for k in 0..self.num[e] {
                let (a, b) = (self.raw[e][k], other.raw[e][k]);
                let wsum = a.gain.abs() + b.gain.abs();
                let delay = if wsum > 0.0 {
                    (a.delay_samples * a.gain.abs() + b.delay_samples * b.gain.abs()) / wsum
                } else {
                    a.delay_samples
                };
                self.raw[e][k] = RawTap {
                    delay_samples: delay,
                    gain: a.gain + b.gain,
                };
            }
        }
    }
}

/// A playing unit.
#[derive(Clone, Copy, Debug, Default)]
pub struct Voice {
    /// Playing?
    pub active: bool,
    /// Unit index in the database.
    pub unit: u32,
    /// Crumple cell of the unit.
    pub cell: u16,
    /// Samples already rendered since the voice started.
    pub pos: u64,
    /// `pos` at which every tap has read past the unit's end.
    pub end: u64,
    /// Renderer clock at the start.
    pub start_clock: u64,
    /// Trigger batch (render-call index) it was started in.
    pub batch: u64,
    /// Estimated output peak (linear): unit peak × summed |tap gain| of the louder ear.
    pub est_peak: f32,
    /// Raw taps.
    pub taps: VoiceTaps,
    /// Filter taps per ear.
    pub filters: [[FracTap; MAX_TAPS]; 2],
    /// Largest integer delay over all filters.
    pub max_delay_int: u32,
}

impl Voice {
    /// (Re)computes the filters and the end from the raw taps.
    pub fn update_filters(&mut self, unit_len: usize) {
        let mut max_int = 0;
        for e in 0..2 {
            for k in 0..self.taps.num[e] {
                let t = self.taps.raw[e][k];
                let f = FracTap::new(t.delay_samples, t.gain);
                max_int = max_int.max(f.delay_int);
                self.filters[e][k] = f;
            }
        }
        self.max_delay_int = max_int;
        // Tap k reads x[n − D_int − 2 + k]; the last output touching x[len − 1] is
        // n = len + D_int + 1, so the voice ends (exclusive) at len + D_int + 2.
        self.end = unit_len as u64 + u64::from(max_int) + 2;
    }

    /// Estimated peak of the remaining output (linear decay assumption), for stealing.
    pub fn remaining_level(&self) -> f32 {
        if self.end == 0 {
            return 0.0;
        }
        let left = self.end.saturating_sub(self.pos) as f32 / self.end as f32;
        self.est_peak * left
    }

    /// Adds the next `out_l.len()` samples of this voice into `out_l` / `out_r` and advances.
    /// `scratch` must hold at least `out_l.len() + max_delay_int + 3` samples. Returns the number
    /// of image taps rendered.
    pub fn render(
        &mut self,
        db: &SoundDb,
        scratch: &mut [f32],
        out_l: &mut [f32],
        out_r: &mut [f32],
    ) -> u64 {
        let n = out_l.len().min(out_r.len());
        let u = *db.unit(self.unit as usize);
        let pcm = db.unit_padded_pcm(self.unit as usize);
        // Scratch index s ↔ unit sample i = pos − max_delay_int − 2 + s.
        let dmax = self.max_delay_int as i64;
        let first = self.pos as i64 - dmax - 2;
        let need = n + dmax as usize + 3;
        let scratch = &mut scratch[..need];
        // Padded index = i + UNIT_PAD; valid 0 ≤ padded < pcm.len(). Only the scratch ranges
        // the taps read are decoded: with a far reflector the span dmax is hundreds of samples,
        // many times a short block, and the taps read just n + 3 samples each.
        let pad = UNIT_PAD as i64;
        let mut spans = [(0usize, 0usize); 2 * MAX_TAPS];
        let mut num_spans = 0;
        for e in 0..2 {
            for k in 0..self.taps.num[e] {
                let a = (dmax - i64::from(self.filters[e][k].delay_int)) as usize;
                spans[num_spans] = (a, (a + n + 3).min(need));
                num_spans += 1;
            }
        }
        let spans = &mut spans[..num_spans];
        spans.sort_unstable();
        let mut k = 0;
        while k < spans.len() {
            let (a, mut b) = spans[k];
            k += 1;
            while k < spans.len() && spans[k].0 <= b {
                b = b.max(spans[k].1);
                k += 1;
            }
            // Scratch [a, b) ↔ padded [first + pad + a, first + pad + b), zero outside the PCM.
            let lo = (-(first + pad)).clamp(a as i64, b as i64) as usize;
            let hi = (pcm.len() as i64 - (first + pad)).clamp(a as i64, b as i64) as usize;
            if lo < hi {
                scratch[a..lo].fill(0.0);
                let src =
                    &pcm[(first + pad + lo as i64) as usize..(first + pad + hi as i64) as usize];
                for (s, &q) in scratch[lo..hi].iter_mut().zip(src) {
                    *s = f32::from(q) * u.scale;
                }
                scratch[hi..b].fill(0.0);
            } else {
                scratch[a..b].fill(0.0);
            }
        }
        let mut images = 0;
        for (e, out) in [&mut out_l[..n], &mut out_r[..n]].into_iter().enumerate() {
            let num = self.taps.num[e];
            let off = |k: usize| (dmax - i64::from(self.filters[e][k].delay_int)) as usize;
            match num {
                0 => {}
                1 => self.filters[e][0].add_to(&scratch[off(0)..], out),
                2 => add_two(
                    &self.filters[e][0],
                    &scratch[off(0)..],
                    &self.filters[e][1],
                    &scratch[off(1)..],
                    out,
                ),
                _ => {
                    add_two(
                        &self.filters[e][0],
                        &scratch[off(0)..],
                        &self.filters[e][1],
                        &scratch[off(1)..],
                        out,
                    );
                    for k in 2..num {
                        self.filters[e][k].add_to(&scratch[off(k)..], out);
                    }
                }
            }
            images += num.saturating_sub(1) as u64;
        }
        self.pos += n as u64;
        images
    }
}

/// Two taps in one pass over `out` (one load/store of the output for eight input reads). Same
/// arithmetic order as two [`FracTap::add_to`] calls: (out + tap a) + tap b.
#[inline]
fn add_two(a: &FracTap, xa: &[f32], b: &FracTap, xb: &[f32], out: &mut [f32]) {
    let n = out.len();
    let [a0, a1, a2, a3] = a.coeffs;
    let [b0, b1, b2, b3] = b.coeffs;
    let (p0, p1, p2, p3) = (&xa[..n], &xa[1..n + 1], &xa[2..n + 2], &xa[3..n + 3]);
    let (q0, q1, q2, q3) = (&xb[..n], &xb[1..n + 1], &xb[2..n + 2], &xb[3..n + 3]);
    for t in 0..n {
        let ta = a0 * p0[t] + a1 * p1[t] + a2 * p2[t] + a3 * p3[t];
        let tb = b0 * q0[t] + b1 * q1[t] + b2 * q2[t] + b3 * q3[t];
        out[t] = (out[t] + ta) + tb;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sounddb::{Cell, Database, DbInfo, Unit};

    fn impulse_db() -> SoundDb {
        let mut db = Database::new(DbInfo::default(), 48_000);
        let mut x = vec![0.0f32; 64];
        x[0] = 1.0;
        x[1] = 0.5;
        db.units.push(Unit {
            cell: Cell::Constrained,
            samples: x,
            file: String::new(),
        });
        SoundDb::prepare(&db, 48_000.0)
    }

    #[test]
    fn direct_and_image_taps_in_any_block_split() {
        let db = impulse_db();
        let mut v = Voice {
            active: true,
            unit: 0,
            ..Voice::default()
        };
        v.taps.num = [2, 1];
        v.taps.raw[0][0] = RawTap {
            delay_samples: 0.0,
            gain: 1.0,
        };
        v.taps.raw[0][1] = RawTap {
            delay_samples: 5.5,
            gain: -0.5,
        };
        v.taps.raw[1][0] = RawTap {
            delay_samples: 2.0,
            gain: 0.25,
        };
        v.update_filters(db.unit(0).len);
        let mut scratch = vec![0.0f32; 64];
        let mut whole = [vec![0.0f32; 16], vec![0.0f32; 16]];
        let mut w = v;
        let [wl, wr] = &mut whole;
        w.render(&db, &mut scratch, wl, wr);
        let mut parts = [vec![0.0f32; 16], vec![0.0f32; 16]];
        let mut p = v;
        for (a, b) in [(0, 3), (3, 4), (4, 16)] {
            let [pl, pr] = &mut parts;
            p.render(&db, &mut scratch, &mut pl[a..b], &mut pr[a..b]);
        }
        assert_eq!(whole, parts);
        // 16-bit storage: within one LSB of the unit's peak.
        let lsb = 1.0 / 32767.0;
        assert!((whole[0][0] - 1.0).abs() <= lsb);
        assert!((whole[0][1] - 0.5).abs() <= lsb);
        assert!((whole[1][2] - 0.25).abs() <= lsb);
        // The image is centred at 5.5 with total weight −0.5·(1 + 0.5).
        let img: f32 = whole[0][3..10].iter().sum();
        assert!((img + 0.75).abs() < 1e-4, "{img}");
        // Voice length: the trimmed unit (2 samples) + the largest integer delay (5) + 2.
        assert_eq!(v.end, db.unit(0).len as u64 + 5 + 2);
    }
}
