//! The concrete semantics of a [`Model`]: expressions evaluated on explicit states, and the
//! initial states and successors they define (see the header of [`super`] for the rules).
//!
//! In: a [`Model`], a state (one [`Value`] per [`VarId`], `IVAR`s included), the parameters
//! (one `bool` per [`ParamId`](super::ParamId), the controller outputs of the step) and, inside `TRANS`, the
//! successor state. Out: values, sets of values, states; or an [`EvalError`] naming the
//! construct (`next(pos)`, `DEFINE grip1`, `TRANS`, ...) and its line.
//!
//! Nondeterminism is enumerated: a set `{a, b}` as the value of `init`/`next` (or of a case
//! branch of one), a `VAR` without `init`/`next` and an `IVAR` range over their choices, and
//! `INIT`, `INVAR` and `TRANS` filter the result. An `IVAR` is part of the state here: its
//! value at step `t` is the input of the transition from `t` to `t + 1`, which is what NuSMV
//! means as long as it is read only in `next` and `TRANS` (as NuSMV requires).
//!
//! Errors are raised where an evaluation actually meets them (on a reachable state), with the
//! line of the innermost named construct: a define's line, a constraint's line, or the
//! declaration line of the variable whose `init`/`next` is evaluated (the model keeps no line
//! for the assignment itself).

use super::{BinOp, DefineId, Expr, Model, Name, Type, Value, Var, VarId, VarKind};
use std::fmt;
use std::path::PathBuf;

/// A state: the value of every variable, indexed by [`VarId`].
pub(crate) type State = Vec<Value>;

/// Where an expression being evaluated comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Site {
    /// `init(v)`.
    Init(VarId),
    /// `next(v)`.
    Next(VarId),
    /// The body of a define.
    Define(DefineId),
    /// The k-th `INIT` constraint (0-based in [`Model::init`]).
    InitConstraint(usize),
    /// The k-th `INVAR` constraint.
    Invar(usize),
    /// The k-th `TRANS` constraint.
    Trans(usize),
    /// The k-th `FAIRNESS`/`JUSTICE` constraint.
    Fairness(usize),
}

impl Site {
    /// The construct as the user wrote it, and its line.
    fn describe(self, m: &Model) -> (String, usize) {
        match self {
            Site::Init(v) => (format!("init({})", m.var(v).name), m.var(v).line),
            Site::Next(v) => (format!("next({})", m.var(v).name), m.var(v).line),
            Site::Define(d) => (
                format!("DEFINE {}", m.defines[d.0].name),
                m.defines[d.0].line,
            ),
            Site::InitConstraint(k) => ("INIT".into(), m.init[k].line),
            Site::Invar(k) => ("INVAR".into(), m.invar[k].line),
            Site::Trans(k) => ("TRANS".into(), m.trans[k].line),
            Site::Fairness(k) => ("FAIRNESS".into(), m.fairness[k].line),
        }
    }
}

/// What went wrong evaluating an expression.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum EvalErrorKind {
    /// No condition of a `case` holds.
    NoCaseBranch,
    /// An integer division or `mod` by zero.
    DivisionByZero,
    /// `init`/`next` gives a variable a value outside its type.
    OutOfDomain {
        /// The variable assigned.
        var: String,
        /// The offending value, as NuSMV prints it.
        value: String,
    },
    /// An operand of the wrong type (`3 & TRUE`, `idle < 2`, a set inside an operator, ...).
    Type(String),
    /// `next(v)` where there is no successor state (outside `TRANS`).
    NextOutsideTrans(String),
    /// More candidate successors than [`MAX_CANDIDATES`] before filtering.
    TooManyChoices(u128),
}

/// An evaluation error, located at a construct of the plant file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct EvalError {
    /// Path of the plant file.
    pub(crate) file: PathBuf,
    /// 1-based line of the construct (0: a caller's expression).
    pub(crate) line: usize,
    /// `next(pos)`, `DEFINE grip1`, `TRANS`, ...
    pub(crate) construct: String,
    /// What went wrong.
    pub(crate) kind: EvalErrorKind,
}

impl fmt::Display for EvalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}: in {}: ",
            self.file.display(),
            self.line,
            self.construct
        )?;
        match &self.kind {
            EvalErrorKind::NoCaseBranch => write!(f, "no condition of the case holds"),
            EvalErrorKind::DivisionByZero => write!(f, "division by zero"),
            EvalErrorKind::OutOfDomain { var, value } => {
                write!(f, "value {value} is outside the type of '{var}'")
            }
            EvalErrorKind::Type(m) => write!(f, "{m}"),
            EvalErrorKind::NextOutsideTrans(v) => {
                write!(f, "next({v}) is only meaningful inside TRANS")
            }
            EvalErrorKind::TooManyChoices(n) => write!(
                f,
                "{n} candidate successors of one state (more than {MAX_CANDIDATES}): too many free variables"
            ),
        }
    }
}

/// Most candidate successors (before `TRANS`/`INVAR` filtering) enumerated for one state.
pub(crate) const MAX_CANDIDATES: u128 = 1 << 20;

/// Evaluates `expr` on `state` and `params` (and `next` inside `TRANS`): every value it can
/// take, sorted, without repetition (one value unless sets are involved).
pub(crate) fn eval(
    model: &Model,
    expr: &Expr,
    site: Site,
    state: &[Value],
    params: &[bool],
    next: Option<&[Value]>,
) -> Result<Vec<Value>, EvalError> {
    let mut v = Env::new(model, state, params, next).values(expr, site)?;
    v.sort();
    v.dedup();
    Ok(v)
}

/// Whether `value` belongs to the type of `var`.
pub(crate) fn in_domain(var: &Var, value: Value) -> bool {
    match (&var.ty, value) {
        (Type::Bool, Value::Bool(_)) => true,
        (Type::Range(lo, hi), Value::Int(i)) => *lo <= i && i <= *hi,
        (Type::Enum(vs), v) => vs.contains(&v),
        _ => false,
    }
}

/// One evaluation environment: the state, parameters and successor an expression reads, with
/// the values of the defines computed so far.
struct Env<'a> {
    model: &'a Model,
    state: &'a [Value],
    params: &'a [bool],
    next: Option<&'a [Value]>,
    defines: Vec<Option<Value>>,
}

impl<'a> Env<'a> {
    fn new(
        model: &'a Model,
        state: &'a [Value],
        params: &'a [bool],
        next: Option<&'a [Value]>,
    ) -> Env<'a> {
        Env {
            model,
            state,
            params,
            next,
            defines: vec![None; model.defines.len()],
        }
    }

    fn error(&self, site: Site, kind: EvalErrorKind) -> EvalError {
        let (construct, line) = site.describe(self.model);
        EvalError {
            file: self.model.file.clone(),
            line,
            construct,
            kind,
        }
    }

    fn type_error(&self, site: Site, message: String) -> EvalError {
        self.error(site, EvalErrorKind::Type(message))
    }

    /// Every value of an expression that may be a set or a case with set branches.
    fn values(&mut self, e: &Expr, site: Site) -> Result<Vec<Value>, EvalError> {
        match e {
            Expr::Set(items) => {
                let mut out = Vec::with_capacity(items.len());
                for item in items {
                    out.extend(self.values(item, site)?);
                }
                Ok(out)
            }
            Expr::Case(branches) => {
                for (c, v) in branches {
                    if self.boolean(c, site)? {
                        return self.values(v, site);
                    }
                }
                Err(self.error(site, EvalErrorKind::NoCaseBranch))
            }
            _ => Ok(vec![self.value(e, site)?]),
        }
    }

    fn boolean(&mut self, e: &Expr, site: Site) -> Result<bool, EvalError> {
        match self.value(e, site)? {
            Value::Bool(b) => Ok(b),
            other => Err(self.type_error(
                site,
                format!("expected TRUE or FALSE, got {}", self.model.show(other)),
            )),
        }
    }

    fn integer(&mut self, e: &Expr, site: Site) -> Result<i64, EvalError> {
        match self.value(e, site)? {
            Value::Int(i) => Ok(i),
            other => Err(self.type_error(
                site,
                format!("expected an integer, got {}", self.model.show(other)),
            )),
        }
    }

    fn define(&mut self, d: DefineId) -> Result<Value, EvalError> {
        if let Some(v) = self.defines[d.0] {
            return Ok(v);
        }
        let model = self.model;
        let v = self.value(&model.defines[d.0].expr, Site::Define(d))?;
        self.defines[d.0] = Some(v);
        Ok(v)
    }

    /// The single value of an expression.
    fn value(&mut self, e: &Expr, site: Site) -> Result<Value, EvalError> {
        Ok(match e {
            Expr::Const(v) => *v,
            Expr::Var(v) => self.state[v.0],
            Expr::Next(v) => match self.next {
                Some(n) => n[v.0],
                None => {
                    let name = self.model.var(*v).name.clone();
                    return Err(self.error(site, EvalErrorKind::NextOutsideTrans(name)));
                }
            },
            Expr::Define(d) => self.define(*d)?,
            Expr::Param(p) => Value::Bool(self.params[p.0]),
            Expr::Not(a) => Value::Bool(!self.boolean(a, site)?),
            Expr::Neg(a) => Value::Int(super::arith::negate(self.integer(a, site)?)),
            Expr::Case(branches) => {
                for (c, v) in branches {
                    if self.boolean(c, site)? {
                        return self.value(v, site);
                    }
                }
                return Err(self.error(site, EvalErrorKind::NoCaseBranch));
            }
            Expr::Set(_) => {
                return Err(self.type_error(
                    site,
                    "a set of values is allowed only as the value of init, next or a case branch of one".into(),
                ))
            }
            Expr::Bin(op, a, b) => self.binary(*op, a, b, site)?,
        })
    }

    fn binary(&mut self, op: BinOp, a: &Expr, b: &Expr, site: Site) -> Result<Value, EvalError> {
        use BinOp::*;
        // `&`, `|` and `->` do not evaluate an operand that cannot change the result, so a
        // guard like `n != 0 & 10 / n > 2` is not a division by zero.
        match op {
            And => {
                return Ok(Value::Bool(
                    self.boolean(a, site)? && self.boolean(b, site)?,
                ))
            }
            Or => {
                return Ok(Value::Bool(
                    self.boolean(a, site)? || self.boolean(b, site)?,
                ))
            }
            Implies => {
                return Ok(Value::Bool(
                    !self.boolean(a, site)? || self.boolean(b, site)?,
                ))
            }
            Xor | Xnor | Iff => {
                let (x, y) = (self.boolean(a, site)?, self.boolean(b, site)?);
                return Ok(Value::Bool((x != y) == (op == Xor)));
            }
            Eq | Ne => {
                let (x, y) = (self.value(a, site)?, self.value(b, site)?);
                let comparable = matches!(
                    (x, y),
                    (Value::Bool(_), Value::Bool(_))
                        | (Value::Int(_) | Value::Sym(_), Value::Int(_) | Value::Sym(_))
                );
                if !comparable {
                    return Err(self.type_error(
                        site,
                        format!(
                            "cannot compare {} with {}",
                            self.model.show(x),
                            self.model.show(y)
                        ),
                    ));
                }
                return Ok(Value::Bool((x == y) == (op == Eq)));
            }
            _ => {}
        }
        let (x, y) = (self.integer(a, site)?, self.integer(b, site)?);
        Ok(match op {
            Lt => Value::Bool(x < y),
            Le => Value::Bool(x <= y),
            Gt => Value::Bool(x > y),
            Ge => Value::Bool(x >= y),
            // NuSMV's 32-bit arithmetic, wrapping around, C's `/` and `%` (see `arith`).
            _ => match super::arith::arithmetic(op, x, y) {
                Some(r) => Value::Int(r),
                None => return Err(self.error(site, EvalErrorKind::DivisionByZero)),
            },
        })
    }
}

/// How the initial values of one variable are found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum InitMode {
    /// No `init`: every value of the domain.
    Free,
    /// `init` reads no variable: its values, computed once per parameter vector.
    Direct,
    /// `init` reads variables: every value of the domain, kept where `init` allows it.
    Filter,
}

/// The semantics of one model, with what can be computed once (which `init`s read the state).
#[derive(Debug, Clone)]
pub(crate) struct Semantics<'m> {
    model: &'m Model,
    init_mode: Vec<InitMode>,
}

impl<'m> Semantics<'m> {
    /// Prepares the semantics of `model` (classifies each `init` by whether it reads the state).
    pub(crate) fn new(model: &'m Model) -> Semantics<'m> {
        let init_mode = model
            .vars
            .iter()
            .map(|v| match &v.init {
                None => InitMode::Free,
                Some(e) if reads_state(model, e) => InitMode::Filter,
                Some(_) => InitMode::Direct,
            })
            .collect();
        Semantics { model, init_mode }
    }

    /// The model these semantics run.
    pub(crate) fn model(&self) -> &'m Model {
        self.model
    }

    /// The initial states under parameters `params`: `init` assignments, `INIT` and `INVAR`.
    pub(crate) fn initial_states(&self, params: &[bool]) -> Result<Vec<State>, EvalError> {
        let m = self.model;
        let empty: State = m.vars.iter().map(|v| v.domain[0]).collect();
        let mut choices = Vec::with_capacity(m.vars.len());
        for (i, var) in m.vars.iter().enumerate() {
            choices.push(match (self.init_mode[i], &var.init) {
                (InitMode::Direct, Some(e)) => {
                    self.checked_values(e, Site::Init(VarId(i)), &empty, params)?
                }
                _ => var.domain.clone(),
            });
        }
        let mut out = Vec::new();
        for_each_combination(m, &choices, &mut |s| {
            if self.initial_ok(s, params)? {
                out.push(s.to_vec());
            }
            Ok::<(), EvalError>(())
        })?;
        Ok(out)
    }

    fn initial_ok(&self, s: &[Value], params: &[bool]) -> Result<bool, EvalError> {
        let m = self.model;
        let mut env = Env::new(m, s, params, None);
        for (i, var) in m.vars.iter().enumerate() {
            if let (InitMode::Filter, Some(e)) = (self.init_mode[i], &var.init) {
                let allowed = env.values(e, Site::Init(VarId(i)))?;
                if let Some(bad) = allowed.iter().find(|v| !in_domain(var, **v)) {
                    return Err(out_of_domain(m, VarId(i), Site::Init(VarId(i)), *bad));
                }
                if !allowed.contains(&s[i]) {
                    return Ok(false);
                }
            }
        }
        for (k, c) in m.init.iter().enumerate() {
            if !env.boolean(&c.expr, Site::InitConstraint(k))? {
                return Ok(false);
            }
        }
        for (k, c) in m.invar.iter().enumerate() {
            if !env.boolean(&c.expr, Site::Invar(k))? {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The successors of `state` when the plant reads `params`: every `next` assignment and
    /// `TRANS` hold on `state`, `params` and the successor, and `INVAR` holds on the successor
    /// with `next_params` (the parameters of the next step: in the closed loop, the
    /// controller's outputs change together with the plant). Sorted, without repetition.
    pub(crate) fn successors(
        &self,
        state: &[Value],
        params: &[bool],
        next_params: &[bool],
    ) -> Result<Vec<State>, EvalError> {
        let mut out = Vec::new();
        self.for_each_successor(state, params, next_params, &mut |s| {
            out.push(s.to_vec());
            Ok::<(), EvalError>(())
        })?;
        Ok(out)
    }

    /// Calls `f` on each successor of [`Self::successors`], in the same order, without
    /// collecting them: the candidates (every combination of the values the assignments allow,
    /// free variables ranging over their domains) are made one at a time, so that a plant with
    /// many free inputs costs time per state, not memory.
    pub fn for_each_successor<E: From<EvalError>>(
        &self,
        state: &[Value],
        params: &[bool],
        next_params: &[bool],
        f: &mut impl FnMut(&[Value]) -> Result<(), E>,
    ) -> Result<(), E> {
        self.for_each_successor_where(state, params, next_params, &[], f)
    }

    /// The successors of `state` ([`Self::successors`]) in which each variable of `known`
    /// has the value given: the candidates are made with those values only, so that a replay
    /// that knows the next sensor values does not enumerate the others' combinations.
    pub(crate) fn successors_where(
        &self,
        state: &[Value],
        params: &[bool],
        next_params: &[bool],
        known: &[(VarId, Value)],
    ) -> Result<Vec<State>, EvalError> {
        let mut out = Vec::new();
        self.for_each_successor_where(state, params, next_params, known, &mut |s| {
            out.push(s.to_vec());
            Ok::<(), EvalError>(())
        })?;
        Ok(out)
    }

    fn for_each_successor_where<E: From<EvalError>>(
        &self,
        state: &[Value],
        params: &[bool],
        next_params: &[bool],
        known: &[(VarId, Value)],
        f: &mut impl FnMut(&[Value]) -> Result<(), E>,
    ) -> Result<(), E> {
        let (mut choices, later) = self.next_choices(state, params, known)?;
        let Some(order) = next_order(self.model, &later) else {
            return self.each_checked(state, params, next_params, &choices, &later, f);
        };
        // Each assignment that reads next values is evaluated once the values it reads are
        // chosen, instead of trying every value of its domain: a learned plant whose
        // environment reads the sensors' next values, with observers of next values, would
        // otherwise try 2^k candidates per successor.
        for &(i, _) in &order {
            choices[i].truncate(1);
        }
        let mut found = Vec::new();
        for_each_combination(self.model, &choices, &mut |s| {
            let mut s = s.to_vec();
            self.assign_next_readers(state, params, &order, known, &mut s, &mut |t| {
                if self.transition_ok(state, params, t, next_params)? {
                    found.push(t.to_vec());
                }
                Ok(())
            })
        })?;
        // The same order as the enumeration of [`Self::each_checked`]: sorted, without
        // repetition.
        found.sort();
        found.iter().try_for_each(|t| f(t))
    }

    /// Per variable, the values its next state may take from `state` (restricted by `known`),
    /// sorted and distinct; and the assignments that read another variable's next value, whose
    /// variables keep their whole domain here.
    fn next_choices<'e>(
        &'e self,
        state: &[Value],
        params: &[bool],
        known: &[(VarId, Value)],
    ) -> Result<(Vec<Vec<Value>>, NextReaders<'e>), EvalError> {
        let m = self.model;
        let mut env = Env::new(m, state, params, None);
        let mut choices = Vec::with_capacity(m.vars.len());
        // Assignments that read another variable's next value are checked on each candidate
        // successor instead (NuSMV allows `next(fills) := ... next(level) ...`).
        let mut later = Vec::new();
        for (i, var) in m.vars.iter().enumerate() {
            let mut vs = match (&var.next, var.kind) {
                (Some(e), VarKind::State) if reads_next(m, e) => {
                    later.push((i, e));
                    var.domain.clone()
                }
                (Some(e), VarKind::State) => {
                    let site = Site::Next(VarId(i));
                    let vs = env.values(e, site)?;
                    if let Some(bad) = vs.iter().find(|v| !in_domain(var, **v)) {
                        return Err(out_of_domain(m, VarId(i), site, *bad));
                    }
                    vs
                }
                _ => var.domain.clone(),
            };
            if let Some(&(_, v)) = known.iter().find(|(k, _)| k.0 == i) {
                vs.retain(|&x| x == v);
            }
            // Sorted choices make the combinations come sorted and distinct.
            vs.sort();
            vs.dedup();
            choices.push(vs);
        }
        Ok((choices, later))
    }

    /// Calls `f` on every combination of `choices` that the assignments in `later` give
    /// and the transition constraints admit, in sorted order.
    fn each_checked<E: From<EvalError>>(
        &self,
        state: &[Value],
        params: &[bool],
        next_params: &[bool],
        choices: &[Vec<Value>],
        later: &[(usize, &Expr)],
        f: &mut impl FnMut(&[Value]) -> Result<(), E>,
    ) -> Result<(), E> {
        let m = self.model;
        for_each_combination(m, choices, &mut |s| {
            if !later.is_empty() {
                let mut env = Env::new(m, state, params, Some(s));
                for &(i, e) in later {
                    let site = Site::Next(VarId(i));
                    let vs = env.values(e, site)?;
                    if let Some(bad) = vs.iter().find(|v| !in_domain(&m.vars[i], **v)) {
                        return Err(out_of_domain(m, VarId(i), site, *bad).into());
                    }
                    if !vs.contains(&s[i]) {
                        return Ok(());
                    }
                }
            }
            if self.transition_ok(state, params, s, next_params)? {
                f(s)?;
            }
            Ok(())
        })
    }

    /// Calls `f` on `s` with the variables of `order` (from the first) set, in turn, to each
    /// value their `next` assignment gives on `state`, `params` and `s` (restricted by
    /// `known`).
    fn assign_next_readers(
        &self,
        state: &[Value],
        params: &[bool],
        order: &[(usize, &Expr)],
        known: &[(VarId, Value)],
        s: &mut Vec<Value>,
        f: &mut impl FnMut(&[Value]) -> Result<(), EvalError>,
    ) -> Result<(), EvalError> {
        let Some((&(i, e), rest)) = order.split_first() else {
            return f(s);
        };
        let m = self.model;
        let site = Site::Next(VarId(i));
        let mut vs = Env::new(m, state, params, Some(s)).values(e, site)?;
        if let Some(bad) = vs.iter().find(|v| !in_domain(&m.vars[i], **v)) {
            return Err(out_of_domain(m, VarId(i), site, *bad));
        }
        if let Some(&(_, v)) = known.iter().find(|(k, _)| k.0 == i) {
            vs.retain(|&x| x == v);
        }
        vs.sort();
        vs.dedup();
        for v in vs {
            s[i] = v;
            self.assign_next_readers(state, params, rest, known, s, f)?;
        }
        Ok(())
    }

    /// How many combinations of values the plant's free variables (`IVAR`s, `VAR`s without
    /// `init` and `next`) take: a lower bound on the successors of every state when no
    /// `TRANS` or `INVAR` constrains them (saturating).
    pub fn free_combinations(&self) -> u128 {
        (self.model.vars.iter())
            .filter(|v| v.kind == VarKind::Input || (v.init.is_none() && v.next.is_none()))
            .fold(1u128, |n, v| n.saturating_mul(v.domain.len() as u128))
    }

    fn transition_ok(
        &self,
        state: &[Value],
        params: &[bool],
        succ: &[Value],
        next_params: &[bool],
    ) -> Result<bool, EvalError> {
        let m = self.model;
        if !m.trans.is_empty() {
            let mut env = Env::new(m, state, params, Some(succ));
            for (k, c) in m.trans.iter().enumerate() {
                if !env.boolean(&c.expr, Site::Trans(k))? {
                    return Ok(false);
                }
            }
        }
        if !m.invar.is_empty() {
            let mut env = Env::new(m, succ, next_params, None);
            for (k, c) in m.invar.iter().enumerate() {
                if !env.boolean(&c.expr, Site::Invar(k))? {
                    return Ok(false);
                }
            }
        }
        Ok(true)
    }

    /// Which `FAIRNESS` constraints hold on `state` with `params`: bit `k` for constraint `k`.
    /// At most 64 constraints (the caller checks).
    pub(crate) fn fairness(&self, state: &[Value], params: &[bool]) -> Result<u64, EvalError> {
        let mut env = Env::new(self.model, state, params, None);
        let mut bits = 0u64;
        for (k, c) in self.model.fairness.iter().enumerate() {
            if env.boolean(&c.expr, Site::Fairness(k))? {
                bits |= 1 << k;
            }
        }
        Ok(bits)
    }

    /// The value of a variable or define on `state` with `params`.
    pub(crate) fn read(
        &self,
        name: Name,
        state: &[Value],
        params: &[bool],
    ) -> Result<Value, EvalError> {
        Ok(match name {
            Name::Var(v) => state[v.0],
            Name::Define(d) => Env::new(self.model, state, params, None).define(d)?,
            Name::Param(p) => Value::Bool(params[p.0]),
        })
    }

    fn checked_values(
        &self,
        e: &Expr,
        site: Site,
        state: &[Value],
        params: &[bool],
    ) -> Result<Vec<Value>, EvalError> {
        let Site::Init(v) = site else {
            unreachable!("only init values are computed without a state")
        };
        let mut vs = eval(self.model, e, site, state, params, None)?;
        if let Some(bad) = vs.iter().find(|x| !in_domain(self.model.var(v), **x)) {
            return Err(out_of_domain(self.model, v, site, *bad));
        }
        vs.dedup();
        Ok(vs)
    }
}

fn out_of_domain(m: &Model, v: VarId, site: Site, value: Value) -> EvalError {
    let (construct, line) = site.describe(m);
    EvalError {
        file: m.file.clone(),
        line,
        construct,
        kind: EvalErrorKind::OutOfDomain {
            var: m.var(v).name.clone(),
            value: m.show(value),
        },
    }
}

/// Assignments that read another variable's next value: the variable and its `next`.
type NextReaders<'e> = Vec<(usize, &'e Expr)>;

/// The assignments of `later` (variable, `next` expression) ordered so that each comes after
/// those whose next values it reads; `None` when they read each other in a cycle (left to
/// the candidates' check, as NuSMV refuses such a model).
fn next_order<'e>(m: &Model, later: &[(usize, &'e Expr)]) -> Option<Vec<(usize, &'e Expr)>> {
    let mut left: Vec<(usize, &Expr, Vec<usize>)> = (later.iter())
        .map(|&(i, e)| {
            let mut read = Vec::new();
            next_reads(m, e, &mut read);
            // A variable reading its own next value is a cycle too: never ready below.
            read.retain(|w| later.iter().any(|(j, _)| j == w));
            (i, e, read)
        })
        .collect();
    let mut order = Vec::with_capacity(left.len());
    while !left.is_empty() {
        let k = (left.iter())
            .position(|(_, _, read)| read.iter().all(|w| order.iter().any(|(j, _)| j == w)))?;
        let (i, e, _) = left.remove(k);
        order.push((i, e));
    }
    Some(order)
}

/// The variables whose next value `e` reads (directly or through a define).
fn next_reads(m: &Model, e: &Expr, out: &mut Vec<usize>) {
    match e {
        Expr::Next(v) => out.push(v.0),
        Expr::Const(_) | Expr::Var(_) | Expr::Param(_) => {}
        Expr::Define(d) => next_reads(m, &m.defines[d.0].expr, out),
        Expr::Not(a) | Expr::Neg(a) => next_reads(m, a, out),
        Expr::Bin(_, a, b) => {
            next_reads(m, a, out);
            next_reads(m, b, out);
        }
        Expr::Case(bs) => bs.iter().for_each(|(c, v)| {
            next_reads(m, c, out);
            next_reads(m, v, out);
        }),
        Expr::Set(items) => items.iter().for_each(|i| next_reads(m, i, out)),
    }
}

/// Whether `e` reads a variable (directly, through `next` or through a define).
fn reads_state(m: &Model, e: &Expr) -> bool {
    reads(m, e, &|leaf| matches!(leaf, Expr::Var(_) | Expr::Next(_)))
}

/// Whether `e` reads a next value (directly or through a define).
fn reads_next(m: &Model, e: &Expr) -> bool {
    reads(m, e, &|leaf| matches!(leaf, Expr::Next(_)))
}

/// Whether `e` reads a parameter (directly or through a define).
pub(crate) fn reads_params(m: &Model, e: &Expr) -> bool {
    reads(m, e, &|leaf| matches!(leaf, Expr::Param(_)))
}

/// Whether some leaf of `e`, looking into defines, satisfies `hit`.
fn reads(m: &Model, e: &Expr, hit: &dyn Fn(&Expr) -> bool) -> bool {
    match e {
        Expr::Const(_) | Expr::Var(_) | Expr::Next(_) | Expr::Param(_) => hit(e),
        Expr::Define(d) => reads(m, &m.defines[d.0].expr, hit),
        Expr::Not(a) | Expr::Neg(a) => reads(m, a, hit),
        Expr::Bin(_, a, b) => reads(m, a, hit) || reads(m, b, hit),
        Expr::Case(bs) => bs.iter().any(|(c, v)| reads(m, c, hit) || reads(m, v, hit)),
        Expr::Set(items) => items.iter().any(|i| reads(m, i, hit)),
    }
}

/// Calls `f` on every combination of one value per variable, in lexicographic order of the
/// choices (the last variable changing fastest), one at a time; an error when there are more
/// than [`MAX_CANDIDATES`].
fn for_each_combination<E: From<EvalError>>(
    m: &Model,
    choices: &[Vec<Value>],
    f: &mut impl FnMut(&[Value]) -> Result<(), E>,
) -> Result<(), E> {
    let total = choices
        .iter()
        .fold(1u128, |n, c| n.saturating_mul(c.len() as u128));
    if total > MAX_CANDIDATES {
        return Err(EvalError {
            file: m.file.clone(),
            line: 0,
            construct: "the variables without init/next".into(),
            kind: EvalErrorKind::TooManyChoices(total),
        }
        .into());
    }
    if total == 0 {
        return Ok(());
    }
    let mut digits = vec![0; choices.len()];
    let mut current: State = choices.iter().map(|c| c[0]).collect();
    loop {
        f(&current)?;
        // An odometer: the last digit that can still advance does, those after it restart.
        let Some(k) = (0..choices.len())
            .rev()
            .find(|&k| digits[k] + 1 < choices[k].len())
        else {
            return Ok(());
        };
        digits[k] += 1;
        current[k] = choices[k][digits[k]];
        for j in k + 1..choices.len() {
            digits[j] = 0;
            current[j] = choices[j][0];
        }
    }
}

/// A parameter vector from bits: bit `p` is parameter `p`.
pub(crate) fn params_from_bits(bits: u64, n: usize) -> Vec<bool> {
    (0..n).map(|p| bits >> p & 1 == 1).collect()
}
