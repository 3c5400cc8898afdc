//! `synth diff`: do two machines behave alike, and if not, on which inputs do they differ;
//! then their states matched up and what differs between matched states.

use crate::ecc::bits_to_string;
use crate::ecc::diff::{difference, structure, Difference, Structure};
use crate::ecc::{Ecc, StateId};
use crate::pipeline::event::plural;
use crate::pipeline::recordings::read_ecc;
use crate::pipeline::summary::DiffSummary;
use crate::pipeline::Error;
use std::fmt;
use std::path::PathBuf;

/// Two machines compared.
pub(crate) struct Compared {
    /// The first machine's file.
    pub first: PathBuf,
    /// The second machine's file.
    pub second: PathBuf,
    /// The first machine.
    pub a: Ecc,
    /// The shortest input sequence on which they answer differently.
    pub difference: Option<Difference>,
    /// Their states matched up.
    pub structure: Structure,
}

/// Reads both machines and compares them.
pub(crate) fn run(first: &std::path::Path, second: &std::path::Path) -> Result<Compared, Error> {
    let a = read_ecc(first)?;
    let b = read_ecc(second)?;
    let found = difference(&a, &b)?;
    Ok(Compared {
        first: first.to_path_buf(),
        second: second.to_path_buf(),
        structure: structure(&a, &b)?,
        a,
        difference: found,
    })
}

impl Compared {
    /// The `--json` summary.
    pub fn summary(&self) -> DiffSummary {
        DiffSummary::new(self.difference.as_ref())
    }

    /// When they differ, the failure that says so.
    pub fn failure(&self) -> Option<Error> {
        (self.difference.is_some()).then(|| Error::Negative("the machines differ".into()))
    }
}

/// "equivalent", or the shortest sequence step by step and both answers; then the structure.
impl fmt::Display for Compared {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Some(d) = &self.difference else {
            writeln!(
                f,
                "equivalent: {} and {} answer every input sequence alike",
                self.first.display(),
                self.second.display()
            )?;
            return write!(f, "{}", Matched(&self.structure));
        };
        let answer = |o: &Option<Vec<bool>>| match o {
            Some(o) => format!("CNF[{}]", bits_to_string(o)),
            None => "nothing".to_string(),
        };
        writeln!(
            f,
            "different: after {} they answer differently",
            plural(d.inputs.len(), "REQ")
        )?;
        writeln!(f, "inputs: {}", self.a.inputs.join(" "))?;
        writeln!(f, "outputs: {}", self.a.outputs.join(" "))?;
        for (k, x) in d.inputs.iter().enumerate() {
            let last = k + 1 == d.inputs.len();
            let alike = if last { "" } else { " (answered alike)" };
            writeln!(f, "  step {}: inputs {}{alike}", k + 1, bits_to_string(x))?;
        }
        if d.inputs.is_empty() {
            writeln!(f, "  their initial outputs differ")?;
        }
        writeln!(f, "  {} answers {}", self.first.display(), answer(&d.first))?;
        writeln!(
            f,
            "  {} answers {}",
            self.second.display(),
            answer(&d.second)
        )?;
        write!(f, "{}", Matched(&self.structure))
    }
}

/// The states matched up (first machine's state ~ second's), then every change per pair.
struct Matched<'a>(&'a Structure);

impl fmt::Display for Matched<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = self.0;
        let pairs: Vec<String> = (s.pairs.iter())
            .map(|p| format!("{}~{}", p.first, p.second))
            .collect();
        let changed = s.pairs.iter().filter(|p| !p.changes.is_empty()).count();
        write!(
            f,
            "structure: {} ({}); {}",
            plural(s.pairs.len(), "state pair"),
            pairs.join(" "),
            match changed {
                0 => "no change".to_string(),
                n => format!("{n} with changes (first machine, then second):"),
            }
        )?;
        for p in s.pairs.iter().filter(|p| !p.changes.is_empty()) {
            for c in &p.changes {
                write!(f, "\n  {}~{}: {c}", p.first, p.second)?;
            }
        }
        let list = |v: &[StateId]| {
            v.iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        };
        if !s.unmatched_first.is_empty() {
            write!(
                f,
                "\n  only in the first machine: {}",
                list(&s.unmatched_first)
            )?;
        }
        if !s.unmatched_second.is_empty() {
            write!(
                f,
                "\n  only in the second machine: {}",
                list(&s.unmatched_second)
            )?;
        }
        Ok(())
    }
}
