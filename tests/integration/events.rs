//! `synth events` through the binary: outputs, default CSV path, errors with their place and
//! exit code 1, and no output left behind by a failed run.

use crate::common::{synth_in, text, Dir, TestCommand};
use std::path::Path;
use std::process::Stdio;

const MAP: &str = "%IX0.1 in ll\n%QX0.0 out inlet\n";

#[test]
fn writes_xes_and_csv_beside_it_and_counts() {
    let dir = Dir::new();
    std::fs::write(dir.path().join("t.map"), MAP).unwrap();
    std::fs::write(
        dir.path().join("t.csv"),
        "timestamp,address,value\n0,%QX0.0,1\n1,%IX0.1,1\n2,%IX0.1,0\n2,%QX0.0,0\n",
    )
    .unwrap();
    let o = synth_in(
        dir.path(),
        &[
            "events", "--log", "t.csv", "--map", "t.map", "--reset", "ll false", "--out", "o/t.xes",
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("4 events in 2 traces (1 of them the reset '%IX0.1 false')"),
        "{}",
        text(&o.stdout)
    );
    assert!(dir.path().join("o/t.xes").is_file());
    let csv = std::fs::read_to_string(dir.path().join("o/t.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5);
    assert!(csv.contains("\n2,%IX0.1 false,"));
}

#[test]
fn errors_name_their_place_and_leave_no_output() {
    let dir = Dir::new();
    std::fs::write(dir.path().join("t.map"), MAP).unwrap();
    std::fs::write(
        dir.path().join("bad.csv"),
        "timestamp,address,value\n0,%QX0.0,1\n1,%IX0.1,maybe\n",
    )
    .unwrap();
    let run = |log: &str, reset: &str| {
        synth_in(
            dir.path(),
            &[
                "events", "--log", log, "--map", "t.map", "--reset", reset, "--out", "t.xes",
            ],
        )
    };
    let o = run("bad.csv", "%IX0.1 false");
    assert_eq!(o.status.code(), Some(4));
    assert_eq!(
        text(&o.stderr).trim(),
        "error: bad.csv:3: column 'value': cannot read 'maybe'\n(--lenient skips bad rows and counts them instead)"
    );
    let o = run("bad.csv", "%IX0.9 false");
    assert_eq!(o.status.code(), Some(4));
    assert_eq!(
        text(&o.stderr).trim(),
        "error: reset activity '%IX0.9 false': '%IX0.9' is not an address or name of the mapping"
    );
    assert!(!dir.path().join("t.xes").exists() && !dir.path().join("t.csv").exists());
    // The default CSV path beside `--out bad.xes` is the input log itself: refused.
    let o = synth_in(
        dir.path(),
        &[
            "events",
            "--log",
            "./bad.csv",
            "--map",
            "t.map",
            "--reset",
            "ll 0",
            "--out",
            "bad.xes",
        ],
    );
    assert_eq!(o.status.code(), Some(4));
    assert_eq!(
        text(&o.stderr).trim(),
        "error: the output bad.csv would overwrite the input log; give --out/--csv other paths"
    );
    assert!(std::fs::read_to_string(dir.path().join("bad.csv"))
        .unwrap()
        .contains("maybe"));
}

/// A Petri net that cannot be written (here: the machine names a signal the mapping lacks) is
/// found out before anything is written: no event log is left behind without its net.
#[test]
fn a_net_that_fails_leaves_no_event_logs() {
    let dir = Dir::new();
    std::fs::write(dir.path().join("t.map"), MAP).unwrap();
    std::fs::write(
        dir.path().join("t.csv"),
        "timestamp,address,value\n0,%QX0.0,1\n1,%IX0.1,1\n",
    )
    .unwrap();
    let ecc = r#"{"inputs":["ll","xx"],"outputs":["inlet"],"initial_outputs":"0",
        "states":[{"name":"s0","algorithm":"x"}],"transitions":[]}"#;
    std::fs::write(dir.path().join("m.json"), ecc).unwrap();
    let o = synth_in(
        dir.path(),
        &[
            "events", "--log", "t.csv", "--map", "t.map", "--reset", "ll false", "--out", "o.xes",
            "--ecc", "m.json", "--pnml", "o.pnml",
        ],
    );
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("'xx' is not in the mapping"),
        "{}",
        text(&o.stderr)
    );
    for f in ["o.xes", "o.csv", "o.pnml"] {
        assert!(!dir.path().join(f).exists(), "{f} was written");
    }
}

#[test]
fn a_timestamp_out_of_range_is_refused_not_clamped() {
    let dir = Dir::new();
    std::fs::write(dir.path().join("t.map"), MAP).unwrap();
    std::fs::write(
        dir.path().join("far.csv"),
        "timestamp,address,value\n0,%QX0.0,1\n1e20,%IX0.1,1\n",
    )
    .unwrap();
    let o = synth_in(
        dir.path(),
        &[
            "events", "--log", "far.csv", "--map", "t.map", "--reset", "ll false", "--out", "t.xes",
        ],
    );
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stdout));
    assert!(
        text(&o.stderr).starts_with("error: far.csv:3: column 'timestamp': '1e20' is out of range"),
        "{}",
        text(&o.stderr)
    );
    assert!(!dir.path().join("t.xes").exists());
}

/// A run stopped by a signal while it streams leaves no hidden temporary file beside its
/// outputs. The log is a FIFO that this test keeps open, so the run is
/// surely mid-stream when the signal comes.
#[test]
fn a_signal_mid_stream_leaves_no_temporary_file() {
    use std::io::Write;
    let dir = Dir::new();
    std::fs::write(dir.path().join("t.map"), MAP).unwrap();
    let fifo = dir.path().join("log.csv");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: mkfifo reads the NUL-terminated path only.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let out = dir.path().join("o");
    std::fs::create_dir(&out).unwrap();
    let mut child = TestCommand::new()
        .args([
            "events", "--log", "log.csv", "--map", "t.map", "--reset", "ll false", "--out",
            "o/t.xes",
        ])
        .current_dir(dir.path())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn();
    let mut log = std::fs::OpenOptions::new().write(true).open(&fifo).unwrap();
    writeln!(log, "timestamp,address,value").unwrap();
    for t in 0..1000 {
        writeln!(log, "{t},%IX0.1,{}", t % 2).unwrap();
    }
    log.flush().unwrap();
    let temporaries = || -> Vec<String> {
        std::fs::read_dir(&out)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect()
    };
    let started = (0..100).any(|_| {
        std::thread::sleep(std::time::Duration::from_millis(50));
        !temporaries().is_empty()
    });
    // SAFETY: a signal to the child this test started and has not reaped.
    unsafe { libc::kill(child.id() as i32, libc::SIGTERM) };
    let status = child.wait().unwrap();
    drop(log);
    assert!(started, "no temporary output appeared");
    assert_eq!(status.code(), Some(130), "{status:?}");
    assert_eq!(temporaries(), Vec::<String>::new());
}

/// The XES `synth events` writes validates against the IEEE 1849 serialization
/// (tests/schemas/xes.xsd) with a real validator, and the schema refuses what strict tools
/// refuse: a version that is no decimal, a classifier name with a space.
#[test]
fn the_xes_validates_against_the_ieee_1849_schema() {
    let Some(xmllint_bin) =
        crate::common::tool_or_skip("XMLLINT", "xmllint", ".ci/install-xmllint.sh")
    else {
        return;
    };
    let dir = Dir::new();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let o = synth_in(
        dir.path(),
        &[
            "events",
            "--log",
            root.join("specs/tank/scenario1.csv").to_str().unwrap(),
            "--map",
            root.join("specs/tank/tank.map").to_str().unwrap(),
            "--reset",
            "ll false",
            "--out",
            "t.xes",
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let xes = dir.path().join("t.xes");
    let (ok, messages) = crate::common::xmllint(&xmllint_bin, "xes.xsd", &xes);
    assert!(ok, "{messages}");
    let text_of = std::fs::read_to_string(&xes).unwrap();
    for (what, from, to) in [
        (
            "version",
            "xes.version=\"1849.2016\"",
            "xes.version=\"1849-2016\"",
        ),
        (
            "classifier",
            "name=\"Activity_and_class\"",
            "name=\"Activity and class\"",
        ),
    ] {
        assert!(text_of.contains(from), "{what}");
        let bad = dir.path().join(format!("bad_{what}.xes"));
        std::fs::write(&bad, text_of.replace(from, to)).unwrap();
        let (ok, messages) = crate::common::xmllint(&xmllint_bin, "xes.xsd", &bad);
        assert!(!ok, "the schema takes a bad {what}");
        assert!(messages.contains("not a valid value"), "{messages}");
    }
}

/// The summary line of `--pnml` gives the net's places and transitions, counted in the file
/// written: for the tank machines (2 and more states) many more than the machine's states.
#[test]
fn the_net_summary_counts_the_nets_places_and_transitions() {
    let dir = Dir::new();
    let programs = [
        crate::cases::tank::Program::FillDrain,
        crate::cases::tank::Program::Cycles,
    ];
    for (k, program) in programs.into_iter().enumerate() {
        let ecc = program.reference();
        let json = dir.path().join(format!("M{k}.json"));
        std::fs::write(&json, fbsynth::export::json::to_string(&ecc)).unwrap();
        let pnml = dir.path().join(format!("M{k}.pnml"));
        let o = synth_in(
            crate::common::root(),
            &[
                "events",
                "--log",
                "specs/tank/scenario1.csv",
                "--map",
                "specs/tank/tank.map",
                "--reset",
                crate::cases::tank::RESET,
                "--out",
                dir.path().join(format!("M{k}.xes")).to_str().unwrap(),
                "--ecc",
                json.to_str().unwrap(),
                "--pnml",
                pnml.to_str().unwrap(),
            ],
        );
        assert!(o.status.success(), "{}", text(&o.stderr));
        let net = std::fs::read_to_string(&pnml).unwrap();
        let places = net.matches("<place id=").count();
        let transitions = net.matches("<transition id=").count();
        assert!(places > ecc.states.len(), "{places} places");
        let line = format!(
            "(Petri net of {}: {places} places, {transitions} transitions)",
            json.display()
        );
        let stdout = text(&o.stdout);
        assert!(stdout.contains(&line), "{line} in {stdout}");
    }
}
