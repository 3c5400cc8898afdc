//! Modular synthesis as a user runs it (`synth infer --modules`), its files read back and
//! replayed, and the composite SMV checked against the simulator inside NuSMV.

use crate::common::{nusmv_or_skip, synth, text, Dir};
use fbsynth::ecc::modular::{Modular, Module, Topology};
use fbsynth::ecc::{InputId, OutputId};
use fbsynth::export::json::read_json;
use fbsynth::export::modular::composite_smv_to_string;
use fbsynth::nusmv::Verdict;
use fbsynth::scenario::{fbsat, ScenarioSet};
use std::path::Path;
use std::process::Output;

const LAMPS: &str = "tests/data/scenarios/lamps.traces";

/// `synth infer -q --modules 2 --traces lamps.traces --out dir` and `extra`.
fn infer_lamps(dir: &str, extra: &[&str]) -> Output {
    let mut args = vec![
        "infer",
        "-q",
        "--modules",
        "2",
        "--traces",
        LAMPS,
        "--out",
        dir,
    ];
    args.extend_from_slice(extra);
    synth(&args)
}

fn lamps() -> ScenarioSet {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let names = |v: &[&str]| Some(v.iter().map(|s| s.to_string()).collect());
    fbsat::read(
        &dir.join(LAMPS),
        names(&["start", "stop", "sensor"]),
        names(&["start_led", "motor"]),
    )
    .unwrap()
}

/// Rebuilds the composite from the files `synth infer --modules` wrote.
fn read_back(dir: &Path, stem: &str, set: &ScenarioSet) -> Modular {
    let doc: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join(format!("{stem}.modules.json"))).unwrap(),
    )
    .unwrap();
    let modules = doc["modules"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| {
            let ty = m["type"].as_str().unwrap();
            let file = dir.join(format!("{ty}.json"));
            let ecc = read_json(&std::fs::read_to_string(&file).unwrap(), &file).unwrap();
            Module {
                inputs: ecc
                    .inputs
                    .iter()
                    .map(|n| InputId(set.inputs.iter().position(|i| i == n).unwrap()))
                    .collect(),
                outputs: ecc
                    .outputs
                    .iter()
                    .map(|n| OutputId(set.outputs.iter().position(|o| o == n).unwrap()))
                    .collect(),
                ecc,
            }
        })
        .collect();
    Modular {
        inputs: set.inputs.clone(),
        outputs: set.outputs.clone(),
        initial_outputs: set.initial_outputs.clone(),
        modules,
        topology: Topology::Parallel,
    }
}

#[test]
fn two_modules_split_the_lamp_from_the_motor_and_the_files_replay() {
    let out = Dir::new();
    let dir = out.path().to_str().unwrap();
    let o = infer_lamps(dir, &["--name", "Line"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(
        stdout.contains("largest module = 2 states  A = 3 inputs used  N' = 4 states"),
        "{stdout}"
    );
    assert!(
        stdout.contains("outputs: start_led; inputs: start, stop"),
        "{stdout}"
    );
    assert!(
        stdout.contains("outputs: motor; inputs: sensor"),
        "{stdout}"
    );
    let set = lamps();
    let modular = read_back(out.path(), "Line", &set);
    modular.validate().unwrap();
    set.check(&modular).unwrap();
    // The composite is well-formed XML naming both module types.
    let xml = std::fs::read_to_string(out.path().join("Line.fbt")).unwrap();
    let mut reader = quick_xml::Reader::from_str(&xml);
    let mut types = Vec::new();
    loop {
        match reader.read_event().unwrap() {
            quick_xml::events::Event::Eof => break,
            quick_xml::events::Event::Empty(e) if e.name().as_ref() == b"FB" => {
                let ty = e.try_get_attribute("Type").unwrap().unwrap();
                types.push(String::from_utf8(ty.value.to_vec()).unwrap());
            }
            _ => {}
        }
    }
    assert_eq!(types, ["Line_M1", "Line_M2", "E_SPLIT", "E_MERGE"]);
}

#[test]
fn pinned_outputs_go_where_they_are_pinned() {
    let out = Dir::new();
    let dir = out.path().to_str().unwrap();
    let o = infer_lamps(dir, &["--pin", "2=start_led"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(
        stdout.contains("module 2: 2 states, 3 transitions, 4 guard literals; outputs: start_led"),
        "{stdout}"
    );
    let o = infer_lamps(dir, &["--pin", "1=start_led,motor"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("outputs: start_led, motor"),
        "{}",
        text(&o.stdout)
    );
}

#[test]
fn bad_pins_are_usage_errors_naming_the_problem() {
    let out = Dir::new();
    let dir = out.path().to_str().unwrap();
    for (pin, says) in [
        (
            "3=motor",
            "module 3 does not exist; modules are numbered 1 to 2",
        ),
        (
            "1=moto",
            "`moto` is not an output; the outputs are start_led, motor",
        ),
        ("motor", "expected MODULE=OUTPUT"),
    ] {
        let o = infer_lamps(dir, &["--pin", pin]);
        assert_eq!(o.status.code(), Some(2), "{pin}");
        assert!(text(&o.stderr).contains(says), "{pin}: {}", text(&o.stderr));
    }
    assert_eq!(std::fs::read_dir(out.path()).unwrap().count(), 0);
}

/// Inside NuSMV, the composite SMV module emits exactly the CNFs and outputs the simulator
/// (and so the recordings) says, step by step, on every scenario.
#[test]
fn composite_smv_agrees_with_the_recordings_in_nusmv() {
    let Some(nusmv) = nusmv_or_skip() else {
        return;
    };
    let out = Dir::new();
    let dir = out.path().to_str().unwrap();
    let o = infer_lamps(dir, &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let set = lamps();
    let modular = read_back(out.path(), "SynthesizedFB", &set);
    let smv = composite_smv_to_string(&modular, "ECC").unwrap();
    nusmv_replays(&nusmv, &smv, &set, out.path());
}

/// Inside NuSMV, the controller module `ECC` of `smv` emits exactly the CNFs and outputs of
/// every scenario of `set`, step by step (one model per scenario, written into `dir`).
fn nusmv_replays(nusmv: &fbsynth::nusmv::Nusmv, smv: &str, set: &ScenarioSet, dir: &Path) {
    let b = |v: bool| if v { "TRUE" } else { "FALSE" };
    for (k, sc) in set.scenarios.iter().enumerate() {
        let mut model = smv.to_string();
        let len = sc.steps.len();
        model.push_str(&format!(
            "\nMODULE main\nVAR\n  t : 0..{};\n  ctrl : ECC(TRUE, {});\n",
            len + 1,
            set.inputs.join(", ")
        ));
        model.push_str(&format!(
            "ASSIGN\n  init(t) := 0;\n  next(t) := t <= {len} ? t + 1 : {len} + 1;\nDEFINE\n"
        ));
        for (x, name) in set.inputs.iter().enumerate() {
            let on: Vec<String> = (0..len)
                .filter(|&t| sc.steps[t].inputs[x])
                .map(|t| format!("t = {t}"))
                .collect();
            let expr = if on.is_empty() {
                "FALSE".into()
            } else {
                on.join(" | ")
            };
            model.push_str(&format!("  {name} := {expr};\n"));
        }
        // After step t (at t + 1): CNF iff the step is active, outputs as recorded.
        let mut outputs = set.initial_outputs.clone();
        let mut expect = Vec::new();
        for (t, step) in sc.steps.iter().enumerate() {
            if let Some(o) = &step.outputs {
                outputs = o.clone();
            }
            let mut parts = vec![format!("ctrl.CNF = {}", b(step.outputs.is_some()))];
            for (z, name) in set.outputs.iter().enumerate() {
                parts.push(format!("ctrl.{name} = {}", b(outputs[z])));
            }
            expect.push(format!("(t = {} -> {})", t + 1, parts.join(" & ")));
        }
        model.push_str(&format!("LTLSPEC G ({});\n", expect.join(" & ")));
        let file = dir.join(format!("check{k}.smv"));
        std::fs::write(&file, model).unwrap();
        let results = nusmv.check_file(&file).unwrap();
        assert_eq!(results.len(), 1);
        assert_eq!(results[0].verdict, Verdict::Holds, "scenario {k}");
    }
}

/// Distributed synthesis from the CLI: two controllers that read each other's outputs,
/// recorded as a whole network, rebuilt with no controller larger than the originals; the
/// files replay the recordings, and inside NuSMV the network's SMV module (each controller
/// reading the others' values from before the scan) gives the recorded CNFs and outputs.
#[test]
fn a_network_of_controllers_is_rebuilt_and_its_smv_agrees_in_nusmv() {
    use fbsynth::ecc::random::random_network;
    use rand::{Rng, SeedableRng};
    let original = random_network(3, 3, 2);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let runs: Vec<Vec<Vec<bool>>> = (0..6)
        .map(|_| {
            (0..14)
                .map(|_| vec![rng.gen_bool(0.5), rng.gen_bool(0.5)])
                .collect()
        })
        .collect();
    let m = &original.modular;
    let set = ScenarioSet::recorded(
        &original,
        original.inputs().to_vec(),
        m.outputs.clone(),
        m.initial_outputs.clone(),
        &runs,
    );
    let dir = Dir::new();
    let traces = dir.path().join("net.traces");
    let mut text_of_set = Vec::new();
    fbsat::write(&set, &mut text_of_set).unwrap();
    std::fs::write(&traces, text_of_set).unwrap();
    std::fs::write(dir.path().join("in.names"), "a\nb\n").unwrap();
    std::fs::write(dir.path().join("out.names"), "p\nq\nr\n").unwrap();
    let net = dir.path().join("net.json");
    std::fs::write(
        &net,
        r#"{"controllers": [
            {"name": "C1", "inputs": ["a", "q"], "outputs": ["p"]},
            {"name": "C2", "inputs": ["b", "p"], "outputs": ["q", "r"]}]}"#,
    )
    .unwrap();
    let out = dir.path().join("out");
    let p = |f: &Path| f.to_str().unwrap().to_string();
    let o = synth(&[
        "infer",
        "-q",
        "--distributed",
        &p(&net),
        "--name",
        "Net",
        "--traces",
        &p(&traces),
        "--input-names",
        &p(&dir.path().join("in.names")),
        "--output-names",
        &p(&dir.path().join("out.names")),
        "--out",
        &p(&out),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("Net.network.json")).unwrap())
            .unwrap();
    let largest = doc["largest_controller_states"].as_u64().unwrap();
    assert!(largest <= 3, "{doc}");
    for c in doc["controllers"].as_array().unwrap() {
        let name = c["name"].as_str().unwrap();
        let file = out.join(format!("{name}.json"));
        let ecc = read_json(&std::fs::read_to_string(&file).unwrap(), &file).unwrap();
        assert_eq!(
            ecc.inputs,
            c["inputs"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_str().unwrap().to_string())
                .collect::<Vec<_>>()
        );
        assert!(out.join(format!("{name}.fbt")).is_file());
    }
    let Some(nusmv) = nusmv_or_skip() else {
        return;
    };
    let smv = std::fs::read_to_string(out.join("Net.smv")).unwrap();
    nusmv_replays(
        &nusmv,
        &smv.replace("MODULE Net(", "MODULE ECC("),
        &set,
        dir.path(),
    );
}

/// The composite SMV takes the controller's place in the closed loop with the Pick-and-Place
/// surrogate plant: NuSMV accepts the model and gives a verdict for every property.
#[test]
fn composite_closes_the_loop_with_the_pnp_plant() {
    use fbsynth::ltl::parse_spec_file;
    use fbsynth::sat::modular::{synthesize_modular, ModularOptions};
    use fbsynth::scenario::tree::ScenarioTree;
    use fbsynth::smv::composition::{check_coupling, compose_controller, CONTROLLER_MODULE};
    use fbsynth::smv::plant::read_plant;
    let Some(nusmv) = nusmv_or_skip() else {
        return;
    };
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let names = |f: &str| {
        let text = std::fs::read_to_string(root.join("specs").join(f)).unwrap();
        Some(text.split_whitespace().map(String::from).collect())
    };
    let set = fbsat::read(
        &root.join("specs/pnp.traces"),
        names("pnp.inputs"),
        names("pnp.outputs"),
    )
    .unwrap();
    let tree = ScenarioTree::build(&set).unwrap();
    let opts = ModularOptions {
        modules: 2,
        ..ModularOptions::default()
    };
    let r = synthesize_modular(&set, &tree, &opts, &mut |_| {}).unwrap();
    let spec = root.join("specs/pnp.ltl");
    let props = parse_spec_file(&spec).unwrap();
    let plant = read_plant(&root.join("smv/pnp_surrogate.smv")).unwrap();
    let coupling = check_coupling(&set.inputs, &set.outputs, &plant, &spec, &props).unwrap();
    let controller = composite_smv_to_string(&r.modular, CONTROLLER_MODULE).unwrap();
    let model = compose_controller(controller, &set.inputs, &plant, &coupling, &props);
    let dir = Dir::new();
    let file = dir.path().join("closed_loop.smv");
    std::fs::write(&file, &model.text).unwrap();
    let results = nusmv.check_file(&file).unwrap();
    assert_eq!(results.len(), props.len());
    let holds = results
        .iter()
        .filter(|r| r.verdict == Verdict::Holds)
        .count();
    eprintln!("{holds} of {} properties hold in closed loop", props.len());
}

fn distribution(file: &str) -> ScenarioSet {
    fbsynth::scenario::csvlog::read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join(file),
        None,
        None,
    )
    .unwrap()
}

/// The distribution station's clean logs in two modules; with the lamps and the station's
/// actuators pinned apart, the HMI becomes a module of its own (the SAT reconstruction paper's Fig. 6).
#[test]
fn distribution_station_splits_in_two_and_pins_give_the_hmi_module() {
    let clean = distribution("specs/distribution.csv");
    let out = Dir::new();
    let dir = out.path().to_str().unwrap();
    let o = synth(&[
        "infer",
        "--modules",
        "2",
        "--traces",
        "specs/distribution.csv",
        "--out",
        dir,
        "-q",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let free = read_back(out.path(), "SynthesizedFB", &clean);
    assert_eq!(free.modules.len(), 2);
    assert_eq!(clean.check(&free), Ok(()));
    let pinned = Dir::new();
    let o = synth(&[
        "infer",
        "--modules",
        "2",
        "--pin",
        "1=start_led,reset_led",
        "--pin",
        "2=retract,vacuum_on,vacuum_off,to_magazine,to_client",
        "--traces",
        "specs/distribution.csv",
        "--out",
        pinned.path().to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let hmi = read_back(pinned.path(), "SynthesizedFB", &clean);
    assert_eq!(hmi.modules[0].ecc.outputs, ["start_led", "reset_led"]);
    assert_eq!(hmi.modules[1].ecc.outputs.len(), 5);
    assert_eq!(clean.check(&hmi), Ok(()));
}

/// `--noisy --modules`: the traces are corrected first, then the logic is distributed.
#[test]
fn noisy_then_modular_distributes_the_corrected_traces() {
    let out = Dir::new();
    let o = synth(&[
        "infer",
        "--noisy",
        "--max-errors",
        "2",
        "--modules",
        "2",
        "--pin",
        "1=start_led,reset_led",
        "--traces",
        "specs/distribution_noisy.csv",
        "--out",
        out.path().to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let corrected = distribution(
        out.path()
            .join("candidate_1/corrected.csv")
            .to_str()
            .unwrap(),
    );
    let composite = read_back(&out.path().join("modular"), "SynthesizedFB", &corrected);
    assert!(composite.modules[0]
        .ecc
        .outputs
        .iter()
        .any(|o| o == "start_led"));
    assert_eq!(corrected.check(&composite), Ok(()));
}

/// NuSMV's verdicts on the composite rebuilt from the files in `dir`, checked here from the
/// files alone (not the tool's report); `None` without NuSMV.
fn composite_verdicts(dir: &Path, set: &ScenarioSet, ltl: &str, plant: &str) -> Option<bool> {
    let nusmv = nusmv_or_skip()?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let composite = read_back(dir, "SynthesizedFB", set);
    set.check(&composite).unwrap();
    let problem = fbsynth::pipeline::Problem::load(
        &root.join(ltl),
        &root.join(plant),
        &set.inputs,
        &set.outputs,
    )
    .unwrap();
    let check = fbsynth::pipeline::Check::new(problem, nusmv);
    let text = composite_smv_to_string(&composite, "ECC").unwrap();
    let v = check
        .verifier()
        .unwrap()
        .verify_controller(text, &set.inputs, fbsynth::nusmv::CheckMode::VerdictsOnly)
        .unwrap();
    Some(v.report.all_hold())
}

/// Modular synthesis learns from the recordings only: on Pick-and-Place its M = 2 composite
/// breaks properties. With --ltl the composite is refined along NuSMV's counterexamples until
/// NuSMV verifies it, and the files say so.
#[test]
fn the_pnp_composite_is_verified_in_closed_loop() {
    if nusmv_or_skip().is_none() {
        return;
    }
    let out = Dir::new();
    let dir = out.path().join("m");
    let (ltl, plant) = ("specs/pnp.ltl", "smv/pnp_surrogate.smv");
    let o = synth(&[
        "infer",
        "-q",
        "--modules",
        "2",
        "--traces",
        "specs/pnp.traces",
        "--ltl",
        ltl,
        "--plant",
        plant,
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("verified: all 8 properties hold for the composite"));
    let set = fbsynth::pipeline::Recordings::files(vec!["specs/pnp.traces".into()])
        .load()
        .unwrap();
    assert_eq!(composite_verdicts(&dir, &set, ltl, plant), Some(true));
    // The single machine it was split from is there too, verified.
    let single = std::fs::read_to_string(dir.join("single/verification.txt")).unwrap();
    assert!(
        single.contains("HOLDS") && !single.contains("VIOLATED"),
        "{single}"
    );
    let rounds: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("rounds.json")).unwrap()).unwrap();
    let rounds = rounds.as_array().unwrap();
    // The first composite, from the recordings alone, fails; the last holds.
    assert!(!rounds[0]["failing"].as_array().unwrap().is_empty());
    assert!(rounds.last().unwrap()["failing"]
        .as_array()
        .unwrap()
        .is_empty());
}

/// `--noisy --modules 2 --ltl`: the traces are corrected, the least verified machine found,
/// and that machine split into a composite NuSMV verifies. The machine reproduces the clean
/// logs and a held-out recording it never saw.
#[test]
fn a_noisy_log_gives_one_verified_machine_and_its_verified_composite() {
    if nusmv_or_skip().is_none() {
        return;
    }
    let out = Dir::new();
    let dir = out.path().join("n");
    let (ltl, plant) = ("specs/distribution.ltl", "smv/distribution_surrogate.smv");
    let o = synth(&[
        "infer",
        "-q",
        "--noisy",
        "--max-errors",
        "2",
        "--modules",
        "2",
        "--traces",
        "specs/distribution_noisy.csv",
        "--ltl",
        ltl,
        "--plant",
        plant,
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let machine = dir.join("verified/SynthesizedFB.json");
    let machine = machine.to_str().unwrap();
    for (command, traces) in [
        ("replay", "specs/distribution.csv"),
        ("conform", "specs/distribution_heldout.csv"),
    ] {
        let o = synth(&[command, "--ecc", machine, "--traces", traces]);
        assert!(
            o.status.success(),
            "{command} {traces}: {}",
            text(&o.stderr)
        );
    }
    // The summary says what NuSMV made of each candidate as found, and which one the closed
    // loop verified.
    let summary = std::fs::read_to_string(dir.join("summary.txt")).unwrap();
    assert!(summary.contains("violates emergency_stops"), "{summary}");
    assert_eq!(summary.matches("yes (").count(), 1, "{summary}");
    let report = std::fs::read_to_string(dir.join("verified/verification.txt")).unwrap();
    assert!(
        report.contains("HOLDS") && !report.contains("VIOLATED"),
        "{report}"
    );
    // The composite splits that machine: it reproduces the corrected traces and NuSMV
    // verifies it.
    let corrected = dir.join("verified/corrected.csv");
    let set = fbsynth::pipeline::Recordings::files(vec![corrected])
        .load()
        .unwrap();
    assert_eq!(
        composite_verdicts(&dir.join("modular"), &set, ltl, plant),
        Some(true)
    );
}

const SLOTS: &str = "tests/data/modular/slots.traces";

#[test]
fn too_few_slots_are_widened_and_the_truth_is_rebuilt_no_larger() {
    let out = Dir::new();
    let dir = out.path().to_str().unwrap();
    let o = synth(&["infer", "--modules", "2", "--traces", SLOTS, "--out", dir]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let (stdout, stderr) = (text(&o.stdout), text(&o.stderr));
    assert!(
        stderr.contains("with 3 transitions per state: widening to 4"),
        "{stderr}"
    );
    assert!(
        stdout.contains("K = 4 slots per state, widened"),
        "{stdout}"
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let truth_file = root.join("tests/data/modular/slots_truth.json");
    let truth = read_json(&std::fs::read_to_string(&truth_file).unwrap(), &truth_file).unwrap();
    let set = fbsat::read(
        &root.join(SLOTS),
        Some(truth.inputs.clone()),
        Some(truth.outputs.clone()),
    )
    .unwrap();
    set.check(&truth).unwrap();
    let composite = read_back(out.path(), "SynthesizedFB", &set);
    set.check(&composite).unwrap();
    assert!(composite.size().max_states <= truth.states.len());

    // Given, the slots stay: no composite of modules up to 6 states has 3 per state.
    let fixed = Dir::new();
    let o = synth(&[
        "infer",
        "-q",
        "--modules",
        "2",
        "--slots",
        "3",
        "--max-states",
        "6",
        "--traces",
        SLOTS,
        "--out",
        fixed.path().join("r").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("raise --max-states or --slots"));
}

#[test]
fn every_method_stops_at_the_time_limit_with_exit_3_and_no_files() {
    let out = Dir::new();
    for extra in [&[][..], &["--modules", "2"], &["--noisy"]] {
        let dir = out.path().join(format!("r{}", extra.len()));
        let mut args = vec![
            "infer",
            "-q",
            "--traces",
            SLOTS,
            "--time-limit",
            "0.001",
            "--out",
            dir.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = synth(&args);
        assert_eq!(o.status.code(), Some(3), "{extra:?}: {}", text(&o.stderr));
        assert!(
            text(&o.stderr).contains("time limit of 0.001 s reached"),
            "{extra:?}: {}",
            text(&o.stderr)
        );
        assert!(!dir.exists(), "{extra:?}");
    }
}

/// `--topology consecutive`: a chain of two blocks, each rewriting both outputs. The files
/// give the chain as one block (which replays every recording) and each module, and say
/// "consecutive"; pins are refused for a chain (usage, exit 2).
#[test]
fn a_chain_of_two_blocks_is_written_as_one_block_that_replays_the_recordings() {
    let out = Dir::new();
    let dir = out.path().to_str().unwrap();
    let o = infer_lamps(dir, &["--topology", "consecutive"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("modules = 2 in a chain"), "{stdout}");
    let set = lamps();
    let file = out.path().join("SynthesizedFB.json");
    let block = read_json(&std::fs::read_to_string(&file).unwrap(), &file).unwrap();
    set.check(&block).unwrap();
    let doc: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.path().join("SynthesizedFB.modules.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(doc["topology"], "consecutive");
    for m in doc["modules"].as_array().unwrap() {
        assert_eq!(m["outputs"].as_array().unwrap().len(), 2, "{m}");
        let ty = m["type"].as_str().unwrap();
        assert!(out.path().join(format!("{ty}.json")).is_file(), "{ty}");
    }
    for ext in ["fbt", "smv", "st"] {
        assert!(
            out.path().join(format!("SynthesizedFB.{ext}")).is_file(),
            "{ext}"
        );
    }
    let pinned = Dir::new();
    let o = infer_lamps(
        pinned.path().to_str().unwrap(),
        &["--topology", "consecutive", "--pin", "1=motor"],
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("parallel composites only"),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(std::fs::read_dir(pinned.path()).unwrap().count(), 0);
}

/// `--topology arbitrary`: the solver wires the blocks; the files are a network whose blocks
/// replay the recordings side by side. With `--ltl` it is a usage error, with no files.
#[test]
fn an_arbitrary_network_is_written_as_blocks_that_replay_the_recordings() {
    let out = Dir::new();
    let dir = out.path().to_str().unwrap();
    let o = infer_lamps(dir, &["--topology", "arbitrary", "--name", "Line"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("controllers = 2"),
        "{}",
        text(&o.stdout)
    );
    let doc: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.path().join("Line.network.json")).unwrap(),
    )
    .unwrap();
    let mut written = Vec::new();
    for c in doc["controllers"].as_array().unwrap() {
        let name = c["name"].as_str().unwrap();
        assert!(name.starts_with("Line_M"), "{name}");
        for ext in ["fbt", "st", "smv", "json"] {
            assert!(
                out.path().join(format!("{name}.{ext}")).is_file(),
                "{name}.{ext}"
            );
        }
        written.extend(
            c["outputs"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.to_string()),
        );
    }
    written.sort();
    assert_eq!(written, ["\"motor\"", "\"start_led\""]);
    let refused = Dir::new();
    let o = infer_lamps(
        refused.path().to_str().unwrap(),
        &[
            "--topology",
            "arbitrary",
            "--ltl",
            "specs/pnp.ltl",
            "--plant",
            "smv/pnp_surrogate.smv",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert_eq!(std::fs::read_dir(refused.path()).unwrap().count(), 0);
}
