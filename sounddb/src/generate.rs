//! # The synthetic default databases
//!
//! No recordings of paper can be had here (digest-sound §10.1–10.2), so the default databases are
//! **synthesized, not recorded**, with the curved-panel modal model of digest-sound §10.3, in the
//! seeds' layout (T 1905–1909, T 1967):
//!
//! - the 9 × 9 grid of (l_r, l_c/2) cells ([`crate::GRID_CM`]), **3 flap clips per cell** (sheet
//!   bent at 10 % compression, as the seeds' flap recordings, T 1909) plus **6 clac clips** in the
//!   (0, 0) cell: 81 · 3 + 6 = 249 clips, the seeds' count (T 1967);
//! - **1 friction spectrum per cell** (30 % compression, T 1909) plus the constrained (0, 0)
//!   spectrum: 82 spectra of 2048 bins over 0–22.05 kHz;
//! - 44.1 kHz, 16-bit mono WAV; ≈ 8 MB per material (the seeds: ≈ 10 MB).
//!
//! The generator is deterministic: a fixed seed per material ([`Material::seed`]), one
//! independent random stream per clip derived from (seed, cell, variant) by SplitMix64. It is also
//! written to be fast **without optimisation** (it runs in the plugin's build script, whose
//! profile is `opt-level = 0` by default): recursions stop as soon as a mode has decayed by 80 dB.
//!
//! The sub-models ([`panel`] for frequencies, [`clips`] for flap/clac clips, [`friction`] for the
//! spectra) document their equations. What a synthetic database loses compared with recordings is
//! listed in digest-sound §10.4 and in the project README: no nonlinear snap-through, no fibre
//! crackle micro-structure, no stick-slip onset, no real "paper" tone, no room/table/microphone
//! colouring, no absolute level calibration; tests of "size → spectrum" trends check our model's
//! consistency, not physical truth.

pub mod clips;
pub mod friction;
pub mod panel;

use rand_pcg::Pcg64;
use rand_pcg::rand_core::{Rng, SeedableRng};

use crate::cell::{Cell, GRID_CM};
use crate::database::{Database, DbInfo, FrictionSpectrum, Unit};
use panel::PaperProps;

/// Paper types the generator knows (the seeds recorded printer paper, tracing paper and bank-note
/// paper, T 1804, S 145).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Material {
    /// 80 g/m² printer paper (the seeds' main database).
    Printer,
    /// Tracing paper: stiffer, denser, less damped — crisper and more ringing.
    Tracing,
    /// Bank-note (cotton) paper: tough, fibrous, more damped, rougher.
    Banknote,
}

/// Model parameters of a material (proposal values; the seeds give only printer paper's
/// 80 g/m² and no mechanical constants).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialParams {
    /// Mechanical properties.
    pub paper: PaperProps,
    /// Loss factor η (T60 = 2.2 / (η f)).
    pub loss_factor: f64,
    /// Roughness noise spectral tilt above `tilt_corner_hz`, dB/octave (power).
    pub roughness_tilt_db_oct: f64,
    /// Corner of the roughness tilt, Hz.
    pub tilt_corner_hz: f64,
    /// Gain of the obstacle "bump" (wooden table: 2–5 kHz), dB.
    pub bump_db: f64,
    /// Centre of the bump, Hz.
    pub bump_hz: f64,
}

impl Material {
    /// All materials.
    pub const ALL: [Material; 3] = [Material::Printer, Material::Tracing, Material::Banknote];

    /// Parses `printer`, `tracing` or `banknote`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name.to_ascii_lowercase().as_str() {
            "printer" => Some(Material::Printer),
            "tracing" => Some(Material::Tracing),
            "banknote" | "bank-note" | "bank_note" => Some(Material::Banknote),
            _ => None,
        }
    }

    /// The short name.
    pub fn name(&self) -> &'static str {
        match self {
            Material::Printer => "printer",
            Material::Tracing => "tracing",
            Material::Banknote => "banknote",
        }
    }

    /// The generator seed of this material's default database.
    pub fn seed(&self) -> u64 {
        match self {
            Material::Printer => 0x5041_5049_4552_0001,
            Material::Tracing => 0x5041_5049_4552_0002,
            Material::Banknote => 0x5041_5049_4552_0003,
        }
    }

    /// Model parameters.
    pub fn params(&self) -> MaterialParams {
        match self {
            // digest-sound §10.3: ρ_s 0.08 kg/m², h 0.1 mm, E 4 GPa, ν 0.3, η 0.02–0.05;
            // roughness −3 dB/oct above 4 kHz, +3 dB wooden-table bump at 2–5 kHz.
            Material::Printer => MaterialParams {
                paper: PaperProps {
                    density_kg_m2: 0.080,
                    thickness_m: 1.0e-4,
                    youngs_pa: 4.0e9,
                    poisson: 0.3,
                },
                loss_factor: 0.03,
                roughness_tilt_db_oct: -3.0,
                tilt_corner_hz: 4000.0,
                bump_db: 3.0,
                bump_hz: 3200.0,
            },
            // Tracing paper: ~90 g/m², thin (0.08 mm) and glassy-stiff, low loss; a smooth surface
            // gives less high-frequency roughness noise.
            Material::Tracing => MaterialParams {
                paper: PaperProps {
                    density_kg_m2: 0.090,
                    thickness_m: 0.8e-4,
                    youngs_pa: 6.0e9,
                    poisson: 0.3,
                },
                loss_factor: 0.02,
                roughness_tilt_db_oct: -4.5,
                tilt_corner_hz: 3000.0,
                bump_db: 2.0,
                bump_hz: 3200.0,
            },
            // Bank-note paper: cotton rag, ~90 g/m², 0.11 mm, tough and fibrous (higher loss),
            // rough surface (flatter roughness spectrum).
            Material::Banknote => MaterialParams {
                paper: PaperProps {
                    density_kg_m2: 0.090,
                    thickness_m: 1.1e-4,
                    youngs_pa: 5.0e9,
                    poisson: 0.3,
                },
                loss_factor: 0.05,
                roughness_tilt_db_oct: -2.0,
                tilt_corner_hz: 5000.0,
                bump_db: 4.0,
                bump_hz: 3200.0,
            },
        }
    }
}

/// Compression of the flap recordings (T 1909).
pub const FLAP_COMPRESSION: f64 = 0.10;
/// Compression of the friction recordings (T 1909).
pub const FRICTION_COMPRESSION: f64 = 0.30;
/// Flap variants per cell (T 1905).
pub const FLAP_VARIANTS: usize = 3;
/// Clac variants in the (0, 0) cell (digest-sound §10.3).
pub const CLAC_VARIANTS: usize = 6;

/// Generates a material's default database (its fixed seed, 44.1 kHz).
pub fn generate(material: Material) -> Database {
    generate_with_seed(material, material.seed())
}

/// Generates a database with another seed (same layout).
pub fn generate_with_seed(material: Material, seed: u64) -> Database {
    let rate = crate::DEFAULT_SAMPLE_RATE_HZ;
    let p = material.params();
    let mut db = Database::new(
        DbInfo {
            name: format!("{} paper (synthesized)", material.name()),
            material: material.name().to_string(),
            obstacle: "wooden table (modelled)".into(),
            synthesized: true,
            description: "Generated by sounddb::generate with the curved-panel modal model of \
                          digest-sound §10.3; not recorded. Layout of the seeds: 9x9 (l_r, l_c/2) \
                          grid, 3 flap clips per cell at 10 % compression, 6 clac clips, 1 friction \
                          spectrum per cell at 30 % compression plus the constrained (0,0) spectrum."
                .into(),
            seed: Some(seed),
        },
        rate,
    );
    for s in GRID_CM {
        for c in GRID_CM {
            let cell = Cell::Free {
                straight_cm: s,
                curved_cm: c,
            };
            for v in 0..FLAP_VARIANTS {
                let mut rng = clip_rng(seed, 1, s, c, v);
                db.units.push(Unit {
                    cell,
                    samples: clips::flap_clip(&p, f64::from(s), f64::from(c), &mut rng, rate),
                    file: String::new(),
                });
            }
        }
    }
    for v in 0..CLAC_VARIANTS {
        let mut rng = clip_rng(seed, 2, 0.0, 0.0, v);
        db.units.push(Unit {
            cell: Cell::Constrained,
            samples: clips::clac_clip(&mut rng, rate),
            file: String::new(),
        });
    }
    let bins = crate::SPECTRUM_BINS;
    for s in GRID_CM {
        for c in GRID_CM {
            let mut rng = clip_rng(seed, 3, s, c, 0);
            db.spectra.push(FrictionSpectrum {
                cell: Cell::Free {
                    straight_cm: s,
                    curved_cm: c,
                },
                magnitudes: friction::free_spectrum(
                    &p,
                    f64::from(s),
                    f64::from(c),
                    FRICTION_COMPRESSION,
                    &mut rng,
                    f64::from(rate),
                    bins,
                ),
                speed_m_s: crate::REFERENCE_SLIDE_SPEED_M_S,
                file: String::new(),
            });
        }
    }
    let mut rng = clip_rng(seed, 4, 0.0, 0.0, 0);
    db.spectra.push(FrictionSpectrum {
        cell: Cell::Constrained,
        magnitudes: friction::constrained_spectrum(&p, &mut rng, f64::from(rate), bins),
        speed_m_s: crate::REFERENCE_SLIDE_SPEED_M_S,
        file: String::new(),
    });
    db
}

/// Independent random stream for one clip or spectrum.
pub fn clip_rng(seed: u64, kind: u64, straight_cm: f32, curved_cm: f32, variant: usize) -> GenRng {
    let mut h = seed;
    for v in [
        kind,
        u64::from(straight_cm.to_bits()),
        u64::from(curved_cm.to_bits()),
        variant as u64,
    ] {
        h = splitmix(h ^ v);
    }
    GenRng(Pcg64::seed_from_u64(h))
}

fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The generator's random stream (PCG64, stable across platforms).
pub struct GenRng(Pcg64);

impl GenRng {
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.0.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Uniform in [−1, 1).
    pub fn signed(&mut self) -> f64 {
        2.0 * self.uniform() - 1.0
    }

    /// Standard exponential variate.
    pub fn exponential(&mut self) -> f64 {
        -(1.0 - self.uniform()).ln()
    }

    /// A draw from P(E) ∝ E^(−γ) on [lo, hi] (inverse CDF).
    pub fn power_law(&mut self, gamma: f64, lo: f64, hi: f64) -> f64 {
        let e = 1.0 - gamma;
        let (a, b) = (lo.powf(e), hi.powf(e));
        (a + (b - a) * self.uniform()).powf(1.0 / e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn material_names() {
        for m in Material::ALL {
            assert_eq!(Material::from_name(m.name()), Some(m));
        }
        assert_eq!(Material::from_name("cardboard"), None);
    }

    #[test]
    fn rng_streams_are_independent_and_repeatable() {
        let a = clip_rng(1, 1, 10.0, 5.0, 0).uniform();
        let b = clip_rng(1, 1, 10.0, 5.0, 0).uniform();
        let c = clip_rng(1, 1, 10.0, 5.0, 1).uniform();
        assert_eq!(a, b);
        assert_ne!(a, c);
        let mut r = clip_rng(7, 0, 0.0, 0.0, 0);
        for _ in 0..1000 {
            let e = r.power_law(1.4, 0.05, 1.0);
            assert!((0.05..=1.0).contains(&e));
        }
    }
}
