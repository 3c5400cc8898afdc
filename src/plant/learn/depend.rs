//! Which signals a sensor's next value depends on, and its rule in each context seen.
//!
//! In: the recorded [`Runs`] and a sensor. Out: its [`Part`]: the dependency set (greedy, see
//! the header of [`super`]), the rule of every context the recordings show, and the dwell
//! bounds of the delayed ones.

use super::{Half, Part, Rule, Runs};
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
/// drives may come up to `slack` scans later than recorded.
pub(crate) fn part(runs: &Runs, x: usize, slack: usize) -> Part {
    let halves = [false, true].map(|v| half(runs, x, v, slack));
    let wait_cap = halves.iter().map(Half::wait_cap).max().unwrap_or(0);
    let free_start = (halves.iter())
        .flat_map(|h| &h.rules)
        .all(|(_, r)| *r == Rule::Free);
    Part {
        sensor: x,
        halves,
        wait_cap,
        free_start,
    }
}

/// The half of sensor `x`'s part that starts from value `v`.
fn half(runs: &Runs, x: usize, v: bool, slack: usize) -> Half {
    let depends = dependencies(runs, x, v);
    let counts = counts(runs, x, v, &depends);
    // A command (on, or off as for a spring-return cylinder) drives the sensor in this half.
    let driven = depends.iter().any(|&f| f >= runs.inputs.len());
    let command_on = |_: &[bool]| driven;
    let mut rules: Vec<(Vec<bool>, Rule)> = (counts.iter())
        .map(|(c, &(stays, changes))| {
            let rule = match (stays, changes) {
                (_, 0) => Rule::To(v),
                (0, _) if command_on(c) && slack > 0 => Rule::Within(0, 0),
                (0, _) => Rule::To(!v),
                _ if command_on(c) => Rule::Within(0, 0),
                _ => Rule::Free,
            };
            (c.clone(), rule)
        })
        .collect();
    let waits = dwell_bounds(runs, x, &depends, &rules);
    for (c, rule) in &mut rules {
        if let Rule::Within(least, most) = rule {
            let (shortest, longest) = waits.get(c).copied().unwrap_or((0, None));
            *least = shortest / SPEEDUP;
            *most = longest.map_or(0, |w| w + 1) + slack;
        }
    }
    Half { depends, rules }
}

/// The dependency set of sensor `x` when it is `v`: itself, then greedily the signal that
/// most reduces the ambiguous transitions, while it removes at least a tenth of them (and
/// at least two); on a tie, a controller output before a sensor, then the signal on at more
/// of the recorded changes (a command that is on moves the sensor, not one that is off).
fn dependencies(runs: &Runs, x: usize, v: bool) -> Vec<usize> {
    let signals = runs.inputs.len() + runs.outputs.len();
    let mut depends = vec![x];
    let mut now = ambiguous(&counts(runs, x, v, &depends));
    while now > 0 && depends.len() < MAX_DEPENDS {
        let best = (0..signals)
            .filter(|f| !depends.contains(f))
            .map(|f| {
                let mut with = depends.clone();
                with.push(f);
                let output_first = usize::from(f < runs.inputs.len());
                let off_at_changes = changes(runs, x, v).filter(|(s, _)| !runs.signal(s, f));
                let key = (output_first, off_at_changes.count());
                (ambiguous(&counts(runs, x, v, &with)), key, f)
            })
            .min();
        match best {
            Some((after, _, f)) if now - after >= (now / 10).max(2) => {
                depends.push(f);
                now = after;
            }
            _ => break,
        }
    }
    if let Some(z) = command_behind(runs, x, v, &depends) {
        depends.push(z);
    }
    depends
}

/// When no controller output was chosen but the sensor changed: the output on at every
/// recorded change (the one on least often otherwise), which then moves it. A command that
/// was on all along separates nothing, yet it is what moves the sensor (an inlet filling an
/// empty tank).
fn command_behind(runs: &Runs, x: usize, v: bool, depends: &[usize]) -> Option<usize> {
    let n = runs.inputs.len();
    if depends.iter().any(|&f| f >= n) {
        return None;
    }
    let half = || runs.transitions().filter(|(s, _)| s.inputs[x] == v);
    changes(runs, x, v).next()?;
    (0..runs.outputs.len())
        .filter(|&z| changes(runs, x, v).all(|(s, _)| s.outputs[z]))
        .min_by_key(|&z| half().filter(|(s, _)| s.outputs[z]).count())
        .map(|z| n + z)
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
