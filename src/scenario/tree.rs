//! The scenario tree: all scenarios merged by common input history.
//!
//! Nodes stand for input histories that the (deterministic) controller cannot tell apart:
//! the root is the empty history, and an active step from node `p` on input vector `u` leads to
//! a child. A passive step does not change the controller's state or outputs, so its history is
//! merged with its parent's: the step becomes a *passive mark* `(p, u)`: in the state of `p`, no
//! transition may fire on `u`. This is exact, not an approximation: the simulator's semantics
//! makes the two histories indistinguishable.
//!
//! Input vectors are interned: `u` is an index into [`ScenarioTree::input_vectors`].
//!
//! Two scenarios that make the same node answer the same input differently (different outputs,
//! or `CNF` in one and none in the other) contradict each other: no deterministic controller
//! reproduces both, and building the tree fails naming both places.

use super::{Origin, ScenarioError, ScenarioSet};
use std::collections::HashMap;

/// Index of a tree node; node 0 is the root.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) struct NodeId(pub(crate) usize);

/// Index of a distinct input vector of the tree.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) struct InputVec(pub(crate) usize);

/// One node: output values reached, the edge from its parent, its children and passive marks.
#[derive(Debug, Clone)]
pub(crate) struct Node {
    /// Outputs after the history of this node (the root has the initial outputs).
    pub(crate) outputs: Vec<bool>,
    /// `(parent, input)` of the active step leading here; `None` for the root.
    pub(crate) parent: Option<(NodeId, InputVec)>,
    /// Active steps from here, in order of first appearance.
    pub(crate) children: Vec<(InputVec, NodeId)>,
    /// Inputs on which nothing fires here, in order of first appearance.
    pub(crate) passive: Vec<InputVec>,
}

/// Where an edge was first seen: scenario and 1-based step.
#[derive(Debug, Clone)]
struct Seen {
    origin: Origin,
    step: usize,
    says: String,
}

/// The merged scenarios, ready to be coloured.
#[derive(Debug, Clone)]
pub struct ScenarioTree {
    /// The distinct input vectors of the scenarios, indexed by [`InputVec`].
    pub input_vectors: Vec<Vec<bool>>,
    /// The nodes, indexed by [`NodeId`]; node 0 is the root (initial outputs).
    pub(crate) nodes: Vec<Node>,
    /// For every node, the first scenario and step that reached it (`step` 0 = the root).
    pub(crate) witness: Vec<(usize, usize)>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Edge {
    Passive,
    Active(NodeId),
}

impl ScenarioTree {
    /// A tree (or trace graph) of the root alone, which holds the initial outputs.
    pub(crate) fn root_only(initial_outputs: &[bool]) -> ScenarioTree {
        ScenarioTree {
            input_vectors: Vec::new(),
            nodes: vec![Node {
                outputs: initial_outputs.to_vec(),
                parent: None,
                children: Vec::new(),
                passive: Vec::new(),
            }],
            witness: vec![(0, 0)],
        }
    }

    /// Builds the tree, failing on contradictory scenarios.
    pub fn build(set: &ScenarioSet) -> Result<ScenarioTree, ScenarioError> {
        let mut tree = ScenarioTree::root_only(&set.initial_outputs);
        let mut interned: HashMap<Vec<bool>, InputVec> = HashMap::new();
        let mut edges: HashMap<(NodeId, InputVec), (Edge, Seen)> = HashMap::new();
        for (si, sc) in set.scenarios.iter().enumerate() {
            let mut node = NodeId(0);
            for (k, step) in sc.steps.iter().enumerate() {
                let next_id = InputVec(interned.len());
                let u = *interned.entry(step.inputs.clone()).or_insert_with(|| {
                    tree.input_vectors.push(step.inputs.clone());
                    next_id
                });
                let seen = || Seen {
                    origin: sc.origin.clone(),
                    step: k + 1,
                    says: step.describe(),
                };
                match (edges.get(&(node, u)), &step.outputs) {
                    (None, None) => {
                        tree.nodes[node.0].passive.push(u);
                        edges.insert((node, u), (Edge::Passive, seen()));
                    }
                    (None, Some(out)) => {
                        let child = NodeId(tree.nodes.len());
                        tree.nodes.push(Node {
                            outputs: out.clone(),
                            parent: Some((node, u)),
                            children: Vec::new(),
                            passive: Vec::new(),
                        });
                        tree.witness.push((si, k + 1));
                        tree.nodes[node.0].children.push((u, child));
                        edges.insert((node, u), (Edge::Active(child), seen()));
                        node = child;
                    }
                    (Some((Edge::Passive, _)), None) => {}
                    (Some((Edge::Active(child), _)), Some(out))
                        if tree.nodes[child.0].outputs == *out =>
                    {
                        node = *child;
                    }
                    (Some((_, first)), _) => {
                        return Err(ScenarioError::Contradiction(Box::new(
                            super::Contradiction {
                                first: first.origin.clone(),
                                first_step: first.step,
                                first_says: first.says.clone(),
                                second: sc.origin.clone(),
                                second_step: k + 1,
                                second_says: step.describe(),
                            },
                        )))
                    }
                }
            }
        }
        Ok(tree)
    }

    /// The root node, which holds the initial outputs.
    pub(crate) fn root(&self) -> NodeId {
        NodeId(0)
    }

    #[cfg(test)]
    /// Number of active edges (nodes other than the root).
    pub(crate) fn active_edges(&self) -> usize {
        self.nodes.len() - 1
    }

    /// Total number of passive marks.
    pub(crate) fn passive_marks(&self) -> usize {
        self.nodes.iter().map(|n| n.passive.len()).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::super::fbsat;
    use super::*;
    use std::path::Path;

    fn tree(text: &str) -> Result<ScenarioTree, ScenarioError> {
        ScenarioTree::build(&fbsat::parse(Path::new("s.txt"), text, None, None).unwrap())
    }

    #[test]
    fn shared_prefixes_merge_and_passive_steps_collapse() {
        let t = tree(
            "2\nin=REQ[0]; in=REQ[1]; out=CNF[1]; in=REQ[0]; out=CNF[0];\n\
             in=REQ[1]; out=CNF[1]; in=REQ[1];\n",
        )
        .unwrap();
        // root -1-> a -0-> b ; passive 0 at root, passive 1 at a
        assert_eq!(t.nodes.len(), 3);
        assert_eq!(t.input_vectors, vec![vec![false], vec![true]]);
        assert_eq!(t.nodes[0].passive, vec![InputVec(0)]);
        assert_eq!(t.nodes[1].passive, vec![InputVec(1)]);
        assert_eq!(t.nodes[2].parent, Some((NodeId(1), InputVec(0))));
        assert_eq!(t.active_edges(), 2);
    }

    #[test]
    fn contradiction_names_both_places() {
        let e = tree("2\nin=REQ[0]; in=REQ[1]; out=CNF[1];\nin=REQ[1]; out=CNF[0];\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "contradictory scenarios: s.txt:2 step 2 answers inputs 1 with CNF[1], \
             but s.txt:3 step 1 answers inputs 1 with CNF[0] after the same input history"
        );
        let e = tree("2\nin=REQ[1]; out=CNF[1];\nin=REQ[1];\n").unwrap_err();
        assert!(
            e.to_string().contains("s.txt:3 step 1 ignores inputs 1"),
            "{e}"
        );
    }
}
