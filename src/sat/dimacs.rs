//! The size questions around a minimum as DIMACS CNF, for any other SAT solver to check the
//! minimum (`synth infer --dump-cnf`).
//!
//! In: the scenario tree, the options of the synthesis and the least machine's size. Out: the
//! [`Question`]s "at most C states" (satisfiable) and "at most C - 1" (not), and with C
//! states "at most T transitions" (satisfiable) and "at most T - 1" (not), each a whole CNF
//! formula ([`super::basic::formula`]) answered by a fresh solver on exactly that formula.

use super::basic::{formula, Options};
use super::solver::Solver;
use crate::ecc::Size;
use crate::scenario::tree::ScenarioTree;
use varisat::{CnfFormula, ExtendFormula};

/// One size question and its answer.
pub(crate) struct Question {
    /// Its file name: `states-<C>.cnf` or `transitions-<T>.cnf`.
    pub(crate) name: String,
    /// The formula, every bound a unit clause.
    pub(crate) formula: CnfFormula,
    /// Whether it is satisfiable.
    pub(crate) satisfiable: bool,
}

impl Question {
    /// The formula in DIMACS CNF.
    pub(crate) fn dimacs(&self) -> Vec<u8> {
        let mut text = Vec::new();
        varisat::dimacs::write_dimacs(&mut text, &self.formula)
            .expect("writing into memory does not fail");
        text
    }

    /// Its line of `verdicts.txt`: the name and `SATISFIABLE` or `UNSATISFIABLE`.
    pub(crate) fn verdict_line(&self) -> String {
        let verdict = match self.satisfiable {
            true => "SATISFIABLE",
            false => "UNSATISFIABLE",
        };
        format!("{} {verdict}\n", self.name)
    }
}

/// The questions around `size`, the least machine's for `tree` (module documentation).
pub(crate) fn size_questions(tree: &ScenarioTree, opts: &Options, size: &Size) -> Vec<Question> {
    let mut asked = vec![(format!("states-{}.cnf", size.c), size.c, None)];
    if size.c > 1 {
        asked.push((format!("states-{}.cnf", size.c - 1), size.c - 1, None));
    }
    asked.push((format!("transitions-{}.cnf", size.t), size.c, Some(size.t)));
    if size.t > 0 {
        asked.push((
            format!("transitions-{}.cnf", size.t - 1),
            size.c,
            Some(size.t - 1),
        ));
    }
    asked
        .into_iter()
        .map(|(name, c, t)| {
            let formula = formula(tree, opts, c, t);
            Question {
                satisfiable: answer(&formula),
                name,
                formula,
            }
        })
        .collect()
}

/// A fresh solver's answer on `formula` alone.
fn answer(formula: &CnfFormula) -> bool {
    let mut solver = Solver::new();
    for _ in 0..formula.var_count() {
        solver.new_var();
    }
    for clause in formula.iter() {
        solver.add_clause(clause);
    }
    solver.solve(&[]).is_some()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::fbsat;
    use std::path::Path;

    /// A toggle's least machine: the questions at its size are satisfiable, one below not.
    #[test]
    fn the_questions_around_the_minimum_say_sat_at_it_and_unsat_below() {
        let text = "1\nin=REQ[1]; out=CNF[1]; in=REQ[0]; in=REQ[1]; out=CNF[0]; in=REQ[0]; in=REQ[1]; out=CNF[1];\n";
        let set = fbsat::parse(Path::new("toggle.txt"), text, None, None).unwrap();
        let tree = ScenarioTree::build(&set).unwrap();
        let opts = Options::default();
        let least = crate::sat::synthesize(&set, &tree, &opts, &mut |_| {}).unwrap();
        let qs = size_questions(&tree, &opts, &least.size);
        let verdicts: Vec<(String, bool)> =
            qs.iter().map(|q| (q.name.clone(), q.satisfiable)).collect();
        let s = least.size;
        let mut want = vec![(format!("states-{}.cnf", s.c), true)];
        if s.c > 1 {
            want.push((format!("states-{}.cnf", s.c - 1), false));
        }
        want.push((format!("transitions-{}.cnf", s.t), true));
        if s.t > 0 {
            want.push((format!("transitions-{}.cnf", s.t - 1), false));
        }
        assert_eq!(verdicts, want);
        let dimacs = String::from_utf8(qs[0].dimacs()).unwrap();
        assert!(dimacs.starts_with("p cnf "), "{dimacs}");
        assert_eq!(
            qs[0].verdict_line(),
            format!("states-{}.cnf SATISFIABLE\n", s.c)
        );
    }
}
