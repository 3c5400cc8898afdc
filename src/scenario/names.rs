//! Interface variable names: files of names separated by whitespace or newlines.
//!
//! Names end up as identifiers in SMV, Structured Text and IEC 61499 XML, so only
//! `[A-Za-z][A-Za-z0-9_]*` ([`is_identifier`]) is accepted, each name once. (Keywords of the
//! target languages are checked where those languages are emitted.)

use super::ScenarioError;
use crate::quote::quote;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

pub(crate) use crate::ecc::ident::is_identifier;

/// Parses the text of a names file.
pub(crate) fn parse_names(file: &Path, text: &str) -> Result<Vec<String>, ScenarioError> {
    let mut names = Vec::new();
    let mut seen: HashMap<String, usize> = HashMap::new();
    for (i, line) in text.lines().enumerate() {
        for word in line.split_whitespace() {
            let line_no = i + 1;
            if !is_identifier(word) {
                return Err(ScenarioError::Names {
                    file: file.to_path_buf(),
                    line: line_no,
                    message: format!(
                        "{} is not a valid name (letters, digits and '_', starting with a letter)",
                        quote(word)
                    ),
                });
            }
            if let Some(first) = seen.insert(word.to_string(), line_no) {
                return Err(ScenarioError::Names {
                    file: file.to_path_buf(),
                    line: line_no,
                    message: format!("duplicate name {} (first on line {first})", quote(word)),
                });
            }
            names.push(word.to_string());
        }
    }
    if names.is_empty() {
        return Err(ScenarioError::Names {
            file: file.to_path_buf(),
            line: 1,
            message: "no names in file".into(),
        });
    }
    Ok(names)
}

/// Reads a names file.
pub fn read_names(file: &Path) -> Result<Vec<String>, ScenarioError> {
    let text = crate::files::read_text(file, Some(crate::files::MAX_LINE_BYTES))?;
    parse_names(file, &text)
}

/// Default names files beside a trace file: `<stem>.inputs` / `<stem>.outputs`, else
/// `input-names` / `output-names` in the same folder (the fbSAT layout).
/// The stem drops every extension: `tests-10.gz` -> `tests-10`, `pnp.traces` -> `pnp`.
pub(crate) fn default_names_files(traces: &Path) -> Option<(PathBuf, PathBuf)> {
    // Standard input lies beside nothing: its names come from --input-names/--output-names.
    if crate::files::is_stdin(traces) {
        return None;
    }
    let dir = traces.parent().unwrap_or(Path::new("."));
    let file = traces.file_name()?.to_str()?;
    let stem = file.split('.').next().unwrap_or(file);
    let candidates = [
        (
            dir.join(format!("{stem}.inputs")),
            dir.join(format!("{stem}.outputs")),
        ),
        (dir.join("input-names"), dir.join("output-names")),
    ];
    candidates
        .into_iter()
        .find(|(i, o)| i.is_file() && o.is_file())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_split_on_any_whitespace() {
        let n = parse_names(Path::new("n"), "a b\n c\r\n\td\n").unwrap();
        assert_eq!(n, vec!["a", "b", "c", "d"]);
    }

    #[test]
    fn bad_and_duplicate_names_have_lines() {
        let e = parse_names(Path::new("n"), "a\nb\n1x\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "n:3: '1x' is not a valid name (letters, digits and '_', starting with a letter)"
        );
        let e = parse_names(Path::new("n"), "a\nb a\n").unwrap_err();
        assert_eq!(e.to_string(), "n:2: duplicate name 'a' (first on line 1)");
        assert!(parse_names(Path::new("n"), " \n").is_err());
    }
}
