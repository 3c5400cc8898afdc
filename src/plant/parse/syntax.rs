//! The syntax tree of a plant file: the file as written, names unresolved, every node with
//! its byte offset, and the [`Source`] that turns an offset into a located error. Built from
//! pest's parse by the parent module, turned into a model by `resolve`.

use crate::plant::{BinOp, ModelError, VarKind};
use crate::quote::cut;
use std::path::Path;

/// The most operators on one path from the root of an expression to a leaf (a chain `a | b |
/// ...` counts one per operator). Every walk over an expression recurses once per level.
pub(super) const MAX_DEPTH: usize = 1000;

/// The text of the plant file, with what turns a byte offset into a place.
pub(super) struct Source<'a> {
    pub(super) text: &'a str,
    pub(super) file: &'a Path,
    /// Byte offset of the start of every line.
    pub(super) line_starts: Vec<usize>,
}

impl<'a> Source<'a> {
    pub(super) fn new(text: &'a str, file: &'a Path) -> Self {
        let mut line_starts = vec![0];
        line_starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        Source {
            text,
            file,
            line_starts,
        }
    }

    /// 1-based line of a byte offset.
    pub(super) fn line(&self, pos: usize) -> usize {
        self.line_starts.partition_point(|&start| start <= pos)
    }

    /// An error at a byte offset; the column counts characters, not bytes.
    pub(super) fn error(&self, pos: usize, message: impl Into<String>) -> ModelError {
        let line = self.line(pos);
        let start = self.line_starts[line - 1];
        let column = self.text[start..pos].chars().count() + 1;
        ModelError::At {
            file: self.file.to_path_buf(),
            line,
            column,
            message: message.into(),
        }
    }

    /// The code between two offsets for a message: comments dropped, blanks collapsed, long
    /// code cut ([`cut`]).
    pub(super) fn snippet(&self, start: usize, end: usize) -> String {
        let code: Vec<&str> = self.text[start..end]
            .lines()
            .map(|l| l.split("--").next().unwrap_or(""))
            .flat_map(str::split_whitespace)
            .collect();
        cut(&code.join(" ")).to_string()
    }
}

/// A module of the plant file as written: its parameters, declarations and sections in
/// [`Plant`], and the module instances it declares.
pub(super) struct Module {
    /// The module's name, where the header writes it.
    pub(super) name: Ident,
    pub(super) body: Plant,
    pub(super) instances: Vec<Instance>,
}

/// `name : module(args);` in a `VAR` section.
pub(super) struct Instance {
    pub(super) name: Ident,
    pub(super) module: Ident,
    pub(super) args: Vec<Node>,
}

/// A module as written, or the flat `MODULE plant` that [`flatten`](super::flatten) makes of
/// the file.
pub(super) struct Plant {
    pub(super) params: Vec<Ident>,
    pub(super) vars: Vec<VarDecl>,
    pub(super) defines: Vec<DefineDecl>,
    pub(super) assigns: Vec<Assign>,
    pub(super) constraints: Vec<ConstraintDecl>,
}

/// A name and the byte offset where it is written.
#[derive(Clone)]
pub(super) struct Ident {
    pub(super) name: String,
    pub(super) pos: usize,
}

pub(super) struct VarDecl {
    pub(super) name: Ident,
    pub(super) kind: VarKind,
    pub(super) ty: TypeDecl,
}

#[derive(Clone)]
pub(super) enum TypeDecl {
    Bool,
    Range { lo: i64, hi: i64, pos: usize },
    Enum(Vec<EnumItem>),
}

#[derive(Clone)]
pub(super) struct EnumItem {
    pub(super) pos: usize,
    pub(super) value: EnumLit,
}

#[derive(Clone)]
pub(super) enum EnumLit {
    Int(i64),
    Bool(bool),
    Sym(String),
}

pub(super) struct DefineDecl {
    pub(super) name: Ident,
    pub(super) expr: Node,
}

/// Which assignment of `ASSIGN`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(super) enum Target {
    Init,
    Next,
}

impl Target {
    pub(super) fn keyword(self) -> &'static str {
        match self {
            Target::Init => "init",
            Target::Next => "next",
        }
    }
}

pub(super) struct Assign {
    pub(super) target: Target,
    /// Offset of the `init` / `next` keyword.
    pub(super) pos: usize,
    pub(super) var: Ident,
    pub(super) value: Node,
}

/// A constraint section.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Section {
    Init,
    Invar,
    Trans,
    Fairness,
    Justice,
}

impl Section {
    pub(super) fn keyword(self) -> &'static str {
        match self {
            Section::Init => "INIT",
            Section::Invar => "INVAR",
            Section::Trans => "TRANS",
            Section::Fairness => "FAIRNESS",
            Section::Justice => "JUSTICE",
        }
    }
}

pub(super) struct ConstraintDecl {
    pub(super) section: Section,
    /// Offset of the section keyword.
    pub(super) pos: usize,
    pub(super) expr: Node,
}

/// An expression as written, spanning `pos..end` of the text.
#[derive(Clone)]
pub(super) struct Node {
    pub(super) pos: usize,
    pub(super) end: usize,
    /// Operators on the longest path to a leaf (0 for a leaf).
    pub(super) depth: usize,
    pub(super) kind: NodeKind,
}

#[derive(Clone)]
pub(super) enum NodeKind {
    Bool(bool),
    Int(i64),
    Name(String),
    /// `next(e)` (the resolver accepts only a variable inside).
    Next(Box<Node>),
    Not(Box<Node>),
    Neg(Box<Node>),
    Bin {
        op: BinOp,
        /// Offset of the operator.
        op_pos: usize,
        left: Box<Node>,
        right: Box<Node>,
    },
    Case(Vec<(Node, Node)>),
    /// `c ? a : b`.
    Ite(Box<Node>, Box<Node>, Box<Node>),
    Set(Vec<Node>),
}

impl Node {
    /// The operator nodes, where a chain that exceeds [`MAX_DEPTH`] is refused.
    pub(super) fn new(
        src: &Source,
        pos: usize,
        end: usize,
        op_pos: usize,
        kind: NodeKind,
    ) -> Result<Node, ModelError> {
        let depth = Node::depth_of(&kind);
        if depth > MAX_DEPTH {
            return Err(src.error(
                op_pos,
                format!(
                    "the expression is more than {MAX_DEPTH} operators deep; split it with DEFINEs"
                ),
            ));
        }
        Ok(Node {
            pos,
            end,
            depth,
            kind,
        })
    }

    /// Operators on the longest path from a node of this kind to a leaf.
    pub(super) fn depth_of(kind: &NodeKind) -> usize {
        1 + match kind {
            NodeKind::Bool(_) | NodeKind::Int(_) | NodeKind::Name(_) => 0,
            NodeKind::Next(x) | NodeKind::Not(x) | NodeKind::Neg(x) => x.depth,
            NodeKind::Bin { left, right, .. } => left.depth.max(right.depth),
            NodeKind::Case(branches) => branches
                .iter()
                .map(|(c, v)| c.depth.max(v.depth))
                .max()
                .unwrap_or(0),
            NodeKind::Ite(c, a, b) => c.depth.max(a.depth).max(b.depth),
            NodeKind::Set(items) => items.iter().map(|x| x.depth).max().unwrap_or(0),
        }
    }

    pub(super) fn leaf(pos: usize, end: usize, kind: NodeKind) -> Node {
        Node {
            pos,
            end,
            depth: 0,
            kind,
        }
    }
}
