//! # The rendered audio as a stereo 32-bit float WAV (`hound`), with its running peak and RMS.

use std::io::BufWriter;
use std::path::{Path, PathBuf};

use super::OfflineError;

/// The stereo WAV being written, with its running peak and energy.
pub struct AudioOut {
    path: PathBuf,
    wav: hound::WavWriter<BufWriter<std::fs::File>>,
    samples: u64,
    sum_sq: f64,
    peak: f32,
}

impl AudioOut {
    /// Creates the file (and its folder).
    pub fn create(path: &Path, sample_rate_hz: u32) -> Result<Self, OfflineError> {
        if let Some(parent) = path.parent()
            && !parent.as_os_str().is_empty()
        {
            std::fs::create_dir_all(parent).map_err(|e| {
                OfflineError::Output(format!("cannot create {}: {e}", parent.display()))
            })?;
        }
        let spec = hound::WavSpec {
            channels: 2,
            sample_rate: sample_rate_hz,
            bits_per_sample: 32,
            sample_format: hound::SampleFormat::Float,
        };
        let wav = hound::WavWriter::create(path, spec)
            .map_err(|e| OfflineError::Output(format!("cannot write {}: {e}", path.display())))?;
        Ok(Self {
            path: path.to_path_buf(),
            wav,
            samples: 0,
            sum_sq: 0.0,
            peak: 0.0,
        })
    }

    fn error(&self, e: hound::Error) -> OfflineError {
        OfflineError::Output(format!("cannot write {}: {e}", self.path.display()))
    }

    /// Appends a block (both channels the same length).
    pub fn write(&mut self, left: &[f32], right: &[f32]) -> Result<(), OfflineError> {
        for (&l, &r) in left.iter().zip(right) {
            self.sum_sq += f64::from(l) * f64::from(l) + f64::from(r) * f64::from(r);
            self.peak = self.peak.max(l.abs()).max(r.abs());
            if let Err(e) = self
                .wav
                .write_sample(l)
                .and_then(|_| self.wav.write_sample(r))
            {
                return Err(self.error(e));
            }
        }
        self.samples += left.len().min(right.len()) as u64;
        Ok(())
    }

    /// Finalizes the file; returns (peak, RMS over both channels).
    pub fn finish(self) -> Result<(f32, f32), OfflineError> {
        let path = self.path;
        self.wav
            .finalize()
            .map_err(|e| OfflineError::Output(format!("cannot write {}: {e}", path.display())))?;
        let rms = if self.samples > 0 {
            (self.sum_sq / (2 * self.samples) as f64).sqrt() as f32
        } else {
            0.0
        };
        Ok((self.peak, rms))
    }
}

/// What the engine does to every block it renders, and the replay too: never let a NaN, an
/// infinity or a subnormal out (the render path already guarantees finite, normal output).
pub fn sanitize(left: &mut [f32], right: &mut [f32]) {
    for s in left.iter_mut().chain(right.iter_mut()) {
        if !(s.is_normal() || *s == 0.0) {
            *s = 0.0;
        }
    }
}
