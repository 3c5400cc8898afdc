//! The lists of files written, as every command prints them (and notes them for the generic
//! `--json` summary).

use std::path::{Path, PathBuf};

/// The list of files written, on stdout.
pub fn print_written(files: &[PathBuf]) {
    super::note_written(files);
    out!("wrote:");
    for f in files {
        out!("  {}", f.display());
    }
}

/// The closing lines of a verified run: where the results are.
pub fn print_files(out: &Path, files: &[PathBuf]) {
    super::note_written(files);
    out!("results in {}:", out.display());
    for f in files {
        out!("  {}", f.display());
    }
}
