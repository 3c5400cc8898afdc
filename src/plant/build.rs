//! Plants written as Rust, for tests: a small builder and expression constructors.
//!
//! In: names, types and [`Expr`]s. Out: a [`Model`] as the parser would resolve it (lines are
//! made up: variable `k` on line `k + 2`, defines from 100, constraints from 200).
use crate::plant::*;

pub(crate) struct Builder {
    pub(crate) m: Model,
}

impl Builder {
    pub(crate) fn new(params: &[&str]) -> Builder {
        Builder {
            m: Model {
                file: "built.smv".into(),
                params: params.iter().map(|p| p.to_string()).collect(),
                vars: Vec::new(),
                defines: Vec::new(),
                init: Vec::new(),
                invar: Vec::new(),
                trans: Vec::new(),
                fairness: Vec::new(),
                symbols: Vec::new(),
            },
        }
    }

    pub(crate) fn sym(&mut self, name: &str) -> Value {
        match self.m.symbol(name) {
            Some(v) => v,
            None => {
                self.m.symbols.push(name.into());
                Value::Sym(self.m.symbols.len() as u32 - 1)
            }
        }
    }

    fn declare(&mut self, name: &str, ty: Type, kind: VarKind) -> Expr {
        let domain = match &ty {
            Type::Bool => vec![Value::Bool(false), Value::Bool(true)],
            Type::Range(lo, hi) => (*lo..=*hi).map(Value::Int).collect(),
            Type::Enum(vs) => vs.clone(),
        };
        self.m.vars.push(Var {
            name: name.into(),
            ty,
            kind,
            line: self.m.vars.len() + 2,
            domain,
            init: None,
            next: None,
        });
        Expr::Var(VarId(self.m.vars.len() - 1))
    }

    pub(crate) fn var(&mut self, name: &str, ty: Type) -> Expr {
        self.declare(name, ty, VarKind::State)
    }

    pub(crate) fn ivar(&mut self, name: &str, ty: Type) -> Expr {
        self.declare(name, ty, VarKind::Input)
    }

    pub(crate) fn enumeration(&mut self, name: &str, values: &[&str]) -> Expr {
        let vs = values.iter().map(|v| self.sym(v)).collect();
        self.var(name, Type::Enum(vs))
    }

    pub(crate) fn define(&mut self, name: &str, e: Expr) -> Expr {
        self.m.defines.push(Define {
            name: name.into(),
            line: 100 + self.m.defines.len(),
            expr: e,
        });
        Expr::Define(DefineId(self.m.defines.len() - 1))
    }

    pub(crate) fn param(&self, name: &str) -> Expr {
        match self.m.lookup(name) {
            Some(Name::Param(p)) => Expr::Param(p),
            _ => panic!("no parameter {name}"),
        }
    }

    fn id(v: &Expr) -> usize {
        match v {
            Expr::Var(VarId(i)) => *i,
            _ => panic!("not a variable"),
        }
    }

    pub(crate) fn init(&mut self, v: &Expr, e: Expr) {
        self.m.vars[Self::id(v)].init = Some(e);
    }

    pub(crate) fn next(&mut self, v: &Expr, e: Expr) {
        self.m.vars[Self::id(v)].next = Some(e);
    }

    fn constraint(&self, e: Expr) -> Constraint {
        Constraint {
            line: 200 + self.m.init.len() + self.m.invar.len() + self.m.trans.len(),
            expr: e,
        }
    }

    pub(crate) fn init_constraint(&mut self, e: Expr) {
        let c = self.constraint(e);
        self.m.init.push(c);
    }
    pub(crate) fn invar(&mut self, e: Expr) {
        let c = self.constraint(e);
        self.m.invar.push(c);
    }
    pub(crate) fn trans(&mut self, e: Expr) {
        let c = self.constraint(e);
        self.m.trans.push(c);
    }
    pub(crate) fn fairness(&mut self, e: Expr) {
        let c = self.constraint(e);
        self.m.fairness.push(c);
    }
}

pub(crate) fn int(i: i64) -> Expr {
    Expr::Const(Value::Int(i))
}
pub(crate) fn bool(b: bool) -> Expr {
    Expr::Const(Value::Bool(b))
}
pub(crate) fn not(a: Expr) -> Expr {
    Expr::Not(Box::new(a))
}
pub(crate) fn bin(op: BinOp, a: Expr, b: Expr) -> Expr {
    Expr::Bin(op, Box::new(a), Box::new(b))
}
pub(crate) fn and(parts: Vec<Expr>) -> Expr {
    parts
        .into_iter()
        .reduce(|a, b| bin(BinOp::And, a, b))
        .unwrap_or(bool(true))
}
pub(crate) fn or(parts: Vec<Expr>) -> Expr {
    parts
        .into_iter()
        .reduce(|a, b| bin(BinOp::Or, a, b))
        .unwrap_or(bool(false))
}
pub(crate) fn eq(a: Expr, b: Expr) -> Expr {
    bin(BinOp::Eq, a, b)
}
pub(crate) fn case(branches: Vec<(Expr, Expr)>) -> Expr {
    Expr::Case(branches)
}
pub(crate) fn set(items: Vec<Expr>) -> Expr {
    Expr::Set(items)
}
pub(crate) fn next_of(v: &Expr) -> Expr {
    match v {
        Expr::Var(id) => Expr::Next(*id),
        _ => panic!("not a variable"),
    }
}
