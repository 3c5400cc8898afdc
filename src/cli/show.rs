//! What several commands print the same way.

use fbsynth::ecc::modular::Modular;
use fbsynth::ingest::{ReadStats, RowKind};
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

/// The line that says a controller is verified (only ever printed after NuSMV said so).
pub fn verified_line(properties: usize, scenarios: usize) -> String {
    let holds = if properties == 1 {
        "the property holds".to_string()
    } else {
        format!("all {properties} properties hold")
    };
    let s = if scenarios == 1 { "" } else { "s" };
    format!("verified: {holds} (NuSMV), {scenarios} scenario{s} reproduced")
}

/// One line per module: its outputs, inputs and size.
pub fn describe_modules(modular: &Modular) -> Vec<String> {
    modular
        .modules
        .iter()
        .enumerate()
        .map(|(m, module)| {
            let s = module.ecc.size();
            let list = |v: &[String]| {
                if v.is_empty() {
                    "-".to_string()
                } else {
                    v.join(", ")
                }
            };
            format!(
                "module {}: {} states, {} transitions, {} guard literals; outputs: {}; inputs: {}",
                m + 1,
                s.c,
                s.t,
                s.n,
                list(&module.ecc.outputs),
                list(&module.ecc.inputs)
            )
        })
        .collect()
}

/// What reading a raw log took: rows, samples, rows skipped by kind, time and throughput.
pub fn print_read_stats(stats: &ReadStats, secs: f64) {
    out!("rows:    {}", stats.rows);
    out!("samples: {}", stats.samples);
    for kind in RowKind::ALL {
        let n = stats.skipped(kind);
        if n > 0 {
            out!("skipped: {n} rows ({})", kind.label());
        }
    }
    out!(
        "time:    {secs:.2} s ({:.2} M rows/s)",
        stats.rows as f64 / secs.max(1e-9) / 1e6
    );
}
