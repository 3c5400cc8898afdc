//! Verification in the loop through the `synth` binary, with real NuSMV: the main job, `synth
//! verify`, and every kind of bad input with its place. Needs NuSMV: skipped with a note where
//! it is not installed, and failing under CI=true.

use crate::common::{nusmv_or_skip, text, Dir, TestCommand};
use std::path::Path;
use std::process::{Output, Stdio};

/// `synth` with `args`, checking with the NuSMV at `nusmv`.
fn with_nusmv(nusmv: &Path, args: &[&str]) -> Output {
    TestCommand::new().args(args).nusmv(nusmv).output()
}

const DIR: &str = "tests/data/closed_loop";

fn main_job(nusmv: &Path, ltl: &str, plant: &str, out: &Path, extra: &[&str]) -> Output {
    let ltl = format!("{DIR}/{ltl}");
    let plant = format!("{DIR}/{plant}");
    let mut args = vec![
        "-q",
        "--ltl",
        &ltl,
        "--plant",
        &plant,
        "--traces",
        "tests/data/closed_loop/lamp.traces",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    with_nusmv(nusmv, &args)
}

/// `synth verify` of a machine against the lamp's properties and plant.
fn verify_lamp(nusmv: &Path, json: &Path) -> Output {
    verify_lamp_with(nusmv, json, "lamp_plant.smv")
}

/// `synth verify` of a machine against the lamp's properties and the plant `plant`.
fn verify_lamp_with(nusmv: &Path, json: &Path, plant: &str) -> Output {
    let plant = format!("{DIR}/{plant}");
    with_nusmv(
        nusmv,
        &[
            "verify",
            "--ecc",
            json.to_str().unwrap(),
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            &plant,
        ],
    )
}

#[test]
fn main_job_verifies_and_verify_agrees() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let o = main_job(&n.path, "lamp.ltl", "lamp_plant.smv", out.path(), &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("verified: all 2 properties hold"));
    let report = std::fs::read_to_string(out.path().join("verification.txt")).unwrap();
    assert!(
        report.contains("HOLDS    goes_out") && report.contains("is true"),
        "{report}"
    );
    let json = out.path().join("SynthesizedFB.json");
    let v = verify_lamp(&n.path, &json);
    assert!(v.status.success(), "{}", text(&v.stderr));
    assert!(text(&v.stdout).contains("verified: all 2 properties hold"));
}

#[test]
fn the_main_job_avoids_a_negative_scenario_and_nusmv_verifies_the_result() {
    let Some(n) = nusmv_or_skip() else { return };
    let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let negs = fbsynth::scenario::negative::read(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(DIR)
            .join("lamp_negative.traces"),
        &names(&["button", "timeout"]),
        &names(&["lamp"]),
        &[false],
    )
    .unwrap();
    let machine = |dir: &Path| {
        let file = dir.join("SynthesizedFB.json");
        let json = std::fs::read_to_string(&file).unwrap();
        fbsynth::export::json::read_json(&json, &file).unwrap()
    };
    let plain = Dir::new();
    let o = main_job(&n.path, "lamp.ltl", "lamp_plant.smv", plain.path(), &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    // Button and timer together from the start light the lamp in the least machine.
    assert!(negs[0].followed_by(&machine(plain.path())));

    let out = Dir::new();
    let negative = format!("{DIR}/lamp_negative.traces");
    let o = main_job(
        &n.path,
        "lamp.ltl",
        "lamp_plant.smv",
        out.path(),
        &["--negative", &negative],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("verified: all 2 properties hold"));
    assert!(!negs[0].followed_by(&machine(out.path())));
    let v = verify_lamp(&n.path, &out.path().join("SynthesizedFB.json"));
    assert!(v.status.success(), "{}", text(&v.stderr));
}

#[test]
fn scenarios_alone_do_not_make_the_lamp_go_out() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let o = TestCommand::new()
        .args([
            "infer",
            "-q",
            "--traces",
            "tests/data/closed_loop/lamp.traces",
            "--out",
        ])
        .arg(out.path())
        .output();
    assert!(o.status.success(), "{}", text(&o.stderr));
    let json = out.path().join("SynthesizedFB.json");
    let v = verify_lamp(&n.path, &json);
    assert_eq!(v.status.code(), Some(1));
    assert!(
        text(&v.stdout).contains("VIOLATED goes_out"),
        "{}",
        text(&v.stdout)
    );
    assert!(text(&v.stderr).contains("not verified: goes_out violated"));
    // Why it fails, shown: a table on stdout and, with --out, a waveform as VCD and SVG.
    let cx = out.path().join("cx");
    let v = with_nusmv(
        &n.path,
        &[
            "verify",
            "--ecc",
            json.to_str().unwrap(),
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            "tests/data/closed_loop/lamp_plant.smv",
            "--out",
            cx.to_str().unwrap(),
        ],
    );
    assert_eq!(v.status.code(), Some(1), "{}", text(&v.stderr));
    let stdout = text(&v.stdout);
    assert!(stdout.contains("counterexample of goes_out ("), "{stdout}");
    for f in ["closed_loop.smv", "goes_out.vcd", "goes_out.svg"] {
        assert!(cx.join(f).is_file(), "{f} missing; {stdout}");
    }
    // The table's lamp row, and the loop marks under the step numbers.
    let row = |name: &str| -> Vec<String> {
        let line = stdout
            .lines()
            .find(|l| l.split_whitespace().take(2).eq(name.split(' ')))
            .unwrap_or_else(|| panic!("no row {name} in {stdout}"));
        line.split_whitespace().skip(2).map(String::from).collect()
    };
    let lamp_row = row("out lamp");
    let loop_start = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("loop"))
        .map(|l| lamp_row.len() - l.matches('^').count())
        .unwrap();
    let vcd_lamp = vcd_values(&cx.join("goes_out.vcd"), &["closed_loop", "out", "lamp"]);
    // The VCD holds the lasso and its loop once more.
    assert_eq!(
        vcd_lamp.len(),
        2 * lamp_row.len() - loop_start,
        "{vcd_lamp:?}"
    );
    assert_eq!(vcd_lamp[..lamp_row.len()], lamp_row[..], "{stdout}");
    // A run that violates `G (lamp -> F !lamp)` keeps the lamp on for ever: all through the loop.
    assert!(
        vcd_lamp[loop_start..].iter().all(|v| v == "1"),
        "{vcd_lamp:?}"
    );
    let svg = std::fs::read_to_string(cx.join("goes_out.svg")).unwrap();
    let mut reader = quick_xml::Reader::from_str(&svg);
    let mut elements = 0;
    loop {
        match reader.read_event() {
            Ok(quick_xml::events::Event::Eof) => break,
            Ok(quick_xml::events::Event::Start(_) | quick_xml::events::Event::Empty(_)) => {
                elements += 1
            }
            Ok(_) => {}
            Err(e) => panic!("goes_out.svg is not XML: {e}"),
        }
    }
    assert!(elements > 10 && svg.contains(">out lamp</text>"), "{svg}");
}

/// The values (`0`, `1`, or a number) of the VCD variable at `path` at every time step from 0
/// to the last timestamp, read with the `vcd` crate.
fn vcd_values(file: &Path, path: &[&str]) -> Vec<String> {
    let text = std::fs::read(file).unwrap();
    let mut parser = vcd::Parser::new(&text[..]);
    let header = parser.parse_header().unwrap();
    let code = header.find_var(path).expect("variable in the VCD").code;
    let (mut values, mut now, mut value) = (Vec::new(), 0u64, String::from("x"));
    for command in parser {
        match command.unwrap() {
            vcd::Command::Timestamp(t) => {
                while now < t {
                    values.push(value.clone());
                    now += 1;
                }
            }
            vcd::Command::ChangeScalar(c, v) if c == code => value = v.to_string(),
            vcd::Command::ChangeVector(c, v) if c == code => value = v.to_string(),
            _ => {}
        }
    }
    values
}

/// (plant, spec, expected start of the error message)
const BAD: &[(&str, &str, &str)] = &[
    // Refused before NuSMV runs: each would give a verdict or message about synth's own
    // model rather than the user's file.
    (
        "ecc_module_plant.smv",
        "lamp.ltl",
        "error: tests/data/closed_loop/ecc_module_plant.smv:16: the plant file must not define MODULE ECC",
    ),
    (
        "spec_plant.smv",
        "lamp.ltl",
        "error: tests/data/closed_loop/spec_plant.smv:16: the plant file must not hold a specification (LTLSPEC)",
    ),
    (
        "process_plant.smv",
        "lamp.ltl",
        "error: tests/data/closed_loop/process_plant.smv:7: the plant must not instantiate a process",
    ),
    (
        "broken_plant.smv",
        "lamp.ltl",
        "error: NuSMV rejected the closed-loop model:\n  tests/data/closed_loop/broken_plant.smv:10: at token \"DEFINE\": syntax error",
    ),
    (
        "open_case_plant.smv",
        "lamp.ltl",
        "error: NuSMV rejected the closed-loop model:\n  tests/data/closed_loop/open_case_plant.smv:13: at token \"MODULE\": syntax error after the end of the plant: something is left open",
    ),
    (
        "typo_plant.smv",
        "lamp.ltl",
        "error: NuSMV rejected the closed-loop model:\n  tests/data/closed_loop/typo_plant.smv:8: \"plant.one\" undefined",
    ),
    (
        "wrong_param_plant.smv",
        "lamp.ltl",
        "error: tests/data/closed_loop/wrong_param_plant.smv:2: plant parameter 'light' is not a controller output",
    ),
    (
        "lamp_plant.smv",
        "unknown_name.ltl",
        "error: tests/data/closed_loop/unknown_name.ltl:3: unknown name 'dark'",
    ),
    (
        "lamp_plant.smv",
        "syntax.ltl",
        "error: tests/data/closed_loop/syntax.ltl:2:21: syntax error: expected formula after '&'",
    ),
];

#[test]
fn bad_plants_and_specs_are_reported_with_file_and_line() {
    let Some(n) = nusmv_or_skip() else { return };
    for (plant, spec, want) in BAD {
        let out = Dir::new();
        let dir = out.path().join("res");
        let o = main_job(&n.path, spec, plant, &dir, &[]);
        assert_eq!(
            o.status.code(),
            Some(4),
            "{plant} {spec}: {}",
            text(&o.stderr)
        );
        let e = text(&o.stderr);
        assert!(e.starts_with(want), "{plant} {spec}:\n{e}");
        assert!(!dir.join("SynthesizedFB.json").exists());
    }
}

/// On this plant the lamp's timer may never fire, so `goes_out` cannot hold: the first
/// counterexample rules out every machine, and the error says so instead of asking for more
/// states. Nothing is written.
#[test]
fn properties_no_machine_can_satisfy_are_named() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let dir = out.path().join("res");
    let o = main_job(&n.path, "lamp.ltl", "slow_plant.smv", &dir, &[]);
    assert_eq!(o.status.code(), Some(3), "{}", text(&o.stderr));
    let e = text(&o.stderr);
    assert!(
        e.contains("avoids every counterexample found so far")
            && e.contains("the last candidate failed goes_out"),
        "{e}"
    );
    assert!(!dir.exists());
}

/// On a timeout NuSMV is killed with everything it started: a wrapper script's own child
/// (here a `sleep` standing for the real NuSMV) does not outlive synth.
#[test]
fn a_timeout_kills_what_nusmv_started_too() {
    use std::os::unix::fs::PermissionsExt;
    let dir = Dir::new();
    let fake = dir.path().join("NuSMV");
    let pid_file = dir.path().join("child.pid");
    std::fs::write(
        &fake,
        "#!/bin/sh\nsleep 1000 &\necho $! > \"$CHILD_PID_FILE\"\nwait\n",
    )
    .unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    let o = TestCommand::new()
        .args([
            "-q",
            "--ltl",
            &format!("{DIR}/lamp.ltl"),
            "--plant",
            &format!("{DIR}/lamp_plant.smv"),
            "--traces",
            &format!("{DIR}/lamp.traces"),
            "--out",
            dir.path().join("out").to_str().unwrap(),
            "--timeout",
            "1",
            "--nusmv",
            fake.to_str().unwrap(),
        ])
        .env("CHILD_PID_FILE", &pid_file)
        .output();
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("within 1 s and was killed"),
        "{}",
        text(&o.stderr)
    );
    let pid: i32 = std::fs::read_to_string(&pid_file)
        .unwrap()
        .trim()
        .parse()
        .unwrap();
    // The killed sleep is reparented and reaped by init: give that a moment.
    let gone = (0..50).any(|_| {
        std::thread::sleep(std::time::Duration::from_millis(100));
        // SAFETY: signal 0 only asks whether the process exists.
        unsafe { libc::kill(pid, 0) != 0 }
    });
    if !gone {
        // SAFETY: cleaning up after a failed test.
        unsafe { libc::kill(pid, libc::SIGKILL) };
    }
    assert!(gone, "NuSMV's child {pid} outlived synth");
}

/// A warning NuSMV prints while it checks a model is shown with the verdicts, on stdout and
/// in verification.txt, not dropped: here a wrapper around the real NuSMV
/// warns for every model it reads.
#[test]
fn nusmv_warnings_are_shown_with_the_verdicts() {
    use std::os::unix::fs::PermissionsExt;
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let wrapper = dir.path().join("NuSMV");
    std::fs::write(
        &wrapper,
        format!(
            "#!/bin/sh\nwhile IFS= read -r line; do\n  printf '%s\\n' \"$line\"\n  case \"$line\" in read_model*) echo '*** WARNING: made up' >&2;; esac\ndone | exec '{}' \"$@\"\n",
            n.path.display()
        ),
    )
    .unwrap();
    std::fs::set_permissions(&wrapper, std::fs::Permissions::from_mode(0o755)).unwrap();
    let out = dir.path().join("out");
    let o = main_job(&wrapper, "lamp.ltl", "lamp_plant.smv", &out, &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let shown = "NuSMV WARNING (read it: it may change a verdict): *** WARNING: made up";
    assert!(text(&o.stdout).contains(shown), "{}", text(&o.stdout));
    let report = std::fs::read_to_string(out.join("verification.txt")).unwrap();
    assert!(report.contains(shown), "{report}");
}

#[test]
fn nusmv_timeout_is_one_clear_error() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let o = main_job(
        &n.path,
        "lamp.ltl",
        "slow_frozen_plant.smv",
        out.path(),
        &["--timeout", "1"],
    );
    assert_eq!(o.status.code(), Some(4));
    assert_eq!(
        text(&o.stderr).trim(),
        "error: NuSMV did not finish checking the closed loop with plant tests/data/closed_loop/slow_frozen_plant.smv within 1 s and was killed; raise --timeout SECONDS or make the plant model smaller"
    );
}

#[test]
fn missing_nusmv_says_how_to_install() {
    let o = with_nusmv(
        Path::new("/no/such/NuSMV"),
        &[
            "-q",
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            "tests/data/closed_loop/lamp_plant.smv",
        ],
    );
    assert_eq!(o.status.code(), Some(4));
    assert_eq!(
        text(&o.stderr).trim(),
        "error: NuSMV binary `/no/such/NuSMV` (from --nusmv or NUSMV) does not exist"
    );
}

/// The headline: the shipped Pick-and-Place scenarios, properties and surrogate plant give a
/// controller that NuSMV verifies and that replays every scenario, proven least in C, T and N
/// by default (no proof budget asked for): the summary says so, beside the size.
#[test]
fn pick_and_place_main_job_is_verified() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let o = with_nusmv(
        &n.path,
        &[
            "-q",
            "--ltl",
            "specs/pnp.ltl",
            "--plant",
            "smv/pnp_surrogate.smv",
            "--out",
            out.path().to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout)
        .contains("verified: all 8 properties hold (NuSMV), 10 scenarios reproduced"));
    let json = std::fs::read_to_string(out.path().join("SynthesizedFB.json")).unwrap();
    let ecc = fbsynth::export::json::read_json(&json, Path::new("SynthesizedFB.json")).unwrap();
    let set = crate::cases::pnp::generate();
    set.check(&ecc).unwrap();
    let summary = std::fs::read_to_string(out.path().join("summary.json")).unwrap();
    let summary: serde_json::Value = serde_json::from_str(&summary).unwrap();
    assert_eq!(summary["transitions_proven_minimal"], true, "{summary}");
    assert_eq!(summary["guards_proven_minimal"], true, "{summary}");
    let size = &summary["size"];
    let ctn = [&size["c"], &size["t"], &size["n"]].map(|v| v.as_u64());
    assert_eq!(ctn, [Some(8), Some(13), Some(18)], "{summary}");
}

/// A plant whose constraints no run satisfies makes every property hold vacuously: synth
/// must refuse to call anything verified, whether the constraint empties the initial states
/// (INIT), all states (INVAR; NuSMV warns for both), the transitions (TRANS) or only the fair
/// paths (FAIRNESS; NuSMV says nothing). The main job and `synth verify` both say so and exit
/// 1: the check came out negative.
#[test]
fn a_plant_without_runs_is_an_error_not_a_verification() {
    let Some(n) = nusmv_or_skip() else { return };
    const PLANTS: [&str; 4] = [
        "vacuous_init_plant.smv",
        "vacuous_invar_plant.smv",
        "vacuous_trans_plant.smv",
        "vacuous_fairness_plant.smv",
    ];
    // NuSMV's verdict names the plant; the search's in-process checker meets the empty closed
    // loop first and says so in its words.
    let no_behaviour = |plant: &str, o: &Output| {
        assert_eq!(o.status.code(), Some(1), "{plant}: {}", text(&o.stdout));
        let err = text(&o.stderr);
        assert!(
            (err.contains(&format!("plant {DIR}/{plant} has no"))
                && err.contains("the plant allows no behaviour")
                || err.contains("the in-process checker: the closed loop has no"))
                && err.contains("vacuously"),
            "{plant}: {err}"
        );
        assert!(!text(&o.stdout).contains("verified"), "{plant}");
    };
    for plant in PLANTS {
        let out = Dir::new();
        for method in ["sat", "search"] {
            let o = main_job(
                &n.path,
                "lamp.ltl",
                plant,
                out.path(),
                &["--method", method],
            );
            no_behaviour(plant, &o);
            assert!(!out.path().join("SynthesizedFB.json").exists());
        }
    }
    // `synth verify` of a machine that holds with the real plant.
    let out = Dir::new();
    let o = main_job(&n.path, "lamp.ltl", "lamp_plant.smv", out.path(), &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let json = out.path().join("SynthesizedFB.json");
    for plant in PLANTS {
        no_behaviour(plant, &verify_lamp_with(&n.path, &json, plant));
    }
}

/// `--time-limit` ends the exact loop wherever it is (exit 3), says what was found by then,
/// and writes nothing.
#[test]
fn the_time_limit_ends_the_main_job_with_what_was_found() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let o = main_job(
        &n.path,
        "lamp.ltl",
        "lamp_plant.smv",
        out.path(),
        &["--time-limit", "0.001"],
    );
    assert_eq!(o.status.code(), Some(3), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("time limit of 0.001 s reached before a verified machine (raise --time-limit SECONDS): no candidate yet"),
        "{err}"
    );
    assert!(!out.path().join("SynthesizedFB.json").exists());
}

/// The main job on Pick-and-Place's first scenario alone, into `out`.
fn pnp_first1(nusmv: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "--ltl",
        "specs/pnp.ltl",
        "--plant",
        "smv/pnp_surrogate.smv",
        "--traces",
        "specs/pnp_first/first1.traces",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    with_nusmv(nusmv, &args)
}

/// Recordings that never show an input value the properties read (Pick-and-Place's first
/// scenario: no piece on track 2 or 3) are named before the synthesis and again when it gives
/// up.
#[test]
fn inputs_the_recordings_never_vary_are_named_when_the_time_runs_out() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let dir = out.path().join("r");
    let o = pnp_first1(&n.path, &dir, &["--time-limit", "0.5"]);
    assert_eq!(o.status.code(), Some(3), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    let named = "the recordings never show pp2 = TRUE (read by track2_served), pp3 = TRUE (read by track3_served)";
    assert_eq!(err.matches(named).count(), 2, "{err}");
    assert!(
        err.contains("time limit of 0.5 s reached before a verified machine (raise --time-limit SECONDS): the closed-loop game's guide had not ended"),
        "{err}"
    );
    assert!(!dir.exists());
}

/// Pick-and-Place from its first scenario alone: tracks 2 and 3 never carry a piece there, so
/// the properties alone say what to do with one. The closed-loop game guides SAT, and NuSMV
/// verifies the machine.
#[test]
fn the_game_guides_the_synthesis_where_nothing_was_recorded() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let dir = out.path().join("r");
    let o = pnp_first1(&n.path, &dir, &["--json"]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(err.contains("guide: the closed-loop game is won"), "{err}");
    assert!(
        err.contains("guide: NuSMV: every property holds on the least machine"),
        "{err}"
    );
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["method"], "game guide");
    assert_eq!(summary["least_for_recordings_and_runs"], true);
    // The exact loop had its turn below the guide's machine and found none smaller.
    assert!(
        summary["exact_loop_below_it"]
            .as_str()
            .unwrap()
            .starts_with("no smaller verified machine within"),
        "{summary}"
    );
    // 8 states (the recordings alone need 6; the tracks they never show need 2 more), and the
    // bound the recordings prove is said.
    assert_eq!(summary["size"]["c"], 8, "{summary}");
    assert_eq!(summary["states_at_least"], 6, "{summary}");
    let report = std::fs::read_to_string(dir.join("verification.txt")).unwrap();
    assert_eq!(report.matches("\nHOLDS ").count(), 8, "{report}");
    published_first1_machine(&n.path, &dir);
}

/// The machine published in `dir` for Pick-and-Place's first scenario: NuSMV (`synth verify`)
/// judges it again on its own, and it replays the recording.
fn published_first1_machine(nusmv: &Path, dir: &Path) -> fbsynth::ecc::Ecc {
    let ecc = dir.join("SynthesizedFB.json");
    let o = with_nusmv(
        nusmv,
        &[
            "verify",
            "--ecc",
            ecc.to_str().unwrap(),
            "--ltl",
            "specs/pnp.ltl",
            "--plant",
            "smv/pnp_surrogate.smv",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let machine =
        fbsynth::export::json::read_json(&std::fs::read_to_string(&ecc).unwrap(), &ecc).unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let set =
        fbsynth::pipeline::Recordings::files(vec![root.join("specs/pnp_first/first1.traces")])
            .load()
            .unwrap();
    set.check(&machine).unwrap();
    machine
}

/// With fbSAT's conventions (binary algorithms, state 0 a start state no transition enters) the
/// game guides the synthesis too: on Pick-and-Place's first scenario NuSMV verifies a machine
/// that keeps both conventions and replays the recording.
#[test]
fn the_game_guides_the_synthesis_in_fbsats_conventions() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let dir = out.path().join("r");
    let o = pnp_first1(
        &n.path,
        &dir,
        &["--algorithms", "binary", "--start-state", "--json"],
    );
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(err.contains("guide: the closed-loop game is won"), "{err}");
    assert!(
        err.contains("guide: least machine with binary algorithms, a start state no transition enters for the recordings"),
        "{err}"
    );
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let method = summary["method"].as_str().unwrap();
    assert!(
        ["game guide", "exact loop after the game's guide"].contains(&method),
        "{summary}"
    );
    // Binary algorithms can need fewer states than the three-valued machine of the recordings
    // (a toggle): no bound on C is claimed from it.
    if method == "game guide" {
        assert!(summary["states_at_least"].is_null(), "{summary}");
    }
    let report = std::fs::read_to_string(dir.join("verification.txt")).unwrap();
    assert_eq!(report.matches("\nHOLDS ").count(), 8, "{report}");
    let machine = published_first1_machine(&n.path, &dir);
    for s in &machine.states {
        assert!(
            matches!(s.algorithm, fbsynth::ecc::Algorithm::Binary { .. }),
            "{}: {}",
            s.name,
            s.algorithm
        );
        assert!(
            s.transitions.iter().all(|t| t.target.0 != 0),
            "{} enters the start state",
            s.name
        );
    }
}

/// `synth infer --ltl` runs the main job's method: on Pick-and-Place's first scenario, where
/// the closed-loop game guides the synthesis, both give the same machine.
#[test]
fn infer_with_properties_gives_the_main_jobs_machine() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let main = out.path().join("main");
    let o = pnp_first1(&n.path, &main, &["-q"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let inferred = out.path().join("infer");
    let o = with_nusmv(
        &n.path,
        &[
            "infer",
            "-q",
            "--ltl",
            "specs/pnp.ltl",
            "--plant",
            "smv/pnp_surrogate.smv",
            "--traces",
            "specs/pnp_first/first1.traces",
            "--out",
            inferred.to_str().unwrap(),
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let json = |dir: &Path, file: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join(file)).unwrap()).unwrap()
    };
    assert_eq!(
        json(&inferred, "SynthesizedFB.json"),
        json(&main, "SynthesizedFB.json")
    );
    for dir in [&main, &inferred] {
        assert_eq!(json(dir, "summary.json")["method"], "game guide");
    }
}

/// The guide's machine is least only for its own runs; where the exact loop finds a smaller
/// verified one in its short turn after the guide, that one is the result.
#[test]
fn the_exact_loop_below_the_guide_replaces_its_machine_when_it_finds_a_smaller_one() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let o = main_job(
        &n.path,
        "lamp_timeout.ltl",
        "lamp_latched_plant.smv",
        out.path(),
        &["--json"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["method"], "exact loop after the game's guide");
    let key = |z: &serde_json::Value| {
        (
            z["c"].as_u64().unwrap(),
            z["t"].as_u64().unwrap(),
            z["n"].as_u64().unwrap(),
        )
    };
    assert!(
        key(&summary["size"]) < key(&summary["guide_size"]),
        "{summary}"
    );
    let report = std::fs::read_to_string(out.path().join("verification.txt")).unwrap();
    assert_eq!(report.matches("\nHOLDS ").count(), 2, "{report}");
}

/// A lost game stops nothing by itself (its verdict is not NuSMV's): the exact loop goes on,
/// and when it gives up the guide's verdict is part of the message.
#[test]
fn the_guide_says_when_the_game_is_lost_and_the_loop_goes_on() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let dir = out.path().join("r");
    let o = main_job(
        &n.path,
        "lamp_never_times_out.ltl",
        "lamp_latched_plant.smv",
        &dir,
        &["--time-limit", "60"],
    );
    assert_eq!(o.status.code(), Some(3), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("(guide: the closed-loop game is lost (")
            && err.contains("no controller of any size answers the recordings as recorded"),
        "{err}"
    );
    // The game was solved once, by the guide.
    assert!(
        !err.contains("solving the closed-loop game to tell"),
        "{err}"
    );
    assert!(!dir.exists());
}

/// SIGTERM and SIGHUP, like Ctrl-C, take the NuSMV processes down with synth.
#[test]
fn termination_signals_leave_no_nusmv_behind() {
    let Some(n) = nusmv_or_skip() else { return };
    for signal in [libc::SIGTERM, libc::SIGHUP] {
        let out = Dir::new();
        let tmp = Dir::new();
        let mut child = TestCommand::new()
            .args([
                "-q",
                "--ltl",
                "tests/data/closed_loop/lamp.ltl",
                "--plant",
                "tests/data/closed_loop/slow_frozen_plant.smv",
                "--traces",
                "tests/data/closed_loop/lamp.traces",
                "--out",
                // A folder the run makes: it goes too.
                out.path().join("r").to_str().unwrap(),
                "--nusmv",
                n.path.to_str().unwrap(),
            ])
            .env("TMPDIR", tmp.path())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn();
        // Wait (at most 20 s) until synth has started NuSMV on the slow plant.
        let mut nusmv = Vec::new();
        for _ in 0..200 {
            // NuSMV is started by one of synth's threads; look in all of them.
            nusmv = std::fs::read_dir(format!("/proc/{}/task", child.id()))
                .map(|tasks| {
                    tasks
                        .flatten()
                        .filter_map(|t| std::fs::read_to_string(t.path().join("children")).ok())
                        .flat_map(|s| {
                            s.split_whitespace()
                                .filter_map(|p| p.parse::<u32>().ok())
                                .collect::<Vec<_>>()
                        })
                        .collect()
                })
                .unwrap_or_default();
            if !nusmv.is_empty() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
        assert!(!nusmv.is_empty(), "synth started no NuSMV");
        // SAFETY: sending a signal to our own child process.
        assert_eq!(unsafe { libc::kill(child.id() as i32, signal) }, 0);
        let status = child.wait().unwrap();
        assert!(!status.success());
        for pid in nusmv {
            let alive = std::fs::read_to_string(format!("/proc/{pid}/stat"))
                .is_ok_and(|s| !s.contains(") Z "));
            assert!(!alive, "NuSMV {pid} survived signal {signal}");
        }
        // Neither NuSMV's work folder nor the output folder the run made is left.
        let left: Vec<_> = std::fs::read_dir(tmp.path())
            .unwrap()
            .chain(std::fs::read_dir(out.path()).unwrap())
            .flatten()
            .map(|e| e.path())
            .collect();
        assert!(left.is_empty(), "left after signal {signal}: {left:?}");
    }
}

/// A NuSMV that dies at once (here: a script that exits before reading its input) is a located
/// error, not a silent death of synth by SIGPIPE; and the run's temporary folder is gone.
/// What a broken NuSMV prints is shown, not sent to the terminal: escape sequences in its
/// output cannot recolour, retitle or clear the user's screen.
#[test]
fn garbage_from_nusmv_is_shown_escaped() {
    use std::os::unix::fs::PermissionsExt;
    let dir = Dir::new();
    let fake = dir.path().join("NuSMV");
    std::fs::write(
        &fake,
        "#!/bin/sh\nprintf '\\033[2J\\033]0;owned\\007 broken\\n' >&2\nexit 3\n",
    )
    .unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    let o = main_job(
        &fake,
        "lamp.ltl",
        "lamp_plant.smv",
        &dir.path().join("out"),
        &[],
    );
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{err}");
    assert!(!err.contains('\u{1b}') && !err.contains('\u{7}'), "{err:?}");
    assert!(
        err.contains("NuSMV failed (exit status: 3): \\u{1b}[2J\\u{1b}]0;owned\\u{7} broken"),
        "{err}"
    );
}

#[test]
fn a_nusmv_that_dies_at_once_is_an_error_not_a_silent_death() {
    use std::os::unix::fs::PermissionsExt;
    let dir = Dir::new();
    let fake = dir.path().join("NuSMV");
    std::fs::write(&fake, "#!/bin/sh\nexit 3\n").unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let out = dir.path().join("out");
    let run = TestCommand::new()
        .args([
            "--ltl",
            &format!("{DIR}/lamp.ltl"),
            "--plant",
            &format!("{DIR}/slow_frozen_plant.smv"),
            "--traces",
            &format!("{DIR}/lamp.traces"),
            "--out",
            out.to_str().unwrap(),
            "--nusmv",
            fake.to_str().unwrap(),
        ])
        .env("TMPDIR", &tmp)
        .output();
    let err = text(&run.stderr);
    assert!(
        run.status.code().is_some(),
        "synth died by a signal: {:?}; stderr: {err}",
        run.status
    );
    assert!(!run.status.success());
    assert!(
        err.contains("NuSMV failed (exit status: 3): it printed nothing"),
        "{err}"
    );
    assert!(!out.join("SynthesizedFB.json").exists());
    let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().flatten().collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
}

/// Controller inputs that are IVARs: NuSMV prints them in the input sections of its traces, as
/// the values of the step from the state before. The loop converges on them whether its
/// counterexamples come from the in-process checker or (with a frozen variable outside its
/// subset) from NuSMV, and `synth verify` agrees.
#[test]
fn controller_inputs_may_be_ivars() {
    let Some(n) = nusmv_or_skip() else { return };
    for plant in ["lamp_ivar_plant.smv", "lamp_ivar_frozen_plant.smv"] {
        let out = Dir::new();
        let o = main_job(&n.path, "lamp.ltl", plant, out.path(), &[]);
        assert!(o.status.success(), "{plant}: {}", text(&o.stderr));
        assert!(text(&o.stdout).contains("verified: all 2 properties hold"));
        let json = out.path().join("SynthesizedFB.json");
        let v = verify_lamp_with(&n.path, &json, plant);
        assert!(v.status.success(), "{plant}: {}", text(&v.stderr));
    }
}

/// With `--ambiguity` the main job looks for rivals and NuSMV checks each: the verdict of
/// every rival is printed, and `synth verify` on a rival's file agrees with it.
#[test]
fn the_main_job_checks_every_rival_with_nusmv() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let args = [
        "-q",
        "--ltl",
        "specs/pnp.ltl",
        "--plant",
        "smv/pnp_surrogate.smv",
        "--out",
        out.path().to_str().unwrap(),
        "--ambiguity",
        "--rivals",
        "2",
        // A rival takes about 4 s; the default 20 s budget is not enough on a loaded machine.
        "--ambiguity-budget",
        "300",
    ];
    let o = with_nusmv(&n.path, &args);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "{stdout}{}", text(&o.stderr));
    assert!(stdout.contains("ambiguous"), "{stdout}");
    for k in 1..=2 {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(&format!("rival {k}: NuSMV: ")))
            .unwrap_or_else(|| panic!("no verdict for rival {k}: {stdout}"));
        let rival = out.path().join(format!("rival{k}.json"));
        let v = with_nusmv(
            &n.path,
            &[
                "verify",
                "--ecc",
                rival.to_str().unwrap(),
                "--ltl",
                "specs/pnp.ltl",
                "--plant",
                "smv/pnp_surrogate.smv",
            ],
        );
        // verify exits 0 exactly when every property holds.
        assert_eq!(
            v.status.success(),
            line.contains("every property holds"),
            "{line}"
        );
    }
}

/// `--json` on the main job and on `verify`: the summary and NuSMV's report on stdout.
#[test]
fn json_summaries_of_the_main_job_and_verify() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let o = main_job(
        &n.path,
        "lamp.ltl",
        "lamp_plant.smv",
        out.path(),
        &["--json"],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON value");
    assert!(v["report"]["properties"]
        .as_array()
        .unwrap()
        .iter()
        .all(|p| p["holds"] == true));
    assert!(!v["files"].as_array().unwrap().is_empty());
    let json = out.path().join("SynthesizedFB.json");
    let ltl = format!("{DIR}/lamp.ltl");
    let plant = format!("{DIR}/lamp_plant.smv");
    let args = [
        "verify",
        "--ecc",
        json.to_str().unwrap(),
        "--ltl",
        &ltl,
        "--plant",
        &plant,
        "--json",
    ];
    let v = with_nusmv(&n.path, &args);
    assert!(v.status.success(), "{}", text(&v.stderr));
    let r: serde_json::Value = serde_json::from_slice(&v.stdout).unwrap();
    assert_eq!(r["verified"], true);
}

/// `synth infer --ltl --plant` runs the main job's loop on the recordings: where `infer`
/// alone gives a machine whose lamp never goes out, with the properties it gives one NuSMV
/// verifies, written with its report. A verified machine needs its report: `--out -` is a
/// usage error then.
#[test]
fn infer_with_properties_gives_a_verified_machine() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let dir = out.path().join("v");
    let args = |out: &str| -> Vec<String> {
        [
            "infer",
            "-q",
            "--traces",
            &format!("{DIR}/lamp.traces"),
            "--ltl",
            &format!("{DIR}/lamp.ltl"),
            "--plant",
            &format!("{DIR}/lamp_plant.smv"),
            "--out",
            out,
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    };
    let o = with_nusmv(
        &n.path,
        &args(dir.to_str().unwrap())
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("verified: all 2 properties hold (NuSMV)"));
    let report = std::fs::read_to_string(dir.join("verification.txt")).unwrap();
    assert!(report.contains("HOLDS    goes_out"), "{report}");
    let v = verify_lamp(&n.path, &dir.join("SynthesizedFB.json"));
    assert!(v.status.success(), "{}", text(&v.stderr));
    let o = with_nusmv(
        &n.path,
        &args("-").iter().map(String::as_str).collect::<Vec<_>>(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("--out -"), "{}", text(&o.stderr));
}

/// NuSMV runs under a memory cap: a plant too large for it fails at once with NuSMV's own
/// "Out of memory" and what to do, not after gigabytes and a timeout (exit 4, no result).
#[test]
fn nusmv_out_of_memory_is_an_early_error_with_advice() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let res = out.path().join("res");
    let o = TestCommand::new()
        .args([
            "-q",
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            "tests/data/closed_loop/huge_range_plant.smv",
            "--traces",
            "tests/data/closed_loop/lamp.traces",
            "--out",
            res.to_str().unwrap(),
            "--nusmv",
            n.path.to_str().unwrap(),
        ])
        .env("FBSYNTH_NUSMV_MEMORY_MB", "300")
        .output();
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{e}");
    assert!(e.contains("Out of memory"), "{e}");
    assert!(
        e.contains("NuSMV may take 300 MB") && e.contains("FBSYNTH_NUSMV_MEMORY_MB"),
        "{e}"
    );
    assert!(!res.join("SynthesizedFB.json").exists());
}
