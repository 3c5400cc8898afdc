//! `synth diff`: do two machines behave alike, and if not, on which inputs do they differ.

use crate::command::diff::run;
use crate::pipeline::Error;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct DiffArgs {
    /// The first machine, in the JSON format `synth infer` writes.
    #[arg(value_name = "A.json")]
    pub first: PathBuf,
    /// The second machine, over the same inputs and outputs.
    #[arg(value_name = "B.json")]
    pub second: PathBuf,
}

/// `synth diff A.json B.json`: "equivalent" (exit 0), or the shortest input sequence from the
/// initial states on which they answer differently, step by step (exit 1); then the states
/// matched up and what differs between matched states.
pub fn diff(args: &DiffArgs) -> Result<(), Error> {
    if super::json() {
        super::data_on_stdout();
    }
    let compared = run(&args.first, &args.second)?;
    if super::json() {
        super::write_json(&compared.summary())?;
    }
    out!("{compared}");
    compared.failure().map_or(Ok(()), Err)
}
