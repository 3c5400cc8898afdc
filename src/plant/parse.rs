//! The parser of plant files: text in, [`Model`] or a located [`ModelError`] out.
//!
//! Two steps. Here, `grammar/smv.pest` parses the file and its tree becomes a private syntax
//! tree whose nodes keep their byte offsets; pest types never leave this file. A parse failure
//! is explained in words, and a NuSMV construct outside the subset (FROZENVAR, arrays, words,
//! processes, function calls, ...) is named where the parse stopped. Then `flatten` makes one
//! flat `MODULE plant` of the modules (NuSMV's `flatten_hierarchy`), and `resolve`
//! turns the syntax tree into a [`Model`]: names become indices, types are checked, defines are
//! ordered, and the rules of the subset that a grammar cannot express are enforced.
//!
//! Every error is a [`ModelError::At`] with the file, the 1-based line and the 1-based column
//! (in characters) of the offending token.

mod flatten;
mod reach;
mod resolve;
mod syntax;
#[cfg(test)]
mod tests;

use super::{BinOp, Model, ModelError, VarKind};
use crate::quote::{cut, quote};
use pest::iterators::{Pair, Pairs};
use pest::Parser;
use std::path::Path;

// In a module of its own so that the generated `Rule` enum stays private.
mod parser {
    #[derive(pest_derive::Parser)]
    #[grammar = "grammar/smv.pest"]
    pub(super) struct SmvParser;
}
use parser::{Rule, SmvParser};
use syntax::{
    Assign, ConstraintDecl, DefineDecl, EnumItem, EnumLit, Ident, Instance, Module, Node, NodeKind,
    Plant, Section, Source, Target, TypeDecl, VarDecl,
};

/// Reads and parses a plant file.
pub fn parse_file(path: &Path) -> Result<Model, ModelError> {
    use crate::files::{read_text, ReadError, MAX_LINE_BYTES};
    let text = read_text(path, Some(MAX_LINE_BYTES)).map_err(|e| match e.error {
        ReadError::Io(source) => ModelError::Io {
            file: path.to_path_buf(),
            source,
        },
        _ => ModelError::Read(e),
    })?;
    parse_str(&text, path)
}

/// Parses the text of a plant file; `file` names it in the model and in error messages.
pub(crate) fn parse_str(text: &str, file: &Path) -> Result<Model, ModelError> {
    let src = Source::new(text, file);
    let modules = syntax(&src)?;
    let plant = flatten::flatten(&src, modules)?;
    resolve::resolve(&src, plant)
}

/// The deepest that parentheses, `case`, sets, `next( )` and the `a` of `c ? a : b` may nest
/// inside each other. Each level costs the parser a dozen stack frames; far beyond any real
/// plant, this keeps the parse well inside the stack of a test thread.
const MAX_NESTING: usize = 100;

// ---------------------------------------------------------------------------------------------
// From pest's tree to the syntax tree.

fn syntax(src: &Source) -> Result<Vec<Module>, ModelError> {
    let mut pairs = SmvParser::parse(Rule::file, src.text).map_err(|e| explain(src, &e))?;
    let file = pairs.next().expect("the file rule always yields one pair");
    let mut modules = Vec::new();
    for pair in file.into_inner() {
        match pair.as_rule() {
            Rule::module => modules.push(module(src, pair)?),
            Rule::EOI => {}
            r => unreachable!("a file holds modules, not {r:?}"),
        }
    }
    Ok(modules)
}

fn module(src: &Source, pair: Pair<Rule>) -> Result<Module, ModelError> {
    let mut inner = pair.into_inner();
    let mut header = inner
        .next()
        .expect("a module starts with its header")
        .into_inner();
    let _keyword = header.next();
    let name = ident(header.next().expect("a header names the module"));
    let params = header
        .next()
        .into_iter()
        .flat_map(Pair::into_inner)
        .filter(|p| p.as_rule() == Rule::name)
        .map(ident)
        .collect();
    let mut module = Module {
        name,
        body: Plant {
            params,
            vars: Vec::new(),
            defines: Vec::new(),
            assigns: Vec::new(),
            constraints: Vec::new(),
        },
        instances: Vec::new(),
    };
    for pair in inner {
        section(src, only_child(pair), &mut module)?;
    }
    Ok(module)
}

fn section(src: &Source, pair: Pair<Rule>, module: &mut Module) -> Result<(), ModelError> {
    let rule = pair.as_rule();
    let pos = pair.as_span().start();
    let mut inner = pair.into_inner();
    let _keyword = inner.next();
    match rule {
        Rule::var_section => declarations(src, inner, VarKind::State, module)?,
        Rule::ivar_section => declarations(src, inner, VarKind::Input, module)?,
        Rule::define_section => {
            for define in inner {
                let mut parts = define.into_inner();
                let name = ident(parts.next().expect("a define has a name"));
                let _becomes = parts.next();
                let expr = expr(src, parts.next().expect("and an expression"), 0)?;
                module.body.defines.push(DefineDecl { name, expr });
            }
        }
        Rule::assign_section => {
            for assignment in inner {
                module.body.assigns.push(assign(src, assignment)?);
            }
        }
        Rule::init_section
        | Rule::invar_section
        | Rule::trans_section
        | Rule::fairness_section
        | Rule::justice_section => {
            let section = match rule {
                Rule::init_section => Section::Init,
                Rule::invar_section => Section::Invar,
                Rule::trans_section => Section::Trans,
                Rule::fairness_section => Section::Fairness,
                _ => Section::Justice,
            };
            let constraint = inner.next().expect("a constraint has an expression");
            let expr = expr(src, constraint, 0)?;
            (module.body.constraints).push(ConstraintDecl { section, pos, expr });
        }
        r => unreachable!("no section is built from rule {r:?}"),
    }
    Ok(())
}

/// The declarations of a `VAR` (`kind` state) or `IVAR` (`kind` input) section: variables,
/// and under `VAR` instances of other modules.
fn declarations(
    src: &Source,
    decls: Pairs<Rule>,
    kind: VarKind,
    module: &mut Module,
) -> Result<(), ModelError> {
    for decl in decls {
        let mut parts = decl.into_inner();
        let name = ident(parts.next().expect("a declaration has a name"));
        let _colon = parts.next();
        let ty = only_child(parts.next().expect("and a type"));
        if ty.as_rule() != Rule::instance_type {
            let ty = var_type(src, ty)?;
            module.body.vars.push(VarDecl { name, kind, ty });
            continue;
        }
        let mut parts = ty.into_inner();
        let of = ident(parts.next().expect("an instance names its module"));
        let args = parts.filter(|p| p.as_rule() == Rule::expr);
        let args = args.map(|a| expr(src, a, 0)).collect::<Result<_, _>>()?;
        if kind == VarKind::Input {
            return Err(src.error(
                name.pos,
                format!("{} is a module instance under IVAR", quote(&name.name)),
            ));
        }
        module.instances.push(Instance {
            name,
            module: of,
            args,
        });
    }
    Ok(())
}

/// One assignment of an `ASSIGN` section: `init(x) := ...` or `next(x) := ...` (an invariant
/// `x := ...` is outside the subset).
fn assign(src: &Source, assignment: Pair<Rule>) -> Result<Assign, ModelError> {
    let mut parts = assignment.into_inner();
    let target = parts.next().expect("an assignment has a target");
    let pos = target.as_span().start();
    let target_rule = target.as_rule();
    let var = (target.into_inner())
        .find(|p| p.as_rule() == Rule::name)
        .map(ident)
        .expect("a target names a variable");
    let target = match target_rule {
        Rule::init_target => Target::Init,
        Rule::next_target => Target::Next,
        _ => {
            return Err(src.error(
                pos,
                format!(
                    "'{0} := ...' (an invariant assignment) is outside the subset: \
                     assign init({0}) and next({0}), or use INVAR",
                    cut(&var.name)
                ),
            ))
        }
    };
    let _becomes = parts.next();
    let value = expr(src, parts.next().expect("and a value"), 0)?;
    Ok(Assign {
        target,
        pos,
        var,
        value,
    })
}

fn ident(pair: Pair<Rule>) -> Ident {
    Ident {
        name: pair.as_str().to_string(),
        pos: pair.as_span().start(),
    }
}

fn only_child(pair: Pair<Rule>) -> Pair<Rule> {
    pair.into_inner().next().expect("rule has one child")
}

fn var_type(src: &Source, pair: Pair<Rule>) -> Result<TypeDecl, ModelError> {
    match pair.as_rule() {
        Rule::boolean_type => Ok(TypeDecl::Bool),
        Rule::range_type => {
            let pos = pair.as_span().start();
            let mut ints = pair
                .into_inner()
                .filter(|p| p.as_rule() == Rule::signed_int);
            let lo = integer(src, &ints.next().expect("a range has a low end"))?;
            let hi = integer(src, &ints.next().expect("and a high end"))?;
            Ok(TypeDecl::Range { lo, hi, pos })
        }
        Rule::enum_type => {
            let mut items = Vec::new();
            for value in pair
                .into_inner()
                .filter(|p| p.as_rule() == Rule::enum_value)
            {
                let value = only_child(value);
                let pos = value.as_span().start();
                let value = match value.as_rule() {
                    Rule::signed_int => EnumLit::Int(integer(src, &value)?),
                    Rule::bool_lit => EnumLit::Bool(value.as_str() == "TRUE"),
                    Rule::name => EnumLit::Sym(value.as_str().to_string()),
                    r => unreachable!("no enumeration value is a {r:?}"),
                };
                items.push(EnumItem { pos, value });
            }
            Ok(TypeDecl::Enum(items))
        }
        r => unreachable!("no type is built from rule {r:?}"),
    }
}

/// An integer literal, within NuSMV's range (a C `int`).
fn integer(src: &Source, pair: &Pair<Rule>) -> Result<i64, ModelError> {
    let text = pair.as_str();
    match text.parse::<i64>() {
        Ok(i) if i.unsigned_abs() <= i32::MAX as u64 => Ok(i),
        _ => Err(src.error(
            pair.as_span().start(),
            format!(
                "integer {} is out of NuSMV's range (at most {} in absolute value)",
                cut(text),
                i32::MAX
            ),
        )),
    }
}

/// Builds an expression. `nest` counts the parentheses, cases, sets and `next( )` around it.
fn expr(src: &Source, pair: Pair<Rule>, nest: usize) -> Result<Node, ModelError> {
    let pair = operand_level(pair);
    let (pos, end) = (pair.as_span().start(), pair.as_span().end());
    let text = pair.as_str();
    match pair.as_rule() {
        Rule::implies | Rule::ite => fold_right(src, pair, nest),
        Rule::iff | Rule::or | Rule::and | Rule::rel | Rule::sum | Rule::product => {
            fold_left(src, pair, nest)
        }
        Rule::unary => unary(src, pair, nest),
        Rule::bool_lit => Ok(Node::leaf(pos, end, NodeKind::Bool(text == "TRUE"))),
        Rule::integer => Ok(Node::leaf(pos, end, NodeKind::Int(integer(src, &pair)?))),
        Rule::name => Ok(Node::leaf(pos, end, NodeKind::Name(text.to_string()))),
        Rule::paren => {
            let mut node = expr(src, only_expr(pair), nesting(src, pos, nest)?)?;
            // The node spans its parentheses, so that messages quote them.
            node.pos = pos;
            node.end = end;
            Ok(node)
        }
        Rule::next_expr => {
            let arg = expr(src, only_expr(pair), nesting(src, pos, nest)?)?;
            Node::new(src, pos, end, pos, NodeKind::Next(Box::new(arg)))
        }
        Rule::case_expr => case_expr(src, pair, nesting(src, pos, nest)?),
        Rule::set_expr => {
            let nest = nesting(src, pos, nest)?;
            let items = (pair.into_inner())
                .filter(|p| p.as_rule() == Rule::expr)
                .map(|p| expr(src, p, nest))
                .collect::<Result<Vec<_>, _>>()?;
            Node::new(src, pos, end, pos, NodeKind::Set(items))
        }
        r => unreachable!("no expression is built from rule {r:?}"),
    }
}

/// The first level below `pair` with more than one operand (or a leaf): a level with a single
/// operand is a wrapper, descended without recursing.
fn operand_level(mut pair: Pair<Rule>) -> Pair<Rule> {
    loop {
        let mut inner = pair.clone().into_inner();
        match (pair.as_rule(), inner.next(), inner.next()) {
            (Rule::expr, Some(only), _) => pair = only,
            (level, Some(only), None) if LEVELS.contains(&level) => pair = only,
            _ => return pair,
        }
    }
}

/// The grammar's levels of operators, loosest first.
const LEVELS: &[Rule] = &[
    Rule::implies,
    Rule::iff,
    Rule::ite,
    Rule::or,
    Rule::and,
    Rule::rel,
    Rule::sum,
    Rule::product,
    Rule::unary,
];

/// The expression inside parentheses or `next( )`.
fn only_expr(pair: Pair<Rule>) -> Pair<Rule> {
    (pair.into_inner())
        .find(|p| p.as_rule() == Rule::expr)
        .expect("parentheses and next( ) hold an expression")
}

/// A left-associative level: `a op b op c` as `(a op b) op c`.
fn fold_left(src: &Source, pair: Pair<Rule>, nest: usize) -> Result<Node, ModelError> {
    let mut inner = pair.into_inner();
    let first = inner.next().expect("a level starts with an operand");
    let mut acc = expr(src, first, nest)?;
    while let Some(op) = inner.next() {
        let right = inner.next().expect("an operator has a right operand");
        let right = expr(src, right, nest)?;
        let op_pos = op.as_span().start();
        let (start, end) = (acc.pos, right.end);
        let kind = NodeKind::Bin {
            op: bin_op(op.as_str()),
            op_pos,
            left: Box::new(acc),
            right: Box::new(right),
        };
        acc = Node::new(src, start, end, op_pos, kind)?;
    }
    Ok(acc)
}

/// Prefix operators (`!`, `-`), innermost first.
fn unary(src: &Source, pair: Pair<Rule>, nest: usize) -> Result<Node, ModelError> {
    let end = pair.as_span().end();
    let mut ops: Vec<Pair<Rule>> = pair.into_inner().collect();
    let body = ops.pop().expect("unary ends with an operand");
    let mut acc = expr(src, body, nest)?;
    for op in ops.iter().rev() {
        let op_pos = op.as_span().start();
        let operand = Box::new(acc);
        let kind = match op.as_str() {
            "!" => NodeKind::Not(operand),
            _ => NodeKind::Neg(operand),
        };
        acc = Node::new(src, op_pos, end, op_pos, kind)?;
    }
    Ok(acc)
}

/// `case c1 : v1; ... esac`, its branches nested at `nest`.
fn case_expr(src: &Source, pair: Pair<Rule>, nest: usize) -> Result<Node, ModelError> {
    let (pos, end) = (pair.as_span().start(), pair.as_span().end());
    let mut branches = Vec::new();
    for branch in pair.into_inner().filter(|p| p.as_rule() == Rule::branch) {
        let mut parts = branch.into_inner().filter(|p| p.as_rule() == Rule::expr);
        let cond = expr(src, parts.next().expect("a branch has a condition"), nest)?;
        let value = expr(src, parts.next().expect("and a value"), nest)?;
        branches.push((cond, value));
    }
    Node::new(src, pos, end, pos, NodeKind::Case(branches))
}

/// The nesting level inside a parenthesis (or case, set, `next( )`, `? :`) at `pos`.
fn nesting(src: &Source, pos: usize, nest: usize) -> Result<usize, ModelError> {
    if nest >= MAX_NESTING {
        Err(src.error(
            pos,
            format!(
                "expressions nest more than {MAX_NESTING} levels deep (parentheses, case, sets, \
                 next, ? :); split them with DEFINEs"
            ),
        ))
    } else {
        Ok(nest + 1)
    }
}

/// `a -> b -> c` is `a -> (b -> c)`; `a ? b : c ? d : e` is `a ? b : (c ? d : e)`.
fn fold_right(src: &Source, pair: Pair<Rule>, nest: usize) -> Result<Node, ModelError> {
    let is_ite = pair.as_rule() == Rule::ite;
    // Operands, each with the offset of the operator before it (`->` or `?`).
    let mut operands = Vec::new();
    let mut op_pos = 0;
    for p in pair.into_inner() {
        match p.as_rule() {
            Rule::op_implies | Rule::op_question => op_pos = p.as_span().start(),
            Rule::colon => {}
            // The `a` of `c ? a : b` is a whole expression, nested like a parenthesis.
            Rule::expr => {
                let nest = nesting(src, p.as_span().start(), nest)?;
                operands.push((op_pos, expr(src, p, nest)?));
            }
            _ => operands.push((op_pos, expr(src, p, nest)?)),
        }
    }
    let (mut acc_op, mut acc) = operands.pop().expect("a level has an operand");
    if is_ite {
        // c0 ? a0 : c1 ? a1 : ... : e, the `?` before each a_i.
        while let (Some((op_pos, then)), Some((_, cond))) = (operands.pop(), operands.pop()) {
            let (start, end) = (cond.pos, acc.end);
            let kind = NodeKind::Ite(Box::new(cond), Box::new(then), Box::new(acc));
            acc = Node::new(src, start, end, op_pos, kind)?;
        }
    } else {
        while let Some((op_pos, left)) = operands.pop() {
            let (start, end) = (left.pos, acc.end);
            let kind = NodeKind::Bin {
                op: BinOp::Implies,
                op_pos: acc_op,
                left: Box::new(left),
                right: Box::new(acc),
            };
            acc = Node::new(src, start, end, acc_op, kind)?;
            acc_op = op_pos;
        }
    }
    Ok(acc)
}

fn bin_op(op: &str) -> BinOp {
    match op {
        "<->" => BinOp::Iff,
        "|" => BinOp::Or,
        "xor" => BinOp::Xor,
        "xnor" => BinOp::Xnor,
        "&" => BinOp::And,
        "=" => BinOp::Eq,
        "!=" => BinOp::Ne,
        "<" => BinOp::Lt,
        "<=" => BinOp::Le,
        ">" => BinOp::Gt,
        ">=" => BinOp::Ge,
        "+" => BinOp::Add,
        "-" => BinOp::Sub,
        "*" => BinOp::Mul,
        "/" => BinOp::Div,
        "mod" => BinOp::Mod,
        other => unreachable!("binary operator {other:?}"),
    }
}

// ---------------------------------------------------------------------------------------------
// Parse failures in words.

/// Turns a pest failure into an error at the token where the parse stopped.
///
/// pest reports the rules it could have matched there; they become a list of what was
/// expected. Before that, the token found is checked against the NuSMV constructs outside the
/// subset, so that FROZENVAR, an array or a function call is named rather than "unexpected".
fn explain(src: &Source, e: &pest::error::Error<Rule>) -> ModelError {
    let pos = match e.location {
        pest::error::InputLocation::Pos(p) => p,
        pest::error::InputLocation::Span((s, _)) => s,
    };
    let positives = match &e.variant {
        pest::error::ErrorVariant::ParsingError { positives, .. } => positives.as_slice(),
        // pest's own limits (its stack guard) are the only custom errors.
        pest::error::ErrorVariant::CustomError { message } => {
            return src.error(
                pos,
                format!(
                    "expressions nest too deeply for the parser here ({message}); split them \
                     with DEFINEs"
                ),
            )
        }
    };
    let tokens = tokens(src.text);
    let failure = Failure::at(src, &tokens, pos, positives);
    match failure.outside_subset() {
        Some(e) => e,
        None => failure.expected(),
    }
}

/// Where a parse stopped: the token there, its neighbours, and the rules pest could have
/// matched.
struct Failure<'s> {
    src: &'s Source<'s>,
    /// Byte offset of the token found.
    pos: usize,
    /// The token at the failure (or the one after it), the ones before and after that.
    found: &'s str,
    prev: &'s str,
    after: &'s str,
    positives: &'s [Rule],
}

impl<'s> Failure<'s> {
    fn at(
        src: &'s Source<'s>,
        tokens: &[(usize, &'s str)],
        pos: usize,
        positives: &'s [Rule],
    ) -> Failure<'s> {
        let k = tokens.partition_point(|&(start, tok)| start + tok.len() <= pos);
        let token = |i: usize| tokens.get(i).map_or("", |t| t.1);
        Failure {
            src,
            pos: tokens.get(k).map_or(pos, |t| t.0),
            found: token(k),
            prev: k.checked_sub(1).map_or("", token),
            after: token(k + 1),
            positives,
        }
    }

    fn expects(&self, rules: &[Rule]) -> bool {
        self.positives.iter().any(|r| rules.contains(r))
    }

    fn error(&self, message: impl Into<String>) -> ModelError {
        self.src.error(self.pos, message)
    }

    fn refused(&self, what: String) -> ModelError {
        self.error(format!("{what} is outside the subset of plant files"))
    }

    /// The NuSMV construct outside the subset (or the misplaced keyword) the token found
    /// starts, named; `None` when it is an ordinary syntax error.
    fn outside_subset(&self) -> Option<ModelError> {
        let (found, prev, after) = (self.found, self.prev, self.after);
        if let Some(what) = refused_keyword(found) {
            return Some(self.refused(what));
        }
        let is_word = found.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_');
        if self.expects(&[Rule::var_type]) && is_word {
            return Some(self.refused_type());
        }
        if let Some(e) = self.refused_operator() {
            return Some(e);
        }
        if is_word_constant(found) {
            return Some(self.refused(format!("the word constant {}", quote(found))));
        }
        if self.in_expression() {
            if found == "(" && is_name_like(prev) {
                return Some(self.refused(format!("the function call '{}(...)'", cut(prev))));
            }
            if after == "(" && found == "init" {
                return Some(self.error(
                    "init(...) is not an expression: it only names the target of an assignment",
                ));
            }
            if after == "(" && is_keyword(found) && !SYNTAX_KEYWORDS.contains(&found) {
                return Some(self.refused(format!("the function '{found}(...)'")));
            }
        }
        if matches!(found, "init" | "next") && after == "(" && self.expects(&[Rule::section]) {
            return Some(self.error(format!(
                "{found}(...) := ... stands only in an ASSIGN section"
            )));
        }
        if is_keyword(found) && (!SYNTAX_KEYWORDS.contains(&found) || self.expects(NAME_RULES)) {
            return Some(self.error(format!("'{found}' is a NuSMV keyword, not a name")));
        }
        None
    }

    fn in_expression(&self) -> bool {
        (self.positives.iter()).any(|&r| matches!(describe(r).1, AN_EXPRESSION | AN_OPERATOR))
    }

    /// A word where a type is expected: a NuSMV type outside the subset, or no type at all.
    fn refused_type(&self) -> ModelError {
        let found = self.found;
        let what = match found {
            "array" => "an array type".to_string(),
            "word" | "unsigned" | "signed" | "Word" => "a word type".to_string(),
            "integer" | "real" | "Integer" | "Real" => {
                format!("the unbounded type '{found}' (declare a range lo..hi)")
            }
            "process" => "a process".to_string(),
            _ if is_keyword(found) => {
                return self.error(format!("'{found}' is a NuSMV keyword, not a type"))
            }
            _ => format!("the type {}", quote(found)),
        };
        self.refused(what)
    }

    /// An operator, selection or dotted name outside the subset.
    fn refused_operator(&self) -> Option<ModelError> {
        let (found, prev, after) = (self.found, self.prev, self.after);
        let what = match found {
            "[" => "an array or bit selection ('[...]')".to_string(),
            "<<" | ">>" | "::" | "union" | "in" => format!("the word and set operator '{found}'"),
            "." if is_name_like(prev) => format!(
                "a dotted name ({}, a part of a module instance)",
                quote(&format!("{prev}.{after}"))
            ),
            _ => return None,
        };
        Some(self.refused(what))
    }

    /// "expected X or Y after P, found F", from the rules pest could have matched.
    fn expected(&self) -> ModelError {
        let mut expected: Vec<(u8, &str)> = self.positives.iter().map(|&r| describe(r)).collect();
        expected.sort();
        expected.dedup();
        let expected: Vec<&str> = expected.into_iter().map(|(_, text)| text).collect();
        let expected = match expected.as_slice() {
            [] => "something else".to_string(),
            [one] => one.to_string(),
            [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
        };
        let after_prev = match self.prev {
            "" => String::new(),
            prev => format!(" after {}", quote(prev)),
        };
        let found = match self.found {
            "" => "the end of the file".to_string(),
            found => quote(found).to_string(),
        };
        self.error(format!("expected {expected}{after_prev}, found {found}"))
    }
}

const AN_EXPRESSION: &str = "an expression";
const AN_OPERATOR: &str = "an operator";

/// Rules after which a name is expected, so that a keyword there is one used as a name.
const NAME_RULES: &[Rule] = &[
    Rule::name,
    Rule::var_decl,
    Rule::define,
    Rule::plain_target,
    Rule::enum_value,
];

/// What a rule stands for in a message, with its rank in the list of what was expected.
fn describe(rule: Rule) -> (u8, &'static str) {
    match rule {
        Rule::file | Rule::module | Rule::header | Rule::kw_module => (0, "'MODULE'"),
        Rule::params | Rule::lparen => (1, "'('"),
        Rule::rparen => (2, "')'"),
        Rule::lbrace => (1, "'{'"),
        Rule::rbrace => (2, "'}'"),
        Rule::comma => (3, "','"),
        Rule::colon => (3, "':'"),
        Rule::becomes => (3, "':='"),
        Rule::dotdot => (3, "'..'"),
        Rule::semi => (4, "';'"),
        Rule::kw_esac => (4, "'esac'"),
        Rule::name | Rule::plain_target => (5, "a name"),
        Rule::integer | Rule::signed_int => (5, "an integer"),
        Rule::enum_value => (5, "a value (a name or an integer)"),
        Rule::var_type
        | Rule::boolean_type
        | Rule::range_type
        | Rule::enum_type
        | Rule::instance_type
        | Rule::kw_boolean => (
            5,
            "a type (boolean, lo..hi, {a, b, ...} or a module instance m(args))",
        ),
        Rule::var_decl => (5, "a declaration 'name : type;'"),
        Rule::define => (5, "a definition 'name := expression;'"),
        Rule::assignment | Rule::init_target | Rule::next_target | Rule::kw_init => {
            (5, "an assignment 'init(v) := ...;' or 'next(v) := ...;'")
        }
        Rule::branch => (5, "a case branch 'condition : value;'"),
        Rule::expr
        | Rule::implies
        | Rule::iff
        | Rule::ite
        | Rule::or
        | Rule::and
        | Rule::rel
        | Rule::sum
        | Rule::product
        | Rule::unary
        | Rule::primary
        | Rule::bool_lit
        | Rule::next_expr
        | Rule::case_expr
        | Rule::set_expr
        | Rule::paren
        | Rule::op_not
        | Rule::op_neg
        | Rule::kw_next
        | Rule::kw_case => (5, AN_EXPRESSION),
        Rule::op_implies
        | Rule::op_iff
        | Rule::op_question
        | Rule::op_or
        | Rule::op_and
        | Rule::op_rel
        | Rule::op_sum
        | Rule::op_product => (6, AN_OPERATOR),
        Rule::section
        | Rule::var_section
        | Rule::ivar_section
        | Rule::define_section
        | Rule::assign_section
        | Rule::init_section
        | Rule::invar_section
        | Rule::trans_section
        | Rule::fairness_section
        | Rule::justice_section
        | Rule::kw_var
        | Rule::kw_ivar
        | Rule::kw_define
        | Rule::kw_assign
        | Rule::kw_init_section
        | Rule::kw_invar
        | Rule::kw_trans
        | Rule::kw_fairness
        | Rule::kw_justice => (
            7,
            "a section (VAR, IVAR, DEFINE, ASSIGN, INIT, INVAR, TRANS, FAIRNESS, JUSTICE)",
        ),
        Rule::EOI => (8, "the end of the file"),
        // Silent or inside atomic rules: pest never reports them.
        Rule::WHITESPACE | Rule::COMMENT | Rule::keyword | Rule::ident_char | Rule::ident_start => {
            (9, "something else")
        }
    }
}

/// The NuSMV sections and declarations outside the subset, by their keyword.
fn refused_keyword(found: &str) -> Option<String> {
    Some(match found {
        "FROZENVAR" => "FROZENVAR (declare a VAR with next(v) := v)".to_string(),
        "COMPASSION" => "COMPASSION (strong fairness; FAIRNESS and JUSTICE are in)".to_string(),
        "SPEC" | "CTLSPEC" | "LTLSPEC" | "INVARSPEC" | "PSLSPEC" | "COMPUTE" => {
            format!("{found} (properties belong in the specification file, not in the plant)")
        }
        "ISA" | "CONSTANTS" | "PRED" | "PREDICATES" | "MIRROR" | "MDEFINE" | "CONSTRAINT" => {
            found.to_string()
        }
        "process" => "a process".to_string(),
        "self" => "'self' (a module's reference to itself)".to_string(),
        _ => return None,
    })
}

/// Keywords the subset's grammar itself uses.
const SYNTAX_KEYWORDS: &[&str] = &[
    "MODULE", "VAR", "IVAR", "DEFINE", "ASSIGN", "INIT", "INVAR", "TRANS", "FAIRNESS", "JUSTICE",
    "boolean", "init", "next", "case", "esac", "TRUE", "FALSE", "mod", "xor", "xnor",
];

fn is_keyword(s: &str) -> bool {
    crate::ecc::ident::NUSMV_LEXER_KEYWORDS.contains(&s)
}

/// A token that reads as a name (keywords included).
fn is_name_like(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
}

/// NuSMV's word constants: `0ub4_1`, `0sd8_3`, `0b101`, ...
fn is_word_constant(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next() == Some('0')
        && s.len() > 2
        && chars.next().is_some_and(|c| "usbBoOdDhH".contains(c))
}

/// Operators and punctuation of more than one character, longest first.
const SYMBOLS: &[&str] = &["<->", "->", ":=", "..", "!=", "<=", ">=", "<<", ">>", "::"];

/// The tokens of the text with their byte offsets, as NuSMV's lexer (and the grammar) cut
/// them; blanks and comments skipped. A number runs on over letters, so that a word constant
/// is one token.
fn tokens(text: &str) -> Vec<(usize, &str)> {
    let bytes = text.as_bytes();
    let ident = |i: usize| {
        let c = bytes[i];
        c.is_ascii_alphanumeric()
            || matches!(c, b'_' | b'$' | b'#')
            || (c == b'-' && !matches!(bytes.get(i + 1), Some(b'>' | b'-')))
    };
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if text[i..].starts_with("--") {
            i = text[i..].find('\n').map_or(bytes.len(), |k| i + k);
            continue;
        }
        let start = i;
        if c.is_ascii_alphabetic() || c == b'_' {
            while i < bytes.len() && ident(i) {
                i += 1;
            }
        } else if c.is_ascii_digit() {
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
        } else if let Some(sym) = SYMBOLS.iter().find(|s| text[i..].starts_with(*s)) {
            i += sym.len();
        } else {
            i += text[i..].chars().next().map_or(1, char::len_utf8);
        }
        out.push((start, &text[start..i]));
    }
    out
}
