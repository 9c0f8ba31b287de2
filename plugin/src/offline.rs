//! # The offline renderer (`papier-render`)
//!
//! Renders Papier without a host, with the same engine code as the plugin's `process()`
//! ([`render`]). The sheet is stepped in lockstep with the audio
//! ([`crate::engine::SimMode::Lockstep`]), so two renders of the same input give the same bytes,
//! whatever the block size. It uses the engine, the render path and sim-core, never the plugin
//! face (parameters, persistence, editor).
//!
//! Inputs ([`cli`]): Standard MIDI Files ([`midi_file`]), TOML scripts and built-in scenes
//! ([`sim_core::script`]), merged on one timeline ([`timeline`]). Output: a stereo WAV (32-bit
//! float) via `hound`, and optionally the sheet as a sequence of Wavefront OBJ files and the
//! sound input as a frame log (`--write-frames`). A frame log can also be the input
//! (`--frames`): it is then played through the render path alone, with no sheet
//! ([`frame_replay`]; the log format is [`frame_log`]).
//!
//! Parts: [`cli`] (arguments), [`render`] (the render loop), [`batch`] (many takes from a job
//! file, on every core, sharded over machines), [`report`], [`wav_out`],
//! [`obj_out`], [`progress`], [`frame_log`] / [`frame_replay`] (sound-frame logs), [`midi_file`]
//! / [`midi_export`] (Standard MIDI Files in and out), [`timeline`] (inputs merged in time),
//! [`error`].

pub mod batch;
pub mod cli;
pub mod error;
pub mod frame_log;
pub mod frame_replay;
pub mod midi_export;
pub mod midi_file;
pub mod obj_out;
pub mod progress;
pub mod render;
pub mod report;
pub mod timeline;
pub mod wav_out;

use std::path::Path;

use sim_core::script::Script;

use self::cli::InputSpec;
pub use self::error::OfflineError;
use self::midi_export::MidiExport;
pub use self::render::render;
pub use self::report::{RenderReport, SheetAccuracy};
use crate::engine::FrameClock;

/// Longest render accepted, seconds (one hour).
pub const MAX_RENDER_S: f64 = 3600.0;

/// The built-in scene names.
pub fn scene_names() -> Vec<&'static str> {
    sim_core::scenario::names().collect()
}

pub(crate) fn load_scene(name: &str) -> Result<Script, OfflineError> {
    if sim_core::scenario::text(name).is_none() {
        return Err(OfflineError::Input(format!(
            "unknown scene {name:?}; available: {}",
            scene_names().join(", ")
        )));
    }
    sim_core::scenario::get(name).map_err(|e| OfflineError::Input(format!("scene {name}: {e}")))
}

/// Writes the inputs as a MIDI performance (README map) to `out` ([`midi_export`]).
pub fn write_midi(inputs: &[InputSpec], out: &Path) -> Result<MidiExport, OfflineError> {
    let sr = 48_000.0;
    let frames = FrameClock::new(sr, sim_core::sim::DEFAULT_FRAME_RATE_HZ);
    let tl = render::read_inputs(inputs, sr, frames)?;
    let x = midi_export::export(&tl, sr);
    if let Some(parent) = out.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent).map_err(|e| {
            OfflineError::Output(format!("cannot create {}: {e}", parent.display()))
        })?;
    }
    std::fs::write(out, x.to_smf())
        .map_err(|e| OfflineError::Output(format!("cannot write {}: {e}", out.display())))?;
    Ok(x)
}

/// Prints to stdout, ignoring a closed pipe (`papier-render ... | head` must not panic).
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($t)*);
    }};
}

/// The phrases `papier-render` plays from MIDI notes: the factory set, plus a folder's.
pub fn phrase_bank(dir: Option<&std::path::Path>) -> crate::phrase::PhraseBank {
    match dir {
        Some(d) => crate::phrase::PhraseBank::with_folder(d),
        None => crate::phrase::PhraseBank::factory(),
    }
}

/// `papier-render`'s entry point: parses the arguments (without the program name), renders,
/// prints the report, and returns the exit code.
pub fn main_with_args(args: &[String]) -> i32 {
    let cli = match cli::parse(args) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("papier-render: error: {e}");
            return 2;
        }
    };
    match cli {
        cli::Cli::Help => {
            say!("{}", cli::USAGE);
            0
        }
        cli::Cli::ListScenes => {
            for n in scene_names() {
                say!("{n}");
            }
            0
        }
        cli::Cli::ListPhrases(dir) => {
            let bank = phrase_bank(dir.as_deref());
            for e in &bank.errors {
                eprintln!("papier-render: warning: {e}");
            }
            for p in bank.by_note() {
                let start = match p.start {
                    crate::phrase::PhraseStart::Fresh => "fresh",
                    crate::phrase::PhraseStart::Current => "current",
                };
                say!(
                    "{:>3}  {:<4} {:<28} {:>5.1} s  {start}  ({})",
                    p.note,
                    crate::phrase::note_name(p.note),
                    p.name,
                    p.duration_s,
                    p.source
                );
            }
            0
        }
        cli::Cli::WriteMidi { inputs, out, quiet } => match write_midi(&inputs, &out) {
            Ok(x) => {
                if !quiet {
                    let sets: String = x.sets.iter().map(|s| format!(" --set {s}")).collect();
                    say!(
                        "papier-render: wrote {} ({} messages, {:.2} s)\n  render it: papier-render --midi {}{sets} --out OUT.wav",
                        out.display(),
                        x.events.len(),
                        x.length_s,
                        out.display()
                    );
                    if !x.dropped.is_empty() {
                        say!(
                            "  not in the file (no MIDI control for them): {}",
                            x.dropped.join(", ")
                        );
                    }
                }
                0
            }
            Err(e) => {
                eprintln!("papier-render: error: {e}");
                e.exit_code()
            }
        },
        cli::Cli::Batch {
            file,
            shard,
            jobs,
            quiet,
        } => {
            let takes = match batch::read(&file) {
                Ok(t) => t,
                Err(e) => {
                    eprintln!("papier-render: error: {e}");
                    return 2;
                }
            };
            let threads = jobs.unwrap_or_else(|| {
                std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
            });
            let summary = batch::run(&takes, shard, threads, quiet);
            if !quiet {
                say!("{}", summary.to_string().trim_end());
            }
            for r in &summary.results {
                if let Err(e) = &r.outcome {
                    eprintln!("papier-render: error: take {}: {e}", r.stem);
                }
            }
            i32::from(summary.failed() > 0)
        }
        cli::Cli::Render(opts) => match render(&opts) {
            Ok(report) => {
                if !opts.quiet {
                    say!("{report}");
                }
                0
            }
            Err(e) => {
                eprintln!("papier-render: error: {e}");
                e.exit_code()
            }
        },
    }
}
