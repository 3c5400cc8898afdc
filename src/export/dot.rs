//! Graphviz DOT drawing of an ECC, and rendering it to SVG with the `dot` program.
//!
//! In: a valid [`Ecc`]. Out: a `digraph` with one node per state, labelled with the state's
//! name and what its algorithm does, by output name (`c1Extend := 1`, `vacuum_on := 0`,
//! `z toggles`; outputs it keeps are not listed); the initial state marked by an entry arrow
//! from a dot (no double border: that conventionally means "accepting"); one edge per
//! transition labelled `k: guard` with `k` its 1-based priority within the source state. [`render_svg`] turns such text into an SVG file if Graphviz is installed.

use crate::ecc::Ecc;
use crate::files::{self, Folders};
use std::io::{self, Read, Write};
use std::path::Path;
use std::process::{Command, Stdio};

/// A DOT double-quoted string: `"` and `\` escaped, line breaks as DOT's `\n`.
fn quoted(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// What a state's algorithm does, one output per line by name: `name := 1`, `name := 0`,
/// `name toggles`; outputs it keeps are left out (`keeps all outputs` when it keeps every one).
fn actions(ecc: &Ecc, algorithm: &crate::ecc::Algorithm) -> String {
    let lines: Vec<String> = ecc
        .outputs
        .iter()
        .enumerate()
        .filter_map(|(z, name)| {
            match (algorithm.apply_one(z, false), algorithm.apply_one(z, true)) {
                (false, true) => None,
                (true, true) => Some(format!("{name} := 1")),
                (false, false) => Some(format!("{name} := 0")),
                (true, false) => Some(format!("{name} toggles")),
            }
        })
        .collect();
    match lines.is_empty() {
        true => "keeps all outputs".to_string(),
        false => lines.join("\n"),
    }
}

/// Writes the DOT text.
pub(crate) fn write_dot(ecc: &Ecc, w: &mut impl Write) -> io::Result<()> {
    writeln!(w, "digraph ecc {{")?;
    writeln!(w, "  // {}", ecc.size())?;
    writeln!(w, "  rankdir=LR;")?;
    let title = format!(
        "outputs: {} (initially {})",
        if ecc.outputs.is_empty() {
            "none".to_string()
        } else {
            ecc.outputs.join(" ")
        },
        crate::ecc::bits_to_string(&ecc.initial_outputs)
    );
    writeln!(w, "  label={};", quoted(&title))?;
    writeln!(w, "  labelloc=t;")?;
    writeln!(
        w,
        "  node [shape=box, style=rounded, fontname=\"Helvetica\"];"
    )?;
    writeln!(w, "  edge [fontname=\"Helvetica\", fontsize=10];")?;
    // `_init` cannot clash with a state: state nodes are `s<number>`.
    writeln!(w, "  _init [shape=point, width=0.15, label=\"\"];")?;
    writeln!(w, "  _init -> s0;")?;
    for (i, s) in ecc.states.iter().enumerate() {
        let label = quoted(&format!("{}\n{}", s.name, actions(ecc, &s.algorithm)));
        writeln!(w, "  s{i} [label={label}];")?;
    }
    for (i, s) in ecc.states.iter().enumerate() {
        for (k, t) in s.transitions.iter().enumerate() {
            let label = quoted(&format!("{}: {}", k + 1, t.guard.display(&ecc.inputs)));
            writeln!(w, "  s{i} -> s{} [label={label}];", t.target.0)?;
        }
    }
    writeln!(w, "}}")
}

/// [`write_dot`] into a string.
pub(crate) fn to_string(ecc: &Ecc) -> String {
    let mut buf = Vec::new();
    write_dot(ecc, &mut buf).expect("writing to a Vec does not fail");
    String::from_utf8(buf).expect("the DOT emitter writes UTF-8 only")
}

/// Renders DOT text to an SVG file with `dot -Tsvg` if the `dot` program is on the `PATH`.
///
/// Returns `Ok(false)` without touching `out` when `dot` is not installed, `Ok(true)` once the
/// SVG is written. The file is replaced atomically, so a failing `dot` leaves no partial file.
pub(crate) fn render_svg(dot_text: &str, out: &Path) -> Result<bool, io::Error> {
    let Ok(dot) = which::which("dot") else {
        return Ok(false);
    };
    let mut child = Command::new(dot)
        .arg("-Tsvg")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()?;
    let mut stdin = child.stdin.take().expect("stdin is piped");
    let text = dot_text.to_string();
    // Feed the input from another thread so neither side can block on a full pipe.
    let feeder = std::thread::spawn(move || stdin.write_all(text.as_bytes()));
    let mut svg = Vec::new();
    child
        .stdout
        .take()
        .expect("stdout is piped")
        .read_to_end(&mut svg)?;
    let output = child.wait_with_output()?;
    let fed = feeder.join().expect("the stdin feeder does not panic");
    if !output.status.success() {
        return Err(io::Error::other(format!(
            "dot -Tsvg failed ({}): {}",
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        )));
    }
    fed?;
    files::write_atomic_in(out, &svg, Folders::MustExist).map_err(|e| e.source)?;
    Ok(true)
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
    fn labels_are_escaped() {
        assert_eq!(quoted("a\"b\\c\nd"), r#""a\"b\\c\nd""#);
    }

    /// Both outcomes are checked: which one runs depends on whether Graphviz is installed.
    #[test]
    fn render_svg_writes_svg_or_reports_missing_dot() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("m.svg");
        let rendered = render_svg(&to_string(&samples::tri()), &out).unwrap();
        assert_eq!(rendered, which::which("dot").is_ok());
        if rendered {
            let svg = std::fs::read_to_string(&out).unwrap();
            assert!(svg.contains("<svg"), "{svg}");
            assert!(svg.contains("c1Home"), "guards appear in the drawing");
        } else {
            assert!(!out.exists());
        }
    }

    #[test]
    fn broken_dot_text_is_an_error_and_leaves_no_file() {
        if which::which("dot").is_err() {
            return; // Nothing to run; the missing-dot path is tested above.
        }
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("m.svg");
        let e = render_svg("digraph {", &out).unwrap_err();
        assert!(e.to_string().starts_with("dot -Tsvg failed"), "{e}");
        assert!(!out.exists());
    }
}
