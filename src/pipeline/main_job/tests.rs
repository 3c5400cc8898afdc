use super::*;
use crate::pipeline::cegis::Iteration;
use crate::pipeline::explain::Unrecorded;
use crate::verify::Report;
use std::time::Instant;

fn options(method: Method) -> Options {
    Options {
        method,
        exact: exact::Options::default(),
        limit: Limit::new(Instant::now(), 60.0),
    }
}

fn explanation(unrecorded: bool) -> Explanation {
    Explanation {
        violations: Vec::new(),
        checked: 1,
        undecidable: Vec::new(),
        unrecorded: match unrecorded {
            true => vec![Unrecorded {
                input: "pp2".into(),
                never: true,
                properties: vec!["track2_served".into()],
            }],
            false => Vec::new(),
        },
    }
}

/// The guide runs only for the exact method, where the recordings leave a property's input
/// open, and on the problem its own synthesis states: with fbSAT's conventions too, not with
/// negative scenarios.
#[test]
fn the_guide_runs_only_where_the_recordings_leave_an_input_open() {
    let open = explanation(true);
    assert!(guides(&options(Method::Sat), &open));
    assert!(!guides(&options(Method::Sat), &explanation(false)));
    assert!(!guides(
        &options(Method::Search(search::Options::default())),
        &open
    ));
    let mut fbsat = options(Method::Sat);
    fbsat.exact.sat.algorithms = crate::ecc::AlgorithmKind::Binary;
    fbsat.exact.sat.start_state = true;
    assert!(guides(&fbsat, &open));
    let mut negative = options(Method::Sat);
    negative.exact.negatives = vec![crate::scenario::negative::NegativeScenario {
        steps: Vec::new(),
        loop_start: None,
        label: "never".into(),
    }];
    assert!(!guides(&negative, &open));
}

/// Fewer states first, then fewer transitions, then fewer literals; K is not compared.
#[test]
fn the_size_order_is_states_then_transitions_then_literals() {
    let size = |c, k, t, n| Size { c, k, t, n };
    assert!(size(7, 9, 30, 90).is_smaller_than(&size(8, 1, 1, 1)));
    assert!(size(8, 5, 12, 90).is_smaller_than(&size(8, 1, 13, 1)));
    assert!(size(8, 5, 13, 17).is_smaller_than(&size(8, 1, 13, 18)));
    assert!(!size(8, 1, 13, 18).is_smaller_than(&size(8, 5, 13, 18)));
    assert!(!size(8, 5, 13, 18).is_smaller_than(&size(8, 5, 13, 18)));
}

fn report() -> Report {
    Report {
        properties: Vec::new(),
        nusmv_seconds: 0.1,
        nusmv_warnings: Vec::new(),
    }
}

fn exact_summary() -> ExactSummary {
    ExactSummary {
        size: Size {
            c: 2,
            k: 1,
            t: 2,
            n: 2,
        },
        transitions_proven_minimal: true,
        guards_proven_minimal: false,
        iterations: vec![Iteration {
            number: 1,
            checked_by: "NuSMV",
            c: 2,
            t: 2,
            failing: Vec::new(),
            counterexample_length: None,
            sat_seconds: 0.5,
            nusmv_seconds: 0.25,
            check_seconds: 0.25,
        }],
        report: report(),
        sat_seconds: 0.5,
        nusmv_seconds: 0.25,
        total_seconds: 1.0,
    }
}

fn guide_summary() -> GuideSummary {
    GuideSummary {
        exact_loop_below_it: "no smaller machine".into(),
        size: exact_summary().size,
        proven_least: false,
        least_for_recordings_and_runs: true,
        for_runs_unproven: false,
        states_at_least: Some(6),
        made_smaller: false,
        conventions: String::new(),
        guide: vec!["guide: the closed-loop game is won".into()],
        report: report(),
        sat_seconds: 0.5,
        nusmv_calls: 1,
        nusmv_seconds: 0.25,
        total_seconds: 1.0,
    }
}

fn search_summary() -> SearchSummary {
    let size = exact_summary().size;
    SearchSummary {
        seed: 1,
        start: "sat".into(),
        size,
        searched_size: size,
        shrunk_size: Some(size),
        replaced_by_exact_loop: false,
        shrink_rounds: Vec::new(),
        fitness: 1.0,
        search: crate::search::algorithm::Stats::default(),
        nusmv_runs: 0,
        in_process_checks: 3,
        cache_hits: 0,
        report: report(),
        total_seconds: 1.0,
    }
}

fn keys(s: &Summary) -> Vec<String> {
    let json = s.to_json();
    json.as_object().unwrap().keys().cloned().collect()
}

/// Every shape of `summary.json` keeps the keys its readers (and the tests) know.
#[test]
fn each_summary_has_the_keys_of_its_method() {
    let exact = Summary::Exact(exact_summary());
    assert_eq!(
        keys(&exact),
        [
            "guards_proven_minimal",
            "iterations",
            "nusmv_seconds",
            "report",
            "sat_seconds",
            "size",
            "total_seconds",
            "transitions_proven_minimal"
        ]
    );
    let below = Summary::Turn(Turn::BelowGuide(BelowGuideSummary {
        exact: exact_summary(),
        guide_size: exact_summary().size,
        guide: Vec::new(),
    }));
    let mut want = keys(&exact);
    want.extend(["guide", "guide_size", "method"].map(String::from));
    want.sort();
    assert_eq!(keys(&below), want);
    assert_eq!(
        below.to_json()["method"],
        "exact loop after the game's guide"
    );
    let guide = Summary::Turn(Turn::Guide(guide_summary()));
    assert_eq!(
        keys(&guide),
        [
            "exact_loop_below_it",
            "guide",
            "least_for_recordings_and_runs",
            "method",
            "nusmv_calls",
            "nusmv_seconds",
            "proven_least",
            "report",
            "sat_seconds",
            "size",
            "states_at_least",
            "total_seconds"
        ]
    );
    assert_eq!(guide.to_json()["method"], "game guide");
    let search = Summary::Turn(Turn::Search(Box::new(search_summary())));
    assert_eq!(search.to_json()["method"], "search");
    assert_eq!(
        keys(&search),
        [
            "cache_hits",
            "fitness",
            "in_process_checks",
            "method",
            "nusmv_runs",
            "replaced_by_exact_loop",
            "report",
            "search",
            "searched_size",
            "seed",
            "shrink_rounds",
            "shrunk_size",
            "size",
            "start",
            "total_seconds"
        ]
    );
    assert_eq!(search.size(), exact_summary().size);
}

/// Each shape validates against the schema `summary::schema` derives, and a summary with a
/// field of the wrong type does not.
#[test]
fn every_summary_validates_against_its_schema() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("summary.schema.json");
    let text = serde_json::to_string(&summary::schema()).unwrap();
    std::fs::write(&file, text).unwrap();
    let mut schemas = boon::Schemas::new();
    let index = boon::Compiler::new()
        .compile(file.to_str().unwrap(), &mut schemas)
        .expect("the schema compiles");
    let below = Turn::BelowGuide(BelowGuideSummary {
        exact: exact_summary(),
        guide_size: exact_summary().size,
        guide: Vec::new(),
    });
    for s in [
        Summary::Exact(exact_summary()),
        Summary::Turn(below),
        Summary::Turn(Turn::Guide(guide_summary())),
        Summary::Turn(Turn::Search(Box::new(search_summary()))),
    ] {
        let json = s.to_json();
        schemas
            .validate(&json, index)
            .unwrap_or_else(|e| panic!("{e}: {json}"));
    }
    let mut bad = Summary::Exact(exact_summary()).to_json();
    bad["size"]["c"] = "two".into();
    assert!(schemas.validate(&bad, index).is_err());
}

#[test]
fn the_guides_summary_says_which_bound_on_the_states_is_proven() {
    let said = |least: Option<usize>| {
        let g = GuideSummary {
            states_at_least: least,
            ..guide_summary()
        };
        Summary::Turn(Turn::Guide(g)).to_string()
    };
    let c = guide_summary().size.c;
    assert!(said(Some(c - 2)).contains(&format!("\nproven: C >= {} (no machine with fewer states reproduces the recordings); T and N are not bounded", c - 2)));
    assert!(said(Some(c)).contains(&format!("\nproven: C = {c} is least")));
    assert!(!said(None).contains("proven:"));
}

/// The guide's machine is called least only when it meets every bound (C, T at it, N at both,
/// each proven) and its guards are conjunctions, the machines the bounds are proven for.
#[test]
fn a_machine_meets_the_floor_only_in_every_figure_with_cube_guards() {
    use crate::ecc::{Algorithm, AlgorithmKind, Guard, InputId, State, StateId, Transition};
    let x = |i: usize| Guard::Var(InputId(i));
    let state = |target: usize, guard: Guard| State {
        name: String::new(),
        algorithm: Algorithm::keep_all(AlgorithmKind::Tri, 0),
        transitions: vec![Transition {
            target: StateId(target),
            guard,
        }],
    };
    let machine = |guard: Guard| Ecc {
        inputs: vec!["a".into(), "b".into()],
        outputs: vec![],
        initial_outputs: vec![],
        states: vec![state(1, guard), state(0, x(1))],
    };
    let cubes = machine(Guard::And(vec![x(0), x(1)]));
    let floor = Floor {
        c: 2,
        t: 2,
        n: Some(3),
    };
    assert!(floor.met_by(&cubes));
    assert!(!Floor {
        n: Some(2),
        ..floor
    }
    .met_by(&cubes));
    assert!(!Floor { n: None, ..floor }.met_by(&cubes));
    assert!(!Floor { t: 0, ..floor }.met_by(&cubes));
    assert!(!Floor { c: 1, ..floor }.met_by(&cubes));
    let dnf = machine(Guard::Or(vec![x(0), x(1)]));
    assert_eq!(dnf.size().n, 3);
    assert!(!floor.met_by(&dnf));
}

/// A guide's machine proven least says so in place of what it is least for, and drops the
/// bound on the states alone.
#[test]
fn the_guides_summary_says_least_when_it_is_proven() {
    let g = GuideSummary {
        proven_least: true,
        made_smaller: true,
        ..guide_summary()
    };
    let said = Summary::Turn(Turn::Guide(g)).to_string();
    assert!(
        said.contains(
            "\nC, T and N are least: the machine meets the lower bounds of the recordings alone"
        ),
        "{said}"
    );
    assert!(!said.contains("not proven least"), "{said}");
    assert!(!said.contains("proven: C"), "{said}");
}

/// The polish's progress line names the smallest machine so far, the moves judged and the
/// seconds since the moves began.
#[test]
fn the_polishing_line_says_the_machine_so_far_and_the_moves_judged() {
    let step = Step::Polishing {
        size: Size {
            c: 8,
            k: 3,
            t: 16,
            n: 43,
        },
        judged: 1492,
        seconds: 11.34,
    };
    assert_eq!(
        step.to_string(),
        "guide: making its machine smaller in process: C=8 K=3 T=16 N=43 so far (1492 moves judged, 11.3 s)"
    );
}
