//! Sampled PLC I/O logs in CSV, as a data collector writes them, and their conversion to
//! scenarios by the rules of the SAT reconstruction paper (section IV.A).
//!
//! # Format
//! ```text
//! time,scenario,in:start,in:sensor,out:motor
//! 0.00,1,0,0,0
//! 0.01,1,1,0,0
//! 0.02,1,1,0,1
//! ```
//! - A header row, then one row per sample. Cells are separated by `,` (or `;` when the header
//!   has no `,`) and may be quoted as RFC 4180 says ([`Records`]). Values are
//!   `0`/`1`/`true`/`false` in any case. Blank lines and a leading byte order mark are ignored.
//! - Inputs and outputs are told apart by a prefix in the header: `in:NAME` or `out:NAME`.
//!   Plain `NAME` headers are allowed when names files (`--input-names`/`--output-names`) say
//!   which side a name is on; with names files, their order is the interface order and every
//!   listed name must have a column.
//! - Optional columns: `time` or `timestamp` (kept for the user, ignored here), and `scenario`
//!   (rows with the same value in a contiguous block form one scenario; without it the whole
//!   file is one scenario). `synth record` counts it up after a lost connection, so a gap in
//!   a live recording is a scenario break, never a step.
//!
//! # Conversion (the SAT reconstruction paper, implemented in [`super::steps`])
//! 1. Consecutive identical rows collapse into one element.
//! 2. While two consecutive elements have equal inputs and different outputs, the first is
//!    dropped: the output change belongs to the input change before it (scan-cycle skew).
//! 3. Every element becomes a `REQ`; an element whose outputs differ from the previous one's
//!    (for the first: from the initial outputs) is answered with `CNF` and those outputs.
//!
//! Writing a scenario set as CSV gives one row per step with the outputs after it. Reading it
//! back is lossless except for active steps that did not change the outputs (they become
//! passive): a sampled log cannot see an event that changed nothing.

pub(crate) use super::steps::samples_to_steps;
pub use super::steps::Sample;
use super::{read_text, Origin, Scenario, ScenarioError, ScenarioSet};
use crate::ecc::ident::is_identifier;
use crate::files::csv::{parse_bool_cell, Record, Records};
use crate::quote::quote;
use std::io::Write;
use std::path::Path;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Column {
    Time,
    Scenario,
    Input(usize),
    Output(usize),
}

/// Parses a CSV log into scenarios.
pub(crate) fn parse(
    file: &Path,
    text: &str,
    input_names: Option<&[String]>,
    output_names: Option<&[String]>,
) -> Result<ScenarioSet, ScenarioError> {
    let err = |line: usize, message: String| ScenarioError::Syntax {
        file: file.to_path_buf(),
        line,
        message,
    };
    // Reading from memory fails only on a line over the limit.
    let read = |e: crate::files::ReadError| ScenarioError::Read(e.at(file));
    let header_line = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("");
    let sep = if header_line.contains(',') || !header_line.contains(';') {
        b','
    } else {
        b';'
    };
    let mut records = Records::new(text.as_bytes(), sep);
    let (hline, header) = match records.next_record().map_err(read)? {
        Some((line, cells)) => (line, cells.iter().map(lossy).collect::<Vec<String>>()),
        None => return Err(err(1, "empty file: expected a header row".into())),
    };
    let (columns, inputs, outputs) =
        classify(&header, input_names, output_names).map_err(|m| err(hline, m))?;

    let mut groups: Vec<Group> = Vec::new();
    while let Some((line_no, cells)) = records.next_record().map_err(read)? {
        if cells.len() != columns.len() {
            return Err(err(
                line_no,
                format!("{} cells, the header has {}", cells.len(), columns.len()),
            ));
        }
        let (sample, id) = row(&cells, &columns, &header, (inputs.len(), outputs.len()))
            .map_err(|m| err(line_no, m))?;
        match groups.last_mut() {
            Some((_, last, samples)) if *last == id => samples.push((sample, line_no)),
            _ => groups.push((line_no, id, vec![(sample, line_no)])),
        }
    }
    if groups.is_empty() {
        return Err(err(hline, "no sample rows after the header".into()));
    }
    let initial = vec![false; outputs.len()];
    let scenarios = (groups.into_iter())
        .map(|group| scenario(file, &initial, group))
        .collect();
    Ok(ScenarioSet {
        inputs,
        outputs,
        initial_outputs: initial,
        scenarios,
    })
}

/// Samples grouped by the scenario column: per scenario its first line, its id, and its
/// samples with their lines.
type Group = (usize, String, Vec<(Sample, usize)>);

/// One sample row as `(sample, scenario id)`, with `(inputs, outputs)` signals; the
/// message names the column of a cell that is not a Boolean.
fn row(
    cells: &Record<'_>,
    columns: &[Column],
    header: &[String],
    (inputs, outputs): (usize, usize),
) -> Result<(Sample, String), String> {
    let mut sample = Sample {
        inputs: vec![false; inputs],
        outputs: vec![false; outputs],
    };
    let mut id = String::new();
    for (k, (cell, col)) in cells.iter().zip(columns).enumerate() {
        let value = || {
            parse_bool_cell(cell).ok_or_else(|| {
                format!(
                    "column {} ({}): {} is not 0/1/true/false",
                    k + 1,
                    quote(&header[k]),
                    quote(&lossy(cell))
                )
            })
        };
        match *col {
            Column::Time => {}
            Column::Scenario => id = lossy(cell),
            Column::Input(i) => sample.inputs[i] = value()?,
            Column::Output(o) => sample.outputs[o] = value()?,
        }
    }
    Ok((sample, id))
}

/// The scenario of one group of samples, converted by the stream the other readers use
/// ([`super::steps::StepStream`]), with each step's row kept for messages.
fn scenario(file: &Path, initial: &[bool], (line, _, samples): Group) -> Scenario {
    let mut stream = super::steps::StepStream::new(initial.to_vec());
    let (mut steps, mut rows) = (Vec::new(), Vec::new());
    let tagged = samples
        .into_iter()
        .filter_map(|(s, l)| stream.push_tagged(s, l));
    for (step, row) in tagged
        .collect::<Vec<_>>()
        .into_iter()
        .chain(stream.finish_tagged())
    {
        steps.push(step);
        rows.push(row);
    }
    Scenario {
        origin: Origin {
            file: file.to_path_buf(),
            line,
            rows: Some(rows.into()),
        },
        steps,
    }
}

/// A cell as text (the log is UTF-8 already; this only changes the type).
fn lossy(cell: &[u8]) -> String {
    String::from_utf8_lossy(cell).into_owned()
}

type Classified = (Vec<Column>, Vec<String>, Vec<String>);

fn classify(
    header: &[String],
    input_names: Option<&[String]>,
    output_names: Option<&[String]>,
) -> Result<Classified, String> {
    let mut inputs: Vec<String> = input_names.map(<[String]>::to_vec).unwrap_or_default();
    let mut outputs: Vec<String> = output_names.map(<[String]>::to_vec).unwrap_or_default();
    let fixed_in = input_names.is_some();
    let fixed_out = output_names.is_some();
    let mut columns = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for (k, cell) in header.iter().map(String::as_str).enumerate() {
        let col_no = k + 1;
        if !seen.insert(cell.to_string()) {
            return Err(format!("column {col_no}: duplicate column {}", quote(cell)));
        }
        let lower = cell.to_ascii_lowercase();
        if lower == "time" || lower == "timestamp" {
            columns.push(Column::Time);
            continue;
        }
        if lower == "scenario" {
            columns.push(Column::Scenario);
            continue;
        }
        let col = signal_column(
            cell,
            col_no,
            (&mut inputs, fixed_in),
            (&mut outputs, fixed_out),
        )?;
        columns.push(col);
    }
    for (names, is_input) in [(&inputs, true), (&outputs, false)] {
        for (i, n) in names.iter().enumerate() {
            let want = if is_input {
                Column::Input(i)
            } else {
                Column::Output(i)
            };
            if !columns.contains(&want) {
                return Err(format!(
                    "no column for signal {} of the names file",
                    quote(n)
                ));
            }
        }
    }
    if inputs.is_empty() {
        return Err("no input columns (prefix them with 'in:')".into());
    }
    if outputs.is_empty() {
        return Err("no output columns (prefix them with 'out:')".into());
    }
    Ok((columns, inputs, outputs))
}

/// The column of signal header `cell` (column `col_no`, 1-based): by its `in:`/`out:` prefix
/// or by the names files. A prefixed name not yet known is added to its side unless that
/// side's names are `fixed` (given in a names file).
fn signal_column(
    cell: &str,
    col_no: usize,
    (inputs, fixed_in): (&mut Vec<String>, bool),
    (outputs, fixed_out): (&mut Vec<String>, bool),
) -> Result<Column, String> {
    let (side, name) = if let Some(n) = cell.strip_prefix("in:") {
        (Some(true), n)
    } else if let Some(n) = cell.strip_prefix("out:") {
        (Some(false), n)
    } else {
        (None, cell)
    };
    if !is_identifier(name) {
        return Err(format!(
            "column {col_no}: {} is not a valid signal name",
            quote(name)
        ));
    }
    let in_pos = inputs.iter().position(|n| n == name);
    let out_pos = outputs.iter().position(|n| n == name);
    Ok(match (side, in_pos, out_pos) {
        (Some(true), Some(i), _) | (None, Some(i), None) => Column::Input(i),
        (Some(false), _, Some(o)) | (None, None, Some(o)) => Column::Output(o),
        (Some(true), None, _) if !fixed_in => {
            inputs.push(name.to_string());
            Column::Input(inputs.len() - 1)
        }
        (Some(false), _, None) if !fixed_out => {
            outputs.push(name.to_string());
            Column::Output(outputs.len() - 1)
        }
        (Some(true), None, _) => {
            return Err(format!(
                "column {col_no}: input {} is not in the input names file",
                quote(name)
            ))
        }
        (Some(false), _, None) => {
            return Err(format!(
                "column {col_no}: output {} is not in the output names file",
                quote(name)
            ))
        }
        (None, Some(_), Some(_)) => {
            return Err(format!(
                "column {col_no}: {} is listed both as an input and as an output",
                quote(name)
            ))
        }
        (None, None, None) => {
            return Err(format!(
                "column {col_no}: unknown signal {}: write {} or {} in the header, or list it in a names file",
                quote(name),
                quote(&format!("in:{name}")),
                quote(&format!("out:{name}"))
            ))
        }
    })
}

/// Reads a CSV log file (plain or gzip).
pub fn read(
    file: &Path,
    input_names: Option<&[String]>,
    output_names: Option<&[String]>,
) -> Result<ScenarioSet, ScenarioError> {
    let text = read_text(file, Some(crate::files::MAX_LINE_BYTES))?;
    parse(file, &text, input_names, output_names)
}

/// Writes scenarios as a CSV log: `scenario` column, `in:`/`out:` prefixed signals, one row
/// per step with the outputs after that step.
pub(crate) fn write(set: &ScenarioSet, w: &mut impl Write) -> std::io::Result<()> {
    let mut header = vec!["scenario".to_string()];
    header.extend(set.inputs.iter().map(|n| format!("in:{n}")));
    header.extend(set.outputs.iter().map(|n| format!("out:{n}")));
    writeln!(w, "{}", header.join(","))?;
    for (k, sc) in set.scenarios.iter().enumerate() {
        let mut outputs = set.initial_outputs.clone();
        for step in &sc.steps {
            if let Some(o) = &step.outputs {
                outputs.clone_from(o);
            }
            let cells: Vec<&str> = std::iter::once(&step.inputs)
                .chain(std::iter::once(&outputs))
                .flatten()
                .map(|&b| if b { "1" } else { "0" })
                .collect();
            writeln!(w, "{},{}", k + 1, cells.join(","))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steps(text: &str) -> Vec<(String, Option<String>)> {
        let set = parse(Path::new("log.csv"), text, None, None).unwrap();
        set.scenarios[0]
            .steps
            .iter()
            .map(|s| {
                (
                    crate::ecc::bits_to_string(&s.inputs),
                    s.outputs.as_deref().map(crate::ecc::bits_to_string),
                )
            })
            .collect()
    }

    #[test]
    fn seed_000_rules() {
        // rows: 00/0, 00/0 (repeat), 10/0, 10/1 (skew: same inputs, new outputs), 11/1, 11/1
        let text = "time,in:a,in:b,out:z\n0,0,0,0\n1,0,0,0\n2,1,0,0\n3,1,0,1\n4,1,1,1\n5,1,1,1\n";
        assert_eq!(
            steps(text),
            vec![
                ("00".into(), None),
                ("10".into(), Some("1".into())),
                ("11".into(), None),
            ]
        );
    }

    #[test]
    fn first_element_compares_with_initial_outputs() {
        assert_eq!(
            steps("in:a,out:z\n0,1\n"),
            vec![("0".into(), Some("1".into()))]
        );
    }

    #[test]
    fn dropping_repeats_until_stable() {
        // 0/0, 1/0, 1/1, 1/0 : drop 1/0 (skew) then 1/1 (skew again) -> 0/0, 1/0
        assert_eq!(
            steps("in:a,out:z\n0,0\n1,0\n1,1\n1,0\n"),
            vec![("0".into(), None), ("1".into(), None)]
        );
    }

    #[test]
    fn scenario_column_splits_and_names_files_classify() {
        let ins = vec!["b".to_string(), "a".to_string()];
        let outs = vec!["z".to_string()];
        let set = parse(
            Path::new("log.csv"),
            "scenario;a;b;z\n1;1;0;0\n2;0;1;1\n",
            Some(&ins),
            Some(&outs),
        )
        .unwrap();
        assert_eq!(set.inputs, ins);
        assert_eq!(set.scenarios.len(), 2);
        assert_eq!(set.scenarios[0].steps[0].inputs, vec![false, true]);
        assert_eq!(set.scenarios[1].origin.line, 3);
    }

    #[test]
    fn errors_have_lines_and_columns() {
        let cases = [
            ("in:a,out:z\n0,2\n", "log.csv:2: column 2 ('out:z'): '2' is not 0/1/true/false"),
            ("in:a,out:z\n0\n", "log.csv:2: 1 cells, the header has 2"),
            ("in:a,q\n0,1\n", "log.csv:1: column 2: unknown signal 'q': write 'in:q' or 'out:q' in the header, or list it in a names file"),
            ("in:a,in:a,out:z\n", "log.csv:1: column 2: duplicate column 'in:a'"),
            ("in:a,out:z\n", "log.csv:1: no sample rows after the header"),
            ("in:a\n1\n", "log.csv:1: no output columns (prefix them with 'out:')"),
        ];
        for (text, msg) in cases {
            let e = parse(Path::new("log.csv"), text, None, None).unwrap_err();
            assert_eq!(e.to_string(), msg, "for {text:?}");
        }
    }

    #[test]
    fn quoted_cells_and_a_byte_order_mark_are_read() {
        assert_eq!(
            steps("\u{feff}\"in:a\",out:z\n\"1\",0\n"),
            vec![("1".into(), None)]
        );
    }

    #[test]
    fn write_then_read_keeps_changing_steps() {
        let text = "in:a,out:z\n0,0\n1,1\n0,1\n0,0\n";
        let set = parse(Path::new("l.csv"), text, None, None).unwrap();
        let mut buf = Vec::new();
        write(&set, &mut buf).unwrap();
        let back = parse(
            Path::new("l.csv"),
            std::str::from_utf8(&buf).unwrap(),
            None,
            None,
        )
        .unwrap();
        assert_eq!(back.scenarios[0].steps, set.scenarios[0].steps);
    }
}
