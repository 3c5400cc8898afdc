//! `synth record` and `synth monitor`: the live runs of [`crate::live`] with their files.
//!
//! In: the connection, the mapping file, the output (a log file; a result folder for the
//! monitor), when to stop. Out: the file(s) written and what the commands print.

use super::refuse_overwrite;
use crate::ecc::bits_to_string;
use crate::files::output_rule::Claim;
use crate::files::ResultSet;
use crate::live::client::{node_ids, Sampler};
use crate::live::monitor::{self, Divergence, Outcome};
use crate::live::record::{self, Ended};
use crate::live::{Connection, Counters, Mapping, Until};
use crate::pipeline::recordings::read_ecc;
use crate::pipeline::Error;
use std::fmt;
use std::path::{Path, PathBuf};

/// What `synth record` wrote.
pub(crate) struct Recorded {
    /// Rows, gaps, seconds.
    pub counters: Counters,
    /// The log.
    pub file: PathBuf,
    /// Whether a signal stopped the recording (the program then ends with 130).
    pub stopped: bool,
}

impl fmt::Display for Recorded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = &self.counters;
        write!(
            f,
            "recorded {} rows in {:.1} s, {} gap{} ({} scenario{}){}\nwrote {}",
            c.rows,
            c.seconds,
            c.gaps,
            plural(c.gaps),
            c.scenarios,
            plural(c.scenarios),
            if self.stopped {
                ", stopped by a signal"
            } else {
                ""
            },
            crate::quote::path(&self.file)
        )
    }
}

fn plural(n: u64) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// `synth record`: samples the mapped nodes into the CSV log `out`.
pub(crate) fn record(
    conn: &Connection,
    map: &Path,
    out: &Path,
    until: Until,
    progress: &mut dyn FnMut(&Counters),
) -> Result<Recorded, Error> {
    refuse_overwrite(&[out], &[map])?;
    let mapping = Mapping::read(map)?;
    let ids = node_ids(&mapping, map)?;
    let mut sampler = Sampler::connect(conn, &mapping, ids)?;
    // From here the first SIGINT ends the recording with a whole file.
    crate::signals::stop_first();
    let (counters, ended) = record::record(&mut sampler, &mapping, out, until, progress)?;
    sampler.close();
    Ok(Recorded {
        counters,
        file: out.to_path_buf(),
        stopped: ended == Ended::Signal,
    })
}

/// What `synth monitor` found.
pub(crate) struct Monitored {
    /// How the run ended.
    pub outcome: Outcome,
    /// The divergent stretch, when there is one.
    pub files: Vec<PathBuf>,
    /// The machine's signal names, for the report.
    pub names: (Vec<String>, Vec<String>),
}

impl Monitored {
    /// Whether a signal stopped the run (the program then ends with 130).
    pub(crate) fn stopped(&self) -> bool {
        self.outcome.ended == Ended::Signal
    }

    /// The failure of a run that found a divergence (exit 1).
    pub(crate) fn failure(&self) -> Option<Error> {
        let d = self.outcome.divergence.as_ref()?;
        Some(Error::Negative(format!(
            "the machine and the PLC part at step {} (learn the stretch with synth conform --refine)",
            d.step
        )))
    }
}

impl fmt::Display for Monitored {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = &self.outcome.counters;
        match &self.outcome.divergence {
            None => write!(
                f,
                "no divergence: {} steps agree ({} rows, {:.1} s)",
                c.steps, c.rows, c.seconds
            ),
            Some(d) => {
                writeln!(f, "{}", describe(d, &self.names))?;
                write!(
                    f,
                    "{} steps agree before it ({} rows, {:.1} s)",
                    d.step - 1,
                    c.rows,
                    c.seconds
                )
            }
        }
    }
}

/// `DIVERGENCE at step K (t = S s): inputs a=1 b=0; PLC: CNF[..] z=..; machine: ...`.
fn describe(d: &Divergence, (inputs, outputs): &(Vec<String>, Vec<String>)) -> String {
    let named = |names: &[String], bits: &[bool]| {
        (names.iter().zip(bits))
            .map(|(n, b)| format!("{n}={}", u8::from(*b)))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let outs = |o: &Option<Vec<bool>>| match o {
        Some(v) => format!("CNF[{}] {}", bits_to_string(v), named(outputs, v)),
        None => "no CNF (outputs unchanged)".to_string(),
    };
    format!(
        "DIVERGENCE at step {} (t = {:.3} s): inputs {}; PLC outputs {}; machine outputs {}",
        d.step,
        d.time,
        named(inputs, &d.inputs),
        outs(&d.plc),
        outs(&d.machine)
    )
}

/// `synth monitor`: runs the machine in `ecc_file` beside the PLC; the divergent stretch goes
/// to `out/divergences.csv`.
pub(crate) fn monitor(
    conn: &Connection,
    map: &Path,
    ecc_file: &Path,
    out: &Path,
    until: Until,
    progress: &mut dyn FnMut(&Counters),
) -> Result<Monitored, Error> {
    let mapping = Mapping::read(map)?;
    let ecc = read_ecc(ecc_file)?;
    let ids = node_ids(&mapping, map)?;
    let results = ResultSet::open(out, Claim::new("monitor", [map, ecc_file]))?;
    let stretch = results.staging().join("divergences.csv");
    let mut sampler = Sampler::connect(conn, &mapping, ids)?;
    crate::signals::stop_first();
    let outcome = monitor::monitor(
        &mut sampler,
        &mapping,
        (&ecc, ecc_file),
        &stretch,
        until,
        progress,
    )?;
    sampler.close();
    let staged: Vec<PathBuf> = match outcome.divergence {
        Some(_) => vec![stretch],
        None => Vec::new(),
    };
    let files = super::publish(results, &staged)?;
    Ok(Monitored {
        outcome,
        files,
        names: (ecc.inputs.clone(), ecc.outputs.clone()),
    })
}
