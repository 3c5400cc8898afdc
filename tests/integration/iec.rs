//! What IEC 61131-3 tools accept of the exports: the Structured Text the `.st`, `.fbt` and
//! PLCopen files carry has one unary operator before a primary (never `NOT NOT`), and the
//! names of the standard's functions, function blocks and generic types are refused as names.

use crate::common::{root, synth, synth_in, text, Dir};
use fbsynth::export::json::read_json;
use fbsynth::scenario::fbsat;
use std::path::{Path, PathBuf};

/// Every format `synth export` writes.
const FORMATS: &str = "json,fbt,smv,dot,st,pnml,plcopen";

/// `synth export --ecc json --out out --name name` in every format; the files written.
fn export_all(json: &Path, out: &Path, name: &str) -> Vec<PathBuf> {
    let o = synth(&[
        "export",
        "--ecc",
        json.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--name",
        name,
        "--format",
        FORMATS,
    ]);
    assert!(
        o.status.success(),
        "{}: {}",
        json.display(),
        text(&o.stderr)
    );
    files_in(out)
}

fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = (std::fs::read_dir(dir).unwrap())
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
}

/// How many times `NOT NOT` occurs in the file, as `grep -c` would find it on its lines.
fn double_nots(file: &Path) -> usize {
    let bytes = std::fs::read(file).unwrap();
    String::from_utf8_lossy(&bytes)
        .lines()
        .filter(|l| l.contains("NOT NOT"))
        .count()
}

/// The Pick-and-Place recordings with their names files.
fn pnp_set() -> fbsynth::scenario::ScenarioSet {
    let names = |f: &str| {
        let text = std::fs::read_to_string(root().join("specs").join(f)).unwrap();
        Some(text.split_whitespace().map(String::from).collect())
    };
    fbsat::read(
        &root().join("specs/pnp.traces"),
        names("pnp.inputs"),
        names("pnp.outputs"),
    )
    .unwrap()
}

/// Whether a conjunction written in the guard syntax has a literal and its negation among its
/// top-level conjuncts (guards with `|` or parentheses are not judged here).
fn contradicts_itself(guard: &str) -> bool {
    if guard.contains(['|', '(']) {
        return false;
    }
    let conjuncts: Vec<&str> = guard.split('&').map(str::trim).collect();
    (conjuncts.iter()).any(|c| conjuncts.contains(&format!("!{c}").as_str()))
}

/// `grep -c 'NOT NOT'` is 0 over every export of the shipped machines, of the Pick-and-Place
/// chain of two blocks as `synth infer` writes it and as `synth export` rewrites it, and of a
/// hand-written `!(!a)`. The chain keeps no transition whose guard contradicts itself and still
/// replays every recording.
#[test]
fn no_export_doubles_a_negation_modular_chains_included() {
    let dir = Dir::new();
    let mut written = Vec::new();
    for (k, json) in crate::schemas::machines(dir.path()).iter().enumerate() {
        written.extend(export_all(
            json,
            &dir.path().join(format!("out{k}")),
            "Machine",
        ));
    }
    let chain = dir.path().join("chain");
    let o = synth_in(
        root(),
        &[
            "infer",
            "-q",
            "--no-ambiguity",
            "--modules",
            "2",
            "--topology",
            "consecutive",
            "--traces",
            "specs/pnp.traces",
            "--out",
            chain.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    written.extend(files_in(&chain));
    let block = chain.join("SynthesizedFB.json");
    let ecc = read_json(&std::fs::read_to_string(&block).unwrap(), &block).unwrap();
    pnp_set().check(&ecc).unwrap();
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&block).unwrap()).unwrap();
    for t in doc["transitions"].as_array().unwrap() {
        let g = t["guard"].as_str().unwrap();
        assert!(!g.contains("!!"), "{g}");
        assert!(!contradicts_itself(g), "{g}");
    }
    written.extend(export_all(&block, &dir.path().join("chain_out"), "Chain"));
    let hand = dir.path().join("hand.json");
    std::fs::write(
        &hand,
        r#"{"inputs": ["a", "b"], "outputs": ["z"], "initial_outputs": "0",
            "states": [{"name": "off", "algorithm": "0"}, {"name": "on", "algorithm": "1"}],
            "transitions": [{"from": 0, "to": 1, "guard": "!(!a)"},
                            {"from": 1, "to": 0, "guard": "!!!(a & !!b) | !(!(!b))"}]}"#,
    )
    .unwrap();
    let hand_files = export_all(&hand, &dir.path().join("hand_out"), "Hand");
    let st = std::fs::read_to_string(dir.path().join("hand_out/Hand.st")).unwrap();
    assert!(st.contains("IF a THEN"), "{st}");
    assert!(st.contains("IF NOT (a AND b) OR NOT b THEN"), "{st}");
    written.extend(hand_files);
    let st_like = (written.iter())
        .filter(|f| {
            matches!(
                f.extension().and_then(|e| e.to_str()),
                Some("st" | "fbt" | "xml")
            )
        })
        .count();
    assert!(st_like >= 20, "{st_like} Structured Text carrying files");
    for file in &written {
        assert_eq!(double_nots(file), 0, "{}", file.display());
    }
    // The Structured Text files against the standard's grammar.
    let st: Vec<&PathBuf> = (written.iter())
        .filter(|f| f.extension().is_some_and(|e| e == "st"))
        .collect();
    assert!(st.len() >= 9, "{} .st files", st.len());
    for file in st {
        let text = std::fs::read_to_string(file).unwrap();
        crate::st_grammar::check(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    }
}

/// The Structured Text of 20 random machines (up to 8 states, 6 inputs, 4 outputs) follows
/// the standard's grammar.
#[test]
fn the_st_of_random_machines_follows_the_grammar() {
    for seed in 0..20u64 {
        let c = 1 + seed as usize % 8;
        let ecc = crate::common::random_ecc(seed, c, 1 + seed as usize % 6, 1 + seed as usize % 4);
        let text = fbsynth::export::text(&ecc, "Random", fbsynth::export::Format::St).unwrap();
        assert!(text.contains("END_FUNCTION_BLOCK"), "{text}");
        crate::st_grammar::check(&text).unwrap_or_else(|e| panic!("seed {seed}: {e}\n{text}"));
    }
}

/// A standard function block's name as `--name`, as an input and as an output, and a type
/// conversion function's name, through `synth infer` and `synth export`: refused before
/// anything is written, with a message naming the reserved word and what it is.
#[test]
fn standard_names_are_refused_as_block_input_and_output_names() {
    let dir = Dir::new();
    let door = |f: &str| root().join("tests/data/scenarios").join(f);
    let out = dir.path().join("out");
    let o = synth(&[
        "infer",
        "--traces",
        door("door.traces").to_str().unwrap(),
        "--input-names",
        door("door.inputs").to_str().unwrap(),
        "--output-names",
        door("door.outputs").to_str().unwrap(),
        "--name",
        "TON",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("`TON` is an IEC 61131-3 keyword: a standard function block"),
        "{stderr}"
    );
    assert!(!out.exists());
    for (inputs, outputs, word, what) in [
        (
            r#"["r_trig", "b"]"#,
            r#"["z"]"#,
            "R_TRIG",
            "a standard function block",
        ),
        (r#"["a", "b"]"#, r#"["Sel"]"#, "SEL", "a standard function"),
        (
            r#"["Any_Bit", "b"]"#,
            r#"["z"]"#,
            "ANY_BIT",
            "a generic data type",
        ),
        (
            r#"["a", "INT_TO_BOOL"]"#,
            r#"["z"]"#,
            "INT_TO_BOOL",
            "a standard function",
        ),
    ] {
        let json = dir.path().join(format!("{word}.json"));
        std::fs::write(
            &json,
            format!(
                r#"{{"inputs": {inputs}, "outputs": {outputs}, "initial_outputs": "0",
                    "states": [{{"name": "s0", "algorithm": "1"}}], "transitions": []}}"#
            ),
        )
        .unwrap();
        let out = dir.path().join(format!("out_{word}"));
        let o = synth(&[
            "export",
            "--ecc",
            json.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--format",
            "st",
        ]);
        let stderr = text(&o.stderr);
        assert!(!o.status.success(), "{word}: {stderr}");
        let message = format!("`{word}` is an IEC 61131-3 keyword: {what}");
        assert!(stderr.contains(&message), "{word}: {stderr}");
        assert!(!out.join("SynthesizedFB.st").exists(), "{word}");
    }
}
