//! `synth-dev`: the developer's commands, apart from the user's `synth`. They measure the
//! figures of the README and BENCHMARKS.md, reproduce a paper's experiment, and re-record the
//! data shipped under `specs/` from the benchmark cases (plant simulations with reference
//! controllers, `fbsynth::cases`, which need the cargo feature `cases`).
//!
//! ```text
//! cargo run --release --features cases --bin synth-dev -- COMMAND [OPTIONS]
//! cargo run --release --features cases --bin synth-dev -- COMMAND --help
//! ```
//!
//! | command | what it measures or writes |
//! |---|---|
//! | `bench` | exact synthesis on `specs/pnp.traces` (and fbSAT's `tests-N.gz` with `--fbsat-data DIR`), min / median / max of `--runs`; then the main job on Pick-and-Place (candidates, SAT and NuSMV time) |
//! | `bench-noisy` | noisy synthesis (`synth infer --noisy`) on generated distribution-station logs of `--samples` lengths, with skew injected |
//! | `bench-long` | exact synthesis on one long generated run of the distribution station (lazy synthesis), `--steps` 10^4 to 10^6 |
//! | `bench-modular` | modular synthesis (`synth infer --modules M`) for M = 1..4 on `--traces` |
//! | `bench-search` | the search's scenario-fitness evaluations per second, one thread and all |
//! | `bench-ambiguity` | the ambiguity check of `synth infer` on each shipped case |
//! | `bench-fbsat-pnp --fbsat DIR` | the main job on fbSAT's own Pick-and-Place plant (read from a checkout of fbSAT, inside a wrapper module) with its nine properties, for `tests-1`, `-10`, `-39`: size, time, and fbSAT's own model's verdict on each machine |
//! | `bench-ingest` | ingestion throughput (M rows/s) and peak memory on a generated raw log |
//! | `experiment table1` | Table I of the verification-in-the-loop paper with the search (scenarios; scenarios + LTL without `F_ce`; scenarios + LTL) |
//! | `generate pnp\|tank\|distribution` | the case's scenario files and logs in `specs/`, as the tests check them |
//! | `generate free-inputs --inputs N --out DIR` | a plant of N free sensors, its recordings and properties (the free-input growth of BENCHMARKS.md) |
//!
//! Every command takes `-q`, `-v` and `--json` as `synth` does, and exits with `synth`'s codes:
//! both binaries share the library's command-line module ([`fbsynth::cli`]).

// Commands return the library's `pipeline::Error` (128 bytes) by value; an error ends the
// run, so its size costs nothing that matters.
#![allow(clippy::result_large_err)]

use fbsynth::cli;

mod bench;
mod experiment;
mod fbsat_pnp;
mod generate;
mod generated;
mod stats;

use clap::{Parser, Subcommand};
use cli::OutputArgs;

/// The developer's commands of fbsynth: benchmarks, a paper's experiment, and the generators
/// of the data shipped under specs/.
#[derive(Debug, Parser)]
#[command(name = "synth-dev", version)]
struct DevCli {
    #[command(flatten)]
    output: OutputArgs,
    #[command(subcommand)]
    command: Command,
}

// Parsed once per run: the size of the largest variant costs nothing that matters.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Subcommand)]
enum Command {
    /// Regenerate a shipped case's scenario files from its reference controller and plant
    /// simulation (`pnp`: the Pick-and-Place manipulator).
    Generate(generate::GenerateArgs),
    /// Measure synthesis time on the project's and (when present) fbSAT's scenario sets.
    Bench(bench::BenchArgs),
    /// Measure the main job on fbSAT's own Pick-and-Place model (read from a checkout of fbSAT).
    BenchFbsatPnp(fbsat_pnp::BenchFbsatPnpArgs),
    /// Measure ingestion throughput and peak memory on a generated long-format log.
    BenchIngest(generated::BenchIngestArgs),
    /// Measure modular synthesis (infer --modules) for M = 1..4 on a scenario set.
    BenchModular(bench::BenchModularArgs),
    /// Reproduce a paper's experiment (`table1`: the verification-in-the-loop paper's Table I with the search).
    Experiment(experiment::ExperimentArgs),
    /// Measure the search's scenario-fitness evaluations per second per thread.
    BenchSearch(bench::BenchSearchArgs),
    /// Measure the ambiguity check of `synth infer` on each shipped case.
    BenchAmbiguity(bench::BenchAmbiguityArgs),
    /// Measure noisy synthesis (--noisy) on generated distribution-station logs.
    BenchNoisy(generated::BenchNoisyArgs),
    /// Measure exact synthesis on one long generated recording (lazy synthesis).
    BenchLong(generated::BenchLongArgs),
}

impl Command {
    /// The command's name on the command line, for the generic `--json` summary.
    fn name(&self) -> &'static str {
        match self {
            Command::Generate(_) => "generate",
            Command::Bench(_) => "bench",
            Command::BenchFbsatPnp(_) => "bench-fbsat-pnp",
            Command::BenchIngest(_) => "bench-ingest",
            Command::BenchModular(_) => "bench-modular",
            Command::Experiment(_) => "experiment",
            Command::BenchSearch(_) => "bench-search",
            Command::BenchAmbiguity(_) => "bench-ambiguity",
            Command::BenchNoisy(_) => "bench-noisy",
            Command::BenchLong(_) => "bench-long",
        }
    }
}

fn main() {
    let cli = match DevCli::try_parse() {
        Ok(c) => c,
        Err(e) => std::process::exit(cli::clap_error(e)),
    };
    cli::start(&cli.output);
    let name = cli.command.name();
    let result = match cli.command {
        Command::Generate(a) => generate::generate(&a),
        Command::Bench(a) => bench::bench(&a),
        Command::BenchFbsatPnp(a) => fbsat_pnp::bench_fbsat_pnp(&a),
        Command::BenchIngest(a) => generated::bench_ingest(&a),
        Command::BenchModular(a) => bench::bench_modular(&a),
        Command::Experiment(a) => experiment::experiment(&a),
        Command::BenchSearch(a) => bench::bench_search(&a),
        Command::BenchAmbiguity(a) => bench::bench_ambiguity(&a),
        Command::BenchNoisy(a) => generated::bench_noisy(&a),
        Command::BenchLong(a) => generated::bench_long(&a),
    };
    std::process::exit(cli::finish(name, result));
}
