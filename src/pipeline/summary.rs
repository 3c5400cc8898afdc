//! The summaries the commands write (`summary.json`) and print with `--json`: one typed
//! struct per command, each with a `format` that names it and its version
//! (`fbsynth-summary/<command>/<version>`), and the JSON Schema of them all ([`schema`],
//! `synth schema --summary`), in which each summary's `format` is a constant.
//!
//! The letters are the same in every summary: C states (`c`), K largest out-degree (`k`),
//! T transitions (`t`), N guard literals (`n`), ε corrected errors (`errors`), M modules.
//! A summary's keys are written sorted ([`to_json`]).

use crate::ecc::{bits_to_string, Ecc, Size};
use crate::pipeline::active::Asked;
use crate::pipeline::ambiguity::{self, Ambiguity, Uniqueness};
use crate::pipeline::{cegis::Iteration, main_job, Report};
use crate::scenario::ScenarioSet;
use schemars::JsonSchema;
use serde::Serialize;
use std::path::PathBuf;

/// The main job's, and `synth infer --ltl`'s: the verified machine.
pub(crate) const MAIN: &str = "fbsynth-summary/main/1";
/// `synth infer` without `--ltl`: the least machine for the recordings.
pub(crate) const INFER: &str = "fbsynth-summary/infer/1";
/// `synth infer --noisy`: the candidates by corrected errors.
pub(crate) const NOISY: &str = "fbsynth-summary/noisy/1";
/// `synth infer --noisy --ltl`: the verified machine of one candidate (`verified/`).
pub(crate) const NOISY_VERIFIED: &str = "fbsynth-summary/noisy-verified/1";
/// `synth conform --refine` with `--ltl`: the refined, verified machine.
pub(crate) const REFINED: &str = "fbsynth-summary/refined/1";
/// `synth batch`: one row per PLC.
pub(crate) const BATCH: &str = "fbsynth-summary/batch/1";
/// `synth next-recording`: the rivals and the plan.
pub(crate) const NEXT_RECORDING: &str = "fbsynth-summary/next-recording/1";
/// `synth learn`: the rounds and the passive comparison.
pub(crate) const LEARN: &str = "fbsynth-summary/learn/1";
/// `synth diff`: equivalent, or the difference.
pub(crate) const DIFF: &str = "fbsynth-summary/diff/1";
/// `synth verify`: NuSMV's verdicts.
pub(crate) const VERIFY: &str = "fbsynth-summary/verify/1";
/// `--json` of a command without a summary of its own.
pub(crate) const COMMAND: &str = "fbsynth-summary/command/1";

/// A summary as JSON, its keys sorted.
pub(crate) fn to_json(summary: &impl Serialize) -> serde_json::Value {
    serde_json::to_value(summary).expect("a summary is JSON")
}

/// The main job's `summary.json` (also `synth infer --ltl`'s, and `single/` of `synth infer
/// --modules M --ltl`); with `--json` also the files written.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct MainSummary {
    /// The summary's name and version: `fbsynth-summary/main/1`.
    #[schemars(extend("const" = MAIN))]
    pub format: &'static str,
    /// How the machine was found and what is proven.
    #[serde(flatten)]
    pub machine: main_job::Summary,
    /// With `--json`: the files written (not in `summary.json`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub files: Option<Vec<PathBuf>>,
    /// The plant learned from the recordings, when the main job learned it (`--learn-plant`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub learned_plant: Option<LearnedPlantSummary>,
}

impl MainSummary {
    /// The summary of `machine`, with `files` for `--json`.
    pub fn new(machine: &main_job::Summary, files: Option<Vec<PathBuf>>) -> MainSummary {
        MainSummary {
            format: MAIN,
            machine: machine.clone(),
            files,
            learned_plant: None,
        }
    }

    /// The summary, with the plant learned on the way.
    pub fn with_learned_plant(mut self, plant: Option<LearnedPlantSummary>) -> MainSummary {
        self.learned_plant = plant;
        self
    }
}

/// A plant the main job learned from the recordings (`--learn-plant`), as `synth
/// learn-plant` reports it: every recorded scan is a step of it.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub(crate) struct LearnedPlantSummary {
    /// The plant file, in the output folder.
    pub file: PathBuf,
    /// The recordings it was learned from.
    pub recordings: Vec<PathBuf>,
    /// The observers added to it (`--observe`).
    pub observers: Option<PathBuf>,
    /// Scans a sensor change a command drives may come later than recorded (`--slack`).
    pub slack: usize,
    /// Recorded scans, every one a step of the plant.
    pub scans: usize,
    /// Recorded runs.
    pub runs: usize,
    /// Sensors (controller inputs) it drives.
    pub sensors: usize,
    /// Sensors a command moves over several scans (each with a dwell counter).
    pub delayed: usize,
}

/// `synth infer --json` without `--ltl`: the least machine for the recordings.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct InferSummary {
    /// The summary's name and version: `fbsynth-summary/infer/1`.
    #[schemars(extend("const" = INFER))]
    pub format: &'static str,
    /// The machine's C, K, T and N.
    pub size: Size,
    /// Whether no machine with C states and T transitions has fewer guard literals.
    pub guards_proven_minimal: bool,
    /// Whether no machine with C states has fewer transitions.
    pub transitions_proven_minimal: bool,
    /// Scenarios reproduced.
    pub scenarios: usize,
    /// Seconds since the run started.
    pub seconds: f64,
    /// The SAT figures.
    pub stats: crate::sat::Stats,
    /// The files written.
    pub files: Vec<PathBuf>,
    /// The ambiguity check, when it ran.
    pub ambiguity: Option<AmbiguitySummary>,
}

/// The ambiguity check: verdict, bounds and every rival's sequence with both machines'
/// answers (`null` for no `CNF`).
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct AmbiguitySummary {
    /// Unique, ambiguous or unknown within the bounds.
    pub verdict: Uniqueness,
    /// Whether the list of rivals is complete within the bounds.
    pub complete: bool,
    /// States a rival may have (C of the machine, plus `extra_states`).
    pub states: usize,
    /// States a rival may have beyond the machine's.
    pub extra_states: usize,
    /// Transitions per state a rival may have (a bound on its K).
    pub per_state: usize,
    /// The longest distinguishing sequence looked for, in steps.
    pub depth: usize,
    /// Input vectors the sequences were drawn from.
    pub alphabet: usize,
    /// Whether those are every input vector rather than the recorded combinations.
    pub all_inputs: bool,
    /// Seconds the check took.
    pub seconds: f64,
    /// Every rival found.
    pub rivals: Vec<RivalSummary>,
}

/// A rival and the sequence that tells it from the machine.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct RivalSummary {
    /// The rival's C, K, T and N.
    pub size: Size,
    /// Where the sequence starts, after a recorded prefix.
    pub start: ambiguity::Start,
    /// Every step from the initial state: the recorded prefix, then the sequence.
    pub steps: Vec<StepSummary>,
}

/// One step of a distinguishing sequence.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct StepSummary {
    /// The input vector, as bits.
    pub inputs: String,
    /// Part of the recorded prefix.
    pub recorded: bool,
    /// The machine's outputs with `CNF`, or `null`.
    pub machine: Option<String>,
    /// The rival's outputs with `CNF`, or `null`.
    pub rival: Option<String>,
}

impl AmbiguitySummary {
    /// The summary of `found`, the check of `machine` on `set`.
    pub fn new(found: &Ambiguity, set: &ScenarioSet, machine: &Ecc) -> AmbiguitySummary {
        let bits = |b: &Option<Vec<bool>>| b.as_deref().map(bits_to_string);
        let rivals = (found.rivals.iter())
            .map(|r| RivalSummary {
                size: r.ecc.size(),
                start: r.start,
                steps: (r.answers(set, machine).iter())
                    .map(|a| StepSummary {
                        inputs: bits_to_string(&a.inputs),
                        recorded: a.recorded,
                        machine: bits(&a.machine),
                        rival: bits(&a.rival),
                    })
                    .collect(),
            })
            .collect();
        AmbiguitySummary {
            verdict: found.verdict,
            complete: found.complete,
            states: found.states,
            extra_states: found.extra_states,
            per_state: found.max_out_degree,
            depth: found.depth,
            alphabet: found.alphabet,
            all_inputs: found.all_inputs,
            seconds: found.seconds,
            rivals,
        }
    }
}

/// `synth next-recording --json`: the ambiguity check of the machine and the files of the
/// plan.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct NextRecordingSummary {
    /// The summary's name and version: `fbsynth-summary/next-recording/1`.
    #[schemars(extend("const" = NEXT_RECORDING))]
    pub format: &'static str,
    /// The check.
    #[serde(flatten)]
    pub ambiguity: AmbiguitySummary,
    /// The files written.
    pub files: Vec<PathBuf>,
}

/// `summary.json` of `synth infer --noisy`: the candidates by corrected errors ε.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct NoisySummary {
    /// The summary's name and version: `fbsynth-summary/noisy/1`.
    #[schemars(extend("const" = NOISY))]
    pub format: &'static str,
    /// The least C over the corrections.
    pub c: usize,
    /// K for that C.
    pub k: usize,
    /// The least T for that C and K.
    pub t: usize,
    /// Whether every candidate up to the bounds was listed.
    pub exhausted: bool,
    /// The candidate whose verified machine is the result (1-based), with a check.
    pub chosen: Option<usize>,
    /// Every candidate, by ε.
    pub candidates: Vec<crate::pipeline::output::NoisyRow>,
    /// The SAT figures.
    pub stats: crate::sat::noisy::NoisyStats,
    /// Seconds since the run started.
    pub total_seconds: f64,
}

/// The exact loop's figures on a noisy candidate's corrected traces (`closed_loop` in
/// `verified/summary.json`).
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct LoopSummary {
    /// The machine's C, K, T and N.
    pub size: Size,
    /// Whether no machine with C states has fewer transitions.
    pub transitions_proven_minimal: bool,
    /// Whether no machine with C states and T transitions has fewer guard literals.
    pub guards_proven_minimal: bool,
    /// Every candidate of the loop.
    pub iterations: Vec<Iteration>,
    /// NuSMV's verdicts on the machine.
    pub report: Option<Report>,
    /// Seconds since the run started.
    pub total_seconds: f64,
}

/// `verified/summary.json` of `synth infer --noisy --ltl`.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct NoisyVerifiedSummary {
    /// The summary's name and version: `fbsynth-summary/noisy-verified/1`.
    #[schemars(extend("const" = NOISY_VERIFIED))]
    pub format: &'static str,
    /// The candidate whose corrected traces gave the machine (1-based).
    pub candidate: usize,
    /// The errors ε it corrects.
    pub errors: usize,
    /// The exact loop's figures.
    pub closed_loop: LoopSummary,
}

/// `summary.json` of `synth conform --refine --ltl`: the refined machine, verified.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct RefinedSummary {
    /// The summary's name and version: `fbsynth-summary/refined/1`.
    #[schemars(extend("const" = REFINED))]
    pub format: &'static str,
    /// The machine's C, K, T and N.
    pub size: Size,
    /// Every candidate of the exact loop.
    pub iterations: Vec<Iteration>,
    /// NuSMV's verdicts (all hold).
    pub report: Report,
}

/// `summary.json` of `synth batch` (also its `--json`).
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct BatchSummary {
    /// The summary's name and version: `fbsynth-summary/batch/1`.
    #[schemars(extend("const" = BATCH))]
    pub format: &'static str,
    /// The folder of logs.
    pub logs: PathBuf,
    /// One row per PLC.
    pub plcs: Vec<crate::pipeline::batch::Row>,
}

/// `synth learn --json`: every round, the result, and the passive runs.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct LearnSummary {
    /// The summary's name and version: `fbsynth-summary/learn/1`.
    #[schemars(extend("const" = LEARN))]
    pub format: &'static str,
    /// Every round.
    pub rounds: Vec<RoundSummary>,
    /// Steps recorded on the oracle beyond the initial recordings.
    pub recorded_steps: usize,
    /// Steps of the initial recordings.
    pub initial_steps: usize,
    /// Whether the last machine is unique within the bounds.
    pub unique: bool,
    /// C of the last machine.
    pub states: usize,
    /// Whether it answers every input sequence as the oracle does.
    pub equivalent: bool,
    /// Each passive run.
    pub passive: Vec<PassiveSummary>,
}

/// A round of active learning.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct RoundSummary {
    /// C of the round's machine.
    pub states: usize,
    /// What the round recorded.
    pub asked: Asked,
    /// The ambiguity check's verdict, when it ran.
    pub verdict: Option<Uniqueness>,
    /// Steps recorded after the round.
    pub recorded_steps: usize,
    /// Whether the round widened the alphabet to every input vector.
    pub widened: bool,
}

/// A machine learned from random recordings of the active loop's length.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct PassiveSummary {
    /// The seed of the recordings.
    pub seed: u64,
    /// C of the machine.
    pub states: usize,
    /// Whether it is equivalent to the oracle.
    pub equivalent: bool,
}

/// `synth diff --json`.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct DiffSummary {
    /// The summary's name and version: `fbsynth-summary/diff/1`.
    #[schemars(extend("const" = DIFF))]
    pub format: &'static str,
    /// Whether the machines answer every input sequence alike.
    pub equivalent: bool,
    /// The shortest sequence on which they differ.
    pub difference: Option<DifferenceSummary>,
}

/// A shortest input sequence on which two machines answer differently.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct DifferenceSummary {
    /// The input vector of each `REQ`, as bits.
    pub inputs: Vec<String>,
    /// The first machine's answer to the last one: outputs with `CNF`, or `null`.
    pub first: Option<String>,
    /// The second machine's.
    pub second: Option<String>,
}

impl DiffSummary {
    /// The summary of `found`.
    pub fn new(found: Option<&crate::ecc::diff::Difference>) -> DiffSummary {
        DiffSummary {
            format: DIFF,
            equivalent: found.is_none(),
            difference: found.map(|d| DifferenceSummary {
                inputs: d.inputs.iter().map(|x| bits_to_string(x)).collect(),
                first: d.first.as_deref().map(bits_to_string),
                second: d.second.as_deref().map(bits_to_string),
            }),
        }
    }
}

/// `synth verify --json`.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct VerifySummary {
    /// The summary's name and version: `fbsynth-summary/verify/1`.
    #[schemars(extend("const" = VERIFY))]
    pub format: &'static str,
    /// Whether every property holds.
    pub verified: bool,
    /// NuSMV's verdicts.
    pub report: Report,
}

/// `--json` of a command without a summary of its own.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct CommandSummary {
    /// The summary's name and version: `fbsynth-summary/command/1`.
    #[schemars(extend("const" = COMMAND))]
    pub format: &'static str,
    /// The command's name (`main` for the main job).
    pub command: String,
    /// The exit code.
    pub exit: i32,
    /// The files it wrote.
    pub files: Vec<PathBuf>,
    /// What it printed: its result lines, and data it would have written on stdout.
    pub output: String,
    /// The error, when it failed.
    pub error: Option<String>,
}

/// Every summary: `synth schema --summary` writes the schema of this, where each summary is
/// told by its `format`.
#[derive(JsonSchema)]
#[serde(untagged)]
#[allow(dead_code)]
enum AnySummary {
    Main(MainSummary),
    Infer(InferSummary),
    Noisy(NoisySummary),
    NoisyVerified(NoisyVerifiedSummary),
    Refined(RefinedSummary),
    Batch(BatchSummary),
    NextRecording(NextRecordingSummary),
    Learn(LearnSummary),
    Diff(DiffSummary),
    Verify(VerifySummary),
    Command(CommandSummary),
}

/// The JSON Schema of every summary (`synth schema --summary`): one of the summaries above,
/// told by `format`.
pub(crate) fn schema() -> serde_json::Value {
    let mut schema = schemars::schema_for!(AnySummary);
    schema.insert("title".into(), "fbsynth summary".into());
    schema.insert(
        "description".into(),
        "A summary.json or --json summary written by synth; `format` names which and its version."
            .into(),
    );
    schema.to_value()
}
