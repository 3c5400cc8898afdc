//! Synthesis from noisy logs: the distribution-station case end to end (library), the
//! shipped files, and `synth infer --noisy` as a user runs it.

use crate::cases::distribution::{self, generate, to_scenarios, SHIPPED_RATE, SHIPPED_SEED};
use crate::common::{nusmv_or_skip, synth, text, Dir};
use fbsynth::export::json::read_json;
use fbsynth::sat::noisy::{synthesize_noisy, Flow, NoisyOptions};
use std::path::Path;

/// With the injected number of errors as the bound, the tool corrects no more than were
/// injected, and among the first candidates one behaves like the reference on the clean
/// training logs and on held-out runs it never saw.
#[test]
fn noisy_distribution_logs_give_the_reference_behaviour() {
    let logs = generate(SHIPPED_RATE, SHIPPED_SEED);
    assert!(logs.injected > 0);
    let noisy = to_scenarios(&logs.noisy, "noisy.csv");
    let opts = NoisyOptions {
        max_errors: Some(logs.injected),
        enumerate: 3,
        ..NoisyOptions::default()
    };
    let r = synthesize_noisy(&noisy, &opts, &mut |_| {}, &mut |_| Flow::Continue).unwrap();
    let first = &r.candidates[0];
    assert!(first.errors <= logs.injected);
    // The noisy traces contradict each other: some correction is needed.
    assert!(first.errors > 0);
    let clean = to_scenarios(&logs.clean, "clean.csv");
    let held_out = to_scenarios(&logs.held_out, "held_out.csv");
    assert_eq!(held_out.check(&distribution::reference()), Ok(()));
    let good = r
        .candidates
        .iter()
        .position(|c| clean.check(&c.ecc).is_ok() && held_out.check(&c.ecc).is_ok());
    assert!(good.is_some(), "no candidate replays the held-out runs");
}

/// `specs/` holds exactly what `synth-dev generate distribution` writes.
#[test]
fn shipped_distribution_files_match_the_generator() {
    let dir = Dir::new();
    let (files, _) = distribution::write_files(dir.path()).unwrap();
    let specs = Path::new(env!("CARGO_MANIFEST_DIR")).join("specs");
    for f in files {
        let name = f.file_name().unwrap();
        let shipped = std::fs::read(specs.join(name)).unwrap();
        assert!(
            shipped == std::fs::read(&f).unwrap(),
            "specs/{} differs from the generator: run synth-dev generate distribution",
            name.to_string_lossy()
        );
        assert!(shipped.len() < 200_000);
    }
}

#[test]
fn infer_noisy_writes_a_folder_per_candidate_and_a_summary() {
    let out = Dir::new();
    let o = synth(&[
        "infer",
        "--noisy",
        "--max-errors",
        "1",
        "--enumerate",
        "4",
        "--traces",
        "tests/data/noisy/skewed.csv",
        "--format",
        "json,fbt",
        "--out",
        out.path().to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["c"], 2);
    let candidates = summary["candidates"].as_array().unwrap();
    assert!(!candidates.is_empty());
    assert_eq!(candidates[0]["errors"], 1);
    assert!(out.path().join("summary.txt").is_file());
    let dir = out.path().join("candidate_1");
    for f in [
        "SynthesizedFB.json",
        "SynthesizedFB.fbt",
        "corrected.txt",
        "corrected.csv",
        "candidate.json",
    ] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    // The corrected log replays on the candidate, the raw one does not.
    let json = dir.join("SynthesizedFB.json");
    let ecc = read_json(&std::fs::read_to_string(&json).unwrap(), &json).unwrap();
    let corrected =
        fbsynth::scenario::csvlog::read(&dir.join("corrected.csv"), None, None).unwrap();
    assert_eq!(corrected.check(&ecc), Ok(()));
    let raw = fbsynth::scenario::csvlog::read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/noisy/skewed.csv"),
        None,
        None,
    )
    .unwrap();
    assert!(raw.check(&ecc).is_err());
    // Bounds are checked: no error allowed, no machine.
    let o = synth(&[
        "infer",
        "--noisy",
        "--max-errors",
        "0",
        "--max-states",
        "3",
        "--traces",
        "tests/data/noisy/skewed.csv",
        "--out",
        out.path().to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", text(&o.stderr));
}

/// The shipped properties hold for the reference controller in closed loop (NuSMV).
#[test]
fn reference_satisfies_the_distribution_properties() {
    if nusmv_or_skip().is_none() {
        return;
    }
    let o = synth(&[
        "verify",
        "--ecc",
        "specs/distribution_reference.json",
        "--ltl",
        "specs/distribution.ltl",
        "--plant",
        "smv/distribution_surrogate.smv",
    ]);
    assert!(o.status.success(), "{}{}", text(&o.stdout), text(&o.stderr));
    assert!(text(&o.stdout).contains("verified: all 8 properties hold"));
}
