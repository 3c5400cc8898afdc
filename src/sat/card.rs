//! Cardinality constraints: the totalizer encoding (Bailleux and Boufkhad, 2003).
//!
//! For inputs `x_1..x_n` the totalizer builds unary outputs `o_1..o_n` with
//! `(x_1 + ... + x_n >= k) -> o_k`. Only this direction is encoded, which is all an upper bound
//! needs: assuming `!o_{b+1}` forces at most `b` inputs true. Bounds are therefore passed as
//! solver *assumptions*, so one solver serves every bound of a minimization loop.

use varisat::{ExtendFormula, Lit};

/// Unary counter over a set of literals.
#[derive(Debug, Clone)]
pub(crate) struct Totalizer {
    /// `outputs[k-1]` is implied when at least `k` inputs are true.
    outputs: Vec<Lit>,
}

impl Totalizer {
    /// Encodes a totalizer over `inputs`, counting up to `limit` (outputs above it are not
    /// built; a bound `b >= limit` then constrains nothing).
    pub(crate) fn new(f: &mut impl ExtendFormula, inputs: &[Lit], limit: usize) -> Totalizer {
        let outputs = build(f, inputs, limit.max(1));
        Totalizer { outputs }
    }

    /// The assumption that at most `bound` inputs are true, or `None` if the counter cannot
    /// exceed `bound` anyway.
    pub(crate) fn at_most(&self, bound: usize) -> Option<Lit> {
        self.outputs.get(bound).map(|&o| !o)
    }

    /// Number of outputs built.
    pub(crate) fn width(&self) -> usize {
        self.outputs.len()
    }
}

fn build(f: &mut impl ExtendFormula, inputs: &[Lit], limit: usize) -> Vec<Lit> {
    if inputs.len() <= 1 {
        return inputs.to_vec();
    }
    let (l, r) = inputs.split_at(inputs.len() / 2);
    let left = build(f, l, limit);
    let right = build(f, r, limit);
    let width = (left.len() + right.len()).min(limit + 1);
    let out: Vec<Lit> = (0..width).map(|_| f.new_lit()).collect();
    // left >= i and right >= j  ->  out >= i + j   (i, j = 0 meaning "no premise")
    for i in 0..=left.len() {
        for j in 0..=right.len() {
            let sum = i + j;
            if sum == 0 || sum > width {
                continue;
            }
            let mut clause = vec![out[sum - 1]];
            if i > 0 {
                clause.push(!left[i - 1]);
            }
            if j > 0 {
                clause.push(!right[j - 1]);
            }
            f.add_clause(&clause);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use varisat::{CnfFormula, Solver};

    /// Exhaustive over every assignment of 5 inputs and every bound: the totalizer with the
    /// bound assumed is satisfiable exactly when the assignment has at most `bound` ones.
    #[test]
    fn totalizer_is_exact_for_every_assignment() {
        for limit in [2usize, 5] {
            let mut f = CnfFormula::new();
            let xs: Vec<Lit> = (0..5).map(|_| f.new_lit()).collect();
            let tot = Totalizer::new(&mut f, &xs, limit);
            for mask in 0u32..32 {
                for bound in 0..=5usize {
                    let mut s = Solver::new();
                    s.add_formula(&f);
                    let mut assume: Vec<Lit> = xs
                        .iter()
                        .enumerate()
                        .map(|(i, &x)| if mask >> i & 1 == 1 { x } else { !x })
                        .collect();
                    assume.extend(tot.at_most(bound));
                    s.assume(&assume);
                    let ones = mask.count_ones() as usize;
                    let expect = ones <= bound || bound >= tot.width();
                    assert_eq!(
                        s.solve().unwrap(),
                        expect,
                        "limit {limit} mask {mask:05b} bound {bound}"
                    );
                }
            }
        }
    }
}
