//! Helpers shared by the integration tests.

use fbsynth::ecc::{Ecc, Run};
use fbsynth::scenario::{Origin, Scenario, ScenarioSet, Step};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::{Path, PathBuf};
use std::process::Command;

pub use fbsynth::ecc::random::random_ecc;

/// Records `runs` random runs of `len` steps of `ecc` as scenarios.
pub fn record(ecc: &Ecc, seed: u64, runs: usize, len: usize) -> ScenarioSet {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    let scenarios = (0..runs)
        .map(|r| {
            let mut run = Run::new(ecc);
            let steps = (0..len)
                .map(|_| {
                    let x: Vec<bool> = (0..ecc.inputs.len())
                        .map(|_| rng.gen_bool(0.5))
                        .collect::<Vec<bool>>();
                    let fired = run.step(&x).is_some();
                    Step {
                        inputs: x,
                        outputs: fired.then(|| run.outputs.clone()),
                    }
                })
                .collect();
            Scenario {
                origin: Origin {
                    file: PathBuf::from("random"),
                    line: r + 2,
                    rows: None,
                },
                steps,
            }
        })
        .collect();
    ScenarioSet {
        inputs: ecc.inputs.clone(),
        outputs: ecc.outputs.clone(),
        initial_outputs: ecc.initial_outputs.clone(),
        scenarios,
    }
}

/// An external tool from the variable `env` or the PATH (`name`); `None` (a skip, with a note)
/// without it, and a failure under `CI=true`, since CI installs it with `installer`.
pub fn tool_or_skip(env: &str, name: &str, installer: &str) -> Option<PathBuf> {
    let found = std::env::var_os(env)
        .map(PathBuf::from)
        .filter(|p| p.is_file())
        .or_else(|| which::which(name).ok());
    match found {
        Some(p) => Some(p),
        None if std::env::var("CI").as_deref() == Ok("true") => {
            panic!("{name} is required when CI=true ({installer} installs it)")
        }
        None => {
            eprintln!("skipping: no {name} (set {env} or put it on the PATH)");
            None
        }
    }
}

/// Validates `file` with xmllint against `schema` (a file in tests/schemas/: `.xsd` is an XML
/// Schema, `.rng` a RELAX NG grammar, `.dtd` a DTD); the verdict and xmllint's messages.
/// `--nonet`: a DOCTYPE's address on the web is never fetched, the given schema decides.
pub fn xmllint(xmllint: &Path, schema: &str, file: &Path) -> (bool, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/schemas")
        .join(schema);
    let option = match path.extension().and_then(|e| e.to_str()) {
        Some("xsd") => "--schema",
        Some("rng") => "--relaxng",
        Some("dtd") => "--dtdvalid",
        _ => panic!("{schema}: not a schema xmllint reads"),
    };
    let o = Command::new(xmllint)
        .args(["--noout", "--nonet", option])
        .arg(&path)
        .arg(file)
        .output()
        .expect("run xmllint");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}
