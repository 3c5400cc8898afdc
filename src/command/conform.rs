//! `synth conform`: replay new recordings on a machine in service, report every trace's first
//! divergence, and with `--refine` learn the divergent traces and synthesize again (verified
//! again with `--ltl`/`--plant`).

use super::{publish, Spec};
use crate::ecc::Ecc;
use crate::export::Format;
use crate::files::output_rule::Claim;
use crate::files::ResultSet;
use crate::pipeline::{exact, refine, Error, Events, Recordings};
use crate::scenario::ScenarioSet;
use std::fmt;
use std::path::PathBuf;

/// How far a machine reproduces recordings: each trace's first divergence.
pub(crate) struct Conformance {
    /// One line per trace, then the agreement.
    pub lines: Vec<String>,
    /// Traces that diverge.
    pub divergent: usize,
    /// Traces in all.
    pub traces: usize,
}

impl fmt::Display for Conformance {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.lines.join("\n"))
    }
}

impl Conformance {
    /// With a divergent trace and no `--refine`: the failure that says so.
    pub fn failure(&self) -> Error {
        Error::Negative(format!(
            "{} of {} traces diverge (use --refine --train FILE... to learn them)",
            self.divergent, self.traces
        ))
    }
}

/// The conformance of `ecc` to `set`.
pub(crate) fn conformance(ecc: &Ecc, set: &ScenarioSet) -> Conformance {
    let divergences = set.divergences(ecc);
    let mut agreeing_steps = 0;
    let mut lines = Vec::new();
    for (k, sc) in set.scenarios.iter().enumerate() {
        match divergences.iter().find(|d| d.scenario == k) {
            None => {
                agreeing_steps += sc.steps.len();
                lines.push(format!(
                    "{}: agrees on all {} steps",
                    sc.origin,
                    sc.steps.len()
                ));
            }
            Some(d) => {
                agreeing_steps += d.step;
                lines.push(format!("{}: DIVERGES: {}", sc.origin, d.describe_step()));
            }
        }
    }
    let steps = set.step_count().max(1);
    lines.push(format!(
        "agreement: {} of {} traces reproduced; {} of {} steps before the first divergence ({:.1}%)",
        set.scenarios.len() - divergences.len(),
        set.scenarios.len(),
        agreeing_steps,
        set.step_count(),
        100.0 * agreeing_steps as f64 / steps as f64
    ));
    Conformance {
        lines,
        divergent: divergences.len(),
        traces: set.scenarios.len(),
    }
}

/// What `synth conform --refine` is asked.
pub(crate) struct Request {
    /// The scenarios the machine was synthesized from.
    pub training: Recordings,
    /// The properties to verify the refined machine against.
    pub spec: Option<Spec>,
    /// Output folder (default `out/refined`).
    pub out: Option<PathBuf>,
    /// The machine in service and the new recordings: read, never replaced.
    pub reads: Vec<PathBuf>,
}

/// The refined machine, published.
pub(crate) struct Done {
    /// The refinement.
    pub refined: refine::Refined,
    /// Where the training and divergent traces were published.
    pub traces_file: PathBuf,
    /// The files published.
    pub files: Vec<PathBuf>,
}

/// What was learned, the verdict and the size.
impl fmt::Display for Done {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.refined;
        writeln!(
            f,
            "refining: {} training scenarios + {} divergent traces -> {}",
            r.training_scenarios,
            r.divergent.len(),
            crate::quote::path(&self.traces_file)
        )?;
        if let Some(cert) = &r.exact.certificate {
            let holds = cert.report.properties.len();
            writeln!(f, "verified: all {holds} properties hold (NuSMV)")?;
            cert.report
                .warning_lines()
                .try_for_each(|w| writeln!(f, "{w}"))?;
        }
        write!(f, "{:#}", r.exact.synthesis.size)
    }
}

/// `synth conform --refine`: the divergent traces of `set` added to the training scenarios,
/// and the machine synthesized again (verified with a spec).
pub(crate) fn refine(
    r: &Request,
    ecc: &Ecc,
    set: &ScenarioSet,
    events: Events<'_>,
) -> Result<Done, Error> {
    let training = r.training.load()?;
    let check = match &r.spec {
        Some(spec) => Some(spec.check(set)?),
        None => None,
    };
    let out = r
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out/refined"));
    let formats = [
        Format::Json,
        Format::Fbt,
        Format::Smv,
        Format::Dot,
        Format::St,
    ];
    // One result in the folder, published whole at the end, as `infer` does.
    let reads = (r.training.paths().into_iter())
        .chain(r.spec.iter().flat_map(Spec::paths))
        .chain(r.reads.iter().cloned());
    let claim = Claim::new("conform", reads).writing("SynthesizedFB");
    let results = ResultSet::open(&out, claim)?;
    let opts = refine::Options {
        out: results.staging(),
        formats: &formats,
        name: "SynthesizedFB",
        exact: exact::Options {
            // The model NuSMV failed on is kept for the user, beside the results.
            keep_failed_model: check.is_some().then(|| out.join("closed_loop.last.smv")),
            ..exact::Options::default()
        },
    };
    let refined = refine::run(ecc, set, training, check.as_ref(), &opts, events)?
        .ok_or_else(|| Error::Bug("no divergent trace to refine on".into()))?;
    let traces_file = results.published(&refined.traces_file);
    let files = publish(results, &refined.files)?;
    Ok(Done {
        refined,
        traces_file,
        files,
    })
}
