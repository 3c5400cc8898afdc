//! Random plant × controller × property triples, checked in process and by NuSMV: the verdicts
//! (holds / violated / no behaviour at all) must agree on every one.
//!
//! Plants have Boolean variables `a`, `b` (and sometimes a free `c`), an integer `n` in a
//! small range, an enumeration `s`, sometimes an input variable `i`; defines `d1` (`d2`);
//! `init` and `next` with sets and cases; sometimes `INIT`, `INVAR`, `TRANS` and `FAIRNESS`.
//! Controllers are random ECCs reading Boolean variables and defines and writing the plant's
//! parameters `u` (`w`) and sometimes an output `z` the plant ignores. Properties come from
//! [`crate::ltl::arb::formula`], past operators replaced by their future mirror images and the
//! atoms `a`, `b` renamed to random Boolean names of the closed loop. The composition for
//! NuSMV is the production one ([`crate::smv::composition::compose`]) over the printed plant
//! ([`crate::plant::print`]). Every counterexample is also replayed step by step through the
//! plant semantics and the ECC simulator.

use super::super::*;
use crate::ecc::Run;
use crate::ltl::Ltl;
use crate::plant::build::*;
use crate::plant::explicit::Semantics;
use crate::plant::{BinOp, Expr, Type, VarId};
use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;
use std::path::Path;

/// Random expressions over the plant being built.
struct Gen {
    rng: ChaCha8Rng,
    /// Boolean variables, parameters and defines usable anywhere.
    bools: Vec<Expr>,
    n: Expr,
    lo: i64,
    hi: i64,
    s: Expr,
    syms: Vec<Value>,
    ivar: Option<Expr>,
}

impl Gen {
    fn pick(&mut self, items: &[Expr]) -> Expr {
        items.choose(&mut self.rng).expect("non-empty").clone()
    }

    fn leaf(&mut self, with_input: bool) -> Expr {
        let k = self.rng.gen_range(self.lo..=self.hi);
        match self.rng.gen_range(0..10) {
            0..=3 => {
                let bools = self.bools.clone();
                self.pick(&bools)
            }
            4 => {
                let op = *[BinOp::Eq, BinOp::Ne, BinOp::Lt, BinOp::Ge]
                    .choose(&mut self.rng)
                    .expect("non-empty");
                bin(op, self.n.clone(), int(k))
            }
            5 => {
                let v = *self.syms.choose(&mut self.rng).expect("non-empty");
                eq(self.s.clone(), Expr::Const(v))
            }
            6 => eq(
                bin(BinOp::Mod, bin(BinOp::Add, self.n.clone(), int(k)), int(2)),
                int(0),
            ),
            7 => bin(
                BinOp::Gt,
                bin(BinOp::Mul, self.n.clone(), int(2)),
                bin(BinOp::Div, int(k), int(2)),
            ),
            8 if with_input && self.ivar.is_some() => self.ivar.clone().expect("checked"),
            _ => bool(self.rng.gen_bool(0.5)),
        }
    }

    fn boolean(&mut self, depth: usize, with_input: bool) -> Expr {
        if depth == 0 || self.rng.gen_bool(0.4) {
            return self.leaf(with_input);
        }
        let a = self.boolean(depth - 1, with_input);
        if self.rng.gen_bool(0.2) {
            return not(a);
        }
        let b = self.boolean(depth - 1, with_input);
        let op = *[
            BinOp::And,
            BinOp::Or,
            BinOp::Xor,
            BinOp::Xnor,
            BinOp::Implies,
            BinOp::Iff,
        ]
        .choose(&mut self.rng)
        .expect("non-empty");
        bin(op, a, b)
    }

    /// A value for a variable of type `ty` (itself `v`): constants, sets, expressions.
    fn value(&mut self, v: &Expr, ty: &Type) -> Expr {
        match ty {
            Type::Bool => match self.rng.gen_range(0..4) {
                0 => bool(self.rng.gen_bool(0.5)),
                1 => set(vec![bool(false), bool(true)]),
                2 => v.clone(),
                _ => self.boolean(1, true),
            },
            _ if self.rng.gen_bool(0.6) => self.constants(ty),
            _ => v.clone(),
        }
    }

    /// A constant of type `ty`, or a set of two.
    fn constants(&mut self, ty: &Type) -> Expr {
        let domain: Vec<Value> = match ty {
            Type::Bool => vec![Value::Bool(false), Value::Bool(true)],
            Type::Range(lo, hi) => (*lo..=*hi).map(Value::Int).collect(),
            Type::Enum(values) => values.clone(),
        };
        let pair = self.rng.gen_bool(0.3);
        let mut k = || Expr::Const(*domain.choose(&mut self.rng).expect("non-empty"));
        if pair {
            set(vec![k(), k()])
        } else {
            k()
        }
    }

    /// `next(v)`: a case of one to three guarded values and a default.
    fn next(&mut self, v: &Expr, ty: &Type) -> Expr {
        let mut branches = Vec::new();
        for _ in 0..self.rng.gen_range(0..=2) {
            let c = self.boolean(1, true);
            let value = match ty {
                // Steps that stay inside the range, as the shipped plants write them.
                Type::Range(lo, hi) if self.rng.gen_bool(0.5) => {
                    if self.rng.gen_bool(0.5) {
                        branches.push((
                            and(vec![c, bin(BinOp::Lt, v.clone(), int(*hi))]),
                            bin(BinOp::Add, v.clone(), int(1)),
                        ));
                    } else {
                        branches.push((
                            and(vec![c, bin(BinOp::Gt, v.clone(), int(*lo))]),
                            bin(BinOp::Sub, v.clone(), int(1)),
                        ));
                    }
                    continue;
                }
                _ => self.value(v, ty),
            };
            branches.push((c, value));
        }
        let default = self.value(v, ty);
        if branches.is_empty() && self.rng.gen_bool(0.5) {
            return default;
        }
        branches.push((bool(true), default));
        case(branches)
    }
}

/// One random plant, controller and properties.
struct Case {
    seed: u64,
    model: Model,
    ecc: Ecc,
    props: Vec<Property>,
}

const PROPS_PER_CASE: usize = 8;
/// Random cases per run.
const CASES: u64 = 150;

fn random_case(seed: u64) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let params: &[&str] = if rng.gen_bool(0.5) {
        &["u"]
    } else {
        &["u", "w"]
    };
    let mut b = Builder::new(params);
    let va = b.var("a", Type::Bool);
    let vb = b.var("b", Type::Bool);
    let (lo, hi) = (rng.gen_range(-2..=0), rng.gen_range(1..=2));
    let vn = b.var("n", Type::Range(lo, hi));
    let vs = b.enumeration("s", &["idle", "busy", "done"]);
    let free_c = rng.gen_bool(0.3).then(|| b.var("c", Type::Bool));
    let ivar = rng.gen_bool(0.3).then(|| b.ivar("i", Type::Bool));
    let syms = (0..3).map(|k| Value::Sym(k as u32)).collect();
    let mut bools = vec![va.clone(), vb.clone()];
    bools.extend(free_c.clone());
    bools.extend(params.iter().map(|p| b.param(p)));
    let mut g = Gen {
        rng: ChaCha8Rng::seed_from_u64(seed ^ 0x5eed),
        bools,
        n: vn.clone(),
        lo,
        hi,
        s: vs.clone(),
        syms,
        ivar,
    };
    let mut names = vec!["a", "b"];
    if free_c.is_some() {
        names.push("c");
    }
    let d1 = g.boolean(2, false);
    let d1 = b.define("d1", d1);
    g.bools.push(d1);
    names.push("d1");
    if rng.gen_bool(0.5) {
        let e = case(vec![
            (g.boolean(1, false), g.boolean(1, false)),
            (bool(true), g.boolean(1, false)),
        ]);
        let d2 = b.define("d2", e);
        g.bools.push(d2);
        names.push("d2");
    }
    for (v, ty) in [
        (&va, Type::Bool),
        (&vb, Type::Bool),
        (&vn, Type::Range(lo, hi)),
        (&vs, b.m.vars[3].ty.clone()),
    ] {
        match rng.gen_range(0..5) {
            0 => {}
            1 if matches!(ty, Type::Bool) && !matches!(v, Expr::Var(VarId(0))) => {
                // An init that reads another variable.
                b.init(v, not(va.clone()))
            }
            _ => {
                let e = g.constants(&ty);
                b.init(v, e)
            }
        }
        if rng.gen_range(0..6) != 0 {
            let e = g.next(v, &ty);
            b.next(v, e);
        }
    }
    if rng.gen_bool(0.15) {
        let e = g.boolean(1, false);
        b.init_constraint(e);
    }
    if rng.gen_bool(0.15) {
        let e = g.boolean(1, false);
        b.invar(e);
    }
    if rng.gen_bool(0.15) {
        let target = g.pick(&[va.clone(), vb.clone()]);
        let c = g.boolean(1, true);
        let e = g.boolean(1, true);
        b.trans(bin(BinOp::Implies, c, bin(BinOp::Iff, next_of(&target), e)));
    }
    for _ in 0..[0, 0, 0, 1, 2][rng.gen_range(0..5)] {
        let e = g.leaf(false);
        b.fairness(e);
    }
    let model = b.m;

    // The controller.
    names.shuffle(&mut rng);
    let inputs: Vec<String> = names[..rng.gen_range(1..=3.min(names.len()))]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let mut outputs: Vec<String> = params.iter().map(|s| s.to_string()).collect();
    if rng.gen_bool(0.3) {
        outputs.push("z".into());
    }
    let mut ecc =
        crate::ecc::random::random_ecc(seed, rng.gen_range(1..=4), inputs.len(), outputs.len());
    ecc.inputs = inputs;
    ecc.initial_outputs = outputs.iter().map(|_| rng.gen_bool(0.3)).collect();
    ecc.outputs = outputs;

    // The properties.
    let mut atoms: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    atoms.extend(ecc.outputs.iter().cloned());
    let mut seed_bytes = [0u8; 32];
    rng.fill(&mut seed_bytes);
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes),
    );
    let strategy = crate::ltl::arb::formula(true);
    let props = (0..PROPS_PER_CASE)
        .map(|k| {
            let f = strategy
                .new_tree(&mut runner)
                .expect("the strategy generates")
                .current();
            let pick = |rng: &mut ChaCha8Rng| atoms.choose(rng).expect("non-empty").clone();
            let renaming = (pick(&mut rng), pick(&mut rng));
            let formula = future_mirror(&f, &renaming);
            Property {
                label: None,
                text: formula.to_string(),
                formula,
                line: k + 1,
            }
        })
        .collect();
    Case {
        seed,
        model,
        ecc,
        props,
    }
}

/// `f` with each past operator replaced by its future mirror (`Y`, `Z` -> `X`, `H` -> `G`,
/// `O` -> `F`, `S` -> `U`, `T` -> `V`) and the atoms `a`, `b` renamed.
fn future_mirror(f: &Ltl, (a, b): &(String, String)) -> Ltl {
    use Ltl::*;
    let go = |g: &Ltl| Box::new(future_mirror(g, &(a.clone(), b.clone())));
    match f {
        Atom(n) if n == "a" => Atom(a.clone()),
        Atom(n) if n == "b" => Atom(b.clone()),
        True | False | Atom(_) | Int(_) | Cmp(..) => f.clone(),
        Not(x) => Not(go(x)),
        X(x) | Y(x) | Z(x) => X(go(x)),
        F(x) | O(x) => F(go(x)),
        G(x) | H(x) => G(go(x)),
        And(x, y) => And(go(x), go(y)),
        Or(x, y) => Or(go(x), go(y)),
        Xor(x, y) => Xor(go(x), go(y)),
        Xnor(x, y) => Xnor(go(x), go(y)),
        Implies(x, y) => Implies(go(x), go(y)),
        Iff(x, y) => Iff(go(x), go(y)),
        U(x, y) | S(x, y) => U(go(x), go(y)),
        V(x, y) | T(x, y) => V(go(x), go(y)),
    }
}

/// The case written out for a failure report.
fn describe(c: &Case, prop: Option<usize>) -> String {
    let ecc = crate::smv::ecc_module::ecc_module_to_string(&c.ecc, "ECC")
        .unwrap_or_else(|e| format!("(ECC not printable: {e})"));
    let props: Vec<String> = match prop {
        Some(k) => vec![c.props[k].text.clone()],
        None => c.props.iter().map(|p| p.text.clone()).collect(),
    };
    format!(
        "seed {}\n--- plant\n{}--- controller\n{ecc}--- properties\n{}\n",
        c.seed,
        crate::plant::print::to_smv(&c.model),
        props.join("\n")
    )
}

/// The closed-loop model NuSMV checks, as the production composition writes it.
fn nusmv_model(c: &Case, dir: &Path) -> std::path::PathBuf {
    let file = dir.join(format!("case{}.smv", c.seed));
    let text = crate::plant::print::to_smv(&c.model);
    let plant = crate::smv::plant::parse_plant(&file, &text).expect("the printed plant scans");
    let coupling = crate::smv::composition::check_coupling(
        &c.ecc.inputs,
        &c.ecc.outputs,
        &plant,
        Path::new("case.ltl"),
        &c.props,
    )
    .expect("the random coupling is valid");
    let mut props = c.props.clone();
    props.push(Property {
        label: Some(ALIVE.into()),
        formula: Ltl::False,
        line: props.len() + 1,
        text: "FALSE".into(),
    });
    let closed = crate::smv::composition::compose(&c.ecc, &plant, &coupling, &props)
        .expect("the random controller composes");
    std::fs::write(&file, closed.text).expect("write the model");
    file
}

/// The plant alone, its parameters free: NuSMV finds no behaviour iff [`behaviour`] does not.
fn nusmv_free_plant(c: &Case, dir: &Path) -> std::path::PathBuf {
    let file = dir.join(format!("free{}.smv", c.seed));
    let mut text = crate::plant::print::to_smv(&c.model);
    text.push_str("MODULE main\nVAR\n");
    for p in &c.model.params {
        text.push_str(&format!("  {p} : boolean;\n"));
    }
    text.push_str(&format!(
        "  plant : plant({});\n",
        c.model.params.join(", ")
    ));
    text.push_str(&format!("LTLSPEC NAME {ALIVE} := FALSE;\n"));
    std::fs::write(&file, text).expect("write the model");
    file
}

/// The name of the property `FALSE` added to every model: violated iff the model has a fair
/// infinite path from an initial state.
const ALIVE: &str = "alive";

/// NuSMV's verdicts on the properties of `model`, by name (`true`: holds).
///
/// An `-int` process prints verdicts in an order of its own, and reprints `a V b` as
/// `!(!a U !b)`, so verdicts are matched by the names it prints under
/// `set prop_print_method name`.
pub(super) fn nusmv_verdicts(nusmv: &Path, model: &Path) -> BTreeMap<String, bool> {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let mut child = Command::new(nusmv)
        .arg("-int")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("NuSMV starts");
    let commands = format!(
        "set prop_print_method name\nread_model -i {}\ngo\n\
         set oreg_justice_emptiness_bdd_algorithm EL_fwd\ncheck_ltlspec\nquit\n",
        model.display()
    );
    child
        .stdin
        .take()
        .expect("piped")
        .write_all(commands.as_bytes())
        .expect("NuSMV reads its commands");
    let out = child.wait_with_output().expect("NuSMV ends");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let errors = crate::nusmv::parse_errors(&stderr);
    assert!(
        errors.is_empty(),
        "NuSMV rejects {}: {errors:?}",
        model.display()
    );
    crate::nusmv::parse_output(&stdout)
        .unwrap_or_else(|e| panic!("NuSMV output on {}: {e}\n{stdout}", model.display()))
        .into_iter()
        .map(|r| {
            let name = r
                .name
                .expect("names are printed")
                .trim_matches('\'')
                .to_string();
            (name, r.verdict == crate::nusmv::Verdict::Holds)
        })
        .collect()
}

/// Replays a counterexample through the plant semantics and the ECC simulator.
fn replay(c: &Case, lasso: &Lasso) -> Result<(), String> {
    let sem = Semantics::new(&c.model);
    let coupling = Wiring::of_model(&c.model, &c.ecc.inputs, &c.ecc.outputs).expect("coupled");
    let params =
        |s: &LoopState| -> Vec<bool> { coupling.params.iter().map(|&z| s.outputs[z]).collect() };
    let first = &lasso.states[0];
    if first.ctrl != StateId(0) || first.outputs != c.ecc.initial_outputs {
        return Err("the first state is not the controller's initial state".into());
    }
    if !sem
        .initial_states(&params(first))
        .map_err(|e| e.to_string())?
        .contains(&first.plant)
    {
        return Err("the first state is not an initial plant state".into());
    }
    let n = lasso.states.len();
    for k in 0..n {
        let (s, t) = (
            &lasso.states[k],
            &lasso.states[if k + 1 < n { k + 1 } else { lasso.loop_start }],
        );
        let x: Vec<bool> = coupling
            .inputs
            .iter()
            .map(|name| sem.read(*name, &s.plant, &params(s)) == Ok(Value::Bool(true)))
            .collect();
        let mut run = Run::new(&c.ecc);
        run.state = s.ctrl;
        run.outputs = s.outputs.clone();
        run.step(&x);
        if (run.state, &run.outputs) != (t.ctrl, &t.outputs) {
            return Err(format!("step {k}: the controller does not step like this"));
        }
        let succ = sem
            .successors(&s.plant, &params(s), &params(t))
            .map_err(|e| e.to_string())?;
        if !succ.contains(&t.plant) {
            return Err(format!("step {k}: the plant does not step like this"));
        }
    }
    Ok(())
}

#[derive(Default)]
struct Tally {
    triples: usize,
    violated: usize,
    no_behaviour: usize,
    free_plant_dead: usize,
    disagreements: Vec<String>,
    inproc: std::time::Duration,
}

#[test]
fn verdicts_agree_with_nusmv_on_random_triples() {
    let Some(nusmv) = crate::nusmv::nusmv_for_tests() else {
        return;
    };
    let dir = tempfile::tempdir().expect("temporary directory");
    let dir = match std::env::var_os("FBSYNTH_KEEP_MODELS") {
        Some(d) => tempfile::TempDir::new_in(d).expect("directory").keep(),
        None => dir.path().to_path_buf(),
    };
    let mut tally = Tally::default();
    for seed in 0..CASES {
        let c = random_case(seed);
        let start = std::time::Instant::now();
        let coupling = Wiring::of_model(&c.model, &c.ecc.inputs, &c.ecc.outputs)
            .unwrap_or_else(|e| panic!("{e}\n{}", describe(&c, None)));
        let ours = check(&c.model, &coupling, &c.ecc, &c.props, &Limits::default());
        let free = behaviour(&c.model, &Limits::default());
        tally.inproc += start.elapsed();
        let theirs = nusmv_verdicts(&nusmv.path, &nusmv_model(&c, &dir));
        match ours {
            Err(CheckError::NoBehaviour { .. }) if theirs[ALIVE] => tally.no_behaviour += 1,
            Ok(ours) if !theirs[ALIVE] => {
                for (k, o) in ours.iter().enumerate() {
                    tally.triples += 1;
                    let nusmv_holds = theirs[&crate::ltl::property_name(k, &c.props[k])];
                    let agree = match o {
                        ExplicitVerdict::Holds => nusmv_holds,
                        ExplicitVerdict::Violated(lasso) => {
                            tally.violated += 1;
                            if let Err(e) = replay(&c, lasso) {
                                tally.disagreements.push(format!(
                                    "counterexample is no run of the closed loop: {e}\n{}",
                                    describe(&c, Some(k))
                                ));
                            }
                            !nusmv_holds
                        }
                        ExplicitVerdict::Unsupported(why) => {
                            panic!("unsupported: {why}\n{}", describe(&c, Some(k)))
                        }
                    };
                    if !agree {
                        tally.disagreements.push(format!(
                            "in-process {}, NuSMV {}\n{}",
                            if nusmv_holds { "violated" } else { "holds" },
                            if nusmv_holds { "holds" } else { "violated" },
                            describe(&c, Some(k))
                        ));
                    }
                }
            }
            ours => tally.disagreements.push(format!(
                "in-process {:?}, NuSMV: {}\n{}",
                ours.map(|v| v.len()),
                if theirs[ALIVE] {
                    "no behaviour"
                } else {
                    "behaviour"
                },
                describe(&c, None)
            )),
        }
        let free_theirs = nusmv_verdicts(&nusmv.path, &nusmv_free_plant(&c, &dir));
        match free {
            Ok(()) if !free_theirs[ALIVE] => {}
            Err(CheckError::NoBehaviour { .. }) if free_theirs[ALIVE] => tally.free_plant_dead += 1,
            ours => tally.disagreements.push(format!(
                "plant alone: in-process {ours:?}, NuSMV: {}\n{}",
                if free_theirs[ALIVE] {
                    "no behaviour"
                } else {
                    "behaviour"
                },
                describe(&c, None)
            )),
        }
    }
    eprintln!(
        "differential: {} triples ({} violated), {} closed loops and {} free plants without behaviour, {} disagreements; in-process time {:?}",
        tally.triples,
        tally.violated,
        tally.no_behaviour,
        tally.free_plant_dead,
        tally.disagreements.len(),
        tally.inproc
    );
    assert!(
        tally.disagreements.is_empty(),
        "{} disagreements, the first:\n{}",
        tally.disagreements.len(),
        tally.disagreements[0]
    );
    assert!(
        tally.triples >= 200,
        "only {} triples compared",
        tally.triples
    );
}
