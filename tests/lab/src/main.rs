//! `papier-lab`: Papier's lab — the probes that a document or a test cites, the benchmark report
//! and the long stress run, as subcommands of one binary. Dev only: not part of the product
//! (the plugin, the renderer and the tools a user runs never link it).
//!
//! ```text
//! cargo run --release -p papier-lab -- help              lists the subcommands
//! cargo run --release -p papier-lab -- NAME [ARGS...]    runs one (`NAME --help`: its usage)
//! ```
//!
//! Each subcommand is one module (`src/<name>.rs`) whose doc says what question it answers and
//! how to run it. An unknown subcommand or a bad argument prints one line of error and the usage
//! and exits with status 2; a failure exits with status 1.

mod args;
mod bench_report;
mod fixture_step;
mod flip_probe;
mod frame_tail;
mod fuzz_restore;
mod hold_probe;
mod insert_probe;
mod iso_conv;
mod iter_hist;
mod layer_probe;
mod octaves;
mod play;
mod rest_family;
mod rest_probe;
mod scenario_probe;
mod singular_probe;
mod sound_hash;
mod strain_frames;
mod stress;
mod stress_family;
mod stress_fixture;

use std::process::ExitCode;

use args::BadArgs;

/// One subcommand.
struct Command {
    name: &'static str,
    /// One line for `papier-lab help`.
    about: &'static str,
    /// Its arguments, after the name.
    usage: &'static str,
    run: fn(&[String]) -> anyhow::Result<()>,
}

const COMMANDS: &[Command] = &[
    Command {
        name: "scenario-probe",
        about: "every library scenario with a solver configuration: timing, error, health, state hashes",
        usage: scenario_probe::USAGE,
        run: scenario_probe::run,
    },
    Command {
        name: "iter-hist",
        about: "Newton iterations per frame of a scene as a histogram, with timing and undone frames",
        usage: iter_hist::USAGE,
        run: iter_hist::run,
    },
    Command {
        name: "frame-tail",
        about: "the slowest frames of a scene by phase, and each phase's median",
        usage: frame_tail::USAGE,
        run: frame_tail::run,
    },
    Command {
        name: "strain-frames",
        about: "the frames of a scene strained beyond half a limit, and their worst triangle",
        usage: strain_frames::USAGE,
        run: strain_frames::run,
    },
    Command {
        name: "hold-probe",
        about: "whether a held sheet comes to rest: step time, iterations, isometry per 50 frames",
        usage: hold_probe::USAGE,
        run: hold_probe::run,
    },
    Command {
        name: "rest-family",
        about: "seeded random gesture combinations held still: settle time, strain, events, step time",
        usage: rest_family::USAGE,
        run: rest_family::run,
    },
    Command {
        name: "rest-probe",
        about: "what keeps a held sheet from settling: strain, speed, events, slips, squeeze per 0.25 s",
        usage: rest_probe::USAGE,
        run: rest_probe::run,
    },
    Command {
        name: "flip-probe",
        about: "edge flips in flat regions per scene, with flips off and on",
        usage: flip_probe::USAGE,
        run: flip_probe::run,
    },
    Command {
        name: "insert-probe",
        about: "singular points at their drawn position, with and without vertex insertion",
        usage: insert_probe::USAGE,
        run: insert_probe::run,
    },
    Command {
        name: "singular-probe",
        about: "when, where and why a scene creates singular points",
        usage: singular_probe::USAGE,
        run: singular_probe::run,
    },
    Command {
        name: "iso-conv",
        about: "the isometry step's Phase I convergence after k iterations, every 60 frames",
        usage: iso_conv::USAGE,
        run: iso_conv::run,
    },
    Command {
        name: "octaves",
        about: "the octave profile and centroid of rendered WAV files, as a table and a PNG",
        usage: octaves::USAGE,
        run: octaves::run,
    },
    Command {
        name: "layer-probe",
        about: "the layers' friction sources of a scene per 0.25 s: how many, their slip and size",
        usage: layer_probe::USAGE,
        run: layer_probe::run,
    },
    Command {
        name: "sound-hash",
        about: "a hash of every frame's sound input per scenario (for bit-identical changes)",
        usage: sound_hash::USAGE,
        run: sound_hash::run,
    },
    Command {
        name: "stress",
        about: "the long hostile stress run (10⁶ frames by default) of sim_core::stress",
        usage: stress::USAGE,
        run: stress::run,
    },
    Command {
        name: "stress-family",
        about: "the test suite's stress session over many seeds: how many fail",
        usage: stress_family::USAGE,
        run: stress_family::run,
    },
    Command {
        name: "stress-fixture",
        about: "saves a stress session's sheet at a frame as a regression fixture, then steps it",
        usage: stress_fixture::USAGE,
        run: stress_fixture::run,
    },
    Command {
        name: "fixture-step",
        about: "restores a saved sheet or fixture and steps it a few frames",
        usage: fixture_step::USAGE,
        run: fixture_step::run,
    },
    Command {
        name: "fuzz-restore",
        about: "a long run of the saved-sheet mutation test: panics and non-finite positions",
        usage: fuzz_restore::USAGE,
        run: fuzz_restore::run,
    },
    Command {
        name: "bench-report",
        about: "the benchmark report: run time against length error into docs/benchmarks.md",
        usage: bench_report::USAGE,
        run: bench_report::run,
    },
];

const USAGE: &str = "usage: papier-lab SUBCOMMAND [ARGS...] (`papier-lab help` lists them)";

fn help() {
    println!("papier-lab: Papier's lab (dev only, not part of the product)");
    println!("usage: cargo run --release -p papier-lab -- SUBCOMMAND [ARGS...]\n");
    let width = COMMANDS.iter().map(|c| c.name.len()).max().unwrap_or(0);
    for c in COMMANDS {
        println!("  {:width$}  {}", c.name, c.about);
    }
    println!("\n`papier-lab SUBCOMMAND --help` prints a subcommand's arguments.");
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(name) = args.first() else {
        eprintln!("papier-lab: no subcommand");
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    };
    if matches!(name.as_str(), "help" | "-h" | "--help") {
        match args.get(1) {
            None => help(),
            Some(n) => match COMMANDS.iter().find(|c| c.name == n) {
                Some(c) => println!("usage: papier-lab {} {}\n{}", c.name, c.usage, c.about),
                None => {
                    eprintln!("papier-lab: unknown subcommand {n:?}");
                    eprintln!("{USAGE}");
                    return ExitCode::from(2);
                }
            },
        }
        return ExitCode::SUCCESS;
    }
    let Some(command) = COMMANDS.iter().find(|c| c.name == name) else {
        eprintln!("papier-lab: unknown subcommand {name:?}");
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    };
    let rest = &args[1..];
    if rest.iter().any(|a| a == "-h" || a == "--help") {
        println!("usage: papier-lab {} {}", command.name, command.usage);
        return ExitCode::SUCCESS;
    }
    match (command.run)(rest) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            if let Some(BadArgs(msg)) = e.downcast_ref::<BadArgs>() {
                eprintln!("papier-lab {}: {msg}", command.name);
                eprintln!("usage: papier-lab {} {}", command.name, command.usage);
                ExitCode::from(2)
            } else {
                eprintln!("papier-lab {}: {e:#}", command.name);
                ExitCode::FAILURE
            }
        }
    }
}
