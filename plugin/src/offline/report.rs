//! # What a render did ([`RenderReport`]) and how `papier-render` prints it: the simulation's
//! cost, the sheet's accuracy against its pattern (c_mean, n_comp, strain: at the end and the
//! worst seen), the audio's level, the OBJ frames and the frame log written.

use std::path::PathBuf;

use sim_core::metrics::Metrics;

use super::frame_replay::RecordedLog;

/// What a render did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderReport {
    /// Output file.
    pub out: PathBuf,
    /// Rendered length, seconds.
    pub length_s: f64,
    /// Sample rate, Hz.
    pub sample_rate_hz: u32,
    /// Simulation frames stepped.
    pub frames: u64,
    /// Frames in which the sheet slept.
    pub frames_asleep: u64,
    /// Mean step time, ms.
    pub mean_step_ms: f64,
    /// Longest step time, ms.
    pub max_step_ms: f64,
    /// Crumple events delivered to the sound.
    pub crumple_events: u64,
    /// Interior singular vertices at the end.
    pub num_singular: u32,
    /// Accuracy of the sheet against its 2D pattern (sim_core::metrics), when a sheet was
    /// simulated: the last frame's figures and the worst seen at the end of any sub-block.
    pub sheet: Option<SheetAccuracy>,
    /// Peak sample, linear.
    pub peak: f32,
    /// RMS over both channels, linear.
    pub rms: f32,
    /// OBJ frames written.
    pub obj_frames: u64,
    /// The frame log played (`--frames`): no sheet was simulated, `frames` counts its frames.
    pub frame_log_in: Option<PathBuf>,
    /// The frame log written (`--write-frames`).
    pub frame_log_out: Option<RecordedLog>,
    /// Wall-clock time, seconds.
    pub wall_s: f64,
    /// `--realtime`: frames the simulation thread skipped because it fell behind the audio.
    pub frames_skipped: Option<u64>,
}

/// How isometric the simulated sheet stayed (see `sim_core::metrics::Metrics`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SheetAccuracy {
    /// The last frame's metrics.
    pub end: Metrics,
    /// Largest mean edge compression seen, %.
    pub max_c_mean_pct: f64,
    /// Largest share of edges compressed > 1 % seen, %.
    pub max_n_comp_pct: f64,
    /// Largest principal Green strain seen.
    pub max_strain: f64,
}

impl SheetAccuracy {
    pub(super) fn observe(&mut self, m: &Metrics) {
        self.end = *m;
        self.max_c_mean_pct = self.max_c_mean_pct.max(m.c_mean_pct);
        self.max_n_comp_pct = self.max_n_comp_pct.max(m.n_comp_pct);
        self.max_strain = self.max_strain.max(m.max_strain);
    }
}

fn db_string(x: f32) -> String {
    if x > 0.0 {
        format!("{:.1} dBFS", 20.0 * x.log10())
    } else {
        "silent".into()
    }
}

impl std::fmt::Display for RenderReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "papier-render: {:.2} s at {} Hz -> {} (stereo, 32-bit float)",
            self.length_s,
            self.sample_rate_hz,
            self.out.display()
        )?;
        match &self.frame_log_in {
            Some(log) => writeln!(
                f,
                "  log:   {} frames played from {} (no sheet simulated)",
                self.frames,
                log.display()
            )?,
            None => writeln!(
                f,
                "  sim:   {} frames ({:.0} % asleep), step mean {:.3} ms, max {:.3} ms, {} singular points",
                self.frames,
                if self.frames > 0 {
                    100.0 * self.frames_asleep as f64 / self.frames as f64
                } else {
                    0.0
                },
                self.mean_step_ms,
                self.max_step_ms,
                self.num_singular
            )?,
        }
        if let Some(a) = &self.sheet {
            writeln!(
                f,
                "  sheet: c_mean {:.3} %, n_comp {:.2} %, max strain {:.4} at the end \
                 (worst: c_mean {:.3} %, n_comp {:.2} %, strain {:.4})",
                a.end.c_mean_pct,
                a.end.n_comp_pct,
                a.end.max_strain,
                a.max_c_mean_pct,
                a.max_n_comp_pct,
                a.max_strain
            )?;
        }
        writeln!(
            f,
            "  audio: peak {}, RMS {}, {} crumple events",
            db_string(self.peak),
            db_string(self.rms),
            self.crumple_events
        )?;
        if let Some(n) = self.frames_skipped {
            writeln!(
                f,
                "  live:  {n} frames skipped by the simulation thread (played in real time)"
            )?;
        }
        if self.obj_frames > 0 {
            writeln!(f, "  obj:   {} frames", self.obj_frames)?;
        }
        if let Some(log) = &self.frame_log_out {
            writeln!(
                f,
                "  log:   {} sound frames -> {}\n  replay it: {}",
                log.frames,
                log.path.display(),
                log.replay_command()
            )?;
            if !log.not_in_log.is_empty() {
                writeln!(
                    f,
                    "  not in the log (the inputs change them after t = 0): {}",
                    log.not_in_log.join(", ")
                )?;
            }
        }
        write!(
            f,
            "  took {:.2} s ({:.1}x real time)",
            self.wall_s,
            if self.wall_s > 0.0 {
                self.length_s / self.wall_s
            } else {
                0.0
            }
        )
    }
}
