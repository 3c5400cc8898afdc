//! Every file a command writes can be read by others: mode 0644 under umask 022, like any
//! file the user creates (a shared 4diac workspace, another engineer's account).

use fbsynth::nusmv::test_support::nusmv_or_skip;
use std::os::unix::fs::PermissionsExt;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `synth` under umask 022; panics with its stderr when it fails.
fn synth(args: &[&str]) {
    run(env!("CARGO_BIN_EXE_synth"), args)
}

/// Runs the developer binary `synth-dev` likewise.
fn synth_dev(args: &[&str]) {
    run(env!("CARGO_BIN_EXE_synth-dev"), args)
}

/// Runs `binary` under umask 022; panics with its stderr when it fails.
fn run(binary: &str, args: &[&str]) {
    let mut cmd = Command::new(binary);
    cmd.args(args).current_dir(env!("CARGO_MANIFEST_DIR"));
    // SAFETY: umask is async-signal-safe; nothing else runs between fork and exec.
    unsafe {
        cmd.pre_exec(|| {
            libc::umask(0o022);
            Ok(())
        });
    }
    let o = cmd.output().expect("run the binary");
    assert!(
        o.status.success(),
        "{binary} {}: {}",
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
    let dir = tempfile::tempdir().unwrap();
    let at = |p: &str| dir.path().join(p).to_str().unwrap().to_string();
    let door = "tests/data/scenarios/door.traces";
    synth(&["infer", "--traces", door, "--out", &at("infer"), "-q"]);
    synth(&[
        "infer",
        "--modules",
        "2",
        "--traces",
        "tests/data/scenarios/lamps.traces",
        "--out",
        &at("modular"),
        "-q",
    ]);
    synth(&[
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
    synth(&[
        "convert",
        "--traces",
        door,
        "--to",
        "csv",
        "-o",
        &at("convert/door.csv"),
    ]);
    synth(&[
        "ingest",
        "--log",
        "specs/tank/scenario1.csv",
        "--map",
        "specs/tank/tank.map",
        "-o",
        &at("ingest/tank.traces"),
    ]);
    synth(&[
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
    synth(&[
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
    synth_dev(&["generate", "pnp", "--out", &at("generate")]);
    if let Some(n) = nusmv_or_skip() {
        synth(&[
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
