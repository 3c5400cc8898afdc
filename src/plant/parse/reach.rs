//! Whether a branch of an assignment can be taken: some values of the variables, parameters
//! and successor values its conditions read make every condition on the way to it come out as
//! needed. NuSMV refuses an assignment that can produce a value outside the variable's type
//! over the whole state space (reachable or not, invariants ignored), so this search goes over
//! whole domains too.
//!
//! The resolver asks only about constants outside the domain, and refuses one only when a
//! witness is found: a branch that is dead (`FALSE : 7`, or `x = 0 & x = 1 : 7`) is accepted,
//! as NuSMV accepts it. When the conditions read more than [`MAX_ASSIGNMENTS`] combinations of
//! values, or a condition cannot be evaluated (division by zero, a case without a true
//! branch), nothing is concluded and nothing is refused.

use crate::plant::{arith, BinOp, Define, Expr, Value, Var};
use std::collections::BTreeSet;

/// The most combinations of values the search tries.
const MAX_ASSIGNMENTS: u64 = 1 << 16;

/// What a condition reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Leaf {
    Var(usize),
    Next(usize),
    Param(usize),
}

/// Values of the leaves and of the defines, for one combination.
struct Env {
    vars: Vec<Option<Value>>,
    next: Vec<Option<Value>>,
    params: Vec<Option<Value>>,
    defines: Vec<Option<Value>>,
}

const BOOLS: [Value; 2] = [Value::Bool(false), Value::Bool(true)];

/// Whether some combination of values makes every `(condition, wanted)` of `path` evaluate to
/// `wanted`. `defines` are in dependency order (each refers only to earlier ones).
pub(super) fn can_be_taken(
    vars: &[Var],
    defines: &[Define],
    n_params: usize,
    path: &[(Expr, bool)],
) -> bool {
    let mut leaves = BTreeSet::new();
    let mut needed = BTreeSet::new();
    let mut todo: Vec<&Expr> = path.iter().map(|(c, _)| c).collect();
    while let Some(e) = todo.pop() {
        e.walk(&mut |e| match *e {
            Expr::Var(v) => {
                leaves.insert(Leaf::Var(v.0));
            }
            Expr::Next(v) => {
                leaves.insert(Leaf::Next(v.0));
            }
            Expr::Param(p) => {
                leaves.insert(Leaf::Param(p.0));
            }
            Expr::Define(d) if needed.insert(d.0) => todo.push(&defines[d.0].expr),
            _ => {}
        });
    }
    let leaves: Vec<Leaf> = leaves.into_iter().collect();
    let domains: Vec<&[Value]> = leaves
        .iter()
        .map(|&leaf| match leaf {
            Leaf::Var(v) | Leaf::Next(v) => vars[v].domain.as_slice(),
            Leaf::Param(_) => &BOOLS,
        })
        .collect();
    let combinations = domains
        .iter()
        .try_fold(1u64, |acc, d| acc.checked_mul(d.len() as u64));
    if combinations.is_none_or(|c| c > MAX_ASSIGNMENTS) {
        return false;
    }
    let mut env = Env {
        vars: vec![None; vars.len()],
        next: vec![None; vars.len()],
        params: vec![None; n_params],
        defines: vec![None; defines.len()],
    };
    // An odometer over the domains.
    let mut digits = vec![0; leaves.len()];
    loop {
        for (k, &leaf) in leaves.iter().enumerate() {
            let value = Some(domains[k][digits[k]]);
            match leaf {
                Leaf::Var(v) => env.vars[v] = value,
                Leaf::Next(v) => env.next[v] = value,
                Leaf::Param(p) => env.params[p] = value,
            }
        }
        // Ascending define ids are a dependency order.
        for &d in &needed {
            env.defines[d] = eval(&defines[d].expr, &env);
        }
        if path
            .iter()
            .all(|(c, wanted)| eval(c, &env) == Some(Value::Bool(*wanted)))
        {
            return true;
        }
        let Some(k) = (0..digits.len()).find(|&k| digits[k] + 1 < domains[k].len()) else {
            return false;
        };
        digits[k] += 1;
        digits[..k].iter_mut().for_each(|d| *d = 0);
    }
}

/// The value of an expression, or `None` where it cannot be told (an evaluation error, a
/// set). Integers are NuSMV's (32 bits, wrapping around, C's `/` and `%`: module `arith`).
fn eval(e: &Expr, env: &Env) -> Option<Value> {
    let int = |e: &Expr| match eval(e, env)? {
        Value::Int(i) => Some(i),
        _ => None,
    };
    let boolean = |e: &Expr| match eval(e, env)? {
        Value::Bool(b) => Some(b),
        _ => None,
    };
    match e {
        Expr::Const(v) => Some(*v),
        Expr::Var(v) => env.vars[v.0],
        Expr::Next(v) => env.next[v.0],
        Expr::Param(p) => env.params[p.0],
        Expr::Define(d) => env.defines[d.0],
        Expr::Not(x) => Some(Value::Bool(!boolean(x)?)),
        Expr::Neg(x) => Some(Value::Int(arith::negate(int(x)?))),
        Expr::Bin(op, a, b) => {
            let logic = |f: fn(bool, bool) -> bool| Some(Value::Bool(f(boolean(a)?, boolean(b)?)));
            let compare = |f: fn(i64, i64) -> bool| Some(Value::Bool(f(int(a)?, int(b)?)));
            let compute = || arith::arithmetic(*op, int(a)?, int(b)?).map(Value::Int);
            match op {
                BinOp::And => logic(|x, y| x & y),
                BinOp::Or => logic(|x, y| x | y),
                BinOp::Xor => logic(|x, y| x ^ y),
                BinOp::Xnor | BinOp::Iff => logic(|x, y| x == y),
                BinOp::Implies => logic(|x, y| !x | y),
                BinOp::Eq => Some(Value::Bool(eval(a, env)? == eval(b, env)?)),
                BinOp::Ne => Some(Value::Bool(eval(a, env)? != eval(b, env)?)),
                BinOp::Lt => compare(|x, y| x < y),
                BinOp::Le => compare(|x, y| x <= y),
                BinOp::Gt => compare(|x, y| x > y),
                BinOp::Ge => compare(|x, y| x >= y),
                BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Mod => compute(),
            }
        }
        Expr::Case(branches) => {
            for (c, v) in branches {
                if boolean(c)? {
                    return eval(v, env);
                }
            }
            None
        }
        Expr::Set(_) => None,
    }
}
