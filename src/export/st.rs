//! IEC 61131-3 Structured Text `FUNCTION_BLOCK` that behaves like the ECC, for PLCs without
//! IEC 61499.
//!
//! In: a valid [`Ecc`] and a block name. Out: one `FUNCTION_BLOCK` with `REQ` and the inputs as
//! `VAR_INPUT`, `CNF` and the outputs (with their initial values) as `VAR_OUTPUT`, and the
//! current state as `state : INT` (0-based, 0 = initial).
//!
//! Each call of the block with `REQ = TRUE` is one `REQ` event: in a `CASE` over `state`, an
//! `IF`/`ELSIF` chain tries the transitions of the current state in priority order; the first
//! whose guard holds sets `state` to its target, runs the target's algorithm inline and sets
//! `CNF := TRUE` for this call. A call with `REQ = FALSE`, or in which no guard holds, changes
//! nothing and leaves `CNF` FALSE. So calling the block once per PLC cycle with `REQ` from an
//! edge or a timer reproduces [`Run::step`](crate::ecc::Run::step) call by call.

use super::{check_iec_names, NameError};
use crate::ecc::ident::BLOCK_MEMBERS;
use crate::ecc::Ecc;
use crate::ecc::Effect;
use crate::smv::bool_literal;
use std::io::{self, Write};

/// Checks the block name and the interface names (IEC identifiers, distinct ignoring case,
/// none of `REQ`, `CNF`, `state`).
pub(crate) fn check_names(ecc: &Ecc, block_name: &str) -> Result<(), NameError> {
    let reserved: Vec<String> = BLOCK_MEMBERS.iter().map(|r| r.to_string()).collect();
    check_iec_names(ecc, "Structured Text", block_name, &reserved)
}

/// Writes the function block; fails with [`io::ErrorKind::InvalidInput`] (wrapping a
/// [`NameError`]) before writing anything if a name is unusable.
pub(crate) fn write_st(ecc: &Ecc, block_name: &str, w: &mut impl Write) -> io::Result<()> {
    check_names(ecc, block_name)?;
    writeln!(w, "FUNCTION_BLOCK {block_name}")?;
    writeln!(w, "(* Synthesized by fbsynth ({}).", ecc.size())?;
    writeln!(
        w,
        "   Each call with REQ = TRUE is one REQ event: the first transition of the current"
    )?;
    writeln!(
        w,
        "   state whose guard holds fires, the outputs are updated and CNF is TRUE for this"
    )?;
    writeln!(w, "   call. Otherwise nothing changes and CNF is FALSE. *)")?;
    writeln!(w, "VAR_INPUT")?;
    writeln!(w, "    REQ : BOOL;")?;
    for x in &ecc.inputs {
        writeln!(w, "    {x} : BOOL;")?;
    }
    writeln!(w, "END_VAR")?;
    writeln!(w, "VAR_OUTPUT")?;
    writeln!(w, "    CNF : BOOL;")?;
    for (z, &init) in ecc.outputs.iter().zip(&ecc.initial_outputs) {
        let initial = if init { " := TRUE" } else { "" };
        writeln!(w, "    {z} : BOOL{initial};")?;
    }
    writeln!(w, "END_VAR")?;
    writeln!(w, "VAR")?;
    writeln!(w, "    state : INT := 0; (* current state, 0 = initial *)")?;
    writeln!(w, "END_VAR")?;
    writeln!(w)?;
    write_statements(ecc, w)?;
    writeln!(w, "END_FUNCTION_BLOCK")
}

/// The block's statements (what follows its declarations): clear `CNF`, then on `REQ` the
/// `CASE` over `state`. Shared with the PLCopen body ([`super::plcopen`]), which declares the
/// same variables in XML.
pub(crate) fn write_statements(ecc: &Ecc, w: &mut impl Write) -> io::Result<()> {
    writeln!(w, "CNF := FALSE;")?;

    if ecc.states.iter().all(|s| s.transitions.is_empty()) {
        // CASE needs at least one branch; without transitions REQ never has an effect.
        writeln!(w, "(* No transitions: REQ changes nothing. *)")?;
    } else {
        writeln!(w, "IF REQ THEN")?;
        writeln!(w, "    CASE state OF")?;
        for (i, s) in ecc.states.iter().enumerate() {
            if s.transitions.is_empty() {
                continue;
            }
            let label = if s.name == format!("s{i}") {
                String::new()
            } else {
                format!(" (* {} *)", s.name)
            };
            writeln!(w, "        {i}:{label}")?;
            for (k, t) in s.transitions.iter().enumerate() {
                let keyword = if k == 0 { "IF" } else { "ELSIF" };
                writeln!(
                    w,
                    "            {keyword} {} THEN",
                    t.guard.display_st(&ecc.inputs)
                )?;
                writeln!(w, "                state := {};", t.target.0)?;
                let effects = Effect::all(&ecc.states[t.target.0].algorithm);
                for (z, e) in ecc.outputs.iter().zip(effects) {
                    match e {
                        Effect::Keep => {}
                        Effect::Set(v) => {
                            writeln!(w, "                {z} := {};", bool_literal(v))?
                        }
                        Effect::Flip => writeln!(w, "                {z} := NOT {z};")?,
                    }
                }
                writeln!(w, "                CNF := TRUE;")?;
            }
            writeln!(w, "            END_IF;")?;
        }
        writeln!(w, "    END_CASE;")?;
        writeln!(w, "END_IF;")?;
    }
    Ok(())
}

/// [`write_st`] into a string.
pub(crate) fn to_string(ecc: &Ecc, block_name: &str) -> io::Result<String> {
    let mut buf = Vec::new();
    write_st(ecc, block_name, &mut buf)?;
    Ok(String::from_utf8(buf).expect("the ST emitter writes UTF-8 only"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::{Algorithm, State, Tri};
    use crate::export::samples;

    /// One snapshot per sample ECC, named after the sample.
    #[test]
    fn snapshots() {
        samples::snapshot_each_sample!(|ecc| to_string(ecc, "Fb").unwrap());
    }

    #[test]
    fn no_transitions_means_no_case() {
        let ecc = Ecc {
            inputs: vec![],
            outputs: vec!["z".into()],
            initial_outputs: vec![true],
            states: vec![State {
                name: "idle".into(),
                algorithm: Algorithm::Tri(vec![Tri::Keep]),
                transitions: vec![],
            }],
        };
        let text = to_string(&ecc, "Fb").unwrap();
        assert!(!text.contains("CASE"), "{text}");
        assert!(text.contains("    z : BOOL := TRUE;"), "{text}");
    }

    #[test]
    fn the_state_variable_is_reserved() {
        let mut ecc = samples::tri();
        ecc.inputs[0] = "STATE".into();
        let e = to_string(&ecc, "Fb").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        assert_eq!(
            e.to_string(),
            "input 1 `STATE` cannot be used in Structured Text: the exported block uses this \
             name itself"
        );
    }
}
