//! The Pick-and-Place manipulator (PnP) of the metaheuristic and verification-in-the-loop
//! papers: plant simulation, reference controller and the generator of its execution scenarios.
//!
//! In: a work-piece order such as `1-2-3`. Out: the scans of the reference controller (a
//! hand-made "legacy PLC" program, [`reference()`]) running on a simulated plant, as scenario
//! [`Step`]s; for the ten test cases of the metaheuristic paper ([`SEED_ORDERS`]) a
//! [`ScenarioSet`] ([`generate`]) and the files `pnp.traces`, `pnp.inputs`, `pnp.outputs`
//! ([`write_files`]).
//!
//! # Geometry
//! Seen from the front, left to right: input track 1, track 2, track 3 and the output slider V,
//! one pitch apart. Horizontal cylinder II (stroke: two pitches) is fixed to the frame and carries
//! horizontal cylinder I (stroke: one pitch), which carries the vertical cylinder III with the
//! suction unit IV. The hand is thus over pitch `c1 + 2*c2` (1 = extended):
//!
//! | cylinder I | cylinder II | hand over            |
//! |------------|-------------|----------------------|
//! | retracted  | retracted   | track 1 (home)       |
//! | extended   | retracted   | track 2              |
//! | retracted  | extended    | track 3              |
//! | extended   | extended    | output slider V      |
//!
//! `cNHome`/`cNEnd` are true only with the cylinder fully retracted/extended; while it travels
//! the hand is over no track. The vertical cylinder goes down while `vcExtend` is held and a
//! spring pulls it back up otherwise (`vcHome` = top, `vcEnd` = bottom).
//!
//! # Plant rules ([`PlantState::tick`])
//! - A horizontal cylinder moves one unit per scan towards the commanded end
//!   ([`H_STROKE`] units end to end); with both or neither of its commands it stays.
//! - `vacuum_on` / `vacuum_off` switch the suction unit and it stays so (pulse commands; both at
//!   once change nothing).
//! - With suction on, the cup at the bottom over a track holding a piece, and nothing held yet,
//!   the cup grips the piece: `vac` becomes true. The piece leaves its track (`ppN` becomes
//!   false) when the vertical cylinder first moves up while holding it.
//! - Suction off drops a held piece: over the output slider it is *delivered*, anywhere else it
//!   is *lost* (a gripped piece not lifted yet just stays on its track).
//!
//! # Timing
//! One scan = one `REQ`: the controller reads the sensors, fires at most one transition, and then
//! the plant moves for one scan period under the commands just written. A step is active iff a
//! transition fired; it records the outputs after it.
//!
//! # Work-piece orders
//! Groups of track numbers separated by `-`, e.g. `3-2-1`; the pieces of one group are placed at
//! the same scan (`123`: all three at once). The first group appears at scan
//! [`FIRST_ARRIVAL`] (after scans of an empty plant, so the data shows the controller ignoring
//! them); every later group appears [`NEXT_ARRIVAL`] scans after the last piece of the group
//! before it left its track, i.e. while the manipulator carries that piece to the slider. A run
//! ends when every piece is delivered and the machine is at rest (hand home and up, all commands
//! off), followed by a few idle scans.
//!
//! # What the case shows
//! The reference controller has 11 states. Its runs on the ten orders (`1`, `1-2`, `1-2-3`,
//! `2`, `2-1`, `2-3`, `3`, `3-2`, `3-2-1`, `123`) are `specs/pnp.traces`, 566 steps; `synth-dev
//! generate pnp` writes them again. From them the main job finds an 8-state, 13-transition
//! controller that NuSMV verifies against all 8 properties of `specs/pnp.ltl` with
//! `smv/pnp_surrogate.smv`.
//!
//! Scenarios alone are not enough, as the verification-in-the-loop paper reports: the minimal
//! machine synthesized from the scenarios only reproduces them all, yet violates
//! `G (pp1 -> F vp1)`:
//!
//! ```text
//! synth infer --traces specs/pnp.traces --out out/scenarios-only
//! synth verify --ecc out/scenarios-only/SynthesizedFB.json --ltl specs/pnp.ltl --plant smv/pnp_surrogate.smv
//! # VIOLATED track1_served (line 10): G (pp1 -> F vp1)
//! # VIOLATED held_until_placed, track3_served; the other five hold; exit code 1
//! ```

pub use super::reference::pnp::{input_names, output_names, reference, INPUTS, OUTPUTS};
use super::{closed_loop, Drive, Scanned, Simulated};
use crate::ecc::Ecc;
use crate::files::{write_atomic, WriteError};
use crate::scenario::{fbsat, Origin, Scenario, ScenarioSet, Step};
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

// Output indices, for the plant and the safety checks.
const C1_EXTEND: usize = 0;
const C1_RETRACT: usize = 1;
const C2_EXTEND: usize = 2;
const C2_RETRACT: usize = 3;
const VC_EXTEND: usize = 4;
const VACUUM_ON: usize = 5;
const VACUUM_OFF: usize = 6;

/// The ten test cases of the metaheuristic paper, in its order.
pub const SEED_ORDERS: [&str; 10] = [
    "1", "1-2", "1-2-3", "2", "2-1", "2-3", "3", "3-2", "3-2-1", "123",
];

/// Scans a horizontal cylinder needs from one end to the other.
pub const H_STROKE: u8 = 4;
/// Scans the vertical cylinder needs from top to bottom (and back).
pub const V_STROKE: u8 = 3;
/// 0-based scan at which the first group of pieces appears.
pub const FIRST_ARRIVAL: usize = 2;
/// Scans between the last piece of a group leaving its track and the next group appearing.
pub const NEXT_ARRIVAL: usize = 5;
/// Idle scans [`generate`] records after the machine is at rest again.
pub const IDLE_AFTER: usize = 3;
/// A run that is not at rest after this many scans is cut off.
pub const MAX_SCANS: usize = 2_000;

/// File names [`write_files`] writes, in its order: the scenarios,
pub const TRACES_FILE: &str = "pnp.traces";
/// the input names,
pub const INPUTS_FILE: &str = "pnp.inputs";
/// the output names.
pub const OUTPUTS_FILE: &str = "pnp.outputs";

/// An error in a work-piece order, or a run that did not finish.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PnpError {
    /// The order cannot be read.
    #[error("work-piece order '{order}': {message}")]
    Order {
        /// The order as written.
        order: String,
        /// What is wrong with it.
        message: String,
    },
    /// The run did not come to rest within [`MAX_SCANS`].
    #[error("work-piece order '{order}': the machine is not at rest after {scans} scans")]
    Unfinished {
        /// The order as written.
        order: String,
        /// Scans run.
        scans: usize,
    },
}

/// An input track, 0-based inside (track `1` of the papers is `Track(0)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Track(pub usize);

impl fmt::Display for Track {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0 + 1)
    }
}

/// Groups of pieces in the order they are placed; see the module doc.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WorkOrder {
    /// The order as written.
    pub text: String,
    /// The groups of pieces, each placed at one scan.
    pub groups: Vec<Vec<Track>>,
}

impl FromStr for WorkOrder {
    type Err = PnpError;

    fn from_str(s: &str) -> Result<WorkOrder, PnpError> {
        let text = s.trim().to_string();
        let err = |message: String| PnpError::Order {
            order: text.clone(),
            message,
        };
        let mut groups = Vec::new();
        for (g, part) in text.split('-').enumerate() {
            if part.is_empty() {
                return Err(err(format!("group {} is empty", g + 1)));
            }
            let mut group = Vec::new();
            for c in part.chars() {
                let track = match c {
                    '1'..='3' => Track(c as usize - '1' as usize),
                    _ => return Err(err(format!("'{c}' is not a track (1, 2 or 3)"))),
                };
                if group.contains(&track) {
                    return Err(err(format!("track {track} twice in group {}", g + 1)));
                }
                group.push(track);
            }
            groups.push(group);
        }
        Ok(WorkOrder { text, groups })
    }
}

/// Where the hand is horizontally.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Over {
    /// Over an input track.
    Track(Track),
    /// Over the output slider.
    Slider,
    /// A horizontal cylinder is between its ends.
    Between,
}

/// A piece in the suction cup.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Held {
    /// The track the piece was gripped on.
    pub track: Track,
    /// Whether it has left its track yet.
    pub lifted: bool,
}

/// The plant at one scan. Cylinder positions count scans of travel from the retracted (or top)
/// end: `0..=H_STROKE` horizontally, `0..=V_STROKE` vertically (`V_STROKE` = bottom).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlantState {
    /// Horizontal cylinder I.
    pub c1: u8,
    /// Horizontal cylinder II.
    pub c2: u8,
    /// The vertical cylinder.
    pub vc: u8,
    /// Suction switched on.
    pub suction: bool,
    /// The piece in the cup, if any.
    pub held: Option<Held>,
    /// A piece lies on track `i`.
    pub on_track: [bool; 3],
    /// Tracks of the pieces that reached the output slider, in delivery order.
    pub delivered: Vec<Track>,
    /// Tracks of the pieces dropped anywhere but on the output slider.
    pub lost: Vec<Track>,
}

impl Default for PlantState {
    fn default() -> Self {
        PlantState::new()
    }
}

impl PlantState {
    /// Everything retracted and up, suction off, no pieces.
    pub fn new() -> PlantState {
        PlantState {
            c1: 0,
            c2: 0,
            vc: 0,
            suction: false,
            held: None,
            on_track: [false; 3],
            delivered: Vec::new(),
            lost: Vec::new(),
        }
    }

    /// Where the hand is horizontally (see the geometry table of the module doc).
    pub fn over(&self) -> Over {
        let end = |p: u8| match p {
            0 => Some(0),
            H_STROKE => Some(1),
            _ => None,
        };
        match (end(self.c1), end(self.c2)) {
            (Some(1), Some(1)) => Over::Slider,
            (Some(a), Some(b)) => Over::Track(Track(a + 2 * b)),
            _ => Over::Between,
        }
    }

    /// Sensor values in [`INPUTS`] order.
    pub fn sensors(&self) -> Vec<bool> {
        vec![
            self.c1 == 0,
            self.c1 == H_STROKE,
            self.c2 == 0,
            self.c2 == H_STROKE,
            self.vc == 0,
            self.vc == V_STROKE,
            self.on_track[0],
            self.on_track[1],
            self.on_track[2],
            self.held.is_some(),
        ]
    }

    /// Hand home and up, suction off, nothing held.
    pub fn at_rest(&self) -> bool {
        self.c1 == 0 && self.c2 == 0 && self.vc == 0 && !self.suction && self.held.is_none()
    }

    /// One scan period under the commands `z` (in [`OUTPUTS`] order).
    pub fn tick(&mut self, z: &[bool]) {
        match (z[VACUUM_ON], z[VACUUM_OFF]) {
            (true, false) => self.suction = true,
            (false, true) => self.suction = false,
            _ => {}
        }
        if !self.suction {
            if let Some(h) = self.held.take() {
                if h.lifted {
                    match self.over() {
                        Over::Slider => self.delivered.push(h.track),
                        _ => self.lost.push(h.track),
                    }
                }
            }
        }
        if self.suction && self.held.is_none() && self.vc == V_STROKE {
            if let Over::Track(t) = self.over() {
                if self.on_track[t.0] {
                    self.held = Some(Held {
                        track: t,
                        lifted: false,
                    });
                }
            }
        }
        let horizontal = |pos: u8, extend: bool, retract: bool| match (extend, retract) {
            (true, false) => (pos + 1).min(H_STROKE),
            (false, true) => pos.saturating_sub(1),
            _ => pos,
        };
        self.c1 = horizontal(self.c1, z[C1_EXTEND], z[C1_RETRACT]);
        self.c2 = horizontal(self.c2, z[C2_EXTEND], z[C2_RETRACT]);
        self.vc = if z[VC_EXTEND] {
            (self.vc + 1).min(V_STROKE)
        } else {
            self.vc.saturating_sub(1)
        };
        if let Some(h) = &mut self.held {
            if !h.lifted && self.vc < V_STROKE {
                h.lifted = true;
                self.on_track[h.track.0] = false;
            }
        }
    }
}

/// One scan of a simulated run.
pub type ScanRecord = Scanned<PlantState>;

impl Simulated for PlantState {
    fn read(&self) -> Vec<bool> {
        self.sensors()
    }
    fn scan(&mut self, z: &[bool]) {
        self.tick(z)
    }
}

/// A simulated run of a controller on the plant.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// Every scan of the run.
    pub scans: Vec<ScanRecord>,
    /// The plant after the last scan.
    pub last: PlantState,
    /// Every piece delivered and the machine at rest with all commands off.
    pub finished: bool,
}

impl Recording {
    /// The scans as scenario steps.
    pub fn steps(&self) -> Vec<Step> {
        self.scans
            .iter()
            .map(|s| Step {
                inputs: s.inputs.clone(),
                outputs: s.fired.map(|_| s.outputs.clone()),
            })
            .collect()
    }
}

/// Runs `ecc` (over [`INPUTS`] / [`OUTPUTS`]) on the plant for `order`, until every piece is
/// delivered and the machine is at rest, then `extra_steps` more scans; cut off after
/// [`MAX_SCANS`] scans (then `finished` is false).
pub fn simulate(ecc: &Ecc, order: &WorkOrder, extra_steps: usize) -> Recording {
    let pieces: usize = order.groups.iter().map(Vec::len).sum();
    let mut next_group = 0;
    let mut next_arrival = FIRST_ARRIVAL;
    let mut rest_since = None;
    let drive = |scan: usize, plant: &mut PlantState, scans: &[ScanRecord]| {
        if let Some(last) = scans.last() {
            let done = next_group == order.groups.len()
                && plant.delivered.len() == pieces
                && plant.at_rest()
                && last.outputs.iter().all(|z| !z);
            let previous = scan - 1;
            if !done {
                rest_since = None;
            } else if previous - *rest_since.get_or_insert(previous) >= extra_steps {
                return Drive::Stop;
            }
        }
        if next_group < order.groups.len() && scan == next_arrival {
            for t in &order.groups[next_group] {
                plant.on_track[t.0] = true;
            }
            next_group += 1;
            // Set again, and pushed on, every scan until the group has left its tracks.
            next_arrival = usize::MAX;
        }
        if next_group > 0 && next_arrival == usize::MAX {
            let placed = &order.groups[next_group - 1];
            // A gripped piece stays on its track until lifted, so `on_track` says it all.
            if placed.iter().all(|t| !plant.on_track[t.0]) {
                next_arrival = scan + NEXT_ARRIVAL;
            }
        }
        Drive::Scan
    };
    let (scans, plant) = closed_loop(ecc, PlantState::new(), MAX_SCANS, drive);
    Recording {
        finished: rest_since.is_some(),
        last: plant,
        scans,
    }
}

/// Runs the reference controller for `order` (see the module doc) and returns one step per scan.
pub fn record(order: &str, extra_steps: usize) -> Result<Vec<Step>, PnpError> {
    let order: WorkOrder = order.parse()?;
    let rec = simulate(&reference(), &order, extra_steps);
    if !rec.finished {
        return Err(PnpError::Unfinished {
            order: order.text,
            scans: rec.scans.len(),
        });
    }
    Ok(rec.steps())
}

/// One scenario per test case of [`SEED_ORDERS`], each followed by [`IDLE_AFTER`] idle scans.
/// Origins name [`TRACES_FILE`] and the line the scenario has in it.
pub fn generate() -> ScenarioSet {
    let scenarios = SEED_ORDERS
        .iter()
        .enumerate()
        .map(|(k, order)| Scenario {
            origin: Origin {
                file: PathBuf::from(TRACES_FILE),
                line: k + 2,
                rows: None,
            },
            steps: record(order, IDLE_AFTER)
                .unwrap_or_else(|e| panic!("the reference controller fails a seed order: {e}")),
        })
        .collect();
    ScenarioSet {
        inputs: input_names(),
        outputs: output_names(),
        initial_outputs: vec![false; OUTPUTS.len()],
        scenarios,
    }
}

/// Writes [`TRACES_FILE`], [`INPUTS_FILE`] and [`OUTPUTS_FILE`] into `dir` (created if
/// missing), each atomically, and returns their paths.
pub fn write_files(dir: &Path) -> Result<Vec<PathBuf>, WriteError> {
    let mut traces = Vec::new();
    fbsat::write(&generate(), &mut traces).expect("writing into memory cannot fail");
    let names = |names: &[&str]| names.iter().map(|n| format!("{n}\n")).collect::<String>();
    let files = [
        (TRACES_FILE, traces),
        (INPUTS_FILE, names(&INPUTS).into_bytes()),
        (OUTPUTS_FILE, names(&OUTPUTS).into_bytes()),
    ];
    let mut written = Vec::new();
    for (name, bytes) in files {
        let path = dir.join(name);
        write_atomic(&path, &bytes)?;
        written.push(path);
    }
    Ok(written)
}

/// A breach of the safety rules of the manipulator found in a simulated run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Hazard {
    /// Extend and retract of one horizontal cylinder commanded together (`cylinder` 1 or 2).
    ExtendAndRetract {
        /// 0-based scan.
        scan: usize,
        /// 1 or 2.
        cylinder: u8,
    },
    /// `vacuum_on` and `vacuum_off` together.
    VacuumOnAndOff {
        /// 0-based scan.
        scan: usize,
    },
    /// A horizontal command while the vertical cylinder is not up or is commanded down.
    HorizontalWhileDown {
        /// 0-based scan.
        scan: usize,
    },
    /// A piece dropped anywhere but on the output slider.
    PieceLost {
        /// The track the piece came from.
        track: Track,
    },
}

impl fmt::Display for Hazard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Hazard::ExtendAndRetract { scan, cylinder } => write!(
                f,
                "scan {scan}: cylinder {cylinder} commanded to extend and retract at once"
            ),
            Hazard::VacuumOnAndOff { scan } => {
                write!(f, "scan {scan}: vacuum_on and vacuum_off at once")
            }
            Hazard::HorizontalWhileDown { scan } => write!(
                f,
                "scan {scan}: horizontal move commanded while the vertical cylinder is not up"
            ),
            Hazard::PieceLost { track } => {
                write!(f, "the piece from track {track} was dropped off the slider")
            }
        }
    }
}

/// Every hazard of a run, scan by scan, then the lost pieces. A horizontal command is judged
/// against the vertical cylinder during the scan period it acts in: up at the start of the
/// period and not commanded down.
pub fn hazards(rec: &Recording) -> Vec<Hazard> {
    let mut found = Vec::new();
    for (k, s) in rec.scans.iter().enumerate() {
        let z = &s.outputs;
        let scan = k + 1;
        if z[C1_EXTEND] && z[C1_RETRACT] {
            found.push(Hazard::ExtendAndRetract { scan, cylinder: 1 });
        }
        if z[C2_EXTEND] && z[C2_RETRACT] {
            found.push(Hazard::ExtendAndRetract { scan, cylinder: 2 });
        }
        if z[VACUUM_ON] && z[VACUUM_OFF] {
            found.push(Hazard::VacuumOnAndOff { scan });
        }
        let horizontal = z[C1_EXTEND] || z[C1_RETRACT] || z[C2_EXTEND] || z[C2_RETRACT];
        if horizontal && (s.plant.vc != 0 || z[VC_EXTEND]) {
            found.push(Hazard::HorizontalWhileDown { scan });
        }
    }
    found.extend(
        rec.last
            .lost
            .iter()
            .map(|&track| Hazard::PieceLost { track }),
    );
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::{Algorithm, Tri};
    use crate::scenario::tree::ScenarioTree;

    fn orders() -> Vec<WorkOrder> {
        SEED_ORDERS.iter().map(|o| o.parse().unwrap()).collect()
    }

    #[test]
    fn reference_is_valid_and_small() {
        let e = reference();
        e.validate().unwrap();
        let size = e.size();
        assert_eq!((size.c, size.t), (11, 13));
        let names = input_names();
        let idle: Vec<String> = e.states[0]
            .transitions
            .iter()
            .map(|t| t.guard.display(&names).to_string())
            .collect();
        assert_eq!(idle, ["pp1", "pp2", "pp3"]);
        assert_eq!(
            e.states[8].transitions[0].guard.display(&names).to_string(),
            "!vac"
        );
    }

    #[test]
    fn orders_parse_and_bad_ones_are_refused() {
        let o: WorkOrder = "3-21".parse().unwrap();
        assert_eq!(o.groups, vec![vec![Track(2)], vec![Track(1), Track(0)]]);
        let bad = [
            ("1--2", "work-piece order '1--2': group 2 is empty"),
            ("", "work-piece order '': group 1 is empty"),
            (
                "1-4",
                "work-piece order '1-4': '4' is not a track (1, 2 or 3)",
            ),
            ("11", "work-piece order '11': track 1 twice in group 1"),
        ];
        for (text, msg) in bad {
            assert_eq!(text.parse::<WorkOrder>().unwrap_err().to_string(), msg);
        }
        assert!(record("x", 0).is_err());
    }

    #[test]
    fn plant_geometry_and_sensors() {
        let mut p = PlantState::new();
        assert_eq!(p.over(), Over::Track(Track(0)));
        p.c1 = H_STROKE;
        assert_eq!(p.over(), Over::Track(Track(1)));
        p.c2 = H_STROKE;
        assert_eq!(p.over(), Over::Slider);
        p.c1 = 0;
        assert_eq!(p.over(), Over::Track(Track(2)));
        p.c2 = 1;
        assert_eq!(p.over(), Over::Between);
        let s = p.sensors();
        assert_eq!(&s[..4], &[true, false, false, false]);
    }

    #[test]
    fn plant_picks_only_at_the_bottom_and_drops_where_it_is() {
        let mut z = vec![false; OUTPUTS.len()];
        let mut p = PlantState::new();
        p.on_track[0] = true;
        z[VACUUM_ON] = true;
        p.tick(&z);
        assert_eq!(p.held, None, "the cup is up: nothing to grip");
        z[VC_EXTEND] = true;
        for _ in 0..V_STROKE + 1 {
            p.tick(&z);
        }
        assert!(p.held.is_some() && p.on_track[0], "gripped, not lifted yet");
        z[VC_EXTEND] = false;
        p.tick(&z);
        assert!(!p.on_track[0] && p.sensors()[9], "lifted, vac on");
        z[VACUUM_ON] = false;
        z[VACUUM_OFF] = true;
        p.tick(&z);
        assert_eq!((p.lost.clone(), p.held), (vec![Track(0)], None));
    }

    #[test]
    fn every_piece_of_every_order_reaches_the_slider_safely() {
        let e = reference();
        for o in orders().iter().chain(&["1-1".parse().unwrap()]) {
            let rec = simulate(&e, o, IDLE_AFTER);
            assert!(rec.finished, "order {} did not finish", o.text);
            assert_eq!(hazards(&rec), vec![], "order {}", o.text);
            let mut want: Vec<Track> = o.groups.concat();
            let mut got = rec.last.delivered.clone();
            want.sort();
            got.sort();
            assert_eq!(got, want, "order {}", o.text);
            assert_eq!(rec.last.on_track, [false; 3]);
        }
    }

    #[test]
    fn pieces_are_served_in_the_order_they_appear() {
        let e = reference();
        for o in orders() {
            let rec = simulate(&e, &o, 0);
            // Within a group (only '123' has several) the priority 1 > 2 > 3 decides.
            let want: Vec<Track> = o
                .groups
                .iter()
                .flat_map(|g| {
                    let mut g = g.clone();
                    g.sort();
                    g
                })
                .collect();
            assert_eq!(rec.last.delivered, want, "order {}", o.text);
        }
    }

    #[test]
    fn hazards_are_detected() {
        // Return commands extend and retract of cylinder 1; Down keeps cylinder 1 moving.
        let mut e = reference();
        e.states[10].algorithm = Algorithm::Tri("1101000".chars().map(tri).collect());
        e.states[3].algorithm = Algorithm::Tri("1000100".chars().map(tri).collect());
        let rec = simulate(&e, &"2".parse().unwrap(), 0);
        let h = hazards(&rec);
        assert!(h
            .iter()
            .any(|h| matches!(h, Hazard::ExtendAndRetract { cylinder: 1, .. })));
        assert!(h
            .iter()
            .any(|h| matches!(h, Hazard::HorizontalWhileDown { .. })));
        // Suction off while leaving track 1 for the slider.
        let mut e = reference();
        e.states[6].algorithm = Algorithm::Tri("1010001".chars().map(tri).collect());
        let rec = simulate(&e, &"1".parse().unwrap(), 0);
        assert!(!rec.finished);
        assert_eq!(hazards(&rec), vec![Hazard::PieceLost { track: Track(0) }]);
    }

    fn tri(c: char) -> Tri {
        Tri::from_symbol(c).unwrap()
    }

    #[test]
    fn runs_start_with_idle_scans_and_end_with_them() {
        let steps = record("3", IDLE_AFTER).unwrap();
        assert!(steps[..FIRST_ARRIVAL].iter().all(|s| s.outputs.is_none()));
        assert!(steps[FIRST_ARRIVAL].outputs.is_some(), "Idle -> ToTrack3");
        let tail = &steps[steps.len() - IDLE_AFTER..];
        assert!(tail.iter().all(|s| s.outputs.is_none()));
        assert!(steps[steps.len() - IDLE_AFTER - 1].outputs.is_some());
    }

    #[test]
    fn generated_scenarios_replay_and_build_a_tree() {
        let set = generate();
        assert_eq!(set.scenarios.len(), SEED_ORDERS.len());
        set.check(&reference()).unwrap();
        let tree = ScenarioTree::build(&set).unwrap();
        // Every active step of the reference is one of its 13 transitions; the tree merges the
        // common prefixes of the ten runs.
        assert!(tree.active_edges() < set.active_count());
        assert!(tree.active_edges() >= reference().size().t);
    }

    #[test]
    fn generation_is_deterministic() {
        let mut a = Vec::new();
        let mut b = Vec::new();
        fbsat::write(&generate(), &mut a).unwrap();
        fbsat::write(&generate(), &mut b).unwrap();
        assert_eq!(a, b);
    }

    fn committed_specs() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("specs")
    }

    #[test]
    fn committed_files_match_the_generator() {
        let dir = tempfile::tempdir().unwrap();
        let written = write_files(dir.path()).unwrap();
        assert_eq!(written.len(), 3);
        for path in written {
            let name = path.file_name().unwrap();
            let committed = committed_specs().join(name);
            let want = std::fs::read(&committed)
                .unwrap_or_else(|e| panic!("{}: {e}", committed.display()));
            assert!(
                std::fs::read(&path).unwrap() == want,
                "{} differs from the generator: run \
                 `cargo test --lib cases::pnp -- --ignored regenerate` and commit the result",
                committed.display()
            );
        }
        // And the committed data reads back as the generated set.
        let traces = committed_specs().join(TRACES_FILE);
        let read = fbsat::read(&traces, Some(input_names()), Some(output_names())).unwrap();
        assert_eq!(read.step_count(), generate().step_count());
        read.check(&reference()).unwrap();
    }

    /// Names declared in `VAR` / `DEFINE` sections of the surrogate, and its module parameters.
    fn surrogate_names(text: &str) -> (Vec<String>, Vec<String>) {
        let mut params = Vec::new();
        let mut names = Vec::new();
        let mut section = "";
        for raw in text.lines() {
            let line = raw.split("--").next().unwrap().trim();
            if let Some(rest) = line.strip_prefix("MODULE plant(") {
                let inside = rest.strip_suffix(')').expect("one-line module header");
                params = inside.split(',').map(|p| p.trim().to_string()).collect();
            } else if ["VAR", "DEFINE", "ASSIGN"].contains(&line) {
                section = line;
            } else if section != "ASSIGN" && !line.is_empty() {
                names.push(line.split(':').next().unwrap().trim().to_string());
            }
        }
        (params, names)
    }

    #[test]
    fn surrogate_and_properties_follow_the_coupling_convention() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let smv = std::fs::read_to_string(root.join("smv/pnp_surrogate.smv")).unwrap();
        let (params, names) = surrogate_names(&smv);
        assert_eq!(params, output_names(), "the plant reads every command");
        for input in INPUTS {
            assert!(names.iter().any(|n| n == input), "{input} not declared");
        }
        for output in OUTPUTS {
            assert!(!names.iter().any(|n| n == output), "{output} redeclared");
        }
        let ltl = std::fs::read_to_string(root.join("specs/pnp.ltl")).unwrap();
        let mut labels = Vec::new();
        for raw in ltl.lines() {
            let line = raw.split("--").next().unwrap().trim();
            if line.is_empty() {
                continue;
            }
            let (label, formula) = line.split_once(':').expect("every property is labelled");
            labels.push(label.trim());
            let words = formula
                .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .filter(|w| !w.is_empty() && !["G", "F", "X", "U", "V"].contains(w));
            for w in words {
                assert!(
                    OUTPUTS.contains(&w) || names.iter().any(|n| n == w),
                    "{label}: '{w}' is neither a command nor a plant name"
                );
            }
        }
        assert_eq!(labels.len(), 8);
        let mut unique = labels.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), labels.len(), "labels are unique");
    }

    /// Writes the committed data files; run on purpose after changing the generator.
    #[test]
    #[ignore]
    fn regenerate_committed_files() {
        write_files(&committed_specs()).unwrap();
    }
}
