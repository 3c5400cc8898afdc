//! The closed loop: controller + surrogate plant + properties as one NuSMV model.
//!
//! # Coupling convention
//! - The plant file defines `MODULE plant(<params>)`. Each parameter is named after a
//!   controller output the plant reads (e.g. `c1Extend`); outputs the plant ignores need not be
//!   parameters.
//! - Every controller input (e.g. `c1Home`) is a `VAR`, `IVAR`, `FROZENVAR` or `DEFINE` of
//!   module `plant` with exactly that name.
//! - synth generates `MODULE main`:
//!   ```text
//!   VAR ctrl  : ECC(TRUE, plant.c1Home, ..., plant.vac);  -- REQ at every step: one PLC scan
//!       plant : plant(ctrl.c1Extend, ...);                  -- in the plant's parameter order
//!   DEFINE c1Extend := ctrl.c1Extend; ...                   -- every controller output
//!          c1Home := plant.c1Home; ... vp1 := plant.vp1;    -- every name module plant declares
//!   LTLSPEC NAME _p1 := ...;  -- label: text                -- the properties, over bare names
//!   ```
//!   so a bare name in a property is a controller output or a name of the plant. Anything else
//!   is an error before NuSMV runs. The names `ctrl`, `plant`, `main` and `ECC` are reserved.
//! - Each property is named `_p<k>` after its position `k` (1-based) in the spec file
//!   ([`smv_property_name`]), whatever its label: NuSMV is asked for verdicts by these names,
//!   so no label ever has to be one (and names starting with `_` are reserved for generated
//!   identifiers, so no label looks like one either).
//! - Timing: at step `t` the controller reads the plant's values of step `t`; its outputs change
//!   at `t + 1`. The plant reads the controller outputs of step `t`.
//!
//! # What reaches the model
//! The plant file verbatim (it is the user's model); names that passed
//! [`check_identifier`] (controller inputs and outputs, the plant's
//! names); formulas printed from their syntax tree ([`crate::ltl::Ltl::to_smv`]), never from
//! the user's text; generated names. Anything else the user wrote (the plant's path, a
//! property's text and label) appears only in comments, through [`comment`], which lets no
//! line break or other control character through.
//!
//! The composed text keeps the plant file verbatim, so NuSMV's error lines inside it map back
//! to the user's file by a fixed offset; lines of properties map back to the spec file.

use super::ecc_module::write_ecc_module;
use super::plant::Plant;
use super::{check_identifier, SmvError};
use crate::ecc::Ecc;
use crate::ltl::{property_name, Property};
use crate::quote::{cut, quote};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub use crate::ecc::ident::CONTROLLER_MODULE;

/// Instance names in `main`.
pub(crate) const CONTROLLER_INSTANCE: &str = "ctrl";
/// Instance name of the plant module in `main` (the plant's names are `plant.x` there).
pub(crate) const PLANT_INSTANCE: &str = "plant";

/// The controller's events a plant may read as parameters: its output event, and its input
/// event (TRUE at every step of the closed loop).
const EVENTS: &[&str] = &["CNF", "REQ"];

/// The names the closed loop gives its own modules and instances.
const RESERVED: &[&str] = &[
    CONTROLLER_INSTANCE,
    PLANT_INSTANCE,
    "main",
    CONTROLLER_MODULE,
];

/// A coupling mistake, found before NuSMV runs.
#[derive(Debug, thiserror::Error)]
pub enum CouplingError {
    /// A name breaks the convention: a reserved or unusable name, a plant parameter that is no
    /// controller output, a controller input the plant lacks, an unknown name in a property.
    #[error("{file}:{line}: {message}")]
    At {
        /// The plant file or the specification file, whichever holds the mistake.
        file: PathBuf,
        /// 1-based line: the declaration, the property, or `MODULE plant` for interface names.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A name of the controller's interface (from the recordings' names or the machine, not
    /// from the plant file) cannot be used in the closed loop.
    #[error("{0}")]
    ControllerName(String),
    /// A pair of `--couple plant.SIGNAL=NAME` that names no plant signal or no controller
    /// input or output, or one a second time.
    #[error("--couple plant.{plant}={controller}: {message}")]
    Couple {
        /// The plant's side of the pair.
        plant: String,
        /// The controller's side of the pair.
        controller: String,
        /// What is wrong.
        message: String,
    },
    /// The controller cannot be emitted as SMV (e.g. an unusable identifier).
    #[error("{0}")]
    Smv(#[from] SmvError),
}

/// What a bare name stands for in the closed loop.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Binding {
    /// An output of the controller: `main` defines it as `ctrl.<name>`.
    ControllerOutput,
    /// A `VAR`, `IVAR`, `FROZENVAR` or `DEFINE` of module `plant`: `main` defines it as
    /// `plant.<name>`.
    Plant,
}

/// The checked coupling: every bare name and what it resolves to, and which controller output
/// drives each plant parameter. Checked once ([`check_coupling`]); the NuSMV model
/// ([`compose`]) and the in-process checker ([`crate::check::Wiring::new`]) are both built
/// from it.
#[derive(Debug, Clone)]
pub struct Coupling {
    /// Bare name -> what it is, sorted by name.
    pub names: BTreeMap<String, Binding>,
    /// The controller's inputs in interface order.
    pub(crate) inputs: Vec<String>,
    /// Per controller input, in interface order: the name the plant declares for it (the
    /// input's own name unless a pair of `--couple` says otherwise).
    pub(crate) sensors: Vec<String>,
    /// Per parameter of `MODULE plant` that is a controller output, in order: its name in the
    /// plant (the output's own name unless a pair of `--couple` says otherwise).
    pub(crate) param_names: Vec<String>,
    /// The controller's outputs in interface order.
    pub(crate) outputs: Vec<String>,
    /// Per parameter of `MODULE plant` that is a controller output, in order: the index in
    /// [`Coupling::outputs`] of that output (parameters `CNF` and `REQ` have none).
    pub(crate) params: Vec<usize>,
}

/// Checks the coupling convention between a controller interface, a plant and properties.
/// Runs before synthesis, so mistakes surface in seconds, with file and line. The one check of
/// the convention: whatever is built on the result needs none of its own.
pub fn check_coupling(
    inputs: &[String],
    outputs: &[String],
    plant: &Plant,
    spec_file: &Path,
    props: &[Property],
) -> Result<Coupling, CouplingError> {
    check_coupling_by(inputs, outputs, plant, spec_file, props, &[])
}

/// A pair of `--couple plant.SIGNAL=NAME`: the plant's signal (a parameter of `MODULE plant`,
/// or a name it declares) that is the controller's output or input `NAME`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Couple {
    /// The plant's name.
    pub plant: String,
    /// The controller's name.
    pub controller: String,
}

impl std::str::FromStr for Couple {
    type Err = String;

    /// Reads `plant.SIGNAL=NAME`.
    fn from_str(s: &str) -> Result<Couple, String> {
        let (left, right) = (s.split_once('='))
            .ok_or_else(|| format!("{}: expected plant.SIGNAL=NAME", quote(s)))?;
        let plant = (left.trim().strip_prefix("plant.")).ok_or_else(|| {
            format!(
                "{}: the left side names a plant signal, plant.SIGNAL",
                quote(s)
            )
        })?;
        let (plant, controller) = (plant.trim().to_string(), right.trim().to_string());
        if plant.is_empty() || controller.is_empty() {
            return Err(format!("{}: expected plant.SIGNAL=NAME", quote(s)));
        }
        Ok(Couple { plant, controller })
    }
}

/// The pairs of a coupling file: one `plant.SIGNAL=NAME` per line, as `--couple` takes them;
/// blank lines and `--` comments are skipped. An error names the file and line.
pub fn read_couples(path: &Path) -> Result<Vec<Couple>, String> {
    let text = crate::files::read_text(path, Some(crate::files::MAX_LINE_BYTES))
        .map_err(|e| e.to_string())?;
    let mut pairs = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let code = line.split("--").next().unwrap_or("").trim();
        if code.is_empty() {
            continue;
        }
        let pair = code
            .parse()
            .map_err(|e| format!("{}:{}: {e}", path.display(), k + 1))?;
        pairs.push(pair);
    }
    Ok(pairs)
}

/// [`check_coupling`] where the plant's names differ from the controller's: each pair of
/// `couple` says which plant signal is which controller input or output.
pub fn check_coupling_by(
    inputs: &[String],
    outputs: &[String],
    plant: &Plant,
    spec_file: &Path,
    props: &[Property],
    couple: &[Couple],
) -> Result<Coupling, CouplingError> {
    check_pairs(inputs, outputs, plant, couple)?;
    // The plant's name of a controller signal.
    let plant_name = |n: &String| {
        (couple.iter().find(|c| c.controller == *n)).map_or(n.clone(), |c| c.plant.clone())
    };
    check_controller_names(inputs, outputs)?;
    let (params, param_names) = plant_params(plant, outputs, plant_name)?;
    let names = bindings(plant, outputs)?;
    let sensors: Vec<String> = inputs.iter().map(plant_name).collect();
    for i in &sensors {
        if names.get(i) != Some(&Binding::Plant) {
            return Err(at(
                &plant.file,
                plant.module_line,
                format!(
                    "module plant declares no variable or define {} for the controller input of that name",
                    quote(i)
                ),
            ));
        }
    }
    check_property_names(props, spec_file, &names, &plant.file)?;
    Ok(Coupling {
        names,
        inputs: inputs.to_vec(),
        sensors,
        param_names,
        outputs: outputs.to_vec(),
        params,
    })
}

/// An error at `file:line`.
fn at(file: &Path, line: usize, message: String) -> CouplingError {
    CouplingError::At {
        file: file.to_path_buf(),
        line,
        message,
    }
}

/// Every controller input and output name is an identifier the closed loop does not reserve.
fn check_controller_names(inputs: &[String], outputs: &[String]) -> Result<(), CouplingError> {
    for (n, side) in
        (inputs.iter().map(|n| (n, "input"))).chain(outputs.iter().map(|n| (n, "output")))
    {
        check_identifier(n).map_err(|m| {
            CouplingError::ControllerName(format!("controller {side} name {}: {m}", quote(n)))
        })?;
        if RESERVED.contains(&n.as_str()) {
            return Err(CouplingError::ControllerName(format!(
                "controller {side} name {} is reserved by the closed loop (like {}): rename it in the recordings' names files or the machine",
                quote(n),
                RESERVED.join(", ")
            )));
        }
    }
    Ok(())
}

/// Per parameter of `MODULE plant` that is a controller output (its plant name by
/// `plant_name`): the output's index, and the parameter's name. The events are parameters too
/// and have no index; any other parameter is an error at its line.
fn plant_params(
    plant: &Plant,
    outputs: &[String],
    plant_name: impl Fn(&String) -> String,
) -> Result<(Vec<usize>, Vec<String>), CouplingError> {
    let mut params = Vec::with_capacity(plant.params.len());
    let mut param_names = Vec::with_capacity(plant.params.len());
    for p in &plant.params {
        match outputs.iter().position(|o| plant_name(o) == p.name) {
            Some(z) => {
                params.push(z);
                param_names.push(p.name.clone());
            }
            // The controller's events: NuSMV reads them (`ctrl.CNF`, `REQ` is TRUE at every
            // step); the in-process engines, whose plant parameters are outputs only, refuse
            // such a plant by name ([`crate::check::Wiring::new`]).
            None if EVENTS.contains(&p.name.as_str()) => {}
            None => {
                return Err(at(
                    &plant.file,
                    p.line,
                    format!(
                        "plant parameter {} is not a controller output (outputs: {}; or the event CNF or REQ)",
                        quote(&p.name),
                        cut(&outputs.join(" "))
                    ),
                ))
            }
        }
    }
    Ok((params, param_names))
}

/// Which side each name of the closed loop belongs to: the controller's outputs and the
/// plant's variables and defines, each an identifier, none reserved, none on both sides.
fn bindings(plant: &Plant, outputs: &[String]) -> Result<BTreeMap<String, Binding>, CouplingError> {
    let pf = plant.file.as_path();
    let mut names: BTreeMap<String, Binding> = BTreeMap::new();
    for o in outputs {
        names.insert(o.clone(), Binding::ControllerOutput);
    }
    // An instance of a submodule is no value: the plant's defines reach into it.
    for d in (plant.names.iter()).filter(|d| !plant.instances.contains(&d.name)) {
        if RESERVED.contains(&d.name.as_str()) {
            return Err(at(
                pf,
                d.line,
                format!("the name {} is reserved by the closed loop", quote(&d.name)),
            ));
        }
        if outputs.contains(&d.name) {
            return Err(at(
                pf,
                d.line,
                format!(
                    "controller output {} has the name of a plant variable or define: in the closed loop a name belongs to one side",
                    quote(&d.name)
                ),
            ));
        }
        check_identifier(&d.name)
            .map_err(|m| at(pf, d.line, format!("{}: {m}", quote(&d.name))))?;
        names.insert(d.name.clone(), Binding::Plant);
    }
    Ok(names)
}

/// Every property's name is an identifier and every name its formula reads is bound in
/// `names`; an error names the line of `spec_file`.
fn check_property_names(
    props: &[Property],
    spec_file: &Path,
    names: &BTreeMap<String, Binding>,
    plant_file: &Path,
) -> Result<(), CouplingError> {
    for (k, p) in props.iter().enumerate() {
        if let Err(m) = check_identifier(&property_name(k, p)) {
            return Err(at(
                spec_file,
                p.line,
                format!("property name {}: {m}", quote(&property_name(k, p))),
            ));
        }
        for n in p.formula.names() {
            if !names.contains_key(&n) {
                return Err(at(
                    spec_file,
                    p.line,
                    format!(
                        "unknown name {}: neither a controller output nor a variable or define of module plant in {}",
                        quote(&n),
                        plant_file.display()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Each pair of `couple` names a controller input with a name the plant declares, or a
/// controller output with a parameter of `MODULE plant`; no side twice.
fn check_pairs(
    inputs: &[String],
    outputs: &[String],
    plant: &Plant,
    couple: &[Couple],
) -> Result<(), CouplingError> {
    for (k, c) in couple.iter().enumerate() {
        let bad = |message: String| CouplingError::Couple {
            plant: c.plant.clone(),
            controller: c.controller.clone(),
            message,
        };
        let declared = |n: &str| plant.names.iter().any(|d| d.name == n);
        let param = |n: &str| plant.params.iter().any(|d| d.name == n);
        if inputs.contains(&c.controller) {
            if !declared(&c.plant) || plant.instances.contains(&c.plant) {
                return Err(bad(format!(
                    "module plant declares no variable or define {}",
                    quote(&c.plant)
                )));
            }
        } else if outputs.contains(&c.controller) {
            if !param(&c.plant) {
                return Err(bad(format!(
                    "{} is no parameter of MODULE plant",
                    quote(&c.plant)
                )));
            }
        } else {
            return Err(bad(format!(
                "{} is neither a controller input nor a controller output",
                quote(&c.controller)
            )));
        }
        let earlier = &couple[..k];
        if (earlier.iter()).any(|e| e.plant == c.plant || e.controller == c.controller) {
            return Err(bad("a side of this pair is coupled twice".into()));
        }
    }
    Ok(())
}

/// Where a line of the composed model came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Source {
    /// A line of the user's plant file.
    Plant(usize),
    /// The property defined on this line of the spec file.
    Spec(usize),
    /// Generated code (the controller module or `main`).
    Generated,
}

/// A composed closed-loop model.
#[derive(Debug, Clone)]
pub struct ComposedModel {
    /// The whole NuSMV model: controller module, plant file verbatim, `main`, `LTLSPEC`s.
    pub text: String,
    /// First model line (1-based) holding plant line 1.
    plant_first: usize,
    plant_lines: usize,
    /// Each property's `LTLSPEC`, in spec order.
    specs: Vec<SpecLine>,
}

/// One `LTLSPEC` of a composed model.
#[derive(Debug, Clone)]
struct SpecLine {
    /// 1-based line in the model.
    model_line: usize,
    /// 1-based line in the spec file.
    spec_line: usize,
    /// The property's name for the user ([`property_name`]).
    name: String,
    /// Its name in the model ([`smv_property_name`]).
    smv_name: String,
    /// The formula as written into the model.
    formula: String,
}

/// The name in the model of the property at 0-based position `index` of its spec file:
/// `_p{index+1}`, whatever its label (see the module header).
pub fn smv_property_name(index: usize) -> String {
    format!("_p{}", index + 1)
}

/// `text` made safe for an SMV comment (`-- ...` up to the end of the line): every control
/// character (line breaks above all, which would end the comment and let the rest become
/// model text) and every Unicode line or paragraph separator is written as its Rust escape
/// (`\n`, `\u{2028}`). The one way user text reaches a model outside checked identifiers.
pub fn comment(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() || matches!(c, '\u{2028}' | '\u{2029}') {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

impl ComposedModel {
    /// Where a line of the composed model came from.
    pub(crate) fn source(&self, model_line: usize) -> Source {
        if model_line >= self.plant_first && model_line < self.plant_first + self.plant_lines {
            return Source::Plant(model_line - self.plant_first + 1);
        }
        match self.specs.iter().find(|s| s.model_line == model_line) {
            Some(s) => Source::Spec(s.spec_line),
            None => Source::Generated,
        }
    }

    /// Whether `model_line` is one of the two generated lines right after the plant (a blank
    /// line and `MODULE main`).
    pub(crate) fn follows_plant(&self, model_line: usize) -> bool {
        let end = self.plant_first + self.plant_lines;
        (end..end + 2).contains(&model_line)
    }

    /// Property names in order.
    pub fn property_names(&self) -> Vec<String> {
        self.specs.iter().map(|s| s.name.clone()).collect()
    }

    /// Each property's name in the model and its formula as written there, in spec order:
    /// what NuSMV is asked about.
    pub fn smv_properties(&self) -> impl Iterator<Item = (&str, &str)> + '_ {
        (self.specs.iter()).map(|s| (s.smv_name.as_str(), s.formula.as_str()))
    }
}

/// Composes the closed loop of `ecc` and `plant` with `props` (checked by [`check_coupling`]).
pub(crate) fn compose(
    ecc: &Ecc,
    plant: &Plant,
    coupling: &Coupling,
    props: &[Property],
) -> Result<ComposedModel, SmvError> {
    let mut out: Vec<u8> = Vec::new();
    write_ecc_module(ecc, CONTROLLER_MODULE, &mut out)?;
    let text = String::from_utf8(out).expect("emitter writes UTF-8");
    Ok(compose_controller(
        text,
        &ecc.inputs,
        plant,
        coupling,
        props,
    ))
}

/// Composes the closed loop of any controller given as SMV text that defines
/// `MODULE ECC(REQ, <inputs in order>)` with a `CNF` and every output (e.g. a modular
/// controller's composite, [`crate::export::modular`]).
pub fn compose_controller(
    controller: String,
    inputs: &[String],
    plant: &Plant,
    coupling: &Coupling,
    props: &[Property],
) -> ComposedModel {
    let mut text = controller;
    if !text.ends_with('\n') {
        text.push('\n');
    }
    text.push_str(&format!(
        "-- plant: {}\n",
        comment(&plant.file.display().to_string())
    ));
    let plant_first = text.lines().count() + 1;
    text.push_str(&plant.text);
    if !plant.text.ends_with('\n') {
        text.push('\n');
    }
    let plant_lines = plant.text.lines().count();
    text.push_str(&main_module(inputs, plant, coupling));
    let mut specs = Vec::new();
    // One line per property: its formula is printed from the tree, the rest is a comment.
    let first = text.lines().count() + 1;
    for (k, p) in props.iter().enumerate() {
        let spec = SpecLine {
            model_line: first + k,
            spec_line: p.line,
            name: property_name(k, p),
            smv_name: smv_property_name(k),
            formula: p.formula.to_smv(&|n: &str| n.to_string()),
        };
        text.push_str(&format!(
            "LTLSPEC NAME {} := {};  -- {}\n",
            spec.smv_name,
            spec.formula,
            comment(&format!("{}: {}", spec.name, p.text))
        ));
        specs.push(spec);
    }
    ComposedModel {
        text,
        plant_first,
        plant_lines,
        specs,
    }
}

/// `MODULE main` of the closed loop: the controller reads the plant's sensors (its `inputs`,
/// by their plant names), the plant its commands (the controller's outputs and events), and
/// every name a property reads is defined as the side's own.
fn main_module(inputs: &[String], plant: &Plant, coupling: &Coupling) -> String {
    let mut main = String::from("\nMODULE main\nVAR\n");
    let sensors: Vec<String> = inputs
        .iter()
        .map(|i| {
            let k = coupling.inputs.iter().position(|c| c == i);
            let name = k.map_or(i, |k| &coupling.sensors[k]);
            format!("{PLANT_INSTANCE}.{name}")
        })
        .collect();
    main.push_str(&format!(
        "  {CONTROLLER_INSTANCE} : {CONTROLLER_MODULE}(TRUE{}{});\n",
        if sensors.is_empty() { "" } else { ", " },
        sensors.join(", ")
    ));
    let commands: Vec<String> = plant
        .params
        .iter()
        .map(|p| match p.name.as_str() {
            "REQ" => "TRUE".to_string(),
            name => match coupling.param_names.iter().position(|n| n == name) {
                Some(k) => format!(
                    "{CONTROLLER_INSTANCE}.{}",
                    coupling.outputs[coupling.params[k]]
                ),
                None => format!("{CONTROLLER_INSTANCE}.{name}"),
            },
        })
        .collect();
    main.push_str(&format!(
        "  {PLANT_INSTANCE} : plant({});\n",
        commands.join(", ")
    ));
    main.push_str("DEFINE\n");
    for (name, binding) in &coupling.names {
        let inst = match binding {
            Binding::ControllerOutput => CONTROLLER_INSTANCE,
            Binding::Plant => PLANT_INSTANCE,
        };
        main.push_str(&format!("  {name} := {inst}.{name};\n"));
    }
    main
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::ident::{check_block_name, CLOSED_LOOP_MODULES};

    #[test]
    fn comments_let_no_line_break_or_control_character_through() {
        assert_eq!(
            comment("a\nINVAR !lamp\r\n--\t\u{2028}\u{85}\u{1b}[2J é"),
            "a\\nINVAR !lamp\\r\\n--\\t\\u{2028}\\u{85}\\u{1b}[2J é"
        );
    }

    /// A plant path holding line breaks stays inside its comment: the model's lines are the
    /// plant's, the generated ones and the properties, named `_p<k>`, printed from their tree.
    #[test]
    fn user_text_reaches_the_model_only_inside_comments() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/closed_loop");
        let mut plant = super::super::plant::read_plant(&root.join("lamp_plant.smv")).unwrap();
        plant.file = PathBuf::from("/tmp/p\nINVAR !lamp\n--.smv");
        let json = std::fs::read_to_string(root.join("lamp_two_state.json")).unwrap();
        let ecc = crate::export::json::read_json(&json, Path::new("m.json")).unwrap();
        let spec = "never_lit: G ( !lamp )  -- a comment\nG (lamp -> F !lamp)\n";
        let props = crate::ltl::parse_spec(Path::new("s.ltl"), spec).unwrap();
        let coupling = check_coupling(
            &ecc.inputs,
            &ecc.outputs,
            &plant,
            Path::new("s.ltl"),
            &props,
        )
        .unwrap();
        let model = compose(&ecc, &plant, &coupling, &props).unwrap();
        assert!(
            !model
                .text
                .lines()
                .any(|l| l.trim_start().starts_with("INVAR")),
            "{}",
            model.text
        );
        assert!(model
            .text
            .contains("\n-- plant: /tmp/p\\nINVAR !lamp\\n--.smv\n"));
        let specs: Vec<&str> = (model.text.lines())
            .filter(|l| l.starts_with("LTLSPEC"))
            .collect();
        assert_eq!(
            specs,
            [
                "LTLSPEC NAME _p1 := G !lamp;  -- never_lit: G ( !lamp )",
                "LTLSPEC NAME _p2 := G (lamp -> F !lamp);  -- p2: G (lamp -> F !lamp)",
            ]
        );
        let asked: Vec<(&str, &str)> = model.smv_properties().collect();
        assert_eq!(asked, [("_p1", "G !lamp"), ("_p2", "G (lamp -> F !lamp)")]);
        assert_eq!(model.property_names(), ["never_lit", "p2"]);
        let line = |prefix: &str| {
            1 + model
                .text
                .lines()
                .position(|l| l.starts_with(prefix))
                .unwrap()
        };
        assert_eq!(model.source(line("LTLSPEC NAME _p2")), Source::Spec(2));
        assert_eq!(model.source(line("MODULE plant")), Source::Plant(2));
    }

    #[test]
    fn no_block_takes_the_name_of_a_closed_loop_module() {
        // The plant file's module is `plant`, like its instance.
        for module in ["main", CONTROLLER_MODULE, PLANT_INSTANCE] {
            assert!(CLOSED_LOOP_MODULES.contains(&module), "{module}");
            assert!(check_block_name(module).is_err(), "{module}");
        }
    }
}
