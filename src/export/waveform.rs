//! A counterexample as an engineer reads it: a table of steps, a VCD waveform (GTKWave and
//! every logic-analyzer viewer open it) and an SVG picture of the same waveform.
//!
//! In: a [`Waveform`], the signals of a closed-loop lasso step by step (built from NuSMV's
//! trace by [`crate::verify::Counterexample::waveform`]). Out: text in each form, pure and
//! byte-for-byte stable ([`table`], [`vcd`], [`svg`]).
//!
//! A lasso is a finite prefix and a loop that repeats forever: every form marks the step the
//! loop returns to, and the VCD and SVG draw the loop once more after the last step, so the
//! repetition is visible.

use crate::ecc::ident::{parse_smv_value, SmvValue};
use crate::files::xml::escape_attr;
use std::fmt::Write;

/// Where a signal belongs in the closed loop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Group {
    /// A controller input (a plant value the controller reads).
    Input,
    /// A controller output.
    Output,
    /// The controller's state.
    State,
    /// A variable of the plant model that is not a controller input.
    Plant,
}

impl Group {
    fn label(self) -> &'static str {
        match self {
            Group::Input => "in",
            Group::Output => "out",
            Group::State => "ctrl",
            Group::Plant => "plant",
        }
    }
}

/// One value of a signal at one step.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Value {
    /// `TRUE` or `FALSE`.
    Bool(bool),
    /// A bounded integer.
    Int(i64),
    /// An enumeration value or a controller state name.
    Text(String),
    /// Not printed in the trace.
    Unknown,
}

impl Value {
    /// A value as NuSMV prints it: `TRUE`/`FALSE`, an integer, or a symbol
    /// ([`parse_smv_value`]).
    pub(crate) fn parse(text: &str) -> Value {
        match parse_smv_value(text) {
            SmvValue::Bool(b) => Value::Bool(b),
            SmvValue::Int(i) => Value::Int(i),
            SmvValue::Symbol(s) => Value::Text(s.to_string()),
        }
    }

    fn short(&self) -> String {
        match self {
            Value::Bool(b) => u8::from(*b).to_string(),
            Value::Int(i) => i.to_string(),
            Value::Text(t) => t.clone(),
            Value::Unknown => "?".into(),
        }
    }
}

/// One signal along the lasso.
#[derive(Debug, Clone)]
pub(crate) struct Signal {
    /// Where it comes from, which orders the rows.
    pub(crate) group: Group,
    /// Its name in the closed loop.
    pub(crate) name: String,
    /// A value per step.
    pub(crate) values: Vec<Value>,
}

/// The signals of a lasso-shaped run: steps `0..steps`, after which the run goes on at
/// `loop_start` forever.
#[derive(Debug, Clone)]
pub(crate) struct Waveform {
    /// What the run is a counterexample of (a property name).
    pub(crate) title: String,
    /// The rows, in display order.
    pub(crate) signals: Vec<Signal>,
    /// Steps in the prefix and the loop together.
    pub(crate) steps: usize,
    /// The step the run returns to after the last one.
    pub(crate) loop_start: usize,
}

impl Waveform {
    /// Step `i` of the endless run (`i` may pass the last step: the loop repeats).
    fn step_of(&self, i: usize) -> usize {
        let period = (self.steps - self.loop_start).max(1);
        match i < self.steps {
            true => i,
            false => self.loop_start + (i - self.steps) % period,
        }
    }

    /// Steps drawn in the VCD and SVG: the lasso and its loop once more.
    fn drawn(&self) -> usize {
        self.steps + (self.steps - self.loop_start)
    }
}

/// The run as a table, a signal a row and a step a column, the loop marked under the step
/// numbers:
///
/// ```text
/// counterexample of p (4 steps; steps 1-3 repeat forever)
///       step      0  1  2  3
///       loop         ^  ^  ^
/// in    button    0  1  0  0
/// ```
pub(crate) fn table(w: &Waveform) -> String {
    let cells: Vec<Vec<String>> = w
        .signals
        .iter()
        .map(|s| s.values.iter().map(Value::short).collect())
        .collect();
    let width = (cells.iter().flatten())
        .map(|c| c.chars().count())
        .chain([w.steps.saturating_sub(1).to_string().len()])
        .max()
        .unwrap_or(1)
        + 1;
    let label = w
        .signals
        .iter()
        .map(|s| s.name.chars().count())
        .max()
        .unwrap_or(0)
        .max(4);
    let mut out = String::new();
    let last = w.steps.saturating_sub(1);
    let repeat = match w.loop_start == last {
        true => format!("step {last} repeats"),
        false => format!("steps {}-{last} repeat", w.loop_start),
    };
    let _ = writeln!(
        out,
        "counterexample of {} ({} steps; {repeat} forever)",
        w.title, w.steps
    );
    let head = |out: &mut String, group: &str, name: &str| {
        let _ = write!(out, "{group:<6}{name:<label$}");
    };
    head(&mut out, "", "step");
    for i in 0..w.steps {
        let _ = write!(out, "{i:>width$}");
    }
    out.push('\n');
    head(&mut out, "", "loop");
    for i in 0..w.steps {
        let _ = write!(out, "{:>width$}", if i >= w.loop_start { "^" } else { "" });
    }
    out.push('\n');
    for (s, row) in w.signals.iter().zip(&cells) {
        head(&mut out, s.group.label(), &s.name);
        for c in row {
            let _ = write!(out, "{c:>width$}");
        }
        out.push('\n');
    }
    out
}

/// The VCD identifier of the `k`th signal: printable ASCII from `!`, in base 94.
fn vcd_id(mut k: usize) -> String {
    let mut id = String::new();
    loop {
        id.push(char::from(b'!' + (k % 94) as u8));
        k /= 94;
        if k == 0 {
            return id;
        }
        k -= 1;
    }
}

/// A VCD name: VCD separates tokens by whitespace, so none may hold any.
fn vcd_name(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_whitespace() { '_' } else { c })
        .collect()
}

/// The run as a Value Change Dump (IEEE 1364 §18): one time unit per step (a PLC scan), a
/// scope per [`Group`], Boolean signals as 1-bit wires, integers and controller states as
/// 32-bit integers (a state `sK` as `K`), and a wire `in_loop` that is 1 from the loop start
/// on. The loop is drawn once more after the last step.
pub(crate) fn vcd(w: &Waveform) -> String {
    let mut out = String::new();
    out.push_str("$version fbsynth counterexample $end\n");
    let _ = writeln!(
        out,
        "$comment {} ; one time unit is one step (scan) ; the run loops back to step {} after step {} $end",
        vcd_name(&w.title),
        w.loop_start,
        w.steps.saturating_sub(1)
    );
    // The kind of each signal: a wire when every value is Boolean, else an integer.
    let wire: Vec<bool> = (w.signals.iter())
        .map(|s| (s.values.iter()).all(|v| matches!(v, Value::Bool(_) | Value::Unknown)))
        .collect();
    vcd_declarations(&mut out, w, &wire);
    vcd_changes(&mut out, w, &wire);
    out
}

/// The VCD header's scopes and variables: one scope per [`Group`], then `in_loop`.
fn vcd_declarations(out: &mut String, w: &Waveform, wire: &[bool]) {
    out.push_str("$timescale 1 ms $end\n$scope module closed_loop $end\n");
    let mut current: Option<Group> = None;
    for (k, s) in w.signals.iter().enumerate() {
        if current != Some(s.group) {
            if current.is_some() {
                out.push_str("$upscope $end\n");
            }
            let _ = writeln!(out, "$scope module {} $end", s.group.label());
            current = Some(s.group);
        }
        let (kind, bits) = if wire[k] {
            ("wire", 1)
        } else {
            ("integer", 32)
        };
        let (id, name) = (vcd_id(k), vcd_name(&s.name));
        let _ = writeln!(out, "$var {kind} {bits} {id} {name} $end");
    }
    if current.is_some() {
        out.push_str("$upscope $end\n");
    }
    let loop_id = vcd_id(w.signals.len());
    let _ = writeln!(out, "$var wire 1 {loop_id} in_loop $end");
    out.push_str("$upscope $end\n$enddefinitions $end\n");
}

/// The VCD body: the values at time 0 (`$dumpvars`), then each change, one time unit per
/// drawn step.
fn vcd_changes(out: &mut String, w: &Waveform, wire: &[bool]) {
    let loop_id = vcd_id(w.signals.len());
    for i in 0..w.drawn() {
        let step = w.step_of(i);
        let _ = writeln!(out, "#{i}");
        if i == 0 {
            out.push_str("$dumpvars\n");
        }
        for (k, s) in w.signals.iter().enumerate() {
            let v = &s.values[step];
            if i == 0 || s.values[w.step_of(i - 1)] != *v {
                let _ = writeln!(out, "{}", vcd_value(&vcd_id(k), wire[k], v));
            }
        }
        if i == 0 || i == w.loop_start {
            let _ = writeln!(out, "{}{loop_id}", u8::from(i >= w.loop_start));
        }
        if i == 0 {
            out.push_str("$end\n");
        }
    }
    let _ = writeln!(out, "#{}", w.drawn());
}

/// One value change of the signal `id`: a wire's bit, or an integer's binary digits (a
/// controller state `sK` as `K`); `x` where unknown.
fn vcd_value(id: &str, wire: bool, v: &Value) -> String {
    match (wire, v) {
        (true, Value::Bool(b)) => format!("{}{id}", u8::from(*b)),
        (true, _) => format!("x{id}"),
        (false, Value::Bool(b)) => format!("b{} {id}", u8::from(*b)),
        (false, Value::Int(i)) => format!("b{:b} {id}", *i as u32),
        (false, Value::Text(t)) => match state_number(t) {
            Some(n) => format!("b{n:b} {id}"),
            None => format!("bx {id}"),
        },
        (false, Value::Unknown) => format!("bx {id}"),
    }
}

/// `K` of a controller state named `sK`.
fn state_number(name: &str) -> Option<u32> {
    name.strip_prefix('s')?.parse().ok()
}

/// Pixels of one step, one signal row, and the name column.
const STEP: usize = 36;
const ROW: usize = 26;
const NAMES: usize = 170;

/// The run as an SVG waveform: a row per signal (Booleans as high/low lines, other values as
/// labelled boxes), step numbers on top, the loop shaded and drawn once more, dashed, after
/// the last step.
pub(crate) fn svg(w: &Waveform) -> String {
    let drawn = w.drawn();
    let width = NAMES + STEP * drawn + 20;
    let height = ROW * (w.signals.len() + 2) + 10;
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="monospace" font-size="12">"#
    );
    let _ = writeln!(
        out,
        r#"<title>counterexample of {}</title>"#,
        escape_attr(&w.title)
    );
    // The loop, shaded: the lasso's own steps, then the repetition.
    let _ = writeln!(
        out,
        r##"<rect x="{}" y="{}" width="{}" height="{}" fill="#eef4ff"/>"##,
        step_x(w.loop_start),
        ROW,
        STEP * (drawn - w.loop_start),
        ROW * (w.signals.len() + 1)
    );
    let _ = writeln!(
        out,
        r##"<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#7a8fb8" stroke-dasharray="4 3"/>"##,
        step_x(w.steps),
        ROW,
        ROW * (w.signals.len() + 2)
    );
    let _ = writeln!(
        out,
        r#"<text x="{}" y="{}">loop back to step {}</text>"#,
        step_x(w.steps) + 4,
        ROW - 8,
        w.loop_start
    );
    for i in 0..drawn {
        let _ = writeln!(
            out,
            r##"<text x="{}" y="{}" text-anchor="middle" fill="#555">{}</text>"##,
            step_x(i) + STEP / 2,
            2 * ROW - 8,
            w.step_of(i)
        );
    }
    for (r, s) in w.signals.iter().enumerate() {
        let top = ROW * (r + 2);
        let _ = writeln!(
            out,
            r#"<text x="4" y="{}">{} {}</text>"#,
            top + ROW / 2 + 4,
            s.group.label(),
            escape_attr(&s.name)
        );
        let boolean = (s.values.iter()).all(|v| matches!(v, Value::Bool(_) | Value::Unknown));
        match boolean {
            true => boolean_row(&mut out, w, s, top),
            false => value_boxes(&mut out, w, s, top),
        }
    }
    out.push_str("</svg>\n");
    out
}

/// The x coordinate where drawn step `i` begins.
fn step_x(i: usize) -> usize {
    NAMES + STEP * i
}

/// A Boolean signal's row at `top`: a line, high where it is true.
fn boolean_row(out: &mut String, w: &Waveform, s: &Signal, top: usize) {
    let (high, low) = (top + 5, top + ROW - 5);
    let mut points = String::new();
    for i in 0..w.drawn() {
        let y = match s.values[w.step_of(i)] {
            Value::Bool(true) => high,
            _ => low,
        };
        let _ = write!(points, "{},{y} {},{y} ", step_x(i), step_x(i + 1));
    }
    let _ = writeln!(
        out,
        r##"<polyline points="{}" fill="none" stroke="#1a4fa0" stroke-width="1.5"/>"##,
        points.trim_end()
    );
}

/// Another signal's row at `top`: a box per run of equal values, labelled with the value (a
/// run ends where the loop's repetition begins).
fn value_boxes(out: &mut String, w: &Waveform, s: &Signal, top: usize) {
    let drawn = w.drawn();
    let mut i = 0;
    while i < drawn {
        let v = &s.values[w.step_of(i)];
        let mut j = i + 1;
        while j < drawn && s.values[w.step_of(j)] == *v && j != w.steps {
            j += 1;
        }
        let _ = writeln!(
            out,
            r##"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#1a4fa0"/>"##,
            step_x(i) + 1,
            top + 5,
            STEP * (j - i) - 2,
            ROW - 10
        );
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
            step_x(i) + STEP * (j - i) / 2,
            top + ROW / 2 + 4,
            escape_attr(&v.short())
        );
        i = j;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lamp whose button is pressed at step 1 and which never lights: steps 1-2 repeat.
    fn sample() -> Waveform {
        let b = Value::Bool;
        Waveform {
            title: "lights".into(),
            signals: vec![
                Signal {
                    group: Group::Input,
                    name: "button".into(),
                    values: vec![b(false), b(true), b(false)],
                },
                Signal {
                    group: Group::Output,
                    name: "lamp".into(),
                    values: vec![b(false), b(false), b(false)],
                },
                Signal {
                    group: Group::State,
                    name: "state".into(),
                    values: vec![
                        Value::Text("s0".into()),
                        Value::Text("s1".into()),
                        Value::Text("s1".into()),
                    ],
                },
                Signal {
                    group: Group::Plant,
                    name: "on_for".into(),
                    values: vec![Value::Int(0), Value::Int(2), Value::Int(2)],
                },
            ],
            steps: 3,
            loop_start: 1,
        }
    }

    #[test]
    fn table() {
        insta::assert_snapshot!(super::table(&sample()));
    }

    #[test]
    fn vcd() {
        insta::assert_snapshot!(super::vcd(&sample()));
    }

    #[test]
    fn svg() {
        insta::assert_snapshot!(super::svg(&sample()));
    }

    #[test]
    fn values_as_nusmv_prints_them() {
        assert_eq!(Value::parse("TRUE"), Value::Bool(true));
        assert_eq!(Value::parse("-3"), Value::Int(-3));
        assert_eq!(Value::parse("s4"), Value::Text("s4".into()));
    }

    #[test]
    fn vcd_identifiers_are_distinct_printable_and_short() {
        let ids: Vec<String> = (0..10_000).map(vcd_id).collect();
        let distinct: std::collections::HashSet<&String> = ids.iter().collect();
        assert_eq!(distinct.len(), ids.len());
        assert!(ids
            .iter()
            .flat_map(|i| i.bytes())
            .all(|b| (33..=126).contains(&b)));
        assert_eq!(ids[93], "~");
        assert_eq!(ids[94].len(), 2);
    }

    #[test]
    fn the_loop_repeats_after_the_last_step() {
        let w = sample();
        let steps: Vec<usize> = (0..w.drawn()).map(|i| w.step_of(i)).collect();
        assert_eq!(steps, [0, 1, 2, 1, 2]);
    }
}
