//! A surrogate plant learned from the recordings: what the sensors (the controller's inputs)
//! did after each scan under the commands (its outputs) in force, generalized into a
//! `MODULE plant(<controller outputs>)` of the plant subset ([`super`]).
//!
//! In: a [`ScenarioSet`] (the recordings), where each scan `k` gives the sensors `s_k` the
//! controller read and the outputs `o_k` it left in force, so that the plant moved from
//! `s_k` under `o_k` to `s_{k+1}`; optionally observers (SMV declarations of the names the
//! properties use that no recording shows, such as an overflow or a "piece placed" event).
//! Out: a [`Learned`] plant: its SMV text, what it is made of ([`Part`]s), and the proof
//! that it admits every recorded step; or a [`LearnError`] naming the file and step.
//!
//! # The method
//! In the spirit of Buzhinsky and Vyatkin, "Automatic inference of finite-state plant models
//! from traces and temporal properties" (IEEE TII 2017), the state is the sensors' valuation,
//! plus one hidden dwell counter per sensor a command moves over several scans. Each sensor's
//! rise (from FALSE) and fall (from TRUE) are learned apart ([`depend`]):
//! - *Who moves it*: a change is driven by a command (an output at one value) when the
//!   command was in force at every recorded change of it, it matters (had the sensor changed
//!   as often without it, the recorded scans without it would show a change but for a chance
//!   below 5%, shared among the outputs tried as in Bonferroni's correction), and it reliably
//!   produced the change: in at least two episodes where it came into force with the sensor
//!   unmoved, the change followed, and no episode with it in force as long as the longest
//!   that did ended without the change. The other change of a sensor one command drives may
//!   be driven by that command's withdrawal (a spring returns a cylinder) when it came at
//!   each withdrawal recorded. A sensor is the controller's when both its changes are driven;
//!   otherwise the environment moves it (an operator's button, no command releases; the stock
//!   of a magazine; a piece put on a track), however well a lamp happens to predict a press.
//! - *Valves*: a sensor whose rise and whose fall two different commands drive, each of
//!   which the controller only ever switches on for single scans (pulses), follows a hidden
//!   valve that keeps the last pulse ([`Valve`]: a bistable valve, a latching relay); its
//!   changes read the valve where they would read the commands. A suction cup then may grip
//!   after the pulse ended, when a change may come later than recorded (`--slack`).
//! - *Structure of a driven change*: its command, and the signals chosen greedily, starting
//!   from the sensor itself, by the Bayesian information criterion: the log-likelihood of
//!   the recorded next values (each context a Bernoulli trial at its recorded frequency) less
//!   half the log of the number of transitions per context; a signal that splits a few
//!   chance changes apart does not pay for the contexts it adds. What remains ambiguous is a
//!   delay: a cylinder under way, a level between two sensors.
//! - *Structure of the environment's change*: only the other sensors (the environment does not
//!   read the controller's outputs) that matter to it in the sense above, with the number of
//!   sensors tried shared out, then those that matter among the scans where the first hold
//!   (the cup holds a piece: over the track it leaves, over the slider a new piece stays);
//!   usually none, so that a button is free in every context. A change bound nowhere (an
//!   operator's) is only narrowed by its gates, and a gate there by chance would leave out
//!   runs the plant makes: its gates must pass the test with the chance shared among every
//!   change of the environment's the recordings show, not only its own. A change of the
//!   environment's sensor never recorded (a switch turned on, not back) is free everywhere,
//!   and the sensor starts free.
//! - *Behaviour*: in a context seen in the recordings the sensor takes the values seen there;
//!   the environment's change is free there, unless at least three recorded stays in the
//!   context ended with it and none with the context left (a piece leaves the track the cup
//!   holds it over): then it comes there at the latest as recorded, where the controller's
//!   sensors outside the context show what they showed at every recorded scan in it (the
//!   scene: the hand over this track, not over another while a piece waits here). In a
//!   context never seen the sensor keeps its value (a sensor does not change without a
//!   cause). Every command is accepted in every state (the model is receptive by
//!   construction).
//! - *Scans*: with `--slack`, where the model's scan need not be the recording PLC's, a
//!   change a command drives may come that many scans later than recorded, and a change the
//!   environment makes when a sensor of the controller's has a value may come in the scan that
//!   sensor takes it (the piece leaves as the cup grips, `next(vac)`); where such a bound
//!   change's sensors all held, each in this scan or the next, but will not all hold in the
//!   next (the cup gripped as it left), it comes by the next scan.
//! - *Delays*: in an ambiguous context of a driven change, the sensor must change once it
//!   stayed longer than the longest stay recorded there (plus a slack), and may change once
//!   it stayed a quarter of the shortest stay recorded before a change (a counter per sensor
//!   and direction counts the scans), so that "a cylinder told to extend eventually reaches its
//!   end" holds without any fairness.
//! - *Check* ([`admit`]): the text is read back by the plant parser and every recorded run
//!   replayed on it, step by step; the first step it cannot produce is an error.

pub(crate) mod admit;
pub(crate) mod assume;
pub(crate) mod compare;
pub(crate) mod depend;
pub(crate) mod emit;

use crate::scenario::{Origin, ScenarioSet};
use std::path::PathBuf;

/// One recorded scan: the sensors read and the outputs in force after it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Scan {
    /// The sensors (controller inputs), in interface order.
    pub(crate) inputs: Vec<bool>,
    /// The controller outputs after the scan, in interface order.
    pub(crate) outputs: Vec<bool>,
}

/// The recordings as runs of scans, with where each run comes from.
#[derive(Debug, Clone)]
pub(crate) struct Runs {
    /// Sensor names.
    pub(crate) inputs: Vec<String>,
    /// Controller output names.
    pub(crate) outputs: Vec<String>,
    /// Per run: its origin and its scans.
    pub(crate) runs: Vec<(Origin, Vec<Scan>)>,
}

impl Runs {
    /// The scans of `set`: each step's inputs with the outputs in force after it.
    pub(crate) fn of(set: &ScenarioSet) -> Runs {
        let runs = (set.scenarios.iter())
            .map(|s| {
                let mut outputs = set.initial_outputs.clone();
                let scans = (s.steps.iter())
                    .map(|step| {
                        if let Some(o) = &step.outputs {
                            outputs.clone_from(o);
                        }
                        Scan {
                            inputs: step.inputs.clone(),
                            outputs: outputs.clone(),
                        }
                    })
                    .collect();
                (s.origin.clone(), scans)
            })
            .collect();
        Runs {
            inputs: set.inputs.clone(),
            outputs: set.outputs.clone(),
            runs,
        }
    }

    /// Every recorded transition: (the scan, the sensors of the next scan).
    pub(crate) fn transitions(&self) -> impl Iterator<Item = (&Scan, &[bool])> {
        (self.runs.iter())
            .flat_map(|(_, scans)| scans.windows(2).map(|w| (&w[0], w[1].inputs.as_slice())))
    }

    /// The value of signal `f` (a sensor index, or `inputs.len() + output index`) in `scan`.
    pub(crate) fn signal(&self, scan: &Scan, f: usize) -> bool {
        match f.checked_sub(self.inputs.len()) {
            None => scan.inputs[f],
            Some(z) => scan.outputs[z],
        }
    }

    /// The name of signal `f`.
    pub(crate) fn signal_name(&self, f: usize) -> &str {
        match f.checked_sub(self.inputs.len()) {
            None => &self.inputs[f],
            Some(z) => &self.outputs[z],
        }
    }
}

/// Observers: SMV declarations added verbatim to the learned module.
#[derive(Debug, Clone)]
pub(crate) struct Observers {
    /// The file they come from.
    pub(crate) file: PathBuf,
    /// Its text.
    pub(crate) text: String,
}

/// What a sensor's next value is learned to depend on, and how.
#[derive(Debug, Clone)]
pub(crate) struct Part {
    /// The sensor (index into the inputs).
    pub(crate) sensor: usize,
    /// Its rise (from FALSE) and its fall (from TRUE).
    pub(crate) halves: [Half; 2],
    /// The largest dwell bound of a delayed rule (0: no counter).
    pub(crate) wait_cap: usize,
    /// Whether the sensor is free at the start (the environment's: not both changes driven).
    pub(crate) free_start: bool,
    /// The valve that keeps the last of two pulsed commands, when the sensor follows one
    /// ([`depend`]); its halves then read the valve where they read the commands.
    pub(crate) valve: Option<Valve>,
}

/// A device that keeps the last of two commands the controller pulses: open after a pulse
/// of one, closed after a pulse of the other (both at once change nothing).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Valve {
    /// The output whose pulse opens it (the sensor's rise follows).
    pub(crate) open: usize,
    /// The output whose pulse closes it (the sensor's fall follows).
    pub(crate) close: usize,
}

impl Valve {
    /// Whether the valve is open after a scan with `outputs` in force, when it was `was`.
    pub(crate) fn opened(self, was: bool, outputs: &[bool]) -> bool {
        match (outputs[self.open], outputs[self.close]) {
            (true, false) => true,
            (false, true) => false,
            _ => was,
        }
    }

    /// `runs` as the sensor `x` sees them through the valve: the opening output reads "the
    /// valve is open", the closing one "it is closed". The valve starts as the sensor does.
    pub(crate) fn held(self, runs: &Runs, x: usize) -> Runs {
        let mut held = runs.clone();
        for (_, scans) in &mut held.runs {
            let mut was = scans.first().is_some_and(|s| s.inputs[x]);
            for s in scans.iter_mut() {
                was = self.opened(was, &s.outputs);
                s.outputs[self.open] = was;
                s.outputs[self.close] = !was;
            }
        }
        held
    }
}

/// The next value of a sensor that has one value, by context.
#[derive(Debug, Clone)]
pub(crate) struct Half {
    /// The signals its next value depends on (the sensor itself first).
    pub(crate) depends: Vec<usize>,
    /// The command that drives it, as (output, value in force), if one does; otherwise the
    /// environment moves it, free in the contexts where it was seen changing.
    pub(crate) driver: Option<(usize, bool)>,
    /// Per context seen (values of `depends`, in order; the sensor's own value first): the
    /// rule.
    pub(crate) rules: Vec<(Vec<bool>, Rule)>,
    /// The controller's sensors among `depends` and the scenes whose value in a context may
    /// also be the one they take in the same scan ([`early`]).
    pub(crate) early: Vec<usize>,
    /// Per context where the environment's change is bound: the controller's sensors outside
    /// `depends` with one value at every recorded scan there ([`scenes`]); it is bound only
    /// where they have it.
    pub(crate) scenes: Vec<(Vec<bool>, Scene)>,
}

/// Sensors at the value each had (signal index, value).
pub(crate) type Scene = Vec<(usize, bool)>;

impl Half {
    /// The largest dwell bound of a delayed rule (0: no counter).
    pub(crate) fn wait_cap(&self) -> usize {
        (self.rules.iter())
            .filter_map(|(_, r)| match r {
                Rule::Within(_, n) => Some(*n),
                _ => None,
            })
            .max()
            .unwrap_or(0)
    }
}

/// The next value of a sensor in one context.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Rule {
    /// Always this value.
    To(bool),
    /// Either value, at every scan.
    Free,
    /// A command moves it: it keeps its value while it stayed fewer than the first count of
    /// scans, may change from then on, and must once it stayed the second.
    Within(usize, usize),
}

impl Rule {
    /// Whether the rule forces the change of a sensor that is `v` (at once or within bounds).
    pub(crate) fn forces(self, v: bool) -> bool {
        match self {
            Rule::To(to) => to != v,
            Rule::Within(..) => true,
            Rule::Free => false,
        }
    }
}

/// A learned plant.
#[derive(Debug, Clone)]
pub(crate) struct Learned {
    /// One part per sensor.
    pub(crate) parts: Vec<Part>,
    /// The sensor valuations a run starts with (over the sensors not free at the start).
    pub(crate) starts: Vec<Vec<bool>>,
    /// The SMV text of the plant.
    pub(crate) text: String,
    /// Recorded scans (steps) and runs it was learned from.
    pub(crate) steps: usize,
    /// Number of recorded runs.
    pub(crate) runs: usize,
}

/// Why no plant could be learned.
#[derive(Debug, thiserror::Error)]
pub(crate) enum LearnError {
    /// No recorded transition at all.
    #[error("{file}: the recordings hold no two consecutive scans: nothing to learn a plant from")]
    NoTransition {
        /// The first trace file.
        file: String,
    },
    /// An output that is never on: nothing says what it does.
    #[error("{file}: the recordings are too short to learn the plant from: the controller output {output} is never on in them, so nothing shows what it moves; record a run where it acts")]
    NeverOn {
        /// The first trace file.
        file: String,
        /// The output.
        output: String,
    },
    /// A sensor that never changes.
    #[error("{file}: the recordings are too short to learn the plant from: the sensor {sensor} never changes in them, so nothing shows what moves it; record a run where it does")]
    NeverChanges {
        /// The first trace file.
        file: String,
        /// The sensor.
        sensor: String,
    },
    /// The learned text is not a model of the subset (observers that do not parse).
    #[error("the learned plant does not read back{observers}: {message}")]
    Unreadable {
        /// ` (check the observers in FILE)` when observers were given.
        observers: String,
        /// The parser's message.
        message: String,
    },
    /// A recorded step the learned plant cannot produce.
    #[error("{place}: the learned plant cannot produce this recorded step: {why}")]
    NotAdmitted {
        /// File, line and step.
        place: String,
        /// What it refuses.
        why: String,
    },
}

/// Learns the plant of `set` (see the module header); `source` names the recordings in the
/// header of the text; a change a command drives may come `slack` scans later than recorded.
pub(crate) fn learn(
    set: &ScenarioSet,
    source: &str,
    observers: Option<&Observers>,
    slack: usize,
) -> Result<Learned, LearnError> {
    let runs = Runs::of(set);
    refuse_too_short(&runs, set)?;
    let drivers: Vec<depend::Drivers> = (0..runs.inputs.len())
        .map(|x| depend::drivers(&runs, x))
        .collect();
    let family = depend::environment_changes(&runs, &drivers);
    let mut parts: Vec<Part> = (drivers.iter().enumerate())
        .map(|(x, &d)| depend::part(&runs, x, d, slack, family))
        .collect();
    scenes(&mut parts, &runs);
    if slack > 0 {
        early(&mut parts);
    }
    let starts = emit::starts(&runs, &parts);
    let mut learned = Learned {
        parts,
        starts,
        text: String::new(),
        steps: set.step_count(),
        runs: runs.runs.len(),
    };
    learned.text = emit::text(&learned, &runs, source, observers);
    admit::check(&learned, &runs, observers)?;
    Ok(learned)
}

/// With `--slack`, the scan of the model need not be the recording PLC's: where the
/// environment changes a sensor when a sensor of the controller's has a value (a piece leaves
/// its track once the cup holds it), it may change in the same scan as that sensor takes the
/// value (the piece leaves as the cup grips). Only the controller's sensors are read so: their
/// next values read no other sensor's next value, so the model stays free of cycles.
fn early(parts: &mut [Part]) {
    let commanded: Vec<bool> = parts.iter().map(|p| !p.free_start).collect();
    for p in parts.iter_mut().filter(|p| p.free_start) {
        let x = p.sensor;
        for h in p.halves.iter_mut().filter(|h| h.driver.is_none()) {
            let scenes = h.scenes.iter().flat_map(|(_, s)| s.iter().map(|&(f, _)| f));
            let mut early: Vec<usize> = (h.depends.iter().copied())
                .filter(|&f| f != x && commanded.get(f) == Some(&true))
                .chain(scenes)
                .collect();
            early.sort_unstable();
            early.dedup();
            h.early = early;
        }
    }
}

/// Where the environment's change is bound (a piece leaves the track the cup holds it
/// over), the scene of the context: each sensor of the controller's that had one value at
/// every recorded scan there. The gates say where the change may come; forcing it where the
/// machine stood otherwise than ever recorded (the cup gripping over another track while a
/// piece waits on this one) would speak beyond the recordings, so there the sensor keeps its
/// value, as in any context never seen.
fn scenes(parts: &mut [Part], runs: &Runs) {
    let commanded: Vec<bool> = parts.iter().map(|p| !p.free_start).collect();
    for p in parts.iter_mut().filter(|p| p.free_start) {
        for (v, h) in [false, true].into_iter().zip(p.halves.iter_mut()) {
            h.scenes = (h.rules.iter())
                .filter(|(_, r)| r.forces(v))
                .map(|(c, _)| (c.clone(), scene(runs, &h.depends, c, &commanded)))
                .collect();
        }
    }
}

/// The controller's sensors outside `depends` that had one value at every recorded scan in
/// context `c` of `depends` (the stays there and the changes alike), with that value.
fn scene(runs: &Runs, depends: &[usize], c: &[bool], commanded: &[bool]) -> Scene {
    let seen: Vec<&Scan> = (runs.transitions())
        .map(|(s, _)| s)
        .filter(|s| {
            depends
                .iter()
                .map(|&f| runs.signal(s, f))
                .eq(c.iter().copied())
        })
        .collect();
    let Some(first) = seen.first() else {
        return Vec::new();
    };
    (0..runs.inputs.len())
        .filter(|f| commanded[*f] && !depends.contains(f))
        .filter(|&f| seen.iter().all(|s| s.inputs[f] == first.inputs[f]))
        .map(|f| (f, first.inputs[f]))
        .collect()
}

/// Refuses recordings that show no transition, an output never on or a sensor never
/// changing.
fn refuse_too_short(runs: &Runs, set: &ScenarioSet) -> Result<(), LearnError> {
    let file = (set.scenarios.first())
        .map(|s| s.origin.file.display().to_string())
        .unwrap_or_else(|| "the recordings".into());
    if runs.transitions().next().is_none() {
        return Err(LearnError::NoTransition { file });
    }
    for (z, name) in runs.outputs.iter().enumerate() {
        if !runs.transitions().any(|(s, _)| s.outputs[z]) {
            return Err(LearnError::NeverOn {
                file,
                output: name.clone(),
            });
        }
    }
    for (x, name) in runs.inputs.iter().enumerate() {
        if !runs.transitions().any(|(s, n)| s.inputs[x] != n[x]) {
            return Err(LearnError::NeverChanges {
                file,
                sensor: name.clone(),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::{Scenario, Step};

    /// Three recorded runs of a suction cup: the controller pulses `on` (the cup grips at the
    /// next scan) and later `off` (it lets go at the next scan). With `held_on`, `on` stays on
    /// for two scans and the cup grips after the second (no pulse).
    pub(super) fn cup(held_on: bool) -> ScenarioSet {
        let scenarios = (0..3)
            .map(|r| {
                let mut held = false;
                let steps = (0..20)
                    .map(|k| {
                        let first = k % 10 == 2 + r;
                        let second = held_on && k % 10 == 3 + r;
                        let (on, off) = (first || second, k % 10 == 7);
                        let step = Step {
                            inputs: vec![held],
                            outputs: Some(vec![on, off]),
                        };
                        held = (held || (on && (second || !held_on))) && !off;
                        step
                    })
                    .collect();
                Scenario {
                    origin: Origin {
                        file: "cup.traces".into(),
                        line: r + 1,
                        rows: None,
                    },
                    steps,
                }
            })
            .collect();
        ScenarioSet {
            inputs: vec!["held".into()],
            outputs: vec!["on".into(), "off".into()],
            initial_outputs: vec![false, false],
            scenarios,
        }
    }

    #[test]
    fn a_sensor_behind_a_valve_is_written_with_the_valve_and_admits_every_recorded_step() {
        let learned = learn(&cup(false), "cup.traces", None, 1).unwrap();
        assert_eq!(learned.parts[0].valve, Some(Valve { open: 0, close: 1 }));
        insta::assert_snapshot!("valve", learned.text);
    }

    #[test]
    fn hidden_variables_take_names_no_signal_has() {
        let mut set = cup(false);
        set.outputs = vec!["wait_up_held".into(), "valve_held".into()];
        let learned = learn(&set, "cup.traces", None, 1).unwrap();
        for hidden in ["valve_held_ : boolean;", "wait_up_held_ : 0..1;"] {
            assert!(learned.text.contains(hidden), "{}", learned.text);
        }
    }
}
