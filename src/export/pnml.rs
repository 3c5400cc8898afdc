//! PNML (ISO/IEC 15909-2 place/transition net) of an ECC, for replaying event logs on it in
//! process-mining tools (pm4py, ProM).
//!
//! In: a valid [`Ecc`] and the text of each input and output in activities ([`Labels`]: the
//! signal names, or the PLC addresses of a mapping so that the net speaks the language of the
//! logs `synth events` writes). Out: a PNML document ([`write_pnml`]).
//!
//! # Mapping
//! - One place per ECC state (`p<i>`, named after the state); the initial marking is one token
//!   in state 0; the final marking (pm4py's `<finalmarkings>` extension) is the same, since the
//!   tank-like processes a reset activity slices return to their initial state.
//! - Per ECC transition `s -> t`, one net transition from `p<s>` to `p<t>` per distinct set of
//!   output changes it can cause, labelled like the output event of seed 002's conversion
//!   (`%QX0.0 true + %QX0.1 false`, outputs in interface order). The outputs a state can be
//!   entered with are found by a fixpoint from the initial outputs, so algorithms that keep
//!   an output (`x`) get one net transition per outcome. A transition that changes no output
//!   leaves no event in a log and becomes an invisible (`tau`) transition.
//! - Guards read levels, which an event log does not show; input events therefore never block:
//!   every place has a self-loop per input activity (`ADDRESS true`, `ADDRESS false`). The net
//!   thus checks what an ECC decides: which output events may follow in which order. Merged
//!   input events (two inputs changing at one timestamp) have no transition.
//!
//! Ids: places `p<state>`, output transitions `t<state>_<transition>_<outcome>`, input
//! self-loops `i<state>_<input>_<0|1>`, arcs `a<n>` in writing order.

use crate::ecc::Ecc;
use quick_xml::escape::escape;
use std::collections::BTreeSet;
use std::io::{self, Write};

/// How inputs and outputs appear in activities.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Labels {
    /// Per input, in interface order.
    pub inputs: Vec<String>,
    /// Per output, in interface order.
    pub outputs: Vec<String>,
}

impl Labels {
    /// The ECC's own signal names.
    pub fn names(ecc: &Ecc) -> Labels {
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

/// Writes the net of `ecc` labelled by its own signal names.
pub fn write_pnml(ecc: &Ecc, w: &mut impl Write) -> io::Result<()> {
    write_pnml_labelled(ecc, &Labels::names(ecc), "SynthesizedFB", w)
}

/// Writes the net of `ecc` with activities built from `labels`; `name` names the net.
pub fn write_pnml_labelled(
    ecc: &Ecc,
    labels: &Labels,
    name: &str,
    w: &mut impl Write,
) -> io::Result<()> {
    let entry = entry_outputs(ecc);
    writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#)?;
    writeln!(w, "<pnml>")?;
    writeln!(
        w,
        r#"  <net id="{}" type="http://www.pnml.org/version-2009/grammar/pnmlcoremodel">"#,
        escape(name)
    )?;
    writeln!(w, "    <name><text>{}</text></name>", escape(name))?;
    writeln!(w, r#"    <page id="page0">"#)?;
    for (i, s) in ecc.states.iter().enumerate() {
        write!(
            w,
            r#"      <place id="p{i}"><name><text>{}</text></name>"#,
            escape(s.name.as_str())
        )?;
        if i == 0 {
            write!(w, "<initialMarking><text>1</text></initialMarking>")?;
        }
        writeln!(w, "</place>")?;
    }
    let mut arcs: Vec<(String, String)> = Vec::new();
    for (i, s) in ecc.states.iter().enumerate() {
        for (x, label) in labels.inputs.iter().enumerate() {
            for v in [false, true] {
                let id = format!("i{i}_{x}_{}", u8::from(v));
                writeln!(
                    w,
                    r#"      <transition id="{id}"><name><text>{} {v}</text></name></transition>"#,
                    escape(label.as_str())
                )?;
                arcs.push((format!("p{i}"), id.clone()));
                arcs.push((id, format!("p{i}")));
            }
        }
        for (k, t) in s.transitions.iter().enumerate() {
            let outcomes: BTreeSet<Vec<(usize, bool)>> = entry[i]
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
                if changes.is_empty() {
                    writeln!(
                        w,
                        r#"      <transition id="{id}"><name><text>tau</text></name><toolspecific tool="ProM" version="6.4" activity="$invisible$" localNodeID="{id}"/></transition>"#
                    )?;
                } else {
                    let text: Vec<String> = changes
                        .iter()
                        .map(|&(z, v)| format!("{} {v}", labels.outputs[z]))
                        .collect();
                    writeln!(
                        w,
                        r#"      <transition id="{id}"><name><text>{}</text></name></transition>"#,
                        escape(text.join(crate::events::JOIN).as_str())
                    )?;
                }
                arcs.push((format!("p{i}"), id.clone()));
                arcs.push((id, format!("p{}", t.target.0)));
            }
        }
    }
    for (n, (source, target)) in arcs.iter().enumerate() {
        writeln!(
            w,
            r#"      <arc id="a{n}" source="{source}" target="{target}"/>"#
        )?;
    }
    writeln!(w, "    </page>")?;
    writeln!(
        w,
        r#"    <finalmarkings><marking><place idref="p0"><text>1</text></place></marking></finalmarkings>"#
    )?;
    writeln!(w, "  </net>")?;
    writeln!(w, "</pnml>")
}

/// [`write_pnml`] into a string.
pub fn to_string(ecc: &Ecc) -> String {
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
        for (name, ecc) in samples::all() {
            insta::assert_snapshot!(name, to_string(&ecc));
        }
        let tank = crate::cases::tank::Program::FillDrain.reference();
        insta::assert_snapshot!("tank1", to_string(&tank));
    }

    /// Well-formed, every arc joins existing nodes, one place per state, and per ECC
    /// transition at least one net transition from its source to its target place.
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
            assert_eq!(places.len(), ecc.states.len(), "{name}");
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
                            arcs.contains(&(format!("p{i}"), id.clone()))
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
        write_pnml_labelled(&ecc, &labels, "tank", &mut buf).unwrap();
        let xml = String::from_utf8(buf).unwrap();
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
