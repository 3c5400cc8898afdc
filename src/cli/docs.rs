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
    let text = String::from_utf8(buf).expect("clap_mangen writes UTF-8");
    // `.TH title section date source manual`: clap_mangen writes an empty date as nothing, so
    // the source (`synth 0.1.0`) would be read as the date. The line is written here with
    // every field in its place: no date (the page is the same whenever it is generated),
    // the program and its version as the source.
    let th = title_line(title);
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        out.push_str(if line.starts_with(".TH ") { &th } else { line });
        out.push('\n');
    }
    Ok(out.into_bytes())
}

/// The `.TH` line of the page `title`: section 1, an empty date, `synth VERSION` as the
/// source and the manual's name.
fn title_line(title: &str) -> String {
    format!(
        ".TH {title} 1 \"\" \"synth {}\" \"User Commands\"",
        env!("CARGO_PKG_VERSION")
    )
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The arguments of a roff request line, as troff reads them: separated by spaces, a
    /// double-quoted argument may hold spaces or be empty.
    fn roff_args(line: &str) -> Vec<String> {
        let mut args = Vec::new();
        let mut rest = line.trim_start();
        while !rest.is_empty() {
            if let Some(quoted) = rest.strip_prefix('"') {
                let end = quoted.find('"').unwrap_or(quoted.len());
                args.push(quoted[..end].to_string());
                rest = quoted.get(end + 1..).unwrap_or("");
            } else {
                let end = rest.find(' ').unwrap_or(rest.len());
                args.push(rest[..end].to_string());
                rest = &rest[end..];
            }
            rest = rest.trim_start();
        }
        args
    }

    #[test]
    fn the_title_line_has_the_date_and_the_version_in_their_places() {
        let cmd = Cli::command().name("synth");
        let mut pages = vec![("synth".to_string(), cmd.clone())];
        for sub in cmd.get_subcommands() {
            pages.push((format!("synth-{}", sub.get_name()), sub.clone()));
        }
        for (title, cmd) in pages {
            let text = String::from_utf8(page(cmd, &title).unwrap()).unwrap();
            let th: Vec<&str> = text.lines().filter(|l| l.starts_with(".TH ")).collect();
            assert_eq!(th.len(), 1, "{title}: {text}");
            let args = roff_args(th[0].strip_prefix(".TH").unwrap());
            let source = format!("synth {}", env!("CARGO_PKG_VERSION"));
            assert_eq!(
                args,
                [title.as_str(), "1", "", &source, "User Commands"],
                "{}",
                th[0]
            );
            // The rest of the page is clap_mangen's.
            assert!(text.contains(".SH NAME"), "{title}");
        }
        assert_eq!(roff_args(r#"a 1 "" "b c""#), ["a", "1", "", "b c"]);
    }
}
