//! `synth learn-plant` and `synth compare-plants` on the shipped cases: the learned plant
//! admits every recording, the main job with it gives a machine NuSMV verifies against the
//! hand-written surrogate too, and recordings too short to learn from are refused by name
//! with nothing written.

use crate::common::{nusmv_or_skip, synth, text, Dir};
use std::path::{Path, PathBuf};

/// `synth learn-plant` on `traces` with `observers`; the plant file written.
fn learn(traces: &str, observers: &str, dir: &Path) -> PathBuf {
    let out = dir.join("plant.smv");
    let o = synth(&[
        "learn-plant",
        "--traces",
        traces,
        "--observe",
        observers,
        "--out",
        out.to_str().unwrap(),
    ]);
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
    let plant = learn("specs/tank2.traces", "specs/tank2.observers", dir.path());
    let ecc = main_job(
        &n.path,
        "specs/tank2.ltl",
        &plant,
        "specs/tank2.traces",
        &dir.path().join("m"),
    );
    let hand = Path::new("smv/tank_surrogate.smv");
    assert!(verified(&n.path, &ecc, "specs/tank2.ltl", hand));
    // Bounded inclusion: the hand-written closed loop's random runs are runs of the learned
    // plant (at least 99% of them).
    let o = synth(&[
        "compare-plants",
        "--ecc",
        ecc.to_str().unwrap(),
        "--plants",
        "smv/tank_surrogate.smv",
        plant.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let first = text(&o.stdout)
        .lines()
        .next()
        .unwrap_or_default()
        .to_string();
    let admitted: usize = first.split(' ').next().unwrap().parse().unwrap();
    assert!(admitted >= 990, "{first}");
}

#[test]
fn the_distribution_plant_learned_verifies_a_machine_and_refutes_the_recordings_own() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let traces = "specs/distribution.csv";
    let plant = learn(traces, "specs/distribution.observers", dir.path());
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
    let ltl = "specs/distribution.ltl";
    let ecc = main_job(&n.path, ltl, &plant, traces, &dir.path().join("m"));
    let hand = Path::new("smv/distribution_surrogate.smv");
    assert!(verified(&n.path, &ecc, ltl, hand));
    // Not vacuous: the machine of the recordings alone, which the hand-written plant
    // refutes, is refuted by the learned plant too.
    let own = dir.path().join("own");
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
    assert!(!verified(&n.path, &own, ltl, hand));
    assert!(!verified(&n.path, &own, ltl, &plant));
}

#[test]
fn the_pnp_plant_learned_admits_every_recording() {
    let dir = Dir::new();
    let plant = learn("specs/pnp.traces", "specs/pnp.observers", dir.path());
    let smv = std::fs::read_to_string(plant).unwrap();
    assert!(
        smv.starts_with("-- Surrogate plant learned by `synth learn-plant` from specs/pnp.traces")
    );
    assert!(smv.contains(
        "MODULE plant(c1Extend, c1Retract, c2Extend, c2Retract, vcExtend, vacuum_on, vacuum_off)"
    ));
    // The pieces the operator puts on the tracks are the environment's: never forced to
    // appear, and free at the start.
    for piece in ["pp1", "pp2", "pp3"] {
        let line = (smv.lines())
            .find(|l| l.starts_with(&format!("--   {piece}:")))
            .unwrap_or_default();
        assert!(
            line.ends_with("(the environment's: free where seen changing)"),
            "{line}"
        );
        assert!(!smv.contains(&format!("wait_up_{piece}")), "{smv}");
    }
}

#[test]
fn recordings_where_an_output_never_acts_are_refused_by_name_with_nothing_written() {
    let dir = Dir::new();
    // The first scans of the tank: the outlet is never opened.
    let full = std::fs::read_to_string("specs/tank2.traces").unwrap();
    let first = full.lines().nth(1).unwrap();
    let short: Vec<&str> = first.split("; ").take(12).collect();
    let traces = dir.path().join("short.traces");
    std::fs::write(
        &traces,
        format!("1\n{};\n", short.join("; ").trim_end_matches(';')),
    )
    .unwrap();
    for names in ["inputs", "outputs"] {
        std::fs::copy(
            format!("specs/tank2.{names}"),
            dir.path().join(format!("short.{names}")),
        )
        .unwrap();
    }
    let out = dir.path().join("plant.smv");
    let o = synth(&[
        "learn-plant",
        "--traces",
        traces.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("short.traces") && err.contains("outlet is never on"),
        "{err}"
    );
    assert!(!out.exists());
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
