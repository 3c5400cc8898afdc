//! The variable registry: every Boolean variable of the encoding, allocated once, with index
//! functions that say what each one means.
//!
//! Numbering: states `q, q' in 0..C_max` (0-based, 0 initial), tree nodes `v` as
//! [`NodeId`], input vectors `u` as [`InputVec`], outputs `z` 0-based. The "no transition"
//! target is written `⊥` in the doc comments and stored at index `C_max` of the target axis.

use crate::scenario::tree::{InputVec, NodeId, ScenarioTree};
use varisat::{ExtendFormula, Lit};

/// All variables of the basic ECC encoding for at most `c_max` states.
#[derive(Debug, Clone)]
pub struct Vars {
    pub c_max: usize,
    pub nodes: usize,
    pub inputs: usize,
    pub outputs: usize,
    /// `used[q]`: state `q` exists. States in use form a prefix `0..C`.
    used: Vec<Lit>,
    /// `color[v][q]`: tree node `v` is coloured with (mapped to) state `q`.
    color: Vec<Lit>,
    /// `y[u][q][q']`: in state `q`, input `u` leads to `q'` (`q' = C_max` is `⊥`: nothing fires).
    /// Stored per input so the alphabet can grow (counterexamples bring new input vectors).
    y: Vec<Vec<Lit>>,
    /// `a0[q][z]`: state `q`'s algorithm sets output `z` to 1 when it was 0.
    a0: Vec<Lit>,
    /// `a1[q][z]`: state `q`'s algorithm sets output `z` to 1 when it was 1.
    a1: Vec<Lit>,
    /// `t[q][q']`: there is a transition from `q` to `q'` (for some input).
    t: Vec<Lit>,
    /// `p[j][i]` (`i < j`): state `i` is the BFS parent of state `j`.
    p: Vec<Lit>,
    /// `m[u][i][j]`: `u` is the smallest input on which `i` goes to `j`.
    m: Vec<Vec<Lit>>,
    /// `nm[u][i][j]`: no input smaller than `u` leads from `i` to `j` (`u` in `0..=U`).
    nm: Vec<Vec<Lit>>,
    /// Guards inside the encoding (see [`super::cubes`]); `None` in the tree-exact mode.
    pub cubes: Option<CubeVars>,
}

/// Variables of the cube-guard model: `slots` ordered transition slots per state, each with a
/// target and a guard that is a conjunction of literals over the `bits` input variables.
#[derive(Debug, Clone)]
pub struct CubeVars {
    pub slots: usize,
    pub bits: usize,
    /// `en[q][k]`: slot `k` of state `q` holds a transition.
    en: Vec<Lit>,
    /// `tgt[q][k][q']`: its target.
    tgt: Vec<Lit>,
    /// `pos[q][k][x]` / `neg[q][k][x]`: its guard contains `x` / `!x`.
    pos: Vec<Lit>,
    neg: Vec<Lit>,
    /// Per input vector `u`: `fire[u][q][k]` (the guard holds), `nf[u][q][k]` (no slot before
    /// `k` fires, `k` in `0..=slots`).
    fire: Vec<Vec<Lit>>,
    nf: Vec<Vec<Lit>>,
}

impl CubeVars {
    pub fn en(&self, q: usize, k: usize) -> Lit {
        self.en[q * self.slots + k]
    }
    pub fn tgt(&self, q: usize, k: usize, c_max: usize, t: usize) -> Lit {
        self.tgt[(q * self.slots + k) * c_max + t]
    }
    pub fn pos(&self, q: usize, k: usize, x: usize) -> Lit {
        self.pos[(q * self.slots + k) * self.bits + x]
    }
    pub fn neg(&self, q: usize, k: usize, x: usize) -> Lit {
        self.neg[(q * self.slots + k) * self.bits + x]
    }
    pub fn fire(&self, u: InputVec, q: usize, k: usize) -> Lit {
        self.fire[u.0][q * self.slots + k]
    }
    pub fn nf(&self, u: InputVec, q: usize, k: usize) -> Lit {
        self.nf[u.0][q * (self.slots + 1) + k]
    }
    pub fn all_en(&self) -> &[Lit] {
        &self.en
    }
    pub fn en_row(&self, q: usize) -> &[Lit] {
        &self.en[q * self.slots..(q + 1) * self.slots]
    }
    /// Every guard literal, for counting N.
    pub fn all_literals(&self) -> Vec<Lit> {
        self.pos.iter().chain(&self.neg).copied().collect()
    }
}

fn alloc(f: &mut impl ExtendFormula, n: usize) -> Vec<Lit> {
    (0..n).map(|_| f.new_lit()).collect()
}

impl Vars {
    /// `cube_slots`: `Some(k)` for the cube-guard model with `k` slots per state.
    pub fn new(
        f: &mut impl ExtendFormula,
        tree: &ScenarioTree,
        c_max: usize,
        cube_slots: Option<usize>,
    ) -> Vars {
        let nodes = tree.nodes.len();
        let outputs = tree.nodes[0].outputs.len();
        let mut v = Vars {
            c_max,
            nodes,
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
            cubes: cube_slots.map(|slots| {
                let bits = tree.input_vectors.first().map_or(0, Vec::len);
                CubeVars {
                    slots,
                    bits,
                    en: alloc(f, c_max * slots),
                    tgt: alloc(f, c_max * slots * c_max),
                    pos: alloc(f, c_max * slots * bits),
                    neg: alloc(f, c_max * slots * bits),
                    fire: Vec::new(),
                    nf: Vec::new(),
                }
            }),
        };
        for _ in 0..tree.input_vectors.len() {
            v.add_input(f);
        }
        v
    }

    /// Allocates the variables of one more input vector (index `self.inputs` before the call).
    pub fn add_input(&mut self, f: &mut impl ExtendFormula) -> InputVec {
        let c = self.c_max;
        self.y.push(alloc(f, c * (c + 1)));
        self.m.push(alloc(f, c * c));
        self.nm.push(alloc(f, c * c));
        if let Some(cv) = &mut self.cubes {
            cv.fire.push(alloc(f, c * cv.slots));
            cv.nf.push(alloc(f, c * (cv.slots + 1)));
        }
        self.inputs += 1;
        InputVec(self.inputs - 1)
    }

    /// Index of the `⊥` ("nothing fires") target.
    pub fn none(&self) -> usize {
        self.c_max
    }

    pub fn used(&self, q: usize) -> Lit {
        self.used[q]
    }
    pub fn color(&self, v: NodeId, q: usize) -> Lit {
        self.color[v.0 * self.c_max + q]
    }
    pub fn y(&self, q: usize, u: InputVec, target: usize) -> Lit {
        self.y[u.0][q * (self.c_max + 1) + target]
    }
    pub fn a0(&self, q: usize, z: usize) -> Lit {
        self.a0[q * self.outputs + z]
    }
    pub fn a1(&self, q: usize, z: usize) -> Lit {
        self.a1[q * self.outputs + z]
    }
    /// `a0` or `a1` by the old value of the output.
    pub fn a(&self, q: usize, z: usize, old: bool) -> Lit {
        if old {
            self.a1(q, z)
        } else {
            self.a0(q, z)
        }
    }
    pub fn t(&self, q: usize, target: usize) -> Lit {
        self.t[q * self.c_max + target]
    }
    pub fn p(&self, j: usize, i: usize) -> Lit {
        self.p[j * self.c_max + i]
    }
    pub fn m(&self, i: usize, u: InputVec, j: usize) -> Lit {
        self.m[u.0][i * self.c_max + j]
    }
    pub fn nm(&self, i: usize, u: usize, j: usize) -> Lit {
        self.nm[u][i * self.c_max + j]
    }
    /// All `t[q][q']` literals, for counting transitions.
    pub fn all_t(&self) -> &[Lit] {
        &self.t
    }
    /// `t[q][·]`, for counting the out-degree of `q`.
    pub fn t_row(&self, q: usize) -> &[Lit] {
        &self.t[q * self.c_max..(q + 1) * self.c_max]
    }
}
