//! Properties as deterministic monitors with at most one bit of memory each: the fragment of
//! LTL the game engine solves.
//!
//! In: the properties, the plant and the coupling (to resolve atoms). Out: [`Monitors`], whose
//! [`Monitors::step`] reads one closed-loop step (the atoms' values) and says whether a safety
//! part failed and which recurring goals were met; or why a property is outside the fragment.
//!
//! | form | memory | bad step | goal (met infinitely often) |
//! |---|---|---|---|
//! | `G p` | - | `!p` | - |
//! | `G (a -> X b)` | `a` held last step | memory and `!b` | - |
//! | `G (a -> F b)` | an open request | - | no open request |
//! | `G (a -> (b U c))` | an open request | open (or `a`), `!c`, `!b` | no open request |
//! | `G F p` | - | - | `p` |
//! | `(F G e) -> ψ`, `ψ` one of the two above with a goal | as `ψ` | as `ψ` | `ψ`'s goal or `!e` |
//!
//! `p`, `a`, `b`, `c`, `e` are propositional (no temporal operator); a conjunction at the top
//! splits. The assumption form is exact because `G F x | G F y` is `G F (x | y)`: the
//! property fails only where the environment keeps `e` from some step on.

use crate::check::{Atom, AtomError, Source, Wiring};
use crate::ltl::{Ltl, Property};
use crate::plant::explicit::Semantics;
use crate::plant::{Model, Name, Value};
use std::collections::HashMap;

/// A propositional formula over resolved atoms (bit `i` of a valuation: atom `i`).
#[derive(Debug, Clone)]
enum Prop {
    Const(bool),
    Atom(usize),
    Not(Box<Prop>),
    And(Box<Prop>, Box<Prop>),
    Or(Box<Prop>, Box<Prop>),
    Iff(Box<Prop>, Box<Prop>),
}

impl Prop {
    fn eval(&self, v: u64) -> bool {
        match self {
            Prop::Const(b) => *b,
            Prop::Atom(i) => v >> i & 1 == 1,
            Prop::Not(a) => !a.eval(v),
            Prop::And(a, b) => a.eval(v) && b.eval(v),
            Prop::Or(a, b) => a.eval(v) || b.eval(v),
            Prop::Iff(a, b) => a.eval(v) == b.eval(v),
        }
    }
}

/// One monitor.
#[derive(Debug, Clone)]
enum Kind {
    Invariant(Prop),
    Next {
        trigger: Prop,
        then: Prop,
    },
    Response {
        trigger: Prop,
        answer: Prop,
        excuse: Option<Prop>,
    },
    Until {
        trigger: Prop,
        hold: Prop,
        release: Prop,
    },
    Recurrence {
        goal: Prop,
        excuse: Option<Prop>,
    },
}

/// What one step of the closed loop does to the monitors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Step {
    /// The monitors' memory after the step.
    pub(crate) memory: u64,
    /// A safety part failed at this step.
    pub(crate) bad: bool,
    /// Bit `g`: goal `g` was met at this step.
    pub(crate) goals: u64,
}

/// The monitors of every property, with the atoms they read.
#[derive(Debug, Clone)]
pub(crate) struct Monitors {
    kinds: Vec<Kind>,
    /// Per monitor: its memory bit, if it has one.
    bits: Vec<Option<u32>>,
    /// Per monitor: its goal, if it has one.
    goals: Vec<Option<u32>>,
    atoms: Vec<Atom>,
    /// Per atom: whether it reads only the plant's state (not the outputs, directly or
    /// through a define of the plant that reads its parameters).
    plant_only: Vec<bool>,
    /// Per goal: the name of its property.
    pub(crate) goal_names: Vec<String>,
}

/// Why a property is outside the fragment (or cannot be resolved).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Outside(pub(crate) String);

struct Builder<'a> {
    model: &'a Model,
    coupling: &'a Wiring,
    atoms: Vec<Atom>,
    index: HashMap<Ltl, usize>,
}

impl Builder<'_> {
    fn prop(&mut self, f: &Ltl) -> Option<Prop> {
        let two =
            |b: &mut Self, x: &Ltl, y: &Ltl| Some((Box::new(b.prop(x)?), Box::new(b.prop(y)?)));
        Some(match f {
            Ltl::True => Prop::Const(true),
            Ltl::False => Prop::Const(false),
            Ltl::Atom(_) | Ltl::Cmp(..) => {
                if let Some(&i) = self.index.get(f) {
                    return Some(Prop::Atom(i));
                }
                let a = Atom::resolve(f, self.model, self.coupling).ok()?;
                self.atoms.push(a);
                self.index.insert(f.clone(), self.atoms.len() - 1);
                Prop::Atom(self.atoms.len() - 1)
            }
            Ltl::Not(a) => Prop::Not(Box::new(self.prop(a)?)),
            Ltl::And(a, b) => {
                let (a, b) = two(self, a, b)?;
                Prop::And(a, b)
            }
            Ltl::Or(a, b) => {
                let (a, b) = two(self, a, b)?;
                Prop::Or(a, b)
            }
            Ltl::Implies(a, b) => {
                let (a, b) = two(self, a, b)?;
                Prop::Or(Box::new(Prop::Not(a)), b)
            }
            Ltl::Iff(a, b) | Ltl::Xnor(a, b) => {
                let (a, b) = two(self, a, b)?;
                Prop::Iff(a, b)
            }
            Ltl::Xor(a, b) => {
                let (a, b) = two(self, a, b)?;
                Prop::Not(Box::new(Prop::Iff(a, b)))
            }
            // Not a property of one state: the formula is outside what the monitors cover.
            // Listed one by one, so that a new operator is placed here or above knowingly.
            Ltl::Int(_)
            | Ltl::X(_)
            | Ltl::F(_)
            | Ltl::G(_)
            | Ltl::U(..)
            | Ltl::V(..)
            | Ltl::Y(_)
            | Ltl::Z(_)
            | Ltl::H(_)
            | Ltl::O(_)
            | Ltl::S(..)
            | Ltl::T(..) => return None,
        })
    }

    /// `F G e` (or a conjunction of such) as `e`.
    fn persistence(&mut self, f: &Ltl) -> Option<Prop> {
        match f {
            Ltl::F(g) => match &**g {
                Ltl::G(e) => self.prop(e),
                _ => None,
            },
            Ltl::And(a, b) => Some(Prop::And(
                Box::new(self.persistence(a)?),
                Box::new(self.persistence(b)?),
            )),
            _ => None,
        }
    }

    fn kinds(&mut self, f: &Ltl, out: &mut Vec<Kind>) -> Option<()> {
        match f {
            Ltl::And(a, b) => {
                self.kinds(a, out)?;
                self.kinds(b, out)
            }
            Ltl::G(body) => {
                if let Some(p) = self.prop(body) {
                    out.push(Kind::Invariant(p));
                    return Some(());
                }
                out.push(match &**body {
                    Ltl::F(g) => Kind::Recurrence {
                        goal: self.prop(g)?,
                        excuse: None,
                    },
                    Ltl::Implies(a, b) => {
                        let trigger = self.prop(a)?;
                        match &**b {
                            Ltl::X(then) => Kind::Next {
                                trigger,
                                then: self.prop(then)?,
                            },
                            Ltl::F(answer) => Kind::Response {
                                trigger,
                                answer: self.prop(answer)?,
                                excuse: None,
                            },
                            Ltl::U(hold, release) => Kind::Until {
                                trigger,
                                hold: self.prop(hold)?,
                                release: self.prop(release)?,
                            },
                            _ => return None,
                        }
                    }
                    _ => return None,
                });
                Some(())
            }
            Ltl::Implies(assumption, guarantee) => {
                let e = self.persistence(assumption)?;
                let mut inner = Vec::new();
                self.kinds(guarantee, &mut inner)?;
                let [k] = <[Kind; 1]>::try_from(inner).ok()?;
                let excuse = Some(Prop::Not(Box::new(e)));
                out.push(match k {
                    Kind::Response {
                        trigger,
                        answer,
                        excuse: None,
                    } => Kind::Response {
                        trigger,
                        answer,
                        excuse,
                    },
                    Kind::Recurrence { goal, excuse: None } => Kind::Recurrence { goal, excuse },
                    _ => return None,
                });
                Some(())
            }
            _ => None,
        }
    }
}

impl Monitors {
    /// The monitors of `props` (names as [`crate::ltl::property_name`]), or the first property
    /// outside the fragment.
    pub(crate) fn of(
        props: &[Property],
        model: &Model,
        coupling: &Wiring,
    ) -> Result<Monitors, Outside> {
        let mut b = Builder {
            model,
            coupling,
            atoms: Vec::new(),
            index: HashMap::new(),
        };
        let mut kinds = Vec::new();
        let mut owner = Vec::new();
        for (i, p) in props.iter().enumerate() {
            let before = kinds.len();
            if b.kinds(&p.formula, &mut kinds).is_none() {
                return Err(Outside(format!(
                    "{} (line {}) is not of a form the strategy engine solves",
                    crate::ltl::property_name(i, p),
                    p.line
                )));
            }
            owner.extend(std::iter::repeat_n(i, kinds.len() - before));
        }
        if b.atoms.len() > 64 {
            return Err(Outside(format!("{} atoms (at most 64)", b.atoms.len())));
        }
        let (mut bits, mut goals, mut goal_names) = (Vec::new(), Vec::new(), Vec::new());
        let mut nbits = 0;
        for (k, &i) in kinds.iter().zip(&owner) {
            let has_bit = matches!(
                k,
                Kind::Next { .. } | Kind::Response { .. } | Kind::Until { .. }
            );
            bits.push(has_bit.then(|| {
                nbits += 1;
                nbits - 1
            }));
            let has_goal = !matches!(k, Kind::Invariant(_) | Kind::Next { .. });
            goals.push(has_goal.then(|| {
                goal_names.push(crate::ltl::property_name(i, &props[i]));
                goal_names.len() as u32 - 1
            }));
        }
        if nbits > 64 || goal_names.len() > 64 {
            return Err(Outside("more than 64 monitor bits or goals".into()));
        }
        let plant_only = b
            .atoms
            .iter()
            .map(|a| {
                a.sources().iter().all(|s| match s {
                    Source::Output(_) => false,
                    Source::Plant(Name::Define(d)) => {
                        !crate::plant::explicit::reads_params(model, &model.defines[d.0].expr)
                    }
                    _ => true,
                })
            })
            .collect();
        Ok(Monitors {
            kinds,
            bits,
            goals,
            atoms: b.atoms,
            plant_only,
            goal_names,
        })
    }

    /// How many recurring goals there are.
    pub(crate) fn goal_count(&self) -> usize {
        self.goal_names.len()
    }

    /// The values of the atoms that read only the plant, on `plant` (bits).
    pub(crate) fn plant_atoms(
        &self,
        sem: &Semantics,
        plant: &[Value],
        params: &[bool],
    ) -> Result<u64, AtomError> {
        let mut v = 0;
        for (i, a) in self.atoms.iter().enumerate() {
            if self.plant_only[i] && a.holds_on(sem, plant, 0, params)? {
                v |= 1 << i;
            }
        }
        Ok(v)
    }

    /// The values of the other atoms, with outputs `outputs`.
    pub(crate) fn output_atoms(
        &self,
        sem: &Semantics,
        plant: &[Value],
        outputs: u64,
        params: &[bool],
    ) -> Result<u64, AtomError> {
        let mut v = 0;
        for (i, a) in self.atoms.iter().enumerate() {
            if !self.plant_only[i] && a.holds_on(sem, plant, outputs, params)? {
                v |= 1 << i;
            }
        }
        Ok(v)
    }

    /// One step of every monitor from `memory` on the atom valuation `v`.
    pub(crate) fn step(&self, memory: u64, v: u64) -> Step {
        let mut out = Step {
            memory: 0,
            bad: false,
            goals: 0,
        };
        for (m, k) in self.kinds.iter().enumerate() {
            let held = self.bits[m].is_some_and(|b| memory >> b & 1 == 1);
            let (keep, goal) = match k {
                Kind::Invariant(p) => {
                    out.bad |= !p.eval(v);
                    (false, false)
                }
                Kind::Next { trigger, then } => {
                    out.bad |= held && !then.eval(v);
                    (trigger.eval(v), false)
                }
                Kind::Response {
                    trigger,
                    answer,
                    excuse,
                } => {
                    let open = (held || trigger.eval(v)) && !answer.eval(v);
                    (open, !open || excuse.as_ref().is_some_and(|e| e.eval(v)))
                }
                Kind::Until {
                    trigger,
                    hold,
                    release,
                } => {
                    let active = (held || trigger.eval(v)) && !release.eval(v);
                    out.bad |= active && !hold.eval(v);
                    (active, !active)
                }
                Kind::Recurrence { goal, excuse } => (
                    false,
                    goal.eval(v) || excuse.as_ref().is_some_and(|e| e.eval(v)),
                ),
            };
            if let (Some(b), true) = (self.bits[m], keep) {
                out.memory |= 1 << b;
            }
            if let (Some(g), true) = (self.goals[m], goal) {
                out.goals |= 1 << g;
            }
        }
        out
    }
}
