//! Where scenarios come from: trace files (fbSAT text or CSV logs, plain or gzip) and the
//! interface names files, read into one [`ScenarioSet`].

use super::Error;
use crate::ecc::Ecc;
use crate::scenario::{csvlog, fbsat, names, parquet, ScenarioSet};
use std::path::{Path, PathBuf};

/// Trace files and the names of their bits.
#[derive(Debug, Clone, Default)]
pub struct Recordings {
    /// Scenario files: fbSAT text format or CSV logs (`.csv`, `.csv.gz`); at least one.
    pub traces: Vec<PathBuf>,
    /// Input names file (default: `<stem>.inputs` or `input-names` beside the first trace).
    pub input_names: Option<PathBuf>,
    /// Output names file (default: beside the first trace, like the inputs).
    pub output_names: Option<PathBuf>,
}

fn is_csv(path: &Path) -> bool {
    if crate::files::is_stdin(path) {
        // No name to go by: fbSAT scenarios hold `REQ[` in their first lines, a CSV log not.
        let head = crate::files::stdin_text_head(1 << 16).unwrap_or_default();
        return !String::from_utf8_lossy(&head).contains("REQ[");
    }
    let name = path.to_string_lossy().to_ascii_lowercase();
    name.ends_with(".csv") || name.ends_with(".csv.gz")
}

impl Recordings {
    /// Recordings in `traces` with the default names files.
    pub fn files(traces: Vec<PathBuf>) -> Recordings {
        Recordings {
            traces,
            ..Recordings::default()
        }
    }

    /// Every file these recordings read: the traces and the names files.
    pub(crate) fn paths(&self) -> Vec<PathBuf> {
        let (inputs, outputs) = self.names_files();
        (self.traces.iter().cloned())
            .chain(inputs)
            .chain(outputs)
            .collect()
    }

    /// The names files read: those given, else the defaults beside the first trace file.
    fn names_files(&self) -> (Option<PathBuf>, Option<PathBuf>) {
        let defaults = self
            .traces
            .first()
            .and_then(|t| names::default_names_files(t));
        let in_file = self
            .input_names
            .clone()
            .or_else(|| defaults.as_ref().map(|d| d.0.clone()));
        let out_file = self
            .output_names
            .clone()
            .or_else(|| defaults.as_ref().map(|d| d.1.clone()));
        (in_file, out_file)
    }

    /// Where the name of input (or, with `output`, output) `index` (0-based) was written:
    /// `FILE:LINE` in its names file, or the header of the first trace file when that is a
    /// CSV log and no names file is read. `None` for names nobody wrote (fbSAT traces without
    /// names files).
    pub(crate) fn name_place(&self, output: bool, index: usize) -> Option<String> {
        let (in_file, out_file) = self.names_files();
        if let Some(file) = if output { out_file } else { in_file } {
            // The file was read once already; a line is found the way parse_names counts.
            let text = crate::files::read_text(&file, Some(crate::files::MAX_LINE_BYTES)).ok()?;
            let line = text
                .lines()
                .enumerate()
                .flat_map(|(i, l)| l.split_whitespace().map(move |_| i + 1))
                .nth(index)?;
            return Some(format!("{}:{line}", file.display()));
        }
        let first = self.traces.first()?;
        is_csv(first).then(|| format!("{}: header", first.display()))
    }

    /// Reads every trace file into one scenario set.
    pub fn load(&self) -> Result<ScenarioSet, Error> {
        if self.traces.is_empty() {
            return Err(Error::Usage("no trace file given".into()));
        }
        let (in_file, out_file) = self.names_files();
        let inputs = in_file.as_deref().map(names::read_names).transpose()?;
        let outputs = out_file.as_deref().map(names::read_names).transpose()?;
        if let (Some(i), Some(o)) = (&inputs, &outputs) {
            if let Some((k, n)) = i.iter().enumerate().find(|(_, n)| o.contains(n)) {
                let j = o.iter().position(|m| m == n).unwrap_or(0);
                let place = |output, index| self.name_place(output, index).unwrap_or_default();
                return Err(Error::Input(format!(
                    "{} is named both as an input ({}) and as an output ({})",
                    crate::quote::quote(n),
                    place(false, k),
                    place(true, j)
                )));
            }
        }
        let mut set: Option<ScenarioSet> = None;
        for file in &self.trace_files()? {
            let s = if parquet::is_parquet(file) {
                parquet::read(file, inputs.as_deref(), outputs.as_deref())
            } else if is_csv(file) {
                csvlog::read(file, inputs.as_deref(), outputs.as_deref())
            } else {
                fbsat::read(file, inputs.clone(), outputs.clone())
            }?;
            match &mut set {
                None => set = Some(s),
                Some(all) => all.merge(s)?,
            }
        }
        let set = set.expect("at least one trace file");
        // A CSV log without rows is refused by its reader; an fbSAT file counting 0 scenarios
        // would otherwise give a one-state machine "reproducing" nothing.
        if set.scenarios.iter().all(|s| s.steps.is_empty()) {
            let files: Vec<String> = self
                .traces
                .iter()
                .map(|f| f.display().to_string())
                .collect();
            return Err(Error::Input(format!(
                "{}: no recorded step (the recordings hold no scenario, or only empty ones)",
                files.join(", ")
            )));
        }
        Ok(set)
    }

    /// The trace files, a folder standing for the logs inside it ([`logs_in`]).
    fn trace_files(&self) -> Result<Vec<PathBuf>, Error> {
        let mut files = Vec::new();
        for t in &self.traces {
            if t.is_dir() {
                let inside = logs_in(t)?;
                if inside.is_empty() {
                    return Err(Error::Input(format!(
                        "{}: a folder without logs (.parquet, .csv, .csv.gz)",
                        t.display()
                    )));
                }
                files.extend(inside);
            } else {
                files.push(t.clone());
            }
        }
        Ok(files)
    }

    /// The first trace file's name up to its first dot (`specs/pnp.traces` -> `pnp`): the
    /// default name of an output folder.
    pub(crate) fn stem(&self) -> String {
        self.traces
            .first()
            .map_or_else(|| "traces".into(), |p| stem(p))
    }

    /// The trace files, comma-separated, for messages.
    pub fn show(&self) -> String {
        self.traces
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Whether a file is a log (not an fbSAT scenario file): CSV, plain or gzip, or Parquet.
pub(crate) fn is_log(path: &Path) -> bool {
    parquet::is_parquet(path) || is_csv(path)
}

/// The logs in a folder and its subfolders (a partitioned data set such as Spark writes:
/// `plc=3/part-00000.parquet`): files ending in `.parquet`, `.csv` or `.csv.gz`, in path
/// order. Hidden files and Spark's markers (`_SUCCESS`) are skipped.
pub(crate) fn logs_in(dir: &Path) -> Result<Vec<PathBuf>, Error> {
    let mut found = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        let entries =
            std::fs::read_dir(&d).map_err(|e| Error::Input(format!("{}: {e}", d.display())))?;
        for entry in entries {
            let path = entry
                .map_err(|e| Error::Input(format!("{}: {e}", d.display())))?
                .path();
            let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
            if name.as_deref().is_none_or(|n| n.starts_with(['.', '_'])) {
                continue;
            }
            if path.is_dir() {
                todo.push(path);
            } else if is_log(&path) {
                found.push(path);
            }
        }
    }
    found.sort();
    Ok(found)
}

/// A file's name up to its first dot.
pub(crate) fn stem(path: &Path) -> String {
    if crate::files::is_stdin(path) {
        return "stdin".into();
    }
    let f = path
        .file_name()
        .map(|f| f.to_string_lossy().into_owned())
        .unwrap_or_else(|| "traces".into());
    f.split('.').next().unwrap_or("traces").to_string()
}

/// Reads a machine from its JSON file.
pub(crate) fn read_ecc(path: &Path) -> Result<Ecc, Error> {
    // Machines may be written as one line of JSON: only the file's size is limited.
    let text = crate::files::read_text(path, None).map_err(|e| Error::Input(e.to_string()))?;
    Ok(crate::export::json::read_json(&text, path)?)
}

/// Reads a machine and recordings and checks that they share one interface.
pub(crate) fn machine_and_scenarios(
    ecc_file: &Path,
    recordings: &Recordings,
) -> Result<(Ecc, ScenarioSet), Error> {
    let ecc = read_ecc(ecc_file)?;
    let set = recordings.load()?;
    if set.inputs != ecc.inputs || set.outputs != ecc.outputs {
        let list = |names: &[String]| crate::quote::cut(&names.join(" ")).to_string();
        return Err(Error::Input(format!(
            "{} has inputs [{}] and outputs [{}], the scenarios [{}] and [{}]",
            ecc_file.display(),
            list(&ecc.inputs),
            list(&ecc.outputs),
            list(&set.inputs),
            list(&set.outputs)
        )));
    }
    Ok((ecc, set))
}
