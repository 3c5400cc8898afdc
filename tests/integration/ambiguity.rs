//! The ambiguity report of `synth infer` and the plan of `synth next-recording` on the shipped
//! cases: every rival replays the recordings, and the plan's sequence tells it apart from the
//! machine.

use crate::common::{synth, Dir};
use fbsynth::ecc::{Ecc, Run};
use fbsynth::export::json::read_json;
use fbsynth::pipeline::Recordings;
use std::path::{Path, PathBuf};

fn machine(path: &Path) -> Ecc {
    read_json(&std::fs::read_to_string(path).unwrap(), path).unwrap()
}

fn recordings(traces: &str) -> fbsynth::scenario::ScenarioSet {
    Recordings::files(vec![PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(traces)])
        .load()
        .unwrap()
}

/// Runs `next-recording` on `traces`; checks that the machine and every rival replay the
/// recordings and that each planned sequence makes them answer as the plan expects, differently
/// at its last step. Returns stdout.
fn plan_tells_rivals_apart(traces: &str, more: &[&str]) -> String {
    let dir = Dir::new();
    let out = dir.path().join("next");
    let mut args = vec![
        "next-recording",
        "-q",
        "--traces",
        traces,
        "--out",
        out.to_str().unwrap(),
        // Seconds per rival on an idle machine; a loaded one must not turn them "unknown".
        "--ambiguity-budget",
        "300",
    ];
    args.extend(more);
    let o = synth(&args);
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        o.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(stdout.contains("ambiguous"), "{stdout}");
    let set = recordings(traces);
    let m = machine(&out.join("machine.json"));
    set.check(&m).unwrap();
    let plan = std::fs::read_to_string(out.join("plan.csv")).unwrap();
    let mut k = 1;
    while out.join(format!("rival{k}.json")).exists() {
        let r = machine(&out.join(format!("rival{k}.json")));
        set.check(&r).unwrap();
        let rows: Vec<Vec<&str>> = plan
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect())
            .filter(|c: &Vec<&str>| c[0] == k.to_string())
            .collect();
        assert!(!rows.is_empty(), "{plan}");
        let (mut a, mut b) = (Run::new(&m), Run::new(&r));
        let answer = |run: &Run, fired: bool| {
            if fired {
                run.outputs
                    .iter()
                    .map(|&v| if v { '1' } else { '0' })
                    .collect()
            } else {
                "-".to_string()
            }
        };
        let n = set.inputs.len();
        let mut last = (String::new(), String::new());
        for row in &rows {
            let x: Vec<bool> = row[3..3 + n].iter().map(|v| *v == "1").collect();
            let fa = a.step(&x).is_some();
            let fb = b.step(&x).is_some();
            last = (answer(&a, fa), answer(&b, fb));
            assert_eq!(last.0, row[3 + n], "{plan}");
            assert_eq!(last.1, row[4 + n], "{plan}");
        }
        assert_ne!(last.0, last.1, "the last step must tell them apart: {plan}");
        k += 1;
    }
    assert!(k > 1, "no rival written: {stdout}");
    stdout
}

#[test]
fn pnp_scenarios_are_ambiguous_and_the_plan_tells_the_rival_apart() {
    plan_tells_rivals_apart("specs/pnp.traces", &[]);
}

/// Over every input vector, with a rival allowed one state more: the sequence may use input
/// combinations nobody recorded.
#[test]
fn pnp_rivals_over_every_input_vector_are_told_apart_too() {
    let stdout =
        plan_tells_rivals_apart("specs/pnp.traces", &["--all-inputs", "--extra-states", "1"]);
    assert!(stdout.contains("at most 9 states"), "{stdout}");
    assert!(stdout.contains("any of the 1024 input vectors"), "{stdout}");
}

#[test]
fn distribution_logs_are_ambiguous_and_the_plan_tells_the_rival_apart() {
    plan_tells_rivals_apart("specs/distribution.csv", &[]);
}

#[test]
fn tank_logs_are_ambiguous_and_the_plan_tells_the_rival_apart() {
    plan_tells_rivals_apart("specs/tank2.traces", &["--rivals", "2"]);
}

#[test]
fn infer_says_unique_when_no_rival_fits() {
    let dir = Dir::new();
    let out = dir.path().join("r");
    let o = synth(&[
        "infer",
        "-q",
        "--traces",
        "specs/tank1.traces",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{stdout}");
    assert!(
        stdout.contains("unique: no other machine with 2 states"),
        "{stdout}"
    );
    assert!(!out.join("rival1.json").exists());
    assert!(out.join("ambiguity.txt").exists());
}

#[test]
fn infer_reports_rivals_with_their_sequences() {
    let dir = Dir::new();
    let out = dir.path().join("r");
    let o = synth(&[
        "infer",
        "-q",
        "--traces",
        "specs/tank2.traces",
        "--rivals",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{stdout}");
    assert!(stdout.contains("ambiguous"), "{stdout}");
    assert!(stdout.contains("<- differs"), "{stdout}");
    let set = recordings("specs/tank2.traces");
    for k in 1..=2 {
        let r = machine(&out.join(format!("rival{k}.json")));
        set.check(&r).unwrap();
        assert_eq!(r.states.len(), 8);
    }
    // The second rival differs from the first too: they are not the same machine.
    assert_ne!(
        machine(&out.join("rival1.json")),
        machine(&out.join("rival2.json"))
    );
}

#[test]
fn the_active_loop_ends_with_a_machine_equivalent_to_the_reference() {
    let dir = Dir::new();
    let learned = dir.path().join("learned.json");
    let reference = dir.path().join("reference.json");
    let ecc = crate::cases::tank::Program::Cycles.reference();
    std::fs::write(&reference, fbsynth::export::json::to_string(&ecc)).unwrap();
    let learn = |more: &[&str]| {
        let mut args = vec![
            "learn",
            "-q",
            "--oracle",
            "case:tank2",
            "--traces",
            "specs/tank2.traces",
            "--all-inputs",
            "--passive-runs",
            "1",
        ];
        args.extend(more);
        synth(&args)
    };
    let o = learn(&["--out", learned.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        stdout.contains("; unique; equivalent to the oracle"),
        "{stdout}"
    );
    assert!(stdout.contains("passive (seed 1)"), "{stdout}");
    let d = synth(&[
        "diff",
        learned.to_str().unwrap(),
        reference.to_str().unwrap(),
    ]);
    assert!(d.status.success(), "{}", String::from_utf8_lossy(&d.stdout));
    assert!(String::from_utf8_lossy(&d.stdout).contains("equivalent"));
    // The same run as JSON.
    let j = learn(&["--json"]);
    assert!(j.status.success(), "{}", String::from_utf8_lossy(&j.stderr));
    let v: serde_json::Value = serde_json::from_slice(&j.stdout).unwrap();
    assert_eq!(v["unique"], true);
    assert_eq!(v["equivalent"], true);
    assert!(v["recorded_steps"].as_u64().unwrap() > 0);
    // Tours and probes come before rivals; the last round asked for rivals and found none.
    let rounds = v["rounds"].as_array().unwrap();
    assert_eq!(rounds[0]["asked"], "tour", "{rounds:?}");
    let last = rounds.last().unwrap();
    assert_eq!(
        (&last["asked"], &last["verdict"]),
        (&"rivals".into(), &"unique".into())
    );
    // The loop recorded something: the shipped recordings alone leave the machine ambiguous.
    let rounds: usize = stdout
        .split("active: ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap();
    assert!(rounds > 1, "{stdout}");
}

#[test]
fn an_oracle_with_another_interface_is_refused() {
    let o = synth(&[
        "learn",
        "-q",
        "--oracle",
        "case:pnp",
        "--traces",
        "specs/tank2.traces",
    ]);
    assert_eq!(
        o.status.code(),
        Some(4),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("interface"));
}
