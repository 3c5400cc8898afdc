//! Models that put the plant to the test before any controller exists: whether it accepts
//! every output a controller can give ([`receptiveness`]), and whether it can produce the
//! recorded inputs under the recorded outputs ([`replay`]).
//!
//! In: the [`Plant`] and its [`Coupling`] (and, for [`replay`], the recorded runs as
//! [`Replayed`] states). Out: SMV text: the plant file verbatim (so NuSMV's lines in it are the
//! file's), then a generated `MODULE main`. Only generated names and names that passed the
//! coupling check reach it.
//!
//! # Receptiveness
//! `MODULE main` gives every controller output the plant reads two free variables: `_o_y`,
//! the output of this step (the plant's parameter), and `_p_y`, the output of the next one
//! (`next(_o_y) := _p_y`). Every reachable plant state thus appears with every value of the
//! outputs and of the next outputs, and the plant is receptive exactly when each such state
//! has a successor: NuSMV's `check_fsm` answers that, and its deadlock state names the plant
//! state (`plant.*`), the outputs it read (`_o_*`) and the outputs it refuses (`_p_*`).
//!
//! # Replay
//! The recorded runs, one after the other, are states `0..` of a counter `_g` (a run of `n`
//! steps takes `n + 1` states, as in [`crate::pipeline::explain`]): state `i < n` of a run is
//! step `i + 1`'s inputs with the outputs before it, state `n` the outputs after the last
//! step. `_g` starts at the first state of any run and counts up to its last, where it stays;
//! the plant reads the recorded outputs of state `_g`, and every transition out of a state
//! that is not the last of its run requires the plant's values to be the recorded inputs. The
//! last state of run `j` is reachable exactly when the plant can produce run `j`.

use super::bool_literal;
use super::composition::{Coupling, PLANT_INSTANCE};
use super::plant::Plant;
use std::fmt::Write;

/// The receptiveness model of `plant` (see the module header).
pub(crate) fn receptiveness(plant: &Plant, coupling: &Coupling) -> String {
    let mut text = plant_text(plant);
    text.push_str(
        "\n-- every output the controller can give, now (_o_) and next (_p_)\nMODULE main\nVAR\n",
    );
    let params: Vec<&str> = (coupling.params.iter())
        .map(|&z| coupling.outputs[z].as_str())
        .collect();
    for y in &params {
        let _ = writeln!(text, "  _o_{y} : boolean;\n  _p_{y} : boolean;");
    }
    let args: Vec<String> = params.iter().map(|y| format!("_o_{y}")).collect();
    let _ = writeln!(text, "  {PLANT_INSTANCE} : plant({});", args.join(", "));
    if !params.is_empty() {
        text.push_str("ASSIGN\n");
        for y in &params {
            let _ = writeln!(text, "  next(_o_{y}) := _p_{y};");
        }
    }
    text
}

/// One state of a recorded run: the outputs in force (interface order) and the inputs
/// recorded (interface order; `None` for a run's last state).
pub(crate) type RecordedState = (Vec<bool>, Option<Vec<bool>>);

/// The recorded runs as the replay model reads them: per run, its states (see the module
/// header), each with the controller outputs in force and the inputs recorded (`None` for
/// the last state, whose inputs nobody recorded).
pub(crate) struct Replayed {
    /// Per run, per state: the outputs (interface order) and the inputs (interface order).
    pub(crate) runs: Vec<Vec<RecordedState>>,
}

impl Replayed {
    /// The index of the last state of each run in the counter `_g`.
    pub(crate) fn last_states(&self) -> Vec<usize> {
        let mut g = 0;
        (self.runs.iter())
            .map(|r| {
                g += r.len();
                g - 1
            })
            .collect()
    }
}

/// The replay model of `plant` over `runs` (see the module header).
pub(crate) fn replay(plant: &Plant, coupling: &Coupling, runs: &Replayed) -> String {
    let states: Vec<&RecordedState> = runs.runs.iter().flatten().collect();
    let lasts = runs.last_states();
    let firsts: Vec<usize> = std::iter::once(0)
        .chain(lasts.iter().map(|l| l + 1))
        .take(lasts.len())
        .collect();
    let mut text = plant_text(plant);
    text.push_str("\n-- the recorded runs, one state after the other\nMODULE main\nVAR\n");
    let _ = writeln!(text, "  _g : 0..{};", states.len().saturating_sub(1));
    let args: Vec<String> = (coupling.params.iter())
        .map(|&z| format!("_o_{}", coupling.outputs[z]))
        .collect();
    let _ = writeln!(text, "  {PLANT_INSTANCE} : plant({});", args.join(", "));
    let _ = writeln!(text, "DEFINE\n  _last := {};", any_of("_g", &lasts));
    for &z in &coupling.params {
        let column: Vec<bool> = states.iter().map(|(o, _)| o[z]).collect();
        let _ = writeln!(
            text,
            "  _o_{} := {};",
            coupling.outputs[z],
            steps_of(&column)
        );
    }
    let mut matches = Vec::new();
    for (x, name) in coupling.inputs.iter().enumerate() {
        // The last state's value is never read (its transitions need no match).
        let column: Vec<bool> = (states.iter())
            .map(|(_, i)| i.as_ref().is_some_and(|i| i[x]))
            .collect();
        let _ = writeln!(text, "  _i_{name} := {};", steps_of(&column));
        let sensor = &coupling.sensors[x];
        matches.push(format!("({PLANT_INSTANCE}.{sensor} <-> _i_{name})"));
    }
    let _ = writeln!(
        text,
        "ASSIGN\n  init(_g) := {{{}}};\n  next(_g) := _last ? _g : _g + 1;",
        firsts
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    );
    if !matches.is_empty() {
        let _ = writeln!(text, "TRANS !_last -> ({})", matches.join(" & "));
    }
    text
}

/// The plant file, ending with a line break.
fn plant_text(plant: &Plant) -> String {
    let mut text = plant.text.clone();
    if !text.ends_with('\n') {
        text.push('\n');
    }
    text
}

/// `(var = a | var = b ...)`, or `FALSE` for none.
fn any_of(var: &str, values: &[usize]) -> String {
    match values {
        [] => "FALSE".into(),
        _ => {
            let all: Vec<String> = values.iter().map(|v| format!("{var} = {v}")).collect();
            format!("({})", all.join(" | "))
        }
    }
}

/// A Boolean column over `_g` as a `case` of ranges: one branch per run of equal values.
fn steps_of(column: &[bool]) -> String {
    let mut branches = String::from("case");
    let mut g = 0;
    while g < column.len() {
        let v = column[g];
        let mut end = g;
        while end + 1 < column.len() && column[end + 1] == v {
            end += 1;
        }
        match end + 1 == column.len() {
            true => {
                let _ = write!(branches, " TRUE : {};", bool_literal(v));
            }
            false => {
                let _ = write!(branches, " _g <= {end} : {};", bool_literal(v));
            }
        }
        g = end + 1;
    }
    if column.is_empty() {
        branches.push_str(" TRUE : FALSE;");
    }
    branches + " esac"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_column_is_one_branch_per_run_of_equal_values() {
        assert_eq!(
            steps_of(&[true, true, false, true]),
            "case _g <= 1 : TRUE; _g <= 2 : FALSE; TRUE : TRUE; esac"
        );
        assert_eq!(steps_of(&[false]), "case TRUE : FALSE; esac");
    }

    #[test]
    fn runs_follow_one_another_on_the_counter() {
        let state = |o: bool| (vec![o], Some(vec![o]));
        let runs = Replayed {
            runs: vec![vec![state(false), (vec![true], None)], vec![state(true)]],
        };
        assert_eq!(runs.last_states(), vec![1, 2]);
    }
}
