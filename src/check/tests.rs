//! Tests of the in-process checker: hand-made plants with known verdicts, the Pick-and-Place
//! plant with its reference controller, and a differential test against NuSMV on random
//! plants, controllers and properties.

use super::*;
use crate::ecc::{Algorithm, Guard, InputId, State, Transition, Tri};
use crate::plant::{BinOp, Constraint, Expr, ParamId, VarId};
use std::path::Path;

use crate::plant::build::*;

fn prop(text: &str) -> Property {
    crate::ltl::parse_spec(Path::new("t.ltl"), text)
        .unwrap()
        .remove(0)
}

/// A lamp the controller switches: `lamp` follows `on` one step later; a free button `b`.
fn lamp() -> Model {
    let mut b = Builder::new(&["on"]);
    let lamp = b.var("lamp", Type::Bool);
    let button = b.var("button", Type::Bool);
    b.init(&lamp, bool(false));
    let on = b.param("on");
    b.next(&lamp, on);
    let _ = button;
    b.m
}

/// A toggle controller: `button` pressed switches `on`.
fn toggle() -> Ecc {
    let pressed = Guard::Var(InputId(0));
    let state = |name: &str, out: Tri, target: usize| State {
        name: name.into(),
        algorithm: Algorithm::Tri(vec![out]),
        transitions: vec![Transition {
            target: StateId(target),
            guard: pressed.clone(),
        }],
    };
    Ecc {
        inputs: vec!["button".into()],
        outputs: vec!["on".into()],
        initial_outputs: vec![false],
        states: vec![state("off", Tri::Zero, 1), state("on", Tri::One, 0)],
    }
}

fn verdicts(model: &Model, ecc: &Ecc, texts: &[&str]) -> Vec<ExplicitVerdict> {
    let coupling = Wiring::of_model(model, &ecc.inputs, &ecc.outputs).unwrap();
    let props: Vec<Property> = texts.iter().map(|t| prop(t)).collect();
    check(model, &coupling, ecc, &props, &Limits::default()).unwrap()
}

#[test]
fn lamp_verdicts_and_counterexamples() {
    let (m, e) = (lamp(), toggle());
    let v = verdicts(
        &m,
        &e,
        &[
            "G (on -> X lamp)",
            "G (lamp -> on | X !lamp)",
            "F lamp",
            "G !lamp",
            "G (button & !on -> X on)",
            "Y lamp",
        ],
    );
    assert_eq!(v[0], ExplicitVerdict::Holds);
    assert_eq!(v[1], ExplicitVerdict::Holds);
    let ExplicitVerdict::Violated(l) = &v[2] else {
        panic!("F lamp is violated: the button may never be pressed")
    };
    assert!(l.states.iter().all(|s| s.plant[0] == Value::Bool(false)));
    assert!(matches!(v[3], ExplicitVerdict::Violated(_)));
    assert_eq!(v[4], ExplicitVerdict::Holds);
    assert!(matches!(&v[5], ExplicitVerdict::Unsupported(why) if why.contains("past")));
}

/// "Every property holds" stops at the first that does not, and says what the verdicts say:
/// for each prefix of the lamp's properties (an unsupported one counts as not holding).
#[test]
fn all_hold_says_what_the_verdicts_say() {
    let (m, e) = (lamp(), toggle());
    let texts = [
        "G (on -> X lamp)",
        "G (lamp -> on | X !lamp)",
        "F lamp",
        "Y lamp",
    ];
    let coupling = Wiring::of_model(&m, &e.inputs, &e.outputs).unwrap();
    for k in 0..=texts.len() {
        let props: Vec<Property> = texts[..k].iter().map(|t| prop(t)).collect();
        let automata = Automata::of(&props);
        let limits = Limits::default();
        let mut memo = PlantMemo::default();
        let all = Judge::of(&m, &coupling, &e, &limits, &mut memo)
            .and_then(|j| j.all_hold(&props, &automata));
        let v = check(&m, &coupling, &e, &props, &limits).unwrap();
        let expected = v.iter().all(|v| *v == ExplicitVerdict::Holds);
        assert_eq!(all.unwrap(), expected, "{:?}", &texts[..k]);
        assert_eq!(expected, k <= 2);
    }
}

#[test]
fn fairness_restricts_the_paths() {
    let mut m = lamp();
    m.fairness.push(Constraint {
        line: 9,
        expr: Expr::Var(VarId(1)),
    });
    // With the button pressed infinitely often, the lamp is lit infinitely often.
    let v = verdicts(&m, &toggle(), &["G F lamp", "F G lamp"]);
    assert_eq!(v[0], ExplicitVerdict::Holds);
    let ExplicitVerdict::Violated(l) = &v[1] else {
        panic!("F G lamp is violated")
    };
    let pressed_in_loop = l.states[l.loop_start..]
        .iter()
        .any(|s| s.plant[1] == Value::Bool(true));
    assert!(pressed_in_loop, "the counterexample is a fair path");
}

#[test]
fn no_behaviour_is_an_error_not_a_vacuous_verdict() {
    let falsum = || Constraint {
        line: 1,
        expr: bool(false),
    };
    let mut dead = Vec::new();
    for what in ["INIT FALSE", "INVAR FALSE", "TRANS FALSE", "FAIRNESS FALSE"] {
        let mut m = lamp();
        match what {
            "INIT FALSE" => m.init.push(falsum()),
            "INVAR FALSE" => m.invar.push(falsum()),
            "TRANS FALSE" => m.trans.push(falsum()),
            _ => m.fairness.push(falsum()),
        }
        dead.push((what, m));
    }
    behaviour(&lamp(), &Limits::default()).unwrap();
    for (what, m) in dead {
        let e = behaviour(&m, &Limits::default()).unwrap_err();
        assert!(matches!(e, CheckError::NoBehaviour { .. }), "{what}: {e}");
        let coupling = Wiring::of_model(&m, &["button".into()], &["on".into()]).unwrap();
        let e = check(
            &m,
            &coupling,
            &toggle(),
            &[prop("G lamp")],
            &Limits::default(),
        )
        .unwrap_err();
        assert!(matches!(e, CheckError::NoBehaviour { .. }), "{what}: {e}");
    }
    // The plant may live while this controller cannot: the lamp must not stay lit.
    let mut m = lamp();
    m.trans.push(Constraint {
        line: 1,
        expr: not(Expr::Param(ParamId(0))),
    });
    behaviour(&m, &Limits::default()).unwrap();
}

#[test]
fn the_state_limit_is_an_error() {
    let (m, e) = (lamp(), toggle());
    let coupling = Wiring::of_model(&m, &e.inputs, &e.outputs).unwrap();
    let err = check(
        &m,
        &coupling,
        &e,
        &[prop("G TRUE")],
        &Limits {
            max_states: 3,
            ..Limits::default()
        },
    )
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "more than 3 reachable states: raise the limit or check with NuSMV"
    );
    assert!(check(
        &m,
        &coupling,
        &e,
        &[prop("G TRUE")],
        &Limits {
            max_states: 8,
            ..Limits::default()
        }
    )
    .is_ok());
}

/// Integers are NuSMV's C `int`s: 32 bits that wrap around, C's `/` and `%` (the values are
/// NuSMV 2.5.4's own). A lamp lit only while `2147483647 + 1 > 0` is never lit, as NuSMV
/// finds.
#[test]
fn integer_arithmetic_wraps_around_as_in_nusmv() {
    use crate::plant::explicit::{eval, Site};
    let m = lamp();
    let state = [Value::Bool(false), Value::Bool(false)];
    let value = |e: Expr| eval(&m, &e, Site::Init(VarId(0)), &state, &[false], None).unwrap();
    let add = |a, b| bin(BinOp::Add, a, b);
    let cases = [
        (
            bin(BinOp::Gt, add(int(2147483647), int(1)), int(0)),
            Value::Bool(false),
        ),
        (bin(BinOp::Mul, int(65536), int(65536)), Value::Int(0)),
        (
            bin(BinOp::Sub, int(-2147483647), int(2)),
            Value::Int(2147483647),
        ),
        (bin(BinOp::Div, int(-7), int(2)), Value::Int(-3)),
        (bin(BinOp::Mod, int(-7), int(2)), Value::Int(-1)),
        (bin(BinOp::Mod, int(7), int(-2)), Value::Int(1)),
        (
            Expr::Neg(Box::new(bin(BinOp::Sub, int(-2147483647), int(1)))),
            Value::Int(-2147483648),
        ),
    ];
    for (e, want) in cases {
        assert_eq!(value(e.clone()), vec![want], "{e:?}");
    }
    let mut b = Builder::new(&["on"]);
    let lamp = b.var("lamp", Type::Bool);
    b.init(&lamp, bool(false));
    let on = b.param("on");
    let never = bin(BinOp::Gt, add(int(2147483647), int(1)), int(0));
    b.next(&lamp, and(vec![on, never]));
    b.var("button", Type::Bool);
    let always_on = Ecc {
        states: vec![State {
            name: "s".into(),
            algorithm: Algorithm::Tri(vec![Tri::One]),
            transitions: vec![],
        }],
        initial_outputs: vec![true],
        ..toggle()
    };
    assert_eq!(
        verdicts(&b.m, &always_on, &["G !lamp"]),
        vec![ExplicitVerdict::Holds]
    );
}

/// Every structure is bounded: twelve free inputs make at least 4096 × 4096 transitions,
/// which the checker refuses before exploring, naming the bound; the same plant with a
/// `TRANS` that fixes the inputs is explored.
#[test]
fn too_many_transitions_are_refused_before_exploring() {
    let plant = |fixed: bool| {
        let mut b = Builder::new(&["on"]);
        let inputs: Vec<Expr> = (0..12)
            .map(|k| b.var(&format!("x{k}"), Type::Bool))
            .collect();
        b.define("button", inputs[0].clone());
        if fixed {
            for x in &inputs {
                b.trans(not(next_of(x)));
            }
        }
        b.m
    };
    let ecc = toggle();
    let m = plant(false);
    let coupling = Wiring::of_model(&m, &ecc.inputs, &ecc.outputs).unwrap();
    let e = check(&m, &coupling, &ecc, &[prop("G TRUE")], &Limits::default()).unwrap_err();
    assert!(e.is_bound(), "{e}");
    assert_eq!(
        e.to_string(),
        "more than 8000000 transitions of the closed loop (at least 4096 × 4096: the plant's \
         free inputs take 4096 combinations of values, and every state has that many \
         successors): raise the limit or check with NuSMV"
    );
    let m = plant(true);
    let coupling = Wiring::of_model(&m, &ecc.inputs, &ecc.outputs).unwrap();
    let v = check(
        &m,
        &coupling,
        &ecc,
        &[prop("G !button")],
        &Limits::default(),
    );
    assert!(
        matches!(v.as_deref(), Ok([ExplicitVerdict::Violated(_)])),
        "{v:?}"
    );
    // A bound on transitions or memory found while exploring is named too.
    let tight = Limits {
        max_transitions: 100,
        ..Limits::default()
    };
    let e = check(&m, &coupling, &ecc, &[prop("G TRUE")], &tight).unwrap_err();
    assert!(
        e.is_bound() && e.to_string().starts_with("more than 100 transitions"),
        "{e}"
    );
    let tight = Limits {
        max_bytes: 1 << 10,
        ..Limits::default()
    };
    let e = check(&m, &coupling, &ecc, &[prop("G TRUE")], &tight).unwrap_err();
    assert!(
        e.is_bound() && e.to_string().starts_with("more than 1024 bytes"),
        "{e}"
    );
}

/// The prediction comes before a single state is enumerated: 24 free inputs take more
/// combinations than one state's successors may enumerate, and the checker refuses them
/// by the bound without trying.
#[test]
fn free_inputs_are_predicted_before_the_initial_states_are_enumerated() {
    let mut b = Builder::new(&["on"]);
    let inputs: Vec<Expr> = (0..24)
        .map(|k| b.var(&format!("x{k}"), Type::Bool))
        .collect();
    b.define("button", inputs[0].clone());
    let m = b.m;
    let ecc = toggle();
    let coupling = Wiring::of_model(&m, &ecc.inputs, &ecc.outputs).unwrap();
    let e = check(&m, &coupling, &ecc, &[prop("G TRUE")], &Limits::default()).unwrap_err();
    assert!(e.is_bound(), "{e}");
    assert!(
        e.to_string()
            .contains("at least 16777216 × 16777216: the plant's free inputs"),
        "{e}"
    );
}

#[test]
fn coupling_mistakes_are_reported() {
    let m = lamp();
    let e = Wiring::of_model(&m, &["lamp_off".into()], &["on".into()]).unwrap_err();
    assert!(
        e.to_string().contains("no variable or define 'lamp_off'"),
        "{e}"
    );
    let e = Wiring::of_model(&m, &["button".into()], &["off".into()]).unwrap_err();
    assert!(
        e.to_string()
            .contains("plant parameter 'on' is not a controller output"),
        "{e}"
    );
    let e = Wiring::of_model(&m, &["button".into()], &["on".into(), "lamp".into()]).unwrap_err();
    assert!(
        e.to_string()
            .contains("'lamp' has the name of a plant variable"),
        "{e}"
    );
    let c = Wiring::of_model(&m, &["button".into()], &["on".into()]).unwrap();
    let e = check(&m, &c, &toggle(), &[prop("G nothing")], &Limits::default()).unwrap_err();
    assert!(e.to_string().contains("unknown name 'nothing'"), "{e}");
}

#[test]
fn evaluation_errors_name_the_construct_and_line() {
    let mut b = Builder::new(&[]);
    let n = b.var("n", Type::Range(0, 3));
    b.init(&n, int(0));
    b.next(&n, bin(BinOp::Add, n.clone(), int(1)));
    let m = b.m;
    let coupling = Wiring::of_model(&m, &[], &[]).unwrap();
    let ecc = Ecc {
        inputs: vec![],
        outputs: vec![],
        initial_outputs: vec![],
        states: vec![State {
            name: "s0".into(),
            algorithm: Algorithm::Tri(vec![]),
            transitions: vec![],
        }],
    };
    let e = check(&m, &coupling, &ecc, &[prop("G TRUE")], &Limits::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "built.smv:2: in next(n): value 4 is outside the type of 'n'"
    );

    let mut b = Builder::new(&[]);
    let n = b.var("n", Type::Range(0, 3));
    let d = b.define("half", bin(BinOp::Div, int(6), n.clone()));
    b.next(&n, case(vec![(eq(d, int(2)), int(3))]));
    let m = b.m;
    let sem = Semantics::new(&m);
    let e = sem.successors(&[Value::Int(0)], &[], &[]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "built.smv:100: in DEFINE half: division by zero"
    );
    let e = sem.successors(&[Value::Int(1)], &[], &[]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "built.smv:2: in next(n): no condition of the case holds"
    );
    assert_eq!(
        sem.successors(&[Value::Int(3)], &[], &[]).unwrap(),
        vec![vec![Value::Int(3)]]
    );
}

#[test]
fn successors_enumerate_sets_free_variables_and_constraints() {
    let mut b = Builder::new(&["u"]);
    let x = b.var("x", Type::Range(0, 2));
    let free = b.var("free", Type::Bool);
    let i = b.ivar("i", Type::Bool);
    let u = b.param("u");
    b.init(&x, set(vec![int(0), int(1)]));
    b.next(
        &x,
        case(vec![
            (u.clone(), set(vec![int(1), int(2)])),
            (bool(true), x.clone()),
        ]),
    );
    // TRANS: the free variable copies the input.
    b.trans(eq(next_of(&free), i.clone()));
    // INVAR, read with the next step's parameters: x = 2 needs u.
    b.invar(bin(BinOp::Implies, eq(x.clone(), int(2)), u));
    // INIT reads a variable: init(free) := x = 1.
    b.init(&free, eq(x.clone(), int(1)));
    let m = b.m;
    let sem = Semantics::new(&m);
    let (f, t) = (Value::Bool(false), Value::Bool(true));
    let init = sem.initial_states(&[false]).unwrap();
    let expect: Vec<Vec<Value>> = vec![
        vec![Value::Int(0), f, f],
        vec![Value::Int(0), f, t],
        vec![Value::Int(1), t, f],
        vec![Value::Int(1), t, t],
    ];
    assert_eq!(init, expect);
    let s = vec![Value::Int(0), f, t];
    let succ = sem.successors(&s, &[true], &[false]).unwrap();
    // x in {1, 2} but x = 2 violates INVAR under u = FALSE; free = i (TRUE) now.
    assert_eq!(
        succ,
        vec![vec![Value::Int(1), t, f], vec![Value::Int(1), t, t]]
    );
    let succ = sem.successors(&s, &[true], &[true]).unwrap();
    assert_eq!(succ.len(), 4);
    // With values known (as a replay knows the next sensors): the successors that show them.
    for known in [
        vec![(VarId(1), t)],
        vec![(VarId(0), Value::Int(2)), (VarId(2), f)],
        vec![(VarId(0), Value::Int(0))],
    ] {
        let shown = |v: &Vec<Value>| known.iter().all(|(k, x)| v[k.0] == *x);
        let filtered: Vec<Vec<Value>> = succ.iter().filter(|v| shown(v)).cloned().collect();
        let succ_known = sem.successors_where(&s, &[true], &[true], &known).unwrap();
        assert_eq!(succ_known, filtered, "{known:?}");
    }
}

#[test]
fn assignments_reading_next_values_are_evaluated_in_the_order_they_read_each_other() {
    // c reads next(b), which reads next(a): declared c, b, a, so the order of evaluation is
    // not the order of declaration.
    let mut b = Builder::new(&["go"]);
    let c = b.var("c", Type::Range(0, 2));
    let x = b.var("b", Type::Bool);
    let a = b.var("a", Type::Bool);
    let go = b.param("go");
    b.next(&a, set(vec![bool(false), bool(true)]));
    b.next(&x, or(vec![next_of(&a), a.clone()]));
    b.next(
        &c,
        case(vec![
            (and(vec![next_of(&x), go]), set(vec![int(1), int(2)])),
            (bool(true), int(0)),
        ]),
    );
    let m = b.m;
    let sem = Semantics::new(&m);
    let (f, t) = (Value::Bool(false), Value::Bool(true));
    let s = vec![Value::Int(0), f, f];
    let expect: Vec<Vec<Value>> = vec![
        vec![Value::Int(0), f, f],
        vec![Value::Int(1), t, t],
        vec![Value::Int(2), t, t],
    ];
    assert_eq!(sem.successors(&s, &[true], &[true]).unwrap(), expect);
    let without_go = sem.successors(&s, &[false], &[false]).unwrap();
    assert_eq!(
        without_go,
        vec![vec![Value::Int(0), f, f], vec![Value::Int(0), t, t]]
    );
    // A value known of a reader, or of what it reads, keeps the successors that show it.
    let known = sem.successors_where(&s, &[true], &[true], &[(VarId(0), Value::Int(2))]);
    assert_eq!(known.unwrap(), expect[2..].to_vec());
    let known = sem.successors_where(&s, &[true], &[true], &[(VarId(2), f)]);
    assert_eq!(known.unwrap(), expect[..1].to_vec());
}

#[test]
fn successors_with_next_readers_are_the_candidates_every_assignment_admits() {
    use crate::plant::explicit::{eval, Site};
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let (f, t) = (Value::Bool(false), Value::Bool(true));
    for round in 0..200 {
        // Four Boolean variables; each assignment reads current values, the parameter and
        // the next values of the variables before it in a random order.
        let mut b = Builder::new(&["u"]);
        let vars: Vec<Expr> = (0..4)
            .map(|k| b.var(&format!("v{k}"), Type::Bool))
            .collect();
        let u = b.param("u");
        let mut order: Vec<usize> = (0..4).collect();
        for k in (1..4).rev() {
            order.swap(k, rng.gen_range(0..=k));
        }
        for (pos, &k) in order.iter().enumerate() {
            let leaf = |rng: &mut rand_chacha::ChaCha8Rng| match rng.gen_range(0..4) {
                0 if pos > 0 => next_of(&vars[order[rng.gen_range(0..pos)]]),
                1 => u.clone(),
                _ => vars[rng.gen_range(0..4)].clone(),
            };
            let e = match rng.gen_range(0..4) {
                0 => set(vec![bool(false), bool(true)]),
                1 => bin(BinOp::And, leaf(&mut rng), not(leaf(&mut rng))),
                2 => case(vec![
                    (leaf(&mut rng), set(vec![bool(false), bool(true)])),
                    (bool(true), leaf(&mut rng)),
                ]),
                _ => bin(BinOp::Or, leaf(&mut rng), leaf(&mut rng)),
            };
            if rng.gen_bool(0.9) {
                b.next(&vars[k], e);
            }
        }
        let m = b.m;
        let sem = Semantics::new(&m);
        let state: Vec<Value> = (0..4)
            .map(|_| if rng.gen_bool(0.5) { t } else { f })
            .collect();
        let params = [rng.gen_bool(0.5)];
        let mut expect = Vec::new();
        for bits in 0..16u32 {
            let cand: Vec<Value> = (0..4)
                .map(|k| if bits >> (3 - k) & 1 == 1 { t } else { f })
                .collect();
            let admitted = m.vars.iter().enumerate().all(|(k, var)| match &var.next {
                Some(e) => eval(&m, e, Site::Next(VarId(k)), &state, &params, Some(&cand))
                    .unwrap()
                    .contains(&cand[k]),
                None => true,
            });
            if admitted {
                expect.push(cand);
            }
        }
        let succ = sem.successors(&state, &params, &params).unwrap();
        assert_eq!(succ, expect, "round {round}: {:?}", m.vars);
    }
}

#[test]
fn an_assignment_reading_its_own_next_value_is_checked_on_every_candidate() {
    // The parser refuses such a model; one built in memory keeps the candidates' semantics.
    let (f, t) = (Value::Bool(false), Value::Bool(true));
    for (negated, expect) in [(true, vec![]), (false, vec![vec![f], vec![t]])] {
        let mut b = Builder::new(&[]);
        let x = b.var("x", Type::Bool);
        let own = next_of(&x);
        b.next(&x, if negated { not(own) } else { own });
        let m = b.m;
        let succ = Semantics::new(&m).successors(&[f], &[], &[]).unwrap();
        assert_eq!(succ, expect, "negated: {negated}");
    }
}

/// The Pick-and-Place surrogate plant (`smv/pnp_surrogate.smv`), transcribed.
pub(super) fn pnp_plant() -> Model {
    let mut b = Builder::new(&crate::cases::pnp::OUTPUTS);
    let p: Vec<Expr> = (1..=3)
        .map(|k| b.var(&format!("p{k}"), Type::Bool))
        .collect();
    let pp: Vec<Expr> = (1..=3)
        .map(|k| b.var(&format!("pp{k}"), Type::Bool))
        .collect();
    let c1pos = b.var("c1pos", Type::Range(0, 2));
    let c2pos = b.var("c2pos", Type::Range(0, 2));
    let vcpos = b.var("vcpos", Type::Range(0, 2));
    let vs = b.var("vs", Type::Bool);
    let vac = b.var("vac", Type::Bool);
    let vp: Vec<Expr> = (1..=3)
        .map(|k| b.var(&format!("vp{k}"), Type::Bool))
        .collect();
    let placed = b.var("placed", Type::Bool);
    let dropped = b.var("dropped", Type::Bool);
    let at = |v: &Expr, k: i64| eq(v.clone(), int(k));
    let c1home = b.define("c1Home", at(&c1pos, 0));
    let c1end = b.define("c1End", at(&c1pos, 2));
    let c2home = b.define("c2Home", at(&c2pos, 0));
    let c2end = b.define("c2End", at(&c2pos, 2));
    let _vchome = b.define("vcHome", at(&vcpos, 0));
    let vcend = b.define("vcEnd", at(&vcpos, 2));
    let over1 = b.define("over1", and(vec![c1home.clone(), c2home.clone()]));
    let over2 = b.define("over2", and(vec![c1end.clone(), c2home]));
    let over3 = b.define("over3", and(vec![c1home, c2end.clone()]));
    let over_v = b.define("overV", and(vec![c1end, c2end]));
    let over = [over1, over2, over3];
    let grip: Vec<Expr> = (0..3)
        .map(|k| {
            let e = and(vec![
                vs.clone(),
                not(vac.clone()),
                vcend.clone(),
                over[k].clone(),
                pp[k].clone(),
            ]);
            b.define(&format!("grip{}", k + 1), e)
        })
        .collect();
    let release = b.define("release", and(vec![vac.clone(), not(vs.clone())]));
    let t = || bool(true);
    for k in 0..3 {
        b.init(&pp[k], bool(false));
        b.next(
            &pp[k],
            case(vec![
                (grip[k].clone(), bool(false)),
                (pp[k].clone(), t()),
                (t(), p[k].clone()),
            ]),
        );
    }
    let cmd = |b: &Builder, n: &str| b.param(n);
    let cylinder = |b: &mut Builder, pos: &Expr, ext: &str, ret: &str| {
        let (e, r) = (cmd(b, ext), cmd(b, ret));
        b.init(pos, int(0));
        b.next(
            pos,
            case(vec![
                (
                    and(vec![
                        e.clone(),
                        not(r.clone()),
                        bin(BinOp::Lt, pos.clone(), int(2)),
                    ]),
                    bin(BinOp::Add, pos.clone(), int(1)),
                ),
                (
                    and(vec![r, not(e), bin(BinOp::Gt, pos.clone(), int(0))]),
                    bin(BinOp::Sub, pos.clone(), int(1)),
                ),
                (t(), pos.clone()),
            ]),
        );
    };
    cylinder(&mut b, &c1pos, "c1Extend", "c1Retract");
    cylinder(&mut b, &c2pos, "c2Extend", "c2Retract");
    let down = b.param("vcExtend");
    b.init(&vcpos, int(0));
    b.next(
        &vcpos,
        case(vec![
            (
                and(vec![down.clone(), bin(BinOp::Lt, vcpos.clone(), int(2))]),
                bin(BinOp::Add, vcpos.clone(), int(1)),
            ),
            (
                and(vec![not(down), bin(BinOp::Gt, vcpos.clone(), int(0))]),
                bin(BinOp::Sub, vcpos.clone(), int(1)),
            ),
            (t(), vcpos.clone()),
        ]),
    );
    let (on, off) = (b.param("vacuum_on"), b.param("vacuum_off"));
    b.init(&vs, bool(false));
    b.next(
        &vs,
        case(vec![
            (and(vec![on.clone(), not(off.clone())]), t()),
            (and(vec![off, not(on)]), bool(false)),
            (t(), vs.clone()),
        ]),
    );
    b.init(&vac, bool(false));
    b.next(
        &vac,
        case(vec![
            (not(vs.clone()), bool(false)),
            (or(grip.clone()), t()),
            (t(), vac.clone()),
        ]),
    );
    for k in 0..3 {
        b.init(&vp[k], bool(false));
        b.next(&vp[k], grip[k].clone());
    }
    b.init(&placed, bool(false));
    b.next(&placed, and(vec![release.clone(), over_v.clone()]));
    b.init(&dropped, bool(false));
    b.next(&dropped, and(vec![release, not(over_v)]));
    b.m
}

fn pnp_props() -> Vec<Property> {
    crate::ltl::parse_spec_file(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/specs/pnp.ltl"
    )))
    .unwrap()
}

#[test]
fn pnp_reference_controller_satisfies_its_specification() {
    let model = pnp_plant();
    let ecc = crate::cases::pnp::reference();
    let coupling = Wiring::of_model(&model, &ecc.inputs, &ecc.outputs).unwrap();
    let props = pnp_props();
    behaviour(&model, &Limits::default()).unwrap();
    let start = std::time::Instant::now();
    let v = check(&model, &coupling, &ecc, &props, &Limits::default()).unwrap();
    eprintln!(
        "pnp reference: {} properties in {:?}",
        props.len(),
        start.elapsed()
    );
    assert!(v.iter().all(|v| *v == ExplicitVerdict::Holds), "{v:?}");
    // The plain "every piece on track 2 is picked up" is false (track 1 starves it).
    let v = check(
        &model,
        &coupling,
        &ecc,
        &[prop("G (pp2 -> F vp2)")],
        &Limits::default(),
    )
    .unwrap();
    assert!(matches!(v[0], ExplicitVerdict::Violated(_)));
}

#[test]
fn pnp_random_machines_check_fast() {
    let model = pnp_plant();
    let props = pnp_props();
    let inputs = crate::cases::pnp::input_names();
    let outputs = crate::cases::pnp::output_names();
    let coupling = Wiring::of_model(&model, &inputs, &outputs).unwrap();
    let mut worst = std::time::Duration::ZERO;
    for seed in 0..5 {
        let mut ecc = crate::ecc::random::random_ecc(seed, 8, inputs.len(), outputs.len());
        ecc.inputs = inputs.clone();
        ecc.outputs = outputs.clone();
        let start = std::time::Instant::now();
        let v = check(&model, &coupling, &ecc, &props, &Limits::default()).unwrap();
        worst = worst.max(start.elapsed());
        assert_eq!(v.len(), props.len());
    }
    eprintln!("pnp, random 8-state machines: worst {worst:?}");
}

/// The transcribed PnP plant against the shipped file in NuSMV: the reference controller and
/// random 8-state machines get the same verdicts on every property of `specs/pnp.ltl` (and on
/// the plain track-2 liveness, which the reference violates).
#[test]
fn pnp_verdicts_agree_with_nusmv_on_the_shipped_plant() {
    let Some(nusmv) = crate::nusmv::nusmv_for_tests() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let model = pnp_plant();
    let mut props = pnp_props();
    props.push(Property {
        label: Some("track2_plain".into()),
        ..prop("G (pp2 -> F vp2)")
    });
    let plant_file = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/smv/pnp_surrogate.smv"
    ));
    let plant = crate::smv::plant::read_plant(plant_file).unwrap();
    let mut machines = vec![crate::cases::pnp::reference()];
    for seed in 0..3 {
        let mut e = crate::ecc::random::random_ecc(seed, 8, 10, 7);
        e.inputs = crate::cases::pnp::input_names();
        e.outputs = crate::cases::pnp::output_names();
        machines.push(e);
    }
    for (k, ecc) in machines.iter().enumerate() {
        let coupling = Wiring::of_model(&model, &ecc.inputs, &ecc.outputs).unwrap();
        let ours = check(&model, &coupling, ecc, &props, &Limits::default()).unwrap();
        if k == 0 {
            assert!(matches!(ours.last(), Some(ExplicitVerdict::Violated(_))));
        }
        let smv_coupling = crate::smv::composition::check_coupling(
            &ecc.inputs,
            &ecc.outputs,
            &plant,
            Path::new("pnp.ltl"),
            &props,
        )
        .unwrap();
        // The harness asks for a verdict on `alive` (FALSE) to know that NuSMV read the model.
        let mut with_alive = props.clone();
        with_alive.push(crate::ltl::Property {
            label: Some(differential::ALIVE.into()),
            formula: crate::ltl::Ltl::False,
            line: props.len() + 1,
            text: "FALSE".into(),
        });
        let closed =
            crate::smv::composition::compose(ecc, &plant, &smv_coupling, &with_alive).unwrap();
        let file = dir.path().join(format!("pnp{k}.smv"));
        std::fs::write(&file, closed.text).unwrap();
        let theirs = differential::nusmv_verdicts(&nusmv.path, &file);
        for (i, (p, v)) in props.iter().zip(&ours).enumerate() {
            let name = crate::ltl::property_name(i, p);
            assert_eq!(
                *v == ExplicitVerdict::Holds,
                theirs[&name],
                "machine {k}, property {name}: in-process {v:?}"
            );
        }
    }
}

/// The differential test against NuSMV, on random triples.
mod differential;
