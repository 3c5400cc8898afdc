//! Every XML file fbsynth writes, validated by a real validator (libxml2's `xmllint`) against
//! a schema written in the project from the standard it follows (tests/schemas/): `.fbt`
//! against the IEC 61499-2 LibraryElement DTD, PNML against the ISO/IEC 15909-2 P/T net
//! grammar (RELAX NG), PLCopen XML against the TC6 2.01 XML Schema. (XES: `events.rs`.) Each
//! schema is also shown to refuse what its standard refuses, so a pass means something.
//!
//! Without xmllint the tests are skipped with a note, except under `CI=true`, where
//! `.ci/install-xmllint.sh` provides it and its absence fails them.
//!
//! The JSON fbsynth writes is validated by boon (draft 2020-12) against the schemas `synth
//! schema` prints: every machine against the machine contract, every summary (`summary.json`
//! and `--json`) against the schema of the summaries.

use crate::common::{
    nusmv_or_skip, printed_schema, root, synth, synth_in, text, tool_or_skip, xmllint, Dir,
};
use std::path::{Path, PathBuf};

const FBT: &str = "iec61499-library-element.dtd";
const PNML: &str = "pnml-ptnet.rng";
const PNML_PROM: &str = "pnml-prom.rng";
const PLCOPEN: &str = "plcopen-tc6-0201.xsd";

/// The schema of a file fbsynth wrote, by its extension.
fn schema_of(file: &Path) -> Option<&'static str> {
    match file.extension()?.to_str()? {
        "fbt" => Some(FBT),
        "pnml" => Some(PNML),
        "xml" => Some(PLCOPEN),
        _ => None,
    }
}

/// Machines that reach every branch of the emitters: the shipped ones, the benchmark cases'
/// reference controllers, and the corner cases (no inputs, no transitions, keep and flip).
pub(crate) fn machines(dir: &Path) -> Vec<PathBuf> {
    let mut files = vec![
        root().join("tests/data/export/cylinder.json"),
        root().join("specs/distribution_reference.json"),
    ];
    let written = [
        ("pnp", crate::cases::pnp::reference()),
        ("tank1", crate::cases::tank::Program::FillDrain.reference()),
        ("tank2", crate::cases::tank::Program::Cycles.reference()),
    ];
    for (name, ecc) in written {
        let path = dir.join(format!("{name}.json"));
        std::fs::write(&path, fbsynth::export::json::to_string(&ecc)).unwrap();
        files.push(path);
    }
    let corners = [
        (
            "no_transitions",
            r#"{"inputs": ["a"], "outputs": ["z"], "initial_outputs": "1",
                "states": [{"name": "idle", "algorithm": "x"}], "transitions": []}"#,
        ),
        (
            "no_inputs",
            r#"{"inputs": [], "outputs": ["z", "w"], "initial_outputs": "00",
                "states": [{"name": "a", "algorithm": "10"}, {"name": "b", "algorithm": "x1"}],
                "transitions": [{"from": 0, "to": 1, "guard": "TRUE"},
                                {"from": 1, "to": 0, "guard": "TRUE"}]}"#,
        ),
    ];
    for (name, json) in corners {
        let path = dir.join(format!("{name}.json"));
        std::fs::write(&path, json).unwrap();
        files.push(path);
    }
    files
}

/// Asserts that every file in `files` with a schema validates against it; returns how many
/// were checked per schema.
fn validate_all(
    xmllint_bin: &Path,
    files: &[PathBuf],
) -> std::collections::BTreeMap<&'static str, usize> {
    let mut checked = std::collections::BTreeMap::new();
    for file in files {
        let Some(schema) = schema_of(file) else {
            continue;
        };
        let (ok, messages) = xmllint(xmllint_bin, schema, file);
        assert!(ok, "{} against {schema}:\n{messages}", file.display());
        *checked.entry(schema).or_insert(0) += 1;
    }
    checked
}

fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
}

/// `synth export` of every machine in the XML formats, and the modular output (composite and
/// module types): all valid.
#[test]
fn every_exported_fbt_pnml_and_plcopen_file_validates() {
    let Some(xmllint_bin) = tool_or_skip("XMLLINT", "xmllint", ".ci/install-xmllint.sh") else {
        return;
    };
    let dir = Dir::new();
    let mut written = Vec::new();
    for (k, json) in machines(dir.path()).iter().enumerate() {
        let out = dir.path().join(format!("out{k}"));
        let o = synth_in(
            dir.path(),
            &[
                "export",
                "--ecc",
                json.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--name",
                "Machine",
                "--format",
                "fbt,pnml,plcopen",
            ],
        );
        assert!(
            o.status.success(),
            "{}: {}",
            json.display(),
            text(&o.stderr)
        );
        written.extend(files_in(&out));
    }
    let modular = dir.path().join("modular");
    let o = synth_in(
        dir.path(),
        &[
            "infer",
            "-q",
            "--modules",
            "2",
            "--traces",
            root()
                .join("tests/data/scenarios/lamps.traces")
                .to_str()
                .unwrap(),
            "--name",
            "Line",
            "--out",
            modular.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    written.extend(files_in(&modular));
    let checked = validate_all(&xmllint_bin, &written);
    // 7 machines in 3 formats, plus the composite (.fbt, PLCopen) and its 2 module types.
    assert_eq!(checked.get(FBT), Some(&10), "{checked:?}");
    assert_eq!(checked.get(PNML), Some(&7), "{checked:?}");
    assert_eq!(checked.get(PLCOPEN), Some(&8), "{checked:?}");
}

/// `synth events --pnml`: the ISO net validates against the ISO grammar; the ProM dialect
/// validates against its own grammar and is refused by the ISO one, as strict tools refuse it.
#[test]
fn event_log_nets_validate_in_both_dialects() {
    let Some(xmllint_bin) = tool_or_skip("XMLLINT", "xmllint", ".ci/install-xmllint.sh") else {
        return;
    };
    let dir = Dir::new();
    let json = dir.path().join("tank1.json");
    let tank = crate::cases::tank::Program::FillDrain.reference();
    std::fs::write(&json, fbsynth::export::json::to_string(&tank)).unwrap();
    let net = |dialect: &str| {
        let pnml = dir.path().join(format!("{dialect}.pnml"));
        let o = synth_in(
            root(),
            &[
                "events",
                "--log",
                "specs/tank/scenario1.csv",
                "--map",
                "specs/tank/tank.map",
                "--reset",
                crate::cases::tank::RESET,
                "--out",
                dir.path().join(format!("{dialect}.xes")).to_str().unwrap(),
                "--ecc",
                json.to_str().unwrap(),
                "--pnml",
                pnml.to_str().unwrap(),
                "--pnml-dialect",
                dialect,
            ],
        );
        assert!(o.status.success(), "{}", text(&o.stderr));
        pnml
    };
    let iso = net("iso");
    let (ok, messages) = xmllint(&xmllint_bin, PNML, &iso);
    assert!(ok, "{messages}");
    let prom = net("prom");
    let (ok, messages) = xmllint(&xmllint_bin, PNML_PROM, &prom);
    assert!(ok, "{messages}");
    let (ok, _) = xmllint(&xmllint_bin, PNML, &prom);
    assert!(!ok, "the ISO grammar takes the ProM dialect");
}

/// Each schema refuses a file its standard refuses: the emitted file, changed in one place.
#[test]
fn the_schemas_refuse_what_the_standards_refuse() {
    let Some(xmllint_bin) = tool_or_skip("XMLLINT", "xmllint", ".ci/install-xmllint.sh") else {
        return;
    };
    let dir = Dir::new();
    let out = dir.path().join("out");
    let o = synth_in(
        dir.path(),
        &[
            "export",
            "--ecc",
            root()
                .join("tests/data/export/cylinder.json")
                .to_str()
                .unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--name",
            "Cylinder",
            "--format",
            "fbt,pnml,plcopen",
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let cases: [(&str, &str, &str, &str, &str); 9] = [
        // (file, schema, what, from, to)
        (
            "Cylinder.fbt",
            FBT,
            "no VersionInfo (VersionInfo+)",
            "<VersionInfo Organization=\"fbsynth\" Version=\"1.0\" Author=\"fbsynth\" Date=\"\"/>",
            "",
        ),
        (
            "Cylinder.fbt",
            FBT,
            "a transition without a condition",
            "Condition=\"REQ[atEnd]\"",
            "",
        ),
        (
            "Cylinder.pnml",
            PNML,
            "no PNML namespace",
            " xmlns=\"http://www.pnml.org/version-2009/grammar/pnml\"",
            "",
        ),
        (
            "Cylinder.pnml",
            PNML,
            "the core-model type with markings",
            "grammar/ptnet\"",
            "grammar/pnmlcoremodel\"",
        ),
        (
            "Cylinder.pnml",
            PNML,
            "a marking that is not a number",
            "<initialMarking><text>1</text>",
            "<initialMarking><text>one</text>",
        ),
        (
            "Cylinder.pnml",
            PNML,
            "an arc to an unknown node",
            "target=\"p0\"",
            "target=\"nowhere\"",
        ),
        (
            "Cylinder.xml",
            PLCOPEN,
            "a creation time that is no xsd:dateTime",
            "creationDateTime=\"",
            "creationDateTime=\"yesterday ",
        ),
        (
            "Cylinder.xml",
            PLCOPEN,
            "an unknown POU type",
            "pouType=\"functionBlock\"",
            "pouType=\"block\"",
        ),
        (
            "Cylinder.xml",
            PLCOPEN,
            "no file header",
            "<fileHeader ",
            "<fileHeaderX ",
        ),
    ];
    for (file, schema, what, from, to) in cases {
        let original = std::fs::read_to_string(out.join(file)).unwrap();
        let (ok, messages) = xmllint(&xmllint_bin, schema, &out.join(file));
        assert!(ok, "{file}: {messages}");
        assert!(original.contains(from), "{file} has no {from}");
        let bad = dir.path().join(format!("bad_{file}"));
        std::fs::write(&bad, original.replacen(from, to, 1)).unwrap();
        let (ok, _) = xmllint(&xmllint_bin, schema, &bad);
        assert!(!ok, "{schema} takes {file} with {what}");
    }
}

/// `synth schema` is a JSON Schema a real validator (boon, draft 2020-12) compiles; every
/// machine synth writes, and the shipped ones, validate against it; it refuses a misspelt
/// field, a symbol no algorithm has and a newer format, as `synth` itself does.
#[test]
fn machines_validate_against_the_json_schema_synth_prints() {
    let dir = Dir::new();
    let (schemas, index) = printed_schema(dir.path(), &[]);
    let validate = |file: &Path| {
        let value: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
        schemas.validate(&value, index).map_err(|e| e.to_string())
    };
    let mut written = machines(dir.path());
    for (k, json) in machines(dir.path()).iter().enumerate() {
        let out = dir.path().join(format!("out{k}"));
        let o = synth_in(
            dir.path(),
            &[
                "export",
                "--ecc",
                json.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--format",
                "json",
            ],
        );
        assert!(o.status.success(), "{}", text(&o.stderr));
        written.push(out.join("SynthesizedFB.json"));
    }
    let modular = dir.path().join("modular");
    let o = synth_in(
        dir.path(),
        &[
            "infer",
            "-q",
            "--modules",
            "2",
            "--traces",
            root()
                .join("tests/data/scenarios/lamps.traces")
                .to_str()
                .unwrap(),
            "--out",
            modular.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let modules: Vec<PathBuf> = files_in(&modular)
        .into_iter()
        .filter(|f| {
            f.to_str().unwrap().ends_with("_M1.json") || f.to_str().unwrap().ends_with("_M2.json")
        })
        .collect();
    assert_eq!(modules.len(), 2);
    written.extend(modules);
    for file in &written {
        if let Err(e) = validate(file) {
            panic!("{}: {e}", file.display());
        }
    }
    // A machine synth wrote names the schema for editors, and synth still reads it.
    let exported = dir.path().join("out0/SynthesizedFB.json");
    let text_of = std::fs::read_to_string(&exported).unwrap();
    assert!(text_of.contains("\"format\": 1"), "{text_of}");
    let marked = dir.path().join("marked.json");
    std::fs::write(
        &marked,
        text_of.replacen('{', "{\"$schema\": \"machine.schema.json\",", 1),
    )
    .unwrap();
    assert!(validate(&marked).is_ok());
    let o = synth_in(
        dir.path(),
        &[
            "export",
            "--ecc",
            "marked.json",
            "--out",
            "m",
            "--format",
            "json",
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    for (what, from, to) in [
        ("a misspelt field", "\"guard\":", "\"guards\":"),
        (
            "a symbol no algorithm has",
            "\"algorithm\": \"1x\"",
            "\"algorithm\": \"2x\"",
        ),
        ("a newer format", "\"format\": 1", "\"format\": 2"),
    ] {
        assert!(text_of.contains(from), "{what}: {text_of}");
        let bad = dir.path().join("bad.json");
        std::fs::write(&bad, text_of.replacen(from, to, 1)).unwrap();
        assert!(validate(&bad).is_err(), "the schema takes {what}");
        let o = synth_in(
            dir.path(),
            &[
                "export", "--ecc", "bad.json", "--out", "b", "--format", "json",
            ],
        );
        assert_eq!(o.status.code(), Some(4), "synth takes {what}");
        assert!(text(&o.stderr).contains("bad.json"), "{}", text(&o.stderr));
    }
}

/// Runs `synth` with `args` in the repository; its stdout as JSON, after it exited with
/// `code`.
fn json_exiting(code: i32, args: &[&str]) -> serde_json::Value {
    let o = synth(args);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {}", text(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{args:?}: {e}"))
}

/// [`json_exiting`] a run that succeeds.
fn json_of(args: &[&str]) -> serde_json::Value {
    json_exiting(0, args)
}

/// A JSON file.
fn json_file(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Every summary synth writes, as `(its format, the summary)`: each command's `summary.json`
/// and `--json` output. The commands that need NuSMV only where it runs (always under
/// `CI=true`).
fn summaries(dir: &Path) -> Vec<(&'static str, serde_json::Value)> {
    let d = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let door = "tests/data/scenarios/door.traces";
    let machine = d("least/SynthesizedFB.json");
    let mut all = vec![
        (
            "infer",
            json_of(&["infer", "--traces", door, "--out", &d("least"), "--json"]),
        ),
        (
            "command",
            json_of(&["replay", "--ecc", &machine, "--traces", door, "--json"]),
        ),
    ];
    // A failing command has the generic summary too, with its error.
    let missing = d("missing.json");
    let failed = json_exiting(4, &["export", "--ecc", &missing, "--json"]);
    assert!(failed["error"].as_str().unwrap().contains("missing.json"));
    all.push(("command", failed));
    let rival = d("least/rival1.json");
    all.push((
        "diff",
        json_exiting(1, &["diff", &machine, &rival, "--json"]),
    ));
    all.push(("diff", json_of(&["diff", &machine, &machine, "--json"])));
    let next = [
        "next-recording",
        "--traces",
        door,
        "--out",
        &d("next"),
        "--json",
    ];
    all.push(("next-recording", json_of(&next)));
    let learn = [
        "learn",
        "--oracle",
        &rival,
        "--traces",
        door,
        "--passive-runs",
        "1",
    ];
    all.push(("learn", json_of(&[&learn[..], &["--json"]].concat())));
    let noisy = ["infer", "--noisy", "--max-errors", "1", "--enumerate", "2"];
    let traces = [
        "--traces",
        "tests/data/noisy/skewed.csv",
        "--out",
        &d("noisy"),
        "--json",
    ];
    all.push(("command", json_of(&[&noisy[..], &traces].concat())));
    all.push(("noisy", json_file(&dir.join("noisy/summary.json"))));
    std::fs::create_dir(dir.join("logs")).unwrap();
    let log = d("logs/door.csv");
    json_of(&[
        "convert", "--traces", door, "--to", "csv", "-o", &log, "--json",
    ]);
    let batch = json_of(&[
        "batch",
        "--logs",
        &d("logs"),
        "--out",
        &d("batch"),
        "--json",
    ]);
    all.push(("batch", batch));
    all.push(("batch", json_file(&dir.join("batch/summary.json"))));
    if nusmv_or_skip().is_some() {
        all.extend(verified_summaries(dir));
    }
    all
}

/// The summaries of the commands that run NuSMV: the main job's and `infer --ltl`'s (on
/// stdout and in `summary.json`), `verify --json`, `verified/summary.json` of `infer --noisy
/// --ltl` and `summary.json` of `conform --refine --ltl`.
fn verified_summaries(dir: &Path) -> Vec<(&'static str, serde_json::Value)> {
    let d = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let (ltl, plant) = (
        "tests/data/closed_loop/lamp.ltl",
        "tests/data/closed_loop/lamp_plant.smv",
    );
    let lamp = "tests/data/closed_loop/lamp.traces";
    let closed = ["--ltl", ltl, "--plant", plant];
    let mut all = vec![(
        "main",
        json_of(&[&closed[..], &["--out", &d("main"), "--json"]].concat()),
    )];
    all.push(("main", json_file(&dir.join("main/summary.json"))));
    let infer = ["infer", "--traces", lamp, "--out", &d("ltl"), "--json"];
    all.push(("main", json_of(&[&infer[..], &closed].concat())));
    let verified = d("main/SynthesizedFB.json");
    let verify = [
        "verify", "--ecc", &verified, "--ltl", ltl, "--plant", plant, "--json",
    ];
    all.push(("verify", json_of(&verify)));
    let noisy = ["infer", "--noisy", "--max-errors", "0", "--traces", lamp];
    json_of(&[&noisy[..], &closed, &["--out", &d("noisy-ltl"), "--json"]].concat());
    let file = dir.join("noisy-ltl/verified/summary.json");
    all.push(("noisy-verified", json_file(&file)));
    // The least machine of the recordings keeps the lamp on; a timeout that switches it off
    // diverges, and the refined machine is verified.
    let first = [
        "infer",
        "--traces",
        lamp,
        "--out",
        &d("lamp"),
        "--no-ambiguity",
        "--json",
    ];
    json_of(&first);
    let new = dir.join("new.traces");
    std::fs::write(&new, "1\nin=REQ[10]; out=CNF[1]; in=REQ[01]; out=CNF[0];\n").unwrap();
    let conform = [
        "conform",
        "--ecc",
        &d("lamp/SynthesizedFB.json"),
        "--traces",
        new.to_str().unwrap(),
        "--input-names",
        "tests/data/closed_loop/lamp.inputs",
        "--output-names",
        "tests/data/closed_loop/lamp.outputs",
        "--refine",
        "--train",
        lamp,
        "--out",
        &d("refined"),
    ];
    json_of(&[&conform[..], &closed, &["--json"]].concat());
    all.push(("refined", json_file(&dir.join("refined/summary.json"))));
    all
}

/// `synth schema --summary` is a JSON Schema boon compiles; every summary synth writes
/// (each command's `summary.json` and `--json` output) names its format and validates against
/// it; a summary with a field of the wrong type, or another format's name, does not.
#[test]
fn every_summary_validates_against_the_schema_synth_prints() {
    let dir = Dir::new();
    let (schemas, index) = printed_schema(dir.path(), &["--summary"]);
    let all = summaries(dir.path());
    let mut seen = std::collections::BTreeSet::new();
    for (command, summary) in &all {
        assert_eq!(
            summary["format"],
            format!("fbsynth-summary/{command}/1"),
            "{summary:#}"
        );
        if let Err(e) = schemas.validate(summary, index) {
            panic!("{command}: {e}\n{summary:#}");
        }
        seen.insert(*command);
    }
    let mut want = vec![
        "command",
        "infer",
        "diff",
        "next-recording",
        "learn",
        "noisy",
        "batch",
    ];
    if nusmv_or_skip().is_some() {
        want.extend(["main", "verify", "noisy-verified", "refined"]);
    }
    assert_eq!(seen, want.into_iter().collect());
    let (_, infer) = &all[0];
    let mut bad = infer.clone();
    bad["size"]["c"] = "two".into();
    assert!(schemas.validate(&bad, index).is_err());
    let mut other = infer.clone();
    other["format"] = "fbsynth-summary/diff/1".into();
    assert!(schemas.validate(&other, index).is_err());
}
