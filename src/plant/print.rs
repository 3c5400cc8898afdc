//! A [`Model`] as SMV text: `MODULE plant(params)` with the same meaning, which NuSMV reads.
//!
//! In: a model (parsed or built by a program). Out: text in a fixed order: `VAR`, `IVAR`,
//! `DEFINE`, `ASSIGN` (`init` then `next`, per variable in declaration order), then `INIT`,
//! `INVAR`, `TRANS`, `FAIRNESS`, each constraint in model order. Every compound expression is
//! parenthesized, so NuSMV's precedences never matter. Comments and layout of a parsed file
//! are not kept. A model read from a file with module instances keeps their flattened names
//! (`inst.x`), which the parser reads back but NuSMV does not take as declarations.

use super::{BinOp, Expr, Model, Type, Value, VarKind};
use std::fmt::{self, Write};

/// Writes the model as one `MODULE plant`.
pub(crate) fn write_plant(m: &Model, w: &mut impl Write) -> fmt::Result {
    if m.params.is_empty() {
        writeln!(w, "MODULE plant")?;
    } else {
        writeln!(w, "MODULE plant({})", m.params.join(", "))?;
    }
    for (kind, section) in [(VarKind::State, "VAR"), (VarKind::Input, "IVAR")] {
        let vars: Vec<_> = m.vars.iter().filter(|v| v.kind == kind).collect();
        if vars.is_empty() {
            continue;
        }
        writeln!(w, "{section}")?;
        for v in vars {
            write!(w, "  {} : ", v.name)?;
            match &v.ty {
                Type::Bool => write!(w, "boolean")?,
                Type::Range(lo, hi) => write!(w, "{lo}..{hi}")?,
                Type::Enum(values) => {
                    let shown: Vec<String> = values.iter().map(|x| m.show(*x)).collect();
                    write!(w, "{{{}}}", shown.join(", "))?
                }
            }
            writeln!(w, ";")?;
        }
    }
    if !m.defines.is_empty() {
        writeln!(w, "DEFINE")?;
        for d in &m.defines {
            writeln!(w, "  {} := {};", d.name, expr(m, &d.expr))?;
        }
    }
    if m.vars.iter().any(|v| v.init.is_some() || v.next.is_some()) {
        writeln!(w, "ASSIGN")?;
        for v in &m.vars {
            if let Some(e) = &v.init {
                writeln!(w, "  init({}) := {};", v.name, expr(m, e))?;
            }
            if let Some(e) = &v.next {
                writeln!(w, "  next({}) := {};", v.name, expr(m, e))?;
            }
        }
    }
    for (section, constraints) in [
        ("INIT", &m.init),
        ("INVAR", &m.invar),
        ("TRANS", &m.trans),
        ("FAIRNESS", &m.fairness),
    ] {
        for c in constraints {
            writeln!(w, "{section}\n  {};", expr(m, &c.expr))?;
        }
    }
    Ok(())
}

/// [`write_plant`] into a string.
pub(crate) fn to_smv(m: &Model) -> String {
    let mut s = String::new();
    write_plant(m, &mut s).expect("writing to a String cannot fail");
    s
}

/// An expression as SMV text, every compound part in parentheses.
pub(crate) fn expr(m: &Model, e: &Expr) -> String {
    let mut s = String::new();
    write_expr(m, e, &mut s);
    s
}

fn write_expr(m: &Model, e: &Expr, out: &mut String) {
    match e {
        Expr::Const(Value::Int(i)) if *i < 0 => out.push_str(&format!("({i})")),
        Expr::Const(v) => out.push_str(&m.show(*v)),
        Expr::Var(v) => out.push_str(&m.var(*v).name),
        Expr::Next(v) => out.push_str(&format!("next({})", m.var(*v).name)),
        Expr::Define(d) => out.push_str(&m.defines[d.0].name),
        Expr::Param(p) => out.push_str(&m.params[p.0]),
        Expr::Not(a) if matches!(**a, Expr::Var(_) | Expr::Define(_) | Expr::Param(_)) => {
            out.push('!');
            write_expr(m, a, out);
        }
        Expr::Not(a) | Expr::Neg(a) => {
            out.push_str(if matches!(e, Expr::Not(_)) {
                "!("
            } else {
                "-("
            });
            write_expr(m, a, out);
            out.push(')');
        }
        Expr::Bin(op, a, b) => {
            out.push('(');
            write_expr(m, a, out);
            out.push(' ');
            out.push_str(symbol(*op));
            out.push(' ');
            write_expr(m, b, out);
            out.push(')');
        }
        Expr::Case(branches) => {
            out.push_str("case ");
            for (c, v) in branches {
                write_expr(m, c, out);
                out.push_str(" : ");
                write_expr(m, v, out);
                out.push_str("; ");
            }
            out.push_str("esac");
        }
        Expr::Set(items) => {
            out.push('{');
            for (k, i) in items.iter().enumerate() {
                if k > 0 {
                    out.push_str(", ");
                }
                write_expr(m, i, out);
            }
            out.push('}');
        }
    }
}

/// The SMV spelling of an operator.
pub(crate) fn symbol(op: BinOp) -> &'static str {
    use BinOp::*;
    match op {
        And => "&",
        Or => "|",
        Xor => "xor",
        Xnor => "xnor",
        Implies => "->",
        Iff => "<->",
        Eq => "=",
        Ne => "!=",
        Lt => "<",
        Le => "<=",
        Gt => ">",
        Ge => ">=",
        Add => "+",
        Sub => "-",
        Mul => "*",
        Div => "/",
        Mod => "mod",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::build::*;

    #[test]
    fn snapshot() {
        let mut b = Builder::new(&["u", "w"]);
        let x = b.var("x", Type::Range(-1, 2));
        let st = b.enumeration("st", &["idle", "busy"]);
        let i = b.ivar("i", Type::Bool);
        let busy = Expr::Const(b.sym("busy"));
        let d = b.define("ready", and(vec![eq(st.clone(), busy), not(b.param("w"))]));
        b.init(&x, set(vec![int(-1), int(0)]));
        b.next(
            &x,
            case(vec![
                (
                    and(vec![d, bin(BinOp::Lt, x.clone(), int(2))]),
                    bin(BinOp::Add, x.clone(), int(1)),
                ),
                (bool(true), bin(BinOp::Mod, x.clone(), int(2))),
            ]),
        );
        b.trans(bin(BinOp::Iff, next_of(&st), i));
        b.fairness(b.param("u"));
        insta::assert_snapshot!(to_smv(&b.m));
    }
}
