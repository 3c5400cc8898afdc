//! fbsynth as a library: the main job from code. Reads the Pick-and-Place recordings, states
//! the properties and the plant, synthesizes the least controller that NuSMV verifies, replays
//! it on every recording and prints it as Structured Text.
//!
//! Run from the repository root with NuSMV installed (`.ci/install-nusmv.sh`):
//!
//! ```sh
//! NUSMV="$(.ci/install-nusmv.sh)" cargo run --release --example synthesize_and_verify
//! ```

use fbsynth::export::{self, Format};
use fbsynth::pipeline::{self, exact, Check, Problem, Recordings};
use std::path::{Path, PathBuf};

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    // The scenarios, with the interface names from specs/pnp.inputs and specs/pnp.outputs.
    let set = Recordings::files(vec![PathBuf::from("specs/pnp.traces")]).load()?;
    // The properties over that interface, in closed loop with the surrogate plant.
    let problem = Problem::load(
        Path::new("specs/pnp.ltl"),
        Path::new("smv/pnp_surrogate.smv"),
        &set.inputs,
        &set.outputs,
    )?;
    // NuSMV from $NUSMV, the PATH or the install script's cache; 60 s per model at most.
    let check = Check::new(problem, pipeline::nusmv(None, 60.0)?);
    let result = exact::run(&set, Some(&check), &exact::Options::default(), &mut |e| {
        eprintln!("{}", describe(&e));
    })?;
    let certificate = result
        .certificate
        .expect("a check gives NuSMV's certificate");
    assert!(
        certificate.report.all_hold(),
        "only a verified machine is returned"
    );
    // Every synthesized machine reproduces its recordings; check it here too.
    set.check(&result.synthesis.ecc)?;
    println!(
        "verified by NuSMV: {} properties; {}",
        certificate.report.properties.len(),
        result.synthesis.size
    );
    println!(
        "{}",
        export::text(&result.synthesis.ecc, "PickAndPlace", Format::St)?
    );
    Ok(())
}

/// One progress line per event: the candidates and their verdicts.
fn describe(e: &pipeline::Event<'_>) -> String {
    match e {
        pipeline::Event::Candidate(it) => format!(
            "candidate {}: C = {} T = {}, failing: {:?}",
            it.number, it.c, it.t, it.failing
        ),
        pipeline::Event::Solver(step) => step.to_string(),
        other => format!("{other:?}"),
    }
}
