//! `synth record` and `synth monitor` against a real OPC UA server: Python asyncua
//! (`$ASYNCUA_PYTHON`, from `.ci/install-asyncua.sh`) running `tests/opcua/plc_server.py`, a
//! simulated PLC that replays the distribution station's reference controller in closed loop
//! with its plant. Loopback only, a free port per server; under `CI=true` a missing asyncua
//! fails the test.

use crate::cases::distribution;
use crate::common::{root, stderr, text, Dir, TestCommand};
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

/// Seconds each replayed scan lasts on the simulated PLC: several samples (50 ms apart) per
/// scan, so a busy machine does not miss one.
const SCAN: &str = "0.25";

/// asyncua's python (`$ASYNCUA_PYTHON`), or `None` after a skip note; under `CI=true` a
/// missing one fails (CI installs it).
fn asyncua_or_skip() -> Option<PathBuf> {
    match std::env::var_os("ASYNCUA_PYTHON") {
        Some(p) if Path::new(&p).is_file() => Some(PathBuf::from(p)),
        other => {
            let why = match other {
                Some(p) => format!("ASYNCUA_PYTHON={} is not a file", Path::new(&p).display()),
                None => "ASYNCUA_PYTHON is not set (.ci/install-asyncua.sh prints it)".to_string(),
            };
            if std::env::var("CI").as_deref() == Ok("true") {
                panic!("asyncua is required when CI=true, but {why}");
            }
            eprintln!("skipping OPC UA test: {why}");
            None
        }
    }
}

/// A simulated PLC server, stopped when dropped.
struct Plc {
    child: Child,
    url: String,
}

impl Drop for Plc {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts the simulated PLC replaying `replay` on a free loopback port; `break_after`: the
/// seconds after which its logic breaks.
fn start_plc(python: &Path, replay: &Path, break_after: Option<&str>) -> Plc {
    start_plc_with(python, replay, break_after.map(|s| ["--break-after", s]))
}

/// [`start_plc`] with more arguments for the server.
fn start_plc_with<'a>(
    python: &Path,
    replay: &Path,
    more: impl IntoIterator<Item = [&'a str; 2]>,
) -> Plc {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    start_plc_on(python, replay, port, more)
}

/// [`start_plc_with`] on a given loopback port.
fn start_plc_on<'a>(
    python: &Path,
    replay: &Path,
    port: u16,
    more: impl IntoIterator<Item = [&'a str; 2]>,
) -> Plc {
    let mut cmd = Command::new(python);
    cmd.arg(root().join("tests/opcua/plc_server.py"))
        .args([
            "--port",
            &port.to_string(),
            "--scan",
            SCAN,
            "--lifetime",
            "40",
        ])
        .arg("--replay")
        .arg(replay)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    for pair in more {
        cmd.args(pair);
    }
    let mut child = cmd.spawn().expect("start the OPC UA test server");
    let mut line = String::new();
    let stdout = child.stdout.take().unwrap();
    BufReader::new(stdout).read_line(&mut line).unwrap();
    if line.trim() != "ready" {
        let mut err = String::new();
        let _ = child.kill();
        let _ = child.stderr.take().unwrap().read_to_string(&mut err);
        panic!("the OPC UA test server did not start: {line}{err}");
    }
    Plc {
        child,
        url: format!("opc.tcp://127.0.0.1:{port}/plc"),
    }
}

/// The replayed run: the reference controller on the station through one use case, each
/// scan once (a scan that changes nothing is held by the server's clock instead).
fn write_replay(dir: &Path) -> PathBuf {
    let case = &distribution::use_cases()[0];
    let mut samples = distribution::record(case);
    samples.dedup();
    let path = dir.join("replay.csv");
    let mut bytes = Vec::new();
    distribution::write_csv(&[samples], &mut bytes).unwrap();
    std::fs::write(&path, bytes).unwrap();
    path
}

fn write_map(dir: &Path) -> PathBuf {
    let mut map = String::from("# node id, side, name\n");
    for n in distribution::INPUTS {
        map.push_str(&format!("ns=2;s={n} in {n}\n"));
    }
    for n in distribution::OUTPUTS {
        map.push_str(&format!("ns=2;s={n} out {n}\n"));
    }
    let path = dir.join("plc.map");
    std::fs::write(&path, map).unwrap();
    path
}

fn run(args: &[&str]) -> std::process::Output {
    TestCommand::new().args(args).output()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Record 10 s, infer the machine from the log, monitor 8 s without a divergence, then a PLC
/// whose logic breaks after 3 s: exit 1, the step named, the stretch a recording that
/// `synth conform` finds divergent.
#[test]
fn record_infer_and_monitor_a_live_plc() {
    let Some(python) = asyncua_or_skip() else {
        return;
    };
    let dir = Dir::new();
    let replay = write_replay(dir.path());
    let map = write_map(dir.path());
    let log = dir.path().join("plc.csv");

    // The run's temporary folders: nothing of the connection may stay there.
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let plc = start_plc(&python, &replay, None);
    let o = TestCommand::new()
        .umask(0o022)
        .env("TMPDIR", &tmp)
        .args([
            "record",
            "--opcua",
            &plc.url,
            "--map",
            s(&map),
            "--out",
            s(&log),
            "--duration",
            "10",
        ])
        .output();
    drop(plc);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(text(&o.stdout).contains("recorded"), "{}", text(&o.stdout));
    let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().collect();
    assert!(left.is_empty(), "left in the temporary folder: {left:?}");
    let csv = std::fs::read_to_string(&log).unwrap();
    let mut lines = csv.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("time,scenario,in:"), "{header}");
    let rows: Vec<&str> = lines.collect();
    assert!(rows.len() >= 50, "{} rows", rows.len());
    assert!(
        rows.iter().all(|r| r.split(',').nth(1) == Some("1")),
        "a gap in\n{csv}"
    );
    use std::os::unix::fs::PermissionsExt;
    let mode = std::fs::metadata(&log).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o644);

    let m = dir.path().join("m");
    let o = run(&[
        "infer",
        "-q",
        "--traces",
        s(&log),
        "--no-ambiguity",
        "--out",
        s(&m),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let ecc = m.join("SynthesizedFB.json");

    // Eight seconds of `monitor` beside a PLC of its own (one whose logic breaks after
    // `break_after` seconds), the result in `out`.
    let monitor = |break_after: Option<&str>, out: &Path| {
        let plc = start_plc(&python, &replay, break_after);
        let (url, map, ecc) = (plc.url.as_str(), s(&map), s(&ecc));
        let args = ["monitor", "--opcua", url, "--map", map, "--ecc", ecc];
        run(&[&args[..], &["--duration", "8", "--out", s(out)]].concat())
    };
    let calm = dir.path().join("calm");
    let o = monitor(None, &calm);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}{}",
        text(&o.stdout),
        stderr(&o)
    );
    assert!(
        text(&o.stdout).contains("no divergence"),
        "{}",
        text(&o.stdout)
    );
    assert!(
        stderr(&o).contains("monitoring: "),
        "no live counter: {}",
        stderr(&o)
    );
    assert!(!calm.join("divergences.csv").exists());

    let broken = dir.path().join("broken");
    let o = monitor(Some("3"), &broken);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}{}",
        text(&o.stdout),
        stderr(&o)
    );
    let out = text(&o.stdout);
    let step: u64 = out
        .split("DIVERGENCE at step ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no step in:\n{out}"));
    assert!(step > 1, "{out}");
    assert!(
        out.contains("PLC outputs") && out.contains("machine outputs"),
        "{out}"
    );
    let stretch = broken.join("divergences.csv");
    let o = run(&["conform", "--ecc", s(&ecc), "--traces", s(&stretch)]);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}{}",
        text(&o.stdout),
        stderr(&o)
    );
    assert!(
        text(&o.stdout).contains(&format!("DIVERGES: step {step}:")),
        "conform and monitor disagree on the step ({step}):\n{}",
        text(&o.stdout)
    );
}

/// A server that offers Basic256Sha256 only: refused without `--certs`, then until its
/// certificate is trusted (moved from `rejected/` to `trusted/`), then recorded; SIGINT ends
/// an open-ended recording with exit 130 and a whole log.
#[test]
fn a_secure_server_is_recorded_once_its_certificate_is_trusted() {
    let Some(python) = asyncua_or_skip() else {
        return;
    };
    let dir = Dir::new();
    let replay = write_replay(dir.path());
    let map = write_map(dir.path());
    let server_certs = dir.path().join("server-pki");
    std::fs::create_dir_all(&server_certs).unwrap();
    let plc = start_plc_with(&python, &replay, [["--certs", s(&server_certs)]]);
    let certs = dir.path().join("pki");
    let log = dir.path().join("secure.csv");
    let record = |with_certs: bool| {
        let mut args = vec!["record", "--opcua", &plc.url, "--map", s(&map)];
        args.extend(["--out", s(&log), "--samples", "5"]);
        if with_certs {
            args.extend(["--certs", s(&certs)]);
        }
        run(&args)
    };
    let o = record(false);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(stderr(&o).contains("--certs"), "{}", stderr(&o));
    let o = record(true);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(!log.exists());
    let rejected: Vec<PathBuf> = std::fs::read_dir(certs.join("rejected"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(rejected.len(), 1, "{rejected:?}");
    std::fs::create_dir_all(certs.join("trusted")).unwrap();
    let name = rejected[0].file_name().unwrap();
    std::fs::rename(&rejected[0], certs.join("trusted").join(name)).unwrap();
    let o = record(true);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&log).unwrap().lines().count(), 6);

    let open_ended = dir.path().join("until-sigint.csv");
    let mut child = TestCommand::new()
        .args([
            "record",
            "--opcua",
            &plc.url,
            "--map",
            s(&map),
            "--certs",
            s(&certs),
        ])
        .args(["--out", s(&open_ended)])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn();
    // Rows are written once the session is up: wait for the first progress line.
    let mut progress = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    progress.read_line(&mut line).unwrap();
    assert!(line.starts_with("recording: "), "{line}");
    std::thread::sleep(std::time::Duration::from_millis(500));
    // SAFETY: the pid is our own child's, still running.
    unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) };
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let csv = std::fs::read_to_string(&open_ended).unwrap();
    assert!(csv.ends_with('\n') && csv.lines().count() >= 2, "{csv}");
    let cells = csv.lines().next().unwrap().split(',').count();
    assert!(csv.lines().all(|l| l.split(',').count() == cells), "{csv}");
    drop(plc);
}

/// A PLC that goes away and comes back on the same port: the recording goes on, and the rows
/// after the gap form a second scenario; none is written for the time it was away.
#[test]
fn a_reconnect_starts_a_new_scenario() {
    let Some(python) = asyncua_or_skip() else {
        return;
    };
    let dir = Dir::new();
    let replay = write_replay(dir.path());
    let map = write_map(dir.path());
    let log = dir.path().join("gap.csv");
    let plc = start_plc_with(&python, &replay, []);
    let port: u16 = plc
        .url
        .rsplit(':')
        .next()
        .unwrap()
        .trim_end_matches("/plc")
        .parse()
        .unwrap();
    let url = plc.url.clone();
    let mut child = TestCommand::new()
        .args([
            "record",
            "--opcua",
            &url,
            "--map",
            s(&map),
            "--out",
            s(&log),
        ])
        .args(["--duration", "20"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn();
    let mut progress = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    progress.read_line(&mut line).unwrap();
    assert!(line.starts_with("recording: "), "{line}");
    std::thread::sleep(std::time::Duration::from_secs(1));
    drop(plc);
    std::thread::sleep(std::time::Duration::from_secs(1));
    let plc = start_plc_on(&python, &replay, port, []);
    let mut rest = String::new();
    progress.read_to_string(&mut rest).unwrap();
    let status = child.wait().unwrap();
    drop(plc);
    let mut out = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    assert!(status.success(), "{rest}");
    assert!(out.contains("1 gap (2 scenarios)"), "{out}");
    let csv = std::fs::read_to_string(&log).unwrap();
    let scenarios: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap())
        .collect();
    let first_2 = scenarios
        .iter()
        .position(|c| *c == "2")
        .expect("no second scenario");
    assert!(
        first_2 > 0 && scenarios[first_2..].iter().all(|c| *c == "2"),
        "{csv}"
    );
    // No row stands for the time the PLC was away: the times jump over it.
    let time = |k: usize| -> f64 {
        csv.lines()
            .nth(k + 1)
            .unwrap()
            .split(',')
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    assert!(time(first_2) - time(first_2 - 1) > 0.5, "{csv}");
}
