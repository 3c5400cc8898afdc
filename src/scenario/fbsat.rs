//! The fbSAT scenario text format, read and written.
//!
//! ```text
//! 2
//! in=REQ[0010]; in=REQ[1010]; out=CNF[10]; in=REQ[1010];
//! in=REQ[0110]; out=CNF[01];
//! ```
//! Line 1 holds the number of scenarios; then one scenario per line, actions separated by `;`
//! (spaces allowed), each `in=REQ[bits]` or `out=CNF[bits]`. An `in` directly followed by an
//! `out` is an active step; an `in` followed by another `in` (or ending the line) is passive.
//! Files may be gzip-compressed and use LF or CRLF line ends.

use super::{read_text, Origin, Scenario, ScenarioError, ScenarioSet, Step};
use crate::ecc::{bits_from_str, bits_to_string};
use crate::quote::quote;
use std::io::Write;
use std::path::Path;

/// The input event every `in` action must carry.
pub(crate) const INPUT_EVENT: &str = "REQ";
/// The output event every `out` action must carry.
pub(crate) const OUTPUT_EVENT: &str = "CNF";

/// Parses scenario text. `inputs`/`outputs` are the interface names; when `None`, names
/// `x1..xN` / `z1..zM` are made up from the bit counts of the first actions.
pub(crate) fn parse(
    file: &Path,
    text: &str,
    inputs: Option<Vec<String>>,
    outputs: Option<Vec<String>>,
) -> Result<ScenarioSet, ScenarioError> {
    let syntax = |line: usize, message: String| ScenarioError::Syntax {
        file: file.to_path_buf(),
        line,
        message,
    };
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim()));
    let (count_line, count_text) = lines
        .by_ref()
        .find(|(_, l)| !l.is_empty())
        .ok_or_else(|| syntax(1, "empty file: expected the number of scenarios".into()))?;
    let declared: usize = count_text.parse().map_err(|_| {
        syntax(
            count_line,
            format!(
                "expected the number of scenarios, found {}",
                quote(count_text)
            ),
        )
    })?;

    let mut widths = (
        inputs.as_ref().map(Vec::len),
        outputs.as_ref().map(Vec::len),
    );
    let mut scenarios = Vec::new();
    for (line_no, line) in lines {
        if line.is_empty() {
            continue;
        }
        scenarios.push(parse_line(file, line_no, line, &mut widths)?);
    }
    if scenarios.len() != declared {
        return Err(syntax(
            count_line,
            format!(
                "the file declares {declared} scenarios but holds {}",
                scenarios.len()
            ),
        ));
    }
    let (ni, no) = (widths.0.unwrap_or(0), widths.1.unwrap_or(0));
    let inputs = inputs.unwrap_or_else(|| (1..=ni).map(|i| format!("x{i}")).collect());
    let outputs = outputs.unwrap_or_else(|| (1..=no).map(|i| format!("z{i}")).collect());
    Ok(ScenarioSet {
        initial_outputs: vec![false; outputs.len()],
        inputs,
        outputs,
        scenarios,
    })
}

fn parse_line(
    file: &Path,
    line_no: usize,
    line: &str,
    widths: &mut (Option<usize>, Option<usize>),
) -> Result<Scenario, ScenarioError> {
    let mut steps: Vec<Step> = Vec::new();
    // Whether the last step may still receive an `out`.
    let mut open = false;
    for action in line.split(';').map(str::trim).filter(|a| !a.is_empty()) {
        let step_no = steps.len() + usize::from(action.starts_with("in"));
        let err = |message: String| ScenarioError::Step {
            file: file.to_path_buf(),
            line: line_no,
            step: step_no.max(1),
            message,
        };
        let (kind, event, values) = parse_action(action).map_err(err)?;
        match kind {
            "in" => {
                if event != INPUT_EVENT {
                    return Err(err(format!(
                        "unknown input event {} (only {INPUT_EVENT} is supported)",
                        quote(event)
                    )));
                }
                check_width(&mut widths.0, values.len(), "input").map_err(err)?;
                steps.push(Step {
                    inputs: values,
                    outputs: None,
                });
                open = true;
            }
            "out" => {
                if event != OUTPUT_EVENT {
                    return Err(err(format!(
                        "unknown output event {} (only {OUTPUT_EVENT} is supported)",
                        quote(event)
                    )));
                }
                check_width(&mut widths.1, values.len(), "output").map_err(err)?;
                if !open {
                    return Err(err(if steps.is_empty() {
                        "out= before any in=: an output event must answer an input event".into()
                    } else {
                        "two out= in a row: each in= is answered by at most one out=".into()
                    }));
                }
                steps.last_mut().expect("open implies a step").outputs = Some(values);
                open = false;
            }
            other => {
                return Err(err(format!(
                    "unknown action {} (expected 'in' or 'out')",
                    quote(other)
                )))
            }
        }
    }
    if steps.is_empty() {
        return Err(ScenarioError::Syntax {
            file: file.to_path_buf(),
            line: line_no,
            message: "scenario without any in= action".into(),
        });
    }
    Ok(Scenario {
        origin: Origin {
            file: file.to_path_buf(),
            line: line_no,
            rows: None,
        },
        steps,
    })
}

/// One action, `KIND=EVENT[bits]`: its kind and event (trimmed) and its bits.
fn parse_action(action: &str) -> Result<(&str, &str, Vec<bool>), String> {
    let (kind, rest) = action.split_once('=').ok_or_else(|| {
        format!(
            "expected in=EVENT[bits] or out=EVENT[bits], found {}",
            quote(action)
        )
    })?;
    let (event, bits) = (rest.trim().strip_suffix(']'))
        .and_then(|r| r.split_once('['))
        .ok_or_else(|| {
            format!(
                "expected EVENT[bits] after {}, found {}",
                quote(&format!("{kind}=")),
                quote(rest)
            )
        })?;
    let values = bits_from_str(bits.trim())
        .ok_or_else(|| format!("bits must be 0 or 1, found {}", quote(bits)))?;
    Ok((kind.trim(), event.trim(), values))
}

fn check_width(width: &mut Option<usize>, got: usize, what: &str) -> Result<(), String> {
    match *width {
        Some(w) if w != got => Err(format!("{got} {what} bits, expected {w}")),
        Some(_) => Ok(()),
        None => {
            *width = Some(got);
            Ok(())
        }
    }
}

/// Reads a scenario file (plain or gzip).
pub fn read(
    file: &Path,
    inputs: Option<Vec<String>>,
    outputs: Option<Vec<String>>,
) -> Result<ScenarioSet, ScenarioError> {
    // One scenario is one line, as long as the recording: only the file's size is limited.
    parse(file, &read_text(file, None)?, inputs, outputs)
}

/// Writes scenarios in the fbSAT format (LF line ends, `; ` separators).
pub fn write(set: &ScenarioSet, w: &mut impl Write) -> std::io::Result<()> {
    let mut out = ScenarioWriter::new(w, set.scenarios.len())?;
    for sc in &set.scenarios {
        for step in &sc.steps {
            out.step(step)?;
        }
        out.end_scenario()?;
    }
    Ok(())
}

/// Writes the fbSAT format step by step, as [`write()`] does, for scenarios too long to hold in
/// memory (a raw log of any length is one scenario): the number of scenarios first, then
/// [`ScenarioWriter::step`] for each step and [`ScenarioWriter::end_scenario`] after each
/// scenario.
pub(crate) struct ScenarioWriter<W: Write> {
    w: W,
    /// Whether the scenario being written has no step yet.
    fresh: bool,
}

impl<W: Write> ScenarioWriter<W> {
    /// Writes line 1: the number of scenarios that will follow.
    pub(crate) fn new(mut w: W, scenarios: usize) -> std::io::Result<ScenarioWriter<W>> {
        writeln!(w, "{scenarios}")?;
        Ok(ScenarioWriter { w, fresh: true })
    }

    /// Appends a step to the scenario being written.
    pub(crate) fn step(&mut self, step: &Step) -> std::io::Result<()> {
        if !self.fresh {
            write!(self.w, "; ")?;
        }
        self.fresh = false;
        write!(self.w, "in={INPUT_EVENT}[{}]", bits_to_string(&step.inputs))?;
        if let Some(o) = &step.outputs {
            write!(self.w, "; out={OUTPUT_EVENT}[{}]", bits_to_string(o))?;
        }
        Ok(())
    }

    /// Ends the scenario's line.
    pub(crate) fn end_scenario(&mut self) -> std::io::Result<()> {
        self.fresh = true;
        writeln!(self.w, ";")
    }

    /// The writer, for the caller to flush or commit.
    pub(crate) fn into_inner(self) -> W {
        self.w
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(text: &str) -> Result<ScenarioSet, ScenarioError> {
        parse(Path::new("t.txt"), text, None, None)
    }

    #[test]
    fn active_and_passive_steps_and_crlf() {
        let s =
            p("2\r\nin=REQ[01];  in=REQ[11]; out=CNF[1];\r\nin=REQ[00]; out=CNF[0]\r\n").unwrap();
        assert_eq!(s.inputs, vec!["x1", "x2"]);
        assert_eq!(s.outputs, vec!["z1"]);
        assert_eq!(s.scenarios.len(), 2);
        let st = &s.scenarios[0].steps;
        assert_eq!(st[0].outputs, None);
        assert_eq!(st[1].outputs, Some(vec![true]));
        assert_eq!(s.scenarios[1].origin.line, 3);
    }

    #[test]
    fn round_trip() {
        let text = "2\nin=REQ[01]; in=REQ[11]; out=CNF[1];\nin=REQ[00]; out=CNF[0];\n";
        let s = p(text).unwrap();
        let mut out = Vec::new();
        write(&s, &mut out).unwrap();
        assert_eq!(String::from_utf8(out).unwrap(), text);
    }

    #[test]
    fn errors_name_line_and_step() {
        let cases = [
            (
                "1\nin=REQ[01]; in=REQ[1];\n",
                "t.txt:2: step 2: 1 input bits, expected 2",
            ),
            (
                "1\nin=REQ[01]; out=ACK[1];\n",
                "t.txt:2: step 1: unknown output event 'ACK' (only CNF is supported)",
            ),
            (
                "1\nin=INIT[01];\n",
                "t.txt:2: step 1: unknown input event 'INIT' (only REQ is supported)",
            ),
            (
                "2\nin=REQ[01];\n",
                "t.txt:1: the file declares 2 scenarios but holds 1",
            ),
            (
                "x\n",
                "t.txt:1: expected the number of scenarios, found 'x'",
            ),
            (
                "1\nin=REQ[0a];\n",
                "t.txt:2: step 1: bits must be 0 or 1, found '0a'",
            ),
            (
                "1\nin=REQ[01]; out=CNF[1]; out=CNF[1];\n",
                "t.txt:2: step 1: two out= in a row: each in= is answered by at most one out=",
            ),
            (
                "1\nout=CNF[1];\n",
                "t.txt:2: step 1: out= before any in=: an output event must answer an input event",
            ),
            (
                "1\nin=REQ01;\n",
                "t.txt:2: step 1: expected EVENT[bits] after 'in=', found 'REQ01'",
            ),
        ];
        for (text, msg) in cases {
            assert_eq!(p(text).unwrap_err().to_string(), msg, "for {text:?}");
        }
    }

    #[test]
    fn names_fix_the_widths() {
        let e = parse(
            Path::new("t.txt"),
            "1\nin=REQ[01];\n",
            Some(vec!["a".into(), "b".into(), "c".into()]),
            Some(vec!["z".into()]),
        )
        .unwrap_err();
        assert_eq!(e.to_string(), "t.txt:2: step 1: 2 input bits, expected 3");
    }

    #[test]
    fn bad_gzip_is_reported() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("x.gz");
        std::fs::write(&f, [0x1f, 0x8b, 8, 0, 1, 2, 3]).unwrap();
        let e = read(&f, None, None).unwrap_err();
        assert!(e.to_string().contains("not a valid gzip stream"), "{e}");
    }
}
