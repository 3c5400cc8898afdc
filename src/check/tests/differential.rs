//! The differential campaign: random plants, controllers and properties, judged in process
//! and by NuSMV. The in-process checker's verdicts (holds / violated / no behaviour at all)
//! must be NuSMV's on every one, and the closed-loop game's answers must stand NuSMV's
//! judgement.
//!
//! Plants have Boolean variables `a`, `b` (and sometimes a free `c`), an integer `n` in a
//! small range, an enumeration `s`, sometimes an integer `m` whose values are at the edges of
//! NuSMV's 32-bit integers, input variables `i` (Boolean) and `j` (integer); defines `d1`
//! (`d2`), integer defines computed at the 32-bit edges (`+`, `-`, `*`, `/` and `mod` by
//! constants of either sign, wrapping around as NuSMV's do) and a define `k` that renames `n`;
//! `init` and `next` with sets and cases; sometimes `INIT`, `INVAR`, `TRANS` (some of which
//! leave states without successors) and `FAIRNESS`. The plant is printed
//! ([`crate::plant::print`]) and read back with the parser, so that the checker runs what the
//! tool reads from a file. Controllers are random ECCs reading Boolean variables and defines
//! and writing the plant's parameters `u` (`w`) and sometimes an output `z` the plant ignores.
//! Properties use every LTL operator, past ones included (the in-process checker refuses
//! those: it must say so rather than give a verdict), over Boolean names and comparisons of
//! integers (against constants at the edges and against the define `k`, on either side),
//! enumerations and Booleans. Every counterexample is also replayed step by step through the
//! plant semantics and the ECC simulator.
//!
//! The game ([`crate::game`]) is played on plants it takes (no `INIT`, `INVAR`, `TRANS`,
//! `FAIRNESS`) with properties of its fragment, and either no recordings or a recording of a
//! random machine (which is then the recordings' machine). A won game's machine (the
//! recordings' machine repaired until it wins) must be verified by NuSMV. A lost game says no
//! machine that answers the recordings keeps the properties: NuSMV must refute every
//! candidate tried (without recordings every one-state machine and random ones, with them the
//! recordings' machine).
//!
//! NuSMV runs as the driver runs it: `-int` dialogues fed many models each, two side by side;
//! after a model NuSMV refuses, the dialogue is restarted. The closed loops are composed by the
//! production composition ([`crate::smv::composition::compose`]).

use super::super::*;
use crate::ecc::{Algorithm, Guard, Run, State, StateId, Transition, Tri};
use crate::game::{self, repair};
use crate::ltl::Ltl;
use crate::plant::build::*;
use crate::plant::explicit::Semantics;
use crate::plant::{BinOp, Expr, Type, VarId};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::{Origin, Scenario, ScenarioSet, Step};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Integer constants of expressions and comparisons: small ones and NuSMV's edges (never
/// `-2147483648`, which NuSMV does not read as a literal).
const EDGES: [i64; 10] = [
    0,
    1,
    -1,
    2,
    3,
    65536,
    46341,
    1073741824,
    2147483647,
    -2147483647,
];

/// Divisors of `/` and `mod`: never zero (NuSMV refuses a division by zero anywhere in the
/// state space, reachable or not).
const DIVISORS: [i64; 6] = [2, -2, 3, -3, 7, -1];

/// The values of `m`: both edges, and the negation of each is one of them.
const M_VALUES: [i64; 5] = [-2147483647, -1, 0, 1, 2147483647];

/// Random expressions over the plant being built.
struct Gen {
    rng: ChaCha8Rng,
    /// Boolean variables, parameters and defines usable anywhere.
    bools: Vec<Expr>,
    /// Integer variables and defines usable anywhere.
    ints: Vec<Expr>,
    n: Expr,
    lo: i64,
    hi: i64,
    s: Expr,
    syms: Vec<Value>,
    /// Input variables (and whether Boolean), usable in `next` and `TRANS` only.
    inputs: Vec<(Expr, bool)>,
}

impl Gen {
    fn pick(&mut self, items: &[Expr]) -> Expr {
        items.choose(&mut self.rng).expect("non-empty").clone()
    }

    fn edge(&mut self) -> i64 {
        *EDGES.choose(&mut self.rng).expect("non-empty")
    }

    /// An integer expression: wrapping arithmetic over the integers and constants at the edges.
    fn integer(&mut self, depth: usize) -> Expr {
        if depth == 0 || self.rng.gen_bool(0.35) {
            return if self.rng.gen_bool(0.6) {
                let ints = self.ints.clone();
                self.pick(&ints)
            } else {
                int(self.edge())
            };
        }
        let divisor = int(*DIVISORS.choose(&mut self.rng).expect("non-empty"));
        match self.rng.gen_range(0..6) {
            0 => bin(BinOp::Add, self.integer(depth - 1), self.integer(depth - 1)),
            1 => bin(BinOp::Sub, self.integer(depth - 1), self.integer(depth - 1)),
            2 => bin(BinOp::Mul, self.integer(depth - 1), self.integer(depth - 1)),
            3 => bin(BinOp::Div, self.integer(depth - 1), divisor),
            4 => bin(BinOp::Mod, self.integer(depth - 1), divisor),
            _ => Expr::Neg(Box::new(self.integer(depth - 1))),
        }
    }

    fn comparison(&mut self) -> BinOp {
        *[
            BinOp::Eq,
            BinOp::Ne,
            BinOp::Lt,
            BinOp::Le,
            BinOp::Gt,
            BinOp::Ge,
        ]
        .choose(&mut self.rng)
        .expect("non-empty")
    }

    fn leaf(&mut self, with_input: bool) -> Expr {
        let k = self.rng.gen_range(self.lo..=self.hi);
        match self.rng.gen_range(0..13) {
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
            8 if with_input && !self.inputs.is_empty() => {
                let (i, boolean) = self
                    .inputs
                    .choose(&mut self.rng)
                    .expect("non-empty")
                    .clone();
                if boolean {
                    i
                } else {
                    bin(BinOp::Gt, bin(BinOp::Add, i, int(1)), int(1))
                }
            }
            9..=11 => {
                let op = self.comparison();
                let (x, y) = (self.integer(2), self.integer(1));
                bin(op, x, y)
            }
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
            // `m`'s domain is closed under negation.
            Type::Enum(values) if values.contains(&Value::Int(M_VALUES[0])) => {
                match self.rng.gen_range(0..4) {
                    0 => Expr::Neg(Box::new(v.clone())),
                    1 => set(vec![v.clone(), Expr::Neg(Box::new(v.clone()))]),
                    2 => v.clone(),
                    _ => self.constants(ty),
                }
            }
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
    /// The plant as built; the checker runs it as read back from its printed text.
    model: Model,
    ecc: Ecc,
    props: Vec<Property>,
}

/// The names of a random plant that properties and controllers read.
struct Names {
    /// Boolean variables and defines (no input variable).
    bools: Vec<String>,
    /// Integer variables and defines (no input variable), with `k`, the define that renames
    /// `n`, if there is one.
    ints: Vec<String>,
    k: Option<String>,
    syms: Vec<String>,
}

const PROPS_PER_CASE: usize = 8;
/// Random cases of the campaign in `cargo test`.
const CASES: u64 = 480;

/// A random plant; `constraints`: with INIT, INVAR, TRANS and FAIRNESS sometimes.
fn random_plant(seed: u64, rng: &mut ChaCha8Rng, constraints: bool) -> (Model, Names) {
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
    let m_ty = Type::Enum(M_VALUES.iter().map(|&v| Value::Int(v)).collect());
    let vm = rng.gen_bool(0.5).then(|| b.var("m", m_ty.clone()));
    let free_c = rng.gen_bool(0.3).then(|| b.var("c", Type::Bool));
    let mut inputs = Vec::new();
    if rng.gen_bool(0.3) {
        inputs.push((b.ivar("i", Type::Bool), true));
    }
    if rng.gen_bool(0.2) {
        inputs.push((b.ivar("j", Type::Range(-2, 2)), false));
    }
    let syms = (0..3).map(|k| Value::Sym(k as u32)).collect();
    let mut bools = vec![va.clone(), vb.clone()];
    bools.extend(free_c.clone());
    bools.extend(params.iter().map(|p| b.param(p)));
    let mut ints = vec![vn.clone()];
    ints.extend(vm.clone());
    let mut g = Gen {
        rng: ChaCha8Rng::seed_from_u64(seed ^ 0x5eed),
        bools,
        ints,
        n: vn.clone(),
        lo,
        hi,
        s: vs.clone(),
        syms,
        inputs,
    };
    let mut names = Names {
        bools: vec!["a".into(), "b".into()],
        ints: vec!["n".into()],
        k: None,
        syms: vec!["idle".into(), "busy".into(), "done".into()],
    };
    if free_c.is_some() {
        names.bools.push("c".into());
    }
    if vm.is_some() {
        names.ints.push("m".into());
    }
    if rng.gen_bool(0.5) {
        let k = b.define("k", vn.clone());
        g.ints.push(k);
        names.k = Some("k".into());
    }
    if rng.gen_bool(0.6) {
        let e = g.integer(2);
        let big = b.define("big", e);
        g.ints.push(big);
        names.ints.push("big".into());
    }
    let d1 = g.boolean(2, false);
    let d1 = b.define("d1", d1);
    g.bools.push(d1);
    names.bools.push("d1".into());
    if rng.gen_bool(0.5) {
        let e = case(vec![
            (g.boolean(1, false), g.boolean(1, false)),
            (bool(true), g.boolean(1, false)),
        ]);
        let d2 = b.define("d2", e);
        g.bools.push(d2);
        names.bools.push("d2".into());
    }
    let mut assigned = vec![
        (&va, Type::Bool),
        (&vb, Type::Bool),
        (&vn, Type::Range(lo, hi)),
        (&vs, b.m.vars[3].ty.clone()),
    ];
    if let Some(m) = &vm {
        assigned.push((m, m_ty));
    }
    for (v, ty) in assigned {
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
    if constraints {
        add_constraints(&mut b, &mut g, rng, [&va, &vb]);
    }
    (b.m, names)
}

/// INIT, INVAR, TRANS (some leaving states without successors) and FAIRNESS, sometimes.
fn add_constraints(b: &mut Builder, g: &mut Gen, rng: &mut ChaCha8Rng, targets: [&Expr; 2]) {
    if rng.gen_bool(0.15) {
        let e = g.boolean(1, false);
        b.init_constraint(e);
    }
    if rng.gen_bool(0.2) {
        let e = g.boolean(1, false);
        b.invar(e);
    }
    if rng.gen_bool(0.2) {
        let target = g.pick(&[targets[0].clone(), targets[1].clone()]);
        let c = g.boolean(1, true);
        let e = g.boolean(1, true);
        b.trans(bin(BinOp::Implies, c, bin(BinOp::Iff, next_of(&target), e)));
    }
    if rng.gen_bool(0.1) {
        // No successor wherever the leaf holds: a deadlock, which LTL's infinite runs avoid.
        let e = g.leaf(false);
        b.trans(not(e));
    }
    for _ in 0..[0, 0, 0, 1, 2][rng.gen_range(0..5)] {
        let e = g.leaf(false);
        b.fairness(e);
    }
}

/// A random controller over `names`' Boolean names, writing `params` and sometimes `z`.
fn random_controller(seed: u64, rng: &mut ChaCha8Rng, names: &Names, params: &[String]) -> Ecc {
    let mut readable = names.bools.clone();
    readable.shuffle(rng);
    let inputs: Vec<String> = readable[..rng.gen_range(1..=3.min(readable.len()))].to_vec();
    let mut outputs = params.to_vec();
    if rng.gen_bool(0.3) {
        outputs.push("z".into());
    }
    let mut ecc =
        crate::ecc::random::random_ecc(seed, rng.gen_range(1..=4), inputs.len(), outputs.len());
    ecc.inputs = inputs;
    ecc.initial_outputs = outputs.iter().map(|_| rng.gen_bool(0.3)).collect();
    ecc.outputs = outputs;
    ecc
}

/// The atoms of properties: Boolean names, and comparisons of integers with constants at the
/// edges and with `k` on either side, of `s` with its constants, of Booleans with each other.
fn atoms(names: &Names, outputs: &[String], rng: &mut ChaCha8Rng) -> Vec<Ltl> {
    use crate::ltl::CmpOp;
    let atom = |n: &str| Box::new(Ltl::Atom(n.to_string()));
    let mut bools: Vec<String> = names.bools.clone();
    bools.extend(outputs.iter().cloned());
    let mut out: Vec<Ltl> = bools.iter().map(|n| Ltl::Atom(n.clone())).collect();
    let ops = [
        CmpOp::Eq,
        CmpOp::Ne,
        CmpOp::Lt,
        CmpOp::Le,
        CmpOp::Gt,
        CmpOp::Ge,
    ];
    for _ in 0..4 {
        let op = *ops.choose(rng).expect("non-empty");
        let x = names.ints.choose(rng).expect("non-empty");
        let k = if rng.gen_bool(0.5) {
            *EDGES.choose(rng).expect("non-empty")
        } else {
            rng.gen_range(-3..=3)
        };
        out.push(Ltl::Cmp(op, atom(x), Box::new(Ltl::Int(k))));
    }
    if let Some(k) = &names.k {
        let op = *ops.choose(rng).expect("non-empty");
        out.push(Ltl::Cmp(op, atom("n"), atom(k)));
        out.push(Ltl::Cmp(CmpOp::Ne, atom(k), atom("n")));
    }
    let sym = names.syms.choose(rng).expect("non-empty");
    out.push(Ltl::Cmp(CmpOp::Eq, atom("s"), atom(sym)));
    let (x, y) = (
        bools.choose(rng).expect("non-empty"),
        bools.choose(rng).expect("non-empty"),
    );
    out.push(Ltl::Cmp(CmpOp::Ne, atom(x), atom(y)));
    out.push(Ltl::Cmp(CmpOp::Eq, atom(x), Box::new(Ltl::True)));
    out
}

/// A random formula of depth at most `depth` over `atoms`, with past operators if `past`.
fn formula(rng: &mut ChaCha8Rng, atoms: &[Ltl], depth: usize, past: bool) -> Ltl {
    use Ltl::*;
    if depth == 0 || rng.gen_bool(0.25) {
        return match rng.gen_range(0..12) {
            0 => True,
            1 => False,
            _ => atoms.choose(rng).expect("non-empty").clone(),
        };
    }
    let go = |rng: &mut ChaCha8Rng| Box::new(formula(rng, atoms, depth - 1, past));
    let unary = if past { 8 } else { 4 };
    let binary = if past { 10 } else { 8 };
    if rng.gen_bool(0.45) {
        let a = go(rng);
        match rng.gen_range(0..unary) {
            0 => Not(a),
            1 => X(a),
            2 => F(a),
            3 => G(a),
            4 => Y(a),
            5 => Z(a),
            6 => H(a),
            _ => O(a),
        }
    } else {
        let (a, b) = (go(rng), go(rng));
        match rng.gen_range(0..binary) {
            0 => And(a, b),
            1 => Or(a, b),
            2 => Xor(a, b),
            3 => Xnor(a, b),
            4 => Implies(a, b),
            5 => Iff(a, b),
            6 => U(a, b),
            7 => V(a, b),
            8 => S(a, b),
            _ => T(a, b),
        }
    }
}

fn property(formula: Ltl, k: usize) -> Property {
    Property {
        label: None,
        text: formula.to_string(),
        formula,
        line: k + 1,
    }
}

fn random_case(seed: u64) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (model, names) = random_plant(seed, &mut rng, true);
    let ecc = random_controller(seed, &mut rng, &names, &model.params);
    let atoms = atoms(&names, &ecc.outputs, &mut rng);
    let props = (0..PROPS_PER_CASE)
        .map(|k| {
            let past = rng.gen_bool(0.15);
            property(formula(&mut rng, &atoms, 4, past), k)
        })
        .collect();
    Case {
        seed,
        model,
        ecc,
        props,
    }
}

/// The case written out for a failure report.
fn describe(model: &Model, ecc: &Ecc, seed: u64, props: &[Property]) -> String {
    let ecc = crate::smv::ecc_module::ecc_module_to_string(ecc, "ECC")
        .unwrap_or_else(|e| format!("(ECC not printable: {e})"));
    let props: Vec<String> = props.iter().map(|p| p.text.clone()).collect();
    format!(
        "seed {seed}\n--- plant\n{}--- controller\n{ecc}--- properties\n{}\n",
        crate::plant::print::to_smv(model),
        props.join("\n")
    )
}

/// The name of the property `FALSE` added to every model: violated iff the model has a fair
/// infinite path from an initial state.
pub(super) const ALIVE: &str = "alive";

/// The closed loop of `ecc` and `model` with `props` (and [`ALIVE`]), as the production
/// composition writes it, in `file`.
fn write_closed_loop(file: &Path, model: &Model, ecc: &Ecc, props: &[Property]) {
    write_closed_loop_of(file, &crate::plant::print::to_smv(model), ecc, props);
}

/// [`write_closed_loop`] of the plant file `text`.
fn write_closed_loop_of(file: &Path, text: &str, ecc: &Ecc, props: &[Property]) {
    let plant = crate::smv::plant::parse_plant(file, text).expect("the printed plant scans");
    let coupling = crate::smv::composition::check_coupling(
        &ecc.inputs,
        &ecc.outputs,
        &plant,
        Path::new("case.ltl"),
        props,
    )
    .expect("the random coupling is valid");
    let mut props = props.to_vec();
    props.push(Property {
        label: Some(ALIVE.into()),
        formula: Ltl::False,
        line: props.len() + 1,
        text: "FALSE".into(),
    });
    let closed = crate::smv::composition::compose(ecc, &plant, &coupling, &props)
        .expect("the random controller composes");
    std::fs::write(file, closed.text).expect("write the model");
}

/// The plant alone, its parameters free, in `file`: NuSMV finds no behaviour iff
/// [`behaviour`] does not.
fn write_free_plant(file: &Path, model: &Model) {
    write_free_plant_of(file, crate::plant::print::to_smv(model), model);
}

/// [`write_free_plant`] of the plant file `text`, read as `model`.
fn write_free_plant_of(file: &Path, mut text: String, model: &Model) {
    text.push_str("MODULE main\nVAR\n");
    for p in &model.params {
        text.push_str(&format!("  {p} : boolean;\n"));
    }
    text.push_str(&format!("  plant : plant({});\n", model.params.join(", ")));
    text.push_str(&format!("LTLSPEC NAME {ALIVE} := FALSE;\n"));
    std::fs::write(file, text).expect("write the model");
}

/// NuSMV's verdicts on a model, by property name (`true`: holds), or its error.
type Verdicts = Result<BTreeMap<String, bool>, String>;

/// NuSMV's verdicts on every model of `models`, in order: two `-int` dialogues side by side,
/// each fed half of the models.
fn nusmv_batch(nusmv: &Path, models: &[PathBuf]) -> Vec<Verdicts> {
    let half = models.len().div_ceil(2).max(1);
    std::thread::scope(|scope| {
        let dialogues: Vec<_> = models
            .chunks(half)
            .map(|chunk| scope.spawn(move || dialogue(nusmv, chunk)))
            .collect();
        dialogues
            .into_iter()
            .flat_map(|s| s.join().expect("a NuSMV dialogue"))
            .collect()
    })
}

/// NuSMV's verdicts on the properties of `model`, by name (`true`: holds).
pub(super) fn nusmv_verdicts(nusmv: &Path, model: &Path) -> BTreeMap<String, bool> {
    let mut v = nusmv_batch(nusmv, &[model.to_path_buf()]);
    v.remove(0)
        .unwrap_or_else(|e| panic!("NuSMV rejects {}: {e}", model.display()))
}

/// Models fed to one NuSMV process at most. A refused model ends the process's useful work,
/// but the commands for the models after it are already written: a short batch keeps what
/// is run again after a refusal small.
const MODELS_PER_PROCESS: usize = 24;

/// One `-int` dialogue per run of models NuSMV accepts: a model it refuses ends the dialogue
/// (what a failed `read_model` or `go` leaves behind is not trusted), and the next one starts
/// with the model after it.
fn dialogue(nusmv: &Path, models: &[PathBuf]) -> Vec<Verdicts> {
    let mut out = Vec::with_capacity(models.len());
    while out.len() < models.len() {
        let end = (out.len() + MODELS_PER_PROCESS).min(models.len());
        out.extend(one_process(nusmv, &models[out.len()..end]));
    }
    out
}

/// Runs `models` through one NuSMV process: per model `read_model`, `go`, `check_ltlspec`, a
/// marker on both streams and `reset`. Returns the verdicts up to and including the first
/// model NuSMV refuses.
fn one_process(nusmv: &Path, models: &[PathBuf]) -> Vec<Verdicts> {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let mut child = Command::new(nusmv)
        .arg("-int")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("NuSMV starts");
    let mut commands = String::new();
    for (k, model) in models.iter().enumerate() {
        commands.push_str(&format!(
            "set prop_print_method name\nset oreg_justice_emptiness_bdd_algorithm EL_fwd\n\
             read_model -i {}\ngo\ncheck_ltlspec\necho @@end {k}\necho -2 @@end {k}\nreset\n",
            model.display()
        ));
    }
    commands.push_str("quit\n");
    let mut stdin = child.stdin.take().expect("piped");
    let writer = std::thread::spawn(move || {
        // NuSMV stops reading after a failure that ends it: a broken pipe is then expected.
        let _ = stdin.write_all(commands.as_bytes());
    });
    let out = child.wait_with_output().expect("NuSMV ends");
    writer.join().expect("the writer ends");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let (outs, errs) = (split(&stdout), split(&stderr));
    let mut verdicts = Vec::new();
    for (k, model) in models.iter().enumerate() {
        let errors: Vec<&str> = errs
            .get(k)
            .into_iter()
            .flat_map(|e| e.lines())
            .filter(|l| {
                l.contains("file ") && l.contains(": line ")
                    || l.contains("ERROR")
                    // NuSMV 2.5.4's LTL tableau fails on some formulas over defines that
                    // simplify to `xnor` ("reached invalid code").
                    || l.contains("error occured")
                    || l.contains("invalid code")
            })
            .collect();
        let v = match outs.get(k) {
            _ if !errors.is_empty() => Err(errors.join("\n")),
            None => Err(format!(
                "NuSMV ended before the end of {} ({})",
                model.display(),
                out.status
            )),
            Some(text) => {
                let v = by_user_name(verdict_lines(text), &models[k]);
                if v.contains_key(ALIVE) {
                    Ok(v)
                } else {
                    Err(format!("no verdict on {ALIVE}:\n{text}"))
                }
            }
        };
        let refused = v.is_err();
        verdicts.push(v);
        if refused {
            break;
        }
    }
    verdicts
}

/// The output of each model, split at the `@@end` markers.
fn split(text: &str) -> Vec<String> {
    let mut parts = vec![String::new()];
    for line in text.lines() {
        if line.contains("@@end ") {
            parts.push(String::new());
        } else {
            let last = parts.last_mut().expect("never empty");
            last.push_str(line);
            last.push('\n');
        }
    }
    parts.pop();
    parts
}

/// `verdicts` keyed by the names the properties were given: the composition names each
/// `LTLSPEC` by its index (`_p3`) and writes the property's own name in the comment after it
/// (`LTLSPEC NAME _p3 := ...;  -- door_shut: ...`). A model written by hand keeps its names.
fn by_user_name(verdicts: BTreeMap<String, bool>, model: &Path) -> BTreeMap<String, bool> {
    let text = std::fs::read_to_string(model).expect("the model file");
    let names: BTreeMap<&str, &str> = text
        .lines()
        .filter_map(|l| {
            let rest = l.strip_prefix("LTLSPEC NAME ")?;
            let (smv, rest) = rest.split_once(" := ")?;
            let (_, comment) = rest.split_once(";  -- ")?;
            Some((smv, comment.split_once(':')?.0))
        })
        .collect();
    (verdicts.into_iter())
        .map(|(k, v)| (names.get(k.as_str()).map_or(k, |n| n.to_string()), v))
        .collect()
}

/// `-- specification 'name'  is true` lines, by name.
fn verdict_lines(text: &str) -> BTreeMap<String, bool> {
    text.lines()
        .filter_map(|l| {
            let rest = &l[l.find("-- specification ")? + "-- specification ".len()..];
            let (name, verdict) = rest.rsplit_once(" is ")?;
            let name = name.trim().trim_matches('\'').to_string();
            Some((name, verdict.trim() == "true"))
        })
        .collect()
}

/// Replays a counterexample through the plant semantics and the ECC simulator.
fn replay(model: &Model, ecc: &Ecc, lasso: &Lasso) -> Result<(), String> {
    let sem = Semantics::new(model);
    let coupling = Wiring::of_model(model, &ecc.inputs, &ecc.outputs).expect("coupled");
    let params =
        |s: &LoopState| -> Vec<bool> { coupling.params.iter().map(|&z| s.outputs[z]).collect() };
    let first = &lasso.states[0];
    if first.ctrl != StateId(0) || first.outputs != ecc.initial_outputs {
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
        let mut run = Run::new(ecc);
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

/// What the campaign counted.
#[derive(Default)]
struct Tally {
    cases: usize,
    /// Plant × controller × property triples whose verdicts were compared.
    triples: usize,
    violated: usize,
    /// Properties with past operators, which the checker refuses (and must).
    past: usize,
    no_behaviour: usize,
    free_plant_dead: usize,
    /// Plants NuSMV refuses (an error on a state the checker never reaches, ...).
    refused_by_nusmv: usize,
    /// Closed loops past a bound of the checker.
    too_large: usize,
    games: usize,
    games_won: usize,
    games_lost: usize,
    games_outside: usize,
    repairs_failed: usize,
    /// Machines of the games judged by NuSMV.
    game_machines: usize,
    models: usize,
    /// The first reasons NuSMV gave for refusing a model.
    refusals: Vec<String>,
    disagreements: Vec<String>,
    inproc: Duration,
    nusmv: Duration,
}

impl Tally {
    fn disagree(&mut self, what: String) {
        self.disagreements.push(what);
    }

    fn report(&self, seconds: f64) -> String {
        format!(
            "differential: {} cases, {} triples compared ({} violated), {} with past operators refused in process, \
             {} closed loops and {} free plants without behaviour, {} refused by NuSMV, {} past a bound; \
             {} games ({} won, {} lost, {} outside the engine, {} repairs failed), {} of their machines judged by NuSMV; \
             {} NuSMV models; {} disagreements; {seconds:.1} s (in process {:.1} s, NuSMV {:.1} s)",
            self.cases,
            self.triples,
            self.violated,
            self.past,
            self.no_behaviour,
            self.free_plant_dead,
            self.refused_by_nusmv,
            self.too_large,
            self.games,
            self.games_won,
            self.games_lost,
            self.games_outside,
            self.repairs_failed,
            self.game_machines,
            self.models,
            self.disagreements.len(),
            self.inproc.as_secs_f64(),
            self.nusmv.as_secs_f64(),
        )
    }
}

/// A case's in-process results, to be compared with NuSMV's.
struct Judged {
    case: Case,
    /// The plant as read back from its printed text, or why the parser refused it.
    read: Result<Model, String>,
    ours: Option<Result<Vec<ExplicitVerdict>, CheckError>>,
    free: Option<Result<(), CheckError>>,
}

fn judge(case: Case) -> Judged {
    let text = crate::plant::print::to_smv(&case.model);
    judge_text(case, &text)
}

/// [`judge`] with the plant read from `text`.
fn judge_text(case: Case, text: &str) -> Judged {
    let read =
        crate::plant::parse::parse_str(text, Path::new("case.smv")).map_err(|e| e.to_string());
    let (ours, free) = match &read {
        Ok(model) => {
            let coupling = Wiring::of_model(model, &case.ecc.inputs, &case.ecc.outputs)
                .unwrap_or_else(|e| {
                    panic!(
                        "{e}\n{}",
                        describe(model, &case.ecc, case.seed, &case.props)
                    )
                });
            let ours = check(model, &coupling, &case.ecc, &case.props, &Limits::default());
            (Some(ours), Some(behaviour(model, &Limits::default())))
        }
        Err(_) => (None, None),
    };
    Judged {
        case,
        read,
        ours,
        free,
    }
}

/// Compares the checker's verdicts with NuSMV's on one case.
fn compare(t: &mut Tally, j: &Judged, theirs: &Verdicts, free_theirs: &Verdicts) {
    let c = &j.case;
    let about = |model: &Model| describe(model, &c.ecc, c.seed, &c.props);
    let (theirs, model) = match (theirs, &j.read) {
        (Err(e), _) => {
            t.refused_by_nusmv += 1;
            if t.refusals.len() < 3 {
                t.refusals.push(e.clone());
            }
            return;
        }
        (Ok(_), Err(e)) => {
            return t.disagree(format!(
                "the parser refuses a plant NuSMV checks: {e}\n{}",
                about(&c.model)
            ))
        }
        (Ok(v), Ok(model)) => (v, model),
    };
    let alive = !theirs[ALIVE];
    match j.ours.as_ref().expect("judged") {
        Err(e) if e.is_bound() => t.too_large += 1,
        Err(CheckError::NoBehaviour { .. }) if !alive => t.no_behaviour += 1,
        Ok(ours) if alive => {
            for (k, o) in ours.iter().enumerate() {
                let p = &c.props[k];
                let Some(&nusmv_holds) = theirs.get(&crate::ltl::property_name(k, p)) else {
                    t.disagree(format!(
                        "no verdict of NuSMV on {} ({:?})\n{}",
                        p.text,
                        theirs.keys().collect::<Vec<_>>(),
                        about(model)
                    ));
                    continue;
                };
                let agree = match o {
                    ExplicitVerdict::Unsupported(_) if !p.formula.is_future_only() => {
                        t.past += 1;
                        continue;
                    }
                    ExplicitVerdict::Unsupported(why) => {
                        t.disagree(format!("unsupported: {why}\n{}", about(model)));
                        continue;
                    }
                    _ if !p.formula.is_future_only() => {
                        t.disagree(format!("a verdict on a past formula: {}", p.text));
                        continue;
                    }
                    ExplicitVerdict::Holds => nusmv_holds,
                    ExplicitVerdict::Violated(lasso) => {
                        t.violated += 1;
                        if let Err(e) = replay(model, &c.ecc, lasso) {
                            t.disagree(format!(
                                "counterexample is no run of the closed loop: {e}\n{}",
                                about(model)
                            ));
                        }
                        !nusmv_holds
                    }
                };
                t.triples += 1;
                if !agree {
                    t.disagree(format!(
                        "{}: in-process {}, NuSMV {}\n{}",
                        p.text,
                        if nusmv_holds { "violated" } else { "holds" },
                        if nusmv_holds { "holds" } else { "violated" },
                        about(model)
                    ));
                }
            }
        }
        ours => t.disagree(format!(
            "in-process {:?}, NuSMV: {}\n{}",
            ours.as_ref().map(|v| v.len()),
            if alive { "behaviour" } else { "no behaviour" },
            about(model)
        )),
    }
    match (j.free.as_ref().expect("judged"), free_theirs) {
        (_, Err(_)) => {}
        (Ok(()), Ok(v)) if !v[ALIVE] => {}
        (Err(CheckError::NoBehaviour { .. }), Ok(v)) if v[ALIVE] => t.free_plant_dead += 1,
        (Err(e), _) if e.is_bound() => {}
        (ours, Ok(v)) => t.disagree(format!(
            "plant alone: in-process {ours:?}, NuSMV: {}\n{}",
            if v[ALIVE] {
                "no behaviour"
            } else {
                "behaviour"
            },
            about(model)
        )),
    }
}

// ---------------------------------------------------------------------------------------------
// The game.

/// A game on a random plant the engine takes, with properties of its fragment.
struct GameCase {
    seed: u64,
    model: Model,
    props: Vec<Property>,
    set: ScenarioSet,
    /// A machine that reproduces the recordings.
    base: Ecc,
}

/// A propositional formula over `atoms`.
fn proposition(rng: &mut ChaCha8Rng, atoms: &[Ltl], depth: usize) -> Ltl {
    use Ltl::*;
    if depth == 0 || rng.gen_bool(0.4) {
        return atoms.choose(rng).expect("non-empty").clone();
    }
    let go = |rng: &mut ChaCha8Rng| Box::new(proposition(rng, atoms, depth - 1));
    match rng.gen_range(0..5) {
        0 => Not(go(rng)),
        1 => And(go(rng), go(rng)),
        2 => Or(go(rng), go(rng)),
        3 => Implies(go(rng), go(rng)),
        _ => Iff(go(rng), go(rng)),
    }
}

/// A property of the game's fragment: `G p`, `G (a -> X b)`, `G (a -> F b)`,
/// `G (a -> (b U c))`, `G F p`, an assumption `(F G e) -> ...` before one with a goal.
fn fragment_property(rng: &mut ChaCha8Rng, atoms: &[Ltl]) -> Ltl {
    use Ltl::*;
    let mut p = |rng: &mut ChaCha8Rng| Box::new(proposition(rng, atoms, 1));
    let with_goal = |rng: &mut ChaCha8Rng, p: &mut dyn FnMut(&mut ChaCha8Rng) -> Box<Ltl>| {
        if rng.gen_bool(0.5) {
            G(Box::new(Implies(p(rng), Box::new(F(p(rng))))))
        } else {
            G(Box::new(F(p(rng))))
        }
    };
    match rng.gen_range(0..7) {
        0 => G(p(rng)),
        1 => G(Box::new(Implies(p(rng), Box::new(X(p(rng)))))),
        2 => G(Box::new(Implies(p(rng), Box::new(U(p(rng), p(rng)))))),
        3 => {
            let e = p(rng);
            Implies(
                Box::new(F(Box::new(G(e)))),
                Box::new(with_goal(rng, &mut p)),
            )
        }
        4 => And(Box::new(G(p(rng))), Box::new(with_goal(rng, &mut p))),
        _ => with_goal(rng, &mut p),
    }
}

/// A one-state machine that starts with `ecc`'s initial outputs (those the game is played
/// from) and sets the outputs to `values` at the first `REQ`, keeping them ever after.
fn constant_machine(ecc: &Ecc, values: &[bool]) -> Ecc {
    let tri = |v: &bool| if *v { Tri::One } else { Tri::Zero };
    Ecc {
        inputs: ecc.inputs.clone(),
        outputs: ecc.outputs.clone(),
        initial_outputs: ecc.initial_outputs.clone(),
        states: vec![State {
            name: "s0".into(),
            algorithm: Algorithm::Tri(values.iter().map(tri).collect()),
            transitions: vec![Transition {
                target: StateId(0),
                guard: Guard::True,
            }],
        }],
    }
}

fn random_game(seed: u64) -> GameCase {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x6a3e);
    let (model, names) = random_plant(seed ^ 0x6a3e, &mut rng, false);
    let base = random_controller(seed, &mut rng, &names, &model.params);
    let atoms = atoms(&names, &base.outputs, &mut rng);
    let props = (0..rng.gen_range(1..=3))
        .map(|k| property(fragment_property(&mut rng, &atoms), k))
        .collect();
    // A recording of the base machine on random inputs, or none.
    let mut scenarios = Vec::new();
    if rng.gen_bool(0.35) {
        let mut run = Run::new(&base);
        let steps = (0..rng.gen_range(1..=4))
            .map(|_| {
                let inputs: Vec<bool> = base.inputs.iter().map(|_| rng.gen_bool(0.5)).collect();
                let outputs = run.step(&inputs).map(|_| run.outputs.clone());
                Step { inputs, outputs }
            })
            .collect();
        scenarios.push(Scenario {
            origin: Origin {
                file: "random".into(),
                line: 1,
                rows: None,
            },
            steps,
        });
    }
    let set = ScenarioSet {
        inputs: base.inputs.clone(),
        outputs: base.outputs.clone(),
        initial_outputs: base.initial_outputs.clone(),
        scenarios,
    };
    GameCase {
        seed,
        model,
        props,
        set,
        base,
    }
}

/// What the game said, and the machines NuSMV must judge: `(machine, must be verified)`.
struct Played {
    case: GameCase,
    machines: Vec<(Ecc, bool)>,
}

/// Plays the game of `g` and picks the machines to judge: a won game's repaired machine (to be
/// verified), a lost game's candidates (to be refuted).
fn play(t: &mut Tally, g: GameCase) -> Played {
    t.games += 1;
    let model = match crate::plant::parse::parse_str(
        &crate::plant::print::to_smv(&g.model),
        Path::new("game.smv"),
    ) {
        Ok(m) => m,
        Err(_) => {
            t.games_outside += 1;
            return Played {
                case: g,
                machines: vec![],
            };
        }
    };
    let coupling = Wiring::of_model(&model, &g.base.inputs, &g.base.outputs).expect("coupled");
    let tree = ScenarioTree::build(&g.set).expect("a machine's own recording");
    let outcome = game::solve(
        &model,
        &coupling,
        &g.props,
        &tree,
        &g.set.initial_outputs,
        100_000,
        crate::deadline::Deadline::NONE,
    );
    let mut machines = Vec::new();
    match outcome {
        Ok(game::Outcome::Won(s)) => {
            t.games_won += 1;
            match repair::repair(&s, &g.base, 1_000) {
                Ok(r) => {
                    if let Err(e) = g.set.check(&r.ecc) {
                        t.disagree(format!(
                            "the repaired machine departs from the recording: {e}"
                        ));
                    }
                    machines.push((r.ecc, true));
                }
                Err(_) => t.repairs_failed += 1,
            }
        }
        Ok(game::Outcome::Lost) => {
            t.games_lost += 1;
            machines.push((g.base.clone(), false));
            if g.set.scenarios.is_empty() {
                let (i, o) = (&g.base.inputs, &g.base.outputs);
                for bits in 0..1u32 << o.len() {
                    let values: Vec<bool> = (0..o.len()).map(|z| bits >> z & 1 == 1).collect();
                    machines.push((constant_machine(&g.base, &values), false));
                }
                for k in 0..4 {
                    let mut rng = ChaCha8Rng::seed_from_u64(g.seed * 16 + k);
                    let mut m = crate::ecc::random::random_ecc(
                        g.seed * 16 + k,
                        rng.gen_range(1..=3),
                        i.len(),
                        o.len(),
                    );
                    m.inputs = i.clone();
                    m.outputs = o.clone();
                    m.initial_outputs = g.base.initial_outputs.clone();
                    machines.push((m, false));
                }
            }
        }
        Err(e) => {
            t.games_outside += 1;
            if t.refusals.len() < 6 {
                t.refusals.push(format!("game: {e}"));
            }
        }
    }
    Played { case: g, machines }
}

/// Compares NuSMV's verdicts on a game's machines with what the game said.
fn compare_game(t: &mut Tally, p: &Played, theirs: &[Verdicts]) {
    for ((ecc, must_hold), v) in p.machines.iter().zip(theirs) {
        let Ok(v) = v else {
            t.refused_by_nusmv += 1;
            continue;
        };
        t.game_machines += 1;
        let verified = !v[ALIVE]
            && (0..p.case.props.len()).all(|k| v[&crate::ltl::property_name(k, &p.case.props[k])]);
        if verified != *must_hold {
            t.disagree(format!(
                "the game was {}, but NuSMV {} this machine\n{}",
                if *must_hold { "won" } else { "lost" },
                if verified { "verifies" } else { "refutes" },
                describe(&p.case.model, ecc, p.case.seed, &p.case.props)
            ));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The campaign.

/// The cases `seeds` (a plant × controller × properties case and a game each), judged in
/// process and by NuSMV; models are kept in `dir`.
fn campaign(t: &mut Tally, nusmv: &Path, dir: &Path, seeds: std::ops::Range<u64>) {
    let start = Instant::now();
    let judged: Vec<Judged> = seeds.clone().map(|s| judge(random_case(s))).collect();
    let played: Vec<Played> = seeds.clone().map(|s| play(t, random_game(s))).collect();
    t.inproc += start.elapsed();
    let mut models = Vec::new();
    for j in &judged {
        let c = &j.case;
        let file = dir.join(format!("case{}.smv", c.seed));
        write_closed_loop(&file, &c.model, &c.ecc, &c.props);
        let free = dir.join(format!("free{}.smv", c.seed));
        write_free_plant(&free, &c.model);
        models.extend([file, free]);
    }
    for p in &played {
        for (k, (ecc, _)) in p.machines.iter().enumerate() {
            let file = dir.join(format!("game{}_{k}.smv", p.case.seed));
            write_closed_loop(&file, &p.case.model, ecc, &p.case.props);
            models.push(file);
        }
    }
    let start = Instant::now();
    let verdicts = nusmv_batch(nusmv, &models);
    t.nusmv += start.elapsed();
    t.models += models.len();
    let mut at = verdicts.iter();
    for j in &judged {
        let (theirs, free) = (at.next().expect("a verdict"), at.next().expect("a verdict"));
        compare(t, j, theirs, free);
        t.cases += 1;
    }
    for p in &played {
        let theirs: Vec<Verdicts> = at.by_ref().take(p.machines.len()).cloned().collect();
        compare_game(t, p, &theirs);
    }
}

/// The plant of `model` one module down, as models written for other work often are: its
/// body in `MODULE body(params)`, instantiated as `P` by a `MODULE plant` that names every
/// variable and define of `P` by a define (the controller reads them there); or `None` when the plant has input variables (a define over
/// an input variable is not what the flat plant means in a property).
fn nested(model: &Model) -> Option<String> {
    if model
        .vars
        .iter()
        .any(|v| v.kind == crate::plant::VarKind::Input)
    {
        return None;
    }
    let flat = crate::plant::print::to_smv(model);
    let (header, body) = flat.split_once('\n')?;
    let params = header.strip_prefix("MODULE plant").unwrap_or("");
    let mut text = format!("MODULE body{params}\n{body}\nMODULE plant{params}\nVAR\n");
    let args = if params.is_empty() { "" } else { params };
    text.push_str(&format!("  P : body{args};\nDEFINE\n"));
    let names = (model.vars.iter().map(|v| &v.name)).chain(model.defines.iter().map(|d| &d.name));
    for n in names {
        text.push_str(&format!("  {n} := P.{n};\n"));
    }
    Some(text)
}

/// The cases `seeds` whose plant [`nested`] takes, judged on the nested plant in process and
/// by NuSMV on the closed loop composed with the nested plant (the submodule kept).
fn nested_campaign(t: &mut Tally, nusmv: &Path, dir: &Path, seeds: std::ops::Range<u64>) {
    let mut judged = Vec::new();
    let mut models = Vec::new();
    for seed in seeds {
        let case = random_case(seed);
        let Some(text) = nested(&case.model) else {
            continue;
        };
        let file = dir.join(format!("nested{seed}.smv"));
        write_closed_loop_of(&file, &text, &case.ecc, &case.props);
        let free = dir.join(format!("nested_free{seed}.smv"));
        write_free_plant_of(&free, text.clone(), &case.model);
        models.extend([file, free]);
        judged.push(judge_text(case, &text));
    }
    let verdicts = nusmv_batch(nusmv, &models);
    let mut at = verdicts.iter();
    for j in &judged {
        let (theirs, free) = (at.next().expect("a verdict"), at.next().expect("a verdict"));
        compare(t, j, theirs, free);
        t.cases += 1;
    }
}

/// Where the models go: a temporary folder, or one inside `FBSYNTH_KEEP_MODELS` if set.
fn model_dir() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = match std::env::var_os("FBSYNTH_KEEP_MODELS") {
        Some(d) => tempfile::TempDir::new_in(d).expect("directory").keep(),
        None => dir.path().to_path_buf(),
    };
    (dir, path)
}

fn assert_no_disagreement(t: &Tally) {
    for d in &t.disagreements {
        eprintln!(
            "disagreement: {}",
            d.lines().take(2).collect::<Vec<_>>().join(" / ")
        );
    }
    assert!(
        t.disagreements.is_empty(),
        "{} disagreements, the first:\n{}",
        t.disagreements.len(),
        t.disagreements[0]
    );
}

#[test]
fn verdicts_agree_with_nusmv_on_random_triples() {
    let Some(nusmv) = crate::nusmv::nusmv_for_tests() else {
        return;
    };
    let (_keep, dir) = model_dir();
    let start = Instant::now();
    let mut tally = Tally::default();
    let cases = std::env::var("DIFF_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(CASES);
    campaign(&mut tally, &nusmv.path, &dir, 0..cases);
    eprintln!("{}", tally.report(start.elapsed().as_secs_f64()));
    for r in &tally.refusals {
        eprintln!("--- refused by NuSMV\n{}", &r[..r.len().min(2000)]);
    }
    assert_no_disagreement(&tally);
    assert!(
        tally.triples >= 2000,
        "only {} triples compared",
        tally.triples
    );
    assert!(
        tally.games_won >= 10 && tally.games_lost >= 20 && tally.game_machines >= 100,
        "too few games decided: {}",
        tally.report(0.0)
    );
}

/// The plant's module hierarchy as the parser flattens it means what NuSMV's flattening
/// means: the random plants one module down get NuSMV's verdicts.
#[test]
fn verdicts_on_nested_plants_agree_with_nusmv() {
    let Some(nusmv) = crate::nusmv::nusmv_for_tests() else {
        return;
    };
    let (_keep, dir) = model_dir();
    let mut tally = Tally::default();
    nested_campaign(&mut tally, &nusmv.path, &dir, 0..NESTED_CASES);
    eprintln!("{}", tally.report(0.0));
    assert_no_disagreement(&tally);
    assert!(
        tally.triples >= 200,
        "only {} triples compared",
        tally.triples
    );
}

/// Random cases tried one module down (those with input variables are left out).
const NESTED_CASES: u64 = 120;

/// The long campaign: `FBSYNTH_DIFFERENTIAL_SECONDS` (600 unless set) of random cases after
/// those of [`verdicts_agree_with_nusmv_on_random_triples`], reporting its figures:
/// `cargo test --lib differential::long_campaign -- --ignored --nocapture`.
#[test]
#[ignore = "a ten-minute run"]
fn long_campaign() {
    let nusmv = crate::nusmv::nusmv_for_tests().expect("NuSMV for the long campaign");
    let seconds: u64 = std::env::var("FBSYNTH_DIFFERENTIAL_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let (_keep, dir) = model_dir();
    let start = Instant::now();
    let mut tally = Tally::default();
    let mut seed = CASES;
    while start.elapsed() < Duration::from_secs(seconds) {
        campaign(&mut tally, &nusmv.path, &dir, seed..seed + 100);
        seed += 100;
        for entry in std::fs::read_dir(&dir).expect("the model folder").flatten() {
            let _ = std::fs::remove_file(entry.path());
        }
        eprintln!("{}", tally.report(start.elapsed().as_secs_f64()));
    }
    for d in tally.disagreements.iter().take(5) {
        eprintln!("--- disagreement\n{d}");
    }
    assert_no_disagreement(&tally);
}
