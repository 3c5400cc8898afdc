//! Modular controllers (the SAT reconstruction paper, section V): `M` ECCs that share the input event and split the
//! outputs among them.
//!
//! In: module ECCs, each over a subset of the composite's inputs and owning a subset of its
//! outputs. Out: the composite's behaviour on full input/output vectors ([`ModularRun`]).
//!
//! # Semantics of the composite
//! - Every output belongs to exactly one module (the paper's θ); a module reads any subset of
//!   the inputs (α). A module's [`Ecc`] is written over its own interface: its inputs and
//!   outputs are those subsets, in the composite's order.
//! - On `REQ` with input vector `x`, every module receives `REQ` with `x` restricted to its
//!   inputs and steps as a basic ECC ([`Run::step`]). The composite's outputs are the union of
//!   the modules' outputs.
//! - The composite emits `CNF` iff at least one module fired (emitted its own `CNF`); if none
//!   fired nothing happens. So a recorded active step ([`Step`](crate::scenario::Step) with
//!   `Some` outputs) needs at least one module to fire and a passive step needs all of them to
//!   stay put: the composite is a drop-in replacement for a single ECC on scenarios.

use super::{Controller, Ecc, InputId, OutputId, Reactive, Run, Size};

/// One module: which composite inputs it reads, which outputs it owns, and its ECC over them.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Module {
    /// Composite inputs read by the module, ascending; the ECC's input `i` is `inputs[i]`.
    pub inputs: Vec<InputId>,
    /// Composite outputs owned by the module, ascending; the ECC's output `j` is `outputs[j]`.
    pub outputs: Vec<OutputId>,
    /// The module's own machine, over its inputs and outputs only.
    pub ecc: Ecc,
}

/// A modular controller: modules in order (module `m` is numbered `m + 1` for users).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Modular {
    /// Names of the composite's inputs (every module reads a subset).
    pub inputs: Vec<String>,
    /// Names of the composite's outputs (each owned by exactly one module).
    pub outputs: Vec<String>,
    /// Output values before the first `REQ`.
    pub initial_outputs: Vec<bool>,
    /// The modules, each called once per `REQ` in this order.
    pub modules: Vec<Module>,
}

/// Size figures of a modular controller, as the SAT reconstruction paper minimizes them.
#[derive(Debug, Clone, PartialEq, Eq, Hash, serde::Serialize)]
pub struct ModularSize {
    /// States of the largest module.
    pub max_states: usize,
    /// Inputs read, summed over the modules (the paper's `A`).
    pub inputs_used: usize,
    /// States, summed over the modules (the paper's `N'`).
    pub total_states: usize,
    /// Per module, its ECC's size.
    pub modules: Vec<Size>,
}

impl Modular {
    /// Checks that the modules partition the outputs, read existing inputs and that each
    /// module's ECC is valid over its own interface with the composite's names.
    pub fn validate(&self) -> Result<(), String> {
        if self.initial_outputs.len() != self.outputs.len() {
            return Err("initial_outputs does not match the outputs".into());
        }
        let mut owner = vec![None; self.outputs.len()];
        for (m, module) in self.modules.iter().enumerate() {
            let e = &module.ecc;
            e.validate().map_err(|s| format!("module {}: {s}", m + 1))?;
            if !module.inputs.windows(2).all(|w| w[0] < w[1])
                || !module.outputs.windows(2).all(|w| w[0] < w[1])
            {
                return Err(format!("module {}: interface not ascending", m + 1));
            }
            let in_names: Vec<&String> = module
                .inputs
                .iter()
                .map(|i| self.inputs.get(i.0))
                .collect::<Option<_>>()
                .ok_or_else(|| format!("module {} reads a missing input", m + 1))?;
            if e.inputs.iter().collect::<Vec<_>>() != in_names {
                return Err(format!("module {}: input names differ", m + 1));
            }
            for (j, z) in module.outputs.iter().enumerate() {
                let slot = owner
                    .get_mut(z.0)
                    .ok_or_else(|| format!("module {} owns a missing output", m + 1))?;
                if let Some(other) = slot.replace(m) {
                    return Err(format!(
                        "output {} belongs to modules {} and {}",
                        self.outputs[z.0],
                        other + 1,
                        m + 1
                    ));
                }
                if e.outputs.get(j) != Some(&self.outputs[z.0])
                    || e.initial_outputs.get(j) != Some(&self.initial_outputs[z.0])
                {
                    return Err(format!("module {}: output {j} differs", m + 1));
                }
            }
            if e.outputs.len() != module.outputs.len() {
                return Err(format!("module {}: output count differs", m + 1));
            }
        }
        if let Some(z) = owner.iter().position(Option::is_none) {
            return Err(format!("output {} belongs to no module", self.outputs[z]));
        }
        Ok(())
    }

    /// Its size: per module and the totals the modular minimization works on.
    pub fn size(&self) -> ModularSize {
        let modules: Vec<Size> = self.modules.iter().map(|m| m.ecc.size()).collect();
        ModularSize {
            max_states: modules.iter().map(|s| s.c).max().unwrap_or(0),
            inputs_used: self.modules.iter().map(|m| m.inputs.len()).sum(),
            total_states: modules.iter().map(|s| s.c).sum(),
            modules,
        }
    }

    /// The module owning output `z`.
    pub fn owner(&self, z: OutputId) -> Option<usize> {
        self.modules.iter().position(|m| m.outputs.contains(&z))
    }
}

/// A running composite: one [`Run`] per module and the composite's output vector.
#[derive(Debug, Clone)]
pub struct ModularRun<'a> {
    modular: &'a Modular,
    /// Each module's run, in module order.
    pub runs: Vec<Run<'a>>,
    /// The composite's current output values.
    pub outputs: Vec<bool>,
}

impl<'a> ModularRun<'a> {
    /// Every module in its initial state, the composite outputs at their initial values.
    pub fn new(modular: &'a Modular) -> ModularRun<'a> {
        ModularRun {
            modular,
            runs: modular.modules.iter().map(|m| Run::new(&m.ecc)).collect(),
            outputs: modular.initial_outputs.clone(),
        }
    }

    /// One `REQ` on the full input vector `x`: every module steps on its inputs. Returns
    /// whether the composite emitted `CNF` (some module fired); `self.outputs` then holds the
    /// values emitted.
    pub fn step(&mut self, x: &[bool]) -> bool {
        let mut any = false;
        for (module, run) in self.modular.modules.iter().zip(&mut self.runs) {
            let local: Vec<bool> = module.inputs.iter().map(|i| x[i.0]).collect();
            if run.step(&local).is_some() {
                any = true;
                for (j, z) in module.outputs.iter().enumerate() {
                    self.outputs[z.0] = run.outputs[j];
                }
            }
        }
        any
    }
}

impl Reactive for ModularRun<'_> {
    fn react(&mut self, x: &[bool]) -> Option<&[bool]> {
        self.step(x).then_some(self.outputs.as_slice())
    }
}

impl Controller for Modular {
    type Run<'a> = ModularRun<'a>;
    fn start(&self) -> ModularRun<'_> {
        ModularRun::new(self)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::ecc::{Algorithm, Guard, State, StateId, Transition, Tri};

    /// A lamp toggled by a button: state 1 = lamp on.
    fn toggle(button: &str, lamp: &str) -> Ecc {
        let b = Guard::Var(InputId(0));
        let state = |name: &str, on: bool, target: usize| State {
            name: name.into(),
            algorithm: Algorithm::Tri(vec![if on { Tri::One } else { Tri::Zero }]),
            transitions: vec![Transition {
                target: StateId(target),
                guard: b.clone(),
            }],
        };
        Ecc {
            inputs: vec![button.into()],
            outputs: vec![lamp.into()],
            initial_outputs: vec![false],
            states: vec![state("s0", false, 1), state("s1", true, 0)],
        }
    }

    /// Two independent toggles: `a` toggles `la`, `b` toggles `lb`.
    pub(crate) fn two_toggles() -> Modular {
        Modular {
            inputs: vec!["a".into(), "b".into()],
            outputs: vec!["la".into(), "lb".into()],
            initial_outputs: vec![false, false],
            modules: vec![
                Module {
                    inputs: vec![InputId(0)],
                    outputs: vec![OutputId(0)],
                    ecc: toggle("a", "la"),
                },
                Module {
                    inputs: vec![InputId(1)],
                    outputs: vec![OutputId(1)],
                    ecc: toggle("b", "lb"),
                },
            ],
        }
    }

    #[test]
    fn composite_emits_cnf_iff_some_module_fires() {
        let m = two_toggles();
        m.validate().unwrap();
        let mut r = ModularRun::new(&m);
        assert!(!r.step(&[false, false]));
        assert!(r.step(&[true, false]));
        assert_eq!(r.outputs, vec![true, false]);
        assert!(r.step(&[true, true]));
        assert_eq!(r.outputs, vec![false, true]);
        let steps: [(&[bool], Option<&[bool]>); 2] = [
            (&[false, true], Some(&[false, true])),
            (&[false, false], Some(&[false, true])),
        ];
        let e = crate::ecc::replay(&m, steps).unwrap_err();
        assert_eq!((e.step, e.actual), (1, None));
    }

    #[test]
    fn validate_rejects_shared_and_orphan_outputs() {
        let mut m = two_toggles();
        m.modules[1].outputs = vec![OutputId(0)];
        m.modules[1].ecc.outputs = vec!["la".into()];
        let e = m.validate().unwrap_err();
        assert!(e.contains("belongs to modules 1 and 2"), "{e}");
        m.modules.pop();
        let e = m.validate().unwrap_err();
        assert!(e.contains("lb belongs to no module"), "{e}");
    }
}
