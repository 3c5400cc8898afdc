//! The tank level control of the process-mining paper ("Process Mining of Programmable Logic
//! Controllers: Input/Output Event Logs"): two plants, two PLC programs, three recorded
//! scenarios.
//!
//! In: nothing but this file's constants (and a seed for the noisy plant). Out: simulated runs
//! ([`simulate`]) of a reference program ([`Program::reference`]) on a plant ([`Plant`]), as
//! scenario steps (one per PLC scan), as raw long-format data-flow logs with the PLC addresses
//! of the paper's case study ([`write_long_log`], [`MAP_TEXT`]), and the committed files
//! ([`write_files`]).
//!
//! # Plant
//! A tank of [`CAPACITY`] gallons with a binary inlet valve (`inlet`, `%QX0.0`) and a binary
//! outlet valve (`outlet`, `%QX0.1`), and three level sensors, true when liquid reaches them:
//! `ll` (`%IX0.1`) at [`LL`], `ml` (`%IX0.2`) at [`ML`], `ul` (`%IX0.0`) at [`UL`] gallons.
//! - [`Plant::Constant`]: an open valve moves [`FLOW`] gallons per second, a closed one none.
//! - [`Plant::Noisy`]: every second each open valve's flow is drawn from a normal distribution
//!   (mean [`FLOW`], deviation [`FLOW_SD`], at least 0) and each closed valve leaks an amount
//!   drawn uniformly from `0..`[`LEAK`]; seeded (ChaCha8), so a run is reproducible.
//!
//! The level stays within `0..=CAPACITY` (an overflowing tank spills).
//!
//! # Timing
//! One scan per [`SCAN`] seconds: the PLC reads the sensors, its program reacts (at most one
//! ECC transition), then the plant runs for one scan under the new valve commands.
//!
//! # Programs (the "legacy PLC" whose logic is recovered)
//! - [`Program::FillDrain`] (program 1): fill until `ul`, then drain until `ll` is uncovered,
//!   and again.
//! - [`Program::Cycles`] (program 2): fill until `ul`, then [`CYCLES`] times drain until `ml` is
//!   uncovered and fill until `ul` again, then drain until `ll` is uncovered, and again. The
//!   counter is written out as states, as a ladder program's counter is a register.
//!
//! Both start in their drain-to-empty state with both valves closed: the tank starts empty,
//! so the first scan opens the inlet.
//!
//! # Scenarios (the paper's section VI-C)
//! [`SCENARIOS`]: 1 = program 1 on the constant plant, 2 = program 2 on the constant plant,
//! 3 = program 2 on the noisy plant, 600 scans each; [`HELD_OUT`] lists runs never used for
//! training. `synth-dev generate tank` writes the per-scan scenarios `specs/tank1.traces`
//! (scenario 1) and `specs/tank2.traces` (scenarios 2 and 3) with their names files, and under
//! `specs/tank/` the mapping `tank.map`, the raw long-format logs `scenario1.csv` to
//! `scenario3.csv` and two held-out runs on the noisy plant (`heldout1.csv`, `heldout2.csv`,
//! 1200 scans); a unit test checks that the shipped files equal the generator's output.
//!
//! # Surrogate and properties
//! `smv/tank_surrogate.smv` abstracts both plants: level 0..14 in coarse units, every open
//! valve moves it by 1 or 2 per step nondeterministically, leakage by at most 1, and an
//! observer `fills` counts how often the level rose to `ul` since `ll` was last uncovered.
//! `specs/tank1.ltl`: valves never open at once, no overflow, `G F ul`, `G F !ll`, one fill per
//! drain. `specs/tank2.ltl`: the same four, the cycle count `G ((ll & X !ll) -> fills = 4)`,
//! and `ll` stays covered while cycles remain.
//!
//! ```text
//! synth --ltl specs/tank1.ltl --plant smv/tank_surrogate.smv        # program 1
//! synth --ltl specs/tank2.ltl --plant smv/tank_surrogate.smv        # program 2
//! # from the raw logs alone:
//! synth ingest --log specs/tank/scenario2.csv --map specs/tank/tank.map -o out/s2.traces
//! synth ingest --log specs/tank/scenario3.csv --map specs/tank/tank.map -o out/s3.traces
//! synth infer --traces out/s2.traces out/s3.traces --out out/tank2-raw
//! synth verify --ecc out/tank2-raw/SynthesizedFB.json --ltl specs/tank2.ltl --plant smv/tank_surrogate.smv
//! ```
//!
//! # Results
//! (Times in `BENCHMARKS.md`.)
//!
//! | program | scenarios | result | properties |
//! |---|---|---|---|
//! | 1 | 1 (600 steps) | C = 2, T = 2, N = 2 | 5 of 5 hold |
//! | 2 | 2 + 3 (1200 steps) | C = 8, T = 8, N = 8 | 6 of 6 hold |
//! | 2, raw logs via `ingest` + `infer` | 2 + 3 (261 steps) | C = 8, T = 8, N = 8 | 6 of 6 hold (`synth verify`) |
//!
//! The machines are the reference programs up to state names: program 2's counter became the
//! six states of the three drain/fill cycles, with guards `!ll`, `ul`, `!ml`. On 20 held-out
//! noisy-plant runs per program (seeds 2000..2019, 1500 scans each, 30,000 scans per program),
//! fed the sensor values the reference program saw, each machine computes the reference's
//! valve commands at every scan (0 disagreements), and in closed loop with the same seeded
//! plant it reproduces the reference's runs exactly. These checks, the verification and the
//! replay of every training scenario and ingested log are the integration tests
//! `tank::tank_programs_are_rebuilt_exactly_and_verified` and
//! `tank::program_2_from_the_raw_logs_alone`. The properties can fail: program 1's machine
//! violates `cycle_count` of `specs/tank2.ltl`
//! (`tank::program_1_does_not_satisfy_the_cycle_count_of_program_2`).
//!
//! # Compared with the paper and with process mining
//! From the same kind of data (tapped I/O, three scenarios) the paper discovers with Split
//! Miner a Petri net that, for program 2, "does not count the number of transition firings",
//! and adds DREAM-NAP, a neural network trained on 17 traces, to predict the next activity
//! (100 % on 5 test traces). Here the counter is exact and readable: 8 states, 8 transitions,
//! one literal per guard, verified by NuSMV against the cycle count in closed loop, and exact
//! on every held-out scan. pm4py's inductive miner on the same event logs
//! (`tests/pm4py_check.py`) gives 9 places / 10 transitions for scenario 1, and 12 / 14
//! (scenario 2) and 12 / 13 (scenario 3) for program 2: nets with a loop that fit the logs
//! (fitness 1.0) but, like the paper's, let the loop run any number of times (token-based
//! precision 0.85 on scenario 2). The PNML export of the synthesized machines (program 1: 5
//! places, 19 transitions; program 2: 17 places, 55 transitions) replays every complete trace
//! of the three logs in pm4py (19 of 19, 7 of 8, 7 of 7; the last trace of scenario 2 is cut
//! off by the end of the recording; log fitness 1.0, 0.995, 1.0). The counting shows in
//! replay: a controller that does one middle cycle instead of three (program 2 with
//! `Raise1 -> Drain`, 600 scans on the constant plant, 13 traces) fits the inductive miner's net
//! of scenario 2 completely (13 of 13 traces, fitness 1.0), while the net of program 2's
//! machine rejects every trace (0 of 13, fitness 0.93); test
//! `tank::only_the_machine_net_notices_a_wrong_cycle_count`. To reproduce (with `PY` from
//! `.ci/install-pm4py.sh`):
//!
//! ```text
//! synth --ltl specs/tank2.ltl --plant smv/tank_surrogate.smv --out out/tank2
//! synth events --log specs/tank/scenario2.csv --map specs/tank/tank.map --reset "%IX0.1 false" \
//!     --out out/tank/scenario2.xes --ecc out/tank2/SynthesizedFB.json --pnml out/tank/tank2.pnml
//! $PY tests/pm4py_check.py out/tank/scenario2.xes --pnml out/tank/tank2.pnml [--replay OTHER.xes]
//! ```

pub use super::reference::tank::{CYCLES, INPUTS, OUTPUTS};
use super::{closed_loop, Drive, Simulated};
use crate::ecc::{Ecc, Run};
use crate::files::{write_atomic, WriteError};
use crate::scenario::{fbsat, Origin, Scenario, ScenarioSet, Step};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::io::Write;
use std::path::{Path, PathBuf};

/// OpenPLC addresses of [`INPUTS`], as in the process-mining paper.
pub const INPUT_ADDRESSES: [&str; 3] = ["%IX0.1", "%IX0.2", "%IX0.0"];
/// OpenPLC addresses of [`OUTPUTS`].
pub const OUTPUT_ADDRESSES: [&str; 2] = ["%QX0.0", "%QX0.1"];
/// The mapping file of the logs.
pub const MAP_TEXT: &str = "\
# Tank of seed 002: level sensors and valves at their OpenPLC addresses.
%IX0.1 in  ll
%IX0.2 in  ml
%IX0.0 in  ul
%QX0.0 out inlet
%QX0.1 out outlet
";
/// The reset activity that slices the logs into traces: the tank is almost empty.
pub const RESET: &str = "%IX0.1 false";

/// Tank volume, gallons.
pub const CAPACITY: f64 = 100.0;
/// Height of the lower level sensor `ll`, gallons.
pub const LL: f64 = 20.0;
/// Height of the middle level sensor `ml`, gallons.
pub const ML: f64 = 50.0;
/// Height of the upper level sensor `ul`, gallons.
pub const UL: f64 = 80.0;
/// Flow of an open valve (constant plant; mean of the noisy plant), gallons per second.
pub const FLOW: f64 = 4.0;
/// Standard deviation of the noisy plant's flows, gallons per second.
pub const FLOW_SD: f64 = 1.0;
/// Upper bound of the noisy plant's leakage through a closed valve, gallons per second.
pub const LEAK: f64 = 0.2;
/// Seconds per PLC scan.
pub const SCAN: f64 = 1.0;

/// One of the two PLC programs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Program {
    /// Program 1: fill to `ul`, drain to `ll`.
    FillDrain,
    /// Program 2: fill to `ul`, [`CYCLES`] times down to `ml` and up to `ul`, drain to `ll`.
    Cycles,
}

impl Program {
    /// The program as an ECC: state 0 (`Drain`) initial, valves closed initially.
    pub fn reference(self) -> Ecc {
        match self {
            Program::FillDrain => super::reference::tank::fill_drain(),
            Program::Cycles => super::reference::tank::cycles(),
        }
    }
}

/// One of the two plants.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plant {
    /// Constant flows, no leakage.
    Constant,
    /// Random flows and leakage.
    Noisy {
        /// Seed of the flows and leaks.
        seed: u64,
    },
}

/// A recorded run: scenario name, program, plant, number of scans.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunSpec {
    /// The scenario's name.
    pub name: &'static str,
    /// The PLC program.
    pub program: Program,
    /// The plant it runs on.
    pub plant: Plant,
    /// Scans recorded.
    pub scans: usize,
}

/// The process-mining paper's three scenarios, recorded for training.
pub const SCENARIOS: [RunSpec; 3] = [
    RunSpec {
        name: "scenario1",
        program: Program::FillDrain,
        plant: Plant::Constant,
        scans: 600,
    },
    RunSpec {
        name: "scenario2",
        program: Program::Cycles,
        plant: Plant::Constant,
        scans: 600,
    },
    RunSpec {
        name: "scenario3",
        program: Program::Cycles,
        plant: Plant::Noisy { seed: 3 },
        scans: 600,
    },
];

/// Runs never used for training: both programs on the noisy plant with other seeds, longer.
pub const HELD_OUT: [RunSpec; 2] = [
    RunSpec {
        name: "heldout1",
        program: Program::FillDrain,
        plant: Plant::Noisy { seed: 1001 },
        scans: 1200,
    },
    RunSpec {
        name: "heldout2",
        program: Program::Cycles,
        plant: Plant::Noisy { seed: 1002 },
        scans: 1200,
    },
];

/// The tank's state and its random source.
#[derive(Debug, Clone)]
pub struct Tank {
    /// Gallons.
    pub level: f64,
    rng: Option<ChaCha8Rng>,
}

impl Tank {
    /// An empty tank of the given plant.
    pub fn new(plant: Plant) -> Tank {
        Tank {
            level: 0.0,
            rng: match plant {
                Plant::Constant => None,
                Plant::Noisy { seed } => Some(ChaCha8Rng::seed_from_u64(seed)),
            },
        }
    }

    /// Sensor values `ll, ml, ul`.
    pub fn sensors(&self) -> Vec<bool> {
        vec![self.level >= LL, self.level >= ML, self.level >= UL]
    }

    /// Runs the plant for `seconds` under the valve commands `inlet, outlet`.
    pub fn tick(&mut self, valves: &[bool], seconds: f64) {
        let mut flow = |open: bool| -> f64 {
            match (&mut self.rng, open) {
                (None, true) => FLOW,
                (None, false) => 0.0,
                (Some(rng), true) => (FLOW + FLOW_SD * standard_normal(rng)).max(0.0),
                (Some(rng), false) => rng.gen_range(0.0..LEAK),
            }
        };
        let inflow = flow(valves[0]);
        let outflow = flow(valves[1]);
        self.level = (self.level + (inflow - outflow) * seconds).clamp(0.0, CAPACITY);
    }
}

/// A standard normal sample (Box-Muller), so no distribution crate is needed.
fn standard_normal(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.gen::<f64>();
    let u2: f64 = rng.gen();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// One PLC scan of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Scan {
    /// Seconds since the start.
    pub time: f64,
    /// Gallons when the sensors were read.
    pub level: f64,
    /// The sensor values read.
    pub inputs: Vec<bool>,
    /// Whether a transition fired (the step is active).
    pub fired: bool,
    /// Valve commands after the scan.
    pub outputs: Vec<bool>,
}

/// Runs `ecc` (over [`INPUTS`] / [`OUTPUTS`]) on an empty tank of `plant` for `scans` scans.
pub fn simulate(ecc: &Ecc, plant: Plant, scans: usize) -> Vec<Scan> {
    closed_loop(ecc, Tank::new(plant), scans, |_, _, _| Drive::Scan)
        .0
        .into_iter()
        .enumerate()
        .map(|(k, s)| Scan {
            time: k as f64 * SCAN,
            level: s.plant.level,
            inputs: s.inputs,
            fired: s.fired.is_some(),
            outputs: s.outputs,
        })
        .collect()
}

impl Simulated for Tank {
    fn read(&self) -> Vec<bool> {
        self.sensors()
    }
    fn scan(&mut self, z: &[bool]) {
        self.tick(z, SCAN)
    }
}

/// Runs a spec's reference program.
pub fn record(spec: &RunSpec) -> Vec<Scan> {
    simulate(&spec.program.reference(), spec.plant, spec.scans)
}

/// The scans as scenario steps (one `REQ` per scan, `CNF` when a transition fired).
pub fn steps(scans: &[Scan]) -> Vec<Step> {
    scans
        .iter()
        .map(|s| Step {
            inputs: s.inputs.clone(),
            outputs: s.fired.then(|| s.outputs.clone()),
        })
        .collect()
}

/// Feeds the input sequence of `scans` to `ecc` and returns the first scan (0-based) whose
/// outputs differ from the recorded ones, if any: the open-loop comparison of a machine with
/// the program that made the recording, on the same plant inputs.
pub fn first_disagreement(ecc: &Ecc, scans: &[Scan]) -> Option<usize> {
    let mut run = Run::new(ecc);
    scans.iter().position(|s| {
        run.step(&s.inputs);
        run.outputs != s.outputs
    })
}

/// Writes the run as a long-format data-flow log (`timestamp,address,value`, one row per
/// changed signal, the sensors read before the valves written; every signal starts 0).
pub fn write_long_log(scans: &[Scan], w: &mut impl Write) -> std::io::Result<()> {
    writeln!(w, "timestamp,address,value")?;
    let mut inputs = vec![false; INPUTS.len()];
    let mut outputs = vec![false; OUTPUTS.len()];
    for s in scans {
        for (old, (new, address)) in inputs.iter_mut().zip(s.inputs.iter().zip(INPUT_ADDRESSES)) {
            if old != new {
                writeln!(w, "{:.2},{address},{}", s.time, u8::from(*new))?;
                *old = *new;
            }
        }
        for (old, (new, address)) in outputs
            .iter_mut()
            .zip(s.outputs.iter().zip(OUTPUT_ADDRESSES))
        {
            if old != new {
                writeln!(w, "{:.2},{address},{}", s.time, u8::from(*new))?;
                *old = *new;
            }
        }
    }
    Ok(())
}

/// The training scenario set of a program: every scenario of [`SCENARIOS`] it ran in, one
/// scenario each; origins name `<stem>.traces` and the scenario's line in it.
pub fn training_set(program: Program) -> ScenarioSet {
    let stem = traces_stem(program);
    let scenarios = SCENARIOS
        .iter()
        .filter(|s| s.program == program)
        .enumerate()
        .map(|(k, s)| Scenario {
            origin: Origin {
                file: PathBuf::from(format!("{stem}.traces")),
                line: k + 2,
                rows: None,
            },
            steps: steps(&record(s)),
        })
        .collect();
    ScenarioSet {
        inputs: INPUTS.iter().map(|s| s.to_string()).collect(),
        outputs: OUTPUTS.iter().map(|s| s.to_string()).collect(),
        initial_outputs: vec![false; OUTPUTS.len()],
        scenarios,
    }
}

/// `tank1` for program 1, `tank2` for program 2: the stem of the spec files.
pub fn traces_stem(program: Program) -> &'static str {
    match program {
        Program::FillDrain => "tank1",
        Program::Cycles => "tank2",
    }
}

/// Writes into `dir` (e.g. `specs/`), each file atomically: `tank1.traces` / `tank2.traces`
/// with `.inputs` / `.outputs` names files (the per-scan scenarios of each program), and under
/// `tank/` the mapping `tank.map` and one long-format log per scenario and held-out run
/// (`scenario1.csv` ... `heldout2.csv`). Returns the paths written.
pub fn write_files(dir: &Path) -> Result<Vec<PathBuf>, WriteError> {
    let mut files: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    let names = |names: &[&str]| names.iter().map(|n| format!("{n}\n")).collect::<String>();
    for program in [Program::FillDrain, Program::Cycles] {
        let stem = traces_stem(program);
        let mut traces = Vec::new();
        fbsat::write(&training_set(program), &mut traces).expect("writing into memory");
        files.push((dir.join(format!("{stem}.traces")), traces));
        files.push((
            dir.join(format!("{stem}.inputs")),
            names(&INPUTS).into_bytes(),
        ));
        files.push((
            dir.join(format!("{stem}.outputs")),
            names(&OUTPUTS).into_bytes(),
        ));
    }
    files.push((dir.join("tank/tank.map"), MAP_TEXT.as_bytes().to_vec()));
    for spec in SCENARIOS.iter().chain(&HELD_OUT) {
        let mut log = Vec::new();
        write_long_log(&record(spec), &mut log).expect("writing into memory");
        files.push((dir.join(format!("tank/{}.csv", spec.name)), log));
    }
    let mut written = Vec::new();
    for (path, bytes) in files {
        write_atomic(&path, &bytes)?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ingest::{read_scenarios, Mapping};

    fn reset_times(scans: &[Scan]) -> usize {
        scans
            .windows(2)
            .filter(|w| w[0].inputs[0] && !w[1].inputs[0])
            .count()
    }

    #[test]
    fn program_1_fills_to_the_upper_sensor_and_drains_to_the_lower() {
        let scans = record(&SCENARIOS[0]);
        assert!(scans.iter().all(|s| !(s.outputs[0] && s.outputs[1])));
        // The level never leaves the band between just below ll and just above ul.
        let top = scans.iter().map(|s| s.level).fold(0.0, f64::max);
        assert!((UL..UL + 2.0 * FLOW).contains(&top), "top {top}");
        assert!(scans.iter().skip(40).all(|s| s.level > LL - 2.0 * FLOW));
        assert!(reset_times(&scans) > 10);
    }

    #[test]
    fn program_2_cycles_between_middle_and_upper_before_draining() {
        let scans = record(&SCENARIOS[1]);
        // Between two uncoverings of ll, ul is reached 1 + CYCLES times.
        let mut count = 0;
        let mut counts = Vec::new();
        for w in scans.windows(2) {
            if !w[0].inputs[2] && w[1].inputs[2] {
                count += 1;
            }
            if w[0].inputs[0] && !w[1].inputs[0] {
                counts.push(count);
                count = 0;
            }
        }
        assert!(counts.len() >= 3, "{counts:?}");
        assert!(counts.iter().all(|&c| c == 1 + CYCLES), "{counts:?}");
    }

    #[test]
    fn the_noisy_plant_is_seeded_and_differs_from_the_constant_one() {
        let a = record(&SCENARIOS[2]);
        assert_eq!(a, record(&SCENARIOS[2]));
        assert_ne!(
            a.iter().map(|s| s.level).collect::<Vec<_>>(),
            record(&SCENARIOS[1])
                .iter()
                .map(|s| s.level)
                .collect::<Vec<_>>()
        );
    }

    #[test]
    fn the_long_log_ingests_into_the_recorded_behaviour() {
        // Reading the raw log back gives the recorded run without its repeated scans.
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("s.csv");
        let scans = record(&SCENARIOS[1]);
        let mut text = Vec::new();
        write_long_log(&scans, &mut text).unwrap();
        std::fs::write(&log, text).unwrap();
        let m = Mapping::parse(Path::new("tank.map"), MAP_TEXT).unwrap();
        let (set, _) = read_scenarios(&log, &m, false).unwrap();
        set.check(&Program::Cycles.reference()).unwrap();
    }

    #[test]
    fn the_shipped_files_are_what_the_generator_writes() {
        let dir = tempfile::tempdir().unwrap();
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("specs");
        for path in write_files(dir.path()).unwrap() {
            let rel = path.strip_prefix(dir.path()).unwrap();
            let shipped = std::fs::read(root.join(rel)).unwrap_or_else(|e| {
                panic!("{}: {e} (run `synth-dev generate tank`)", rel.display())
            });
            assert!(
                shipped == std::fs::read(&path).unwrap(),
                "specs/{} differs from the generator (run `synth-dev generate tank`)",
                rel.display()
            );
        }
    }
}
