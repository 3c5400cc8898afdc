//! The output rule: no run removes or replaces a file it reads, or a result another command
//! wrote, unless the user asked (`--force`). Every command that writes declares what it reads
//! ([`Claim`]); the checks are here, for output folders ([`super::ResultSet`]: before any
//! work, and again for the exact files a publish replaces or removes) and for single output
//! files ([`refuse_inputs`]).
//!
//! In: the paths a run reads and writes. Out: a refusal ([`RuleError`]) naming both files, or
//! the output folder and the command whose result it holds.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// `--force`: the user allows replacing inputs and other commands' results.
static FORCE: AtomicBool = AtomicBool::new(false);

/// Sets `--force` for this process (the command line, once, after parsing).
pub(crate) fn allow_replacing(force: bool) {
    FORCE.store(force, Ordering::Relaxed);
}

fn forced() -> bool {
    FORCE.load(Ordering::Relaxed)
}

/// Names of result files that do not depend on the machine's name: an input under one of
/// them inside an output folder is refused before any work.
const RESULT_NAMES: [&str; 4] = [
    "summary.json",
    "verification.txt",
    "closed_loop.smv",
    "closed_loop.last.smv",
];

/// What a run that writes an output folder is, and what it reads.
#[derive(Debug, Clone, Default)]
pub(crate) struct Claim {
    /// The command, as the folder's list of files records it (`main`, `infer`, `verify`...).
    pub command: &'static str,
    /// Every file the run reads (`-`, standard input, is never in a folder).
    pub reads: Vec<PathBuf>,
    /// The names the run gives its machine files (`SynthesizedFB` for `SynthesizedFB.fbt`...).
    pub stems: Vec<String>,
    /// Further result files the run writes under a fixed name (`plant.smv`, a plant learned
    /// on the way).
    pub names: Vec<String>,
}

impl Claim {
    /// The claim of `command`, reading `reads`.
    pub(crate) fn new<P: AsRef<Path>>(
        command: &'static str,
        reads: impl IntoIterator<Item = P>,
    ) -> Claim {
        Claim {
            command,
            reads: reads
                .into_iter()
                .map(|p| p.as_ref().to_path_buf())
                .collect(),
            stems: Vec::new(),
            names: Vec::new(),
        }
    }

    /// The claim, writing machine files named `stem`.
    pub(crate) fn writing(mut self, stem: &str) -> Claim {
        self.stems.push(stem.to_string());
        self
    }

    /// The claim, writing a result file named `name` too.
    pub(crate) fn naming(mut self, name: &str) -> Claim {
        self.names.push(name.to_string());
        self
    }

    /// Before any work: refuses an output folder that holds another command's result
    /// (`previous`, from its list of files), or an input under a name this run writes, or
    /// that the previous result listed (`listed`, which publishing replaces or removes).
    pub(crate) fn check_folder(
        &self,
        out: &Path,
        previous: Option<&str>,
        listed: &[PathBuf],
    ) -> Result<(), RuleError> {
        if forced() {
            return Ok(());
        }
        if let Some(other) = previous.filter(|p| *p != self.command) {
            return Err(RuleError::Other {
                out: out.to_path_buf(),
                other: other.to_string(),
                this: self.command,
            });
        }
        let Ok(folder) = std::fs::canonicalize(out) else {
            return Ok(());
        };
        for input in &self.reads {
            let Some(rel) = std::fs::canonicalize(input)
                .ok()
                .and_then(|i| i.strip_prefix(&folder).ok().map(Path::to_path_buf))
            else {
                continue;
            };
            let name = rel.file_name().unwrap_or_default().to_string_lossy();
            let stem = rel.file_stem().unwrap_or_default().to_string_lossy();
            let written = listed.contains(&rel)
                || RESULT_NAMES.contains(&name.as_ref())
                || self.names.iter().any(|n| *n == name)
                || self.stems.iter().any(|s| *s == stem);
            if written {
                return Err(RuleError::Input {
                    output: out.join(&rel),
                    input: input.clone(),
                });
            }
        }
        Ok(())
    }

    /// At publishing: refuses when `target`, a file the publish replaces or removes, is one
    /// of the inputs (also through a link).
    pub(crate) fn check_target(&self, target: &Path) -> Result<(), RuleError> {
        if forced() || std::fs::symlink_metadata(target).is_err() {
            return Ok(());
        }
        match self.reads.iter().find(|i| super::same_file(target, i)) {
            Some(input) => Err(RuleError::Input {
                output: target.to_path_buf(),
                input: input.clone(),
            }),
            None => Ok(()),
        }
    }
}

/// Refuses single output files that are inputs of the same run (the atomic rename would
/// replace the input with the result), unless `--force`.
pub(crate) fn refuse_inputs<P: AsRef<Path>, Q: AsRef<Path>>(
    outputs: &[P],
    inputs: &[Q],
) -> Result<(), RuleError> {
    if forced() {
        return Ok(());
    }
    for out in outputs.iter().map(AsRef::as_ref) {
        let same = |i: &&Q| !super::is_stdin(out) && super::same_file(out, i.as_ref());
        if let Some(input) = inputs.iter().find(same) {
            return Err(RuleError::File {
                output: out.to_path_buf(),
                input: input.as_ref().to_path_buf(),
            });
        }
    }
    Ok(())
}

/// A refusal of the output rule.
#[derive(Debug, thiserror::Error)]
pub enum RuleError {
    /// Publishing into a folder would replace or remove a file the run reads.
    #[error("the output {} would replace or remove the input {}: give another output folder, or --force", .output.display(), .input.display())]
    Input {
        /// The file in the output folder.
        output: PathBuf,
        /// The input, as the user named it.
        input: PathBuf,
    },
    /// An output file is a file the run reads.
    #[error("the output {} would overwrite the input {}; choose another output path, or --force", .output.display(), .input.display())]
    File {
        /// The output file.
        output: PathBuf,
        /// The input, as the user named it.
        input: PathBuf,
    },
    /// The output folder holds another command's result.
    #[error("{} holds the result of {} (listed in {}), which {} would replace: give another output folder, or --force", .out.display(), shown(.other), .out.join(super::result_set::MANIFEST).display(), shown(.this))]
    Other {
        /// The output folder.
        out: PathBuf,
        /// The command whose result the folder holds.
        other: String,
        /// This run's command.
        this: &'static str,
    },
}

/// A command as the user types it.
fn shown(command: &str) -> String {
    match command {
        "main" => "the main job (`synth --ltl ...`)".into(),
        c => format!("`synth {c}`"),
    }
}
