//! The variable registry of the modular encoding: every variable allocated once, with index
//! functions that say what each one means.
//!
//! Numbering (all 0-based): modules `m in 0..M` (users see `m + 1`), states `q, q' in 0..N`
//! per module, transition slots `k in 0..K` per state, tree nodes `v` as [`NodeId`], distinct
//! input vectors `g` as [`InputVec`](crate::scenario::tree::InputVec), input variables `x in 0..X`, outputs `z in 0..Z`. The
//! paper's names are kept where they exist (θ, α, `f`, `nf`, `uc`, `tr`, `p`). Each module's
//! colouring is a [`Coloring`] view, its guards are the module's part of one [`CubeVars`].

use crate::sat::vars::CubeVars;
use crate::sat::vars::{alloc, Coloring, Scope};
use crate::scenario::tree::{NodeId, ScenarioTree};
use varisat::{ExtendFormula, Lit};

/// Dimensions of the encoding.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Dims {
    /// Modules `M`.
    pub(crate) modules: usize,
    /// States per module at most (`N` of the paper, the encoding window).
    pub(crate) c_max: usize,
    /// The largest out-degree `K`: transition slots per state.
    pub(crate) max_out_degree: usize,
    /// Input variables `X`.
    pub(crate) bits: usize,
    /// Output variables `Z`.
    pub(crate) outputs: usize,
    /// Tree nodes.
    pub(crate) nodes: usize,
    /// Distinct input vectors of the tree (`G`).
    pub(crate) vectors: usize,
}

/// All variables of the modular encoding; per module `m` every block is contiguous.
#[derive(Debug, Clone)]
pub(crate) struct ModVars {
    /// The encoding's dimensions, from which every index below is computed.
    pub(crate) d: Dims,
    /// `uc[m][q]`: module `m` uses state `q`; used states form a prefix.
    used: Vec<Lit>,
    /// `c[m][v][q]`: tree node `v` is coloured with state `q` of module `m`.
    color: Vec<Lit>,
    /// `θ[m][z]`: output `z` belongs to module `m`.
    theta: Vec<Lit>,
    /// `α[m][x]`: module `m` reads input `x`.
    alpha: Vec<Lit>,
    /// Slots (`en`, the target `tgt` is the paper's `y`, the guard `pos/neg` the paper's β with
    /// α) and firing (`f`, `nf`) of every module.
    pub(crate) cubes: CubeVars,
    /// `d0/d1[m][q][z]`: the algorithm of `q` sets `z` to 1 when it was 0 / 1.
    a0: Vec<Lit>,
    a1: Vec<Lit>,
    /// `fired[m][v]`: module `m` makes a transition on the tree edge into `v` (root unused).
    fired: Vec<Lit>,
    /// `tr[m][q][q']`: some slot of `q` leads to `q'`.
    tr: Vec<Lit>,
    /// `p[m][j][i]`: `i` is the BFS parent of `j`.
    parent: Vec<Lit>,
    /// Consecutive composites only (empty otherwise): `val[m][v][z]`, the value of output `z`
    /// after module `m` on the tree edge into `v` (root unused).
    values: Vec<Lit>,
}

impl ModVars {
    /// Allocates every variable for `modules` modules of at most `c_max` states and `slots`
    /// transition slots per state over `tree`, including the cube variables of the tree's input
    /// vectors, and with `chain` the values passed along a consecutive composite.
    pub(crate) fn new(
        f: &mut impl ExtendFormula,
        tree: &ScenarioTree,
        modules: usize,
        c_max: usize,
        max_out_degree: usize,
        chain: bool,
    ) -> ModVars {
        let d = Dims {
            modules,
            c_max,
            max_out_degree,
            bits: tree.input_vectors.first().map_or(0, Vec::len),
            outputs: tree.nodes[0].outputs.len(),
            nodes: tree.nodes.len(),
            vectors: tree.input_vectors.len(),
        };
        let (m, n) = (modules, c_max);
        let used = alloc(f, m * n);
        let color = alloc(f, m * d.nodes * n);
        let theta = alloc(f, m * d.outputs);
        let alpha = alloc(f, m * d.bits);
        let mut cubes = CubeVars::new(f, m, n, max_out_degree, d.bits);
        let a0 = alloc(f, m * n * d.outputs);
        let a1 = alloc(f, m * n * d.outputs);
        cubes.add_inputs(f, d.vectors);
        ModVars {
            used,
            color,
            theta,
            alpha,
            cubes,
            a0,
            a1,
            fired: alloc(f, m * d.nodes),
            tr: alloc(f, m * n * n),
            parent: alloc(f, m * n * n),
            values: if chain {
                alloc(f, m * d.nodes * d.outputs)
            } else {
                Vec::new()
            },
            d,
        }
    }

    /// Module `m`'s colouring, for the shared constraint families.
    pub(crate) fn module(&self, m: usize) -> Coloring<'_> {
        let d = &self.d;
        let (n, per_state) = (d.c_max, d.c_max * d.outputs);
        Coloring {
            c_max: n,
            outputs: d.outputs,
            used: &self.used[m * n..(m + 1) * n],
            color: &self.color[m * d.nodes * n..(m + 1) * d.nodes * n],
            a0: &self.a0[m * per_state..(m + 1) * per_state],
            a1: &self.a1[m * per_state..(m + 1) * per_state],
            edge: &self.tr[m * n * n..(m + 1) * n * n],
            parent: &self.parent[m * n * n..(m + 1) * n * n],
            scope: Scope::Module {
                owns: &self.theta[m * d.outputs..(m + 1) * d.outputs],
                fires: &self.fired[m * d.nodes..(m + 1) * d.nodes],
            },
        }
    }

    /// Every module's colouring, in order.
    pub(crate) fn modules(&self) -> Vec<Coloring<'_>> {
        (0..self.d.modules).map(|m| self.module(m)).collect()
    }

    /// `uc[m][q]`: module `m` uses state `q`.
    pub(crate) fn used(&self, m: usize, q: usize) -> Lit {
        self.used[m * self.d.c_max + q]
    }
    /// `c[m][v][q]`: tree node `v` is coloured with state `q` of module `m`.
    pub(crate) fn color(&self, m: usize, v: NodeId, q: usize) -> Lit {
        self.color[(m * self.d.nodes + v.0) * self.d.c_max + q]
    }
    /// `θ[m][z]`: output `z` belongs to module `m`.
    pub(crate) fn theta(&self, m: usize, z: usize) -> Lit {
        self.theta[m * self.d.outputs + z]
    }
    /// `α[m][x]`: module `m` reads input variable `x`.
    pub(crate) fn alpha(&self, m: usize, x: usize) -> Lit {
        self.alpha[m * self.d.bits + x]
    }
    /// `d0[m][q][z]`: the algorithm of state `q` of module `m` sets output `z` to 1 when it was 0.
    pub(crate) fn a0(&self, m: usize, q: usize, z: usize) -> Lit {
        self.a0[(m * self.d.c_max + q) * self.d.outputs + z]
    }
    /// `d1[m][q][z]`: the algorithm of state `q` of module `m` sets output `z` to 1 when it was 1.
    pub(crate) fn a1(&self, m: usize, q: usize, z: usize) -> Lit {
        self.a1[(m * self.d.c_max + q) * self.d.outputs + z]
    }
    /// `fired[m][v]`: module `m` makes a transition on the tree edge into `v`.
    pub(crate) fn fired(&self, m: usize, v: NodeId) -> Lit {
        self.fired[m * self.d.nodes + v.0]
    }
    /// `val[m][v][z]`: output `z` after module `m` of a consecutive composite on the edge into
    /// `v`.
    pub(crate) fn value(&self, m: usize, v: NodeId, z: usize) -> Lit {
        self.values[(m * self.d.nodes + v.0) * self.d.outputs + z]
    }
    /// `tr[m][q][t]`: some slot of state `q` of module `m` leads to state `t`.
    pub(crate) fn tr(&self, m: usize, q: usize, t: usize) -> Lit {
        self.tr[(m * self.d.c_max + q) * self.d.c_max + t]
    }
    /// Assumptions "no module has more than `n` states" (empty when the window is `n`).
    pub(crate) fn size_at_most(&self, n: usize) -> Vec<Lit> {
        if n >= self.d.c_max {
            return Vec::new();
        }
        (0..self.d.modules).map(|m| !self.used(m, n)).collect()
    }

    /// Every `α`, for counting the inputs used (`A`).
    pub(crate) fn all_alpha(&self) -> &[Lit] {
        &self.alpha
    }
    /// Every `uc`, for counting the states used (`N'`).
    pub(crate) fn all_used(&self) -> &[Lit] {
        &self.used
    }
}
