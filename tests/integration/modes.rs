//! Every file a command writes can be read by others: mode 0644 under umask 022, like any
//! file the user creates (a shared 4diac workspace, another engineer's account).

use crate::common::{nusmv_or_skip, Dir, TestCommand};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

/// Runs `synth` under umask 022; panics with its stderr when it fails.
fn run(args: &[&str]) {
    run_022(TestCommand::new(), args)
}

/// Runs `cmd` with `args` under umask 022; panics with its stderr when it fails.
fn run_022(mut cmd: TestCommand, args: &[&str]) {
    let o = cmd.args(args).umask(0o022).output();
    assert!(
        o.status.success(),
        "synth {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Every regular file below `dir`.
fn files_below(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(files_below(&path));
        } else {
            out.push(path);
        }
    }
    out
}

#[test]
fn every_file_a_command_writes_is_0644() {
    let dir = Dir::new();
    let at = |p: &str| dir.path().join(p).to_str().unwrap().to_string();
    let door = "tests/data/scenarios/door.traces";
    run(&["infer", "--traces", door, "--out", &at("infer"), "-q"]);
    run(&[
        "infer",
        "--modules",
        "2",
        "--traces",
        "tests/data/scenarios/lamps.traces",
        "--out",
        &at("modular"),
        "-q",
    ]);
    run(&[
        "infer",
        "--noisy",
        "--max-errors",
        "1",
        "--enumerate",
        "2",
        "--traces",
        "tests/data/noisy/skewed.csv",
        "--out",
        &at("noisy"),
        "-q",
    ]);
    run(&[
        "convert",
        "--traces",
        door,
        "--to",
        "csv",
        "-o",
        &at("convert/door.csv"),
    ]);
    run(&[
        "ingest",
        "--log",
        "specs/tank/scenario1.csv",
        "--map",
        "specs/tank/tank.map",
        "-o",
        &at("ingest/tank.traces"),
    ]);
    run(&[
        "events",
        "--log",
        "specs/tank/scenario1.csv",
        "--map",
        "specs/tank/tank.map",
        "--reset",
        "%IX0.1 false",
        "--out",
        &at("events/tank.xes"),
    ]);
    run(&[
        "conform",
        "--ecc",
        &at("infer/SynthesizedFB.json"),
        "--log",
        "tests/data/scenarios/door_new.traces",
        "--refine",
        "--train",
        door,
        "--out",
        &at("refined"),
    ]);
    run_022(
        TestCommand::developer(),
        &["generate", "pnp", "--out", &at("generate")],
    );
    if let Some(n) = nusmv_or_skip() {
        run(&[
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            "tests/data/closed_loop/lamp_plant.smv",
            "--nusmv",
            n.path.to_str().unwrap(),
            "--out",
            &at("main"),
            "-q",
        ]);
    }
    let files = files_below(dir.path());
    assert!(files.len() > 30, "only {} files written", files.len());
    let wrong: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let mode = std::fs::metadata(f).unwrap().permissions().mode() & 0o777;
            (mode != 0o644).then(|| format!("{} {mode:o}", f.display()))
        })
        .collect();
    assert!(wrong.is_empty(), "not 0644: {wrong:#?}");
}
