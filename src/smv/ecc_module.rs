//! An ECC as a NuSMV module.
//!
//! In: a valid [`Ecc`] and a module name. Out: one `MODULE name(REQ, x1, ..., xX)` whose
//! formal parameters are the input event and the input variables, and whose variables are
//! `_state`, `CNF` and the outputs. Names are checked first ([`check_names`]); nothing is
//! written when one is unusable.
//!
//! # Semantics
//! One SMV step is one chance for a `REQ`. With the parameters `REQ(t)`, `x(t)` and the
//! variables `_state(t)`, `z(t)` at step `t`:
//! - `_target` is the target of the first transition of `_state(t)` whose guard holds on
//!   `x(t)`, if `REQ(t)`; otherwise (or when no guard holds) `_state(t)`;
//! - `_fired` is TRUE iff `REQ(t)` and some guard of `_state(t)` holds;
//! - `_state(t+1) = _target`, `CNF(t+1) = _fired`, and `z(t+1)` is `z(t)` with the algorithm
//!   of `_target` applied iff `_fired`.
//!
//! So `(_state, z)` at `t+1` and `CNF(t+1)` are exactly what [`Run::step`](crate::ecc::Run::step)
//! yields from `(_state, z)` at `t` on input `x(t)` when `REQ(t)` (CNF = `Some`), and the state
//! is unchanged when not. `CNF` is FALSE initially.
//!
//! State `i` is the enumeration value `s{i}` ([`state_value`]). NuSMV turns a one-valued
//! enumeration into a constant, so a one-state ECC gets a second, unreachable value
//! `s0_unused`.

use crate::ecc::ident::{bool_literal, check_smv};
use crate::ecc::{Ecc, Effect, Guard, StateId};
use std::collections::HashMap;
use std::io::{self, Write};

/// Why an ECC could not be emitted as SMV.
#[derive(Debug, thiserror::Error)]
pub enum SmvError {
    /// A name cannot be used verbatim in SMV code.
    #[error(
        "{role} {} cannot be used in the SMV model: {reason}",
        crate::quote::backquote(name)
    )]
    Identifier {
        /// Where the name comes from: `module name`, `input 3`, `output 1` (1-based).
        role: String,
        /// The offending name, as given.
        name: String,
        /// Why it cannot be used (not an identifier, a keyword, a clash, ...).
        reason: String,
    },
    /// Writing the module to the output failed.
    #[error(transparent)]
    Io(#[from] io::Error),
}

/// The SMV enumeration value of a state: `s{i}` for 0-based index `i`.
pub(crate) fn state_value(id: StateId) -> String {
    format!("s{}", id.0)
}

/// The values of the `_state` enumeration, in order; see the module header for the second
/// value of a one-state ECC.
fn state_values(ecc: &Ecc) -> Vec<String> {
    let mut v: Vec<String> = (0..ecc.states.len())
        .map(|i| state_value(StateId(i)))
        .collect();
    if v.len() == 1 {
        v.push("s0_unused".into());
    }
    v
}

/// Checks every name the module would contain: module name, inputs and outputs must pass
/// [`check_smv`], be distinct, and differ from `REQ`, `CNF` and the state values
/// (NuSMV resolves a variable and an enumeration constant of the same name ambiguously); the
/// module is not `main`, NuSMV's top module.
pub(crate) fn check_names(ecc: &Ecc, module_name: &str) -> Result<(), SmvError> {
    let bad = |role: String, name: &str, reason: String| SmvError::Identifier {
        role,
        name: name.to_string(),
        reason,
    };
    check_smv(module_name).map_err(|r| bad("module name".into(), module_name, r))?;
    if module_name == "main" {
        let why = "it is NuSMV's top module, which takes no parameters";
        return Err(bad("module name".into(), module_name, why.into()));
    }
    let constants = state_values(ecc);
    let mut seen: HashMap<&str, String> = HashMap::new();
    let named = ecc
        .inputs
        .iter()
        .enumerate()
        .map(|(i, n)| (format!("input {}", i + 1), n))
        .chain(
            ecc.outputs
                .iter()
                .enumerate()
                .map(|(i, n)| (format!("output {}", i + 1), n)),
        );
    for (role, name) in named {
        check_smv(name).map_err(|r| bad(role.clone(), name, r))?;
        if name == "REQ" || name == "CNF" {
            return Err(bad(role, name, "it is the name of an event".into()));
        }
        if constants.contains(name) {
            return Err(bad(
                role,
                name,
                "it is the name of a state value in the model".into(),
            ));
        }
        if let Some(first) = seen.get(name.as_str()) {
            return Err(bad(role, name, format!("{first} has the same name")));
        }
        seen.insert(name, role);
    }
    Ok(())
}

/// A guard as one conjunct after `REQ & _state = sK`, or `None` for `TRUE`. `|` binds weaker
/// than `&`, so a disjunction needs parentheses there.
fn conjunct(g: &Guard, names: &[String]) -> Option<String> {
    match g {
        Guard::True => None,
        Guard::Or(_) => Some(format!("({})", g.display(names))),
        _ => Some(g.display(names).to_string()),
    }
}

/// Writes the module; see the module header for its semantics.
pub(crate) fn write_ecc_module(
    ecc: &Ecc,
    module_name: &str,
    w: &mut impl Write,
) -> Result<(), SmvError> {
    check_names(ecc, module_name)?;
    let mut params = vec!["REQ".to_string()];
    params.extend(ecc.inputs.iter().cloned());

    let plural = if ecc.states.len() == 1 { "" } else { "s" };
    writeln!(
        w,
        "-- ECC with {} state{plural} as a module: one SMV step = one chance for a REQ event.",
        ecc.states.len()
    )?;
    writeln!(w, "MODULE {}({})", module_name, params.join(", "))?;
    writeln!(w, "VAR")?;
    writeln!(w, "  _state : {{{}}};", state_values(ecc).join(", "))?;
    writeln!(w, "  CNF : boolean;")?;
    for z in &ecc.outputs {
        writeln!(w, "  {z} : boolean;")?;
    }

    writeln!(w, "DEFINE")?;
    write_target(ecc, w)?;
    write_fired(ecc, w)?;
    writeln!(w, "ASSIGN")?;
    writeln!(w, "  init(_state) := {};", state_value(StateId(0)))?;
    writeln!(w, "  next(_state) := _target;")?;
    writeln!(w, "  init(CNF) := FALSE;")?;
    writeln!(w, "  next(CNF) := _fired;")?;
    for z in 0..ecc.outputs.len() {
        write_output(ecc, z, w)?;
    }
    Ok(())
}

/// `_target`: the state after this step, the target of the first transition whose guard
/// holds on `REQ`, else the current state (transitions in priority order).
fn write_target(ecc: &Ecc, w: &mut impl Write) -> io::Result<()> {
    writeln!(w, "  _target :=")?;
    writeln!(w, "    case")?;
    for (i, s) in ecc.states.iter().enumerate() {
        for t in &s.transitions {
            let mut cond = format!("REQ & _state = {}", state_value(StateId(i)));
            if let Some(g) = conjunct(&t.guard, &ecc.inputs) {
                cond.push_str(" & ");
                cond.push_str(&g);
            }
            writeln!(w, "      {cond} : {};", state_value(t.target))?;
        }
    }
    writeln!(w, "      TRUE : _state;")?;
    writeln!(w, "    esac;")
}

/// `_fired`: whether a transition fires in this step (`REQ` and some guard of the current
/// state holds).
fn write_fired(ecc: &Ecc, w: &mut impl Write) -> io::Result<()> {
    let names = &ecc.inputs;
    if ecc.states.iter().all(|s| s.transitions.is_empty()) {
        return writeln!(w, "  _fired := FALSE;");
    }
    writeln!(w, "  _fired := REQ &")?;
    writeln!(w, "    case")?;
    for (i, s) in ecc.states.iter().enumerate() {
        if s.transitions.is_empty() {
            continue;
        }
        let any = if s.transitions.iter().any(|t| t.guard == Guard::True) {
            "TRUE".to_string()
        } else {
            let parts: Vec<String> = s
                .transitions
                .iter()
                .map(|t| match &t.guard {
                    // Parentheses only for readability: `&` binds tighter than `|`.
                    g @ (Guard::And(_) | Guard::Or(_)) if s.transitions.len() > 1 => {
                        format!("({})", g.display(names))
                    }
                    g => g.display(names).to_string(),
                })
                .collect();
            parts.join(" | ")
        };
        writeln!(w, "      _state = {} : {any};", state_value(StateId(i)))?;
    }
    writeln!(w, "      TRUE : FALSE;")?;
    writeln!(w, "    esac;")
}

/// `init` and `next` of output `z`: its initial value, then what the algorithm of the state
/// a transition enters does to it (kept when nothing fires).
fn write_output(ecc: &Ecc, z: usize, w: &mut impl Write) -> io::Result<()> {
    let name = &ecc.outputs[z];
    writeln!(
        w,
        "  init({name}) := {};",
        bool_literal(ecc.initial_outputs[z])
    )?;
    let lines: Vec<(usize, String)> = ecc
        .states
        .iter()
        .enumerate()
        .filter_map(|(i, s)| match Effect::of(&s.algorithm, z) {
            Effect::Keep => None,
            Effect::Set(v) => Some((i, bool_literal(v).to_string())),
            Effect::Flip => Some((i, format!("!{name}"))),
        })
        .collect();
    if lines.is_empty() {
        return writeln!(w, "  next({name}) := {name};");
    }
    writeln!(w, "  next({name}) :=")?;
    writeln!(w, "    case")?;
    for (i, value) in lines {
        writeln!(
            w,
            "      _fired & _target = {} : {value};",
            state_value(StateId(i))
        )?;
    }
    writeln!(w, "      TRUE : {name};")?;
    writeln!(w, "    esac;")
}

/// [`write_ecc_module`] into a string.
pub(crate) fn ecc_module_to_string(ecc: &Ecc, module_name: &str) -> Result<String, SmvError> {
    let mut buf = Vec::new();
    write_ecc_module(ecc, module_name, &mut buf)?;
    Ok(String::from_utf8(buf).expect("the SMV emitter writes UTF-8 only"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::samples;

    /// One snapshot per sample ECC, named after the sample.
    #[test]
    fn snapshots() {
        for (name, ecc) in samples::all() {
            insta::assert_snapshot!(name, ecc_module_to_string(&ecc, "m").unwrap());
        }
    }

    fn name_error(ecc: &Ecc, module: &str) -> String {
        let mut buf = Vec::new();
        let e = write_ecc_module(ecc, module, &mut buf).unwrap_err();
        assert!(
            buf.is_empty(),
            "nothing is written before names are checked"
        );
        e.to_string()
    }

    #[test]
    fn bad_names_are_reported_by_name_and_role() {
        let e = samples::tri();
        assert_eq!(
            name_error(&e, "next"),
            "module name `next` cannot be used in the SMV model: it is a NuSMV keyword"
        );
        assert_eq!(
            name_error(&e, "main"),
            "module name `main` cannot be used in the SMV model: it is NuSMV's top module, which \
             takes no parameters"
        );
        let mut bad = e.clone();
        bad.inputs[1] = "_x".into();
        assert!(name_error(&bad, "m").starts_with("input 2 `_x` cannot"));
        let mut bad = e.clone();
        bad.outputs[0] = "REQ".into();
        assert!(name_error(&bad, "m").ends_with("it is the name of an event"));
        let mut bad = e.clone();
        bad.outputs[2] = bad.inputs[0].clone();
        assert!(name_error(&bad, "m").ends_with("input 1 has the same name"));
        let mut bad = e.clone();
        bad.inputs[0] = "s3".into();
        assert!(name_error(&bad, "m").contains("state value"));
        let mut bad = samples::one_state();
        bad.outputs[0] = "s0_unused".into();
        assert!(name_error(&bad, "m").contains("state value"));
    }

    /// A `main` module that drives `module` with a fixed input sequence (a function of the step
    /// counter `t`) and one invariant stating, for every step, the state, outputs and `CNF`
    /// that [`Run::step`](crate::ecc::Run::step) computes on the same sequence.
    fn differential_model(ecc: &Ecc, module: &str, seed: u64, steps: usize) -> String {
        use crate::ecc::Run;
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let script: Vec<(bool, Vec<bool>)> = (0..steps)
            .map(|_| {
                let x = (0..ecc.inputs.len()).map(|_| rng.gen_bool(0.5)).collect();
                (rng.gen_bool(0.8), x)
            })
            .collect();
        // The SMV expression of one driven signal as a function of `t`.
        let signal = |values: Vec<bool>| {
            let mut c = String::from("case ");
            for (k, v) in values.into_iter().enumerate() {
                c += &format!("t = {k} : {}; ", bool_literal(v));
            }
            c + "TRUE : FALSE; esac"
        };
        // The counter stops one beyond the last claimed step: a saturated counter repeats its
        // inputs, so the state reached there is not a function of `t` any more.
        let stop = steps + 1;
        let mut m = format!("MODULE main\nVAR\n  t : 0..{stop};\n");
        let mut args = vec!["d_REQ".to_string()];
        args.extend(ecc.inputs.iter().map(|n| format!("d_{n}")));
        m += &format!("  e : {module}({});\n", args.join(", "));
        m += &format!("ASSIGN\n  init(t) := 0;\n  next(t) := t < {stop} ? t + 1 : t;\nDEFINE\n");
        m += &format!(
            "  d_REQ := {};\n",
            signal(script.iter().map(|s| s.0).collect())
        );
        for (i, n) in ecc.inputs.iter().enumerate() {
            m += &format!(
                "  d_{n} := {};\n",
                signal(script.iter().map(|s| s.1[i]).collect())
            );
        }
        let mut run = Run::new(ecc);
        let mut cnf = false;
        let mut claims = Vec::new();
        for k in 0..=steps {
            let mut c = format!(
                "e._state = {} & e.CNF = {}",
                state_value(run.state),
                bool_literal(cnf)
            );
            for (z, n) in ecc.outputs.iter().enumerate() {
                c += &format!(" & e.{n} = {}", bool_literal(run.outputs[z]));
            }
            claims.push(format!("(t = {k} -> {c})"));
            if let Some((req, x)) = script.get(k) {
                cnf = *req && run.step(x).is_some();
            }
        }
        m += &format!("INVARSPEC\n  {}\n", claims.join(" &\n  "));
        m + &ecc_module_to_string(ecc, module).unwrap()
    }

    /// The module agrees with the simulator step by step, on the samples and on random ECCs.
    /// Runs wherever NuSMV is installed, and always under CI (where a missing NuSMV fails).
    #[test]
    fn module_agrees_with_simulator_in_nusmv() {
        let Some(nusmv) = crate::nusmv::nusmv_for_tests() else {
            return;
        };
        let nusmv = nusmv.path;
        let dir = tempfile::tempdir().unwrap();
        let mut machines: Vec<(String, Ecc)> = samples::all()
            .into_iter()
            .map(|(n, e)| (n.to_string(), e))
            .collect();
        for seed in 0..12u64 {
            let (c, i, o) = (
                1 + seed as usize % 4,
                1 + seed as usize % 3,
                1 + seed as usize % 3,
            );
            machines.push((
                format!("random{seed}"),
                crate::ecc::random::random_ecc(seed, c, i, o),
            ));
        }
        for (name, ecc) in machines {
            for seed in 0..3 {
                let path = dir.path().join(format!("{name}_{seed}.smv"));
                std::fs::write(&path, differential_model(&ecc, "m", seed, 40)).unwrap();
                let out = std::process::Command::new(&nusmv)
                    .arg(&path)
                    .output()
                    .unwrap();
                let stdout = String::from_utf8_lossy(&out.stdout);
                assert!(
                    out.status.success() && stdout.contains("is true"),
                    "{name} seed {seed}:\n{stdout}\n{}",
                    String::from_utf8_lossy(&out.stderr)
                );
            }
        }
    }
}
