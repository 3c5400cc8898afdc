//! The `synth` binary as a user runs it: outputs, exit codes, messages with places, and no
//! partial files on failure.

use crate::common::{synth, text, Dir, TestCommand};
use fbsynth::export::json::read_json;
use fbsynth::scenario::fbsat;
use std::path::{Path, PathBuf};
use std::process::Output;

fn data(name: &str) -> String {
    format!("tests/data/scenarios/{name}")
}

fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|r| r.map(|e| e.unwrap().path()).collect())
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn infer_writes_every_format_and_the_json_replays_the_scenarios() {
    let out = Dir::new();
    let o = synth(&[
        "infer",
        "--traces",
        &data("door.traces"),
        "--out",
        out.path().to_str().unwrap(),
        "--format",
        "json,fbt,smv,dot,st",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("C = 2  K = 1  T = 2  N = 2"), "{stdout}");
    for ext in ["json", "fbt", "smv", "dot", "st"] {
        assert!(
            out.path().join(format!("SynthesizedFB.{ext}")).is_file(),
            "{ext}"
        );
    }
    let json = std::fs::read_to_string(out.path().join("SynthesizedFB.json")).unwrap();
    let ecc = read_json(&json, Path::new("SynthesizedFB.json")).unwrap();
    let set = fbsat::read(
        Path::new(&format!(
            "{}/{}",
            env!("CARGO_MANIFEST_DIR"),
            data("door.traces")
        )),
        Some(vec!["start".into(), "stop".into()]),
        Some(vec!["motor".into(), "lamp".into()]),
    )
    .unwrap();
    set.check(&ecc).unwrap();
}

/// Synthesizes the door machine from door.traces into `dir`; returns its JSON file.
fn infer_door(dir: &Path) -> PathBuf {
    let o = synth(&[
        "infer",
        "-q",
        "--traces",
        &data("door.traces"),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    dir.join("SynthesizedFB.json")
}

#[test]
fn replay_reports_the_first_step_a_machine_gets_wrong() {
    let out = Dir::new();
    let json = infer_door(out.path());
    let o = synth(&[
        "replay",
        "--ecc",
        json.to_str().unwrap(),
        "--traces",
        &data("door.traces"),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).starts_with("replayed 3 scenarios (12 steps): all reproduced"));
    // Make the machine ignore `stop`: scenario 1 step 4 is then not reproduced.
    let broken = std::fs::read_to_string(&json)
        .unwrap()
        .replace("\"guard\": \"stop\"", "\"guard\": \"FALSE\"");
    std::fs::write(&json, broken).unwrap();
    let o = synth(&[
        "replay",
        "--ecc",
        json.to_str().unwrap(),
        "--traces",
        &data("door.traces"),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("scenario tests/data/scenarios/door.traces:2 step 4: inputs 01 recorded CNF[01], the machine gives no CNF"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn malformed_traces_fail_with_file_line_and_step_and_write_nothing() {
    let out = Dir::new();
    let dir = out.path().join("res");
    let o = synth(&[
        "infer",
        "--traces",
        &data("badbits.traces"),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4));
    assert_eq!(
        text(&o.stderr).trim(),
        "error: tests/data/scenarios/badbits.traces:3: step 1: 1 input bits, expected 2"
    );
    assert!(files_in(&dir).is_empty());
}

#[test]
fn contradictory_traces_name_both_scenarios() {
    let o = synth(&["infer", "--traces", &data("contradict.traces"), "-q"]);
    assert_eq!(o.status.code(), Some(4));
    let e = text(&o.stderr);
    assert!(
        e.contains("contradictory scenarios: tests/data/scenarios/contradict.traces:2 step 1")
            && e.contains("contradict.traces:3 step 1"),
        "{e}"
    );
}

#[test]
fn missing_file_and_bad_format_are_reported() {
    let o = synth(&[
        "infer",
        "--traces",
        "no/such.traces",
        "--input-names",
        &data("door.inputs"),
        "--output-names",
        &data("door.outputs"),
    ]);
    assert_eq!(o.status.code(), Some(4));
    assert!(
        text(&o.stderr).starts_with("error: no/such.traces: "),
        "{}",
        text(&o.stderr)
    );
    let o = synth(&[
        "infer",
        "--traces",
        &data("door.traces"),
        "--format",
        "json,pdf",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("pdf"), "{}", text(&o.stderr));
}

#[test]
fn convert_round_trips_through_csv() {
    let dir = Dir::new();
    let csv = dir.path().join("door.csv");
    let back = dir.path().join("door.traces");
    let o = synth(&[
        "convert",
        "--traces",
        &data("door.traces"),
        "--to",
        "csv",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = synth(&[
        "convert",
        "--traces",
        csv.to_str().unwrap(),
        "--to",
        "fbsat",
        "-o",
        back.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let original = std::fs::read_to_string(data("door.traces")).unwrap();
    // Sampled logs cannot tell a repeated row from a held one: the SAT reconstruction paper's rule 1 collapses the
    // passive repeat of 10/11 in scenario 2. Everything else survives.
    let expected = original.replace(
        "out=CNF[11]; in=REQ[10]; in=REQ[01]",
        "out=CNF[11]; in=REQ[01]",
    );
    assert_ne!(expected, original);
    assert_eq!(std::fs::read_to_string(&back).unwrap(), expected);
}

#[test]
fn help_documents_exit_codes() {
    let o = synth(&["--help"]);
    assert!(o.status.success());
    assert!(text(&o.stdout).contains("70  internal error"));
}

#[test]
fn conform_finds_an_injected_divergence_and_refine_removes_it() {
    let out = Dir::new();
    let json = infer_door(&out.path().join("first"));
    // door_new.traces: after stop, a second stop switches the lamp off (step 4), which the
    // machine learned from door.traces does not do.
    let o = synth(&[
        "conform",
        "--ecc",
        json.to_str().unwrap(),
        "--log",
        &data("door_new.traces"),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let report = text(&o.stdout);
    assert!(
        report.contains("door_new.traces:2: DIVERGES: step 4: inputs 01 recorded CNF[00], the machine gives no CNF"),
        "{report}"
    );
    assert!(report.contains("agreement: 0 of 1 traces reproduced; 3 of 4 steps"));
    let refined = out.path().join("refined");
    let o = synth(&[
        "conform",
        "--ecc",
        json.to_str().unwrap(),
        "--log",
        &data("door_new.traces"),
        "--refine",
        "--train",
        &data("door.traces"),
        "--out",
        refined.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("after refinement, on the new recordings:\ntests/data/scenarios/door_new.traces:2: agrees on all 4 steps"));
    // One result, published whole: the listed files and the learned traces, no staging.
    let names: Vec<String> = std::fs::read_dir(&refined)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.iter().all(|n| !n.starts_with(".synth-staging")),
        "{names:?}"
    );
    for f in [
        "SynthesizedFB.fbt",
        "refined.traces",
        "refined.inputs",
        ".synth-files",
    ] {
        assert!(names.iter().any(|n| n == f), "{f} not in {names:?}");
    }
    for f in ["SynthesizedFB.json", "refined.traces"] {
        let shown = refined.join(f);
        assert!(
            text(&o.stdout).contains(shown.to_str().unwrap()),
            "{}",
            text(&o.stdout)
        );
    }
    // The refined machine still reproduces the training scenarios.
    let o = synth(&[
        "replay",
        "--ecc",
        refined.join("SynthesizedFB.json").to_str().unwrap(),
        "--traces",
        &data("door.traces"),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
}

#[test]
fn times_that_are_not_finite_positive_seconds_are_usage_errors() {
    let main = |extra: &[&str]| {
        let mut args = vec![
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            "tests/data/closed_loop/lamp_plant.smv",
            "--out",
            "/nonexistent/never-written",
        ];
        args.extend_from_slice(extra);
        synth(&args)
    };
    for t in ["inf", "1e300", "nan", "0", "-1"] {
        let o = main(&[&format!("--timeout={t}")]);
        assert_eq!(
            o.status.code(),
            Some(2),
            "--timeout {t}: {}",
            text(&o.stderr)
        );
        assert!(text(&o.stderr).contains("--timeout takes a positive number of seconds"));
    }
    let o = main(&[
        "--method",
        "search",
        "--time-limit",
        "inf",
        "--nusmv",
        "/bin/true",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("--time-limit takes a positive number"));
    let o = synth(&[
        "infer",
        "--traces",
        &data("door.traces"),
        "--guard-budget",
        "inf",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("--guard-budget"));
}

/// The two files hold the same bytes (an input left as it was).
fn assert_same_bytes(a: impl AsRef<Path>, b: impl AsRef<Path>) {
    assert_eq!(std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
}

#[test]
fn outputs_never_replace_inputs() {
    let dir = Dir::new();
    let traces = dir.path().join("door.traces");
    std::fs::copy(data("door.traces"), &traces).unwrap();
    std::fs::copy(data("door.inputs"), dir.path().join("door.inputs")).unwrap();
    std::fs::copy(data("door.outputs"), dir.path().join("door.outputs")).unwrap();
    let before = std::fs::read(&traces).unwrap();
    let t = traces.to_str().unwrap();
    let o = synth(&["convert", "--traces", t, "--to", "csv", "-o", t]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("would overwrite the input"));
    let names = dir.path().join("door.inputs");
    let o = synth(&[
        "convert",
        "--traces",
        t,
        "--to",
        "csv",
        "-o",
        names.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert_eq!(std::fs::read(&traces).unwrap(), before);
    assert_same_bytes(&names, data("door.inputs"));
    // ingest: -o equal to the log or to the map.
    let log = dir.path().join("tank.csv");
    let map = dir.path().join("tank.map");
    std::fs::copy("specs/tank/scenario1.csv", &log).unwrap();
    std::fs::copy("specs/tank/tank.map", &map).unwrap();
    for out in [&log, &map] {
        let o = synth(&[
            "ingest",
            "--log",
            log.to_str().unwrap(),
            "--map",
            map.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
        assert!(text(&o.stderr).contains("would overwrite the input"));
    }
    assert_same_bytes(&log, "specs/tank/scenario1.csv");
    assert_same_bytes(&map, "specs/tank/tank.map");
    // events: --out equal to the map.
    let o = synth(&[
        "events",
        "--log",
        log.to_str().unwrap(),
        "--map",
        map.to_str().unwrap(),
        "--reset",
        "%IX0.1 false",
        "--out",
        map.to_str().unwrap(),
        "--csv",
        dir.path().join("e.csv").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert_same_bytes(&map, "specs/tank/tank.map");
}

#[test]
fn special_outputs_stay_what_they_are() {
    use std::os::unix::fs::FileTypeExt;
    let dir = Dir::new();
    let door = data("door.traces");
    // A symlink: the file it names gets the result, the link stays a link.
    let real = dir.path().join("real.csv");
    std::fs::write(&real, "old").unwrap();
    let link = dir.path().join("link.csv");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    let o = synth(&[
        "convert",
        "--traces",
        &door,
        "--to",
        "csv",
        "-o",
        link.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(std::fs::read_to_string(&real)
        .unwrap()
        .starts_with("scenario,"));
    // A device: written in place, still a device.
    let o = synth(&[
        "convert",
        "--traces",
        &door,
        "--to",
        "csv",
        "-o",
        "/dev/null",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
    // A FIFO: the reader at its other end gets the result.
    let fifo = dir.path().join("pipe.csv");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let o = synth(&[
        "convert",
        "--traces",
        &door,
        "--to",
        "csv",
        "-o",
        fifo.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(reader.join().unwrap().starts_with("scenario,"));
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
}

#[test]
fn sizes_that_would_exhaust_the_machine_are_usage_errors() {
    let lamp = [
        "--ltl",
        "tests/data/closed_loop/lamp.ltl",
        "--plant",
        "tests/data/closed_loop/lamp_plant.smv",
    ];
    for extra in [
        &["--max-out-degree", "1000"][..],
        &["--max-out-degree", "0"],
        &["--max-states", "100000"],
        &["--method", "search", "--threads", "100000"],
        &["--method", "search", "--colonies", "100000"],
    ] {
        let mut args = lamp.to_vec();
        args.extend_from_slice(extra);
        let o = synth(&args);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", text(&o.stderr));
        assert!(
            text(&o.stderr).contains("is not in 1..="),
            "{}",
            text(&o.stderr)
        );
    }
    let lamps = data("lamps.traces");
    for extra in [
        &["--modules", "1000"][..],
        &["--modules", "2", "--slots", "100000"],
    ] {
        let mut args = vec!["infer", "--traces", &lamps];
        args.extend_from_slice(extra);
        let o = synth(&args);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", text(&o.stderr));
    }
}

/// fbSAT's conventions belong to the exact method: the search is refused them by name, not
/// left to ignore them.
#[test]
fn the_search_refuses_fbsats_conventions_by_name() {
    for (flag, extra) in [
        ("--algorithms binary", &["--algorithms", "binary"][..]),
        ("--start-state", &["--start-state"]),
    ] {
        let mut args = vec![
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            "tests/data/closed_loop/lamp_plant.smv",
            "--method",
            "search",
            "--out",
            "/nonexistent/never-written",
        ];
        args.extend_from_slice(extra);
        let o = synth(&args);
        assert_eq!(o.status.code(), Some(2), "{flag}: {}", text(&o.stderr));
        assert!(
            text(&o.stderr).contains(&format!("{flag} works with the exact method only")),
            "{}",
            text(&o.stderr)
        );
    }
}

/// Recordings that already violate a property end the main job before any synthesis, and
/// before NuSMV is needed: the message names the property with its line, and the file, line
/// and step of the first violating state, plain or gzipped (fbSAT's CRLF layout).
#[test]
fn recordings_that_violate_a_property_are_refused_before_synthesis() {
    let dir = "tests/data/explain";
    let main = |traces: &str| {
        synth(&[
            "--ltl",
            "specs/pnp.ltl",
            "--plant",
            "smv/pnp_surrogate.smv",
            "--traces",
            traces,
            "--input-names",
            &format!("{dir}/input-names"),
            "--output-names",
            &format!("{dir}/output-names"),
            "--out",
            "/nonexistent/never-written",
            "--nusmv",
            "/nonexistent/NuSMV",
        ])
    };
    let expected = |file: &str| {
        format!(
            "error: the recordings violate property up_before_moving (specs/pnp.ltl:17): first at \
             {file}:3 step 5 (its inputs with the outputs after step 4); 2 of the 15 states the \
             recordings show violate it; "
        )
    };
    // Without NuSMV the plant's replay of the recordings is unknown: the refusal stands, the
    // claim about controllers is not made.
    let no_claim = "so this says nothing of controllers in closed loop with it";
    let plain = format!("{dir}/diagonal.traces");
    let o = main(&plain);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains(&expected(&plain)) && text(&o.stderr).contains(no_claim),
        "{}",
        text(&o.stderr)
    );

    let tmp = Dir::new();
    let gz = tmp.path().join("diagonal.gz");
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    std::io::Write::write_all(&mut enc, &std::fs::read(&plain).unwrap()).unwrap();
    std::fs::write(&gz, enc.finish().unwrap()).unwrap();
    let gz = gz.to_str().unwrap();
    let o = main(gz);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains(&expected(gz)) && text(&o.stderr).contains(no_claim),
        "{}",
        text(&o.stderr)
    );
}

/// A result folder holds one result: a second run with fewer formats removes the files of the
/// first that it does not write again (the user's own files stay), and nothing of a run is
/// left in the folder but its results (no staging folder).
#[test]
fn a_result_folder_holds_one_result() {
    let dir = Dir::new();
    let out = dir.path().join("out");
    let run = |formats: &str| {
        synth(&[
            "infer",
            "-q",
            "--traces",
            &data("door.traces"),
            "--format",
            formats,
            "--out",
            out.to_str().unwrap(),
            "--no-ambiguity",
        ])
    };
    let o = run("json,fbt,st");
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(out.join("SynthesizedFB.fbt").is_file());
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let o = run("json");
    assert!(o.status.success(), "{}", text(&o.stderr));
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with(".synth.lock") && n != ".synth-files")
        .collect();
    names.sort();
    assert_eq!(names, ["SynthesizedFB.json", "notes.txt"]);
}

/// A second run into a folder another run is writing stops at once with a clear message
/// (exit 1) instead of mixing the files of two machines.
#[test]
fn a_second_run_into_a_busy_folder_stops() {
    let dir = Dir::new();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let lock = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(out.join(".synth.lock"))
        .unwrap();
    // SAFETY: flock on a descriptor this test owns, as a concurrent run would hold it.
    assert_eq!(
        unsafe {
            libc::flock(
                std::os::unix::io::AsRawFd::as_raw_fd(&lock),
                libc::LOCK_EX | libc::LOCK_NB,
            )
        },
        0
    );
    let o = synth(&[
        "infer",
        "-q",
        "--traces",
        &data("door.traces"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("another synth run is writing into"),
        "{}",
        text(&o.stderr)
    );
    assert!(!out.join("SynthesizedFB.json").exists());
}

/// A copy of `file` in `dir` under `name`, with a UTF-8 byte order mark in front, as Windows
/// editors and spreadsheet programs save text.
fn with_bom(file: impl AsRef<Path>, dir: &Path, name: &str) -> PathBuf {
    let mut bytes = b"\xEF\xBB\xBF".to_vec();
    bytes.extend(std::fs::read(file).unwrap());
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// `synth convert --traces TRACES ... --to TO`: the bytes written.
fn converted(traces: &Path, names: Option<(&Path, &Path)>, to: &str, dir: &Path) -> Vec<u8> {
    let out = dir.join(format!("converted.{to}"));
    let mut args = vec!["convert", "--traces", traces.to_str().unwrap()];
    if let Some((i, o)) = names {
        args.extend(["--input-names", i.to_str().unwrap()]);
        args.extend(["--output-names", o.to_str().unwrap()]);
    }
    args.extend(["--to", to, "-o", out.to_str().unwrap()]);
    let o = synth(&args);
    assert!(o.status.success(), "{args:?}: {}", text(&o.stderr));
    std::fs::read(out).unwrap()
}

#[test]
fn a_byte_order_mark_is_ignored_in_scenario_files() {
    let dir = Dir::new();
    let traces = with_bom(data("door.traces"), dir.path(), "door.traces");
    for ext in ["inputs", "outputs"] {
        std::fs::copy(
            data(&format!("door.{ext}")),
            dir.path().join(format!("door.{ext}")),
        )
        .unwrap();
    }
    let plain = Path::new(env!("CARGO_MANIFEST_DIR")).join(data("door.traces"));
    assert_eq!(
        converted(&traces, None, "csv", dir.path()),
        converted(&plain, None, "csv", dir.path())
    );
}

#[test]
fn a_byte_order_mark_is_ignored_in_names_files() {
    let dir = Dir::new();
    let inputs = with_bom(data("door.inputs"), dir.path(), "in.names");
    let outputs = with_bom(data("door.outputs"), dir.path(), "out.names");
    let door = Path::new(env!("CARGO_MANIFEST_DIR")).join(data("door.traces"));
    assert_eq!(
        converted(&door, Some((&inputs, &outputs)), "csv", dir.path()),
        converted(&door, None, "csv", dir.path())
    );
}

#[test]
fn a_byte_order_mark_is_ignored_in_json_machines() {
    let dir = Dir::new();
    let json = infer_door(dir.path());
    let marked = with_bom(&json, dir.path(), "marked.json");
    for ecc in [&json, &marked] {
        let o = synth(&[
            "replay",
            "--ecc",
            ecc.to_str().unwrap(),
            "--traces",
            &data("door.traces"),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        assert!(text(&o.stdout).contains("all reproduced"));
    }
}

#[test]
fn a_byte_order_mark_is_ignored_in_mapping_files() {
    let dir = Dir::new();
    let map = with_bom("specs/tank/tank.map", dir.path(), "tank.map");
    let log = with_bom("specs/tank/scenario1.csv", dir.path(), "tank.csv");
    let ingest = |map: &str, log: &str, out: &str| {
        let out = dir.path().join(out);
        let o = synth(&[
            "ingest",
            "--log",
            log,
            "--map",
            map,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        std::fs::read(out).unwrap()
    };
    assert_eq!(
        ingest(map.to_str().unwrap(), log.to_str().unwrap(), "a.traces"),
        ingest(
            "specs/tank/tank.map",
            "specs/tank/scenario1.csv",
            "b.traces"
        )
    );
}

/// The main job reads the LTL file before anything needs NuSMV: recordings that violate a
/// property are refused in the same words, the property's line counted the same.
#[test]
fn a_byte_order_mark_is_ignored_in_ltl_files() {
    let dir = Dir::new();
    let ltl = with_bom("specs/pnp.ltl", dir.path(), "pnp.ltl");
    let main = |ltl: &str| {
        let o = synth(&[
            "--ltl",
            ltl,
            "--plant",
            "smv/pnp_surrogate.smv",
            "--traces",
            "tests/data/explain/diagonal.traces",
            "--input-names",
            "tests/data/explain/input-names",
            "--output-names",
            "tests/data/explain/output-names",
            "--out",
            "/nonexistent/never-written",
            "--nusmv",
            "/nonexistent/NuSMV",
        ]);
        assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
        // Progress lines start with the elapsed time, which differs from run to run.
        text(&o.stderr)
            .replace(ltl, "LTL")
            .lines()
            .map(|l| l.split_once("s] ").map_or(l, |(_, rest)| rest))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let plain = main("specs/pnp.ltl");
    assert!(
        plain.contains("property up_before_moving (LTL:17)"),
        "{plain}"
    );
    assert_eq!(main(ltl.to_str().unwrap()), plain);
}

/// NuSMV reads the plant as synth copied it into the closed loop: `verify` gives the same
/// verdicts with a marked plant.
#[test]
fn a_byte_order_mark_is_ignored_in_plants() {
    let Some(nusmv) = crate::common::nusmv_or_skip() else {
        return;
    };
    let dir = Dir::new();
    let lamp = "tests/data/closed_loop/lamp";
    let o = synth(&[
        "infer",
        "-q",
        "--traces",
        &format!("{lamp}.traces"),
        "--out",
        dir.path().to_str().unwrap(),
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let json = dir.path().join("SynthesizedFB.json");
    let verify = |ecc: &Path, ltl: &Path, plant: &Path| {
        let o = synth(&[
            "verify",
            "--ecc",
            ecc.to_str().unwrap(),
            "--ltl",
            ltl.to_str().unwrap(),
            "--plant",
            plant.to_str().unwrap(),
            "--nusmv",
            nusmv.path.to_str().unwrap(),
        ]);
        (o.status.code(), text(&o.stdout))
    };
    let plain = verify(
        &json,
        Path::new(&format!("{lamp}.ltl")),
        Path::new(&format!("{lamp}_plant.smv")),
    );
    assert!(plain.1.contains("HOLDS    lights"), "{}", plain.1);
    let marked = verify(
        &json,
        Path::new(&format!("{lamp}.ltl")),
        &with_bom(format!("{lamp}_plant.smv"), dir.path(), "plant.smv"),
    );
    assert_eq!(marked, plain);
}

/// A token of a million characters, as a broken export or a runaway logger writes one.
fn giant() -> String {
    "a".repeat(1_000_000)
}

/// The run failed with exit code 1, in a message of at most a few KB that still names
/// `place` (file and line) and shows the token's length, not the token.
fn assert_short_error(o: &Output, place: &str) {
    let stderr = text(&o.stderr);
    let head: String = stderr.chars().take(600).collect();
    assert_eq!(o.status.code(), Some(4), "{head}");
    assert!(
        stderr.len() < 4096,
        "{} bytes of stderr: {head}",
        stderr.len()
    );
    assert!(stderr.contains(place), "{place} not in {stderr}");
    assert!(stderr.contains("characters)"), "{stderr}");
}

/// `synth infer` of a trace file `name` holding `content` fails at `place` (after the path).
fn assert_infer_is_short(name: &str, content: &str, place: &str) {
    let dir = Dir::new();
    let traces = dir.path().join(name);
    std::fs::write(&traces, content).unwrap();
    let t = traces.to_str().unwrap();
    let o = synth(&[
        "infer",
        "--traces",
        t,
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert_short_error(&o, &format!("{t}:{place}"));
}

#[test]
fn giant_tokens_in_scenario_files_are_not_echoed() {
    let content = format!("1\nin=REQ[{}];\n", giant());
    assert_infer_is_short("t.traces", &content, "2: step 1");
}

#[test]
fn giant_tokens_in_csv_logs_are_not_echoed() {
    let content = format!("in:a,out:z\n0,0\n{},1\n", giant());
    assert_infer_is_short("log.csv", &content, "3: column 1");
}

#[test]
fn giant_tokens_in_names_files_are_not_echoed() {
    let dir = Dir::new();
    let inputs = dir.path().join("in.names");
    std::fs::write(&inputs, format!("start\nstop 1{}\n", giant())).unwrap();
    let i = inputs.to_str().unwrap();
    let o = synth(&[
        "infer",
        "--traces",
        &data("door.traces"),
        "--input-names",
        i,
        "--output-names",
        &data("door.outputs"),
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert_short_error(&o, &format!("{i}:2:"));
}

#[test]
fn giant_tokens_in_ltl_files_are_not_echoed() {
    let dir = Dir::new();
    let ltl = dir.path().join("lamp.ltl");
    let l = ltl.to_str().unwrap();
    let main = || {
        synth(&[
            "--ltl",
            l,
            "--plant",
            "tests/data/closed_loop/lamp_plant.smv",
            "--traces",
            "tests/data/closed_loop/lamp.traces",
            "--out",
            "/nonexistent/never-written",
            "--nusmv",
            "/nonexistent/NuSMV",
        ])
    };
    // An unexpected token, shown with the line around it and a caret under it.
    std::fs::write(&ltl, format!("-- lamp\nG (lamp {} & button)\n", giant())).unwrap();
    let o = main();
    assert_short_error(&o, &format!("{l}:2:9: syntax error"));
    // A label, which is a name that no file limits.
    std::fs::write(&ltl, format!("-- lamp\n1{}: G lamp\n", giant())).unwrap();
    assert_short_error(&main(), &format!("{l}:2:1: "));
}

#[test]
fn giant_tokens_in_mappings_and_logs_for_ingest_are_not_echoed() {
    let dir = Dir::new();
    let map = dir.path().join("tank.map");
    let m = map.to_str().unwrap();
    let out = dir.path().join("out.traces");
    let ingest = |log: &str| {
        synth(&[
            "ingest",
            "--log",
            log,
            "--map",
            m,
            "-o",
            out.to_str().unwrap(),
        ])
    };
    std::fs::write(&map, format!("%IX0.1 in ll\n%QX0.0 out 1{}\n", giant())).unwrap();
    assert_short_error(&ingest("specs/tank/scenario1.csv"), &format!("{m}:2: "));
    std::fs::copy("specs/tank/tank.map", &map).unwrap();
    let log = dir.path().join("log.csv");
    let l = log.to_str().unwrap();
    std::fs::write(&log, format!("timestamp,address,value\n0,{},1\n", giant())).unwrap();
    assert_short_error(&ingest(l), &format!("{l}:2: unknown address"));
    assert!(!out.exists());
}

#[test]
fn giant_tokens_in_json_machines_are_not_echoed() {
    let dir = Dir::new();
    let json = infer_door(dir.path());
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let bad = dir.path().join("bad.json");
    let b = bad.to_str().unwrap();
    let replay = || synth(&["replay", "--ecc", b, "--traces", &data("door.traces")]);
    // A name the contract refuses, and a field serde does not know (it quotes the key).
    doc["inputs"][0] = format!("1{}", giant()).into();
    std::fs::write(&bad, doc.to_string()).unwrap();
    assert_short_error(&replay(), &format!("{b}: inputs[0]: "));
    let mut object = doc.as_object().unwrap().clone();
    object.remove("inputs");
    object.insert(giant(), 1.into());
    std::fs::write(&bad, serde_json::Value::Object(object).to_string()).unwrap();
    assert_short_error(&replay(), &format!("{b}:1:"));
}

#[test]
fn giant_tokens_in_plants_are_not_echoed() {
    let dir = Dir::new();
    let lamp = std::fs::read_to_string("tests/data/closed_loop/lamp_plant.smv").unwrap();
    let plant = dir.path().join("plant.smv");
    let p = plant.to_str().unwrap();
    let main = |nusmv: &str| {
        synth(&[
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            p,
            "--traces",
            "tests/data/closed_loop/lamp.traces",
            "--out",
            dir.path().join("out").to_str().unwrap(),
            "--nusmv",
            nusmv,
        ])
    };
    // The coupling check reads the plant before NuSMV is needed.
    let parameter = lamp.replace(
        "MODULE plant(lamp)",
        &format!("MODULE plant(lamp, {})", giant()),
    );
    std::fs::write(&plant, parameter).unwrap();
    assert_short_error(
        &main("/nonexistent/NuSMV"),
        &format!("{p}:2: plant parameter"),
    );
    // NuSMV quotes the token it cannot parse.
    let Some(nusmv) = crate::common::nusmv_or_skip() else {
        return;
    };
    let token = lamp.replace("TRUE       : 2;", &format!("TRUE       : 2 {};", giant()));
    std::fs::write(&plant, token).unwrap();
    assert_short_error(&main(nusmv.path.to_str().unwrap()), &format!("{p}:11: "));
}

/// A `--name` that NuSMV, an ST compiler or the closed loop would refuse is a usage error
/// before anything is read or written, naming the option and why.
#[test]
fn block_names_an_export_would_refuse_are_usage_errors() {
    let dir = Dir::new();
    for (name, why) in [
        ("main", "NuSMV's top module"),
        ("ECC", "closed-loop model"),
        ("plant", "closed-loop model"),
        ("VAR", "NuSMV keyword"),
        ("esac", "NuSMV keyword"),
        ("MAX", "NuSMV keyword"),
        ("END_VAR", "IEC 61131-3 keyword"),
        ("state", "its own members"),
    ] {
        let out = dir.path().join(name);
        let o = synth(&[
            "infer",
            "--traces",
            "tests/data/closed_loop/lamp.traces",
            "--name",
            name,
            "--out",
            out.to_str().unwrap(),
        ]);
        let stderr = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {stderr}");
        assert!(
            stderr.contains("'--name <NAME>'") && stderr.contains(why),
            "{stderr}"
        );
        assert!(!out.exists(), "{name}");
    }
    let o = synth(&[
        "--ltl",
        "tests/data/closed_loop/lamp.ltl",
        "--plant",
        "tests/data/closed_loop/lamp_plant.smv",
        "--name",
        "main",
        "--out",
        dir.path().join("main_job").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
}

/// A log with a header and no data row has no scenario in it: ingest says so and writes no
/// scenario file that `synth infer` would refuse.
#[test]
fn ingest_refuses_a_log_without_data_rows() {
    let dir = Dir::new();
    for (file, log) in [
        ("long.csv", "timestamp,address,value\n"),
        (
            "wide.csv",
            "timestamp,%IX0.1,%IX0.2,%IX0.0,%QX0.0,%QX0.1\n\n",
        ),
    ] {
        let path = dir.path().join(file);
        std::fs::write(&path, log).unwrap();
        let out = dir.path().join("out/tank.traces");
        let o = synth(&[
            "ingest",
            "--log",
            path.to_str().unwrap(),
            "--map",
            "specs/tank/tank.map",
            "-o",
            out.to_str().unwrap(),
        ]);
        let stderr = text(&o.stderr);
        assert_eq!(o.status.code(), Some(4), "{stderr}");
        assert_eq!(
            stderr,
            format!("error: {}: the log has no data rows\n", path.display())
        );
        assert!(files_in(&dir.path().join("out")).is_empty(), "{file}");
    }
}

/// An interface name that an export cannot use is reported in the names file, at its line,
/// before any search: that is where the user renames it.
#[test]
fn export_name_errors_name_the_names_file_and_line() {
    let dir = Dir::new();
    let inputs = dir.path().join("in.names");
    std::fs::write(&inputs, "start\nEND_VAR\n").unwrap();
    let i = inputs.to_str().unwrap();
    let out = dir.path().join("out");
    let o = synth(&[
        "infer",
        "--traces",
        &data("door.traces"),
        "--input-names",
        i,
        "--output-names",
        &data("door.outputs"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains(&format!(
            "\nerror: {i}:2: input 2 `END_VAR` cannot be used in an IEC 61499 .fbt file"
        )),
        "{}",
        text(&o.stderr)
    );
    assert!(!out.exists());
}

/// Recordings that contradict each other, read as exact, point at `--noisy`: a logger's
/// scan-cycle glitch is the usual cause.
#[test]
fn a_contradiction_suggests_noisy_synthesis() {
    let dir = Dir::new();
    let (log, o) = infer_glitchy_log(dir.path(), &[]);
    let stderr = text(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{stderr}");
    // Both samples by their CSV rows.
    let at = |row: usize, first: usize| {
        format!(
            "{}:{row} (step 2 of the scenario from line {first})",
            log.display()
        )
    };
    assert!(
        stderr.starts_with(&format!(
            "error: contradictory scenarios: {} answers inputs 1 with CNF[1], but {} ignores",
            at(3, 2),
            at(5, 4)
        )),
        "{stderr}"
    );
    assert!(
        stderr.contains("\nhint: if the recording has scan-cycle glitches"),
        "{stderr}"
    );
    assert!(stderr.contains("--noisy --max-errors N"), "{stderr}");
}

/// `synth infer -q ARGS` of a CSV log, written into `dir`, whose two scenarios answer one
/// input history differently; the log's path and the run.
fn infer_glitchy_log(dir: &Path, args: &[&str]) -> (PathBuf, Output) {
    let log = dir.join("glitch.csv");
    std::fs::write(&log, "scenario,in:a,out:z\n1,0,0\n1,1,1\n2,0,0\n2,1,0\n").unwrap();
    let out = dir.join("out");
    let mut all = vec!["infer", "-q"];
    all.extend_from_slice(args);
    all.extend([
        "--traces",
        log.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let o = synth(&all);
    (log, o)
}

/// Noisy synthesis that finds no machine within an error bound says to raise the bound, not
/// only --max-states, which cannot help when uncorrected glitches contradict every machine.
#[test]
fn too_few_errors_allowed_says_raise_max_errors() {
    let dir = Dir::new();
    let noisy = ["--noisy", "--max-errors", "0", "--max-states", "3"];
    let (_, o) = infer_glitchy_log(dir.path(), &noisy);
    let stderr = text(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{stderr}");
    assert!(
        stderr.contains("with at most 0 corrected samples: raise --max-errors"),
        "{stderr}"
    );
}

/// A glitchy log read as exact makes the number of states climb; from 10 states on, exact
/// synthesis says that `--noisy` may be what the log needs.
#[test]
fn a_climbing_number_of_states_suggests_noisy_synthesis() {
    let dir = Dir::new();
    let o = synth(&[
        "infer",
        "--max-states",
        "10",
        "--traces",
        "specs/distribution_noisy.csv",
        "--out",
        dir.path().join("out").to_str().unwrap(),
    ]);
    let stderr = text(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{stderr}");
    let hint = stderr
        .lines()
        .position(|l| l.contains("] hint: if the recording has scan-cycle glitches"))
        .expect("a hint");
    assert!(
        stderr
            .lines()
            .nth(hint - 1)
            .unwrap()
            .contains("trying C = 10"),
        "{stderr}"
    );
}

/// `synth diff`: a machine and a renumbered copy are equivalent; a copy with one transition
/// led elsewhere differs on a sequence the command prints.
#[test]
fn diff_tells_a_renumbered_copy_from_a_changed_machine() {
    let dir = Dir::new();
    let reference = "specs/distribution_reference.json";
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(reference).unwrap()).unwrap();
    let c = doc["states"].as_array().unwrap().len();
    // State i > 0 becomes state c - i; the initial state stays first.
    let new = |i: u64| if i == 0 { 0 } else { c as u64 - i };
    let mut renumbered = doc.clone();
    let states = doc["states"].as_array().unwrap();
    let mut reordered = states.clone();
    for (i, s) in states.iter().enumerate() {
        reordered[new(i as u64) as usize] = s.clone();
    }
    renumbered["states"] = reordered.into();
    for t in renumbered["transitions"].as_array_mut().unwrap() {
        for end in ["from", "to"] {
            t[end] = new(t[end].as_u64().unwrap()).into();
        }
    }
    let copy = dir.path().join("renumbered.json");
    std::fs::write(&copy, renumbered.to_string()).unwrap();
    let o = synth(&["diff", reference, copy.to_str().unwrap()]);
    assert!(o.status.success(), "{}{}", text(&o.stdout), text(&o.stderr));
    assert!(
        text(&o.stdout).starts_with("equivalent: "),
        "{}",
        text(&o.stdout)
    );

    let mut changed = doc.clone();
    let to = changed["transitions"][0]["to"].as_u64().unwrap();
    changed["transitions"][0]["to"] = ((to + 1) % c as u64).into();
    let other = dir.path().join("changed.json");
    std::fs::write(&other, changed.to_string()).unwrap();
    let o = synth(&["diff", reference, other.to_str().unwrap()]);
    let stdout = text(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{stdout}{}", text(&o.stderr));
    assert!(stdout.starts_with("different: after "), "{stdout}");
    // A sequence is printed, and two different answers to it (ecc::diff replays them).
    let inputs: Vec<&str> = stdout
        .lines()
        .filter_map(|l| l.trim().strip_prefix("step "))
        .map(|l| l.split_whitespace().nth(2).unwrap())
        .collect();
    assert!(!inputs.is_empty(), "{stdout}");
    let answer = |machine: &str| {
        stdout
            .lines()
            .find_map(|l| l.trim().strip_prefix(&format!("{machine} answers ")))
            .unwrap()
            .to_string()
    };
    assert_ne!(answer(reference), answer(other.to_str().unwrap()));
    // The structure shows the one transition led elsewhere.
    assert!(stdout.contains("1 with changes"), "{stdout}");
    assert!(stdout.contains(": transition 1: `"), "{stdout}");
}

/// Completion scripts and manual pages come from the same definitions as the parser: every
/// command is in them.
#[test]
fn completions_and_manual_pages_cover_every_command() {
    let o = synth(&["completions", "bash"]);
    assert!(o.status.success());
    let bash = text(&o.stdout);
    assert!(bash.contains("_synth()"), "{bash}");
    for command in ["infer", "next-recording", "learn", "verify", "diff", "man"] {
        assert!(
            bash.contains(command),
            "{command} missing from the bash completions"
        );
    }
    for shell in ["zsh", "fish"] {
        assert!(synth(&["completions", shell]).status.success());
    }
    assert_eq!(
        synth(&["completions", "tcsh-from-1985"]).status.code(),
        Some(2)
    );
    let o = synth(&["man"]);
    assert!(o.status.success());
    let page = text(&o.stdout);
    assert!(page.contains(".TH synth 1"), "{page}");
    assert!(page.contains("\\-\\-ltl"), "{page}");
    let dir = Dir::new();
    let o = synth(&["man", "--out", dir.path().to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let infer = std::fs::read_to_string(dir.path().join("synth-infer.1")).unwrap();
    assert!(infer.contains(".TH synth-infer 1"), "{infer}");
    assert!(infer.contains("\\-\\-noisy"), "{infer}");
    assert!(dir.path().join("synth-next-recording.1").is_file());
}

/// `synth export` writes every format from a JSON machine, and the JSON it writes replays the
/// recordings as the original does (infer's machines and the hand-written reference).
#[test]
fn export_round_trips_json_machines_of_the_shipped_cases() {
    let dir = Dir::new();
    let d = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    let mut cases: Vec<(String, &str)> = Vec::new();
    for (k, traces) in ["specs/pnp.traces", "specs/tank2.traces"]
        .iter()
        .enumerate()
    {
        let o = synth(&[
            "infer",
            "-q",
            "--no-ambiguity",
            "--traces",
            traces,
            "--format",
            "json",
            "--out",
            &d(&format!("inferred{k}")),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        cases.push((d(&format!("inferred{k}/SynthesizedFB.json")), traces));
    }
    cases.push((
        "specs/distribution_reference.json".to_string(),
        "specs/distribution.csv",
    ));
    for (k, (json, traces)) in cases.iter().enumerate() {
        let out = d(&format!("exported{k}"));
        let o = synth(&[
            "export",
            "--ecc",
            json,
            "--out",
            &out,
            "--name",
            "Rebuilt",
            "--format",
            "json,fbt,smv,dot,st,pnml,plcopen",
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let net = std::fs::read_to_string(format!("{out}/Rebuilt.pnml")).unwrap();
        assert!(net.contains("<name><text>Rebuilt</text></name>"), "{net}");
        let project = std::fs::read_to_string(format!("{out}/Rebuilt.xml")).unwrap();
        assert!(
            project.contains("<pou name=\"Rebuilt\" pouType=\"functionBlock\">"),
            "{project}"
        );
        for ext in ["json", "fbt", "smv", "dot", "st", "pnml", "xml"] {
            assert!(dir
                .path()
                .join(format!("exported{k}/Rebuilt.{ext}"))
                .is_file());
        }
        let exported = format!("{out}/Rebuilt.json");
        let r = synth(&["replay", "--ecc", &exported, "--traces", traces]);
        assert!(r.status.success(), "{json}: {}", text(&r.stderr));
        // The same machine: the exported JSON exports to itself.
        let again = d(&format!("again{k}"));
        assert!(synth(&[
            "export", "--ecc", &exported, "--out", &again, "--name", "Rebuilt", "--format", "json"
        ])
        .status
        .success());
        assert_eq!(
            std::fs::read_to_string(&exported).unwrap(),
            std::fs::read_to_string(format!("{again}/Rebuilt.json")).unwrap()
        );
    }
    // Never into the folder the machine is read from (the output rule: bad input, 4).
    let o = synth(&["export", "--ecc", &cases[0].0, "--out", &d("inferred0")]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(std::path::Path::new(&cases[0].0).is_file());
}

/// `-` is stdin for scenario files and machines, and stdout for `infer --out`, `export --out`
/// and `convert -o`; then every other line goes to stderr, so that pipes carry the result only.
#[test]
fn dash_means_stdin_and_stdout_in_pipes() {
    use std::io::Write as _;
    use std::process::Stdio;
    let pipe = |args: &[&str], input: &[u8]| {
        let mut child = TestCommand::new()
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn();
        child.stdin.take().unwrap().write_all(input).unwrap();
        child.wait_with_output().unwrap()
    };
    let traces = std::fs::read("specs/tank2.traces").unwrap();
    // fbSAT scenarios on stdin, names from files, the machine on stdout.
    let o = pipe(
        &[
            "infer",
            "--traces",
            "-",
            "--input-names",
            "specs/tank2.inputs",
            "--output-names",
            "specs/tank2.outputs",
            "--out",
            "-",
        ],
        &traces,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let machine = o.stdout;
    assert!(text(&machine).starts_with('{'), "{}", text(&machine));
    assert!(text(&o.stderr).contains("C = 8"), "{}", text(&o.stderr));
    // The machine from stdin replays the recordings.
    let r = pipe(
        &["replay", "--ecc", "-", "--traces", "specs/tank2.traces"],
        &machine,
    );
    assert!(r.status.success(), "{}", text(&r.stderr));
    // And exports to one format on stdout.
    let e = pipe(
        &["export", "--ecc", "-", "--out", "-", "--format", "st"],
        &machine,
    );
    assert!(e.status.success(), "{}", text(&e.stderr));
    assert!(
        text(&e.stdout).starts_with("FUNCTION_BLOCK SynthesizedFB"),
        "{}",
        text(&e.stdout)
    );
    // A CSV log on stdin is told apart from fbSAT scenarios by its content.
    let c = synth(&[
        "convert",
        "--traces",
        "specs/tank2.traces",
        "--to",
        "csv",
        "-o",
        "-",
    ]);
    assert!(c.status.success(), "{}", text(&c.stderr));
    assert!(
        text(&c.stdout).starts_with("scenario,in:"),
        "{}",
        text(&c.stdout)
    );
    let o = pipe(
        &[
            "infer",
            "-q",
            "--no-ambiguity",
            "--traces",
            "-",
            "--out",
            "-",
        ],
        &c.stdout,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(o.stdout, machine, "the same machine from the CSV form");
    // Errors in stdin name it.
    let bad = pipe(
        &["infer", "--traces", "-", "--out", "-"],
        b"1\nin=REQ[1]; out=CNF[1\n",
    );
    assert_eq!(bad.status.code(), Some(4), "{}", text(&bad.stderr));
    assert!(text(&bad.stderr).contains("-:2"), "{}", text(&bad.stderr));
    assert!(bad.stdout.is_empty());
}

/// Common exports of the same long log read alike: ISO 8601 timestamps (UTC, with an offset,
/// or with a space as spreadsheets write them), quoted fields and a byte order mark, and `;`
/// between cells with decimal commas.
#[test]
fn ingest_reads_iso_timestamps_and_quoted_addresses_as_the_plain_log() {
    let dir = Dir::new();
    let plain = std::fs::read_to_string("specs/tank/scenario1.csv").unwrap();
    let iso = |seconds: f64, style: usize| {
        // 2024-05-01T10:00:00Z is 1714557600 s after the Unix epoch.
        let t = 1_714_557_600.0 + seconds;
        let (h, m, s) = ((t as u64 / 3600) % 24, (t as u64 / 60) % 60, t % 60.0);
        match style {
            0 => format!("2024-05-01T{h:02}:{m:02}:{s:06.3}Z"),
            1 => format!("\"2024-05-01T{:02}:{m:02}:{s:06.3}+02:00\"", h + 2),
            _ => format!("2024-05-01 {h:02}:{m:02}:{s:06.3}"),
        }
    };
    let run = |name: &str, log: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, log).unwrap();
        let out = dir.path().join(format!("{name}.traces"));
        let o = synth(&[
            "ingest",
            "--log",
            path.to_str().unwrap(),
            "--map",
            "specs/tank/tank.map",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
        std::fs::read_to_string(out).unwrap()
    };
    let expected = run("plain.csv", &plain);
    for style in 0..3 {
        let mut log = String::from("\u{feff}\"timestamp\",\"address\",\"value\"\n");
        for line in plain.lines().skip(1) {
            let f: Vec<&str> = line.split(',').collect();
            let t: f64 = f[0].parse().unwrap();
            log.push_str(&format!("{},\"{}\",{}\n", iso(t, style), f[1], f[2]));
        }
        assert_eq!(
            run(&format!("iso{style}.csv"), &log),
            expected,
            "style {style}"
        );
    }
    // Excel in a locale with a decimal comma: `;` between cells, `5,25` seconds.
    let mut log = String::from("\u{feff}timestamp;address;value\n");
    for line in plain.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        log.push_str(&format!("{};{};{}\n", f[0].replace('.', ","), f[1], f[2]));
    }
    assert!(log.contains(",00;"), "{log}");
    assert_eq!(run("semicolons.csv", &log), expected);
    // The same without the byte order mark (the delimiter was once sniffed from the three
    // bytes read to look for the mark, and only a marked file was read).
    let bare = log.trim_start_matches('\u{feff}');
    assert_eq!(run("semicolons-bare.csv", bare), expected);
}

/// `--json` puts one machine-readable summary on stdout, and nothing else there.
#[test]
fn json_summaries_are_the_only_stdout() {
    let dir = Dir::new();
    let out = dir.path().join("r");
    let o = synth(&[
        "infer",
        "--traces",
        "specs/tank2.traces",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is one JSON value");
    assert_eq!(v["size"]["c"], 8);
    assert_eq!(v["ambiguity"]["verdict"], "ambiguous");
    let steps = v["ambiguity"]["rivals"][0]["steps"].as_array().unwrap();
    let last = steps.last().unwrap();
    assert_ne!(last["machine"], last["rival"], "{last}");
    assert!(
        text(&o.stderr).contains("C = 8"),
        "the text summary moves to stderr"
    );
    let machine = out.join("SynthesizedFB.json");
    let m = machine.to_str().unwrap();
    let d = synth(&["diff", m, m, "--json"]);
    assert!(d.status.success());
    let v: serde_json::Value = serde_json::from_slice(&d.stdout).unwrap();
    assert_eq!(v["equivalent"], true);
    let rival = out.join("rival1.json");
    let d = synth(&["diff", m, rival.to_str().unwrap(), "--json"]);
    assert_eq!(d.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&d.stdout).unwrap();
    assert_eq!(v["equivalent"], false);
    assert!(!v["difference"]["inputs"].as_array().unwrap().is_empty());
}

/// The door machine's interface and its negative scenarios read from `file`.
fn door_negatives(file: &str) -> Vec<fbsynth::scenario::negative::NegativeScenario> {
    let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    fbsynth::scenario::negative::read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join(data(file)),
        &names(&["start", "stop"]),
        &names(&["motor", "lamp"]),
        &[false, false],
    )
    .unwrap()
}

#[test]
fn a_negative_scenario_excludes_the_behaviour_it_names() {
    // Pressing both buttons while the motor runs: the least machine stops it (the stop guard
    // needs no more), which the negative scenario forbids.
    let negs = door_negatives("door_negative.traces");
    let plain = Dir::new();
    let ecc = read_json(
        &std::fs::read_to_string(infer_door(plain.path())).unwrap(),
        Path::new("plain.json"),
    )
    .unwrap();
    assert!(
        negs[0].followed_by(&ecc),
        "the fixture must name the least machine's behaviour"
    );

    let out = Dir::new();
    let o = synth(&[
        "infer",
        "--traces",
        &data("door.traces"),
        "--negative",
        &data("door_negative.traces"),
        "--out",
        out.path().to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    // Same states and transitions; one more literal keeps `stop` from winning over `start`.
    assert!(
        text(&o.stdout).contains("C = 2  K = 1  T = 2  N = 3"),
        "{}",
        text(&o.stdout)
    );
    let json = std::fs::read_to_string(out.path().join("SynthesizedFB.json")).unwrap();
    let ecc = read_json(&json, Path::new("SynthesizedFB.json")).unwrap();
    assert!(!negs[0].followed_by(&ecc));
    let set = fbsat::read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join(data("door.traces")),
        Some(vec!["start".into(), "stop".into()]),
        Some(vec!["motor".into(), "lamp".into()]),
    )
    .unwrap();
    set.check(&ecc).unwrap();
}

#[test]
fn a_negative_scenario_the_recordings_force_is_refused_with_both_places() {
    let out = Dir::new();
    let dir = out.path().join("result");
    let o = synth(&[
        "infer",
        "--traces",
        &data("door.traces"),
        "--negative",
        &data("door_negative_recorded.traces"),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    // The passive step is recorded in scenario 1 after the same history as scenario 2's step 2.
    assert!(
        err.contains("door_negative_recorded.traces:2:")
            && err.contains("door.traces:2 step 2")
            && err.contains("shows this negative scenario"),
        "{err}"
    );
    assert!(!dir.exists());
}

#[test]
fn the_least_guards_are_looked_for_over_every_machine_of_the_least_size() {
    // A machine with 5 states and 10 transitions that needs 24 guard literals: what infer
    // reported when only the first structure's guards were minimized.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let set = fbsat::read(
        &root.join(data("structures.traces")),
        Some(["x1", "x2", "x3", "x4"].map(String::from).to_vec()),
        Some(vec!["z1".into(), "z2".into()]),
    )
    .unwrap();
    let first_file = root.join(data("structures_first.json"));
    let first = read_json(&std::fs::read_to_string(&first_file).unwrap(), &first_file).unwrap();
    set.check(&first).unwrap();
    let s = first.size();
    assert_eq!((s.c, s.t, s.n), (5, 10, 24));

    let out = Dir::new();
    let o = synth(&[
        "infer",
        "--no-ambiguity",
        "--traces",
        &data("structures.traces"),
        "--out",
        out.path().to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("C = 5  K = 3  T = 10  N = 15\n"),
        "{}",
        text(&o.stdout)
    );
    assert!(
        text(&o.stderr).contains("guards: N = 15 (minimal)"),
        "{}",
        text(&o.stderr)
    );
    let file = out.path().join("SynthesizedFB.json");
    let ecc = read_json(&std::fs::read_to_string(&file).unwrap(), &file).unwrap();
    set.check(&ecc).unwrap();
    assert_eq!((ecc.size().c, ecc.size().t, ecc.size().n), (5, 10, 15));
}

#[test]
fn fixed_bounds_ask_for_a_size_and_say_when_none_fits() {
    let lamps = || {
        fbsat::read(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join(data("lamps.traces")),
            Some(["start", "stop", "sensor"].map(String::from).to_vec()),
            Some(["start_led", "motor"].map(String::from).to_vec()),
        )
        .unwrap()
    };
    let infer = |dir: &Path, bounds: &[&str]| {
        let mut args = vec![
            "infer",
            "-q",
            "--no-ambiguity",
            "--traces",
            "tests/data/scenarios/lamps.traces",
            "--out",
            dir.to_str().unwrap(),
        ];
        args.extend_from_slice(bounds);
        synth(&args)
    };
    let out = Dir::new();
    // The least machine: C 4, K 3, T 11, N 17.
    let o = infer(&out.path().join("least"), &[]);
    assert!(
        text(&o.stdout).contains("C = 4  K = 3  T = 11  N = 17"),
        "{}",
        text(&o.stdout)
    );
    // Two transitions per state at most: five states more.
    let o = infer(&out.path().join("k2"), &["--out-degree", "2"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("C = 9  K = 2  T = 17  N = 19"),
        "{}",
        text(&o.stdout)
    );
    let file = out.path().join("k2/SynthesizedFB.json");
    let ecc = read_json(&std::fs::read_to_string(&file).unwrap(), &file).unwrap();
    lamps().check(&ecc).unwrap();
    // At most five states: the fewest transitions there need only four.
    let o = infer(&out.path().join("c5"), &["--states", "5"]);
    assert!(
        text(&o.stdout).contains("C = 4  K = 3  T = 11"),
        "{}",
        text(&o.stdout)
    );
    // Four states with ten transitions: none, exit 3 naming the bounds, no files.
    let dir = out.path().join("none");
    let o = infer(&dir, &["--states", "4", "--transitions", "10"]);
    assert_eq!(o.status.code(), Some(3), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("within the bounds given (4 states, at most 10 transitions)"),
        "{}",
        text(&o.stderr)
    );
    assert!(!dir.exists());
    // The bounds are for the exact single machine only.
    let o = infer(&out.path().join("u"), &["--states", "4", "--modules", "2"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn every_command_takes_quiet_verbose_and_json() {
    // The user's commands, and the developer's in synth-dev.
    let run = |binary: &str, args: &[&str]| match binary {
        "synth-dev" => TestCommand::developer().args(args).output(),
        _ => TestCommand::new().args(args).output(),
    };
    let mut commands: Vec<(&str, String)> = Vec::new();
    for binary in ["synth", "synth-dev"] {
        let help = text(&run(binary, &["--help"]).stdout);
        commands.extend(
            help.lines()
                .skip_while(|l| !l.starts_with("Commands:"))
                .skip(1)
                .take_while(|l| l.starts_with("  "))
                .filter_map(|l| l.split_whitespace().next().map(String::from))
                .filter(|c| c != "help")
                .map(|c| (binary, c)),
        );
    }
    assert!(commands.len() >= 20, "{commands:?}");
    for (binary, c) in &commands {
        let h = text(&run(binary, &[c, "--help"]).stdout);
        for flag in ["-q, --quiet", "-v, --verbose", "--json"] {
            assert!(h.contains(flag), "synth {c} lacks {flag}");
        }
    }
    // Before the command name too; the main job's own options are not taken there.
    let o = synth(&["-q", "replay", "--help"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = synth(&[
        "--ltl",
        "specs/pnp.ltl",
        "replay",
        "--ecc",
        "m.json",
        "--traces",
        "t",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("cannot be used with '--ltl'"),
        "{}",
        text(&o.stderr)
    );
    // A command without a summary of its own: the generic one, alone on stdout.
    let dir = Dir::new();
    let json = infer_door(dir.path());
    let o = synth(&[
        "replay",
        "--ecc",
        json.to_str().unwrap(),
        "--traces",
        &data("door.traces"),
        "--json",
        "-q",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["command"], "replay");
    assert_eq!(v["exit"], 0);
    assert!(
        v["output"].as_str().unwrap().contains("all reproduced"),
        "{v}"
    );
    // Its failure: the same object with the exit code and the error, still on stdout.
    let o = synth(&[
        "replay",
        "--ecc",
        "missing.json",
        "--traces",
        &data("door.traces"),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(4));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["exit"], 4);
    assert!(v["error"].as_str().unwrap().contains("missing.json"), "{v}");
    // Files written are listed.
    let out = dir.path().join("conv.csv");
    let o = synth(&[
        "convert",
        "--traces",
        &data("door.traces"),
        "--to",
        "csv",
        "--output",
        out.to_str().unwrap(),
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["files"][0], out.to_str().unwrap());
}

#[test]
fn the_plateau_search_trades_a_state_for_fewer_guard_literals() {
    let out = Dir::new();
    let infer = |extra: &[&str], dir: &str| {
        let mut args = vec![
            "infer",
            "--no-ambiguity",
            "--traces",
            "specs/pnp.traces",
            "--format",
            "json",
            "--out",
        ];
        let dir = out.path().join(dir);
        let d = dir.to_str().unwrap().to_string();
        args.push(&d);
        args.extend_from_slice(extra);
        let o = synth(&args);
        assert!(o.status.success(), "{}", text(&o.stderr));
        (
            text(&o.stdout),
            text(&o.stderr),
            dir.join("SynthesizedFB.json"),
        )
    };
    let (least, _, _) = infer(&[], "least");
    assert!(least.contains("C = 8  K = 5  T = 13  N = 18"), "{least}");
    // One state more (at most 9, to keep the test short): four literals fewer, same T.
    let (more, progress, file) = infer(&["--plateau", "1", "--max-states", "9"], "plateau");
    assert!(
        progress.contains("plateau: at most 9 states: N = 14"),
        "{progress}"
    );
    assert!(more.contains("C = 9  K = 3  T = 13  N = 14"), "{more}");
    assert_eq!(
        read_json(&std::fs::read_to_string(&file).unwrap(), &file)
            .unwrap()
            .size()
            .n,
        14
    );
    let o = synth(&[
        "replay",
        "--ecc",
        file.to_str().unwrap(),
        "--traces",
        "specs/pnp.traces",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("all reproduced"),
        "{}",
        text(&o.stdout)
    );
}

/// `export` never writes over the machine it reads, also when the `--ecc` path is a symbolic
/// or a hard link to a file inside the output folder.
#[cfg(unix)]
#[test]
fn export_refuses_an_output_folder_that_holds_its_input_through_a_link() {
    let dir = Dir::new();
    let folder = dir.path().join("ow");
    std::fs::create_dir(&folder).unwrap();
    let input = folder.join("cyl.json");
    std::fs::copy("tests/data/export/cylinder.json", &input).unwrap();
    let before = std::fs::read(&input).unwrap();
    let soft = dir.path().join("soft.json");
    std::os::unix::fs::symlink(&input, &soft).unwrap();
    let hard = dir.path().join("hard.json");
    std::fs::hard_link(&input, &hard).unwrap();
    for link in [&soft, &hard] {
        let o = synth(&[
            "export",
            "--ecc",
            link.to_str().unwrap(),
            "--out",
            folder.to_str().unwrap(),
            "--name",
            "cyl",
        ]);
        // The output rule's refusal: bad input (4), naming both files.
        assert_eq!(
            o.status.code(),
            Some(4),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(String::from_utf8_lossy(&o.stderr).contains("give another output folder"));
        assert_eq!(std::fs::read(&input).unwrap(), before, "{}", link.display());
    }
}

/// Recordings that name one signal both ways, or hold no step, and an output folder that is a
/// file, are refused with the places that say so (found by fuzzing the command line).
#[test]
fn names_clashing_empty_recordings_and_a_file_as_output_folder_are_refused() {
    let dir = Dir::new();
    let d = dir.path();
    std::fs::write(d.join("t.traces"), "1\nin=REQ[10]; out=CNF[1];\n").unwrap();
    std::fs::write(d.join("t.inputs"), "a\nb\n").unwrap();
    std::fs::write(d.join("t.outputs"), "b\n").unwrap();
    let path = |n: &str| d.join(n).to_str().unwrap().to_string();
    let o = synth(&["infer", "--traces", &path("t.traces"), "--out", &path("o")]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    let e = text(&o.stderr);
    assert!(
        e.contains("'b' is named both as an input (")
            && e.contains("t.inputs:2) and as an output (")
            && e.contains("t.outputs:1)"),
        "{e}"
    );
    assert!(!d.join("o").exists());

    std::fs::write(d.join("z.traces"), "0\n").unwrap();
    std::fs::write(d.join("z.inputs"), "a\n").unwrap();
    std::fs::write(d.join("z.outputs"), "b\n").unwrap();
    let o = synth(&["infer", "--traces", &path("z.traces"), "--out", &path("o")]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("z.traces: no recorded step"),
        "{}",
        text(&o.stderr)
    );
    assert!(!d.join("o").exists());

    std::fs::write(d.join("f"), "mine").unwrap();
    let o = synth(&[
        "infer",
        "--traces",
        "specs/tank1.traces",
        "--out",
        &path("f"),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("it is a file, not a folder"),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(std::fs::read_to_string(d.join("f")).unwrap(), "mine");
}
