//! Playing a scene frame by frame, shared by the probes. A scene on the command line is a
//! library scenario `NAME`, the same scene with another seed `NAME@SEED`
//! ([`sim_core::scenario::get_seeded`]), or a script file `FILE.toml`.

use std::path::Path;

use anyhow::Context;
use sim_core::scenario;
use sim_core::script::Script;
use sim_core::script_runner::ScriptRunner;
use sim_core::sim::{FrameOutput, Sim, SimConfig};

use crate::args::bad;

/// The script of a scene argument (`NAME`, `NAME@SEED` or `FILE.toml`); an unknown scene is a
/// bad argument.
pub fn script(arg: &str) -> anyhow::Result<Script> {
    if arg.ends_with(".toml") {
        Script::from_file(Path::new(arg)).with_context(|| format!("script file {arg}"))
    } else {
        scenario::get_seeded(arg).map_err(|e| bad(e.to_string()))
    }
}

/// The scenes named by `args`, or every library scenario when there are none.
pub fn scenes_or_all(args: &[String]) -> Vec<String> {
    if args.is_empty() {
        scenario::names().map(str::to_string).collect()
    } else {
        args.to_vec()
    }
}

/// A scene being played: its script runner, the sim it drives and the last frame's output.
pub struct Play {
    pub runner: ScriptRunner,
    pub sim: Sim,
    pub out: FrameOutput,
}

impl Play {
    /// `script` set up on `cfg` (its `[set]` values and initial commands applied).
    pub fn new(script: &Script, cfg: SimConfig) -> anyhow::Result<Self> {
        let runner = ScriptRunner::new(script, cfg.frame_rate_hz, cfg.room)?;
        let sim = runner.start(cfg);
        Ok(Self {
            runner,
            sim,
            out: FrameOutput::default(),
        })
    }

    /// The scene `arg` ([`script`]) set up on `cfg`.
    pub fn scene(arg: &str, cfg: SimConfig) -> anyhow::Result<Self> {
        Self::new(&script(arg)?, cfg)
    }

    /// Plays the next frame into `out`; false when the script has ended (no frame played).
    pub fn frame(&mut self) -> bool {
        self.runner.drive(&mut self.sim, &mut self.out)
    }
}
