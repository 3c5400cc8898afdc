//! Inputs without end, through the binary: a line longer than the limit, or a file that never
//! ends (`/dev/zero`), stops a command with exit 1 and the file and line, after reading no more
//! than the limit, and leaves no output; a long log is ingested in memory that does not grow
//! with it.

use crate::common::{stderr, synth_in, Dir, TestCommand};
use fbsynth::files::MAX_LINE_BYTES;
use std::path::Path;
use std::process::Output;

const MAP: &str = "%IX0.1 in ll\n%QX0.0 out inlet\n";

/// A long-format log whose line 3 is one byte over the limit.
fn log_with_a_long_line(dir: &Path) {
    let mut log = b"timestamp,address,value\n0,%IX0.1,1\n".to_vec();
    log.resize(log.len() + MAX_LINE_BYTES + 1, b'0');
    log.extend(b"\n1,%IX0.1,0\n");
    std::fs::write(dir.join("long.csv"), log).unwrap();
}

fn ingest(dir: &Path, log: &str, map: &str) -> Output {
    synth_in(
        dir,
        &["ingest", "--log", log, "--map", map, "-o", "out.traces"],
    )
}

fn events(dir: &Path, log: &str, map: &str) -> Output {
    synth_in(
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
    let dir = Dir::new();
    let dir = dir.path();
    std::fs::write(dir.join("t.map"), MAP).unwrap();
    log_with_a_long_line(dir);
    let want = format!("error: long.csv:3: line 3 is longer than {MAX_LINE_BYTES} bytes");
    for o in [
        ingest(dir, "long.csv", "t.map"),
        events(dir, "long.csv", "t.map"),
    ] {
        assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
        assert_eq!(stderr(&o), want);
    }
    assert_no_output(dir);
}

#[test]
fn an_endless_log_is_refused_at_line_1() {
    let dir = Dir::new();
    let dir = dir.path();
    std::fs::write(dir.join("t.map"), MAP).unwrap();
    let want = format!("error: /dev/zero:1: line 1 is longer than {MAX_LINE_BYTES} bytes");
    for o in [
        ingest(dir, "/dev/zero", "t.map"),
        events(dir, "/dev/zero", "t.map"),
    ] {
        assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
        assert_eq!(stderr(&o), want);
    }
    assert_no_output(dir);
}

#[test]
fn an_endless_mapping_is_refused_at_line_1() {
    let dir = Dir::new();
    let dir = dir.path();
    std::fs::write(dir.join("t.csv"), "timestamp,address,value\n").unwrap();
    let want = format!("error: /dev/zero:1: line 1 is longer than {MAX_LINE_BYTES} bytes");
    for o in [
        ingest(dir, "t.csv", "/dev/zero"),
        events(dir, "t.csv", "/dev/zero"),
    ] {
        assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
        assert_eq!(stderr(&o), want);
    }
    assert_no_output(dir);
}

/// The shipped door scenarios, their names files and the lamp's LTL and plant, copied into
/// `dir`, and `zero.*` links to `/dev/zero` for every kind of file.
fn inputs_and_endless_ones(dir: &Path) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (from, to) in [
        ("tests/data/scenarios/door.traces", "door.traces"),
        ("tests/data/scenarios/door.inputs", "door.inputs"),
        ("tests/data/scenarios/door.outputs", "door.outputs"),
        ("tests/data/closed_loop/lamp.ltl", "lamp.ltl"),
        ("tests/data/closed_loop/lamp_plant.smv", "lamp.smv"),
    ] {
        std::fs::copy(root.join(from), dir.join(to)).unwrap();
    }
    for name in ["zero.csv", "zero.names", "zero.ltl", "zero.smv"] {
        std::os::unix::fs::symlink("/dev/zero", dir.join(name)).unwrap();
    }
}

#[test]
fn endless_traces_names_ltl_and_plant_files_are_refused_at_line_1() {
    let dir = Dir::new();
    let dir = dir.path();
    inputs_and_endless_ones(dir);
    let infer = |extra: &[&str]| {
        let mut args = vec!["infer", "--out", "out"];
        args.extend(extra);
        synth_in(dir, &args)
    };
    let names = [
        "--input-names",
        "door.inputs",
        "--output-names",
        "door.outputs",
    ];
    // The main job reads the specification and the plant.
    let main_job = |ltl: &str, plant: &str| {
        let args = ["--ltl", ltl, "--plant", plant, "--traces", "door.traces"];
        synth_in(dir, &[&args[..], &["--out", "out"]].concat())
    };
    let cases = [
        (
            infer(&[&["--traces", "zero.csv"][..], &names].concat()),
            "zero.csv",
        ),
        (
            infer(&["--traces", "door.traces", "--input-names", "zero.names"]),
            "zero.names",
        ),
        (main_job("zero.ltl", "lamp.smv"), "zero.ltl"),
        (main_job("lamp.ltl", "zero.smv"), "zero.smv"),
    ];
    for (o, file) in cases {
        assert_eq!(o.status.code(), Some(4), "{file}: {}", stderr(&o));
        // The main job reports its progress first.
        assert_eq!(
            stderr(&o).lines().last().unwrap(),
            format!("error: {file}:1: line 1 is longer than {MAX_LINE_BYTES} bytes")
        );
    }
    assert!(!dir.join("out").exists());
}

#[test]
fn files_read_whole_are_refused_beyond_1_gib_before_reading() {
    let dir = Dir::new();
    let dir = dir.path();
    inputs_and_endless_ones(dir);
    // Sparse: nothing of it is on disk, and the size alone is refused.
    let big = |name: &str| {
        let f = std::fs::File::create(dir.join(name)).unwrap();
        f.set_len(fbsynth::files::MAX_FILE_BYTES + 1).unwrap();
    };
    big("big.traces");
    big("big.json");
    let cases = [
        (
            synth_in(
                dir,
                &[
                    "infer",
                    "--traces",
                    "big.traces",
                    "--input-names",
                    "door.inputs",
                    "--output-names",
                    "door.outputs",
                    "--out",
                    "out",
                ],
            ),
            "big.traces",
        ),
        (
            synth_in(
                dir,
                &["replay", "--ecc", "big.json", "--traces", "door.traces"],
            ),
            "big.json",
        ),
    ];
    for (o, file) in cases {
        assert_eq!(o.status.code(), Some(4), "{file}: {}", stderr(&o));
        assert_eq!(
            stderr(&o),
            format!(
                "error: {file}: larger than 1073741824 bytes (1 GiB), the most read from one file"
            )
        );
    }
}

#[test]
fn ingest_of_a_million_rows_fits_in_64_mb_of_address_space() {
    let dir = Dir::new();
    let dir = dir.path();
    let mut log = std::io::BufWriter::new(std::fs::File::create(dir.join("big.csv")).unwrap());
    let map = fbsynth::ingest::write_random_log(&mut log, 8, 8, 1_000_000, 1).unwrap();
    drop(log);
    std::fs::write(dir.join("big.map"), map).unwrap();
    // The ingested scenario alone would take about 40 MB if it were held in memory; streamed,
    // the run needs about 12 MB (debug build, most of it the mapped binary).
    let o = TestCommand::new()
        .address_space(65536 * 1024)
        .args([
            "ingest",
            "--log",
            "big.csv",
            "--map",
            "big.map",
            "-o",
            "big.traces",
        ])
        .current_dir(dir)
        .output();
    assert!(o.status.success(), "{:?}: {}", o.status, stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    let steps: usize = stdout
        .lines()
        .find_map(|l| l.strip_prefix("steps:"))
        .and_then(|l| l.split_whitespace().next()?.parse().ok())
        .unwrap_or_else(|| panic!("no step count in {stdout}"));
    let scenario = std::fs::read_to_string(dir.join("big.traces")).unwrap();
    assert!(scenario.starts_with("1\nin=REQ["), "{}", &scenario[..40]);
    assert_eq!(scenario.matches("in=REQ[").count(), steps);
}
