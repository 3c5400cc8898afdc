//! `synth completions SHELL` and `synth man`: shell completion scripts and the manual page,
//! generated from the same clap definitions that parse the command line; `synth schema`: the
//! JSON Schema of the machine contract, derived from the types that read it, or with
//! `--summary` of every summary the commands write.

use super::{Cli, Error};
use clap::{Args, CommandFactory};
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

/// `synth completions SHELL`: the completion script on stdout.
pub fn completions(args: &CompletionsArgs) -> Result<(), Error> {
    let mut cmd = Cli::command();
    let mut buf = Vec::new();
    clap_complete::generate(args.shell, &mut cmd, "synth", &mut buf);
    super::write_data(&buf)
}

#[derive(Debug, Args)]
pub struct ManArgs {
    /// Write `synth.1` and one page per command (`synth-infer.1`, ...) into this folder
    /// instead of printing `synth.1` on stdout.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// The roff text of one manual page, titled `title`.
fn page(cmd: clap::Command, title: &str) -> Result<Vec<u8>, Error> {
    let mut buf = Vec::new();
    clap_mangen::Man::new(cmd).title(title).render(&mut buf)?;
    Ok(buf)
}

/// `synth man`: the manual page (roff), on stdout or as files.
pub fn man(args: &ManArgs) -> Result<(), Error> {
    let cmd = Cli::command().name("synth");
    let Some(dir) = &args.out else {
        return super::write_data(&page(cmd, "synth")?);
    };
    std::fs::create_dir_all(dir).map_err(|source| crate::files::WriteError {
        path: dir.clone(),
        source,
    })?;
    let mut written = vec![(dir.join("synth.1"), page(cmd.clone(), "synth")?)];
    for sub in cmd.get_subcommands() {
        let name = format!("synth-{}", sub.get_name());
        written.push((dir.join(format!("{name}.1")), page(sub.clone(), &name)?));
    }
    for (path, bytes) in &written {
        crate::files::write_atomic(path, bytes)?;
        out!("wrote {}", crate::quote::path(path));
    }
    super::note_written(&written.into_iter().map(|(p, _)| p).collect::<Vec<_>>());
    Ok(())
}

#[derive(Debug, Args)]
pub struct SchemaArgs {
    /// Write the schema to this file instead of stdout (e.g. `machine.schema.json`, for an
    /// editor: a machine may name it in `"$schema"`).
    #[arg(long, short = 'o', value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// The schema of the summaries instead (`summary.json` and `--json`): one of them,
    /// told by its `format`.
    #[arg(long)]
    pub summary: bool,
}

/// `synth schema`: the JSON Schema of the machine contract, or of the summaries.
pub fn schema(args: &SchemaArgs) -> Result<(), Error> {
    let schema = match args.summary {
        true => crate::pipeline::summary::schema(),
        false => crate::export::json::schema(),
    };
    let mut text = serde_json::to_string_pretty(&schema).expect("a schema is JSON");
    text.push('\n');
    let Some(path) = args.out.as_ref().filter(|p| !crate::files::is_stdin(p)) else {
        return super::write_data(text.as_bytes());
    };
    crate::files::write_atomic(path, text.as_bytes())?;
    out!("wrote {}", crate::quote::path(path));
    super::note_written(std::slice::from_ref(path));
    Ok(())
}
