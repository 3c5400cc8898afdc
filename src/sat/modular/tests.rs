//! Known minima of the modular encoding on tiny hand-made instances.

use super::*;
use crate::ecc::modular::tests::two_toggles;
use crate::ecc::modular::{ModularRun, Module, Topology};
use crate::ecc::InputId;
use crate::scenario::{Origin, Scenario, Step};

/// Records the composite `m` on each input sequence, as scenarios.
pub(crate) fn record(m: &Modular, runs: &[Vec<Vec<bool>>]) -> ScenarioSet {
    let scenarios = runs
        .iter()
        .enumerate()
        .map(|(i, xs)| {
            let mut run = ModularRun::new(m);
            let steps = xs
                .iter()
                .map(|x| Step {
                    inputs: x.clone(),
                    outputs: run.step(x).then(|| run.outputs.clone()),
                })
                .collect();
            Scenario {
                origin: Origin {
                    file: "recorded".into(),
                    line: i + 1,
                    rows: None,
                },
                steps,
            }
        })
        .collect();
    ScenarioSet {
        inputs: m.inputs.clone(),
        outputs: m.outputs.clone(),
        initial_outputs: m.initial_outputs.clone(),
        scenarios,
    }
}

/// Every input combination of two buttons, pressed in a few orders.
fn toggle_runs() -> Vec<Vec<Vec<bool>>> {
    let v = |a: bool, b: bool| vec![a, b];
    let (n, a, b, ab) = (
        v(false, false),
        v(true, false),
        v(false, true),
        v(true, true),
    );
    vec![
        vec![
            n.clone(),
            a.clone(),
            b.clone(),
            a.clone(),
            b.clone(),
            n.clone(),
        ],
        vec![
            b.clone(),
            ab.clone(),
            a.clone(),
            n.clone(),
            ab.clone(),
            b.clone(),
        ],
        vec![ab.clone(), ab.clone(), a.clone(), ab.clone(), b.clone(), ab],
        vec![a.clone(), a, b.clone(), b, n],
    ]
}

fn opts(modules: usize) -> ModularOptions {
    ModularOptions {
        modules,
        max_out_degree: 3,
        max_states: 8,
        ..ModularOptions::default()
    }
}

fn toggles() -> (ScenarioSet, ScenarioTree) {
    let set = record(&two_toggles(), &toggle_runs());
    let tree = ScenarioTree::build(&set).unwrap();
    (set, tree)
}

#[test]
fn one_module_needs_four_states_two_need_two() {
    let (_, tree) = toggles();
    assert!(satisfiable_modular(&tree, &opts(1), 4));
    assert!(!satisfiable_modular(&tree, &opts(1), 3));
    assert!(satisfiable_modular(&tree, &opts(2), 2));
    assert!(!satisfiable_modular(&tree, &opts(2), 1));
}

#[test]
fn two_modules_split_the_toggles_and_replay() {
    let (set, tree) = toggles();
    let r = synthesize_modular(&set, &tree, &opts(2), &mut |_| {}).unwrap();
    assert_eq!(r.size.max_states, 2);
    assert_eq!(r.size.inputs_used, 2);
    assert_eq!(r.size.total_states, 4);
    set.check(&r.modular).unwrap();
    // Each lamp with its own button.
    for module in &r.modular.modules {
        assert_eq!(module.outputs.len(), 1);
        assert_eq!(module.inputs, vec![InputId(module.outputs[0].0)]);
    }
    let one = synthesize_modular(&set, &tree, &opts(1), &mut |_| {}).unwrap();
    assert_eq!((one.size.max_states, one.size.inputs_used), (4, 2));
    set.check(&one.modular).unwrap();
}

#[test]
fn a_third_module_does_not_help_and_stays_empty_of_states() {
    let (set, tree) = toggles();
    let r = synthesize_modular(&set, &tree, &opts(3), &mut |_| {}).unwrap();
    assert_eq!(r.size.max_states, 2);
    // The spare module keeps one state and reads nothing.
    assert_eq!((r.size.inputs_used, r.size.total_states), (2, 5));
    set.check(&r.modular).unwrap();
}

#[test]
fn pinned_outputs_stay_together() {
    let (set, tree) = toggles();
    let mut o = opts(2);
    o.pins = parse_pins(&["2=la,lb".to_string()], &set.outputs, 2).unwrap();
    assert!(!satisfiable_modular(&tree, &o, 3));
    let r = synthesize_modular(&set, &tree, &o, &mut |_| {}).unwrap();
    assert_eq!(r.size.max_states, 4);
    assert_eq!(r.modular.owner(OutputId(0)), Some(1));
    assert_eq!(r.modular.owner(OutputId(1)), Some(1));
    set.check(&r.modular).unwrap();

    // One pinned, the other left to the solver, which puts it apart.
    o.pins = parse_pins(&["2=la".to_string()], &set.outputs, 2).unwrap();
    let r = synthesize_modular(&set, &tree, &o, &mut |_| {}).unwrap();
    assert_eq!(r.size.max_states, 2);
    assert_eq!(r.modular.owner(OutputId(0)), Some(1));
    assert_eq!(r.modular.owner(OutputId(1)), Some(0));
}

#[test]
fn pins_are_validated_with_clear_messages() {
    let outs = vec!["la".to_string(), "lb".to_string()];
    let e = |args: &[&str]| {
        let a: Vec<String> = args.iter().map(|s| s.to_string()).collect();
        parse_pins(&a, &outs, 2).unwrap_err().to_string()
    };
    assert!(e(&["la"]).contains("expected MODULE=OUTPUT"));
    assert!(e(&["3=la"]).contains("numbered 1 to 2"));
    assert!(e(&["0=la"]).contains("numbered 1 to 2"));
    assert!(e(&["1=lc"]).contains("`lc` is not an output; the outputs are la, lb"));
    assert!(e(&["1=la", "2=la"]).contains("already pinned to module 1"));
    assert!(e(&["1=la,"]).contains("expected MODULE=OUTPUT"));
    let ok = parse_pins(&["1=lb".into(), "1=lb,la".into()], &outs, 2).unwrap();
    assert_eq!(ok, vec![vec![OutputId(1), OutputId(0)], vec![]]);
}

/// An active step whose outputs do not change still needs some module to fire (`CNF`).
#[test]
fn active_step_without_change_is_reproduced() {
    let set = ScenarioSet {
        inputs: vec!["a".into()],
        outputs: vec!["z".into()],
        initial_outputs: vec![false],
        scenarios: vec![Scenario {
            origin: Origin {
                file: "t".into(),
                line: 1,
                rows: None,
            },
            steps: vec![
                Step {
                    inputs: vec![true],
                    outputs: Some(vec![false]),
                },
                Step {
                    inputs: vec![false],
                    outputs: None,
                },
            ],
        }],
    };
    let tree = ScenarioTree::build(&set).unwrap();
    let r = synthesize_modular(&set, &tree, &opts(2), &mut |_| {}).unwrap();
    set.check(&r.modular).unwrap();
    assert_eq!(r.size.inputs_used, 1);
}

#[test]
fn zero_modules_is_an_error() {
    let (set, tree) = toggles();
    let e = synthesize_modular(&set, &tree, &opts(0), &mut |_| {}).unwrap_err();
    assert!(matches!(e, ModularError::NoModules));
}

/// Encoding size on the two-toggle instance, to catch blow-ups.
#[test]
fn encoding_size_is_stable() {
    let (_, tree) = toggles();
    let enc = Encoding::new(&tree, 4, &opts(2));
    let size = enc.solver.stats();
    insta::assert_json_snapshot!((size.variables, size.clauses));
}

/// Two random machines over disjoint inputs and outputs, run side by side: modular synthesis
/// with two modules finds a controller no larger than the larger of them, and one module a
/// controller no larger than their product; both replay every run.
#[test]
fn random_composites_are_rebuilt_no_larger() {
    use crate::ecc::random::random_ecc;
    use rand::{Rng, SeedableRng};
    for seed in 0..6u64 {
        let (c1, c2) = (2 + seed as usize % 2, 2 + (seed as usize / 2) % 2);
        let mut e1 = random_ecc(seed, c1, 2, 1);
        let mut e2 = random_ecc(seed + 100, c2, 2, 2);
        e1.inputs = vec!["a1".into(), "a2".into()];
        e1.outputs = vec!["p".into()];
        e2.inputs = vec!["b1".into(), "b2".into()];
        e2.outputs = vec!["q".into(), "r".into()];
        let original = Modular {
            inputs: ["a1", "a2", "b1", "b2"].map(String::from).to_vec(),
            outputs: ["p", "q", "r"].map(String::from).to_vec(),
            initial_outputs: vec![false; 3],
            modules: vec![
                Module {
                    inputs: vec![InputId(0), InputId(1)],
                    outputs: vec![OutputId(0)],
                    ecc: e1,
                },
                Module {
                    inputs: vec![InputId(2), InputId(3)],
                    outputs: vec![OutputId(1), OutputId(2)],
                    ecc: e2,
                },
            ],
            topology: Topology::Parallel,
        };
        original.validate().unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let runs: Vec<Vec<Vec<bool>>> = (0..6)
            .map(|_| {
                (0..12)
                    .map(|_| (0..4).map(|_| rng.gen_bool(0.5)).collect())
                    .collect()
            })
            .collect();
        let set = record(&original, &runs);
        let tree = ScenarioTree::build(&set).unwrap();
        let two = synthesize_modular(&set, &tree, &opts(2), &mut |_| {}).unwrap();
        assert!(two.size.max_states <= c1.max(c2), "seed {seed}");
        set.check(&two.modular).unwrap();
        let one = synthesize_modular(&set, &tree, &opts(1), &mut |_| {}).unwrap();
        assert!(one.size.max_states <= c1 * c2, "seed {seed}");
        assert!(one.size.max_states >= two.size.max_states, "seed {seed}");
        set.check(&one.modular).unwrap();
    }
}

#[test]
fn too_few_states_is_reported_with_the_limits() {
    let (set, tree) = toggles();
    let mut o = opts(1);
    o.max_states = 3;
    let e = synthesize_modular(&set, &tree, &o, &mut |_| {}).unwrap_err();
    assert!(
        matches!(e, ModularError::NoController { max_states: 3, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("raise --max-states"), "{e}");
}

/// A random chain of two machines over overlapping inputs, both writing both outputs (the
/// second one always fires, so every active step runs the whole chain, as the encoding
/// assumes): consecutive synthesis with two modules rebuilds it with modules no larger than
/// the larger original, and the result replays every run as a chain.
#[test]
fn random_consecutive_composites_are_rebuilt_no_larger() {
    use crate::ecc::random::random_ecc;
    use crate::ecc::{Guard, StateId, Transition};
    use rand::{Rng, SeedableRng};
    for seed in 0..6u64 {
        let (c1, c2) = (2 + seed as usize % 2, 2 + (seed as usize / 2) % 2);
        let mut e1 = random_ecc(seed, c1, 2, 2);
        let mut e2 = random_ecc(seed + 100, c2, 2, 2);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        for state in &mut e2.states {
            state.transitions.push(Transition {
                target: StateId(rng.gen_range(0..c2)),
                guard: Guard::True,
            });
        }
        e1.inputs = vec!["a".into(), "b".into()];
        e2.inputs = vec!["b".into(), "c".into()];
        for e in [&mut e1, &mut e2] {
            e.outputs = vec!["p".into(), "q".into()];
        }
        let original = Modular {
            inputs: ["a", "b", "c"].map(String::from).to_vec(),
            outputs: ["p", "q"].map(String::from).to_vec(),
            initial_outputs: vec![false; 2],
            modules: vec![
                Module {
                    inputs: vec![InputId(0), InputId(1)],
                    outputs: vec![OutputId(0), OutputId(1)],
                    ecc: e1,
                },
                Module {
                    inputs: vec![InputId(1), InputId(2)],
                    outputs: vec![OutputId(0), OutputId(1)],
                    ecc: e2,
                },
            ],
            topology: Topology::Consecutive,
        };
        original.validate().unwrap();
        let runs: Vec<Vec<Vec<bool>>> = (0..6)
            .map(|_| {
                (0..12)
                    .map(|_| (0..3).map(|_| rng.gen_bool(0.5)).collect())
                    .collect()
            })
            .collect();
        let set = record(&original, &runs);
        let tree = ScenarioTree::build(&set).unwrap();
        let mut o = opts(2);
        o.topology = Topology::Consecutive;
        let two = synthesize_modular(&set, &tree, &o, &mut |_| {}).unwrap();
        assert_eq!(two.modular.topology, Topology::Consecutive);
        assert!(
            two.size.max_states <= c1.max(c2),
            "seed {seed}: {:?}",
            two.size
        );
        set.check(&two.modular).unwrap();
        two.modular.validate().unwrap();
        // The flattened chains behave as the chains, on the recordings and off them.
        set.check(&two.modular.flatten(10_000).unwrap()).unwrap();
        let other: Vec<Vec<Vec<bool>>> = (0..6)
            .map(|_| {
                (0..12)
                    .map(|_| (0..3).map(|_| rng.gen_bool(0.5)).collect())
                    .collect()
            })
            .collect();
        let fresh = record(&original, &other);
        fresh.check(&original.flatten(10_000).unwrap()).unwrap();
    }
}

/// Pins have no meaning in a chain, where every module writes every output.
#[test]
fn pins_in_a_chain_are_refused() {
    let (set, tree) = toggles();
    let mut o = opts(2);
    o.topology = Topology::Consecutive;
    o.pins = vec![vec![OutputId(0)], vec![]];
    let e = synthesize_modular(&set, &tree, &o, &mut |_| {}).unwrap_err();
    assert!(matches!(e, ModularError::PinsInChain), "{e}");
}

/// A synthesized chain flattens into one ECC that replays the recordings too, and the chain's
/// modules after the first end every state with an unconditional transition.
#[test]
fn a_synthesized_chain_flattens_into_one_machine_with_the_same_behaviour() {
    let (set, tree) = toggles();
    let mut o = opts(2);
    o.topology = Topology::Consecutive;
    let r = synthesize_modular(&set, &tree, &o, &mut |_| {}).unwrap();
    let flat = r.modular.flatten(1000).unwrap();
    set.check(&flat).unwrap();
    let mut parallel = r.modular.clone();
    parallel.topology = Topology::Parallel;
    assert!(parallel.flatten(1000).is_err());
    let mut broken = r.modular.clone();
    broken.modules[1].ecc.states[0].transitions.clear();
    let e = broken.validate().unwrap_err();
    assert!(
        e.contains("does not end with an unconditional transition"),
        "{e}"
    );
}
