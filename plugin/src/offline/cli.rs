//! # `papier-render` command line
//!
//! ```text
//! papier-render (--midi FILE.mid | --script FILE.toml | --scene NAME)... --out FILE.wav
//!               [--sample-rate HZ] [--block N] [--seed N] [--set ID=VALUE]...
//!               [--obj-dir DIR] [--obj-fps N] [--db DIR] [--quiet]
//! ```
//! Every input plays on one shared timeline from t = 0 (like tracks of a DAW); the render
//! lasts as long as the longest input. Values given with `--seed` and `--set` are applied at
//! t = 0 after the scripts' `[set]` tables, so the command line wins.

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
    /// Print only errors.
    pub quiet: bool,
}

impl RenderOptions {
    /// Options with `papier-render`'s defaults (48 kHz, blocks of 512, no seed or settings, no
    /// OBJ, the embedded database, progress shown) for these inputs and output.
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
            quiet: false,
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
                     [--sample-rate HZ] [--block N] [--seed N] [--set ID=VALUE]...
                     [--obj-dir DIR] [--obj-fps N] [--db DIR] [--quiet]
       papier-render --list-scenes
Renders Papier offline (the plugin's engine, stepped in lockstep with the audio) to a WAV file.
  --midi FILE        play a Standard MIDI File (README: MIDI map)
  --script FILE      play a TOML automation script (sim-core/src/script.rs)
  --scene NAME       play a built-in scenario (see --list-scenes)
  --out FILE         output WAV (stereo, 32-bit float)
  --sample-rate HZ   8000-192000 (default 48000)
  --block N          host block size to emulate, 1-16384 (default 512)
  --seed N           seed of the sheet and of the sound (parameter `seed`)
  --set ID=VALUE     set a parameter at t = 0, e.g. --set size=a6 (ids: README)
  --obj-dir DIR      write the sheet as frame_00000.obj, ... (v: metres, vt: pattern metres)
  --obj-fps N        OBJ frames per second (default 30)
  --db DIR           use a user sound database instead of the embedded one
  --write-midi FILE  write the inputs as a MIDI performance (README map: grabs as notes,
                     gestures as CCs) instead of rendering; prints the --set options it needs
  --quiet            print only errors";

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
    let mut quiet = defaults.quiet;
    let mut write_midi = None;

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
            "--midi" => inputs.push(InputSpec::Midi(value("--midi")?.into())),
            "--script" => inputs.push(InputSpec::Script(value("--script")?.into())),
            "--scene" => inputs.push(InputSpec::Scene(value("--scene")?)),
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
                let max = crate::params::MAX_SEED as u64;
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
            "--quiet" | "-q" => quiet = true,
            other => return Err(format!("unknown option {other:?} (see --help)")),
        }
        i += 1;
    }
    if inputs.is_empty() {
        return Err("no input: give at least one --midi, --script or --scene".into());
    }
    if let Some(path) = write_midi {
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
        quiet,
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
             --seed 7 --set size=a6 --set=table=off --obj-dir objs --obj-fps 24 --db mydb --quiet",
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
        assert!(o.quiet);
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
        ] {
            let e = parse(&args(a)).unwrap_err();
            assert!(!e.contains('\n'), "{a}: {e}");
        }
    }
}
