//! The fitness function: `F = c1·F_ed + c2·F_fe + c3·F_sc + c4·F_sat + c5·F_ce`
//! (the metaheuristic paper, section IV.F; the verification-in-the-loop paper, section III.B).
//!
//! In: the scenarios, precomputed once into [`ScenarioData`] ([`super::data`]), a [`Machine`],
//! and for the verification terms the [`Verdicts`] of NuSMV.
//! Out: a [`ScenarioScore`] (the three scenario terms) and the weighted sum.
//!
//! The scenario terms, per scenario, averaged over scenarios:
//! - `F_ed = 1 - d / n`, with `d` the Levenshtein distance between the produced and the
//!   recorded sequences of `CNF` outputs (one symbol per `REQ`: the emitted output vector, or
//!   "no CNF") and `n` the number of steps;
//! - `F_fe = i / n` for the first step `i` where they differ (`1` without error);
//! - `F_sc = 1 - changes / steps`, over all scenarios, where a change is a step that enters a
//!   state other than the current one (the papers want fewer; they give no normalization).
//!
//! The verification terms: `F_sat` = share of properties that hold; `F_ce = 1` when all hold,
//! else `1 - 1/(1 + l/10)^(1/10)` with `l` the longest counterexample (the verification-in-the-loop paper).
//!
//! [`Evaluator::evaluate`] is the hot loop: it labels the states and replays every scenario on
//! buffers it owns, so an evaluation allocates nothing once the buffers have grown.

pub(crate) use super::data::{DataError, ScenarioData};
use super::data::{StepData, PASSIVE};
use super::labeling::{self, Counts};
use super::machine::Machine;
use crate::ecc::Tri;
use crate::scenario::negative::NegativeScenario;

/// The scenario terms of one machine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScenarioScore {
    /// `F_ed`: one minus the normalized edit distance of the `CNF` outputs, in `[0, 1]`.
    pub ed: f64,
    /// `F_fe`: how far into each scenario the first wrong output comes, in `[0, 1]`.
    pub(crate) fe: f64,
    /// `F_sc`: one minus the share of steps that change state, in `[0, 1]`.
    pub(crate) sc: f64,
    /// Scenarios reproduced exactly.
    pub(crate) reproduced: usize,
    /// Number of (non-empty) scenarios scored.
    pub(crate) scenarios: usize,
}

impl ScenarioScore {
    /// Every scenario reproduced exactly.
    pub(crate) fn perfect(&self) -> bool {
        self.reproduced == self.scenarios
    }
}

/// What NuSMV said about a candidate, reduced to what the search uses.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub(crate) struct Verdicts {
    /// Number of properties that hold.
    pub(crate) satisfied: usize,
    /// Number of properties checked.
    pub(crate) total: usize,
    /// Longest counterexample (states of the lasso); 0 when every property holds.
    pub(crate) longest_counterexample: usize,
    /// Controller input vectors (bit masks) of every counterexample, for the weighted
    /// mutation.
    pub(crate) counterexamples: Vec<Vec<u32>>,
    /// The counterexamples seen from the controller. A machine that still follows one of
    /// them violates its property for sure, without asking NuSMV.
    pub(crate) negatives: Vec<NegativeScenario>,
}

impl Verdicts {
    /// Whether every property holds (also without properties).
    pub(crate) fn all_hold(&self) -> bool {
        self.satisfied == self.total
    }

    /// `F_sat`: the share of properties that hold (1 without properties).
    pub(crate) fn f_sat(&self) -> f64 {
        if self.total == 0 {
            1.0
        } else {
            self.satisfied as f64 / self.total as f64
        }
    }

    /// `F_ce` of the verification-in-the-loop paper.
    pub(crate) fn f_ce(&self) -> f64 {
        f_ce(if self.all_hold() {
            0
        } else {
            self.longest_counterexample.max(1)
        })
    }
}

/// The verification-in-the-loop paper: `1` for `l_max = 0`, else `1 - 1/(1 + l_max/10)^(1/10)`, increasing in `l_max`.
pub(crate) fn f_ce(l_max: usize) -> f64 {
    if l_max == 0 {
        1.0
    } else {
        1.0 - 1.0 / (1.0 + l_max as f64 / 10.0).powf(0.1)
    }
}

/// The constants `c1..c5`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weights {
    /// `c1`, the weight of `F_ed`.
    pub ed: f64,
    /// `c2`, the weight of `F_fe`.
    pub(crate) fe: f64,
    /// `c3`, the weight of `F_sc`.
    pub(crate) sc: f64,
    /// `c4`, the weight of `F_sat`.
    pub(crate) sat: f64,
    /// `c5`, the weight of `F_ce`.
    pub(crate) ce: f64,
}

impl Default for Weights {
    /// The metaheuristic paper's `0.9, 0.1, 0.0001`. The verification-in-the-loop paper gives no values for `c4, c5`, only that every
    /// ECC above `1.1` satisfies everything; `c4 = 0.1, c5 = 0.01` put a machine with all
    /// properties (`F_sat = F_ce = 1`) above every machine with a violated one once the
    /// scenarios are reproduced.
    fn default() -> Self {
        Weights {
            ed: 0.9,
            fe: 0.1,
            sc: 0.0001,
            sat: 0.1,
            ce: 0.01,
        }
    }
}

impl Weights {
    /// `c1·F_ed + c2·F_fe + c3·F_sc`.
    pub(crate) fn scenario_part(&self, s: &ScenarioScore) -> f64 {
        self.ed * s.ed + self.fe * s.fe + self.sc * s.sc
    }

    /// Largest possible scenario part.
    pub(crate) fn scenario_max(&self) -> f64 {
        self.ed + self.fe + self.sc
    }

    /// `c4·F_sat + c5·F_ce` (0 without verdicts).
    pub(crate) fn verification_part(&self, v: Option<&Verdicts>) -> f64 {
        v.map_or(0.0, |v| self.sat * v.f_sat() + self.ce * v.f_ce())
    }

    /// The whole fitness.
    pub(crate) fn total(&self, s: &ScenarioScore, v: Option<&Verdicts>) -> f64 {
        self.scenario_part(s) + self.verification_part(v)
    }
}

/// Where a scenario the machine fails first goes wrong: the step (index into
/// [`ScenarioData`]'s steps) and the state the machine is in before it. The repair mutation
/// ([`super::operators::repair`]) acts there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Divergence {
    /// The scenario (index into [`ScenarioData`]'s bounds).
    pub(crate) scenario: usize,
    /// The first wrong step, as an index into all steps.
    pub(crate) step: usize,
    /// The state before that step.
    pub(crate) state: usize,
}

/// Computes scenario scores; owns every buffer the hot loop needs.
#[derive(Debug)]
pub struct Evaluator<'a> {
    data: &'a ScenarioData,
    path: Vec<u32>,
    divergences: Vec<Divergence>,
    counts: Vec<Counts>,
    /// Per state: (outputs set to 0, outputs set to 1).
    masks: Vec<(u32, u32)>,
    produced: Vec<u32>,
    row: Vec<u32>,
}

impl<'a> Evaluator<'a> {
    /// An evaluator over `data` with empty buffers (they grow on the first evaluations).
    pub fn new(data: &'a ScenarioData) -> Evaluator<'a> {
        Evaluator {
            data,
            path: Vec::with_capacity(data.steps.len()),
            divergences: Vec::new(),
            counts: Vec::new(),
            masks: Vec::new(),
            produced: Vec::new(),
            row: Vec::new(),
        }
    }

    /// The scenarios this evaluator scores against.
    pub(crate) fn data(&self) -> &'a ScenarioData {
        self.data
    }

    /// Labels the states and scores `m` on every scenario.
    pub fn evaluate(&mut self, m: &Machine) -> ScenarioScore {
        let data = self.data;
        let z = data.outputs.len();
        labeling::run(m, data, &mut self.path, &mut self.counts);
        self.masks.clear();
        for s in 0..m.states.len() {
            let (mut zero, mut one) = (0u32, 0u32);
            for (j, &c) in self.counts[s * z..(s + 1) * z].iter().enumerate() {
                match labeling::decide(c) {
                    Tri::Zero => zero |= 1 << j,
                    Tri::One => one |= 1 << j,
                    Tri::Keep => {}
                }
            }
            self.masks.push((zero, one));
        }
        let (mut ed, mut fe, mut reproduced, mut changes) = (0.0, 0.0, 0, 0usize);
        self.divergences.clear();
        for (k, range) in data.bounds.iter().enumerate() {
            let steps = &data.steps[range.clone()];
            let path = &self.path[range.clone()];
            self.produced.clear();
            let mut out = data.initial;
            let mut state = 0u32;
            for &p in path {
                if p == u32::MAX {
                    self.produced.push(PASSIVE);
                } else {
                    if p != state {
                        changes += 1;
                        state = p;
                    }
                    let (zero, one) = self.masks[p as usize];
                    out = (out & !zero) | one;
                    self.produced.push(out);
                }
            }
            let n = steps.len();
            let first = steps
                .iter()
                .zip(&self.produced)
                .position(|(s, &p)| s.expected != p);
            match first {
                None => {
                    reproduced += 1;
                    ed += 1.0;
                    fe += 1.0;
                }
                Some(i) => {
                    let state = path[..i].iter().rev().find(|&&p| p != u32::MAX);
                    self.divergences.push(Divergence {
                        scenario: k,
                        step: range.start + i,
                        state: state.map_or(0, |&p| p as usize),
                    });
                    let d = if data.peq[k].is_empty() {
                        levenshtein(&self.produced[i..], &steps[i..], &mut self.row)
                    } else {
                        myers(&self.produced, &data.peq[k], n)
                    };
                    ed += 1.0 - d as f64 / n as f64;
                    fe += i as f64 / n as f64;
                }
            }
        }
        let k = data.bounds.len() as f64;
        ScenarioScore {
            ed: ed / k,
            fe: fe / k,
            sc: 1.0 - changes as f64 / data.steps.len() as f64,
            reproduced,
            scenarios: data.bounds.len(),
        }
    }

    /// The first divergence of every scenario the last evaluated machine fails, in scenario
    /// order.
    pub(crate) fn divergences(&self) -> &[Divergence] {
        &self.divergences
    }

    /// Per state of the last evaluated machine: the outputs its labeled algorithm sets to 0
    /// and those it sets to 1, as bit masks.
    pub(crate) fn label_masks(&self) -> &[(u32, u32)] {
        &self.masks
    }

    /// The labeled algorithms of the last evaluated machine, one `{0,1,x}` string per state.
    pub(crate) fn algorithms(&self) -> Vec<Vec<Tri>> {
        let z = self.data.outputs.len();
        self.masks
            .iter()
            .map(|&(zero, one)| {
                (0..z)
                    .map(|j| {
                        if zero >> j & 1 == 1 {
                            Tri::Zero
                        } else if one >> j & 1 == 1 {
                            Tri::One
                        } else {
                            Tri::Keep
                        }
                    })
                    .collect()
            })
            .collect()
    }
}

/// Levenshtein distance between `text` and a recorded pattern of `m <= 128` symbols given by
/// its match masks, by Myers' bit-parallel algorithm (Hyyrö's formulation for the global
/// distance): one column of the distance matrix per text symbol, as two bit vectors of
/// vertical +1/-1 deltas.
fn myers(text: &[u32], peq: &[(u32, u128)], m: usize) -> usize {
    debug_assert!((1..=128).contains(&m));
    let high = 1u128 << (m - 1);
    let (mut pv, mut mv) = (!0u128, 0u128);
    let mut score = m;
    for &c in text {
        let eq = peq.iter().find(|(s, _)| *s == c).map_or(0, |&(_, e)| e);
        let xv = eq | mv;
        let xh = ((eq & pv).wrapping_add(pv) ^ pv) | eq;
        let mut ph = mv | !(xh | pv);
        let mut mh = pv & xh;
        if ph & high != 0 {
            score += 1;
        } else if mh & high != 0 {
            score -= 1;
        }
        // Row 0 of the matrix grows by one per text symbol: a +1 shifts in.
        ph = (ph << 1) | 1;
        mh <<= 1;
        pv = mh | !(xv | ph);
        mv = ph & xv;
    }
    score
}

/// Levenshtein distance between the produced symbols and the recorded ones, with one reused
/// row. The common suffix is stripped first (the common prefix is stripped by the caller).
fn levenshtein(a: &[u32], b: &[StepData], row: &mut Vec<u32>) -> usize {
    let mut n = a.len();
    let mut m = b.len();
    while n > 0 && m > 0 && a[n - 1] == b[m - 1].expected {
        n -= 1;
        m -= 1;
    }
    let (a, b) = (&a[..n], &b[..m]);
    if n == 0 || m == 0 {
        return n.max(m);
    }
    row.clear();
    row.extend(0..=m as u32);
    for (i, &ca) in a.iter().enumerate() {
        let mut diag = row[0];
        row[0] = i as u32 + 1;
        for j in 0..m {
            let up = row[j + 1];
            let cost = u32::from(ca != b[j].expected);
            row[j + 1] = (diag + cost).min(up + 1).min(row[j] + 1);
            diag = up;
        }
    }
    row[m] as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::{InputId, StateId};
    use crate::scenario::{Origin, Scenario, ScenarioSet, Step};
    use crate::search::machine::{Group, SearchState};

    fn sd(expected: &[u32]) -> Vec<StepData> {
        expected
            .iter()
            .map(|&e| StepData {
                x: 0,
                expected: e,
                before: 0,
            })
            .collect()
    }

    #[test]
    fn levenshtein_distances() {
        let mut row = Vec::new();
        assert_eq!(levenshtein(&[1, 2, 3], &sd(&[1, 2, 3]), &mut row), 0);
        assert_eq!(levenshtein(&[1, 2, 3], &sd(&[1, 3]), &mut row), 1);
        assert_eq!(levenshtein(&[7, 1, 2], &sd(&[1, 2, 9]), &mut row), 2);
        assert_eq!(levenshtein(&[], &sd(&[1, 2]), &mut row), 2);
        // kitten -> sitting
        let k: Vec<u32> = "kitten".bytes().map(u32::from).collect();
        let s: Vec<u32> = "sitting".bytes().map(u32::from).collect();
        assert_eq!(levenshtein(&k, &sd(&s), &mut row), 3);
    }

    #[test]
    fn bit_parallel_distance_agrees_with_the_table() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let mut row = Vec::new();
        for _ in 0..2000 {
            let m = rng.gen_range(1..=128);
            let n = rng.gen_range(0..=140);
            let b: Vec<u32> = (0..m).map(|_| rng.gen_range(0..4)).collect();
            let a: Vec<u32> = (0..n).map(|_| rng.gen_range(0..4)).collect();
            let mut peq: Vec<(u32, u128)> = Vec::new();
            for (j, &c) in b.iter().enumerate() {
                match peq.iter_mut().find(|(s, _)| *s == c) {
                    Some((_, x)) => *x |= 1 << j,
                    None => peq.push((c, 1 << j)),
                }
            }
            assert_eq!(
                myers(&a, &peq, m),
                levenshtein(&a, &sd(&b), &mut row),
                "{a:?} {b:?}"
            );
        }
    }

    #[test]
    fn counterexample_term() {
        assert_eq!(f_ce(0), 1.0);
        assert!(f_ce(1) > 0.0 && f_ce(1) < f_ce(10) && f_ce(10) < f_ce(1000));
        assert!((f_ce(10) - (1.0 - 1.0 / 2f64.powf(0.1))).abs() < 1e-12);
        let v = Verdicts {
            satisfied: 2,
            total: 3,
            longest_counterexample: 10,
            ..Verdicts::default()
        };
        assert!((v.f_sat() - 2.0 / 3.0).abs() < 1e-12);
        assert_eq!(v.f_ce(), f_ce(10));
        let w = Weights::default();
        let perfect = ScenarioScore {
            ed: 1.0,
            fe: 1.0,
            sc: 1.0,
            reproduced: 1,
            scenarios: 1,
        };
        let all = Verdicts {
            satisfied: 3,
            total: 3,
            ..Verdicts::default()
        };
        assert!((w.total(&perfect, Some(&all)) - 1.1101).abs() < 1e-12);
        assert!(w.total(&perfect, Some(&v)) < 1.1);
    }

    /// One input `b`, one output `lamp`; recorded: lamp follows b, with CNF on every step.
    fn follow() -> ScenarioData {
        let steps = [true, true, false, true, false, false]
            .iter()
            .map(|&b| Step {
                inputs: vec![b],
                outputs: Some(vec![b]),
            })
            .collect();
        let set = ScenarioSet {
            inputs: vec!["b".into()],
            outputs: vec!["lamp".into()],
            initial_outputs: vec![false],
            scenarios: vec![Scenario {
                origin: Origin {
                    file: "t".into(),
                    line: 1,
                    rows: None,
                },
                steps,
            }],
        };
        ScenarioData::new(&set).unwrap()
    }

    fn two_states(on_b: usize, on_not_b: usize) -> Machine {
        let mut g0 = Group::empty(vec![InputId(0)]);
        g0.table = vec![Some(StateId(on_not_b)), Some(StateId(on_b))];
        let g1 = g0.clone();
        Machine {
            inputs: 1,
            states: vec![
                SearchState { groups: vec![g0] },
                SearchState { groups: vec![g1] },
            ],
        }
    }

    #[test]
    fn scenario_terms() {
        let data = follow();
        let mut ev = Evaluator::new(&data);
        // Correct: s1 = lamp on, s0 = lamp off. Changes at steps 0, 2, 3, 4 of 6.
        let good = ev.evaluate(&two_states(1, 0));
        assert!(good.perfect());
        assert_eq!((good.ed, good.fe), (1.0, 1.0));
        assert!((good.sc - (1.0 - 4.0 / 6.0)).abs() < 1e-12);
        assert_eq!(ev.algorithms(), vec![vec![Tri::Zero], vec![Tri::One]]);
        // Never leaves s0: 2 rises, 2 falls, one stay each; `0` and `1` tie at 3, `0` wins,
        // so the lamp stays 0: produced 0 0 0 0 0 0 vs 1 1 0 1 0 0.
        let stuck = ev.evaluate(&two_states(0, 0));
        assert!(!stuck.perfect());
        assert_eq!(stuck.fe, 0.0);
        assert!((stuck.ed - (1.0 - 3.0 / 6.0)).abs() < 1e-12);
        assert_eq!(stuck.sc, 1.0);
        // Passive everywhere: produced "no CNF" six times, distance 6.
        let mut silent = two_states(0, 0);
        silent.states[0].groups.clear();
        let s = ev.evaluate(&silent);
        assert_eq!((s.ed, s.fe), (0.0, 0.0));
    }
}
