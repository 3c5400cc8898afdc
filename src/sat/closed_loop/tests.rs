use super::*;
use crate::ecc::Run;
use crate::ltl::parse_spec;
use crate::plant::{Expr, Model, Type, Var, VarId};
use crate::sat::{Options, SatError, Synthesizer};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::{Origin, Scenario, ScenarioSet, Step};
use std::path::Path;

/// A lamp that follows the controller output `on` one step late, and a button the operator
/// presses at will.
fn lamp() -> Model {
    let boolean = |name: &str, init: Option<Expr>, next: Option<Expr>| Var {
        name: name.into(),
        ty: Type::Bool,
        kind: VarKind::State,
        line: 1,
        domain: vec![Value::Bool(false), Value::Bool(true)],
        init,
        next,
    };
    Model {
        file: "lamp.smv".into(),
        params: vec!["on".into()],
        vars: vec![
            boolean("button", None, None),
            boolean(
                "lamp",
                Some(Expr::Const(Value::Bool(false))),
                Some(Expr::Param(crate::plant::ParamId(0))),
            ),
        ],
        defines: vec![],
        init: vec![],
        invar: vec![],
        trans: vec![],
        fairness: vec![],
        symbols: vec![],
    }
}

/// Recorded: the button never pressed, the lamp never lit.
fn idle_recording() -> ScenarioSet {
    ScenarioSet {
        inputs: vec!["button".into()],
        outputs: vec!["on".into()],
        initial_outputs: vec![false],
        scenarios: vec![Scenario {
            origin: Origin {
                file: "idle".into(),
                line: 1,
                rows: None,
            },
            steps: vec![
                Step {
                    inputs: vec![false],
                    outputs: None,
                };
                3
            ],
        }],
    }
}

fn spec(formulas: &str) -> Arc<Spec> {
    let props = parse_spec(Path::new("lamp.ltl"), formulas).unwrap();
    Arc::new(Spec {
        plant: Arc::new(lamp()),
        inputs: vec![Name::Var(VarId(0))],
        params: vec![0],
        outputs: vec!["on".into()],
        properties: props.into_iter().map(|p| p.formula).collect(),
        response_bound: 4,
        initial_outputs: vec![false],
    })
}

/// The button pressed once, at step 1.
fn one_press() -> Environment {
    let s = |button: bool| vec![Value::Bool(button), Value::Bool(false)];
    Environment {
        states: vec![s(false), s(true), s(false)],
        loop_start: 2,
    }
}

fn options() -> Options {
    Options {
        max_out_degree: Some(2),
        max_states: 3,
        ..Options::default()
    }
}

/// The lamp's closed loop simulated directly: the lamp value at every step of `presses`.
fn lamp_run(ecc: &crate::ecc::Ecc, presses: &[bool]) -> Vec<bool> {
    let mut run = Run::new(ecc);
    let mut lamp = false;
    let mut out = Vec::new();
    for &b in presses {
        out.push(lamp);
        let on = run.outputs[0];
        run.step(&[b]);
        lamp = on;
    }
    out
}

/// The recording alone gives the machine with no transition; the property on the press
/// environment forces a machine that lights the lamp two steps after the press.
#[test]
fn environment_forces_the_reaction_the_recording_lacks() {
    let set = idle_recording();
    let tree = ScenarioTree::build(&set).unwrap();
    let mut synth = Synthesizer::new(&set, &tree, &options());
    let alone = synth.minimize(&mut |_| {}).unwrap();
    assert_eq!(alone.size.t, 0);
    let spec = spec("G (button -> X X lamp)");
    synth.add_environment(&spec, one_press()).unwrap();
    let s = synth.minimize(&mut |_| {}).unwrap();
    assert!(s.size.t >= 1, "{:?}", s.ecc);
    let lamp = lamp_run(&s.ecc, &[false, true, false, false]);
    assert_eq!(lamp, vec![false, false, false, true], "{:?}", s.ecc);
}

/// The same property written with other operators (equivalence, exclusive or, until,
/// release, and negations that turn one into its dual) forces the same reaction.
#[test]
fn dual_forms_of_one_property_force_the_same_reaction() {
    let p = "(button -> X X lamp)";
    for formula in [
        format!("G ({p} <-> TRUE)"),
        format!("G !({p} xor TRUE)"),
        format!("!F !{p}"),
        format!("!(TRUE U !{p})"),
        format!("FALSE V {p}"),
        format!("!!G {p}"),
    ] {
        let set = idle_recording();
        let tree = ScenarioTree::build(&set).unwrap();
        let mut synth = Synthesizer::new(&set, &tree, &options());
        synth.add_environment(&spec(&formula), one_press()).unwrap();
        let s = synth.minimize(&mut |_| {}).unwrap();
        let lamp = lamp_run(&s.ecc, &[false, true, false, false]);
        assert_eq!(
            lamp,
            vec![false, false, false, true],
            "{formula}: {:?}",
            s.ecc
        );
    }
}

/// A property no machine can satisfy on the environment: no machine at any size.
#[test]
fn contradictory_property_leaves_no_machine() {
    let set = idle_recording();
    let tree = ScenarioTree::build(&set).unwrap();
    let mut synth = Synthesizer::new(&set, &tree, &options());
    let spec = spec("G (button -> X X lamp)\nG !lamp");
    synth.add_environment(&spec, one_press()).unwrap();
    assert!(matches!(
        synth.minimize(&mut |_| {}),
        Err(SatError::TooManyStates { .. })
    ));
}

/// An eventuality beyond the response bound is not required; within it, it is.
#[test]
fn eventualities_are_strong_up_to_the_deadline() {
    let set = idle_recording();
    let tree = ScenarioTree::build(&set).unwrap();
    let mut synth = Synthesizer::new(&set, &tree, &options());
    let spec = spec("G (button -> F lamp)");
    synth.add_environment(&spec, one_press()).unwrap();
    let s = synth.minimize(&mut |_| {}).unwrap();
    let lamp = lamp_run(&s.ecc, &[false, true, false, false, false, false, false]);
    assert!(lamp.iter().any(|&l| l), "{:?}", s.ecc);
}

/// An assumption on the environment alone is evaluated exactly: with the button pressed
/// only once, `G F button` is false, so the implication asks nothing.
#[test]
fn environment_assumptions_are_exact() {
    let set = idle_recording();
    let tree = ScenarioTree::build(&set).unwrap();
    let mut synth = Synthesizer::new(&set, &tree, &options());
    let spec = spec("(G F button) -> G (button -> X X lamp)\nG !lamp");
    synth.add_environment(&spec, one_press()).unwrap();
    let s = synth.minimize(&mut |_| {}).unwrap();
    assert_eq!(s.size.t, 0);
}

#[test]
fn the_encoding_alone_excludes_machines_that_miss_the_press() {
    use varisat::{CnfFormula, Solver};
    let set = idle_recording();
    let tree = ScenarioTree::build(&set).unwrap();
    let mut f = CnfFormula::new();
    let vars = crate::sat::vars::Vars::new(&mut f, &tree, 1, Some(1));
    let crate::sat::vars::GuardModel::Cubes(cv) = &vars.guards else {
        panic!()
    };
    let spec = spec("G (button -> X X lamp)");
    encode(&mut f, &vars, cv, &spec, &one_press());
    // The machine with no transition must be excluded.
    let mut s = Solver::new();
    s.add_formula(&f);
    s.assume(&[!cv.en(0, 0, 0)]);
    assert!(!s.solve().unwrap(), "no-transition machine allowed");
    s.assume(&[
        cv.en(0, 0, 0),
        cv.tgt(0, 0, 0, 0),
        cv.pos(0, 0, 0, 0),
        !vars.a(0, 0, false),
    ]);
    assert!(!s.solve().unwrap(), "keep machine allowed");
}

/// `spec(formulas)` over the lamp with the defines `(name, expression)` added.
fn spec_with_defines(formulas: &str, defines: &[(&str, Expr)]) -> Arc<Spec> {
    let mut s = (*spec(formulas)).clone();
    let mut plant = lamp();
    for (name, expr) in defines {
        plant.defines.push(crate::plant::Define {
            name: name.to_string(),
            line: 1,
            expr: expr.clone(),
        });
    }
    s.plant = Arc::new(plant);
    Arc::new(s)
}

/// A define on the right of a comparison is read like any other name: with `k := lamp`,
/// `lamp != k` is false at every step, so no machine satisfies `G (lamp != k)`, while
/// `G (lamp = k)` rules nothing out.
#[test]
fn a_define_compared_with_a_variable_is_read() {
    let k = [("k", Expr::Var(VarId(1)))];
    let set = idle_recording();
    let tree = ScenarioTree::build(&set).unwrap();
    let mut synth = Synthesizer::new(&set, &tree, &options());
    synth
        .add_environment(&spec_with_defines("G (lamp != k)", &k), one_press())
        .unwrap();
    assert!(matches!(
        synth.minimize(&mut |_| {}),
        Err(SatError::TooManyStates { .. })
    ));
    let mut synth = Synthesizer::new(&set, &tree, &options());
    let spec = spec_with_defines("G (lamp = k)\nG (button -> X X lamp)", &k);
    synth.add_environment(&spec, one_press()).unwrap();
    let s = synth.minimize(&mut |_| {}).unwrap();
    let lamp = lamp_run(&s.ecc, &[false, true, false, false]);
    assert_eq!(lamp, vec![false, false, false, true], "{:?}", s.ecc);
}

/// A comparison of a free input with a define is not the environment's alone, even when the
/// define only renames the input: `button = pressed` holds at every step, so `G (button =
/// pressed)` leaves the recording's machine.
#[test]
fn a_define_of_a_free_input_is_no_constant_of_the_environment() {
    let pressed = [("pressed", Expr::Var(VarId(0)))];
    let set = idle_recording();
    let tree = ScenarioTree::build(&set).unwrap();
    let mut synth = Synthesizer::new(&set, &tree, &options());
    let spec = spec_with_defines("G (button = pressed)", &pressed);
    synth.add_environment(&spec, one_press()).unwrap();
    let s = synth.minimize(&mut |_| {}).unwrap();
    assert_eq!(s.size.t, 0, "{:?}", s.ecc);
}

/// One formula parsed.
fn formula(text: &str) -> Ltl {
    parse_spec(Path::new("t.ltl"), text)
        .unwrap()
        .remove(0)
        .formula
}

/// The safety part of `text`, `p` the environment's only name.
fn safety_part_of(text: &str) -> Option<Ltl> {
    property::safety_part(&formula(text), &|n| n == "p")
}

#[test]
fn a_held_piece_is_not_dropped_before_it_is_placed() {
    assert_eq!(
        safety_part_of("G (vac -> (vac U placed))"),
        Some(formula("G (vac -> (placed V (vac | placed)))"))
    );
}

#[test]
fn a_response_has_no_safety_part() {
    assert_eq!(safety_part_of("G (a -> F b)"), None);
    assert_eq!(safety_part_of("(F G !p) -> G (a -> F b)"), None);
    // Past operators are not encoded, so neither is a part of them.
    assert_eq!(safety_part_of("G (a -> (a U Y b))"), None);
}

#[test]
fn eventualities_in_negative_position_are_made_weak_too() {
    // `!(a V b)` is `!a U !b`: its weak form is the negation of `b U (a & b)`.
    assert_eq!(
        safety_part_of("G ((a V b) -> X c)"),
        Some(formula("G ((b U (a & b)) -> X c)"))
    );
    // `!(G a)` is `F !a`: nothing of it stays, nor of the implication.
    assert_eq!(safety_part_of("(G a) -> (b U c)"), None);
    // Environment-only parts are read exactly, so they stay: `G F p` is no eventuality here.
    assert_eq!(
        safety_part_of("(G F p) | G (a -> (a U b))"),
        Some(formula("(G F p) | G (a -> (b V (a | b)))"))
    );
}

#[test]
fn a_safety_property_is_its_own_safety_part() {
    assert_eq!(safety_part_of("G !(a & b)"), Some(formula("G !(a & b)")));
}
