//! Inputs without end, through the binary: a line longer than the limit, or a file that never
//! ends (`/dev/zero`), stops a command with exit 1 and the file and line, after reading no more
//! than the limit, and leaves no output.

use fbsynth::files::MAX_LINE_BYTES;
use std::path::Path;
use std::process::{Command, Output};

fn synth(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_synth"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run synth")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).trim().to_string()
}

const MAP: &str = "%IX0.1 in ll\n%QX0.0 out inlet\n";

/// A long-format log whose line 3 is one byte over the limit.
fn log_with_a_long_line(dir: &Path) {
    let mut log = b"timestamp,address,value\n0,%IX0.1,1\n".to_vec();
    log.resize(log.len() + MAX_LINE_BYTES + 1, b'0');
    log.extend(b"\n1,%IX0.1,0\n");
    std::fs::write(dir.join("long.csv"), log).unwrap();
}

fn ingest(dir: &Path, log: &str, map: &str) -> Output {
    synth(
        dir,
        &["ingest", "--log", log, "--map", map, "-o", "out.traces"],
    )
}

fn events(dir: &Path, log: &str, map: &str) -> Output {
    synth(
        dir,
        &[
            "events", "--log", log, "--map", map, "--reset", "ll false", "--out", "out.xes",
        ],
    )
}

fn assert_no_output(dir: &Path) {
    for f in [
        "out.traces",
        "out.inputs",
        "out.outputs",
        "out.xes",
        "out.csv",
    ] {
        assert!(!dir.join(f).exists(), "{f} was written");
    }
}

#[test]
fn a_log_line_over_the_limit_stops_ingest_and_events_with_its_place() {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    std::fs::write(dir.join("t.map"), MAP).unwrap();
    log_with_a_long_line(dir);
    let want = format!("error: long.csv:3: line 3 is longer than {MAX_LINE_BYTES} bytes");
    for o in [
        ingest(dir, "long.csv", "t.map"),
        events(dir, "long.csv", "t.map"),
    ] {
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert_eq!(stderr(&o), want);
    }
    assert_no_output(dir);
}

#[test]
fn an_endless_log_is_refused_at_line_1() {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    std::fs::write(dir.join("t.map"), MAP).unwrap();
    let want = format!("error: /dev/zero:1: line 1 is longer than {MAX_LINE_BYTES} bytes");
    for o in [
        ingest(dir, "/dev/zero", "t.map"),
        events(dir, "/dev/zero", "t.map"),
    ] {
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert_eq!(stderr(&o), want);
    }
    assert_no_output(dir);
}
