//! `synth infer --noisy`, `synth bench-noisy` and `synth generate distribution`: synthesis
//! from noisy sampled logs (seed 000, Algorithm 1) on the command line.
//!
//! In: [`InferArgs`] with `--noisy`. Out: a folder with one subfolder per candidate
//! (`candidate_<k>/`: the machine in every requested format, `corrected.txt` and
//! `corrected.csv` with the error-free traces, `candidate.json` with ε and sizes) and a summary
//! (`summary.txt`, `summary.json`). With `--ltl` and `--plant` every candidate is checked by
//! NuSMV in closed loop and the first verified one is reported; otherwise all are written,
//! ranked by ε.

use super::infer::{check_exportable, load_scenarios, parse_formats, AlgorithmsArg, InferArgs};
use super::verified::{load_setup, session, NusmvArgs};
use super::{exit, Failure, Progress};
use crate::cases::distribution;
use crate::ecc::AlgorithmKind;
use crate::export;
use crate::files::write_atomic;
use crate::sat::noisy::{synthesize_noisy, Candidate, Flow, NoisyOptions};
use crate::sat::SatError;
use crate::scenario::{csvlog, fbsat};
use crate::verify::{self, Setup};
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The options of `synth infer` that only `--noisy` reads.
#[derive(Debug, Args, Clone)]
pub struct NoisyArgs {
    /// Read the traces as noisy (scan-cycle skew between PLC and data collector): correct up
    /// to --max-errors recorded output changes and list the minimal machines by errors.
    #[arg(long)]
    pub noisy: bool,
    /// With --noisy: at most this many corrected errors (default: no bound).
    #[arg(long, value_name = "E", requires = "noisy")]
    pub max_errors: Option<usize>,
    /// With --noisy: stop after this many distinct candidate machines.
    #[arg(long, default_value_t = 5, value_name = "N", requires = "noisy")]
    pub enumerate: usize,
    /// With --noisy: LTL properties each candidate is checked against (needs --plant).
    #[arg(long, value_name = "FILE", requires_all = ["noisy", "plant"])]
    pub ltl: Option<PathBuf>,
    /// With --noisy: surrogate plant for the check (needs --ltl).
    #[arg(long, value_name = "FILE", requires_all = ["noisy", "ltl"])]
    pub plant: Option<PathBuf>,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
}

impl NoisyArgs {
    /// `--noisy` not given (for commands that run `infer` themselves).
    pub fn off() -> NoisyArgs {
        NoisyArgs {
            noisy: false,
            max_errors: None,
            enumerate: 5,
            ltl: None,
            plant: None,
            nusmv: NusmvArgs {
                nusmv: None,
                timeout: 60.0,
            },
        }
    }
}

fn folder_error(dir: &Path, e: std::io::Error) -> Failure {
    Failure::msg(exit::INPUT, format!("cannot create {}: {e}", dir.display()))
}

/// One row of the summary.
#[derive(Debug, serde::Serialize)]
struct Row {
    candidate: usize,
    errors: usize,
    size: crate::ecc::Size,
    guards_exact: bool,
    /// `Some(true)`: every property holds; `None`: not checked.
    verified: Option<bool>,
    folder: String,
}

pub fn infer_noisy(args: &InferArgs) -> Result<(), Failure> {
    let progress = Progress::new(args.quiet);
    let set = load_scenarios(&args.traces)?;
    let formats = parse_formats(&args.format)?;
    check_exportable(&set, &args.name, &formats)?;
    let n = &args.noisy;
    let checker = match (&n.ltl, &n.plant) {
        (Some(ltl), Some(plant)) => Some((
            load_setup(ltl, plant, &set.inputs, &set.outputs)?,
            session(&n.nusmv)?,
        )),
        _ => None,
    };
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = args.traces.traces[0]
            .file_name()
            .map(|f| {
                f.to_string_lossy()
                    .split('.')
                    .next()
                    .unwrap_or("traces")
                    .to_string()
            })
            .unwrap_or_else(|| "traces".into());
        PathBuf::from("out").join(stem)
    });
    std::fs::create_dir_all(&out).map_err(|e| folder_error(&out, e))?;
    let work = tempfile::tempdir().map_err(Failure::input)?;
    let opts = NoisyOptions {
        algorithms: match args.algorithms {
            AlgorithmsArg::Tri => AlgorithmKind::Tri,
            AlgorithmsArg::Binary => AlgorithmKind::Binary,
        },
        max_states: args.max_states,
        max_errors: n.max_errors,
        enumerate: n.enumerate.max(1),
        guard_budget: Duration::from_secs_f64(args.guard_budget.max(0.0)),
        ..NoisyOptions::default()
    };
    let mut verdicts: Vec<Option<bool>> = Vec::new();
    let mut check_error: Option<Failure> = None;
    let mut checker = checker;
    let ltl_file = n.ltl.clone().unwrap_or_default();
    let mut accept = |c: &Candidate| -> Flow {
        let Some(((props, plant, coupling), session)) = checker.as_mut() else {
            verdicts.push(None);
            return Flow::Continue;
        };
        let setup = Setup {
            plant,
            coupling,
            spec_file: &ltl_file,
            props,
        };
        match verify::verify(&c.ecc, &setup, session, work.path()) {
            Ok(v) => {
                let holds = v.report.all_hold();
                progress.line(&format!(
                    "  NuSMV: {}",
                    if holds {
                        "every property holds".to_string()
                    } else {
                        format!("violated: {}", v.report.failing().join(", "))
                    }
                ));
                verdicts.push(Some(holds));
                if holds {
                    Flow::Stop
                } else {
                    Flow::Continue
                }
            }
            Err(e) => {
                check_error = Some(Failure::input(e));
                Flow::Stop
            }
        }
    };
    let result = synthesize_noisy(&set, &opts, &mut |m| progress.line(m), &mut accept).map_err(
        |e| match e {
            SatError::TooManyStates { .. } => Failure::with_code(exit::NO_MACHINE, e),
            SatError::Bug(_) => Failure::with_code(exit::BUG, e),
        },
    )?;
    if let Some(f) = check_error {
        return Err(f);
    }
    let mut rows = Vec::new();
    for (k, c) in result.candidates.iter().enumerate() {
        let folder = format!("candidate_{}", k + 1);
        let dir = out.join(&folder);
        std::fs::create_dir_all(&dir).map_err(|e| folder_error(&dir, e))?;
        export::write_all(&c.ecc, &dir, &args.name, &formats).map_err(Failure::input)?;
        let mut text = Vec::new();
        fbsat::write(&c.corrected, &mut text).map_err(Failure::input)?;
        write_atomic(&dir.join("corrected.txt"), &text).map_err(Failure::input)?;
        let mut csv = Vec::new();
        csvlog::write(&c.corrected, &mut csv).map_err(Failure::input)?;
        write_atomic(&dir.join("corrected.csv"), &csv).map_err(Failure::input)?;
        let row = Row {
            candidate: k + 1,
            errors: c.errors,
            size: c.size,
            guards_exact: c.guards_exact,
            verified: verdicts.get(k).copied().flatten(),
            folder,
        };
        let json = serde_json::to_string_pretty(&row).expect("serializable");
        write_atomic(&dir.join("candidate.json"), json.as_bytes()).map_err(Failure::input)?;
        rows.push(row);
    }
    let verified = rows
        .iter()
        .find(|r| r.verified == Some(true))
        .map(|r| r.candidate);
    let mut table = format!(
        "noisy synthesis: N = {}  K = {}  R = {}; {} alternative edges; {} candidate(s){}\n\n\
         candidate  errors  C   K   T   N    verified  folder\n",
        result.n,
        result.k,
        result.r,
        result.stats.alternatives,
        rows.len(),
        if result.exhausted { ", all" } else { "" }
    );
    for r in &rows {
        table.push_str(&format!(
            "{:<10} {:<7} {:<3} {:<3} {:<3} {:<4} {:<9} {}\n",
            r.candidate,
            r.errors,
            r.size.c,
            r.size.k,
            r.size.t,
            r.size.n,
            match r.verified {
                None => "-",
                Some(true) => "yes",
                Some(false) => "no",
            },
            r.folder
        ));
    }
    write_atomic(&out.join("summary.txt"), table.as_bytes()).map_err(Failure::input)?;
    let summary = serde_json::json!({
        "n": result.n, "k": result.k, "r": result.r,
        "exhausted": result.exhausted,
        "first_verified": verified,
        "candidates": rows,
        "stats": result.stats,
        "total_seconds": progress.elapsed(),
    });
    write_atomic(
        &out.join("summary.json"),
        serde_json::to_string_pretty(&summary)
            .expect("serializable")
            .as_bytes(),
    )
    .map_err(Failure::input)?;
    print!("{table}");
    println!("results in {}", out.display());
    // Seed 000's toolchain: correct the traces first, then distribute the logic.
    if let Some(m) = args.modules {
        let chosen = verified.unwrap_or(1);
        let c = &result.candidates[chosen - 1];
        let dir = out.join("modular");
        std::fs::create_dir_all(&dir).map_err(|e| folder_error(&dir, e))?;
        println!(
            "modular synthesis (M = {m}) on the corrected traces of candidate {chosen} (ε = {}):",
            c.errors
        );
        super::modular::distribute(args, m, &c.corrected, &dir, &progress)?;
    }
    match (checker_given(n), verified) {
        (false, _) => Ok(()),
        (true, Some(k)) => {
            println!("first verified candidate: {k} (NuSMV: every property holds)");
            Ok(())
        }
        (true, None) => Err(Failure::msg(
            exit::NO_MACHINE,
            "no candidate satisfies every property (raise --enumerate or --max-errors)",
        )),
    }
}

fn checker_given(n: &NoisyArgs) -> bool {
    n.ltl.is_some() && n.plant.is_some()
}

/// `synth generate distribution`: writes the shipped logs.
pub fn generate_distribution(dir: &Path) -> Result<(), Failure> {
    let (files, injected) = distribution::write_files(dir).map_err(Failure::input)?;
    println!(
        "recorded {} use cases and {} held-out runs of the distribution station; \
         {injected} scan-cycle errors injected (rate {}, seed {}):",
        distribution::use_cases().len(),
        distribution::held_out_cases().len(),
        distribution::SHIPPED_RATE,
        distribution::SHIPPED_SEED
    );
    for f in files {
        println!("  {}", f.display());
    }
    Ok(())
}

#[derive(Debug, Args)]
pub struct BenchNoisyArgs {
    /// Log lengths in samples, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1000,10000,100000")]
    pub samples: Vec<usize>,
    /// Probability that an output change is recorded one sample early.
    #[arg(long, default_value_t = 0.02)]
    pub rate: f64,
    /// Seed of the use cases and of the injected errors.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Candidates to enumerate after minimization.
    #[arg(long, default_value_t = 1)]
    pub enumerate: usize,
    /// Bound on corrected errors, as a multiple of the number injected (0: no bound).
    #[arg(long, default_value_t = 1.0)]
    pub error_bound: f64,
    /// Progress of every minimization step on stderr.
    #[arg(long, short)]
    pub verbose: bool,
}

/// `synth bench-noisy`: times noisy synthesis on generated distribution-station logs
/// ([`distribution::random_logs`], skew injected per log).
pub fn bench_noisy(args: &BenchNoisyArgs) -> Result<(), Failure> {
    println!(
        "samples  steps   nodes   alts  injected  N  K  R   ε(first)  vars      clauses    minimize_s  enumerate_s  total_s"
    );
    for &len in &args.samples {
        let mut injected = 0;
        let noisy: Vec<_> = distribution::random_logs(len, args.seed)
            .iter()
            .enumerate()
            .map(|(k, log)| {
                let (n, i) = distribution::inject_skew(log, args.rate, args.seed + k as u64);
                injected += i;
                n
            })
            .collect();
        let set = distribution::to_scenarios(&noisy, "<generated>");
        let opts = NoisyOptions {
            enumerate: args.enumerate.max(1),
            max_errors: (args.error_bound > 0.0)
                .then(|| (injected as f64 * args.error_bound).ceil() as usize),
            ..NoisyOptions::default()
        };
        let t = Instant::now();
        let progress = Progress::new(!args.verbose);
        let r = synthesize_noisy(&set, &opts, &mut |m| progress.line(m), &mut |_| {
            Flow::Continue
        })
        .map_err(|e| Failure::with_code(exit::BUG, e))?;
        let total = t.elapsed().as_secs_f64();
        println!(
            "{:<8} {:<7} {:<7} {:<5} {:<9} {:<2} {:<2} {:<3} {:<9} {:<9} {:<10} {:<11.2} {:<12.2} {:.2}",
            len,
            set.step_count(),
            r.stats.graph_nodes,
            r.stats.alternatives,
            injected,
            r.n,
            r.k,
            r.r,
            r.candidates.first().map_or(0, |c| c.errors),
            r.stats.variables,
            r.stats.clauses,
            r.stats.minimize_seconds,
            r.stats.enumerate_seconds,
            total
        );
    }
    Ok(())
}
