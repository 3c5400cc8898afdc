//! Closed-loop verification of one ECC: compose, run NuSMV, report, and turn a counterexample
//! into a negative scenario.
//!
//! In: an [`Ecc`], a [`Plant`], checked [`Coupling`], properties, and a NuSMV [`Session`].
//! Out: a [`Report`] with one [`PropertyReport`] per property (NuSMV's verdict line kept), and
//! for every violated property with a trace, a [`Counterexample`]: the lasso as NuSMV printed
//! it, with a loop point that really violates the property, and as a [`NegativeScenario`].
//!
//! Every "holds" in a report comes from NuSMV; nothing here decides a verdict itself. The
//! lasso evaluation only picks *which* of NuSMV's `-- Loop starts here` markers to use: NuSMV
//! marks every earlier state equal to the last one, and some of those loop points satisfy the
//! property (its tableau variables are not printed).

use crate::ecc::Ecc;
use crate::export::waveform::Waveform;
use crate::ltl::{property_name, Ltl, Property};
use crate::nusmv::{CheckMode, ModelError, NusmvError, PropertyResult, Session, Trace, Verdict};
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
    /// What NuSMV printed on stderr that no verdict accounts for ([`Session::warnings`]).
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
    /// A verdict's formula (carried, as NuSMV reprinted it) equals no remaining property's.
    #[error("NuSMV reported a verdict on `{0}`, which matches none of the properties")]
    Unmatched(String),
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
        let props = crate::ltl::parse_spec_file(spec_file)?;
        // The file is read once: the scan for the coupling and the full parse share its text.
        let plant = crate::smv::plant::read_plant(plant_file)?;
        let coupling =
            crate::smv::composition::check_coupling(inputs, outputs, &plant, spec_file, &props)?;
        let model = crate::plant::parse::parse_str(&plant.text, plant_file)
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

    /// The properties' names, in spec order.
    pub(crate) fn property_names(&self) -> Vec<String> {
        self.props
            .iter()
            .enumerate()
            .map(|(k, p)| property_name(k, p))
            .collect()
    }
}

/// The one verifier: a NuSMV session and a private folder for the closed-loop model, over a
/// shared [`Problem`].
pub struct Verifier {
    problem: std::sync::Arc<Problem>,
    session: Session,
    workdir: tempfile::TempDir,
}

impl Verifier {
    /// Opens a session of `nusmv` for `problem`.
    pub(crate) fn new(
        problem: std::sync::Arc<Problem>,
        nusmv: &crate::nusmv::Nusmv,
    ) -> Result<Verifier, VerifyError> {
        let workdir = tempfile::tempdir()?;
        crate::files::remove_on_signal(workdir.path());
        // The models written there are the user's plant and properties: for their eyes only.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(workdir.path(), std::fs::Permissions::from_mode(0o700))?;
        }
        Ok(Verifier {
            problem,
            session: nusmv.session(),
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
            &mut self.session,
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
        check_model(model, p, &mut self.session, self.workdir.path(), mode)
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

impl Drop for Verifier {
    fn drop(&mut self) {
        // The work folder goes with its TempDir right after this.
        crate::files::keep_on_signal(self.workdir.path());
    }
}

/// Verifies `ecc` in closed loop; `workdir` receives the model file.
pub(crate) fn verify(
    ecc: &Ecc,
    problem: &Problem,
    session: &mut Session,
    workdir: &Path,
    mode: CheckMode,
) -> Result<VerificationResult, VerifyError> {
    let model = compose(ecc, &problem.plant, &problem.coupling, &problem.props)?;
    check_model(model, problem, session, workdir, mode)
}

/// Writes the composed closed loop into `workdir` and has NuSMV check it.
fn check_model(
    model: ComposedModel,
    problem: &Problem,
    session: &mut Session,
    workdir: &Path,
    mode: CheckMode,
) -> Result<VerificationResult, VerifyError> {
    let path = workdir.join("closed_loop.smv");
    std::fs::write(&path, &model.text)?;
    let t = Instant::now();
    let results = match session.check(&path, mode) {
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
    let results = match_results(&problem.props, results)?;
    let mut properties = Vec::new();
    let mut counterexamples = Vec::new();
    for (k, (p, r)) in problem.props.iter().zip(&results).enumerate() {
        let name = property_name(k, p);
        let (holds, trace) = match &r.verdict {
            Verdict::Holds => (true, None),
            Verdict::Violated(t) => (false, t.as_ref()),
        };
        let cx = trace.map(|t| counterexample_of(&name, p, t));
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
            nusmv_warnings: session.warnings().to_vec(),
        },
        counterexamples,
        model,
    })
}

/// The formula text with whitespace and parentheses removed: NuSMV reprints formulas with its
/// own spacing and parentheses, so this is what stays comparable.
fn normalized(text: &str) -> String {
    text.chars()
        .filter(|c| !c.is_whitespace() && *c != '(' && *c != ')')
        .collect()
}

/// Puts NuSMV's results in spec order. NuSMV does not always report properties in the order
/// of the `LTLSPEC`s, so each result is matched to the property whose formula it reprints
/// (among equal texts, in order).
fn match_results(
    props: &[Property],
    results: Vec<PropertyResult>,
) -> Result<Vec<PropertyResult>, VerifyError> {
    let keys: Vec<String> = props
        .iter()
        .map(|p| normalized(&p.formula.to_smv(&|n: &str| n.to_string())))
        .collect();
    let mut slots: Vec<Option<PropertyResult>> = vec![None; props.len()];
    for r in results {
        let key = normalized(&r.formula);
        let Some(k) = (0..props.len()).find(|&k| slots[k].is_none() && keys[k] == key) else {
            return Err(VerifyError::Unmatched(r.formula));
        };
        slots[k] = Some(r);
    }
    Ok(slots
        .into_iter()
        .map(|s| s.expect("counts are equal"))
        .collect())
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
fn counterexample_of(name: &str, p: &Property, t: &Trace) -> Counterexample {
    // NuSMV's last printed state repeats the loop start: drop it.
    let n = t.states.len().saturating_sub(1).max(1);
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
    let violating = candidates
        .iter()
        .copied()
        .find(|&l| p.formula.holds_on_lasso(&states, l) == Ok(false));
    let loop_start = violating.unwrap_or_else(|| candidates.last().copied().unwrap_or(n - 1));
    let key = format!("{CONTROLLER_INSTANCE}._state");
    let controller_states = states.iter().map(|s| s.get(&key).cloned()).collect();
    let violation_at = match &p.formula {
        Ltl::G(inner) if is_propositional(inner) => states
            .iter()
            .position(|s| inner.holds_on_lasso(std::slice::from_ref(s), 0) == Ok(false)),
        _ => None,
    };
    Counterexample {
        property: name.to_string(),
        states,
        loop_start,
        violation_at,
        controller_states,
    }
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
