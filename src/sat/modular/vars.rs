//! The variable registry of the modular encoding: every variable allocated once, with index
//! functions that say what each one means.
//!
//! Numbering (all 0-based): modules `m in 0..M` (users see `m + 1`), states `q, q' in 0..N`
//! per module, transition slots `k in 0..K` per state, tree nodes `v` as [`NodeId`], distinct
//! input vectors `g` as [`InputVec`], input variables `x in 0..X`, outputs `z in 0..Z`. The
//! paper's names are kept where they exist (θ, α, `f`, `nf`, `uc`, `tr`, `p`).

use crate::scenario::tree::{InputVec, NodeId, ScenarioTree};
use varisat::{ExtendFormula, Lit};

/// Dimensions of the encoding.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dims {
    /// Modules `M`.
    pub modules: usize,
    /// States per module at most (`N` of the paper, the encoding window).
    pub c_max: usize,
    /// Transition slots per state (`K`).
    pub slots: usize,
    /// Input variables `X`.
    pub bits: usize,
    /// Output variables `Z`.
    pub outputs: usize,
    /// Tree nodes.
    pub nodes: usize,
    /// Distinct input vectors of the tree (`G`).
    pub vectors: usize,
}

/// All variables of the modular encoding.
#[derive(Debug, Clone)]
pub struct ModVars {
    pub d: Dims,
    /// `uc[m][q]`: module `m` uses state `q`; used states form a prefix.
    used: Vec<Lit>,
    /// `c[m][v][q]`: tree node `v` is coloured with state `q` of module `m`.
    color: Vec<Lit>,
    /// `θ[m][z]`: output `z` belongs to module `m`.
    theta: Vec<Lit>,
    /// `α[m][x]`: module `m` reads input `x`.
    alpha: Vec<Lit>,
    /// `en[m][q][k]`: slot `k` of state `q` holds a transition.
    en: Vec<Lit>,
    /// `tgt[m][q][k][q']`: its target (the paper's `y`).
    tgt: Vec<Lit>,
    /// `pos/neg[m][q][k][x]`: its guard contains `x` / `!x` (the paper's β with α).
    pos: Vec<Lit>,
    neg: Vec<Lit>,
    /// `d0/d1[m][q][z]`: the algorithm of `q` sets `z` to 1 when it was 0 / 1.
    a0: Vec<Lit>,
    a1: Vec<Lit>,
    /// `f[m][g][q][k]`: the guard of slot `k` of `q` holds on input vector `g`.
    fire: Vec<Lit>,
    /// `nf[m][g][q][k]`, `k in 0..=K`: no slot before `k` holds on `g`.
    nf: Vec<Lit>,
    /// `fired[m][v]`: module `m` makes a transition on the tree edge into `v` (root unused).
    fired: Vec<Lit>,
    /// `tr[m][q][q']`: some slot of `q` leads to `q'`.
    tr: Vec<Lit>,
    /// `p[m][j][i]`: `i` is the BFS parent of `j`.
    parent: Vec<Lit>,
}

fn alloc(f: &mut impl ExtendFormula, n: usize) -> Vec<Lit> {
    (0..n).map(|_| f.new_lit()).collect()
}

impl ModVars {
    pub fn new(
        f: &mut impl ExtendFormula,
        tree: &ScenarioTree,
        modules: usize,
        c_max: usize,
        slots: usize,
    ) -> ModVars {
        let d = Dims {
            modules,
            c_max,
            slots,
            bits: tree.input_vectors.first().map_or(0, Vec::len),
            outputs: tree.nodes[0].outputs.len(),
            nodes: tree.nodes.len(),
            vectors: tree.input_vectors.len(),
        };
        let (m, n, k) = (modules, c_max, slots);
        ModVars {
            used: alloc(f, m * n),
            color: alloc(f, m * d.nodes * n),
            theta: alloc(f, m * d.outputs),
            alpha: alloc(f, m * d.bits),
            en: alloc(f, m * n * k),
            tgt: alloc(f, m * n * k * n),
            pos: alloc(f, m * n * k * d.bits),
            neg: alloc(f, m * n * k * d.bits),
            a0: alloc(f, m * n * d.outputs),
            a1: alloc(f, m * n * d.outputs),
            fire: alloc(f, m * d.vectors * n * k),
            nf: alloc(f, m * d.vectors * n * (k + 1)),
            fired: alloc(f, m * d.nodes),
            tr: alloc(f, m * n * n),
            parent: alloc(f, m * n * n),
            d,
        }
    }

    pub fn used(&self, m: usize, q: usize) -> Lit {
        self.used[m * self.d.c_max + q]
    }
    pub fn color(&self, m: usize, v: NodeId, q: usize) -> Lit {
        self.color[(m * self.d.nodes + v.0) * self.d.c_max + q]
    }
    pub fn theta(&self, m: usize, z: usize) -> Lit {
        self.theta[m * self.d.outputs + z]
    }
    pub fn alpha(&self, m: usize, x: usize) -> Lit {
        self.alpha[m * self.d.bits + x]
    }
    fn slot(&self, m: usize, q: usize, k: usize) -> usize {
        (m * self.d.c_max + q) * self.d.slots + k
    }
    pub fn en(&self, m: usize, q: usize, k: usize) -> Lit {
        self.en[self.slot(m, q, k)]
    }
    pub fn tgt(&self, m: usize, q: usize, k: usize, t: usize) -> Lit {
        self.tgt[self.slot(m, q, k) * self.d.c_max + t]
    }
    pub fn pos(&self, m: usize, q: usize, k: usize, x: usize) -> Lit {
        self.pos[self.slot(m, q, k) * self.d.bits + x]
    }
    pub fn neg(&self, m: usize, q: usize, k: usize, x: usize) -> Lit {
        self.neg[self.slot(m, q, k) * self.d.bits + x]
    }
    pub fn a0(&self, m: usize, q: usize, z: usize) -> Lit {
        self.a0[(m * self.d.c_max + q) * self.d.outputs + z]
    }
    pub fn a1(&self, m: usize, q: usize, z: usize) -> Lit {
        self.a1[(m * self.d.c_max + q) * self.d.outputs + z]
    }
    /// `d0` or `d1` by the old value of the output.
    pub fn a(&self, m: usize, q: usize, z: usize, old: bool) -> Lit {
        if old {
            self.a1(m, q, z)
        } else {
            self.a0(m, q, z)
        }
    }
    pub fn fire(&self, m: usize, g: InputVec, q: usize, k: usize) -> Lit {
        let d = &self.d;
        self.fire[((m * d.vectors + g.0) * d.c_max + q) * d.slots + k]
    }
    /// `k in 0..=K`; `nf[.., K]` says that nothing fires.
    pub fn nf(&self, m: usize, g: InputVec, q: usize, k: usize) -> Lit {
        let d = &self.d;
        self.nf[((m * d.vectors + g.0) * d.c_max + q) * (d.slots + 1) + k]
    }
    pub fn fired(&self, m: usize, v: NodeId) -> Lit {
        self.fired[m * self.d.nodes + v.0]
    }
    pub fn tr(&self, m: usize, q: usize, t: usize) -> Lit {
        self.tr[(m * self.d.c_max + q) * self.d.c_max + t]
    }
    pub fn parent(&self, m: usize, j: usize, i: usize) -> Lit {
        self.parent[(m * self.d.c_max + j) * self.d.c_max + i]
    }
    /// Every `α`, for counting the inputs used (`A`).
    pub fn all_alpha(&self) -> &[Lit] {
        &self.alpha
    }
    /// Every `uc`, for counting the states used (`N'`).
    pub fn all_used(&self) -> &[Lit] {
        &self.used
    }
}
