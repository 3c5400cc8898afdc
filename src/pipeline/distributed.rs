//! Distributed synthesis: several controllers, each with its own interface, synthesized
//! together from recordings of the whole network (fbSAT's distributed synthesis).
//!
//! In: a [`ScenarioSet`] over the plant-side inputs and every controller's outputs, a
//! [`Description`] of the controllers (which signals each reads and which outputs it writes,
//! read by [`read_description`]) and [`Options`]. Out: a [`Distributed`]: the
//! [`Network`], replayed on every scenario, and its figures.
//!
//! # Method
//! A controller reads other controllers' outputs as they were before the scan
//! ([`crate::ecc::network`]), and those values are in the recordings. So each step's input
//! vector is extended with the outputs before it ([`extend`]) and the network is the parallel
//! modular encoding ([`crate::sat::modular`]) over the extended vectors, with every output
//! pinned to its controller and each controller's inputs restricted to those the description
//! gives it. The controllers are synthesized together: which of them fires on an active step
//! is the solver's choice, as in a parallel composite. Minimized: the largest controller,
//! then the inputs read in all, then the states in all.
//!
//! # Description file
//! JSON, `{"controllers": [{"name": "Feeder", "inputs": ["start", "busy"], "outputs":
//! ["feed"]}, ...]}`. A name is an identifier (it names the controller's function block); an
//! input is a plant-side input of the recordings or another controller's output; the
//! controllers' outputs partition the recordings' outputs. Every violation is an error naming
//! the file and the controller.

use super::{Error, Event, Events};
use crate::ecc::ident::check_block_name;
use crate::ecc::modular::Topology;
use crate::ecc::network::Network;
use crate::ecc::{AlgorithmKind, InputId, OutputId};
use crate::sat::modular::{synthesize_modular, ModularError, ModularOptions, ModularSynthesis};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::{Scenario, ScenarioSet, Step};
use std::path::{Path, PathBuf};

/// One controller of a [`Description`].
#[derive(Debug, Clone, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ControllerSpec {
    /// Its name, which names its function block.
    pub(crate) name: String,
    /// The signals it reads: plant-side inputs or other controllers' outputs.
    pub(crate) inputs: Vec<String>,
    /// The outputs it writes.
    pub(crate) outputs: Vec<String>,
}

/// The controllers of a network and their interfaces.
#[derive(Debug, Clone, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Description {
    /// The controllers, in order.
    pub(crate) controllers: Vec<ControllerSpec>,
}

/// A description that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum DescriptionError {
    /// The file could not be read.
    #[error("cannot read {}: {source}", file.display())]
    Read {
        /// The description file.
        file: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Not JSON of the documented shape.
    #[error("{}:{line}:{column}: {message}", file.display())]
    Syntax {
        /// The description file.
        file: PathBuf,
        /// Line of the error, from 1.
        line: usize,
        /// Column of the error, from 1.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A controller's interface does not fit the recordings or the other controllers.
    #[error("{}: controller {controller}: {message}", file.display())]
    Controller {
        /// The description file.
        file: PathBuf,
        /// The controller's name (or its number when the name is the problem).
        controller: String,
        /// What is wrong.
        message: String,
    },
    /// Something about the whole network (no controller, an output nobody writes).
    #[error("{}: {message}", file.display())]
    Network {
        /// The description file.
        file: PathBuf,
        /// What is wrong.
        message: String,
    },
}

/// Reads a description file (not yet checked against any recordings).
pub(crate) fn read_description(file: &Path) -> Result<Description, DescriptionError> {
    let text = std::fs::read_to_string(file).map_err(|source| DescriptionError::Read {
        file: file.to_path_buf(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|e| DescriptionError::Syntax {
        file: file.to_path_buf(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })
}

/// A description resolved against recordings: per controller, the outputs it writes and the
/// extended inputs ([`extend`]) it may read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Interfaces {
    /// Controller names, in order.
    pub(crate) names: Vec<String>,
    /// `pins[m]`: the outputs controller `m` writes.
    pub(crate) pins: Vec<Vec<OutputId>>,
    /// `reads[m]`: the extended inputs controller `m` may read.
    pub(crate) reads: Vec<Vec<InputId>>,
}

impl Description {
    /// Checks the description against the recordings' names; `file` is named in errors.
    pub(crate) fn resolve(
        &self,
        set: &ScenarioSet,
        file: &Path,
    ) -> Result<Interfaces, DescriptionError> {
        if self.controllers.is_empty() {
            return Err(DescriptionError::Network {
                file: file.to_path_buf(),
                message: "no controller".into(),
            });
        }
        let Writers { names, pins, owner } = self.pins(set, file)?;
        if let Some(z) = owner.iter().position(Option::is_none) {
            return Err(DescriptionError::Network {
                file: file.to_path_buf(),
                message: format!(
                    "output `{}` of the recordings is written by no controller",
                    set.outputs[z]
                ),
            });
        }
        let reads = (self.controllers.iter().enumerate())
            .map(|(m, c)| reads(set, c, m, &owner, file))
            .collect::<Result<_, _>>()?;
        Ok(Interfaces { names, pins, reads })
    }

    /// The controllers' names and the outputs each writes (sorted), and per output of the
    /// recordings the controller that writes it: each name a block's, no name twice, each
    /// controller writing at least one output, no output written twice.
    fn pins(&self, set: &ScenarioSet, file: &Path) -> Result<Writers, DescriptionError> {
        let bad = |controller: &str, message: String| controller_error(file, controller, message);
        let mut owner: Vec<Option<usize>> = vec![None; set.outputs.len()];
        let mut names: Vec<String> = Vec::new();
        let mut pins = Vec::new();
        for (m, c) in self.controllers.iter().enumerate() {
            check_block_name(&c.name).map_err(|r| {
                bad(
                    &format!("{} (number {})", c.name, m + 1),
                    format!("its name cannot name a block: {r}"),
                )
            })?;
            if names.iter().any(|n| n.eq_ignore_ascii_case(&c.name)) {
                return Err(bad(
                    &c.name,
                    "the name is taken by another controller".into(),
                ));
            }
            names.push(c.name.clone());
            if c.outputs.is_empty() {
                return Err(bad(&c.name, "it writes no output".into()));
            }
            let mut mine = Vec::new();
            for o in &c.outputs {
                let z = (set.outputs.iter().position(|n| n == o)).ok_or_else(|| {
                    bad(
                        &c.name,
                        format!(
                            "`{o}` is not an output of the recordings ({})",
                            set.outputs.join(", ")
                        ),
                    )
                })?;
                if let Some(other) = owner[z].replace(m) {
                    return Err(bad(
                        &c.name,
                        format!(
                            "output `{o}` is written by {} too",
                            self.controllers[other].name
                        ),
                    ));
                }
                mine.push(OutputId(z));
            }
            mine.sort();
            pins.push(mine);
        }
        Ok(Writers { names, pins, owner })
    }
}

/// Who writes what ([`Description::pins`]).
struct Writers {
    /// Controller names, in order.
    names: Vec<String>,
    /// Per controller, the outputs it writes.
    pins: Vec<Vec<OutputId>>,
    /// Per output of the recordings, the controller that writes it.
    owner: Vec<Option<usize>>,
}

/// What controller `c` (number `m`) may read, sorted: inputs of the recordings and the outputs
/// other controllers write (`owner`), as extended inputs ([`extend`]).
fn reads(
    set: &ScenarioSet,
    c: &ControllerSpec,
    m: usize,
    owner: &[Option<usize>],
    file: &Path,
) -> Result<Vec<InputId>, DescriptionError> {
    let bad = |message: String| controller_error(file, &c.name, message);
    let mut mine = Vec::new();
    for i in &c.inputs {
        let x = if let Some(x) = set.inputs.iter().position(|n| n == i) {
            x
        } else if let Some(z) = set.outputs.iter().position(|n| n == i) {
            if owner[z] == Some(m) {
                return Err(bad(format!("it reads its own output `{i}`")));
            }
            set.inputs.len() + z
        } else {
            return Err(bad(format!(
                "input `{i}` is neither an input of the recordings nor another controller's output"
            )));
        };
        if !mine.contains(&InputId(x)) {
            mine.push(InputId(x));
        }
    }
    mine.sort();
    Ok(mine)
}

/// An error of the controller named `controller` in the description `file`.
fn controller_error(file: &Path, controller: &str, message: String) -> DescriptionError {
    DescriptionError::Controller {
        file: file.to_path_buf(),
        controller: controller.to_string(),
        message,
    }
}

/// The recordings with each step's inputs followed by the outputs before the step (the
/// initial ones, then the last recorded), the input names followed by the output names.
pub(crate) fn extend(set: &ScenarioSet) -> ScenarioSet {
    let scenarios = (set.scenarios.iter())
        .map(|sc| {
            let mut before = set.initial_outputs.clone();
            let steps = (sc.steps.iter())
                .map(|s| {
                    let mut inputs = s.inputs.clone();
                    inputs.extend_from_slice(&before);
                    if let Some(o) = &s.outputs {
                        before.clone_from(o);
                    }
                    Step {
                        inputs,
                        outputs: s.outputs.clone(),
                    }
                })
                .collect();
            Scenario {
                origin: sc.origin.clone(),
                steps,
            }
        })
        .collect();
    ScenarioSet {
        inputs: set.inputs.iter().chain(&set.outputs).cloned().collect(),
        outputs: set.outputs.clone(),
        initial_outputs: set.initial_outputs.clone(),
        scenarios,
    }
}

/// Settings of a distributed run.
#[derive(Debug, Clone)]
pub(crate) struct Options {
    /// The largest out-degree `K`: transition slots per state (guards are conjunctions).
    pub max_out_degree: usize,
    /// Give up above this many states in one controller.
    pub(crate) max_states: usize,
    /// The algorithm form of every controller.
    pub(crate) algorithms: AlgorithmKind,
    /// Where every solver call stops.
    pub(crate) deadline: crate::deadline::Deadline,
}

/// The result of [`run`].
#[derive(Debug, Clone)]
pub(crate) struct Distributed {
    /// The controllers, replayed as a network on every scenario.
    pub(crate) network: Network,
    /// The composite's figures (largest controller, inputs read, states in all, solver).
    pub(crate) synthesis: ModularSynthesis,
}

/// The least network of the described controllers that reproduces `set`.
pub(crate) fn run(
    set: &ScenarioSet,
    interfaces: &Interfaces,
    opts: &Options,
    events: Events<'_>,
) -> Result<Distributed, Error> {
    let extended = extend(set);
    let modular = ModularOptions {
        modules: interfaces.names.len(),
        max_out_degree: opts.max_out_degree,
        max_states: opts.max_states,
        algorithms: opts.algorithms,
        pins: interfaces.pins.clone(),
        widen_max_out_degree: false,
        topology: Topology::Parallel,
        reads: Some(interfaces.reads.clone()),
        feedback: Some(set.inputs.len()),
        deadline: opts.deadline,
    };
    synthesize(set, &extended, interfaces.names.clone(), &modular, events)
}

/// The least network of `opts.modules` blocks named `names` whose wiring the solver chooses
/// (`--topology arbitrary`): each output written by one block, each block reading any recorded
/// input and any other block's output (before the scan). `opts.pins` may fix some outputs.
pub(crate) fn run_arbitrary(
    set: &ScenarioSet,
    names: Vec<String>,
    opts: &ModularOptions,
    events: Events<'_>,
) -> Result<Distributed, Error> {
    let extended = extend(set);
    let modular = ModularOptions {
        topology: Topology::Parallel,
        reads: None,
        feedback: Some(set.inputs.len()),
        ..opts.clone()
    };
    synthesize(set, &extended, names, &modular, events)
}

/// The network of `opts` over the `extended` recordings of `set`, replayed on `set`.
fn synthesize(
    set: &ScenarioSet,
    extended: &ScenarioSet,
    names: Vec<String>,
    opts: &ModularOptions,
    events: Events<'_>,
) -> Result<Distributed, Error> {
    let tree = ScenarioTree::build(extended)?;
    let found = synthesize_modular(extended, &tree, opts, &mut |m| events(Event::Solver(m)));
    let synthesis = match found {
        Err(ModularError::NoController {
            max_states,
            max_out_degree,
            ..
        }) => {
            let reads = match opts.reads {
                Some(_) => ", or let a controller read more signals",
                None => "",
            };
            return Err(Error::NoMachine(format!(
                "no network of {} blocks with at most {max_states} states each and {max_out_degree} transitions per state reproduces the recordings (raise --max-states or --slots{reads})",
                names.len()
            )));
        }
        found => found?,
    };
    let network = Network {
        names,
        external: set.inputs.len(),
        modular: synthesis.modular.clone(),
    };
    network.validate().map_err(Error::Bug)?;
    set.check(&network)
        .map_err(|m| Error::Bug(format!("the network does not replay {m}")))?;
    Ok(Distributed { network, synthesis })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::network::Network;
    use crate::ecc::random::random_network as pair;
    use rand::{Rng, SeedableRng};

    fn description(text: &str) -> Description {
        serde_json::from_str(text).unwrap()
    }

    fn record(net: &Network, runs: &[Vec<Vec<bool>>]) -> ScenarioSet {
        let m = &net.modular;
        let (outputs, initial) = (m.outputs.clone(), m.initial_outputs.clone());
        ScenarioSet::recorded(net, net.inputs().to_vec(), outputs, initial, runs)
    }

    const PAIR: &str = r#"{"controllers": [
        {"name": "C1", "inputs": ["a", "q"], "outputs": ["p"]},
        {"name": "C2", "inputs": ["b", "p"], "outputs": ["q", "r"]}]}"#;

    /// Random pairs of controllers that read each other's outputs, recorded as a whole:
    /// distributed synthesis rebuilds them with no controller larger than the larger
    /// original, each over the interface described, and the network replays every run.
    #[test]
    fn random_networks_are_rebuilt_no_larger() {
        for seed in 0..6u64 {
            let (c1, c2) = (2 + seed as usize % 2, 2 + (seed as usize / 2) % 2);
            let original = pair(seed, c1, c2);
            original.validate().unwrap();
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let runs: Vec<Vec<Vec<bool>>> = (0..6)
                .map(|_| {
                    (0..12)
                        .map(|_| vec![rng.gen_bool(0.5), rng.gen_bool(0.5)])
                        .collect()
                })
                .collect();
            let set = record(&original, &runs);
            let file = Path::new("net.json");
            let interfaces = description(PAIR).resolve(&set, file).unwrap();
            let opts = Options {
                max_out_degree: 3,
                max_states: 8,
                algorithms: AlgorithmKind::Tri,
                deadline: crate::deadline::Deadline::NONE,
            };
            let r = run(&set, &interfaces, &opts, &mut |_| {}).unwrap();
            assert!(r.synthesis.size.max_states <= c1.max(c2), "seed {seed}");
            set.check(&r.network).unwrap();
            let m = &r.network.modular.modules;
            assert_eq!(
                (m[0].ecc.outputs.clone(), m[1].ecc.outputs.len()),
                (vec!["p".to_string()], 2)
            );
            for (module, allowed) in m.iter().zip([["a", "q"], ["b", "p"]]) {
                assert!(
                    module
                        .ecc
                        .inputs
                        .iter()
                        .all(|i| allowed.contains(&i.as_str())),
                    "seed {seed}"
                );
            }
        }
    }

    /// The same networks, with nothing said about their wiring (`--topology arbitrary`): the
    /// solver chooses who writes what and who reads whom, no block is larger than the larger
    /// original, none reads its own output, and the network replays every run.
    #[test]
    fn random_networks_are_rebuilt_no_larger_when_the_solver_wires_them() {
        for seed in 0..6u64 {
            let (c1, c2) = (2 + seed as usize % 2, 2 + (seed as usize / 2) % 2);
            let original = pair(seed, c1, c2);
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let runs: Vec<Vec<Vec<bool>>> = (0..6)
                .map(|_| {
                    (0..12)
                        .map(|_| vec![rng.gen_bool(0.5), rng.gen_bool(0.5)])
                        .collect()
                })
                .collect();
            let set = record(&original, &runs);
            let opts = ModularOptions {
                modules: 2,
                max_states: 8,
                ..ModularOptions::default()
            };
            let names = vec!["M1".to_string(), "M2".to_string()];
            let r = run_arbitrary(&set, names, &opts, &mut |_| {}).unwrap();
            assert!(r.synthesis.size.max_states <= c1.max(c2), "seed {seed}");
            r.network.validate().unwrap();
            set.check(&r.network).unwrap();
        }
    }

    /// Every way a description can miss the recordings is refused, naming file and controller.
    #[test]
    fn bad_descriptions_name_the_file_and_the_controller() {
        let net = pair(1, 2, 2);
        let set = record(&net, &[vec![vec![true, false]]]);
        let file = Path::new("net.json");
        let e = |text: &str| {
            description(text)
                .resolve(&set, file)
                .unwrap_err()
                .to_string()
        };
        let one = |name: &str, inputs: &str, outputs: &str| {
            format!(
                r#"{{"controllers": [{{"name": "{name}", "inputs": [{inputs}], "outputs": [{outputs}]}}, {{"name": "C2", "inputs": [], "outputs": ["q", "r"]}}]}}"#
            )
        };
        assert!(e(&one("C1", r#""zz""#, r#""p""#))
            .contains("net.json: controller C1: input `zz` is neither"));
        assert!(e(&one("C1", r#""p""#, r#""p""#)).contains("reads its own output `p`"));
        assert!(e(&one("C1", "", r#""q""#)).contains("output `q` is written by C1 too"));
        assert!(e(&one("C1", "", r#""x""#)).contains("`x` is not an output of the recordings"));
        assert!(e(&one("main", "", r#""p""#)).contains("its name cannot name a block"));
        assert!(e(&one("C2", "", r#""p""#)).contains("the name is taken"));
        assert!(e(&one("C1", "", "")).contains("it writes no output"));
        let lone = r#"{"controllers": [{"name": "C1", "inputs": [], "outputs": ["p"]}]}"#;
        assert!(e(lone).contains("output `q` of the recordings is written by no controller"));
        assert!(e(r#"{"controllers": []}"#).contains("no controller"));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("net.json");
        std::fs::write(&path, "{\"controllers\": [\n  {\"name\": 3}]}").unwrap();
        let e = read_description(&path).unwrap_err().to_string();
        assert!(e.contains("net.json:2:"), "{e}");
    }
}
