//! The module hierarchy of a plant file made flat, as NuSMV's `flatten_hierarchy` makes it:
//! the modules as written in, one [`Plant`] for `MODULE plant` out, or an error naming the
//! instance, module or name at fault with its line.
//!
//! `MODULE plant` keeps its parameters (the controller outputs) and its names. Every instance
//! `inst : m(args);` declared in a module instantiated under the prefix `p` contributes the
//! variables, defines, assignments and constraints of `m`, each of its names `x` renamed
//! `p.inst.x`, each of its parameters replaced by the argument expression (written in the
//! instantiating module, so already renamed there). A name that no module declares stays as
//! it is: a symbolic constant, global in NuSMV, or an unknown name the resolver reports. A
//! dotted name `a.b` reads `b` of the instance `a`; when `a` is a parameter bound to an
//! instance, of that instance. Every node keeps its byte offset in the file, so that an error
//! in a submodule names the submodule's line.

use super::syntax::{
    Assign, ConstraintDecl, DefineDecl, Ident, Module, Node, NodeKind, Plant, Source,
};
use crate::plant::ModelError;
use crate::quote::{cut, quote};
use std::collections::{HashMap, HashSet};

/// The deepest chain of instances (`plant` at depth 0); far beyond any real plant, it bounds
/// the recursion.
const MAX_INSTANCE_DEPTH: usize = 64;

/// The flat `MODULE plant` of the file's modules.
pub(super) fn flatten(src: &Source, modules: Vec<Module>) -> Result<Plant, ModelError> {
    let mut by_name: HashMap<&str, usize> = HashMap::new();
    for (i, m) in modules.iter().enumerate() {
        if let Some(first) = by_name.insert(&m.name.name, i) {
            let line = src.line(modules[first].name.pos);
            return Err(src.error(
                m.name.pos,
                format!(
                    "module {} is declared twice (first on line {line})",
                    quote(&m.name.name)
                ),
            ));
        }
    }
    let Some(&top) = by_name.get("plant") else {
        let first = modules.first().map_or(0, |m| m.name.pos);
        let found: Vec<&str> = modules.iter().map(|m| m.name.name.as_str()).collect();
        return Err(src.error(
            first,
            format!(
                "no MODULE plant(outputs...) in the file (found {}); the plant is the module \
                 named plant",
                cut(&found.join(", "))
            ),
        ));
    };
    let plant = &modules[top];
    let mut out = Plant {
        params: plant.body.params.clone(),
        vars: Vec::new(),
        defines: Vec::new(),
        assigns: Vec::new(),
        constraints: Vec::new(),
    };
    let flat = Flattener {
        src,
        modules: &modules,
        by_name,
    };
    let scope = Scope {
        prefix: String::new(),
        args: HashMap::new(),
    };
    flat.instantiate(top, &scope, &mut vec![top], &mut out)?;
    Ok(out)
}

struct Flattener<'a> {
    src: &'a Source<'a>,
    modules: &'a [Module],
    by_name: HashMap<&'a str, usize>,
}

/// Where a module is instantiated: the prefix of its names and what its parameters stand for.
struct Scope {
    prefix: String,
    args: HashMap<String, Node>,
}

impl Flattener<'_> {
    /// Adds module `m`, instantiated in `scope`, and its instances to `out`. `stack` holds the
    /// modules being instantiated, `m` last.
    fn instantiate(
        &self,
        m: usize,
        scope: &Scope,
        stack: &mut Vec<usize>,
        out: &mut Plant,
    ) -> Result<(), ModelError> {
        let module = &self.modules[m];
        let body = &module.body;
        let local: HashSet<&str> = (body.vars.iter().map(|v| v.name.name.as_str()))
            .chain(body.defines.iter().map(|d| d.name.name.as_str()))
            .chain(module.instances.iter().map(|i| i.name.name.as_str()))
            .collect();
        let rename = |node: &Node| rename(node, &local, scope);
        let renamed = |id: &Ident| Ident {
            name: format!("{}{}", scope.prefix, id.name),
            pos: id.pos,
        };
        for v in &body.vars {
            out.vars.push(super::syntax::VarDecl {
                name: renamed(&v.name),
                kind: v.kind,
                ty: v.ty.clone(),
            });
        }
        for d in &body.defines {
            out.defines.push(DefineDecl {
                name: renamed(&d.name),
                expr: rename(&d.expr),
            });
        }
        for a in &body.assigns {
            out.assigns.push(Assign {
                target: a.target,
                pos: a.pos,
                var: self.assigned(&a.var, &local, scope),
                value: rename(&a.value),
            });
        }
        for c in &body.constraints {
            out.constraints.push(ConstraintDecl {
                section: c.section,
                pos: c.pos,
                expr: rename(&c.expr),
            });
        }
        for inst in &module.instances {
            let sub = self.module_of(inst, stack)?;
            let params = &self.modules[sub].body.params;
            if params.len() != inst.args.len() {
                return Err(self.src.error(
                    inst.module.pos,
                    format!(
                        "module {} takes {} parameters, the instance {} passes {}",
                        quote(&inst.module.name),
                        params.len(),
                        quote(&inst.name.name),
                        inst.args.len()
                    ),
                ));
            }
            let args = (params.iter().map(|p| p.name.clone()))
                .zip(inst.args.iter().map(rename))
                .collect();
            let inner = Scope {
                prefix: format!("{}{}.", scope.prefix, inst.name.name),
                args,
            };
            stack.push(sub);
            self.instantiate(sub, &inner, stack, out)?;
            stack.pop();
        }
        Ok(())
    }

    /// The module an instance declares, refused when unknown, recursive or too deep.
    fn module_of(
        &self,
        inst: &super::syntax::Instance,
        stack: &[usize],
    ) -> Result<usize, ModelError> {
        let name = &inst.module.name;
        let Some(&sub) = self.by_name.get(name.as_str()) else {
            return Err(self.src.error(
                inst.module.pos,
                format!(
                    "no module {} in the file (the type of {})",
                    quote(name),
                    quote(&inst.name.name)
                ),
            ));
        };
        if stack.contains(&sub) {
            return Err(self.src.error(
                inst.module.pos,
                format!(
                    "module {} instantiates itself (recursive modules have no finite model)",
                    quote(name)
                ),
            ));
        }
        if stack.len() > MAX_INSTANCE_DEPTH {
            return Err(self.src.error(
                inst.module.pos,
                format!("module instances nest more than {MAX_INSTANCE_DEPTH} deep"),
            ));
        }
        Ok(sub)
    }

    /// The variable an assignment of the module in `scope` targets: a local one renamed, a
    /// parameter bound to a variable that variable (NuSMV assigns through it).
    fn assigned(&self, var: &Ident, local: &HashSet<&str>, scope: &Scope) -> Ident {
        let node = Node::leaf(
            var.pos,
            var.pos + var.name.len(),
            NodeKind::Name(var.name.clone()),
        );
        match rename(&node, local, scope).kind {
            NodeKind::Name(name) => Ident { name, pos: var.pos },
            // Bound to an expression: the resolver refuses the assignment under its own name.
            _ => var.clone(),
        }
    }
}

/// `node` with the names of the module instantiated in `scope` renamed (`local`: the names
/// it declares) and its parameters replaced by their arguments.
fn rename(node: &Node, local: &HashSet<&str>, scope: &Scope) -> Node {
    let kind = match &node.kind {
        NodeKind::Name(name) => {
            let (head, tail) = name
                .split_once('.')
                .map_or((name.as_str(), None), |(h, t)| (h, Some(t)));
            if let Some(arg) = scope.args.get(head) {
                return match (tail, &arg.kind) {
                    // A name or constant stands where the parameter is written, so that a
                    // message about it names the submodule's line.
                    (None, NodeKind::Name(_) | NodeKind::Bool(_) | NodeKind::Int(_)) => {
                        Node::leaf(node.pos, node.end, arg.kind.clone())
                    }
                    (None, _) => arg.clone(),
                    // A parameter bound to an instance: a part of that instance.
                    (Some(tail), NodeKind::Name(bound)) => Node::leaf(
                        node.pos,
                        node.end,
                        NodeKind::Name(format!("{bound}.{tail}")),
                    ),
                    // A part of an expression: left for the resolver to refuse by name.
                    (Some(_), _) => node.clone(),
                };
            }
            if local.contains(head) {
                NodeKind::Name(format!("{}{name}", scope.prefix))
            } else {
                NodeKind::Name(name.clone())
            }
        }
        NodeKind::Bool(_) | NodeKind::Int(_) => return node.clone(),
        NodeKind::Next(x) => NodeKind::Next(Box::new(rename(x, local, scope))),
        NodeKind::Not(x) => NodeKind::Not(Box::new(rename(x, local, scope))),
        NodeKind::Neg(x) => NodeKind::Neg(Box::new(rename(x, local, scope))),
        NodeKind::Bin {
            op,
            op_pos,
            left,
            right,
        } => NodeKind::Bin {
            op: *op,
            op_pos: *op_pos,
            left: Box::new(rename(left, local, scope)),
            right: Box::new(rename(right, local, scope)),
        },
        NodeKind::Case(branches) => NodeKind::Case(
            (branches.iter())
                .map(|(c, v)| (rename(c, local, scope), rename(v, local, scope)))
                .collect(),
        ),
        NodeKind::Ite(c, a, b) => NodeKind::Ite(
            Box::new(rename(c, local, scope)),
            Box::new(rename(a, local, scope)),
            Box::new(rename(b, local, scope)),
        ),
        NodeKind::Set(items) => {
            NodeKind::Set(items.iter().map(|x| rename(x, local, scope)).collect())
        }
    };
    let depth = if matches!(kind, NodeKind::Name(_)) {
        0
    } else {
        Node::depth_of(&kind)
    };
    Node {
        pos: node.pos,
        end: node.end,
        depth,
        kind,
    }
}
