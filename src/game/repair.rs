//! A small machine that wins the solved game: the recordings' own machine, repaired where the
//! closed loop shows it wrong.
//!
//! In: a winning [`Strategy`] and a machine that reproduces the recordings (the least one SAT
//! finds for them alone). Out: a machine that answers the recordings exactly as the base does
//! and wins the game: every closed-loop run stays in winning positions and meets every
//! recurring goal again and again ([`repair`]), or why it could not be made so.
//!
//! The closed loop of a machine and the game is explored explicitly: a node is `(q, c)`, the
//! machine's state and the game's position (which holds the outputs). Two kinds of defect:
//! a step into a position the game does not win (a safety property can be broken from there),
//! and a cycle of the closed loop that never meets some goal `j` (the environment can keep the
//! run there forever). A cycle is cut where its step does not lower `j`'s attractor layer, the
//! one nearest the goal first. Each round fixes one defect by overriding the machine's answer
//! to one input vector in one state, cheapest first: stay (a self-loop); else enter an existing
//! state whose algorithm gives a good move (fewest changed outputs); else a new state whose
//! algorithm is the strategy's move. An answer the recordings use is never changed.
//!
//! The repaired machine is a guide, not the result: its overrides are whole input vectors. The
//! pipeline records it along every node of the closed loop ([`covering_runs`]) and lets SAT find
//! the least machine for the recordings and those runs; NuSMV judges both.

use super::{bits, Strategy, NONE};
use crate::ecc::{Algorithm, Ecc, Guard, InputId, State, StateId, Transition, Tri};
use crate::scenario::tree::{InputVec, ScenarioTree};
use crate::scenario::{Origin, Scenario, Step};
use rustc_hash::{FxHashMap, FxHashSet};
use std::collections::VecDeque;

/// Why a machine could not be repaired.
#[derive(Debug, thiserror::Error)]
pub(crate) enum RepairError {
    /// The base machine does not fit the game (another algorithm form, other interface).
    #[error("the machine does not fit the game: {0}")]
    Unfit(String),
    /// A defect whose every culprit is an answer the recordings fix.
    #[error("a {0} the recordings themselves lead to (their answers are kept)")]
    Recorded(&'static str),
    /// The machine does not win the game (runs through its closed loop need one that does).
    #[error("the machine does not win the game")]
    Loses,
    /// Still defects after the last round.
    #[error("still not winning after {0} rounds")]
    Rounds(usize),
}

/// A repaired machine and how it came about.
#[derive(Debug, Clone)]
pub(crate) struct Repaired {
    /// The machine: the base's states and transitions, with the overrides first in each state.
    pub(crate) ecc: Ecc,
    /// Defects fixed (one per round).
    pub(crate) rounds: usize,
}

/// An output algorithm as bit masks: outputs in `set` take their bit of `values`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Masks {
    set: u64,
    values: u64,
}

impl Masks {
    fn apply(self, o: u64) -> u64 {
        (o & !self.set) | (self.values & self.set)
    }
}

/// A machine as the repair sees it: the base's transitions, overridden per (state, inputs).
struct Table<'e> {
    base: &'e Ecc,
    algorithms: Vec<Masks>,
    overrides: FxHashMap<(u32, u64), u32>,
    /// The base's answer per (state, inputs): the target, or `NONE` when nothing fires.
    memo: FxHashMap<(u32, u64), u32>,
    n_inputs: usize,
}

impl<'e> Table<'e> {
    fn of(base: &'e Ecc) -> Result<Table<'e>, RepairError> {
        if base.inputs.len() > 64 || base.outputs.len() > 64 {
            return Err(RepairError::Unfit("more than 64 inputs or outputs".into()));
        }
        let algorithms = (base.states.iter())
            .map(|s| match &s.algorithm {
                Algorithm::Tri(t) => {
                    let mut m = Masks { set: 0, values: 0 };
                    for (z, v) in t.iter().enumerate() {
                        match v {
                            Tri::Zero => m.set |= 1 << z,
                            Tri::One => {
                                m.set |= 1 << z;
                                m.values |= 1 << z;
                            }
                            Tri::Keep => {}
                        }
                    }
                    Ok(m)
                }
                Algorithm::Binary { .. } => {
                    Err(RepairError::Unfit("binary output algorithms".into()))
                }
            })
            .collect::<Result<_, _>>()?;
        Ok(Table {
            base,
            algorithms,
            overrides: FxHashMap::default(),
            memo: FxHashMap::default(),
            n_inputs: base.inputs.len(),
        })
    }

    /// The state entered on inputs `x` in state `q`, or `NONE` when nothing fires.
    fn target(&mut self, q: u32, x: u64) -> u32 {
        if let Some(&t) = self.overrides.get(&(q, x)) {
            return t;
        }
        if q as usize >= self.base.states.len() {
            return NONE;
        }
        let n = self.n_inputs;
        let base = self.base;
        *self.memo.entry((q, x)).or_insert_with(|| {
            let v: Vec<bool> = (0..n).map(|i| x >> i & 1 == 1).collect();
            (base.states[q as usize].fired(&v)).map_or(NONE, |t| t.target.0 as u32)
        })
    }

    /// One step: the next state and outputs.
    fn step(&mut self, q: u32, x: u64, o: u64) -> (u32, u64) {
        match self.target(q, x) {
            NONE => (q, o),
            t => (t, self.algorithms[t as usize].apply(o)),
        }
    }

    fn to_ecc(&self) -> Ecc {
        let mut ecc = self.base.clone();
        for (k, m) in self.algorithms.iter().enumerate().skip(ecc.states.len()) {
            let tri = (0..ecc.outputs.len())
                .map(|z| match (m.set >> z & 1, m.values >> z & 1) {
                    (0, _) => Tri::Keep,
                    (_, 0) => Tri::Zero,
                    _ => Tri::One,
                })
                .collect();
            ecc.states.push(State {
                name: format!("s{k}"),
                algorithm: Algorithm::Tri(tri),
                transitions: Vec::new(),
            });
        }
        let mut overrides: Vec<(&(u32, u64), &u32)> = self.overrides.iter().collect();
        overrides.sort();
        for (&(q, x), &t) in overrides.into_iter().rev() {
            let lits: Vec<(InputId, bool)> = (0..self.n_inputs)
                .map(|i| (InputId(i), x >> i & 1 == 1))
                .collect();
            ecc.states[q as usize].transitions.insert(
                0,
                Transition {
                    target: StateId(t as usize),
                    guard: Guard::cube(&lits),
                },
            );
        }
        ecc
    }
}

/// The closed loop of a machine with the game, explored breadth first.
struct Product {
    nodes: Vec<(u32, u32)>,
    /// The node each was first reached from (`NONE` for the initial ones).
    parent: Vec<u32>,
    /// Per node: the next nodes with the goals met on the way.
    edges: Vec<Vec<(u32, u64)>>,
}

impl Strategy {
    fn goal_met(&self, goals: u64, j: usize) -> bool {
        self.goal_count == 0 || goals >> j & 1 == 1
    }

    /// Whether move `m` at position `c` only enters winning positions.
    fn safe_move(&self, c: u32, m: usize) -> bool {
        let e = self.arena.expanded[c as usize].as_ref().expect("winning");
        let k = e.out.len();
        (e.succ[m * k..(m + 1) * k].iter()).all(|&s| self.winning[s as usize])
    }

    /// Whether move `m` at position `c` is safe and brings goal `j` nearer on every outcome.
    fn progress_move(&self, c: u32, m: usize, j: usize) -> bool {
        let e = self.arena.expanded[c as usize].as_ref().expect("winning");
        let k = e.out.len();
        let lc = self.layers[j][c as usize];
        (e.succ[m * k..(m + 1) * k].iter().zip(&e.out)).all(|(&s, &(_, g))| {
            self.winning[s as usize] && (self.goal_met(g, j) || self.layers[j][s as usize] < lc)
        })
    }
}

/// The closed loop of `table` with the game, or its first node (machine state, position)
/// whose step may enter a position the game does not win.
fn explore(s: &Strategy, table: &mut Table) -> Result<Product, (u32, u32)> {
    let a = &s.arena;
    let mut p = Product {
        nodes: Vec::new(),
        parent: Vec::new(),
        edges: Vec::new(),
    };
    let mut index: FxHashMap<(u32, u32), u32> = FxHashMap::default();
    let mut queue = VecDeque::new();
    for &c in &s.initial {
        if index.insert((0, c), p.nodes.len() as u32).is_none() {
            p.nodes.push((0, c));
            p.parent.push(NONE);
            queue.push_back(p.nodes.len() as u32 - 1);
        }
    }
    while let Some(u) = queue.pop_front() {
        let (q, c) = p.nodes[u as usize];
        let e = a.expanded[c as usize]
            .as_ref()
            .expect("only winning positions are entered");
        let o = a.nodes[c as usize].1;
        let (q2, o2) = table.step(q, e.obs, o);
        let Some(m) = (e.moves.iter().position(|&mv| mv == o2)).filter(|&m| s.safe_move(c, m))
        else {
            return Err((q, c));
        };
        let k = e.out.len();
        let mut edges = Vec::with_capacity(k);
        for (&c2, &(_, g)) in e.succ[m * k..(m + 1) * k].iter().zip(&e.out) {
            let v = *index.entry((q2, c2)).or_insert_with(|| {
                p.nodes.push((q2, c2));
                p.parent.push(u);
                queue.push_back(p.nodes.len() as u32 - 1);
                p.nodes.len() as u32 - 1
            });
            edges.push((v, g));
        }
        p.edges.push(edges);
    }
    Ok(p)
}

/// Strongly connected components (Tarjan, without recursion): per node its component.
pub(super) fn components(adj: &[Vec<u32>]) -> Vec<u32> {
    let n = adj.len();
    let (mut index, mut low) = (vec![NONE; n], vec![0u32; n]);
    let mut on_stack = vec![false; n];
    let mut comp = vec![NONE; n];
    let (mut stack, mut calls): (Vec<u32>, Vec<(u32, usize)>) = (Vec::new(), Vec::new());
    let (mut next, mut count) = (0u32, 0u32);
    for root in 0..n as u32 {
        if index[root as usize] != NONE {
            continue;
        }
        // The node to enter next: the root, then each unvisited successor, in one place.
        let mut enter = Some(root);
        loop {
            if let Some(w) = enter.take() {
                index[w as usize] = next;
                low[w as usize] = next;
                next += 1;
                stack.push(w);
                on_stack[w as usize] = true;
                calls.push((w, 0));
            }
            let Some(&(v, i)) = calls.last() else { break };
            let vu = v as usize;
            if let Some(&w) = adj[vu].get(i) {
                calls.last_mut().expect("not empty").1 += 1;
                if index[w as usize] == NONE {
                    enter = Some(w);
                } else if on_stack[w as usize] {
                    low[vu] = low[vu].min(index[w as usize]);
                }
                continue;
            }
            calls.pop();
            if let Some(&(parent, _)) = calls.last() {
                low[parent as usize] = low[parent as usize].min(low[vu]);
            }
            if low[vu] == index[vu] {
                loop {
                    let w = stack.pop().expect("v is on the stack");
                    on_stack[w as usize] = false;
                    comp[w as usize] = count;
                    if w == v {
                        break;
                    }
                }
                count += 1;
            }
        }
    }
    comp
}

/// The first cycle that never meets a goal `j`: the node to change (nearest the goal first)
/// and `j`.
fn starving(
    s: &Strategy,
    p: &Product,
    locked: &dyn Fn(u32) -> bool,
) -> Option<Result<(u32, usize), RepairError>> {
    for j in 0..s.goals {
        let adj: Vec<Vec<u32>> = (p.edges.iter())
            .map(|es| {
                (es.iter())
                    .filter(|&&(_, g)| !s.goal_met(g, j))
                    .map(|&(v, _)| v)
                    .collect()
            })
            .collect();
        let comp = components(&adj);
        let layer = |u: u32| s.layers[j][p.nodes[u as usize].1 as usize];
        let mut found = false;
        let mut best: Option<(u32, u32)> = None;
        for (u, vs) in adj.iter().enumerate() {
            let u = u as u32;
            // An edge inside a component lies on a cycle that avoids the goal; along it the
            // layers cannot fall at every step.
            let culprit =
                (vs.iter()).any(|&v| comp[v as usize] == comp[u as usize] && layer(v) >= layer(u));
            if culprit {
                found = true;
                if !locked(u) && best.is_none_or(|(l, _)| layer(u) < l) {
                    best = Some((layer(u), u));
                }
            }
        }
        match best {
            Some((_, u)) => return Some(Ok((u, j))),
            None if found => return Some(Err(RepairError::Recorded("cycle missing a goal"))),
            None => {}
        }
    }
    None
}

/// The (state, inputs) answers the recordings use, by replaying them on the base machine.
fn recorded_entries(s: &Strategy, base: &Ecc) -> FxHashSet<(u32, u64)> {
    let tree = &s.arena.tree;
    let mut locked = FxHashSet::default();
    // The tree holds every recorded step; its nodes are reached by the base in one state each.
    let mut stack = vec![(0usize, 0u32, bits(&base.initial_outputs))];
    let mut table = Table::of(base).expect("checked by the caller");
    while let Some((node, q, o)) = stack.pop() {
        let n = &tree.nodes[node];
        for &u in &n.passive {
            locked.insert((q, bits(&tree.input_vectors[u.0])));
        }
        for &(u, child) in &n.children {
            let x = bits(&tree.input_vectors[u.0]);
            locked.insert((q, x));
            let (q2, o2) = table.step(q, x, o);
            stack.push((child.0, q2, o2));
        }
    }
    locked
}

/// Repairs `base` (a machine that reproduces the recordings of the game) until it wins the
/// game, in at most `max_rounds` fixes.
pub(crate) fn repair(s: &Strategy, base: &Ecc, max_rounds: usize) -> Result<Repaired, RepairError> {
    if bits(&base.initial_outputs) != bits(&s.initial_outputs)
        || base.initial_outputs.len() != s.initial_outputs.len()
    {
        return Err(RepairError::Unfit("other initial outputs".into()));
    }
    let mut table = Table::of(base)?;
    let locked = recorded_entries(s, base);
    for round in 0..=max_rounds {
        let Some(defect) = defect(s, &mut table, &locked)? else {
            return Ok(Repaired {
                ecc: table.to_ecc(),
                rounds: round,
            });
        };
        if round == max_rounds {
            break;
        }
        let (q, c, _) = defect;
        let obs = s.arena.expanded[c as usize].as_ref().expect("winning").obs;
        if locked.contains(&(q, obs)) {
            return Err(RepairError::Recorded("step into a losing position"));
        }
        let target = fix(s, &mut table, defect);
        table.overrides.insert((q, obs), target);
    }
    Err(RepairError::Rounds(max_rounds))
}

/// The machine's next defect in the game: `(state, position, goal)` where its move steps
/// into a losing position (no goal), or where it starves goal `j` (`Some(j)`); `None` when it
/// wins. Starving through entries the recordings fix is a [`RepairError`].
fn defect(
    s: &Strategy,
    table: &mut Table,
    locked: &FxHashSet<(u32, u64)>,
) -> Result<Option<(u32, u32, Option<usize>)>, RepairError> {
    let a = &s.arena;
    let p = match explore(s, table) {
        Err((q, c)) => return Ok(Some((q, c, None))),
        Ok(p) => p,
    };
    let entry = |u: u32| {
        let (q, c) = p.nodes[u as usize];
        locked.contains(&(q, a.expanded[c as usize].as_ref().expect("winning").obs))
    };
    match starving(s, &p, &entry) {
        None => Ok(None),
        Some(Err(e)) => Err(e),
        Some(Ok((u, j))) => {
            let (q, c) = p.nodes[u as usize];
            Ok(Some((q, c, Some(j))))
        }
    }
}

/// The state the machine should enter instead at `defect`: cheapest first, the same state,
/// then an existing one (fewest outputs changed) whose move is safe (or makes progress toward
/// the starved goal), else a new state with the strategy's move.
fn fix(s: &Strategy, table: &mut Table, (q, c, goal): (u32, u32, Option<usize>)) -> u32 {
    let a = &s.arena;
    let e = a.expanded[c as usize].as_ref().expect("winning");
    let good = |m: usize| match goal {
        Some(j) => s.progress_move(c, m, j),
        None => s.safe_move(c, m),
    };
    let o = a.nodes[c as usize].1;
    let existing = (0..table.algorithms.len() as u32)
        .filter_map(|t| {
            let o2 = table.algorithms[t as usize].apply(o);
            let m = e.moves.iter().position(|&mv| mv == o2)?;
            good(m).then_some(((t != q, (o2 ^ o).count_ones(), t), t))
        })
        .min();
    if let Some((_, t)) = existing {
        return t;
    }
    let row = |j: usize| s.choice[c as usize * s.goals + j];
    let m = match row(goal.unwrap_or(0)) {
        NONE => (0..s.goals)
            .map(row)
            .find(|&m| m != NONE)
            .expect("a winning position has a move"),
        m => m,
    };
    let all = match table.base.outputs.len() {
        64 => u64::MAX,
        n => (1u64 << n) - 1,
    };
    table.algorithms.push(Masks {
        set: all,
        values: e.moves[m as usize],
    });
    table.algorithms.len() as u32 - 1
}

/// The recordings' tree as a machine: a state per node, entered with the node's outputs, a
/// transition per recorded active step, guarded by its whole input vector. It answers every
/// recording as recorded and merges no two histories, so a repair that the least machine's
/// merges block (a defect whose culprit is an answer the recordings fix in a shared state)
/// can start from it. `like` gives the interface and initial outputs.
pub(crate) fn tree_machine(tree: &ScenarioTree, like: &Ecc) -> Ecc {
    let states = (tree.nodes.iter().enumerate())
        .map(|(v, node)| State {
            name: format!("s{v}"),
            algorithm: Algorithm::Tri(
                (node.outputs.iter())
                    .map(|&b| if b { Tri::One } else { Tri::Zero })
                    .collect(),
            ),
            transitions: (node.children.iter())
                .map(|&(u, child)| Transition {
                    target: StateId(child.0),
                    guard: Guard::cube(&whole_vector(tree, u)),
                })
                .collect(),
        })
        .collect();
    Ecc {
        inputs: like.inputs.clone(),
        outputs: like.outputs.clone(),
        initial_outputs: like.initial_outputs.clone(),
        states,
    }
}

/// `base` (a machine that reproduces the recordings of `tree`) with every guard narrowed to
/// the input vectors the recordings fire it on, each a whole cube; transitions they never
/// fire go. It answers every recording as `base` does, and in every pair of state and input
/// vector they do not show it stays: the repair then decides there from the game alone, where
/// `base` would carry its guards' generalizations (chosen by SAT for fewest literals, not for
/// the plant) into the closed loop.
pub(crate) fn narrowed(tree: &ScenarioTree, base: &Ecc) -> Ecc {
    let mut fired: Vec<Vec<Vec<InputVec>>> = (base.states.iter())
        .map(|s| vec![Vec::new(); s.transitions.len()])
        .collect();
    let mut stack = vec![(0usize, 0usize)];
    while let Some((node, q)) = stack.pop() {
        for &(u, child) in &tree.nodes[node].children {
            let x = &tree.input_vectors[u.0];
            let t = (base.states[q].transitions.iter())
                .position(|t| t.guard.eval(x))
                .expect("the base reproduces the recordings");
            if !fired[q][t].contains(&u) {
                fired[q][t].push(u);
            }
            stack.push((child.0, base.states[q].transitions[t].target.0));
        }
    }
    let mut e = base.clone();
    for (st, fired) in e.states.iter_mut().zip(fired) {
        let guards = fired.into_iter().map(|us| {
            let cubes: Vec<Vec<(InputId, bool)>> =
                (us.into_iter()).map(|u| whole_vector(tree, u)).collect();
            Guard::dnf(&cubes)
        });
        for (t, g) in st.transitions.iter_mut().zip(guards) {
            t.guard = g;
        }
        st.transitions.retain(|t| t.guard != Guard::False);
    }
    e
}

/// The recorded input vector `u` of `tree` as the literals of a cube that holds on it alone.
fn whole_vector(tree: &ScenarioTree, u: InputVec) -> Vec<(InputId, bool)> {
    (tree.input_vectors[u.0].iter().enumerate())
        .map(|(i, &b)| (InputId(i), b))
        .collect()
}

/// Whether `ecc` wins the game: every closed-loop run stays in winning positions and meets
/// every goal again and again (in the game's model of the plant; NuSMV has the last word).
pub(crate) fn wins(s: &Strategy, ecc: &Ecc) -> Result<bool, RepairError> {
    let mut table = Table::of(ecc)?;
    Ok(match explore(s, &mut table) {
        Err(_) => false,
        Ok(p) => starving(s, &p, &|_| false).is_none(),
    })
}

/// Runs of `ecc` in closed loop with the game that together pass every node of the closed loop
/// (one per leaf of its breadth-first tree), as scenarios with the machine's answers.
pub(crate) fn covering_runs(s: &Strategy, ecc: &Ecc) -> Result<Vec<Scenario>, RepairError> {
    let mut table = Table::of(ecc)?;
    let p = explore(s, &mut table).map_err(|_| RepairError::Loses)?;
    let mut is_parent = vec![false; p.nodes.len()];
    for &u in &p.parent {
        if u != NONE {
            is_parent[u as usize] = true;
        }
    }
    let a = &s.arena;
    let n = ecc.inputs.len();
    let mut runs = Vec::new();
    for leaf in (0..p.nodes.len()).filter(|&u| !is_parent[u]) {
        let mut path = vec![leaf as u32];
        while let Some(&u) = path.last().filter(|&&u| p.parent[u as usize] != NONE) {
            path.push(p.parent[u as usize]);
        }
        path.reverse();
        let mut run = crate::ecc::Run::new(ecc);
        let steps = (path.iter())
            .map(|&u| {
                let c = p.nodes[u as usize].1;
                let x = a.expanded[c as usize].as_ref().expect("winning").obs;
                let inputs: Vec<bool> = (0..n).map(|i| x >> i & 1 == 1).collect();
                let outputs = run.step(&inputs).map(|_| run.outputs.clone());
                Step { inputs, outputs }
            })
            .collect();
        runs.push(Scenario {
            origin: Origin {
                file: "closed-loop game".into(),
                line: runs.len() + 1,
                rows: None,
            },
            steps,
        });
    }
    Ok(runs)
}
