//! Mapping files: which PLC address is which named input or output.
//!
//! In: the text of a mapping file. Out: a [`Mapping`] (interface names in order, and a lookup
//! from address or name to the signal's slot). Format in the [`super`] module header.

use super::IngestError;
use crate::ecc::ident::is_identifier;
use crate::ecc::{InputId, OutputId};
use crate::quote::quote;
use std::collections::HashMap;
use std::path::Path;

/// Where a signal's value goes in a sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Slot {
    /// The signal is this input variable of the interface.
    Input(InputId),
    /// The signal is this output variable of the interface.
    Output(OutputId),
}

/// The interface of a log: named inputs and outputs, each tied to one PLC address.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mapping {
    inputs: Vec<String>,
    outputs: Vec<String>,
    addresses: Vec<(String, Slot)>,
    /// The mapping file's line of each address, in the order of `addresses`.
    lines: Vec<usize>,
    /// Addresses and names, both resolving to their slot.
    lookup: HashMap<Box<[u8]>, Slot>,
}

/// The three words of a mapping line `ADDRESS in|out NAME` (the side not yet checked), or
/// what is wrong with them.
fn entry(content: &str) -> Result<[&str; 3], String> {
    let words: Vec<&str> = content.split_whitespace().collect();
    let [address, side, name] = words[..] else {
        return Err(format!(
            "expected 'ADDRESS in|out NAME', found {}",
            quote(content)
        ));
    };
    if address.contains(',') {
        return Err(format!("address {} contains ','", quote(address)));
    }
    if !is_identifier(name) {
        return Err(format!(
            "{} is not a valid name (letters, digits and '_', starting with a letter)",
            quote(name)
        ));
    }
    Ok([address, side, name])
}

/// A name that is also another signal's address (`seen_*`: line of each), as the line to
/// report and the message.
fn name_as_address(
    seen_name: &HashMap<String, usize>,
    seen_addr: &HashMap<String, usize>,
) -> Option<(usize, String)> {
    for (name, name_line) in seen_name {
        match seen_addr.get(name) {
            Some(addr_line) if addr_line != name_line => {
                return Some((
                    *addr_line.max(name_line),
                    format!(
                        "{} is both an address (line {addr_line}) and the name of another signal (line {name_line})",
                        quote(name)
                    ),
                ));
            }
            _ => {}
        }
    }
    None
}

impl Mapping {
    /// Parses the text of a mapping file; `file` is only used in error messages.
    pub fn parse(file: &Path, text: &str) -> Result<Mapping, IngestError> {
        let err = |line: usize, message: String| IngestError::Mapping {
            file: file.to_path_buf(),
            line,
            message,
        };
        let mut m = Mapping {
            inputs: Vec::new(),
            outputs: Vec::new(),
            addresses: Vec::new(),
            lines: Vec::new(),
            lookup: HashMap::new(),
        };
        // Line of first use, for duplicate messages.
        let mut seen_addr: HashMap<String, usize> = HashMap::new();
        let mut seen_name: HashMap<String, usize> = HashMap::new();
        let mut outs: Vec<(String, String)> = Vec::new();
        let mut ins: Vec<(String, String)> = Vec::new();
        let mut last_line = 1;
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            last_line = line;
            let content = raw.split('#').next().unwrap_or("").trim();
            if content.is_empty() {
                continue;
            }
            let [address, side, name] = entry(content).map_err(|m| err(line, m))?;
            if let Some(first) = seen_addr.insert(address.to_string(), line) {
                return Err(err(
                    line,
                    format!(
                        "duplicate address {} (first on line {first})",
                        quote(address)
                    ),
                ));
            }
            if let Some(first) = seen_name.insert(name.to_string(), line) {
                return Err(err(
                    line,
                    format!("duplicate name {} (first on line {first})", quote(name)),
                ));
            }
            match side {
                "in" => ins.push((address.to_string(), name.to_string())),
                "out" => outs.push((address.to_string(), name.to_string())),
                _ => {
                    return Err(err(
                        line,
                        format!(
                            "expected 'in' or 'out' after the address, found {}",
                            quote(side)
                        ),
                    ))
                }
            }
        }
        if ins.is_empty() || outs.is_empty() {
            return Err(err(
                last_line,
                "the mapping needs at least one 'in' and one 'out' signal".into(),
            ));
        }
        for (address, name) in ins {
            m.lines.push(seen_addr[&address]);
            m.add(address, name, Slot::Input(InputId(m.inputs.len())));
        }
        for (address, name) in outs {
            m.lines.push(seen_addr[&address]);
            m.add(address, name, Slot::Output(OutputId(m.outputs.len())));
        }
        // A name may not double as another signal's address: a column would be ambiguous.
        if let Some((line, message)) = name_as_address(&seen_name, &seen_addr) {
            return Err(err(line, message));
        }
        Ok(m)
    }

    /// Reads a mapping file.
    pub fn read(file: &Path) -> Result<Mapping, IngestError> {
        let text = crate::files::read_text(file, Some(crate::files::MAX_LINE_BYTES))?;
        Mapping::parse(file, &text)
    }

    fn add(&mut self, address: String, name: String, slot: Slot) {
        self.lookup
            .insert(address.as_bytes().to_vec().into_boxed_slice(), slot);
        self.lookup
            .insert(name.as_bytes().to_vec().into_boxed_slice(), slot);
        match slot {
            Slot::Input(_) => self.inputs.push(name),
            Slot::Output(_) => self.outputs.push(name),
        }
        self.addresses.push((address, slot));
    }

    /// Input names in interface order (file order of the `in` lines).
    pub(crate) fn inputs(&self) -> &[String] {
        &self.inputs
    }

    /// Output names in interface order (file order of the `out` lines).
    pub fn outputs(&self) -> &[String] {
        &self.outputs
    }

    /// `(address, slot)` of every signal, inputs first, each side in file order.
    pub(crate) fn addresses(&self) -> &[(String, Slot)] {
        &self.addresses
    }

    /// The mapping file's line of the `k`-th address of [`Mapping::addresses`].
    pub(crate) fn line(&self, k: usize) -> usize {
        self.lines[k]
    }

    /// The slot of an address or a name.
    pub(crate) fn slot(&self, key: &[u8]) -> Option<Slot> {
        self.lookup.get(key).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Mapping, String> {
        Mapping::parse(Path::new("m.map"), text).map_err(|e| e.to_string())
    }

    #[test]
    fn order_is_file_order_of_inputs_then_outputs() {
        let m = parse("# tank\n%QX0.0 out valve\n%IX0.1 in start # button\n\n%IX0.2 in stop\n")
            .unwrap();
        assert_eq!(m.inputs, ["start", "stop"]);
        assert_eq!(m.outputs, ["valve"]);
        assert_eq!(m.slot(b"%IX0.2"), Some(Slot::Input(InputId(1))));
        assert_eq!(m.slot(b"valve"), Some(Slot::Output(OutputId(0))));
        assert_eq!(m.slot(b"%IX9.9"), None);
    }

    #[test]
    fn a_mapping_file_that_is_not_utf8_names_the_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.map");
        std::fs::write(&path, b"%IX0.1 in a\n%QX0.0 out \xff\n").unwrap();
        let got = Mapping::read(&path).unwrap_err().to_string();
        assert_eq!(got, format!("{}:2: not UTF-8 text", path.display()));
    }

    #[test]
    fn errors_name_their_line() {
        let cases = [
            (
                "%IX0.1 in a\n%IX0.1 in b\n%QX0.0 out z\n",
                "m.map:2: duplicate address '%IX0.1' (first on line 1)",
            ),
            (
                "%IX0.1 in a\n\n%IX0.2 out a\n",
                "m.map:3: duplicate name 'a' (first on line 1)",
            ),
            ("%IX0.1 in 1a\n", "m.map:1: '1a' is not a valid name"),
            ("%IX0.1 inout a\n", "m.map:1: expected 'in' or 'out'"),
            ("%IX0.1 in\n", "m.map:1: expected 'ADDRESS in|out NAME'"),
            (
                "%IX0.1 in a\nb out z\n%IX0.2 in b\n",
                "m.map:3: 'b' is both an address (line 2) and the name of another signal (line 3)",
            ),
            (
                "%IX0.1 in a\n# only inputs\n",
                "m.map:2: the mapping needs at least one",
            ),
        ];
        for (text, want) in cases {
            let got = parse(text).unwrap_err();
            assert!(got.starts_with(want), "{got:?} should start with {want:?}");
        }
    }
}
