//! How far the recordings determine the machine: "unique", or "ambiguous" with rivals.
//!
//! In: the [`ScenarioSet`], the minimal machine found for it, and [`Options`]. Out: an
//! [`Ambiguity`]: the rivals found ([`crate::sat::ambiguity`]), each a machine with the same
//! number of states that reproduces every recording, with the shortest input sequence on which
//! it answers differently from every machine before it, and the recorded prefix to reproduce
//! first.
//!
//! "Unique" is a bounded claim and is worded as one: no machine with at most `C` states
//! reproduces the recordings and answers differently on a sequence of at most `depth`
//! alphabet vectors started at a recorded point. The alphabet is the recorded input
//! combinations (sequences the plant can produce), or every input vector when asked.
//!
//! Every rival is replayed on every scenario, and its difference is recomputed by the
//! breadth-first search of [`crate::ecc::diff`]; a disagreement with the solver is a bug.

use super::Error;
use crate::ecc::diff::{difference_from, Configuration, Difference};
use crate::ecc::{AlgorithmKind, Ecc, Run};
use crate::sat::ambiguity::{self, node_states, Outcome, Query};
use crate::sat::SatError;
use crate::scenario::tree::{NodeId, ScenarioTree};
use crate::scenario::ScenarioSet;
use std::fmt::Write as _;
use std::time::{Duration, Instant};

/// Settings of the ambiguity check.
#[derive(Debug, Clone)]
pub struct Options {
    /// The algorithm form of the machines (`{0, 1, x}` per output, or two bit strings).
    pub(crate) algorithms: AlgorithmKind,
    /// Rivals to list at most, at least 1 (each differs from the machine and from every
    /// rival before it).
    pub(crate) rivals: usize,
    /// The longest distinguishing sequence looked for; `None`: the default, `C`.
    pub(crate) depth: Option<usize>,
    /// Sequences over every input vector, not only the recorded ones (at most
    /// [`MAX_ALL_INPUTS`] inputs).
    pub(crate) all_inputs: bool,
    /// Time for each rival's search.
    pub(crate) budget: Duration,
    /// Time to make each rival found smaller (fewer transitions, then guard literals).
    pub(crate) polish: Duration,
    /// States a rival may have beyond the machine's: a machine in service may need more
    /// states than the recordings show, and only a rival with more can say so.
    pub(crate) extra_states: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            algorithms: AlgorithmKind::Tri,
            rivals: 1,
            depth: None,
            all_inputs: false,
            budget: Duration::from_secs(10),
            polish: Duration::from_secs(2),
            extra_states: 0,
        }
    }
}

/// The most inputs for which [`Options::all_inputs`] enumerates every vector.
pub(crate) const MAX_ALL_INPUTS: usize = 10;

/// Where a distinguishing sequence starts: after the first `step` steps of scenario
/// `scenario` (0-based index; `step` 0 is the initial state).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, schemars::JsonSchema)]
pub struct Start {
    /// 0-based index of the scenario in the [`ScenarioSet`].
    pub(crate) scenario: usize,
    /// Number of that scenario's steps reproduced first (0: from the initial state).
    pub(crate) step: usize,
}

/// A second machine that fits the recordings as well, and where it differs.
#[derive(Debug, Clone)]
pub(crate) struct Rival {
    /// The rival machine; it reproduces every recording.
    pub(crate) ecc: Ecc,
    /// Where the distinguishing sequence starts, after a recorded prefix.
    pub(crate) start: Start,
    /// The sequence after the prefix; `first` is the minimal machine's answer to its last
    /// step, `second` the rival's.
    pub(crate) difference: Difference,
}

/// The verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Uniqueness {
    /// No rival within the bounds.
    Unique,
    /// At least one rival.
    Ambiguous,
    /// The budget ran out before the first answer.
    Unknown,
}

/// The result of [`check`].
#[derive(Debug, Clone)]
pub struct Ambiguity {
    /// Unique, ambiguous or unknown within the bounds.
    pub verdict: Uniqueness,
    /// The rivals found, each differing from the machine and every rival before it.
    pub(crate) rivals: Vec<Rival>,
    /// Whether the list is complete within the bounds (the last search found no further
    /// rival), rather than cut by [`Options::rivals`] or the budget.
    pub(crate) complete: bool,
    /// States a rival may have: the machine's plus [`extra_states`](Self::extra_states).
    pub(crate) states: usize,
    /// States a rival may have beyond the machine's ([`Options::extra_states`]).
    pub(crate) extra_states: usize,
    /// At most this many transitions per state.
    pub(crate) max_out_degree: usize,
    /// The longest distinguishing sequence looked for, in steps.
    pub(crate) depth: usize,
    /// Number of input vectors the sequences were drawn from.
    pub(crate) alphabet: usize,
    /// Whether the alphabet is every input vector rather than the recorded combinations.
    pub(crate) all_inputs: bool,
    /// Wall-clock seconds the check took.
    pub(crate) seconds: f64,
    /// Recorded steps whose points the check started from: all of them, or on long
    /// recordings the part of them that [`check_long`] encoded last.
    pub(crate) steps_encoded: usize,
    /// Recorded steps in all.
    pub(crate) steps: usize,
}

impl Ambiguity {
    /// The verdict line: `unique (...)`, `ambiguous: ...` or `unknown (...)`.
    pub(crate) fn summary(&self) -> String {
        let over = if self.all_inputs {
            format!("any of the {} input vectors", self.alphabet)
        } else {
            format!("the {} recorded input combinations", self.alphabet)
        };
        let size = format!(
            "{} {} state{} (at most {} transition{} per state)",
            if self.extra_states > 0 { "at most" } else { "" },
            self.states,
            if self.states == 1 { "" } else { "s" },
            self.max_out_degree,
            if self.max_out_degree == 1 { "" } else { "s" }
        )
        .trim_start()
        .to_string();
        let points = match self.steps_encoded < self.steps {
            true => format!(
                "a point of the first {} of the {} recorded steps",
                self.steps_encoded, self.steps
            ),
            false => "a recorded point".to_string(),
        };
        match self.verdict {
            Uniqueness::Unique => format!(
                "unique: no other machine with {size} reproduces the recordings and answers differently within {} step{} of {points} (inputs: {over}; {:.2} s)",
                self.depth,
                if self.depth == 1 { "" } else { "s" },
                self.seconds
            ),
            Uniqueness::Ambiguous => format!(
                "ambiguous: {}{} other machine{} with {size} reproduce{} the recordings but answer{} differently (inputs: {over}; {:.2} s)",
                if self.complete { "" } else { "at least " },
                self.rivals.len(),
                if self.rivals.len() == 1 { "" } else { "s" },
                if self.rivals.len() == 1 { "s" } else { "" },
                if self.rivals.len() == 1 { "s" } else { "" },
                self.seconds
            ),
            Uniqueness::Unknown => format!(
                "unknown: no answer within the budget ({:.2} s); raise --ambiguity-budget",
                self.seconds
            ),
        }
    }
}

/// The alphabet of the check: the tree's vectors, then (with `all_inputs`) every other one.
pub(crate) fn alphabet(
    tree: &ScenarioTree,
    inputs: usize,
    all_inputs: bool,
) -> Result<Vec<Vec<bool>>, Error> {
    let mut out = tree.input_vectors.clone();
    if all_inputs {
        if inputs > MAX_ALL_INPUTS {
            return Err(Error::Usage(format!(
                "{inputs} inputs are too many to try every input vector (at most {MAX_ALL_INPUTS}); check over the recorded input combinations instead"
            )));
        }
        for v in 0..1u32 << inputs {
            let x: Vec<bool> = (0..inputs)
                .map(|i| v >> (inputs - 1 - i) & 1 == 1)
                .collect();
            if !out.contains(&x) {
                out.push(x);
            }
        }
    }
    Ok(out)
}

/// Looks for rivals of `machine` (minimal for `set`, replaying it).
pub fn check(
    set: &ScenarioSet,
    tree: &ScenarioTree,
    machine: &Ecc,
    opts: &Options,
) -> Result<Ambiguity, Error> {
    let t0 = Instant::now();
    let size = machine.size();
    let states = size.c + opts.extra_states;
    let depth = opts.depth.unwrap_or(states).max(1);
    let alphabet = alphabet(tree, set.inputs.len(), opts.all_inputs)?;
    let query = Query {
        tree,
        kind: opts.algorithms,
        states,
        max_out_degree: size.k.max(1),
        polish: opts.polish,
        // Over every vector the steps' inputs are free bits (see the encoding).
        alphabet: match opts.all_inputs {
            true => tree.input_vectors.clone(),
            false => alphabet.clone(),
        },
        every_vector: opts.all_inputs,
        depth,
        inputs: set.inputs.clone(),
        outputs: set.outputs.clone(),
    };
    let mut known: Vec<Ecc> = vec![machine.clone()];
    let mut rivals: Vec<Rival> = Vec::new();
    let mut verdict = Uniqueness::Unique;
    let mut complete = true;
    let limit = opts.rivals.max(1);
    while rivals.len() < limit {
        let refs: Vec<&Ecc> = known.iter().collect();
        match ambiguity::rival(&query, &refs, Instant::now() + opts.budget) {
            Outcome::None => break,
            Outcome::Unknown => {
                if rivals.is_empty() {
                    verdict = Uniqueness::Unknown;
                }
                complete = false;
                break;
            }
            Outcome::Rival(ecc) => {
                set.check(&ecc).map_err(|m| {
                    SatError::Bug(format!("a rival does not reproduce the recordings: {m}"))
                })?;
                let rival = told_apart(tree, machine, ecc, &alphabet)?;
                verdict = Uniqueness::Ambiguous;
                known.push(rival.ecc.clone());
                rivals.push(rival);
            }
        }
    }
    if rivals.len() == limit {
        complete = false;
    }
    Ok(Ambiguity {
        verdict,
        rivals,
        complete,
        states,
        extra_states: opts.extra_states,
        max_out_degree: query.max_out_degree,
        depth,
        alphabet: alphabet.len(),
        all_inputs: opts.all_inputs,
        seconds: t0.elapsed().as_secs_f64(),
        steps_encoded: set.step_count(),
        steps: set.step_count(),
    })
}

/// [`check`] on recordings of any length. Long ones (see [`super::lazy`]) are searched a part
/// at a time: rivals are looked for on prefixes of the scenarios, each rival found is replayed
/// on the whole recordings, and a scenario it departs from gets a longer prefix before the
/// search is repeated. Every rival returned reproduces every recorded step; "unique" is
/// claimed for distinguishing sequences started in the part encoded (the summary says so),
/// since any machine that fits the whole fits the part.
pub(crate) fn check_long(
    set: &ScenarioSet,
    machine: &Ecc,
    opts: &Options,
) -> Result<Ambiguity, Error> {
    use super::lazy::{until_reproduced, whole_tree, FIRST_PART_STEPS};
    let t0 = Instant::now();
    if let Some(tree) = whole_tree(set)? {
        return check(set, &tree, machine, opts);
    }
    let (mut found, _) = until_reproduced(
        set,
        FIRST_PART_STEPS,
        &mut |part, tree, _| check(part, tree, machine, opts),
        &|found: &Ambiguity| {
            let rivals = found.rivals.iter();
            rivals.flat_map(|r| set.divergences(&r.ecc)).collect()
        },
        &mut |_| {},
    )?;
    found.steps = set.step_count();
    found.seconds = t0.elapsed().as_secs_f64();
    Ok(found)
}

/// The rival with the shortest sequence, from a recorded point, on which it answers
/// differently from the minimal machine.
fn told_apart(
    tree: &ScenarioTree,
    machine: &Ecc,
    ecc: Ecc,
    alphabet: &[Vec<bool>],
) -> Result<Rival, Error> {
    // Recorded points by depth, so that among the shortest sequences the shortest prefix wins.
    let mut nodes: Vec<NodeId> = (0..tree.nodes.len()).map(NodeId).collect();
    nodes.sort_by_key(|v| tree.witness[v.0].1);
    let (rival_at, at) = (node_states(&ecc, tree), node_states(machine, tree));
    let starts: Vec<(Configuration, Configuration)> = nodes
        .iter()
        .map(|v| {
            let z = tree.nodes[v.0].outputs.clone();
            ((at[v.0], z.clone()), (rival_at[v.0], z))
        })
        .collect();
    let (i, difference) = difference_from(machine, &ecc, &starts, alphabet).ok_or_else(|| {
        SatError::Bug("the solver's rival answers every sequence as the machine does".into())
    })?;
    let (scenario, step) = tree.witness[nodes[i].0];
    Ok(Rival {
        ecc,
        start: Start { scenario, step },
        difference,
    })
}

/// One step of a rival's sequence as both machines answer it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Answer {
    /// The input vector of this step.
    pub(crate) inputs: Vec<bool>,
    /// `CNF` with the outputs, or `None`.
    pub(crate) machine: Option<Vec<bool>>,
    /// The rival's answer: `CNF` with the outputs, or `None`.
    pub(crate) rival: Option<Vec<bool>>,
    /// Part of the recorded prefix (both machines answer as recorded).
    pub(crate) recorded: bool,
}

impl Rival {
    /// Every input vector to apply from the initial state: the recorded prefix, then the
    /// distinguishing sequence.
    pub(crate) fn inputs(&self, set: &ScenarioSet) -> Vec<Vec<bool>> {
        let prefix = &set.scenarios[self.start.scenario].steps[..self.start.step];
        prefix
            .iter()
            .map(|s| s.inputs.clone())
            .chain(self.difference.inputs.iter().cloned())
            .collect()
    }

    /// Both machines' answers along [`Self::inputs`].
    pub(crate) fn answers(&self, set: &ScenarioSet, machine: &Ecc) -> Vec<Answer> {
        let (mut a, mut b) = (Run::new(machine), Run::new(&self.ecc));
        self.inputs(set)
            .into_iter()
            .enumerate()
            .map(|(i, x)| Answer {
                machine: a.step(&x).map(|_| a.outputs.clone()),
                rival: b.step(&x).map(|_| b.outputs.clone()),
                recorded: i < self.start.step,
                inputs: x,
            })
            .collect()
    }

    /// A readable account: where to start, then the sequence with both answers.
    pub(crate) fn describe(&self, set: &ScenarioSet, machine: &Ecc, name: &str) -> Vec<String> {
        let origin = &set.scenarios[self.start.scenario].origin;
        let mut lines = vec![match self.start.step {
            0 => "from the initial state, apply:".to_string(),
            k => format!(
                "reproduce steps 1-{k} of the scenario at {}:{} (scenario {}), then apply:",
                origin.file.display(),
                origin.line,
                self.start.scenario + 1
            ),
        }];
        let answer = |o: &Option<Vec<bool>>| match o {
            Some(z) => format!("CNF {}", crate::ecc::bits_to_string(z)),
            None => "no CNF".to_string(),
        };
        lines.push(format!(
            "  {:>4}  {:<w$}  {:<14}  {}",
            "step",
            "inputs",
            "this machine",
            name,
            w = set.inputs.len().max(6)
        ));
        let answers = self.answers(set, machine);
        for (k, a) in answers.iter().enumerate().skip(self.start.step) {
            lines.push(format!(
                "  {:>4}  {:<w$}  {:<14}  {}{}",
                k - self.start.step + 1,
                crate::ecc::bits_to_string(&a.inputs),
                answer(&a.machine),
                answer(&a.rival),
                if a.machine != a.rival {
                    "   <- differs"
                } else {
                    ""
                },
                w = set.inputs.len().max(6)
            ));
        }
        lines
    }
}

impl Ambiguity {
    /// NuSMV's verdict on every rival in closed loop, in order: the properties it violates
    /// (none: every property holds for the rival too).
    pub(crate) fn verify_rivals(&self, check: &super::Check) -> Result<Vec<Vec<String>>, Error> {
        let mut verifier = check.verifier()?;
        let mut out = Vec::new();
        for r in &self.rivals {
            let v = verifier.verify(&r.ecc)?;
            out.push(v.report.failing().iter().map(|s| s.to_string()).collect());
        }
        Ok(out)
    }

    /// The verdict and every rival with its sequence, as `synth infer` prints it and writes
    /// `ambiguity.txt`.
    pub(crate) fn to_text(&self, set: &ScenarioSet, machine: &Ecc) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "{}", self.summary());
        if !self.rivals.is_empty() {
            let _ = writeln!(
                s,
                "  inputs: {}; outputs: {}",
                set.inputs.join(" "),
                set.outputs.join(" ")
            );
        }
        for (k, r) in self.rivals.iter().enumerate() {
            let name = format!("rival {} (rival{}.json)", k + 1, k + 1);
            let _ = writeln!(s, "  {name}: {}", r.ecc.size());
            for line in r.describe(set, machine, &format!("rival {}", k + 1)) {
                let _ = writeln!(s, "    {line}");
            }
        }
        if self.verdict == Uniqueness::Ambiguous {
            let _ = writeln!(
                s,
                "  to tell them apart, record the sequences above on the machine in service (`synth next-recording` writes them as a plan)"
            );
        }
        s
    }

    /// The plan of what to record (`plan.csv`): one row per step to apply, `scenario`,
    /// `step`, `phase` (`replay` for the recorded prefix, `probe` after it), the inputs, and
    /// what the machine and the rival would answer (`-` for no `CNF`).
    pub(crate) fn plan_csv(&self, set: &ScenarioSet, machine: &Ecc) -> String {
        let mut csv = String::from("scenario,step,phase");
        for x in &set.inputs {
            let _ = write!(csv, ",in:{x}");
        }
        csv.push_str(",expect_machine,expect_rival\n");
        for (k, r) in self.rivals.iter().enumerate() {
            for (i, a) in r.answers(set, machine).iter().enumerate() {
                let phase = if a.recorded { "replay" } else { "probe" };
                let _ = write!(csv, "{},{},{phase}", k + 1, i + 1);
                for &b in &a.inputs {
                    let _ = write!(csv, ",{}", u8::from(b));
                }
                let _ = writeln!(
                    csv,
                    ",{},{}",
                    plan_answer(&a.machine),
                    plan_answer(&a.rival)
                );
            }
        }
        csv
    }

    /// The plan as a table (`plan.txt`): per sequence, its length and the steps to probe
    /// after the recorded prefix.
    pub(crate) fn plan_text(&self, set: &ScenarioSet, machine: &Ecc) -> String {
        let mut txt = String::new();
        for (k, r) in self.rivals.iter().enumerate() {
            let answers = r.answers(set, machine);
            let _ = writeln!(
                txt,
                "sequence {}: {} steps ({} to reproduce a recording, {} new), tells rival {} apart",
                k + 1,
                answers.len(),
                r.start.step,
                answers.len() - r.start.step,
                k + 1
            );
            for (i, a) in answers.iter().enumerate().filter(|(_, a)| !a.recorded) {
                let _ = writeln!(
                    txt,
                    "  {:>4}  {}  machine {:<12} rival {}",
                    i + 1,
                    crate::ecc::bits_to_string(&a.inputs),
                    plan_answer(&a.machine),
                    plan_answer(&a.rival)
                );
            }
        }
        txt
    }
}

/// An answer in the plan: the outputs with `CNF`, `-` without.
fn plan_answer(o: &Option<Vec<bool>>) -> String {
    match o {
        Some(z) => crate::ecc::bits_to_string(z),
        None => "-".to_string(),
    }
}
