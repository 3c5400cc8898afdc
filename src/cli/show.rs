//! What several commands print the same way.

use super::progress::Progress;
use crate::ecc::modular::Modular;
use crate::ecc::Size;
use crate::ingest::{ReadStats, RowKind};
use crate::pipeline::explain::Explanation;
use crate::pipeline::main_job::{Summary, Turn};
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

/// `C = …  K = …  T = …  N = …`.
pub fn size_line(s: &Size) -> String {
    format!("{s:#}")
}

/// The progress lines after the recordings were checked against `properties` properties.
pub fn explained(progress: &Progress, e: &Explanation, properties: usize) {
    progress.line(&e.checked_line(properties));
    if let Some(line) = e.unrecorded_line() {
        progress.line(&line);
    }
}

/// `1 candidate` or `n candidates` (of anything).
fn plural(n: usize, what: &str) -> String {
    format!("{n} {what}{}", if n == 1 { "" } else { "s" })
}

/// The closing lines of the main job: how the machine was found and what is proven.
pub fn closing(summary: &Summary) -> String {
    match summary {
        Summary::Exact(e) => {
            // C is always proven least; T and N only when the proof fit in the budget.
            let unproven: Vec<&str> = [
                (!e.transitions_proven_minimal).then_some("T"),
                (!e.guards_proven_minimal).then_some("N"),
            ]
            .into_iter()
            .flatten()
            .collect();
            format!(
                "{}, {:.2} s total (SAT {:.2} s, NuSMV {:.2} s){}",
                plural(e.iterations.len(), "candidate"),
                e.total_seconds,
                e.sat_seconds,
                e.nusmv_seconds,
                match unproven.is_empty() {
                    true => String::new(),
                    false => format!(
                        "\n{} not proven minimal within the proof budget (--proof-budget SECONDS to try longer)",
                        unproven.join(" and ")
                    ),
                }
            )
        }
        Summary::Turn(Turn::BelowGuide(b)) => format!(
            "{}\n(the exact loop found it below the game's guide's {})",
            closing(&Summary::Exact(b.exact.clone())),
            b.guide_size
        ),
        Summary::Turn(Turn::Guide(g)) => format!(
            "closed-loop game as the guide: {:.2} s total (SAT {:.2} s, NuSMV {:.2} s in {})\n{}",
            g.total_seconds,
            g.sat_seconds,
            g.nusmv_seconds,
            plural(g.nusmv_calls, "check"),
            match g.least_for_recordings_and_runs {
                true => "C, T and N are least for the recordings and the closed-loop runs of the guide; a smaller machine that answers differently where nothing was recorded is not ruled out",
                false => "the repaired machine itself (the least machine for the runs failed NuSMV); it is not minimal",
            }
        ),
        Summary::Turn(Turn::Search(s)) => format!(
            "search, seed {}: {:.2} s total, {} evaluations, {} in-process checks, {} NuSMV runs; its machine ({}) made small in {} ({}){}",
            s.seed,
            s.total_seconds,
            s.search.evaluations,
            s.in_process_checks,
            s.nusmv_runs,
            s.searched_size,
            plural(s.shrink_rounds.len(), "round"),
            s.shrunk_size,
            match s.replaced_by_exact_loop {
                true => "; the exact loop below it found this smaller one",
                false => "",
            }
        ),
    }
}
