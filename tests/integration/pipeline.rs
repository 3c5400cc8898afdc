//! Every pipeline called as a library user calls it: one function per method, one problem
//! type ([`Check`]), no files read back.

use crate::common::{nusmv_or_skip, Dir};
use fbsynth::pipeline::{self, exact, modular, noisy, refine, search, Check, Problem, Recordings};
use std::path::{Path, PathBuf};
use std::time::Duration;

fn file(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn lamp_check(set: &fbsynth::scenario::ScenarioSet) -> Option<Check> {
    let nusmv = nusmv_or_skip()?;
    let problem = Problem::load(
        &file("tests/data/closed_loop/lamp.ltl"),
        &file("tests/data/closed_loop/lamp_plant.smv"),
        &set.inputs,
        &set.outputs,
    )
    .unwrap();
    Some(Check::new(problem, nusmv))
}

fn lamp() -> fbsynth::scenario::ScenarioSet {
    Recordings::files(vec![file("tests/data/closed_loop/lamp.traces")])
        .load()
        .unwrap()
}

#[test]
fn exact_with_a_check_is_certified_by_nusmv_and_replays() {
    let set = lamp();
    let Some(check) = lamp_check(&set) else {
        return;
    };
    let mut events = 0;
    let r = exact::run(&set, Some(&check), &exact::Options::default(), &mut |_| {
        events += 1
    })
    .unwrap();
    let cert = r.certificate.expect("checked");
    assert!(cert.report.all_hold(), "{}", cert.report.to_text());
    assert!(!r.iterations.is_empty() && events > 0);
    set.check(&r.synthesis.ecc).unwrap();
    // The certificate is NuSMV's: asking again gives the same verdicts.
    let again = pipeline::verify(&r.synthesis.ecc, &check).unwrap();
    assert!(again.report.all_hold());
}

/// A loop stopped for lack of progress hands every counterexample it learned to the next
/// turn on the same problem, which then never proposes a machine one of them refutes.
#[test]
fn a_stalled_loop_hands_what_it_learned_to_the_next_turn() {
    let set = lamp();
    let Some(check) = lamp_check(&set) else {
        return;
    };
    let fresh = exact::run(&set, Some(&check), &exact::Options::default(), &mut |_| {}).unwrap();
    let refuted = |r: &exact::Exact| {
        r.iterations
            .iter()
            .filter(|i| !i.failing.is_empty())
            .count()
    };
    assert!(refuted(&fresh) >= 2, "{:?}", fresh.iterations);
    let stalling = exact::Options {
        stall: Some(pipeline::Stall {
            rounds: 1,
            time: Duration::from_secs(3600),
            hard_time: Duration::from_secs(3600),
        }),
        ..exact::Options::default()
    };
    let learned = match exact::run(&set, Some(&check), &stalling, &mut |_| {}) {
        Err(pipeline::Error::Cegis(pipeline::CegisError::Stalled { learned, .. })) => learned,
        other => panic!(
            "expected the loop to stall: {:?}",
            other.map(|r| r.iterations)
        ),
    };
    assert!(!learned.is_empty());
    let next = exact::Options {
        learned: *learned,
        ..exact::Options::default()
    };
    let r = exact::run(&set, Some(&check), &next, &mut |_| {}).unwrap();
    assert!(r.certificate.as_ref().expect("checked").report.all_hold());
    set.check(&r.synthesis.ecc).unwrap();
    assert_eq!(r.synthesis.size, fresh.synthesis.size);
    assert!(
        refuted(&r) < refuted(&fresh),
        "{:?} after {:?}",
        r.iterations,
        fresh.iterations
    );
}

/// Where a candidate's descent in `T` runs out of its work budget (station seed 1: its
/// candidates with 8 states need more transitions than its recording alone), the loop stalls
/// after [`pipeline::Stall::hard_time`] of refuting them, not after `time`; without that, the
/// same loop goes on to a verified machine.
#[test]
fn a_loop_whose_descent_in_t_runs_out_stalls_after_the_hard_time() {
    let Some(nusmv) = nusmv_or_skip() else { return };
    let dir = Dir::new();
    fbsynth::cases::station::write_files(dir.path(), 1).unwrap();
    let set = Recordings::files(vec![dir.path().join("station.traces")])
        .load()
        .unwrap();
    let problem = Problem::load(
        &dir.path().join("station.ltl"),
        &dir.path().join("plant.smv"),
        &set.inputs,
        &set.outputs,
    )
    .unwrap();
    let check = Check::new(problem, nusmv);
    let stall = |hard_time| exact::Options {
        stall: Some(pipeline::Stall {
            rounds: 1_000,
            time: Duration::from_secs(3600),
            hard_time,
        }),
        ..exact::Options::default()
    };
    match exact::run(&set, Some(&check), &stall(Duration::ZERO), &mut |_| {}) {
        Err(pipeline::Error::Cegis(pipeline::CegisError::Stalled { rounds, .. })) => {
            assert!(rounds >= 3, "stalled after {rounds} candidates")
        }
        other => panic!(
            "expected the loop to stall: {:?}",
            other.map(|r| r.iterations)
        ),
    }
    let r = exact::run(
        &set,
        Some(&check),
        &stall(Duration::from_secs(3600)),
        &mut |_| {},
    )
    .unwrap();
    assert!(r.certificate.as_ref().expect("checked").report.all_hold());
    set.check(&r.synthesis.ecc).unwrap();
}

#[test]
fn search_ends_with_nusmv_s_verdict_on_its_machine() {
    let set = lamp();
    let Some(check) = lamp_check(&set) else {
        return;
    };
    let opts = search::Options {
        threads: Some(1),
        colonies: 1,
        time_limit: 5.0,
        ..search::Options::default()
    };
    let mut rounds = 0;
    let r = search::run(&set, &check, &opts, None, &mut |e| {
        if matches!(e, pipeline::Event::SearchRound(_)) {
            rounds += 1
        }
    })
    .unwrap();
    // The final verdict is NuSMV's, on every property, whatever the search saw.
    assert_eq!(r.verification.report.properties.len(), 2);
    let fresh = pipeline::verify(&r.outcome.ecc, &check).unwrap();
    assert_eq!(fresh.report.all_hold(), r.verification.report.all_hold());
    match r.certified(&set, &opts) {
        Ok(ecc) => {
            set.check(ecc).unwrap();
            // Made small along the closed loop: no larger, still reproducing the recordings,
            // and NuSMV's verdict on it (asked again here) is that every property holds.
            let (small, followed) = search::shrink(&set, ecc, &check, 6, &mut |_| {}).unwrap();
            let (a, b) = (small.size, ecc.size());
            assert!((a.c, a.t, a.n) <= (b.c, b.t, b.n), "{a} after {b}");
            set.check(&small.ecc).unwrap();
            assert!(followed.certificate.report.all_hold());
            assert!(pipeline::verify(&small.ecc, &check)
                .unwrap()
                .report
                .all_hold());
        }
        Err(e) => assert_eq!(e.class(), pipeline::Class::NoMachine, "{e}"),
    }
    assert!(rounds > 0);
}

#[test]
fn noisy_and_modular_run_from_the_library() {
    let set = Recordings::files(vec![file("tests/data/noisy/skewed.csv")])
        .load()
        .unwrap();
    let opts = noisy::Options {
        max_errors: Some(1),
        enumerate: 2,
        ..noisy::Options::default()
    };
    let r = noisy::run(&set, None, &opts, &mut |_| {}).unwrap();
    assert!(!r.synthesis.candidates.is_empty());
    assert!(r.closed.is_empty() && r.chosen().is_none());
    for c in &r.synthesis.candidates {
        c.corrected.check(&c.ecc).unwrap();
    }
    let lamps = Recordings::files(vec![file("tests/data/scenarios/lamps.traces")])
        .load()
        .unwrap();
    let m = modular::run(
        &lamps,
        &modular::Options {
            modules: 2,
            ..modular::Options::default()
        },
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(m.modular.modules.len(), 2);
}

#[test]
fn refine_learns_divergent_traces_in_process() {
    let old = Recordings::files(vec![file("tests/data/scenarios/door.traces")])
        .load()
        .unwrap();
    let new = Recordings::files(vec![file("tests/data/scenarios/door_new.traces")])
        .load()
        .unwrap();
    let first = exact::run(&old, None, &exact::Options::default(), &mut |_| {})
        .unwrap()
        .synthesis
        .ecc;
    assert!(!new.divergences(&first).is_empty());
    let out = Dir::new();
    let formats = [fbsynth::export::Format::Json];
    let opts = refine::Options {
        out: out.path(),
        formats: &formats,
        name: "Door",
        exact: exact::Options::default(),
    };
    let refined = refine::run(&first, &new, old.clone(), None, &opts, &mut |_| {})
        .unwrap()
        .expect("a trace diverges");
    assert_eq!(refined.divergent, vec![0]);
    assert!(new.divergences(refined.ecc()).is_empty());
    old.check(refined.ecc()).unwrap();
    assert!(refined.traces_file.is_file());
    // A machine that already reproduces everything needs no refinement.
    let again = refine::run(refined.ecc(), &new, old, None, &opts, &mut |_| {}).unwrap();
    assert!(again.is_none());
}

/// Safety properties that demand behaviour the recording lacks: the loop gets it from the
/// properties inside the encoding (environments from the in-process checker's
/// counterexamples), and NuSMV certifies the result.
#[test]
fn properties_inside_the_encoding_supply_unrecorded_behaviour() {
    let set = lamp();
    let Some(nusmv) = nusmv_or_skip() else {
        return;
    };
    let problem = Problem::load(
        &file("tests/data/closed_loop/lamp_safety.ltl"),
        &file("tests/data/closed_loop/lamp_plant.smv"),
        &set.inputs,
        &set.outputs,
    )
    .unwrap();
    assert!(problem.model.is_ok(), "{:?}", problem.model.as_ref().err());
    let check = Check::new(problem, nusmv);
    // The recording alone: the lamp never goes out.
    let alone = exact::run(&set, None, &exact::Options::default(), &mut |_| {}).unwrap();
    assert!(!pipeline::verify(&alone.synthesis.ecc, &check)
        .unwrap()
        .report
        .all_hold());
    let r = exact::run(&set, Some(&check), &exact::Options::default(), &mut |_| {}).unwrap();
    let cert = r.certificate.expect("checked");
    assert!(cert.report.all_hold(), "{}", cert.report.to_text());
    set.check(&r.synthesis.ecc).unwrap();
    assert!(
        r.iterations.iter().any(|i| i.checked_by == "in-process"),
        "the in-process checker found no counterexample: {:?}",
        r.iterations
    );
    // The result is a machine NuSMV passed: the last iteration, or the candidate just before
    // a final pass that found nothing smaller.
    let passed = r
        .iterations
        .iter()
        .rposition(|i| i.checked_by == "NuSMV" && i.failing.is_empty())
        .expect("a candidate NuSMV passed");
    assert!(
        passed + 1 == r.iterations.len()
            || r.iterations.last().unwrap().checked_by == fbsynth::pipeline::exact::UNCHANGED
    );
}
