//! The surrogate plant as a finite-state model the tool itself can run: the subset of SMV the
//! project's plants use, parsed with `grammar/smv.pest` ([`parse`]) and resolved into a
//! [`Model`] whose every name is an index.
//!
//! In: the text of a plant file (`MODULE plant(params)` and the modules it instantiates). Out:
//! a [`Model`] of `MODULE plant` with its instances flattened as NuSMV flattens them (a name
//! `x` of instance `inst` becomes `inst.x`, a module's parameters its arguments),
//! or a [`ModelError`] naming the file, line and construct that is outside the subset.
//! [`explicit`] runs a model (initial states, successors, evaluation errors with their line);
//! [`print`](mod@print) writes it back as SMV text with the same meaning.
//!
//! # The subset
//! - `VAR` / `IVAR` of type `boolean`, `lo..hi` or `{a, b, ...}` (symbolic constants or
//!   integers); `DEFINE`; `ASSIGN` with `init(v) :=` and `next(v) :=` (a plain `v :=` is
//!   refused);
//! - expressions: `TRUE`/`FALSE`, integers, symbolic constants, names, `!`, `&`, `|`, `xor`,
//!   `xnor`, `->`, `<->`, `=`, `!=`, `<`, `<=`, `>`, `>=`, `+`, `-` (also unary), `*`, `/`,
//!   `mod`, `case ... esac`, `c ? a : b`, sets `{e1, e2}` (only as the value of `init`, `next`
//!   or a case branch of one), `next(v)` of a `VAR` (only inside `TRANS` and in the value of a
//!   `next` assignment, as NuSMV allows: `next(fills) := ... next(level) ...`), with NuSMV
//!   2.5.4's precedence (`grammar/smv.pest` lists it);
//! - `INIT`, `INVAR`, `TRANS`, `FAIRNESS` / `JUSTICE` (the same thing for LTL);
//! - NuSMV's static rules: strict types (Boolean and integer never mix), no `IVAR` in `INIT`,
//!   `INVAR` or `init(v)`, no cycle between defines, between `init` or between `next`
//!   assignments, no constant outside a variable's domain where an assignment can produce it;
//! - module instances `inst : m(args);` under `VAR`, at any depth, and dotted names `inst.x`;
//!
//! Anything else (`FROZENVAR`, arrays, words, processes, `COMPASSION`, CTL/LTL specs inside
//! the plant, ...) is refused with its line.
//!
//! # Semantics (NuSMV's, for a module instantiated once by the closed loop)
//! A state gives every `VAR` (and `IVAR`) a value of its domain. Initial states: every `init`
//! assignment holds (a set means "any of"; it may read other variables of the initial state),
//! every `INIT` and `INVAR` holds; a `VAR` without `init` is free. Successors of `s` with the
//! controller outputs `o` (the parameters): every `next` assignment holds, evaluated on `s`,
//! `o` and, for each `next(y)` it reads, the successor's `y` (the parser refuses cycles, so the
//! assignments can be evaluated in dependency order); `TRANS` holds on `s`, `o` and the
//! successor; `INVAR` holds on the successor; a `VAR` without `next` is free. A value outside a
//! variable's domain, a division by zero or a case without a true branch is an evaluation
//! error, as NuSMV reports it. An `IVAR` is chosen freely at every step, like a `VAR` without
//! `init` and `next`. Integers are NuSMV's C `int`s: 32 bits, wrapping around (module `arith`).

pub(crate) mod arith;
#[cfg(test)]
pub(crate) mod build;
pub(crate) mod explicit;
pub(crate) mod learn;
pub mod parse;
pub(crate) mod print;

pub use explicit::EvalError;

use std::fmt;
use std::path::PathBuf;

/// Index of a variable in [`Model::vars`] (0-based, declaration order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) struct VarId(pub(crate) usize);

/// Index of a define in [`Model::defines`] (0-based; defines are ordered so that each refers
/// only to earlier ones).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) struct DefineId(pub(crate) usize);

/// Index of a formal parameter of `MODULE plant` (0-based): a controller output, Boolean.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) struct ParamId(pub(crate) usize);

/// A value of the subset. Symbolic constants are interned in [`Model::symbols`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum Value {
    /// A Boolean (`TRUE`/`FALSE`).
    Bool(bool),
    /// An integer (of a range or an enumeration).
    Int(i64),
    /// A symbolic constant: index in [`Model::symbols`].
    Sym(u32),
}

/// The declared type of a variable.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Type {
    /// `boolean`.
    Bool,
    /// `lo..hi`, both included.
    Range(i64, i64),
    /// `{a, b, 3}`: the listed values, in order.
    Enum(Vec<Value>),
}

/// State variable (`VAR`) or input variable (`IVAR`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum VarKind {
    /// A `VAR`: part of the state, constrained by `init`/`next`.
    State,
    /// An `IVAR`: chosen freely at every step, not part of `INIT`/`INVAR`.
    Input,
}

/// A declared variable.
#[derive(Debug, Clone)]
pub(crate) struct Var {
    /// The name as declared.
    pub(crate) name: String,
    /// The declared type.
    pub(crate) ty: Type,
    /// Whether it was declared under `VAR` or `IVAR`.
    pub(crate) kind: VarKind,
    /// 1-based line of the declaration.
    pub(crate) line: usize,
    /// Every value of the type, in order (`Bool`: false, true).
    pub(crate) domain: Vec<Value>,
    /// `init(v) := e`, if any.
    pub(crate) init: Option<Expr>,
    /// `next(v) := e`, if any.
    pub(crate) next: Option<Expr>,
}

/// A `DEFINE name := expr;`.
#[derive(Debug, Clone)]
pub(crate) struct Define {
    /// The defined name.
    pub(crate) name: String,
    /// 1-based line of the definition.
    pub(crate) line: usize,
    /// The right-hand side, evaluated on the same state.
    pub(crate) expr: Expr,
}

/// A constraint section entry (`INIT`, `INVAR`, `TRANS`, `FAIRNESS`/`JUSTICE`), Boolean.
#[derive(Debug, Clone)]
pub(crate) struct Constraint {
    /// 1-based line of the entry.
    pub(crate) line: usize,
    /// The Boolean condition.
    pub(crate) expr: Expr,
}

/// Binary operators of the subset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum BinOp {
    /// `&`.
    And,
    /// `|`.
    Or,
    /// `xor`.
    Xor,
    /// `xnor`.
    Xnor,
    /// `->`.
    Implies,
    /// `<->`.
    Iff,
    /// `=`.
    Eq,
    /// `!=`.
    Ne,
    /// `<`.
    Lt,
    /// `<=`.
    Le,
    /// `>`.
    Gt,
    /// `>=`.
    Ge,
    /// `+`.
    Add,
    /// `-`.
    Sub,
    /// `*`.
    Mul,
    /// `/` (integer division; by zero is an evaluation error).
    Div,
    /// `mod` (by zero is an evaluation error).
    Mod,
}

/// An expression with every name resolved.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Expr {
    /// A literal value.
    Const(Value),
    /// Current value of a variable.
    Var(VarId),
    /// `next(v)` of a state variable, only inside `TRANS` and the value of a `next` assignment.
    Next(VarId),
    /// A define (evaluated on the same state).
    Define(DefineId),
    /// A formal parameter: the controller output of the current step.
    Param(ParamId),
    /// Boolean negation `!`.
    Not(Box<Expr>),
    /// Unary minus.
    Neg(Box<Expr>),
    /// A binary operation `lhs op rhs`.
    Bin(BinOp, Box<Expr>, Box<Expr>),
    /// `case c1 : e1; ...; esac`: the first branch whose condition holds.
    Case(Vec<(Expr, Expr)>),
    /// `{e1, e2, ...}`: any of the values (nondeterministic choice).
    Set(Vec<Expr>),
}

impl Expr {
    /// Calls `f` on this node and every node below it, parents first (not into the defines
    /// it refers to).
    pub(crate) fn walk(&self, f: &mut impl FnMut(&Expr)) {
        f(self);
        match self {
            Expr::Const(_) | Expr::Var(_) | Expr::Next(_) | Expr::Define(_) | Expr::Param(_) => {}
            Expr::Not(x) | Expr::Neg(x) => x.walk(f),
            Expr::Bin(_, a, b) => {
                a.walk(f);
                b.walk(f);
            }
            Expr::Case(branches) => branches.iter().for_each(|(c, v)| {
                c.walk(f);
                v.walk(f);
            }),
            Expr::Set(items) => items.iter().for_each(|x| x.walk(f)),
        }
    }
}

/// The plant, resolved.
#[derive(Debug, Clone)]
pub struct Model {
    /// Path of the plant file the model was read from (for messages).
    pub(crate) file: PathBuf,
    /// Formal parameters of `MODULE plant`, in order: controller outputs the plant reads.
    pub(crate) params: Vec<String>,
    /// Declared variables (`VAR` and `IVAR`), indexed by [`VarId`].
    pub(crate) vars: Vec<Var>,
    /// Defines, indexed by [`DefineId`], each referring only to earlier ones.
    pub(crate) defines: Vec<Define>,
    /// `INIT` constraints: every one holds in an initial state.
    pub(crate) init: Vec<Constraint>,
    /// `INVAR` constraints: every one holds in every reachable state.
    pub(crate) invar: Vec<Constraint>,
    /// `TRANS` constraints: every one holds between a state and its successor.
    pub(crate) trans: Vec<Constraint>,
    /// `FAIRNESS p` / `JUSTICE p`: along every fair path `p` holds infinitely often.
    pub(crate) fairness: Vec<Constraint>,
    /// Symbolic constants, indexed by [`Value::Sym`].
    pub(crate) symbols: Vec<String>,
}

/// What a bare name of the plant stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Name {
    /// A variable (`VAR` or `IVAR`).
    Var(VarId),
    /// A `DEFINE`.
    Define(DefineId),
    /// A formal parameter of `MODULE plant` (a controller output).
    Param(ParamId),
}

impl Model {
    /// The variable, define or parameter called `name`.
    pub(crate) fn lookup(&self, name: &str) -> Option<Name> {
        if let Some(i) = self.vars.iter().position(|v| v.name == name) {
            return Some(Name::Var(VarId(i)));
        }
        if let Some(i) = self.defines.iter().position(|d| d.name == name) {
            return Some(Name::Define(DefineId(i)));
        }
        self.params
            .iter()
            .position(|p| p == name)
            .map(|i| Name::Param(ParamId(i)))
    }

    /// The declaration of variable `v` (panics if `v` is not an index of [`Model::vars`]).
    pub(crate) fn var(&self, v: VarId) -> &Var {
        &self.vars[v.0]
    }

    /// The name a [`Name`] stands for.
    pub(crate) fn name_of(&self, n: Name) -> &str {
        match n {
            Name::Var(v) => &self.vars[v.0].name,
            Name::Define(d) => &self.defines[d.0].name,
            Name::Param(p) => &self.params[p.0],
        }
    }

    /// The symbolic constant called `name`, if the plant uses it.
    pub(crate) fn symbol(&self, name: &str) -> Option<Value> {
        self.symbols
            .iter()
            .position(|s| s == name)
            .map(|i| Value::Sym(i as u32))
    }

    /// A value as NuSMV prints it (`TRUE`, `3`, `idle`).
    pub(crate) fn show(&self, v: Value) -> String {
        match v {
            Value::Bool(true) => "TRUE".into(),
            Value::Bool(false) => "FALSE".into(),
            Value::Int(i) => i.to_string(),
            Value::Sym(s) => self.symbols[s as usize].clone(),
        }
    }
}

/// Why a plant file is not a [`Model`] of the subset.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The plant file could not be read.
    #[error("cannot read plant {}", file.display())]
    Io {
        /// Path of the plant file.
        file: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A line over the limit, or a file too large to read.
    #[error(transparent)]
    Read(crate::files::FileReadError),
    /// Displayed as `file:line:column: message`.
    #[error("{}:{line}:{column}: {message}", file.display())]
    At {
        /// Path of the plant file.
        file: PathBuf,
        /// 1-based line of the offending construct.
        line: usize,
        /// 1-based column of the offending construct.
        column: usize,
        /// What is wrong (e.g. a construct outside the subset, a type error).
        message: String,
    },
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Bool(true) => write!(f, "TRUE"),
            Value::Bool(false) => write!(f, "FALSE"),
            Value::Int(i) => write!(f, "{i}"),
            Value::Sym(s) => write!(f, "#{s}"),
        }
    }
}

impl Model {
    /// The variables and defines whose values no parameter (controller output or event) can
    /// influence: none of them is assigned, constrained or defined, directly or through other
    /// names, from a parameter. A fairness constraint that a parameter influences changes
    /// which runs count at all, so then no name is free of the controller.
    pub(crate) fn uncontrolled(&self) -> Vec<&str> {
        let mut var = vec![false; self.vars.len()];
        let mut def = vec![false; self.defines.len()];
        let reads = |e: &Expr, var: &[bool], def: &[bool]| {
            let mut hit = false;
            e.walk(&mut |x| match x {
                Expr::Param(_) => hit = true,
                Expr::Var(v) | Expr::Next(v) => hit |= var[v.0],
                Expr::Define(d) => hit |= def[d.0],
                _ => {}
            });
            hit
        };
        let constraints = || self.init.iter().chain(&self.invar).chain(&self.trans);
        loop {
            let before = (var.clone(), def.clone());
            // Defines refer only to earlier ones: one pass in order settles them.
            for d in 0..self.defines.len() {
                def[d] = def[d] || reads(&self.defines[d].expr, &var, &def);
            }
            for v in 0..self.vars.len() {
                let x = &self.vars[v];
                let assigned = x.init.iter().chain(&x.next);
                var[v] = var[v] || assigned.into_iter().any(|e| reads(e, &var, &def));
            }
            // A constraint couples every variable it reads with the controller.
            for c in constraints() {
                if reads(&c.expr, &var, &def) {
                    c.expr.walk(&mut |x| {
                        if let Expr::Var(v) | Expr::Next(v) = x {
                            var[v.0] = true;
                        }
                    });
                }
            }
            if (var.clone(), def.clone()) == before {
                break;
            }
        }
        if self.fairness.iter().any(|c| reads(&c.expr, &var, &def)) {
            return Vec::new();
        }
        let vars = (self.vars.iter().zip(&var)).filter(|(_, c)| !**c);
        let defines = (self.defines.iter().zip(&def)).filter(|(_, c)| !**c);
        (vars.map(|(v, _)| v.name.as_str()))
            .chain(defines.map(|(d, _)| d.name.as_str()))
            .collect()
    }
}
