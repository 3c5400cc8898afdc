//! An in-process explicit-state model checker of the closed loop: plant [`Model`] × [`Ecc`] ×
//! LTL properties, with NuSMV's semantics (NuSMV stays the authority; this one is fast enough
//! to run on every candidate of a synthesis loop).
//!
//! In: a resolved plant, the [`Wiring`] of its names with a controller interface, an ECC,
//! future-only LTL [`Property`]s and [`Limits`]. Out: one [`ExplicitVerdict`] per property, each
//! violation with a [`Lasso`] that has been re-evaluated with [`Ltl::holds_on_lasso`]; or a
//! [`CheckError`] (a plant evaluation error with its line, too many states, no behaviour at
//! all).
//!
//! # The closed loop (as `smv::composition` composes it for NuSMV)
//! A state is `(s, q, o)`: plant variables, ECC state, ECC outputs. Initially `q` is state 0,
//! `o` the ECC's initial outputs and `s` an initial plant state under parameters `o`. REQ is
//! TRUE at every step: `(q', o')` is the ECC's step from `(q, o)` on the inputs read from `s`
//! (an input named `x` is the plant's variable or define `x`, evaluated on `s` and `o`), and
//! `s'` is any plant successor of `s` under `o` whose `INVAR` holds under `o'`. Only infinite
//! paths that visit every `FAIRNESS` condition infinitely often count: a state without a
//! successor is not a path, as in NuSMV. A closed loop without any such path is an error
//! ([`CheckError::NoBehaviour`]), never a list of vacuous verdicts.
//!
//! # Method
//! The reachable closed loop is built once per [`check`] call (at most
//! [`Limits::max_states`] states) and shared by the properties. Per property `φ`, `¬φ` becomes
//! a generalized Büchi automaton (`gba`, the tableau of Gerth, Peled, Vardi and Wolper); the
//! product with the closed loop is explored on the fly and searched for a cycle through every
//! acceptance set and every fairness condition (`emptiness`, Couvreur's algorithm). Such a
//! cycle is a run violating `φ`.

mod emptiness;
mod gba;
#[cfg(test)]
mod tests;

use crate::ecc::{Ecc, StateId};
use crate::ltl::{CmpOp, Ltl, Property};
use crate::plant::explicit::{self, EvalError, Semantics};
use crate::plant::{Model, Name, Type, Value};
use crate::scenario::negative::{NegativeScenario, NegativeStep};
use crate::smv::composition;
use emptiness::{find_lasso, Graph};
use gba::Gba;
use rustc_hash::FxHashMap;
use std::collections::BTreeMap;
use std::sync::Arc;

/// How the controller and the plant are wired, by index.
#[derive(Debug, Clone)]
pub(crate) struct Wiring {
    /// Per ECC input (interface order): the plant variable or define it reads.
    pub(crate) inputs: Vec<Name>,
    /// Per plant parameter ([`crate::plant::ParamId`] order): the ECC output it is.
    pub(crate) params: Vec<usize>,
    /// The ECC outputs, by name (LTL atoms may name them).
    pub(crate) outputs: Vec<String>,
}

impl Wiring {
    /// Wires a controller to `model` along `coupling`, checked by
    /// [`check_coupling`](composition::check_coupling) on the plant file `model` was read from
    /// (as [`crate::verify::Problem::load`] does): the plant variable or define each input
    /// reads, the output each plant parameter is. The coupling convention is not checked again;
    /// refused here is what this checker cannot run (an input on a variable that is not
    /// Boolean, more than 64 outputs) and a `model` of another plant.
    pub(crate) fn new(
        model: &Model,
        coupling: &composition::Coupling,
    ) -> Result<Wiring, CheckError> {
        let bad = |message: String| CheckError::Coupling {
            file: model.file.display().to_string(),
            message,
        };
        let mut wired = Vec::with_capacity(coupling.inputs.len());
        for i in &coupling.sensors {
            match model.lookup(i) {
                Some(Name::Var(v)) if model.var(v).ty != Type::Bool => {
                    return Err(bad(format!(
                        "controller input {} is plant variable {}, which is not boolean",
                        crate::quote::quote(i),
                        crate::quote::quote(&model.var(v).name)
                    )))
                }
                Some(n @ (Name::Var(_) | Name::Define(_))) => wired.push(n),
                _ => {
                    return Err(bad(format!(
                        "the plant declares no variable or define {} for the controller input of that name",
                        crate::quote::quote(i)
                    )))
                }
            }
        }
        if let Some(e) = (model.params.iter()).find(|p| !coupling.param_names.contains(p)) {
            return Err(bad(format!(
                "the plant reads {} as a parameter, which is no controller output (the in-process checker gives the plant controller outputs only)",
                crate::quote::quote(e)
            )));
        }
        let same_params =
            model.params.len() == coupling.params.len() && model.params == coupling.param_names;
        if !same_params {
            return Err(bad(format!(
                "the plant's parameters ({}) are not those the coupling was checked with",
                model.params.join(", ")
            )));
        }
        if coupling.outputs.len() > 64 {
            return Err(bad(format!(
                "{} controller outputs (the in-process checker takes at most 64)",
                coupling.outputs.len()
            )));
        }
        Ok(Wiring {
            inputs: wired,
            params: coupling.params.clone(),
            outputs: coupling.outputs.clone(),
        })
    }

    /// The coupling of `model`, a plant built in a test, with a controller over `inputs` and
    /// `outputs`, made as for a plant file: `model` printed, scanned and checked, then wired.
    #[cfg(test)]
    pub(crate) fn of_model(
        model: &Model,
        inputs: &[String],
        outputs: &[String],
    ) -> Result<Wiring, String> {
        let text = crate::plant::print::to_smv(model);
        let plant =
            crate::smv::plant::parse_plant(&model.file, &text).map_err(|e| e.to_string())?;
        let spec = std::path::Path::new("t.ltl");
        let coupling = composition::check_coupling(inputs, outputs, &plant, spec, &[])
            .map_err(|e| e.to_string())?;
        Wiring::new(model, &coupling).map_err(|e| e.to_string())
    }

    /// The plant parameters for the output bits `o` (bit `z`: output `z`).
    pub(crate) fn params(&self, o: u64) -> Vec<bool> {
        self.params.iter().map(|&z| o >> z & 1 == 1).collect()
    }

    /// The controller's inputs (interface order) on a state of the closed loop.
    pub(crate) fn inputs_on(&self, model: &Model, s: &LoopState) -> Result<Vec<bool>, CheckError> {
        let params: Vec<bool> = self.params.iter().map(|&z| s.outputs[z]).collect();
        self.read_inputs(&Semantics::new(model), &s.plant, &params)
    }

    /// The controller's inputs on plant state `plant` under plant parameters `params`.
    pub(crate) fn read_inputs(
        &self,
        sem: &Semantics,
        plant: &[Value],
        params: &[bool],
    ) -> Result<Vec<bool>, CheckError> {
        let model = sem.model();
        self.inputs
            .iter()
            .map(|name| match sem.read(*name, plant, params)? {
                Value::Bool(b) => Ok(b),
                other => Err(CheckError::Coupling {
                    file: model.file.display().to_string(),
                    message: format!(
                        "controller input '{}' has the value {}, not TRUE or FALSE",
                        model.name_of(*name),
                        model.show(other)
                    ),
                }),
            })
            .collect()
    }

    /// The controller's side of a counterexample to `property`: the lasso of its inputs and
    /// outputs, which a machine must leave to avoid the same run of the plant (the plant sees
    /// only the outputs).
    pub(crate) fn negative(
        &self,
        model: &Model,
        lasso: &Lasso,
        property: &str,
    ) -> Result<NegativeScenario, CheckError> {
        let inputs = lasso
            .states
            .iter()
            .map(|s| self.inputs_on(model, s))
            .collect::<Result<Vec<_>, _>>()?;
        let steps = (0..lasso.states.len())
            .map(|i| {
                let next = if i + 1 < lasso.states.len() {
                    i + 1
                } else {
                    lasso.loop_start
                };
                NegativeStep {
                    inputs: inputs[i].clone(),
                    before: lasso.states[i].outputs.clone(),
                    after: lasso.states[next].outputs.clone(),
                }
            })
            .collect();
        Ok(NegativeScenario {
            steps,
            loop_start: Some(lasso.loop_start),
            label: format!("counterexample of {property}"),
        })
    }
}

/// The verdict on one property.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum ExplicitVerdict {
    /// The property holds on every fair run of the closed loop.
    Holds,
    /// A run of the closed loop on which the property is false.
    Violated(Lasso),
    /// The property is outside what this checker decides (past operators, ...): ask NuSMV.
    Unsupported(String),
}

/// A lasso-shaped run: `states[..loop_start]` followed by `states[loop_start..]` forever.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Lasso {
    /// The run's states; the last one's successor is `states[loop_start]`.
    pub(crate) states: Vec<LoopState>,
    /// Index in `states` where the repeated cycle starts (`< states.len()`).
    pub(crate) loop_start: usize,
}

/// One state of the closed loop.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(crate) struct LoopState {
    /// The plant's variables, indexed by [`crate::plant::VarId`].
    pub(crate) plant: Vec<Value>,
    /// The ECC's state.
    pub(crate) ctrl: StateId,
    /// The ECC's outputs, in interface order.
    pub(crate) outputs: Vec<bool>,
}

/// Bounds on the exploration. Every structure the checker builds is bounded by them, and a
/// check that would pass one stops with an error that names it ([`CheckError::is_bound`]):
/// the caller then leaves the verdict to NuSMV.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Limits {
    /// Most closed-loop states (or plant states, for [`behaviour`]) explored.
    pub(crate) max_states: usize,
    /// Most transitions of the closed loop (successor entries stored).
    pub(crate) max_transitions: usize,
    /// Most bytes the checker's structures are estimated to take: the closed loop, what a
    /// [`PlantMemo`] keeps, and the search of a property's counterexample.
    pub(crate) max_bytes: usize,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_states: 1_000_000,
            max_transitions: 8_000_000,
            max_bytes: 512 << 20,
        }
    }
}

/// Why the closed loop could not be checked.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CheckError {
    /// The plant and the controller interface do not fit together (an input the plant lacks or
    /// that is not Boolean, a parameter that is no output, a name clash, too many outputs, ...).
    #[error("{file}: {message}")]
    Coupling {
        /// The plant file, as displayed.
        file: String,
        /// What does not fit.
        message: String,
    },
    /// The ECC is invalid, or its interface is not the one the [`Wiring`] was made for.
    #[error("the controller: {0}")]
    Ecc(String),
    /// Evaluating a plant expression failed (located in the plant file).
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// The reachable states exceed [`Limits::max_states`].
    #[error("more than {limit} reachable states: raise the limit or check with NuSMV")]
    TooManyStates {
        /// The limit that was exceeded.
        limit: usize,
    },
    /// The closed loop has more transitions than [`Limits::max_transitions`] (found while
    /// exploring, or predicted before: `why` says how).
    #[error("more than {limit} transitions of the closed loop{why}: raise the limit or check with NuSMV")]
    TooManyTransitions {
        /// The limit that was exceeded.
        limit: usize,
        /// Empty, or how the count was predicted (with a leading blank).
        why: String,
    },
    /// The checker's structures would take more than [`Limits::max_bytes`].
    #[error("more than {} estimated for {what}: raise the limit or check with NuSMV", show_bytes(*limit))]
    TooMuchMemory {
        /// The limit that was exceeded, in bytes.
        limit: usize,
        /// Which structure (`the closed loop`, `the search of a property`, ...).
        what: &'static str,
    },
    /// No initial state, or no infinite path that is fair to every `FAIRNESS` condition: every
    /// property would hold vacuously.
    #[error("the {scope} has no {what}: every property would hold vacuously; check the plant's INIT, INVAR, TRANS and FAIRNESS constraints")]
    NoBehaviour {
        /// `closed loop` or `plant`.
        scope: &'static str,
        /// `initial state` or `fair infinite path`.
        what: &'static str,
    },
    /// A property reads a name or compares values the closed loop does not have.
    #[error("property {index} (line {line}): {message}")]
    Property {
        /// 0-based position in the property list.
        index: usize,
        /// 1-based line of the property in its file.
        line: usize,
        /// What is wrong with it.
        message: String,
    },
    /// The checker contradicts itself (a counterexample that does not violate its property):
    /// a bug, reported instead of a verdict.
    #[error("internal error of the in-process checker: {0}")]
    Bug(String),
}

/// `bytes` in MB when it is at least one, else in bytes.
fn show_bytes(bytes: usize) -> String {
    if bytes >= 1 << 20 {
        format!("{} MB", bytes >> 20)
    } else {
        format!("{bytes} bytes")
    }
}

impl CheckError {
    /// Whether the check stopped at a bound of [`Limits`] (states, transitions, memory): the
    /// closed loop is too large for this checker, and NuSMV alone can judge it.
    pub(crate) fn is_bound(&self) -> bool {
        matches!(
            self,
            CheckError::TooManyStates { .. }
                | CheckError::TooManyTransitions { .. }
                | CheckError::TooMuchMemory { .. }
        )
    }
}

/// The properties' negations as Büchi automata, built once for many [`check_with`] calls (a
/// search checks thousands of machines against the same properties).
#[derive(Debug, Clone)]
pub(crate) struct Automata(Vec<Result<Gba, gba::Refused>>);

impl Automata {
    /// Builds the automaton of each property's negation (or why it is refused), in order.
    pub(crate) fn of(props: &[Property]) -> Automata {
        Automata(
            props
                .iter()
                .map(|p| Gba::of(&Ltl::Not(Box::new(p.formula.clone()))))
                .collect(),
        )
    }
}

/// The plant's side of closed-loop states, which does not depend on the controller: kept
/// across the checks of many machines against one plant and coupling (a search's), where it
/// was most of the work of building each closed loop. Use one memo per plant and coupling.
///
/// Plant states are interned once and referred to by number, so that a state with thousands
/// of successors (a plant with many free inputs) costs four bytes per successor. The memo is a
/// cache: [`check_with`] empties it when it holds more than half of [`Limits::max_bytes`].
#[derive(Debug, Default)]
pub(crate) struct PlantMemo {
    /// Plant states, by number.
    states: Vec<Arc<[Value]>>,
    /// The number of each plant state.
    ids: FxHashMap<Arc<[Value]>, u32>,
    /// Per plant state number: what is known about it.
    info: Vec<PlantState>,
    /// Bytes the memo is estimated to hold.
    bytes: usize,
}

/// Plant successor states (numbers in a [`PlantMemo`]), shared between the memo and a closed
/// loop's build.
type Successors = Arc<[u32]>;

/// What is known about one plant state, by the controller's outputs (bits).
#[derive(Debug, Default)]
struct PlantState {
    /// Under outputs `o`: what the controller reads, and the fairness conditions that hold.
    at: FxHashMap<u64, (Arc<[bool]>, u64)>,
    /// Under outputs `o` now and `o'` next: the plant's successors.
    successors: FxHashMap<(u64, u64), Successors>,
}

/// Estimated bytes of a plant state in a [`PlantMemo`] besides its values: the two handles,
/// the table entry and the empty tables of [`PlantState`].
const PLANT_STATE_BYTES: usize = 160;
/// Estimated bytes of a table entry of [`PlantState`] besides the list it holds.
const MEMO_ENTRY_BYTES: usize = 64;

impl PlantMemo {
    /// The number of plant state `plant`, interned if new.
    fn intern(&mut self, plant: &[Value]) -> u32 {
        if let Some(&i) = self.ids.get(plant) {
            return i;
        }
        let i = self.states.len() as u32;
        let s: Arc<[Value]> = plant.into();
        self.bytes += PLANT_STATE_BYTES + std::mem::size_of_val(plant);
        self.ids.insert(s.clone(), i);
        self.states.push(s);
        self.info.push(PlantState::default());
        i
    }

    /// The controller's inputs on plant state `plant` under outputs `outputs`, and the
    /// fairness conditions that hold there.
    fn at(
        &mut self,
        sem: &Semantics,
        coupling: &Wiring,
        plant: u32,
        outputs: u64,
    ) -> Result<(Arc<[bool]>, u64), CheckError> {
        let p = plant as usize;
        if let Some(a) = self.info[p].at.get(&outputs) {
            return Ok(a.clone());
        }
        let params = coupling.params(outputs);
        let values = &self.states[p];
        let inputs: Arc<[bool]> = coupling.read_inputs(sem, values, &params)?.into();
        let a = (inputs, sem.fairness(values, &params)?);
        self.bytes += MEMO_ENTRY_BYTES + a.0.len();
        self.info[p].at.insert(outputs, a.clone());
        Ok(a)
    }

    /// The successors of plant state `plant` under outputs `outputs` now and `next_outputs`
    /// next.
    fn successors(
        &mut self,
        sem: &Semantics,
        coupling: &Wiring,
        plant: u32,
        outputs: u64,
        next_outputs: u64,
    ) -> Result<Successors, CheckError> {
        let p = plant as usize;
        if let Some(s) = self.info[p].successors.get(&(outputs, next_outputs)) {
            return Ok(s.clone());
        }
        let params = coupling.params(outputs);
        let next_params = coupling.params(next_outputs);
        let values = self.states[p].clone();
        let mut ids = Vec::new();
        sem.for_each_successor(&values, &params, &next_params, &mut |t| {
            ids.push(self.intern(t));
            Ok::<(), CheckError>(())
        })?;
        let s: Successors = ids.into();
        self.bytes += MEMO_ENTRY_BYTES + 4 * s.len();
        self.info[p]
            .successors
            .insert((outputs, next_outputs), s.clone());
        Ok(s)
    }
}

/// Checks every property on the closed loop of `model` and `ecc`.
pub(crate) fn check(
    model: &Model,
    coupling: &Wiring,
    ecc: &Ecc,
    props: &[Property],
    limits: &Limits,
) -> Result<Vec<ExplicitVerdict>, CheckError> {
    check_with(
        model,
        coupling,
        ecc,
        props,
        &Automata::of(props),
        limits,
        &mut PlantMemo::default(),
    )
}

/// [`check`] with the automata of `props` built beforehand.
pub(crate) fn check_with(
    model: &Model,
    coupling: &Wiring,
    ecc: &Ecc,
    props: &[Property],
    automata: &Automata,
    limits: &Limits,
    memo: &mut PlantMemo,
) -> Result<Vec<ExplicitVerdict>, CheckError> {
    Judge::of(model, coupling, ecc, limits, memo)?.verdicts(props, automata)
}

/// The closed loop of one machine, explored, ready to judge properties on: every verdict
/// ([`check_with`]), or whether all hold, up to the first that does not ([`Judge::all_hold`]).
pub(crate) struct Judge<'a> {
    model: &'a Model,
    coupling: &'a Wiring,
    closed: ExplicitLoop<'a>,
    limits: &'a Limits,
    /// Bytes left for a property's search once the closed loop is built.
    budget: usize,
}

impl<'a> Judge<'a> {
    /// The closed loop of `model` and `ecc`, checked to have an initial state and a fair
    /// infinite path.
    pub(crate) fn of(
        model: &'a Model,
        coupling: &'a Wiring,
        ecc: &'a Ecc,
        limits: &'a Limits,
        memo: &'a mut PlantMemo,
    ) -> Result<Judge<'a>, CheckError> {
        ecc.validate().map_err(CheckError::Ecc)?;
        if ecc.inputs.len() != coupling.inputs.len() || ecc.outputs != coupling.outputs {
            return Err(CheckError::Ecc(
                "its interface is not the one the coupling was made for".into(),
            ));
        }
        // The memo is a cache: one that has grown over many checks is dropped rather than let
        // crowd out the closed loop.
        if memo.bytes > limits.max_bytes / 2 {
            *memo = PlantMemo::default();
        }
        let closed = ExplicitLoop::build(model, coupling, ecc, limits, memo)?;
        if closed.initial.is_empty() {
            return Err(CheckError::NoBehaviour {
                scope: "closed loop",
                what: "initial state",
            });
        }
        let budget = limits.max_bytes.saturating_sub(closed.bytes);
        let all_fair = mask(model.fairness.len());
        if find_lasso(&mut Plain(&closed), all_fair, budget)?.is_none() {
            return Err(CheckError::NoBehaviour {
                scope: "closed loop",
                what: "fair infinite path",
            });
        }
        Ok(Judge {
            model,
            coupling,
            closed,
            limits,
            budget,
        })
    }

    /// The verdict on every property of `props`, in order.
    fn verdicts(
        &self,
        props: &[Property],
        automata: &Automata,
    ) -> Result<Vec<ExplicitVerdict>, CheckError> {
        (props.iter().zip(&automata.0).enumerate())
            .map(|(index, (p, gba))| self.verdict(index, p, gba))
            .collect()
    }

    /// Whether every property of `props` holds, judged in order up to the first that does
    /// not: a search that keeps only machines keeping every property spends most of its
    /// checks on machines that break one.
    pub(crate) fn all_hold(
        &self,
        props: &[Property],
        automata: &Automata,
    ) -> Result<bool, CheckError> {
        for (index, (p, gba)) in props.iter().zip(&automata.0).enumerate() {
            if !matches!(self.verdict(index, p, gba)?, ExplicitVerdict::Holds) {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The verdict on property `p` (the `index`-th), whose negation is `gba`.
    fn verdict(
        &self,
        index: usize,
        p: &Property,
        gba: &Result<Gba, gba::Refused>,
    ) -> Result<ExplicitVerdict, CheckError> {
        let (model, closed) = (self.model, &self.closed);
        let fairness = model.fairness.len();
        let gba = match gba {
            Ok(g) => g,
            Err(gba::Refused(why)) => return Ok(ExplicitVerdict::Unsupported(why.clone())),
        };
        if gba.sets + fairness > 64 {
            return Ok(ExplicitVerdict::Unsupported(format!(
                "{} acceptance sets and {fairness} fairness conditions (at most 64 in all)",
                gba.sets
            )));
        }
        let atoms = gba
            .atoms
            .iter()
            .map(|a| Atom::resolve(a, model, self.coupling))
            .collect::<Result<Vec<_>, String>>()
            .map_err(|message| CheckError::Property {
                index,
                line: p.line,
                message,
            })?;
        let labels = closed
            .keys
            .iter()
            .map(|k| closed.valuation(&atoms, k))
            .collect::<Result<Vec<u64>, _>>()
            .map_err(|e| match e {
                AtomError::Eval(e) => CheckError::Eval(e),
                AtomError::Type(message) => CheckError::Property {
                    index,
                    line: p.line,
                    message,
                },
            })?;
        let nodes = gba.successors.len();
        if closed.keys.len().saturating_mul(nodes.max(1)) >= u32::MAX as usize {
            return Err(CheckError::TooManyStates {
                limit: self.limits.max_states,
            });
        }
        let mut product = Product {
            closed,
            gba,
            labels: &labels,
        };
        let all = mask(gba.sets) | mask(fairness) << gba.sets;
        Ok(match find_lasso(&mut product, all, self.budget)? {
            None => ExplicitVerdict::Holds,
            Some(l) => {
                let nodes = nodes as u32;
                let project = |v: &[u32]| v.iter().map(|n| n / nodes).collect::<Vec<u32>>();
                let lasso = closed.lasso(&project(&l.prefix), &project(&l.cycle));
                closed.confirm(&p.formula, &lasso)?;
                ExplicitVerdict::Violated(lasso)
            }
        })
    }
}

/// Every pair of controller state and input vector the closed loop of `model` and `ecc`
/// reaches, each once, in order: where the machine's answers decide what the closed loop
/// does. A machine that answers as `ecc` on every pair has the same closed loop, so the same
/// verdicts.
pub(crate) fn reached_inputs(
    model: &Model,
    coupling: &Wiring,
    ecc: &Ecc,
    limits: &Limits,
) -> Result<Vec<(StateId, Vec<bool>)>, CheckError> {
    ecc.validate().map_err(CheckError::Ecc)?;
    let mut memo = PlantMemo::default();
    let closed = ExplicitLoop::build(model, coupling, ecc, limits, &mut memo)?;
    let mut pairs = std::collections::BTreeSet::new();
    for k in &closed.keys {
        let (inputs, _) = memo.at(&closed.sem, coupling, k.plant, k.outputs)?;
        pairs.insert((k.ctrl as usize, inputs.to_vec()));
    }
    Ok(pairs.into_iter().map(|(q, x)| (StateId(q), x)).collect())
}

/// Checks that the plant alone, its parameters chosen freely at every step, has an initial
/// state and a fair infinite path: [`CheckError::NoBehaviour`] otherwise.
pub(crate) fn behaviour(model: &Model, limits: &Limits) -> Result<(), CheckError> {
    if model.params.len() > 16 || model.fairness.len() > 64 {
        return Err(CheckError::Coupling {
            file: model.file.display().to_string(),
            message: "more than 16 parameters or 64 fairness conditions".into(),
        });
    }
    let mut free = FreePlant::new(model, limits);
    let initial = free.initial()?;
    if initial.is_empty() {
        return Err(CheckError::NoBehaviour {
            scope: "plant",
            what: "initial state",
        });
    }
    // The states take at most half of the bytes allowed, the search the other half.
    match find_lasso(&mut free, mask(model.fairness.len()), limits.max_bytes / 2)? {
        Some(_) => Ok(()),
        None => Err(CheckError::NoBehaviour {
            scope: "plant",
            what: "fair infinite path",
        }),
    }
}

fn mask(n: usize) -> u64 {
    if n >= 64 {
        u64::MAX
    } else {
        (1 << n) - 1
    }
}

/// A closed-loop state, compactly: the plant state by its number in the [`PlantMemo`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct Key {
    plant: u32,
    ctrl: u32,
    outputs: u64,
}

/// What entering a state does to the output bits: `((o & keep) | set) ^ flip`.
#[derive(Debug, Clone, Copy)]
struct OutputEffect {
    keep: u64,
    set: u64,
    flip: u64,
}

impl OutputEffect {
    fn of(a: &crate::ecc::Algorithm) -> OutputEffect {
        use crate::ecc::Effect;
        let mut e = OutputEffect {
            keep: 0,
            set: 0,
            flip: 0,
        };
        for (z, effect) in Effect::all(a).into_iter().enumerate() {
            match effect {
                Effect::Keep => e.keep |= 1 << z,
                Effect::Flip => {
                    e.keep |= 1 << z;
                    e.flip |= 1 << z
                }
                Effect::Set(true) => e.set |= 1 << z,
                Effect::Set(false) => {}
            }
        }
        e
    }

    fn apply(self, o: u64) -> u64 {
        ((o & self.keep) | self.set) ^ self.flip
    }
}

/// The reachable closed loop, explicitly.
struct ExplicitLoop<'a> {
    sem: Semantics<'a>,
    coupling: &'a Wiring,
    keys: Vec<Key>,
    succ: Vec<Vec<u32>>,
    initial: Vec<u32>,
    /// Per state: the fairness conditions it satisfies.
    fair: Vec<u64>,
    /// The plant states, by their number in the memo the loop was built with.
    plants: Vec<Arc<[Value]>>,
    /// Transitions stored (entries of `succ`).
    transitions: usize,
    /// Bytes the closed loop and the memo are estimated to hold.
    bytes: usize,
}

/// Estimated bytes of a closed-loop state: its key, its table entry, its successor list's
/// header, its fairness and label words.
const CLOSED_STATE_BYTES: usize = 96;

impl<'a> ExplicitLoop<'a> {
    fn build(
        model: &'a Model,
        coupling: &'a Wiring,
        ecc: &Ecc,
        limits: &Limits,
        memo: &mut PlantMemo,
    ) -> Result<ExplicitLoop<'a>, CheckError> {
        let effects: Vec<OutputEffect> = ecc
            .states
            .iter()
            .map(|s| OutputEffect::of(&s.algorithm))
            .collect();
        let o0 =
            (ecc.initial_outputs.iter().enumerate()).fold(0u64, |o, (z, &v)| o | (v as u64) << z);
        let mut c = ExplicitLoop {
            sem: Semantics::new(model),
            coupling,
            keys: Vec::new(),
            succ: Vec::new(),
            initial: Vec::new(),
            fair: Vec::new(),
            plants: Vec::new(),
            transitions: 0,
            bytes: 0,
        };
        let mut index: FxHashMap<Key, u32> = FxHashMap::default();
        let mut intern = |c: &mut ExplicitLoop, key: Key| c.intern(&mut index, key, limits);
        // Without INIT constraints an initial state exists (or evaluating one fails): the
        // prediction holds before the free inputs' combinations are enumerated at all.
        if model.init.is_empty() {
            c.predict(limits, true)?;
        }
        for s in c.sem.initial_states(&coupling.params(o0))? {
            let key = Key {
                plant: memo.intern(&s),
                ctrl: 0,
                outputs: o0,
            };
            let i = intern(&mut c, key)?;
            c.initial.push(i);
        }
        c.predict(limits, !c.initial.is_empty())?;
        let mut next = 0;
        while next < c.keys.len() {
            let key = c.keys[next];
            let (inputs, fair) = memo.at(&c.sem, coupling, key.plant, key.outputs)?;
            let (q, o) = react(ecc, &effects, key, &inputs);
            let successors = memo.successors(&c.sem, coupling, key.plant, key.outputs, o)?;
            c.within(limits, successors.len(), memo)?;
            let mut out = Vec::with_capacity(successors.len());
            for &plant in successors.iter() {
                out.push(intern(
                    &mut c,
                    Key {
                        plant,
                        ctrl: q,
                        outputs: o,
                    },
                )?);
            }
            c.succ.push(out);
            c.fair.push(fair);
            next += 1;
        }
        c.plants = memo.states.clone();
        Ok(c)
    }

    /// The number of the closed-loop state `key`, numbered next when it is new (at most
    /// [`Limits::max_states`] of them).
    fn intern(
        &mut self,
        index: &mut FxHashMap<Key, u32>,
        key: Key,
        limits: &Limits,
    ) -> Result<u32, CheckError> {
        if let Some(&i) = index.get(&key) {
            return Ok(i);
        }
        if self.keys.len() >= limits.max_states {
            return Err(CheckError::TooManyStates {
                limit: limits.max_states,
            });
        }
        let i = self.keys.len() as u32;
        index.insert(key, i);
        self.keys.push(key);
        Ok(i)
    }

    /// Refuses, before exploring, a closed loop whose transitions can be told to exceed the
    /// limit: without `TRANS` and `INVAR` every successor of a state takes every combination
    /// of the plant's free inputs (`IVAR`s, `VAR`s without `init` and `next`), so from a
    /// non-empty set of initial states (`has_initial`) at least that many states are
    /// reached, each with at least that many successors.
    fn predict(&self, limits: &Limits, has_initial: bool) -> Result<(), CheckError> {
        let model = self.sem.model();
        if !has_initial || !model.trans.is_empty() || !model.invar.is_empty() {
            return Ok(());
        }
        let f = self.sem.free_combinations();
        if f.saturating_mul(f) > limits.max_transitions as u128 {
            return Err(CheckError::TooManyTransitions {
                limit: limits.max_transitions,
                why: format!(
                    " (at least {f} × {f}: the plant's free inputs take {f} combinations of \
                     values, and every state has that many successors)"
                ),
            });
        }
        Ok(())
    }

    /// Counts a new state with `successors` transitions against the limits, with what `memo`
    /// holds.
    fn within(
        &mut self,
        limits: &Limits,
        successors: usize,
        memo: &PlantMemo,
    ) -> Result<(), CheckError> {
        self.transitions += successors;
        if self.transitions > limits.max_transitions {
            return Err(CheckError::TooManyTransitions {
                limit: limits.max_transitions,
                why: String::new(),
            });
        }
        self.bytes = memo.bytes + self.keys.len() * CLOSED_STATE_BYTES + 4 * self.transitions;
        if self.bytes > limits.max_bytes {
            return Err(CheckError::TooMuchMemory {
                limit: limits.max_bytes,
                what: "the closed loop",
            });
        }
        Ok(())
    }

    /// The atoms' values on a state, bit `i` for atom `i`.
    fn valuation(&self, atoms: &[Atom], k: &Key) -> Result<u64, AtomError> {
        let params = self.coupling.params(k.outputs);
        let mut bits = 0;
        for (i, a) in atoms.iter().enumerate() {
            if a.holds(self, k, &params)? {
                bits |= 1 << i;
            }
        }
        Ok(bits)
    }

    fn loop_state(&self, i: u32) -> LoopState {
        let k = &self.keys[i as usize];
        LoopState {
            plant: self.plants[k.plant as usize].to_vec(),
            ctrl: StateId(k.ctrl as usize),
            outputs: (0..self.coupling.outputs.len())
                .map(|z| k.outputs >> z & 1 == 1)
                .collect(),
        }
    }

    fn lasso(&self, prefix: &[u32], cycle: &[u32]) -> Lasso {
        Lasso {
            states: prefix
                .iter()
                .chain(cycle)
                .map(|&i| self.loop_state(i))
                .collect(),
            loop_start: prefix.len(),
        }
    }

    /// Every name of the closed loop with its value on `s`, as NuSMV prints it: outputs,
    /// plant variables and the defines that evaluate.
    fn names(&self, s: &LoopState) -> BTreeMap<String, String> {
        let model = self.sem.model();
        let params: Vec<bool> = self.coupling.params.iter().map(|&z| s.outputs[z]).collect();
        let mut m = BTreeMap::new();
        for (z, name) in self.coupling.outputs.iter().enumerate() {
            m.insert(name.clone(), model.show(Value::Bool(s.outputs[z])));
        }
        for (v, var) in model.vars.iter().enumerate() {
            m.insert(var.name.clone(), model.show(s.plant[v]));
        }
        for (d, def) in model.defines.iter().enumerate() {
            let name = Name::Define(crate::plant::DefineId(d));
            if let Ok(value) = self.sem.read(name, &s.plant, &params) {
                m.insert(def.name.clone(), model.show(value));
            }
        }
        m
    }

    /// Confirms that `lasso` is a fair run on which `formula` is false, by the independent
    /// evaluation of [`Ltl::holds_on_lasso`].
    fn confirm(&self, formula: &Ltl, lasso: &Lasso) -> Result<(), CheckError> {
        let bug = |what: String| {
            CheckError::Bug(format!(
                "counterexample to `{formula}` with {} states (loop at {}): {what}",
                lasso.states.len(),
                lasso.loop_start
            ))
        };
        let states: Vec<BTreeMap<String, String>> =
            lasso.states.iter().map(|s| self.names(s)).collect();
        match formula.holds_on_lasso(&states, lasso.loop_start) {
            Ok(false) => {}
            Ok(true) => return Err(bug("the formula holds on it".into())),
            Err(e) => return Err(bug(format!("it cannot be evaluated: {e}"))),
        }
        let model = self.sem.model();
        let mut seen = 0u64;
        for s in &lasso.states[lasso.loop_start..] {
            let params: Vec<bool> = self.coupling.params.iter().map(|&z| s.outputs[z]).collect();
            seen |= self.sem.fairness(&s.plant, &params)?;
        }
        if seen != mask(model.fairness.len()) {
            return Err(bug("its loop is not fair".into()));
        }
        Ok(())
    }
}

/// The controller's answer in closed-loop state `key` to `inputs`: the first transition of
/// its state whose guard holds fires (its target and the outputs after the target's
/// algorithm), or nothing changes.
fn react(ecc: &Ecc, effects: &[OutputEffect], key: Key, inputs: &[bool]) -> (u32, u64) {
    match ecc.states[key.ctrl as usize].fired(inputs) {
        Some(t) => (t.target.0 as u32, effects[t.target.0].apply(key.outputs)),
        None => (key.ctrl, key.outputs),
    }
}

/// The closed loop itself as a graph whose acceptance sets are the fairness conditions.
struct Plain<'c, 'a>(&'c ExplicitLoop<'a>);

impl Graph for Plain<'_, '_> {
    type Error = CheckError;
    fn initial(&mut self) -> Result<Vec<u32>, CheckError> {
        Ok(self.0.initial.clone())
    }
    fn successors(&mut self, n: u32, out: &mut Vec<u32>) -> Result<(), CheckError> {
        out.extend(&self.0.succ[n as usize]);
        Ok(())
    }
    fn marks(&self, n: u32) -> u64 {
        self.0.fair[n as usize]
    }
    fn too_large(&self, bytes: usize) -> CheckError {
        CheckError::TooMuchMemory {
            limit: bytes,
            what: "the search for a fair path of the closed loop",
        }
    }
}

/// The product of the closed loop with the automaton of a negated property: node
/// `s * |Q| + q`.
struct Product<'p, 'a> {
    closed: &'p ExplicitLoop<'a>,
    gba: &'p Gba,
    labels: &'p [u64],
}

impl Product<'_, '_> {
    fn nodes(&self) -> u32 {
        self.gba.successors.len() as u32
    }
}

impl Graph for Product<'_, '_> {
    type Error = CheckError;
    fn initial(&mut self) -> Result<Vec<u32>, CheckError> {
        let mut out = Vec::new();
        for &s in &self.closed.initial {
            for &q in &self.gba.initial {
                if self.gba.reads(q, self.labels[s as usize]) {
                    out.push(s * self.nodes() + q);
                }
            }
        }
        Ok(out)
    }
    fn successors(&mut self, n: u32, out: &mut Vec<u32>) -> Result<(), CheckError> {
        let (s, q) = (n / self.nodes(), n % self.nodes());
        for &t in &self.closed.succ[s as usize] {
            let label = self.labels[t as usize];
            for &r in &self.gba.successors[q as usize] {
                if self.gba.reads(r, label) {
                    out.push(t * self.nodes() + r);
                }
            }
        }
        Ok(())
    }
    fn marks(&self, n: u32) -> u64 {
        let (s, q) = (n / self.nodes(), n % self.nodes());
        self.gba.accepting[q as usize] | self.closed.fair[s as usize] << self.gba.sets
    }
    fn too_large(&self, bytes: usize) -> CheckError {
        CheckError::TooMuchMemory {
            limit: bytes,
            what: "the search for a counterexample to a property",
        }
    }
}

/// The plant alone with free parameters, explored on demand. A node is a plant state, with
/// the parameter bits when a constraint the next step checks (`INVAR`, `FAIRNESS`) reads them,
/// or when the initial state depends on them (`INIT`, `init(v)`): a parameter is a variable,
/// so the value the initial state was chosen under is the value the first step reads.
struct FreePlant<'a> {
    sem: Semantics<'a>,
    params_in_state: bool,
    keys: Vec<(Box<[Value]>, u64)>,
    index: FxHashMap<(Box<[Value]>, u64), u32>,
    fair: Vec<u64>,
    limits: Limits,
    /// Bytes the states are estimated to hold.
    bytes: usize,
}

impl<'a> FreePlant<'a> {
    fn new(model: &'a Model, limits: &Limits) -> FreePlant<'a> {
        let params_in_state = (model.invar.iter())
            .chain(&model.fairness)
            .chain(&model.init)
            .map(|c| &c.expr)
            .chain(model.vars.iter().filter_map(|v| v.init.as_ref()))
            .any(|e| explicit::reads_params(model, e));
        FreePlant {
            sem: Semantics::new(model),
            params_in_state,
            keys: Vec::new(),
            index: FxHashMap::default(),
            fair: Vec::new(),
            limits: *limits,
            bytes: 0,
        }
    }

    fn all_params(&self) -> impl Iterator<Item = u64> {
        0..1u64 << self.sem.model().params.len()
    }

    fn intern(&mut self, s: Vec<Value>, o: u64) -> Result<u32, CheckError> {
        let key = (
            s.into_boxed_slice(),
            if self.params_in_state { o } else { 0 },
        );
        if let Some(&i) = self.index.get(&key) {
            return Ok(i);
        }
        if self.keys.len() >= self.limits.max_states {
            return Err(CheckError::TooManyStates {
                limit: self.limits.max_states,
            });
        }
        // Two copies of the key (list and table) and the table entry.
        self.bytes += 2 * std::mem::size_of_val(&*key.0) + CLOSED_STATE_BYTES;
        if self.bytes > self.limits.max_bytes / 2 {
            return Err(CheckError::TooMuchMemory {
                limit: self.limits.max_bytes / 2,
                what: "the plant's states",
            });
        }
        let n = self.sem.model().params.len();
        let fair = self
            .sem
            .fairness(&key.0, &explicit::params_from_bits(key.1, n))?;
        let i = self.keys.len() as u32;
        self.index.insert(key.clone(), i);
        self.keys.push(key);
        self.fair.push(fair);
        Ok(i)
    }
}

impl Graph for FreePlant<'_> {
    type Error = CheckError;
    fn initial(&mut self) -> Result<Vec<u32>, CheckError> {
        let n = self.sem.model().params.len();
        let mut out = Vec::new();
        for o in self.all_params() {
            for s in self.sem.initial_states(&explicit::params_from_bits(o, n))? {
                let i = self.intern(s, o)?;
                out.push(i);
            }
        }
        out.sort_unstable();
        out.dedup();
        Ok(out)
    }
    fn successors(&mut self, node: u32, out: &mut Vec<u32>) -> Result<(), CheckError> {
        let n = self.sem.model().params.len();
        let (s, o) = self.keys[node as usize].clone();
        let current: Vec<u64> = if self.params_in_state {
            vec![o]
        } else {
            self.all_params().collect()
        };
        let next: Vec<u64> = if self.params_in_state {
            self.all_params().collect()
        } else {
            vec![0]
        };
        for &p in &current {
            let params = explicit::params_from_bits(p, n);
            for &q in &next {
                let next_params = explicit::params_from_bits(q, n);
                let sem = self.sem.clone();
                sem.for_each_successor(&s, &params, &next_params, &mut |t| {
                    out.push(self.intern(t.to_vec(), q)?);
                    Ok::<(), CheckError>(())
                })?;
            }
        }
        out.sort_unstable();
        out.dedup();
        Ok(())
    }
    fn marks(&self, n: u32) -> u64 {
        self.fair[n as usize]
    }
    fn too_large(&self, bytes: usize) -> CheckError {
        CheckError::TooMuchMemory {
            limit: bytes,
            what: "the search for a fair path of the plant",
        }
    }
}

/// Why an atom could not be evaluated on a state.
pub(crate) enum AtomError {
    Eval(EvalError),
    Type(String),
}

impl From<EvalError> for AtomError {
    fn from(e: EvalError) -> AtomError {
        AtomError::Eval(e)
    }
}

/// Where the value of a name comes from.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Source {
    Output(usize),
    Plant(Name),
    Const(Value),
}

/// An LTL atom resolved against the closed loop.
#[derive(Debug, Clone)]
pub(crate) enum Atom {
    Bool(Source, String),
    Cmp(CmpOp, Source, Source, String),
}

impl Atom {
    /// The sources the atom reads.
    pub(crate) fn sources(&self) -> Vec<Source> {
        match self {
            Atom::Bool(s, _) => vec![*s],
            Atom::Cmp(_, l, r, _) => vec![*l, *r],
        }
    }

    pub(crate) fn resolve(a: &Ltl, model: &Model, coupling: &Wiring) -> Result<Atom, String> {
        let name = |n: &str| -> Option<Source> {
            if let Some(z) = coupling.outputs.iter().position(|o| o == n) {
                return Some(Source::Output(z));
            }
            match model.lookup(n) {
                Some(v @ (Name::Var(_) | Name::Define(_))) => Some(Source::Plant(v)),
                _ => None,
            }
        };
        let unknown = |n: &str| {
            format!("unknown name '{n}': neither a controller output nor a variable or define of the plant")
        };
        match a {
            Ltl::Atom(n) => Ok(Atom::Bool(
                name(n).ok_or_else(|| unknown(n))?,
                a.to_string(),
            )),
            Ltl::Cmp(op, l, r) => {
                let var_left = matches!(**l, Ltl::Atom(_));
                let operand = |side: &Ltl, is_var: bool| -> Result<Source, String> {
                    Ok(match side {
                        Ltl::Atom(n) if is_var => name(n).ok_or_else(|| unknown(n))?,
                        Ltl::Atom(n) => match name(n) {
                            Some(s) => s,
                            None => Source::Const(
                                model
                                    .symbol(n)
                                    .ok_or_else(|| format!("unknown name or constant '{n}'"))?,
                            ),
                        },
                        Ltl::Int(i) => Source::Const(Value::Int(*i)),
                        Ltl::True => Source::Const(Value::Bool(true)),
                        Ltl::False => Source::Const(Value::Bool(false)),
                        other => return Err(format!("'{other}' cannot be compared")),
                    })
                };
                Ok(Atom::Cmp(
                    *op,
                    operand(l, var_left)?,
                    operand(r, !var_left)?,
                    a.to_string(),
                ))
            }
            other => Err(format!("'{other}' is not an atom")),
        }
    }

    fn holds(&self, c: &ExplicitLoop, k: &Key, params: &[bool]) -> Result<bool, AtomError> {
        self.holds_on(&c.sem, &c.plants[k.plant as usize], k.outputs, params)
    }

    /// The atom on plant state `plant` with controller outputs `outputs` (bits) and the plant
    /// parameters they make.
    pub(crate) fn holds_on(
        &self,
        sem: &Semantics,
        plant: &[Value],
        outputs: u64,
        params: &[bool],
    ) -> Result<bool, AtomError> {
        let value = |s: Source| -> Result<Value, AtomError> {
            Ok(match s {
                Source::Output(z) => Value::Bool(outputs >> z & 1 == 1),
                Source::Plant(n) => sem.read(n, plant, params)?,
                Source::Const(v) => v,
            })
        };
        let model = sem.model();
        match self {
            Atom::Bool(s, text) => match value(*s)? {
                Value::Bool(b) => Ok(b),
                v => Err(AtomError::Type(format!(
                    "'{text}' is {}, not TRUE or FALSE",
                    model.show(v)
                ))),
            },
            Atom::Cmp(op, l, r, text) => {
                let (x, y) = (value(*l)?, value(*r)?);
                match (x, y) {
                    (Value::Int(a), Value::Int(b)) => Ok(match op {
                        CmpOp::Eq => a == b,
                        CmpOp::Ne => a != b,
                        CmpOp::Lt => a < b,
                        CmpOp::Le => a <= b,
                        CmpOp::Gt => a > b,
                        CmpOp::Ge => a >= b,
                    }),
                    _ if op.is_ordering() => Err(AtomError::Type(format!(
                        "'{text}' orders {} and {}, which are not both integers",
                        model.show(x),
                        model.show(y)
                    ))),
                    (Value::Bool(_), Value::Bool(_))
                    | (Value::Int(_) | Value::Sym(_), Value::Int(_) | Value::Sym(_)) => {
                        Ok((x == y) == (*op == CmpOp::Eq))
                    }
                    _ => Err(AtomError::Type(format!(
                        "'{text}' compares {} with {}",
                        model.show(x),
                        model.show(y)
                    ))),
                }
            }
        }
    }
}
