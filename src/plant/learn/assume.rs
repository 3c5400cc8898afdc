//! The user's assumptions about the plant (`--assume PLANT.ltl`): what the user knows of it
//! beyond the recordings, such as two end sensors of one cylinder never on at once.
//!
//! In: the properties of the assumptions file, the recordings' interface. Out: the
//! [`Assumptions`], whose names the learned plant's header lists; or an [`AssumeError`]
//! naming the file and line. The caller checks the recordings against them first: a recorded
//! run that breaks one is named with its first violating step, and nothing is written.
//!
//! They are not constraints of the learned module. As an `INVAR`, even an exclusion the
//! recordings keep makes states of the learned plant dead ends: its dwell bounds, learned per
//! sensor, can force two changes that together break it, and a plant that blocks is refused
//! (NuSMV ignores the runs it blocks). Enforcing them needs the learned timing refined where
//! it contradicts them, which the learner does not do.
//!
//! An assumption that reads a controller output is refused: it would speak of the
//! controller, not of the plant.

use crate::ltl::Property;
use std::path::{Path, PathBuf};

/// The assumptions of one file.
#[derive(Debug, Clone)]
pub(crate) struct Assumptions {
    /// The file they come from.
    pub(crate) file: PathBuf,
    /// Their names, in file order.
    pub(crate) names: Vec<String>,
}

/// An assumption the tool cannot take.
#[derive(Debug, thiserror::Error)]
pub(crate) enum AssumeError {
    /// It reads a name that is neither a sensor nor a controller output.
    #[error("{file}:{line}: the assumption {name} reads {signal}, which is neither a sensor nor a controller output of the recordings")]
    Unknown {
        file: String,
        line: usize,
        name: String,
        signal: String,
    },
    /// It reads a controller output.
    #[error("{file}:{line}: the assumption {name} reads the controller output {signal}: a plant must accept every command (a constraint on the commands would block the controller, and NuSMV's verdicts ignore blocked runs); state assumptions over the sensors only")]
    ReadsOutput {
        file: String,
        line: usize,
        name: String,
        signal: String,
    },
}

impl Assumptions {
    /// `props` from `file`, over the recordings' `sensors` and `outputs`.
    pub(crate) fn of(
        file: &Path,
        props: &[Property],
        sensors: &[String],
        outputs: &[String],
    ) -> Result<Assumptions, AssumeError> {
        let mut names = Vec::new();
        for (k, p) in props.iter().enumerate() {
            let name = crate::ltl::property_name(k, p);
            refuse_names(file, p, &name, sensors, outputs)?;
            names.push(name);
        }
        Ok(Assumptions {
            file: file.to_path_buf(),
            names,
        })
    }

    /// The comment added to the learned module: what is assumed, and how far.
    pub(crate) fn text(&self) -> String {
        format!(
            "    -- Assumed (from {}): {}; the recordings keep them, this model does not enforce them.\n",
            self.file.display(),
            self.names.join(", ")
        )
    }
}

/// Refuses a name of `p` that is a controller output, or neither a sensor nor an output.
fn refuse_names(
    file: &Path,
    p: &Property,
    name: &str,
    sensors: &[String],
    outputs: &[String],
) -> Result<(), AssumeError> {
    for signal in p.formula.names() {
        let (file, line, name) = (file.display().to_string(), p.line, name.to_string());
        if outputs.contains(&signal) {
            return Err(AssumeError::ReadsOutput {
                file,
                line,
                name,
                signal,
            });
        }
        if !sensors.contains(&signal) {
            return Err(AssumeError::Unknown {
                file,
                line,
                name,
                signal,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn props(text: &str) -> Vec<Property> {
        crate::ltl::parse_spec(Path::new("a.ltl"), text).unwrap()
    }

    fn names(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn the_header_names_every_assumption() {
        let a = Assumptions::of(
            Path::new("a.ltl"),
            &props("ends: G !(home & end)\nG (home -> F end)\n"),
            &names(&["home", "end"]),
            &names(&["extend"]),
        )
        .unwrap();
        assert_eq!(a.names, vec!["ends".to_string(), "p2".to_string()]);
        assert!(
            a.text().contains("Assumed (from a.ltl): ends, p2;"),
            "{}",
            a.text()
        );
    }

    #[test]
    fn a_command_or_an_unknown_name_is_refused_with_the_line() {
        let sensors = names(&["home"]);
        let outputs = names(&["push"]);
        let e = Assumptions::of(
            Path::new("a.ltl"),
            &props("ok: G home\nbad: G (push -> home)\n"),
            &sensors,
            &outputs,
        )
        .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("a.ltl:2: the assumption bad reads the controller output push"),
            "{e}"
        );
        let e = Assumptions::of(Path::new("a.ltl"), &props("G ghost\n"), &sensors, &outputs)
            .unwrap_err();
        assert!(
            e.to_string()
                .contains("a.ltl:1: the assumption p1 reads ghost"),
            "{e}"
        );
    }
}
