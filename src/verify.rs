//! Closed-loop verification of one ECC: compose, run NuSMV, report, and turn a counterexample
//! into a negative scenario.
//!
//! In: an [`Ecc`], a [`Plant`], checked [`Coupling`], properties, and a NuSMV [`Dialogue`].
//! Out: a [`Report`] with one [`PropertyReport`] per property (NuSMV's verdict line kept), and
//! for every violated property with a trace, a [`Counterexample`]: the lasso as NuSMV printed
//! it, with a loop point that really violates the property, and as a [`NegativeScenario`].
//!
//! Every "holds" in a report comes from NuSMV; nothing here decides a verdict itself. Each
//! verdict is NuSMV's answer to the question about that very property, asked by the name the
//! model gives it ([`crate::smv::closed_loop::smv_property_name`]), never matched by the text
//! NuSMV reprints. The lasso evaluation only picks *which* of NuSMV's `-- Loop starts here`
//! markers to use: NuSMV marks every earlier state equal to the last one, and some of those
//! loop points satisfy the property (its tableau variables are not printed). A counterexample
//! without a loop marker, or without the values of a name its property reads, was cut short:
//! it is an error ([`VerifyError::Incomplete`]), never shown as a run.

use crate::ecc::Ecc;
use crate::export::waveform::Waveform;
use crate::ltl::{property_name, Ltl, Property};
use crate::nusmv::{CheckMode, Dialogue, ModelError, NusmvError, Query, Trace, Verdict};
use crate::scenario::negative::{NegativeScenario, NegativeStep};
use crate::smv::composition::{
    compose, compose_controller, ComposedModel, Coupling, Source, CONTROLLER_INSTANCE,
    PLANT_INSTANCE,
};
use crate::smv::plant::Plant;
use crate::smv::SmvError;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The verdict on one property.
#[derive(Debug, Clone, serde::Serialize, schemars::JsonSchema)]
pub struct PropertyReport {
    /// The property's name: its label, or `p<k>` for the unlabelled `k`-th one.
    pub(crate) name: String,
    /// The formula as the user wrote it.
    pub(crate) text: String,
    /// Line in the spec file.
    pub(crate) line: usize,
    /// Whether NuSMV found the property true on the closed loop.
    pub(crate) holds: bool,
    /// NuSMV's own verdict line, verbatim.
    pub(crate) verdict_line: String,
    /// Length (states, without the repeated last one) of the counterexample, if one was printed.
    pub(crate) counterexample_length: Option<usize>,
}

/// The verdicts on every property, in spec order.
#[derive(Debug, Clone, serde::Serialize, schemars::JsonSchema)]
pub struct Report {
    /// One report per property, in spec order.
    pub properties: Vec<PropertyReport>,
    /// Wall-clock time NuSMV took to check the closed loop, in seconds.
    pub(crate) nusmv_seconds: f64,
    /// What NuSMV printed on stderr that no verdict accounts for ([`Dialogue::warnings`]).
    pub(crate) nusmv_warnings: Vec<String>,
}

impl Report {
    /// Whether every property holds: the controller passed verification.
    pub fn all_hold(&self) -> bool {
        self.properties.iter().all(|p| p.holds)
    }

    /// The names of the violated properties, in spec order.
    pub(crate) fn failing(&self) -> Vec<&str> {
        self.properties
            .iter()
            .filter(|p| !p.holds)
            .map(|p| p.name.as_str())
            .collect()
    }

    /// The report as text, one property per line.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        for p in &self.properties {
            s.push_str(&format!(
                "{:8} {} (line {}): {}\n         NuSMV: {}\n",
                if p.holds { "HOLDS" } else { "VIOLATED" },
                p.name,
                p.line,
                p.text,
                p.verdict_line
            ));
        }
        for w in self.warning_lines() {
            s.push_str(&w);
            s.push('\n');
        }
        s
    }

    /// A line per NuSMV warning, as reports show them.
    pub(crate) fn warning_lines(&self) -> impl Iterator<Item = String> + '_ {
        (self.nusmv_warnings.iter())
            .map(|w| format!("NuSMV WARNING (read it: it may change a verdict): {w}"))
    }
}

/// A counterexample of one property, as a lasso over full closed-loop states.
#[derive(Debug, Clone)]
pub struct Counterexample {
    /// Name of the violated property (as in [`PropertyReport::name`]).
    pub(crate) property: String,
    /// States of the lasso without the repeated last state.
    pub(crate) states: Vec<BTreeMap<String, String>>,
    /// Index of the state the loop returns to.
    pub(crate) loop_start: usize,
    /// For a safety property `G p` (`p` without temporal operators): the first state where `p`
    /// is false. The prefix up to it is a violation on its own, whatever follows.
    pub(crate) violation_at: Option<usize>,
    /// Whether the lasso evaluation confirmed that this loop point violates the property.
    pub(crate) confirmed: bool,
    /// Controller state names (`s0`, ...) along the lasso, when the trace shows them.
    pub(crate) controller_states: Vec<Option<String>>,
}

impl Counterexample {
    /// The run as signals to show ([`crate::export::waveform`]): the controller's `inputs`,
    /// its `outputs` and state, then the plant's own variables, in the order NuSMV names them.
    pub(crate) fn waveform(&self, inputs: &[String], outputs: &[String]) -> Waveform {
        use crate::export::waveform::{Group, Signal, Value};
        let along = |key: &str| -> Vec<Value> {
            (self.states.iter())
                .map(|s| s.get(key).map_or(Value::Unknown, |v| Value::parse(v)))
                .collect()
        };
        let signal = |group, name: &str, key: &str| Signal {
            group,
            name: name.to_string(),
            values: along(key),
        };
        let mut signals: Vec<Signal> = Vec::new();
        signals.extend(inputs.iter().map(|n| signal(Group::Input, n, n)));
        signals.extend(outputs.iter().map(|n| signal(Group::Output, n, n)));
        signals.push(Signal {
            group: Group::State,
            name: "state".into(),
            values: (self.controller_states.iter())
                .map(|s| {
                    s.as_deref()
                        .map_or(Value::Unknown, |v| Value::Text(v.into()))
                })
                .collect(),
        });
        let plant: std::collections::BTreeSet<&str> = (self.states.iter())
            .flat_map(|s| s.keys())
            .filter_map(|k| k.strip_prefix("plant."))
            .filter(|k| !inputs.iter().any(|i| i == k))
            .collect();
        signals.extend(
            plant
                .into_iter()
                .map(|n| signal(Group::Plant, n, &format!("plant.{n}"))),
        );
        Waveform {
            title: self.property.clone(),
            signals,
            steps: self.states.len(),
            loop_start: self.loop_start,
        }
    }
}

/// Why a verification could not give verdicts.
#[derive(Debug, thiserror::Error)]
pub enum VerifyError {
    /// NuSMV rejected the closed-loop model; each error is mapped back to the plant file, the
    /// spec file or the generated model.
    #[error("{}", describe(.0))]
    Model(Vec<LocatedError>),
    /// Running NuSMV failed otherwise (not found, crashed, unparsable output, ...).
    #[error("{0}")]
    Nusmv(#[from] NusmvError),
    /// The ECC could not be emitted as an SMV module.
    #[error("{0}")]
    Smv(#[from] SmvError),
    /// Creating the work folder or writing the closed-loop model file failed.
    #[error("cannot write the closed-loop model: {0}")]
    Io(#[from] std::io::Error),
    /// NuSMV exceeded its timeout on the closed loop and was killed.
    #[error("NuSMV did not finish checking the closed loop with plant {} within {seconds} s and was killed; raise --timeout SECONDS or make the plant model smaller", plant.display())]
    Timeout {
        /// The timeout that was exceeded, in seconds.
        seconds: f64,
        /// The plant file of the closed loop.
        plant: PathBuf,
    },
    /// The closed loop has no initial state or no fair infinite path, so every property would
    /// hold vacuously (from [`NusmvError::Vacuous`]).
    #[error("the closed loop with plant {} has no {what}: the plant allows no behaviour, so every property would hold vacuously and nothing is verified; check the plant's INIT, INVAR, TRANS and FAIRNESS constraints{}", plant.display(), warning.as_deref().map(|w| format!(" (NuSMV: {w})")).unwrap_or_default())]
    Vacuous {
        /// The plant file of the closed loop.
        plant: PathBuf,
        /// What is missing: `initial state`, `state` or `fair infinite path`.
        what: &'static str,
        /// NuSMV's own warning about the empty set, if it printed one.
        warning: Option<String>,
    },
    /// NuSMV returned a different number of verdicts than the model has properties.
    #[error("NuSMV reported {got} verdicts for {expected} properties")]
    Count {
        /// The number of properties in the model.
        expected: usize,
        /// The number of verdicts NuSMV printed.
        got: usize,
    },
    /// NuSMV's counterexample of a violated property lacks what a lasso needs: it was cut
    /// short, so it shows no run and proves nothing about one.
    #[error(
        "NuSMV's counterexample of {} is incomplete: {gap}",
        crate::quote::backquote(property)
    )]
    Incomplete {
        /// The property's name (as in [`PropertyReport::name`]).
        property: String,
        /// What is missing.
        gap: TraceGap,
    },
}

/// What a counterexample lacks ([`VerifyError::Incomplete`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TraceGap {
    /// Fewer than two states: no loop can be closed.
    #[error(
        "{0} state(s), where a lasso needs at least its loop state and the state that repeats it"
    )]
    States(usize),
    /// No `-- Loop starts here` before the last state.
    #[error("no loop marker (`-- Loop starts here`) before its last state")]
    NoLoop,
    /// A name the property reads has no value in a state.
    #[error(
        "no value for {} in state {state} (0-based)",
        crate::quote::backquote(name)
    )]
    Value {
        /// The name, as the property reads it.
        name: String,
        /// 0-based index of the state.
        state: usize,
    },
    /// The property cannot be evaluated on the lasso (a value of the wrong type).
    #[error("the property cannot be evaluated on it: {0}")]
    Eval(Box<crate::ltl::EvalError>),
}

/// A NuSMV error mapped back to the user's file.
#[derive(Debug, Clone)]
pub struct LocatedError {
    /// The plant file, the spec file, or the generated closed-loop model.
    pub(crate) file: PathBuf,
    /// 1-based line in `file`.
    pub(crate) line: usize,
    /// NuSMV's message.
    pub(crate) message: String,
    /// The error is in generated code, not in a user file.
    pub(crate) generated: bool,
}

fn describe(errors: &[LocatedError]) -> String {
    let mut s = String::from("NuSMV rejected the closed-loop model:");
    for e in errors {
        // A generated model lives in a work folder that is gone by the time this is read:
        // its name only (the main job keeps a copy in its output folder and says where).
        let file = match (e.generated, e.file.file_name()) {
            (true, Some(name)) => PathBuf::from(name),
            _ => e.file.clone(),
        };
        s.push_str(&format!(
            "\n  {}:{}: {}{}",
            file.display(),
            e.line,
            // NuSMV quotes the token it choked on, however long the plant file made it.
            crate::quote::message(&e.message),
            if e.generated {
                " (in code generated by synth)"
            } else {
                ""
            }
        ));
    }
    s
}

/// The verification problem: what a controller is checked against, owned so that colonies
/// on other threads, candidates of a noisy enumeration and the final check share one value.
///
/// Built once per run with [`Problem::load`], which checks the spec, the plant and their
/// coupling with the controller interface before any synthesis starts.
#[derive(Debug, Clone)]
pub struct Problem {
    /// The surrogate plant (`MODULE plant(...)`).
    pub(crate) plant: Plant,
    /// How plant and controller signals are wired.
    pub(crate) coupling: Coupling,
    /// The spec file the properties come from (errors are located in it).
    pub(crate) spec_file: PathBuf,
    /// The LTL properties, in spec order.
    pub(crate) props: Vec<Property>,
    /// The plant as a model the tool can run itself ([`crate::plant`]), or why the plant is
    /// outside the subset it reads. Without it the properties stay outside the synthesis and
    /// only NuSMV's counterexamples guide it.
    pub model: Result<std::sync::Arc<crate::plant::Model>, String>,
}

/// Why a verification problem could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ProblemError {
    /// The LTL specification file could not be read or parsed.
    #[error(transparent)]
    Spec(#[from] crate::ltl::LtlError),
    /// The plant file could not be read or breaks the coupling convention.
    #[error(transparent)]
    Plant(#[from] crate::smv::plant::PlantError),
    /// Plant, controller interface and properties do not fit together.
    #[error(transparent)]
    Coupling(#[from] crate::smv::composition::CouplingError),
    /// [`Problem::select`] was asked for a property name the spec does not define.
    #[error("{file}: no property named {}", crate::quote::backquote(name), file = .file.display())]
    UnknownProperty {
        /// The spec file.
        file: PathBuf,
        /// The name asked for.
        name: String,
    },
}

impl Problem {
    /// Reads the spec and the plant and checks their coupling with a controller over
    /// `inputs` and `outputs`.
    pub fn load(
        spec_file: &Path,
        plant_file: &Path,
        inputs: &[String],
        outputs: &[String],
    ) -> Result<Problem, ProblemError> {
        Problem::load_by(spec_file, plant_file, inputs, outputs, &[])
    }

    /// [`Problem::load`] where plant and controller name signals differently: `couple` says
    /// which plant signal is which controller input or output.
    pub fn load_by(
        spec_file: &Path,
        plant_file: &Path,
        inputs: &[String],
        outputs: &[String],
        couple: &[crate::smv::composition::Couple],
    ) -> Result<Problem, ProblemError> {
        let props = crate::ltl::parse_spec_file(spec_file)?;
        // The file is read once: the scan for the coupling and the full parse share its text.
        let plant = crate::smv::plant::read_plant(plant_file)?;
        Problem::with_plant(spec_file, props, plant, inputs, outputs, couple)
    }

    /// [`Problem::load_by`] with a plant not read from its file: `text`, a plant learned on
    /// the way, that will be `plant_file` (which messages name).
    pub(crate) fn load_text(
        spec_file: &Path,
        plant_file: &Path,
        text: &str,
        inputs: &[String],
        outputs: &[String],
        couple: &[crate::smv::composition::Couple],
    ) -> Result<Problem, ProblemError> {
        let props = crate::ltl::parse_spec_file(spec_file)?;
        let plant = crate::smv::plant::parse_plant(plant_file, text)?;
        Problem::with_plant(spec_file, props, plant, inputs, outputs, couple)
    }

    /// The problem of `props`, read from `spec_file`, with `plant`.
    fn with_plant(
        spec_file: &Path,
        props: Vec<Property>,
        plant: crate::smv::plant::Plant,
        inputs: &[String],
        outputs: &[String],
        couple: &[crate::smv::composition::Couple],
    ) -> Result<Problem, ProblemError> {
        let coupling = crate::smv::composition::check_coupling_by(
            inputs, outputs, &plant, spec_file, &props, couple,
        )?;
        let model = crate::plant::parse::parse_str(&plant.text, &plant.file)
            .map(std::sync::Arc::new)
            .map_err(|e| e.to_string());
        Ok(Problem {
            plant,
            coupling,
            spec_file: spec_file.to_path_buf(),
            props,
            model,
        })
    }

    /// Keeps only the properties named (by label or `p<k>`); `all` keeps every one.
    pub fn select(mut self, names: &[String]) -> Result<Problem, ProblemError> {
        if names.iter().any(|n| n == "all") {
            return Ok(self);
        }
        let named: Vec<(String, Property)> = self
            .props
            .iter()
            .enumerate()
            .map(|(k, p)| (property_name(k, p), p.clone()))
            .collect();
        self.props = names
            .iter()
            .map(|n| {
                named
                    .iter()
                    .find(|(m, _)| m == n)
                    .map(|(_, p)| p.clone())
                    .ok_or_else(|| ProblemError::UnknownProperty {
                        file: self.spec_file.clone(),
                        name: n.clone(),
                    })
            })
            .collect::<Result<_, _>>()?;
        Ok(self)
    }

    /// The properties no controller can affect, each with the reason: every name it reads is
    /// a signal of the plant that no controller output influences (in the plant model the
    /// tool reads; none are found in a plant outside it), so its verdict is the plant's alone.
    pub(crate) fn unaffected(&self) -> Vec<(String, String)> {
        let Ok(model) = self.model.as_ref() else {
            return Vec::new();
        };
        let free = model.uncontrolled();
        let mut found = Vec::new();
        for (k, p) in self.props.iter().enumerate() {
            let names = p.formula.names();
            if !names.iter().all(|n| free.contains(&n.as_str())) {
                continue;
            }
            let why = match names.is_empty() {
                true => "it reads no signal".to_string(),
                false => format!(
                    "it reads only {}, which no controller output influences",
                    (names.iter().map(|n| crate::quote::quote(n).to_string()))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            };
            found.push((property_name(k, p), why));
        }
        found
    }

    /// The properties' names, in spec order.
    pub(crate) fn property_names(&self) -> Vec<String> {
        self.props
            .iter()
            .enumerate()
            .map(|(k, p)| property_name(k, p))
            .collect()
    }
}

/// The one verifier: a NuSMV dialogue and a private folder for the closed-loop model, over a
/// shared [`Problem`].
pub struct Verifier {
    problem: std::sync::Arc<Problem>,
    dialogue: Dialogue,
    workdir: crate::files::WorkDir,
}

impl Verifier {
    /// Opens a dialogue of `nusmv` for `problem`.
    pub(crate) fn new(
        problem: std::sync::Arc<Problem>,
        nusmv: &crate::nusmv::Nusmv,
    ) -> Result<Verifier, VerifyError> {
        let workdir = crate::files::WorkDir::new()?;
        // The models written there are the user's plant and properties: for their eyes only.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(workdir.path(), std::fs::Permissions::from_mode(0o700))?;
        }
        Ok(Verifier {
            problem,
            dialogue: nusmv.dialogue(),
            workdir,
        })
    }

    /// The problem this verifier checks against.
    pub(crate) fn problem(&self) -> &Problem {
        &self.problem
    }

    /// The folder the models are written into (0700).
    pub(crate) fn workdir(&self) -> &Path {
        self.workdir.path()
    }

    /// Verifies `ecc` in closed loop (see [`verify`]).
    pub(crate) fn verify(&mut self, ecc: &Ecc) -> Result<VerificationResult, VerifyError> {
        self.verify_with(ecc, CheckMode::AllCounterexamples)
    }

    /// Verifies `ecc`, asking NuSMV for the traces `mode` says (see [`verify`]).
    pub(crate) fn verify_with(
        &mut self,
        ecc: &Ecc,
        mode: CheckMode,
    ) -> Result<VerificationResult, VerifyError> {
        verify(
            ecc,
            &self.problem,
            &mut self.dialogue,
            self.workdir.path(),
            mode,
        )
    }

    /// Verifies any controller given as SMV text defining `MODULE ECC(REQ, inputs...)` with a
    /// `CNF` and every output (a modular composite, [`crate::export::modular`]) over `inputs`.
    pub fn verify_controller(
        &mut self,
        controller: String,
        inputs: &[String],
        mode: CheckMode,
    ) -> Result<VerificationResult, VerifyError> {
        let p = &self.problem;
        let model = compose_controller(controller, inputs, &p.plant, &p.coupling, &p.props);
        check_model(model, p, &mut self.dialogue, self.workdir.path(), mode)
    }

    /// The closed-loop model of the last check, if one was written (kept for the user when
    /// NuSMV rejects it).
    pub(crate) fn last_model(&self) -> Option<PathBuf> {
        let p = self.workdir.path().join("closed_loop.smv");
        p.is_file().then_some(p)
    }
}

/// The result of one verification run.
pub struct VerificationResult {
    /// The verdict on every property.
    pub report: Report,
    /// Counterexamples of the violated properties that have a trace, in spec order.
    pub counterexamples: Vec<Counterexample>,
    /// The composed model (kept for the user or for error reports).
    pub(crate) model: ComposedModel,
}

/// Verifies `ecc` in closed loop; `workdir` receives the model file.
pub(crate) fn verify(
    ecc: &Ecc,
    problem: &Problem,
    dialogue: &mut Dialogue,
    workdir: &Path,
    mode: CheckMode,
) -> Result<VerificationResult, VerifyError> {
    let model = compose(ecc, &problem.plant, &problem.coupling, &problem.props)?;
    check_model(model, problem, dialogue, workdir, mode)
}

/// Writes the composed closed loop into `workdir` and has NuSMV check it.
fn check_model(
    model: ComposedModel,
    problem: &Problem,
    dialogue: &mut Dialogue,
    workdir: &Path,
    mode: CheckMode,
) -> Result<VerificationResult, VerifyError> {
    let path = workdir.join("closed_loop.smv");
    std::fs::write(&path, &model.text)?;
    let queries: Vec<Query> = (model.smv_properties())
        .map(|(name, formula)| Query {
            name: name.to_string(),
            formula: formula.to_string(),
        })
        .collect();
    let t = Instant::now();
    let results = match dialogue.check(&path, &queries, mode) {
        Ok(r) => r,
        Err(NusmvError::Model(errors)) => {
            return Err(VerifyError::Model(locate_errors(
                &errors, &model, problem, &path,
            )))
        }
        Err(NusmvError::Vacuous { what, warning, .. }) => {
            return Err(VerifyError::Vacuous {
                plant: problem.plant.file.clone(),
                what,
                warning,
            })
        }
        Err(NusmvError::Timeout { seconds, .. }) => {
            return Err(VerifyError::Timeout {
                seconds,
                plant: problem.plant.file.clone(),
            })
        }
        Err(e) => return Err(e.into()),
    };
    let nusmv_seconds = t.elapsed().as_secs_f64();
    if results.len() != problem.props.len() {
        return Err(VerifyError::Count {
            expected: problem.props.len(),
            got: results.len(),
        });
    }
    let mut properties = Vec::new();
    let mut counterexamples = Vec::new();
    for (k, (p, r)) in problem.props.iter().zip(&results).enumerate() {
        let name = property_name(k, p);
        let (holds, trace) = match &r.verdict {
            Verdict::Holds => (true, None),
            Verdict::Violated(t) => (false, t.as_ref()),
        };
        let cx = trace.map(|t| counterexample_of(&name, p, t)).transpose()?;
        properties.push(PropertyReport {
            name,
            text: p.text.clone(),
            line: p.line,
            holds,
            verdict_line: r.verdict_line.clone(),
            counterexample_length: cx.as_ref().map(|c| c.states.len()),
        });
        counterexamples.extend(cx);
    }
    Ok(VerificationResult {
        report: Report {
            properties,
            nusmv_seconds,
            nusmv_warnings: dialogue.warnings().to_vec(),
        },
        counterexamples,
        model,
    })
}

fn locate_errors(
    errors: &[ModelError],
    model: &ComposedModel,
    problem: &Problem,
    path: &Path,
) -> Vec<LocatedError> {
    errors
        .iter()
        .map(|e| match model.source(e.line) {
            Source::Plant(l) => LocatedError {
                file: problem.plant.file.clone(),
                line: l,
                message: e.message.clone(),
                generated: false,
            },
            Source::Spec(l) => LocatedError {
                file: problem.spec_file.to_path_buf(),
                line: l,
                message: e.message.clone(),
                generated: false,
            },
            // The first thing after the plant is generated (`MODULE main`): a syntax error
            // there is the plant ending inside a construct left open.
            // NuSMV also counts a preprocessor directive's line break before it complains.
            Source::Generated if model.follows_plant(e.line) => LocatedError {
                file: problem.plant.file.clone(),
                line: problem.plant.text.lines().count().max(1),
                message: if e.message.contains("syntax error") {
                    format!(
                        "{} after the end of the plant: something is left open at its end (a `case` without `esac`, a missing `;`)",
                        e.message
                    )
                } else {
                    e.message.clone()
                },
                generated: false,
            },
            Source::Generated => LocatedError {
                file: path.to_path_buf(),
                line: e.line,
                message: e.message.clone(),
                generated: true,
            },
        })
        .collect()
}

/// Picks the loop point: the first NuSMV marker whose lasso really violates the property.
/// A trace cut short (no loop, a value of the property missing) is an error, not a run.
fn counterexample_of(name: &str, p: &Property, t: &Trace) -> Result<Counterexample, VerifyError> {
    let incomplete = |gap| VerifyError::Incomplete {
        property: name.to_string(),
        gap,
    };
    if t.states.len() < 2 {
        return Err(incomplete(TraceGap::States(t.states.len())));
    }
    // NuSMV's last printed state repeats the loop start: drop it.
    let n = t.states.len() - 1;
    // The inputs NuSMV prints before state `i + 1` (IVARs, and defines over them) are those of
    // the step from state `i`: what the controller reads at step `i`.
    let states: Vec<BTreeMap<String, String>> = t.states[..n.min(t.states.len())]
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let mut s = s.clone();
            if let Some(input) = t.inputs.get(i + 1) {
                for (k, v) in input {
                    s.entry(k.clone()).or_insert_with(|| v.clone());
                }
            }
            s
        })
        .collect();
    let candidates: Vec<usize> = t.loop_starts.iter().copied().filter(|&l| l < n).collect();
    let Some(&last_candidate) = candidates.last() else {
        return Err(incomplete(TraceGap::NoLoop));
    };
    for name in p.formula.names() {
        if let Some(state) = states.iter().position(|s| !s.contains_key(&name)) {
            return Err(incomplete(TraceGap::Value { name, state }));
        }
    }
    let mut violating = None;
    for &l in &candidates {
        match p.formula.holds_on_lasso(&states, l) {
            Ok(false) => {
                violating = Some(l);
                break;
            }
            Ok(true) => {}
            Err(e) => return Err(incomplete(TraceGap::Eval(Box::new(e)))),
        }
    }
    let (loop_start, confirmed) = match violating {
        Some(l) => (l, true),
        None => (last_candidate, false),
    };
    let key = format!("{CONTROLLER_INSTANCE}._state");
    let controller_states = states.iter().map(|s| s.get(&key).cloned()).collect();
    let violation_at = match &p.formula {
        Ltl::G(inner) if is_propositional(inner) => states
            .iter()
            .position(|s| inner.holds_on_lasso(std::slice::from_ref(s), 0) == Ok(false)),
        _ => None,
    };
    Ok(Counterexample {
        property: name.to_string(),
        states,
        loop_start,
        violation_at,
        confirmed,
        controller_states,
    })
}

/// No temporal operator: the formula's value depends on one state only.
fn is_propositional(l: &Ltl) -> bool {
    match l {
        Ltl::True | Ltl::False | Ltl::Atom(_) | Ltl::Int(_) => true,
        Ltl::Not(a) => is_propositional(a),
        Ltl::And(a, b)
        | Ltl::Or(a, b)
        | Ltl::Xor(a, b)
        | Ltl::Xnor(a, b)
        | Ltl::Implies(a, b)
        | Ltl::Iff(a, b)
        | Ltl::Cmp(_, a, b) => is_propositional(a) && is_propositional(b),
        _ => false,
    }
}

fn value(state: &BTreeMap<String, String>, name: &str, instance: &str) -> Option<bool> {
    let v = state
        .get(name)
        .or_else(|| state.get(&format!("{instance}.{name}")))?;
    crate::smv::parse_bool_literal(v)
}

impl Counterexample {
    /// The counterexample seen from the controller: inputs and outputs before/after every
    /// step. For a safety violation, the finite prefix up to the violating state; otherwise
    /// the lasso. `None` if a controller input or output is missing from the trace or not
    /// Boolean, or if the violation is in the initial state (no controller can avoid it).
    pub(crate) fn negative_scenario(
        &self,
        inputs: &[String],
        outputs: &[String],
    ) -> Option<NegativeScenario> {
        let read = |s: &BTreeMap<String, String>, names: &[String], inst: &str| {
            names
                .iter()
                .map(|n| value(s, n, inst))
                .collect::<Option<Vec<bool>>>()
        };
        let (n, loop_start) = match self.violation_at {
            Some(0) => return None,
            Some(k) => (k, None),
            None => (self.states.len(), Some(self.loop_start)),
        };
        let mut steps = Vec::with_capacity(n);
        for i in 0..n {
            let next = if i + 1 < self.states.len() {
                i + 1
            } else {
                self.loop_start
            };
            steps.push(NegativeStep {
                inputs: read(&self.states[i], inputs, PLANT_INSTANCE)?,
                before: read(&self.states[i], outputs, CONTROLLER_INSTANCE)?,
                after: read(&self.states[next], outputs, CONTROLLER_INSTANCE)?,
            });
        }
        Some(NegativeScenario {
            steps,
            loop_start,
            label: format!("counterexample of {}", self.property),
        })
    }
}

#[cfg(test)]
mod workdir_tests {
    use super::*;

    /// The closed-loop models hold the user's plant and properties: the folder NuSMV reads
    /// them from is the user's alone.
    #[cfg(unix)]
    #[test]
    fn the_work_folder_is_private() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let spec = dir.path().join("s.ltl");
        std::fs::write(&spec, "G !lamp\n").unwrap();
        let plant =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/closed_loop/lamp_plant.smv");
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let problem = Problem::load(
            &spec,
            &plant,
            &names(&["button", "timeout"]),
            &names(&["lamp"]),
        )
        .unwrap();
        // No NuSMV is started before the first check.
        let nusmv = crate::nusmv::Nusmv::new(PathBuf::from("/nonexistent/NuSMV"));
        let v = Verifier::new(std::sync::Arc::new(problem), &nusmv).unwrap();
        let mode = std::fs::metadata(v.workdir()).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o700);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nusmv::{nusmv_for_tests, parse_output, PropertyResult};
    use std::sync::Arc;

    fn repo(path: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
    }

    fn property(text: &str) -> Property {
        crate::ltl::parse_spec(Path::new("t.ltl"), text)
            .unwrap()
            .remove(0)
    }

    /// Lines `from..=to` (1-based) of a real NuSMV output, without those `drop` names.
    fn lines_of(fixture: &str, from: usize, to: usize, drop: &str) -> String {
        let text = std::fs::read_to_string(repo("tests/data/nusmv").join(fixture)).unwrap();
        (text.lines().skip(from - 1).take(to + 1 - from))
            .filter(|l| drop.is_empty() || !l.starts_with(drop))
            .map(|l| format!("{l}\n"))
            .collect()
    }

    /// The counterexample of `G (ctrl = out -> F pos = extended)` in cylinder.batch.stdout
    /// (its lines 52 to 84), taken whole, cut short, or with a variable's lines dropped.
    fn cylinder_trace(to: usize, drop: &str) -> Trace {
        let results = parse_output(&lines_of("cylinder.batch.stdout", 52, to, drop)).unwrap();
        match &results[..] {
            [PropertyResult {
                verdict: Verdict::Violated(Some(t)),
                ..
            }] => t.clone(),
            other => panic!("one violated property with a trace expected: {other:?}"),
        }
    }

    fn gap(to: usize, drop: &str) -> Option<TraceGap> {
        let p = property("G (ctrl = out -> F pos = extended)");
        match counterexample_of("out_reaches_end", &p, &cylinder_trace(to, drop)) {
            Ok(_) => None,
            Err(VerifyError::Incomplete { gap, property }) => {
                assert_eq!(property, "out_reaches_end");
                Some(gap)
            }
            Err(e) => panic!("{e}"),
        }
    }

    #[test]
    fn a_whole_counterexample_is_a_confirmed_lasso() {
        let p = property("G (ctrl = out -> F pos = extended)");
        let cx = counterexample_of("out_reaches_end", &p, &cylinder_trace(84, "")).unwrap();
        assert!(cx.confirmed);
        assert_eq!(cx.states.len(), 5);
        assert_eq!(cx.loop_start, 2);
    }

    /// NuSMV's output cut short (a killed process, a closed pipe) gives a trace without its
    /// loop, or without the values of a variable: an error saying what is missing, not a run
    /// whose last state repeats forever, nor a run with unknown values.
    #[test]
    fn a_counterexample_cut_short_is_an_error_naming_what_is_missing() {
        // Cut after state 2.2: no `-- Loop starts here` yet.
        assert_eq!(gap(67, ""), Some(TraceGap::NoLoop));
        // Cut after state 2.1: one state only.
        assert_eq!(gap(61, ""), Some(TraceGap::States(1)));
        // Every `pos` line gone: the property reads it.
        assert_eq!(
            gap(84, "  pos = "),
            Some(TraceGap::Value {
                name: "pos".into(),
                state: 0
            })
        );
        // A name the property does not read may be missing.
        assert_eq!(gap(84, "  alarm = "), None);
        let message = VerifyError::Incomplete {
            property: "out_reaches_end".into(),
            gap: TraceGap::NoLoop,
        }
        .to_string();
        assert_eq!(
            message,
            "NuSMV's counterexample of `out_reaches_end` is incomplete: no loop marker (`-- Loop starts here`) before its last state"
        );
    }

    /// Every LTL operator NuSMV 2.5.4 accepts (it has no bounded ones) goes from the spec file
    /// to NuSMV and back: each property's verdict is NuSMV's on that very property (NuSMV
    /// reprints `a V b` as `!(!a U !b)`, `Z a` as `!Y !a`, ...), and each counterexample is a
    /// lasso on which the property evaluates to false in process.
    #[test]
    fn every_operator_gets_its_own_verdict_and_a_confirmed_counterexample() {
        let Some(nusmv) = nusmv_for_tests() else {
            return;
        };
        let dir = repo("tests/data/closed_loop");
        let ecc = crate::pipeline::recordings::read_ecc(&dir.join("lamp_two_state.json")).unwrap();
        let problem = Problem::load(
            &dir.join("lamp_operators.ltl"),
            &dir.join("lamp_plant.smv"),
            &ecc.inputs,
            &ecc.outputs,
        )
        .unwrap();
        let texts: Vec<String> = problem.props.iter().map(|p| p.text.clone()).collect();
        for op in [
            "X", "F", "G", "U", "V", "Y", "Z", "H", "O", "S", "T", "xor", "xnor", "<->", "->", "!",
            "&", "|",
        ] {
            assert!(
                texts
                    .iter()
                    .any(|t| t.split([' ', '(', ')']).any(|w| w == op)
                        || (op == "!" && t.contains('!'))),
                "no property uses {op}"
            );
        }
        let mut verifier = Verifier::new(Arc::new(problem), &nusmv).unwrap();
        let v = verifier.verify(&ecc).unwrap();
        assert_eq!(v.report.properties.len(), texts.len());
        for p in &v.report.properties {
            assert_eq!(
                p.holds,
                p.name.ends_with("_holds"),
                "{}: {} ({})",
                p.name,
                p.text,
                p.verdict_line
            );
        }
        let failing = v.report.failing();
        let shown: Vec<&str> = v
            .counterexamples
            .iter()
            .map(|c| c.property.as_str())
            .collect();
        assert_eq!(shown, failing);
        for cx in &v.counterexamples {
            assert!(
                cx.confirmed,
                "{}: no marker gives a violating lasso",
                cx.property
            );
        }
    }
}
