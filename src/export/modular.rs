//! Exports of a modular controller: an IEC 61499 composite FB wiring one basic FB per module,
//! the composite as one SMV controller module, and every module in the single-ECC formats.
//!
//! In: a valid [`Modular`] and a stem. Out: pure emitters ([`write_composite_fbt`],
//! [`write_composite_smv`]) and [`write_modular`], which writes the files:
//! - `<stem>.fbt`: the `CompositeFBType` (interface `REQ`/`CNF` with every input and output);
//! - `<stem>_M<i>.fbt`, `.json`, `.dot` (and `.svg` with Graphviz): module `i` (1-based) as a
//!   basic FB of type `<stem>_M<i>` over its own inputs and outputs;
//! - `<stem>.smv`: the module SMVs and `MODULE <stem>(REQ, inputs...)` composing them;
//! - `<stem>.st`: every module as a Structured Text `FUNCTION_BLOCK` (as the `.st` export of
//!   one ECC), then the composite block calling them ([`write_composite_st`]);
//! - `<stem>.xml`: the same blocks as a PLCopen TC6 XML project ([`write_composite_plcopen`]);
//! - `<stem>.dot` (and `.svg` with Graphviz): the network, inputs to modules to outputs
//!   ([`composite_dot`]);
//! - `<stem>.modules.json`: the decomposition (inputs, outputs, sizes per module).
//!
//! # Consecutive composites
//! A chain ([`Topology::Consecutive`]) is not written as an FB network: a module's `x` passes
//! on the previous module's value, which a basic FB of the module alone cannot read. It is one
//! ECC ([`Modular::flatten`]), so `<stem>.fbt`, `.smv`, `.st`, `.json` and `.dot` are the
//! single-block exports of that ECC, which behaves as the chain; `<stem>_M<i>.json` and `.dot`
//! show each module (its `x` meaning "the previous module's value"), and
//! `<stem>.modules.json` says `"topology": "consecutive"`.
//!
//! # Composite FB network
//! IEC 61499 allows neither fan-out nor fan-in of event connections, so the events go through
//! the standard event FBs: `REQ` reaches the modules' `REQ` in module order through a chain of
//! `E_SPLIT` (`SPLIT1..`), and the modules' `CNF` reach the composite's `CNF` through a chain
//! of `E_MERGE` (`MERGE1..`); with one module the events connect directly. Data inputs fan out
//! to every module that reads them, each output comes from the module that owns it.
//! A `REQ` on which no module fires gives no `CNF`, as in the simulator. On a `REQ` where `k`
//! modules fire, the composite emits `k` CNFs (one per firing module, the merge does not
//! combine them); once the modules have all handled the `REQ`, the outputs are the composite's
//! values of [`crate::ecc::modular`]. A consumer that needs exactly one `CNF` per `REQ` should
//! read the outputs on the last one.
//!
//! # Composite Structured Text
//! The composite `FUNCTION_BLOCK <stem>` has the interface of one ECC's block and one instance
//! `M<i>` of each module type. A call passes `REQ` and each module's inputs to every module,
//! in module order, then copies each output from its owner and sets `CNF` when some module
//! fired: one call is one `REQ` of [`crate::ecc::modular`], with one `CNF`.
//!
//! # Composite SMV
//! `MODULE <stem>(REQ, x1, ..., xX)` has the signature and the variables (`CNF`, every output)
//! of a single ECC's module ([`crate::smv::ecc_module`]): instances `_m1.._mM` of the module
//! types `<stem>_M<i>`, `CNF := _m1.CNF | ... | _mM.CNF` and each output defined as its
//! owner's. Named [`crate::smv::composition::CONTROLLER_MODULE`], it replaces the controller
//! of a closed loop.

use super::fbt::write_head;
use super::{check_iec_identifier, ExportError, Format, NameError};
use crate::ecc::ident::BLOCK_MEMBERS;
use crate::ecc::modular::{Modular, Topology};
use crate::ecc::{Algorithm, AlgorithmKind, Ecc, State};
use crate::files::xml::XmlWriter;
use crate::smv::ecc_module::{self, write_ecc_module};
use crate::smv::SmvError;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// Type name of module `m` (0-based) of a composite named `stem`: `<stem>_M<m+1>`.
pub(crate) fn module_type_name(stem: &str, m: usize) -> String {
    format!("{stem}_M{}", m + 1)
}

/// Instance name of module `m` (0-based) in the composite FB network: `M<m+1>`.
fn instance_name(m: usize) -> String {
    format!("M{}", m + 1)
}

/// Instance name of module `m` (0-based) in the composite SMV module: `_m<m+1>`.
pub(super) fn smv_instance(m: usize) -> String {
    format!("_m{}", m + 1)
}

/// The composite's interface as an ECC without behaviour, to check names as for one block.
fn interface(modular: &Modular) -> Ecc {
    Ecc {
        inputs: modular.inputs.clone(),
        outputs: modular.outputs.clone(),
        initial_outputs: modular.initial_outputs.clone(),
        states: vec![State {
            name: "s0".into(),
            algorithm: Algorithm::keep_all(AlgorithmKind::Tri, modular.outputs.len()),
            transitions: Vec::new(),
        }],
    }
}

/// Checks every name the `.fbt` files would contain: the composite's interface and type name
/// and every module's type name.
pub(crate) fn check_fbt_names(modular: &Modular, stem: &str) -> Result<(), NameError> {
    super::fbt::check_names(&interface(modular), stem)?;
    for (m, module) in modular.modules.iter().enumerate() {
        let name = module_type_name(stem, m);
        check_iec_identifier(&name).map_err(|reason| NameError {
            role: "module type name".into(),
            name: name.clone(),
            format: "an IEC 61499 .fbt file",
            reason,
        })?;
        super::fbt::check_names(&module.ecc, &name)?;
    }
    Ok(())
}

/// Writes the `CompositeFBType`; see the module header for its network. Fails with
/// [`io::ErrorKind::InvalidInput`] before writing anything if a name is unusable.
pub(crate) fn write_composite_fbt(
    modular: &Modular,
    stem: &str,
    w: &mut impl Write,
) -> io::Result<()> {
    check_fbt_names(modular, stem)?;
    let size = modular.size();
    let comment = format!(
        "Composite FB synthesized by fbsynth: {} modules, largest {} states, A={}, N'={}",
        modular.modules.len(),
        size.max_states,
        size.inputs_used,
        size.total_states
    );
    let mut x = XmlWriter::new(w);
    write_head(
        &mut x,
        stem,
        &comment,
        "",
        [&modular.inputs, &modular.outputs],
        &modular.initial_outputs,
        [
            "Request: every module fires its first enabled transition",
            "Confirmation: a module fired, its outputs updated (one CNF per firing module)",
        ],
    )?;
    x.open(1, "FBNetwork", &[])?;
    write_blocks(&mut x, modular, stem)?;
    write_event_connections(&mut x, modular.modules.len())?;
    write_data_connections(&mut x, modular)?;
    x.close(1, "FBNetwork")?;
    x.close(0, "FBType")
}

/// One connection of the network, from `source` to `destination`.
fn connection(x: &mut XmlWriter<impl Write>, source: &str, destination: &str) -> io::Result<()> {
    x.leaf(
        3,
        "Connection",
        &[("Source", source), ("Destination", destination)],
    )
}

/// The blocks of the network: one instance per module (its outputs in the comment), and
/// between consecutive modules an `E_SPLIT` and an `E_MERGE`.
fn write_blocks(x: &mut XmlWriter<impl Write>, modular: &Modular, stem: &str) -> io::Result<()> {
    for (m, module) in modular.modules.iter().enumerate() {
        let names: Vec<&str> = module.ecc.outputs.iter().map(String::as_str).collect();
        x.leaf(
            2,
            "FB",
            &[
                ("Name", &instance_name(m)),
                ("Type", &module_type_name(stem, m)),
                ("Comment", &format!("outputs: {}", names.join(", "))),
                ("x", "1500"),
                ("y", &(300 + 800 * m).to_string()),
            ],
        )?;
    }
    for i in 0..modular.modules.len().saturating_sub(1) {
        let y = (300 + 800 * i).to_string();
        for (name, ty, x_pos) in [("SPLIT", "E_SPLIT", "700"), ("MERGE", "E_MERGE", "2600")] {
            x.leaf(
                2,
                "FB",
                &[
                    ("Name", &format!("{name}{}", i + 1)),
                    ("Type", ty),
                    ("x", x_pos),
                    ("y", &y),
                ],
            )?;
        }
    }
    Ok(())
}

/// The event connections of `count` modules: `REQ` reaches every module through the chain
/// of splits, every module's `CNF` reaches `CNF` through the chain of merges.
fn write_event_connections(x: &mut XmlWriter<impl Write>, count: usize) -> io::Result<()> {
    x.open(2, "EventConnections", &[])?;
    let m_ev = |m: usize, e: &str| format!("{}.{e}", instance_name(m));
    let splits = count.saturating_sub(1);
    if count == 1 {
        connection(x, "REQ", &m_ev(0, "REQ"))?;
        connection(x, &m_ev(0, "CNF"), "CNF")?;
    } else {
        // REQ -> SPLIT1; SPLITi.EO1 -> Mi.REQ; SPLITi.EO2 -> SPLIT(i+1) or, last, M(count).
        connection(x, "REQ", "SPLIT1.EI")?;
        for i in 0..splits {
            connection(x, &format!("SPLIT{}.EO1", i + 1), &m_ev(i, "REQ"))?;
            let next = if i + 1 < splits {
                format!("SPLIT{}.EI", i + 2)
            } else {
                m_ev(count - 1, "REQ")
            };
            connection(x, &format!("SPLIT{}.EO2", i + 1), &next)?;
        }
        // M1.CNF -> MERGE1.EI1; M(i+1).CNF -> MERGEi.EI2; MERGEi.EO -> MERGE(i+1).EI1 or CNF.
        connection(x, &m_ev(0, "CNF"), "MERGE1.EI1")?;
        for i in 0..splits {
            connection(x, &m_ev(i + 1, "CNF"), &format!("MERGE{}.EI2", i + 1))?;
            let next = if i + 1 < splits {
                format!("MERGE{}.EI1", i + 2)
            } else {
                "CNF".to_string()
            };
            connection(x, &format!("MERGE{}.EO", i + 1), &next)?;
        }
    }
    x.close(2, "EventConnections")
}

/// The data connections: every input a module reads from the composite's input of that
/// name, every output a module owns to the composite's output; none when no module is wired.
fn write_data_connections(x: &mut XmlWriter<impl Write>, modular: &Modular) -> io::Result<()> {
    let wired = modular
        .modules
        .iter()
        .any(|m| !m.inputs.is_empty() || !m.outputs.is_empty());
    if !wired {
        return Ok(());
    }
    x.open(2, "DataConnections", &[])?;
    for (m, module) in modular.modules.iter().enumerate() {
        for i in &module.inputs {
            let name = &modular.inputs[i.0];
            connection(x, name, &format!("{}.{name}", instance_name(m)))?;
        }
        for z in &module.outputs {
            let name = &modular.outputs[z.0];
            connection(x, &format!("{}.{name}", instance_name(m)), name)?;
        }
    }
    x.close(2, "DataConnections")
}

/// [`write_composite_fbt`] into a string.
pub(crate) fn composite_fbt_to_string(modular: &Modular, stem: &str) -> io::Result<String> {
    let mut buf = Vec::new();
    write_composite_fbt(modular, stem, &mut buf)?;
    Ok(String::from_utf8(buf).expect("the .fbt emitter writes UTF-8 only"))
}

/// Checks the names of the composite SMV: the composite as one ECC module and every module.
/// The instance names `_m<i>` cannot clash: SMV names starting with `_` are reserved for
/// generated identifiers ([`crate::smv::check_identifier`]).
pub(crate) fn check_smv_names(modular: &Modular, module_name: &str) -> Result<(), SmvError> {
    ecc_module::check_names(&interface(modular), module_name)?;
    for (m, module) in modular.modules.iter().enumerate() {
        ecc_module::check_names(&module.ecc, &module_type_name(module_name, m))?;
    }
    Ok(())
}

/// The most states a chain's single ECC may have before the export gives up.
pub(crate) const FLAT_LIMIT: usize = 4096;

/// Writes the composite as SMV: every module's ECC module, then `MODULE module_name`; see the
/// module header. A chain is written as its single ECC.
pub(crate) fn write_composite_smv(
    modular: &Modular,
    module_name: &str,
    w: &mut impl Write,
) -> Result<(), SmvError> {
    if modular.topology == Topology::Consecutive {
        let flat = (modular.flatten(FLAT_LIMIT))
            .map_err(|e| SmvError::Io(io::Error::new(io::ErrorKind::InvalidInput, e)))?;
        return write_ecc_module(&flat, module_name, w);
    }
    check_smv_names(modular, module_name)?;
    for (m, module) in modular.modules.iter().enumerate() {
        write_ecc_module(&module.ecc, &module_type_name(module_name, m), w)?;
        writeln!(w)?;
    }
    let mut params = vec!["REQ".to_string()];
    params.extend(modular.inputs.iter().cloned());
    writeln!(
        w,
        "-- Composite of {} modules: every module gets REQ, CNF if some module fired.",
        modular.modules.len()
    )?;
    writeln!(w, "MODULE {}({})", module_name, params.join(", "))?;
    writeln!(w, "VAR")?;
    for (m, module) in modular.modules.iter().enumerate() {
        let mut args = vec!["REQ".to_string()];
        args.extend(module.ecc.inputs.iter().cloned());
        writeln!(
            w,
            "  {} : {}({});",
            smv_instance(m),
            module_type_name(module_name, m),
            args.join(", ")
        )?;
    }
    write_smv_defines(modular, w)?;
    Ok(())
}

/// The `DEFINE` section of a composite or network SMV module: `CNF` when any instance
/// emits it, and each output from the instance that owns it.
pub(super) fn write_smv_defines(modular: &Modular, w: &mut impl Write) -> std::io::Result<()> {
    writeln!(w, "DEFINE")?;
    let cnf: Vec<String> = (0..modular.modules.len())
        .map(|m| format!("{}.CNF", smv_instance(m)))
        .collect();
    writeln!(w, "  CNF := {};", cnf.join(" | "))?;
    for (z, name) in modular.outputs.iter().enumerate() {
        let owner = modular
            .owner(crate::ecc::OutputId(z))
            .expect("a validated composite or network has an owner for every output");
        writeln!(w, "  {name} := {}.{name};", smv_instance(owner))?;
    }
    Ok(())
}

/// [`write_composite_smv`] into a string.
pub fn composite_smv_to_string(modular: &Modular, module_name: &str) -> Result<String, SmvError> {
    let mut buf = Vec::new();
    write_composite_smv(modular, module_name, &mut buf)?;
    Ok(String::from_utf8(buf).expect("the SMV emitter writes UTF-8 only"))
}

/// Checks every name the `.st` and PLCopen files would contain: the composite's interface
/// (which may not use an instance name `M<i>` either) and type name, and every module.
pub(crate) fn check_st_names(modular: &Modular, stem: &str) -> Result<(), NameError> {
    let mut reserved: Vec<String> = BLOCK_MEMBERS.iter().map(|r| r.to_string()).collect();
    reserved.extend((0..modular.modules.len()).map(instance_name));
    super::check_iec_names(&interface(modular), "Structured Text", stem, &reserved)?;
    for (m, module) in modular.modules.iter().enumerate() {
        super::st::check_names(&module.ecc, &module_type_name(stem, m))?;
    }
    Ok(())
}

/// The composite block's statements: call every module, copy the outputs, `CNF` if some
/// module fired.
fn composite_statements(modular: &Modular) -> String {
    let mut text = String::new();
    for (m, module) in modular.modules.iter().enumerate() {
        let args: Vec<String> = std::iter::once("REQ".to_string())
            .chain(module.ecc.inputs.iter().cloned())
            .map(|x| format!("{x} := {x}"))
            .collect();
        text.push_str(&format!("{}({});\n", instance_name(m), args.join(", ")));
    }
    for (z, name) in modular.outputs.iter().enumerate() {
        let owner = modular
            .owner(crate::ecc::OutputId(z))
            .expect("a valid composite has an owner for every output");
        text.push_str(&format!("{name} := {}.{name};\n", instance_name(owner)));
    }
    let cnf: Vec<String> = (0..modular.modules.len())
        .map(|m| format!("{}.CNF", instance_name(m)))
        .collect();
    text.push_str(&format!("CNF := {};\n", cnf.join(" OR ")));
    text
}

/// Writes every module's `FUNCTION_BLOCK` and the composite's; see the module header. Fails
/// with [`io::ErrorKind::InvalidInput`] before writing anything if a name is unusable.
pub(crate) fn write_composite_st(
    modular: &Modular,
    stem: &str,
    w: &mut impl Write,
) -> io::Result<()> {
    check_st_names(modular, stem)?;
    for (m, module) in modular.modules.iter().enumerate() {
        super::st::write_st(&module.ecc, &module_type_name(stem, m), w)?;
        writeln!(w)?;
    }
    writeln!(w, "FUNCTION_BLOCK {stem}")?;
    writeln!(
        w,
        "(* Composite of {} modules synthesized by fbsynth: each call passes REQ to every",
        modular.modules.len()
    )?;
    writeln!(w, "   module; CNF is TRUE when some module fired. *)")?;
    writeln!(w, "VAR_INPUT")?;
    writeln!(w, "    REQ : BOOL;")?;
    for x in &modular.inputs {
        writeln!(w, "    {x} : BOOL;")?;
    }
    writeln!(w, "END_VAR")?;
    writeln!(w, "VAR_OUTPUT")?;
    writeln!(w, "    CNF : BOOL;")?;
    for (z, &init) in modular.outputs.iter().zip(&modular.initial_outputs) {
        let initial = if init { " := TRUE" } else { "" };
        writeln!(w, "    {z} : BOOL{initial};")?;
    }
    writeln!(w, "END_VAR")?;
    writeln!(w, "VAR")?;
    for m in 0..modular.modules.len() {
        writeln!(
            w,
            "    {} : {};",
            instance_name(m),
            module_type_name(stem, m)
        )?;
    }
    writeln!(w, "END_VAR")?;
    writeln!(w)?;
    w.write_all(composite_statements(modular).as_bytes())?;
    writeln!(w, "END_FUNCTION_BLOCK")
}

/// Writes the modules and the composite as one PLCopen project named `stem`, created at
/// `created` (an `xsd:dateTime`). Fails like [`write_composite_st`].
pub(crate) fn write_composite_plcopen(
    modular: &Modular,
    stem: &str,
    created: &str,
    w: &mut impl Write,
) -> io::Result<()> {
    use super::plcopen::{Pou, TypeName, Var};
    check_st_names(modular, stem)?;
    let mut pous = Vec::new();
    for (m, module) in modular.modules.iter().enumerate() {
        pous.push(Pou::of_ecc(&module.ecc, &module_type_name(stem, m))?);
    }
    pous.push(Pou {
        name: stem.to_string(),
        inputs: std::iter::once(Var::boolean("REQ", false))
            .chain(modular.inputs.iter().map(|x| Var::boolean(x, false)))
            .collect(),
        outputs: std::iter::once(Var::boolean("CNF", false))
            .chain(
                (modular.outputs.iter())
                    .zip(&modular.initial_outputs)
                    .map(|(z, &init)| Var::boolean(z, init)),
            )
            .collect(),
        locals: (0..modular.modules.len())
            .map(|m| Var {
                name: instance_name(m),
                type_name: TypeName::Derived(module_type_name(stem, m)),
                initial: None,
            })
            .collect(),
        body: composite_statements(modular),
    });
    let size = modular.size();
    let description = format!(
        "Composite function block synthesized by fbsynth: {} modules, largest {} states, \
         A={}, N'={}",
        modular.modules.len(),
        size.max_states,
        size.inputs_used,
        size.total_states
    );
    super::plcopen::write_project(stem, created, &description, &pous, w)
}

/// The network as a Graphviz drawing: each input, module and output a node, an edge from each
/// input to every module that reads it and from each module to the outputs it owns.
pub(crate) fn composite_dot(modular: &Modular, stem: &str) -> String {
    // DOT strings escape quotes and backslashes; `\n` is DOT's line break.
    let quote = |s: &str| {
        let escaped = s.replace('\\', "\\\\").replace('"', "\\\"");
        format!("\"{}\"", escaped.replace('\n', "\\n"))
    };
    let mut text = format!("digraph {} {{\n", quote(stem));
    text.push_str("  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n");
    for x in &modular.inputs {
        text.push_str(&format!(
            "  {} [shape=plaintext];\n",
            quote(&format!("in {x}"))
        ));
    }
    for (m, module) in modular.modules.iter().enumerate() {
        let size = module.ecc.size();
        let label = format!(
            "{}: {}\n{} states, {} transitions",
            instance_name(m),
            module_type_name(stem, m),
            size.c,
            size.t
        );
        text.push_str(&format!(
            "  {} [shape=box, label={}];\n",
            instance_name(m),
            quote(&label)
        ));
        for &i in &module.inputs {
            let x = &modular.inputs[i.0];
            text.push_str(&format!(
                "  {} -> {};\n",
                quote(&format!("in {x}")),
                instance_name(m)
            ));
        }
        for &z in &module.outputs {
            let name = &modular.outputs[z.0];
            text.push_str(&format!(
                "  {} -> {};\n",
                instance_name(m),
                quote(&format!("out {name}"))
            ));
        }
    }
    for z in &modular.outputs {
        text.push_str(&format!(
            "  {} [shape=plaintext];\n",
            quote(&format!("out {z}"))
        ));
    }
    text.push_str("}\n");
    text
}

/// The decomposition as JSON: per module, its type name, inputs, outputs and size.
pub(crate) fn decomposition_json(modular: &Modular, stem: &str) -> String {
    let modules: Vec<serde_json::Value> = modular
        .modules
        .iter()
        .enumerate()
        .map(|(m, module)| {
            let size = module.ecc.size();
            serde_json::json!({
                "module": m + 1,
                "type": module_type_name(stem, m),
                "inputs": module.ecc.inputs,
                "outputs": module.ecc.outputs,
                "states": size.c,
                "transitions": size.t,
                "guard_literals": size.n,
            })
        })
        .collect();
    let size = modular.size();
    let doc = serde_json::json!({
        "composite": stem,
        "topology": modular.topology.name(),
        "largest_module_states": size.max_states,
        "inputs_used": size.inputs_used,
        "total_states": size.total_states,
        "modules": modules,
    });
    let mut text = serde_json::to_string_pretty(&doc).expect("JSON values serialize");
    text.push('\n');
    text
}

/// Writes every file of the module header into `dir`, and returns the paths in the order
/// written. Every name is checked before the first file is touched; files are written
/// atomically.
pub(crate) fn write_modular(
    modular: &Modular,
    dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>, ExportError> {
    modular.validate().map_err(ExportError::InvalidEcc)?;
    if modular.topology == Topology::Consecutive {
        return write_chain(modular, dir, stem);
    }
    check_fbt_names(modular, stem).map_err(|source| ExportError::Name {
        format: Format::Fbt,
        source,
    })?;
    check_st_names(modular, stem).map_err(|source| ExportError::Name {
        format: Format::St,
        source,
    })?;
    let smv = composite_smv_to_string(modular, stem).map_err(ExportError::Smv)?;
    let fbt = composite_fbt_to_string(modular, stem).expect("names are checked");
    let mut st = Vec::new();
    write_composite_st(modular, stem, &mut st).expect("names are checked");
    let mut xml = Vec::new();
    let created = super::plcopen::creation_time();
    write_composite_plcopen(modular, stem, &created, &mut xml).expect("names are checked");
    let utf8 = |b: Vec<u8>| String::from_utf8(b).expect("the emitters write UTF-8");
    let texts = [
        (format!("{stem}.fbt"), fbt),
        (format!("{stem}.smv"), smv),
        (format!("{stem}.st"), utf8(st)),
        (format!("{stem}.xml"), utf8(xml)),
        (format!("{stem}.dot"), composite_dot(modular, stem)),
        (
            format!("{stem}.modules.json"),
            decomposition_json(modular, stem),
        ),
    ];
    let mut written = super::write_texts(dir, texts)?;
    for (m, module) in modular.modules.iter().enumerate() {
        let name = module_type_name(stem, m);
        written.extend(super::write_all(
            &module.ecc,
            dir,
            &name,
            &[Format::Fbt, Format::Json, Format::Dot],
        )?);
    }
    Ok(written)
}

/// [`write_modular`] for a chain: its single ECC in the block formats, each module as JSON
/// and Graphviz, and the decomposition (see the module header). Every text is made, and so
/// every name checked, before the first file is written.
fn write_chain(modular: &Modular, dir: &Path, stem: &str) -> Result<Vec<PathBuf>, ExportError> {
    let flat = modular
        .flatten(FLAT_LIMIT)
        .map_err(ExportError::InvalidEcc)?;
    let block = [
        Format::Fbt,
        Format::Smv,
        Format::St,
        Format::Json,
        Format::Dot,
    ];
    let mut texts = Vec::new();
    for format in block {
        texts.push((
            format!("{stem}.{}", format.extension()),
            super::text(&flat, stem, format)?,
        ));
    }
    for (m, module) in modular.modules.iter().enumerate() {
        let name = module_type_name(stem, m);
        for format in [Format::Json, Format::Dot] {
            let text = super::text(&module.ecc, &name, format)?;
            texts.push((format!("{name}.{}", format.extension()), text));
        }
    }
    texts.push((
        format!("{stem}.modules.json"),
        decomposition_json(modular, stem),
    ));
    super::write_texts(dir, texts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::modular::tests::two_toggles;
    use crate::export::fbt::tests::{parse, Node};

    fn connections<'a>(net: &'a Node, list: &str) -> Vec<(&'a str, &'a str)> {
        net.one(list)
            .all("Connection")
            .into_iter()
            .map(|c| (c.attr("Source").unwrap(), c.attr("Destination").unwrap()))
            .collect()
    }

    #[test]
    fn composite_fbt_snapshot() {
        insta::assert_snapshot!(composite_fbt_to_string(&two_toggles(), "Lamps").unwrap());
    }

    #[test]
    fn composite_st_plcopen_and_dot_snapshots() {
        let mut st = Vec::new();
        write_composite_st(&two_toggles(), "Lamps", &mut st).unwrap();
        insta::assert_snapshot!("composite_st", String::from_utf8(st).unwrap());
        let mut xml = Vec::new();
        write_composite_plcopen(&two_toggles(), "Lamps", "2026-12-03T09:00:00Z", &mut xml).unwrap();
        insta::assert_snapshot!("composite_plcopen", String::from_utf8(xml).unwrap());
        insta::assert_snapshot!("composite_dot", composite_dot(&two_toggles(), "Lamps"));
    }

    /// The composite block calls every module with its own inputs and takes each output from
    /// its owner; an input named like an instance is refused before anything is written.
    #[test]
    fn the_composite_st_wires_each_module() {
        let modular = two_toggles();
        let mut st = Vec::new();
        write_composite_st(&modular, "Lamps", &mut st).unwrap();
        let text = String::from_utf8(st).unwrap();
        assert_eq!(text.matches("FUNCTION_BLOCK Lamps_M").count(), 2, "{text}");
        for (m, module) in modular.modules.iter().enumerate() {
            let call = format!("M{}(REQ := REQ", m + 1);
            let line = text.lines().find(|l| l.starts_with(&call)).expect("a call");
            for x in &module.ecc.inputs {
                assert!(line.contains(&format!("{x} := {x}")), "{line}");
            }
            for z in &module.ecc.outputs {
                assert!(text.contains(&format!("{z} := M{}.{z};", m + 1)), "{text}");
            }
        }
        let mut clash = modular.clone();
        clash.inputs[0] = "m1".into();
        clash.modules[0].ecc.inputs[0] = "m1".into();
        let mut buf = Vec::new();
        let e = write_composite_st(&clash, "Lamps", &mut buf).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput, "{e}");
        assert!(buf.is_empty());
    }

    #[test]
    fn composite_smv_snapshot() {
        insta::assert_snapshot!(composite_smv_to_string(&two_toggles(), "ECC").unwrap());
    }

    #[test]
    fn decomposition_snapshot() {
        insta::assert_snapshot!(decomposition_json(&two_toggles(), "Lamps"));
    }

    /// Every written XML file parses; the composite wires each event and variable once.
    #[test]
    fn written_xml_is_well_formed_and_wired() {
        let mut three = two_toggles();
        // A third module with no outputs and no inputs still gets REQ and merges its CNF.
        let mut spare = three.modules[0].clone();
        spare.inputs.clear();
        spare.outputs.clear();
        spare.ecc = Ecc {
            inputs: vec![],
            outputs: vec![],
            initial_outputs: vec![],
            states: vec![State {
                name: "s0".into(),
                algorithm: Algorithm::Tri(vec![]),
                transitions: vec![],
            }],
        };
        three.modules.push(spare);
        for (modular, splits) in [(two_toggles(), 1), (three, 2)] {
            let dir = tempfile::tempdir().unwrap();
            let files = write_modular(&modular, dir.path(), "Lamps").unwrap();
            let mut xml = 0;
            for f in &files {
                if f.extension().is_some_and(|e| e == "fbt") {
                    let text = std::fs::read_to_string(f).unwrap();
                    let root = parse(&text);
                    assert_eq!(root.name, "FBType");
                    xml += 1;
                }
            }
            assert_eq!(xml, 1 + modular.modules.len());
            let text = std::fs::read_to_string(dir.path().join("Lamps.fbt")).unwrap();
            let root = parse(&text);
            let net = root.one("FBNetwork");
            let fbs = net.all("FB");
            assert_eq!(fbs.len(), modular.modules.len() + 2 * splits);
            let events = connections(net, "EventConnections");
            // Every event input of the network is driven exactly once.
            let mut dests: Vec<&str> = events.iter().map(|c| c.1).collect();
            dests.sort();
            let before = dests.len();
            dests.dedup();
            assert_eq!(before, dests.len(), "no event fan-in");
            for m in 0..modular.modules.len() {
                assert!(dests.contains(&format!("M{}.REQ", m + 1).as_str()));
            }
            assert_eq!(events.iter().filter(|c| c.1 == "CNF").count(), 1);
            let data = connections(net, "DataConnections");
            assert!(data.contains(&("a", "M1.a")));
            assert!(data.contains(&("M2.lb", "lb")));
            for f in &fbs {
                let ty = f.attr("Type").unwrap();
                if ty == "E_SPLIT" || ty == "E_MERGE" {
                    continue;
                }
                assert!(dir.path().join(format!("{ty}.fbt")).is_file(), "{ty}");
            }
        }
    }

    #[test]
    fn bad_names_write_nothing() {
        let mut m = two_toggles();
        m.inputs[0] = "REQ".into();
        m.modules[0].ecc.inputs[0] = "REQ".into();
        let dir = tempfile::tempdir().unwrap();
        let e = write_modular(&m, dir.path(), "Lamps").unwrap_err();
        assert!(matches!(e, ExportError::Name { .. }), "{e}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        let mut m = two_toggles();
        m.outputs[0] = "_m2".into();
        m.modules[0].ecc.outputs[0] = "_m2".into();
        let e = check_smv_names(&m, "ECC").unwrap_err();
        assert!(e.to_string().contains("reserved"), "{e}");
    }
}
