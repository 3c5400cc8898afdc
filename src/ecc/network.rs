//! Distributed controllers (fbSAT's distributed synthesis): several basic function blocks, each
//! with an interface of its own, that read the plant's signals and each other's outputs.
//!
//! In: the controllers, each a [`Module`](super::modular::Module) of a parallel [`Modular`] over an *extended* input
//! vector: the plant-side inputs, then every output of the network. Out: the network's
//! behaviour on the plant-side inputs ([`NetworkRun`]), as one controller of the recordings.
//!
//! # Semantics
//! - Every output belongs to exactly one controller. A controller reads plant-side inputs and
//!   other controllers' outputs, never its own (its ECC knows them).
//! - On `REQ` with plant-side inputs `x`, every controller scans once: it reads `x` and the
//!   other controllers' outputs *as they were before this scan* (what a controller on another
//!   device received over the network at the end of the previous cycle), and steps as a basic
//!   ECC. The network emits `CNF` iff some controller fired; its outputs are the union of the
//!   controllers'. The order of the controllers therefore does not matter.
//! - So the network is the parallel composite of [`crate::ecc::modular`] run on `x` extended
//!   with the outputs before the step, and a recording of the whole network is a recording of
//!   that composite on the extended inputs: what the synthesis encodes.

use super::modular::{Modular, ModularRun, Topology};
use super::{Controller as Behaviour, Reactive};

/// A network of controllers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Network {
    /// Names of the controllers, in order (each is its function block's type name).
    pub(crate) names: Vec<String>,
    /// Plant-side inputs (the first `external` entries of `modular.inputs`).
    pub(crate) external: usize,
    /// The controllers as a parallel composite over the plant-side inputs followed by every
    /// output (a read of output `z` is a read of input `external + z`).
    pub modular: Modular,
}

impl Network {
    /// Checks the composite, the extended inputs and that no controller reads its own output.
    pub(crate) fn validate(&self) -> Result<(), String> {
        self.modular.validate()?;
        if self.modular.topology != Topology::Parallel {
            return Err("the controllers of a network run side by side".into());
        }
        if self.names.len() != self.modular.modules.len() {
            return Err("one name per controller".into());
        }
        let m = &self.modular;
        if m.inputs.len() != self.external + m.outputs.len()
            || m.inputs[self.external..] != m.outputs[..]
        {
            return Err("the inputs are not the plant-side inputs followed by the outputs".into());
        }
        for (name, module) in self.names.iter().zip(&m.modules) {
            if let Some(i) = (module.inputs.iter()).find(|i| {
                i.0 >= self.external && module.outputs.iter().any(|z| z.0 == i.0 - self.external)
            }) {
                return Err(format!(
                    "controller {name} reads its own output {}",
                    m.inputs[i.0]
                ));
            }
        }
        Ok(())
    }

    /// The plant-side input names.
    pub fn inputs(&self) -> &[String] {
        &self.modular.inputs[..self.external]
    }
}

/// A running network.
#[derive(Debug, Clone)]
pub struct NetworkRun<'a> {
    run: ModularRun<'a>,
    extended: Vec<bool>,
    external: usize,
}

impl NetworkRun<'_> {
    /// One scan of every controller on plant-side inputs `x`; whether the network emitted `CNF`.
    pub(crate) fn step(&mut self, x: &[bool]) -> bool {
        self.extended.truncate(0);
        self.extended.extend_from_slice(&x[..self.external]);
        self.extended.extend_from_slice(&self.run.outputs);
        let extended = std::mem::take(&mut self.extended);
        let fired = self.run.step(&extended);
        self.extended = extended;
        fired
    }
}

impl Reactive for NetworkRun<'_> {
    fn react(&mut self, x: &[bool]) -> Option<&[bool]> {
        self.step(x).then_some(self.run.outputs.as_slice())
    }
}

impl Behaviour for Network {
    type Run<'a> = NetworkRun<'a>;
    fn start(&self) -> NetworkRun<'_> {
        NetworkRun {
            run: ModularRun::new(&self.modular),
            extended: Vec::with_capacity(self.modular.inputs.len()),
            external: self.external,
        }
    }
}
