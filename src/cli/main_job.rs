//! The main job (`synth --ltl SPEC --plant PLANT`, by exact SAT or by search) and
//! `synth verify`.

use super::args::{
    check, out_dir, parse_formats, problem, AlgorithmsArg, Judge, NusmvArgs, Start, TraceArgs,
};
use super::progress::Progress;
use super::show::{print_files, verified_line};
use super::{exit, Failure};
use clap::{Args, ValueEnum};
use fbsynth::files::ResultSet;
use fbsynth::pipeline::explain::{self, Explanation};
use fbsynth::pipeline::output::{check_exportable, write_verified, Provenance};
use fbsynth::pipeline::recordings::{read_ecc, stem};
use fbsynth::pipeline::{self, exact, limit, search};
use fbsynth::scenario::negative::NegativeScenario;
use std::path::PathBuf;

/// Arguments of the main job (no subcommand).
#[derive(Debug, Args, Clone)]
pub struct MainArgs {
    /// LTL properties, one per line (NuSMV syntax over bare names; `--` comments; `name:`).
    #[arg(long, value_name = "FILE")]
    pub ltl: Option<PathBuf>,
    /// Surrogate plant model: an SMV file defining `MODULE plant(<controller outputs>)`.
    #[arg(long, value_name = "FILE")]
    pub plant: Option<PathBuf>,
    /// Scenario files. Default: `<stem>.traces` beside the --ltl file (specs/pnp.ltl ->
    /// specs/pnp.traces), with names from `<stem>.inputs` / `<stem>.outputs`.
    #[arg(long = "traces", value_name = "FILE", num_args = 1..)]
    pub traces: Vec<PathBuf>,
    /// Input names file (default: beside the first trace file).
    #[arg(long, value_name = "FILE")]
    pub input_names: Option<PathBuf>,
    /// Output names file (default: beside the first trace file).
    #[arg(long, value_name = "FILE")]
    pub output_names: Option<PathBuf>,
    /// Output folder. Default: `out/<stem of the --ltl file>`.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// After synthesis: look for rivals (machines with as many states that reproduce the
    /// recordings but answer differently) and check each with NuSMV.
    #[arg(long)]
    pub ambiguity: bool,
    /// Negative scenarios: behaviours the machine must not show, in the scenario syntax
    /// (fbSAT's complete synthesis); repeatable. A machine shows one when its outputs after
    /// every step equal the scenario's (a step without `out=` keeps the outputs).
    #[arg(long, value_name = "FILE", conflicts_with = "ambiguity")]
    pub negative: Vec<PathBuf>,
    #[command(flatten)]
    pub ambiguity_args: super::args::AmbiguityArgs,
    /// Form of the state output algorithms.
    #[arg(long, value_enum, default_value_t = AlgorithmsArg::Tri)]
    pub algorithms: AlgorithmsArg,
    /// Give up when more states than this would be needed.
    #[arg(long, default_value_t = 32, value_name = "C", value_parser = super::args::states())]
    pub max_states: usize,
    /// Transitions per state at most (each guarded by a conjunction of input literals).
    #[arg(long, default_value_t = exact::DEFAULT_OUT_DEGREE, value_name = "K", value_parser = super::args::per_state())]
    pub max_out_degree: usize,
    /// Give up after this many candidate controllers.
    #[arg(long, default_value_t = 500, value_name = "N")]
    pub max_iterations: usize,
    /// Give up after this many seconds of synthesis and verification, with either method
    /// (exit 3, saying what was found by then).
    #[arg(long, default_value_t = 600.0, value_name = "SECONDS")]
    pub time_limit: f64,
    /// Seconds the final machine's transition and literal counts may take to be proven
    /// minimal once it is verified; past it the result says "not proven minimal". 0 skips the
    /// proof.
    #[arg(long, default_value_t = exact::DEFAULT_PROOF_BUDGET.as_secs_f64(), value_name = "SECONDS")]
    pub proof_budget: f64,
    /// Formats to write, comma-separated: json, fbt, smv, dot, st, pnml, plcopen
    /// (PLCopen TC6 XML, written as .xml).
    #[arg(long, value_delimiter = ',', default_value = "json,fbt,smv,dot,st")]
    pub format: Vec<String>,
    /// Name of the function block type in the exports (an identifier, no keyword of SMV or
    /// IEC 61131-3, none of main, ECC, plant, REQ, CNF, state).
    #[arg(long, default_value = "SynthesizedFB", value_parser = super::args::block_name)]
    pub name: String,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
    /// How to synthesize: exact SAT with counterexample-guided refinement (default), or
    /// metaheuristic search (options under "Search").
    #[arg(long, value_enum, default_value_t = Method::Sat)]
    pub method: Method,
    #[command(flatten)]
    pub search: SearchArgs,
}

/// Synthesis method of the main job.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// Exact SAT synthesis, minimal, with CEGIS against NuSMV.
    Sat,
    /// Metaheuristic search with verification-aware fitness.
    Search,
}

/// Options of the search (`--method search`).
#[derive(Debug, Args, Clone)]
#[command(next_help_heading = "Search (--method search)")]
pub struct SearchArgs {
    /// Seed of every random choice: the same seed gives the same machine (when the run stops
    /// on a solution, not on the clock).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: all cores). The result does not depend on it.
    #[arg(long, value_parser = super::args::workers())]
    pub threads: Option<usize>,
    /// States of every candidate (default: 8, or the SAT machine's with --start sat).
    #[arg(long, value_name = "C", value_parser = super::args::states())]
    pub states: Option<usize>,
    /// Colonies ((1+λ) strategies sharing their best).
    #[arg(long, default_value_t = 4, value_parser = super::args::workers())]
    pub colonies: usize,
    /// Where the colonies start. From random machines the search does not reproduce all ten
    /// Pick-and-Place scenarios within minutes (the published search took hours), so the main
    /// job starts from SAT's machine for the scenarios and leaves the properties to the search.
    #[arg(long, value_enum, default_value_t = Start::Sat)]
    pub start: Start,
    /// Probability of verifying a candidate whose scenario fitness is below 99% of the maximum
    /// (above it every candidate is verified). Default: 0.01 with --judge in-process, 0.001
    /// with --judge nusmv.
    #[arg(long, value_name = "P")]
    pub verify_probability: Option<f64>,
    /// Who judges the candidates during the search; NuSMV checks the machine it ends with.
    #[arg(long, value_enum, default_value_t = Judge::InProcess)]
    pub judge: Judge,
}

#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// The machine to check, in the JSON format `synth infer` writes.
    #[arg(long, value_name = "FILE")]
    pub ecc: PathBuf,
    /// LTL properties.
    #[arg(long, value_name = "FILE")]
    pub ltl: PathBuf,
    /// Surrogate plant model.
    #[arg(long, value_name = "FILE")]
    pub plant: PathBuf,
    /// Folder to keep the closed-loop model NuSMV checked and, for every violated property,
    /// its counterexample as a waveform (`<property>.vcd` for GTKWave, `<property>.svg`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
}

/// The exact loop's settings from the command line, with at most `max_states` states.
fn exact_options(
    args: &MainArgs,
    negatives: &[NegativeScenario],
    max_states: usize,
    keep_failed_model: Option<PathBuf>,
    proof_budget: std::time::Duration,
) -> exact::Options {
    exact::Options {
        sat: exact::SatOptions {
            algorithms: args.algorithms.into(),
            max_states,
            cube_slots: Some(args.max_out_degree),
            ..exact::SatOptions::default()
        },
        max_iterations: args.max_iterations,
        verbose: super::verbose(),
        keep_failed_model,
        proof_budget,
        negatives: negatives.to_vec(),
    }
}

/// `synth --ltl SPEC --plant PLANT`.
pub fn main_job(args: &MainArgs) -> Result<(), Failure> {
    if super::json() {
        super::data_on_stdout();
    }
    let progress = Progress::new(super::quiet());
    let (Some(ltl), Some(plant_file)) = (&args.ltl, &args.plant) else {
        return Err(Failure::msg(
            exit::USAGE,
            "the main job needs --ltl FILE and --plant FILE (or use a subcommand: synth --help)",
        ));
    };
    let time_limit = pipeline::seconds("--time-limit", args.time_limit, true)?;
    let proof_budget = pipeline::seconds("--proof-budget", args.proof_budget, false)?;
    let traces = if args.traces.is_empty() {
        let default = ltl.with_file_name(format!("{}.traces", stem(ltl)));
        if !default.is_file() {
            return Err(Failure::msg(
                exit::INPUT,
                format!(
                    "no --traces given and no default scenario file {} beside {}",
                    default.display(),
                    ltl.display()
                ),
            ));
        }
        vec![default]
    } else {
        args.traces.clone()
    };
    let recordings = TraceArgs {
        traces,
        input_names: args.input_names.clone(),
        output_names: args.output_names.clone(),
    }
    .recordings();
    let set = recordings.load()?;
    progress.line(&format!(
        "read {} scenarios ({} steps) from {}",
        set.scenarios.len(),
        set.step_count(),
        recordings.show()
    ));
    let problem = problem(ltl, plant_file, &set.inputs, &set.outputs)?;
    progress.line(&format!(
        "read {} properties from {} and plant {}",
        problem.props.len(),
        ltl.display(),
        plant_file.display()
    ));
    // Before any synthesis: recordings that violate a property leave no machine to find.
    let explained =
        explain::refuse_violations(&set, &problem.props, ltl).map_err(pipeline::Error::from)?;
    progress.line(&recordings_line(&explained, problem.props.len()));
    if let Some(line) = unrecorded_line(&explained) {
        progress.line(&line);
    }
    let negatives = super::infer::read_negatives(&args.negative, &set, &progress)?;
    if !negatives.is_empty() && args.method != Method::Sat {
        return Err(Failure::msg(
            exit::USAGE,
            "--negative takes --method sat (the search does not read negative scenarios)",
        ));
    }
    let formats = parse_formats(&args.format)?;
    check_exportable(&set, &args.name, &formats, &recordings)?;
    let out = out_dir(&args.out, &stem(ltl));
    // Taken before the search: a second run into the same folder stops now, not at the end.
    let results = ResultSet::open(&out).map_err(Failure::input)?;
    let check = check(problem, &args.nusmv)?;
    let provenance = Provenance {
        name: &args.name,
        plant_file,
        spec_file: ltl,
    };

    // Properties that read what nobody recorded: the game guides SAT there, the exact loop
    // being slow to learn it one counterexample at a time.
    let guide = args.method == Method::Sat
        && !explained.unrecorded.is_empty()
        && args.algorithms == AlgorithmsArg::Tri
        && negatives.is_empty();
    let (guided, guide_said) = if guide {
        guided(
            &set,
            &check,
            exact_options(args, &negatives, args.max_states, None, proof_budget),
            time_limit,
            unrecorded_line(&explained),
            &progress,
        )?
    } else {
        (None, None)
    };
    let (ecc, size, certificate, summary, closing) = match args.method {
        _ if guided.is_some() => guided.expect("checked"),
        Method::Sat => {
            let opts = exact_options(
                args,
                &negatives,
                args.max_states,
                Some(out.join("closed_loop.last.smv")),
                proof_budget,
            );
            // The limit counts from the start: the guide's time is spent.
            let left =
                time_limit.saturating_sub(std::time::Duration::from_secs_f64(progress.elapsed()));
            let r = limit::exact_within(&set, &check, &opts, left, &mut |e| progress.event(e))
                .map_err(|e| match e {
                    // The user's limit, not what was left of it.
                    pipeline::Error::TimeLimit { so_far, .. } => pipeline::Error::TimeLimit {
                        seconds: time_limit.as_secs_f64(),
                        so_far,
                    },
                    e => e,
                });
            if let Err(pipeline::Error::TimeLimit { .. }) = &r {
                // The loop's thread is still running: its NuSMV must not outlive us.
                fbsynth::nusmv::kill_all_children();
            }
            let r = r.map_err(|e| {
                // Every way of finding no machine within the limits (exit 3).
                let gave_up = e.class() == pipeline::Class::NoMachine;
                let generated = e.in_generated_code();
                let mut f = Failure::from(e);
                if gave_up {
                    if let Some(line) = unrecorded_line(&explained) {
                        f.message.push_str(&format!("\n({line})"));
                    }
                    // The guide has solved the game already: its word stands.
                    if let Some(said) = &guide_said {
                        f.message.push_str(&format!("\n(guide: {said})"));
                    } else {
                        progress.line("no verified machine within the limits; solving the closed-loop game to tell whether any controller exists");
                        if let Some(line) = pipeline::explain::realizability(&set, &check.problem)
                        {
                            f.message.push_str(&format!("\n({line})"));
                        }
                    }
                }
                let kept = out.join("closed_loop.last.smv");
                if generated && kept.is_file() {
                    f.message.push_str(&format!(
                        "\n(the model NuSMV was given is kept as {})",
                        kept.display()
                    ));
                }
                f
            })?;
            exact_outcome(r, &progress)
        }
        Method::Search => {
            let s = &args.search;
            let opts = search::Options {
                seed: s.seed,
                threads: s.threads,
                time_limit: args.time_limit,
                states: s.states,
                colonies: s.colonies,
                start: s.start.into(),
                verify_probability: s.verify_probability,
                judge: s.judge.into(),
                max_out_degree: args.max_out_degree,
                ..search::Options::default()
            };
            let r = search::run(&set, &check, &opts, None, &mut |e| progress.event(e))?;
            let searched = r.certified(&set, &opts)?.clone();
            progress.line(&format!(
                "the search's machine: {}; made small along the closed loop:",
                searched.size()
            ));
            let (small, followed) =
                search::shrink(&set, &searched, &check, args.max_out_degree, &mut |e| {
                    progress.event(e)
                })?;
            // The shrunk machine bounds the exact loop (at most its states): a smaller machine
            // that NuSMV verifies replaces it, so the search's answer is never larger than
            // what SAT finds on the same problem (Pick-and-Place, seed 1: shrunk to T 14
            // N 19, the bounded loop gives T 13 N 18).
            progress.line(&format!(
                "shrunk to {}; the exact loop looks for a smaller verified machine with at most {} states:",
                small.size, small.size.c
            ));
            let opts = exact_options(args, &negatives, small.size.c, None, proof_budget);
            let left =
                time_limit.saturating_sub(std::time::Duration::from_secs_f64(progress.elapsed()));
            let bounded = if left.is_zero() {
                None
            } else {
                match limit::exact_within(&set, &check, &opts, left, &mut |e| progress.event(e)) {
                    Ok(r) => Some(r),
                    Err(pipeline::Error::TimeLimit { .. }) => {
                        fbsynth::nusmv::kill_all_children();
                        progress.line(
                            "the exact loop ran out of --time-limit; the shrunk machine stands",
                        );
                        None
                    }
                    Err(e) => return Err(e.into()),
                }
            };
            let shrunk_size = small.size;
            let key = |z: &fbsynth::ecc::Size| (z.c, z.t, z.n);
            let (ecc, certificate, polished) = match bounded {
                Some(b) if key(&b.synthesis.size) < key(&small.size) => (
                    b.synthesis.ecc,
                    b.certificate.expect("a check gives a certificate"),
                    true,
                ),
                _ => (small.ecc, followed.certificate, false),
            };
            let summary = serde_json::json!({
                "method": "search",
                "seed": s.seed,
                "start": format!("{:?}", s.start).to_lowercase(),
                "size": ecc.size(),
                "searched_size": searched.size(),
                "shrunk_size": shrunk_size,
                "replaced_by_exact_loop": polished,
                "shrink_rounds": followed.rounds,
                "fitness": r.outcome.fitness,
                "search": r.outcome.stats,
                "nusmv_runs": r.nusmv_runs,
                "in_process_checks": r.in_process_checks,
                "cache_hits": r.cache_hits,
                "report": r.verification.report,
                "total_seconds": progress.elapsed(),
            });
            let closing = format!(
                "search, seed {}: {:.2} s total, {} evaluations, {} in-process checks, {} NuSMV runs; its machine ({}) made small in {} round{} ({}){}",
                s.seed,
                progress.elapsed(),
                r.outcome.stats.evaluations,
                r.in_process_checks,
                r.nusmv_runs,
                searched.size(),
                followed.rounds.len(),
                if followed.rounds.len() == 1 { "" } else { "s" },
                shrunk_size,
                if polished {
                    "; the exact loop below it found this smaller one"
                } else {
                    ""
                }
            );
            let size = ecc.size();
            (ecc, size, certificate, summary, closing)
        }
    };
    let mut staged = write_verified(
        results.staging(),
        &formats,
        &ecc,
        &certificate,
        &provenance,
        &summary,
    )?;
    if args.ambiguity {
        staged.extend(super::ambiguity::report_verified(
            &set,
            &ecc,
            &args.ambiguity_args,
            args.algorithms,
            &check,
            &progress,
            results.staging(),
        )?);
    }
    let files: Vec<PathBuf> = staged.iter().map(|f| results.published(f)).collect();
    results
        .publish()
        .map_err(|e| Failure::input(pipeline::Error::from(e)))?;
    out!(
        "{}",
        verified_line(certificate.report.properties.len(), set.scenarios.len())
    );
    for w in certificate.report.warning_lines() {
        out!("{w}");
    }
    let s = size;
    out!("C = {}  K = {}  T = {}  N = {}", s.c, s.k, s.t, s.n);
    out!("{closing}");
    print_files(&out, &files);
    if super::json() {
        let mut summary = summary;
        summary["files"] = serde_json::json!(files);
        return super::write_json(&summary);
    }
    Ok(())
}

/// What a run of the main job gives: the machine, its size, NuSMV's verdicts, the JSON
/// summary and the closing line.
type Outcome = (
    fbsynth::ecc::Ecc,
    fbsynth::ecc::Size,
    exact::Certificate,
    serde_json::Value,
    String,
);

/// The main job's outcome from the exact loop's result.
fn exact_outcome(r: exact::Exact, progress: &Progress) -> Outcome {
    let certificate = r.certificate.expect("a check gives a certificate");
    let sat_total: f64 = r.iterations.iter().map(|i| i.sat_seconds).sum();
    let nusmv_total: f64 = r.iterations.iter().map(|i| i.nusmv_seconds).sum();
    let summary = serde_json::json!({
        "size": r.synthesis.size,
        "transitions_proven_minimal": r.synthesis.transitions_exact,
        "guards_proven_minimal": r.synthesis.guards_exact,
        "iterations": r.iterations,
        "report": certificate.report,
        "sat_seconds": sat_total,
        "nusmv_seconds": nusmv_total,
        "total_seconds": progress.elapsed(),
    });
    let n = r.iterations.len();
    // C is always proven least; T and N only when the proof fit in the budget.
    let unproven: Vec<&str> = [
        (!r.synthesis.transitions_exact).then_some("T"),
        (!r.synthesis.guards_exact).then_some("N"),
    ]
    .into_iter()
    .flatten()
    .collect();
    let closing = format!(
        "{n} candidate{}, {:.2} s total (SAT {:.2} s, NuSMV {:.2} s){}",
        if n == 1 { "" } else { "s" },
        progress.elapsed(),
        sat_total,
        nusmv_total,
        if unproven.is_empty() {
            String::new()
        } else {
            format!(
                "\n{} not proven minimal within the proof budget (--proof-budget SECONDS to try longer)",
                unproven.join(" and ")
            )
        }
    );
    (
        r.synthesis.ecc,
        r.synthesis.size,
        certificate,
        summary,
        closing,
    )
}

/// The closed-loop game's guide ([`pipeline::guide`]) within `time_limit`: its verified machine,
/// or why it has none (said in progress too; the exact loop goes on); `unrecorded` says what the
/// recordings never show, for the message when the limit passes.
fn guided(
    set: &fbsynth::scenario::ScenarioSet,
    check: &pipeline::Check,
    mut opts: exact::Options,
    time_limit: std::time::Duration,
    unrecorded: Option<String>,
    progress: &Progress,
) -> Result<(Option<Outcome>, Option<String>), Failure> {
    use pipeline::guide;
    progress.line("solving the closed-loop game to guide the synthesis where nothing was recorded");
    let r = limit::guide_within(set, check, time_limit, &mut |e| progress.event(e));
    let why = match r {
        Ok(guide::Outcome::Verified(g)) if g.size.c <= opts.sat.max_states => {
            // The guide's machine is least only for its own runs: the exact loop, bounded by
            // its states and by half the time the guide took (at least 2 s), looks for a
            // smaller one. Where the loop converges fast it wins; where it does not (the
            // reason the guide ran), the cost stays a fraction of the run.
            let spent = progress.elapsed();
            let budget = time_limit
                .saturating_sub(std::time::Duration::from_secs_f64(spent))
                .min(std::time::Duration::from_secs_f64((spent / 2.0).max(2.0)));
            opts.sat.max_states = g.size.c;
            let stages: Vec<String> = g.stages.iter().map(|s| s.to_string()).collect();
            let key = |z: &fbsynth::ecc::Size| (z.c, z.t, z.n);
            let mut after = "not run: no time left".to_string();
            if !budget.is_zero() {
                progress.line(&format!(
                    "the exact loop looks for a smaller verified machine with at most {} states, for up to {:.1} s:",
                    g.size.c,
                    budget.as_secs_f64()
                ));
                match limit::exact_within(set, check, &opts, budget, &mut |e| progress.event(e)) {
                    Ok(r) if key(&r.synthesis.size) < key(&g.size) => {
                        let (ecc, size, certificate, mut summary, closing) =
                            exact_outcome(r, progress);
                        summary["method"] = "exact loop after the game's guide".into();
                        summary["guide_size"] = serde_json::json!(g.size);
                        summary["guide"] = serde_json::json!(stages);
                        let closing = format!(
                            "{closing}\n(the exact loop found it below the game's guide's {})",
                            g.size
                        );
                        return Ok((Some((ecc, size, certificate, summary, closing)), None));
                    }
                    Ok(_) => after = "no smaller machine".into(),
                    Err(pipeline::Error::TimeLimit { so_far, .. }) => {
                        // Its thread is still running: its NuSMV must not outlive the job.
                        fbsynth::nusmv::kill_all_children();
                        let by_nusmv = (so_far.candidates.iter())
                            .filter(|c| c.checked_by == "NuSMV")
                            .count();
                        after = format!(
                            "no smaller verified machine within {:.1} s ({} candidates, {by_nusmv} checked by NuSMV)",
                            budget.as_secs_f64(),
                            so_far.candidates.len()
                        );
                    }
                    // A bug stays one; anything else ends the turn, not the verified result.
                    Err(e) if e.class() == pipeline::Class::Bug => return Err(e.into()),
                    Err(e) => after = format!("stopped: {e}"),
                }
                progress.line(&format!(
                    "the exact loop: {after}; the guide's machine stands"
                ));
            }
            let summary = serde_json::json!({
                "method": "game guide",
                "exact_loop_below_it": after,
                "size": g.size,
                "least_for_recordings_and_runs": g.least_for_runs,
                "guide": stages,
                "report": g.certificate.report,
                "sat_seconds": g.sat_seconds,
                "nusmv_calls": g.nusmv_calls,
                "nusmv_seconds": g.nusmv_seconds,
                "total_seconds": progress.elapsed(),
            });
            let closing = format!(
                "closed-loop game as the guide: {:.2} s total (SAT {:.2} s, NuSMV {:.2} s in {} check{})\n{}",
                progress.elapsed(),
                g.sat_seconds,
                g.nusmv_seconds,
                g.nusmv_calls,
                if g.nusmv_calls == 1 { "" } else { "s" },
                if g.least_for_runs {
                    "C, T and N are least for the recordings and the closed-loop runs of the guide; a smaller machine that answers differently where nothing was recorded is not ruled out"
                } else {
                    "the repaired machine itself (the least machine for the runs failed NuSMV); it is not minimal"
                }
            );
            let (size, ecc) = (g.size, g.ecc);
            return Ok((Some((ecc, size, g.certificate, summary, closing)), None));
        }
        Ok(guide::Outcome::Verified(g)) => format!(
            "its machine has {} states, more than --max-states {}",
            g.size.c, opts.sat.max_states
        ),
        Ok(guide::Outcome::NotHere(why)) => why,
        Err(pipeline::Error::Interrupted { seconds, .. }) => {
            fbsynth::nusmv::kill_all_children();
            let mut f = Failure::from(pipeline::Error::NoMachine(format!(
                "time limit of {seconds} s reached before a verified machine (raise --time-limit SECONDS): the closed-loop game's guide had not ended"
            )));
            if let Some(line) = unrecorded {
                f.message.push_str(&format!("\n({line})"));
            }
            return Err(f);
        }
        Err(e) => return Err(e.into()),
    };
    progress.line(&format!(
        "guide: no machine ({why}); the exact loop goes on"
    ));
    Ok((None, Some(why)))
}

/// The progress line after the recordings were checked against the properties.
pub(super) fn recordings_line(e: &Explanation, properties: usize) -> String {
    let mut line = format!(
        "checked {} of {properties} properties on the recordings, none violated",
        e.checked
    );
    if !e.undecidable.is_empty() {
        let names: Vec<&str> = e.undecidable.iter().map(|u| u.property.as_str()).collect();
        line.push_str(&format!(" ({} read names not recorded)", names.join(", ")));
    }
    line
}

/// What the recordings never show of the inputs the properties read, and why it matters;
/// `None` when they show every value.
pub(super) fn unrecorded_line(e: &Explanation) -> Option<String> {
    if e.unrecorded.is_empty() {
        return None;
    }
    let all: Vec<String> = e.unrecorded.iter().map(|u| u.to_string()).collect();
    Some(format!(
        "the recordings never show {}: the machine's answer there comes from the properties \
         alone, and the loop can take long to find it; record runs that show it",
        all.join(", ")
    ))
}

/// Stages the closed-loop model and each waveform as VCD and SVG (named after its property,
/// made a safe file name); the staged paths.
fn write_counterexamples(
    results: &ResultSet,
    model: &str,
    waveforms: &[fbsynth::export::waveform::Waveform],
) -> Result<Vec<PathBuf>, Failure> {
    use fbsynth::export::waveform;
    let dir = results.staging();
    let mut files = vec![dir.join("closed_loop.smv")];
    fbsynth::files::write_atomic(&files[0], model.as_bytes()).map_err(Failure::input)?;
    for w in waveforms {
        let stem: String = (w.title.chars())
            .map(
                |c| match c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                    true => c,
                    false => '_',
                },
            )
            .collect();
        for (ext, text) in [("vcd", waveform::vcd(w)), ("svg", waveform::svg(w))] {
            let path = dir.join(format!("{stem}.{ext}"));
            fbsynth::files::write_atomic(&path, text.as_bytes()).map_err(Failure::input)?;
            files.push(path);
        }
    }
    Ok(files)
}

/// `synth verify`.
pub fn verify(args: &VerifyArgs) -> Result<(), Failure> {
    if super::json() {
        super::data_on_stdout();
    }
    let ecc = read_ecc(&args.ecc)?;
    let problem = problem(&args.ltl, &args.plant, &ecc.inputs, &ecc.outputs)?;
    let check = check(problem, &args.nusmv)?;
    // Taken first: a second run into the same folder stops before NuSMV runs.
    let results = match &args.out {
        Some(out) => Some(ResultSet::open(out).map_err(Failure::input)?),
        None => None,
    };
    let verification = pipeline::verify(&ecc, &check)?;
    let report = &verification.report;
    if super::json() {
        let summary = serde_json::json!({ "verified": report.all_hold(), "report": report });
        super::write_json(&summary)?;
    }
    out_raw!("{}", report.to_text());
    let waveforms: Vec<_> = (verification.counterexamples.iter())
        .map(|cx| cx.waveform(&ecc.inputs, &ecc.outputs))
        .collect();
    for w in &waveforms {
        out!("");
        out_raw!("{}", fbsynth::export::waveform::table(w));
    }
    if let Some(results) = results {
        let files = write_counterexamples(&results, &verification.model.text, &waveforms)?;
        let published: Vec<PathBuf> = files.iter().map(|f| results.published(f)).collect();
        results
            .publish()
            .map_err(|e| Failure::input(pipeline::Error::from(e)))?;
        out!("");
        super::show::print_written(&published);
    }
    if report.all_hold() {
        out!("verified: all {} properties hold", report.properties.len());
        Ok(())
    } else {
        Err(Failure::msg(
            exit::FAILED,
            format!(
                "not verified: {} violated",
                report
                    .failing()
                    .iter()
                    .map(|name| fbsynth::quote::cut(name).to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ))
    }
}
