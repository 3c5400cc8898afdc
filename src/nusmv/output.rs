//! Parsing what NuSMV prints.
//!
//! In: NuSMV 2.5.4's stdout after LTL checks (a batch run, or one model's part of an `-int`
//! dialogue) and its stderr. Out: [`PropertyResult`]s with full-state [`Trace`]s, and
//! [`ModelError`]s with file and line. The grammar is `grammar/nusmv_output.pest`; no pest type
//! leaves this module.
//!
//! NuSMV's default trace printer lists every variable in the first state and afterwards only
//! the values that changed, for states and for inputs alike; [`parse_output`] carries values
//! forward so that every state and input of a [`Trace`] is complete.

use pest::iterators::Pair;
use pest::Parser;
use std::collections::BTreeMap;
use std::fmt;

// The parser and its `Rule` enum stay private: no pest type leaves this module.
mod parser {
    #[derive(pest_derive::Parser)]
    #[grammar = "../grammar/nusmv_output.pest"]
    pub(super) struct OutputGrammar;
}
use parser::{OutputGrammar, Rule};

/// The verdict on one property, as NuSMV printed it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PropertyResult {
    /// The property's name: the name a [`Dialogue`](super::Dialogue) asked for it by, or the
    /// one its verdict line printed (`set prop_print_method name` prints `'name'`); `None`
    /// otherwise (the default print method prints the formula).
    pub name: Option<String>,
    /// What NuSMV printed in place of the property: its reprint of the formula (not the text
    /// of the model file), or `'name'` / `[index]` under the `name` / `index` print methods.
    pub(crate) formula: String,
    /// The whole verdict line, `-- specification ... is true|false`, without the newline.
    pub(crate) verdict_line: String,
    /// Whether the property holds, with the counterexample when it does not.
    pub verdict: Verdict,
}

/// Whether a property holds on the model.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Verdict {
    /// NuSMV printed `is true`: the property holds on every fair path of the model.
    Holds,
    /// The property is false; the counterexample when NuSMV printed one (it does not with
    /// the `EL_fwd` emptiness algorithm).
    Violated(Option<Trace>),
}

/// A counterexample: a finite path whose last state repeats an earlier one (a lasso).
///
/// Step `k` (0-based here; NuSMV prints `N.(k+1)`) is `inputs[k]` followed by `states[k]`:
/// `inputs[k]` is the input read on the transition from `states[k-1]` into `states[k]`.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Trace {
    /// Every state with all its variables and DEFINEs (values carried forward).
    pub states: Vec<BTreeMap<String, String>>,
    /// The input section printed before each state, all IVARs carried forward; empty for
    /// `k = 0` and for models without IVARs.
    pub(crate) inputs: Vec<BTreeMap<String, String>>,
    /// Indices of the states preceded by `-- Loop starts here`. NuSMV marks every earlier
    /// state equal to the last one, so several entries are normal, and not every one of them
    /// need violate the property.
    pub(crate) loop_starts: Vec<usize>,
}

/// One error NuSMV reported about the model on stderr.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModelError {
    /// The file as NuSMV named it (as it was given on its command line or to `read_model`;
    /// `<command-line>` for a formula given with `check_ltlspec -p`).
    pub file: String,
    /// 1-based line in `file`.
    pub(crate) line: usize,
    /// The rest of NuSMV's message, e.g. `case conditions are not exhaustive`.
    pub(crate) message: String,
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // NuSMV quotes the token it choked on, however long the plant file made it.
        let message = crate::quote::message(&self.message);
        write!(f, "{}:{}: {message}", self.file, self.line)
    }
}

/// NuSMV printed something [`parse_output`] does not understand.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}, column {column}: {message}")]
pub struct OutputParseError {
    /// 1-based line of the parsed text.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
    /// What is wrong there: what the grammar expected, or an inconsistency such as an input
    /// section without a following state.
    pub(crate) message: String,
}

/// Parses NuSMV's stdout: banner, prompts (`NuSMV > `), verdict lines and traces. Any other
/// line is an error, so that nothing NuSMV says is silently dropped.
pub fn parse_output(stdout: &str) -> Result<Vec<PropertyResult>, OutputParseError> {
    let mut pairs = OutputGrammar::parse(Rule::output, stdout).map_err(|e| {
        let (line, column) = match e.line_col {
            pest::error::LineColLocation::Pos(p) => p,
            pest::error::LineColLocation::Span(p, _) => p,
        };
        OutputParseError {
            line,
            column,
            message: e.variant.message().into_owned(),
        }
    })?;
    let output = pairs
        .next()
        .expect("the grammar's top rule always yields one pair");
    output
        .into_inner()
        .filter(|p| p.as_rule() == Rule::property)
        .map(property)
        .collect()
}

fn property(pair: Pair<'_, Rule>) -> Result<PropertyResult, OutputParseError> {
    let pos = pair.as_span().start_pos().line_col();
    let mut inner = pair.into_inner();
    let line = inner
        .next()
        .expect("a property starts with its verdict line");
    let verdict_line = line.as_str().trim_end_matches(['\n', '\r']).to_string();
    let mut formula = String::new();
    let mut holds = false;
    for part in line.into_inner() {
        match part.as_rule() {
            Rule::printed => formula = part.as_str().to_string(),
            Rule::verdict => holds = part.as_str() == "true",
            _ => unreachable!("verdict_line holds only printed and verdict"),
        }
    }
    let name = formula
        .strip_prefix('\'')
        .and_then(|s| s.strip_suffix('\''))
        .map(str::to_string);
    let trace = inner.next().map(trace).transpose()?;
    let verdict = match (holds, trace) {
        (true, None) => Verdict::Holds,
        (true, Some(_)) => return Err(error_at(&pos, "a true property with a counterexample")),
        (false, trace) => Verdict::Violated(trace),
    };
    Ok(PropertyResult {
        name,
        formula,
        verdict_line,
        verdict,
    })
}

/// Values (states and inputs, times the variables in each) a [`Trace`] may hold. NuSMV prints
/// only what changes, so a few megabytes of output could otherwise expand, carried forward,
/// into gigabytes.
pub const MAX_TRACE_VALUES: usize = 1_000_000;

fn trace(pair: Pair<'_, Rule>) -> Result<Trace, OutputParseError> {
    let mut trace = Trace::default();
    let mut values = 0usize;
    let mut state: BTreeMap<String, String> = BTreeMap::new();
    let mut input: BTreeMap<String, String> = BTreeMap::new();
    // The input section printed since the last state, waiting for its state.
    let mut pending_input: Option<(usize, usize)> = None;
    let mut input_for_next = None;
    for step in pair.into_inner() {
        let pos = step.as_span().start_pos().line_col();
        match step.as_rule() {
            Rule::input => {
                if trace.states.is_empty() {
                    return Err(error_at(&pos, "an input section before the first state"));
                }
                if pending_input.is_some() {
                    return Err(error_at(&pos, "two input sections without a state between"));
                }
                apply_assignments(&mut input, step);
                input_for_next = Some(input.clone());
                pending_input = Some(pos);
            }
            Rule::state => {
                let k = trace.states.len();
                for part in step.clone().into_inner() {
                    if part.as_rule() == Rule::loop_marker {
                        trace.loop_starts.push(k);
                    }
                }
                apply_assignments(&mut state, step);
                values += state.len() + input.len();
                if values > MAX_TRACE_VALUES {
                    let message = format!(
                        "a counterexample of more than {MAX_TRACE_VALUES} values (states times variables), too large to keep"
                    );
                    return Err(error_at(&pos, &message));
                }
                trace.states.push(state.clone());
                trace.inputs.push(input_for_next.take().unwrap_or_default());
                pending_input = None;
            }
            _ => unreachable!("a trace holds only input and state sections"),
        }
    }
    if let Some(pos) = pending_input {
        return Err(error_at(&pos, "an input section without a following state"));
    }
    Ok(trace)
}

fn apply_assignments(values: &mut BTreeMap<String, String>, section: Pair<'_, Rule>) {
    for part in section.into_inner() {
        if part.as_rule() != Rule::assignment {
            continue;
        }
        let mut name_value = part.into_inner();
        let name = name_value.next().expect("assignment has a name").as_str();
        let value = name_value.next().expect("assignment has a value").as_str();
        values.insert(name.to_string(), value.trim_end().to_string());
    }
}

fn error_at(&(line, column): &(usize, usize), message: &str) -> OutputParseError {
    OutputParseError {
        line,
        column,
        message: message.to_string(),
    }
}

/// Extracts the positioned errors from NuSMV's stderr, in order:
/// `file F: line N: message` and `TYPE ERROR file F: line N : message`. Lines without a
/// position (banner, `ERROR: Property ... is not correct`, `NuSMV terminated by a signal`)
/// are skipped. Repeats are dropped: the interactive shell prints a syntax error twice, and
/// every syntax error is followed by a `Parser error` at the same place.
pub fn parse_errors(stderr: &str) -> Vec<ModelError> {
    let mut errors: Vec<ModelError> = Vec::new();
    for line in stderr.lines() {
        let Some(error) = error_line(line) else {
            continue;
        };
        let repeat = errors.iter().any(|e| {
            e.file == error.file
                && e.line == error.line
                && (e.message == error.message || error.message == "Parser error")
        });
        if !repeat {
            errors.push(error);
        }
    }
    errors
}

fn error_line(line: &str) -> Option<ModelError> {
    let line = line.trim_end();
    // NuSMV puts a category in capitals before some messages (`TYPE ERROR file ...`).
    let start = line.find("file ")?;
    let prefix = &line[..start];
    if !prefix
        .chars()
        .all(|c| c.is_ascii_uppercase() || c == ' ' || c == '_')
    {
        return None;
    }
    let rest = &line[start + "file ".len()..];
    let at = rest.find(": line ")?;
    let file = &rest[..at];
    let after = &rest[at + ": line ".len()..];
    let digits = after.len() - after.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    let number = after[..digits].parse().ok()?;
    let message = after[digits..].trim_start().strip_prefix(':')?.trim();
    Some(ModelError {
        file: file.to_string(),
        line: number,
        message: message.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fmt::Write as _;

    fn fixture(name: &str) -> String {
        let path = format!("{}/tests/data/nusmv/{name}", env!("CARGO_MANIFEST_DIR"));
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("reading {path}: {e}"))
    }

    /// A compact, faithful rendering for snapshots: one line per state and per input.
    fn render(results: &[PropertyResult]) -> String {
        let mut s = String::new();
        for r in results {
            writeln!(s, "{}", r.verdict_line).unwrap();
            writeln!(s, "  name={:?} formula={:?}", r.name, r.formula).unwrap();
            match &r.verdict {
                Verdict::Holds => writeln!(s, "  holds").unwrap(),
                Verdict::Violated(None) => writeln!(s, "  violated, no trace").unwrap(),
                Verdict::Violated(Some(t)) => {
                    writeln!(s, "  violated, loop starts {:?}", t.loop_starts).unwrap();
                    for (k, (state, input)) in t.states.iter().zip(&t.inputs).enumerate() {
                        if !input.is_empty() {
                            writeln!(s, "    input {k}: {}", values(input)).unwrap();
                        }
                        writeln!(s, "    state {k}: {}", values(state)).unwrap();
                    }
                }
            }
        }
        s
    }

    fn values(map: &BTreeMap<String, String>) -> String {
        let pairs: Vec<String> = map.iter().map(|(k, v)| format!("{k}={v}")).collect();
        pairs.join(" ")
    }

    /// The parts of the dialogue transcript between its `echo` markers.
    fn dialogue_chunks(text: &str) -> Vec<String> {
        let mut chunks = vec![String::new()];
        for line in text.split_inclusive('\n') {
            match line.find("==model-") {
                Some(at) => {
                    chunks.last_mut().unwrap().push_str(&line[..at]);
                    chunks.push(String::new());
                }
                None => chunks.last_mut().unwrap().push_str(line),
            }
        }
        chunks
    }

    #[test]
    fn batch_outputs_of_the_models_parse() {
        for model in ["cylinder", "light"] {
            let results = parse_output(&fixture(&format!("{model}.batch.stdout"))).unwrap();
            insta::assert_snapshot!(format!("batch_{model}"), render(&results));
        }
    }

    #[test]
    fn cylinder_verdicts_follow_the_file_order() {
        let results = parse_output(&fixture("cylinder.batch.stdout")).unwrap();
        let verdicts: Vec<bool> = results
            .iter()
            .map(|r| r.verdict == Verdict::Holds)
            .collect();
        assert_eq!(verdicts, [true, false, false, true, false, false, false]);
        assert_eq!(results[2].formula, "G (ctrl = out ->  F pos = extended)");
        assert!(results.iter().all(|r| r.name.is_none()));
    }

    #[test]
    fn changed_values_are_carried_forward() {
        let results = parse_output(&fixture("cylinder.batch.stdout")).unwrap();
        let Verdict::Violated(Some(t)) = &results[2].verdict else {
            panic!("out_reaches_end has a counterexample");
        };
        // Printed: 2.3 sets ctrl, pos, push; 2.4 and 2.5 print nothing.
        assert_eq!(t.states.len(), 6);
        assert_eq!(t.states[3], t.states[2]);
        assert_eq!(t.states[5]["pos"], "middle");
        assert_eq!(t.states[5]["alarm"], "FALSE");
        assert_eq!(t.loop_starts, [2, 3, 4]);
        assert!(t.inputs[0].is_empty());
        // Input 2.4 prints only stop = FALSE; start keeps FALSE from 2.3.
        assert_eq!(t.inputs[3]["start"], "FALSE");
        assert_eq!(t.inputs[3]["stop"], "FALSE");
        assert_eq!(t.inputs[5], t.inputs[3]);
    }

    #[test]
    fn traces_without_ivars_have_empty_inputs() {
        let results = parse_output(&fixture("light.batch.stdout")).unwrap();
        for r in &results[1..] {
            let Verdict::Violated(Some(t)) = &r.verdict else {
                panic!("{} should be violated with a trace", r.formula);
            };
            assert_eq!(t.inputs.len(), t.states.len());
            assert!(t.inputs.iter().all(BTreeMap::is_empty));
        }
    }

    #[test]
    fn dialogue_transcript_parses_model_by_model() {
        let chunks = dialogue_chunks(&fixture("dialogue.stdout"));
        assert_eq!(
            chunks.len(),
            5,
            "four models and the part after the last marker"
        );
        let mut rendered = String::new();
        for (i, chunk) in chunks.iter().enumerate() {
            let results = parse_output(chunk).unwrap();
            writeln!(rendered, "=== chunk {i}").unwrap();
            rendered.push_str(&render(&results));
        }
        insta::assert_snapshot!("dialogue", rendered);
    }

    #[test]
    fn name_print_method_gives_names() {
        let chunks = dialogue_chunks(&fixture("dialogue.stdout"));
        let results = parse_output(&chunks[3]).unwrap();
        let names: Vec<_> = results.iter().map(|r| r.name.as_deref()).collect();
        assert_eq!(
            names,
            [
                Some("red_not_to_yellow"),
                Some("always_red"),
                Some("req_served"),
                Some("green_again")
            ]
        );
        assert_eq!(results[0].formula, "'red_not_to_yellow'");
    }

    #[test]
    fn index_print_method_is_not_a_name() {
        let results = parse_output("-- specification [6]  is true\n").unwrap();
        assert_eq!(results[0].name, None);
        assert_eq!(results[0].formula, "[6]");
        assert_eq!(results[0].verdict, Verdict::Holds);
    }

    #[test]
    fn banner_only_output_has_no_results() {
        let results = parse_output(&fixture("err_syntax.batch.stdout")).unwrap();
        assert!(results.is_empty());
    }

    #[test]
    fn violated_without_trace() {
        let results = parse_output("NuSMV > -- specification  G x  is false\nNuSMV > ").unwrap();
        assert_eq!(results[0].verdict, Verdict::Violated(None));
        assert_eq!(results[0].verdict_line, "-- specification  G x  is false");
    }

    /// Output cut off after any line (NuSMV killed, a pipe closed) still parses: the last
    /// line needs no line break.
    #[test]
    fn output_may_end_without_a_line_break_after_any_line() {
        let text = "-- specification  G x  is false\n\
                    -- as demonstrated by the following execution sequence\n\
                    Trace Type: Counterexample \n\
                    -> State: 1.1 <-\n  x = FALSE\n-> Input: 1.2 <-\n  i = TRUE\n\
                    -- Loop starts here\n-> State: 1.2 <-\n  x = TRUE\n";
        let lines: Vec<&str> = text.split_inclusive('\n').collect();
        for k in 1..=lines.len() {
            let cut = lines[..k].concat();
            let cut = cut.strip_suffix('\n').unwrap();
            match parse_output(cut) {
                Ok(results) => assert_eq!(results.len(), 1, "{cut:?}"),
                // Cut between an input section or a loop marker and its state.
                Err(e) => assert!(matches!(k, 6..=8) && e.line <= k, "{cut:?}: {e}"),
            }
        }
    }

    /// A long run of blanks in a verdict line is read in linear time: looking ahead from each
    /// blank for the `is true` that ends the line took 4 s for 40,000 blanks (debug build),
    /// and would take hours for a megabyte.
    #[test]
    fn blanks_in_a_verdict_line_take_linear_time() {
        let blanks = " ".repeat(200_000);
        let text = format!("-- specification  G (x{blanks}| y)  is true\n");
        let t = std::time::Instant::now();
        let results = parse_output(&text).unwrap();
        assert!(t.elapsed().as_secs_f64() < 5.0, "{:?}", t.elapsed());
        assert_eq!(results[0].formula, format!("G (x{blanks}| y)"));
        assert_eq!(results[0].verdict, Verdict::Holds);
    }

    #[test]
    fn unknown_lines_are_errors_with_their_position() {
        let text = "-- specification  G x  is true\nsomething else\n";
        let err = parse_output(text).unwrap_err();
        assert_eq!((err.line, err.column), (2, 1));
    }

    #[test]
    fn an_input_without_its_state_is_an_error() {
        let text = "-- specification  G x  is false\n\
                    -- as demonstrated by the following execution sequence\n\
                    -> State: 1.1 <-\n  x = FALSE\n-> Input: 1.2 <-\n  i = TRUE\n";
        let err = parse_output(text).unwrap_err();
        assert_eq!((err.line, err.column), (5, 1));
        assert_eq!(err.message, "an input section without a following state");
    }

    #[test]
    fn error_lines_of_every_error_fixture() {
        let mut rendered = String::new();
        for model in [
            "err_syntax",
            "err_keyword",
            "err_undefined",
            "err_case",
            "err_assign",
            "err_twice",
            "err_next_twice",
        ] {
            let errors = parse_errors(&fixture(&format!("{model}.batch.stderr")));
            writeln!(rendered, "{model}:").unwrap();
            for e in errors {
                writeln!(rendered, "  {e}").unwrap();
            }
        }
        insta::assert_snapshot!("errors", rendered);
    }

    #[test]
    fn error_positions() {
        let errors = parse_errors(&fixture("err_undefined.batch.stderr"));
        assert_eq!(
            errors,
            [ModelError {
                file: "err_undefined.smv".into(),
                line: 8,
                message: "undefined identifier 'y'".into()
            }]
        );
        let errors = parse_errors(&fixture("err_twice.batch.stderr"));
        assert_eq!(errors.len(), 1);
        assert_eq!(errors[0].line, 6);
        assert_eq!(errors[0].message, "assigned x, line 7: assigned next(x)");
    }

    #[test]
    fn dialogue_stderr_repeats_are_dropped() {
        let errors = parse_errors(&fixture("dialogue.stderr"));
        let positions: Vec<_> = errors.iter().map(|e| (e.file.as_str(), e.line)).collect();
        assert_eq!(positions, [("err_syntax.smv", 5), ("err_undefined.smv", 8)]);
    }

    #[test]
    fn lines_that_only_mention_a_file_are_not_errors() {
        assert!(
            parse_errors("Input file is (null). You must set the input file before.\n").is_empty()
        );
        assert!(parse_errors("ERROR: Property \" G y \" is not correct\n").is_empty());
    }
}
