//! Which signals a sensor's next value depends on, and its rule in each context seen.
//!
//! In: the recorded [`Runs`] and a sensor. Out: its [`Part`]: per change, the command that
//! drives it if one does, the dependency set (see the header of [`super`]), the rule of every
//! context the recordings show, and the dwell bounds of the delayed ones.

use super::{Half, Part, Rule, Runs, Valve};
use std::collections::BTreeMap;

/// At most this many signals per sensor: more would split the recordings into contexts seen
/// once, which explain everything and generalize nothing.
const MAX_DEPENDS: usize = 5;

/// How much faster than the recordings a delay may run: a change recorded after at least `m`
/// scans in its context comes after at least `m / SPEEDUP` (a model's scan need not be the
/// recording PLC's, but a level does not cross from one sensor to the next at once when the
/// recordings never saw it do so).
const SPEEDUP: usize = 4;

/// Per context: (scans the sensor stayed, scans it changed).
type Counts = BTreeMap<Vec<bool>, (usize, usize)>;

/// The part of sensor `x`: its rise (from FALSE) and its fall (from TRUE) learned apart, as
/// a command that extends a cylinder is not the one that retracts it; each change a command
/// drives may come up to `slack` scans later than recorded. A sensor is the controller's when
/// a command drives each of its changes ([`driver`]); otherwise the environment moves it (an
/// operator's button, which no command releases; a piece put on a track), and it is free in
/// the contexts where it was seen changing, from the start on. The chance that a sensor
/// gates the environment's change by coincidence is shared among the `family` changes of the
/// environment's the recordings show ([`environment_changes`]).
/// `drivers` are the sensor's ([`drivers`]).
pub(crate) fn part(runs: &Runs, x: usize, drivers: Drivers, slack: usize, family: usize) -> Part {
    let commanded = drivers.iter().all(Option::is_some);
    let valve = valve(runs, drivers);
    let held = valve.map(|v| v.held(runs, x));
    let seen = held.as_ref().unwrap_or(runs);
    let halves = [false, true].map(|v| match (commanded, drivers[usize::from(v)]) {
        (true, Some(d)) => half(seen, x, v, Some(d), slack, family),
        _ => half(seen, x, v, None, slack, family),
    });
    let wait_cap = halves.iter().map(Half::wait_cap).max().unwrap_or(0);
    Part {
        sensor: x,
        halves,
        wait_cap,
        free_start: !commanded,
        valve,
    }
}

/// Per change of a sensor (rise, fall): the output and the value of it that drives it.
pub(crate) type Drivers = [Option<(usize, bool)>; 2];

/// The commands that drive the rise and the fall of sensor `x` ([`driver`]); the other
/// change of a sensor one command drives may be driven by its withdrawal ([`withdrawal`]).
pub(crate) fn drivers(runs: &Runs, x: usize) -> Drivers {
    let mut drivers = [false, true].map(|v| driver(runs, x, v));
    for v in [false, true] {
        let (this, other) = (usize::from(v), usize::from(!v));
        if let (None, Some((z, b))) = (drivers[this], drivers[other]) {
            drivers[this] = withdrawal(runs, x, v, z, !b);
        }
    }
    drivers
}

/// How many changes the recordings show the environment making: the rises and falls they
/// show of the sensors no command drives both ways. Each is tested for gates against every
/// other sensor; a model of many such changes would otherwise gate one of them by chance
/// (an operator seen putting pieces on one track only while the cup was up). `drivers` holds
/// every sensor's ([`drivers`]).
pub(crate) fn environment_changes(runs: &Runs, drivers: &[Drivers]) -> usize {
    (0..runs.inputs.len())
        .filter(|&x| !drivers[x].iter().all(Option::is_some))
        .map(|x| {
            [false, true]
                .into_iter()
                .filter(|&v| changes(runs, x, v).next().is_some())
                .count()
        })
        .sum()
}

/// The valve of a sensor whose rise and fall `drivers` are two different outputs that the
/// recorded controller only ever switches on for single scans (pulses): the device keeps the
/// last pulse (a bistable valve, a latching relay), and the sensor follows what it keeps, not
/// the pulse. The recordings may always show the sensor answering the pulse at once; a
/// sensor that answers later (a cup that grips once a piece arrives) still does under the
/// valve, when `--slack` lets it.
fn valve(runs: &Runs, drivers: Drivers) -> Option<Valve> {
    match drivers {
        [Some((open, true)), Some((close, true))]
            if open != close && pulsed(runs, open) && pulsed(runs, close) =>
        {
            Some(Valve { open, close })
        }
        _ => None,
    }
}

/// Whether output `z` is on for single scans only, at least twice, in the recordings.
fn pulsed(runs: &Runs, z: usize) -> bool {
    let mut pulses = 0;
    for (_, scans) in &runs.runs {
        let on: Vec<bool> = scans.iter().map(|s| s.outputs[z]).collect();
        for (k, _) in on.iter().enumerate().filter(|(_, &b)| b) {
            let alone = (k == 0 || !on[k - 1]) && on.get(k + 1) != Some(&true);
            match alone {
                true => pulses += 1,
                false => return false,
            }
        }
    }
    pulses >= 2
}

/// The half of sensor `x`'s part that starts from value `v`, driven by `driver` (output,
/// value in force) or moved by the environment.
fn half(
    runs: &Runs,
    x: usize,
    v: bool,
    driver: Option<(usize, bool)>,
    slack: usize,
    family: usize,
) -> Half {
    // Slack delays what the commands drive; the environment's bound change, which may come a
    // scan early ([`super::early`]), comes at the latest as recorded.
    let slack = if driver.is_some() { slack } else { 0 };
    let n = runs.inputs.len();
    let mut depends = match driver {
        Some((z, _)) => {
            let mut depends = dependencies(runs, x, v);
            if !depends.contains(&(n + z)) {
                depends.push(n + z);
            }
            depends
        }
        // The environment's sensor never seen changing this way (a mode switch turned on
        // and not back): what turned it one way may turn it back, anywhere.
        None if changes(runs, x, v).next().is_none() => {
            return Half {
                depends: vec![x],
                driver,
                rules: vec![(vec![v], Rule::Free)],
                early: Vec::new(),
                scenes: Vec::new(),
            }
        }
        None => gates(runs, x, v, 1),
    };
    let mut rules = rules(runs, x, v, driver, slack, &depends);
    // A change bound nowhere (an operator's, free wherever it was seen) is only narrowed by
    // its gates: a gate there by chance leaves out runs the plant makes, and the verdicts
    // would speak of fewer runs than the plant has. Its gates must hold up against every
    // change of the environment's tested, not only its own.
    if driver.is_none() && !rules.iter().any(|(_, r)| r.forces(v)) && family > 1 {
        depends = gates(runs, x, v, family);
        rules = self::rules(runs, x, v, driver, slack, &depends);
    }
    let waits = dwell_bounds(runs, x, &depends, &rules);
    for (c, rule) in &mut rules {
        if let Rule::Within(least, most) = rule {
            let (shortest, longest) = waits.get(c).copied().unwrap_or((0, None));
            *least = shortest / SPEEDUP;
            *most = longest.map_or(0, |w| w + 1) + slack;
        }
    }
    Half {
        depends,
        driver,
        rules,
        early: Vec::new(),
        scenes: Vec::new(),
    }
}

/// The rule of each context of `depends` seen in the recordings, where sensor `x` is `v`:
/// kept where it never changed; the environment's change free where seen, unless it always
/// came there ([`settled`]); a command's change at once, or within bounds set from the
/// recorded stays.
fn rules(
    runs: &Runs,
    x: usize,
    v: bool,
    driver: Option<(usize, bool)>,
    slack: usize,
    depends: &[usize],
) -> Vec<(Vec<bool>, Rule)> {
    (counts(runs, x, v, depends).into_iter())
        .map(|(c, (stays, changes))| {
            let rule = match (stays, changes) {
                (_, 0) => Rule::To(v),
                _ if driver.is_none() && !settled(runs, x, depends, &c) => Rule::Free,
                (0, _) if slack == 0 => Rule::To(!v),
                _ => Rule::Within(0, 0),
            };
            (c, rule)
        })
        .collect()
}

/// The dependency set of a change the environment makes to sensor `x` from `v`: itself, then
/// each other sensor that [`matters`] to it (at one value at every recorded change, and
/// significantly never changing at the other), then one at a time those that matter among
/// the scans where the ones before have their values. The operator or the stock does not read the
/// controller's outputs, and a few chance coincidences (a stop button pressed mostly once
/// the magazine ran empty) do not close a context to what the environment may do there.
fn gates(runs: &Runs, x: usize, v: bool, family: usize) -> Vec<usize> {
    let mut depends = vec![x];
    let mut within: Vec<(usize, bool)> = Vec::new();
    let tests = 2 * runs.inputs.len().saturating_sub(1) * family.max(1);
    let mut pass = Vec::new();
    for f in (0..runs.inputs.len()).filter(|&f| f != x) {
        for b in [false, true] {
            if depends.len() < MAX_DEPENDS && matters(runs, x, v, f, b, tests, &[]) {
                depends.push(f);
                pass.push((f, b));
            }
        }
    }
    // Then among the scans where those gates hold: a sensor that parts the stays from the
    // changes there (the cup holds a piece over the track, not over the slider).
    while !pass.is_empty() && depends.len() < MAX_DEPENDS {
        within.append(&mut pass);
        let next = (0..runs.inputs.len())
            .filter(|f| !depends.contains(f))
            .flat_map(|f| [(f, false), (f, true)])
            .find(|&(f, b)| matters(runs, x, v, f, b, tests, &within));
        if let Some((f, b)) = next {
            depends.push(f);
            pass.push((f, b));
        }
    }
    depends
}

/// The dependency set of sensor `x` when it is `v`: itself, then greedily the signal whose
/// contexts explain the recorded changes best, while it raises the Bayesian information
/// criterion of the half (the log-likelihood of the recorded next values, each context a
/// Bernoulli trial at its recorded frequency, less half the log of the number of recorded
/// transitions per context): a signal that splits a few chance changes apart does not pay
/// for the contexts it adds. On a tie, a controller output before a sensor, then the signal
/// on at more of the recorded changes (a command that is on moves the sensor, not one that
/// is off).
fn dependencies(runs: &Runs, x: usize, v: bool) -> Vec<usize> {
    let signals = runs.inputs.len() + runs.outputs.len();
    let mut depends = vec![x];
    let mut now = counts(runs, x, v, &depends);
    while ambiguous(&now) > 0 && depends.len() < MAX_DEPENDS {
        let mut best: Option<(f64, (usize, usize), usize, Counts)> = None;
        for f in (0..signals).filter(|f| !depends.contains(f)) {
            let mut with = depends.clone();
            with.push(f);
            let c = counts(runs, x, v, &with);
            let score = bic(&c);
            let output_first = usize::from(f < runs.inputs.len());
            let off_at_changes = changes(runs, x, v).filter(|(s, _)| !runs.signal(s, f));
            let key = (output_first, off_at_changes.count());
            let better = match &best {
                None => true,
                Some((b, k, ..)) => score > b + EPSILON || (score > b - EPSILON && key < *k),
            };
            if better {
                best = Some((score, key, f, c));
            }
        }
        match best {
            Some((score, _, f, c)) if score > bic(&now) + EPSILON => {
                depends.push(f);
                now = c;
            }
            _ => break,
        }
    }
    depends
}

/// Scores closer than this are equal.
const EPSILON: f64 = 1e-9;

/// The Bayesian information criterion of `counts`: the log-likelihood of the recorded next
/// values when each context changes at its recorded frequency, less half the log of the
/// number of transitions per context (one parameter each).
fn bic(counts: &Counts) -> f64 {
    let n: usize = counts.values().map(|(s, c)| s + c).sum();
    let term = |k: usize, of: usize| match k {
        0 => 0.0,
        _ => k as f64 * (k as f64 / of as f64).ln(),
    };
    let ll: f64 = (counts.values())
        .map(|&(s, c)| term(s, s + c) + term(c, s + c))
        .sum();
    ll - counts.len() as f64 / 2.0 * (n.max(1) as f64).ln()
}

/// The command that drives the change of sensor `x` from `v`, as (output, value in force), if
/// any: a value of an output in force at every recorded change, that [`matters`] to it and
/// reliably produced it ([`reliable`]). Among several, the one in force least often while the
/// sensor is `v` (an inlet open all along still fills an empty tank, but the one that is on
/// only while the tank fills is what fills it).
fn driver(runs: &Runs, x: usize, v: bool) -> Option<(usize, bool)> {
    changes(runs, x, v).next()?;
    let in_force = |z: usize, b: bool| {
        (runs.transitions())
            .filter(|(s, _)| s.inputs[x] == v && s.outputs[z] == b)
            .count()
    };
    (0..runs.outputs.len())
        .flat_map(|z| [(z, true), (z, false)])
        .filter(|&(z, b)| {
            let tests = 2 * runs.outputs.len();
            matters(runs, x, v, runs.inputs.len() + z, b, tests, &[])
        })
        .filter(|&(z, b)| reliable(runs, x, v, z, b, true))
        .min_by_key(|&(z, b)| in_force(z, b))
}

/// Below this probability, no change in the scans without a signal is not chance (shared
/// among the signals tried, as in Bonferroni's correction: with many signals, one of them
/// separates a few changes by chance).
const SIGNIFICANCE: f64 = 0.05;

/// The changes of the environment's sensor recorded in a context, each ending a stay there,
/// from which the change is taken as bound to come there ([`settled`]).
const SETTLED: usize = 3;

/// Whether the environment's change of sensor `x` is bound to come in context `c` (of
/// `depends`): at least [`SETTLED`] stays in it ended with the change, and none with the
/// context left while the sensor kept its value (a piece leaves its track once the cup holds
/// it over the track). Otherwise the change is free there (an operator's button, pressed or
/// not). A context of the sensor alone is never left while it stays, and a run that ends
/// first shows nothing: neither is evidence of a bound.
fn settled(runs: &Runs, x: usize, depends: &[usize], c: &[bool]) -> bool {
    if depends.len() < 2 {
        return false;
    }
    let context = |scan: &super::Scan| {
        (depends.iter())
            .map(|&f| runs.signal(scan, f))
            .eq(c.iter().copied())
    };
    let mut ended = 0;
    for (_, scans) in &runs.runs {
        for w in scans.windows(2).filter(|w| context(&w[0])) {
            match w[0].inputs[x] == w[1].inputs[x] {
                false => ended += 1,
                true if !context(&w[1]) => return false,
                true => {}
            }
        }
    }
    ended >= SETTLED
}

/// The withdrawal of the command that drives the other change of sensor `x`, output `z` at
/// `b`, as the driver of its change from `v`: when `z` was `b` at every recorded change and
/// reliably produced it. A spring returns a cylinder once the command that held it back is
/// withdrawn; the recordings need not show the command held longer to tell.
fn withdrawal(runs: &Runs, x: usize, v: bool, z: usize, b: bool) -> Option<(usize, bool)> {
    let gates = changes(runs, x, v).all(|(s, _)| s.outputs[z] == b);
    (gates && reliable(runs, x, v, z, b, false)).then_some((z, b))
}

/// Whether signal `f` (a sensor or an output, as in [`Runs::signal`]) at `b` matters to the
/// change of sensor `x` from `v`: `f` was `b` at every recorded change, and had the sensor
/// changed as often with `f` not `b` as it did with it (per scan), the recorded scans with
/// `f` not `b` would show a change but for a chance below [`SIGNIFICANCE`] over the number of
/// `tests` made; the scans counted are those where every signal of `within` has its value. A
/// button is released whatever the controller does: a command that happened to be in force
/// at its few releases was seldom off while it was pressed.
fn matters(
    runs: &Runs,
    x: usize,
    v: bool,
    f: usize,
    b: bool,
    tests: usize,
    within: &[(usize, bool)],
) -> bool {
    let inside = |s: &super::Scan| within.iter().all(|&(g, c)| runs.signal(s, g) == c);
    if !changes(runs, x, v).all(|(s, _)| runs.signal(s, f) == b) {
        return false;
    }
    let at_v = || (runs.transitions()).filter(move |(s, _)| s.inputs[x] == v && inside(s));
    let with = at_v().filter(|(s, _)| runs.signal(s, f) == b).count();
    let without = at_v().filter(|(s, _)| runs.signal(s, f) != b).count();
    let rate = changes(runs, x, v).count() as f64 / with.max(1) as f64;
    let unseen = (1.0 - rate)
        .max(0.0)
        .powi(i32::try_from(without).unwrap_or(i32::MAX));
    unseen < SIGNIFICANCE / tests.max(1) as f64
}

/// Whether output `z` at `b` reliably moved sensor `x` from `v`. An episode is a maximal
/// stretch of consecutive scans of a run with `x` at `v` and `z` at `b`; it is the command's
/// when `z` came to `b` while `x` was already `v` (the controller acted, the plant answered).
/// At least two of the command's episodes ended in the change, and no episode that lasted as
/// long as the longest that did ended without it (the command withdrawn with the sensor
/// unmoved; a run that ends first shows nothing). An operator presses a button when the
/// recordings happen to show a lamp off since the run began, not because the lamp went off.
/// Without `onset`, any two episodes that ended in the change do (a withdrawal, see
/// [`withdrawal`], comes as the controller answers the change the command made).
pub(crate) fn reliable(runs: &Runs, x: usize, v: bool, z: usize, b: bool, onset: bool) -> bool {
    let episodes = episodes(runs, x, v, z, b);
    let moved = || episodes.iter().filter(|e| e.changed);
    let Some(longest) = moved().map(|e| e.scans).max() else {
        return false;
    };
    moved().filter(|e| e.onset || !onset).count() >= 2
        && (episodes.iter()).all(|e| e.changed || e.scans < longest)
}

/// A stretch of scans with a sensor at one value and an output at one value.
#[derive(Debug, Clone, Copy)]
struct Episode {
    /// How many scans it lasted.
    scans: usize,
    /// Whether the sensor changed at its end (otherwise the output did).
    changed: bool,
    /// Whether the output came to its value while the sensor already had its own.
    onset: bool,
}

/// The episodes of output `z` at `b` on sensor `x` at `v` that end within their run.
fn episodes(runs: &Runs, x: usize, v: bool, z: usize, b: bool) -> Vec<Episode> {
    let mut out = Vec::new();
    for (_, scans) in &runs.runs {
        let mut now: Option<Episode> = None;
        for (k, w) in scans.windows(2).enumerate() {
            if w[0].inputs[x] != v || w[0].outputs[z] != b {
                out.extend(now.take());
                continue;
            }
            let e = now.get_or_insert_with(|| Episode {
                scans: 0,
                changed: false,
                onset: k > 0 && scans[k - 1].inputs[x] == v && scans[k - 1].outputs[z] != b,
            });
            e.scans += 1;
            if w[1].inputs[x] != v {
                e.changed = true;
                out.extend(now.take());
            }
        }
    }
    out
}

/// The recorded transitions where sensor `x` changed from `v`.
fn changes(runs: &Runs, x: usize, v: bool) -> impl Iterator<Item = (&super::Scan, &[bool])> {
    (runs.transitions()).filter(move |(s, next)| s.inputs[x] == v && next[x] != v)
}

/// The recorded transitions whose context saw both next values of the sensor.
fn ambiguous(counts: &Counts) -> usize {
    (counts.values())
        .filter(|(s, c)| *s > 0 && *c > 0)
        .map(|(s, c)| s + c)
        .sum()
}

/// Per context of `depends` (where sensor `x` is `v`): how often `x` stayed and changed.
fn counts(runs: &Runs, x: usize, v: bool, depends: &[usize]) -> Counts {
    let mut counts = Counts::new();
    for (scan, next) in runs.transitions().filter(|(s, _)| s.inputs[x] == v) {
        let c: Vec<bool> = depends.iter().map(|&f| runs.signal(scan, f)).collect();
        let e = counts.entry(c).or_default();
        match scan.inputs[x] == next[x] {
            true => e.0 += 1,
            false => e.1 += 1,
        }
    }
    counts
}

/// Per delayed context: the smallest count of the dwell counter at a recorded change in it,
/// and the largest at a recorded scan where the sensor stayed in it. The counter counts the
/// consecutive scans the sensor stayed in a delayed context, and restarts at 0 otherwise (as
/// `wait_up_<sensor>` or `wait_down_<sensor>` of the emitted model).
fn dwell_bounds(
    runs: &Runs,
    x: usize,
    depends: &[usize],
    rules: &[(Vec<bool>, Rule)],
) -> BTreeMap<Vec<bool>, (usize, Option<usize>)> {
    let delayed: BTreeMap<&Vec<bool>, ()> = (rules.iter())
        .filter(|(_, r)| matches!(r, Rule::Within(..)))
        .map(|(c, _)| (c, ()))
        .collect();
    let mut bounds: BTreeMap<Vec<bool>, (usize, Option<usize>)> = BTreeMap::new();
    for (_, scans) in &runs.runs {
        let mut wait = 0;
        for w in scans.windows(2) {
            let c: Vec<bool> = depends.iter().map(|&f| runs.signal(&w[0], f)).collect();
            let stayed = w[0].inputs[x] == w[1].inputs[x];
            if !delayed.contains_key(&c) {
                wait = 0;
                continue;
            }
            let b = bounds.entry(c).or_insert((usize::MAX, None));
            if stayed {
                b.1 = Some(b.1.map_or(wait, |m| m.max(wait)));
                wait += 1;
            } else {
                b.0 = b.0.min(wait);
                wait = 0;
            }
        }
    }
    for b in bounds.values_mut() {
        if b.0 == usize::MAX {
            b.0 = 0;
        }
    }
    bounds
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::learn::tests::cup;
    use crate::plant::learn::Scan;
    use crate::scenario::Origin;

    /// The part of sensor `x`, its drivers found from `r`.
    fn part_of(r: &Runs, x: usize, slack: usize, family: usize) -> Part {
        part(r, x, drivers(r, x), slack, family)
    }

    /// The environment's changes in `r`, every sensor's drivers found from it.
    fn env_changes(r: &Runs) -> usize {
        let drivers: Vec<Drivers> = (0..r.inputs.len()).map(|x| drivers(r, x)).collect();
        environment_changes(r, &drivers)
    }

    /// Runs of a cylinder (sensor `end`, command `push`: the end is reached two scans after
    /// `push` comes on; the controller withdraws it once it reads the end, and the cylinder
    /// springs back at the next scan) beside a button the operator presses for two scans at
    /// `presses` (the controller lights `lamp` while it reads it), and a sensor `flaky` that
    /// rises with `push` in force but only in the runs listed in `flaky_runs`, falling once
    /// `push` is off.
    fn runs(presses: &[usize], flaky_runs: &[usize]) -> Runs {
        let runs = (0..3)
            .map(|r| {
                let (mut pos, mut push, mut flaky) = (0, false, false);
                let scans = (0..40)
                    .map(|k| {
                        let end = pos >= 2;
                        let button = presses
                            .iter()
                            .any(|&p| k == p + 13 * r || k == p + 13 * r + 1);
                        push = match push {
                            true => !end,
                            false => k % 13 == 4,
                        };
                        let inputs = vec![end, button, flaky];
                        pos = if push { pos + 1 } else { 0 };
                        flaky = push && flaky_runs.contains(&r) && pos >= 1;
                        Scan {
                            inputs,
                            outputs: vec![push, button],
                        }
                    })
                    .collect();
                let origin = Origin {
                    file: "test.traces".into(),
                    line: r + 1,
                    rows: None,
                };
                (origin, scans)
            })
            .collect();
        Runs {
            inputs: vec!["end".into(), "button".into(), "flaky".into()],
            outputs: vec!["push".into(), "lamp".into()],
            runs,
        }
    }

    #[test]
    fn a_cylinder_is_driven_both_ways_and_its_start_is_recorded() {
        let r = runs(&[1, 9], &[0, 1, 2]);
        let p = part_of(&r, 0, 0, 1);
        assert_eq!(p.halves[0].driver, Some((0, true)));
        assert_eq!(p.halves[1].driver, Some((0, false)));
        assert!(!p.free_start);
        assert!(p.halves[0].depends.contains(&3));
    }

    #[test]
    fn a_button_a_lamp_answers_is_the_environments_and_free_everywhere() {
        let r = runs(&[1, 9], &[0, 1, 2]);
        let p = part_of(&r, 1, 0, 1);
        assert!(p.free_start);
        assert!(p.halves.iter().all(|h| h.driver.is_none()));
        // No output is a dependency, and the button is free wherever it changed.
        assert!((p.halves.iter()).all(|h| h.depends.iter().all(|&f| f < 3)));
        assert!((p.halves.iter())
            .flat_map(|h| &h.rules)
            .any(|(_, rule)| *rule == Rule::Free));
    }

    #[test]
    fn a_command_that_once_failed_to_move_a_sensor_does_not_drive_it() {
        let driven = runs(&[1, 9], &[0, 1, 2]);
        assert!(reliable(&driven, 2, false, 0, true, true));
        let flaky = runs(&[1, 9], &[0, 2]);
        assert!(!reliable(&flaky, 2, false, 0, true, true));
        assert!(part_of(&flaky, 2, 0, 1).free_start);
    }

    #[test]
    fn a_sensor_two_pulsed_commands_drive_follows_a_valve_that_keeps_the_last_pulse() {
        let p = part_of(&Runs::of(&cup(false)), 0, 1, 1);
        assert_eq!(p.valve, Some(Valve { open: 0, close: 1 }));
        // Through the valve the grip may come a scan after the pulse ended (slack 1): the
        // context "valve open, cup not holding" is a delayed one.
        let rise = &p.halves[0];
        let open = (rise.depends.iter()).position(|&f| f == 1).unwrap();
        assert!((rise.rules.iter()).any(|(c, r)| c[open] && matches!(r, Rule::Within(0, 1))));
        // A command held on over two scans is no pulse: no valve.
        assert_eq!(part_of(&Runs::of(&cup(true)), 0, 1, 1).valve, None);
    }

    /// Runs of a track (sensors `piece`, `held`, `over`; commands `suck`, `away`): the
    /// operator puts a piece on the track at scan 1 of every 12; the cup over the track
    /// sucks from scan 3 (it holds from the next scan, and the piece leaves the scan after),
    /// carries the piece away from scan 6 and lets it go from scan 9. In every other cycle the
    /// operator puts the next piece while the cup is away holding the last one.
    fn track() -> Runs {
        let runs = (0..3)
            .map(|r| {
                let (mut piece, mut held, mut over) = (false, false, true);
                let scans = (0..48)
                    .map(|k| {
                        let (suck, away) = (k % 12 >= 3 && k % 12 < 9, k % 12 >= 6 && k % 12 < 10);
                        let scan = Scan {
                            inputs: vec![piece, held, over],
                            outputs: vec![suck, away],
                        };
                        let put = k % 12 == 1 || (k % 24 == 20 && !piece);
                        piece = (piece || put) && !(held && over && piece);
                        (held, over) = (suck, !away);
                        scan
                    })
                    .collect();
                let origin = Origin {
                    file: "track.traces".into(),
                    line: r + 1,
                    rows: None,
                };
                (origin, scans)
            })
            .collect();
        Runs {
            inputs: vec!["piece".into(), "held".into(), "over".into()],
            outputs: vec!["suck".into(), "away".into()],
            runs,
        }
    }

    #[test]
    fn a_piece_leaves_the_track_the_cup_holds_it_over_and_the_operator_stays_free() {
        let r = track();
        let p = part_of(&r, 0, 0, 1);
        assert!(p.free_start);
        let [put, taken] = &p.halves;
        // The operator puts pieces whatever the machine does: free, never forced.
        assert!((put.rules.iter()).all(|(_, rule)| matches!(rule, Rule::Free | Rule::To(false))));
        // The piece leaves once the cup holds it over the track, and only there: the cup
        // holding the last piece away from the track does not take the next one.
        assert_eq!(taken.depends, vec![0, 1, 2]);
        let rule = |c: [bool; 3]| {
            (taken.rules.iter())
                .find(|(k, _)| k[..] == c)
                .map(|(_, r)| *r)
        };
        assert_eq!(rule([true, true, true]), Some(Rule::To(false)));
        assert_eq!(rule([true, true, false]), Some(Rule::To(true)));
    }

    #[test]
    fn with_slack_the_piece_may_leave_in_the_scan_the_cup_grips_and_leaves_by_the_next() {
        let r = track();
        let mut parts: Vec<Part> = (0..3).map(|x| part_of(&r, x, 1, 1)).collect();
        assert!(!parts[1].free_start && !parts[2].free_start);
        crate::plant::learn::early(&mut parts);
        // The cup and the hand are the controller's: the piece may leave as they arrive.
        assert_eq!(parts[0].halves[1].early, vec![1, 2]);
        // Slack delays what commands drive, not the environment's bound change.
        let taken = &parts[0].halves[1];
        assert!((taken.rules.iter()).any(|(c, r)| c[..] == [true; 3] && *r == Rule::To(false)));
        // The controller's own sensors wait for nothing earlier.
        assert!(parts[1..]
            .iter()
            .all(|p| p.halves.iter().all(|h| h.early.is_empty())));
    }

    /// One run of a door that opens and closes every five scans and a button pressed for two
    /// scans at scans 2, 22 and 42, each time while the door happens to be open; the lamp
    /// shows the button.
    fn door() -> Runs {
        let (mut door, mut button) = (true, false);
        let scans = (0..60)
            .map(|k| {
                let scan = Scan {
                    inputs: vec![button, door],
                    outputs: vec![button],
                };
                button = [2, 3, 22, 23, 42, 43].contains(&k);
                door = (k + 1) / 5 % 2 == 0;
                scan
            })
            .collect();
        let origin = Origin {
            file: "door.traces".into(),
            line: 1,
            rows: None,
        };
        Runs {
            inputs: vec!["button".into(), "door".into()],
            outputs: vec!["lamp".into()],
            runs: vec![(origin, scans)],
        }
    }

    #[test]
    fn a_free_change_is_gated_only_by_what_holds_up_against_every_change_of_the_environment() {
        let r = door();
        // Four changes of the environment's: the button's and the door's rises and falls.
        assert_eq!(env_changes(&r), 4);
        // Tested alone, the presses seem to wait for the door (a chance of 2% that they came
        // only while it was open)...
        assert_eq!(part_of(&r, 0, 0, 1).halves[0].depends, vec![0, 1]);
        // ... which does not hold up against the four: the button is free whatever the door.
        let p = part_of(&r, 0, 0, env_changes(&r));
        assert_eq!(p.halves[0].depends, vec![0]);
        assert!((p.halves[0].rules.iter()).all(|(_, rule)| *rule == Rule::Free));
        // A bound change keeps the gates its own test gives: they say where it is forced.
        let taken = &part_of(&track(), 0, 0, 1000).halves[1];
        assert_eq!(taken.depends, vec![0, 1, 2]);
    }

    #[test]
    fn the_scene_of_a_bound_change_is_what_the_controllers_sensors_showed_at_every_scan_there() {
        // The track with two more sensors of the controller's: a lamp on the hand, lit in
        // the even cycles only, and a hood, down from scan 2 to 9 of each cycle.
        let mut r = track();
        r.inputs.extend(["lit".into(), "hood".into()]);
        for (_, scans) in &mut r.runs {
            for (k, scan) in scans.iter_mut().enumerate() {
                scan.inputs
                    .extend([k / 12 % 2 == 0, (2..10).contains(&(k % 12))]);
            }
        }
        let commanded = [false, true, true, true, true];
        // Wherever the cup held a piece over the track, the hood was down; the lamp was lit
        // or not.
        let scene = crate::plant::learn::scene(&r, &[0, 1, 2], &[true; 3], &commanded);
        assert_eq!(scene, vec![(4, true)]);
        // The environment's sensors are no part of the scene.
        let scene = crate::plant::learn::scene(&r, &[0, 1, 2], &[true; 3], &[false; 5]);
        assert!(scene.is_empty());
    }

    #[test]
    fn a_signal_splitting_off_no_change_does_not_pay_for_its_contexts() {
        // 100 transitions, 4 changes: one context, or two that split the stays evenly.
        let one = Counts::from([(vec![false], (96, 4))]);
        let two = Counts::from([(vec![false, false], (48, 2)), (vec![false, true], (48, 2))]);
        assert!(bic(&one) > bic(&two));
        // Two contexts that separate the changes from most stays do pay.
        let apart = Counts::from([(vec![false, false], (90, 0)), (vec![false, true], (6, 4))]);
        assert!(bic(&apart) > bic(&one));
    }
}
