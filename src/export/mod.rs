//! Export formats of an ECC, and writing them to files.
//!
//! In: a valid [`Ecc`] and the formats wanted. Out: text in each format (pure emitters, one
//! module each: [`json`], [`fbt`], [`st`], [`dot`], and the SMV module of
//! [`crate::smv::ecc_module`]), or files written atomically by [`write_all`].
//!
//! The names that become code (IEC 61131-3 in `.fbt` and `.st`) are checked here with
//! [`check_iec_identifier`]; names that reach SMV are checked by [`crate::smv`].

pub mod fbt;
pub mod guard_text;
pub mod json;
pub mod st;

#[cfg(test)]
pub(crate) mod samples;

use crate::ecc::Ecc;
use std::collections::HashMap;
use std::io;

/// A name that cannot be used in an exported program.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{role} `{name}` cannot be used in {format}: {reason}")]
pub struct NameError {
    /// Where the name comes from: `type name`, `input 3`, `output 1` (1-based).
    pub role: String,
    pub name: String,
    /// The format that cannot use it, e.g. `an IEC 61499 .fbt file`.
    pub format: &'static str,
    pub reason: String,
}

impl From<NameError> for io::Error {
    fn from(e: NameError) -> io::Error {
        io::Error::new(io::ErrorKind::InvalidInput, e)
    }
}

/// IEC 61131-3 keywords and elementary type names (compared ignoring case, as ST does).
const IEC_KEYWORDS: &[&str] = &[
    "ABSTRACT",
    "ACTION",
    "AND",
    "ANY",
    "ARRAY",
    "AT",
    "BOOL",
    "BY",
    "BYTE",
    "CASE",
    "CHAR",
    "CLASS",
    "CONFIGURATION",
    "CONSTANT",
    "CONTINUE",
    "DATE",
    "DATE_AND_TIME",
    "DINT",
    "DO",
    "DT",
    "DWORD",
    "ELSE",
    "ELSIF",
    "EN",
    "END_ACTION",
    "END_CASE",
    "END_CLASS",
    "END_CONFIGURATION",
    "END_FOR",
    "END_FUNCTION",
    "END_FUNCTION_BLOCK",
    "END_IF",
    "END_INTERFACE",
    "END_METHOD",
    "END_NAMESPACE",
    "END_PROGRAM",
    "END_REPEAT",
    "END_RESOURCE",
    "END_STEP",
    "END_STRUCT",
    "END_TRANSITION",
    "END_TYPE",
    "END_VAR",
    "END_WHILE",
    "ENO",
    "EVENT",
    "EXIT",
    "EXTENDS",
    "FALSE",
    "FINAL",
    "FOR",
    "FROM",
    "FUNCTION",
    "FUNCTION_BLOCK",
    "F_EDGE",
    "IF",
    "IMPLEMENTS",
    "INITIAL_STEP",
    "INT",
    "INTERFACE",
    "INTERNAL",
    "INTERVAL",
    "LINT",
    "LREAL",
    "LWORD",
    "METHOD",
    "MOD",
    "NAMESPACE",
    "NON_RETAIN",
    "NOT",
    "NULL",
    "OF",
    "ON",
    "OR",
    "OVERRIDE",
    "PRIORITY",
    "PRIVATE",
    "PROGRAM",
    "PROTECTED",
    "PUBLIC",
    "READ_ONLY",
    "READ_WRITE",
    "REAL",
    "REF",
    "REF_TO",
    "REPEAT",
    "RESOURCE",
    "RETAIN",
    "RETURN",
    "R_EDGE",
    "SINGLE",
    "SINT",
    "STEP",
    "STRING",
    "STRUCT",
    "SUPER",
    "TASK",
    "THEN",
    "THIS",
    "TIME",
    "TIME_OF_DAY",
    "TO",
    "TOD",
    "TRANSITION",
    "TRUE",
    "TYPE",
    "UDINT",
    "UINT",
    "ULINT",
    "UNTIL",
    "USING",
    "USINT",
    "VAR",
    "VAR_ACCESS",
    "VAR_CONFIG",
    "VAR_EXTERNAL",
    "VAR_GLOBAL",
    "VAR_INPUT",
    "VAR_IN_OUT",
    "VAR_OUTPUT",
    "VAR_TEMP",
    "WCHAR",
    "WHILE",
    "WITH",
    "WORD",
    "WSTRING",
    "XOR",
];

/// Checks an IEC 61131-3 identifier: a letter or `_`, then letters, digits and single `_`s,
/// not ending in `_`, and no keyword or elementary type name (ignoring case).
pub fn check_iec_identifier(name: &str) -> Result<(), String> {
    let mut chars = name.chars();
    match chars.next() {
        None => return Err("the name is empty".into()),
        Some(c) if !(c.is_ascii_alphabetic() || c == '_') => {
            return Err(format!("a name must start with a letter or `_`, not `{c}`"))
        }
        Some(_) => {}
    }
    if let Some(c) = chars.find(|c| !(c.is_ascii_alphanumeric() || *c == '_')) {
        return Err(format!(
            "a name may contain only letters A-Z a-z, digits and `_`, not `{c}`"
        ));
    }
    if name.contains("__") || name.ends_with('_') {
        return Err("IEC 61131-3 allows neither `__` nor a trailing `_` in a name".into());
    }
    let upper = name.to_ascii_uppercase();
    if IEC_KEYWORDS.contains(&upper.as_str()) {
        return Err("it is an IEC 61131-3 keyword".into());
    }
    Ok(())
}

/// Checks the block name and every interface name of `ecc` for a format with IEC 61131-3
/// names: each an IEC identifier, none equal to a name the emitter generates (`reserved`), and
/// all distinct, everything ignoring case.
pub(crate) fn check_iec_names(
    ecc: &Ecc,
    format: &'static str,
    block_name: &str,
    reserved: &[String],
) -> Result<(), NameError> {
    let bad = |role: String, name: &str, reason: String| NameError {
        role,
        name: name.to_string(),
        format,
        reason,
    };
    check_iec_identifier(block_name).map_err(|r| bad("type name".into(), block_name, r))?;
    let reserved: Vec<String> = reserved.iter().map(|r| r.to_ascii_uppercase()).collect();
    let mut seen: HashMap<String, String> = HashMap::new();
    let named = (ecc.inputs.iter().enumerate()).map(|(i, n)| (format!("input {}", i + 1), n));
    let named = named
        .chain((ecc.outputs.iter().enumerate()).map(|(i, n)| (format!("output {}", i + 1), n)));
    for (role, name) in named {
        check_iec_identifier(name).map_err(|r| bad(role.clone(), name, r))?;
        let key = name.to_ascii_uppercase();
        if reserved.contains(&key) {
            return Err(bad(
                role,
                name,
                "the exported block uses this name itself".into(),
            ));
        }
        if let Some(first) = seen.get(&key) {
            let reason = format!("{first} has the same name ignoring case");
            return Err(bad(role, name, reason));
        }
        seen.insert(key, role);
    }
    Ok(())
}

/// `TRUE` / `FALSE`, as ST, SMV and 4diac spell them.
pub(crate) fn iec_bool(v: bool) -> &'static str {
    if v {
        "TRUE"
    } else {
        "FALSE"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iec_identifiers() {
        for ok in ["a", "_a", "c1_home", "START", "Motor2"] {
            assert_eq!(check_iec_identifier(ok), Ok(()), "{ok}");
        }
        for (name, why) in [
            ("", "empty"),
            ("2a", "start with"),
            ("a__b", "`__`"),
            ("a_", "trailing"),
            ("a.b", "not `.`"),
            ("end_if", "keyword"),
            ("Bool", "keyword"),
        ] {
            let e = check_iec_identifier(name).unwrap_err();
            assert!(e.contains(why), "{name}: {e}");
        }
    }

    #[test]
    fn iec_names_of_an_ecc() {
        let e = samples::tri();
        let reserved = vec!["REQ".to_string(), "state".to_string()];
        assert_eq!(check_iec_names(&e, "ST", "Fb", &reserved), Ok(()));
        let mut bad = e.clone();
        bad.outputs[1] = "State".into();
        assert_eq!(
            check_iec_names(&bad, "ST", "Fb", &reserved)
                .unwrap_err()
                .to_string(),
            "output 2 `State` cannot be used in ST: the exported block uses this name itself"
        );
        let mut bad = e.clone();
        bad.outputs[0] = "C1HOME".into();
        assert_eq!(
            check_iec_names(&bad, "ST", "Fb", &reserved)
                .unwrap_err()
                .to_string(),
            "output 1 `C1HOME` cannot be used in ST: input 1 has the same name ignoring case"
        );
        let err = check_iec_names(&e, "ST", "my-fb", &reserved).unwrap_err();
        assert_eq!(err.role, "type name");
    }
}
