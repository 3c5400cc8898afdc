//! The properties inside the synthesis: which properties the SAT encoding can carry for a
//! problem, and counterexamples turned into the environments it is unrolled along
//! ([`crate::sat::closed_loop`]).
//!
//! In: a [`Problem`] with a plant model the tool can run, the scenario set (the controller's
//! interface). Out: a [`LoopEncoding`]: the encoding's [`Spec`] and, per property, whether it is
//! encoded or why not. A property that is not encoded is still checked by NuSMV, and its
//! counterexamples still come back as negative scenarios; a liveness property over the plant
//! alone has its safety part encoded and checked beside it.

use crate::ecc::ident::{parse_smv_value, SmvValue};
use crate::ltl::{Ltl, Property};
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
    /// Per property of [`Self::checked`]: `Ok(())` if encoded, else why not.
    pub(crate) coverage: Vec<Result<(), Uncovered>>,
    /// What the in-process checker judges a candidate on: the problem's properties (spec
    /// order), then the safety part of each liveness property that has one
    /// ([`closed_loop::property::safety_part`]), encoded and checked so that its
    /// counterexamples come back as environments. Every run that satisfies a property
    /// satisfies its safety part, so no verified machine is ruled out.
    pub(crate) checked: Vec<Property>,
    /// The names of [`Self::checked`].
    pub(crate) names: Vec<String>,
    /// How many of [`Self::checked`] are the problem's own.
    pub(crate) own: usize,
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
        let mut coverage: Vec<Result<(), Uncovered>> = (problem.props.iter())
            .map(|p| coverage_of(&spec, &p.formula))
            .collect();
        let mut checked = problem.props.clone();
        let mut names = problem.property_names();
        for (k, p) in problem.props.iter().enumerate() {
            if let Some(part) = safety_part(&spec, p, &coverage[k]) {
                names.push(format!("{} (its safety part)", names[k]));
                checked.push(part);
                coverage.push(Ok(()));
            }
        }
        spec.properties = (checked.iter().zip(&coverage))
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
            own: problem.props.len(),
            checked,
            names,
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

/// Why the encoding does not carry a property.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(crate) enum Uncovered {
    /// It has past operators.
    #[error("past operators are not encoded")]
    Past,
    /// It reads a name that is not one of the closed loop's.
    #[error("'{0}' is not a name of the closed loop")]
    Name(String),
    /// A liveness property: bounded eventualities unrolled along every environment make the
    /// encoding too large to solve in seconds on plants like Pick-and-Place; NuSMV's lassos
    /// come back as negative scenarios instead, and the property's safety part is encoded.
    #[error("a liveness property: its counterexamples come back as negative scenarios")]
    Liveness,
}

/// Whether the encoding carries `formula` on `spec`'s closed loop, or why not.
fn coverage_of(spec: &Spec, formula: &Ltl) -> Result<(), Uncovered> {
    if !closed_loop::property::covered(formula) {
        return Err(Uncovered::Past);
    }
    if let Some(n) = (formula.names().into_iter()).find(|n| !closed_loop::resolves(spec, n)) {
        return Err(Uncovered::Name(n));
    }
    if !closed_loop::property::is_safety(formula, &|n| closed_loop::is_environment(spec, n)) {
        return Err(Uncovered::Liveness);
    }
    Ok(())
}

/// The safety part of the liveness property `p` (not encoded for `why`), as a property of its
/// own at `p`'s line, when `p` reads the plant alone; `None` for a property encoded, outside
/// the encoding for another reason, reading a controller output, or whose safety part says
/// nothing.
///
/// Only over the plant: there a counterexample's environment carries what the plant does
/// under the machine's commands (Pick-and-Place's held piece, `vac`, which only the plant
/// sets), which no negative scenario conveys; from four recorded scenarios the loop needs 9
/// candidates where the lassos alone need 17 to 20. A safety part over the controller's own
/// outputs (a generated station's "an extending cylinder keeps extending until its end") is
/// left out: on the stations its environments make each SAT call slower without sparing
/// candidates (station 5: 28 s with it, 8 s without).
fn safety_part(spec: &Spec, p: &Property, why: &Result<(), Uncovered>) -> Option<Property> {
    let over_plant = (p.formula.names().iter()).all(|n| !spec.outputs.contains(n));
    if *why != Err(Uncovered::Liveness) || !over_plant {
        return None;
    }
    let env = |n: &str| closed_loop::is_environment(spec, n);
    let formula = closed_loop::property::safety_part(&p.formula, &env)?;
    Some(Property {
        label: None,
        text: formula.to_string(),
        formula,
        line: p.line,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::names::read_names;
    use std::path::Path;

    /// The encoding's view of `ltl` (a spec text) on Pick-and-Place's surrogate plant.
    fn pick_and_place(ltl: &str) -> LoopEncoding {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let dir = tempfile::tempdir().unwrap();
        let spec = dir.path().join("p.ltl");
        std::fs::write(&spec, ltl).unwrap();
        let names = |f: &str| read_names(&root.join(f)).unwrap();
        let (inputs, outputs) = (names("specs/pnp.inputs"), names("specs/pnp.outputs"));
        let plant = root.join("smv/pnp_surrogate.smv");
        let problem = Problem::load(&spec, &plant, &inputs, &outputs).unwrap();
        let set = ScenarioSet {
            initial_outputs: vec![false; outputs.len()],
            inputs,
            outputs,
            scenarios: Vec::new(),
        };
        LoopEncoding::new(&problem, &set, DEFAULT_RESPONSE_BOUND).unwrap()
    }

    #[test]
    fn a_liveness_property_over_the_plant_has_its_safety_part_encoded() {
        let closed = pick_and_place(
            "c1_exclusive: G !(c1Extend & c1Retract)\n\
             held_until_placed: G (vac -> (vac U placed))\n\
             track1_served: G (pp1 -> F vp1)\n",
        );
        assert_eq!(closed.own, 3);
        assert_eq!(closed.checked.len(), 4);
        assert_eq!(closed.names[3], "held_until_placed (its safety part)");
        assert_eq!(
            closed.checked[3].formula.to_string(),
            "G (vac -> placed V (vac | placed))"
        );
        let encoded: Vec<bool> = (0..4).map(|k| closed.encodes(k)).collect();
        assert_eq!(encoded, [true, false, false, true]);
        assert_eq!(closed.spec.properties.len(), 2);
    }

    #[test]
    fn a_liveness_property_over_an_output_has_none() {
        // The controller's own output: its answers already show what the safety part says.
        let closed = pick_and_place("held_on: G (vacuum_on -> (vacuum_on U placed))\n");
        assert_eq!((closed.own, closed.checked.len()), (1, 1));
        assert!(closed.spec.properties.is_empty());
    }
}
