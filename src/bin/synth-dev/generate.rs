//! `synth-dev generate`: re-record a shipped case's files from its reference controller and
//! plant simulation.

use fbsynth::cases::{distribution, free_inputs, pnp, station, tank};
use fbsynth::out;
use fbsynth::pipeline::Error;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct GenerateArgs {
    /// The case: `pnp`, `tank` (the tank case: scenarios, raw logs, held-out runs),
    /// `distribution` (the Festo station: clean, noisy and held-out sampled logs),
    /// `free-inputs` (a plant of `--inputs` free sensors, recordings and properties) or
    /// `station` (cylinders and latching requests drawn from `--seed`: plant, properties,
    /// one recorded run of its reference controller).
    #[arg(value_parser = ["pnp", "tank", "distribution", "free-inputs", "station"])]
    pub case: String,
    /// The number of free sensors of `free-inputs`.
    #[arg(long, default_value_t = 12, value_name = "N")]
    pub inputs: usize,
    /// The seed of `station`.
    #[arg(long, default_value_t = 1, value_name = "SEED")]
    pub seed: u64,
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
        "free-inputs" => {
            let files = free_inputs::write_files(&args.out, args.inputs).map_err(Error::from)?;
            out!(
                "wrote a plant of {} free inputs, {} outputs and {} recorded steps:",
                args.inputs,
                free_inputs::OUTPUTS,
                free_inputs::STEPS
            );
            files
        }
        "station" => {
            let (files, s) = station::write_files(&args.out, args.seed).map_err(Error::from)?;
            let r = s.reference().size();
            out!(
                "wrote station {}: {} cylinders, requests of {:?} strokes, its reference controller {r}, {} recorded scans:",
                args.seed,
                s.cylinders,
                s.requests.iter().map(Vec::len).collect::<Vec<_>>(),
                station::STEPS
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
