//! The lists of files written, as every command prints them (and notes them for the generic
//! `--json` summary).

use std::path::{Path, PathBuf};

/// The list of files written, on stdout.
pub fn print_written(files: &[PathBuf]) {
    super::note_written(files);
    out!("wrote:");
    for f in files {
        out!("  {}", crate::quote::path(f));
    }
}

/// The closing lines of a verified run: where the results are.
pub fn print_files(out: &Path, files: &[PathBuf]) {
    super::note_written(files);
    out!("results in {}:", crate::quote::path(out));
    for f in files {
        out!("  {}", crate::quote::path(f));
    }
}
