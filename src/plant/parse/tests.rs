//! Tests of the plant parser: the shipped plants and fixtures, the resolved model of a small
//! plant, the precedence and the desugaring NuSMV would apply, and every refusal with its place.

use super::syntax::MAX_DEPTH;
use super::*;
use crate::plant::{Constraint, DefineId, Expr, Name, ParamId, Type, Value, VarId};
use std::path::PathBuf;

fn parse(text: &str) -> Result<Model, ModelError> {
    parse_str(text, Path::new("plant.smv"))
}

fn model(text: &str) -> Model {
    parse(text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn error(text: &str) -> String {
    match parse(text) {
        Ok(m) => panic!("parsed, expected an error:\n{text}\n{m:?}"),
        Err(e) => e.to_string(),
    }
}

/// The shipped plants and the closed-loop fixtures, by path relative to the repository.
const FILES: &[(&str, &str)] = &[
    (
        "smv/pnp_surrogate.smv",
        include_str!("../../../smv/pnp_surrogate.smv"),
    ),
    (
        "smv/tank_surrogate.smv",
        include_str!("../../../smv/tank_surrogate.smv"),
    ),
    (
        "smv/distribution_surrogate.smv",
        include_str!("../../../smv/distribution_surrogate.smv"),
    ),
    (
        "tests/data/closed_loop/lamp_plant.smv",
        include_str!("../../../tests/data/closed_loop/lamp_plant.smv"),
    ),
    (
        "tests/data/closed_loop/slow_plant.smv",
        include_str!("../../../tests/data/closed_loop/slow_plant.smv"),
    ),
    (
        "tests/data/closed_loop/vacuous_invar_plant.smv",
        include_str!("../../../tests/data/closed_loop/vacuous_invar_plant.smv"),
    ),
    (
        "tests/data/closed_loop/vacuous_fairness_plant.smv",
        include_str!("../../../tests/data/closed_loop/vacuous_fairness_plant.smv"),
    ),
    (
        "tests/data/closed_loop/wrong_param_plant.smv",
        include_str!("../../../tests/data/closed_loop/wrong_param_plant.smv"),
    ),
];

fn file(path: &str) -> Model {
    let (_, text) = FILES
        .iter()
        .find(|(p, _)| *p == path)
        .expect("a listed file");
    parse_str(text, Path::new(path)).unwrap_or_else(|e| panic!("{e}"))
}

/// Sizes of a model: params, vars (state, input), defines, init/invar/trans/fairness
/// constraints, symbols.
fn sizes(m: &Model) -> [usize; 9] {
    let inputs = m.vars.iter().filter(|v| v.kind == VarKind::Input).count();
    [
        m.params.len(),
        m.vars.len() - inputs,
        inputs,
        m.defines.len(),
        m.init.len(),
        m.invar.len(),
        m.trans.len(),
        m.fairness.len(),
        m.symbols.len(),
    ]
}

#[test]
fn shipped_plants_and_fixtures_parse() {
    let expected: &[(&str, [usize; 9])] = &[
        ("smv/pnp_surrogate.smv", [7, 16, 0, 14, 0, 0, 0, 0, 0]),
        ("smv/tank_surrogate.smv", [2, 2, 0, 4, 0, 0, 0, 0, 0]),
        (
            "smv/distribution_surrogate.smv",
            [7, 14, 0, 10, 0, 0, 0, 0, 0],
        ),
        (
            "tests/data/closed_loop/lamp_plant.smv",
            [1, 2, 0, 1, 0, 0, 0, 0, 0],
        ),
        (
            "tests/data/closed_loop/slow_plant.smv",
            [1, 3, 0, 1, 0, 0, 0, 0, 0],
        ),
        (
            "tests/data/closed_loop/vacuous_invar_plant.smv",
            [1, 2, 0, 1, 0, 1, 0, 0, 0],
        ),
        (
            "tests/data/closed_loop/vacuous_fairness_plant.smv",
            [1, 2, 0, 1, 0, 0, 0, 1, 0],
        ),
        (
            "tests/data/closed_loop/wrong_param_plant.smv",
            [1, 1, 0, 1, 0, 0, 0, 0, 0],
        ),
    ];
    assert_eq!(expected.len(), FILES.len());
    for (path, sizes_expected) in expected {
        let m = file(path);
        assert_eq!(&sizes(&m), sizes_expected, "{path}");
        assert_eq!(m.file, PathBuf::from(path));
    }
}

#[test]
fn every_define_refers_only_to_earlier_ones() {
    for (path, _) in FILES {
        let m = file(path);
        for (i, d) in m.defines.iter().enumerate() {
            d.expr.walk(&mut |e| {
                if let Expr::Define(other) = e {
                    assert!(other.0 < i, "{path}: {} refers to a later define", d.name);
                }
            });
        }
    }
}

#[test]
fn the_pnp_plant_resolves_names_and_lines() {
    let m = file("smv/pnp_surrogate.smv");
    assert_eq!(m.params[0], "c1Extend");
    assert_eq!(m.lookup("vacuum_off"), Some(Name::Param(ParamId(6))));
    let Some(Name::Var(c1pos)) = m.lookup("c1pos") else {
        panic!("c1pos is a variable")
    };
    let var = m.var(c1pos);
    assert_eq!(var.ty, Type::Range(0, 2));
    assert_eq!(var.domain, [Value::Int(0), Value::Int(1), Value::Int(2)]);
    assert_eq!(var.line, 50);
    assert_eq!(var.init, Some(Expr::Const(Value::Int(0))));
    // The define `grip1` reads `over1`, declared before it: the order is kept.
    let Some(Name::Define(grip1)) = m.lookup("grip1") else {
        panic!("grip1 is a define")
    };
    assert_eq!(m.defines[grip1.0].line, 81);
    assert!(m.defines.iter().position(|d| d.name == "over1").unwrap() < grip1.0);
    // The pnp plant has no free variable but p1..p3 (the operator).
    let free: Vec<&str> = m
        .vars
        .iter()
        .filter(|v| v.init.is_none() && v.next.is_none())
        .map(|v| v.name.as_str())
        .collect();
    assert_eq!(free, ["p1", "p2", "p3"]);
}

/// The tank plant reads `next(level)` in the value of `next(fills)`, as NuSMV allows.
#[test]
fn a_next_assignment_may_read_the_next_value_of_another_variable() {
    let m = file("smv/tank_surrogate.smv");
    let Some(Name::Var(fills)) = m.lookup("fills") else {
        panic!()
    };
    let Some(Name::Var(level)) = m.lookup("level") else {
        panic!()
    };
    let mut reads_next_level = false;
    m.var(fills).next.as_ref().unwrap().walk(&mut |e| {
        reads_next_level |= *e == Expr::Next(level);
    });
    assert!(reads_next_level);
    // The level's next value is a case whose branches are sets.
    let Some(Expr::Case(branches)) = &m.var(level).next else {
        panic!("{:?}", m.var(level).next)
    };
    assert_eq!(branches.len(), 7);
    assert!(matches!(branches[0].1, Expr::Set(ref s) if s.len() == 2));
}

#[test]
fn vacuous_fixtures_keep_their_constraint() {
    let m = file("tests/data/closed_loop/vacuous_invar_plant.smv");
    assert_eq!(m.invar[0].expr, Expr::Const(Value::Bool(false)));
    assert_eq!(m.invar[0].line, 15);
    let m = file("tests/data/closed_loop/vacuous_fairness_plant.smv");
    assert_eq!(m.fairness[0].expr, Expr::Const(Value::Bool(false)));
}

/// The plant fixtures that NuSMV refuses are refused here at the same line.
#[test]
fn broken_fixtures_are_refused_where_nusmv_refuses_them() {
    let cases = [
        (
            "tests/data/closed_loop/broken_plant.smv",
            include_str!("../../../tests/data/closed_loop/broken_plant.smv"),
            "tests/data/closed_loop/broken_plant.smv:10:1: expected ';' or an operator after \
             'esac', found 'DEFINE'",
        ),
        (
            "tests/data/closed_loop/typo_plant.smv",
            include_str!("../../../tests/data/closed_loop/typo_plant.smv"),
            "tests/data/closed_loop/typo_plant.smv:8:57: unknown name 'one': no parameter, \
             variable, define or symbolic constant of the plant",
        ),
    ];
    for (path, text, message) in cases {
        let e = parse_str(text, Path::new(path)).unwrap_err();
        assert_eq!(e.to_string(), message);
    }
}

const LAMP: &str = "\
-- A staircase lamp with a mode.
MODULE plant(lamp)
VAR
  button : boolean;
  on_for : 0..2;
  mode : {off, on, 3};
IVAR
  noise : -1..1;
ASSIGN
  init(on_for) := 0;
  next(on_for) := case
    !lamp      : 0;
    on_for < 2 : on_for + 1;
    TRUE       : 2;
  esac;
  init(mode) := {off, 3};
  next(mode) := timeout ? on : mode;
DEFINE
  timeout := long & on_for = 2;
  long := !button;
INVAR mode != off | !lamp
TRANS next(button) -> noise >= 0
JUSTICE button
";

#[test]
fn a_small_plant_resolves_to_this_model() {
    insta::assert_debug_snapshot!("lamp_model", model(LAMP));
}

#[test]
fn defines_are_ordered_by_dependency_then_by_declaration() {
    let m = model(LAMP);
    let names: Vec<&str> = m.defines.iter().map(|d| d.name.as_str()).collect();
    assert_eq!(names, ["long", "timeout"]);
    assert_eq!(m.lookup("timeout"), Some(Name::Define(DefineId(1))));
    assert_eq!(
        m.defines[1].expr,
        Expr::Bin(
            BinOp::And,
            Box::new(Expr::Define(DefineId(0))),
            Box::new(Expr::Bin(
                BinOp::Eq,
                Box::new(Expr::Var(VarId(1))),
                Box::new(Expr::Const(Value::Int(2)))
            ))
        )
    );
    let m = model("MODULE plant\nDEFINE a := b; b := c; c := TRUE; d := TRUE;");
    let names: Vec<&str> = m.defines.iter().map(|d| d.name.as_str()).collect();
    assert_eq!(names, ["c", "b", "a", "d"]);
}

#[test]
fn symbols_are_interned_in_order_of_first_appearance() {
    let m = model("MODULE plant()\nVAR a : {red, green}; b : {blue, red, 7};");
    assert_eq!(m.symbols, ["red", "green", "blue"]);
    assert_eq!(
        m.vars[1].ty,
        Type::Enum(vec![Value::Sym(2), Value::Sym(0), Value::Int(7)])
    );
    assert_eq!(
        m.vars[1].domain,
        [Value::Sym(2), Value::Sym(0), Value::Int(7)]
    );
    assert_eq!(m.symbol("green"), Some(Value::Sym(1)));
}

#[test]
fn ranges_may_be_negative_and_as_wide_as_65536_values() {
    let m = model("MODULE plant\nVAR x : -3..-1; y : 0..65535;");
    assert_eq!(
        m.vars[0].domain,
        [Value::Int(-3), Value::Int(-2), Value::Int(-1)]
    );
    assert_eq!(m.vars[1].domain.len(), 1 << 16);
    let m = model("MODULE plant\nVAR x : -3..-1;\nASSIGN init(x) := -2;");
    assert_eq!(m.vars[0].init, Some(Expr::Const(Value::Int(-2))));
}

/// The resolved constraint of `INIT <text>` in a plant with Boolean `a b c d` and integer
/// `n m`.
fn init_of(text: &str) -> Expr {
    let plant = format!(
        "MODULE plant\nVAR a : boolean; b : boolean; c : boolean; d : boolean; n : 0..3; m : 0..3;\nINIT {text}"
    );
    model(&plant).init.remove(0).expr
}

fn var(i: usize) -> Expr {
    Expr::Var(VarId(i))
}

fn bin(op: BinOp, a: Expr, b: Expr) -> Expr {
    Expr::Bin(op, Box::new(a), Box::new(b))
}

fn ite(c: Expr, a: Expr, b: Expr) -> Expr {
    Expr::Case(vec![(c, a), (Expr::Const(Value::Bool(true)), b)])
}

fn int(i: i64) -> Expr {
    Expr::Const(Value::Int(i))
}

/// NuSMV 2.5.4's precedence, as its binary reads these (checked with INVARSPECs against it).
#[test]
fn precedence_and_associativity_are_nusmvs() {
    use BinOp::*;
    let (a, b, c, d, n, m) = (var(0), var(1), var(2), var(3), var(4), var(5));
    let cases: Vec<(&str, Expr)> = vec![
        // `? :` binds tighter than `->` and `<->`, looser than `|`.
        (
            "a -> b ? c : d",
            bin(Implies, a.clone(), ite(b.clone(), c.clone(), d.clone())),
        ),
        (
            "a <-> b ? c : d",
            bin(Iff, a.clone(), ite(b.clone(), c.clone(), d.clone())),
        ),
        (
            "a | b ? c : d",
            ite(bin(Or, a.clone(), b.clone()), c.clone(), d.clone()),
        ),
        (
            "a ? b : c ? d : a",
            ite(a.clone(), b.clone(), ite(c.clone(), d.clone(), a.clone())),
        ),
        (
            "a ? b -> c : d",
            ite(a.clone(), bin(Implies, b.clone(), c.clone()), d.clone()),
        ),
        (
            "a -> b -> c",
            bin(Implies, a.clone(), bin(Implies, b.clone(), c.clone())),
        ),
        (
            "a <-> b <-> c",
            bin(Iff, bin(Iff, a.clone(), b.clone()), c.clone()),
        ),
        (
            "a <-> b -> c",
            bin(Implies, bin(Iff, a.clone(), b.clone()), c.clone()),
        ),
        (
            "a | b & c",
            bin(Or, a.clone(), bin(And, b.clone(), c.clone())),
        ),
        (
            "a xor b | c",
            bin(Or, bin(Xor, a.clone(), b.clone()), c.clone()),
        ),
        (
            "a = b = c",
            bin(Eq, bin(Eq, a.clone(), b.clone()), c.clone()),
        ),
        (
            "a & n < m",
            bin(And, a.clone(), bin(Lt, n.clone(), m.clone())),
        ),
        (
            "n - m - 1 = 0",
            bin(Eq, bin(Sub, bin(Sub, n.clone(), m.clone()), int(1)), int(0)),
        ),
        (
            "n + m * 2 mod 3 >= 1",
            bin(
                Ge,
                bin(
                    Add,
                    n.clone(),
                    bin(Mod, bin(Mul, m.clone(), int(2)), int(3)),
                ),
                int(1),
            ),
        ),
        ("!a = b", bin(Eq, Expr::Not(Box::new(a.clone())), b.clone())),
        ("-n = -1", bin(Eq, Expr::Neg(Box::new(n.clone())), int(-1))),
        (
            "(a -> b) & c",
            bin(And, bin(Implies, a.clone(), b.clone()), c.clone()),
        ),
        ("a->b", bin(Implies, a.clone(), b.clone())),
    ];
    for (text, expected) in cases {
        assert_eq!(init_of(text), expected, "{text}");
    }
}

#[test]
fn comments_crlf_and_optional_semicolons_are_read() {
    let m = model(
        "-- head\r\nMODULE plant(x) -- outputs\r\nVAR--no blank\r\n  v : boolean;\r\nINIT v --c\r\n\
         INVAR v;\r\nTRANS next(v) = x--comment\r\nFAIRNESS v",
    );
    assert_eq!(sizes(&m), [1, 1, 0, 0, 1, 1, 1, 1, 0]);
    assert_eq!(m.invar[0].line, 6);
    assert_eq!(model("MODULE plant()").params.len(), 0);
}

/// A constant outside the domain is refused only where the assignment can produce it: a dead
/// branch is accepted, as NuSMV accepts it.
#[test]
fn a_dead_branch_may_hold_any_constant() {
    for value in [
        "case FALSE : 5; TRUE : 1; esac",
        "case TRUE : 1; TRUE : 5; esac",
        "case x = 0 & x = 1 : 5; TRUE : 1; esac",
        "case x < 2 : x + 1; TRUE : {0, 1}; esac",
        "x = 2 ? 0 : case x = 2 : 9; TRUE : x + 1; esac",
    ] {
        model(&format!(
            "MODULE plant\nVAR x : 0..2;\nASSIGN next(x) := {value};"
        ));
    }
    // Reachability also looks through defines, parameters and next values.
    for (value, refused) in [
        ("case stop : 0; TRUE : 5; esac", false),
        ("case p & !p : 7; TRUE : 0; esac", false),
        ("case next(y) & !y2 : 7; TRUE : 0; esac", false),
        ("case next(y) & y2 : 7; TRUE : 0; esac", true),
        ("case p : 0; TRUE : 7; esac", true),
    ] {
        let text = format!(
            "MODULE plant(p)\nVAR x : 0..2; y : boolean;\nDEFINE y2 := next_y; next_y := TRUE;\n\
             stop := TRUE;\nASSIGN next(x) := {value};"
        );
        let result = parse(&text);
        assert_eq!(result.is_err(), refused, "{value}: {result:?}");
    }
}

#[test]
fn an_unreadable_file_names_its_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing.smv");
    let e = parse_file(&path).unwrap_err();
    assert!(matches!(&e, ModelError::Io { file, .. } if *file == path));
    assert!(e.to_string().contains("missing.smv"));
}

#[test]
fn a_file_is_read_from_disk() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lamp.smv");
    std::fs::write(&path, LAMP).unwrap();
    let m = parse_file(&path).unwrap();
    assert_eq!(m.file, path);
    assert_eq!(m.vars.len(), 4);
}

#[test]
fn errors_carry_file_line_and_column() {
    let e = parse_str(
        "MODULE plant\nVAR\n\tx : 0..2;\n\tüber : boolean;\nINIT x = TRUE",
        Path::new("dir/p.smv"),
    )
    .unwrap_err();
    let ModelError::At {
        file,
        line,
        column,
        message,
    } = e
    else {
        panic!("{e:?}")
    };
    assert_eq!(file, Path::new("dir/p.smv"));
    // `ü` is no identifier character: the parse stops at it, column 2 in characters.
    assert_eq!((line, column), (4, 2));
    assert!(message.starts_with("expected "), "{message}");
    let e = error("MODULE plant\nDEFINE é := 1; x := TRUE & 1;");
    assert!(e.starts_with("plant.smv:2:8: "), "{e}");
}

/// Inputs far beyond any plant are refused with a located error, never a crash.
#[test]
fn huge_expressions_are_refused_not_a_crash() {
    let nested = |depth: usize| {
        format!(
            "MODULE plant\nVAR a : boolean;\nINIT {}a{}",
            "(".repeat(depth),
            ")".repeat(depth)
        )
    };
    model(&nested(MAX_NESTING));
    let e = error(&nested(MAX_NESTING + 1));
    assert!(e.contains("nest more than 100 levels"), "{e}");
    for text in [
        nested(100_000),
        format!(
            "MODULE plant\nVAR a : boolean;\nINIT {}a",
            "!".repeat(100_000)
        ),
        format!(
            "MODULE plant\nVAR a : boolean;\nINIT {}",
            vec!["a"; 100_000].join(" | ")
        ),
        format!(
            "MODULE plant\nVAR a : boolean;\nINIT {}",
            vec!["a"; 100_000].join(" -> ")
        ),
        format!(
            "MODULE plant\nVAR a : boolean;\nINIT {}a",
            "a ? a : ".repeat(100_000)
        ),
        format!(
            "MODULE plant\nVAR a : boolean;\nINIT {}a{}",
            "a ? ".repeat(100_000),
            " : a".repeat(100_000)
        ),
        format!(
            "MODULE plant\nVAR a : boolean;\nINIT {}a{}",
            "a ? ".repeat(150),
            " : a".repeat(150)
        ),
    ] {
        let e = error(&text);
        assert!(e.starts_with("plant.smv:3:"), "{}", &e[..e.len().min(200)]);
    }
}

/// An integer of any length is quoted cut, like every token of the file.
#[test]
fn a_huge_integer_is_quoted_cut() {
    let digits = "1".repeat(100_000);
    for text in [
        format!("MODULE plant\nVAR x : 0..{digits};"),
        format!("MODULE plant\nVAR x : boolean;\nINIT x = {digits}"),
    ] {
        let e = error(&text);
        assert!(e.len() < 200, "{}", &e[..200]);
        assert!(
            e.contains("(100000 characters) is out of NuSMV's range"),
            "{e}"
        );
    }
}

/// The deepest expressions the limits let through are resolved (and their constants checked)
/// within half the stack of a test thread.
#[test]
fn the_deepest_accepted_expressions_fit_in_one_mebibyte_of_stack() {
    let chain = |op: &str| vec!["a"; MAX_DEPTH].join(op);
    let texts = [
        format!("MODULE plant\nVAR a : boolean;\nINIT {}", chain(" | ")),
        format!("MODULE plant\nVAR a : boolean;\nINIT {}", chain(" -> ")),
        format!(
            "MODULE plant\nVAR a : boolean;\nINIT {}a",
            "!".repeat(MAX_DEPTH)
        ),
        format!(
            "MODULE plant\nVAR a : boolean;\nINIT {}{}{}",
            "(".repeat(MAX_NESTING),
            vec!["a"; MAX_DEPTH - MAX_NESTING].join(" & "),
            ")".repeat(MAX_NESTING)
        ),
        // A chain of `? :` whose every branch is checked against the domain of `x`.
        format!(
            "MODULE plant\nVAR a : boolean; x : 0..1;\nASSIGN next(x) := {}1;",
            "a ? 0 : ".repeat(MAX_DEPTH)
        ),
        format!(
            "MODULE plant\nVAR a : boolean; x : 0..1;\nASSIGN next(x) := {}1{};",
            "case a : 0; TRUE : ".repeat(MAX_NESTING),
            "; esac".repeat(MAX_NESTING)
        ),
    ];
    std::thread::Builder::new()
        .stack_size(1 << 20)
        .spawn(move || {
            for text in texts {
                model(&text);
            }
        })
        .unwrap()
        .join()
        .unwrap();
}

/// Every refusal, with its place and message (snapshot `errors`).
const ERRORS: &[(&str, &str)] = &[
    // Syntax.
    ("empty file", ""),
    ("no module", "VAR x : boolean;"),
    ("module not named plant", "MODULE main\nVAR x : boolean;"),
    ("missing semicolon", "MODULE plant\nVAR x : boolean\n    y : boolean;"),
    ("missing type", "MODULE plant\nVAR x : ;"),
    ("missing operand", "MODULE plant\nVAR x : boolean;\nINIT x & "),
    ("missing esac", "MODULE plant\nVAR x : boolean;\nASSIGN next(x) := case x : FALSE;"),
    ("empty case branch", "MODULE plant\nVAR x : boolean;\nASSIGN next(x) := case x : ; esac;"),
    ("unclosed parenthesis", "MODULE plant\nVAR x : boolean;\nINIT (x & x"),
    ("bad parameter list", "MODULE plant(a b)"),
    ("keyword as name", "MODULE plant\nVAR next : boolean;"),
    ("LTL operator as name", "MODULE plant\nVAR x : boolean;\nINVAR X"),
    ("keyword as parameter", "MODULE plant(a, VAR)"),
    ("integer too large", "MODULE plant\nVAR x : 0..2;\nINIT x = 4294967296"),
    ("assignment outside ASSIGN", "MODULE plant\nVAR x : boolean;\ninit(x) := TRUE;"),
    // Outside the subset.
    ("FROZENVAR", "MODULE plant\nFROZENVAR x : boolean;"),
    ("COMPASSION", "MODULE plant\nVAR x : boolean;\nCOMPASSION (x, x)"),
    ("LTLSPEC", "MODULE plant\nVAR x : boolean;\nLTLSPEC G x"),
    ("SPEC", "MODULE plant\nVAR x : boolean;\nSPEC AG x"),
    ("CTLSPEC", "MODULE plant\nVAR x : boolean;\nCTLSPEC AG x"),
    ("INVARSPEC", "MODULE plant\nVAR x : boolean;\nINVARSPEC x"),
    // Modules.
    ("module declared twice", "MODULE m\nVAR x : boolean;\nMODULE plant\nMODULE m"),
    ("module instance of no module", "MODULE plant\nVAR p : cylinder(TRUE);"),
    ("recursive module", "MODULE m(x)\nVAR y : m(x);\nMODULE plant\nVAR a : m(TRUE);"),
    ("wrong argument count", "MODULE m(x, y)\nMODULE plant\nVAR a : m(TRUE);"),
    ("module instance under IVAR", "MODULE m\nMODULE plant\nIVAR a : m;"),
    ("part of no instance", "MODULE m\nVAR x : boolean;\nMODULE plant\nVAR a : m;\nINIT a.y"),
    ("error inside a submodule", "MODULE m(p)\nVAR x : 0..3;\nASSIGN next(x) := p;\nMODULE plant\nVAR a : m(TRUE);"),
    ("process", "MODULE plant\nVAR p : process cylinder;"),
    ("array type", "MODULE plant\nVAR a : array 0..3 of boolean;"),
    ("word type", "MODULE plant\nVAR w : unsigned word[8];"),
    ("integer type", "MODULE plant\nVAR i : integer;"),
    ("array index", "MODULE plant\nVAR x : 0..3;\nINIT x[0]"),
    ("word constant", "MODULE plant\nVAR x : 0..3;\nINIT x = 0ud4_1"),
    ("shift", "MODULE plant\nVAR x : 0..3;\nINIT x << 1 = 2"),
    ("set membership", "MODULE plant\nVAR x : 0..3;\nINIT x in {1, 2}"),
    ("function call", "MODULE plant\nVAR x : 0..3;\nINIT toint(x) = 1"),
    ("call of a name", "MODULE plant\nVAR x : 0..3;\nINIT abs(x) = 1"),
    ("init in an expression", "MODULE plant\nVAR x : 0..3;\nINIT init(x) = 1"),
    ("dotted name", "MODULE plant\nVAR x : 0..3;\nINIT ctrl.x = 1"),
    ("self", "MODULE plant\nVAR x : 0..3;\nINIT self.x = 1"),
    ("plain assignment", "MODULE plant\nVAR x : 0..3;\nASSIGN\n  x := 1;"),
    ("next in INIT", "MODULE plant\nVAR x : 0..3;\nINIT next(x) = 1"),
    ("next in INVAR", "MODULE plant\nVAR x : 0..3;\nINVAR next(x) = 1"),
    ("next in DEFINE", "MODULE plant\nVAR x : 0..3;\nDEFINE d := next(x) = 1;"),
    ("next in init", "MODULE plant\nVAR x : 0..3; y : 0..3;\nASSIGN init(y) := next(x);"),
    ("next in FAIRNESS", "MODULE plant\nVAR x : 0..3;\nFAIRNESS next(x) = 1"),
    ("next of an expression", "MODULE plant\nVAR x : 0..3;\nTRANS next(x + 1) = 1"),
    ("next of a define", "MODULE plant\nVAR x : 0..3;\nDEFINE d := x;\nTRANS next(d) = 1"),
    ("next of a parameter", "MODULE plant(p)\nVAR x : 0..3;\nTRANS next(p)"),
    ("next of an input", "MODULE plant\nIVAR i : boolean;\nTRANS next(i)"),
    ("set in INIT", "MODULE plant\nVAR x : 0..3;\nINIT x = {1, 2}"),
    ("set in DEFINE", "MODULE plant\nVAR x : 0..3;\nDEFINE d := {1, 2};"),
    ("set inside an expression", "MODULE plant\nVAR x : 0..3;\nASSIGN next(x) := {1, 2} + 1;"),
    ("set in a condition", "MODULE plant\nVAR x : boolean;\nASSIGN next(x) := case {TRUE} : x; TRUE : x; esac;"),
    ("set in a set", "MODULE plant\nVAR x : 0..3;\nASSIGN next(x) := {1, {2, 3}};"),
    // Names.
    ("unknown name", "MODULE plant\nVAR x : boolean;\nINIT y"),
    ("unknown dashed name", "MODULE plant\nVAR x : 0..3;\nASSIGN next(x) := x-1;"),
    ("unknown assigned name", "MODULE plant\nASSIGN init(y) := 1;"),
    ("unknown name in next", "MODULE plant\nVAR x : boolean;\nTRANS next(y)"),
    ("unknown symbol", "MODULE plant\nVAR e : {a, b};\nASSIGN init(e) := c;"),
    ("duplicate variable", "MODULE plant\nVAR x : boolean;\nIVAR x : 0..1;"),
    ("duplicate define", "MODULE plant\nDEFINE d := TRUE;\n  d := FALSE;"),
    ("variable named like a parameter", "MODULE plant(lamp)\nVAR lamp : boolean;"),
    ("duplicate parameter", "MODULE plant(a, a)"),
    ("symbol named like a variable", "MODULE plant\nVAR a : boolean;\n  e : {a, b};"),
    ("variable named like a symbol", "MODULE plant\nVAR e : {a, b};\nDEFINE a := TRUE;"),
    ("duplicate enumeration value", "MODULE plant\nVAR e : {a, b, a};"),
    ("TRUE in an enumeration", "MODULE plant\nVAR e : {a, TRUE};"),
    // Assignments.
    ("init assigned twice", "MODULE plant\nVAR x : boolean;\nASSIGN init(x) := TRUE;\n  init(x) := FALSE;"),
    ("next assigned twice", "MODULE plant\nVAR x : boolean;\nASSIGN next(x) := TRUE;\nASSIGN next(x) := FALSE;"),
    ("init of an input", "MODULE plant\nIVAR i : boolean;\nASSIGN init(i) := TRUE;"),
    ("next of an input assigned", "MODULE plant\nIVAR i : boolean;\nASSIGN next(i) := TRUE;"),
    ("assigned define", "MODULE plant\nDEFINE d := TRUE;\nASSIGN next(d) := TRUE;"),
    ("assigned parameter", "MODULE plant(p)\nASSIGN init(p) := TRUE;"),
    ("next cycle", "MODULE plant\nVAR x : boolean; y : boolean;\nASSIGN next(x) := next(y);\n  next(y) := !next(x);"),
    ("next self cycle", "MODULE plant\nVAR x : boolean;\nASSIGN next(x) := !next(x);"),
    ("init cycle through a define", "MODULE plant\nVAR x : 0..3; y : 0..3;\nDEFINE d := y;\nASSIGN init(y) := x; init(x) := d;"),
    ("input in INVAR", "MODULE plant\nIVAR i : boolean;\nINVAR i"),
    ("input in INIT through a define", "MODULE plant\nIVAR i : boolean;\nDEFINE d := !e; e := i;\nINIT d"),
    ("input in init", "MODULE plant\nIVAR i : boolean;\nVAR x : boolean;\nASSIGN init(x) := i;"),
    // Types.
    ("empty range", "MODULE plant\nVAR x : 3..1;"),
    ("range too wide", "MODULE plant\nVAR x : 0..65536;"),
    ("Boolean operand of +", "MODULE plant\nVAR x : 0..3; b : boolean;\nINVAR x + b = 1"),
    ("integer operand of &", "MODULE plant\nVAR x : 0..3; b : boolean;\nINVAR b & x"),
    ("integer operand of !", "MODULE plant\nVAR x : 0..3;\nINVAR !x = 1"),
    ("Boolean operand of unary -", "MODULE plant\nVAR b : boolean;\nINVAR -b = 1"),
    ("symbolic operand of <", "MODULE plant\nVAR e : {a, b};\nINVAR e < b"),
    ("mixed operand of +", "MODULE plant\nVAR e : {a, 1};\nINVAR e + 1 = 2"),
    ("Boolean compared with integer", "MODULE plant\nVAR x : 0..3; b : boolean;\nINVAR b = 1"),
    ("symbol compared with integer", "MODULE plant\nVAR e : {a, b};\nINVAR e = 3"),
    ("integer constraint", "MODULE plant\nVAR x : 0..3;\nINVAR x + 1"),
    ("integer FAIRNESS", "MODULE plant\nVAR x : 0..3;\nFAIRNESS x"),
    ("integer case condition", "MODULE plant\nVAR x : 0..3;\nASSIGN next(x) := case x : 1; TRUE : 0; esac;"),
    ("integer ternary condition", "MODULE plant\nVAR x : 0..3;\nDEFINE d := x ? 1 : 0;"),
    ("mixed case branches", "MODULE plant\nVAR x : 0..3;\nDEFINE d := case x = 0 : TRUE; TRUE : 1; esac;"),
    ("Boolean value of an integer", "MODULE plant\nVAR x : 0..3;\nASSIGN init(x) := TRUE;"),
    ("integer value of a Boolean", "MODULE plant\nVAR b : boolean;\nASSIGN init(b) := 1;"),
    ("integer value of a symbolic", "MODULE plant\nVAR e : {a, b};\nASSIGN init(e) := 1;"),
    ("symbol value of an integer", "MODULE plant\nVAR x : 0..3; e : {a, b};\nASSIGN init(x) := a;"),
    ("mixed value of a symbolic", "MODULE plant\nVAR e : {a, b}; m : {a, 1};\nASSIGN init(e) := m;"),
    ("Boolean branch of an integer", "MODULE plant\nVAR x : 0..3;\nASSIGN next(x) := case x = 0 : 1; TRUE : FALSE; esac;"),
    ("Boolean set member", "MODULE plant\nVAR x : 0..3;\nASSIGN init(x) := {1, TRUE};"),
    ("constant outside the range", "MODULE plant\nVAR x : 0..2;\nASSIGN init(x) := 3;"),
    ("negative constant outside the range", "MODULE plant\nVAR x : 0..2;\nASSIGN init(x) := -1;"),
    ("set member outside the range", "MODULE plant\nVAR x : 0..2;\nASSIGN init(x) := {1, 3};"),
    ("branch outside the range", "MODULE plant(go)\nVAR x : 0..2;\nASSIGN next(x) := case\n    go : 5;\n    TRUE : x;\n  esac;"),
    ("ternary branch outside the range", "MODULE plant\nVAR x : 0..2;\nASSIGN next(x) := x = 0 ? 1 : 7;"),
    ("symbol outside the enumeration", "MODULE plant\nVAR e : {a, b}; f : {c};\nASSIGN init(e) := c;"),
    ("integer outside the enumeration", "MODULE plant\nVAR e : {a, 1};\nASSIGN init(e) := 2;"),
    // Defines.
    ("define cycle", "MODULE plant\nDEFINE d := e & TRUE;\n  f := TRUE;\n  e := !d;"),
    ("define on itself", "MODULE plant\nVAR x : boolean;\nDEFINE d := x & d;"),
];

#[test]
fn refusals_name_their_place_and_construct() {
    let mut seen = std::collections::HashSet::new();
    let rendered: Vec<String> = ERRORS
        .iter()
        .map(|(name, text)| {
            assert!(seen.insert(name), "duplicate case name {name}");
            format!("{name}:\n  {}", error(text))
        })
        .collect();
    insta::assert_snapshot!("errors", rendered.join("\n"));
}

#[test]
fn constraints_keep_their_section_and_line() {
    let m = model(LAMP);
    let lines = |cs: &[Constraint]| cs.iter().map(|c| c.line).collect::<Vec<_>>();
    assert_eq!(lines(&m.invar), [21]);
    assert_eq!(lines(&m.trans), [22]);
    assert_eq!(lines(&m.fairness), [23]);
    // TRANS reads the next value of a state variable and the current input.
    let Expr::Bin(BinOp::Implies, left, _) = &m.trans[0].expr else {
        panic!("{:?}", m.trans[0].expr)
    };
    assert_eq!(**left, Expr::Next(VarId(0)));
}

/// A plant file may hold one token of megabytes; a message shows its start and its length.
#[test]
fn giant_tokens_are_cut_in_messages() {
    let giant = "a".repeat(1_000_000);
    let plants = [
        // Unknown name in an expression.
        format!("MODULE plant(x)\nVAR v : boolean;\nINIT v = {giant}"),
        // A name declared twice.
        format!("MODULE plant(x)\nVAR {giant} : boolean;\n  {giant} : 0..1;"),
        // A token the grammar does not expect.
        format!("MODULE plant(x)\nVAR v : boolean;\nINIT v {giant}"),
        // A value of the wrong type, shown as code.
        format!(
            "MODULE plant(x)\nVAR v : boolean;\nASSIGN init(v) := 1 + {};",
            "1 + ".repeat(100_000) + "1"
        ),
    ];
    for text in plants {
        let e = error(&text);
        assert!(e.len() < 400, "{} bytes: {}", e.len(), &e[..400]);
        assert!(e.starts_with("plant.smv:3:"), "{e}");
    }
}

/// Names no controller output reaches: free inputs, what is assigned or defined from them
/// alone, and nothing a constraint couples with a parameter.
#[test]
fn names_no_parameter_influences_are_found() {
    let text = "MODULE plant(lamp)\nVAR\n  button : boolean;\n  seen : boolean;\n  \
        on_for : 0..2;\n  door : boolean;\n  bell : boolean;\nIVAR\n  noise : boolean;\n\
        ASSIGN\n  init(seen) := FALSE;\n  next(seen) := seen | button;\n  \
        next(on_for) := lamp ? 1 : 0;\nDEFINE\n  pressed := button & !seen;\n  \
        lit := on_for > 0;\nTRANS next(door) -> lit\nTRANS next(bell) -> noise\n";
    let m = parse_str(text, Path::new("p.smv")).unwrap();
    assert_eq!(
        m.uncontrolled(),
        ["button", "seen", "bell", "noise", "pressed"]
    );
    let fair = format!("{text}FAIRNESS lit\n");
    let m = parse_str(&fair, Path::new("p.smv")).unwrap();
    assert!(m.uncontrolled().is_empty());
}

/// Module instances are flattened as NuSMV flattens them: names `inst.x` at any depth, a
/// parameter bound to an instance reads that instance's names, and an assignment to a
/// parameter bound to a variable assigns the variable.
#[test]
fn module_instances_are_flattened_with_dotted_names() {
    let m = model(
        "MODULE cyl(cmd)\nVAR pos : 0..2;\nASSIGN init(pos) := 0; next(pos) := cmd ? 2 : 0;\n\
         MODULE sensor(c)\nDEFINE home := c.pos = 0;\n\
         MODULE setter(v)\nASSIGN next(v) := TRUE;\n\
         MODULE plant(go)\nVAR c : cyl(go); s : sensor(c); x : boolean; t : setter(x);\n\
         DEFINE home := s.home;",
    );
    let vars: Vec<&str> = m.vars.iter().map(|v| v.name.as_str()).collect();
    assert_eq!(vars, ["x", "c.pos"]);
    // `cmd` is the plant's parameter `go`; `c.pos` of the sensor is the cylinder's position.
    assert_eq!(
        m.vars[1].next,
        Some(Expr::Case(vec![
            (Expr::Param(ParamId(0)), Expr::Const(Value::Int(2))),
            (Expr::Const(Value::Bool(true)), Expr::Const(Value::Int(0))),
        ]))
    );
    let Some(Name::Define(d)) = m.lookup("s.home") else {
        panic!("{:?}", m.defines)
    };
    assert_eq!(
        m.defines[d.0].expr,
        Expr::Bin(
            BinOp::Eq,
            Box::new(Expr::Var(VarId(1))),
            Box::new(Expr::Const(Value::Int(0)))
        )
    );
    assert!(matches!(m.lookup("home"), Some(Name::Define(_))));
    // The setter assigns the plant's `x` through its parameter, on the setter's line.
    assert_eq!(m.vars[0].next, Some(Expr::Const(Value::Bool(true))));
    // Every declaration keeps the line of the module that writes it.
    assert_eq!((m.vars[0].line, m.vars[1].line), (9, 2));
}

/// A file without the plant module names the modules it has, a long name cut like any other
/// user text: the message stays a line long.
#[test]
fn the_modules_found_instead_of_the_plant_are_named_cut() {
    let long = "x".repeat(5_000);
    let said = error(&format!("MODULE {long}(a)\nVAR v : boolean;\n"));
    assert!(
        said.contains("no MODULE plant(outputs...) in the file (found xxx"),
        "{said}"
    );
    assert!(said.contains("(5000 characters)"), "{said}");
    assert!(said.len() < 300, "{} bytes: {said}", said.len());
}
