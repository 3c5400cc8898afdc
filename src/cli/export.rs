//! `synth export`: any machine in the JSON contract (one `synth` wrote, or one edited by hand)
//! to every other format.

use super::args::parse_formats;
use super::show::print_written;
use crate::command::export::{run, Exported};
use crate::pipeline::Error;
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The machine (JSON, as `synth infer` writes it; `-`: stdin).
    #[arg(long, value_name = "FILE")]
    pub ecc: PathBuf,
    /// Formats to write, comma-separated: json, fbt, smv, dot, st, pnml, plcopen
    /// (PLCopen TC6 XML, written as .xml).
    #[arg(long, value_delimiter = ',', default_value = "json,fbt,smv,dot,st")]
    pub format: Vec<String>,
    /// Name of the function block type in the exports.
    #[arg(long, default_value = "SynthesizedFB", value_parser = super::args::block_name)]
    pub name: String,
    /// Output folder. Default: `out/<stem of the JSON file>`. `-`: one format on stdout (the
    /// one --format names, JSON when it names several).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// `synth export`.
pub fn export(args: &ExportArgs) -> Result<(), Error> {
    let formats = parse_formats(&args.format)?;
    let to_stdout = args.out.as_deref().is_some_and(crate::files::is_stdin);
    if to_stdout {
        super::data_on_stdout();
    }
    let done = run(&args.ecc, &formats, &args.name, &args.out, to_stdout)?;
    if let Exported::Text(text) = &done {
        return super::write_data(text.as_bytes());
    }
    out!("{done}");
    print_written(done.files());
    Ok(())
}
