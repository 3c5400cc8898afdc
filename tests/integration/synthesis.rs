//! Synthesis from the runs of random machines: the result replays every run and is no larger
//! than the machine that produced them.

use crate::common::{random_ecc, record, Dir, TestCommand};
use fbsynth::sat::{synthesize, Options};
use fbsynth::scenario::tree::ScenarioTree;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn synthesized_machine_replays_runs_and_is_no_larger(
        seed in any::<u64>(),
        c in 1usize..=4,
        inputs in 1usize..=3,
        outputs in 1usize..=3,
        runs in 1usize..=4,
        len in 1usize..=12,
    ) {
        let gen = random_ecc(seed, c, inputs, outputs);
        let set = record(&gen, seed, runs, len);
        let tree = ScenarioTree::build(&set).expect("runs of one machine never contradict");
        let r = synthesize(&set, &tree, &Options::default(), &mut |_| {}).expect("a machine exists");
        prop_assert!(set.check(&r.ecc).is_ok());
        prop_assert!(r.size.c <= c, "synthesized {} states from a {}-state machine", r.size.c, c);
    }
}

/// CaDiCaL from `$CADICAL` or the PATH (`.ci/install-cadical.sh`).
fn cadical_or_skip() -> Option<std::path::PathBuf> {
    crate::common::tool_or_skip("CADICAL", "cadical", ".ci/install-cadical.sh")
}

/// `--dump-cnf` writes the questions that prove C and T minimal; an independent solver gives
/// varisat's verdict on every file, and the verdicts are the minimality claims.
#[test]
fn dumped_cnf_files_solve_alike_with_cadical() {
    let Some(cadical) = cadical_or_skip() else {
        return;
    };
    let dir = Dir::new();
    let cnf = dir.path().join("cnf");
    let o = TestCommand::new()
        .args([
            "infer",
            "-q",
            "--no-ambiguity",
            "--traces",
            "specs/pnp.traces",
            "--out",
        ])
        .arg(dir.path().join("out"))
        .arg("--dump-cnf")
        .arg(&cnf)
        .output();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let verdicts = std::fs::read_to_string(cnf.join("verdicts.txt")).unwrap();
    assert_eq!(
        verdicts,
        "states-8.cnf SATISFIABLE\nstates-7.cnf UNSATISFIABLE\n\
         transitions-13.cnf SATISFIABLE\ntransitions-12.cnf UNSATISFIABLE\n"
    );
    for line in verdicts.lines() {
        let (file, verdict) = line.split_once(' ').unwrap();
        let status = std::process::Command::new(&cadical)
            .arg("-q")
            .arg(cnf.join(file))
            .status()
            .unwrap();
        // The SAT competition's exit codes: 10 satisfiable, 20 unsatisfiable.
        let expected = if verdict == "SATISFIABLE" { 10 } else { 20 };
        assert_eq!(status.code(), Some(expected), "{file}");
    }
}
