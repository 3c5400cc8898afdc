//! `synth export`: any machine in the JSON contract (one `synth` wrote, or one edited by hand)
//! to every other format.

use super::args::{out_dir, parse_formats};
use super::show::print_written;
use super::Failure;
use crate::export;
use crate::files::ResultSet;
use crate::pipeline::{self, recordings::read_ecc};
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
pub fn export(args: &ExportArgs) -> Result<(), Failure> {
    let formats = parse_formats(&args.format)?;
    let ecc = read_ecc(&args.ecc)?;
    let stem = args
        .ecc
        .file_stem()
        .map_or("machine".into(), |s| s.to_string_lossy().into_owned());
    if args.out.as_deref().is_some_and(crate::files::is_stdin) {
        super::data_on_stdout();
        let format = super::args::stdout_format(&formats);
        let text = export::text(&ecc, &args.name, format).map_err(Failure::input)?;
        return super::write_data(text.as_bytes());
    }
    let out = out_dir(&args.out, &stem);
    // A result folder holds one result: publishing into the folder the machine is read from
    // would replace or remove the input. Looking for the input's file among the folder's
    // (same device and inode) also finds it through a symbolic or hard link.
    let holds_input = std::fs::read_dir(&out).is_ok_and(|entries| {
        entries
            .flatten()
            .any(|e| crate::files::same_file(&e.path(), &args.ecc))
    });
    if holds_input {
        return Err(Failure::msg(
            super::exit::USAGE,
            format!(
                "--out {} is the folder {} is read from: choose another output folder",
                out.display(),
                args.ecc.display()
            ),
        ));
    }
    let results = ResultSet::open(&out).map_err(Failure::input)?;
    let staged =
        export::write_all(&ecc, results.staging(), &args.name, &formats).map_err(Failure::input)?;
    let files: Vec<PathBuf> = staged.iter().map(|f| results.published(f)).collect();
    results
        .publish()
        .map_err(|e| Failure::input(pipeline::Error::from(e)))?;
    out!(
        "{}: {} states, {} transitions",
        args.ecc.display(),
        ecc.states.len(),
        ecc.size().t
    );
    print_written(&files);
    Ok(())
}
