//! `synth-dev bench-fbsat-pnp`: the main job on fbSAT's own Pick-and-Place model, a plant
//! written for other work and used unchanged.
//!
//! In: a checkout of fbSAT (ctlab/fbSAT on GitHub; not part of this repository, and none of its
//! files is copied into it). Read from it at run time: the plant `data/pnp/smv/plant.smv`
//! (`MODULE PLANT`, reading the controller's event `CNF` with `next()`), the rest of its
//! closed loop (`extra.smv`, `main.smv`, `spec.smv`), the name lists and the recordings
//! `data/tests-K.gz`. Out, in `--out`: the plant file the main job reads (fbSAT's `plant.smv`
//! followed by this project's wrapper module [`WRAPPER`]), the nine properties in the LTL file
//! format ([`PROPERTIES`]), one result folder per recording and run, and a Markdown table: the
//! machine's size, the main job's wall time, and how many of fbSAT's own properties NuSMV finds
//! true when the machine (exported as `MODULE CONTROL`) takes the place of fbSAT's controller
//! in fbSAT's unchanged model.
//!
//! The main job runs as the user runs it: the `synth` binary beside this one, with the command
//! line the table's caption prints.

use crate::stats::Stats;
use clap::Args;
use fbsynth::out;
use fbsynth::pipeline::Error;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

#[derive(Debug, Args)]
pub struct BenchFbsatPnpArgs {
    /// A checkout of fbSAT (ctlab/fbSAT): its `data/pnp/smv/` model, `data/pnp/` name lists
    /// and `data/tests-K.gz` recordings are read, never copied.
    #[arg(long, value_name = "DIR")]
    pub fbsat: PathBuf,
    /// The recordings `tests-K.gz` to run, by K; a missing file is skipped.
    #[arg(long, value_delimiter = ',', default_values_t = [1, 10, 39], value_name = "K,...")]
    pub cases: Vec<u32>,
    /// Runs per recording; the table shows min / median / max of the wall time.
    #[arg(long, default_value_t = 3, value_parser = crate::cli::args::repetitions())]
    pub runs: usize,
    /// Folder for the generated plant and properties and the results.
    #[arg(long, default_value = "out/bench-fbsat-pnp", value_name = "DIR")]
    pub out: PathBuf,
    /// The NuSMV binary (default: as the main job finds it).
    #[arg(long, value_name = "PATH")]
    pub nusmv: Option<PathBuf>,
}

/// The wrapper around fbSAT's `MODULE PLANT`: the module the main job composes with the
/// controller (parameters: the event `CNF` and the seven outputs, in fbSAT's order). It holds
/// what fbSAT's closed loop keeps outside `PLANT`: the operator who puts work pieces on
/// track 1 at will (tracks 2 and 3 stay empty), the piece sensors, the suction unit and its
/// vacuum sensor, and the record of a lifted piece that the properties read.
pub const WRAPPER: &str = "
-- The cell around PLANT, as the controller sees it: sensors named as its inputs, the work
-- pieces, the suction unit, and the record of a lifted piece.
MODULE plant(CNF, c1Extend, c1Retract, c2Extend, c2Retract, vcExtend, vacuum_on, vacuum_off)
VAR
  P : PLANT(CNF, c1Extend, c1Retract, c2Extend, c2Retract, vcExtend, vacuum_on, vacuum_off);
  p1 : boolean;      -- the operator puts a piece on track 1 (free at every step)
  pp1 : boolean;     -- a piece waits on track i
  pp2 : boolean;
  pp3 : boolean;
  vs : boolean;      -- the suction unit is on
  vac : boolean;     -- the cup holds a piece
  lifted : boolean;  -- a piece was picked up and not yet dropped
DEFINE
  c1Home := P.c1Home;
  c1End := P.c1End;
  c2Home := P.c2Home;
  c2End := P.c2End;
  vcHome := P.vcHome;
  vcEnd := P.vcEnd;
  p2 := FALSE;
  p3 := FALSE;
  -- the cup, down and sucking over track i, takes the piece there
  vp1 := c1End & c2Home & vcEnd & vs & pp1;
  vp2 := c1Home & c2End & vcEnd & vs & pp2;
  vp3 := c1End & c2End & vcEnd & vs & pp3;
  -- a lifted piece let go with the hand down over track 1
  dropped := lifted & c1Home & c2Home & vcEnd & !vacuum_on & vacuum_off;
ASSIGN
  -- switched with every confirmation: on if vacuum_on is set, off otherwise
  init(vs) := FALSE;
  next(vs) := case
    next(CNF) : next(vacuum_on);
    TRUE : vs;
  esac;
  init(vac) := FALSE;
  next(vac) := case
    next(vp1 | vp2 | vp3) : TRUE;
    next(vs) : vac;
    TRUE : FALSE;
  esac;
  init(pp1) := FALSE;
  next(pp1) := case
    vp1 : FALSE;
    TRUE : pp1 | p1;
  esac;
  init(pp2) := FALSE;
  next(pp2) := case
    vp2 : FALSE;
    TRUE : pp2 | p2;
  esac;
  init(pp3) := FALSE;
  next(pp3) := case
    vp3 : FALSE;
    TRUE : pp3 | p3;
  esac;
  init(lifted) := FALSE;
  next(lifted) := case
    vp1 : TRUE;
    dropped : FALSE;
    TRUE : lifted;
  esac;
";

/// fbSAT's nine Pick-and-Place properties over the wrapper's names (the controller's outputs
/// and the wrapper's variables and defines), one per line.
pub const PROPERTIES: &str = "\
-- Never both directions of one cylinder, never suction on and off at once.
c1_exclusive: G !(c1Extend & c1Retract)
c2_exclusive: G !(c2Extend & c2Retract)
vacuum_exclusive: G !(vacuum_on & vacuum_off)
-- The vertical cylinder travels only with cylinder I at an end, and the other way round.
lower_only_at_an_end: G ((!vcHome & !vcEnd) -> (c1Home | c1End))
move_only_up_or_down: G ((!c1Home & !c1End) -> (vcHome | vcEnd))
never_both_travelling: G !(!c1Home & !c1End & !vcHome & !vcEnd)
-- At rest with nothing to do, nothing moves.
rest_when_idle: G ((c1Home & c2Home & vcHome & !pp1 & !lifted) -> X (!c1Extend & !c2Extend & !vcExtend))
-- A piece on track 1 is picked up; a lifted piece is let go.
track1_served: G (pp1 -> F vp1)
lifted_dropped: G (lifted -> F dropped)
";

/// What one run of the main job gave.
struct Run {
    seconds: f64,
    size: [u64; 4],
    /// Candidates, and how many of them NuSMV judged.
    candidates: (usize, usize),
    /// NuSMV's seconds in the run.
    nusmv_seconds: f64,
    folder: PathBuf,
}

/// `synth-dev bench-fbsat-pnp` (module documentation).
pub fn bench_fbsat_pnp(args: &BenchFbsatPnpArgs) -> Result<(), Error> {
    let smv = args.fbsat.join("data/pnp/smv");
    let model = |f: &str| read(&smv.join(f));
    let (plant, extra, main, spec) = (
        model("plant.smv")?,
        model("extra.smv")?,
        model("main.smv")?,
        model("spec.smv")?,
    );
    std::fs::create_dir_all(&args.out)?;
    let wrapper = args.out.join("fbsat_pnp_plant.smv");
    std::fs::write(&wrapper, format!("{plant}{WRAPPER}"))?;
    let ltl = args.out.join("fbsat_pnp.ltl");
    std::fs::write(&ltl, PROPERTIES)?;
    let synth = sibling("synth")?;
    let nusmv = fbsynth::nusmv::locate(args.nusmv.as_deref())?;
    let names = args.fbsat.join("data/pnp");
    out!(
        "plant {} (fbSAT's plant.smv and the wrapper), properties {}",
        wrapper.display(),
        ltl.display()
    );
    let mut header = false;
    for k in &args.cases {
        let traces = args.fbsat.join(format!("data/tests-{k}.gz"));
        if !traces.is_file() {
            out!("tests-{k} skipped: no {}", traces.display());
            continue;
        }
        let mut runs = Vec::with_capacity(args.runs);
        for r in 1..=args.runs {
            let folder = args.out.join(format!("tests-{k}")).join(format!("run-{r}"));
            let mut cmd = Command::new(&synth);
            cmd.arg("-q").args(["--ltl".as_ref(), ltl.as_os_str()]);
            cmd.args(["--plant".as_ref(), wrapper.as_os_str()]);
            cmd.args(["--traces".as_ref(), traces.as_os_str()]);
            cmd.args([
                "--input-names".as_ref(),
                names.join("input-names").as_os_str(),
            ]);
            cmd.args([
                "--output-names".as_ref(),
                names.join("output-names").as_os_str(),
            ]);
            cmd.args(["--nusmv".as_ref(), nusmv.as_os_str()]);
            cmd.args(["--name", "CONTROL", "--format", "json,smv"]);
            cmd.args(["--out".as_ref(), folder.as_os_str()]);
            if !header {
                out!("the main job, per recording: {cmd:?}");
                out!();
                out!("| recording | C | K | T | N | min s | median s | max s | candidates (NuSMV judged) | NuSMV s | fbSAT's model, NuSMV |");
                out!("|---|---|---|---|---|---|---|---|---|---|---|");
                header = true;
            }
            runs.push(main_job(cmd, folder)?);
        }
        let last = runs.last().expect("runs >= 1");
        let verdict = fbsat_verdict(&nusmv, last, &[&extra, &plant, &main, &spec])?;
        let times: Vec<f64> = runs.iter().map(|r| r.seconds).collect();
        let s = Stats::of(&times).expect("runs >= 1");
        let [c, kk, t, n] = last.size;
        out!(
            "| tests-{k} | {c} | {kk} | {t} | {n} | {:.2} | {:.2} | {:.2} | {} ({}) | {:.2} | {verdict} |",
            s.min,
            s.median,
            s.max,
            last.candidates.0,
            last.candidates.1,
            last.nusmv_seconds
        );
    }
    Ok(())
}

/// A file of fbSAT's checkout, or an error naming it.
fn read(path: &Path) -> Result<String, Error> {
    std::fs::read_to_string(path).map_err(|e| {
        Error::Input(format!(
            "cannot read {} (--fbsat takes a checkout of ctlab/fbSAT): {e}",
            path.display()
        ))
    })
}

/// The binary `name` built beside this one.
fn sibling(name: &str) -> Result<PathBuf, Error> {
    let path = std::env::current_exe()?.with_file_name(name);
    if path.is_file() {
        Ok(path)
    } else {
        Err(Error::Input(format!(
            "no {} beside synth-dev: build both binaries (cargo build --release)",
            path.display()
        )))
    }
}

/// Runs the main job `cmd` (writing into `folder`), timed; its size from `summary.json`.
fn main_job(mut cmd: Command, folder: PathBuf) -> Result<Run, Error> {
    if folder.exists() {
        std::fs::remove_dir_all(&folder)?;
    }
    let t = Instant::now();
    let status = cmd.stdout(std::process::Stdio::null()).status()?;
    let seconds = t.elapsed().as_secs_f64();
    if !status.success() {
        return Err(Error::Input(format!(
            "the main job into {} ended with {status}",
            folder.display()
        )));
    }
    let summary = read(&folder.join("summary.json"))?;
    let json: serde_json::Value = serde_json::from_str(&summary)
        .map_err(|e| Error::Input(format!("{}: {e}", folder.join("summary.json").display())))?;
    let size = ["c", "k", "t", "n"].map(|x| json["size"][x].as_u64().unwrap_or(0));
    let iterations = json["iterations"].as_array().map_or(&[][..], |a| a);
    let by_nusmv = (iterations.iter())
        .filter(|i| i["checked_by"] == "NuSMV")
        .count();
    Ok(Run {
        seconds,
        size,
        candidates: (iterations.len(), by_nusmv),
        nusmv_seconds: json["nusmv_seconds"].as_f64().unwrap_or(0.0),
        folder,
    })
}

/// The machine of `run` (`CONTROL.smv`) in fbSAT's model in place of fbSAT's controller, the
/// files concatenated in the order fbSAT's own Makefile gives: how many of its `LTLSPEC`s
/// NuSMV finds true, as `true/all`.
fn fbsat_verdict(nusmv: &Path, run: &Run, rest: &[&str]) -> Result<String, Error> {
    let mut model = read(&run.folder.join("CONTROL.smv"))?;
    rest.iter().for_each(|f| model.push_str(f));
    let file = run.folder.join("fbsat_model.smv");
    std::fs::write(&file, &model)?;
    let output = Command::new(nusmv).arg(&file).output()?;
    let text = String::from_utf8_lossy(&output.stdout);
    let verdicts: Vec<&str> = (text.lines())
        .filter(|l| l.starts_with("-- specification"))
        .collect();
    let specs = model
        .lines()
        .filter(|l| l.trim_start().starts_with("LTLSPEC"))
        .count();
    if verdicts.len() != specs {
        return Err(Error::Input(format!(
            "NuSMV gave {} verdicts for the {specs} properties of {}: {}",
            verdicts.len(),
            file.display(),
            String::from_utf8_lossy(&output.stderr)
                .lines()
                .take(5)
                .collect::<Vec<_>>()
                .join(" ")
        )));
    }
    let holds = verdicts.iter().filter(|l| l.ends_with("is true")).count();
    Ok(format!("{holds}/{specs}"))
}
