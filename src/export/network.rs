//! Exports of a network of distributed controllers ([`crate::ecc::network`]).
//!
//! In: a valid [`Network`] and a stem. Out: pure emitters ([`network_smv_to_string`],
//! [`network_dot`], [`network_json`]) and [`write_network`], which writes:
//! - `<Name>.fbt`, `.st`, `.smv`, `.json`, `.dot` (and `.svg` with Graphviz): each controller
//!   as a basic function block named after it, over its own interface (another controller's
//!   output it reads is an input of the same name);
//! - `<stem>.smv`: the controllers' SMV modules and `MODULE <stem>(REQ, inputs...)` running
//!   them side by side, each reading the others' output variables, which in SMV hold the
//!   values before the step: the network's semantics, with the signature of a single ECC's
//!   module;
//! - `<stem>.st`: every controller's Structured Text `FUNCTION_BLOCK`, then
//!   `FUNCTION_BLOCK <stem>` with one instance `M<i>` of each ([`write_network_st`]): a call
//!   passes `REQ` and each controller's inputs, the other controllers' outputs taken from the
//!   block's own output variables, which still hold the values before the scan; only after
//!   every call are the outputs copied from their owners and `CNF` set if some controller
//!   fired. So one call is one `REQ` of the network, as in the simulator;
//! - `<stem>.dot` (and `.svg`): the network, plant-side inputs to controllers, controllers to
//!   each other and to the outputs;
//! - `<stem>.network.json`: per controller its inputs, outputs and size.

use super::{ExportError, Format};
use crate::ecc::ident::BLOCK_MEMBERS;
use crate::ecc::network::Network;
use crate::ecc::{Algorithm, AlgorithmKind, Ecc, State};
use crate::smv::ecc_module::{self, write_ecc_module};
use crate::smv::SmvError;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Instance name of controller `m` (0-based) in the network's SMV module: as a composite's.
use super::modular::smv_instance as instance;

/// The network's outer interface as an ECC without behaviour, to check its names.
fn interface(net: &Network) -> Ecc {
    let m = &net.modular;
    Ecc {
        inputs: net.inputs().to_vec(),
        outputs: m.outputs.clone(),
        initial_outputs: m.initial_outputs.clone(),
        states: vec![State {
            name: "s0".into(),
            algorithm: Algorithm::keep_all(AlgorithmKind::Tri, m.outputs.len()),
            transitions: Vec::new(),
        }],
    }
}

/// Writes the network as SMV; see the module header.
pub(crate) fn write_network_smv(
    net: &Network,
    module_name: &str,
    w: &mut impl Write,
) -> Result<(), SmvError> {
    ecc_module::check_names(&interface(net), module_name)?;
    let m = &net.modular;
    for (module, name) in m.modules.iter().zip(&net.names) {
        ecc_module::check_names(&module.ecc, name)?;
    }
    for (module, name) in m.modules.iter().zip(&net.names) {
        write_ecc_module(&module.ecc, name, w)?;
        writeln!(w)?;
    }
    let mut params = vec!["REQ".to_string()];
    params.extend(net.inputs().iter().cloned());
    writeln!(
        w,
        "-- Network of {} controllers: each scans on REQ, reading the others' outputs from before the scan; CNF if some controller fired.",
        m.modules.len()
    )?;
    writeln!(w, "MODULE {}({})", module_name, params.join(", "))?;
    writeln!(w, "VAR")?;
    for (k, (module, name)) in m.modules.iter().zip(&net.names).enumerate() {
        let mut args = vec!["REQ".to_string()];
        for i in &module.inputs {
            let signal = &m.inputs[i.0];
            args.push(match i.0.checked_sub(net.external) {
                None => signal.clone(),
                Some(z) => {
                    let owner = m
                        .owner(crate::ecc::OutputId(z))
                        .expect("a valid network has an owner for every output");
                    format!("{}.{signal}", instance(owner))
                }
            });
        }
        writeln!(w, "  {} : {}({});", instance(k), name, args.join(", "))?;
    }
    super::modular::write_smv_defines(m, w)?;
    Ok(())
}

/// [`write_network_smv`] into a string.
pub(crate) fn network_smv_to_string(net: &Network, module_name: &str) -> Result<String, SmvError> {
    let mut buf = Vec::new();
    write_network_smv(net, module_name, &mut buf)?;
    Ok(String::from_utf8(buf).expect("the SMV emitter writes UTF-8 only"))
}

/// Instance name of controller `m` (0-based) in the network's Structured Text block.
fn st_instance(m: usize) -> String {
    format!("M{}", m + 1)
}

/// Checks every name of the network's Structured Text: the block's interface and type name
/// (none an instance `M<i>` or a controller's name) and every controller.
pub(crate) fn check_st_names(net: &Network, stem: &str) -> Result<(), super::NameError> {
    let mut reserved: Vec<String> = BLOCK_MEMBERS.iter().map(|r| r.to_string()).collect();
    reserved.extend((0..net.modular.modules.len()).map(st_instance));
    reserved.extend(net.names.iter().cloned());
    super::check_iec_names(&interface(net), "Structured Text", stem, &reserved)?;
    for (module, name) in net.modular.modules.iter().zip(&net.names) {
        super::st::check_names(&module.ecc, name)?;
    }
    Ok(())
}

/// Writes every controller's `FUNCTION_BLOCK` and the network's; see the module header.
/// Fails with [`std::io::ErrorKind::InvalidInput`] before writing anything if a name is
/// unusable.
pub(crate) fn write_network_st(
    net: &Network,
    stem: &str,
    w: &mut impl Write,
) -> std::io::Result<()> {
    check_st_names(net, stem)?;
    let m = &net.modular;
    for (module, name) in m.modules.iter().zip(&net.names) {
        super::st::write_st(&module.ecc, name, w)?;
        writeln!(w)?;
    }
    writeln!(w, "FUNCTION_BLOCK {stem}")?;
    writeln!(
        w,
        "(* Network of {} controllers synthesized by fbsynth: each call is one scan of every",
        m.modules.len()
    )?;
    writeln!(
        w,
        "   controller, reading the others' outputs from before the scan; CNF is TRUE when"
    )?;
    writeln!(w, "   some controller fired. *)")?;
    writeln!(w, "VAR_INPUT")?;
    writeln!(w, "    REQ : BOOL;")?;
    for x in net.inputs() {
        writeln!(w, "    {x} : BOOL;")?;
    }
    writeln!(w, "END_VAR")?;
    writeln!(w, "VAR_OUTPUT")?;
    writeln!(w, "    CNF : BOOL;")?;
    for (z, &init) in m.outputs.iter().zip(&m.initial_outputs) {
        let initial = if init { " := TRUE" } else { "" };
        writeln!(w, "    {z} : BOOL{initial};")?;
    }
    writeln!(w, "END_VAR")?;
    writeln!(w, "VAR")?;
    for (k, name) in net.names.iter().enumerate() {
        writeln!(w, "    {} : {name};", st_instance(k))?;
    }
    writeln!(w, "END_VAR")?;
    writeln!(w)?;
    for (k, module) in m.modules.iter().enumerate() {
        let args: Vec<String> = std::iter::once("REQ".to_string())
            .chain(module.ecc.inputs.iter().cloned())
            .map(|x| format!("{x} := {x}"))
            .collect();
        writeln!(w, "{}({});", st_instance(k), args.join(", "))?;
    }
    for (z, name) in m.outputs.iter().enumerate() {
        let owner = (m.owner(crate::ecc::OutputId(z)))
            .expect("a valid network has an owner for every output");
        writeln!(w, "{name} := {}.{name};", st_instance(owner))?;
    }
    let cnf: Vec<String> = (0..m.modules.len())
        .map(|k| format!("{}.CNF", st_instance(k)))
        .collect();
    writeln!(w, "CNF := {};", cnf.join(" OR "))?;
    writeln!(w, "END_FUNCTION_BLOCK")
}

/// The network as a Graphviz drawing.
pub(crate) fn network_dot(net: &Network, stem: &str) -> String {
    let quote = |s: &str| format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""));
    let m = &net.modular;
    let mut text = format!(
        "digraph {} {{\n  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n",
        quote(stem)
    );
    for x in net.inputs() {
        text.push_str(&format!(
            "  {} [shape=plaintext];\n",
            quote(&format!("in {x}"))
        ));
    }
    for z in &m.outputs {
        text.push_str(&format!(
            "  {} [shape=plaintext];\n",
            quote(&format!("out {z}"))
        ));
    }
    for (module, name) in m.modules.iter().zip(&net.names) {
        let size = module.ecc.size();
        let label = format!("{name}\\n{} states, {} transitions", size.c, size.t);
        text.push_str(&format!(
            "  {} [shape=box, label=\"{}\"];\n",
            quote(name),
            label.replace('"', "\\\"")
        ));
        for i in &module.inputs {
            let signal = &m.inputs[i.0];
            let from = match i.0.checked_sub(net.external) {
                None => quote(&format!("in {signal}")),
                Some(z) => quote(&net.names[m.owner(crate::ecc::OutputId(z)).expect("owned")]),
            };
            let label = if i.0 >= net.external {
                format!(" [label={}]", quote(signal))
            } else {
                String::new()
            };
            text.push_str(&format!("  {from} -> {}{label};\n", quote(name)));
        }
        for z in &module.outputs {
            text.push_str(&format!(
                "  {} -> {};\n",
                quote(name),
                quote(&format!("out {}", m.outputs[z.0]))
            ));
        }
    }
    text.push_str("}\n");
    text
}

/// The network as JSON: per controller its inputs, outputs and size.
pub(crate) fn network_json(net: &Network, stem: &str) -> String {
    let m = &net.modular;
    let controllers: Vec<serde_json::Value> = (m.modules.iter().zip(&net.names))
        .map(|(module, name)| {
            let size = module.ecc.size();
            serde_json::json!({
                "name": name,
                "inputs": module.ecc.inputs,
                "outputs": module.ecc.outputs,
                "states": size.c,
                "transitions": size.t,
                "guard_literals": size.n,
            })
        })
        .collect();
    let size = m.size();
    let doc = serde_json::json!({
        "network": stem,
        "inputs": net.inputs(),
        "outputs": m.outputs,
        "largest_controller_states": size.max_states,
        "inputs_used": size.inputs_used,
        "total_states": size.total_states,
        "controllers": controllers,
    });
    let mut text = serde_json::to_string_pretty(&doc).expect("JSON values serialize");
    text.push('\n');
    text
}

/// Writes every file of the module header into `dir`; every text is made (and every name
/// checked) before the first file is written. Returns the paths in the order written.
pub(crate) fn write_network(
    net: &Network,
    dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>, ExportError> {
    net.validate().map_err(ExportError::InvalidEcc)?;
    if let Some(name) = net.names.iter().find(|n| n.eq_ignore_ascii_case(stem)) {
        return Err(ExportError::InvalidEcc(format!(
            "controller {name} is named like the network (--name): their files would collide"
        )));
    }
    check_st_names(net, stem).map_err(|source| ExportError::Name {
        format: Format::St,
        source,
    })?;
    let block = [
        Format::Fbt,
        Format::St,
        Format::Smv,
        Format::Json,
        Format::Dot,
    ];
    let mut texts = Vec::new();
    for (module, name) in net.modular.modules.iter().zip(&net.names) {
        for format in block {
            texts.push((
                format!("{name}.{}", format.extension()),
                super::text(&module.ecc, name, format)?,
            ));
        }
    }
    let mut st = Vec::new();
    write_network_st(net, stem, &mut st).expect("names are checked");
    texts.push((
        format!("{stem}.st"),
        String::from_utf8(st).expect("the ST emitter writes UTF-8"),
    ));
    texts.push((
        format!("{stem}.smv"),
        network_smv_to_string(net, stem).map_err(ExportError::Smv)?,
    ));
    texts.push((format!("{stem}.dot"), network_dot(net, stem)));
    texts.push((format!("{stem}.network.json"), network_json(net, stem)));
    let mut seen = std::collections::HashSet::new();
    if let Some((file, _)) = texts
        .iter()
        .find(|(f, _)| !seen.insert(f.to_ascii_lowercase()))
    {
        return Err(ExportError::InvalidEcc(format!(
            "two exports would be written to {file}: a controller is named like the network (--name)"
        )));
    }
    super::write_texts(dir, texts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::random::random_network;

    #[test]
    fn network_smv_dot_and_json_snapshots() {
        let net = random_network(1, 2, 2);
        insta::assert_snapshot!("network_smv", network_smv_to_string(&net, "Net").unwrap());
        insta::assert_snapshot!("network_dot", network_dot(&net, "Net"));
        insta::assert_snapshot!("network_json", network_json(&net, "Net"));
        let mut st = Vec::new();
        write_network_st(&net, "Net", &mut st).unwrap();
        insta::assert_snapshot!("network_st", String::from_utf8(st).unwrap());
    }

    /// A controller named like the network would overwrite its SMV file: nothing is written.
    #[test]
    fn a_controller_named_like_the_network_writes_nothing() {
        let net = random_network(1, 2, 2);
        let dir = tempfile::tempdir().unwrap();
        let e = write_network(&net, dir.path(), "C1").unwrap_err();
        assert!(e.to_string().contains("named like the network"), "{e}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        let files = write_network(&net, dir.path(), "Net").unwrap();
        assert!(files.iter().any(|f| f.ends_with("Net.smv")));
        assert!(files.iter().any(|f| f.ends_with("C2.fbt")));
    }
}
