//! `synth diff`: do two machines behave alike, and if not, on which inputs do they differ.

use super::{exit, Failure};
use fbsynth::ecc::bits_to_string;
use fbsynth::ecc::diff::difference;
use fbsynth::pipeline::recordings::read_ecc;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct DiffArgs {
    /// The first machine, in the JSON format `synth infer` writes.
    #[arg(value_name = "A.json")]
    pub first: PathBuf,
    /// The second machine, over the same inputs and outputs.
    #[arg(value_name = "B.json")]
    pub second: PathBuf,
}

/// `synth diff A.json B.json`: "equivalent" (exit 0), or the shortest input sequence from the
/// initial states on which they answer differently, step by step (exit 1).
pub fn diff(args: &DiffArgs) -> Result<(), Failure> {
    let a = read_ecc(&args.first)?;
    let b = read_ecc(&args.second)?;
    let found = difference(&a, &b).map_err(|e| Failure::msg(exit::INPUT, e.to_string()))?;
    let Some(d) = found else {
        out!(
            "equivalent: {} and {} answer every input sequence alike",
            args.first.display(),
            args.second.display()
        );
        return Ok(());
    };
    let answer = |o: &Option<Vec<bool>>| match o {
        Some(o) => format!("CNF[{}]", bits_to_string(o)),
        None => "nothing".to_string(),
    };
    out!(
        "different: after {} REQ{} they answer differently",
        d.inputs.len(),
        if d.inputs.len() == 1 { "" } else { "s" }
    );
    out!("inputs: {}", a.inputs.join(" "));
    out!("outputs: {}", a.outputs.join(" "));
    for (k, x) in d.inputs.iter().enumerate() {
        let last = k + 1 == d.inputs.len();
        out!(
            "  step {}: inputs {}{}",
            k + 1,
            bits_to_string(x),
            if last { "" } else { " (answered alike)" }
        );
    }
    if d.inputs.is_empty() {
        out!("  their initial outputs differ");
    }
    out!("  {} answers {}", args.first.display(), answer(&d.first));
    out!("  {} answers {}", args.second.display(), answer(&d.second));
    Err(Failure::msg(exit::INPUT, "the machines differ"))
}
