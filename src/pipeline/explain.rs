//! Why no machine can exist, told from the recordings alone, before any synthesis: the
//! recorded runs that already violate a property.
//!
//! In: a [`ScenarioSet`] and the properties of a specification file. Out: an [`Explanation`]:
//! for every property the recordings violate, a [`RecordedViolation`] with the first place
//! (file, line, step) and how much of the recordings violates it; and the properties the
//! recordings cannot decide because they read names that are not recorded (the plant's own
//! variables) or compare integers; and the controller inputs the recordings show with one
//! value only, which properties read ([`Unrecorded`]).
//!
//! # A recorded scenario as a closed-loop run
//! In the closed loop ([`crate::smv::composition`]) the controller reads the plant's values of
//! step `t` and its outputs change at `t + 1`; a counterexample's state `i` becomes the
//! negative step `i` with the inputs of state `i` and the outputs *before* it
//! ([`crate::verify::Counterexample::negative_scenario`]). A recorded scenario of `n` steps is
//! read the same way, as the first `n + 1` states of a closed-loop run:
//! - state `i < n`: the inputs of step `i + 1` (1-based, as messages count steps) with the
//!   outputs after step `i` (the initial outputs for `i = 0`; a passive step keeps them);
//! - state `n`: the outputs after the last step, the inputs unknown (nobody recorded them).
//!
//! So `G ((c1Extend | c2Extend) -> vcHome)` is false in a state whose commanded outputs (from
//! the previous step) extend a cylinder while the sensor read in this step says the suction
//! unit is not up: exactly what NuSMV would see in the closed loop.
//!
//! Every property whose names are all controller inputs or outputs is evaluated in three
//! values on these states ([`Ltl::truth_on_prefix`]); only a violation that no continuation of
//! the run can repair is reported. A controller that reproduces the recordings, fed the
//! recorded inputs, runs through exactly these states, so (in a plant that can produce the
//! recorded inputs, as the real one did) no such controller satisfies the property.

use crate::ltl::{property_name, Ltl, NotEvaluable, Property, Truth};
use crate::scenario::{Origin, Scenario, ScenarioSet};
use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// A closed-loop state of a recorded scenario (see the module header).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Place {
    /// Where the scenario starts in its file.
    pub(crate) origin: Origin,
    /// 0-based state: `i < steps` is step `i + 1`'s inputs with the outputs before them,
    /// `steps` the outputs after the last step.
    pub(crate) state: usize,
    /// Steps of the scenario.
    pub(crate) steps: usize,
}

/// `FILE:LINE step N (...)`: the place as a reader finds it in the file.
impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (i, n) = (self.state, self.steps);
        if i == n {
            return write!(
                f,
                "{} after step {n}, the last (the outputs it leaves)",
                self.origin
            );
        }
        let before = match i {
            0 => "the initial outputs".to_string(),
            _ => format!("the outputs after step {i}"),
        };
        write!(
            f,
            "{} step {} (its inputs with {before})",
            self.origin,
            i + 1
        )
    }
}

/// How much of the recordings violates a property.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Extent {
    /// For `G p`: the states where `p` is definitely false, of all recorded states.
    States {
        /// Recorded states where `p` is definitely false.
        violating: usize,
        /// Recorded states in all.
        of: usize,
    },
    /// For any other formula: the scenarios whose run violates it, of all scenarios.
    Scenarios {
        /// Scenarios whose run violates the formula whatever follows.
        violating: usize,
        /// Scenarios in all.
        of: usize,
    },
}

impl fmt::Display for Extent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Extent::States { violating, of } => write!(
                f,
                "{violating} of the {of} states the recordings show violate it"
            ),
            Extent::Scenarios { violating, of } => {
                write!(f, "{violating} of the {of} scenarios violate it")
            }
        }
    }
}

/// A property the recordings violate whatever would have followed them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct RecordedViolation {
    /// The property's name (label or `p<k>`).
    pub(crate) property: String,
    /// Its line in the spec file.
    pub(crate) line: usize,
    /// The first violating state, in the order of the scenarios and their steps.
    pub(crate) first: Place,
    /// How much of the recordings violates the property.
    pub(crate) extent: Extent,
}

/// A property the recordings cannot decide.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Undecidable {
    /// The property's name (label or `p<k>`).
    pub(crate) property: String,
    /// Why the recordings cannot evaluate it.
    pub(crate) reason: NotEvaluable,
}

/// A controller input that keeps one value through every recorded step, read by properties.
/// What the machine does once it takes the other value is in no recording: only the
/// properties, through the closed loop, shape it, and the loop can take long to find it (the
/// Pick-and-Place loop from a recording without pieces on tracks 2 and 3 had no verified
/// machine after minutes; with them, seconds).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Unrecorded {
    /// The input's name.
    pub(crate) input: String,
    /// The value no recorded step shows.
    pub(crate) never: bool,
    /// The properties that read the input, in spec order.
    pub(crate) properties: Vec<String>,
}

impl fmt::Display for Unrecorded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let value = if self.never { "TRUE" } else { "FALSE" };
        write!(
            f,
            "{} = {value} (read by {})",
            self.input,
            self.properties.join(", ")
        )
    }
}

/// What the recordings say about the properties.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Explanation {
    /// The properties violated, in spec order.
    pub(crate) violations: Vec<RecordedViolation>,
    /// Properties evaluated on the recordings.
    pub(crate) checked: usize,
    /// Properties that read names not recorded or compare integers.
    pub(crate) undecidable: Vec<Undecidable>,
    /// Inputs the properties read that the recordings show with one value only, in input
    /// order.
    pub(crate) unrecorded: Vec<Unrecorded>,
}

impl Explanation {
    /// The line after the recordings were checked against `properties` properties (none
    /// violated), naming the ones that read names not recorded.
    pub(crate) fn checked_line(&self, properties: usize) -> String {
        let mut line = format!(
            "checked {} of {properties} properties on the recordings, none violated",
            self.checked
        );
        if !self.undecidable.is_empty() {
            let names: Vec<&str> = self
                .undecidable
                .iter()
                .map(|u| u.property.as_str())
                .collect();
            line.push_str(&format!(" ({} read names not recorded)", names.join(", ")));
        }
        line
    }

    /// What the recordings never show of the inputs the properties read, and why it matters;
    /// `None` when they show every value.
    pub(crate) fn unrecorded_line(&self) -> Option<String> {
        if self.unrecorded.is_empty() {
            return None;
        }
        let all: Vec<String> = self.unrecorded.iter().map(|u| u.to_string()).collect();
        Some(format!(
            "the recordings never show {}: the machine's answer there comes from the properties \
             alone, and the loop can take long to find it; record runs that show it",
            all.join(", ")
        ))
    }
}

/// The recordings violate properties: no machine that reproduces them satisfies those.
#[derive(Debug, Clone, thiserror::Error)]
pub struct RecordingsViolate {
    /// The specification file the properties come from, for the message.
    pub spec_file: PathBuf,
    /// Every property violated, in spec order.
    pub(crate) violations: Vec<RecordedViolation>,
    /// The first recorded step the plant cannot take after the steps before it as recorded
    /// (its place), if any: then the closed loop never runs through the recorded states, and
    /// nothing follows for controllers; `None` when the plant produces every recorded run.
    pub(crate) unreplayed: Option<String>,
}

impl fmt::Display for RecordingsViolate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let one = |v: &RecordedViolation| {
            format!(
                "{} ({}:{}): first at {}; {}",
                crate::quote::cut(&v.property),
                self.spec_file.display(),
                v.line,
                v.first,
                v.extent
            )
        };
        let consequence = |them: &str| {
            match &self.unreplayed {
            None => format!("no controller that reproduces them can satisfy {them}"),
            Some(place) => format!(
                "the plant cannot produce the recorded runs as recorded (first at {place}), so this says nothing of controllers in closed loop with it, but the recordings themselves break {them}: check the property, and the plant's timing against the recordings"
            ),
        }
        };
        match &self.violations[..] {
            [v] => write!(
                f,
                "the recordings violate property {}; {}",
                one(v),
                consequence("it")
            ),
            all => {
                write!(
                    f,
                    "the recordings violate {} properties; {}:",
                    all.len(),
                    consequence("them")
                )?;
                for v in all {
                    write!(f, "\n  {}", one(v))?;
                }
                Ok(())
            }
        }
    }
}

/// Evaluates every property on every recorded scenario (see the module header).
pub fn explain(set: &ScenarioSet, props: &[Property]) -> Explanation {
    let runs: Vec<Run> = set.scenarios.iter().map(|s| Run::new(set, s)).collect();
    let states: usize = runs.iter().map(|r| r.len).sum();
    let mut out = Explanation {
        violations: Vec::new(),
        checked: 0,
        undecidable: Vec::new(),
        unrecorded: unrecorded(set, props),
    };
    for (k, p) in props.iter().enumerate() {
        let property = property_name(k, p);
        match violation(&p.formula, set, &runs, states) {
            Ok(v) => {
                out.checked += 1;
                out.violations
                    .extend(v.map(|(first, extent)| RecordedViolation {
                        property,
                        line: p.line,
                        first,
                        extent,
                    }));
            }
            Err(reason) => out.undecidable.push(Undecidable { property, reason }),
        }
    }
    out
}

/// The inputs every recorded step shows with the same value, with the properties that read
/// them; none when nothing is recorded.
fn unrecorded(set: &ScenarioSet, props: &[Property]) -> Vec<Unrecorded> {
    let mut seen = vec![[false; 2]; set.inputs.len()];
    for step in set.scenarios.iter().flat_map(|s| &s.steps) {
        for (x, &v) in step.inputs.iter().enumerate() {
            seen[x][usize::from(v)] = true;
        }
    }
    set.inputs
        .iter()
        .zip(&seen)
        .filter_map(|(input, seen)| {
            let never = match seen {
                [true, false] => true,
                [false, true] => false,
                _ => return None,
            };
            let properties: Vec<String> = props
                .iter()
                .enumerate()
                .filter(|(_, p)| p.formula.names().iter().any(|n| n == input))
                .map(|(k, p)| property_name(k, p))
                .collect();
            (!properties.is_empty()).then(|| Unrecorded {
                input: input.clone(),
                never,
                properties,
            })
        })
        .collect()
}

/// Refuses recordings that violate a property (see [`explain`]); otherwise what was checked.
pub fn refuse_violations(
    set: &ScenarioSet,
    props: &[Property],
    spec_file: &Path,
) -> Result<Explanation, RecordingsViolate> {
    let e = explain(set, props);
    if e.violations.is_empty() {
        Ok(e)
    } else {
        Err(RecordingsViolate {
            spec_file: spec_file.to_path_buf(),
            violations: e.violations,
            unreplayed: None,
        })
    }
}

/// The recorded states of one scenario as columns, one per interface name.
struct Run<'a> {
    scenario: &'a Scenario,
    len: usize,
    columns: HashMap<&'a str, Vec<Option<bool>>>,
}

impl<'a> Run<'a> {
    fn new(set: &'a ScenarioSet, scenario: &'a Scenario) -> Run<'a> {
        let n = scenario.steps.len();
        let mut columns = HashMap::new();
        for (x, name) in set.inputs.iter().enumerate() {
            let col = (0..=n)
                .map(|i| scenario.steps.get(i).map(|s| s.inputs[x]))
                .collect();
            columns.insert(name.as_str(), col);
        }
        let mut outputs = set.initial_outputs.clone();
        let mut after = vec![outputs.clone()];
        for s in &scenario.steps {
            if let Some(o) = &s.outputs {
                outputs.clone_from(o);
            }
            after.push(outputs.clone());
        }
        for (z, name) in set.outputs.iter().enumerate() {
            columns.insert(name.as_str(), after.iter().map(|o| Some(o[z])).collect());
        }
        Run {
            scenario,
            len: n + 1,
            columns,
        }
    }

    /// The formula on the first `len` states.
    fn truth(&self, f: &Ltl, len: usize) -> Result<Vec<Truth>, NotEvaluable> {
        f.truth_on_prefix(len, &|n| self.columns.get(n).map(Vec::as_slice))
    }

    fn place(&self, state: usize) -> Place {
        Place {
            origin: self.scenario.origin.clone(),
            state,
            steps: self.len - 1,
        }
    }
}

/// The first violation of `f` on the runs and its extent, if the runs violate it.
fn violation(
    f: &Ltl,
    set: &ScenarioSet,
    runs: &[Run],
    states: usize,
) -> Result<Option<(Place, Extent)>, NotEvaluable> {
    // `G p`: count the states where `p` fails (`G G p` is `G p`).
    let mut body = f;
    while let Ltl::G(inner) = body {
        body = inner;
    }
    if !std::ptr::eq(body, f) {
        let mut first = None;
        let mut violating = 0;
        for run in runs {
            let truths = run.truth(body, run.len)?;
            for (i, t) in truths.iter().enumerate() {
                if *t == Truth::False {
                    violating += 1;
                    first.get_or_insert_with(|| run.place(i));
                }
            }
        }
        return Ok(first.map(|p| {
            (
                p,
                Extent::States {
                    violating,
                    of: states,
                },
            )
        }));
    }
    // Any other formula: the run violates it or not; the first place is the end of the
    // shortest prefix that already does (a violation stays one on every longer prefix).
    let mut first = None;
    let mut violating = 0;
    for run in runs {
        if run.truth(f, run.len)?.first() != Some(&Truth::False) {
            continue;
        }
        violating += 1;
        if first.is_none() {
            let (mut lo, mut hi) = (1, run.len);
            while lo < hi {
                let mid = (lo + hi) / 2;
                if run.truth(f, mid)?.first() == Some(&Truth::False) {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            first = Some(run.place(lo - 1));
        }
    }
    Ok(first.map(|p| {
        (
            p,
            Extent::Scenarios {
                violating,
                of: set.scenarios.len(),
            },
        )
    }))
}

/// Most positions of the closed-loop game [`realizability`] explores (Pick-and-Place from
/// one recorded scenario: 601,356).
pub(crate) const GAME_POSITIONS: usize = 1_000_000;

/// What the closed-loop game ([`crate::game`]) says about a problem the loop found no machine
/// for: whether any controller, of any size, answers the recordings as recorded and keeps every
/// property against every behaviour of the plant. `None` when the game does not apply (a
/// property outside its fragment, a plant it does not take, too many positions).
///
/// Neither answer is a verdict of NuSMV: a won game says a controller exists, as far as the
/// tool's own semantics of the plant go; a lost one says none does.
pub(crate) fn realizability(set: &ScenarioSet, problem: &crate::verify::Problem) -> Option<String> {
    let model = problem.model.as_ref().ok()?;
    let coupling = crate::check::Wiring::new(model, &problem.coupling).ok()?;
    let tree = crate::scenario::tree::ScenarioTree::build(set).ok()?;
    let started = std::time::Instant::now();
    let outcome = crate::game::solve(
        model,
        &coupling,
        &problem.props,
        &tree,
        &set.initial_outputs,
        GAME_POSITIONS,
        crate::deadline::Deadline::NONE,
    )
    .ok()?;
    let seconds = started.elapsed().as_secs_f64();
    Some(match outcome {
        crate::game::Outcome::Won(s) => format!(
            "the closed-loop game is won ({} positions, {seconds:.1} s): a controller that answers the recordings as recorded and keeps every property exists (in the tool's own model of the plant; NuSMV has not checked it); the loop found none within its limits",
            s.positions
        ),
        crate::game::Outcome::Lost => format!(
            "the closed-loop game is lost ({seconds:.1} s): no controller of any size answers the recordings as recorded and keeps every property against every behaviour of the plant (in the tool's own model of it)"
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Step;

    fn set(scenarios: &[&[(&str, Option<&str>)]]) -> ScenarioSet {
        let bits = |s: &str| s.chars().map(|c| c == '1').collect::<Vec<bool>>();
        ScenarioSet {
            inputs: vec!["home".into(), "go".into()],
            outputs: vec!["move".into(), "down".into()],
            initial_outputs: vec![false, false],
            scenarios: scenarios
                .iter()
                .enumerate()
                .map(|(k, steps)| Scenario {
                    origin: Origin {
                        file: "t.traces".into(),
                        line: k + 2,
                        rows: None,
                    },
                    steps: steps
                        .iter()
                        .map(|(i, o)| Step {
                            inputs: bits(i),
                            outputs: o.map(bits),
                        })
                        .collect(),
                })
                .collect(),
        }
    }

    fn props(text: &str) -> Vec<Property> {
        crate::ltl::parse_spec(Path::new("t.ltl"), text).unwrap()
    }

    #[test]
    fn outputs_are_read_with_the_next_inputs() {
        // Step 2 commands `move` while `home` holds; step 3 reads `home` false with `move`
        // still commanded: the state of step 3 violates `G (move -> home)`.
        let s = set(&[&[("10", None), ("11", Some("10")), ("01", None), ("11", None)]]);
        let e = explain(&s, &props("safe: G (move -> home)\n"));
        assert_eq!(e.checked, 1);
        let v = &e.violations[0];
        assert_eq!(v.property, "safe");
        assert_eq!(v.first.state, 2);
        assert_eq!(
            v.first.to_string(),
            "t.traces:2 step 3 (its inputs with the outputs after step 2)"
        );
        // States: initial+step 1, step 2, step 3, step 4, after step 4 (home unknown there).
        assert_eq!(
            v.extent,
            Extent::States {
                violating: 1,
                of: 5
            }
        );
    }

    #[test]
    fn outputs_alone_decide_the_state_after_the_last_step() {
        let s = set(&[&[("00", None)], &[("10", Some("11"))]]);
        let e = explain(&s, &props("G !(move & down)\n"));
        let v = &e.violations[0];
        assert_eq!(v.property, "p1");
        assert_eq!(
            v.first.to_string(),
            "t.traces:3 after step 1, the last (the outputs it leaves)"
        );
        assert_eq!(
            v.extent,
            Extent::States {
                violating: 1,
                of: 4
            }
        );
    }

    #[test]
    fn only_definite_violations_count_and_plant_names_are_undecidable() {
        let s = set(&[&[("01", Some("10")), ("00", None)]]);
        let e = explain(
            &s,
            &props("a: F down\nb: G (go -> X move)\nc: G (move -> F placed)\nd: !move U down\n"),
        );
        assert_eq!(e.checked, 3);
        assert_eq!(e.undecidable.len(), 1);
        assert_eq!(e.undecidable[0].property, "c");
        // `F down` and `G (go -> X move)` hold or are open; `!move U down` fails at the
        // state after step 1, where `move` is on and `down` has never been.
        let names: Vec<&str> = e.violations.iter().map(|v| v.property.as_str()).collect();
        assert_eq!(names, ["d"]);
        assert_eq!(e.violations[0].first.state, 1);
        assert_eq!(
            e.violations[0].extent,
            Extent::Scenarios {
                violating: 1,
                of: 1
            }
        );
    }

    #[test]
    fn inputs_with_one_recorded_value_are_named_with_the_properties_that_read_them() {
        // `home` is always TRUE, `go` shows both values: only `home` is unrecorded, and only
        // for the properties that read it.
        let s = set(&[&[("10", None), ("11", Some("10"))], &[("10", None)]]);
        let e = explain(
            &s,
            &props("a: G (go -> F move)\nback: G (!home -> F down)\nc: G (home | move)\n"),
        );
        assert_eq!(
            e.unrecorded,
            [Unrecorded {
                input: "home".into(),
                never: false,
                properties: vec!["back".into(), "c".into()],
            }]
        );
        assert_eq!(
            e.unrecorded[0].to_string(),
            "home = FALSE (read by back, c)"
        );
        // Both values recorded: nothing to say.
        let both = set(&[&[("10", None), ("01", None)]]);
        assert!(explain(&both, &props("G (home -> F move)\n"))
            .unrecorded
            .is_empty());
    }

    #[test]
    fn the_message_names_property_file_line_and_step() {
        let s = set(&[&[("10", Some("11")), ("10", None)]]);
        let err = refuse_violations(
            &s,
            &props("\n\nno_dive: G !(move & down)\n"),
            Path::new("s.ltl"),
        )
        .unwrap_err();
        assert_eq!(
            err.to_string(),
            "the recordings violate property no_dive (s.ltl:3): first at t.traces:2 step 2 \
             (its inputs with the outputs after step 1); 2 of the 3 states the recordings show \
             violate it; no controller that reproduces them can satisfy it"
        );
    }
}
