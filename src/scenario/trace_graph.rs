//! The trace graph of the SAT reconstruction paper (section IV.A): noisy scenarios laid out without merging, plus
//! the alternative edges of its error model.
//!
//! In: a [`ScenarioSet`] whose scenarios may be noisy (steps from
//! [`csvlog::samples_to_steps`](super::csvlog::samples_to_steps) or any scenario file).
//! Out: a [`TraceGraph`]: one chain per *distinct* scenario, all chains hanging from one shared
//! root (every trace starts in the initial state with the initial outputs, so the paper's
//! per-trace roots, all coloured 0, are one node here), and the list of [`Alternative`] edges.
//!
//! # Layout
//! The graph is stored as a [`ScenarioTree`] so the colouring families of the basic encoding
//! apply to it unchanged: a node per active step, the node's `parent` edge labelled with the
//! *recorded* input, and passive steps as passive marks on the node they leave unchanged
//! (exactly as in the tree: a passive step does not change state or outputs). Unlike a tree
//! built by [`ScenarioTree::build`], nothing is merged beyond the root, so a node may have two
//! children on one input (the noise the paper speaks of); the SAT encoding decides which edges
//! are real.
//!
//! # Error model (scan-cycle skew)
//! The data collector and the PLC scan asynchronously, so an output change can be recorded one
//! sample before the input change that caused it. After preprocessing, such a change shows as
//! an active step `u -x1-> v` (outputs change on the *old* inputs `x1`) followed by the step
//! `v -x2-> l` on the inputs `x2` that really caused it. For every active step whose outputs
//! differ from its source's and that has a next step, the alternative edge `u -x2-> v` is
//! added: the same nodes and outputs, labelled with the next step's input. Selecting it gives
//! the corrected, error-free step `(x2, CNF)`; the step after it stays as recorded.

use super::tree::{InputVec, Node, NodeId, ScenarioTree};
use super::{ScenarioSet, Step};
use crate::ecc::{Ecc, Run, StateId};
use std::collections::HashMap;

/// A hypothesis edge: the active step into `node` may really have happened on `input`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) struct Alternative {
    /// The node the active step enters (its parent is the edge's source).
    pub(crate) node: NodeId,
    /// The input of the step after it in the trace, interned in the tree.
    pub(crate) input: InputVec,
}

/// One distinct scenario laid out as a chain of the graph.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Chain {
    /// Indices (into the scenario set) of every scenario with exactly these steps.
    pub(crate) scenarios: Vec<usize>,
    /// Per step: the node an active step enters, `None` for a passive step.
    pub(crate) nodes: Vec<Option<NodeId>>,
}

/// The trace graph with its alternative edges.
#[derive(Debug, Clone)]
pub(crate) struct TraceGraph {
    /// Nodes and recorded edges, laid out as described in the module doc.
    pub(crate) tree: ScenarioTree,
    /// One chain per distinct scenario, in order of first appearance.
    pub(crate) chains: Vec<Chain>,
    /// Alternative edges, in order of the nodes they enter; at most one per node.
    pub(crate) alternatives: Vec<Alternative>,
    /// `alternative_of[node]`: index into `alternatives`.
    pub(crate) alternative_of: HashMap<NodeId, usize>,
}

impl TraceGraph {
    /// Builds the graph; never fails (noise is what the graph is for).
    pub(crate) fn build(set: &ScenarioSet) -> TraceGraph {
        let mut tree = ScenarioTree::root_only(&set.initial_outputs);
        let mut interned: HashMap<Vec<bool>, InputVec> = HashMap::new();
        let mut intern = |tree: &mut ScenarioTree, x: &[bool]| -> InputVec {
            *interned.entry(x.to_vec()).or_insert_with(|| {
                tree.input_vectors.push(x.to_vec());
                InputVec(tree.input_vectors.len() - 1)
            })
        };
        let mut chains: Vec<Chain> = Vec::new();
        let mut by_steps: HashMap<&[Step], usize> = HashMap::new();
        let mut alternatives = Vec::new();
        let mut alternative_of = HashMap::new();
        for (si, sc) in set.scenarios.iter().enumerate() {
            if let Some(&k) = by_steps.get(sc.steps.as_slice()) {
                chains[k].scenarios.push(si);
                continue;
            }
            by_steps.insert(&sc.steps, chains.len());
            let mut at = NodeId(0);
            let mut nodes = Vec::with_capacity(sc.steps.len());
            for (k, step) in sc.steps.iter().enumerate() {
                let u = intern(&mut tree, &step.inputs);
                let Some(out) = &step.outputs else {
                    let passive = &mut tree.nodes[at.0].passive;
                    if !passive.contains(&u) {
                        passive.push(u);
                    }
                    nodes.push(None);
                    continue;
                };
                let child = NodeId(tree.nodes.len());
                let changed = *out != tree.nodes[at.0].outputs;
                tree.nodes.push(Node {
                    outputs: out.clone(),
                    parent: Some((at, u)),
                    children: Vec::new(),
                    passive: Vec::new(),
                });
                tree.witness.push((si, k + 1));
                tree.nodes[at.0].children.push((u, child));
                if let Some(next) = alternative_input(&sc.steps, k, changed) {
                    let alt = intern(&mut tree, next);
                    alternative_of.insert(child, alternatives.len());
                    alternatives.push(Alternative {
                        node: child,
                        input: alt,
                    });
                }
                nodes.push(Some(child));
                at = child;
            }
            chains.push(Chain {
                scenarios: vec![si],
                nodes,
            });
        }
        TraceGraph {
            tree,
            chains,
            alternatives,
            alternative_of,
        }
    }

    /// The scenarios with the chosen edges: `used[a]` says whether alternative `a` replaces
    /// the recorded edge. Each scenario keeps its origin; a step on a used alternative edge
    /// gets the alternative's input.
    pub(crate) fn corrected(&self, set: &ScenarioSet, used: &[bool]) -> ScenarioSet {
        let mut out = set.clone();
        for chain in &self.chains {
            for &si in &chain.scenarios {
                for (step, node) in out.scenarios[si].steps.iter_mut().zip(&chain.nodes) {
                    let Some(node) = node else { continue };
                    if let Some(&a) = self.alternative_of.get(node) {
                        if used[a] {
                            step.inputs =
                                self.tree.input_vectors[self.alternatives[a].input.0].clone();
                        }
                    }
                }
            }
        }
        out
    }

    /// Source of the recorded (and alternative) edge into `node`, with the recorded input.
    pub(crate) fn parent(&self, node: NodeId) -> (NodeId, InputVec) {
        self.tree.nodes[node.0]
            .parent
            .expect("every node but the root has a parent")
    }
}

/// The input of the alternative edge of active step `k` of `steps`, if it has one: the step
/// `changed` the outputs and a next step exists on other inputs (equal inputs would make the
/// alternative the recorded edge itself). The one rule of the error model, shared by the
/// graph and [`least_corrections`].
pub(crate) fn alternative_input(steps: &[Step], k: usize, changed: bool) -> Option<&[bool]> {
    let next = steps.get(k + 1).filter(|_| changed)?;
    (next.inputs != steps[k].inputs).then_some(next.inputs.as_slice())
}

/// How a fixed machine explains one noisy trace with the fewest corrections.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Corrections {
    /// The steps (0-based) whose alternative edge is taken: the corrected errors.
    pub(crate) steps: Vec<usize>,
    /// Per alternative of the trace, in step order (the order of [`TraceGraph::alternatives`]
    /// along the trace's chain): taken or not.
    pub(crate) used: Vec<bool>,
}

/// The fewest alternative edges with which `ecc` reproduces `steps` (from its initial state
/// and `initial_outputs`), or `None` when no choice of edges does. A dynamic programme over
/// the machine's states, linear in the trace: along every surviving choice the outputs are
/// the recorded ones, so a state is all a choice leaves behind.
///
/// This replays a machine under the error model of [`TraceGraph`] without encoding the trace:
/// the noisy encoding over a graph of this trace alone, with the machine's transitions fixed,
/// has a model with `ε` errors exactly when this finds at most `ε`.
pub(crate) fn least_corrections(
    ecc: &Ecc,
    initial_outputs: &[bool],
    steps: &[Step],
) -> Option<Corrections> {
    // cost[q]: fewest corrections reaching state q after the steps so far.
    let mut cost: Vec<Option<usize>> = vec![None; ecc.states.len()];
    cost[0] = Some(0);
    let mut back: Vec<Back> = Vec::new();
    let mut outputs = initial_outputs.to_vec();
    let fire = |q: usize, outputs: &[bool], x: &[bool]| {
        let mut run = Run::at(ecc, StateId(q), outputs.to_vec());
        run.step(x).map(|f| (f.target.0, run.outputs))
    };
    for (k, step) in steps.iter().enumerate() {
        let Some(out) = &step.outputs else {
            // A step without an answer: nothing may fire on it.
            for (q, c) in cost.iter_mut().enumerate() {
                if c.is_some() && fire(q, &outputs, &step.inputs).is_some() {
                    *c = None;
                }
            }
            if cost.iter().all(Option::is_none) {
                return None;
            }
            continue;
        };
        let alt = alternative_input(steps, k, *out != outputs);
        let mut next: Vec<Option<usize>> = vec![None; cost.len()];
        let mut from: Vec<Option<(usize, bool)>> = vec![None; cost.len()];
        for (q, c) in cost.iter().enumerate() {
            let Some(c) = *c else { continue };
            let labels =
                std::iter::once((step.inputs.as_slice(), false)).chain(alt.map(|a| (a, true)));
            for (x, taken) in labels {
                let Some((q2, emitted)) = fire(q, &outputs, x) else {
                    continue;
                };
                let c2 = c + usize::from(taken);
                if emitted == *out && next[q2].is_none_or(|n| c2 < n) {
                    next[q2] = Some(c2);
                    from[q2] = Some((q, taken));
                }
            }
        }
        if next.iter().all(Option::is_none) {
            return None;
        }
        cost = next;
        back.push(Back {
            step: k,
            has_alternative: alt.is_some(),
            from,
        });
        outputs.clone_from(out);
    }
    traced_back(&cost, &back)
}

/// One answered step of [`least_corrections`]'s programme, kept to trace the choice back.
struct Back {
    /// The step's index.
    step: usize,
    /// Whether the step has an alternative edge.
    has_alternative: bool,
    /// Per state entered: the state left and whether the alternative was taken.
    from: Vec<Option<(usize, bool)>>,
}

/// The corrections of the cheapest state at the end (`cost`), traced back through `back`.
fn traced_back(cost: &[Option<usize>], back: &[Back]) -> Option<Corrections> {
    let (mut q, _) = (cost.iter().enumerate())
        .filter_map(|(q, c)| c.map(|c| (q, c)))
        .min_by_key(|&(_, c)| c)?;
    let mut taken = Vec::new();
    let mut with_alt = Vec::new();
    for b in back.iter().rev() {
        let (p, alt) = b.from[q].expect("a surviving state has a predecessor");
        if alt {
            taken.push(b.step);
        }
        if b.has_alternative {
            with_alt.push(alt);
        }
        q = p;
    }
    taken.reverse();
    with_alt.reverse();
    Some(Corrections {
        steps: taken,
        used: with_alt,
    })
}

#[cfg(test)]
mod tests {
    use super::super::fbsat;
    use super::*;
    use std::path::Path;

    fn graph(text: &str) -> (ScenarioSet, TraceGraph) {
        let set = fbsat::parse(Path::new("s.txt"), text, None, None).unwrap();
        let g = TraceGraph::build(&set);
        (set, g)
    }

    #[test]
    fn one_chain_per_distinct_trace_and_alternatives_on_output_changes() {
        // Trace 1: 0 passive, 1 -> out 1, 0 passive. Trace 2 repeats trace 1; trace 3 starts
        // like trace 1 but is kept apart (no merging beyond the root).
        let (_, g) = graph(
            "3\nin=REQ[0]; in=REQ[1]; out=CNF[1]; in=REQ[0];\n\
             in=REQ[0]; in=REQ[1]; out=CNF[1]; in=REQ[0];\n\
             in=REQ[1]; out=CNF[1]; in=REQ[0]; out=CNF[0];\n",
        );
        assert_eq!(g.chains.len(), 2);
        assert_eq!(g.chains[0].scenarios, vec![0, 1]);
        assert_eq!(g.chains[0].nodes, vec![None, Some(NodeId(1)), None]);
        assert_eq!(g.chains[1].nodes, vec![Some(NodeId(2)), Some(NodeId(3))]);
        // Root has two children on input 1 (one per chain) and a passive mark on 0.
        assert_eq!(g.tree.nodes.len(), 4);
        assert_eq!(g.tree.nodes[0].children.len(), 2);
        // Node 1 (changed outputs, next step on 0) and node 2 get alternatives labelled 0;
        // node 3 is the last step: no child, no alternative.
        let zero = InputVec(0);
        assert_eq!(
            g.alternatives,
            vec![
                Alternative {
                    node: NodeId(1),
                    input: zero
                },
                Alternative {
                    node: NodeId(2),
                    input: zero
                }
            ]
        );
        assert_eq!(g.parent(NodeId(3)), (NodeId(2), zero));
    }

    #[test]
    fn unchanged_outputs_get_no_alternative() {
        // The second CNF repeats the outputs: no change, so no skew to correct.
        let (_, g) = graph("1\nin=REQ[1]; out=CNF[1]; in=REQ[0]; out=CNF[1]; in=REQ[1];\n");
        assert_eq!(g.alternatives.len(), 1);
        assert_eq!(g.alternatives[0].node, NodeId(1));
    }

    #[test]
    fn corrected_traces_take_the_alternative_inputs() {
        let (set, g) = graph("1\nin=REQ[01]; out=CNF[1]; in=REQ[10];\n");
        let fixed = g.corrected(&set, &[true]);
        assert_eq!(fixed.scenarios[0].steps[0].inputs, vec![true, false]);
        assert_eq!(fixed.scenarios[0].steps[1], set.scenarios[0].steps[1]);
        assert_eq!(g.corrected(&set, &[false]), set);
    }
}
