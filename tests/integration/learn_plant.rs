//! `synth learn-plant` and `synth compare-plants` on the shipped cases: the learned plant
//! admits every recording, the main job with it gives a machine NuSMV verifies against the
//! hand-written surrogate too, and recordings too short to learn from are refused by name
//! with nothing written. The main job's `--learn-plant` likewise: the plant learned on the way
//! is published with the machine and named in the summaries.

use crate::common::{nusmv_or_skip, printed_schema, synth, text, Dir, TestCommand};
use std::path::{Path, PathBuf};

/// `synth learn-plant` on `traces` with `observers` and the learner's `options`; the plant
/// file written.
fn learn(traces: &str, observers: &str, options: &[&str], dir: &Path) -> PathBuf {
    let out = dir.join("plant.smv");
    let mut args = vec!["learn-plant", "--traces", traces, "--observe", observers];
    args.extend(options);
    args.extend(["--out", out.to_str().unwrap()]);
    let o = synth(&args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("every recorded step is a step of it"),
        "{}",
        text(&o.stdout)
    );
    out
}

/// The main job with `plant`; the machine's JSON file.
fn main_job(nusmv: &Path, ltl: &str, plant: &Path, traces: &str, out: &Path) -> PathBuf {
    let o = synth(&[
        "-q",
        "--ltl",
        ltl,
        "--plant",
        plant.to_str().unwrap(),
        "--traces",
        traces,
        "--nusmv",
        nusmv.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("verified: all"),
        "{}",
        text(&o.stdout)
    );
    out.join("SynthesizedFB.json")
}

/// `synth verify`: whether every property holds.
fn verified(nusmv: &Path, ecc: &Path, ltl: &str, plant: &Path) -> bool {
    let o = synth(&[
        "verify",
        "--ecc",
        ecc.to_str().unwrap(),
        "--ltl",
        ltl,
        "--plant",
        plant.to_str().unwrap(),
        "--nusmv",
        nusmv.to_str().unwrap(),
    ]);
    text(&o.stdout).contains("verified: all")
}

#[test]
fn the_tank_plant_learned_verifies_a_machine_the_hand_written_plant_verifies_too() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let plant = learn(
        "specs/tank2.traces",
        "specs/tank2.observers",
        &[],
        dir.path(),
    );
    let ecc = main_job(
        &n.path,
        "specs/tank2.ltl",
        &plant,
        "specs/tank2.traces",
        &dir.path().join("m"),
    );
    let hand = Path::new("smv/tank_surrogate.smv");
    assert!(verified(&n.path, &ecc, "specs/tank2.ltl", hand));
    assert_runs_admitted(&ecc, hand, &plant, 1000, 990);
}

/// Bounded inclusion: at least `at_least` of `runs` random runs of `ecc` in closed loop with
/// the hand-written plant `hand` are runs of the learned `plant`.
fn assert_runs_admitted(ecc: &Path, hand: &Path, plant: &Path, runs: usize, at_least: usize) {
    let runs = runs.to_string();
    let o = synth(&[
        "compare-plants",
        "--runs",
        &runs,
        "--ecc",
        ecc.to_str().unwrap(),
        "--plants",
        hand.to_str().unwrap(),
        plant.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let first = text(&o.stdout)
        .lines()
        .next()
        .unwrap_or_default()
        .to_string();
    let admitted: usize = first.split(' ').next().unwrap().parse().unwrap();
    assert!(admitted >= at_least, "{first}");
}

/// Not vacuous: the machine of the recordings alone (`synth infer`), which the hand-written
/// plant `hand` refutes, is refuted by the learned `plant` too.
fn assert_own_machine_refuted(
    nusmv: &Path,
    traces: &str,
    ltl: &str,
    hand: &Path,
    plant: &Path,
    dir: &Path,
) {
    let own = dir.join("own");
    let o = synth(&[
        "-q",
        "infer",
        "--traces",
        traces,
        "--out",
        own.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let own = own.join("SynthesizedFB.json");
    assert!(!verified(nusmv, &own, ltl, hand));
    assert!(!verified(nusmv, &own, ltl, plant));
}

#[test]
fn the_distribution_plant_learned_verifies_a_machine_and_refutes_the_recordings_own() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let traces = "specs/distribution.csv";
    // The hand-written plant's cup grips a scan later than the recorded station's: a change
    // a command drives may come one scan later than recorded.
    let slack = ["--slack", "1"];
    let plant = learn(traces, "specs/distribution.observers", &slack, dir.path());
    // The operator's buttons and the magazine's stock are the environment's: no command is
    // made to press them, and they start free; the cylinder and the arm are driven.
    let smv = std::fs::read_to_string(&plant).unwrap();
    for sensor in ["empty", "start", "stop", "auto_man", "emergency"] {
        let line = format!("--   {sensor}: rises on nothing; falls on nothing (the environment's");
        let mut found = smv
            .lines()
            .filter(|l| l.starts_with(&format!("--   {sensor}:")));
        let found = found.next().unwrap_or_default();
        assert!(
            found.ends_with("(the environment's: free where seen changing)")
                && (sensor == "empty" || found.starts_with(&line)),
            "{found}"
        );
        assert!(
            !smv.contains(&format!("init({sensor})")),
            "{sensor} starts fixed"
        );
    }
    for sensor in [
        "retracted",
        "extended",
        "at_magazine",
        "at_client",
        "vac_on",
    ] {
        assert!(
            !smv.contains(&format!("--   {sensor}: rises on nothing")),
            "{smv}"
        );
        assert!(
            smv.contains(&format!("init({sensor})")),
            "{sensor} starts free"
        );
    }
    // The suction follows a valve the pulses vacuum_on and vacuum_off open and close, so that
    // the cup may grip after the pulse.
    assert!(
        smv.contains("--   vac_on: rises on vacuum_on; falls on vacuum_off (delayed); through valve_vac_on, which the pulses of vacuum_on and vacuum_off open and close"),
        "{smv}"
    );
    let ltl = "specs/distribution.ltl";
    let ecc = main_job(&n.path, ltl, &plant, traces, &dir.path().join("m"));
    let hand = Path::new("smv/distribution_surrogate.smv");
    assert!(verified(&n.path, &ecc, ltl, hand));
    assert_runs_admitted(&ecc, hand, &plant, 1000, 990);
    assert_own_machine_refuted(&n.path, traces, ltl, hand, &plant, dir.path());
}

#[test]
fn the_pnp_plant_learned_admits_every_recording() {
    let dir = Dir::new();
    let plant = learn("specs/pnp.traces", "specs/pnp.observers", &[], dir.path());
    let smv = std::fs::read_to_string(plant).unwrap();
    assert!(smv.starts_with("-- Surrogate plant learned by fbsynth from specs/pnp.traces"));
    assert!(smv.contains(
        "MODULE plant(c1Extend, c1Retract, c2Extend, c2Retract, vcExtend, vacuum_on, vacuum_off)"
    ));
    // The pieces the operator puts on the tracks are the environment's: never forced to
    // appear, and free at the start; a piece leaves its track once the cup holds it there.
    for piece in ["pp1", "pp2", "pp3"] {
        let line = (smv.lines())
            .find(|l| l.starts_with(&format!("--   {piece}:")))
            .unwrap_or_default();
        assert!(
            line.ends_with(
                "(the environment's: free where seen changing, bound where it always came)"
            ),
            "{line}"
        );
        assert!(!smv.contains(&format!("wait_up_{piece}")), "{smv}");
    }
    assert!(
        smv.contains("--   pp1: rises on nothing; falls on vcEnd, vac, c1Home"),
        "{smv}"
    );
    // The operator puts pieces on track 2 whatever the cup does: the recordings show it only
    // with the cup up, which does not hold up against every change of the environment's.
    assert!(smv.contains("--   pp2: rises on nothing;"), "{smv}");
    // The piece is forced to leave only where the hand stood as at every recorded pick.
    assert!(
        smv.contains("pp1 & vcEnd & vac & c1Home & !c1End & c2Home & !c2End & !vcHome : FALSE;"),
        "{smv}"
    );
}

#[test]
fn the_pnp_plant_learned_verifies_a_machine_the_hand_written_plant_verifies_and_refutes_the_recordings_own(
) {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let traces = "specs/pnp.traces";
    let plant = learn(traces, "specs/pnp.observers", &[], dir.path());
    let ltl = "specs/pnp.ltl";
    let ecc = main_job(&n.path, ltl, &plant, traces, &dir.path().join("m"));
    let hand = Path::new("smv/pnp_surrogate.smv");
    assert!(verified(&n.path, &ecc, ltl, hand));
    assert_own_machine_refuted(&n.path, traces, ltl, hand, &plant, dir.path());
}

#[test]
fn the_pnp_plant_learned_with_slack_verifies_a_machine_and_admits_the_hand_written_closed_loop() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let (traces, ltl) = ("specs/pnp.traces", "specs/pnp.ltl");
    // The hand-written cup grips two scans after the pulse (the recorded one at the next),
    // and the piece leaves its track in the scan the cup grips (recorded: the scan after).
    let slack = ["--slack", "1"];
    let plant = learn(traces, "specs/pnp.observers", &slack, dir.path());
    let smv = std::fs::read_to_string(&plant).unwrap();
    // Where the cup gripped as it left, the piece leaves by the next scan.
    assert!(
        smv.contains("& !(next(vcEnd) & next(vac) & next(c1Home) & !next(c1End) & next(c2Home) & !next(c2End) & !next(vcHome)) : FALSE;"),
        "{smv}"
    );
    let ecc = main_job(&n.path, ltl, &plant, traces, &dir.path().join("m"));
    let hand = Path::new("smv/pnp_surrogate.smv");
    assert!(verified(&n.path, &ecc, ltl, hand));
    assert_own_machine_refuted(&n.path, traces, ltl, hand, &plant, dir.path());
    assert_runs_admitted(&ecc, hand, &plant, 1000, 990);
}

/// The first scans of the tank, where the outlet is never opened, as `short.traces` in `dir`
/// with the tank's names files.
fn short_tank(dir: &Path) -> PathBuf {
    let full = std::fs::read_to_string("specs/tank2.traces").unwrap();
    let first = full.lines().nth(1).unwrap();
    let short: Vec<&str> = first.split("; ").take(12).collect();
    let traces = dir.join("short.traces");
    std::fs::write(
        &traces,
        format!("1\n{};\n", short.join("; ").trim_end_matches(';')),
    )
    .unwrap();
    for names in ["inputs", "outputs"] {
        std::fs::copy(
            format!("specs/tank2.{names}"),
            dir.join(format!("short.{names}")),
        )
        .unwrap();
    }
    traces
}

#[test]
fn recordings_where_an_output_never_acts_are_refused_by_name_with_nothing_written() {
    let dir = Dir::new();
    let traces = short_tank(dir.path());
    let out = dir.path().join("plant.smv");
    let o = synth(&[
        "learn-plant",
        "--traces",
        traces.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    refused_as_too_short(&o, &out);
}

#[test]
fn an_assumption_the_recordings_violate_is_refused_with_the_step() {
    let dir = Dir::new();
    // "The upper sensor is never covered": the recordings cover it.
    let observers = dir.path().join("never_full.observers");
    std::fs::write(&observers, "INVAR !ul\n").unwrap();
    let out = dir.path().join("plant.smv");
    let o = synth(&[
        "learn-plant",
        "--traces",
        "specs/tank2.traces",
        "--observe",
        observers.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("specs/tank2.traces:2 step")
            && err.contains("cannot produce this recorded step"),
        "{err}"
    );
    assert!(!out.exists());
}

/// The main job on the tank with `--learn-plant`, with `args` after it.
fn main_job_learning(args: &[&str]) -> TestCommand {
    let mut cmd = TestCommand::new();
    cmd.args(["--ltl", "specs/tank2.ltl", "--learn-plant"])
        .args(args);
    cmd
}

#[test]
fn the_main_job_learns_the_tank_plant_on_the_way_and_publishes_it_with_the_machine() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let out = dir.path().join("t");
    let o = main_job_learning(&[
        "-q",
        "--json",
        "--traces",
        "specs/tank2.traces",
        "--observe",
        "specs/tank2.observers",
        "--out",
        out.to_str().unwrap(),
    ])
    .nusmv(&n.path)
    .umask(0o022)
    .output();
    assert!(o.status.success(), "{}", text(&o.stderr));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let plant = out.join("plant.smv");
    let learned = &json["learned_plant"];
    assert_eq!(learned["file"], plant.to_str().unwrap(), "{json:#}");
    assert_eq!(learned["scans"], 1200, "{json:#}");
    assert_eq!(learned["sensors"], 3, "{json:#}");
    assert!(json["files"]
        .as_array()
        .unwrap()
        .contains(&plant.to_str().unwrap().into()));
    // The plant `synth learn-plant` writes, published with the machine, readable by all.
    let alone = learn(
        "specs/tank2.traces",
        "specs/tank2.observers",
        &[],
        dir.path(),
    );
    assert_eq!(
        std::fs::read_to_string(&plant).unwrap(),
        std::fs::read_to_string(alone).unwrap()
    );
    use std::os::unix::fs::PermissionsExt;
    let mode = std::fs::metadata(&plant).unwrap().permissions().mode();
    assert_eq!(mode & 0o777, 0o644);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["learned_plant"], json["learned_plant"]);
    let verification = std::fs::read_to_string(out.join("verification.txt")).unwrap();
    assert!(
        verification.contains(plant.to_str().unwrap()),
        "{verification}"
    );
    // The --json summary validates against the schema `synth schema --summary` prints.
    let (schemas, index) = printed_schema(dir.path(), &["--summary"]);
    let mut bad = json.clone();
    assert!(schemas.validate(&json, index).is_ok(), "{json:#}");
    bad["learned_plant"]["sensors"] = "three".into();
    assert!(schemas.validate(&bad, index).is_err());
    // The machine verified with the learned plant holds with the hand-written one too.
    let ecc = out.join("SynthesizedFB.json");
    let hand = Path::new("smv/tank_surrogate.smv");
    assert!(verified(&n.path, &ecc, "specs/tank2.ltl", hand));
}

#[test]
fn the_main_job_refuses_recordings_it_cannot_learn_a_plant_from_with_no_result_folder() {
    let dir = Dir::new();
    let traces = short_tank(dir.path());
    let out = dir.path().join("t");
    let o = main_job_learning(&[
        "--traces",
        traces.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
    .output();
    refused_as_too_short(&o, &out);
}

#[test]
fn the_main_job_takes_one_plant_read_or_learned_and_the_learners_options_with_learning() {
    let dir = Dir::new();
    let out = dir.path().join("t");
    let main = |args: &[&str]| {
        let head = ["--ltl", "specs/tank2.ltl", "--out", out.to_str().unwrap()];
        synth(&[&head[..], args].concat())
    };
    let plant = ["--plant", "smv/tank_surrogate.smv"];
    let both = main(&[&plant[..], &["--learn-plant"]].concat());
    let observe = main(&[&plant[..], &["--observe", "specs/tank2.observers"]].concat());
    let slack = main(&[&plant[..], &["--slack", "2"]].concat());
    let neither = main(&[]);
    for (o, says) in [
        (both, "cannot be used with"),
        (observe, "cannot be used with"),
        (slack, "cannot be used with"),
        (neither, "--learn-plant"),
    ] {
        assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
        assert!(text(&o.stderr).contains(says), "{}", text(&o.stderr));
    }
    assert!(!out.exists());
}

#[test]
fn a_learned_plant_never_replaces_an_input_in_the_output_folder() {
    // The observers, or the assumptions, where the learned plant would go.
    let observers = std::fs::read_to_string("specs/tank2.observers").unwrap();
    for (flag, source) in [
        ("--observe", observers.as_str()),
        ("--assume", "ordered: G ((ul -> ml) & (ml -> ll))\n"),
    ] {
        let dir = Dir::new();
        let out = dir.path().join("t");
        std::fs::create_dir(&out).unwrap();
        let input = out.join("plant.smv");
        std::fs::write(&input, source).unwrap();
        // Refused when the folder is taken, before any work: no NuSMV is needed to tell.
        let mut args = vec![
            "--traces",
            "specs/tank2.traces",
            flag,
            input.to_str().unwrap(),
        ];
        if flag == "--assume" {
            args.extend(["--observe", "specs/tank2.observers"]);
        }
        args.extend(["--out", out.to_str().unwrap()]);
        let o = main_job_learning(&args)
            .nusmv(Path::new("/nonexistent/NuSMV"))
            .output();
        assert_eq!(o.status.code(), Some(4), "{flag}: {}", text(&o.stderr));
        assert!(
            text(&o.stderr).contains("would replace or remove the input"),
            "{flag}: {}",
            text(&o.stderr)
        );
        let left: Vec<_> = std::fs::read_dir(&out).unwrap().collect();
        assert_eq!(left.len(), 1, "{left:?}");
        assert_eq!(std::fs::read_to_string(&input).unwrap(), source);
    }
}

/// `--assume`: the recordings are checked against the user's assumptions about the plant; one
/// they break is named with the file, line and first violating step, and nothing is written;
/// assumptions they keep are listed in the plant's header; an assumption about a controller
/// output is refused by line.
#[test]
fn assumptions_are_checked_on_the_recordings_and_named_in_the_header() {
    let dir = Dir::new();
    let learn_with = |assumptions: &str, out: &Path| {
        let file = dir.path().join("tank.assume");
        std::fs::write(&file, assumptions).unwrap();
        synth(&[
            "learn-plant",
            "--traces",
            "specs/tank2.traces",
            "--assume",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let kept = dir.path().join("kept.smv");
    let o = learn_with(
        "-- a level covers every sensor below the highest it reaches\nordered: G ((ul -> ml) & (ml -> ll))\n",
        &kept,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let smv = std::fs::read_to_string(&kept).unwrap();
    assert!(
        smv.contains("-- Assumed (from ") && smv.contains("tank.assume): ordered;"),
        "{smv}"
    );

    let broken = dir.path().join("broken.smv");
    let o = learn_with("dry: G !ul\n", &broken);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("the recordings contradict the assumption dry (")
            && err.contains("tank.assume:1): first at specs/tank2.traces:"),
        "{err}"
    );
    assert!(!broken.exists());

    let o = learn_with("shut: G !(inlet & ul)\n", &broken);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr)
            .contains("tank.assume:1: the assumption shut reads the controller output inlet"),
        "{}",
        text(&o.stderr)
    );
    assert!(!broken.exists());
}

/// `o` refused the short tank recordings by name (the outlet never acts), and `out` was not
/// written.
fn refused_as_too_short(o: &std::process::Output, out: &Path) {
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("short.traces") && err.contains("outlet is never on"),
        "{err}"
    );
    assert!(!out.exists());
}
