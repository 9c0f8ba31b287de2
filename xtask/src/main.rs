//! `cargo xtask …`: Papier's project tasks.
//!
//! - `cargo xtask bundle papier --release`: build and bundle `Papier.clap` and `Papier.vst3`
//!   (nice-plug-xtask);
//! - `cargo xtask demo`: the README's main job (bundles, standalone, demo render);
//! - `cargo xtask test`: the README's test command (everything CI runs);
//! - `cargo xtask sounddb …`: generate or import a sound database;
//! - `cargo xtask bench-report`: run the benchmark report and update `docs/benchmarks.md`
//!   (`--plot-only`: draw its plots again from the last report's CSV, measuring nothing).

mod bench_report;
mod jobs;
mod sounddb_cmd;
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
        "sounddb" => sounddb_cmd::run(&rest),
        "bench-report" => bench_report::run(&rest),
        _ => nice_plug_xtask::main(),
    }
}
