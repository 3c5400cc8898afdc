//! What `synth` makes of NuSMV's answers: each verdict is the one on the property asked for by
//! name, whatever order or text NuSMV answers with; a counterexample cut short is an error, not
//! a run; output without end is cut at a bound; and nothing the user names reaches the model
//! outside a comment. Wrappers around the real NuSMV, and fakes, play a NuSMV that misbehaves.

use crate::common::{nusmv_or_skip, text, Dir, TestCommand};
use std::path::{Path, PathBuf};
use std::process::Output;

const DIR: &str = "tests/data/closed_loop";

/// An executable shell script `dir/NuSMV` with `body`.
fn script(dir: &Path, body: &str) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let path = dir.join("NuSMV");
    std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path
}

/// The real NuSMV `real` with its standard output through the shell filter `filter`.
fn filtered(dir: &Path, real: &Path, filter: &str) -> PathBuf {
    script(dir, &format!("'{}' \"$@\" | {filter}", real.display()))
}

/// `synth verify` of the two-state lamp machine (a press lights the lamp, the timeout puts it
/// out) against `spec`, written to `dir/spec.ltl`, and the plant file `plant`.
fn verify(nusmv: &Path, dir: &Path, spec: &str, plant: &Path, extra: &[&str]) -> Output {
    let ltl = dir.join("spec.ltl");
    std::fs::write(&ltl, spec).unwrap();
    TestCommand::new()
        .args(["verify", "--ecc", &format!("{DIR}/lamp_two_state.json")])
        .arg("--ltl")
        .arg(&ltl)
        .arg("--plant")
        .arg(plant)
        .args(extra)
        .nusmv(nusmv)
        .output()
}

fn lamp_plant() -> PathBuf {
    PathBuf::from(format!("{DIR}/lamp_plant.smv"))
}

/// Two properties whose texts differ only in their parentheses, with different verdicts. A
/// NuSMV that answers them in another order than the file's (here a wrapper turns a plain
/// `check_ltlspec` into checks of `b` then `a`) cannot swap their verdicts: each is asked for
/// by name, and the answer between two markers is the one on the property asked.
#[test]
fn each_verdict_is_the_one_on_the_property_asked() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let reorders = script(
        dir.path(),
        &format!(
            "while IFS= read -r line; do\n  case \"$line\" in\n    check_ltlspec) printf 'check_ltlspec -P b\\ncheck_ltlspec -P a\\n';;\n    *) printf '%s\\n' \"$line\";;\n  esac\ndone | exec '{}' \"$@\"",
            n.path.display()
        ),
    );
    let spec = "a: G (lamp -> X lamp)\nb: (G lamp) -> X lamp\n";
    for nusmv in [&n.path, &reorders] {
        let o = verify(nusmv, dir.path(), spec, &lamp_plant(), &[]);
        let out = text(&o.stdout);
        assert_eq!(o.status.code(), Some(1), "{out}{}", text(&o.stderr));
        assert!(out.contains("VIOLATED a (line 1)"), "{out}");
        assert!(out.contains("HOLDS    b (line 2)"), "{out}");
    }
}

/// `V` and `T`, which NuSMV reprints in other words (`a V b` as `!(!a U !b)`), are verified
/// like every other operator, in the main job as in `verify`.
#[test]
fn release_and_trigger_are_verified() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let spec = dir.path().join("r.ltl");
    std::fs::write(&spec, "r: button V !lamp\nt: G (lamp T on_for <= 2)\n").unwrap();
    let o = TestCommand::new()
        .args(["-q", "--ltl"])
        .arg(&spec)
        .args(["--plant", &format!("{DIR}/lamp_plant.smv")])
        .args(["--traces", &format!("{DIR}/lamp.traces")])
        .arg("--out")
        .arg(dir.path().join("out"))
        .nusmv(&n.path)
        .output();
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let o = verify(
        &n.path,
        dir.path(),
        "r: button V lamp\n",
        &lamp_plant(),
        &[],
    );
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("VIOLATED r (line 1): button V lamp"));
}

/// NuSMV's counterexample without its loop marker, or without the values of a name the
/// property reads (here: lines dropped from the real NuSMV's output), is an error that says
/// what is missing, not a run whose last step repeats forever or whose values are unknown.
#[test]
fn a_counterexample_cut_short_is_an_error() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    for (dropped, message) in [
        (
            "-- Loop starts here",
            "NuSMV's counterexample of `never_lit` is incomplete: no loop marker (`-- Loop starts here`) before its last state",
        ),
        (
            "  lamp = ",
            "NuSMV's counterexample of `never_lit` is incomplete: no value for `lamp` in state 0 (0-based)",
        ),
    ] {
        let nusmv = filtered(
            dir.path(),
            &n.path,
            &format!("grep --line-buffered -v -e '^{dropped}'"),
        );
        let o = verify(&nusmv, dir.path(), "never_lit: G !lamp\n", &lamp_plant(), &[]);
        assert_eq!(o.status.code(), Some(4), "{}", text(&o.stdout));
        assert_eq!(text(&o.stderr).trim(), format!("error: {message}"));
    }
}

/// A NuSMV that prints without end, in lines or in one endless line, is killed once an answer
/// passes the bound, and the error names the bound; synth keeps its memory (here it runs in
/// 1 GiB of address space: reading it all would abort).
#[test]
fn output_without_end_is_cut_at_a_bound() {
    let dir = Dir::new();
    for body in [
        "exec yes 'NuSMV > -- specification  G lamp  is true'",
        "yes | tr -d '\\n'",
    ] {
        let nusmv = script(dir.path(), body);
        let ltl = dir.path().join("spec.ltl");
        std::fs::write(&ltl, "never_lit: G !lamp\n").unwrap();
        let o = TestCommand::new()
            .args(["verify", "--ecc", &format!("{DIR}/lamp_two_state.json")])
            .arg("--ltl")
            .arg(&ltl)
            .args(["--plant", &format!("{DIR}/lamp_plant.smv")])
            .nusmv(&nusmv)
            .address_space(1 << 30)
            .output();
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(4), "{body}: {err}");
        assert!(
            err.starts_with(
                "error: NuSMV printed more than 16777216 bytes on stdout in one answer"
            ),
            "{body}: {err}"
        );
    }
}

/// A plant path holding line breaks (`p`, `INVAR !lamp`, `--.smv`) stays in the comment that
/// names the plant in the model: the machine that lights the lamp is not verified against
/// `G !lamp`, and the model has no `INVAR` line.
#[test]
fn a_plant_path_never_becomes_model_text() {
    let Some(n) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    let plant = dir.path().join("p\nINVAR !lamp\n--.smv");
    std::fs::copy(lamp_plant(), &plant).unwrap();
    let out = dir.path().join("out");
    let o = verify(
        &n.path,
        dir.path(),
        "never_lit: G !lamp\n",
        &plant,
        &["--out", out.to_str().unwrap()],
    );
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("VIOLATED never_lit (line 1)"));
    let model = std::fs::read_to_string(out.join("closed_loop.smv")).unwrap();
    assert!(
        !model.lines().any(|l| l.trim_start().starts_with("INVAR")),
        "{model}"
    );
    assert!(model.contains("p\\nINVAR !lamp\\n--.smv\n"), "{model}");
}
