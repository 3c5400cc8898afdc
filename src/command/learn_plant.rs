//! `synth learn-plant`: the surrogate plant learned from the recordings
//! ([`crate::plant::learn`]), written as a plant file the main job and `synth verify` read;
//! and `synth compare-plants`: two plants compared on random closed-loop runs of a machine.

use super::refuse_overwrite;
use crate::files::write_atomic;
use crate::pipeline::recordings::read_ecc;
use crate::pipeline::{Error, Recordings};
use crate::plant::learn::{self, compare, LearnError, Learned, Observers};
use crate::scenario::ScenarioSet;
use std::path::{Path, PathBuf};

/// A plant learned and written.
pub(crate) struct Written {
    /// The plant.
    pub learned: Learned,
    /// Where it was written.
    pub out: PathBuf,
}

impl Written {
    /// What the command prints: the structure, then where the plant went.
    pub fn lines(&self) -> Vec<String> {
        let l = &self.learned;
        let mut lines = vec![format!(
            "learned a plant from {} recorded scans in {} runs: {} sensors, {} delayed",
            l.steps,
            l.runs,
            l.parts.len(),
            l.parts.iter().filter(|p| p.wait_cap > 0).count()
        )];
        lines.push("every recorded step is a step of it".into());
        lines.push(format!("wrote {}", crate::quote::path(&self.out)));
        lines
    }
}

/// The observers in `file`, read.
pub(crate) fn read_observers(file: &Path) -> Result<Observers, Error> {
    let text = std::fs::read_to_string(file)
        .map_err(|e| Error::Input(format!("cannot read the observers {}: {e}", file.display())))?;
    Ok(Observers {
        file: file.to_path_buf(),
        text,
    })
}

/// How to learn a plant: the observers and the timing slack.
#[derive(Debug, Clone, Default)]
pub(crate) struct Options {
    /// The observers file (`--observe`).
    pub observe: Option<PathBuf>,
    /// Scans a change a command drives may come later than recorded (`--slack`).
    pub slack: usize,
    /// The user's assumptions about the plant (`--assume`).
    pub assume: Option<PathBuf>,
}

/// The plant learned from `set` (read from `recordings`), with `observers`, keeping the
/// assumptions of `options` ([`assumed`]).
pub(crate) fn learn_set(
    set: &ScenarioSet,
    recordings: &Recordings,
    observers: Option<&Observers>,
    options: &Options,
) -> Result<Learned, Error> {
    let assumptions = options
        .assume
        .as_deref()
        .map(|f| assumed(set, f))
        .transpose()?;
    let source: Vec<String> = (recordings.traces.iter())
        .map(|t| t.display().to_string())
        .collect();
    let mut learned =
        learn::learn(set, &source.join(", "), observers, options.slack).map_err(input)?;
    if let Some(a) = assumptions {
        learned.text.push_str(&a.text());
    }
    Ok(learned)
}

/// The assumptions in `file` over the interface of `set` ([`learn::assume`]), after
/// the recordings are checked against them: a recorded run that breaks one is named with its
/// first violating step.
fn assumed(set: &ScenarioSet, file: &Path) -> Result<learn::assume::Assumptions, Error> {
    let props = crate::ltl::parse_spec_file(file).map_err(|e| Error::Input(e.to_string()))?;
    let assumptions = learn::assume::Assumptions::of(file, &props, &set.inputs, &set.outputs)
        .map_err(|e| Error::Input(e.to_string()))?;
    let explained = crate::pipeline::explain::explain(set, &props);
    if let Some(v) = explained.violations.first() {
        return Err(Error::Input(format!(
            "the recordings contradict the assumption {} ({}:{}): first at {}; {}",
            crate::quote::cut(&v.property),
            file.display(),
            v.line,
            v.first,
            v.extent
        )));
    }
    Ok(assumptions)
}

/// `synth learn-plant`: learns the plant of `recordings` and writes it to `out` (whole or
/// not at all).
pub(crate) fn run(
    recordings: &Recordings,
    options: &Options,
    out: &Path,
) -> Result<Written, Error> {
    let mut reads = recordings.paths();
    reads.extend(options.observe.iter().cloned());
    reads.extend(options.assume.iter().cloned());
    refuse_overwrite(&[out], &reads)?;
    let set = recordings.load()?;
    let observers = options.observe.as_deref().map(read_observers).transpose()?;
    let learned = learn_set(&set, recordings, observers.as_ref(), options)?;
    write_atomic(out, learned.text.as_bytes())?;
    Ok(Written {
        learned,
        out: out.to_path_buf(),
    })
}

fn input(e: LearnError) -> Error {
    Error::Input(e.to_string())
}

/// What `synth compare-plants` measured.
pub(crate) struct Compared {
    /// Runs of the first plant's closed loop the second admits.
    pub forward: compare::Inclusion,
    /// Runs of the second plant's closed loop the first admits.
    pub backward: compare::Inclusion,
    /// The two plant files.
    pub plants: [PathBuf; 2],
    /// Scans per run.
    pub scans: usize,
}

impl Compared {
    /// One line per direction.
    pub fn lines(&self) -> Vec<String> {
        let line = |inc: &compare::Inclusion, a: &Path, b: &Path| {
            let pct = 100.0 * inc.admitted as f64 / inc.runs.max(1) as f64;
            let first = match inc.first_refused {
                Some((r, k)) => format!("; first refused: run {}, scan {k}", r + 1),
                None => String::new(),
            };
            format!(
                "{} of {} random {}-scan runs with {} are runs of {} ({pct:.1}%){first}",
                inc.admitted,
                inc.runs,
                self.scans,
                a.display(),
                b.display()
            )
        };
        let [a, b] = &self.plants;
        vec![line(&self.forward, a, b), line(&self.backward, b, a)]
    }
}

/// `synth compare-plants`: `runs` random closed-loop runs of `scans` scans of the machine in
/// `ecc_file` with each plant, replayed on the other.
pub(crate) fn compare(
    ecc_file: &Path,
    plants: [&Path; 2],
    runs: usize,
    scans: usize,
    seed: u64,
) -> Result<Compared, Error> {
    let ecc = read_ecc(ecc_file)?;
    let a = crate::plant::parse::parse_file(plants[0]).map_err(|e| Error::Input(e.to_string()))?;
    let b = crate::plant::parse::parse_file(plants[1]).map_err(|e| Error::Input(e.to_string()))?;
    let forward = compare::inclusion(&ecc, &a, &b, runs, scans, seed).map_err(Error::Input)?;
    let backward = compare::inclusion(&ecc, &b, &a, runs, scans, seed).map_err(Error::Input)?;
    Ok(Compared {
        forward,
        backward,
        plants: plants.map(Path::to_path_buf),
        scans,
    })
}
