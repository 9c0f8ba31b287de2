//! # `papier-render` command line
//!
//! ```text
//! papier-render (--midi FILE.mid | --script FILE.toml | --scene NAME)... --out FILE.wav
//!               [--sample-rate HZ] [--block N] [--seed N] [--preset NAME|FILE]...
//!               [--set ID=VALUE]... [--obj-dir DIR] [--obj-fps N] [--db DIR] [--phrases DIR] [--write-frames FILE.jsonl]
//!               [--quiet] [--realtime]
//! papier-render --frames FILE.jsonl --out FILE.wav
//!               [--sample-rate HZ] [--block N] [--seed N] [--set ID=VALUE]... [--db DIR] [--quiet]
//! papier-render --batch FILE.toml [--shard I/N] [--jobs N] [--quiet]
//! ```
//! Every input plays on one shared timeline from t = 0 (like tracks of a DAW); the render
//! lasts as long as the longest input. Values given with `--seed` and `--set` are applied at
//! t = 0 after the scripts' `[set]` tables and the `--preset`s, so the command line wins.
//!
//! `--frames` plays a recorded log of sound frames ([`super::frame_log`]) through the
//! render path without simulating a sheet ([`super::frame_replay`]); it is an input of its own
//! and cannot be combined with other inputs, `--obj-dir`, `--write-frames` or `--write-midi`
//! (a log holds sounds, not gestures or a sheet). `--write-frames` records the sound frames of a
//! simulated render as such a log. `--realtime` plays the inputs at the pace of the audio clock
//! with the sheet on its own thread, as a host plays the plugin live, and reports the frames that
//! thread skipped (a measurement of the live worker, not a reproducible render: no OBJ, no log).

use std::path::PathBuf;

/// Smallest sample rate accepted, Hz.
pub const MIN_SAMPLE_RATE_HZ: u32 = 8_000;
/// Largest sample rate accepted, Hz.
pub const MAX_SAMPLE_RATE_HZ: u32 = 192_000;
/// Largest block size accepted.
pub const MAX_BLOCK: usize = 16_384;

/// One input of the render.
#[derive(Clone, Debug, PartialEq)]
pub enum InputSpec {
    /// A Standard MIDI File.
    Midi(PathBuf),
    /// A TOML automation script.
    Script(PathBuf),
    /// A scenario of the built-in library.
    Scene(String),
    /// A recorded log of sound frames (JSON lines), played without simulating; on its own.
    Frames(PathBuf),
}

/// Parsed options.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Inputs, in command-line order.
    pub inputs: Vec<InputSpec>,
    /// Output WAV path.
    pub out: PathBuf,
    /// Sample rate, Hz.
    pub sample_rate_hz: u32,
    /// Block size the renderer feeds the engine with.
    pub block: usize,
    /// Seed (sheet and sound), if given.
    pub seed: Option<u64>,
    /// `ID=VALUE` parameter settings.
    pub sets: Vec<String>,
    /// Directory for the OBJ sequence.
    pub obj_dir: Option<PathBuf>,
    /// OBJ frames per second.
    pub obj_fps: f64,
    /// User sound database directory.
    pub db: Option<PathBuf>,
    /// Folder of the user's phrases (added to the factory phrases).
    pub phrases: Option<PathBuf>,
    /// Presets (names or files), applied at t = 0 in order, before `--seed` and `--set`.
    pub presets: Vec<String>,
    /// Where to record the sound frames of the render (JSON lines), if anywhere.
    pub write_frames: Option<PathBuf>,
    /// Print only errors.
    pub quiet: bool,
    /// Play in real time with the simulation on its own thread (the live worker).
    pub realtime: bool,
}

impl RenderOptions {
    /// Options with `papier-render`'s defaults (48 kHz, blocks of 512, no seed or settings, no
    /// OBJ, the embedded database, no frame log written, progress shown) for these inputs and
    /// output.
    pub fn new(inputs: Vec<InputSpec>, out: PathBuf) -> Self {
        Self {
            inputs,
            out,
            sample_rate_hz: 48_000,
            block: 512,
            seed: None,
            sets: Vec::new(),
            obj_dir: None,
            obj_fps: 30.0,
            db: None,
            phrases: None,
            presets: Vec::new(),
            write_frames: None,
            quiet: false,
            realtime: false,
        }
    }
}

/// What the command line asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum Cli {
    /// Render.
    Render(RenderOptions),
    /// Print the usage.
    Help,
    /// List the built-in scenes.
    ListScenes,
    /// List the phrases (factory, and the folder's if given).
    ListPhrases(Option<PathBuf>),
    /// Render the takes of a job file (`--batch`).
    Batch {
        /// The job file.
        file: PathBuf,
        /// The share of the takes to render.
        shard: super::batch::Shard,
        /// Worker threads (default: the cores).
        jobs: Option<usize>,
        /// Print only errors.
        quiet: bool,
    },
    /// Write the inputs as a MIDI performance (README map) instead of rendering.
    WriteMidi {
        /// The inputs.
        inputs: Vec<InputSpec>,
        /// The MIDI file to write.
        out: PathBuf,
        /// Print only errors.
        quiet: bool,
    },
}

/// The usage text.
pub const USAGE: &str =
    "usage: papier-render (--midi FILE.mid | --script FILE.toml | --scene NAME)... --out FILE.wav
                     [--sample-rate HZ] [--block N] [--seed N] [--preset NAME|FILE]...
                     [--set ID=VALUE]... [--obj-dir DIR] [--obj-fps N] [--db DIR] [--phrases DIR]
                     [--write-frames FILE.jsonl] [--quiet] [--realtime]
       papier-render --frames FILE.jsonl --out FILE.wav
                     [--sample-rate HZ] [--block N] [--seed N] [--set ID=VALUE]... [--db DIR] [--quiet]
       papier-render --batch FILE.toml [--shard I/N] [--jobs N] [--quiet]
       papier-render --list-scenes | --list-phrases [--phrases DIR]
Renders Papier offline (the plugin's engine, stepped in lockstep with the audio) to a WAV file.
  --midi FILE        play a Standard MIDI File (README: MIDI map)
  --script FILE      play a TOML automation script (sim-core/src/script.rs)
  --scene NAME       play a built-in scenario (see --list-scenes)
  --frames FILE      play a recorded log of sound frames (JSON lines, one frame per line,
                     plugin/src/offline/frame_log.rs) without simulating the sheet: each frame
                     sounds from its time_s on, the render ends at the last frame's time_s;
                     only the sound settings apply (seed, room, listener, mix); on its own
  --out FILE         output WAV (stereo, 32-bit float)
  --sample-rate HZ   8000-192000 (default 48000)
  --block N          host block size to emulate, 1-16384 (default 512)
  --seed N           seed of the sheet and of the sound (parameter `seed`)
  --preset NAME      apply a paper, room or mix preset at t = 0 (a factory preset's name,
                     a user preset's, or a preset .toml file; README: presets)
  --set ID=VALUE     set a parameter at t = 0, e.g. --set size=a6 (ids: README)
  --obj-dir DIR      write the sheet as frame_00000.obj, ... (v: metres, vt: pattern metres)
  --obj-fps N        OBJ frames per second (default 30)
  --db DIR           use a user sound database instead of the embedded one
  --phrases DIR      add the phrases of a folder (*.toml with a [phrase] table) to the
                     factory phrases; MIDI notes from 60 (C4) play them (README: performing)
  --write-frames FILE  also record the render's sound frames as a log for --frames (its
                     header comment gives the --set options that replay it)
  --write-midi FILE  write the inputs as a MIDI performance (README map: grabs as notes,
                     gestures as CCs) instead of rendering; prints the --set options it needs
  --batch FILE       render every take of a job file (plugin/src/offline/batch.rs), on
                     all cores, each take's bytes those of its single render; a summary
                     table at the end; a failed take is reported and the others go on
  --shard I/N        with --batch: render the takes whose index is I modulo N (job arrays)
  --jobs N           with --batch: worker threads (default: the cores)
  --quiet            print only errors
  --realtime         play at the audio clock's pace with the sheet simulated on its own thread,
                     as a host plays the plugin live; reports the frames that thread skipped
                     (the output is not reproducible; no --obj-dir, --write-frames or --frames)";

/// Parses the arguments (without the program name). The error is one line.
pub fn parse(args: &[String]) -> Result<Cli, String> {
    let defaults = RenderOptions::new(Vec::new(), PathBuf::new());
    let mut inputs = Vec::new();
    let mut out = None;
    let mut sample_rate_hz = defaults.sample_rate_hz;
    let mut block = defaults.block;
    let mut seed = defaults.seed;
    let mut sets = defaults.sets;
    let mut obj_dir = defaults.obj_dir;
    let mut obj_fps = defaults.obj_fps;
    let mut db = defaults.db;
    let mut phrases = defaults.phrases;
    let mut presets = defaults.presets;
    let mut list_phrases = false;
    let mut write_frames = defaults.write_frames;
    let mut quiet = defaults.quiet;
    let mut realtime = defaults.realtime;
    let mut write_midi = None;
    let mut batch_file = None;
    let mut shard = None;
    let mut jobs = None;

    let mut i = 0;
    while i < args.len() {
        let arg = args[i].as_str();
        let (flag, inline) = match arg.split_once('=') {
            Some((f, v)) if f.starts_with("--") => (f, Some(v.to_string())),
            _ => (arg, None),
        };
        let mut value = |name: &str| -> Result<String, String> {
            if let Some(v) = inline.clone() {
                return Ok(v);
            }
            i += 1;
            args.get(i)
                .cloned()
                .ok_or_else(|| format!("{name} needs a value"))
        };
        match flag {
            "-h" | "--help" => return Ok(Cli::Help),
            "--list-scenes" => return Ok(Cli::ListScenes),
            "--list-phrases" => list_phrases = true,
            "--phrases" => phrases = Some(PathBuf::from(value("--phrases")?)),
            "--preset" => presets.push(value("--preset")?),
            "--midi" => inputs.push(InputSpec::Midi(value("--midi")?.into())),
            "--script" => inputs.push(InputSpec::Script(value("--script")?.into())),
            "--scene" => inputs.push(InputSpec::Scene(value("--scene")?)),
            "--frames" => inputs.push(InputSpec::Frames(value("--frames")?.into())),
            "--out" => out = Some(PathBuf::from(value("--out")?)),
            "--sample-rate" => {
                let v = value("--sample-rate")?;
                sample_rate_hz = v
                    .parse::<u32>()
                    .ok()
                    .filter(|r| (MIN_SAMPLE_RATE_HZ..=MAX_SAMPLE_RATE_HZ).contains(r))
                    .ok_or_else(|| {
                        format!(
                            "--sample-rate {v}: expected a whole number of Hz from \
                             {MIN_SAMPLE_RATE_HZ} to {MAX_SAMPLE_RATE_HZ}"
                        )
                    })?;
            }
            "--block" => {
                let v = value("--block")?;
                block = v
                    .parse::<usize>()
                    .ok()
                    .filter(|b| (1..=MAX_BLOCK).contains(b))
                    .ok_or_else(|| format!("--block {v}: expected 1 to {MAX_BLOCK}"))?;
            }
            "--seed" => {
                let v = value("--seed")?;
                let max = crate::engine::param_values::MAX_SEED as u64;
                seed = Some(
                    v.parse::<u64>()
                        .ok()
                        .filter(|s| *s <= max)
                        .ok_or_else(|| format!("--seed {v}: expected 0 to {max}"))?,
                );
            }
            "--set" => sets.push(value("--set")?),
            "--obj-dir" => obj_dir = Some(PathBuf::from(value("--obj-dir")?)),
            "--obj-fps" => {
                let v = value("--obj-fps")?;
                obj_fps = v
                    .parse::<f64>()
                    .ok()
                    .filter(|f| f.is_finite() && (1.0..=1000.0).contains(f))
                    .ok_or_else(|| format!("--obj-fps {v}: expected 1 to 1000"))?;
            }
            "--db" => db = Some(PathBuf::from(value("--db")?)),
            "--write-midi" => write_midi = Some(PathBuf::from(value("--write-midi")?)),
            "--write-frames" => write_frames = Some(PathBuf::from(value("--write-frames")?)),
            "--quiet" | "-q" => quiet = true,
            "--realtime" => realtime = true,
            "--batch" => batch_file = Some(PathBuf::from(value("--batch")?)),
            "--shard" => shard = Some(super::batch::Shard::parse(&value("--shard")?)?),
            "--jobs" => {
                let v = value("--jobs")?;
                jobs = Some(
                    v.parse::<usize>()
                        .ok()
                        .filter(|n| (1..=1024).contains(n))
                        .ok_or_else(|| format!("--jobs {v}: expected 1 to 1024"))?,
                );
            }
            other => return Err(format!("unknown option {other:?} (see --help)")),
        }
        i += 1;
    }
    if list_phrases {
        return Ok(Cli::ListPhrases(phrases));
    }
    if let Some(file) = batch_file {
        if !inputs.is_empty() || out.is_some() || write_midi.is_some() || realtime {
            return Err(
                "--batch takes its inputs and outputs from the job file: drop --midi, --script, \
                 --scene, --frames, --out, --write-midi and --realtime"
                    .into(),
            );
        }
        return Ok(Cli::Batch {
            file,
            shard: shard.unwrap_or(super::batch::Shard::ALL),
            jobs,
            quiet,
        });
    }
    if shard.is_some() || jobs.is_some() {
        return Err("--shard and --jobs go with --batch".into());
    }
    if inputs.is_empty() {
        return Err("no input: give at least one --midi, --script or --scene, or --frames".into());
    }
    if inputs.iter().any(|i| matches!(i, InputSpec::Frames(_))) {
        if inputs.len() > 1 {
            return Err(
                "--frames plays a recorded log on its own: drop the other inputs \
                        (--midi, --script, --scene, another --frames)"
                    .into(),
            );
        }
        if obj_dir.is_some() {
            return Err("--obj-dir writes the simulated sheet; a --frames render has none".into());
        }
        if write_frames.is_some() {
            return Err("--write-frames records a simulated render; --frames replays one".into());
        }
        if write_midi.is_some() {
            return Err("--write-midi exports gestures; a frame log holds only sounds".into());
        }
    }
    if realtime {
        if inputs.iter().any(|i| matches!(i, InputSpec::Frames(_))) {
            return Err("--realtime simulates a sheet; a --frames render has none".into());
        }
        if obj_dir.is_some() || write_frames.is_some() {
            return Err(
                "--realtime renders live, as a host does: drop --obj-dir and --write-frames".into(),
            );
        }
    }
    if let Some(path) = write_midi {
        if write_frames.is_some() {
            return Err("--write-midi renders nothing: drop --write-frames".into());
        }
        if out.is_some() {
            return Err("--write-midi writes a MIDI file and renders nothing: drop --out".into());
        }
        return Ok(Cli::WriteMidi {
            inputs,
            out: path,
            quiet,
        });
    }
    let out = out.ok_or("no output: give --out FILE.wav")?;
    Ok(Cli::Render(RenderOptions {
        inputs,
        out,
        sample_rate_hz,
        block,
        seed,
        sets,
        obj_dir,
        obj_fps,
        db,
        phrases,
        presets,
        write_frames,
        quiet,
        realtime,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn parses_the_documented_interface() {
        let Cli::Render(o) = parse(&args(
            "--midi a.mid --scene s1 --script b.toml --out x.wav --sample-rate 96000 --block 64 \
             --seed 7 --set size=a6 --set=table=off --obj-dir objs --obj-fps 24 --db mydb \
             --write-frames f.jsonl --quiet",
        ))
        .unwrap() else {
            panic!()
        };
        assert_eq!(o.inputs.len(), 3);
        assert_eq!(o.sample_rate_hz, 96_000);
        assert_eq!(o.block, 64);
        assert_eq!(o.seed, Some(7));
        assert_eq!(o.sets, vec!["size=a6", "table=off"]);
        assert_eq!(o.obj_fps, 24.0);
        assert_eq!(o.write_frames, Some(PathBuf::from("f.jsonl")));
        assert!(o.quiet);
        assert!(!o.realtime);
        let Cli::Render(o) = parse(&args("--scene s4 --realtime --out x.wav")).unwrap() else {
            panic!()
        };
        assert!(o.realtime);
        for bad in [
            "--frames f.jsonl --realtime --out x.wav",
            "--scene s4 --realtime --obj-dir o --out x.wav",
            "--scene s4 --realtime --write-frames f.jsonl --out x.wav",
        ] {
            assert!(parse(&args(bad)).is_err(), "{bad}");
        }
        let Cli::Render(o) = parse(&args(
            "--frames log.jsonl --out x.wav --seed 3 --set gain_db=-3",
        ))
        .unwrap() else {
            panic!()
        };
        assert_eq!(o.inputs, vec![InputSpec::Frames("log.jsonl".into())]);
        assert_eq!((o.seed, o.write_frames), (Some(3), None));
        let Cli::WriteMidi { inputs, out, quiet } =
            parse(&args("--scene s1 --write-midi s1.mid")).unwrap()
        else {
            panic!()
        };
        assert_eq!(
            (inputs.len(), out, quiet),
            (1, PathBuf::from("s1.mid"), false)
        );
    }

    /// `--frames` takes the sound options (rate, block, seed, settings, database, quiet) and
    /// both spellings (`--frames F`, `--frames=F`); `--write-frames` goes with every simulated
    /// input and with `=`. Detects an option a frame replay needs being rejected or dropped, and
    /// `--write-frames` recorded under the wrong field.
    #[test]
    fn frame_log_options_parse() {
        let Cli::Render(o) = parse(&args(
            "--frames=log.jsonl --out x.wav --sample-rate 44100 --block 37 --seed 65535 \
             --set wall=on --set wall_dist_cm=12 --db mydb -q",
        ))
        .unwrap() else {
            panic!()
        };
        assert_eq!(o.inputs, vec![InputSpec::Frames("log.jsonl".into())]);
        assert_eq!((o.sample_rate_hz, o.block), (44_100, 37));
        assert_eq!(o.seed, Some(65_535));
        assert_eq!(o.sets, vec!["wall=on", "wall_dist_cm=12"]);
        assert_eq!(o.db, Some(PathBuf::from("mydb")));
        assert_eq!((o.obj_dir, o.write_frames, o.quiet), (None, None, true));
        for input in ["--midi a.mid", "--script a.toml", "--scene s1"] {
            let Cli::Render(o) = parse(&args(&format!(
                "{input} --out x.wav --write-frames=logs/f.jsonl --obj-dir objs"
            )))
            .unwrap() else {
                panic!("{input}")
            };
            assert_eq!(
                o.write_frames,
                Some(PathBuf::from("logs/f.jsonl")),
                "{input}"
            );
            assert_eq!(o.obj_dir, Some(PathBuf::from("objs")), "{input}");
        }
        // The defaults leave both off.
        let Cli::Render(o) = parse(&args("--scene s1 --out x.wav")).unwrap() else {
            panic!()
        };
        assert_eq!(o.write_frames, None);
        assert!(!o.inputs.iter().any(|i| matches!(i, InputSpec::Frames(_))));
        // Errors name what to drop.
        let e = parse(&args("--frames a.jsonl --scene s1 --out x.wav")).unwrap_err();
        assert!(e.contains("--frames") && e.contains("on its own"), "{e}");
        let e = parse(&args("--frames a.jsonl --out x.wav --obj-dir o")).unwrap_err();
        assert!(e.contains("--obj-dir"), "{e}");
        let e = parse(&args("--scene s1 --out x.wav --write-frames")).unwrap_err();
        assert!(e.contains("--write-frames needs a value"), "{e}");
    }

    #[test]
    fn rejects_bad_arguments() {
        for a in [
            "",
            "--out x.wav",
            "--midi a.mid",
            "--midi a.mid --out x.wav --sample-rate 4000",
            "--midi a.mid --out x.wav --sample-rate abc",
            "--midi a.mid --out x.wav --block 0",
            "--midi a.mid --out x.wav --block 20000",
            "--midi a.mid --out x.wav --obj-fps 0",
            "--midi a.mid --out x.wav --seed -3",
            "--midi a.mid --out x.wav --frobnicate",
            "--midi",
            "--scene s1 --write-midi a.mid --out x.wav",
            "--frames",
            "--frames a.jsonl --scene s1 --out x.wav",
            "--midi a.mid --frames a.jsonl --out x.wav",
            "--frames a.jsonl --frames b.jsonl --out x.wav",
            "--frames a.jsonl --out x.wav --obj-dir objs",
            "--frames a.jsonl --out x.wav --write-frames b.jsonl",
            "--frames a.jsonl --write-midi a.mid",
            "--scene s1 --write-midi a.mid --write-frames b.jsonl",
        ] {
            let e = parse(&args(a)).unwrap_err();
            assert!(!e.contains('\n'), "{a}: {e}");
        }
    }
}
