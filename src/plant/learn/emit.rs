//! The learned plant as SMV text of the plant subset.
//!
//! In: the [`Learned`] parts and starts, the [`Runs`] (for names), where the recordings come
//! from, and the observers. Out: the text of `MODULE plant(<controller outputs>)`: a header
//! saying what it was learned from, its size and structure, then one Boolean `VAR` per sensor,
//! one counter per delayed sensor, one Boolean per valve (with a `DEFINE` of whether it is
//! open after the scan's commands), the start values as `init` (a sensor whose recorded starts
//! differ starts free), a `next` assignment per
//! sensor (contexts that keep the value are left to the default branch), and the observers.

use super::{Half, Learned, Observers, Part, Rule, Runs, Valve};
use std::collections::BTreeSet;
use std::fmt::Write;

/// The sensor valuations the recorded runs start with, over the sensors not free at start.
pub(crate) fn starts(runs: &Runs, parts: &[Part]) -> Vec<Vec<bool>> {
    let set: BTreeSet<Vec<bool>> = (runs.runs.iter())
        .filter_map(|(_, scans)| scans.first())
        .map(|s| {
            (parts.iter())
                .filter(|p| !p.free_start)
                .map(|p| s.inputs[p.sensor])
                .collect()
        })
        .collect();
    set.into_iter().collect()
}

/// The text of the plant.
pub(crate) fn text(
    learned: &Learned,
    runs: &Runs,
    source: &str,
    observers: Option<&Observers>,
) -> String {
    let mut t = String::new();
    header(&mut t, learned, runs, source, observers);
    let _ = writeln!(t, "MODULE plant({})", runs.outputs.join(", "));
    t.push_str("VAR\n");
    for name in &runs.inputs {
        let _ = writeln!(t, "    {name} : boolean;");
    }
    for p in (learned.parts.iter()).filter(|p| p.valve.is_some()) {
        let _ = writeln!(t, "    {} : boolean;", valve(runs, p.sensor));
    }
    for p in &learned.parts {
        for (v, h) in [false, true].into_iter().zip(&p.halves) {
            if h.wait_cap() > 0 {
                let name = counter(runs, p.sensor, v);
                let _ = writeln!(t, "    {name} : 0..{};", h.wait_cap());
            }
        }
    }
    valves(&mut t, learned, runs);
    t.push_str("ASSIGN\n");
    init(&mut t, learned, runs);
    for p in &learned.parts {
        next(&mut t, p, runs);
    }
    if let Some(o) = observers {
        let _ = writeln!(t, "-- observers, from {}", o.file.display());
        t.push_str(&o.text);
        if !o.text.ends_with('\n') {
            t.push('\n');
        }
    }
    t
}

fn header(
    t: &mut String,
    learned: &Learned,
    runs: &Runs,
    source: &str,
    observers: Option<&Observers>,
) {
    let counters = (learned.parts.iter())
        .flat_map(|p| &p.halves)
        .filter(|h| h.wait_cap() > 0)
        .count();
    let rules: usize = (learned.parts.iter())
        .flat_map(|p| &p.halves)
        .map(|h| h.rules.len())
        .sum();
    let _ = writeln!(
        t,
        "-- Surrogate plant learned by fbsynth from {source}: {} recorded scans in {} runs.",
        learned.steps, learned.runs
    );
    let _ = writeln!(
        t,
        "-- Size: {} sensors, {counters} dwell counters, {rules} contexts seen, {} start valuations.",
        runs.inputs.len(),
        learned.starts.len()
    );
    t.push_str(
        "-- Assumes: a sensor keeps its value in a context the recordings never show; a sensor\n",
    );
    t.push_str("-- a command moves changes at the latest after the longest stay recorded, and not before a\n-- quarter of the shortest (wait_*); a sensor no command moves both ways is the environment's:\n-- free where seen changing, but bound to change where every recorded stay ended so, while the\n-- controller's other sensors show what they showed at every such scan (elsewhere it keeps its value).\n");
    if let Some(o) = observers {
        let _ = writeln!(
            t,
            "-- Observers (names no recording shows) from {}.",
            o.file.display()
        );
    }
    t.push_str("-- Structure (each sensor's next value depends on):\n");
    for p in &learned.parts {
        let names = |h: &Half| -> String {
            let n: Vec<&str> = h.depends[1..]
                .iter()
                .map(|&f| runs.signal_name(f))
                .collect();
            match n.is_empty() {
                true => "nothing".into(),
                false => n.join(", "),
            }
        };
        let bound = (p.halves.iter()).any(|h| (h.rules.iter()).any(|(c, r)| r.forces(c[0])));
        let kind = match (p.free_start, p.wait_cap) {
            (true, _) if bound => {
                " (the environment's: free where seen changing, bound where it always came)"
            }
            (true, _) => " (the environment's: free where seen changing)",
            (false, 0) => "",
            (false, _) => " (delayed)",
        };
        let held = match p.valve {
            Some(v) => format!(
                "; through {}, which the pulses of {} and {} open and close",
                valve(runs, p.sensor),
                runs.outputs[v.open],
                runs.outputs[v.close]
            ),
            None => String::new(),
        };
        let _ = writeln!(
            t,
            "--   {}: rises on {}; falls on {}{kind}{held}",
            runs.inputs[p.sensor],
            names(&p.halves[0]),
            names(&p.halves[1])
        );
    }
}

fn init(t: &mut String, learned: &Learned, runs: &Runs) {
    // One `init` per sensor (not an `INIT` over all): the in-process checker reads these.
    let fixed = (learned.parts.iter()).filter(|p| !p.free_start).enumerate();
    for (k, p) in fixed {
        let values: BTreeSet<bool> = learned.starts.iter().map(|v| v[k]).collect();
        let value = match (values.contains(&false), values.contains(&true)) {
            (true, false) => "FALSE",
            (false, true) => "TRUE",
            _ => continue,
        };
        let _ = writeln!(t, "    init({}) := {value};", runs.inputs[p.sensor]);
        if p.valve.is_some() {
            let _ = writeln!(t, "    init({}) := {value};", valve(runs, p.sensor));
        }
    }
}

/// The valves' `DEFINE`s: whether each is open after this scan's commands (what it keeps
/// for the next scan, [`next`]).
fn valves(t: &mut String, learned: &Learned, runs: &Runs) {
    let held: Vec<(&Part, Valve)> = (learned.parts.iter())
        .filter_map(|p| p.valve.map(|v| (p, v)))
        .collect();
    if held.is_empty() {
        return;
    }
    t.push_str("DEFINE\n");
    for (p, v) in &held {
        let (open, close) = (&runs.outputs[v.open], &runs.outputs[v.close]);
        let _ = writeln!(
            t,
            "    {} := {open} & !{close} | {} & !({close} & !{open});",
            opened(runs, p.sensor),
            valve(runs, p.sensor)
        );
    }
}

/// The name of the valve that sensor `x` follows.
fn valve(runs: &Runs, x: usize) -> String {
    hidden(runs, format!("valve_{}", runs.inputs[x]))
}

/// The name of "the valve of sensor `x` is open after this scan's commands".
fn opened(runs: &Runs, x: usize) -> String {
    hidden(runs, format!("open_{}", runs.inputs[x]))
}

/// The name of the dwell counter of half `v` (rise: FALSE) of sensor `x`.
fn counter(runs: &Runs, x: usize, v: bool) -> String {
    let name = &runs.inputs[x];
    hidden(
        runs,
        match v {
            false => format!("wait_up_{name}"),
            true => format!("wait_down_{name}"),
        },
    )
}

/// `name`, made unlike every sensor and controller output (an output called `valve_vac`
/// would otherwise be declared twice).
fn hidden(runs: &Runs, mut name: String) -> String {
    while runs.inputs.contains(&name) || runs.outputs.contains(&name) {
        name.push('_');
    }
    name
}

fn next(t: &mut String, p: &Part, runs: &Runs) {
    let name = &runs.inputs[p.sensor];
    if p.valve.is_some() {
        let (valve, opened) = (valve(runs, p.sensor), opened(runs, p.sensor));
        let _ = writeln!(t, "    next({valve}) := {opened};");
    }
    let _ = writeln!(t, "    next({name}) := case");
    for (v, h) in [false, true].into_iter().zip(&p.halves) {
        let wait = counter(runs, p.sensor, v);
        for (c, rule) in &h.rules {
            let ctx = context(p, h, c, runs, false);
            let early = context(p, h, c, runs, true);
            match *rule {
                Rule::To(to) if to == v => {}
                Rule::To(to) => {
                    let _ = writeln!(t, "        {ctx} : {};", constant(to));
                    // In the same scan as the sensors it waits for, the change may come; where
                    // they held, each in this scan or the next, but will not all hold in the
                    // next (the cup gripped as it left), it comes now.
                    if early != ctx {
                        let held = arrived(h, c, runs);
                        let _ = writeln!(t, "        {early} & !({held}) : {};", constant(to));
                        let _ = writeln!(t, "        {early} : {{FALSE, TRUE}};");
                    }
                }
                Rule::Free => {
                    let _ = writeln!(t, "        {early} : {{FALSE, TRUE}};");
                }
                Rule::Within(least, most) => {
                    if least > 0 {
                        let _ = writeln!(t, "        {ctx} & {wait} < {least} : {};", constant(v));
                    }
                    let _ = writeln!(t, "        {ctx} & {wait} >= {most} : {};", constant(!v));
                    let _ = writeln!(t, "        {early} : {{FALSE, TRUE}};");
                }
            }
        }
    }
    let _ = writeln!(t, "        TRUE : {name};\n    esac;");
    for (v, h) in [false, true].into_iter().zip(&p.halves) {
        let cap = h.wait_cap();
        if cap == 0 {
            continue;
        }
        let wait = counter(runs, p.sensor, v);
        let delayed: Vec<String> = (h.rules.iter())
            .filter(|(_, r)| matches!(r, Rule::Within(..)))
            .map(|(c, _)| context(p, h, c, runs, false))
            .collect();
        let any = delayed.join(" | ");
        // Counts the scans the sensor spent with this value in a delayed context; after a
        // change the sensor has the other value, and the count restarts.
        let _ = writeln!(t, "    init({wait}) := 0;");
        let _ = writeln!(t, "    next({wait}) := case");
        let _ = writeln!(t, "        ({any}) & {wait} < {cap} : {wait} + 1;");
        let _ = writeln!(t, "        ({any}) : {cap};");
        let _ = writeln!(t, "        TRUE : 0;\n    esac;");
    }
}

/// The literals of context `c` (with its scene) of half `h` read by the next scan: each
/// sensor of [`Half::early`] at its value in `next(..)`.
fn arrived(h: &Half, c: &[bool], runs: &Runs) -> String {
    let lits: Vec<String> = (literals(h, c).into_iter())
        .filter(|(f, _)| h.early.contains(f))
        .map(|(f, v)| literal(&format!("next({})", runs.signal_name(f)), v))
        .collect();
    lits.join(" & ")
}

/// The scene of context `c` of half `h` ([`Half::scenes`]): none where the change is not
/// bound.
fn scene<'h>(h: &'h Half, c: &[bool]) -> &'h [(usize, bool)] {
    (h.scenes.iter())
        .find(|(k, _)| k == c)
        .map_or(&[], |(_, s)| s.as_slice())
}

/// The literals of context `c` of half `h`, then of its scene.
fn literals(h: &Half, c: &[bool]) -> Vec<(usize, bool)> {
    let mut lits: Vec<(usize, bool)> = h.depends.iter().copied().zip(c.iter().copied()).collect();
    lits.extend_from_slice(scene(h, c));
    lits
}

/// The context `c` of half `h` of part `p` as a conjunction, with its scene; a part behind a
/// valve reads it where its halves read the commands that set it ([`Valve::held`]). With
/// `early`, a sensor of [`Half::early`] has its value in it now or in the next scan.
fn context(p: &Part, h: &Half, c: &[bool], runs: &Runs, early: bool) -> String {
    let n = runs.inputs.len();
    let lits: Vec<String> = (literals(h, c).into_iter())
        .map(|(f, v)| match (p.valve, f.checked_sub(n)) {
            (Some(valve), Some(z)) if z == valve.open => literal(&opened(runs, p.sensor), v),
            (Some(valve), Some(z)) if z == valve.close => literal(&opened(runs, p.sensor), !v),
            _ if early && h.early.contains(&f) => {
                let name = runs.signal_name(f);
                format!(
                    "({} | {})",
                    literal(name, v),
                    literal(&format!("next({name})"), v)
                )
            }
            _ => literal(runs.signal_name(f), v),
        })
        .collect();
    lits.join(" & ")
}

fn literal(name: &str, v: bool) -> String {
    match v {
        true => name.to_string(),
        false => format!("!{name}"),
    }
}

fn constant(v: bool) -> &'static str {
    match v {
        true => "TRUE",
        false => "FALSE",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn with_slack_a_bound_change_whose_gates_held_a_scan_apart_comes_by_the_next_scan() {
        let runs = Runs {
            inputs: vec!["piece".into(), "held".into(), "over".into(), "hood".into()],
            outputs: vec![],
            runs: vec![],
        };
        let keep = Half {
            depends: vec![0],
            driver: None,
            rules: vec![(vec![false], Rule::Free)],
            early: vec![],
            scenes: vec![],
        };
        // Taken where the cup holds it over the track, with the hood down as at every
        // recorded scan there; the cup and the hood may arrive in the scan it leaves.
        let taken = Half {
            depends: vec![0, 1, 2],
            driver: None,
            rules: vec![(vec![true; 3], Rule::To(false))],
            early: vec![1, 2, 3],
            scenes: vec![(vec![true; 3], vec![(3, true)])],
        };
        let part = Part {
            sensor: 0,
            halves: [keep, taken],
            wait_cap: 0,
            free_start: true,
            valve: None,
        };
        let mut t = String::new();
        next(&mut t, &part, &runs);
        let held = "piece & (held | next(held)) & (over | next(over)) & (hood | next(hood))";
        let lines = [
            "        !piece : {FALSE, TRUE};".to_string(),
            "        piece & held & over & hood : FALSE;".into(),
            format!("        {held} & !(next(held) & next(over) & next(hood)) : FALSE;"),
            format!("        {held} : {{FALSE, TRUE}};"),
            "        TRUE : piece;".into(),
        ];
        let body: Vec<&str> = t.lines().skip(1).take(lines.len()).collect();
        assert_eq!(body, lines, "{t}");
    }
}
