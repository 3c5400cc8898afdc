//! IEC 61499 basic function block type (`.fbt`) of an ECC, as XML after the IEC 61499-2
//! `LibraryElement.dtd`, for Eclipse 4diac IDE and Schneider NxtStudio.
//!
//! In: a valid [`Ecc`] and [`FbtOptions`]. Out: one `<FBType>` with
//! - the interface: event input `REQ` associated (`<With>`) with every input variable, event
//!   output `CNF` associated with every output variable, all variables `BOOL`, outputs that
//!   start TRUE with `InitialValue="TRUE"`;
//! - the ECC: state 0 is the first `<ECState>`, named `START` (4diac's convention for the
//!   initial state), state `i > 0` is named `s{i}`; every state emits `CNF` on entry and runs
//!   its algorithm `ALG_<state>` if the algorithm changes anything. Transitions of a state
//!   appear in priority order (4diac and the standard give document order priority), with
//!   condition `REQ[<guard in ST>]`, or `REQ` for a `TRUE` guard. States sit on a grid so the
//!   chart is readable when opened;
//! - one `<Algorithm>` in ST per state that changes something: `z := TRUE;`, `z := FALSE;`,
//!   `z := NOT z;` per changed output (kept outputs get no line).
//!
//! The file is deterministic: the `VersionInfo` date comes from the options, never the clock.
//! An ECC without transitions gets one that never fires (`START` to itself on
//! `REQ[FALSE]`, with a comment saying so): the DTD needs at least one (`ECTransition+`).

use super::{check_iec_names, NameError};
use crate::ecc::Effect;
use crate::ecc::{Ecc, Guard};
use crate::files::xml::XmlWriter;
use crate::smv::bool_literal;
use std::io::{self, Write};

/// The condition of the transition an ECC without transitions gets, which never fires.
const NEVER: &str = "REQ[FALSE]";

/// Options of the `.fbt` export.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct FbtOptions {
    /// Name of the FB type; an IEC 61131-3 identifier. 4diac expects the file to be named
    /// `<type_name>.fbt`.
    pub(crate) type_name: String,
    /// `Date` of `VersionInfo`, e.g. `2024-05-31`; empty by default so output stays
    /// reproducible.
    pub(crate) date: String,
}

impl Default for FbtOptions {
    fn default() -> FbtOptions {
        FbtOptions {
            type_name: "SynthesizedFB".into(),
            date: String::new(),
        }
    }
}

/// Layout grid: distance between state columns and rows, in the file's coordinate units.
const GRID_X: i64 = 1000;
const GRID_Y: i64 = 600;
/// Position of state 0.
const ORIGIN: i64 = 300;
/// Distance between labels of transitions that would otherwise sit on the same spot.
const LABEL_STEP: i64 = 100;

/// The `<ECState>` name of state `i`.
pub(crate) fn state_name(i: usize) -> String {
    if i == 0 {
        "START".into()
    } else {
        format!("s{i}")
    }
}

/// The `<Algorithm>` name of state `i`.
pub(crate) fn algorithm_name(i: usize) -> String {
    format!("ALG_{}", state_name(i))
}

/// Checks the type name and the interface names (IEC identifiers, distinct ignoring case, none
/// equal to an event or algorithm name of the block). State names live apart: no expression
/// can mention a state, so an input may be called `start`.
pub(crate) fn check_names(ecc: &Ecc, type_name: &str) -> Result<(), NameError> {
    let mut reserved = vec!["REQ".to_string(), "CNF".to_string()];
    reserved.extend((0..ecc.states.len()).map(algorithm_name));
    check_iec_names(ecc, "an IEC 61499 .fbt file", type_name, &reserved)
}

/// Grid position of state `i` among `count`: as many columns as rows, filled row by row.
fn position(i: usize, count: usize) -> (i64, i64) {
    let cols = (1..=count).find(|c| c * c >= count).unwrap_or(1);
    let (col, row) = ((i % cols) as i64, (i / cols) as i64);
    // The margin leaves room for the labels of self-loops above the first row.
    (ORIGIN + col * GRID_X, ORIGIN + row * GRID_Y)
}

/// The ST body of a state's algorithm, or `None` if it changes nothing.
fn algorithm_text(ecc: &Ecc, i: usize) -> Option<String> {
    let lines: Vec<String> = Effect::all(&ecc.states[i].algorithm)
        .into_iter()
        .zip(&ecc.outputs)
        .filter_map(|(e, z)| match e {
            Effect::Keep => None,
            Effect::Set(v) => Some(format!("{z} := {};", bool_literal(v))),
            Effect::Flip => Some(format!("{z} := NOT {z};")),
        })
        .collect();
    (!lines.is_empty()).then(|| lines.join("\n"))
}

/// Writes the `.fbt` file; fails with [`io::ErrorKind::InvalidInput`] (wrapping a
/// [`NameError`]) before writing anything if a name is unusable.
pub(crate) fn write_fbt(ecc: &Ecc, options: &FbtOptions, w: &mut impl Write) -> io::Result<()> {
    check_names(ecc, &options.type_name)?;
    let comment = format!("Basic FB synthesized by fbsynth ({})", ecc.size());
    let mut x = XmlWriter::new(w);
    write_head(
        &mut x,
        &options.type_name,
        &comment,
        &options.date,
        [&ecc.inputs, &ecc.outputs],
        &ecc.initial_outputs,
        [
            "Request: fire the first enabled transition of the current state",
            "Confirmation: a transition fired, outputs updated",
        ],
    )?;

    x.open(1, "BasicFB", &[])?;
    x.open(2, "ECC", &[])?;
    let algorithms: Vec<Option<String>> = (0..ecc.states.len())
        .map(|i| algorithm_text(ecc, i))
        .collect();
    write_states(&mut x, ecc, &algorithms)?;
    write_transitions(&mut x, ecc)?;
    x.close(2, "ECC")?;
    for (i, text) in algorithms.iter().enumerate() {
        if let Some(text) = text {
            x.open(2, "Algorithm", &[("Name", &algorithm_name(i))])?;
            x.leaf(3, "ST", &[("Text", text)])?;
            x.close(2, "Algorithm")?;
        }
    }
    x.close(1, "BasicFB")?;
    x.close(0, "FBType")
}

/// One `<ECState>` per state, on the layout's grid, with the action of its algorithm (if it
/// has one, `algorithms[i]`) and `CNF`.
fn write_states(
    x: &mut XmlWriter<impl Write>,
    ecc: &Ecc,
    algorithms: &[Option<String>],
) -> io::Result<()> {
    let count = ecc.states.len();
    for (i, s) in ecc.states.iter().enumerate() {
        let name = state_name(i);
        // Keep a name the user gave a state as its comment; `s{i}` is no such name.
        let default_name = s.name == name || s.name == format!("s{i}");
        let comment = match (i, default_name) {
            (0, true) => "Initial state".to_string(),
            (0, false) => format!("Initial state ({})", s.name),
            (_, true) => String::new(),
            (_, false) => s.name.clone(),
        };
        let (px, py) = position(i, count);
        let (px, py) = (px.to_string(), py.to_string());
        let mut attrs = vec![("Name", name.as_str())];
        if !comment.is_empty() {
            attrs.push(("Comment", &comment));
        }
        attrs.extend([("x", px.as_str()), ("y", py.as_str())]);
        x.open(3, "ECState", &attrs)?;
        let algorithm = algorithm_name(i);
        match algorithms[i] {
            Some(_) => x.leaf(
                4,
                "ECAction",
                &[("Algorithm", &algorithm), ("Output", "CNF")],
            )?,
            None => x.leaf(4, "ECAction", &[("Output", "CNF")])?,
        }
        x.close(3, "ECState")?;
    }
    Ok(())
}

/// One `<ECTransition>` per transition with its guard as the `REQ[...]` condition; a machine
/// without any gets one that never fires, since the DTD needs at least one (`ECTransition+`).
fn write_transitions(x: &mut XmlWriter<impl Write>, ecc: &Ecc) -> io::Result<()> {
    let count = ecc.states.len();
    // A label sits at the middle of its edge, or above the state for a self-loop. Labels that
    // would land on the same spot (both directions between two states, crossing diagonals) are
    // moved one step each: down, or up for self-loops, away from the state.
    let mut on_spot: std::collections::HashMap<(i64, i64), i64> = Default::default();
    for (i, s) in ecc.states.iter().enumerate() {
        for t in &s.transitions {
            let j = t.target.0;
            let ((x1, y1), (x2, y2)) = (position(i, count), position(j, count));
            let (spot, step) = if i == j {
                ((x1 + GRID_X / 4, y1 - GRID_Y / 3), -LABEL_STEP)
            } else {
                (((x1 + x2) / 2, (y1 + y2) / 2), LABEL_STEP)
            };
            let k = on_spot.entry(spot).or_insert(0);
            let (lx, ly) = (spot.0.to_string(), (spot.1 + *k * step).to_string());
            *k += 1;
            let condition = match &t.guard {
                Guard::True => "REQ".to_string(),
                g => format!("REQ[{}]", g.display_st(&ecc.inputs)),
            };
            x.leaf(
                3,
                "ECTransition",
                &[
                    ("Source", &state_name(i)),
                    ("Destination", &state_name(j)),
                    ("Condition", &condition),
                    ("x", &lx),
                    ("y", &ly),
                ],
            )?;
        }
    }
    if ecc.states.iter().all(|s| s.transitions.is_empty()) {
        let (px, py) = position(0, count);
        x.leaf(
            3,
            "ECTransition",
            &[
                ("Source", &state_name(0)),
                ("Destination", &state_name(0)),
                ("Condition", NEVER),
                ("Comment", "Never fires: the machine has no transitions"),
                ("x", &(px + GRID_X / 4).to_string()),
                ("y", &(py - GRID_Y / 3).to_string()),
            ],
        )?;
    }
    Ok(())
}

/// The XML prolog, `<FBType>` start tag, identification and `<InterfaceList>` (REQ with every
/// input, CNF with every output, all `BOOL`): the part basic and composite types share.
pub(crate) fn write_head(
    x: &mut XmlWriter<impl Write>,
    type_name: &str,
    comment: &str,
    date: &str,
    [inputs, outputs]: [&[String]; 2],
    initial_outputs: &[bool],
    [req_comment, cnf_comment]: [&str; 2],
) -> io::Result<()> {
    x.declaration()?;
    x.doctype(r#"FBType SYSTEM "http://www.holobloc.com/xml/LibraryElement.dtd""#)?;
    x.open(0, "FBType", &[("Name", type_name), ("Comment", comment)])?;
    x.leaf(1, "Identification", &[("Standard", "61499-2")])?;
    x.leaf(
        1,
        "VersionInfo",
        &[
            ("Organization", "fbsynth"),
            ("Version", "1.0"),
            ("Author", "fbsynth"),
            ("Date", date),
        ],
    )?;

    x.open(1, "InterfaceList", &[])?;
    let events = [
        ("EventInputs", "REQ", req_comment, inputs),
        ("EventOutputs", "CNF", cnf_comment, outputs),
    ];
    for (list, event, comment, vars) in events {
        x.open(2, list, &[])?;
        x.open(
            3,
            "Event",
            &[("Name", event), ("Type", "Event"), ("Comment", comment)],
        )?;
        for v in vars.iter() {
            x.leaf(4, "With", &[("Var", v)])?;
        }
        x.close(3, "Event")?;
        x.close(2, list)?;
    }
    // The DTD wants at least one declaration inside InputVars/OutputVars.
    if !inputs.is_empty() {
        x.open(2, "InputVars", &[])?;
        for v in inputs {
            x.leaf(3, "VarDeclaration", &[("Name", v), ("Type", "BOOL")])?;
        }
        x.close(2, "InputVars")?;
    }
    if !outputs.is_empty() {
        x.open(2, "OutputVars", &[])?;
        for (v, &init) in outputs.iter().zip(initial_outputs) {
            let mut attrs = vec![("Name", v.as_str()), ("Type", "BOOL")];
            if init {
                attrs.push(("InitialValue", "TRUE"));
            }
            x.leaf(3, "VarDeclaration", &attrs)?;
        }
        x.close(2, "OutputVars")?;
    }
    x.close(1, "InterfaceList")
}

/// [`write_fbt`] into a string.
pub(crate) fn to_string(ecc: &Ecc, options: &FbtOptions) -> io::Result<String> {
    let mut buf = Vec::new();
    write_fbt(ecc, options, &mut buf)?;
    Ok(String::from_utf8(buf).expect("the .fbt emitter writes UTF-8 only"))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::export::samples;
    use quick_xml::events::{BytesStart, Event};
    use std::collections::HashSet;

    /// Just enough of a DOM to check structure.
    #[derive(Debug)]
    pub(crate) struct Node {
        pub(crate) name: String,
        pub(crate) attrs: Vec<(String, String)>,
        pub(crate) children: Vec<Node>,
    }

    impl Node {
        pub(crate) fn attr(&self, key: &str) -> Option<&str> {
            self.attrs
                .iter()
                .find(|(k, _)| k == key)
                .map(|(_, v)| v.as_str())
        }

        pub(crate) fn all(&self, name: &str) -> Vec<&Node> {
            self.children.iter().filter(|c| c.name == name).collect()
        }

        pub(crate) fn one(&self, name: &str) -> &Node {
            let found = self.all(name);
            assert_eq!(found.len(), 1, "exactly one <{name}> in <{}>", self.name);
            found[0]
        }
    }

    fn node(e: &BytesStart<'_>) -> Node {
        Node {
            name: String::from_utf8(e.name().as_ref().to_vec()).unwrap(),
            attrs: e
                .attributes()
                .map(|a| {
                    let a = a.unwrap();
                    (
                        String::from_utf8(a.key.as_ref().to_vec()).unwrap(),
                        a.unescape_value().unwrap().into_owned(),
                    )
                })
                .collect(),
            children: Vec::new(),
        }
    }

    /// Parses well-formed XML (panics otherwise) into a tree of elements.
    pub(crate) fn parse(xml: &str) -> Node {
        let mut reader = quick_xml::Reader::from_str(xml);
        let mut stack: Vec<Node> = vec![Node {
            name: "#document".into(),
            attrs: Vec::new(),
            children: Vec::new(),
        }];
        loop {
            match reader.read_event().unwrap() {
                Event::Start(e) => stack.push(node(&e)),
                Event::Empty(e) => stack.last_mut().unwrap().children.push(node(&e)),
                Event::End(_) => {
                    let done = stack.pop().unwrap();
                    stack.last_mut().unwrap().children.push(done);
                }
                Event::Eof => break,
                _ => {}
            }
        }
        assert_eq!(stack.len(), 1, "every element is closed");
        stack.pop().unwrap().children.pop().unwrap()
    }

    /// The structure 4diac relies on, checked on a parsed file.
    fn check_structure(ecc: &Ecc, xml: &str) {
        let root = parse(xml);
        assert_eq!(root.name, "FBType");
        let iface = root.one("InterfaceList");
        for (list, event, vars) in [
            ("EventInputs", "REQ", &ecc.inputs),
            ("EventOutputs", "CNF", &ecc.outputs),
        ] {
            let ev = iface.one(list).one("Event");
            assert_eq!(ev.attr("Name"), Some(event));
            let with: Vec<&str> = ev
                .all("With")
                .iter()
                .map(|w| w.attr("Var").unwrap())
                .collect();
            let expected: Vec<&str> = vars.iter().map(String::as_str).collect();
            assert_eq!(with, expected, "{event} is associated with every variable");
        }
        let outs = iface.one("OutputVars").all("VarDeclaration");
        for (z, d) in outs.iter().enumerate() {
            assert_eq!(d.attr("Type"), Some("BOOL"));
            let init = d.attr("InitialValue") == Some("TRUE");
            assert_eq!(init, ecc.initial_outputs[z], "{:?}", d.attr("Name"));
        }

        let basic = root.one("BasicFB");
        let chart = basic.one("ECC");
        let states: Vec<&str> = chart
            .all("ECState")
            .iter()
            .map(|s| s.attr("Name").unwrap())
            .collect();
        assert_eq!(states.len(), ecc.states.len());
        assert_eq!(states[0], "START", "the initial state comes first");
        let algorithms: HashSet<&str> = basic
            .all("Algorithm")
            .iter()
            .map(|a| a.attr("Name").unwrap())
            .collect();
        for s in chart.all("ECState") {
            for a in s.all("ECAction") {
                assert_eq!(a.attr("Output"), Some("CNF"), "CNF on every entry");
                if let Some(alg) = a.attr("Algorithm") {
                    assert!(algorithms.contains(alg), "{alg} exists");
                }
            }
        }
        let mut transitions = chart.all("ECTransition");
        if ecc.size().t == 0 {
            assert_eq!(transitions.len(), 1);
            assert_eq!(transitions[0].attr("Condition"), Some(NEVER));
            transitions.clear();
        }
        assert_eq!(transitions.len(), ecc.size().t);
        for t in &transitions {
            assert!(states.contains(&t.attr("Source").unwrap()));
            assert!(states.contains(&t.attr("Destination").unwrap()));
            assert!(t.attr("Condition").unwrap().starts_with("REQ"));
        }
        // Priority is document order within a source state.
        for (i, s) in ecc.states.iter().enumerate() {
            let doc: Vec<&str> = transitions
                .iter()
                .filter(|t| t.attr("Source") == Some(states[i]))
                .map(|t| t.attr("Destination").unwrap())
                .collect();
            let want: Vec<&str> = s.transitions.iter().map(|t| states[t.target.0]).collect();
            assert_eq!(doc, want, "priority order of {}", states[i]);
        }
    }

    #[test]
    fn structure_of_every_sample() {
        for (name, ecc) in samples::all() {
            let xml = to_string(&ecc, &FbtOptions::default()).unwrap();
            println!("{name}");
            check_structure(&ecc, &xml);
        }
    }

    #[test]
    fn st_text_survives_the_attribute_as_lines() {
        let xml = to_string(&samples::binary(), &FbtOptions::default()).unwrap();
        let root = parse(&xml);
        let alg = root.one("BasicFB").all("Algorithm")[1];
        assert_eq!(alg.attr("Name"), Some("ALG_s1"));
        assert_eq!(alg.one("ST").attr("Text"), Some("lamp := NOT lamp;"));
        let alg = root.one("BasicFB").all("Algorithm")[2];
        assert_eq!(
            alg.one("ST").attr("Text"),
            Some("lamp := TRUE;\nbuzzer := NOT buzzer;")
        );
    }

    #[test]
    fn attributes_are_escaped() {
        assert_eq!(
            crate::files::xml::escape_attr("a<b & \"c\"\n"),
            "a&lt;b &amp; &quot;c&quot;&#10;"
        );
        let opts = FbtOptions {
            date: "<today> & \"now\"".into(),
            ..FbtOptions::default()
        };
        let xml = to_string(&samples::one_state(), &opts).unwrap();
        let root = parse(&xml);
        assert_eq!(
            root.one("VersionInfo").attr("Date"),
            Some("<today> & \"now\"")
        );
    }

    #[test]
    fn unusable_names_are_rejected_before_writing() {
        let mut buf = Vec::new();
        let opts = FbtOptions {
            type_name: "My FB".into(),
            ..FbtOptions::default()
        };
        let e = write_fbt(&samples::tri(), &opts, &mut buf).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        assert!(
            e.to_string()
                .starts_with("type name `My FB` cannot be used"),
            "{e}"
        );
        assert!(buf.is_empty());
        let mut ecc = samples::tri();
        ecc.inputs[3] = "Alg_S2".into();
        let e = write_fbt(&ecc, &FbtOptions::default(), &mut buf).unwrap_err();
        assert_eq!(
            e.to_string(),
            "input 4 `Alg_S2` cannot be used in an IEC 61499 .fbt file: the exported block \
             uses this name itself"
        );
    }

    #[test]
    fn grid_is_square_enough() {
        let o = ORIGIN;
        assert_eq!(position(0, 1), (o, o));
        assert_eq!(position(3, 4), (o + GRID_X, o + GRID_Y));
        assert_eq!(position(4, 5), (o + GRID_X, o + GRID_Y));
        assert_eq!(position(2, 5), (o + 2 * GRID_X, o));
    }

    /// One snapshot per sample ECC, named after the sample.
    #[test]
    fn snapshots() {
        samples::snapshot_each_sample!(|ecc| to_string(ecc, &FbtOptions::default()).unwrap());
    }
}
