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

fn queue() -> (Model, Coupling) {
    let model = crate::plant::parse::parse_str(QUEUE, Path::new("queue.smv")).unwrap();
    let coupling = Coupling::new(&model, &["busy".into()], &["work".into()]).unwrap();
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
    let coupling = Coupling::new(&model, &inputs, &outputs).unwrap();
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
