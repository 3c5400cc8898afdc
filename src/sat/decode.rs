//! Reading a satisfying assignment back as an ECC *structure*: the colouring, the transition
//! function on observed inputs, and the algorithms. Guards are made from it in [`super::guards`].

use super::solver::Model;
use super::vars::CubeVars;
use super::vars::{GuardModel, Vars};
use crate::ecc::{Algorithm, AlgorithmKind, Guard, InputId, StateId, Transition, Tri};
use crate::scenario::negative::NegativeScenario;
use crate::scenario::tree::{InputVec, NodeId, ScenarioTree};

/// The machine found by the solver, before guards are minimized.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Structure {
    /// Input vectors, indexed like `delta`'s second axis.
    pub(crate) alphabet: Vec<Vec<bool>>,
    /// Number of states.
    pub(crate) c: usize,
    /// Colour (state) of every tree node.
    pub(crate) colors: Vec<usize>,
    /// `delta[q][u]`: target of state `q` on input `u`, `None` if nothing fires (or unobserved).
    pub(crate) delta: Vec<Vec<Option<usize>>>,
    /// `algorithms[q]`: the output algorithm of state `q`.
    pub(crate) algorithms: Vec<Algorithm>,
    /// `care_inputs[q]`: alphabet inputs on which negative scenarios need state `q` to behave
    /// exactly as the solver chose (beyond what the scenario tree fixes).
    pub(crate) care_inputs: Vec<Vec<usize>>,
    /// Cube-guard model: every state's transitions in priority order, exactly as encoded.
    pub(crate) cube_transitions: Option<Vec<Vec<Transition>>>,
}

/// A negative scenario with the alphabet index of every step's inputs.
pub(crate) type IndexedNegative<'a> = (&'a NegativeScenario, &'a [InputVec]);

/// Runs the solver's machine along a negative scenario until it leaves it, marking every
/// transition input and algorithm entry it uses.
fn mark_negative(
    model: &Model,
    v: &Vars,
    delta: &[Vec<Option<usize>>],
    neg: &NegativeScenario,
    ids: &[InputVec],
    seen: &mut [Vec<[bool; 2]>],
    care_inputs: &mut [Vec<usize>],
) {
    let n = neg.steps.len();
    let horizon = match neg.loop_start {
        Some(p) if p < n => p + (n - p) * v.c_max,
        Some(_) => return,
        None => n,
    };
    let mut q = 0;
    for t in 0..horizon {
        let i = match neg.loop_start {
            Some(p) if t >= n => p + (t - p) % (n - p),
            _ => t,
        };
        let (u, step) = (ids[i].0, &neg.steps[i]);
        if !care_inputs[q].contains(&u) {
            care_inputs[q].push(u);
        }
        let after: Vec<bool> = match delta[q][u] {
            Some(q2) => {
                let out = step
                    .before
                    .iter()
                    .enumerate()
                    .map(|(z, &old)| {
                        seen[q2][z][usize::from(old)] = true;
                        model.value(v.a(q2, z, old))
                    })
                    .collect();
                q = q2;
                out
            }
            None => step.before.clone(),
        };
        if after != step.after {
            return;
        }
    }
}

/// The transition in slot `k` of state `q` of machine `m` (an enabled slot), its inputs renamed
/// by `id` (e.g. into a module's own numbering).
pub(crate) fn cube_transition(
    model: &Model,
    cv: &CubeVars,
    m: usize,
    q: usize,
    k: usize,
    id: impl Fn(usize) -> InputId,
) -> Transition {
    let target = (0..cv.c_max)
        .find(|&t| model.value(cv.tgt(m, q, k, t)))
        .expect("an enabled slot has a target");
    let lits: Vec<(InputId, bool)> = cv
        .cube(model, m, q, k)
        .into_iter()
        .map(|(x, b)| (id(x), b))
        .collect();
    Transition {
        target: StateId(target),
        guard: Guard::cube(&lits),
    }
}

/// The algorithm with entries `a0`, `a1` (per output: the new value when it was 0, 1) in the
/// form `kind`. Every encoding excludes "flip" (`a0 = 1, a1 = 0`) for tri algorithms.
pub(crate) fn algorithm(kind: AlgorithmKind, a0: Vec<bool>, a1: Vec<bool>) -> Algorithm {
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
}

impl Structure {
    /// Decodes a model. Algorithm entries the scenarios never exercise are free; see `bit`
    /// below for the choice made (any choice is as consistent with the scenarios).
    ///
    /// `alphabet` holds every input vector of the encoding (tree inputs first). The solver's
    /// machine leaves every negative scenario at some step; the decoded machine must do the
    /// same, so the transitions and algorithm entries that the solver's machine uses along each
    /// negative scenario, up to and including the step where it leaves, are kept as chosen.
    /// With `closed_loop` (environments encoded, [`super::closed_loop`]) every entry is kept as
    /// chosen: the closed-loop runs the solver checked may use any of them.
    pub(crate) fn decode(
        model: &Model,
        v: &Vars,
        tree: &ScenarioTree,
        kind: AlgorithmKind,
        alphabet: &[Vec<bool>],
        negatives: &[IndexedNegative],
        closed_loop: bool,
    ) -> Structure {
        let c = (0..v.c_max).filter(|&q| model.value(v.used(q))).count();
        let colors: Vec<usize> = (0..tree.nodes.len())
            .map(|n| {
                (0..v.c_max)
                    .find(|&q| model.value(v.color(NodeId(n), q)))
                    .expect("ALO on colours")
            })
            .collect();
        let delta: Vec<Vec<Option<usize>>> = (0..c)
            .map(|q| {
                (0..alphabet.len())
                    .map(|u| (0..c).find(|&t| model.value(v.y(q, InputVec(u), t))))
                    .collect()
            })
            .collect();
        // seen[q][z][old]: entering q with output z at value old happens in some scenario,
        // or along a negative scenario before the solver's machine leaves it.
        let mut seen = vec![vec![[false; 2]; v.outputs]; c];
        let mut care_inputs = vec![Vec::new(); c];
        for &(neg, ids) in negatives {
            mark_negative(model, v, &delta, neg, ids, &mut seen, &mut care_inputs);
        }
        for (w, node) in tree.nodes.iter().enumerate() {
            if let Some((p, _)) = node.parent {
                for z in 0..v.outputs {
                    seen[colors[w]][z][usize::from(tree.nodes[p.0].outputs[z])] = true;
                }
            }
        }
        let algorithms = (0..c)
            .map(|q| state_algorithm(model, v, kind, q, &seen[q], closed_loop))
            .collect();
        let cube_transitions = match &v.guards {
            GuardModel::TreeExact => None,
            GuardModel::Cubes(cv) => Some((0..c).map(|q| cube_transitions(model, cv, q)).collect()),
        };
        Structure {
            cube_transitions,
            care_inputs,
            alphabet: alphabet.to_vec(),
            c,
            colors,
            delta,
            algorithms,
        }
    }

    /// Distinct targets of state `q`, in order of the smallest input leading to them.
    pub(crate) fn targets(&self, q: usize) -> Vec<usize> {
        let mut out = Vec::new();
        for t in self.delta[q].iter().flatten() {
            if !out.contains(t) {
                out.push(*t);
            }
        }
        out
    }

    /// Transitions of state `q`: slots in the cube model, distinct targets otherwise.
    fn out_degree(&self, q: usize) -> usize {
        match &self.cube_transitions {
            Some(ts) => ts[q].len(),
            None => self.targets(q).len(),
        }
    }

    /// Number of transitions.
    pub(crate) fn transition_count(&self) -> usize {
        (0..self.c).map(|q| self.out_degree(q)).sum()
    }

    /// Largest out-degree.
    pub(crate) fn max_out_degree(&self) -> usize {
        (0..self.c).map(|q| self.out_degree(q)).max().unwrap_or(0)
    }

    /// Total guard literals (cube model).
    pub(crate) fn literal_count(&self) -> usize {
        self.cube_transitions
            .iter()
            .flatten()
            .flatten()
            .map(|t| t.guard.literal_count())
            .sum()
    }
}

/// The output algorithm of state `q`. An entry the scenarios exercise (`seen`) comes from the
/// model. An entry they do not: if the other old value was seen, the output is set to what was
/// seen there (the state determines the output, as a Moore machine's would; "keep" would carry
/// stale commands into situations nobody recorded); if neither was seen, the output is kept.
/// With `closed_loop` every entry comes from the model.
fn state_algorithm(
    model: &Model,
    v: &Vars,
    kind: AlgorithmKind,
    q: usize,
    seen: &[[bool; 2]],
    closed_loop: bool,
) -> Algorithm {
    let bit = |z: usize, old: bool| {
        let (this, other) = (usize::from(old), usize::from(!old));
        if seen[z][this] || closed_loop {
            model.value(v.a(q, z, old))
        } else if seen[z][other] {
            model.value(v.a(q, z, !old))
        } else {
            old
        }
    };
    let a0: Vec<bool> = (0..v.outputs).map(|z| bit(z, false)).collect();
    let a1: Vec<bool> = (0..v.outputs).map(|z| bit(z, true)).collect();
    algorithm(kind, a0, a1)
}

/// The enabled transitions of state `q` in the cube model, in priority order.
fn cube_transitions(model: &Model, cv: &CubeVars, q: usize) -> Vec<Transition> {
    (0..cv.max_out_degree)
        .filter(|&k| model.value(cv.en(0, q, k)))
        .map(|k| cube_transition(model, cv, 0, q, k, InputId))
        .collect()
}
