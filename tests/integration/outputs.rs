//! What a run does to the files around it and how it ends: the output rule (no input and no
//! other command's result replaced without `--force`), progress on a closed stderr, options
//! refused before any work, signals, and paths shown as one line each.

use crate::common::{nusmv_or_skip, synth, text, Dir, TestCommand};
use std::path::{Path, PathBuf};
use std::process::{Output, Stdio};

const LAMP: &str = "tests/data/closed_loop";

fn door(name: &str) -> String {
    format!("tests/data/scenarios/door.{name}")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The main job on the lamp into `out`.
fn lamp_main(nusmv: &Path, out: &Path, extra: &[&str]) -> Output {
    let (ltl, plant) = (format!("{LAMP}/lamp.ltl"), format!("{LAMP}/lamp_plant.smv"));
    let mut args = vec!["-q", "--ltl", &ltl, "--plant", &plant, "--out", s(out)];
    args.extend_from_slice(extra);
    TestCommand::new().args(&args).nusmv(nusmv).output()
}

fn infer_door(out: &Path) -> PathBuf {
    let o = synth(&["infer", "-q", "--traces", &door("traces"), "--out", s(out)]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    out.join("SynthesizedFB.json")
}

#[test]
fn verify_into_the_main_jobs_folder_keeps_the_machine() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let o = lamp_main(&n.path, dir.path(), &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let machine = dir.path().join("SynthesizedFB.json");
    let before = std::fs::read(&machine).unwrap();
    let plant = format!("{LAMP}/lamp_plant.smv");
    let verify = |extra: &[&str]| {
        let mut args = vec![
            "verify",
            "-q",
            "--ecc",
            s(&machine),
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            &plant,
            "--out",
            s(dir.path()),
        ];
        args.extend_from_slice(extra);
        TestCommand::new().args(&args).nusmv(&n.path).output()
    };
    let o = verify(&[]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    let e = text(&o.stderr);
    assert!(
        e.contains("holds the result of the main job") && e.contains("--force"),
        "{e}"
    );
    assert_eq!(std::fs::read(&machine).unwrap(), before);
    assert!(dir.path().join("verification.txt").is_file());
    // With --force the user asked: the folder holds verify's result, the machine it read
    // goes with the main job's.
    let o = verify(&["--force"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(dir.path().join("closed_loop.smv").is_file());
    assert!(!machine.exists());
}

#[test]
fn a_plant_named_like_a_result_is_never_replaced() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let plant = dir.path().join("closed_loop.smv");
    std::fs::copy(format!("{LAMP}/lamp_plant.smv"), &plant).unwrap();
    let before = std::fs::read(&plant).unwrap();
    let o = TestCommand::new()
        .args([
            "verify",
            "-q",
            "--ecc",
            "tests/data/closed_loop/lamp_two_state.json",
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            s(&plant),
            "--out",
            s(dir.path()),
        ])
        .nusmv(&n.path)
        .output();
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    let e = text(&o.stderr);
    assert!(
        e.contains(&format!(
            "the output {} would replace or remove the input {}",
            plant.display(),
            plant.display()
        )),
        "{e}"
    );
    assert_eq!(std::fs::read(&plant).unwrap(), before);
}

#[test]
fn inputs_named_like_results_are_refused_before_any_work() {
    // Traces called summary.json, names files called SynthesizedFB.st and .dot: each would be
    // replaced by a result of the same name.
    for (traces, inputs, outputs) in [
        ("summary.json", "door.inputs", "door.outputs"),
        ("door.traces", "SynthesizedFB.st", "door.outputs"),
        ("door.traces", "door.inputs", "SynthesizedFB.dot"),
    ] {
        let dir = Dir::new();
        let at = |name: &str| dir.path().join(name);
        std::fs::copy(door("traces"), at(traces)).unwrap();
        std::fs::copy(door("inputs"), at(inputs)).unwrap();
        std::fs::copy(door("outputs"), at(outputs)).unwrap();
        let o = synth(&[
            "infer",
            "-q",
            "--traces",
            s(&at(traces)),
            "--input-names",
            s(&at(inputs)),
            "--output-names",
            s(&at(outputs)),
            "--out",
            s(dir.path()),
        ]);
        assert_eq!(o.status.code(), Some(4), "{traces}: {}", text(&o.stderr));
        assert!(text(&o.stderr).contains("would replace or remove the input"));
        assert_eq!(
            std::fs::read(at(traces)).unwrap(),
            std::fs::read(door("traces")).unwrap()
        );
        assert!(!at("SynthesizedFB.json").exists());
    }
}

#[test]
fn conform_refine_never_replaces_the_machine_in_service() {
    let dir = Dir::new();
    let machine = infer_door(dir.path());
    let before = std::fs::read(&machine).unwrap();
    let o = synth(&[
        "conform",
        "-q",
        "--ecc",
        s(&machine),
        "--log",
        "tests/data/scenarios/door_new.traces",
        "--refine",
        "--train",
        &door("traces"),
        "--out",
        s(dir.path()),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("holds the result of `synth infer`"));
    assert_eq!(std::fs::read(&machine).unwrap(), before);
}

#[test]
fn learn_never_writes_over_its_oracle() {
    let dir = Dir::new();
    let oracle = infer_door(dir.path());
    let before = std::fs::read(&oracle).unwrap();
    let o = synth(&[
        "learn",
        "-q",
        "--oracle",
        s(&oracle),
        "--traces",
        &door("traces"),
        "--out",
        s(&oracle),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("would overwrite the input"));
    assert_eq!(std::fs::read(&oracle).unwrap(), before);
}

#[test]
fn a_closed_or_full_stderr_loses_progress_not_the_result() {
    use std::os::fd::{FromRawFd, OwnedFd};
    for closed in [true, false] {
        let dir = Dir::new();
        let stderr = match closed {
            // A pipe whose reader is gone (`2>&1 | head -1` once head has exited).
            true => {
                let mut fds = [0; 2];
                // SAFETY: pipe fills the two descriptors, each owned once below.
                assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0);
                // SAFETY: fresh descriptors from pipe, owned by nobody else.
                drop(unsafe { OwnedFd::from_raw_fd(fds[0]) });
                Stdio::from(unsafe { OwnedFd::from_raw_fd(fds[1]) })
            }
            false => Stdio::from(
                std::fs::OpenOptions::new()
                    .write(true)
                    .open("/dev/full")
                    .unwrap(),
            ),
        };
        let o = TestCommand::new()
            .args(["infer", "--traces", &door("traces"), "--out", s(dir.path())])
            .stderr(stderr)
            .output();
        assert_eq!(o.status.code(), Some(0), "closed {closed}");
        assert!(dir.path().join("SynthesizedFB.json").is_file());
        // A failing run keeps its own exit code too.
        let o = TestCommand::new()
            .args(["infer", "--traces", "tests/data/no/such.traces"])
            .stderr(Stdio::from(
                std::fs::OpenOptions::new()
                    .write(true)
                    .open("/dev/full")
                    .unwrap(),
            ))
            .output();
        assert_eq!(o.status.code(), Some(4));
    }
}

#[test]
fn option_values_are_refused_before_any_work() {
    let long_name = "B".repeat(5000);
    let main = ["--ltl", "specs/pnp.ltl", "--plant", "smv/pnp_surrogate.smv"];
    let refused: Vec<Vec<&str>> = vec![
        [
            &main[..],
            &["--method", "search", "--verify-probability", "nan"],
        ]
        .concat(),
        [
            &main[..],
            &["--method", "search", "--verify-probability", "2"],
        ]
        .concat(),
        // Refused before the traces are read: a missing file would be exit 4.
        vec![
            "infer",
            "--traces",
            "tests/data/no/such.traces",
            "--ambiguity-budget",
            "nan",
        ],
        vec![
            "infer",
            "--traces",
            "tests/data/no/such.traces",
            "--name",
            &long_name,
        ],
    ];
    for args in &refused {
        let o = synth(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o.stderr));
    }
    for args in [
        &["bench", "--runs", "1000000000000"][..],
        &["bench-search", "--threads", "5000"][..],
        &["experiment", "table1", "--verify-probability", "nan"][..],
    ] {
        let o = TestCommand::developer().args(args).output();
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o.stderr));
    }
}

#[test]
fn one_iteration_keeps_the_machine_nusmv_verified() {
    let Some(n) = nusmv_or_skip() else { return };
    // The first candidate holds: its iteration is the last one, in the final pass.
    let dir = Dir::new();
    let ltl = dir.path().join("any.ltl");
    std::fs::write(&ltl, "p: G (lamp | !lamp)\n").unwrap();
    let out = dir.path().join("out");
    let o = TestCommand::new()
        .args([
            "-q",
            "--ltl",
            s(&ltl),
            "--plant",
            "tests/data/closed_loop/lamp_plant.smv",
            "--traces",
            "tests/data/closed_loop/lamp.traces",
            "--out",
            s(&out),
            "--max-iterations",
            "1",
        ])
        .nusmv(&n.path)
        .output();
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("verified: the property holds"));
    assert!(out.join("SynthesizedFB.json").is_file());
}

/// Whether `pid` has a handler for `signal` (its `SigCgt` mask in `/proc`).
fn catches(pid: u32, signal: i32) -> bool {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    let mask = (status.lines())
        .find_map(|l| l.strip_prefix("SigCgt:"))
        .and_then(|m| u64::from_str_radix(m.trim(), 16).ok())
        .unwrap_or(0);
    mask & (1 << (signal - 1)) != 0
}

#[test]
#[cfg(target_os = "linux")]
fn a_signal_while_reading_ends_the_run_with_130() {
    use std::os::unix::process::CommandExt;
    for signal in [libc::SIGINT, libc::SIGTERM] {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_synth"));
        command
            .args(["infer", "-q", "--traces", "-"])
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::null());
        // SAFETY: signal is async-signal-safe; as a shell starts a background job.
        unsafe {
            command.pre_exec(|| {
                libc::signal(libc::SIGINT, libc::SIG_IGN);
                Ok(())
            });
        }
        let mut child = command.spawn().unwrap();
        // Still reading standard input, which stays open.
        let _stdin = child.stdin.take();
        let start = std::time::Instant::now();
        while !catches(child.id(), signal) && start.elapsed().as_secs() < 30 {
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        // SAFETY: a signal to the child this test started.
        unsafe { libc::kill(child.id() as i32, signal) };
        let start = std::time::Instant::now();
        let status = loop {
            match child.try_wait().unwrap() {
                Some(status) => break Some(status),
                None if start.elapsed().as_secs() > 30 => break None,
                None => std::thread::sleep(std::time::Duration::from_millis(10)),
            }
        };
        if status.is_none() {
            let _ = child.kill();
            let _ = child.wait();
        }
        let code = status.and_then(|s| s.code());
        assert_eq!(code, Some(130), "signal {signal}: {status:?}");
    }
}

#[test]
fn paths_are_shown_one_line_each() {
    let dir = Dir::new();
    let out = dir.path().join("a\nb");
    let o = synth(&["infer", "-q", "--traces", &door("traces"), "--out", s(&out)]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("a\\nb"), "{stdout}");
    assert!(!stdout.lines().any(|l| l.starts_with('b')), "{stdout}");
}

#[test]
fn a_pipe_named_dev_stdout_gets_the_result() {
    let o = TestCommand::new()
        .args([
            "convert",
            "--traces",
            &door("traces"),
            "--to",
            "csv",
            "-o",
            "/dev/stdout",
        ])
        .stdout(Stdio::piped())
        .output();
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains(','), "{}", text(&o.stdout));
}

#[test]
fn man_names_the_path_it_cannot_write() {
    let o = synth(&["man", "--out", "/dev/null"]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("/dev/null"), "{}", text(&o.stderr));
}
