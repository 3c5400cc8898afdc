//! `synth-dev generate`: re-record a shipped case's files from its reference controller and
//! plant simulation.

use fbsynth::cases::{distribution, pnp, tank};
use fbsynth::out;
use fbsynth::pipeline::Error;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct GenerateArgs {
    /// The case: `pnp`, `tank` (the tank case: scenarios, raw logs, held-out runs) or
    /// `distribution` (the Festo station: clean, noisy and held-out sampled logs).
    #[arg(value_parser = ["pnp", "tank", "distribution"])]
    pub case: String,
    /// Folder to write the scenario and names files into.
    #[arg(long, default_value = "specs", value_name = "DIR")]
    pub out: PathBuf,
}

/// `synth-dev generate CASE`.
pub fn generate(args: &GenerateArgs) -> Result<(), Error> {
    let files = match args.case.as_str() {
        "tank" => {
            let files = tank::write_files(&args.out).map_err(Error::from)?;
            out!(
                "recorded the process-mining paper's tank scenarios and held-out runs from the reference programs:"
            );
            files
        }
        "distribution" => {
            let (files, injected) = distribution::write_files(&args.out).map_err(Error::from)?;
            out!(
                "recorded {} use cases and {} held-out runs of the distribution station; \
                 {injected} scan-cycle errors injected (rate {}, seed {}):",
                distribution::use_cases().len(),
                distribution::held_out_cases().len(),
                distribution::SHIPPED_RATE,
                distribution::SHIPPED_SEED
            );
            files
        }
        _ => {
            let files = pnp::write_files(&args.out).map_err(Error::from)?;
            let set = pnp::generate();
            out!(
                "recorded {} work-piece orders ({} steps) from the reference controller:",
                set.scenarios.len(),
                set.step_count()
            );
            files
        }
    };
    for f in files {
        out!("  {}", f.display());
    }
    Ok(())
}
