//! The rules a plant must follow before any verdict counts: it accepts every output the
//! controller can give (receptive), its fairness constraints read no controller output, every
//! closed loop is free of deadlocks, and it can produce the recorded steps.

use crate::common::{nusmv_or_skip, text, Dir, TestCommand};
use std::path::Path;
use std::process::Output;

const DIR: &str = "tests/data/closed_loop";

/// The main job on the lamp's names with `ltl`, `plant` and `traces` of the lamp folder.
fn main_job(nusmv: &Path, ltl: &str, plant: &str, traces: &str, out: &Path) -> Output {
    TestCommand::new()
        .nusmv(nusmv)
        .args(["-q", "--ltl", &format!("{DIR}/{ltl}")])
        .args(["--plant", &format!("{DIR}/{plant}")])
        .args(["--traces", &format!("{DIR}/{traces}")])
        .args(["--input-names", &format!("{DIR}/lamp.inputs")])
        .args(["--output-names", &format!("{DIR}/lamp.outputs")])
        .args(["--out", out.to_str().unwrap()])
        .output()
}

/// The machine that latches the lamp, inferred from `latch.traces` into `dir`: its JSON file.
fn latch_machine(dir: &Path) -> std::path::PathBuf {
    let o = TestCommand::new()
        .args(["infer", "-q", "--traces", &format!("{DIR}/latch.traces")])
        .args(["--input-names", &format!("{DIR}/lamp.inputs")])
        .args(["--output-names", &format!("{DIR}/lamp.outputs")])
        .args(["--out", dir.to_str().unwrap()])
        .output();
    assert!(o.status.success(), "{}", text(&o.stderr));
    dir.join("SynthesizedFB.json")
}

/// A plant that blocks the runs where the lamp stays on (a TRANS or an INVAR over the
/// controller's output) would make `G (lamp -> X !lamp)` hold for the machine that latches
/// the lamp: it is refused before synthesis (exit 4), with the state and the outputs it
/// refuses, and nothing is called verified.
#[test]
fn a_plant_that_blocks_the_controller_is_refused_before_synthesis() {
    let Some(n) = nusmv_or_skip() else { return };
    for (plant, refused) in [
        ("blocking_trans_plant.smv", "dead = TRUE"),
        (
            "blocking_invar_plant.smv",
            "no successor for the controller outputs lamp = TRUE",
        ),
    ] {
        let out = Dir::new();
        let o = main_job(&n.path, "short.ltl", plant, "latch.traces", out.path());
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(4), "{plant}: {err}");
        assert!(
            err.contains(&format!("{DIR}/{plant}: the plant is not receptive"))
                && err.contains(refused),
            "{plant}: {err}"
        );
        assert!(!text(&o.stdout).contains("verified"), "{plant}");
        assert!(!out.path().join("SynthesizedFB.json").exists(), "{plant}");
    }
}

/// A fairness constraint over the controller's output (`FAIRNESS !lamp`) discards every run
/// where the lamp stays on, and with them the violations of `goes_out`: refused with its line.
#[test]
fn fairness_over_a_controller_output_is_refused_with_its_line() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let plant = "unfair_to_lamp_plant.smv";
    let o = main_job(&n.path, "lamp.ltl", plant, "latch.traces", out.path());
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{err}");
    assert!(
        err.contains(&format!(
            "{DIR}/{plant}:16: this FAIRNESS constraint reads the controller output 'lamp'"
        )),
        "{err}"
    );
    assert!(!text(&o.stdout).contains("verified"));
    // `verify`, with no synthesis before it, refuses the same plant the same way.
    let json = latch_machine(&out.path().join("m"));
    let o = TestCommand::new()
        .nusmv(&n.path)
        .args(["verify", "--ecc", json.to_str().unwrap()])
        .args(["--ltl", &format!("{DIR}/lamp.ltl")])
        .args(["--plant", &format!("{DIR}/{plant}")])
        .output();
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{err}");
    assert!(
        err.contains(&format!(
            "{DIR}/{plant}:16: this FAIRNESS constraint reads the controller output 'lamp'"
        )),
        "{err}"
    );
    assert!(!text(&o.stdout).contains("verified"));
}

/// `synth verify` checks a given machine with no synthesis before it: the machine that latches
/// the lamp, with the plant that ends every run where the lamp stays on, deadlocks in closed
/// loop, and NuSMV's `check_fsm` says so (exit 1), where its LTL verdict alone said "holds".
#[test]
fn a_closed_loop_that_deadlocks_is_not_verified() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let json = latch_machine(out.path());
    let o = TestCommand::new()
        .nusmv(&n.path)
        .args(["verify", "--ecc", json.to_str().unwrap()])
        .args(["--ltl", &format!("{DIR}/short.ltl")])
        .args(["--plant", &format!("{DIR}/blocking_trans_plant.smv")])
        .output();
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("deadlocks") && err.contains("has no successor"),
        "{err}"
    );
    assert!(!text(&o.stdout).contains("verified"), "{}", text(&o.stdout));
}

/// A plant that cannot show what was recorded (a button defined as never pressed, while the
/// recordings press it; or as always pressed, while they release it) is refused (exit 4)
/// naming the first recorded step it cannot produce and where the plant declares the inputs;
/// the recordings' verdict on `G button` is not turned into a claim about controllers.
#[test]
fn a_plant_that_cannot_produce_the_recordings_is_refused_at_the_first_step() {
    let Some(n) = nusmv_or_skip() else { return };
    for (ltl, plant, step) in [
        ("lamp.ltl", "never_pressed_plant.smv", 2),
        ("pressed.ltl", "always_pressed_plant.smv", 1),
    ] {
        let out = Dir::new();
        let o = main_job(&n.path, ltl, plant, "lamp.traces", out.path());
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(4), "{plant}: {err}");
        assert!(
            err.contains(&format!(
                "{DIR}/lamp.traces:2 step {step}: the plant {DIR}/{plant} cannot produce this recorded step"
            )) && err.contains(&format!("button ({DIR}/{plant}:")),
            "{plant}: {err}"
        );
        assert!(!err.contains("no controller"), "{plant}: {err}");
        assert!(!text(&o.stdout).contains("verified"), "{plant}");
    }
}

/// A plant whose names differ from the recordings' (coupled by `--couple`) and whose `INVAR`
/// holds the button released is refused at the recorded press, naming the input it refuses and
/// the plant line that forbids it.
#[test]
fn the_plant_line_that_forbids_a_recorded_step_is_named_also_under_couple() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let plant = format!("{DIR}/released_renamed_plant.smv");
    let o = TestCommand::new()
        .nusmv(&n.path)
        .args(["-q", "--ltl", &format!("{DIR}/lamp_renamed.ltl")])
        .args(["--plant", &plant])
        .args(["--traces", &format!("{DIR}/lamp.traces")])
        .args([
            "--couple",
            "plant.light=lamp",
            "--couple",
            "plant.pushed=button",
        ])
        .args(["--out", out.path().to_str().unwrap()])
        .output();
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{err}");
    assert!(
        err.contains(&format!(
            "{DIR}/lamp.traces:2 step 2: the plant {plant} cannot produce this recorded step"
        )),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "no reachable state shows button = TRUE under these outputs; the plant lines that decide it: pushed ({plant}:17: `INVAR !pushed`)"
        )),
        "{err}"
    );
    assert!(!text(&o.stdout).contains("verified"));
}

/// Recordings that violate `G !lamp` leave no controller that reproduces them only where the
/// plant produces them as recorded: with a button that alternates at every step (it shows
/// each recorded value, but not two releases in a row), the refusal says so and names the
/// step, instead of claiming that no controller exists.
#[test]
fn the_recordings_verdict_claims_no_controller_only_where_the_plant_replays_them() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let o = main_job(
        &n.path,
        "dark.ltl",
        "lamp_plant.smv",
        "lamp.traces",
        out.path(),
    );
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{err}");
    assert!(
        err.contains("no controller that reproduces them can satisfy it"),
        "{err}"
    );
    let o = main_job(
        &n.path,
        "dark.ltl",
        "alternating_plant.smv",
        "lamp.traces",
        out.path(),
    );
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{err}");
    assert!(
        err.contains(&format!(
            "the plant cannot produce the recorded runs as recorded (first at {DIR}/lamp.traces:2 step 4)"
        )) && !err.contains("no controller"),
        "{err}"
    );
}
