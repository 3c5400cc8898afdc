//! The properties inside the synthesis: which properties the SAT encoding can carry for a
//! problem, and counterexamples turned into the environments it is unrolled along
//! ([`crate::sat::closed_loop`]).
//!
//! In: a [`Problem`] with a plant model the tool can run, the scenario set (the controller's
//! interface). Out: a [`LoopEncoding`]: the encoding's [`Spec`] and, per property, whether it is
//! encoded or why not. A property that is not encoded is still checked by NuSMV, and its
//! counterexamples still come back as negative scenarios.

use crate::ecc::ident::{parse_smv_value, SmvValue};
use crate::ltl::Ltl;
use crate::plant::{Model, Value};
use crate::sat::closed_loop::{self, Environment, Spec};
use crate::scenario::negative::NegativeScenario;
use crate::scenario::ScenarioSet;
use crate::verify::{Counterexample, Problem};
use std::collections::BTreeMap;
use std::sync::Arc;

/// Steps within which the encoding requires eventualities to be fulfilled when none is given.
pub(crate) const DEFAULT_RESPONSE_BOUND: usize = 32;

/// The encoding's view of a problem.
#[derive(Debug, Clone)]
pub(crate) struct LoopEncoding {
    /// How plant, machine and the encoded properties fit together in the SAT encoding.
    pub(crate) spec: Arc<Spec>,
    /// Per property (spec order): `Ok(())` if encoded, else why not.
    pub(crate) coverage: Vec<Result<(), String>>,
    /// The wiring for the in-process checker ([`crate::check`]).
    pub(crate) coupling: crate::check::Wiring,
}

impl LoopEncoding {
    /// The encoding's view of `problem` for a controller over `set`'s interface; `Err` says
    /// why no property can be encoded (the plant is outside the subset, ...).
    pub(crate) fn new(
        problem: &Problem,
        set: &ScenarioSet,
        response_bound: usize,
    ) -> Result<LoopEncoding, String> {
        let model = problem.model.clone()?;
        closed_loop::plant::encodable(&model)
            .map_err(|c| format!("the plant uses {c}, which the encoding does not cover"))?;
        let coupling =
            crate::check::Wiring::new(&model, &problem.coupling).map_err(|e| e.to_string())?;
        let mut spec = Spec {
            plant: model,
            inputs: coupling.inputs.clone(),
            params: coupling.params.clone(),
            outputs: set.outputs.clone(),
            properties: Vec::new(),
            response_bound,
            initial_outputs: set.initial_outputs.clone(),
        };
        let coverage: Vec<Result<(), String>> = problem
            .props
            .iter()
            .map(|p| {
                if !closed_loop::property::covered(&p.formula) {
                    return Err("past operators are not encoded".to_string());
                }
                if let Some(n) = p
                    .formula
                    .names()
                    .into_iter()
                    .find(|n| !closed_loop::resolves(&spec, n))
                {
                    return Err(format!("'{n}' is not a name of the closed loop"));
                }
                if !closed_loop::property::is_safety(&p.formula, &|n| {
                    closed_loop::is_environment(&spec, n)
                }) {
                    // Bounded eventualities unrolled along every environment make the
                    // encoding too large to solve in seconds on plants like Pick-and-Place;
                    // NuSMV's lassos come back as negative scenarios instead.
                    return Err(
                        "a liveness property: its counterexamples come back as negative scenarios"
                            .to_string(),
                    );
                }
                Ok(())
            })
            .collect();
        spec.properties = problem
            .props
            .iter()
            .zip(&coverage)
            .filter(|(_, c)| c.is_ok())
            .map(|(p, _)| p.formula.clone())
            .collect();
        // Safety properties need no response bound: only as many steps past the environment
        // as their deepest `X`, for the step a counterexample violates to be read. Every step
        // more is a copy of machine and plant in the solver (with the response bound's steps
        // the Pick-and-Place loop from four scenarios takes far longer).
        if spec.properties.iter().all(|p| {
            closed_loop::property::is_safety(p, &|n| closed_loop::is_environment(&spec, n))
        }) {
            spec.response_bound = spec
                .properties
                .iter()
                .map(Ltl::next_depth)
                .max()
                .unwrap_or(0);
        }
        Ok(LoopEncoding {
            spec: Arc::new(spec),
            coverage,
            coupling,
        })
    }

    /// Whether the property at `index` (spec order) is encoded.
    pub(crate) fn encodes(&self, index: usize) -> bool {
        self.coverage.get(index).is_some_and(|c| c.is_ok())
    }

    /// The environment of a NuSMV counterexample: the plant's state at every step, read from
    /// the trace (`plant.x` or the alias `x`). `None` if the trace lacks a variable.
    pub(crate) fn environment(&self, cx: &Counterexample) -> Option<Environment> {
        let model = &self.spec.plant;
        let end = match cx.violation_at {
            Some(k) => k + 1,
            None => cx.states.len(),
        };
        let states = cx.states[..end.min(cx.states.len())]
            .iter()
            .map(|s| plant_state(model, s))
            .collect::<Option<Vec<_>>>()?;
        if states.is_empty() {
            return None;
        }
        let loop_start = match cx.violation_at {
            Some(_) => states.len() - 1,
            None => cx.loop_start.min(states.len() - 1),
        };
        Some(Environment { states, loop_start })
    }
}

/// The controller's side of an in-process counterexample to `property` (see
/// [`crate::check::Wiring::negative`]). For properties the encoding does not carry.
pub(crate) fn negative_of(
    closed: &LoopEncoding,
    lasso: &crate::check::Lasso,
    property: &str,
) -> Result<NegativeScenario, crate::check::CheckError> {
    closed
        .coupling
        .negative(&closed.spec.plant, lasso, property)
}

/// The environment of an in-process counterexample.
pub(crate) fn environment_of(lasso: &crate::check::Lasso) -> Environment {
    Environment {
        states: lasso.states.iter().map(|s| s.plant.clone()).collect(),
        loop_start: lasso.loop_start,
    }
}

fn plant_state(model: &Model, s: &BTreeMap<String, String>) -> Option<Vec<Value>> {
    model
        .vars
        .iter()
        .map(|v| {
            let text = s
                .get(&format!(
                    "{}.{}",
                    crate::smv::composition::PLANT_INSTANCE,
                    v.name
                ))
                .or_else(|| s.get(&v.name))?;
            parse_value(model, text)
        })
        .collect()
}

/// A value of a NuSMV trace as a value of `model` (a symbol must be one of its constants).
fn parse_value(model: &Model, text: &str) -> Option<Value> {
    match parse_smv_value(text) {
        SmvValue::Bool(b) => Some(Value::Bool(b)),
        SmvValue::Int(i) => Some(Value::Int(i)),
        SmvValue::Symbol(s) => model.symbol(s),
    }
}
