//! The stable JSON contract of an ECC: writing ([`write_json`]) and reading ([`read_json`]).
//!
//! In: an [`Ecc`] (writing) or JSON text and its file name (reading). Out: pretty,
//! deterministic JSON text, or an `Ecc` whose every name, index and algorithm has been checked.
//!
//! # The contract
//! ```json
//! {
//!   "inputs": ["c1Home", "vac"],
//!   "outputs": ["c1Extend", "vacOn"],
//!   "initial_outputs": "01",
//!   "states": [
//!     {"name": "s0", "algorithm": "xx"},
//!     {"name": "s1", "algorithm": "1x"}
//!   ],
//!   "transitions": [
//!     {"from": 0, "to": 1, "guard": "c1Home & !vac"},
//!     {"from": 0, "to": 0, "guard": "TRUE"},
//!     {"from": 1, "to": 0, "guard": "vac | !c1Home"}
//!   ]
//! }
//! ```
//! - `inputs`, `outputs`: variable names in interface order; each must be an identifier
//!   `[A-Za-z][A-Za-z0-9_]*` that is no NuSMV keyword (see [`check_identifier`]), not `REQ`
//!   or `CNF`, and all of them distinct even ignoring case (Structured Text ignores case).
//! - `initial_outputs`: one `0`/`1` per output, in output order. May be omitted when reading
//!   (all `0`); always written.
//! - `states`: index 0 is the initial state. `name` follows the identifier rule above and is
//!   unique. Tri algorithms: `"algorithm"`, one of `0`, `1`, `x` per output (`x` = keep; `X`
//!   is read as `x`). Binary algorithms: `"algorithm0"` and `"algorithm1"`, one `0`/`1` per
//!   output each; the new value of an output is its `algorithm1` bit if it was 1, else its
//!   `algorithm0` bit. All states use the same form.
//! - `transitions`: `from` and `to` are 0-based state indices; `guard` is guard text over the
//!   input names (syntax in [`guard_text`](super::guard_text)). The transitions of one state
//!   have priority in the order they appear; writing sorts the array by `from`, keeping that
//!   order, and reading accepts any interleaving of states.
//!
//! - `format`: the version of the contract, [`FORMAT`] (1). Always written; optional when
//!   reading (files from before it existed), and a newer version is refused with a message
//!   saying so rather than misread.
//! - `$schema`: accepted and ignored, so that editors can be pointed at the contract's JSON
//!   Schema ([`schema`], `synth schema`); never written.
//!
//! Unknown fields are errors, so a misspelt field name is not silently ignored. Errors of
//! syntax carry line and column; errors of content carry the JSON path of the offending value
//! (`transitions[3].guard`), plus the column inside the string where one applies.

use super::guard_text::{parse_guard, GuardTextError};
use crate::ecc::{bits_from_str, bits_to_string, Algorithm, AlgorithmKind, Ecc, State};
use crate::ecc::{StateId, Transition, Tri};
use crate::quote::backquote;
use crate::smv::check_identifier;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// The version of the contract this build writes, and the newest it reads.
pub(crate) const FORMAT: u32 = 1;

// The serde types are the contract: their doc comments become the JSON Schema's descriptions.

/// An IEC 61499 basic function block's Execution Control Chart (a Moore machine over Boolean
/// inputs and outputs), as fbsynth writes and reads it.
#[derive(Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(title = "fbsynth machine")]
struct Document {
    /// The address of this schema, for editors; ignored.
    #[serde(rename = "$schema", default, skip_serializing_if = "Option::is_none")]
    schema: Option<String>,
    /// The version of the contract (1); optional when read, always written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 1, max = 1))]
    format: Option<u32>,
    /// Input variable names in interface order: identifiers, distinct ignoring case, no NuSMV
    /// keyword, not REQ or CNF.
    #[schemars(inner(regex(pattern = r"^[A-Za-z][A-Za-z0-9_]*$")))]
    inputs: Vec<String>,
    /// Output variable names in interface order, under the same rules as the inputs.
    #[schemars(inner(regex(pattern = r"^[A-Za-z][A-Za-z0-9_]*$")))]
    outputs: Vec<String>,
    /// The outputs before the first event: one 0/1 per output (default all 0).
    #[serde(default)]
    #[schemars(regex(pattern = r"^[01]*$"))]
    initial_outputs: Option<String>,
    /// The states; index 0 is the initial state.
    #[schemars(length(min = 1))]
    states: Vec<StateEntry>,
    /// The transitions; those of one state have priority in the order they appear.
    transitions: Vec<TransitionEntry>,
}

/// A state: its name and its output algorithm, either three-valued (`algorithm`) or binary
/// (`algorithm0` and `algorithm1`); all states use the same form.
#[derive(Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
struct StateEntry {
    /// Unique identifier of the state.
    #[schemars(regex(pattern = r"^[A-Za-z][A-Za-z0-9_]*$"))]
    name: String,
    /// Per output: 0 (clear), 1 (set) or x (keep).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(regex(pattern = r"^[01xX]*$"))]
    algorithm: Option<String>,
    /// Binary algorithm: per output, its new value when it was 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(regex(pattern = r"^[01]*$"))]
    algorithm0: Option<String>,
    /// Binary algorithm: per output, its new value when it was 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(regex(pattern = r"^[01]*$"))]
    algorithm1: Option<String>,
}

/// A transition: on REQ, the first transition of the current state whose guard holds fires.
#[derive(Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
struct TransitionEntry {
    /// Index of the source state.
    from: usize,
    /// Index of the target state.
    to: usize,
    /// A Boolean formula over the input names: `!`, `&`, `|`, parentheses, `TRUE`, `FALSE`.
    #[schemars(length(min = 1))]
    guard: String,
}

/// The JSON Schema (draft 2020-12) of the contract, as `synth schema` prints it.
pub(crate) fn schema() -> serde_json::Value {
    serde_json::to_value(schemars::schema_for!(Document)).expect("a schema is JSON")
}

/// Why a JSON file does not describe a usable ECC.
#[derive(Debug, thiserror::Error)]
pub enum JsonError {
    /// Not JSON, or not the shape of the contract (missing field, wrong type, unknown field).
    #[error("{}:{line}:{column}: {message}", file.display())]
    Syntax {
        /// The file read (`-` for stdin).
        file: PathBuf,
        /// 1-based line of the error, as serde_json reports it.
        line: usize,
        /// 1-based column of the error.
        column: usize,
        /// serde_json's description.
        message: String,
    },
    /// Well-formed, but a value breaks the contract; `at` is its JSON path.
    #[error("{}: {at}: {problem}", file.display())]
    Content {
        /// The file read (`-` for stdin).
        file: PathBuf,
        /// The value's JSON path, e.g. `transitions[3].guard`.
        at: String,
        /// What is wrong with it.
        problem: ContentProblem,
    },
}

/// What is wrong with one value of a well-formed document.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ContentProblem {
    /// A `format` this build does not read (a newer synth wrote it, or a typo).
    #[error("format {found} is not one this synth reads (it reads format {FORMAT}); a newer synth wrote it?")]
    Format {
        /// The version given.
        found: u32,
    },
    /// `states` is empty: a machine needs its initial state.
    #[error("the ECC has no states")]
    NoStates,
    /// An input or output name that is no identifier of the languages the tool writes.
    #[error("{} cannot be used as a name: {reason}", backquote(name))]
    BadName {
        /// The name as written.
        name: String,
        /// Which rule it breaks.
        reason: String,
    },
    /// Two signals with one name (inputs and outputs share one namespace).
    #[error("{} is already the name of {first}", backquote(name))]
    DuplicateName {
        /// The repeated name.
        name: String,
        /// The signal that has it first, e.g. `input 2`.
        first: String,
    },
    /// An output string (`initial_outputs`, an algorithm) of the wrong length.
    #[error("has {found} symbols but there are {expected} outputs")]
    Length {
        /// Symbols written.
        found: usize,
        /// Outputs of the machine.
        expected: usize,
    },
    /// A symbol an output string does not allow (`0`/`1`, plus `x` in algorithms).
    #[error("column {column}: `{found}` is not one of {allowed}")]
    Symbol {
        /// 1-based position in the string.
        column: usize,
        /// The symbol found.
        found: char,
        /// The symbols allowed there, in words.
        allowed: &'static str,
    },
    /// A state with neither algorithm form.
    #[error("a state needs `algorithm`, or `algorithm0` and `algorithm1`")]
    MissingAlgorithm,
    /// A state with both algorithm forms.
    #[error("`algorithm` cannot be given together with `algorithm0`/`algorithm1`")]
    BothAlgorithmForms,
    /// Three-valued and binary algorithms mixed in one machine.
    #[error("this state has a {this} algorithm but state 0 has a {first} one")]
    MixedAlgorithms {
        /// State 0's form (`three-valued` or `binary`).
        first: &'static str,
        /// This state's form.
        this: &'static str,
    },
    /// A transition's `from` or `to` past the last state.
    #[error("state {index} does not exist (there are {count} states)")]
    NoSuchState {
        /// The index given.
        index: usize,
        /// How many states there are.
        count: usize,
    },
    /// A guard that does not parse over the machine's inputs.
    #[error("{0}")]
    Guard(GuardTextError),
}

/// Writes the ECC as pretty JSON (two-space indent, fields in contract order, trailing newline).
/// The `Ecc` is expected to be valid ([`Ecc::validate`]).
pub(crate) fn write_json(ecc: &Ecc, w: &mut impl Write) -> io::Result<()> {
    let doc = Document {
        schema: None,
        format: Some(FORMAT),
        inputs: ecc.inputs.clone(),
        outputs: ecc.outputs.clone(),
        initial_outputs: Some(bits_to_string(&ecc.initial_outputs)),
        states: ecc
            .states
            .iter()
            .map(|s| {
                let (algorithm, algorithm0, algorithm1) = match &s.algorithm {
                    a @ Algorithm::Tri(_) => (Some(a.to_string()), None, None),
                    Algorithm::Binary { a0, a1 } => {
                        (None, Some(bits_to_string(a0)), Some(bits_to_string(a1)))
                    }
                };
                StateEntry {
                    name: s.name.clone(),
                    algorithm,
                    algorithm0,
                    algorithm1,
                }
            })
            .collect(),
        // The states are visited in order and each one's list is in priority order, so the
        // array comes out sorted by `from` with priorities kept.
        transitions: ecc
            .states
            .iter()
            .enumerate()
            .flat_map(|(i, s)| {
                s.transitions.iter().map(move |t| TransitionEntry {
                    from: i,
                    to: t.target.0,
                    guard: t.guard.display(&ecc.inputs).to_string(),
                })
            })
            .collect(),
    };
    serde_json::to_writer_pretty(&mut *w, &doc)?;
    writeln!(w)
}

/// [`write_json`] into a string.
pub fn to_string(ecc: &Ecc) -> String {
    let mut buf = Vec::new();
    write_json(ecc, &mut buf).expect("writing to a Vec does not fail");
    String::from_utf8(buf).expect("serde_json writes UTF-8")
}

/// Reads an ECC from JSON text; `file` is only used in error messages.
pub fn read_json(text: &str, file: &Path) -> Result<Ecc, JsonError> {
    let doc: Document = serde_json::from_str(text).map_err(|e| JsonError::Syntax {
        file: file.to_path_buf(),
        line: e.line(),
        column: e.column(),
        // serde_json quotes the key or string it did not expect, whatever its length.
        message: crate::quote::message(&strip_position(&e.to_string(), e.line(), e.column()))
            .to_string(),
    })?;
    read_document(doc).map_err(|(at, problem)| JsonError::Content {
        file: file.to_path_buf(),
        at,
        problem,
    })
}

/// A problem in a document's content, with the JSON path where it is.
type Located = (String, ContentProblem);

/// The machine a parsed document describes, or the first problem in it.
fn read_document(doc: Document) -> Result<Ecc, Located> {
    if let Some(found) = doc.format.filter(|&f| f != FORMAT) {
        return Err(("format".into(), ContentProblem::Format { found }));
    }
    check_names(&doc)?;
    let outputs = doc.outputs.len();
    let initial_outputs = match &doc.initial_outputs {
        None => vec![false; outputs],
        Some(s) => read_bits(s, outputs).map_err(|p| ("initial_outputs".to_string(), p))?,
    };
    if doc.states.is_empty() {
        return Err(("states".into(), ContentProblem::NoStates));
    }
    let mut states = read_states(&doc.states, outputs)?;
    let count = states.len();
    for (k, t) in doc.transitions.iter().enumerate() {
        for (field, index) in [("from", t.from), ("to", t.to)] {
            if index >= count {
                let at = format!("transitions[{k}].{field}");
                return Err((at, ContentProblem::NoSuchState { index, count }));
            }
        }
        let guard = parse_guard(&t.guard, &doc.inputs)
            .map_err(|e| (format!("transitions[{k}].guard"), ContentProblem::Guard(e)))?;
        states[t.from].transitions.push(Transition {
            target: StateId(t.to),
            guard,
        });
    }
    let ecc = Ecc {
        inputs: doc.inputs,
        outputs: doc.outputs,
        initial_outputs,
        states,
    };
    debug_assert_eq!(
        ecc.validate(),
        Ok(()),
        "read_json checks everything validate does"
    );
    Ok(ecc)
}

/// The states of a document, without their transitions; every algorithm of one kind.
fn read_states(docs: &[StateEntry], outputs: usize) -> Result<Vec<State>, Located> {
    let mut states: Vec<State> = Vec::with_capacity(docs.len());
    for (i, s) in docs.iter().enumerate() {
        let algorithm =
            read_algorithm(s, outputs).map_err(|(field, p)| (format!("states[{i}]{field}"), p))?;
        if let Some(first) = states.first().map(|s0| s0.algorithm.kind()) {
            if algorithm.kind() != first {
                let problem = ContentProblem::MixedAlgorithms {
                    first: kind_name(first),
                    this: kind_name(algorithm.kind()),
                };
                return Err((format!("states[{i}]"), problem));
            }
        }
        states.push(State {
            name: s.name.clone(),
            algorithm,
            transitions: Vec::new(),
        });
    }
    Ok(states)
}

/// serde_json appends " at line L column C" to its messages; the position has its own fields.
fn strip_position(message: &str, line: usize, column: usize) -> String {
    let suffix = format!(" at line {line} column {column}");
    message.strip_suffix(&suffix).unwrap_or(message).to_string()
}

fn kind_name(k: AlgorithmKind) -> &'static str {
    match k {
        AlgorithmKind::Tri => "tri (`algorithm`)",
        AlgorithmKind::Binary => "binary (`algorithm0`/`algorithm1`)",
    }
}

/// Interface and state names: identifiers, not the event names, no duplicates.
fn check_names(doc: &Document) -> Result<(), Located> {
    // Interface names clash in Structured Text and 4diac when they differ only in case.
    let mut interface: HashMap<String, String> = HashMap::new();
    let named = (doc
        .inputs
        .iter()
        .enumerate()
        .map(|(i, n)| (format!("inputs[{i}]"), n)))
    .chain(
        doc.outputs
            .iter()
            .enumerate()
            .map(|(i, n)| (format!("outputs[{i}]"), n)),
    );
    for (at, name) in named {
        let bad = |reason: String| ContentProblem::BadName {
            name: name.clone(),
            reason,
        };
        check_identifier(name).map_err(|r| (at.clone(), bad(r)))?;
        let key = name.to_ascii_uppercase();
        if key == "REQ" || key == "CNF" {
            return Err((at, bad("REQ and CNF name the events of the block".into())));
        }
        if let Some(first) = interface.get(&key) {
            return Err((
                at,
                ContentProblem::DuplicateName {
                    name: name.clone(),
                    first: first.clone(),
                },
            ));
        }
        interface.insert(key, at);
    }
    let mut states: HashMap<&str, String> = HashMap::new();
    for (i, s) in doc.states.iter().enumerate() {
        let at = format!("states[{i}].name");
        check_identifier(&s.name).map_err(|reason| {
            (
                at.clone(),
                ContentProblem::BadName {
                    name: s.name.clone(),
                    reason,
                },
            )
        })?;
        if let Some(first) = states.get(s.name.as_str()) {
            return Err((
                at,
                ContentProblem::DuplicateName {
                    name: s.name.clone(),
                    first: first.clone(),
                },
            ));
        }
        states.insert(&s.name, format!("states[{i}]"));
    }
    Ok(())
}

/// A state's algorithm; the error names the field (`.algorithm0`, or empty for the state).
fn read_algorithm(
    s: &StateEntry,
    outputs: usize,
) -> Result<Algorithm, (&'static str, ContentProblem)> {
    match (&s.algorithm, &s.algorithm0, &s.algorithm1) {
        (Some(t), None, None) => {
            check_length(t, outputs).map_err(|p| (".algorithm", p))?;
            let symbols = t
                .chars()
                .enumerate()
                .map(|(k, c)| {
                    Tri::from_symbol(c).ok_or(ContentProblem::Symbol {
                        column: k + 1,
                        found: c,
                        allowed: "`0`, `1`, `x`",
                    })
                })
                .collect::<Result<Vec<_>, _>>()
                .map_err(|p| (".algorithm", p))?;
            Ok(Algorithm::Tri(symbols))
        }
        (None, Some(a0), Some(a1)) => Ok(Algorithm::Binary {
            a0: read_bits(a0, outputs).map_err(|p| (".algorithm0", p))?,
            a1: read_bits(a1, outputs).map_err(|p| (".algorithm1", p))?,
        }),
        (Some(_), _, _) => Err(("", ContentProblem::BothAlgorithmForms)),
        _ => Err(("", ContentProblem::MissingAlgorithm)),
    }
}

fn check_length(s: &str, expected: usize) -> Result<(), ContentProblem> {
    let found = s.chars().count();
    if found == expected {
        Ok(())
    } else {
        Err(ContentProblem::Length { found, expected })
    }
}

/// One `0`/`1` per output.
fn read_bits(s: &str, outputs: usize) -> Result<Vec<bool>, ContentProblem> {
    check_length(s, outputs)?;
    bits_from_str(s).ok_or_else(|| {
        let (k, c) = s
            .chars()
            .enumerate()
            .find(|(_, c)| !matches!(c, '0' | '1'))
            .expect("bits_from_str fails only on a character other than 0 and 1");
        ContentProblem::Symbol {
            column: k + 1,
            found: c,
            allowed: "`0`, `1`",
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::samples;

    /// One snapshot per sample ECC, named after the sample.
    #[test]
    fn snapshots() {
        samples::snapshot_each_sample!(to_string);
    }

    #[test]
    fn json_ecc_json_round_trip_is_identical() {
        for (name, ecc) in samples::all() {
            let text = to_string(&ecc);
            let back = read_json(&text, Path::new("t.json")).unwrap();
            assert_eq!(back, ecc, "{name}");
            assert_eq!(to_string(&back), text, "{name}");
        }
    }

    #[test]
    fn fixture_with_interleaved_transitions_reads_in_priority_order() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/export/cylinder.json");
        let text = std::fs::read_to_string(&path).unwrap();
        let ecc = read_json(&text, &path).unwrap();
        let s0: Vec<usize> = ecc.states[0]
            .transitions
            .iter()
            .map(|t| t.target.0)
            .collect();
        assert_eq!(s0, vec![1, 0]);
        assert_eq!(ecc.initial_outputs, vec![false, true]);
        // Written back, transitions are grouped by source, `X` becomes `x`.
        let out = to_string(&ecc);
        assert!(out.contains("\"algorithm\": \"1x\""), "{out}");
        let first_from_1 = out.find("\"from\": 1").unwrap();
        assert!(out.rfind("\"from\": 0").unwrap() < first_from_1, "{out}");
    }

    /// `format` is written first, read when it is 1 or absent, refused when newer; `$schema` is
    /// accepted and ignored.
    #[test]
    fn the_format_version_and_a_schema_reference() {
        let text = to_string(&samples::tri());
        assert!(text.starts_with("{\n  \"format\": 1,\n"), "{text}");
        let marked = text.replacen('{', r#"{"$schema": "machine.schema.json","#, 1);
        assert_eq!(
            read_json(&marked, Path::new("t.json")).unwrap(),
            samples::tri()
        );
        let unversioned = text.replacen("\"format\": 1,", "", 1);
        assert_eq!(
            read_json(&unversioned, Path::new("t.json")).unwrap(),
            samples::tri()
        );
        let newer = text.replacen("\"format\": 1", "\"format\": 2", 1);
        assert_eq!(
            read_json(&newer, Path::new("t.json"))
                .unwrap_err()
                .to_string(),
            "t.json: format: format 2 is not one this synth reads (it reads format 1); a newer \
             synth wrote it?"
        );
    }

    #[test]
    fn missing_initial_outputs_means_all_zero() {
        let text = r#"{"inputs":["a"],"outputs":["z","y"],
            "states":[{"name":"s0","algorithm":"1x"}],"transitions":[]}"#;
        let ecc = read_json(text, Path::new("t.json")).unwrap();
        assert_eq!(ecc.initial_outputs, vec![false, false]);
    }

    /// A valid two-state document with one spot marked `@` to be replaced by each case.
    fn base(replace: &str, with: &str) -> String {
        let text = r#"{
  "inputs": ["a", "b"],
  "outputs": ["z", "y"],
  "initial_outputs": "01",
  "states": [
    {"name": "s0", "algorithm": "xx"},
    {"name": "s1", "algorithm": "10"}
  ],
  "transitions": [
    {"from": 0, "to": 1, "guard": "a & !b"},
    {"from": 1, "to": 0, "guard": "TRUE"}
  ]
}"#;
        assert!(text.contains(replace), "{replace}");
        text.replacen(replace, with, 1)
    }

    fn error(text: &str) -> String {
        read_json(text, Path::new("dir/m.json"))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn base_document_is_valid() {
        read_json(&base("", ""), Path::new("t.json")).unwrap();
    }

    #[test]
    fn syntax_errors_have_line_and_column() {
        assert_eq!(
            error(&base("\"01\",", "\"01\"")),
            "dir/m.json:5:3: expected `,` or `}`"
        );
        assert_eq!(
            error(&base("\"from\": 1", "\"from\": -1")),
            "dir/m.json:11:15: invalid value: integer `-1`, expected usize"
        );
        let e = error(&base("\"guard\": \"TRUE\"", "\"gaurd\": \"TRUE\""));
        assert_eq!(
            e,
            "dir/m.json:11:32: unknown field `gaurd`, expected one of `from`, `to`, `guard`"
        );
        assert!(error(&base("\"outputs\"", "\"outputz\"")).starts_with("dir/m.json:3:"));
    }

    #[test]
    fn content_errors_name_the_json_path() {
        let cases = [
            (
                ("\"10\"}", "\"1\"}"),
                "dir/m.json: states[1].algorithm: has 1 symbols but there are 2 outputs",
            ),
            (
                ("\"10\"}", "\"1-\"}"),
                "dir/m.json: states[1].algorithm: column 2: `-` is not one of `0`, `1`, `x`",
            ),
            (
                ("\"01\"", "\"0x\""),
                "dir/m.json: initial_outputs: column 2: `x` is not one of `0`, `1`",
            ),
            (
                (
                    "\"algorithm\": \"10\"",
                    "\"algorithm0\": \"10\", \"algorithm1\": \"11\"",
                ),
                "dir/m.json: states[1]: this state has a binary (`algorithm0`/`algorithm1`) \
                 algorithm but state 0 has a tri (`algorithm`) one",
            ),
            (
                ("\"algorithm\": \"10\"", "\"algorithm0\": \"10\""),
                "dir/m.json: states[1]: a state needs `algorithm`, or `algorithm0` and \
                 `algorithm1`",
            ),
            (
                (
                    "\"algorithm\": \"10\"",
                    "\"algorithm\": \"10\", \"algorithm1\": \"10\"",
                ),
                "dir/m.json: states[1]: `algorithm` cannot be given together with \
                 `algorithm0`/`algorithm1`",
            ),
            (
                ("\"a & !b\"", "\"a & !vac\""),
                "dir/m.json: transitions[0].guard: column 6: unknown input `vac`",
            ),
            (
                ("\"a & !b\"", "\"a & \""),
                "dir/m.json: transitions[0].guard: column 5: expected an operand",
            ),
            (
                ("\"to\": 0", "\"to\": 2"),
                "dir/m.json: transitions[1].to: state 2 does not exist (there are 2 states)",
            ),
            (
                ("{\"from\": 0", "{\"from\": 7"),
                "dir/m.json: transitions[0].from: state 7 does not exist (there are 2 states)",
            ),
            (
                ("[\"z\", \"y\"]", "[\"z\", \"B\"]"),
                "dir/m.json: outputs[1]: `B` is already the name of inputs[1]",
            ),
            (
                ("\"name\": \"s1\"", "\"name\": \"s0\""),
                "dir/m.json: states[1].name: `s0` is already the name of states[0]",
            ),
            (
                ("[\"a\", \"b\"]", "[\"a\", \"c-d\"]"),
                "dir/m.json: inputs[1]: `c-d` cannot be used as a name: a name may contain \
                 only letters A-Z a-z, digits and `_`, not `-`",
            ),
            (
                ("[\"a\", \"b\"]", "[\"a\", \"next\"]"),
                "dir/m.json: inputs[1]: `next` cannot be used as a name: it is a NuSMV keyword",
            ),
            (
                ("[\"z\", \"y\"]", "[\"z\", \"Cnf\"]"),
                "dir/m.json: outputs[1]: `Cnf` cannot be used as a name: REQ and CNF name the \
                 events of the block",
            ),
            (
                ("\"name\": \"s1\"", "\"name\": \"_s1\""),
                "dir/m.json: states[1].name: `_s1` cannot be used as a name: names starting \
                 with `_` are reserved for generated identifiers",
            ),
        ];
        for ((replace, with), expected) in cases {
            assert_eq!(error(&base(replace, with)), expected, "{with}");
        }
        let no_states = r#"{"inputs":[],"outputs":[],"states":[],"transitions":[]}"#;
        assert_eq!(
            error(no_states),
            "dir/m.json: states: the ECC has no states"
        );
    }
}
