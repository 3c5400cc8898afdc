//! A controller from the properties themselves: the closed loop as a game between the
//! controller and the plant, solved explicitly, where the recordings leave the machine open.
//!
//! In: a plant [`Model`] with its [`Wiring`], properties in the fragment of [`Monitors`],
//! and the recordings' [`ScenarioTree`]. Out: a winning [`Strategy`] (a [`Controller`] that
//! answers every recorded step as recorded and keeps every property in closed loop with every
//! behaviour of the plant), or why there is none here ([`Outcome`]), or why the engine does not
//! apply ([`GameError::Outside`]). A strategy is large and irregular; the pipeline makes the least
//! machine that behaves like it wherever the closed loop goes, and NuSMV judges that machine.
//!
//! # The game
//! A position is `(s, o, m, τ)`: the plant's state without its free inputs (variables with
//! neither `init` nor `next`, and `IVAR`s), the controller's outputs, the monitors' memory and
//! the node of the scenario tree the run is in (or none). The controller reads its inputs on
//! `s` and chooses the next outputs `o'` (the recorded ones while the run follows a recording);
//! the environment then chooses the free inputs of this step and the plant's successor: the
//! monitors read the step, and the next position is `(s', o', m', τ')`. Choosing the free inputs
//! after the controller only strengthens the environment, so a strategy that wins this game wins
//! the real one; it does not read them, which a controller cannot. Where the next position is
//! not told apart by the controller's inputs, the engine does not apply (it checks, along the
//! strategy).
//!
//! Safety parts lose at once; the recurring goals form a generalized Büchi condition, solved
//! with the classical nested fixpoint (attractors per goal inside the greatest fixpoint). The
//! strategy pursues one goal at a time along its attractor's layers, preferring to keep its
//! outputs (a PLC's natural "nothing to do"), then the fewest changed outputs.

mod monitor;
pub(crate) mod repair;
#[cfg(test)]
mod tests;

pub(crate) use monitor::Monitors;

use crate::check::{CheckError, Wiring};
use crate::deadline::Deadline;
use crate::ecc::sim::{Controller, Reactive};
use crate::ltl::Property;
use crate::plant::explicit::Semantics;
use crate::plant::{Model, Value, VarKind};
use crate::scenario::tree::ScenarioTree;
use rustc_hash::FxHashMap;
use std::collections::VecDeque;

const NONE: u32 = u32::MAX;

/// Why the engine does not give an answer.
#[derive(Debug, thiserror::Error)]
pub(crate) enum GameError {
    /// The problem is outside what the engine solves (the property's form, a plant whose
    /// state the controller cannot know, too many positions).
    #[error("{0}")]
    Outside(String),
    /// Evaluating the plant failed.
    #[error(transparent)]
    Check(#[from] CheckError),
    /// The deadline passed before the game was solved.
    #[error("stopped at the time limit")]
    Stopped,
}

impl From<crate::plant::explicit::EvalError> for GameError {
    fn from(e: crate::plant::explicit::EvalError) -> GameError {
        GameError::Check(CheckError::Eval(e))
    }
}

/// What the game says.
pub(crate) enum Outcome {
    /// The controller wins: a strategy.
    Won(Box<Strategy>),
    /// The environment wins from an initial position: no controller of any size that answers
    /// the recordings as recorded keeps the properties against every behaviour of the plant
    /// (as far as this game's controller, which cannot see the free inputs, is concerned).
    Lost,
}

/// The plant side of a position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct Side {
    plant: u32,
    memory: u64,
    tau: u32,
}

/// A position the controller has reached and may move from.
struct Expanded {
    /// The controller's inputs here (bits).
    obs: u64,
    /// Per environment outcome: the next plant side and the goals met on the way.
    out: Vec<(u32, u64)>,
    /// The outputs the controller may choose.
    moves: Vec<u64>,
    /// Per move and outcome (`moves.len() × out.len()`): the next position.
    succ: Vec<u32>,
}

/// The explicit game.
struct Arena<'a> {
    sem: Semantics<'a>,
    coupling: &'a Wiring,
    monitors: Monitors,
    tree: &'a ScenarioTree,
    tree_inputs: FxHashMap<u64, usize>,
    free: Vec<usize>,
    combos: Vec<Vec<Value>>,
    plants: Vec<Box<[Value]>>,
    plant_index: FxHashMap<Box<[Value]>, u32>,
    /// Per plant and free-input combination: the plant-only atoms.
    plant_atoms: Vec<u64>,
    sides: Vec<Side>,
    side_index: FxHashMap<Side, u32>,
    nodes: Vec<(u32, u64)>,
    node_index: FxHashMap<(u32, u64), u32>,
    expanded: Vec<Option<Box<Expanded>>>,
    /// Per plant, free-input combination and outputs: the plant's successors.
    successors: FxHashMap<(u32, usize, u64), std::rc::Rc<[u32]>>,
    n_outputs: usize,
    max_positions: usize,
    /// Successor entries (moves × outcomes) stored so far: with many outputs each position
    /// holds thousands, and memory, not positions, is the limit.
    entries: usize,
    /// Where the exploration and the fixed point stop.
    deadline: Deadline,
}

/// Successor entries allowed per position of the limit (1 GB of them at a million positions).
const ENTRIES_PER_POSITION: usize = 256;

/// What an entry of the plant's successor cache costs, in successor entries (the key, the
/// list's header, the table's own).
const CACHE_ENTRY: usize = 12;

fn bits(v: &[bool]) -> u64 {
    v.iter()
        .enumerate()
        .fold(0, |a, (i, &b)| a | (b as u64) << i)
}

impl<'a> Arena<'a> {
    fn new(
        model: &'a Model,
        coupling: &'a Wiring,
        props: &[Property],
        tree: &'a ScenarioTree,
        max_positions: usize,
    ) -> Result<Arena<'a>, GameError> {
        let outside = |m: &str| Err(GameError::Outside(m.to_string()));
        if !model.invar.is_empty() || !model.trans.is_empty() || !model.init.is_empty() {
            return outside("the plant has INIT, INVAR or TRANS constraints");
        }
        if !model.fairness.is_empty() {
            return outside("the plant has FAIRNESS constraints");
        }
        if coupling.outputs.len() > 12 {
            return outside("more than 12 controller outputs");
        }
        if coupling.inputs.len() > 64 {
            return outside("more than 64 controller inputs");
        }
        let monitors = Monitors::of(props, model, coupling).map_err(|o| GameError::Outside(o.0))?;
        let free: Vec<usize> = (model.vars.iter().enumerate())
            .filter(|(_, v)| v.kind == VarKind::Input || (v.init.is_none() && v.next.is_none()))
            .map(|(i, _)| i)
            .collect();
        let mut combos = vec![Vec::new()];
        for &i in &free {
            combos = (combos.iter())
                .flat_map(|c| {
                    model.vars[i].domain.iter().map(move |v| {
                        let mut c = c.clone();
                        c.push(*v);
                        c
                    })
                })
                .collect();
            if combos.len() > 256 {
                return outside("more than 256 combinations of the plant's free inputs");
            }
        }
        let tree_inputs = (tree.input_vectors.iter().enumerate())
            .map(|(u, v)| (bits(v), u))
            .collect();
        Ok(Arena {
            sem: Semantics::new(model),
            coupling,
            monitors,
            tree,
            tree_inputs,
            free,
            combos,
            plants: Vec::new(),
            plant_index: FxHashMap::default(),
            plant_atoms: Vec::new(),
            sides: Vec::new(),
            side_index: FxHashMap::default(),
            nodes: Vec::new(),
            node_index: FxHashMap::default(),
            expanded: Vec::new(),
            successors: FxHashMap::default(),
            n_outputs: coupling.outputs.len(),
            max_positions,
            entries: 0,
            deadline: Deadline::NONE,
        })
    }

    fn full(&self, plant: u32, combo: usize) -> Vec<Value> {
        let mut s = self.plants[plant as usize].to_vec();
        for (k, &i) in self.free.iter().enumerate() {
            s[i] = self.combos[combo][k];
        }
        s
    }

    fn plant(&mut self, mut s: Vec<Value>) -> Result<u32, GameError> {
        for &i in &self.free {
            s[i] = self.sem.model().vars[i].domain[0];
        }
        if let Some(&p) = self.plant_index.get(s.as_slice()) {
            return Ok(p);
        }
        let p = self.plants.len() as u32;
        self.plants.push(s.clone().into());
        self.plant_index.insert(s.into(), p);
        let no_params = vec![false; self.sem.model().params.len()];
        for c in 0..self.combos.len() {
            let full = self.full(p, c);
            let v = (self.monitors.plant_atoms(&self.sem, &full, &no_params))
                .map_err(|e| atom_error(e, self.sem.model()))?;
            self.plant_atoms.push(v);
        }
        Ok(p)
    }

    fn side(&mut self, s: Side) -> u32 {
        *self.side_index.entry(s).or_insert_with(|| {
            self.sides.push(s);
            self.sides.len() as u32 - 1
        })
    }

    fn node(&mut self, side: u32, o: u64, queue: &mut VecDeque<u32>) -> Result<u32, GameError> {
        if let Some(&n) = self.node_index.get(&(side, o)) {
            return Ok(n);
        }
        if self.nodes.len() >= self.max_positions {
            return Err(GameError::Outside(format!(
                "more than {} positions of the game",
                self.max_positions
            )));
        }
        let n = self.nodes.len() as u32;
        self.nodes.push((side, o));
        self.node_index.insert((side, o), n);
        self.expanded.push(None);
        queue.push_back(n);
        Ok(n)
    }

    fn build(&mut self, initial_outputs: u64) -> Result<Vec<u32>, GameError> {
        let mut queue = VecDeque::new();
        let params = self.coupling.params(initial_outputs);
        let mut initial = Vec::new();
        for s in self.sem.initial_states(&params).map_err(CheckError::Eval)? {
            let p = self.plant(s)?;
            let side = self.side(Side {
                plant: p,
                memory: 0,
                tau: 0,
            });
            let n = self.node(side, initial_outputs, &mut queue)?;
            if !initial.contains(&n) {
                initial.push(n);
            }
        }
        let mut expanded = 0usize;
        while let Some(n) = queue.pop_front() {
            // The clock is read once per thousand positions: each takes microseconds.
            expanded += 1;
            if expanded.is_multiple_of(1024) && self.deadline.passed() {
                return Err(GameError::Stopped);
            }
            self.expand(n, &mut queue)?;
        }
        Ok(initial)
    }

    /// Position `n`'s moves and their successors; none are stored when the monitors reject
    /// the step under some free-input combination (a safety property is broken there) or the
    /// plant has no successor.
    fn expand(&mut self, n: u32, queue: &mut VecDeque<u32>) -> Result<(), GameError> {
        let (side, o) = self.nodes[n as usize];
        let Side { plant, memory, tau } = self.sides[side as usize];
        let params = self.coupling.params(o);
        let fulls: Vec<Vec<Value>> = (0..self.combos.len())
            .map(|c| self.full(plant, c))
            .collect();
        let Some((obs, steps)) = self.observe(plant, memory, o, &params, &fulls)? else {
            return Ok(());
        };
        let (recorded, tau_next) = recorded_step(self.tree, &self.tree_inputs, tau, obs);
        let forced = recorded.map(|a| a.map(|child| bits(&self.tree.nodes[child].outputs)));
        let mut out: Vec<(u32, u64)> = Vec::new();
        for (c, step) in steps.iter().enumerate() {
            for &p in self
                .plant_successors(plant, c, o, &fulls[c], &params)?
                .iter()
            {
                let side = self.side(Side {
                    plant: p,
                    memory: step.memory,
                    tau: tau_next,
                });
                // Kept apart even when they lead to the same position: the environment picks
                // the edge, and with it which goals are met.
                if !out.contains(&(side, step.goals)) {
                    out.push((side, step.goals));
                }
            }
        }
        if out.is_empty() {
            return Ok(());
        }
        let moves: Vec<u64> = match forced {
            Some(answer) => vec![answer.unwrap_or(o)],
            None => (0..1u64 << self.n_outputs).collect(),
        };
        self.entries += moves.len() * out.len();
        if self.entries > self.max_positions.saturating_mul(ENTRIES_PER_POSITION) {
            return Err(GameError::Outside(format!(
                "more than {} moves of the game (positions × outputs × plant outcomes)",
                self.max_positions.saturating_mul(ENTRIES_PER_POSITION)
            )));
        }
        let mut succ = Vec::with_capacity(moves.len() * out.len());
        for &m in &moves {
            for &(side, _) in &out {
                succ.push(self.node(side, m, queue)?);
            }
        }
        self.expanded[n as usize] = Some(Box::new(Expanded {
            obs,
            out,
            moves,
            succ,
        }));
        Ok(())
    }

    /// The controller's inputs at `plant` with outputs `o` and the monitors' step under each
    /// free-input combination (`fulls`); `None` when one of them breaks a safety monitor.
    fn observe(
        &self,
        plant: u32,
        memory: u64,
        o: u64,
        params: &[bool],
        fulls: &[Vec<Value>],
    ) -> Result<Option<(u64, Vec<monitor::Step>)>, GameError> {
        let mut obs = None;
        let mut steps = Vec::with_capacity(fulls.len());
        for (c, full) in fulls.iter().enumerate() {
            let v = self.plant_atoms[plant as usize * self.combos.len() + c]
                | (self.monitors.output_atoms(&self.sem, full, o, params))
                    .map_err(|e| atom_error(e, self.sem.model()))?;
            let step = self.monitors.step(memory, v);
            if step.bad {
                return Ok(None);
            }
            let x = bits(&self.coupling.read_inputs(&self.sem, full, params)?);
            if obs.is_some_and(|y| y != x) {
                return Err(GameError::Outside(
                    "a controller input reads a free input of the plant".into(),
                ));
            }
            obs = Some(x);
            steps.push(step);
        }
        Ok(Some((obs.expect("at least one combination"), steps)))
    }

    /// The plant states after `plant` (values `full` with free-input combination `c`) under
    /// outputs `o`, computed once per triple.
    fn plant_successors(
        &mut self,
        plant: u32,
        c: usize,
        o: u64,
        full: &[Value],
        params: &[bool],
    ) -> Result<std::rc::Rc<[u32]>, GameError> {
        let key = (plant, c, o);
        if let Some(s) = self.successors.get(&key) {
            return Ok(s.clone());
        }
        let mut ids = Vec::new();
        // One candidate successor at a time: with free inputs there are as many as their
        // combinations, all of which the plant's state forgets.
        let sem = self.sem.clone();
        sem.for_each_successor(full, params, params, &mut |s| {
            let p = self.plant(s.to_vec())?;
            if !ids.contains(&p) {
                ids.push(p);
            }
            Ok::<(), GameError>(())
        })?;
        let ids: std::rc::Rc<[u32]> = ids.into();
        // The cache counts against the same bound as the moves.
        self.entries += ids.len() + CACHE_ENTRY;
        self.successors.insert(key, ids.clone());
        Ok(ids)
    }
}

/// What the recordings say at tree node `tau` (or `NONE`) on inputs `x`: the answer
/// (`Some(None)` passive, `Some(Some(node))` active, entering `node`) and the node after; no
/// answer and `NONE` once the run has left the recordings.
fn recorded_step(
    tree: &ScenarioTree,
    tree_inputs: &FxHashMap<u64, usize>,
    tau: u32,
    x: u64,
) -> (Option<Option<usize>>, u32) {
    if tau == NONE {
        return (None, NONE);
    }
    let node = &tree.nodes[tau as usize];
    let u = tree_inputs.get(&x).copied();
    if let Some(&(_, child)) = node.children.iter().find(|(i, _)| Some(i.0) == u) {
        (Some(Some(child.0)), child.0 as u32)
    } else if node.passive.iter().any(|i| Some(i.0) == u) {
        (Some(None), tau)
    } else {
        (None, NONE)
    }
}

fn atom_error(e: crate::check::AtomError, model: &Model) -> GameError {
    match e {
        crate::check::AtomError::Eval(e) => GameError::Check(CheckError::Eval(e)),
        crate::check::AtomError::Type(m) => {
            GameError::Outside(format!("{}: {m}", model.file.display()))
        }
    }
}

/// The solved game: the winning positions and, per goal, each position's attractor layer.
struct Solution {
    winning: Vec<bool>,
    layers: Vec<Vec<u32>>,
}

impl Arena<'_> {
    fn goal_met(&self, goals: u64, j: usize) -> bool {
        self.monitors.goal_count() == 0 || goals >> j & 1 == 1
    }

    fn solve(&self) -> Result<Solution, GameError> {
        let n = self.nodes.len();
        // Who moves into whom: (position, move × outcome) per successor position.
        let mut starts = vec![0u32; n + 1];
        for e in self.expanded.iter().flatten() {
            for &s in &e.succ {
                starts[s as usize + 1] += 1;
            }
        }
        for i in 0..n {
            starts[i + 1] += starts[i];
        }
        let mut fill = starts.clone();
        let mut rev = vec![(0u32, 0u32); starts[n] as usize];
        for (c, e) in self.expanded.iter().enumerate() {
            if let Some(e) = e {
                for (mk, &s) in e.succ.iter().enumerate() {
                    rev[fill[s as usize] as usize] = (c as u32, mk as u32);
                    fill[s as usize] += 1;
                }
            }
        }
        let mut offsets = vec![0usize; n + 1];
        for (c, e) in self.expanded.iter().enumerate() {
            offsets[c + 1] = offsets[c] + e.as_ref().map_or(0, |e| e.moves.len());
        }
        let goals = self.monitors.goal_count().max(1);
        let mut winning: Vec<bool> = self.expanded.iter().map(Option::is_some).collect();
        loop {
            if self.deadline.passed() {
                return Err(GameError::Stopped);
            }
            let layers: Vec<Vec<u32>> = (0..goals)
                .map(|j| self.attractor(j, &winning, &starts, &rev, &offsets))
                .collect();
            let next: Vec<bool> = (0..n)
                .map(|c| winning[c] && layers.iter().all(|l| l[c] != NONE))
                .collect();
            if next == winning {
                return Ok(Solution { winning, layers });
            }
            winning = next;
        }
    }

    fn attractor(
        &self,
        j: usize,
        z: &[bool],
        starts: &[u32],
        rev: &[(u32, u32)],
        offsets: &[usize],
    ) -> Vec<u32> {
        let n = self.nodes.len();
        let mut layer = vec![NONE; n];
        let mut count = vec![NONE; offsets[n]];
        let mut queue = VecDeque::new();
        for (c, e) in self.expanded.iter().enumerate() {
            let Some(e) = e.as_ref().filter(|_| z[c]) else {
                continue;
            };
            let k = e.out.len();
            for m in 0..e.moves.len() {
                let succ = &e.succ[m * k..(m + 1) * k];
                if succ.iter().all(|&s| z[s as usize]) {
                    let open = (e.out.iter())
                        .filter(|(_, g)| !self.goal_met(*g, j))
                        .count();
                    count[offsets[c] + m] = open as u32;
                    if open == 0 && layer[c] == NONE {
                        layer[c] = 0;
                        queue.push_back(c as u32);
                    }
                }
            }
        }
        while let Some(s) = queue.pop_front() {
            let l = layer[s as usize];
            for &(c, mk) in &rev[starts[s as usize] as usize..starts[s as usize + 1] as usize] {
                let c = c as usize;
                if !z[c] || layer[c] != NONE {
                    continue;
                }
                let e = self.expanded[c]
                    .as_ref()
                    .expect("a predecessor is expanded");
                let (m, k) = (mk as usize / e.out.len(), mk as usize % e.out.len());
                if self.goal_met(e.out[k].1, j) {
                    continue;
                }
                let cnt = &mut count[offsets[c] + m];
                if *cnt == NONE {
                    continue;
                }
                *cnt -= 1;
                if *cnt == 0 {
                    layer[c] = l + 1;
                    queue.push_back(c as u32);
                }
            }
        }
        layer
    }
}

/// A winning strategy, as a controller.
pub(crate) struct Strategy {
    arena: ArenaData,
    /// Per position and goal: the move (index into the position's moves), `NONE` if not
    /// winning.
    choice: Vec<u32>,
    goals: usize,
    /// The monitors' recurring goals (0: safety only, every step counts as goal 0).
    goal_count: usize,
    /// Per position: whether the controller wins from it.
    winning: Vec<bool>,
    /// Per goal and position: the attractor layer (steps to the goal at most), `NONE` outside.
    layers: Vec<Vec<u32>>,
    initial: Vec<u32>,
    initial_outputs: Vec<bool>,
    /// Positions of the game, for the figures.
    pub(crate) positions: usize,
    /// Positions × goals the strategy can reach.
    pub(crate) reachable: usize,
}

/// What a strategy needs of the arena once it is solved.
struct ArenaData {
    tree: ScenarioTree,
    tree_inputs: FxHashMap<u64, usize>,
    nodes: Vec<(u32, u64)>,
    expanded: Vec<Option<Box<Expanded>>>,
}

/// Solves the game of `props` in closed loop with `model`, for controllers answering the
/// recordings of `tree` as recorded, from `initial_outputs`; [`GameError::Stopped`] once
/// `deadline` passes.
pub(crate) fn solve(
    model: &Model,
    coupling: &Wiring,
    props: &[Property],
    tree: &ScenarioTree,
    initial_outputs: &[bool],
    max_positions: usize,
    deadline: Deadline,
) -> Result<Outcome, GameError> {
    let mut arena = Arena::new(model, coupling, props, tree, max_positions)?;
    arena.deadline = deadline;
    let o0 = bits(initial_outputs);
    let initial = arena.build(o0)?;
    let solution = arena.solve()?;
    if initial.is_empty() {
        return Err(GameError::Check(CheckError::NoBehaviour {
            scope: "plant",
            what: "initial state",
        }));
    }
    if initial.iter().any(|&i| !solution.winning[i as usize]) {
        return Ok(Outcome::Lost);
    }
    let goals = arena.monitors.goal_count().max(1);
    let n = arena.nodes.len();
    let mut choice = vec![NONE; n * goals];
    for c in 0..n {
        if !solution.winning[c] {
            continue;
        }
        let e = arena.expanded[c]
            .as_ref()
            .expect("winning positions are expanded");
        let o = arena.nodes[c].1;
        let k = e.out.len();
        let progress = |m: usize, j: usize| {
            let lc = solution.layers[j][c];
            let succ = &e.succ[m * k..(m + 1) * k];
            succ.iter().zip(&e.out).all(|(&s, (_, g))| {
                solution.winning[s as usize]
                    && (arena.goal_met(*g, j) || solution.layers[j][s as usize] < lc)
            })
        };
        // Moves that serve more goals at once first: the fewer the moves depend on the goal
        // pursued (the strategy's memory), the smaller the machine that copies them.
        let serves: Vec<usize> = (0..e.moves.len())
            .map(|m| (0..goals).filter(|&j| progress(m, j)).count())
            .collect();
        for j in 0..goals {
            let best = (0..e.moves.len())
                .filter(|&m| progress(m, j))
                .min_by_key(|&m| {
                    let d = (e.moves[m] ^ o).count_ones();
                    (d, std::cmp::Reverse(serves[m]), e.moves[m])
                });
            choice[c * goals + j] = best.map_or(NONE, |m| m as u32);
        }
    }
    let data = ArenaData {
        tree: tree.clone(),
        tree_inputs: arena.tree_inputs.clone(),
        nodes: arena.nodes,
        expanded: arena.expanded,
    };
    let mut strategy = Strategy {
        arena: data,
        choice,
        goals,
        goal_count: arena.monitors.goal_count(),
        winning: solution.winning,
        layers: solution.layers,
        initial,
        initial_outputs: initial_outputs.to_vec(),
        positions: n,
        reachable: 0,
    };
    strategy.reachable = strategy.check_observable()?;
    Ok(Outcome::Won(Box::new(strategy)))
}

impl Strategy {
    fn next_goal(&self, mut j: usize, goals: u64) -> usize {
        for _ in 0..self.goals {
            if self.goals > 1 && goals >> j & 1 == 0 {
                break;
            }
            j = (j + 1) % self.goals;
        }
        j
    }

    /// The move at `c` pursuing goal `j`, and the next positions with the goals met.
    fn play(&self, c: u32, j: usize) -> (u64, Vec<(u32, u64)>) {
        let e = self.arena.expanded[c as usize]
            .as_ref()
            .expect("the strategy stays in winning positions");
        let m = self.choice[c as usize * self.goals + j];
        assert!(
            m != NONE,
            "the strategy has a move in every winning position"
        );
        let (m, k) = (m as usize, e.out.len());
        let next = (e.succ[m * k..(m + 1) * k].iter().zip(&e.out))
            .map(|(&s, &(_, g))| (s, g))
            .collect();
        (e.moves[m], next)
    }

    /// Every position the strategy reaches must be told apart from its siblings by the
    /// controller's inputs; the count of (position, goal) pairs it reaches.
    fn check_observable(&self) -> Result<usize, GameError> {
        let distinct = |ns: &mut dyn Iterator<Item = u32>| -> Result<(), GameError> {
            let mut seen: FxHashMap<u64, u32> = FxHashMap::default();
            for n in ns {
                let obs = self.arena.expanded[n as usize]
                    .as_ref()
                    .expect("winning")
                    .obs;
                if seen.insert(obs, n).is_some_and(|m| m != n) {
                    return Err(GameError::Outside(
                        "the controller's inputs do not tell the plant's state (two states give the same inputs)".into(),
                    ));
                }
            }
            Ok(())
        };
        distinct(&mut self.initial.iter().copied())?;
        let mut seen = vec![false; self.arena.nodes.len() * self.goals];
        let mut stack: Vec<(u32, usize)> = self.initial.iter().map(|&c| (c, 0)).collect();
        let mut count = 0;
        while let Some((c, j)) = stack.pop() {
            if std::mem::replace(&mut seen[c as usize * self.goals + j], true) {
                continue;
            }
            count += 1;
            let (_, next) = self.play(c, j);
            distinct(&mut next.iter().map(|&(s, _)| s))?;
            for (s, g) in next {
                stack.push((s, self.next_goal(j, g)));
            }
        }
        Ok(count)
    }
}

/// A strategy running as a controller.
pub(crate) struct StrategyRun<'a> {
    s: &'a Strategy,
    /// The positions the plant may be in now, with the goals met on the way there.
    candidates: Vec<(u32, u64)>,
    goal: usize,
    tau: u32,
    outputs: Vec<bool>,
    lost: bool,
}

impl Controller for Strategy {
    type Run<'a> = StrategyRun<'a>;
    fn start(&self) -> StrategyRun<'_> {
        StrategyRun {
            s: self,
            candidates: self.initial.iter().map(|&c| (c, 0)).collect(),
            goal: 0,
            tau: 0,
            outputs: self.initial_outputs.clone(),
            lost: false,
        }
    }
}

impl Reactive for StrategyRun<'_> {
    fn react(&mut self, x: &[bool]) -> Option<&[bool]> {
        let a = &self.s.arena;
        let xb = bits(x);
        // The recordings come first: off the plant's behaviour they are all there is.
        let (recorded, tau) = recorded_step(&a.tree, &a.tree_inputs, self.tau, xb);
        self.tau = tau;
        let recorded = recorded.map(|r| r.map(|child| a.tree.nodes[child].outputs.clone()));
        let mut played = None;
        if !self.lost {
            // Edges into one position may differ in the goals they meet (by free inputs the
            // controller does not see): only the goals met on all of them count.
            let mut here: Option<(u32, u64)> = None;
            for &(c, g) in &self.candidates {
                if a.expanded[c as usize].as_ref().is_some_and(|e| e.obs == xb) {
                    here = Some(here.map_or((c, g), |(c, h)| (c, h & g)));
                }
            }
            match here {
                None => self.lost = true,
                Some((c, g)) => {
                    self.goal = self.s.next_goal(self.goal, g);
                    let (o, next) = self.s.play(c, self.goal);
                    self.candidates = next;
                    played = Some(o);
                }
            }
        }
        let answer: Option<Vec<bool>> = match recorded {
            Some(r) => r,
            None => match played {
                // Always an answer, even with the outputs unchanged: a machine that lets a
                // step pass stays in its state, so it cannot act later on the same inputs
                // (the strategy may, having seen the plant move where the inputs did not).
                Some(o) => Some((0..self.outputs.len()).map(|z| o >> z & 1 == 1).collect()),
                None => None,
            },
        };
        match answer {
            Some(o) => {
                self.outputs = o;
                Some(&self.outputs)
            }
            None => None,
        }
    }
}
