//! `synth diff`: do two machines behave alike, and if not, on which inputs do they differ.

use super::{exit, Failure};
use crate::ecc::bits_to_string;
use crate::ecc::diff::{difference, structure, Structure};
use crate::pipeline::recordings::read_ecc;
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
/// initial states on which they answer differently, step by step (exit 1); then the states
/// matched up and what differs between matched states.
pub fn diff(args: &DiffArgs) -> Result<(), Failure> {
    if super::json() {
        super::data_on_stdout();
    }
    let a = read_ecc(&args.first)?;
    let b = read_ecc(&args.second)?;
    let found = difference(&a, &b).map_err(|e| Failure::msg(exit::INPUT, e.to_string()))?;
    if super::json() {
        let bits = crate::ecc::bits_to_string;
        let summary = serde_json::json!({
            "equivalent": found.is_none(),
            "difference": found.as_ref().map(|d| serde_json::json!({
                "inputs": d.inputs.iter().map(|x| bits(x)).collect::<Vec<_>>(),
                "first": d.first.as_deref().map(bits),
                "second": d.second.as_deref().map(bits),
            })),
        });
        super::write_json(&summary)?;
    }
    let matched = structure(&a, &b).map_err(|e| Failure::msg(exit::INPUT, e.to_string()))?;
    let Some(d) = found else {
        out!(
            "equivalent: {} and {} answer every input sequence alike",
            args.first.display(),
            args.second.display()
        );
        print_structure(&matched);
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
    print_structure(&matched);
    Err(Failure::msg(exit::FAILED, "the machines differ"))
}

/// The states matched up (first machine's state ~ second's), then every change per pair.
fn print_structure(s: &Structure) {
    let pairs: Vec<String> = (s.pairs.iter())
        .map(|p| format!("{}~{}", p.first, p.second))
        .collect();
    let changed = s.pairs.iter().filter(|p| !p.changes.is_empty()).count();
    out!(
        "structure: {} state pair{} ({}); {}",
        s.pairs.len(),
        if s.pairs.len() == 1 { "" } else { "s" },
        pairs.join(" "),
        match changed {
            0 => "no change".to_string(),
            n => format!("{n} with changes (first machine, then second):"),
        }
    );
    for p in s.pairs.iter().filter(|p| !p.changes.is_empty()) {
        for c in &p.changes {
            out!("  {}~{}: {c}", p.first, p.second);
        }
    }
    let list = |v: &[crate::ecc::StateId]| {
        v.iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    if !s.unmatched_first.is_empty() {
        out!("  only in the first machine: {}", list(&s.unmatched_first));
    }
    if !s.unmatched_second.is_empty() {
        out!(
            "  only in the second machine: {}",
            list(&s.unmatched_second)
        );
    }
}
