//! The plant's step in CNF: the expressions of a [`Model`] evaluated on symbolic states.
//!
//! A state is one [`Fd`] per variable. The environment is fixed (see [`super::Environment`]):
//! variables the plant leaves free (`IVAR`, a `VAR` without `next`) take the recorded value of
//! the step, and a set `{a, b}` takes the value the environment chose if the set holds it, its
//! first element otherwise. Everything else follows from the controller outputs, so every
//! literal here is a function of the machine's variables.

use super::gates::{Fd, Gates, B};
use crate::plant::{BinOp, Expr, Model, Value, VarId, VarKind};
use varisat::ExtendFormula;

/// One step's view for evaluation: the state, the controller outputs the plant reads (per
/// parameter), and the defines evaluated so far.
pub(crate) struct Frame<'s> {
    /// The plant state: one value per plant variable ([`crate::plant::VarId`] order).
    pub(crate) state: &'s [Fd],
    /// Per plant parameter: the controller output it reads ([`super::Spec::params`]).
    pub(crate) params: &'s [B],
    /// `defines[d]`: define `d` once evaluated on this frame (memo; `None` until read).
    pub(crate) defines: Vec<Option<Fd>>,
    /// While the next state is computed: the environment's next values and the next values
    /// found so far (a `next` assignment may read another variable's next value; the parser
    /// refuses cycles).
    next: Option<(&'s [Value], Vec<Option<Fd>>)>,
}

impl<'s> Frame<'s> {
    /// A frame on `state` and `params` with no define evaluated yet, before the next state.
    pub(crate) fn new(model: &Model, state: &'s [Fd], params: &'s [B]) -> Frame<'s> {
        Frame {
            state,
            params,
            defines: vec![None; model.defines.len()],
            next: None,
        }
    }
}

/// Evaluates `e` on `frame`; a set takes `choice` when it holds it.
pub(crate) fn eval<F: ExtendFormula>(
    g: &mut Gates<'_, F>,
    model: &Model,
    e: &Expr,
    frame: &mut Frame<'_>,
    choice: Option<Value>,
) -> Fd {
    match e {
        Expr::Const(v) => Fd::constant(*v),
        Expr::Var(v) => frame.state[v.0].clone(),
        // Outside a next assignment only TRANS has `next`, and plants with TRANS are not
        // encoded.
        Expr::Next(v) => {
            next_value(g, model, *v, frame).unwrap_or_else(|| frame.state[v.0].clone())
        }
        Expr::Param(p) => Fd::of_bool(frame.params[p.0]),
        Expr::Define(d) => {
            if let Some(v) = &frame.defines[d.0] {
                return v.clone();
            }
            let v = eval(g, model, &model.defines[d.0].expr, frame, None);
            frame.defines[d.0] = Some(v.clone());
            v
        }
        Expr::Not(a) => {
            let a = boolean(g, model, a, frame);
            Fd::of_bool(!a)
        }
        Expr::Neg(a) => {
            let a = eval(g, model, a, frame, None);
            negate(g, a)
        }
        Expr::Bin(op, a, b) => binary(g, model, *op, a, b, frame),
        Expr::Case(branches) => case(g, model, branches, frame, choice),
        Expr::Set(items) => set(g, model, items, frame, choice),
    }
}

/// `-a`, value by value.
fn negate<F: ExtendFormula>(g: &mut Gates<'_, F>, a: Fd) -> Fd {
    let pairs =
        a.0.into_iter()
            .map(|(v, b)| match v {
                Value::Int(i) => (Value::Int(crate::plant::arith::negate(i)), b),
                other => (other, b),
            })
            .collect();
    g.join(pairs)
}

/// `case c1 : v1; ... esac`: each value where its condition is the first that holds.
fn case<F: ExtendFormula>(
    g: &mut Gates<'_, F>,
    model: &Model,
    branches: &[(Expr, Expr)],
    frame: &mut Frame<'_>,
    choice: Option<Value>,
) -> Fd {
    let mut pairs = Vec::new();
    let mut none_before = B::C(true);
    for (c, v) in branches {
        let c = boolean(g, model, c, frame);
        let here = g.and2(none_before, c);
        if here != B::C(false) {
            let v = eval(g, model, v, frame, choice);
            for (w, b) in v.0 {
                let both = g.and2(here, b);
                pairs.push((w, both));
            }
        }
        none_before = g.and2(none_before, !c);
        if none_before == B::C(false) {
            break;
        }
    }
    g.join(pairs)
}

/// A set `{a, b, ...}`: `choice` where the set holds it, else its first item.
fn set<F: ExtendFormula>(
    g: &mut Gates<'_, F>,
    model: &Model,
    items: &[Expr],
    frame: &mut Frame<'_>,
    choice: Option<Value>,
) -> Fd {
    let values: Vec<Fd> = items
        .iter()
        .map(|i| eval(g, model, i, frame, None))
        .collect();
    let Some(first) = values.first() else {
        return Fd(Vec::new());
    };
    let Some(w) = choice else {
        return first.clone();
    };
    let holds: Vec<B> = values.iter().map(|v| v.is(w)).collect();
    let holds = g.or(&holds);
    let mut pairs = vec![(w, holds)];
    for (v, b) in &first.0 {
        let b = g.and2(!holds, *b);
        pairs.push((*v, b));
    }
    g.join(pairs)
}

/// Evaluates a Boolean expression.
pub(crate) fn boolean<F: ExtendFormula>(
    g: &mut Gates<'_, F>,
    model: &Model,
    e: &Expr,
    frame: &mut Frame<'_>,
) -> B {
    let v = eval(g, model, e, frame, None);
    v.is(Value::Bool(true))
}

fn binary<F: ExtendFormula>(
    g: &mut Gates<'_, F>,
    model: &Model,
    op: BinOp,
    a: &Expr,
    b: &Expr,
    frame: &mut Frame<'_>,
) -> Fd {
    use BinOp::*;
    if matches!(op, And | Or | Xor | Xnor | Implies | Iff) {
        let x = boolean(g, model, a, frame);
        // Short-circuit on constants keeps untaken branches out of the formula.
        let y = match (op, x) {
            (And, B::C(false)) => return Fd::constant(Value::Bool(false)),
            (Or, B::C(true)) => return Fd::constant(Value::Bool(true)),
            (Implies, B::C(false)) => return Fd::constant(Value::Bool(true)),
            _ => boolean(g, model, b, frame),
        };
        let r = match op {
            And => g.and2(x, y),
            Or => g.or2(x, y),
            Implies => g.or2(!x, y),
            Iff | Xnor => g.iff(x, y),
            _ => !g.iff(x, y),
        };
        return Fd::of_bool(r);
    }
    let x = eval(g, model, a, frame, None);
    let y = eval(g, model, b, frame, None);
    let mut pairs = Vec::new();
    for &(v, bv) in &x.0 {
        for &(w, bw) in &y.0 {
            let Some(r) = apply(op, v, w) else { continue };
            let both = g.and2(bv, bw);
            pairs.push((r, both));
        }
    }
    let joined = g.join(pairs);
    // A comparison is Boolean even where neither value occurs.
    if matches!(op, Eq | Ne | Lt | Le | Gt | Ge) {
        return Fd::of_bool(joined.is(Value::Bool(true)));
    }
    joined
}

/// `v op w` on constants; `None` where NuSMV would report an error (division by zero).
pub(crate) fn apply(op: BinOp, v: Value, w: Value) -> Option<Value> {
    use BinOp::*;
    let b = Value::Bool;
    Some(match (op, v, w) {
        (Eq, _, _) => b(v == w),
        (Ne, _, _) => b(v != w),
        (Lt, Value::Int(x), Value::Int(y)) => b(x < y),
        (Le, Value::Int(x), Value::Int(y)) => b(x <= y),
        (Gt, Value::Int(x), Value::Int(y)) => b(x > y),
        (Ge, Value::Int(x), Value::Int(y)) => b(x >= y),
        // NuSMV's 32-bit arithmetic, wrapping around, C's `/` and `%` (`plant::arith`).
        (Add | Sub | Mul | Div | Mod, Value::Int(x), Value::Int(y)) => {
            Value::Int(crate::plant::arith::arithmetic(op, x, y)?)
        }
        _ => return None,
    })
}

/// Whether the plant is in the part of the subset this encoding covers: no `INIT`, `INVAR`,
/// `TRANS` or `FAIRNESS` (their effect on a fixed environment is not a function of the
/// controller). `Err` names the first construct that is not covered.
pub(crate) fn encodable(model: &Model) -> Result<(), String> {
    let sections = [
        ("INIT", &model.init),
        ("INVAR", &model.invar),
        ("TRANS", &model.trans),
        ("FAIRNESS", &model.fairness),
    ];
    for (name, cs) in sections {
        if let Some(c) = cs.first() {
            return Err(format!("{name} on line {}", c.line));
        }
    }
    Ok(())
}

/// The plant state after the frame's state, with the frame's controller outputs and
/// the environment's values `env_next` of the next step (every variable's value in the
/// recorded run).
pub(crate) fn next_state<'s, F: ExtendFormula>(
    g: &mut Gates<'_, F>,
    model: &Model,
    frame: &mut Frame<'s>,
    env_next: &'s [Value],
) -> Vec<Fd> {
    frame.next = Some((env_next, vec![None; model.vars.len()]));
    let out = (0..model.vars.len())
        .map(|i| next_value(g, model, VarId(i), frame).expect("next context is set"))
        .collect();
    frame.next = None;
    out
}

/// The next value of `v` in the frame's next context (`None` outside one).
fn next_value<F: ExtendFormula>(
    g: &mut Gates<'_, F>,
    model: &Model,
    v: VarId,
    frame: &mut Frame<'_>,
) -> Option<Fd> {
    let (env_next, done) = frame.next.as_ref()?;
    if let Some(x) = &done[v.0] {
        return Some(x.clone());
    }
    let choice = env_next[v.0];
    let var = &model.vars[v.0];
    let x = match (&var.next, var.kind) {
        (Some(e), VarKind::State) => eval(g, model, e, frame, Some(choice)),
        _ => Fd::constant(choice),
    };
    if let Some((_, done)) = frame.next.as_mut() {
        done[v.0] = Some(x.clone());
    }
    Some(x)
}
