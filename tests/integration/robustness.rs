//! Robustness under hostile input: every parser of user input is driven by
//! arbitrary bytes and by mutations of the repository's own valid files. Every call must
//! return (a panic fails the case), and a refusal must be located: its message is not empty,
//! stays short, names the file it was given and, where the error has a line, that line is a
//! line of the input.
//!
//! Each parser has two tests, one per strategy, of [`cases()`] cases each
//! (`FBSYNTH_ROBUSTNESS_CASES`, default [`DEFAULT_CASES`]). The ignored
//! [`robustness_long_run`] loops over all parsers for `FBSYNTH_ROBUSTNESS_SECS` seconds
//! (default 600) and prints the cases run per parser.

use crate::common::Dir;
use fbsynth::events::ResetActivity;
use fbsynth::export::guard_text::parse_guard;
use fbsynth::export::json::{read_json, JsonError};
use fbsynth::files::{read_text, FileReadError};
use fbsynth::ingest::{IngestError, Mapping};
use fbsynth::ltl::{parse_spec_file, LtlError};
use fbsynth::nusmv::{parse_errors, parse_output};
use fbsynth::plant::ModelError;
use fbsynth::scenario::tree::ScenarioTree;
use fbsynth::scenario::{csvlog, fbsat, names, ScenarioError};
use fbsynth::smv::plant::{read_plant, PlantError};
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::{Config, TestCaseError, TestError, TestRunner};
use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::sync::LazyLock;
use std::time::{Duration, Instant};

/// Cases per strategy and parser in the normal run: with two strategies, 3000 per parser.
const DEFAULT_CASES: u32 = 1500;

/// The longest error message accepted, in bytes. Messages cut the user input they quote
/// (`fbsynth::quote`), so only the file's path and a few lines of text remain.
const MAX_MESSAGE: usize = 4096;

/// Cases per strategy, from `FBSYNTH_ROBUSTNESS_CASES` or [`DEFAULT_CASES`].
fn cases() -> u32 {
    std::env::var("FBSYNTH_ROBUSTNESS_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_CASES)
}

/// The runner's configuration: `cases` cases, and no regression file, which proptest would
/// otherwise write beside this file on a failure and leave in the work tree.
fn config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: None,
        // A failure is shrunk to a small input; a bound keeps a slow parser from shrinking
        // for minutes.
        max_shrink_time: 60_000,
        ..Config::default()
    }
}

/// A file of the repository, as bytes.
fn repo_file(path: &str) -> Vec<u8> {
    let full = Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read(&full).unwrap_or_else(|e| panic!("reading {}: {e}", full.display()))
}

/// The first `n` lines of a repository file: large seeds cut to keep each case fast.
fn repo_lines(path: &str, n: usize) -> Vec<u8> {
    let text = repo_file(path);
    let mut out = Vec::new();
    for line in text.split_inclusive(|&b| b == b'\n').take(n) {
        out.extend_from_slice(line);
    }
    out
}

/// The first `n` scenarios of an fbSAT scenario file, with the count line to match.
fn fbsat_head(path: &str, n: usize) -> Vec<u8> {
    let text = repo_lines(path, n + 1);
    let first = text.iter().position(|&b| b == b'\n').expect("a count line") + 1;
    [format!("{n}\n").into_bytes(), text[first..].to_vec()].concat()
}

// ---------------------------------------------------------------------------------------------
// What a refusal must be.

/// The lines of `bytes` as `str::lines` counts them (a last line without a line break counts).
fn line_count(bytes: &[u8]) -> usize {
    let breaks = bytes.iter().filter(|&&b| b == b'\n').count();
    breaks + usize::from(!bytes.is_empty() && !bytes.ends_with(b"\n"))
}

/// What a parser did with an input that it handled as promised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Parsed {
    Accepted,
    /// Refused with a located error.
    Refused,
}

/// Checks a refusal: `message` (the error's Display) is not empty, at most [`MAX_MESSAGE`]
/// bytes, names `file` when one is given, and every line in `lines` is within
/// `1..=line_count(input) + 1` (one past the last line: the end of the file).
fn located(
    message: &str,
    file: Option<&Path>,
    lines: &[usize],
    input: &[u8],
) -> Result<Parsed, TestCaseError> {
    let shown = || message.chars().take(300).collect::<String>();
    if message.trim().is_empty() {
        return Err(TestCaseError::fail("empty error message"));
    }
    if message.len() > MAX_MESSAGE {
        return Err(TestCaseError::fail(format!(
            "error message of {} bytes: {}…",
            message.len(),
            shown()
        )));
    }
    if let Some(file) = file {
        if !message.contains(&file.display().to_string()) {
            return Err(TestCaseError::fail(format!(
                "error does not name {}: {}",
                file.display(),
                shown()
            )));
        }
    }
    let last = line_count(input) + 1;
    for &line in lines {
        if !(1..=last).contains(&line) {
            return Err(TestCaseError::fail(format!(
                "line {line} is outside 1..={last}: {}",
                shown()
            )));
        }
    }
    Ok(Parsed::Refused)
}

/// The line of a read error, if it is on one.
fn read_line(e: &FileReadError) -> Vec<usize> {
    e.error.line().into_iter().collect()
}

/// The lines a scenario error points to (both places of a contradiction).
fn scenario_lines(e: &ScenarioError) -> Vec<usize> {
    match e {
        ScenarioError::Syntax { line, .. }
        | ScenarioError::Step { line, .. }
        | ScenarioError::Names { line, .. } => vec![*line],
        ScenarioError::Read(e) => read_line(e),
        ScenarioError::Contradiction(c) => vec![c.first.line, c.second.line],
        ScenarioError::Io { .. } | ScenarioError::Gzip { .. } | ScenarioError::Other(_) => {
            Vec::new()
        }
    }
}

/// The line an ingestion error points to, if any.
fn ingest_lines(e: &IngestError) -> Vec<usize> {
    match e {
        IngestError::Mapping { line, .. }
        | IngestError::Header { line, .. }
        | IngestError::Row { line, .. } => vec![*line],
        IngestError::Read(e) => read_line(e),
        IngestError::Parquet(e) => scenario_lines(e),
        IngestError::Io { .. } | IngestError::Write(_) | IngestError::NoData { .. } => Vec::new(),
    }
}

// ---------------------------------------------------------------------------------------------
// The parsers.

/// One parser under test: where its input comes from and what it must do with it.
struct Target {
    name: &'static str,
    /// The input file's name (its extension matters to no parser here).
    file: &'static str,
    /// Valid inputs from the repository: the starting points of mutations.
    seeds: fn() -> Vec<Vec<u8>>,
    /// Tokens of the format, for token soup and for insertions.
    vocabulary: &'static [&'static str],
    /// Feeds `input` (written to `path` first where the parser reads files) to the parser;
    /// `flag` picks a variant (names files given, lenient mode).
    check: fn(path: &Path, input: &[u8], flag: bool) -> Result<Parsed, TestCaseError>,
}

/// Writes `input` to `path` for the parsers that read files.
fn write(path: &Path, input: &[u8]) {
    std::fs::write(path, input).unwrap_or_else(|e| panic!("writing {}: {e}", path.display()));
}

/// Owned names, as the parsers take them.
fn names(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| s.to_string()).collect()
}

/// fbSAT scenario files, read as `synth` reads them, then built into a scenario tree (which
/// finds contradictions and names both places).
fn check_fbsat(path: &Path, input: &[u8], flag: bool) -> Result<Parsed, TestCaseError> {
    write(path, input);
    // The names of tests/data/scenarios/door.*: the widths of the files the mutations start
    // from.
    let (i, o) = match flag {
        true => (
            Some(names(&["start", "stop"])),
            Some(names(&["motor", "lamp"])),
        ),
        false => (None, None),
    };
    let result = fbsat::read(path, i, o).and_then(|set| ScenarioTree::build(&set).map(drop));
    match result {
        Ok(()) => Ok(Parsed::Accepted),
        Err(e) => located(&e.to_string(), Some(path), &scenario_lines(&e), input),
    }
}

/// CSV scenario logs.
fn check_csvlog(path: &Path, input: &[u8], flag: bool) -> Result<Parsed, TestCaseError> {
    write(path, input);
    // The interface of tests/data/noisy/skewed.csv.
    let (i, o) = (names(&["a", "b"]), names(&["z"]));
    let (i, o) = match flag {
        true => (Some(i.as_slice()), Some(o.as_slice())),
        false => (None, None),
    };
    match csvlog::read(path, i, o) {
        Ok(_) => Ok(Parsed::Accepted),
        Err(e) => located(&e.to_string(), Some(path), &scenario_lines(&e), input),
    }
}

/// The mapping of the tank's logs, which the raw-log seeds use.
static TANK_MAP: LazyLock<Mapping> = LazyLock::new(|| {
    Mapping::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("specs/tank/tank.map"))
        .expect("specs/tank/tank.map is a valid mapping")
});

/// Raw PLC logs, read whole into a scenario (strict, or lenient when `flag`).
fn check_raw_log(path: &Path, input: &[u8], flag: bool) -> Result<Parsed, TestCaseError> {
    write(path, input);
    match fbsynth::ingest::read_scenarios(path, &TANK_MAP, flag) {
        Ok(_) => Ok(Parsed::Accepted),
        Err(e) => located(&e.to_string(), Some(path), &ingest_lines(&e), input),
    }
}

/// Mapping files.
fn check_mapping(path: &Path, input: &[u8], _: bool) -> Result<Parsed, TestCaseError> {
    write(path, input);
    match Mapping::read(path) {
        Ok(_) => Ok(Parsed::Accepted),
        Err(e) => located(&e.to_string(), Some(path), &ingest_lines(&e), input),
    }
}

/// Names files.
fn check_names(path: &Path, input: &[u8], _: bool) -> Result<Parsed, TestCaseError> {
    write(path, input);
    match names::read_names(path) {
        Ok(_) => Ok(Parsed::Accepted),
        Err(e) => located(&e.to_string(), Some(path), &scenario_lines(&e), input),
    }
}

/// LTL specification files.
fn check_ltl(path: &Path, input: &[u8], _: bool) -> Result<Parsed, TestCaseError> {
    write(path, input);
    match parse_spec_file(path) {
        Ok(_) => Ok(Parsed::Accepted),
        Err(e) => {
            let lines = match &e {
                LtlError::At { line, column, .. } => {
                    prop_assert!(*column >= 1, "column 0: {e}");
                    vec![*line]
                }
                LtlError::Read(r) => read_line(r),
                LtlError::Io { .. } | LtlError::Empty { .. } => Vec::new(),
            };
            located(&e.to_string(), Some(path), &lines, input)
        }
    }
}

/// Plant files of the SMV subset, parsed into a model.
fn check_plant(path: &Path, input: &[u8], _: bool) -> Result<Parsed, TestCaseError> {
    write(path, input);
    match fbsynth::plant::parse::parse_file(path) {
        Ok(_) => Ok(Parsed::Accepted),
        Err(e) => {
            let lines = match &e {
                ModelError::At { line, column, .. } => {
                    prop_assert!(*column >= 1, "column 0: {e}");
                    vec![*line]
                }
                ModelError::Read(r) => read_line(r),
                ModelError::Io { .. } => Vec::new(),
            };
            located(&e.to_string(), Some(path), &lines, input)
        }
    }
}

/// Plant files scanned for the coupling with the controller (NuSMV reads the rest).
fn check_plant_scan(path: &Path, input: &[u8], _: bool) -> Result<Parsed, TestCaseError> {
    write(path, input);
    match read_plant(path) {
        Ok(plant) => {
            let last = line_count(input) + 1;
            let lines = plant.params.iter().chain(&plant.names).map(|d| d.line);
            for line in lines.chain([plant.module_line]) {
                prop_assert!((1..=last).contains(&line), "declaration on line {line}");
            }
            Ok(Parsed::Accepted)
        }
        Err(e) => {
            let lines = match &e {
                PlantError::At { line, .. } => vec![*line],
                PlantError::Read(r) => read_line(r),
            };
            located(&e.to_string(), Some(path), &lines, input)
        }
    }
}

/// NuSMV's stdout (verdicts and traces), read as the driver reads it (lossy UTF-8). No file:
/// the output comes from a pipe.
fn check_nusmv(_: &Path, input: &[u8], _: bool) -> Result<Parsed, TestCaseError> {
    let text = String::from_utf8_lossy(input);
    match parse_output(&text) {
        Ok(_) => Ok(Parsed::Accepted),
        Err(e) => {
            prop_assert!(e.column >= 1, "column 0: {e}");
            located(&e.to_string(), None, &[e.line], text.as_bytes())
        }
    }
}

/// NuSMV's stderr: the errors with their places. Lines without one are skipped, so nothing
/// is refused; the message NuSMV quotes must be cut.
fn check_nusmv_errors(_: &Path, input: &[u8], _: bool) -> Result<Parsed, TestCaseError> {
    let text = String::from_utf8_lossy(input);
    for e in parse_errors(&text) {
        let shown = e.to_string();
        // The file is NuSMV's name for the model, which synth chose.
        prop_assert!(
            shown.len() <= e.file.len() + MAX_MESSAGE,
            "message of {} bytes",
            shown.len()
        );
    }
    Ok(Parsed::Accepted)
}

/// JSON machines, read as `synth` reads them (`pipeline::recordings::read_ecc`: the file's
/// text, then the contract).
fn check_json(path: &Path, input: &[u8], _: bool) -> Result<Parsed, TestCaseError> {
    write(path, input);
    let text = match read_text(path, None) {
        Ok(text) => text,
        Err(e) => return located(&e.to_string(), Some(path), &read_line(&e), input),
    };
    match read_json(&text, path) {
        Ok(ecc) => {
            prop_assert_eq!(ecc.validate(), Ok(()));
            Ok(Parsed::Accepted)
        }
        Err(e) => {
            let lines = match &e {
                JsonError::Syntax { line, .. } => vec![*line],
                JsonError::Content { .. } => Vec::new(),
            };
            located(&e.to_string(), Some(path), &lines, text.as_bytes())
        }
    }
}

/// The inputs the guard seeds are written over (specs/distribution_reference.json).
const GUARD_INPUTS: &[&str] = &[
    "empty",
    "retracted",
    "extended",
    "at_magazine",
    "at_client",
    "vac_on",
    "start",
    "stop",
    "auto_man",
    "emergency",
];

/// Guard text, the recursive parser inside JSON machines, fed directly so that deep nesting
/// and long chains reach it without breaking the JSON around them. No file or line: the
/// error's column must be within the guard.
fn check_guard(_: &Path, input: &[u8], _: bool) -> Result<Parsed, TestCaseError> {
    let text = String::from_utf8_lossy(input);
    match parse_guard(&text, &names(GUARD_INPUTS)) {
        Ok(_) => Ok(Parsed::Accepted),
        Err(e) => {
            let last = text.chars().count() + 1;
            prop_assert!(
                (1..=last).contains(&e.column()),
                "column outside 1..={last}: {e}"
            );
            located(&e.to_string(), None, &[], input)
        }
    }
}

/// The `--reset` activity of `synth events`, over the tank's mapping.
fn check_reset(_: &Path, input: &[u8], _: bool) -> Result<Parsed, TestCaseError> {
    let text = String::from_utf8_lossy(input);
    match ResetActivity::parse(&text, &TANK_MAP) {
        Ok(_) => Ok(Parsed::Accepted),
        Err(e) => located(&e.to_string(), None, &[], input),
    }
}

/// Digits beyond every integer type, and numbers at the edges of the ones used.
const NUMBERS: &[&str] = &[
    "0",
    "1",
    "-1",
    "2147483647",
    "2147483648",
    "-2147483649",
    "4294967296",
    "9223372036854775808",
    "18446744073709551616",
    "99999999999999999999999999999999999999",
    "1e400",
    "-1e400",
    "NaN",
    "inf",
    "-0",
    "9e12",
    "9.000000001e12",
    "0x10",
];

/// Bytes that no format expects: a byte order mark, gzip's magic, NUL, invalid UTF-8.
const STRANGE: &[&str] = &[
    "\u{feff}",
    "\x1f\u{8b}",
    "\0",
    "\r",
    "\r\n",
    "\n",
    "\t",
    " ",
    "é",
    "\u{202e}",
    "𝕏",
];

// The vocabularies: tokens of each format, inserted by mutations and strung together into
// token soup.

#[rustfmt::skip]
const FBSAT_WORDS: &[&str] = &[
    "in=REQ[", "out=CNF[", "in=REQ[0]", "out=CNF[1]", "in", "out", "=", "[", "]", ";", "; ",
    "REQ", "CNF", "0", "1", "01", "10", "2", "x", "\n", "0\n", "1\n", "99999999999999999999\n",
    "-1\n",
];

#[rustfmt::skip]
const CSV_WORDS: &[&str] = &[
    ",", ";", "\"", "\"\"", "\n", "\r\n", "in:", "out:", "in:a", "out:z", "a", "b", "z", "time",
    "timestamp", "scenario", "true", "FALSE", "0", "1", "yes", "in:in:", ",,,,", "\"a\nb\"",
];

#[rustfmt::skip]
const RAW_LOG_WORDS: &[&str] = &[
    ",", "\"", "\n", "\r\n", "timestamp,address,value\n", "timestamp,", "time", "address",
    "value", "%IX0.1", "%IX0.0", "%QX0.0", "%QX0.1", "ll", "inlet", "outlet", "true", "false",
    "TRUE", "0", "1", "2", "0.01", "-9e12", "1e20", ",%IX0.1,1\n", "\"%IX0.1\"",
];

#[rustfmt::skip]
const MAPPING_WORDS: &[&str] = &[
    "in", "out", " in ", " out ", "#", "%IX0.1", "%QX0.0", "ll", "inlet", "start", ",", "1x",
    "REQ", "\n", "\r\n", "\t", "%IX0.1 in ll\n", "ll out ll\n",
];

#[rustfmt::skip]
const NAMES_WORDS: &[&str] = &[
    "a", "b", "_a", "1x", "x1", "c1Home", "REQ", "MODULE", "é", " ", "\n", "\r\n", "\t", "a-b",
    "a.b",
];

#[rustfmt::skip]
const LTL_WORDS: &[&str] = &[
    "G", "F", "X", "U", "V", "Y", "Z", "H", "O", "S", "T", " G ", " U ", "!", "(", ")", "&", "|",
    "->", "<->", "xor", "xnor", "=", "!=", "<", "<=", ">", ">=", "--", ":", "label:", "p0:",
    "p1:", "p2:", "TRUE", "FALSE", "next", "MODULE", "a.b", "plant.x", "x$#-y", "(((((((((((",
    "!!!!!!!!", "\n", "\r\n",
];

#[rustfmt::skip]
const PLANT_WORDS: &[&str] = &[
    "MODULE", "plant", "MODULE plant", "MODULE main", "VAR", "IVAR", "FROZENVAR", "DEFINE",
    "ASSIGN", "INIT", "INVAR", "TRANS", "FAIRNESS", "JUSTICE", "COMPASSION", "LTLSPEC", "init(",
    "next(", "case", "esac", "case TRUE : 0; esac", "{", "}", "(", ")", "[", "]", ":", ":=", ";",
    ",", "..", "?", "->", "<->", "|", "&", "!", "-", "+", "*", "/", "mod", "xor", "=", "!=", "<",
    ">", "<=", "boolean", "TRUE", "FALSE", "0..3", "-3..-1", "{a, b}", "x", "plant.x", "0ub4_1",
    "--", "\n", "\r\n", " ", "integer", "array", "process", "self", "word", "a ? b : c",
];

#[rustfmt::skip]
const NUSMV_WORDS: &[&str] = &[
    "-- specification ", "  is true\n", "  is false\n", " is ", "'p1'", "[3]",
    "-- as demonstrated by the following execution sequence\n",
    "Trace Description: LTL Counterexample \n", "Trace Type: Counterexample \n",
    "-> State: 1.1 <-\n", "-> State: 1.2 <-\n", "-> Input: 1.2 <-\n", "-- Loop starts here\n",
    "  a = TRUE\n", "  plant.x = 3\n", "  ", " = ", "NuSMV > ", "*** ", "\n", "\r\n",
];

#[rustfmt::skip]
const NUSMV_ERROR_WORDS: &[&str] = &[
    "file m.smv: line 3: ", "file ", ": line ", "TYPE ERROR ", "ERROR: ", "line ", " : ", ":",
    "Parser error", "at token \"c\": syntax error", "\n", "\r\n", "==model-1==",
];

#[rustfmt::skip]
const JSON_WORDS: &[&str] = &[
    "{", "}", "[", "]", ",", ":", "\"", "\"inputs\"", "\"outputs\"", "\"states\"",
    "\"transitions\"", "\"initial_outputs\"", "\"name\"", "\"algorithm\"", "\"algorithm0\"",
    "\"algorithm1\"", "\"from\"", "\"to\"", "\"guard\"", "null", "true", "\"\"", "\"x\"", "\"01\"",
    "\"1x\"", "\\u0000", "\\ud800", "\\\"", "!", "(", ")", "&", "|", "TRUE", "FALSE", "atHome",
    "REQ", "-1", "1.5", "{\"from\": 0, \"to\": 0, \"guard\": \"TRUE\"}", "[[[[[[[[[[",
    "((((((((((", "!!!!!!!!!!",
];

#[rustfmt::skip]
const GUARD_WORDS: &[&str] = &[
    "!", "&", "|", "(", ")", " ", "TRUE", "FALSE", "start", "stop", "emergency", "empty", "x",
    "&&", "!(", "((((((((((", "!!!!!!!!!!", "! ! ! ! !",
];

#[rustfmt::skip]
const RESET_WORDS: &[&str] = &[
    "+", " + ", " ", "%IX0.1", "%QX0.0", "ll", "inlet", "true", "false", "0", "1", "TRUE", "yes",
];

/// Every parser under test.
fn targets() -> Vec<Target> {
    vec![
        Target {
            name: "fbSAT scenarios",
            file: "input.traces",
            seeds: || {
                vec![
                    repo_file("tests/data/scenarios/door.traces"),
                    repo_file("tests/data/scenarios/door_new.traces"),
                    repo_file("tests/data/scenarios/lamps.traces"),
                    fbsat_head("specs/pnp.traces", 2),
                ]
            },
            vocabulary: FBSAT_WORDS,
            check: check_fbsat,
        },
        Target {
            name: "CSV scenario logs",
            file: "input.csv",
            seeds: || {
                vec![
                    repo_file("tests/data/noisy/skewed.csv"),
                    repo_lines("specs/distribution.csv", 30),
                    // `;` separators, quotes, CRLF, a blank line, two scenarios.
                    b"\"time\";\"scenario\";\"in:a\";\"in:b\";\"out:z\"\r\n0;s;0;\"1\";false\r\n\
                      1;s;TRUE;1;1\r\n\r\n2;t;0;0;0\r\n"
                        .to_vec(),
                ]
            },
            vocabulary: CSV_WORDS,
            check: check_csvlog,
        },
        Target {
            name: "raw PLC logs",
            file: "input.log.csv",
            seeds: || {
                vec![
                    repo_file("specs/tank/scenario1.csv"),
                    // The wide format over the same mapping, by address and by name.
                    b"timestamp,%IX0.1,%IX0.2,ul,%QX0.0,outlet\n0,0,0,0,1,0\n0.5,1,0,0,1,0\n\
                      1,1,1,0,1,0\n1,1,1,1,0,1\n"
                        .to_vec(),
                ]
            },
            vocabulary: RAW_LOG_WORDS,
            check: check_raw_log,
        },
        Target {
            name: "mapping files",
            file: "input.map",
            seeds: || {
                vec![
                    repo_file("specs/tank/tank.map"),
                    b"# address side name\n%IX0.1 in start\n%IX0.2\tin stop # comment\r\n\
                      %QX0.0 out motor\n"
                        .to_vec(),
                ]
            },
            vocabulary: MAPPING_WORDS,
            check: check_mapping,
        },
        Target {
            name: "names files",
            file: "input.inputs",
            seeds: || {
                vec![
                    repo_file("specs/pnp.inputs"),
                    repo_file("tests/data/scenarios/lamps.inputs"),
                    repo_file("specs/tank1.inputs"),
                ]
            },
            vocabulary: NAMES_WORDS,
            check: check_names,
        },
        Target {
            name: "LTL specifications",
            file: "input.ltl",
            seeds: || {
                vec![
                    repo_file("specs/pnp.ltl"),
                    repo_file("specs/tank1.ltl"),
                    repo_file("specs/distribution.ltl"),
                    repo_file("tests/data/closed_loop/lamp.ltl"),
                ]
            },
            vocabulary: LTL_WORDS,
            check: check_ltl,
        },
        Target {
            name: "SMV plant subset",
            file: "input.smv",
            seeds: || {
                vec![
                    repo_file("smv/pnp_surrogate.smv"),
                    repo_file("smv/tank_surrogate.smv"),
                    repo_file("smv/distribution_surrogate.smv"),
                    repo_file("tests/data/closed_loop/lamp_ivar_plant.smv"),
                    repo_file("tests/data/closed_loop/slow_plant.smv"),
                ]
            },
            vocabulary: PLANT_WORDS,
            check: check_plant,
        },
        Target {
            name: "SMV plant scan",
            file: "input.smv",
            seeds: || {
                vec![
                    repo_file("smv/pnp_surrogate.smv"),
                    repo_file("smv/tank_surrogate.smv"),
                    repo_file("tests/data/closed_loop/lamp_ivar_frozen_plant.smv"),
                    repo_file("tests/data/closed_loop/wrong_param_plant.smv"),
                ]
            },
            vocabulary: PLANT_WORDS,
            check: check_plant_scan,
        },
        Target {
            name: "NuSMV output",
            file: "nusmv.out",
            seeds: || {
                vec![
                    repo_file("tests/data/nusmv/light.batch.stdout"),
                    repo_file("tests/data/nusmv/cylinder.batch.stdout"),
                    repo_file("tests/data/nusmv/err_syntax.batch.stdout"),
                ]
            },
            vocabulary: NUSMV_WORDS,
            check: check_nusmv,
        },
        Target {
            name: "NuSMV errors",
            file: "nusmv.err",
            seeds: || {
                vec![
                    repo_file("tests/data/nusmv/dialogue.stderr"),
                    repo_file("tests/data/nusmv/err_undefined.batch.stderr"),
                    repo_file("tests/data/nusmv/err_syntax.batch.stderr"),
                ]
            },
            vocabulary: NUSMV_ERROR_WORDS,
            check: check_nusmv_errors,
        },
        Target {
            name: "JSON machines",
            file: "input.json",
            seeds: || {
                vec![
                    repo_file("tests/data/export/cylinder.json"),
                    repo_file("specs/distribution_reference.json"),
                ]
            },
            vocabulary: JSON_WORDS,
            check: check_json,
        },
        Target {
            name: "guards",
            file: "guard",
            seeds: || {
                let json = repo_file("specs/distribution_reference.json");
                let json = String::from_utf8(json).expect("UTF-8");
                json.lines()
                    .filter_map(|l| l.trim().strip_prefix("\"guard\": \""))
                    .map(|g| g.trim_end_matches([',', '"']).as_bytes().to_vec())
                    .collect()
            },
            vocabulary: GUARD_WORDS,
            check: check_guard,
        },
        Target {
            name: "reset activities",
            file: "reset",
            seeds: || {
                vec![
                    b"%IX0.1 false".to_vec(),
                    b"ll true + ml 1 + %IX0.0 0".to_vec(),
                ]
            },
            vocabulary: RESET_WORDS,
            check: check_reset,
        },
    ]
}

// ---------------------------------------------------------------------------------------------
// The strategies.

/// One change to a seed. Positions are [`Index`]es, resolved against the length of the input
/// when the change is applied, so that every change applies to any input.
#[derive(Debug, Clone)]
enum Mutation {
    /// Delete up to `len` bytes at a position.
    Delete(Index, usize),
    /// Insert arbitrary bytes.
    Insert(Index, Vec<u8>),
    /// Insert a token of the format (or of [`NUMBERS`] or [`STRANGE`]) `times` times: a single
    /// token, or a run deep enough to test the nesting limits.
    Token(Index, Index, usize),
    /// Wrap the expression of a line ([`expressions`]) in `depth` pairs of brackets of one kind
    /// ([`BRACKETS`]): nesting deep enough for every depth limit, and balanced, so that it
    /// often gets past the syntax to the builders that recurse.
    Nest(Index, Index, usize),
    /// Replace an occurrence of a token of the format with another token: changes that keep
    /// the shape of the input, so that the parser gets past its syntax.
    Replace(Index, Index),
    /// Replace an occurrence of a token with another token found in the input (a `0` with a
    /// `1`, a field name with another): the input often stays well-formed and reaches the
    /// checks after the syntax.
    Respell(Index, Index),
    /// Copy a range of up to `len` bytes to another position.
    Duplicate(Index, usize, Index),
    /// Exchange two ranges of up to `len` bytes.
    Swap(Index, Index, usize),
    /// Cut the input at a position.
    Truncate(Index),
    /// Overwrite one byte (often making invalid UTF-8).
    Byte(Index, u8),
}

/// Nesting depths: around every limit (100 for plant expressions and guards, 128 for JSON,
/// 1000 operators for LTL) and far beyond.
fn depth() -> impl Strategy<Value = usize> {
    prop_oneof![1usize..130, 90usize..1100, 1000usize..6000]
}

/// Opening and closing brackets of the formats.
const BRACKETS: &[(&str, &str)] = &[
    ("(", ")"),
    ("[", "]"),
    ("{", "}"),
    ("!(", ")"),
    ("X (", ")"),
    ("next(", ")"),
    ("case TRUE : ", "; esac"),
    ("a ? ", " : b"),
    ("[{\"a\": ", "}]"),
    ("\"", "\""),
];

/// One change, weighted toward those that keep the shape of the input (tokens of the format,
/// balanced nesting), which reach further into a parser than random bytes.
fn mutation() -> impl Strategy<Value = Mutation> {
    let len = 1usize..64;
    // Mostly one token; sometimes a run thousands deep (5000 `(` or `!` would overflow the
    // stack of a parser that recursed once per level).
    let times = prop_oneof![8 => Just(1usize), 2 => 2usize..50, 1 => 900usize..6000];
    prop_oneof![
        2 => (any::<Index>(), len.clone()).prop_map(|(at, n)| Mutation::Delete(at, n)),
        2 => (any::<Index>(), prop::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(at, b)| Mutation::Insert(at, b)),
        5 => (any::<Index>(), any::<Index>(), times).prop_map(|(at, t, n)| Mutation::Token(at, t, n)),
        4 => (any::<Index>(), any::<Index>()).prop_map(|(at, t)| Mutation::Replace(at, t)),
        2 => (any::<Index>(), any::<Index>(), depth())
            .prop_map(|(at, kind, d)| Mutation::Nest(at, kind, d)),
        4 => (any::<Index>(), any::<Index>()).prop_map(|(at, t)| Mutation::Respell(at, t)),
        1 => (any::<Index>(), len.clone(), any::<Index>())
            .prop_map(|(from, n, to)| Mutation::Duplicate(from, n, to)),
        1 => (any::<Index>(), any::<Index>(), len).prop_map(|(a, b, n)| Mutation::Swap(a, b, n)),
        1 => any::<Index>().prop_map(Mutation::Truncate),
        1 => (any::<Index>(), any::<u8>()).prop_map(|(at, b)| Mutation::Byte(at, b)),
    ]
}

/// A position in `0..=len`.
fn pos(i: &Index, len: usize) -> usize {
    i.index(len + 1)
}

/// The tokens insertions choose from: the format's own, then numbers and strange bytes.
fn token<'a>(vocabulary: &'a [&'a str], i: &Index) -> &'a [u8] {
    let all = vocabulary.len() + NUMBERS.len() + STRANGE.len();
    let k = i.index(all);
    let word = if k < vocabulary.len() {
        vocabulary[k]
    } else if k < vocabulary.len() + NUMBERS.len() {
        NUMBERS[k - vocabulary.len()]
    } else {
        STRANGE[k - vocabulary.len() - NUMBERS.len()]
    };
    // `"\x1f\u{8b}"` stands for gzip's magic bytes 1f 8b, which are no UTF-8.
    match word {
        "\x1f\u{8b}" => b"\x1f\x8b",
        w => w.as_bytes(),
    }
}

/// What is likely an expression in each line, as a range of `b`: the part after the last
/// `:=`, else after a label's `: `, else after the indentation; up to a `--` comment, without
/// a final `;` or `,`. The whole formula of an LTL line, the value of a definition or an
/// assignment in a plant, a JSON value.
fn expressions(b: &[u8]) -> Vec<(usize, usize)> {
    let find = |hay: &[u8], needle: &[u8]| hay.windows(needle.len()).position(|w| w == needle);
    let mut found = Vec::new();
    let mut line_start = 0;
    for line in b.split_inclusive(|&c| c == b'\n') {
        let code = &line[..find(line, b"--").unwrap_or(line.len())];
        let mut start = match code.windows(2).rposition(|w| w == b":=") {
            Some(k) => k + 2,
            None => find(code, b": ").map_or(0, |k| k + 2),
        };
        let mut end = code.len();
        while start < end && code[start].is_ascii_whitespace() {
            start += 1;
        }
        while end > start && (code[end - 1].is_ascii_whitespace() || b";,".contains(&code[end - 1]))
        {
            end -= 1;
        }
        if start < end {
            found.push((line_start + start, line_start + end));
        }
        line_start += line.len();
    }
    found
}

/// Where the words of `vocabulary` occur in `b`: (start, length) pairs.
fn occurrences(b: &[u8], vocabulary: &[&str]) -> Vec<(usize, usize)> {
    let mut found = Vec::new();
    for word in vocabulary.iter().chain(NUMBERS).map(|w| w.as_bytes()) {
        if word.is_empty() || word.len() > b.len() {
            continue;
        }
        for (k, w) in b.windows(word.len()).enumerate() {
            if w == word {
                found.push((k, word.len()));
            }
        }
    }
    found
}

/// Applies `mutations` to `seed`, in order.
fn mutate(seed: &[u8], mutations: &[Mutation], vocabulary: &[&str]) -> Vec<u8> {
    let mut b = seed.to_vec();
    for m in mutations {
        let n = b.len();
        match m {
            Mutation::Delete(at, len) => {
                let start = pos(at, n);
                b.drain(start..(start + len).min(n));
            }
            Mutation::Insert(at, bytes) => {
                let at = pos(at, n);
                b.splice(at..at, bytes.iter().copied());
            }
            Mutation::Token(at, t, times) => {
                let at = pos(at, n);
                let run = token(vocabulary, t).repeat(*times);
                b.splice(at..at, run);
            }
            Mutation::Nest(at, kind, depth) => {
                let found = expressions(&b);
                if !found.is_empty() {
                    let (start, end) = found[at.index(found.len())];
                    let (open, close) = BRACKETS[kind.index(BRACKETS.len())];
                    b.splice(end..end, close.repeat(*depth).into_bytes());
                    b.splice(start..start, open.repeat(*depth).into_bytes());
                }
            }
            Mutation::Replace(at, t) => {
                let found = occurrences(&b, vocabulary);
                if !found.is_empty() {
                    let (start, len) = found[at.index(found.len())];
                    b.splice(start..start + len, token(vocabulary, t).iter().copied());
                }
            }
            Mutation::Respell(at, other) => {
                let found = occurrences(&b, vocabulary);
                if !found.is_empty() {
                    let (start, len) = found[at.index(found.len())];
                    let (from, n) = found[other.index(found.len())];
                    let word = b[from..from + n].to_vec();
                    b.splice(start..start + len, word);
                }
            }
            Mutation::Duplicate(from, len, to) => {
                let start = pos(from, n);
                let part = b[start..(start + len).min(n)].to_vec();
                let to = pos(to, n);
                b.splice(to..to, part);
            }
            Mutation::Swap(x, y, len) => {
                let (x, y) = (pos(x, n), pos(y, n));
                let (lo, hi) = (x.min(y), x.max(y));
                // Two ranges that do not overlap: [lo, lo+k) and [hi, hi+k).
                let k = (*len).min(hi - lo).min(n - hi);
                for i in 0..k {
                    b.swap(lo + i, hi + i);
                }
            }
            Mutation::Truncate(at) => b.truncate(pos(at, n)),
            Mutation::Byte(at, byte) => {
                if n > 0 {
                    b[at.index(n)] = *byte;
                }
            }
        }
    }
    b
}

/// Arbitrary input: bytes, text, or a soup of the format's tokens (with arbitrary bytes in
/// between now and then), which gets further into a parser than random bytes do.
fn arbitrary(vocabulary: &'static [&'static str]) -> impl Strategy<Value = Vec<u8>> {
    let soup = prop::collection::vec(
        prop_oneof![
            6 => any::<Index>().prop_map(move |i| token(vocabulary, &i).to_vec()),
            1 => prop::collection::vec(any::<u8>(), 1..4),
        ],
        0..200,
    )
    .prop_map(|parts| parts.concat());
    prop_oneof![
        1 => prop::collection::vec(any::<u8>(), 0..512),
        1 => any::<String>().prop_map(String::into_bytes),
        3 => soup,
    ]
}

/// A seed with mutations applied.
fn mutated(
    seeds: Vec<Vec<u8>>,
    vocabulary: &'static [&'static str],
) -> impl Strategy<Value = Vec<u8>> {
    let count = seeds.len();
    (0..count, prop::collection::vec(mutation(), 1..4))
        .prop_map(move |(k, ms)| mutate(&seeds[k], &ms, vocabulary))
}

/// Where the inputs of a run come from.
#[derive(Debug, Clone, Copy)]
enum Source {
    Arbitrary,
    Mutated,
}

/// What a run of one strategy on one parser saw.
#[derive(Debug, Clone, Copy, Default)]
struct Stats {
    cases: u64,
    /// Cases the parser accepted (the rest it refused with a located error).
    accepted: u64,
    slowest: Duration,
    /// Time spent in the parser, all cases together.
    busy: Duration,
}

impl Stats {
    fn add(&mut self, other: Stats) {
        self.cases += other.cases;
        self.accepted += other.accepted;
        self.slowest = self.slowest.max(other.slowest);
        self.busy += other.busy;
    }
}

/// Runs `cases` cases of one strategy on one parser. A failing case (a broken promise or a
/// panic) fails the run with the shrunk input.
fn run(target: &Target, source: Source, cases: u32) -> Result<Stats, String> {
    let dir = Dir::new();
    let path: PathBuf = dir.path().join(target.file);
    let mut runner = TestRunner::new(config(cases));
    let slowest = Cell::new(Duration::ZERO);
    let accepted = Cell::new(0);
    let busy = Cell::new(Duration::ZERO);
    let test = |(input, flag): (Vec<u8>, bool)| {
        let t = Instant::now();
        let parsed = (target.check)(&path, &input, flag)?;
        slowest.set(slowest.get().max(t.elapsed()));
        busy.set(busy.get() + t.elapsed());
        accepted.set(accepted.get() + u64::from(parsed == Parsed::Accepted));
        Ok(())
    };
    let result = match source {
        Source::Arbitrary => runner.run(&(arbitrary(target.vocabulary), any::<bool>()), test),
        Source::Mutated => runner.run(
            &(mutated((target.seeds)(), target.vocabulary), any::<bool>()),
            test,
        ),
    };
    result
        .map(|()| Stats {
            cases: u64::from(cases),
            accepted: accepted.get(),
            slowest: slowest.get(),
            busy: busy.get(),
        })
        .map_err(|e| match e {
            TestError::Fail(why, (input, flag)) => format!(
                "{} ({source:?}, flag {flag}): {why}\nminimal failing input ({} bytes): b\"{}\"",
                target.name,
                input.len(),
                input.escape_ascii()
            ),
            TestError::Abort(why) => format!("{} ({source:?}): {why}", target.name),
        })
}

/// Every seed passes its parser: mutations start from valid input.
#[test]
fn robustness_seeds_are_valid() {
    let dir = Dir::new();
    for target in targets() {
        let path = dir.path().join(target.file);
        let seeds = (target.seeds)();
        assert!(!seeds.is_empty(), "{} has no seed", target.name);
        for (k, seed) in seeds.iter().enumerate() {
            let parsed = (target.check)(&path, seed, false)
                .unwrap_or_else(|e| panic!("{} seed {k}: {e}", target.name));
            assert_eq!(parsed, Parsed::Accepted, "{} seed {k}", target.name);
        }
    }
}

/// The parser of `targets()` called `name`.
fn target(name: &str) -> Target {
    targets()
        .into_iter()
        .find(|t| t.name == name)
        .unwrap_or_else(|| panic!("no target {name}"))
}

macro_rules! robustness_tests {
    ($($arbitrary:ident, $mutated:ident: $name:expr;)*) => {$(
        #[test]
        fn $arbitrary() {
            if let Err(e) = run(&target($name), Source::Arbitrary, cases()) {
                panic!("{e}");
            }
        }

        #[test]
        fn $mutated() {
            if let Err(e) = run(&target($name), Source::Mutated, cases()) {
                panic!("{e}");
            }
        }
    )*};
}

robustness_tests! {
    robustness_fbsat_arbitrary, robustness_fbsat_mutated: "fbSAT scenarios";
    robustness_csvlog_arbitrary, robustness_csvlog_mutated: "CSV scenario logs";
    robustness_raw_log_arbitrary, robustness_raw_log_mutated: "raw PLC logs";
    robustness_mapping_arbitrary, robustness_mapping_mutated: "mapping files";
    robustness_names_arbitrary, robustness_names_mutated: "names files";
    robustness_ltl_arbitrary, robustness_ltl_mutated: "LTL specifications";
    robustness_plant_arbitrary, robustness_plant_mutated: "SMV plant subset";
    robustness_plant_scan_arbitrary, robustness_plant_scan_mutated: "SMV plant scan";
    robustness_nusmv_arbitrary, robustness_nusmv_mutated: "NuSMV output";
    robustness_nusmv_errors_arbitrary, robustness_nusmv_errors_mutated: "NuSMV errors";
    robustness_json_arbitrary, robustness_json_mutated: "JSON machines";
    robustness_guard_arbitrary, robustness_guard_mutated: "guards";
    robustness_reset_arbitrary, robustness_reset_mutated: "reset activities";
}

/// The long run: all parsers in turn, both strategies, in rounds of 100 cases
/// each, for `FBSYNTH_ROBUSTNESS_SECS` seconds (default 600). Prints the cases run and the
/// slowest case per parser; fails on the first broken promise or panic.
#[test]
#[ignore = "runs for 10 minutes: cargo test --release --test integration robustness_long_run -- --ignored --nocapture"]
fn robustness_long_run() {
    let secs: u64 = std::env::var("FBSYNTH_ROBUSTNESS_SECS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(600);
    let deadline = Instant::now() + Duration::from_secs(secs);
    let targets = targets();
    let mut stats = vec![Stats::default(); targets.len()];
    let start = Instant::now();
    while Instant::now() < deadline {
        for (k, target) in targets.iter().enumerate() {
            for source in [Source::Arbitrary, Source::Mutated] {
                stats[k].add(run(target, source, 100).unwrap_or_else(|e| panic!("{e}")));
            }
        }
    }
    println!(
        "robustness long run: {:.0} s, 0 failures",
        start.elapsed().as_secs_f64()
    );
    for (target, s) in targets.iter().zip(&stats) {
        println!(
            "  {:20} {:>9} cases ({:>4.1} % accepted), {:>5.2} ms per case, slowest {:.1} ms",
            target.name,
            s.cases,
            100.0 * s.accepted as f64 / s.cases as f64,
            s.busy.as_secs_f64() * 1e3 / s.cases as f64,
            s.slowest.as_secs_f64() * 1e3
        );
    }
    let total: u64 = stats.iter().map(|s| s.cases).sum();
    println!("  {:20} {total:>9} cases", "total");
}
