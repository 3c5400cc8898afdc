//! PNML (ISO/IEC 15909-2 place/transition net) of an ECC, for replaying event logs on it in
//! process-mining tools (pm4py, ProM).
//!
//! In: a valid [`Ecc`] and the text of each input and output in activities ([`Labels`]: the
//! signal names, or the PLC addresses of a mapping so that the net speaks the language of the
//! logs `synth events` writes). Out: a PNML document ([`write_pnml`]).
//!
//! # Mapping
//! The net reads an event log of the process-mining paper's conversion: input events (`ADDRESS VALUE`, one
//! input changing) and output events (the outputs one ECC transition changed, joined by
//! ` + ` in interface order). It assumes one `REQ` per scan: a machine waits in a state while
//! no guard holds, and an input event that makes a guard hold fires it at once.
//! - Places: `p<i>` per ECC state; `q<i>_<k>` per ECC transition `k` of state `i` (fired,
//!   output event pending); `start`, holding the initial token.
//! - Input events: for state `i` and each input literal event, every input vector on which
//!   state `i` waits (no guard holds) and which the event changes is tried: when the new
//!   vector makes transition `k` the first to hold, a transition labelled with the input event
//!   moves `p<i>` to `q<i>_<k>`; when no guard holds, a self-loop on `p<i>` carries the label.
//!   So a net replays a log only if every output event follows the input event that caused it.
//!   (For more than [`MAX_EXACT_INPUTS`] inputs the vectors are not enumerated and every event
//!   gets a self-loop and a move to every transition: an over-approximation.)
//! - Output events: per ECC transition, one net transition from `q<i>_<k>` to the target's
//!   place per distinct set of output changes it can cause (found by a fixpoint over the output
//!   vectors each state can be entered with, from the initial outputs), labelled with the
//!   changes; no change: an invisible (`tau`) transition.
//! - `start` has copies of state 0's input-event transitions (a trace that starts at a reset,
//!   in the initial state) and, when a guard of state 0 holds on all-false inputs, the output
//!   transition of the power-up scan, which fires without an input event. Everything leaving
//!   `start` is labelled, so token replay never has to guess an invisible move. The final
//!   marking is `p0`: a reset brings the process back.
//!
//! # Dialects
//! ISO/IEC 15909-2 leaves two things the net needs to tools: silent transitions and the final
//! marking. [`Dialect::Iso`] (the default) writes a P/T net (type `.../grammar/ptnet`) in the
//! PNML namespace and keeps both in `<toolspecific tool="fbsynth">` elements, which strict
//! tools accept and ignore: `<invisible/>` in a silent transition, `<finalMarking>` (places
//! with their token counts, as in `<initialMarking>`) in the net. [`Dialect::Prom`] writes
//! what ProM and pm4py read instead, which the standard rejects: no namespace, the core-model
//! type although places are marked, `<toolspecific tool="ProM" activity="$invisible$">` on
//! silent transitions and a `<finalmarkings>` element in the net. Use it for token replay in
//! those tools (pm4py reads an ISO net, but sees its silent transitions as visible `tau`s and
//! no final marking).
//!
//! Not represented: merged input events (two inputs changing at one timestamp), and a machine
//! that fires again without a new input event (two output events in a row).
//!
//! Ids: `p<i>`, `q<i>_<k>`, `start`; output transitions `t<i>_<k>_<outcome>`; input
//! transitions `e<i>_<input>_<0|1>_<k>` (moves) and `i<i>_<input>_<0|1>` (self-loops), their
//! copies from `start` prefixed `s`, and `power_up_<k>`; arcs `a<n>` in writing order.

use crate::ecc::Ecc;
use crate::files::xml::XmlWriter;
use std::collections::BTreeSet;
use std::fmt;
use std::io::{self, Write};
use std::str::FromStr;

/// The XML namespace of ISO/IEC 15909-2 PNML documents.
pub(crate) const NAMESPACE: &str = "http://www.pnml.org/version-2009/grammar/pnml";

/// The net type URI of a place/transition net.
pub(crate) const PTNET: &str = "http://www.pnml.org/version-2009/grammar/ptnet";

/// The net type URI of the core model, which ProM and pm4py write.
const CORE_MODEL: &str = "http://www.pnml.org/version-2009/grammar/pnmlcoremodel";

/// Which PNML a net is written in; see the module header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) enum Dialect {
    /// ISO/IEC 15909-2 P/T net in the PNML namespace, fbsynth's tool data in
    /// `<toolspecific>`.
    #[default]
    Iso,
    /// What ProM and pm4py write and read for token replay; not valid ISO PNML.
    Prom,
}

impl fmt::Display for Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Dialect::Iso => "iso",
            Dialect::Prom => "prom",
        })
    }
}

impl FromStr for Dialect {
    type Err = String;

    /// `iso` or `prom` (`pm4py` is the same), ignoring case.
    fn from_str(s: &str) -> Result<Dialect, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "iso" => Ok(Dialect::Iso),
            "prom" | "pm4py" => Ok(Dialect::Prom),
            _ => Err(format!(
                "unknown PNML dialect {}; valid: iso, prom",
                crate::quote::backquote(s)
            )),
        }
    }
}

/// How inputs and outputs appear in activities.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Labels {
    /// Per input, in interface order.
    pub(crate) inputs: Vec<String>,
    /// Per output, in interface order.
    pub(crate) outputs: Vec<String>,
}

impl Labels {
    /// The ECC's own signal names.
    pub(crate) fn names(ecc: &Ecc) -> Labels {
        Labels {
            inputs: ecc.inputs.clone(),
            outputs: ecc.outputs.clone(),
        }
    }
}

/// The output vectors each state can be entered with (state 0 also with the initial outputs).
/// At most [`MAX_VECTORS`] per state are followed, which bounds the work for wide interfaces.
fn entry_outputs(ecc: &Ecc) -> Vec<BTreeSet<Vec<bool>>> {
    let mut sets = vec![BTreeSet::new(); ecc.states.len()];
    sets[0].insert(ecc.initial_outputs.clone());
    let mut work = vec![(0, ecc.initial_outputs.clone())];
    while let Some((s, z)) = work.pop() {
        for t in &ecc.states[s].transitions {
            let mut next = z.clone();
            ecc.states[t.target.0].algorithm.apply(&mut next);
            let set = &mut sets[t.target.0];
            if set.len() < MAX_VECTORS && set.insert(next.clone()) {
                work.push((t.target.0, next));
            }
        }
    }
    sets
}

/// Bound of [`entry_outputs`] per state.
const MAX_VECTORS: usize = 64;

/// Writes the ISO net of `ecc` labelled by its own signal names.
pub(crate) fn write_pnml(ecc: &Ecc, w: &mut impl Write) -> io::Result<()> {
    write_pnml_labelled(ecc, &Labels::names(ecc), "SynthesizedFB", Dialect::Iso, w).map(|_| ())
}

/// Inputs up to which input events are analysed exactly (2^n vectors per state).
pub(crate) const MAX_EXACT_INPUTS: usize = 12;

/// What an input event (`input` taking `value`) can do in a state: `None` = nothing fires,
/// `Some(k)` = transition `k` fires. Sorted, `None` first.
fn event_outcomes(ecc: &Ecc, state: usize, input: usize, value: bool) -> BTreeSet<Option<usize>> {
    let transitions = &ecc.states[state].transitions;
    let n = ecc.inputs.len();
    if n > MAX_EXACT_INPUTS {
        return std::iter::once(None)
            .chain((0..transitions.len()).map(Some))
            .collect();
    }
    let first = |x: &[bool]| transitions.iter().position(|t| t.guard.eval(x));
    let mut out = BTreeSet::new();
    for bits in 0u32..(1 << n) {
        let mut x: Vec<bool> = (0..n).map(|b| bits >> b & 1 == 1).collect();
        if x[input] == value || first(&x).is_some() {
            continue;
        }
        x[input] = value;
        out.insert(first(&x));
    }
    out
}

/// How many places and transitions a net has, as written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct NetSize {
    /// Its places (`start`, one per state, one per ECC transition).
    pub places: usize,
    /// Its transitions, silent ones included.
    pub transitions: usize,
}

/// Writes the net of `ecc` in `dialect` with activities built from `labels`; `name` names the
/// net (its `<name>`: any text; the net's `id` is `net`). Returns the net's size.
pub(crate) fn write_pnml_labelled(
    ecc: &Ecc,
    labels: &Labels,
    name: &str,
    dialect: Dialect,
    w: &mut impl Write,
) -> io::Result<NetSize> {
    let entry = entry_outputs(ecc);
    let mut net = Net {
        x: XmlWriter::new(w),
        ecc,
        labels,
        dialect,
        arcs: Vec::new(),
        size: NetSize::default(),
    };
    net.header(name)?;
    net.places()?;
    net.power_up()?;
    net.input_events(0, "start")?;
    for (i, entry) in entry.iter().enumerate() {
        net.input_events(i, &format!("p{i}"))?;
        net.output_events(i, entry)?;
    }
    net.arcs()?;
    net.final_marking()?;
    Ok(net.size)
}

/// A net being written: the page's nodes as they come, its arcs (source, target) collected
/// for the end of the page.
struct Net<'a, W: Write> {
    x: XmlWriter<W>,
    ecc: &'a Ecc,
    labels: &'a Labels,
    dialect: Dialect,
    arcs: Vec<(String, String)>,
    size: NetSize,
}

impl<W: Write> Net<'_, W> {
    /// A transition, place, ... of the page: one line each, `<id><name><text>`, then `more`.
    fn node(
        &mut self,
        kind: &str,
        id: &str,
        label: &str,
        more: impl FnOnce(&mut XmlWriter<W>) -> io::Result<()>,
    ) -> io::Result<()> {
        match kind {
            "place" => self.size.places += 1,
            "transition" => self.size.transitions += 1,
            _ => {}
        }
        let x = &mut self.x;
        x.indent(3)?;
        x.start(kind, &[("id", id)])?;
        x.start("name", &[])?;
        x.text_element("text", label)?;
        x.end("name")?;
        more(x)?;
        x.end(kind)?;
        x.newline()
    }

    /// A silent transition, marked as the dialect says.
    fn tau(&mut self, id: &str) -> io::Result<()> {
        let dialect = self.dialect;
        self.node("transition", id, "tau", |x| match dialect {
            Dialect::Iso => {
                x.start("toolspecific", &FBSYNTH_TOOL)?;
                x.empty("invisible", &[])?;
                x.end("toolspecific")
            }
            Dialect::Prom => x.empty(
                "toolspecific",
                &[
                    ("tool", "ProM"),
                    ("version", "6.4"),
                    ("activity", "$invisible$"),
                    ("localNodeID", id),
                ],
            ),
        })
    }

    /// A transition labelled with an activity.
    fn labelled(&mut self, id: &str, label: &str) -> io::Result<()> {
        self.node("transition", id, label, |_| Ok(()))
    }

    /// A transition for the output `changes` (`(output, value)`): silent when there are none.
    fn output_changes(&mut self, id: &str, changes: &[(usize, bool)]) -> io::Result<()> {
        if changes.is_empty() {
            return self.tau(id);
        }
        let text: Vec<String> = (changes.iter())
            .map(|&(z, v)| format!("{} {v}", self.labels.outputs[z]))
            .collect();
        self.labelled(id, &text.join(crate::events::JOIN))
    }

    /// The declaration and everything up to the open page: the root in the dialect's
    /// namespace, the net with its type and `name`.
    fn header(&mut self, name: &str) -> io::Result<()> {
        let x = &mut self.x;
        x.declaration()?;
        let (root, net_type): (&[(&str, &str)], &str) = match self.dialect {
            Dialect::Iso => (&[("xmlns", NAMESPACE)], PTNET),
            Dialect::Prom => (&[], CORE_MODEL),
        };
        x.open(0, "pnml", root)?;
        x.open(1, "net", &[("id", "net"), ("type", net_type)])?;
        x.indent(2)?;
        x.start("name", &[])?;
        x.text_element("text", name)?;
        x.end("name")?;
        x.newline()?;
        x.open(2, "page", &[("id", "page0")])
    }

    /// The places: `start` with the initial token, `p<i>` per state, `q<i>_<k>` per ECC
    /// transition.
    fn places(&mut self) -> io::Result<()> {
        self.node("place", "start", "start", |x| {
            x.start("initialMarking", &[])?;
            x.text_element("text", "1")?;
            x.end("initialMarking")
        })?;
        let ecc = self.ecc;
        for (i, s) in ecc.states.iter().enumerate() {
            self.node("place", &format!("p{i}"), &s.name, |_| Ok(()))?;
            for k in 0..s.transitions.len() {
                let label = format!("{} fired {k}", s.name);
                self.node("place", &format!("q{i}_{k}"), &label, |_| Ok(()))?;
            }
        }
        Ok(())
    }

    /// From `start`, the power-up scan, which fires without an input event when a guard of
    /// state 0 holds on all-false inputs. Like the input events of state 0 from `start` (a
    /// trace that starts at a reset), it is labelled, so replay never has to guess an
    /// invisible move.
    fn power_up(&mut self) -> io::Result<()> {
        let ecc = self.ecc;
        let zeros = vec![false; ecc.inputs.len()];
        let Some(k) = (ecc.states[0].transitions.iter()).position(|t| t.guard.eval(&zeros)) else {
            return Ok(());
        };
        let target = ecc.states[0].transitions[k].target;
        let mut new = ecc.initial_outputs.clone();
        ecc.states[target.0].algorithm.apply(&mut new);
        let changes: Vec<(usize, bool)> = (0..new.len())
            .filter(|&z| new[z] != ecc.initial_outputs[z])
            .map(|z| (z, new[z]))
            .collect();
        let id = format!("power_up_{k}");
        self.output_changes(&id, &changes)?;
        self.arcs.push(("start".into(), id.clone()));
        self.arcs.push((id, format!("p{}", target.0)));
        Ok(())
    }

    /// Input events of state `i` read from place `from` (`p<i>`, or `start` for state 0):
    /// per input and value, one transition per outcome ([`event_outcomes`]), to `q<i>_<k>`
    /// when transition `k` fires, back to `p<i>` when nothing does.
    fn input_events(&mut self, i: usize, from: &str) -> io::Result<()> {
        let (ecc, labels) = (self.ecc, self.labels);
        for (x, label) in labels.inputs.iter().enumerate() {
            for v in [false, true] {
                let text = format!("{label} {v}");
                for outcome in event_outcomes(ecc, i, x, v) {
                    let (id, to) = match outcome {
                        None => (format!("i{i}_{x}_{}", u8::from(v)), format!("p{i}")),
                        Some(k) => (format!("e{i}_{x}_{}_{k}", u8::from(v)), format!("q{i}_{k}")),
                    };
                    let id = if from == "start" {
                        format!("s{id}")
                    } else {
                        id
                    };
                    self.labelled(&id, &text)?;
                    self.arcs.push((from.to_string(), id.clone()));
                    self.arcs.push((id, to));
                }
            }
        }
        Ok(())
    }

    /// Output events of the transitions of state `i`: from `q<i>_<k>` to the target's place,
    /// one per distinct set of output changes the transition causes on the output vectors
    /// `entry` the state can be entered with.
    fn output_events(&mut self, i: usize, entry: &BTreeSet<Vec<bool>>) -> io::Result<()> {
        let ecc = self.ecc;
        for (k, t) in ecc.states[i].transitions.iter().enumerate() {
            let outcomes: BTreeSet<Vec<(usize, bool)>> = entry
                .iter()
                .map(|old| {
                    let mut new = old.clone();
                    ecc.states[t.target.0].algorithm.apply(&mut new);
                    (0..new.len())
                        .filter(|&z| new[z] != old[z])
                        .map(|z| (z, new[z]))
                        .collect()
                })
                .collect();
            for (j, changes) in outcomes.iter().enumerate() {
                let id = format!("t{i}_{k}_{j}");
                self.output_changes(&id, changes)?;
                self.arcs.push((format!("q{i}_{k}"), id.clone()));
                self.arcs.push((id, format!("p{}", t.target.0)));
            }
        }
        Ok(())
    }

    /// The arcs collected, `a<n>` in writing order; closes the page.
    fn arcs(&mut self) -> io::Result<()> {
        for (n, (source, target)) in self.arcs.iter().enumerate() {
            let id = format!("a{n}");
            self.x.leaf(
                3,
                "arc",
                &[("id", &id), ("source", source), ("target", target)],
            )?;
        }
        self.x.close(2, "page")
    }

    /// The final marking `p0` in the dialect's element; closes the net and the document.
    fn final_marking(&mut self) -> io::Result<()> {
        let x = &mut self.x;
        x.indent(2)?;
        let final_marking: &[&str] = match self.dialect {
            Dialect::Iso => {
                x.start("toolspecific", &FBSYNTH_TOOL)?;
                &["finalMarking"]
            }
            Dialect::Prom => &["finalmarkings", "marking"],
        };
        for element in final_marking {
            x.start(element, &[])?;
        }
        x.start("place", &[("idref", "p0")])?;
        x.text_element("text", "1")?;
        x.end("place")?;
        for element in final_marking.iter().rev() {
            x.end(element)?;
        }
        if self.dialect == Dialect::Iso {
            x.end("toolspecific")?;
        }
        x.newline()?;
        x.close(1, "net")?;
        x.close(0, "pnml")
    }
}

/// The `<toolspecific>` attributes of fbsynth's own data in an ISO net.
const FBSYNTH_TOOL: [(&str, &str); 2] = [("tool", "fbsynth"), ("version", "1.0")];

/// [`write_pnml`] into a string.
pub(crate) fn to_string(ecc: &Ecc) -> String {
    let mut buf = Vec::new();
    write_pnml(ecc, &mut buf).expect("writing into memory cannot fail");
    String::from_utf8(buf).expect("the emitter writes UTF-8")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::events::xes::elements;
    use crate::export::samples;

    #[test]
    fn snapshots() {
        samples::snapshot_each_sample!(to_string);
        let tank = crate::cases::tank::Program::FillDrain.reference();
        insta::assert_snapshot!("tank1", to_string(&tank));
    }

    /// Well-formed, every arc joins a place and a transition, the places are `start`, one per
    /// state and one per ECC transition, and each ECC transition of a reachable state has an
    /// output transition from its pending place to its target's place.
    #[test]
    fn structure_of_every_sample() {
        let mut eccs = samples::all();
        eccs.push(("tank2", crate::cases::tank::Program::Cycles.reference()));
        for (name, ecc) in eccs {
            let xml = to_string(&ecc);
            let els = elements(&xml);
            let ids = |kind: &str| -> BTreeSet<String> {
                els.iter()
                    .filter(|(n, _)| n == kind)
                    .filter_map(|(_, a)| a.iter().find(|(k, _)| k == "id"))
                    .map(|(_, v)| v.clone())
                    .collect()
            };
            let (places, transitions) = (ids("place"), ids("transition"));
            let transitions_total: usize = ecc.states.iter().map(|s| s.transitions.len()).sum();
            assert_eq!(
                places.len(),
                1 + ecc.states.len() + transitions_total,
                "{name}"
            );
            let arcs: Vec<(String, String)> = els
                .iter()
                .filter(|(n, _)| n == "arc")
                .map(|(_, a)| {
                    let get = |k: &str| a.iter().find(|(key, _)| key == k).unwrap().1.clone();
                    (get("source"), get("target"))
                })
                .collect();
            for (s, t) in &arcs {
                assert!(
                    (places.contains(s) && transitions.contains(t))
                        || (transitions.contains(s) && places.contains(t)),
                    "{name}: arc {s} -> {t}"
                );
            }
            for (i, s) in ecc.states.iter().enumerate() {
                for (k, t) in s.transitions.iter().enumerate() {
                    let prefix = format!("t{i}_{k}_");
                    let found = transitions
                        .iter()
                        .filter(|id| id.starts_with(&prefix))
                        .any(|id| {
                            arcs.contains(&(format!("q{i}_{k}"), id.clone()))
                                && arcs.contains(&(id.clone(), format!("p{}", t.target.0)))
                        });
                    // States no run reaches get no output transitions.
                    let reachable = !entry_outputs(&ecc)[i].is_empty();
                    assert_eq!(found, reachable, "{name}: transition {i}.{k}");
                }
            }
        }
    }

    #[test]
    fn labels_are_the_output_changes_and_escaped() {
        let ecc = crate::cases::tank::Program::FillDrain.reference();
        let labels = Labels {
            inputs: vec!["%IX0.1".into(), "%IX0.2".into(), "<&>".into()],
            outputs: vec!["%QX0.0".into(), "%QX0.1".into()],
        };
        let mut buf = Vec::new();
        let size = write_pnml_labelled(&ecc, &labels, "tank", Dialect::Iso, &mut buf).unwrap();
        let xml = String::from_utf8(buf).unwrap();
        // The size returned is the net's, not the machine's (2 states).
        assert_eq!(size.places, xml.matches("<place id=").count());
        assert_eq!(size.transitions, xml.matches("<transition id=").count());
        assert!(size.places > ecc.states.len(), "{size:?}");
        assert!(xml.contains("<text>&lt;&amp;&gt; true</text>"));
        // Drain -> Fill from the initial outputs (00) opens the inlet only; from Drain's own
        // outputs (01) it also closes the outlet: two outcomes, two net transitions.
        assert!(xml.contains(r#"<transition id="t0_0_0"><name><text>%QX0.0 true</text>"#));
        assert!(xml
            .contains(r#"<transition id="t0_0_1"><name><text>%QX0.0 true + %QX0.1 false</text>"#));
        assert!(xml
            .contains(r#"<transition id="t1_0_0"><name><text>%QX0.0 false + %QX0.1 true</text>"#));
    }
}
