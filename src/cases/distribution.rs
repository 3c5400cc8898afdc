//! The Festo distribution station of the SAT reconstruction paper (Chivilikhin et al.,
//! "Automatic state machine reconstruction from legacy PLC using data collection and SAT
//! solver", section VI): plant simulation, reference controller, PLC-style sampled logs and
//! the scan-cycle errors of a data collector.
//!
//! In: a [`UseCase`] (how many work pieces, which buttons when) and, for noisy logs, an error
//! rate and a seed. Out: sampled logs ([`Sample`]s, one per PLC scan) as CSV, clean or with
//! injected skew ([`inject_skew`]); the shipped files `specs/distribution*.csv`
//! ([`write_files`]).
//!
//! # Station
//! - Stack magazine: a stack of pieces (`empty` when none is left) and an ejecting cylinder
//!   that rests extended. `retract` held pulls it back ([`PUSH_STROKE`] scans end to end,
//!   sensors `retracted`/`extended` at the ends); fully retracted, the lowest piece drops in
//!   front of it; released, it extends and pushes that piece to the pick-up point.
//! - Rotating arm with a suction cup: `to_client` / `to_magazine` held turn it
//!   ([`ARM_STROKE`] scans end to end, sensors `at_magazine`/`at_client`); `vacuum_on` /
//!   `vacuum_off` are pulses that switch suction; `vac_on` says the cup holds a piece. At the
//!   magazine with suction on, the cup grips the piece at the pick-up point; suction off drops
//!   it: at the client it is delivered, anywhere else lost.
//! - HMI: buttons `start`, `stop` (also acknowledges an emergency), switch `auto_man`
//!   (1 = automatic), button `emergency`; lamps `start_led` (running) and `reset_led`
//!   (emergency stop, waiting for `stop`).
//!
//! # Logs
//! One scan = one `REQ`: the controller reads the sensors, fires at most one transition, then
//! the plant moves one scan. The data collector records one [`Sample`] per scan: the inputs
//! read and the outputs after the scan. The reference controller is built so that this log
//! loses nothing: every transition changes an output, and no transition can fire twice in a row
//! on one input vector, so [`csvlog::samples_to_steps`] turns a clean log into exactly the
//! scans that mattered.
//!
//! # Shipped data
//! [`reference()`] is a hand-made 9-state controller; [`Station`] the plant; six recorded use
//! cases (1 to 8 pieces, manual and automatic mode, stop, emergency and acknowledge) and three
//! held-out runs. [`inject_skew`] (ChaCha8, seeded) only injects errors of the paper's model.
//! `synth-dev generate distribution` writes into `specs/`: `distribution.csv` (clean, 6 use cases,
//! 684 samples, 27 KB), `distribution_noisy.csv` (the same with skew at rate 0.05, seed 2024: 2
//! errors), `distribution_heldout.csv` (3 clean runs, 419 samples, never used for synthesis)
//! and `distribution_reference.json`. Beside them: `smv/distribution_surrogate.smv`
//! (`MODULE plant(retract, ..., reset_led)`) and `specs/distribution.ltl` (8 properties, all of
//! which hold for the reference under NuSMV: `synth verify --ecc
//! specs/distribution_reference.json --ltl specs/distribution.ltl --plant
//! smv/distribution_surrogate.smv`).
//!
//! # What it showed
//! `synth infer --noisy --max-errors 2 --enumerate 4 --traces specs/distribution_noisy.csv`:
//!
//! | candidate | ε | C | K | T | N | replays the held-out runs |
//! |---|---|---|---|---|---|---|
//! | 1 | 1 | 9 | 3 | 13 | 14 | no |
//! | 2 | 2 | 9 | 3 | 13 | 15 | no |
//! | 3 | 2 | 9 | 3 | 13 | 13 | yes (and the clean logs) |
//!
//! ε never exceeds the 2 errors injected, and the third candidate (ε = 2, the true count)
//! behaves like the reference on every held-out run (`synth replay --ecc
//! out/dist/candidate_3/SynthesizedFB.json --traces specs/distribution_heldout.csv`). The first
//! candidate is *not* the right one: one of the two injected errors can also be read as real
//! behaviour with one correction fewer. Nor does NuSMV pick the right one: every candidate,
//! like the machine synthesized from the *clean* logs, violates `emergency_stops`, because the
//! logs press emergency only in `Idle`/`Ready` and the tree-exact machines have no transition
//! where nothing was recorded. Properties about behaviour the logs never show are the
//! business of the verified main job, not of trace correction.
//!
//! In two modules (the paper's Fig. 6): `synth infer --modules 2 --traces
//! specs/distribution.csv` gives two 5-state modules (A = 12, N' = 10) that together
//! replay all six use cases, but the split the objective prefers (least largest module) mixes
//! lamps and actuators: `retract, vacuum_on, to_magazine` in one module, `vacuum_off,
//! to_client, start_led, reset_led` in the other. Pinning gives the paper's split:
//!
//! ```text
//! synth infer --modules 2 --pin 1=start_led,reset_led \
//!     --pin 2=retract,vacuum_on,vacuum_off,to_magazine,to_client --traces specs/distribution.csv
//! # module 1: 3 states, 5 transitions; outputs start_led, reset_led; inputs start, stop, emergency
//! # module 2: 7 states, 9 transitions; outputs retract, vacuum_on, vacuum_off, to_magazine,
//! #           to_client; inputs empty, retracted, extended, at_magazine, at_client, start, auto_man
//! ```
//!
//! that is, the HMI as a 3-state module over its three buttons and the station as a 7-state
//! module (the monolithic minimum is C = 9, T = 13). `synth infer --noisy --max-errors
//! 2 --modules 2 --pin ...` on `specs/distribution_noisy.csv` runs both steps of the paper's
//! toolchain: it corrects the traces, then distributes the chosen candidate (the first
//! verified one with `--ltl/--plant`, else the first) into `modular/` (the same split;
//! test `modular::distribution_station_splits_in_two_and_pins_give_the_hmi_module`). The
//! composite is exact on its training logs but not on every held-out run (one diverges at
//! step 9: the modules' guards are minimized for the recorded inputs only).

pub use super::reference::distribution::{input_names, output_names, reference, INPUTS, OUTPUTS};
use super::{closed_loop, Drive, Scanned, Simulated};
use crate::ecc::Ecc;
use crate::files::{write_atomic, WriteError};
use crate::scenario::csvlog::{self, Sample};
use crate::scenario::{Origin, Scenario, ScenarioSet};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::io::Write;
use std::path::{Path, PathBuf};

const RETRACT: usize = 0;
const VACUUM_ON: usize = 1;
const VACUUM_OFF: usize = 2;
const TO_MAGAZINE: usize = 3;
const TO_CLIENT: usize = 4;

/// Scans the ejecting cylinder needs from one end to the other.
pub const PUSH_STROKE: u8 = 3;
/// Scans the arm needs from the magazine to the client (and back).
pub const ARM_STROKE: u8 = 4;
/// Scans a button is held down.
pub const PRESS: usize = 2;
/// Scans without a transition after which the station counts as settled and the next action
/// of a use case happens.
pub const SETTLE: usize = 8;
/// A use case that has not finished after this many scans is cut off.
pub const MAX_SCANS: usize = 20_000;

/// File names [`write_files`] writes into `specs/`: the clean logs of the use cases,
pub const CLEAN_FILE: &str = "distribution.csv";
/// the same with the injected skew,
pub const NOISY_FILE: &str = "distribution_noisy.csv";
/// and the clean logs of the held-out runs.
pub const HELDOUT_FILE: &str = "distribution_heldout.csv";
/// The reference controller in the project's JSON format.
pub const REFERENCE_FILE: &str = "distribution_reference.json";
/// Error rate of the shipped noisy log.
pub const SHIPPED_RATE: f64 = 0.05;
/// Seed of the errors injected into the shipped noisy log.
pub const SHIPPED_SEED: u64 = 2024;

/// The simulated station (everything but the controller).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Station {
    /// Pieces left in the stack.
    pub stack: usize,
    /// A piece lies in front of the ejecting cylinder.
    pub in_front: bool,
    /// A piece waits at the pick-up point.
    pub at_pickup: bool,
    /// Ejecting cylinder: 0 = retracted, [`PUSH_STROKE`] = extended.
    pub pusher: u8,
    /// Arm: 0 = at the magazine, [`ARM_STROKE`] = at the client.
    pub arm: u8,
    /// Suction switched on.
    pub suction: bool,
    /// The cup holds a piece.
    pub held: bool,
    /// Pieces dropped at the client.
    pub delivered: usize,
    /// Pieces dropped anywhere else.
    pub lost: usize,
    /// HMI inputs as the operator sets them: `start` pressed,
    pub start: bool,
    /// `stop` pressed,
    pub stop: bool,
    /// the mode switch on automatic,
    pub auto_man: bool,
    /// `emergency` pressed.
    pub emergency: bool,
}

impl Default for Station {
    fn default() -> Self {
        Station::new()
    }
}

impl Station {
    /// Empty magazine, cylinder extended, arm at the magazine, manual mode, nothing pressed.
    pub fn new() -> Station {
        Station {
            stack: 0,
            in_front: false,
            at_pickup: false,
            pusher: PUSH_STROKE,
            arm: 0,
            suction: false,
            held: false,
            delivered: 0,
            lost: 0,
            start: false,
            stop: false,
            auto_man: false,
            emergency: false,
        }
    }

    /// Controller inputs in [`INPUTS`] order.
    pub fn sensors(&self) -> Vec<bool> {
        vec![
            self.stack == 0,
            self.pusher == 0,
            self.pusher == PUSH_STROKE,
            self.arm == 0,
            self.arm == ARM_STROKE,
            self.held,
            self.start,
            self.stop,
            self.auto_man,
            self.emergency,
        ]
    }

    /// One scan period under the commands `z` ([`OUTPUTS`] order).
    pub fn tick(&mut self, z: &[bool]) {
        if z[RETRACT] {
            self.pusher = self.pusher.saturating_sub(1);
        } else if self.pusher < PUSH_STROKE {
            self.pusher += 1;
            if self.pusher == PUSH_STROKE && self.in_front {
                self.in_front = false;
                self.at_pickup = true;
            }
        }
        if self.pusher == 0 && !self.in_front && !self.at_pickup && self.stack > 0 {
            self.stack -= 1;
            self.in_front = true;
        }
        match (z[TO_CLIENT], z[TO_MAGAZINE]) {
            (true, false) if self.arm < ARM_STROKE => self.arm += 1,
            (false, true) if self.arm > 0 => self.arm -= 1,
            _ => {}
        }
        match (z[VACUUM_ON], z[VACUUM_OFF]) {
            (true, false) => self.suction = true,
            (false, true) => self.suction = false,
            _ => {}
        }
        if self.suction && !self.held && self.arm == 0 && self.at_pickup {
            self.held = true;
            self.at_pickup = false;
        }
        if !self.suction && self.held {
            self.held = false;
            if self.arm == ARM_STROKE {
                self.delivered += 1;
            } else {
                self.lost += 1;
            }
        }
    }
}

/// One operator action of a use case; each happens once the station has settled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Put pieces into the magazine.
    Load(usize),
    /// Press and release a button (`start`, `stop` or `emergency`).
    Press(Button),
    /// Turn the mode switch (true = automatic).
    Auto(bool),
}

/// An HMI button.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Button {
    /// `start`.
    Start,
    /// `stop`, which also acknowledges an emergency.
    Stop,
    /// `emergency`.
    Emergency,
}

/// A recorded run: a name and the operator's actions in order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UseCase {
    /// The run's name.
    pub name: &'static str,
    /// The operator's actions, in order.
    pub actions: Vec<Action>,
}

/// The six use cases of the shipped logs: 1 to 8 work pieces, both modes, stop, emergency.
pub fn use_cases() -> Vec<UseCase> {
    use Action::*;
    use Button::*;
    vec![
        UseCase {
            name: "one_piece",
            actions: vec![Load(1), Auto(true), Press(Start), Press(Stop)],
        },
        UseCase {
            name: "two_pieces",
            actions: vec![Auto(true), Load(2), Press(Start), Press(Stop)],
        },
        UseCase {
            name: "manual_then_auto",
            actions: vec![
                Load(3),
                Press(Start),
                Press(Emergency),
                Press(Stop),
                Press(Start),
                Auto(true),
                Press(Stop),
            ],
        },
        UseCase {
            name: "emergency_and_reset",
            actions: vec![
                Auto(true),
                Load(4),
                Press(Emergency),
                Press(Stop),
                Press(Start),
                Press(Stop),
            ],
        },
        UseCase {
            name: "load_while_ready",
            actions: vec![Auto(true), Press(Start), Load(5), Press(Stop)],
        },
        UseCase {
            name: "eight_pieces",
            actions: vec![
                Auto(true),
                Load(8),
                Press(Start),
                Press(Emergency),
                Press(Stop),
            ],
        },
    ]
}

/// Held-out runs, never given to synthesis: to compare a synthesized machine with the
/// reference on behaviour it was not shown.
pub fn held_out_cases() -> Vec<UseCase> {
    use Action::*;
    use Button::*;
    vec![
        UseCase {
            name: "six_pieces",
            actions: vec![Auto(true), Load(6), Press(Start), Press(Stop)],
        },
        UseCase {
            name: "manual_emergency",
            actions: vec![
                Load(2),
                Press(Start),
                Press(Emergency),
                Press(Stop),
                Auto(true),
                Press(Start),
                Press(Stop),
            ],
        },
        UseCase {
            name: "restock",
            actions: vec![
                Auto(true),
                Load(1),
                Press(Start),
                Load(3),
                Press(Stop),
                Press(Start),
                Load(2),
                Press(Stop),
            ],
        },
    ]
}

/// Runs `ecc` (over [`INPUTS`] / [`OUTPUTS`]) on the station through `case`'s actions and
/// returns one sample per scan and the station at the end; `None` if the run does not settle
/// within [`MAX_SCANS`].
pub fn simulate(ecc: &Ecc, case: &UseCase) -> Option<(Vec<Sample>, Station)> {
    simulate_within(ecc, case, MAX_SCANS)
}

/// [`simulate`] with another bound on the scans.
fn simulate_within(ecc: &Ecc, case: &UseCase, max_scans: usize) -> Option<(Vec<Sample>, Station)> {
    let mut quiet = 0;
    let mut actions = case.actions.iter();
    // Pending button: which one and scans left to hold it.
    let mut pressing: Option<(Button, usize)> = None;
    let mut settled = false;
    let drive = |k: usize, station: &mut Station, scans: &[Scanned<Station>]| {
        if let Some(last) = scans.last() {
            if last.fired.is_some() {
                quiet = 0;
            } else {
                quiet += 1;
            }
        }
        if k == max_scans {
            return Drive::Stop;
        }
        if let Some((b, left)) = pressing {
            set_button(station, b, left > 0);
            pressing = (left > 0).then(|| (b, left - 1));
        } else if quiet >= SETTLE {
            match actions.next() {
                None => {
                    settled = true;
                    return Drive::Stop;
                }
                Some(Action::Load(n)) => station.stack += n,
                Some(Action::Auto(a)) => station.auto_man = *a,
                Some(Action::Press(b)) => pressing = Some((*b, PRESS)),
            }
            quiet = 0;
            if let Some((b, left)) = pressing {
                set_button(station, b, true);
                pressing = Some((b, left - 1));
            }
        }
        Drive::Scan
    };
    let (scans, station) = closed_loop(ecc, Station::new(), max_scans, drive);
    settled.then(|| {
        let samples = scans
            .into_iter()
            .map(|s| Sample {
                inputs: s.inputs,
                outputs: s.outputs,
            })
            .collect();
        (samples, station)
    })
}

impl Simulated for Station {
    fn read(&self) -> Vec<bool> {
        self.sensors()
    }
    fn scan(&mut self, z: &[bool]) {
        self.tick(z)
    }
}

fn set_button(s: &mut Station, b: Button, down: bool) {
    match b {
        Button::Start => s.start = down,
        Button::Stop => s.stop = down,
        Button::Emergency => s.emergency = down,
    }
}

/// The reference controller's log of one use case.
pub fn record(case: &UseCase) -> Vec<Sample> {
    simulate(&reference(), case)
        .unwrap_or_else(|| panic!("use case {} does not settle", case.name))
        .0
}

/// Moves output changes one sample early, as an unsynchronized data collector records them:
/// at every scan `k` whose outputs changed while the outputs of scan `k-1` did not, with
/// probability `rate`, sample `k-1` gets the outputs of sample `k`. Returns the noisy samples
/// and the number of errors injected. Seeded, so reproducible.
///
/// Only errors of the SAT reconstruction paper's error model are injected: a skew is skipped
/// where the samples before `k-1` with the same inputs start with a transition (e.g. `start`
/// pressed, then released):
/// preprocessing would drop that transition together with the skewed sample, an error no
/// alternative edge can undo.
pub fn inject_skew(samples: &[Sample], rate: f64, seed: u64) -> (Vec<Sample>, usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = samples.to_vec();
    let mut injected = 0;
    for k in 2..samples.len() {
        let changed = samples[k].outputs != samples[k - 1].outputs;
        let quiet_before = samples[k - 1].outputs == samples[k - 2].outputs;
        let mut j = k - 1;
        while j > 0 && samples[j - 1].inputs == samples[k - 1].inputs {
            j -= 1;
        }
        let hides_transition = j > 0 && samples[j].outputs != samples[j - 1].outputs;
        if changed && quiet_before && !hides_transition && rng.gen_bool(rate.clamp(0.0, 1.0)) {
            out[k - 1].outputs = samples[k].outputs.clone();
            injected += 1;
        }
    }
    (out, injected)
}

/// Writes logs as CSV: `time` (scan number), `scenario` (1-based log index), then `in:` and
/// `out:` columns in interface order.
pub fn write_csv(logs: &[Vec<Sample>], w: &mut impl Write) -> std::io::Result<()> {
    let mut header = vec!["time".to_string(), "scenario".to_string()];
    header.extend(INPUTS.iter().map(|n| format!("in:{n}")));
    header.extend(OUTPUTS.iter().map(|n| format!("out:{n}")));
    writeln!(w, "{}", header.join(","))?;
    let bit = |b: &bool| if *b { "1" } else { "0" };
    for (k, log) in logs.iter().enumerate() {
        for (t, s) in log.iter().enumerate() {
            let cells: Vec<&str> = s.inputs.iter().chain(&s.outputs).map(bit).collect();
            writeln!(w, "{t},{},{}", k + 1, cells.join(","))?;
        }
    }
    Ok(())
}

/// Logs as scenarios, by the same preprocessing as a CSV log read from a file.
pub fn to_scenarios(logs: &[Vec<Sample>], file: &str) -> ScenarioSet {
    let initial = vec![false; OUTPUTS.len()];
    let mut line = 2;
    let scenarios = logs
        .iter()
        .map(|log| {
            let sc = Scenario {
                origin: Origin {
                    file: PathBuf::from(file),
                    line,
                    rows: None,
                },
                steps: csvlog::samples_to_steps(log, &initial),
            };
            line += log.len();
            sc
        })
        .collect();
    ScenarioSet {
        inputs: input_names(),
        outputs: output_names(),
        initial_outputs: initial,
        scenarios,
    }
}

/// The shipped data: clean logs of [`use_cases`], the same with skew at `rate` (seeded), and
/// clean logs of [`held_out_cases`]; plus the number of errors injected.
pub struct Logs {
    /// The clean logs of the use cases.
    pub clean: Vec<Vec<Sample>>,
    /// The same with skew injected.
    pub noisy: Vec<Vec<Sample>>,
    /// The clean logs of the held-out runs.
    pub held_out: Vec<Vec<Sample>>,
    /// Errors injected into `noisy`.
    pub injected: usize,
}

/// Records every use case and injects skew into a copy (one seed per log, derived from
/// `seed`).
pub fn generate(rate: f64, seed: u64) -> Logs {
    let clean: Vec<Vec<Sample>> = use_cases().iter().map(record).collect();
    let mut injected = 0;
    let noisy = clean
        .iter()
        .enumerate()
        .map(|(k, log)| {
            let (n, i) = inject_skew(log, rate, seed.wrapping_add(k as u64));
            injected += i;
            n
        })
        .collect();
    Logs {
        clean,
        noisy,
        held_out: held_out_cases().iter().map(record).collect(),
        injected,
    }
}

/// Logs for benchmarks: random use cases (seeded; each 1 to 3 rounds of loading 1 to 8 pieces,
/// start, sometimes an emergency, stop) until they hold `samples` samples in all; the last log
/// is cut to make the total exact.
pub fn random_logs(samples: usize, seed: u64) -> Vec<Vec<Sample>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut logs = Vec::new();
    let mut total = 0;
    while total < samples {
        let mut actions = vec![Action::Auto(true)];
        for _ in 0..rng.gen_range(1..=3) {
            actions.push(Action::Load(rng.gen_range(1..=8)));
            actions.push(Action::Press(Button::Start));
            if rng.gen_bool(0.3) {
                actions.push(Action::Press(Button::Emergency));
            }
            actions.push(Action::Press(Button::Stop));
        }
        let mut log = record(&UseCase {
            name: "random",
            actions,
        });
        log.truncate(samples - total);
        total += log.len();
        logs.push(log);
    }
    logs
}

/// One long run for benchmarks: the station left in automatic mode for shift after shift
/// (seeded rounds of loading 1 to 8 pieces, start, sometimes an emergency, stop), recorded by
/// the reference controller until the run holds at least `steps` steps after the usual
/// preprocessing; the scenario is then cut to exactly `steps` (a prefix of a real run).
pub fn long_run(steps: usize, seed: u64) -> ScenarioSet {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut actions = vec![Action::Auto(true)];
    loop {
        for _ in 0..(actions.len() / 2).max(8) {
            actions.push(Action::Load(rng.gen_range(1..=8)));
            actions.push(Action::Press(Button::Start));
            if rng.gen_bool(0.3) {
                actions.push(Action::Press(Button::Emergency));
            }
            actions.push(Action::Press(Button::Stop));
        }
        let case = UseCase {
            name: "long run",
            actions: actions.clone(),
        };
        // Far more scans than one use case takes; the rounds, not the bound, end the run.
        let (log, _) = simulate_within(&reference(), &case, usize::MAX)
            .expect("the reference controller settles after every action");
        let mut set = to_scenarios(&[log], "<long run>");
        if set.step_count() >= steps {
            set.scenarios[0].steps.truncate(steps);
            return set;
        }
    }
}

/// Writes [`CLEAN_FILE`], [`NOISY_FILE`] (rate [`SHIPPED_RATE`], seed [`SHIPPED_SEED`]),
/// [`HELDOUT_FILE`] and [`REFERENCE_FILE`] into `dir`; returns the paths and the number of
/// errors injected.
pub fn write_files(dir: &Path) -> Result<(Vec<PathBuf>, usize), WriteError> {
    let logs = generate(SHIPPED_RATE, SHIPPED_SEED);
    let mut written = Vec::new();
    for (name, data) in [
        (CLEAN_FILE, &logs.clean),
        (NOISY_FILE, &logs.noisy),
        (HELDOUT_FILE, &logs.held_out),
    ] {
        let mut bytes = Vec::new();
        write_csv(data, &mut bytes).expect("writing into memory cannot fail");
        let path = dir.join(name);
        write_atomic(&path, &bytes)?;
        written.push(path);
    }
    let path = dir.join(REFERENCE_FILE);
    write_atomic(
        &path,
        crate::export::json::to_string(&reference()).as_bytes(),
    )?;
    written.push(path);
    Ok((written, logs.injected))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_is_valid_and_every_use_case_delivers_every_piece() {
        let ecc = reference();
        ecc.validate().unwrap();
        for case in use_cases().iter().chain(&held_out_cases()) {
            let pieces: usize = case
                .actions
                .iter()
                .map(|a| if let Action::Load(n) = a { *n } else { 0 })
                .sum();
            let (_, st) = simulate(&ecc, case).unwrap();
            // The emergency cases stop in Ready between pieces, so all are delivered.
            assert_eq!(st.lost, 0, "{}", case.name);
            assert_eq!(st.delivered + st.stack, pieces, "{}", case.name);
        }
    }

    /// The log loses nothing: the steps a CSV log yields replay on the reference, and the
    /// reference never fires twice in a row on one input vector.
    #[test]
    fn clean_logs_replay_on_the_reference() {
        let logs = generate(0.0, 1);
        assert_eq!(logs.injected, 0);
        let set = to_scenarios(&logs.clean, "x.csv");
        assert_eq!(set.check(&reference()), Ok(()));
        let held = to_scenarios(&logs.held_out, "y.csv");
        assert_eq!(held.check(&reference()), Ok(()));
    }

    /// Every injected error can be undone by alternative edges: choosing, at each place
    /// where the reference departs from the noisy steps, the alternative there makes the
    /// reference replay everything.
    #[test]
    fn injected_errors_are_within_the_error_model() {
        let mut total = 0;
        for (k, clean) in random_logs(3000, 1).iter().enumerate() {
            let (noisy, injected) = inject_skew(clean, 0.05, k as u64);
            total += injected;
            let set = to_scenarios(&[noisy], "n.csv");
            let g = crate::scenario::trace_graph::TraceGraph::build(&set);
            let mut used = vec![false; g.alternatives.len()];
            loop {
                let fixed = g.corrected(&set, &used);
                let Some(d) = fixed.divergences(&reference()).first().cloned() else {
                    break;
                };
                let a = g.chains[0].nodes[d.step]
                    .and_then(|n| g.alternative_of.get(&n).copied())
                    .filter(|&a| !used[a])
                    .unwrap_or_else(|| panic!("no alternative undoes {}", d.describe_step()));
                used[a] = true;
            }
            assert!(used.iter().filter(|&&u| u).count() <= injected);
        }
        assert!(total > 0);
    }

    #[test]
    fn skew_moves_an_output_change_one_sample_early() {
        let log = record(&use_cases()[0]);
        let (noisy, n) = inject_skew(&log, 1.0, 7);
        assert!(n > 0);
        let diffs: Vec<usize> = (0..log.len()).filter(|&k| log[k] != noisy[k]).collect();
        assert_eq!(diffs.len(), n);
        for k in diffs {
            assert_eq!(noisy[k].outputs, log[k + 1].outputs);
            assert_eq!(noisy[k].inputs, log[k].inputs);
        }
        assert_eq!(inject_skew(&log, 0.5, 3), inject_skew(&log, 0.5, 3));
    }
}
