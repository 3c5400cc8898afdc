//! Emptiness of a generalized Büchi graph: is there a path from an initial node into a cycle
//! that visits every acceptance set? On the fly, with Couvreur's algorithm.
//!
//! In: a [`Graph`] (initial nodes, successors computed on demand, acceptance marks per node)
//! and the mask of all sets. Out: `None`, or an accepting lasso `(prefix, cycle)` of nodes:
//! the path `prefix` followed by `cycle` forever (`cycle[0]` is a successor of the last node
//! of `prefix`, `cycle[0]` a successor of the last node of `cycle`).
//!
//! # Method
//! A depth-first search keeps the roots of the strongly connected components not yet
//! completed, each with the union of the marks of its nodes. An edge back to a live node
//! merges every root above it into one component, which is then strongly connected and
//! holds a cycle: if its marks cover every set, an accepting lasso exists and the search stops
//! before the component is complete. A completed component is dead: never entered again.
//! Only cycles count, so dead ends and finite paths never make a graph non-empty.
//!
//! The lasso: the depth-first stack from an initial node to the component's root, then a
//! cycle from the root through a node of each set and back, by breadth-first searches inside
//! the component.
//!
//! # References
//! - J.-M. Couvreur: *On-the-fly verification of linear temporal logic*, FM 1999.
//! - J. Geldenhuys, A. Valmari: *Tarjan's algorithm makes on-the-fly LTL verification more
//!   efficient*, TACAS 2004.

use rustc_hash::{FxHashMap, FxHashSet};
use std::collections::VecDeque;

/// A graph explored on demand. Node numbers are assigned by the graph.
pub(crate) trait Graph {
    type Error;
    fn initial(&mut self) -> Result<Vec<u32>, Self::Error>;
    /// Appends the successors of `n` to `out`.
    fn successors(&mut self, n: u32, out: &mut Vec<u32>) -> Result<(), Self::Error>;
    /// The acceptance sets `n` belongs to.
    fn marks(&self, n: u32) -> u64;
    /// The error of a search that would hold more than `bytes` bytes.
    fn too_large(&self, bytes: usize) -> Self::Error;
}

/// Estimated bytes the search holds per node it has seen: its number in a table, its place
/// among the live nodes and, while it is on the stack, its frame and component root. Its
/// successors on the stack cost four bytes each more.
const NODE_BYTES: usize = 64;

/// An accepting lasso: `prefix` then `cycle` repeated forever.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct NodeLasso {
    pub(crate) prefix: Vec<u32>,
    pub(crate) cycle: Vec<u32>,
}

/// The search state of a node: not seen, live with its depth-first number, or dead.
const DEAD: u32 = u32::MAX;

struct Frame {
    node: u32,
    succ: Vec<u32>,
    next: usize,
}

/// The depth-first search of [`find_lasso`].
struct Search {
    /// Depth-first number of each node seen, or [`DEAD`].
    number: FxHashMap<u32, u32>,
    count: u32,
    /// Roots of the components on the stack: (number, marks of the component so far).
    roots: Vec<(u32, u64)>,
    /// Live nodes in visiting order (the components not yet completed).
    live: Vec<u32>,
    stack: Vec<Frame>,
    /// Estimated bytes held: [`NODE_BYTES`] per node seen, four per successor on the stack.
    held: usize,
    /// The most bytes the search may hold.
    budget: usize,
}

impl Search {
    fn push<G: Graph>(&mut self, g: &mut G, n: u32) -> Result<(), G::Error> {
        self.count += 1;
        self.number.insert(n, self.count);
        self.roots.push((self.count, g.marks(n)));
        self.live.push(n);
        let mut succ = Vec::new();
        g.successors(n, &mut succ)?;
        self.held += NODE_BYTES + 4 * succ.len();
        if self.held > self.budget {
            return Err(g.too_large(self.budget));
        }
        self.stack.push(Frame {
            node: n,
            succ,
            next: 0,
        });
        Ok(())
    }

    /// An edge to the live node numbered `k`: merges the components above it. Returns the
    /// merged root's number if the component now covers `all`.
    fn merge(&mut self, k: u32, all: u64) -> Option<u32> {
        let mut marks = 0;
        while self.roots.last().expect("a live node has a root").0 > k {
            marks |= self.roots.pop().expect("checked").1;
        }
        let root = self.roots.last_mut().expect("a live node has a root");
        root.1 |= marks;
        (root.1 & all == all).then_some(root.0)
    }

    /// `n` is done: if it is a root, its component is complete and dies.
    fn pop(&mut self, n: u32) {
        if let Some(f) = self.stack.pop() {
            self.held -= 4 * f.succ.len();
        }
        let k = self.number[&n];
        if self.roots.last().map(|r| r.0) == Some(k) {
            self.roots.pop();
            while let Some(&v) = self.live.last() {
                if self.number[&v] < k {
                    break;
                }
                self.live.pop();
                self.number.insert(v, DEAD);
            }
        }
    }
}

/// Searches for an accepting lasso; `all` is the mask of every acceptance set. The search
/// holds at most `budget` bytes (estimated): beyond, it stops with [`Graph::too_large`].
pub(crate) fn find_lasso<G: Graph>(
    g: &mut G,
    all: u64,
    budget: usize,
) -> Result<Option<NodeLasso>, G::Error> {
    let mut s = Search {
        number: FxHashMap::default(),
        count: 0,
        roots: Vec::new(),
        live: Vec::new(),
        stack: Vec::new(),
        held: 0,
        budget,
    };
    for init in g.initial()? {
        if s.number.contains_key(&init) {
            continue;
        }
        s.push(g, init)?;
        while let Some(top) = s.stack.last_mut() {
            if top.next == top.succ.len() {
                let n = top.node;
                s.pop(n);
                continue;
            }
            let t = top.succ[top.next];
            top.next += 1;
            match s.number.get(&t) {
                None => s.push(g, t)?,
                Some(&DEAD) => {}
                Some(&k) => {
                    if let Some(root) = s.merge(k, all) {
                        return Ok(Some(lasso(g, &s, root, all)?));
                    }
                }
            }
        }
    }
    Ok(None)
}

/// The lasso through the component of root number `root` (see the module header).
fn lasso<G: Graph>(g: &mut G, s: &Search, root: u32, all: u64) -> Result<NodeLasso, G::Error> {
    let (stack, live, number) = (&s.stack, &s.live, &s.number);
    let component: FxHashSet<u32> = live.iter().copied().filter(|v| number[v] >= root).collect();
    let root_pos = stack
        .iter()
        .position(|f| number[&f.node] == root)
        .expect("the root of a live component is on the depth-first stack");
    let start = stack[root_pos].node;
    // The depth-first stack reaches the component by some path; the shortest one makes a
    // counterexample a reader (and a synthesis loop) can use: fewer steps to replay.
    let spare = s.budget.saturating_sub(s.held);
    let prefix = match shortest_from_initial(g, start, spare / NODE_BYTES)? {
        Some(p) => p,
        None => stack[..root_pos].iter().map(|f| f.node).collect(),
    };
    let mut cycle = vec![start];
    let mut seen = g.marks(start);
    let mut at = start;
    // Visit a node of each missing set, then return to the start (at least one step).
    loop {
        let missing = all & !seen;
        let path = if missing == 0 {
            bfs(g, &component, at, |_, v| v == start)?
        } else {
            bfs(g, &component, at, |g, v| g.marks(v) & missing != 0)?
        };
        let path = path.expect("a strongly connected component reaches each of its nodes");
        let last = *path.last().expect("a path has at least one step");
        if missing == 0 {
            cycle.extend(&path[..path.len() - 1]);
            return Ok(NodeLasso { prefix, cycle });
        }
        for &v in &path {
            seen |= g.marks(v);
        }
        cycle.extend(&path);
        at = last;
    }
}

/// The nodes of a shortest path from an initial node up to, not including, `target`
/// (empty if `target` is initial); `None` if the search finds no path (it always should) or
/// would see more than `max_nodes` nodes.
fn shortest_from_initial<G: Graph>(
    g: &mut G,
    target: u32,
    max_nodes: usize,
) -> Result<Option<Vec<u32>>, G::Error> {
    let inits = g.initial()?;
    if inits.contains(&target) {
        return Ok(Some(Vec::new()));
    }
    let mut parent: FxHashMap<u32, Option<u32>> = inits.iter().map(|&i| (i, None)).collect();
    let mut queue: VecDeque<u32> = inits.into_iter().collect();
    let mut succ = Vec::new();
    while let Some(v) = queue.pop_front() {
        succ.clear();
        g.successors(v, &mut succ)?;
        for &w in &succ {
            if parent.contains_key(&w) {
                continue;
            }
            if parent.len() >= max_nodes {
                return Ok(None);
            }
            parent.insert(w, Some(v));
            if w == target {
                let mut path = vec![v];
                let mut at = v;
                while let Some(Some(p)) = parent.get(&at) {
                    path.push(*p);
                    at = *p;
                }
                path.reverse();
                return Ok(Some(path));
            }
            queue.push_back(w);
        }
    }
    Ok(None)
}

/// A shortest path of one or more steps from `from` to a node satisfying `goal`, inside
/// `within`; the path lists the nodes after `from`.
fn bfs<G: Graph>(
    g: &mut G,
    within: &FxHashSet<u32>,
    from: u32,
    goal: impl Fn(&G, u32) -> bool,
) -> Result<Option<Vec<u32>>, G::Error> {
    let mut parent: FxHashMap<u32, u32> = FxHashMap::default();
    let mut queue = VecDeque::from([from]);
    let mut succ = Vec::new();
    while let Some(v) = queue.pop_front() {
        succ.clear();
        g.successors(v, &mut succ)?;
        for &w in &succ {
            if !within.contains(&w) || parent.contains_key(&w) {
                continue;
            }
            parent.insert(w, v);
            if goal(g, w) {
                let mut path = vec![w];
                let mut at = w;
                loop {
                    let p = parent[&at];
                    if p == from {
                        break;
                    }
                    path.push(p);
                    at = p;
                }
                path.reverse();
                return Ok(Some(path));
            }
            queue.push_back(w);
        }
    }
    Ok(None)
}
