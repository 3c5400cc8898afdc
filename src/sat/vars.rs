//! The variable registry of the basic encoding: every Boolean variable, allocated once, with
//! index functions that say what each one means; and [`Coloring`], the view of one machine's
//! colouring variables that the shared constraint families are written against.
//!
//! Numbering: states `q, q' in 0..C_max` (0-based, 0 initial), tree nodes `v` as
//! [`NodeId`], input vectors `u` as [`InputVec`], outputs `z` 0-based. The "no transition"
//! target is written `⊥` in the doc comments and stored at index `C_max` of the target axis.

use crate::scenario::tree::{InputVec, NodeId, ScenarioTree};
use varisat::{ExtendFormula, Lit};

/// The colouring variables of one machine: a whole ECC, or one module of a modular controller.
/// Every shared constraint family ([`super::constraints`]) is written against this view, so it
/// is written once for the basic, noisy and modular encodings.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Coloring<'a> {
    /// `C_max`: states allocated (the window); those in use are a prefix `0..C`.
    pub(crate) c_max: usize,
    /// Number of outputs `Z` (the row length of `a0` and `a1`).
    pub(crate) outputs: usize,
    /// `used[q]`: state `q` exists; states in use form a prefix `0..C`.
    pub(crate) used: &'a [Lit],
    /// `color[v][q]`: tree node `v` is coloured with (mapped to) state `q`.
    pub(crate) color: &'a [Lit],
    /// `a0[q][z]` / `a1[q][z]`: state `q`'s algorithm sets output `z` to 1 when it was 0 / 1.
    pub(crate) a0: &'a [Lit],
    /// `a1[q][z]`: see `a0`, when output `z` was 1.
    pub(crate) a1: &'a [Lit],
    /// `edge[q][q']`: some transition leads from `q` to `q'` (the basic encoding's `t`, the
    /// modular encoding's `tr`).
    pub(crate) edge: &'a [Lit],
    /// `parent[j][i]` (`i < j`): state `i` is the BFS parent of state `j`.
    pub(crate) parent: &'a [Lit],
    /// The whole controller, or one module with its ownership and firing literals.
    pub(crate) scope: Scope<'a>,
}

/// What part of the controller a coloured machine is.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Scope<'a> {
    /// The whole controller: it owns every output and fires on every active step.
    Whole,
    /// A module (the SAT reconstruction paper, section V): it owns the outputs with `owns[z]` (θ)
    /// and fires on the tree edge into `v` iff `fires[v]` (which inputs it reads, α, its cube
    /// guards say: [`crate::sat::modular::constraints::slots`]).
    Module {
        /// `owns[z]` (θ): the module owns output `z`.
        owns: &'a [Lit],
        /// `fires[v]`: the module makes a transition on the tree edge into node `v`.
        fires: &'a [Lit],
    },
}

impl Coloring<'_> {
    /// `used[q]`: state `q` exists.
    pub(crate) fn used(&self, q: usize) -> Lit {
        self.used[q]
    }
    /// `color[v][q]`: tree node `v` is coloured with state `q`.
    pub(crate) fn color(&self, v: NodeId, q: usize) -> Lit {
        self.color[v.0 * self.c_max + q]
    }
    /// `a0[q][z]`: state `q`'s algorithm sets output `z` to 1 when it was 0.
    pub(crate) fn a0(&self, q: usize, z: usize) -> Lit {
        self.a0[q * self.outputs + z]
    }
    /// `a1[q][z]`: state `q`'s algorithm sets output `z` to 1 when it was 1.
    pub(crate) fn a1(&self, q: usize, z: usize) -> Lit {
        self.a1[q * self.outputs + z]
    }
    /// `a0` or `a1` by the old value of the output.
    pub(crate) fn a(&self, q: usize, z: usize, old: bool) -> Lit {
        if old {
            self.a1(q, z)
        } else {
            self.a0(q, z)
        }
    }
    /// `edge[q][target]`: some transition leads from `q` to `target`.
    pub(crate) fn edge(&self, q: usize, target: usize) -> Lit {
        self.edge[q * self.c_max + target]
    }
    /// `parent[j][i]` (`i < j`): state `i` is the BFS parent of state `j`.
    pub(crate) fn parent(&self, j: usize, i: usize) -> Lit {
        self.parent[j * self.c_max + i]
    }
    /// Number of tree nodes coloured.
    pub(crate) fn nodes(&self) -> usize {
        self.color.len() / self.c_max
    }
}

/// How the basic encoding models guards.
#[derive(Debug, Clone)]
pub(crate) enum GuardModel {
    /// Transitions exist on recorded inputs only; guards are minimized after solving
    /// ([`super::guards`]).
    TreeExact,
    /// Guards are conjunctions inside the encoding ([`super::cubes`]).
    Cubes(CubeVars),
}

/// All variables of the basic ECC encoding for at most `c_max` states.
#[derive(Debug, Clone)]
pub(crate) struct Vars {
    /// `C_max`: states allocated (the window); a smaller `C` is an assumption
    /// ([`Vars::states_at_most`]).
    pub(crate) c_max: usize,
    /// Input vectors allocated so far: the tree's, then those counterexamples bring
    /// ([`Vars::add_input`]).
    pub(crate) inputs: usize,
    /// Number of outputs `Z`.
    pub(crate) outputs: usize,
    used: Vec<Lit>,
    color: Vec<Lit>,
    /// `y[u][q][q']`: in state `q`, input `u` leads to `q'` (`q' = C_max` is `⊥`: nothing fires).
    /// Stored per input so the alphabet can grow (counterexamples bring new input vectors).
    y: Vec<Vec<Lit>>,
    a0: Vec<Lit>,
    a1: Vec<Lit>,
    /// `t[q][q']`: there is a transition from `q` to `q'` (for some input).
    t: Vec<Lit>,
    p: Vec<Lit>,
    /// `m[u][i][j]`: `u` is the smallest input on which `i` goes to `j`.
    m: Vec<Vec<Lit>>,
    /// `nm[u][i][j]`: no input smaller than `u` leads from `i` to `j` (`u` in `0..=U`).
    nm: Vec<Vec<Lit>>,
    /// How guards are modelled; in the cube model it holds the slot variables.
    pub(crate) guards: GuardModel,
}

pub(crate) fn alloc(f: &mut impl ExtendFormula, n: usize) -> Vec<Lit> {
    (0..n).map(|_| f.new_lit()).collect()
}

impl Vars {
    /// `max_out_degree`: `Some(k)` for the cube-guard model with `k` slots per state.
    pub(crate) fn new(
        f: &mut impl ExtendFormula,
        tree: &ScenarioTree,
        c_max: usize,
        max_out_degree: Option<usize>,
    ) -> Vars {
        let nodes = tree.nodes.len();
        let outputs = tree.nodes[0].outputs.len();
        let mut v = Vars {
            c_max,
            inputs: 0,
            outputs,
            used: alloc(f, c_max),
            color: alloc(f, nodes * c_max),
            y: Vec::new(),
            a0: alloc(f, c_max * outputs),
            a1: alloc(f, c_max * outputs),
            t: alloc(f, c_max * c_max),
            p: alloc(f, c_max * c_max),
            m: Vec::new(),
            nm: vec![alloc(f, c_max * c_max)],
            guards: match max_out_degree {
                Some(max_out_degree) => {
                    let bits = tree.input_vectors.first().map_or(0, Vec::len);
                    GuardModel::Cubes(CubeVars::new(f, 1, c_max, max_out_degree, bits))
                }
                None => GuardModel::TreeExact,
            },
        };
        for _ in 0..tree.input_vectors.len() {
            v.add_input(f);
        }
        v
    }

    /// Allocates the variables of one more input vector (index `self.inputs` before the call).
    pub(crate) fn add_input(&mut self, f: &mut impl ExtendFormula) -> InputVec {
        let c = self.c_max;
        self.y.push(alloc(f, c * (c + 1)));
        self.m.push(alloc(f, c * c));
        self.nm.push(alloc(f, c * c));
        if let GuardModel::Cubes(cv) = &mut self.guards {
            cv.add_inputs(f, 1);
        }
        self.inputs += 1;
        InputVec(self.inputs - 1)
    }

    /// The machine's colouring, for the shared constraint families.
    pub(crate) fn coloring(&self) -> Coloring<'_> {
        Coloring {
            c_max: self.c_max,
            outputs: self.outputs,
            used: &self.used,
            color: &self.color,
            a0: &self.a0,
            a1: &self.a1,
            edge: &self.t,
            parent: &self.p,
            scope: Scope::Whole,
        }
    }

    /// The assumption "at most `c` states" (`None`: the window has no more).
    pub(crate) fn states_at_most(&self, c: usize) -> Option<Lit> {
        (c < self.c_max).then(|| !self.used(c))
    }

    /// Index of the `⊥` ("nothing fires") target.
    pub(crate) fn none(&self) -> usize {
        self.c_max
    }

    /// `used[q]`: state `q` exists (states in use form a prefix).
    pub(crate) fn used(&self, q: usize) -> Lit {
        self.used[q]
    }
    /// `color[v][q]`: tree node `v` is coloured with state `q`.
    pub(crate) fn color(&self, v: NodeId, q: usize) -> Lit {
        self.color[v.0 * self.c_max + q]
    }
    /// `y[u][q][target]`: in state `q`, input `u` leads to `target` (`target = C_max` is `⊥`:
    /// nothing fires).
    pub(crate) fn y(&self, q: usize, u: InputVec, target: usize) -> Lit {
        self.y[u.0][q * (self.c_max + 1) + target]
    }
    /// `a0` or `a1` of state `q` by the old value of output `z`.
    pub(crate) fn a(&self, q: usize, z: usize, old: bool) -> Lit {
        self.coloring().a(q, z, old)
    }
    /// `t[q][target]`: some input leads from `q` to `target`.
    pub(crate) fn t(&self, q: usize, target: usize) -> Lit {
        self.t[q * self.c_max + target]
    }
    /// `m[u][i][j]`: `u` is the smallest input on which `i` goes to `j` (BFS symmetry breaking).
    pub(crate) fn m(&self, i: usize, u: InputVec, j: usize) -> Lit {
        self.m[u.0][i * self.c_max + j]
    }
    /// `nm[u][i][j]`: no input smaller than `u` leads from `i` to `j` (`u` in `0..=U`).
    pub(crate) fn nm(&self, i: usize, u: usize, j: usize) -> Lit {
        self.nm[u][i * self.c_max + j]
    }
    /// All `t[q][q']` literals, for counting transitions.
    pub(crate) fn all_t(&self) -> &[Lit] {
        &self.t
    }
    /// `t[q][·]`, for counting the out-degree of `q`.
    pub(crate) fn t_row(&self, q: usize) -> &[Lit] {
        &self.t[q * self.c_max..(q + 1) * self.c_max]
    }
}

/// Variables of the cube-guard model of `machines` machines: per machine `m` and state `q`,
/// `slots` ordered transition slots, each with a target and a guard that is a conjunction of
/// literals over the `bits` input variables; per input vector `u`, which slots fire.
///
/// Layout: machine-major everywhere. The per-input variables of several machines are allocated
/// at once ([`Self::add_inputs`]); only a single machine's alphabet grows one vector at a time.
#[derive(Debug, Clone)]
pub(crate) struct CubeVars {
    /// Machines sharing the layout: 1 for an ECC, `M` for a modular controller.
    pub(crate) machines: usize,
    /// States per machine `C_max`.
    pub(crate) c_max: usize,
    /// The largest out-degree `K`: transition slots per state.
    pub(crate) max_out_degree: usize,
    /// Input variables `X` a guard may test.
    pub(crate) bits: usize,
    /// Input vectors allocated so far.
    vectors: usize,
    /// `en[m][q][k]`: slot `k` of state `q` holds a transition.
    en: Vec<Lit>,
    /// `tgt[m][q][k][q']`: its target.
    tgt: Vec<Lit>,
    /// `pos[m][q][k][x]` / `neg[m][q][k][x]`: its guard contains `x` / `!x`.
    pos: Vec<Lit>,
    neg: Vec<Lit>,
    /// `fire[m][u][q][k]`: the guard holds on `u`.
    fire: Vec<Lit>,
    /// `nf[m][u][q][k]`, `k in 0..=K`: no slot before `k` fires on `u`.
    nf: Vec<Lit>,
}

impl CubeVars {
    /// The slot variables; per-input variables come with [`Self::add_inputs`].
    pub(crate) fn new(
        f: &mut impl ExtendFormula,
        machines: usize,
        c_max: usize,
        max_out_degree: usize,
        bits: usize,
    ) -> CubeVars {
        let n = machines * c_max * max_out_degree;
        CubeVars {
            machines,
            c_max,
            max_out_degree,
            bits,
            vectors: 0,
            en: alloc(f, n),
            tgt: alloc(f, n * c_max),
            pos: alloc(f, n * bits),
            neg: alloc(f, n * bits),
            fire: Vec::new(),
            nf: Vec::new(),
        }
    }

    /// Allocates `fire` and then `nf` of `count` more input vectors, for every machine.
    pub(crate) fn add_inputs(&mut self, f: &mut impl ExtendFormula, count: usize) {
        debug_assert!(
            self.machines == 1 || self.vectors == 0,
            "machine-major layout"
        );
        let per = self.machines * count * self.c_max;
        self.fire.extend(alloc(f, per * self.max_out_degree));
        self.nf.extend(alloc(f, per * (self.max_out_degree + 1)));
        self.vectors += count;
    }

    fn slot(&self, m: usize, q: usize, k: usize) -> usize {
        (m * self.c_max + q) * self.max_out_degree + k
    }
    fn at(&self, m: usize, u: InputVec, q: usize) -> usize {
        (m * self.vectors + u.0) * self.c_max + q
    }
    /// `en[m][q][k]`: slot `k` of state `q` of machine `m` holds a transition.
    pub(crate) fn en(&self, m: usize, q: usize, k: usize) -> Lit {
        self.en[self.slot(m, q, k)]
    }
    /// `tgt[m][q][k][t]`: that slot's transition leads to state `t`.
    pub(crate) fn tgt(&self, m: usize, q: usize, k: usize, t: usize) -> Lit {
        self.tgt[self.slot(m, q, k) * self.c_max + t]
    }
    /// `pos[m][q][k][x]`: that slot's guard contains the literal `x`.
    pub(crate) fn pos(&self, m: usize, q: usize, k: usize, x: usize) -> Lit {
        self.pos[self.slot(m, q, k) * self.bits + x]
    }
    /// `neg[m][q][k][x]`: that slot's guard contains the literal `!x`.
    pub(crate) fn neg(&self, m: usize, q: usize, k: usize, x: usize) -> Lit {
        self.neg[self.slot(m, q, k) * self.bits + x]
    }
    /// `fire[m][u][q][k]`: the guard of slot `k` of state `q` holds on input vector `u` (whether
    /// or not an earlier slot fires first).
    pub(crate) fn fire(&self, m: usize, u: InputVec, q: usize, k: usize) -> Lit {
        self.fire[self.at(m, u, q) * self.max_out_degree + k]
    }
    /// `k in 0..=K`; `nf[.., K]` says that nothing fires.
    pub(crate) fn nf(&self, m: usize, u: InputVec, q: usize, k: usize) -> Lit {
        self.nf[self.at(m, u, q) * (self.max_out_degree + 1) + k]
    }
    /// Every `en`, for counting transitions.
    pub(crate) fn all_en(&self) -> &[Lit] {
        &self.en
    }
    /// `en[m][q][·]`, for counting the out-degree of `q`.
    pub(crate) fn en_row(&self, m: usize, q: usize) -> &[Lit] {
        let s = self.slot(m, q, 0);
        &self.en[s..s + self.max_out_degree]
    }
    /// Every guard literal, for counting `N`.
    pub(crate) fn all_literals(&self) -> Vec<Lit> {
        self.pos.iter().chain(&self.neg).copied().collect()
    }
    /// The literals of slot `k` of state `q` of machine `m` as a conjunction, read from a model.
    pub(crate) fn cube(
        &self,
        model: &super::solver::Model,
        m: usize,
        q: usize,
        k: usize,
    ) -> Vec<(usize, bool)> {
        (0..self.bits)
            .filter_map(|x| {
                if model.value(self.pos(m, q, k, x)) {
                    Some((x, true))
                } else if model.value(self.neg(m, q, k, x)) {
                    Some((x, false))
                } else {
                    None
                }
            })
            .collect()
    }
}
