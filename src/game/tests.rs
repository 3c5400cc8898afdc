use super::*;
use crate::scenario::{Origin, Scenario, ScenarioSet, Step};
use std::path::Path;

/// A job queue: the environment raises `req`, which makes the plant `busy` until the
/// controller's `work` (read one step later) clears it; a new `req` wins over `work`.
const QUEUE: &str = "\
MODULE plant(work)
VAR
    req : boolean;
    busy : boolean;
ASSIGN
    init(busy) := FALSE;
    next(busy) := case
        req : TRUE;
        work : FALSE;
        TRUE : busy;
    esac;
";

fn queue() -> (Model, Wiring) {
    let model = crate::plant::parse::parse_str(QUEUE, Path::new("queue.smv")).unwrap();
    let coupling = Wiring::of_model(&model, &["busy".into()], &["work".into()]).unwrap();
    (model, coupling)
}

fn props(text: &str) -> Vec<Property> {
    crate::ltl::parse_spec(Path::new("queue.ltl"), text).unwrap()
}

/// Scenarios over `busy` / `work`: per step the input and the recorded output (`None`:
/// passive).
fn recorded(runs: &[&[(bool, Option<bool>)]]) -> ScenarioSet {
    ScenarioSet {
        inputs: vec!["busy".into()],
        outputs: vec!["work".into()],
        initial_outputs: vec![false],
        scenarios: (runs.iter().enumerate())
            .map(|(k, r)| Scenario {
                origin: Origin {
                    file: "queue.traces".into(),
                    line: k + 1,
                    rows: None,
                },
                steps: (r.iter())
                    .map(|&(busy, work)| Step {
                        inputs: vec![busy],
                        outputs: work.map(|w| vec![w]),
                    })
                    .collect(),
            })
            .collect(),
    }
}

fn solve_queue(spec: &str, set: &ScenarioSet) -> Result<Outcome, GameError> {
    let (model, coupling) = queue();
    let tree = ScenarioTree::build(set).unwrap();
    solve(
        &model,
        &coupling,
        &props(spec),
        &tree,
        &set.initial_outputs,
        100_000,
        Deadline::NONE,
    )
}

const SERVED: &str = "\
never_idle_work: G (work -> busy)
served: (F G !req) -> G (busy -> F !busy)
";

#[test]
fn a_controller_exists_when_the_environment_lets_it_serve() {
    let set = recorded(&[&[(false, Some(false)), (false, None)]]);
    let Outcome::Won(s) = solve_queue(SERVED, &set).unwrap() else {
        panic!("the game is won: work in pulses while busy");
    };
    // The strategy answers the recording as recorded, and works when it sees a job.
    set.check(&*s).unwrap();
    let mut run = s.start();
    let answers: Vec<Option<Vec<bool>>> = [false, false, true, true]
        .iter()
        .map(|&b| run.react(&[b]).map(<[bool]>::to_vec))
        .collect();
    assert_eq!(answers[0], Some(vec![false]));
    assert_eq!(answers[1], None, "the recording's passive step");
    assert!(
        answers[2..].contains(&Some(vec![true])),
        "a job seen is worked on: {answers:?}"
    );
}

#[test]
fn no_controller_exists_when_the_environment_can_keep_the_plant_busy() {
    let set = recorded(&[&[(false, Some(false))]]);
    let spec = "served: G (busy -> F !busy)\n";
    assert!(matches!(solve_queue(spec, &set).unwrap(), Outcome::Lost));
}

#[test]
fn a_recording_that_breaks_a_safety_property_loses_the_game() {
    // Working with nothing to do: `work` is on at the next step while `busy` is off (the
    // environment keeps `req` off).
    let set = recorded(&[&[(false, Some(true))]]);
    assert!(matches!(solve_queue(SERVED, &set).unwrap(), Outcome::Lost));
    // Without the recording the same properties can be kept.
    let set = recorded(&[&[(false, Some(false))]]);
    assert!(matches!(
        solve_queue(SERVED, &set).unwrap(),
        Outcome::Won(_)
    ));
}

#[test]
fn properties_outside_the_fragment_are_named_with_their_line() {
    let set = recorded(&[&[(false, Some(false))]]);
    let spec = "never_idle_work: G (work -> busy)\nsettles: F G !busy\n";
    match solve_queue(spec, &set) {
        Err(GameError::Outside(why)) => {
            assert!(why.contains("settles (line 2)"), "{why}")
        }
        other => panic!("expected Outside, got {:?}", other.map(|_| ())),
    }
}

#[test]
fn every_pick_and_place_property_is_a_monitor() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let model = crate::plant::parse::parse_file(&root.join("smv/pnp_surrogate.smv")).unwrap();
    let props = crate::ltl::parse_spec_file(&root.join("specs/pnp.ltl")).unwrap();
    let names = |f: &str| crate::scenario::names::read_names(&root.join(f)).unwrap();
    let (inputs, outputs) = (names("specs/pnp.inputs"), names("specs/pnp.outputs"));
    let coupling = Wiring::of_model(&model, &inputs, &outputs).unwrap();
    let m = Monitors::of(&props, &model, &coupling).unwrap();
    assert_eq!(
        m.goal_names,
        [
            "track1_served",
            "held_until_placed",
            "track2_served",
            "track3_served"
        ]
    );
}

#[test]
fn monitors_follow_the_forms_step_by_step() {
    let (model, coupling) = queue();
    // Atoms in order of appearance: busy (0), work (1), req (2).
    let spec = "held: G (busy -> (busy U work))\nfollowed: G (req -> X busy)\n";
    let m = Monitors::of(&props(spec), &model, &coupling).unwrap();
    let (busy, work, req) = (1u64, 2u64, 4u64);
    // busy opens the until; it stays open while busy holds, `work` releases it.
    let s1 = m.step(0, busy);
    assert!(!s1.bad && s1.goals == 0);
    let s2 = m.step(s1.memory, busy);
    assert!(!s2.bad && s2.goals == 0);
    assert!(m.step(s2.memory, 0).bad, "busy dropped before work");
    let s3 = m.step(s2.memory, work);
    assert!(!s3.bad && s3.goals == 1);
    // req must be followed by busy at the next step.
    let r = m.step(0, req);
    assert!(m.step(r.memory, 0).bad);
    assert!(!m.step(r.memory, busy | work).bad);
}

fn won(spec: &str, set: &ScenarioSet) -> Box<Strategy> {
    match solve_queue(spec, set).unwrap() {
        Outcome::Won(s) => s,
        Outcome::Lost => panic!("the game is won"),
    }
}

/// The least machine SAT finds for `set` alone, as the guide starts from.
fn least(set: &ScenarioSet) -> crate::ecc::Ecc {
    let tree = ScenarioTree::build(set).unwrap();
    crate::sat::synthesize(set, &tree, &Default::default(), &mut |_| {})
        .unwrap()
        .ecc
}

#[test]
fn a_machine_that_never_works_is_repaired_until_it_serves_every_job() {
    let set = recorded(&[&[(false, Some(false)), (false, None)]]);
    let s = won(SERVED, &set);
    let base = least(&set);
    // The recording never shows a job, and the least machine for it never works.
    assert!(!repair::wins(&s, &base).unwrap(), "{base:?}");
    assert!(matches!(
        repair::repair(&s, &base, 0),
        Err(repair::RepairError::Rounds(0))
    ));
    let r = repair::repair(&s, &base, 100).unwrap();
    assert!(r.rounds > 0);
    assert!(repair::wins(&s, &r.ecc).unwrap());
    set.check(&r.ecc).unwrap();
    // Runs through every node of its closed loop; the least machine for them and the
    // recording wins too.
    let runs = repair::covering_runs(&s, &r.ecc).unwrap();
    assert!(!runs.is_empty());
    let mut guided = set.clone();
    guided.scenarios.extend(runs);
    guided.check(&r.ecc).unwrap();
    let small = least(&guided);
    guided.check(&small).unwrap();
    assert!(repair::wins(&s, &small).unwrap(), "{small:?}");
    assert!(small.states.len() <= r.ecc.states.len());
}

/// The least machine narrowed to the recorded inputs answers the recordings as before and
/// stays on every input vector they never show in a state; the game then decides there.
#[test]
fn a_machine_narrowed_to_the_recorded_inputs_stays_elsewhere_and_is_repaired() {
    // A job served once: the least machine's guards also fire in pairs of state and input
    // the recording never shows.
    let set = recorded(&[&[
        (false, Some(false)),
        (true, Some(true)),
        (false, Some(false)),
    ]]);
    let s = won(SERVED, &set);
    let base = least(&set);
    let tree = ScenarioTree::build(&set).unwrap();
    let narrowed = repair::narrowed(&tree, &base);
    set.check(&narrowed).unwrap();
    assert_eq!(narrowed.states.len(), base.states.len());
    // The (state, inputs) pairs the recording shows, replayed on the base.
    let mut seen = Vec::new();
    let mut run = crate::ecc::Run::new(&base);
    for step in &set.scenarios[0].steps {
        seen.push((run.state.0, step.inputs.clone()));
        run.step(&step.inputs);
    }
    let mut generalized = 0;
    for q in 0..base.states.len() {
        for x in [vec![false], vec![true]] {
            let fires =
                |e: &crate::ecc::Ecc| e.states[q].transitions.iter().any(|t| t.guard.eval(&x));
            let shown = seen.contains(&(q, x.clone()));
            assert!(!fires(&narrowed) || shown, "state {q} fires on {x:?}");
            generalized += usize::from(fires(&base) && !shown);
        }
    }
    assert!(
        generalized > 0,
        "the base fires only where the recording shows it, narrowing changes nothing: {base:?}"
    );
    let r = repair::repair(&s, &narrowed, 100).unwrap();
    assert!(repair::wins(&s, &r.ecc).unwrap());
    set.check(&r.ecc).unwrap();
}

#[test]
fn the_recordings_tree_as_a_machine_replays_them_and_is_repaired_until_it_wins() {
    // Two recordings: a passive step and a job served at once.
    let set = recorded(&[
        &[(false, Some(false)), (false, None)],
        &[
            (false, Some(false)),
            (true, Some(true)),
            (false, Some(false)),
        ],
    ]);
    let s = won(SERVED, &set);
    let tree = ScenarioTree::build(&set).unwrap();
    let machine = repair::tree_machine(&tree, &least(&set));
    assert_eq!(machine.states.len(), tree.nodes.len());
    set.check(&machine).unwrap();
    let r = repair::repair(&s, &machine, 100).unwrap();
    assert!(repair::wins(&s, &r.ecc).unwrap());
    set.check(&r.ecc).unwrap();
}

#[test]
fn an_answer_that_breaks_a_safety_property_is_replaced_and_the_recorded_ones_kept() {
    use crate::ecc::{Algorithm, Ecc, Guard, State, StateId, Transition, Tri};
    let set = recorded(&[&[(false, Some(false))]]);
    let s = won(SERVED, &set);
    // s0 answers the recording (work off), then the machine works for ever, busy or not.
    let state = |name: &str, work: Tri, next: usize| State {
        name: name.into(),
        algorithm: Algorithm::Tri(vec![work]),
        transitions: vec![Transition {
            target: StateId(next),
            guard: Guard::True,
        }],
    };
    let base = Ecc {
        inputs: vec!["busy".into()],
        outputs: vec!["work".into()],
        initial_outputs: vec![false],
        states: vec![
            state("s0", Tri::Zero, 1),
            state("s1", Tri::Zero, 2),
            state("s2", Tri::One, 2),
        ],
    };
    set.check(&base).unwrap();
    assert!(!repair::wins(&s, &base).unwrap());
    let r = repair::repair(&s, &base, 100).unwrap();
    assert!(repair::wins(&s, &r.ecc).unwrap());
    set.check(&r.ecc).unwrap();
    // The recorded answer of s0 is still the base's: its first transition is unchanged.
    assert_eq!(
        r.ecc.states[0].transitions[0],
        base.states[0].transitions[0]
    );
}

#[test]
fn strongly_connected_components_are_found_without_recursion() {
    // 0 -> 1 -> 2 -> 0 is one cycle; 3 only reaches it; 4 loops on itself; a long chain
    // checks the depth.
    let mut adj: Vec<Vec<u32>> = vec![vec![1], vec![2], vec![0], vec![0], vec![4]];
    for k in 5..100_000u32 {
        adj.push(vec![k + 1]);
    }
    adj.push(vec![]);
    let comp = repair::components(&adj);
    assert_eq!(comp[0], comp[1]);
    assert_eq!(comp[1], comp[2]);
    assert_ne!(comp[3], comp[0]);
    assert_ne!(comp[4], comp[0]);
    assert_ne!(comp[5], comp[6]);
}

#[test]
fn many_outputs_stop_at_the_move_cap_before_memory_runs_out() {
    // Nine outputs: 512 moves at every position off the recordings.
    let outputs: Vec<String> = (1..=9).map(|k| format!("o{k}")).collect();
    let text = format!(
        "MODULE plant({})\nVAR\n    busy : boolean;\nASSIGN\n    init(busy) := FALSE;\n    next(busy) := o1;\n",
        outputs.join(", ")
    );
    let model = crate::plant::parse::parse_str(&text, Path::new("wide.smv")).unwrap();
    let coupling = Wiring::of_model(&model, &["busy".into()], &outputs).unwrap();
    let set = ScenarioSet {
        inputs: vec!["busy".into()],
        outputs: outputs.clone(),
        initial_outputs: vec![false; 9],
        scenarios: Vec::new(),
    };
    let tree = ScenarioTree::build(&set).unwrap();
    let props = crate::ltl::parse_spec(Path::new("wide.ltl"), "never: G !(busy & o2)\n").unwrap();
    // A limit of one position allows 256 moves: the first position has 512.
    let deadline = Deadline::NONE;
    match solve(
        &model,
        &coupling,
        &props,
        &tree,
        &set.initial_outputs,
        1,
        deadline,
    ) {
        Err(GameError::Outside(why)) => assert!(why.contains("more than 256 moves"), "{why}"),
        other => panic!("expected the move cap, got {:?}", other.map(|_| ())),
    }
    // With room for them the game is solved.
    assert!(matches!(
        solve(
            &model,
            &coupling,
            &props,
            &tree,
            &set.initial_outputs,
            100_000,
            deadline
        ),
        Ok(Outcome::Won(_))
    ));
    // A deadline already passed stops the exploration.
    assert!(matches!(
        solve(
            &model,
            &coupling,
            &props,
            &tree,
            &set.initial_outputs,
            100_000,
            Deadline::after(std::time::Duration::ZERO)
        ),
        Err(GameError::Stopped)
    ));
}
