//! Plants in NuSMV's language as models written for other work use it: submodule instances
//! (two levels deep, parameters passed through), `next()` of the controller's outputs, the
//! controller's output event `CNF`, defines over instances. The main job and `synth verify`
//! take them with NuSMV as the judge; the in-process engines say what they do not read, and
//! where. Needs NuSMV: skipped with a note where it is not installed, failing under CI=true.

use crate::common::{nusmv_or_skip, text, Dir, TestCommand};
use std::path::Path;
use std::process::Output;

/// `synth` with `args`, checking with the NuSMV at `nusmv`.
fn with_nusmv(nusmv: &Path, args: &[&str]) -> Output {
    TestCommand::new().args(args).nusmv(nusmv).output()
}

/// `synth verify` of the machine in `out` against `ltl` and `plant`.
fn verify(nusmv: &Path, out: &Path, ltl: &str, plant: &str) -> Output {
    let json = out.join("SynthesizedFB.json");
    let json = json.to_str().unwrap();
    with_nusmv(
        nusmv,
        &["verify", "--ecc", json, "--ltl", ltl, "--plant", plant],
    )
}

/// The shipped Pick-and-Place surrogate with one more module, instantiated inside `plant`.
fn surrogate_with_a_submodule(dir: &Path) -> String {
    let text = std::fs::read_to_string("smv/pnp_surrogate.smv").unwrap();
    let declared = "    dropped : boolean;\n";
    assert!(text.contains(declared));
    let text = text.replacen(
        declared,
        &format!("{declared}    aux : helper(vs);\n    aux2 : helper(vac);\n"),
        1,
    );
    let helper = "MODULE helper(x)\nVAR\n    seen : boolean;\nASSIGN\n    \
        init(seen) := FALSE;\n    next(seen) := seen | x;\n\n";
    let file = dir.join("pnp_submodule.smv");
    std::fs::write(&file, format!("{helper}{text}")).unwrap();
    file.to_str().unwrap().to_string()
}

#[test]
fn the_surrogate_with_a_submodule_instance_works_in_the_main_job_and_in_verify() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let plant = surrogate_with_a_submodule(dir.path());
    let out = dir.path().join("out");
    let o = with_nusmv(
        &n.path,
        &[
            "--ltl",
            "specs/pnp.ltl",
            "--plant",
            &plant,
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let err = text(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        text(&o.stdout)
            .contains("verified: all 8 properties hold (NuSMV), 10 scenarios reproduced"),
        "{}",
        text(&o.stdout)
    );
    // The in-process engines read the plant with its submodule flattened: they judge
    // candidates (a counterexample found in process), NuSMV verifies the result.
    assert!(
        !err.contains("does not read this closed loop") && err.contains("in-process"),
        "{err}"
    );
    let model = std::fs::read_to_string(out.join("closed_loop.smv")).unwrap();
    assert!(model.contains("aux : helper(vs);"), "{model}");
    let v = verify(&n.path, &out, "specs/pnp.ltl", &plant);
    assert!(v.status.success(), "{}", text(&v.stderr));
    assert!(text(&v.stdout).contains("verified: all 8 properties hold"));
    let json = std::fs::read_to_string(out.join("SynthesizedFB.json")).unwrap();
    let ecc = fbsynth::export::json::read_json(&json, Path::new("SynthesizedFB.json")).unwrap();
    crate::cases::pnp::generate().check(&ecc).unwrap();
}

const WRAPPED: &str = "tests/data/closed_loop/lamp_wrapped_plant.smv";

#[test]
fn a_plant_wrapping_modules_that_read_cnf_and_next_outputs_works_in_the_main_job_and_verify() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let o = with_nusmv(
        &n.path,
        &[
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            WRAPPED,
            "--traces",
            "tests/data/closed_loop/lamp.traces",
            "--out",
            out.path().to_str().unwrap(),
        ],
    );
    let err = text(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        text(&o.stdout).contains("verified: all 2 properties hold"),
        "{}",
        text(&o.stdout)
    );
    // The submodules are read; `next()` of a controller output is not: the construct is
    // named with its line in the submodule, and NuSMV takes over.
    assert!(
        err.contains(&format!(
            "the in-process checker does not read this closed loop: {WRAPPED}:11:"
        )) && err.contains("next(CNF)")
            && err.contains("NuSMV judges every candidate"),
        "{err}"
    );
    let model = std::fs::read_to_string(out.path().join("closed_loop.smv")).unwrap();
    assert!(
        model.contains("plant : plant(ctrl.CNF, ctrl.lamp);"),
        "{model}"
    );
    let v = verify(
        &n.path,
        out.path(),
        "tests/data/closed_loop/lamp.ltl",
        WRAPPED,
    );
    assert!(v.status.success(), "{}", text(&v.stderr));
    assert!(text(&v.stdout).contains("verified: all 2 properties hold"));
    // The machine is the one the plain lamp plant gets too: NuSMV verifies it there.
    let v = verify(
        &n.path,
        out.path(),
        "tests/data/closed_loop/lamp.ltl",
        "tests/data/closed_loop/lamp_plant.smv",
    );
    assert!(v.status.success(), "{}", text(&v.stderr));
}

/// A property over the plant's free button alone is named before any candidate, with why
/// (here a tautology: NuSMV still judges it, and it holds).
#[test]
fn properties_no_controller_can_affect_are_named_before_any_candidate() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let ltl = dir.path().join("lamp.ltl");
    let spec = std::fs::read_to_string("tests/data/closed_loop/lamp.ltl").unwrap();
    std::fs::write(
        &ltl,
        format!("{spec}pressed_or_not: G (button -> button)\n"),
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = with_nusmv(
        &n.path,
        &[
            "--ltl",
            ltl.to_str().unwrap(),
            "--plant",
            "tests/data/closed_loop/lamp_plant.smv",
            "--traces",
            "tests/data/closed_loop/lamp.traces",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let err = text(&o.stderr);
    let line =
        "warning: no controller can affect property pressed_or_not: it reads only 'button', \
        which no controller output influences; its verdict is the plant's alone";
    let at = err.find(line).unwrap_or_else(|| panic!("{err}"));
    let bounds = err.find("lower bounds from the recorded inputs").unwrap();
    assert!(at < bounds, "{err}");
    assert_eq!(err.matches("no controller can affect").count(), 1, "{err}");
    assert!(o.status.success(), "{err}");
    assert!(text(&o.stdout).contains("verified: all 3 properties hold"));
}

/// A plant whose names differ from the recordings' is coupled by `--couple`, in the main job
/// and in `synth verify`; without it the first unknown name is refused, with a wrong pair
/// the pair is named.
#[test]
fn couple_maps_plant_names_to_controller_names() {
    let Some(n) = nusmv_or_skip() else { return };
    let out = Dir::new();
    let plant = "tests/data/closed_loop/lamp_renamed_plant.smv";
    let ltl = "tests/data/closed_loop/lamp_renamed.ltl";
    let couple = [
        "--couple",
        "plant.light=lamp",
        "--couple",
        "plant.pushed=button",
    ];
    let mut args = vec![
        "-q",
        "--ltl",
        ltl,
        "--plant",
        plant,
        "--traces",
        "tests/data/closed_loop/lamp.traces",
        "--out",
        out.path().to_str().unwrap(),
    ];
    args.extend_from_slice(&couple);
    let o = with_nusmv(&n.path, &args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("verified: all 2 properties hold"));
    let model = std::fs::read_to_string(out.path().join("closed_loop.smv")).unwrap();
    assert!(
        model.contains("ctrl : ECC(TRUE, plant.pushed, plant.timeout);"),
        "{model}"
    );
    assert!(model.contains("plant : plant(ctrl.lamp);"), "{model}");
    let json = out.path().join("SynthesizedFB.json");
    let json = json.to_str().unwrap();
    let mut verify = vec!["verify", "--ecc", json, "--ltl", ltl, "--plant", plant];
    verify.extend_from_slice(&couple);
    let v = with_nusmv(&n.path, &verify);
    assert!(v.status.success(), "{}", text(&v.stderr));
    assert!(text(&v.stdout).contains("verified: all 2 properties hold"));
    let v = with_nusmv(&n.path, &verify[..7]);
    assert!(!v.status.success());
    assert!(
        text(&v.stderr).contains("plant parameter 'light' is not a controller output"),
        "{}",
        text(&v.stderr)
    );
    verify[10] = "plant.pressed=button";
    let v = with_nusmv(&n.path, &verify);
    assert!(
        text(&v.stderr).contains(
            "--couple plant.pressed=button: module plant declares no variable or define 'pressed'"
        ),
        "{}",
        text(&v.stderr)
    );
}

/// A plant of 12 free sensors without dynamics, 7 outputs, 67 recorded steps: the in-process
/// checker predicts its size before exploring and hands over to NuSMV, which verifies the
/// machine; the property over the sensors alone is named.
#[test]
fn a_plant_of_twelve_free_inputs_gets_a_verified_answer() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    fbsynth::cases::free_inputs::write_files(dir.path(), 12).unwrap();
    let file = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let out = file("out");
    let o = with_nusmv(
        &n.path,
        &[
            "--ltl",
            &file("free.ltl"),
            "--plant",
            &file("plant.smv"),
            "--out",
            &out,
        ],
    );
    let err = text(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        text(&o.stdout).contains("verified: all 2 properties hold (NuSMV), 3 scenarios reproduced"),
        "{}",
        text(&o.stdout)
    );
    assert!(
        err.contains("no controller can affect property tautology")
            && err.contains("at least 4096 × 4096: the plant's free inputs take 4096 combinations")
            && err.contains("NuSMV alone judges the candidates from here"),
        "{err}"
    );
}

/// `--couple-file`: the pairs of `--couple` in a file, one per line with `--` comments; a bad
/// line is named with the file and line.
#[test]
fn a_coupling_file_maps_plant_names_to_controller_names() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let pairs = dir.path().join("lamp.couple");
    std::fs::write(
        &pairs,
        "-- the renamed lamp\nplant.light=lamp   -- the output\n\nplant.pushed=button\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let plant = "tests/data/closed_loop/lamp_renamed_plant.smv";
    let ltl = "tests/data/closed_loop/lamp_renamed.ltl";
    let o = with_nusmv(
        &n.path,
        &[
            "-q",
            "--ltl",
            ltl,
            "--plant",
            plant,
            "--traces",
            "tests/data/closed_loop/lamp.traces",
            "--couple-file",
            pairs.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("verified: all 2 properties hold"));
    let json = out.join("SynthesizedFB.json");
    let (json, pairs_arg) = (json.to_str().unwrap(), pairs.to_str().unwrap());
    let verify = [
        "verify",
        "--ecc",
        json,
        "--ltl",
        ltl,
        "--plant",
        plant,
        "--couple-file",
        pairs_arg,
    ];
    let v = with_nusmv(&n.path, &verify);
    assert!(v.status.success(), "{}", text(&v.stderr));
    assert!(text(&v.stdout).contains("verified: all 2 properties hold"));
    std::fs::write(&pairs, "plant.light=lamp\nlight=lamp\n").unwrap();
    let v = with_nusmv(&n.path, &verify);
    assert!(!v.status.success());
    assert!(
        text(&v.stderr).contains(&format!(
            "{pairs_arg}:2: 'light=lamp': the left side names a plant signal, plant.SIGNAL"
        )),
        "{}",
        text(&v.stderr)
    );
}

/// Generated stations of cylinders and latching requests (seeds 1 to 4), each from one
/// recorded run of its reference controller: the main job's machine is verified by NuSMV
/// (every property holds) and is no larger than the reference (states, then transitions,
/// then literals).
#[test]
fn generated_stations_get_a_verified_machine_no_larger_than_their_reference() {
    let Some(n) = nusmv_or_skip() else { return };
    for seed in 1..=4 {
        let dir = Dir::new();
        let (_, station) = fbsynth::cases::station::write_files(dir.path(), seed).unwrap();
        let reference = station.reference().size();
        let file = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
        let o = with_nusmv(
            &n.path,
            &[
                "--json",
                "--ltl",
                &file("station.ltl"),
                "--plant",
                &file("plant.smv"),
                "--out",
                &file("out"),
            ],
        );
        let err = text(&o.stderr);
        assert!(o.status.success(), "seed {seed}: {err}");
        let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let report = std::fs::read_to_string(dir.path().join("out/verification.txt")).unwrap();
        let properties = station
            .properties()
            .lines()
            .filter(|l| l.contains(':') && !l.starts_with("--"))
            .count();
        assert_eq!(
            report.matches("\nHOLDS ").count(),
            properties,
            "seed {seed}: {report}"
        );
        let size = |key: &str| summary["size"][key].as_u64().unwrap() as usize;
        // No larger in the one order of sizes: states, then transitions, then literals.
        let found = (size("c"), size("t"), size("n"));
        assert!(
            found <= (reference.c, reference.t, reference.n),
            "seed {seed}: {} against the reference's {reference}",
            summary["size"]
        );
        // "Least" only where the machine meets the recordings' own lower bounds, as the
        // exact loop reported them.
        if summary["proven_least"] == true {
            let floor = lower_bounds(&err).unwrap_or_else(|| panic!("seed {seed}: {err}"));
            assert_eq!(found, floor, "seed {seed}: {err}");
        }
        // Seed 2's loop usually stalls and hands over, and the guide's machine, made smaller,
        // meets them. Which candidates the loop meets depends on when the lower bounds from
        // the second core reach it, so on a loaded host it may find a verified machine
        // itself before it stalls.
        if seed == 2 && err.contains("guide takes over") {
            assert_eq!(summary["proven_least"], true, "seed {seed}: {err}");
        }
    }
}

/// The last lower bounds of the recordings alone in a run's progress (C, T at it, N at both).
fn lower_bounds(progress: &str) -> Option<(usize, usize, usize)> {
    let line = (progress.lines().rev()).find_map(|l| l.split_once("recorded inputs alone: "))?;
    let numbers: Vec<usize> = (line.1.split(", "))
        .take(3)
        .map(|part| part.split(">= ").nth(1)?.split(' ').next()?.parse().ok())
        .collect::<Option<_>>()?;
    match numbers[..] {
        [c, t, n] => Some((c, t, n)),
        _ => None,
    }
}
