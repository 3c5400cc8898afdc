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
//!
//! # Consecutive composites ([`Topology::Consecutive`], fbSAT's consecutive-modular)
//! - The modules form a chain. Each reads any subset of the inputs and every module has every
//!   output: its algorithm rewrites the whole output vector.
//! - On `REQ`, module 1 steps as a basic ECC, its algorithm applied to the composite's outputs
//!   before the step. If it fired, its `CNF` is module 2's `REQ`: module 2 steps on the same
//!   inputs, its algorithm applied to module 1's results (`x` passes module 1's value on), and
//!   so on down the chain. The composite's outputs and `CNF` are the last module's.
//! - If module 1 does not fire nothing happens. Every later module is *complete*: the last
//!   transition of each of its states is unconditional, so it fires whenever it gets `REQ` and
//!   the whole chain fires whenever module 1 does (the synthesis makes it so, which changes
//!   nothing on the recordings, where every active step runs the whole chain). A recorded active
//!   step thus needs every module to fire and a passive step needs module 1 not to fire.
//! - So the chain is one ECC over the product of the modules' states ([`Modular::flatten`]):
//!   what the single-block exports write for it.

use super::{
    Algorithm, Controller, Ecc, Fired, Guard, InputId, OutputId, Reactive, Run, Size, State,
    StateId, Transition, Tri,
};
use std::collections::HashMap;

/// How the modules of a composite are wired (see the module documentation).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Topology {
    /// Every module gets `REQ` and owns some of the outputs; `CNF` if some module fired.
    #[default]
    Parallel,
    /// A chain: `REQ` to module 1, each module's `CNF` to the next, every module rewrites
    /// every output in turn; `CNF` if the last module fired.
    Consecutive,
}

impl Topology {
    /// The name users write (`--topology`) and the JSON files carry.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Topology::Parallel => "parallel",
            Topology::Consecutive => "consecutive",
        }
    }
}

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
    /// How they are wired.
    pub topology: Topology,
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
    /// One line per module: its size, the outputs it writes and the inputs it reads
    /// (`module 1: 2 states, 3 transitions, 4 guard literals; outputs: a; inputs: x, y`).
    pub fn describe(&self) -> Vec<String> {
        let list = |v: &[String]| match v.is_empty() {
            true => "-".to_string(),
            false => v.join(", "),
        };
        (self.modules.iter().enumerate())
            .map(|(m, module)| {
                let s = module.ecc.size();
                format!(
                    "module {}: {} states, {} transitions, {} guard literals; outputs: {}; inputs: {}",
                    m + 1,
                    s.c,
                    s.t,
                    s.n,
                    list(&module.ecc.outputs),
                    list(&module.ecc.inputs)
                )
            })
            .collect()
    }

    /// Checks that the modules partition the outputs, read existing inputs and that each
    /// module's ECC is valid over its own interface with the composite's names.
    pub fn validate(&self) -> Result<(), String> {
        if self.initial_outputs.len() != self.outputs.len() {
            return Err("initial_outputs does not match the outputs".into());
        }
        let mut owner = vec![None; self.outputs.len()];
        let chain = self.topology == Topology::Consecutive;
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
                if let (Some(other), false) = (slot.replace(m), chain) {
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
        if let Some(m) =
            (self.modules.iter()).position(|m| chain && m.outputs.len() != self.outputs.len())
        {
            return Err(format!(
                "module {} of a consecutive composite lacks outputs",
                m + 1
            ));
        }
        for (m, module) in self.modules.iter().enumerate().skip(1) {
            if let Some(q) = (module.ecc.states.iter()).position(|s| {
                chain
                    && !s
                        .transitions
                        .last()
                        .is_some_and(|t| unconditional(&t.guard))
            }) {
                return Err(format!(
                    "module {} of a consecutive composite: state {} does not end with an unconditional transition",
                    m + 1,
                    module.ecc.states[q].name
                ));
            }
        }
        Ok(())
    }

    /// A consecutive composite as one ECC over the composite's interface: its states are the
    /// tuples of module states reachable from the initial one (named `s0_s1...` after the
    /// modules' states), entered when the whole chain fires; a transition's guard is "module
    /// `m` takes its `k_m`-th transition" for every `m` (a conjunction without double
    /// negations; choices no input vector makes are left out), and a state's algorithm is the
    /// modules' algorithms composed. Fails on a parallel composite or past `limit` states.
    pub(crate) fn flatten(&self, limit: usize) -> Result<Ecc, String> {
        if self.topology != Topology::Consecutive {
            return Err("only a consecutive composite is flattened".into());
        }
        self.validate()?;
        let start = vec![StateId(0); self.modules.len()];
        let mut index: HashMap<Vec<StateId>, usize> = HashMap::from([(start.clone(), 0)]);
        let mut tuples = vec![start];
        let mut states: Vec<State> = Vec::new();
        while let Some(tuple) = tuples.get(states.len()).cloned() {
            let counts: Vec<usize> = (self.modules.iter().zip(&tuple))
                .map(|(m, q)| m.ecc.states[q.0].transitions.len())
                .collect();
            let mut transitions = Vec::new();
            // Every choice of one transition per module, the last module's varying fastest;
            // none when module 1 has no transition here (the others always have one).
            let mut choice = Some(vec![0usize; tuple.len()]).filter(|_| counts[0] > 0);
            while let Some(ks) = choice {
                let mut parts = Vec::new();
                let mut target = Vec::new();
                for ((module, q), &k) in self.modules.iter().zip(&tuple).zip(&ks) {
                    let ts = &module.ecc.states[q.0].transitions;
                    parts.extend((ts[..k].iter()).map(|t| Guard::negate(widen(module, &t.guard))));
                    match widen(module, &ts[k].guard) {
                        Guard::And(hs) => parts.extend(hs),
                        g => parts.push(g),
                    }
                    target.push(ts[k].target);
                }
                let mut seen = std::collections::HashSet::new();
                parts.retain(|g| !unconditional(g) && seen.insert(g.clone()));
                let guard = match parts.len() {
                    0 => Guard::True,
                    1 => parts.pop().expect("one part"),
                    _ => Guard::And(parts),
                };
                // A choice no input vector makes (module 1 passing a transition that module 2's
                // earlier one implies, say) never fires: it is left out, which changes nothing.
                if !guard.satisfiable() {
                    choice = odometer(ks, &counts);
                    continue;
                }
                let next = index.len();
                let id = *index.entry(target.clone()).or_insert(next);
                if id == next {
                    if next >= limit {
                        return Err(format!("the chain has more than {limit} states"));
                    }
                    tuples.push(target);
                }
                transitions.push(Transition {
                    target: StateId(id),
                    guard,
                });
                choice = odometer(ks, &counts);
            }
            let names: Vec<&str> = (self.modules.iter().zip(&tuple))
                .map(|(m, q)| m.ecc.states[q.0].name.as_str())
                .collect();
            states.push(State {
                name: names.join("_"),
                algorithm: self.composed(&tuple),
                transitions,
            });
        }
        let ecc = Ecc {
            inputs: self.inputs.clone(),
            outputs: self.outputs.clone(),
            initial_outputs: self.initial_outputs.clone(),
            states,
        };
        ecc.validate()?;
        Ok(ecc)
    }

    /// The algorithms of the states in `tuple` applied one after the other, as one algorithm
    /// of the first module's form.
    fn composed(&self, tuple: &[StateId]) -> Algorithm {
        let algorithms: Vec<&Algorithm> = (self.modules.iter().zip(tuple))
            .map(|(m, q)| &m.ecc.states[q.0].algorithm)
            .collect();
        let after = |z: usize, old: bool| algorithms.iter().fold(old, |v, a| a.apply_one(z, v));
        let z_count = self.outputs.len();
        match algorithms[0] {
            Algorithm::Tri(_) => Algorithm::Tri(
                (0..z_count)
                    .map(|z| match (after(z, false), after(z, true)) {
                        (false, false) => Tri::Zero,
                        (true, true) => Tri::One,
                        // No composition of 0, 1 and keep flips.
                        _ => Tri::Keep,
                    })
                    .collect(),
            ),
            Algorithm::Binary { .. } => Algorithm::Binary {
                a0: (0..z_count).map(|z| after(z, false)).collect(),
                a1: (0..z_count).map(|z| after(z, true)).collect(),
            },
        }
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

    /// The module owning output `z`: in a consecutive composite the last one, whose values
    /// are the composite's.
    pub(crate) fn owner(&self, z: OutputId) -> Option<usize> {
        match self.topology {
            Topology::Parallel => self.modules.iter().position(|m| m.outputs.contains(&z)),
            Topology::Consecutive => self.modules.len().checked_sub(1),
        }
    }
}

/// Whether a guard holds whatever the inputs (as the synthesis writes "always": `TRUE` or an
/// empty conjunction).
fn unconditional(g: &Guard) -> bool {
    match g {
        Guard::True => true,
        Guard::And(hs) => hs.iter().all(unconditional),
        _ => false,
    }
}

/// A module's guard over the composite's inputs.
fn widen(module: &Module, g: &Guard) -> Guard {
    match g {
        Guard::True | Guard::False => g.clone(),
        Guard::Var(i) => Guard::Var(module.inputs[i.0]),
        Guard::Not(h) => Guard::Not(Box::new(widen(module, h))),
        Guard::And(hs) => Guard::And(hs.iter().map(|h| widen(module, h)).collect()),
        Guard::Or(hs) => Guard::Or(hs.iter().map(|h| widen(module, h)).collect()),
    }
}

/// The choice after `ks` (one index per position below `counts`), the last position varying
/// fastest; `None` after the last.
fn odometer(mut ks: Vec<usize>, counts: &[usize]) -> Option<Vec<usize>> {
    for m in (0..ks.len()).rev() {
        ks[m] += 1;
        if ks[m] < counts[m] {
            return Some(ks);
        }
        ks[m] = 0;
    }
    None
}

/// A running composite: one [`Run`] per module and the composite's output vector.
#[derive(Debug, Clone)]
pub struct ModularRun<'a> {
    modular: &'a Modular,
    /// Each module's run, in module order.
    pub runs: Vec<Run<'a>>,
    /// The composite's current output values.
    pub(crate) outputs: Vec<bool>,
    /// Per module, the transition it fired on the last `REQ` (`None`: it did not fire or, in
    /// a chain, got no `REQ`).
    pub(crate) fired: Vec<Option<Fired>>,
}

impl<'a> ModularRun<'a> {
    /// Every module in its initial state, the composite outputs at their initial values.
    pub(crate) fn new(modular: &'a Modular) -> ModularRun<'a> {
        ModularRun {
            modular,
            runs: modular.modules.iter().map(|m| Run::new(&m.ecc)).collect(),
            outputs: modular.initial_outputs.clone(),
            fired: vec![None; modular.modules.len()],
        }
    }

    /// One `REQ` on the full input vector `x`: every module steps on its inputs. Returns
    /// whether the composite emitted `CNF` (some module fired); `self.outputs` then holds the
    /// values emitted.
    pub(crate) fn step(&mut self, x: &[bool]) -> bool {
        self.fired.iter_mut().for_each(|f| *f = None);
        if self.modular.topology == Topology::Consecutive {
            return self.chain(x);
        }
        let mut any = false;
        for ((module, run), fired) in (self.modular.modules.iter())
            .zip(&mut self.runs)
            .zip(&mut self.fired)
        {
            let local: Vec<bool> = module.inputs.iter().map(|i| x[i.0]).collect();
            *fired = run.step(&local);
            if fired.is_some() {
                any = true;
                for (j, z) in module.outputs.iter().enumerate() {
                    self.outputs[z.0] = run.outputs[j];
                }
            }
        }
        any
    }

    /// One `REQ` down a consecutive chain: each module starts from the values the one before
    /// produced (module 1 from the composite's), and the chain stops at a module that does not
    /// fire.
    fn chain(&mut self, x: &[bool]) -> bool {
        let mut values = self.outputs.clone();
        for ((module, run), fired) in (self.modular.modules.iter())
            .zip(&mut self.runs)
            .zip(&mut self.fired)
        {
            let local: Vec<bool> = module.inputs.iter().map(|i| x[i.0]).collect();
            run.outputs.clone_from(&values);
            *fired = run.step(&local);
            if fired.is_none() {
                return false;
            }
            values.clone_from(&run.outputs);
        }
        self.outputs = values;
        true
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
            topology: Topology::Parallel,
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

    /// A chain over one input `a` where module 2 reads the input module 1 just tested: half of
    /// the choices of one transition per module contradict themselves.
    fn contradicting_chain() -> Modular {
        let a = Guard::Var(InputId(0));
        let not_a = Guard::Not(Box::new(a.clone()));
        let state = |name: &str, z: Tri, transitions: Vec<(Guard, usize)>| State {
            name: name.into(),
            algorithm: Algorithm::Tri(vec![z]),
            transitions: (transitions.into_iter())
                .map(|(guard, t)| Transition {
                    target: StateId(t),
                    guard,
                })
                .collect(),
        };
        let ecc = |states| Ecc {
            inputs: vec!["a".into()],
            outputs: vec!["z".into()],
            initial_outputs: vec![false],
            states,
        };
        let module = |ecc| Module {
            inputs: vec![InputId(0)],
            outputs: vec![OutputId(0)],
            ecc,
        };
        let first = ecc(vec![
            state("p", Tri::One, vec![(a.clone(), 1), (Guard::True, 0)]),
            state("q", Tri::Zero, vec![(not_a.clone(), 0)]),
        ]);
        let second = ecc(vec![
            state("u", Tri::Keep, vec![(not_a, 1), (Guard::True, 0)]),
            state("v", Tri::Keep, vec![(Guard::And(vec![]), 0)]),
        ]);
        Modular {
            inputs: vec!["a".into()],
            outputs: vec!["z".into()],
            initial_outputs: vec![false],
            modules: vec![module(first), module(second)],
            topology: Topology::Consecutive,
        }
    }

    #[test]
    fn flattening_leaves_out_impossible_choices_and_double_negations() {
        let chain = contradicting_chain();
        let flat = chain.flatten(100).unwrap();
        let names = &flat.inputs;
        let guards: Vec<String> = (flat.states.iter())
            .flat_map(|s| {
                s.transitions
                    .iter()
                    .map(|t| t.guard.display(names).to_string())
            })
            .collect();
        // From (p, u): `a` then `!a` and `!a` then `a` can never hold; `!!a` is `a`, and
        // `a & a` is `a`.
        assert_eq!(flat.states[0].name, "p_u");
        let first: Vec<String> = (flat.states[0].transitions.iter())
            .map(|t| t.guard.display(names).to_string())
            .collect();
        assert_eq!(first, ["a", "!a"]);
        for (g, t) in guards
            .iter()
            .zip(flat.states.iter().flat_map(|s| &s.transitions))
        {
            assert!(t.guard.satisfiable(), "{g}");
            assert!(!g.contains("!!"), "{g}");
        }
        // The same behaviour as the chain on every input sequence of 8 steps.
        for bits in 0u32..256 {
            let (mut c, mut f) = (chain.start(), flat.start());
            for k in 0..8 {
                let x = [bits >> k & 1 == 1];
                let (c_out, f_out) = (c.react(&x).map(<[bool]>::to_vec), f.react(&x));
                assert_eq!(c_out.as_deref(), f_out, "inputs {bits:08b}, step {k}");
            }
        }
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
