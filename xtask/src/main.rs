//! `cargo xtask …`: Papier's project tasks.
//!
//! - `cargo xtask bundle papier --release`: build and bundle `Papier.clap` and `Papier.vst3`
//!   (nice-plug-xtask);
//! - `cargo xtask demo`: the README's main job (bundles, standalone, demo render);
//! - `cargo xtask test`: the README's test command (everything CI runs);
//! - `cargo xtask sounddb …`: generate, import or check a sound database (runs the sounddb
//!   crate's `sounddb` binary: `cargo run --release -p sounddb --bin sounddb -- …`);
//! - `cargo xtask bench-report [--quick] [--reps N] [--plot-only]`: run the benchmark report and
//!   update `docs/benchmarks.md` (`--plot-only`: draw its plots again from the last report's
//!   CSV, measuring nothing); runs the lab's subcommand,
//!   `cargo run --release -p papier-lab -- bench-report …`.
//!
//! xtask links none of the workspace's crates: the tools that need the simulation or the sound
//! database are built and run through cargo ([`jobs::cargo`]).

mod jobs;
mod system;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let Some(command) = args.next() else {
        return nice_plug_xtask::main();
    };
    let rest: Vec<String> = args.collect();
    match command.as_str() {
        "demo" => jobs::demo(&rest),
        "test" => jobs::test(&rest),
        "sounddb" => jobs::cargo_run(&["-p", "sounddb", "--bin", "sounddb"], &rest),
        "bench-report" => {
            let args: Vec<String> = std::iter::once(command).chain(rest).collect();
            jobs::cargo_run(&["-p", "papier-lab"], &args)
        }
        _ => nice_plug_xtask::main(),
    }
}
