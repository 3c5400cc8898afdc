//! Reading a satisfying assignment back as an ECC *structure*: the colouring, the transition
//! function on observed inputs, and the algorithms. Guards are made from it in [`super::guards`].

use super::vars::Vars;
use crate::ecc::{Algorithm, AlgorithmKind, Tri};
use crate::scenario::tree::{InputVec, NodeId, ScenarioTree};
use varisat::Lit;

/// The machine found by the solver, before guards are minimized.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Structure {
    /// Input vectors, indexed like `delta`'s second axis.
    pub alphabet: Vec<Vec<bool>>,
    /// Number of states.
    pub c: usize,
    /// Colour (state) of every tree node.
    pub colors: Vec<usize>,
    /// `delta[q][u]`: target of state `q` on input `u`, `None` if nothing fires (or unobserved).
    pub delta: Vec<Vec<Option<usize>>>,
    pub algorithms: Vec<Algorithm>,
}

/// Assignment lookup by literal.
pub struct Model(Vec<bool>);

impl Model {
    pub fn new(lits: &[Lit]) -> Model {
        let mut values = vec![false; lits.len() + 1];
        for l in lits {
            let i = l.var().index();
            if i >= values.len() {
                values.resize(i + 1, false);
            }
            values[i] = l.is_positive();
        }
        Model(values)
    }

    pub fn value(&self, l: Lit) -> bool {
        self.0.get(l.var().index()).copied().unwrap_or(false) == l.is_positive()
    }
}

impl Structure {
    /// Decodes a model. Algorithm entries the scenarios never exercise are decoded as "keep",
    /// which reads best and is as consistent with the scenarios as any other choice.
    ///
    /// `alphabet` holds every input vector of the encoding (tree inputs first); `extra[z][old]`
    /// marks algorithm entries that negative scenarios depend on, for every state.
    pub fn decode(
        model: &Model,
        v: &Vars,
        tree: &ScenarioTree,
        kind: AlgorithmKind,
        alphabet: &[Vec<bool>],
        extra: &[[bool; 2]],
    ) -> Structure {
        let c = (0..v.c_max).filter(|&q| model.value(v.used(q))).count();
        let colors: Vec<usize> = (0..tree.nodes.len())
            .map(|n| {
                (0..v.c_max)
                    .find(|&q| model.value(v.color(NodeId(n), q)))
                    .expect("ALO on colours")
            })
            .collect();
        let delta = (0..c)
            .map(|q| {
                (0..alphabet.len())
                    .map(|u| (0..c).find(|&t| model.value(v.y(q, InputVec(u), t))))
                    .collect()
            })
            .collect();
        // seen[q][z][old]: entering q with output z at value old happens in some scenario.
        let mut seen = vec![extra.to_vec(); c];
        for (w, node) in tree.nodes.iter().enumerate() {
            if let Some((p, _)) = node.parent {
                for z in 0..v.outputs {
                    seen[colors[w]][z][usize::from(tree.nodes[p.0].outputs[z])] = true;
                }
            }
        }
        let algorithms = (0..c)
            .map(|q| {
                let bit = |z: usize, old: bool| {
                    if seen[q][z][usize::from(old)] {
                        model.value(v.a(q, z, old))
                    } else {
                        old
                    }
                };
                let a0: Vec<bool> = (0..v.outputs).map(|z| bit(z, false)).collect();
                let a1: Vec<bool> = (0..v.outputs).map(|z| bit(z, true)).collect();
                match kind {
                    AlgorithmKind::Binary => Algorithm::Binary { a0, a1 },
                    AlgorithmKind::Tri => Algorithm::Tri(
                        a0.iter()
                            .zip(&a1)
                            .map(|(&x0, &x1)| match (x0, x1) {
                                (false, false) => Tri::Zero,
                                (true, true) => Tri::One,
                                (false, true) => Tri::Keep,
                                (true, false) => unreachable!("flip is excluded for tri"),
                            })
                            .collect(),
                    ),
                }
            })
            .collect();
        Structure {
            alphabet: alphabet.to_vec(),
            c,
            colors,
            delta,
            algorithms,
        }
    }

    /// Distinct targets of state `q`, in order of the smallest input leading to them.
    pub fn targets(&self, q: usize) -> Vec<usize> {
        let mut out = Vec::new();
        for t in self.delta[q].iter().flatten() {
            if !out.contains(t) {
                out.push(*t);
            }
        }
        out
    }

    /// Number of transitions (distinct `(q, q')` pairs).
    pub fn transition_count(&self) -> usize {
        (0..self.c).map(|q| self.targets(q).len()).sum()
    }

    /// Largest out-degree.
    pub fn max_out_degree(&self) -> usize {
        (0..self.c)
            .map(|q| self.targets(q).len())
            .max()
            .unwrap_or(0)
    }
}
