//! The process-mining paper's tank, end to end: the main job rebuilds both PLC programs from the recorded
//! scenarios, NuSMV verifies them against the tank properties, and the machines agree with the
//! programs on held-out runs; the event logs of the raw tank logs load in pm4py. NuSMV tests
//! skip with a note where NuSMV is missing (and fail under CI=true); the pm4py test needs
//! `$PM4PY_PYTHON` (from `.ci/install-pm4py.sh`) in the same way.

use crate::cases::tank::{self, Plant, Program, RunSpec};
use crate::common::{nusmv_or_skip, synth, text, Dir};
use fbsynth::ecc::Ecc;
use fbsynth::ingest::{read_scenarios, Mapping};
use std::path::{Path, PathBuf};
use std::process::Command;

fn read_ecc(path: &Path) -> Ecc {
    fbsynth::export::json::read_json(&std::fs::read_to_string(path).unwrap(), path).unwrap()
}

/// Noisy-plant seeds of the held-out comparison (never used for training).
const HELD_OUT_SEEDS: std::ops::Range<u64> = 2000..2020;

/// The main job on the shipped tank files; returns the verified machine.
fn rebuild(nusmv: &Path, program: Program, out: &Path) -> Ecc {
    let stem = tank::traces_stem(program);
    let ltl = format!("specs/{stem}.ltl");
    let o = synth(&[
        "-q",
        "--ltl",
        &ltl,
        "--plant",
        "smv/tank_surrogate.smv",
        "--nusmv",
        nusmv.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{stem}: {}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("verified: all"),
        "{}",
        text(&o.stdout)
    );
    read_ecc(&out.join("SynthesizedFB.json"))
}

/// Both programs: the rebuilt machine has the reference's size (program 2's counter became
/// states), replays every training scenario and the ingested raw logs, and on held-out noisy
/// runs computes the reference's outputs at every scan, open loop and closed loop.
#[test]
fn tank_programs_are_rebuilt_exactly_and_verified() {
    let Some(n) = nusmv_or_skip() else { return };
    let map_file = Path::new(env!("CARGO_MANIFEST_DIR")).join("specs/tank/tank.map");
    let mapping = Mapping::read(&map_file).unwrap();
    for program in [Program::FillDrain, Program::Cycles] {
        let out = Dir::new();
        let ecc = rebuild(&n.path, program, out.path());
        let reference = program.reference();
        assert_eq!(ecc.states.len(), reference.states.len(), "{program:?}");
        tank::training_set(program).check(&ecc).unwrap();
        for spec in tank::SCENARIOS.iter().filter(|s| s.program == program) {
            let log =
                Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("specs/tank/{}.csv", spec.name));
            let (set, _) = read_scenarios(&log, &mapping, false).unwrap();
            set.check(&ecc)
                .unwrap_or_else(|e| panic!("{}: {e}", spec.name));
        }
        // The shipped held-out raw log of this program replays too.
        for spec in tank::HELD_OUT.iter().filter(|s| s.program == program) {
            let log =
                Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("specs/tank/{}.csv", spec.name));
            let (set, _) = read_scenarios(&log, &mapping, false).unwrap();
            set.check(&ecc)
                .unwrap_or_else(|e| panic!("{}: {e}", spec.name));
        }
        for seed in HELD_OUT_SEEDS {
            let spec = RunSpec {
                name: "held-out",
                program,
                plant: Plant::Noisy { seed },
                scans: 1500,
            };
            let recorded = tank::record(&spec);
            assert_eq!(
                tank::first_disagreement(&ecc, &recorded),
                None,
                "{program:?}, seed {seed}"
            );
            let closed = tank::simulate(&ecc, spec.plant, spec.scans);
            assert_eq!(closed, recorded, "{program:?}, seed {seed}: closed loop");
        }
    }
}

/// The properties can fail: program 1's own machine violates program 2's cycle count, and
/// `synth verify` says so.
#[test]
fn program_1_does_not_satisfy_the_cycle_count_of_program_2() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let json = dir.path().join("p1.json");
    std::fs::write(
        &json,
        fbsynth::export::json::to_string(&Program::FillDrain.reference()),
    )
    .unwrap();
    let verify = |ltl: &str| {
        synth(&[
            "verify",
            "--ecc",
            json.to_str().unwrap(),
            "--ltl",
            ltl,
            "--plant",
            "smv/tank_surrogate.smv",
            "--nusmv",
            n.path.to_str().unwrap(),
        ])
    };
    let o = verify("specs/tank1.ltl");
    assert!(o.status.success(), "{}", text(&o.stdout));
    let o = verify("specs/tank2.ltl");
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stdout).contains("VIOLATED cycle_count"),
        "{}",
        text(&o.stdout)
    );
}

/// pm4py's python (`$PM4PY_PYTHON`), or `None` after a skip note; under `CI=true` a missing
/// one fails, like NuSMV (CI installs both).
fn pm4py_or_skip() -> Option<PathBuf> {
    match std::env::var_os("PM4PY_PYTHON") {
        Some(p) if Path::new(&p).is_file() => Some(PathBuf::from(p)),
        other => {
            let why = match other {
                Some(p) => format!("PM4PY_PYTHON={} is not a file", Path::new(&p).display()),
                None => "PM4PY_PYTHON is not set (.ci/install-pm4py.sh prints it)".to_string(),
            };
            if std::env::var("CI").as_deref() == Ok("true") {
                panic!("pm4py is required when CI=true, but {why}");
            }
            eprintln!("skipping pm4py test: {why}");
            None
        }
    }
}

/// `key: value` lines of the check script.
fn field(out: &str, key: &str) -> String {
    out.lines()
        .find_map(|l| l.strip_prefix(&format!("{key}: ")))
        .unwrap_or_else(|| panic!("no '{key}' in:\n{out}"))
        .to_string()
}

/// The XES of every tank log loads in pm4py with the traces and events `synth events`
/// counted, the inductive miner discovers a net from it, and the reference program's Petri
/// net (PNML) imports and replays every complete trace of the log.
#[test]
fn pm4py_loads_the_tank_event_logs_and_replays_them_on_the_program_net() {
    let Some(python) = pm4py_or_skip() else {
        return;
    };
    let dir = Dir::new();
    for spec in tank::SCENARIOS.iter() {
        let json = dir.path().join(format!("{}.json", spec.name));
        std::fs::write(
            &json,
            fbsynth::export::json::to_string(&spec.program.reference()),
        )
        .unwrap();
        let xes = dir.path().join(format!("{}.xes", spec.name));
        let pnml = dir.path().join(format!("{}.pnml", spec.name));
        let log = format!("specs/tank/{}.csv", spec.name);
        let o = synth(&[
            "events",
            "--log",
            &log,
            "--map",
            "specs/tank/tank.map",
            "--reset",
            tank::RESET,
            "--out",
            xes.to_str().unwrap(),
            "--ecc",
            json.to_str().unwrap(),
            "--pnml",
            pnml.to_str().unwrap(),
            "--pnml-dialect",
            "prom",
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let summary = text(&o.stdout);
        // "... N events in M traces ..."
        let words: Vec<&str> = summary.split_whitespace().collect();
        let before = |w: &str| words[words.iter().position(|x| *x == w).unwrap() - 1].to_string();
        let (events, traces) = (before("events"), before("traces"));
        let check = Command::new(&python)
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/pm4py_check.py"))
            .arg(&xes)
            .arg("--pnml")
            .arg(&pnml)
            .output()
            .expect("run the pm4py check script");
        let out = text(&check.stdout);
        assert!(
            check.status.success(),
            "{}: {}{}",
            spec.name,
            out,
            text(&check.stderr)
        );
        assert_eq!(field(&out, "traces"), traces, "{}", spec.name);
        assert_eq!(field(&out, "events"), events, "{}", spec.name);
        assert!(field(&out, "transitions").parse::<usize>().unwrap() > 0);
        // `start`, one place per state, one per ECC transition (see export::pnml).
        let reference = spec.program.reference();
        let transitions: usize = reference.states.iter().map(|s| s.transitions.len()).sum();
        assert_eq!(
            field(&out, "pnml_places"),
            (1 + reference.states.len() + transitions).to_string()
        );
        // Every trace fits but the last, which the end of the recording may cut short.
        let fitting: usize = field(&out, "pnml_fitting_traces").parse().unwrap();
        let traces: usize = traces.parse().unwrap();
        assert!(
            fitting + 1 >= traces,
            "{}: {fitting} of {traces} traces fit",
            spec.name
        );
        let fitness: f64 = field(&out, "pnml_fitness").parse().unwrap();
        assert!(fitness > 0.99, "{}: fitness {fitness}", spec.name);
        // The ISO net (the default) is the same net to pm4py: same places and transitions.
        let iso = dir.path().join(format!("{}.iso.pnml", spec.name));
        let o = synth(&[
            "events",
            "--log",
            &log,
            "--map",
            "specs/tank/tank.map",
            "--reset",
            tank::RESET,
            "--out",
            dir.path().join("iso.xes").to_str().unwrap(),
            "--ecc",
            json.to_str().unwrap(),
            "--pnml",
            iso.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let check = Command::new(&python)
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/pm4py_check.py"))
            .arg(&xes)
            .arg("--pnml")
            .arg(&iso)
            .output()
            .expect("run the pm4py check script");
        let iso_out = text(&check.stdout);
        assert!(check.status.success(), "{}", text(&check.stderr));
        for key in ["pnml_places", "pnml_transitions"] {
            assert_eq!(
                field(&iso_out, key),
                field(&out, key),
                "{}: {key}",
                spec.name
            );
        }
    }
}

/// The raw-log route: `synth ingest` of program 2's two raw logs, `synth infer` on the result
/// (no properties), and the machine is the same size, verified by `synth verify`, and exact on
/// held-out runs.
#[test]
fn program_2_from_the_raw_logs_alone() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let mut traces = Vec::new();
    for name in ["scenario2", "scenario3"] {
        let t = dir.path().join(format!("{name}.traces"));
        let log = format!("specs/tank/{name}.csv");
        let o = synth(&[
            "ingest",
            "--log",
            &log,
            "--map",
            "specs/tank/tank.map",
            "-o",
            t.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        traces.push(t.to_str().unwrap().to_string());
    }
    let out = dir.path().join("out");
    let mut args = vec!["infer", "-q", "--out", out.to_str().unwrap(), "--traces"];
    args.extend(traces.iter().map(String::as_str));
    let o = synth(&args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let json = out.join("SynthesizedFB.json");
    let ecc = read_ecc(&json);
    assert_eq!(ecc.states.len(), 2 + 2 * tank::CYCLES);
    for seed in HELD_OUT_SEEDS {
        let recorded = tank::record(&RunSpec {
            name: "held-out",
            program: Program::Cycles,
            plant: Plant::Noisy { seed },
            scans: 1500,
        });
        assert_eq!(
            tank::first_disagreement(&ecc, &recorded),
            None,
            "seed {seed}"
        );
    }
    let o = synth(&[
        "verify",
        "--ecc",
        json.to_str().unwrap(),
        "--ltl",
        "specs/tank2.ltl",
        "--plant",
        "smv/tank_surrogate.smv",
        "--nusmv",
        n.path.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stdout));
}

/// What a net says about a controller that counts wrong: program 2 with one middle cycle
/// instead of three. The net pm4py's inductive miner discovers from program 2's log accepts
/// its log (the paper's problem: the net does not count); the Petri net of program 2's
/// machine rejects every complete trace of it.
#[test]
fn only_the_machine_net_notices_a_wrong_cycle_count() {
    let Some(python) = pm4py_or_skip() else {
        return;
    };
    let dir = Dir::new();
    let mut wrong = Program::Cycles.reference();
    // Raise1 -> Drain instead of Raise1 -> Lower2.
    assert_eq!(wrong.states[3].name, "Raise1");
    wrong.states[3].transitions[0].target = fbsynth::ecc::StateId(0);
    let mut log = Vec::new();
    tank::write_long_log(&tank::simulate(&wrong, Plant::Constant, 600), &mut log).unwrap();
    std::fs::write(dir.path().join("wrong.log.csv"), log).unwrap();
    let json = dir.path().join("p2.json");
    std::fs::write(
        &json,
        fbsynth::export::json::to_string(&Program::Cycles.reference()),
    )
    .unwrap();
    let events = |log: &Path, xes: &Path, extra: &[&str]| {
        let mut args = vec![
            "events",
            "--log",
            log.to_str().unwrap(),
            "--map",
            "specs/tank/tank.map",
            "--reset",
            tank::RESET,
            "--out",
            xes.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = synth(&args);
        assert!(o.status.success(), "{}", text(&o.stderr));
    };
    let (good_xes, wrong_xes) = (dir.path().join("s2.xes"), dir.path().join("wrong.xes"));
    let pnml = dir.path().join("p2.pnml");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    events(
        &root.join("specs/tank/scenario2.csv"),
        &good_xes,
        &[
            "--ecc",
            json.to_str().unwrap(),
            "--pnml",
            pnml.to_str().unwrap(),
            "--pnml-dialect",
            "prom",
        ],
    );
    events(&dir.path().join("wrong.log.csv"), &wrong_xes, &[]);
    let check = Command::new(&python)
        .arg(root.join("tests/pm4py_check.py"))
        .arg(&good_xes)
        .arg("--pnml")
        .arg(&pnml)
        .arg("--replay")
        .arg(&wrong_xes)
        .output()
        .expect("run the pm4py check script");
    let out = text(&check.stdout);
    assert!(check.status.success(), "{out}{}", text(&check.stderr));
    eprintln!("{out}");
    let traces: usize = field(&out, "replay_traces").parse().unwrap();
    assert!(traces > 3, "{out}");
    assert_eq!(field(&out, "replay_inductive_fitness"), "1.0000", "{out}");
    let fitting: usize = field(&out, "replay_pnml_fitting_traces").parse().unwrap();
    // At most the last trace, which the end of the recording may cut before the miscount.
    assert!(fitting <= 1, "{out}");
}
