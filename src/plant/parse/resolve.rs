//! From the syntax tree to the [`Model`]: every name becomes an index, every expression gets a
//! type, and the rules of the subset that the grammar leaves open are enforced, each with the
//! place it is broken:
//!
//! - one namespace for parameters, variables, defines and symbolic constants (a constant may
//!   appear in several enumerations, nothing else twice);
//! - defines ordered so that each refers only to earlier ones (a cycle is named);
//! - `init(v)` and `next(v)` at most once each, only for a `VAR`; `next(v)` inside expressions
//!   only in `TRANS` and in the value of a `next` assignment, without cycles between the
//!   assignments (NuSMV's own rule; `init` assignments likewise);
//! - input variables (`IVAR`) nowhere NuSMV refuses them: `INIT`, `INVAR`, `init(v)`;
//! - sets only as the value of an assignment or of a case branch in one;
//! - NuSMV 2.5's strict types: Boolean and integer never mix, symbolic values only where
//!   NuSMV takes them, and a constant outside a variable's domain is refused where the
//!   assignment can certainly produce it (see [`reach`](super::reach)).

use super::reach;
use super::syntax::{
    Assign, DefineDecl, EnumLit, Ident, Node, NodeKind, Plant, Section, Source, Target, TypeDecl,
};
use crate::plant::{
    BinOp, Constraint, Define, DefineId, Expr, Model, ModelError, ParamId, Type, Value, Var, VarId,
    VarKind,
};
use crate::quote::{cut, message, quote};
use std::collections::{BTreeSet, HashMap};

/// The most values a range type may have.
const MAX_RANGE_VALUES: i64 = 1 << 16;

/// The type of an expression, as NuSMV 2.5 distinguishes them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ty {
    Bool,
    Int,
    /// Symbolic constants only.
    Sym,
    /// Integers and symbolic constants (NuSMV's "integer-and-symbolic-enum").
    IntSym,
}

impl Ty {
    fn describe(self) -> &'static str {
        match self {
            Ty::Bool => "Boolean",
            Ty::Int => "an integer",
            Ty::Sym => "symbolic",
            Ty::IntSym => "an integer-or-symbolic value",
        }
    }

    fn of(ty: &Type) -> Ty {
        match ty {
            Type::Bool => Ty::Bool,
            Type::Range(..) => Ty::Int,
            Type::Enum(values) => {
                let ints = values.iter().any(|v| matches!(v, Value::Int(_)));
                let syms = values.iter().any(|v| matches!(v, Value::Sym(_)));
                match (ints, syms) {
                    (true, true) => Ty::IntSym,
                    (true, false) => Ty::Int,
                    _ => Ty::Sym,
                }
            }
        }
    }

    /// The type of a case whose branches have types `self` and `other`.
    fn join(self, other: Ty) -> Option<Ty> {
        match (self, other) {
            (a, b) if a == b => Some(a),
            (Ty::Bool, _) | (_, Ty::Bool) => None,
            _ => Some(Ty::IntSym),
        }
    }

    /// Whether `=` and `!=` take these two (NuSMV: never Boolean with the rest, never integers
    /// with symbolic constants alone).
    fn comparable(self, other: Ty) -> bool {
        match (self, other) {
            (Ty::Bool, b) | (b, Ty::Bool) => b == Ty::Bool,
            (Ty::Int, Ty::Sym) | (Ty::Sym, Ty::Int) => false,
            _ => true,
        }
    }

    /// Whether a variable of type `self` takes a value of type `value` (NuSMV: only a mixed
    /// enumeration takes more than its own kind).
    fn takes(self, value: Ty) -> bool {
        self == value || (self == Ty::IntSym && value != Ty::Bool)
    }
}

/// What a name of the plant file stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Decl {
    Param(ParamId),
    Var(VarId),
    /// Before the defines are ordered: the index in declaration order; after: the [`DefineId`].
    Define(usize),
    Symbol(u32),
}

/// Where an expression stands, for the rules that depend on it and for messages.
#[derive(Debug, Clone, Copy)]
enum Place<'p> {
    Define(&'p str),
    Assign(Target, &'p str),
    Constraint(Section),
}

impl Place<'_> {
    /// `next(v)` is allowed: in TRANS and in the value of a next assignment.
    fn next_ok(self) -> bool {
        matches!(
            self,
            Place::Assign(Target::Next, _) | Place::Constraint(Section::Trans)
        )
    }

    /// Input variables are allowed: NuSMV refuses them in INIT, INVAR and init assignments.
    fn input_ok(self) -> bool {
        !matches!(
            self,
            Place::Assign(Target::Init, _)
                | Place::Constraint(Section::Init)
                | Place::Constraint(Section::Invar)
        )
    }

    fn describe(self) -> String {
        match self {
            Place::Define(name) => format!("DEFINE {}", cut(name)),
            Place::Assign(target, var) => format!("{}({})", target.keyword(), cut(var)),
            Place::Constraint(section) => section.keyword().to_string(),
        }
    }
}

/// What the resolver knows about a define once it is resolved.
struct DefineInfo {
    ty: Ty,
    /// An input variable it reads, directly or through other defines.
    input: Option<VarId>,
    /// Every variable it reads, directly or through other defines.
    vars: BTreeSet<VarId>,
}

struct Resolver<'a> {
    src: &'a Source<'a>,
    names: HashMap<String, (Decl, usize)>,
    params: Vec<String>,
    vars: Vec<Var>,
    var_ty: Vec<Ty>,
    symbols: Vec<String>,
    /// Resolved defines, in dependency order.
    defines: Vec<Define>,
    define_info: Vec<DefineInfo>,
}

/// Resolves a parsed plant.
pub(super) fn resolve(src: &Source, plant: Plant) -> Result<Model, ModelError> {
    let mut r = Resolver {
        src,
        names: HashMap::new(),
        params: plant.params.iter().map(|p| p.name.clone()).collect(),
        vars: Vec::new(),
        var_ty: Vec::new(),
        symbols: Vec::new(),
        defines: Vec::new(),
        define_info: Vec::new(),
    };
    r.declare(&plant)?;
    r.variables(&plant)?;
    let order = r.define_order(&plant.defines)?;
    for &i in &order {
        r.define(&plant.defines[i])?;
    }
    let mut assigned: HashMap<(Target, VarId), usize> = HashMap::new();
    for assign in &plant.assigns {
        r.assign(assign, &mut assigned)?;
    }
    let (mut init, mut invar, mut trans, mut fairness) = (vec![], vec![], vec![], vec![]);
    for c in &plant.constraints {
        let place = Place::Constraint(c.section);
        let (expr, ty) = r.expr(&c.expr, place)?;
        if ty != Ty::Bool {
            return Err(r.error(
                c.expr.pos,
                format!(
                    "{} needs a Boolean expression, but `{}` is {}",
                    c.section.keyword(),
                    r.text(&c.expr),
                    ty.describe()
                ),
            ));
        }
        let constraint = Constraint {
            line: src.line(c.pos),
            expr,
        };
        match c.section {
            Section::Init => init.push(constraint),
            Section::Invar => invar.push(constraint),
            Section::Trans => trans.push(constraint),
            Section::Fairness | Section::Justice => fairness.push(constraint),
        }
    }
    r.assignment_cycles(Target::Init, &assigned)?;
    r.assignment_cycles(Target::Next, &assigned)?;
    Ok(Model {
        file: src.file.to_path_buf(),
        params: r.params,
        vars: r.vars,
        defines: r.defines,
        init,
        invar,
        trans,
        fairness,
        symbols: r.symbols,
    })
}

impl Resolver<'_> {
    fn error(&self, pos: usize, message: impl Into<String>) -> ModelError {
        self.src.error(pos, message)
    }

    /// An error about an expression, naming where it stands.
    fn error_in(&self, pos: usize, place: Place, message: impl std::fmt::Display) -> ModelError {
        self.error(pos, format!("{message} (in {})", place.describe()))
    }

    fn text(&self, node: &Node) -> String {
        self.src.snippet(node.pos, node.end)
    }

    fn what(&self, decl: Decl) -> &'static str {
        match decl {
            Decl::Param(_) => "a parameter",
            Decl::Var(v) if self.vars.get(v.0).map(|v| v.kind) == Some(VarKind::Input) => {
                "an input variable"
            }
            Decl::Var(_) => "a variable",
            Decl::Define(_) => "a define",
            Decl::Symbol(_) => "a symbolic constant",
        }
    }

    /// Enters every declared name, in the order of the text, so that a clash is reported at
    /// the later of the two. Symbolic constants are interned in the order they first appear.
    fn declare(&mut self, plant: &Plant) -> Result<(), ModelError> {
        let mut decls: Vec<(usize, &str, Option<Decl>)> = Vec::new();
        for (i, p) in plant.params.iter().enumerate() {
            decls.push((p.pos, &p.name, Some(Decl::Param(ParamId(i)))));
        }
        for (i, v) in plant.vars.iter().enumerate() {
            decls.push((v.name.pos, &v.name.name, Some(Decl::Var(VarId(i)))));
            if let TypeDecl::Enum(items) = &v.ty {
                for item in items {
                    if let EnumLit::Sym(s) = &item.value {
                        decls.push((item.pos, s, None));
                    }
                }
            }
        }
        for (i, d) in plant.defines.iter().enumerate() {
            decls.push((d.name.pos, &d.name.name, Some(Decl::Define(i))));
        }
        decls.sort_by_key(|d| d.0);
        for (pos, name, decl) in decls {
            let decl = match (decl, self.names.get(name)) {
                // A symbolic constant may stand in several enumerations.
                (None, Some(&(Decl::Symbol(_), _))) => continue,
                (None, _) => Decl::Symbol(self.symbols.len() as u32),
                (Some(d), _) => d,
            };
            if let Some(&(first, first_pos)) = self.names.get(name) {
                let shown = quote(name);
                let line = self.src.line(first_pos);
                let (what_first, what_now) = (self.what(first), self.what_declared(decl, plant));
                let message = if matches!(first, Decl::Symbol(_)) || matches!(decl, Decl::Symbol(_))
                {
                    format!("{shown} is both {what_now} here and {what_first} on line {line}")
                } else {
                    format!(
                        "{shown} is declared twice: {what_first} on line {line} and {what_now} here"
                    )
                };
                return Err(self.error(pos, message));
            }
            if let Decl::Symbol(_) = decl {
                self.symbols.push(name.to_string());
            }
            self.names.insert(name.to_string(), (decl, pos));
        }
        Ok(())
    }

    /// [`Self::what`] for a declaration whose variable is not built yet.
    fn what_declared(&self, decl: Decl, plant: &Plant) -> &'static str {
        match decl {
            Decl::Var(v) if plant.vars[v.0].kind == VarKind::Input => "an input variable",
            d => self.what(d),
        }
    }

    /// Builds the variables with their types and domains.
    fn variables(&mut self, plant: &Plant) -> Result<(), ModelError> {
        for v in &plant.vars {
            let name = &v.name.name;
            let shown = quote(name);
            let (ty, domain) = match &v.ty {
                TypeDecl::Bool => (Type::Bool, vec![Value::Bool(false), Value::Bool(true)]),
                &TypeDecl::Range { lo, hi, pos } => {
                    if lo > hi {
                        return Err(self.error(
                            pos,
                            format!("the range {lo}..{hi} of {shown} is empty ({lo} > {hi})"),
                        ));
                    }
                    if hi - lo + 1 > MAX_RANGE_VALUES {
                        return Err(self.error(
                            pos,
                            format!(
                                "the range {lo}..{hi} of {shown} has {} values; at most \
                                 {MAX_RANGE_VALUES} are supported",
                                hi - lo + 1
                            ),
                        ));
                    }
                    (Type::Range(lo, hi), (lo..=hi).map(Value::Int).collect())
                }
                TypeDecl::Enum(items) => {
                    let mut values: Vec<Value> = Vec::new();
                    for item in items {
                        let value = match &item.value {
                            EnumLit::Int(i) => Value::Int(*i),
                            EnumLit::Sym(s) => match self.names[s.as_str()].0 {
                                Decl::Symbol(id) => Value::Sym(id),
                                _ => unreachable!("declare refused a constant named like {s}"),
                            },
                            EnumLit::Bool(b) => {
                                let b = if *b { "TRUE" } else { "FALSE" };
                                return Err(self.error(
                                    item.pos,
                                    format!(
                                        "{b} cannot be a value of an enumeration (type of \
                                         {shown}); declare a boolean instead"
                                    ),
                                ));
                            }
                        };
                        if values.contains(&value) {
                            return Err(self.error(
                                item.pos,
                                format!(
                                    "the value {} appears twice in the type of {shown}",
                                    self.show(value)
                                ),
                            ));
                        }
                        values.push(value);
                    }
                    (Type::Enum(values.clone()), values)
                }
            };
            self.var_ty.push(Ty::of(&ty));
            self.vars.push(Var {
                name: name.clone(),
                ty,
                kind: v.kind,
                line: self.src.line(v.name.pos),
                domain,
                init: None,
                next: None,
            });
        }
        Ok(())
    }

    fn show(&self, v: Value) -> String {
        match v {
            Value::Sym(s) => cut(&self.symbols[s as usize]).to_string(),
            v => v.to_string(),
        }
    }

    /// A variable's type as written (`boolean`, `0..2`, `{a, b}`).
    fn show_type(&self, ty: &Type) -> String {
        match ty {
            Type::Bool => "boolean".into(),
            Type::Range(lo, hi) => format!("{lo}..{hi}"),
            Type::Enum(values) => {
                let values: Vec<String> = values.iter().map(|&v| self.show(v)).collect();
                message(&format!("{{{}}}", values.join(", "))).to_string()
            }
        }
    }

    /// Orders the defines so that each refers only to earlier ones, and gives each its
    /// [`DefineId`] in that order. Returns the declaration indices in the new order.
    fn define_order(&mut self, defines: &[DefineDecl]) -> Result<Vec<usize>, ModelError> {
        let deps: Vec<Vec<usize>> = defines
            .iter()
            .map(|d| {
                let mut deps = Vec::new();
                names_in(&d.expr, &mut |name| {
                    if let Some(&(Decl::Define(j), _)) = self.names.get(name) {
                        if !deps.contains(&j) {
                            deps.push(j);
                        }
                    }
                });
                deps
            })
            .collect();
        let order = topological_order(&deps).map_err(|cycle| {
            let names: Vec<&str> = cycle
                .iter()
                .chain(cycle.first())
                .map(|&i| defines[i].name.name.as_str())
                .collect();
            let first = &defines[cycle[0]].name;
            self.error(
                first.pos,
                format!(
                    "define {} depends on itself: {}",
                    quote(&first.name),
                    message(&names.join(" -> "))
                ),
            )
        })?;
        for (id, &i) in order.iter().enumerate() {
            let entry = self
                .names
                .get_mut(&defines[i].name.name)
                .expect("every define is declared");
            entry.0 = Decl::Define(id);
        }
        Ok(order)
    }

    fn define(&mut self, d: &DefineDecl) -> Result<(), ModelError> {
        let (expr, ty) = self.expr(&d.expr, Place::Define(&d.name.name))?;
        let mut info = DefineInfo {
            ty,
            input: None,
            vars: BTreeSet::new(),
        };
        expr.walk(&mut |e| match *e {
            Expr::Var(v) => {
                info.vars.insert(v);
                if self.vars[v.0].kind == VarKind::Input {
                    info.input = info.input.or(Some(v));
                }
            }
            Expr::Define(other) => {
                let other = &self.define_info[other.0];
                info.vars.extend(other.vars.iter().copied());
                info.input = info.input.or(other.input);
            }
            _ => {}
        });
        self.define_info.push(info);
        self.defines.push(Define {
            name: d.name.name.clone(),
            line: self.src.line(d.name.pos),
            expr,
        });
        Ok(())
    }

    fn assign(
        &mut self,
        a: &Assign,
        assigned: &mut HashMap<(Target, VarId), usize>,
    ) -> Result<(), ModelError> {
        let name = &a.var.name;
        let (shown, bare) = (quote(name), cut(name));
        let keyword = a.target.keyword();
        let v = match self.names.get(name.as_str()) {
            Some(&(Decl::Var(v), _)) => v,
            Some(&(decl, _)) => {
                return Err(self.error(
                    a.var.pos,
                    format!(
                        "{keyword}({bare}): {shown} is {}, and only variables are assigned",
                        self.what(decl)
                    ),
                ))
            }
            None => return Err(self.unknown(&a.var)),
        };
        if self.vars[v.0].kind == VarKind::Input {
            return Err(self.error(
                a.var.pos,
                format!(
                    "{keyword}({bare}): {shown} is an input variable (IVAR), chosen freely at \
                     every step; only a VAR is assigned"
                ),
            ));
        }
        if let Some(&first) = assigned.get(&(a.target, v)) {
            return Err(self.error(
                a.pos,
                format!(
                    "{keyword}({bare}) is assigned twice (first on line {})",
                    self.src.line(first)
                ),
            ));
        }
        assigned.insert((a.target, v), a.pos);
        let place = Place::Assign(a.target, name);
        let value = self.value(&a.value, v, place, &mut Vec::new())?;
        let var = &mut self.vars[v.0];
        match a.target {
            Target::Init => var.init = Some(value),
            Target::Next => var.next = Some(value),
        }
        Ok(())
    }

    /// The value of an assignment to `var`: a case (or `? :`) whose branch values are values
    /// again, a set of expressions, or an expression. `path` holds the branch conditions
    /// (with the truth value they need) that lead here.
    fn value(
        &self,
        node: &Node,
        var: VarId,
        place: Place,
        path: &mut Vec<(Expr, bool)>,
    ) -> Result<Expr, ModelError> {
        // A `c ? a : b` is the case `c : a; TRUE : b;` (no condition written for `TRUE`).
        let branches: Vec<(Option<&Node>, &Node)> = match &node.kind {
            NodeKind::Case(branches) => branches.iter().map(|(c, v)| (Some(c), v)).collect(),
            NodeKind::Ite(c, a, b) => vec![(Some(c), a), (None, b)],
            NodeKind::Set(items) => {
                let items = items
                    .iter()
                    .map(|item| self.leaf_value(item, var, place, path))
                    .collect::<Result<Vec<_>, _>>()?;
                return Ok(Expr::Set(items));
            }
            _ => return self.leaf_value(node, var, place, path),
        };
        let ternary = matches!(node.kind, NodeKind::Ite(..));
        let depth = path.len();
        let mut out = Vec::with_capacity(branches.len());
        for (c, v) in branches {
            let cond = match c {
                Some(c) => self.condition(c, place, ternary)?,
                None => Expr::Const(Value::Bool(true)),
            };
            path.push((cond.clone(), true));
            let value = self.value(v, var, place, path)?;
            path.pop();
            path.push((cond.clone(), false));
            out.push((cond, value));
        }
        path.truncate(depth);
        Ok(Expr::Case(out))
    }

    /// One value an assignment can give `var`: of its type, and, if a constant, of its
    /// domain whenever the branches leading here can be taken.
    fn leaf_value(
        &self,
        node: &Node,
        var: VarId,
        place: Place,
        path: &[(Expr, bool)],
    ) -> Result<Expr, ModelError> {
        let (expr, ty) = self.expr(node, place)?;
        let v = &self.vars[var.0];
        if !self.var_ty[var.0].takes(ty) {
            return Err(self.error_in(
                node.pos,
                place,
                format!(
                    "{} has type {}, but the value `{}` is {}",
                    quote(&v.name),
                    self.show_type(&v.ty),
                    self.text(node),
                    ty.describe()
                ),
            ));
        }
        if let Expr::Const(c) = expr {
            if !v.domain.contains(&c)
                && reach::can_be_taken(&self.vars, &self.defines, self.params.len(), path)
            {
                return Err(self.error_in(
                    node.pos,
                    place,
                    format!(
                        "the value {} is outside the type {} of {}",
                        self.show(c),
                        self.show_type(&v.ty),
                        quote(&v.name)
                    ),
                ));
            }
        }
        Ok(expr)
    }

    /// The condition of a case branch or, `ternary`, of `? :`.
    fn condition(&self, node: &Node, place: Place, ternary: bool) -> Result<Expr, ModelError> {
        let (expr, ty) = self.expr(node, place)?;
        self.need(node, ty, Ty::Bool, place, |t| {
            let what = if ternary {
                "the condition of '? :'"
            } else {
                "a case condition"
            };
            format!("{what} must be Boolean, but `{t}` is {}", ty.describe())
        })?;
        Ok(expr)
    }

    /// Refuses `node` of type `got` where `want` is needed, with the message `message(text)`.
    fn need(
        &self,
        node: &Node,
        got: Ty,
        want: Ty,
        place: Place,
        message: impl FnOnce(&str) -> String,
    ) -> Result<(), ModelError> {
        if got == want {
            Ok(())
        } else {
            Err(self.error_in(node.pos, place, message(&self.text(node))))
        }
    }

    fn unknown(&self, ident: &Ident) -> ModelError {
        let name = &ident.name;
        let shown = quote(name);
        let hint = if name.contains('-') {
            format!(" (NuSMV reads {shown} as one name: put blanks around '-' to subtract)")
        } else {
            String::new()
        };
        self.error(
            ident.pos,
            format!(
                "unknown name {shown}: no parameter, variable, define or symbolic constant of \
                 the plant{hint}"
            ),
        )
    }

    /// Resolves an expression that is not the value of an assignment, with its type.
    fn expr(&self, node: &Node, place: Place) -> Result<(Expr, Ty), ModelError> {
        match &node.kind {
            NodeKind::Bool(b) => Ok((Expr::Const(Value::Bool(*b)), Ty::Bool)),
            NodeKind::Int(i) => Ok((Expr::Const(Value::Int(*i)), Ty::Int)),
            NodeKind::Name(name) => self.name(node.pos, name, place),
            NodeKind::Next(arg) => self.next(node, arg, place),
            NodeKind::Not(x) => {
                let (e, ty) = self.expr(x, place)?;
                self.need(x, ty, Ty::Bool, place, |t| {
                    format!(
                        "'!' needs a Boolean operand, but `{t}` is {}",
                        ty.describe()
                    )
                })?;
                Ok((Expr::Not(Box::new(e)), Ty::Bool))
            }
            NodeKind::Neg(x) => {
                let (e, ty) = self.expr(x, place)?;
                self.need(x, ty, Ty::Int, place, |t| {
                    format!(
                        "unary '-' needs an integer operand, but `{t}` is {}",
                        ty.describe()
                    )
                })?;
                Ok(match e {
                    Expr::Const(Value::Int(i)) => (
                        Expr::Const(Value::Int(crate::plant::arith::negate(i))),
                        Ty::Int,
                    ),
                    e => (Expr::Neg(Box::new(e)), Ty::Int),
                })
            }
            NodeKind::Bin {
                op,
                op_pos,
                left,
                right,
            } => self.binary(*op, *op_pos, left, right, place),
            NodeKind::Case(branches) => {
                let mut out = Vec::with_capacity(branches.len());
                let mut ty: Option<Ty> = None;
                for (c, v) in branches {
                    let cond = self.condition(c, place, false)?;
                    let (value, vty) = self.expr(v, place)?;
                    ty = Some(self.join(ty, vty, v, place)?);
                    out.push((cond, value));
                }
                Ok((Expr::Case(out), ty.expect("a case has a branch")))
            }
            NodeKind::Ite(c, a, b) => {
                let cond = self.condition(c, place, true)?;
                let (then, ty) = self.expr(a, place)?;
                let (otherwise, oty) = self.expr(b, place)?;
                let ty = self.join(Some(ty), oty, b, place)?;
                let case = vec![(cond, then), (Expr::Const(Value::Bool(true)), otherwise)];
                Ok((Expr::Case(case), ty))
            }
            NodeKind::Set(_) => Err(self.error_in(
                node.pos,
                place,
                "a set {...} stands only as the whole value of init(v) or next(v), or of a \
                 case branch in one",
            )),
        }
    }

    /// The type of a case so far (`acc`) joined with a branch value's.
    fn join(&self, acc: Option<Ty>, ty: Ty, node: &Node, place: Place) -> Result<Ty, ModelError> {
        let Some(acc) = acc else { return Ok(ty) };
        acc.join(ty).ok_or_else(|| {
            self.error_in(
                node.pos,
                place,
                format!(
                    "the branches mix Boolean and other values: `{}` is {}, an earlier branch \
                     is {}",
                    self.text(node),
                    ty.describe(),
                    acc.describe()
                ),
            )
        })
    }

    fn name(&self, pos: usize, name: &str, place: Place) -> Result<(Expr, Ty), ModelError> {
        let Some(&(decl, _)) = self.names.get(name) else {
            return Err(self.unknown(&Ident {
                name: name.to_string(),
                pos,
            }));
        };
        let input_refused = |var: VarId, through: Option<&str>| {
            let through = through
                .map(|d| format!(" through define {}", quote(d)))
                .unwrap_or_default();
            self.error_in(
                pos,
                place,
                format!(
                    "input variable {} is read{through}; NuSMV refuses input variables in \
                     INIT, INVAR and init()",
                    quote(&self.vars[var.0].name)
                ),
            )
        };
        match decl {
            Decl::Param(p) => Ok((Expr::Param(p), Ty::Bool)),
            Decl::Var(v) => {
                if self.vars[v.0].kind == VarKind::Input && !place.input_ok() {
                    return Err(input_refused(v, None));
                }
                Ok((Expr::Var(v), self.var_ty[v.0]))
            }
            Decl::Define(d) => {
                let info = &self.define_info[d];
                if let (Some(v), false) = (info.input, place.input_ok()) {
                    return Err(input_refused(v, Some(name)));
                }
                Ok((Expr::Define(DefineId(d)), info.ty))
            }
            Decl::Symbol(s) => Ok((Expr::Const(Value::Sym(s)), Ty::Sym)),
        }
    }

    fn next(&self, node: &Node, arg: &Node, place: Place) -> Result<(Expr, Ty), ModelError> {
        if !place.next_ok() {
            return Err(self.error_in(
                node.pos,
                place,
                "next() stands only in TRANS and in the value of next(v) := ...",
            ));
        }
        let NodeKind::Name(name) = &arg.kind else {
            return Err(self.error_in(
                arg.pos,
                place,
                format!(
                    "next() of an expression (`{}`) is outside the subset: write next(v) of \
                     each variable",
                    self.text(arg)
                ),
            ));
        };
        let refuse = |why: String| Err(self.error_in(arg.pos, place, why));
        let (shown, bare) = (quote(name), cut(name));
        match self.names.get(name.as_str()) {
            None => Err(self.unknown(&Ident {
                name: name.clone(),
                pos: arg.pos,
            })),
            Some(&(Decl::Var(v), _)) if self.vars[v.0].kind == VarKind::State => {
                Ok((Expr::Next(v), self.var_ty[v.0]))
            }
            Some(&(Decl::Var(_), _)) => refuse(format!(
                "next({bare}): {shown} is an input variable, which has no next value in NuSMV"
            )),
            Some(&(Decl::Define(_), _)) => refuse(format!(
                "next({bare}) of a define is outside the subset: write it with next() of the \
                 variables {shown} reads"
            )),
            Some(&(Decl::Param(_), _)) => refuse(format!(
                "next({bare}): {shown} is a parameter (a controller output), which the plant \
                 sees only at the current step"
            )),
            Some(&(Decl::Symbol(_), _)) => refuse(format!(
                "next({bare}): {shown} is a symbolic constant, not a variable"
            )),
        }
    }

    fn binary(
        &self,
        op: BinOp,
        op_pos: usize,
        left: &Node,
        right: &Node,
        place: Place,
    ) -> Result<(Expr, Ty), ModelError> {
        let (l, lt) = self.expr(left, place)?;
        let (r, rt) = self.expr(right, place)?;
        let symbol = op_symbol(op);
        let (operand_ty, result) = match op {
            BinOp::And | BinOp::Or | BinOp::Xor | BinOp::Xnor | BinOp::Implies | BinOp::Iff => {
                (Some(Ty::Bool), Ty::Bool)
            }
            BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => (Some(Ty::Int), Ty::Bool),
            BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Mod => {
                (Some(Ty::Int), Ty::Int)
            }
            BinOp::Eq | BinOp::Ne => (None, Ty::Bool),
        };
        match operand_ty {
            Some(want) => {
                for (node, ty) in [(left, lt), (right, rt)] {
                    self.need(node, ty, want, place, |t| {
                        let kind = if want == Ty::Bool {
                            "Boolean"
                        } else {
                            "integer"
                        };
                        format!(
                            "'{symbol}' needs {kind} operands, but `{t}` is {}",
                            ty.describe()
                        )
                    })?;
                }
            }
            None if !lt.comparable(rt) => {
                return Err(self.error_in(
                    op_pos,
                    place,
                    format!(
                        "'{symbol}' cannot compare `{}` ({}) with `{}` ({})",
                        self.text(left),
                        lt.describe(),
                        self.text(right),
                        rt.describe()
                    ),
                ))
            }
            None => {}
        }
        Ok((Expr::Bin(op, Box::new(l), Box::new(r)), result))
    }

    /// Refuses a cycle between the `init` (or `next`) assignments: NuSMV computes them in
    /// dependency order and reports a recursion. `init(x)` depends on `init(y)` when it reads
    /// `y` (directly or through defines) and `y` has an `init` assignment; `next(x)` depends on
    /// `next(y)` when it reads `next(y)` and `y` has a `next` assignment.
    fn assignment_cycles<'a>(
        &'a self,
        target: Target,
        assigned: &HashMap<(Target, VarId), usize>,
    ) -> Result<(), ModelError> {
        let value = |v: &'a Var| match target {
            Target::Init => v.init.as_ref(),
            Target::Next => v.next.as_ref(),
        };
        let deps: Vec<Vec<usize>> = self
            .vars
            .iter()
            .map(|var| {
                let mut deps = Vec::new();
                let mut add = |y: VarId| {
                    if value(&self.vars[y.0]).is_some() && !deps.contains(&y.0) {
                        deps.push(y.0);
                    }
                };
                if let Some(e) = value(var) {
                    e.walk(&mut |e| match (target, e) {
                        (Target::Init, Expr::Var(y)) => add(*y),
                        (Target::Init, Expr::Define(d)) => {
                            self.define_info[d.0].vars.iter().for_each(|&y| add(y))
                        }
                        (Target::Next, Expr::Next(y)) => add(*y),
                        _ => {}
                    });
                }
                deps
            })
            .collect();
        topological_order(&deps).map(drop).map_err(|cycle| {
            let keyword = target.keyword();
            let names: Vec<String> = cycle
                .iter()
                .chain(cycle.first())
                .map(|&i| format!("{keyword}({})", self.vars[i].name))
                .collect();
            let first = cycle[0];
            self.error(
                assigned[&(target, VarId(first))],
                format!("{} depends on itself: {}", names[0], names.join(" -> ")),
            )
        })
    }
}

fn op_symbol(op: BinOp) -> &'static str {
    match op {
        BinOp::And => "&",
        BinOp::Or => "|",
        BinOp::Xor => "xor",
        BinOp::Xnor => "xnor",
        BinOp::Implies => "->",
        BinOp::Iff => "<->",
        BinOp::Eq => "=",
        BinOp::Ne => "!=",
        BinOp::Lt => "<",
        BinOp::Le => "<=",
        BinOp::Gt => ">",
        BinOp::Ge => ">=",
        BinOp::Add => "+",
        BinOp::Sub => "-",
        BinOp::Mul => "*",
        BinOp::Div => "/",
        BinOp::Mod => "mod",
    }
}

/// Calls `f` on every name a syntax tree refers to.
fn names_in<'n>(node: &'n Node, f: &mut impl FnMut(&'n str)) {
    match &node.kind {
        NodeKind::Bool(_) | NodeKind::Int(_) => {}
        NodeKind::Name(name) => f(name),
        NodeKind::Next(x) | NodeKind::Not(x) | NodeKind::Neg(x) => names_in(x, f),
        NodeKind::Bin { left, right, .. } => {
            names_in(left, f);
            names_in(right, f);
        }
        NodeKind::Case(branches) => branches.iter().for_each(|(c, v)| {
            names_in(c, f);
            names_in(v, f);
        }),
        NodeKind::Ite(c, a, b) => [c, a, b].into_iter().for_each(|x| names_in(x, f)),
        NodeKind::Set(items) => items.iter().for_each(|x| names_in(x, f)),
    }
}

/// Orders nodes `0..deps.len()` so that each comes after the nodes it depends on, keeping the
/// given order where the dependencies allow (always the lowest ready node next). On a cycle,
/// returns one, starting at its lowest node.
fn topological_order(deps: &[Vec<usize>]) -> Result<Vec<usize>, Vec<usize>> {
    let n = deps.len();
    let mut users = vec![Vec::new(); n];
    let mut waiting: Vec<usize> = deps.iter().map(Vec::len).collect();
    for (i, ds) in deps.iter().enumerate() {
        for &d in ds {
            users[d].push(i);
        }
    }
    let mut ready: BTreeSet<usize> = (0..n).filter(|&i| waiting[i] == 0).collect();
    let mut order = Vec::with_capacity(n);
    let mut placed = vec![false; n];
    while let Some(i) = ready.pop_first() {
        order.push(i);
        placed[i] = true;
        for &u in &users[i] {
            waiting[u] -= 1;
            if waiting[u] == 0 {
                ready.insert(u);
            }
        }
    }
    if order.len() == n {
        return Ok(order);
    }
    // Every node left waits for another node left: following the first such dependency from
    // any of them must come back to a node already seen.
    let start = (0..n).find(|&i| !placed[i]).expect("a node is left");
    let mut path = vec![start];
    let mut seen = vec![None; n];
    seen[start] = Some(0);
    loop {
        let last = *path.last().expect("the path is never empty");
        let next = *deps[last]
            .iter()
            .find(|&&d| !placed[d])
            .expect("a node left waits for a node left");
        if let Some(k) = seen[next] {
            let mut cycle = path.split_off(k);
            let lowest = (0..cycle.len())
                .min_by_key(|&j| cycle[j])
                .expect("a cycle is never empty");
            cycle.rotate_left(lowest);
            return Err(cycle);
        }
        seen[next] = Some(path.len());
        path.push(next);
    }
}
