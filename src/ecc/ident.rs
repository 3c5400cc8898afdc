//! Identifiers: the names a block, its inputs, outputs and states may have, checked once for
//! every language they end up in.
//!
//! In: a user-chosen name. Out: whether it is usable, and if not, why (the caller adds where
//! the name came from). Three rules, from loosest to strictest per language:
//! - [`is_identifier`]: the portable core `[A-Za-z][A-Za-z0-9_]*` that every names file,
//!   mapping and CSV header must follow;
//! - [`check_smv`]: the core, and no NuSMV keyword ([`SMV_KEYWORDS`] and
//!   [`NUSMV_LEXER_KEYWORDS`], case-sensitive); names starting with `_` are kept for generated
//!   identifiers;
//! - [`check_iec`]: an IEC 61131-3 identifier (`.fbt`, `.st`): a letter or `_` first, no `__`,
//!   no trailing `_`, and no keyword ([`IEC_KEYWORDS`], ignoring case).
//!
//! The block's own name, which every export uses, follows both, and [`check_block_name`] adds
//! the names the exporters write themselves.

/// Letters A-Z a-z, digits and `_`: the characters every rule allows after the first.
fn word_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// Checks the characters after the first.
fn check_rest(name: &str) -> Result<(), String> {
    match name.chars().skip(1).find(|&c| !word_char(c)) {
        Some(c) => Err(format!(
            "a name may contain only letters A-Z a-z, digits and `_`, not `{c}`"
        )),
        None => Ok(()),
    }
}

/// Is `name` in the portable core `[A-Za-z][A-Za-z0-9_]*`, usable as an interface variable
/// name? (Keywords of the target languages are checked where those languages are emitted.)
pub(crate) fn is_identifier(name: &str) -> bool {
    name.starts_with(|c: char| c.is_ascii_alphabetic()) && name.chars().all(word_char)
}

/// NuSMV 2.5's reserved words as its lexer lists them: none can be a name in a file the
/// tool reads (LTL specifications, plants), nor in one it writes ([`check_smv`]).
#[rustfmt::skip]
pub(crate) const NUSMV_LEXER_KEYWORDS: &[&str] = &[
    "A", "ABF", "ABG", "AF", "AG", "ASSIGN", "AX", "BU", "COMPASSION", "COMPID", "COMPUTE",
    "COMPWFF", "CONSTANTS", "CONSTRAINT", "CTLSPEC", "CTLWFF", "DEFINE", "E", "EBF", "EBG", "EF",
    "EG", "EX", "F", "FAIRNESS", "FALSE", "FROZENVAR", "G", "H", "IN", "INIT", "INVAR",
    "INVARSPEC", "ISA", "IVAR", "Integer", "JUSTICE", "LTLSPEC", "LTLWFF", "MAX", "MDEFINE", "MIN",
    "MIRROR", "MODULE", "NAME", "NEXTWFF", "O", "PRED", "PREDICATES", "PSLSPEC", "READ", "Real",
    "S", "SIMPWFF", "SPEC", "T", "TRANS", "TRUE", "U", "V", "VAR", "WRITE", "Word", "X", "Y", "Z",
    "array", "bool", "boolean", "case", "count", "esac", "extend", "in", "init", "integer", "mod",
    "next", "of", "process", "real", "resize", "self", "signed", "sizeof", "swconst", "toint",
    "union", "unsigned", "uwconst", "word", "word1", "xnor", "xor",
];

/// Words NuSMV 2.5/2.6 reserves (case-sensitive), plus the LTL/CTL operator letters, which
/// NuSMV's lexer also treats as keywords. [`check_smv`] refuses these and
/// [`NUSMV_LEXER_KEYWORDS`].
pub(crate) const SMV_KEYWORDS: &[&str] = &[
    "MODULE",
    "VAR",
    "IVAR",
    "DEFINE",
    "ASSIGN",
    "TRANS",
    "INIT",
    "INVAR",
    "SPEC",
    "LTLSPEC",
    "CTLSPEC",
    "INVARSPEC",
    "COMPUTE",
    "FAIRNESS",
    "JUSTICE",
    "COMPASSION",
    "CONSTANTS",
    "FROZENVAR",
    "ISA",
    "PSLSPEC",
    "PRED",
    "MIRROR",
    "NAME",
    "process",
    "array",
    "of",
    "boolean",
    "integer",
    "real",
    "word",
    "unsigned",
    "signed",
    "TRUE",
    "FALSE",
    "case",
    "esac",
    "init",
    "next",
    "self",
    "mod",
    "union",
    "in",
    "xor",
    "xnor",
    "G",
    "F",
    "X",
    "U",
    "V",
    "Y",
    "Z",
    "H",
    "O",
    "S",
    "T",
    "A",
    "E",
    "AG",
    "AF",
    "AX",
    "EG",
    "EF",
    "EX",
    "AU",
    "EU",
    "ABF",
    "ABG",
    "EBF",
    "EBG",
    "BU",
    "count",
    "toint",
    "bool",
    "word1",
    "uwconst",
    "swconst",
    "resize",
    "extend",
    "sizeof",
    "floor",
];

/// Checks that a user-chosen name (input, output, module) can be used verbatim in SMV code.
///
/// SMV itself allows `[A-Za-z_][A-Za-z0-9_$#-]*`; we accept only the portable core
/// `[A-Za-z][A-Za-z0-9_]*`, which is also a legal IEC 61131-3 identifier in almost all cases,
/// and reject NuSMV keywords (case-sensitive, as NuSMV is; NuSMV 2.5.4 reports a syntax error
/// at `MAX` or `Integer` used as a name). Names starting with `_` are reserved
/// for identifiers the emitters generate, so generated names never collide with user names.
/// The error says why the name is rejected; the caller adds where the name came from.
pub(crate) fn check_smv(name: &str) -> Result<(), String> {
    match name.chars().next() {
        None => return Err("the name is empty".into()),
        Some('_') => {
            return Err("names starting with `_` are reserved for generated identifiers".into())
        }
        Some(c) if !c.is_ascii_alphabetic() => {
            return Err(format!(
                "a name must start with a letter A-Z or a-z, not `{c}`"
            ))
        }
        Some(_) => {}
    }
    check_rest(name)?;
    if SMV_KEYWORDS.contains(&name) || NUSMV_LEXER_KEYWORDS.contains(&name) {
        return Err("it is a NuSMV keyword".into());
    }
    Ok(())
}

/// The module name of the controller in the closed loop synth composes.
pub const CONTROLLER_MODULE: &str = "ECC";

/// The modules of the closed loop synth composes: `main` (NuSMV's top module, which takes no
/// parameters) over the controller [`CONTROLLER_MODULE`] and the plant file's `plant`. A block
/// by one of these names could not stand beside them.
pub(crate) const CLOSED_LOOP_MODULES: [&str; 3] = ["main", CONTROLLER_MODULE, "plant"];

/// Names the exported function block declares itself: its events, and the state variable of
/// the Structured Text block (compared ignoring case, as ST does).
pub(crate) const BLOCK_MEMBERS: [&str; 3] = ["REQ", "CNF", "state"];

/// Checks the name of the block itself (`--name`), which names the SMV module, the Structured
/// Text function block and the IEC 61499 type: it must pass [`check_smv`] and [`check_iec`],
/// and be none of [`CLOSED_LOOP_MODULES`] and [`BLOCK_MEMBERS`].
pub(crate) fn check_block_name(name: &str) -> Result<(), String> {
    if name.len() > MAX_BLOCK_NAME {
        return Err(format!(
            "it is {} bytes long; a block name is at most {MAX_BLOCK_NAME} (it names the exported files)",
            name.len()
        ));
    }
    check_smv(name)?;
    check_iec(name)?;
    if name == "main" {
        return Err("it is NuSMV's top module, which takes no parameters".into());
    }
    if CLOSED_LOOP_MODULES.contains(&name) {
        return Err("the closed-loop model synth writes has a module of that name".into());
    }
    if BLOCK_MEMBERS.iter().any(|m| m.eq_ignore_ascii_case(name)) {
        return Err("the exported block uses this name for one of its own members".into());
    }
    Ok(())
}

/// The longest block name: it names the exported files (`<name>.fbt`, ...), and a file name
/// is at most 255 bytes on the usual file systems, the extension included.
pub(crate) const MAX_BLOCK_NAME: usize = 200;

/// IEC 61131-3 keywords and elementary type names (compared ignoring case, as ST does).
pub(crate) const IEC_KEYWORDS: &[&str] = &[
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
pub(crate) fn check_iec(name: &str) -> Result<(), String> {
    match name.chars().next() {
        None => return Err("the name is empty".into()),
        Some(c) if !(c.is_ascii_alphabetic() || c == '_') => {
            return Err(format!("a name must start with a letter or `_`, not `{c}`"))
        }
        Some(_) => {}
    }
    check_rest(name)?;
    if name.contains("__") || name.ends_with('_') {
        return Err("IEC 61131-3 allows neither `__` nor a trailing `_` in a name".into());
    }
    let upper = name.to_ascii_uppercase();
    if IEC_KEYWORDS.contains(&upper.as_str()) {
        return Err("it is an IEC 61131-3 keyword".into());
    }
    Ok(())
}

/// `TRUE` / `FALSE`: how SMV writes a Boolean constant and NuSMV prints one in a trace.
/// IEC 61131-3 Structured Text and 4diac spell them the same way.
pub(crate) fn bool_literal(v: bool) -> &'static str {
    if v {
        "TRUE"
    } else {
        "FALSE"
    }
}

/// A value as NuSMV prints it in a trace (and as SMV writes a constant).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SmvValue<'a> {
    /// `TRUE` or `FALSE`.
    Bool(bool),
    /// An integer, e.g. `-3`.
    Int(i64),
    /// Anything else: a symbolic constant or a controller state name, as printed.
    Symbol(&'a str),
}

/// Reads a value as NuSMV prints it in a trace: `TRUE`/`FALSE`, an integer, or a symbol.
pub(crate) fn parse_smv_value(text: &str) -> SmvValue<'_> {
    match text {
        "TRUE" => SmvValue::Bool(true),
        "FALSE" => SmvValue::Bool(false),
        _ => text.parse().map_or(SmvValue::Symbol(text), SmvValue::Int),
    }
}

/// Reads a Boolean as NuSMV prints it in a trace ([`bool_literal`] read back): `TRUE` or
/// `FALSE` only. Unlike a log's cells ([`crate::files::csv::parse_bool_cell`]), `1` and
/// `true` are not Booleans here: in a trace `1` is an integer and `true` a symbol.
pub(crate) fn parse_bool_literal(value: &str) -> Option<bool> {
    match parse_smv_value(value) {
        SmvValue::Bool(b) => Some(b),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_accept_plain_names() {
        for ok in ["a", "c1Home", "vac_on", "Z9", "Process", "s0", "REQ2"] {
            assert_eq!(check_smv(ok), Ok(()), "{ok}");
        }
    }

    #[test]
    fn identifiers_reject_keywords_reserved_and_odd_characters() {
        let cases = [
            ("", "empty"),
            ("_state", "reserved"),
            ("1a", "start with a letter"),
            ("a-b", "not `-`"),
            ("a$b", "not `$`"),
            ("vác", "not `á`"),
            ("next", "keyword"),
            ("X", "keyword"),
            ("AG", "keyword"),
            ("process", "keyword"),
            ("TRUE", "keyword"),
        ];
        for (name, why) in cases {
            let err = check_smv(name).unwrap_err();
            assert!(err.contains(why), "{name}: {err}");
        }
    }

    #[test]
    fn every_word_of_nusmvs_lexer_is_refused() {
        for word in [
            "MAX", "MIN", "IN", "Integer", "Real", "Word", "READ", "WRITE", "COMPID",
        ] {
            let err = check_smv(word).unwrap_err();
            assert!(err.contains("keyword"), "{word}: {err}");
        }
    }

    #[test]
    fn block_names_that_an_export_would_refuse() {
        for ok in ["SynthesizedFB", "Pnp", "Lamp2", "ECC1", "mainFB"] {
            assert_eq!(check_block_name(ok), Ok(()), "{ok}");
        }
        for (name, why) in [
            ("main", "NuSMV's top module"),
            ("ECC", "closed-loop model"),
            ("plant", "closed-loop model"),
            ("VAR", "NuSMV keyword"),
            ("esac", "NuSMV keyword"),
            ("MAX", "NuSMV keyword"),
            ("IF", "IEC 61131-3 keyword"),
            ("End_Var", "IEC 61131-3 keyword"),
            ("Fb_", "trailing"),
            ("State", "its own members"),
            ("req", "its own members"),
            ("_x", "reserved"),
            ("", "empty"),
        ] {
            let err = check_block_name(name).unwrap_err();
            assert!(err.contains(why), "{name}: {err}");
        }
    }

    #[test]
    fn iec_identifiers() {
        for ok in ["a", "_a", "c1_home", "START", "Motor2"] {
            assert_eq!(check_iec(ok), Ok(()), "{ok}");
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
            let e = check_iec(name).unwrap_err();
            assert!(e.contains(why), "{name}: {e}");
        }
    }

    #[test]
    fn the_portable_core() {
        for ok in ["a", "Z9", "vac_on", "next"] {
            assert!(is_identifier(ok), "{ok}");
        }
        for bad in ["", "_a", "1x", "a-b", "vác"] {
            assert!(!is_identifier(bad), "{bad}");
        }
    }
}
