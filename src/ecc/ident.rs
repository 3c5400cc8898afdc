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
//!   no trailing `_`, and no reserved word: keyword, data type, standard function or
//!   function block ([`IEC_KEYWORDS`] and the type conversion families, ignoring case).
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

/// What a reserved word of IEC 61131-3 is, for the message that refuses it as a name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum IecWord {
    /// A keyword of the languages (`IF`, `END_VAR`, `FUNCTION_BLOCK`, ...).
    Keyword,
    /// An elementary data type (`BOOL`, `INT`, `TIME`, ...).
    ElementaryType,
    /// A generic data type of the standard functions' signatures (`ANY_NUM`, ...).
    GenericType,
    /// A standard function (`ADD`, `SEL`, `LEN`, `INT_TO_REAL`, ...).
    Function,
    /// A standard function block (`TON`, `R_TRIG`, `CTU`, ...).
    FunctionBlock,
}

impl IecWord {
    /// What the word names, in words; empty for a keyword.
    fn what(self) -> &'static str {
        match self {
            IecWord::Keyword => "",
            IecWord::ElementaryType => ": an elementary data type",
            IecWord::GenericType => ": a generic data type",
            IecWord::Function => ": a standard function",
            IecWord::FunctionBlock => ": a standard function block",
        }
    }
}

/// The reserved words of IEC 61131-3 (2nd edition, with the 3rd edition's additions),
/// compared ignoring case as ST does: its keywords, its elementary and generic data types,
/// and the names of its standard functions and function blocks (tables of the standard
/// functions and function blocks), which a compiler such as matiec refuses as names. The type
/// conversion functions (`INT_TO_REAL`, `BCD_TO_INT`, `TO_INT`, ...) form families,
/// recognized by [`conversion_function`].
#[rustfmt::skip]
pub(crate) const IEC_KEYWORDS: &[(&str, IecWord)] = {
    use IecWord::{ElementaryType as T, Function as F, FunctionBlock as B};
    use IecWord::{GenericType as G, Keyword as K};
    &[
    // Keywords of the textual languages, SFC, configurations and the 3rd edition's classes.
    ("ABSTRACT", K), ("ACTION", K), ("ARRAY", K), ("AT", K), ("BY", K), ("CASE", K), ("CLASS", K),
    ("CONFIGURATION", K), ("CONSTANT", K), ("CONTINUE", K), ("DO", K), ("ELSE", K), ("ELSIF", K),
    ("EN", K), ("END_ACTION", K), ("END_CASE", K), ("END_CLASS", K), ("END_CONFIGURATION", K),
    ("END_FOR", K), ("END_FUNCTION", K), ("END_FUNCTION_BLOCK", K), ("END_IF", K),
    ("END_INTERFACE", K), ("END_METHOD", K), ("END_NAMESPACE", K), ("END_PROGRAM", K),
    ("END_REPEAT", K), ("END_RESOURCE", K), ("END_STEP", K), ("END_STRUCT", K),
    ("END_TRANSITION", K), ("END_TYPE", K), ("END_VAR", K), ("END_WHILE", K), ("ENO", K),
    ("EVENT", K), ("EXIT", K), ("EXTENDS", K), ("FALSE", K), ("FINAL", K), ("FOR", K), ("FROM", K),
    ("FUNCTION", K), ("FUNCTION_BLOCK", K), ("F_EDGE", K), ("IF", K), ("IMPLEMENTS", K),
    ("INITIAL_STEP", K), ("INTERFACE", K), ("INTERNAL", K), ("INTERVAL", K), ("METHOD", K),
    ("NAMESPACE", K), ("NON_RETAIN", K), ("NULL", K), ("OF", K), ("ON", K), ("OVERRIDE", K),
    ("PRIORITY", K), ("PRIVATE", K), ("PROGRAM", K), ("PROTECTED", K), ("PUBLIC", K),
    ("READ_ONLY", K), ("READ_WRITE", K), ("REF", K), ("REF_TO", K), ("REPEAT", K), ("RESOURCE", K),
    ("RETAIN", K), ("RETURN", K), ("R_EDGE", K), ("SINGLE", K), ("STEP", K), ("STRUCT", K),
    ("SUPER", K), ("TASK", K), ("THEN", K), ("THIS", K), ("TO", K), ("TRANSITION", K), ("TRUE", K),
    ("TYPE", K), ("UNTIL", K), ("USING", K), ("VAR", K), ("VAR_ACCESS", K), ("VAR_CONFIG", K),
    ("VAR_EXTERNAL", K), ("VAR_GLOBAL", K), ("VAR_INPUT", K), ("VAR_IN_OUT", K), ("VAR_OUTPUT", K),
    ("VAR_TEMP", K), ("WHILE", K), ("WITH", K),
    // Elementary data types.
    ("BOOL", T), ("BYTE", T), ("CHAR", T), ("DATE", T), ("DATE_AND_TIME", T), ("DINT", T),
    ("DT", T), ("DWORD", T), ("INT", T), ("LDATE", T), ("LDATE_AND_TIME", T), ("LDT", T),
    ("LINT", T), ("LREAL", T), ("LTIME", T), ("LTIME_OF_DAY", T), ("LTOD", T), ("LWORD", T),
    ("REAL", T), ("SINT", T), ("STRING", T), ("TIME", T), ("TIME_OF_DAY", T), ("TOD", T),
    ("UDINT", T), ("UINT", T), ("ULINT", T), ("USINT", T), ("WCHAR", T), ("WORD", T),
    ("WSTRING", T),
    // Generic data types.
    ("ANY", G), ("ANY_DERIVED", G), ("ANY_ELEMENTARY", G), ("ANY_MAGNITUDE", G), ("ANY_NUM", G),
    ("ANY_REAL", G), ("ANY_INT", G), ("ANY_BIT", G), ("ANY_STRING", G), ("ANY_DATE", G),
    ("ANY_SIGNED", G), ("ANY_UNSIGNED", G), ("ANY_DURATION", G), ("ANY_CHAR", G), ("ANY_CHARS", G),
    // Standard functions: numerical.
    ("ABS", F), ("SQRT", F), ("LN", F), ("LOG", F), ("EXP", F), ("SIN", F), ("COS", F), ("TAN", F),
    ("ASIN", F), ("ACOS", F), ("ATAN", F), ("ATAN2", F),
    // Standard functions: arithmetic.
    ("ADD", F), ("MUL", F), ("SUB", F), ("DIV", F), ("MOD", F), ("EXPT", F), ("MOVE", F),
    // Standard functions: bit shift.
    ("SHL", F), ("SHR", F), ("ROR", F), ("ROL", F),
    // Standard functions: bitwise Boolean.
    ("AND", F), ("OR", F), ("XOR", F), ("NOT", F),
    // Standard functions: selection.
    ("SEL", F), ("MAX", F), ("MIN", F), ("LIMIT", F), ("MUX", F),
    // Standard functions: comparison.
    ("GT", F), ("GE", F), ("EQ", F), ("LE", F), ("LT", F), ("NE", F),
    // Standard functions: character string.
    ("LEN", F), ("LEFT", F), ("RIGHT", F), ("MID", F), ("CONCAT", F), ("INSERT", F), ("DELETE", F),
    ("REPLACE", F), ("FIND", F),
    // Standard functions: time and date.
    ("ADD_TIME", F), ("ADD_TOD_TIME", F), ("ADD_DT_TIME", F), ("SUB_TIME", F),
    ("SUB_DATE_DATE", F), ("SUB_TOD_TIME", F), ("SUB_TOD_TOD", F), ("SUB_DT_TIME", F),
    ("SUB_DT_DT", F), ("MULTIME", F), ("DIVTIME", F), ("MUL_TIME", F), ("DIV_TIME", F),
    ("CONCAT_DATE_TOD", F), ("CONCAT_DATE", F), ("CONCAT_TOD", F), ("CONCAT_DT", F),
    ("SPLIT_DATE", F), ("SPLIT_TOD", F), ("SPLIT_DT", F), ("DAY_OF_WEEK", F),
    // Standard functions: type conversion.
    ("TRUNC", F),
    // Standard function blocks: bistable.
    ("SR", B), ("RS", B),
    // Standard function blocks: edge detection.
    ("R_TRIG", B), ("F_TRIG", B),
    // Standard function blocks: counter.
    ("CTU", B), ("CTD", B), ("CTUD", B), ("CTU_DINT", B), ("CTU_LINT", B), ("CTU_UDINT", B),
    ("CTU_ULINT", B), ("CTD_DINT", B), ("CTD_LINT", B), ("CTD_UDINT", B), ("CTD_ULINT", B),
    ("CTUD_DINT", B), ("CTUD_LINT", B), ("CTUD_UDINT", B), ("CTUD_ULINT", B),
    // Standard function blocks: timer.
    ("TP", B), ("TON", B), ("TOF", B), ("LTP", B), ("LTON", B), ("LTOF", B),
    // Standard function blocks: real-time clock.
    ("RTC", B),
    ]
};

/// The elementary types the type conversion functions convert between.
fn elementary_type(word: &str) -> bool {
    IEC_KEYWORDS.contains(&(word, IecWord::ElementaryType))
}

/// Whether `upper` (a name in upper case) names a standard type conversion function:
/// `X_TO_Y`, `BCD_TO_X`, `X_TO_BCD`, `X_BCD_TO_Y`, `X_TO_BCD_Y`, `TO_X`, `TRUNC_X` or
/// `X_TRUNC_Y`, with `X` and `Y` elementary types.
fn conversion_function(upper: &str) -> bool {
    let typed = elementary_type;
    let either = |w: &str| typed(w) || w == "BCD";
    if let Some(t) = (upper.strip_prefix("TO_")).or_else(|| upper.strip_prefix("TRUNC_")) {
        return typed(t);
    }
    if let Some((from, to)) = upper.split_once("_TRUNC_") {
        return typed(from) && typed(to);
    }
    if let Some((from, to)) = upper.split_once("_BCD_TO_") {
        return typed(from) && typed(to);
    }
    if let Some((from, to)) = upper.split_once("_TO_BCD_") {
        return typed(from) && typed(to);
    }
    // Type names contain `_` (`DATE_AND_TIME`, `TIME_OF_DAY`) but never `_TO_`.
    upper
        .split_once("_TO_")
        .is_some_and(|(from, to)| either(from) && either(to))
}

/// The reserved word `name` is, if any (ignoring case), spelt as the standard spells it.
pub(crate) fn iec_reserved(name: &str) -> Option<(String, IecWord)> {
    let upper = name.to_ascii_uppercase();
    if let Some(&(word, kind)) = IEC_KEYWORDS.iter().find(|(w, _)| *w == upper) {
        return Some((word.to_string(), kind));
    }
    conversion_function(&upper).then_some((upper, IecWord::Function))
}

/// Checks an IEC 61131-3 identifier: a letter or `_`, then letters, digits and single `_`s,
/// not ending in `_`, and no reserved word ([`IEC_KEYWORDS`], the type conversion functions;
/// ignoring case). The error names the reserved word.
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
    match iec_reserved(name) {
        Some((word, kind)) => Err(format!("`{word}` is an IEC 61131-3 keyword{}", kind.what())),
        None => Ok(()),
    }
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
    fn iec_reserved_words_are_refused_naming_the_word_in_every_category() {
        for (name, message) in [
            ("elsif", "`ELSIF` is an IEC 61131-3 keyword"),
            (
                "Ton",
                "`TON` is an IEC 61131-3 keyword: a standard function block",
            ),
            (
                "r_trig",
                "`R_TRIG` is an IEC 61131-3 keyword: a standard function block",
            ),
            (
                "CTUD",
                "`CTUD` is an IEC 61131-3 keyword: a standard function block",
            ),
            (
                "RTC",
                "`RTC` is an IEC 61131-3 keyword: a standard function block",
            ),
            (
                "sr",
                "`SR` is an IEC 61131-3 keyword: a standard function block",
            ),
            (
                "Add",
                "`ADD` is an IEC 61131-3 keyword: a standard function",
            ),
            (
                "sqrt",
                "`SQRT` is an IEC 61131-3 keyword: a standard function",
            ),
            (
                "SHL",
                "`SHL` is an IEC 61131-3 keyword: a standard function",
            ),
            (
                "Sel",
                "`SEL` is an IEC 61131-3 keyword: a standard function",
            ),
            (
                "max",
                "`MAX` is an IEC 61131-3 keyword: a standard function",
            ),
            ("GT", "`GT` is an IEC 61131-3 keyword: a standard function"),
            (
                "Left",
                "`LEFT` is an IEC 61131-3 keyword: a standard function",
            ),
            (
                "move",
                "`MOVE` is an IEC 61131-3 keyword: a standard function",
            ),
            (
                "xor",
                "`XOR` is an IEC 61131-3 keyword: a standard function",
            ),
            (
                "add_tod_time",
                "`ADD_TOD_TIME` is an IEC 61131-3 keyword: a standard function",
            ),
            (
                "int_to_real",
                "`INT_TO_REAL` is an IEC 61131-3 keyword: a standard function",
            ),
            (
                "BCD_TO_INT",
                "`BCD_TO_INT` is an IEC 61131-3 keyword: a standard function",
            ),
            (
                "Word_To_Bcd",
                "`WORD_TO_BCD` is an IEC 61131-3 keyword: a standard function",
            ),
            ("DATE_AND_TIME_TO_TIME_OF_DAY", "a standard function"),
            (
                "trunc",
                "`TRUNC` is an IEC 61131-3 keyword: a standard function",
            ),
            (
                "TO_INT",
                "`TO_INT` is an IEC 61131-3 keyword: a standard function",
            ),
            ("REAL_TRUNC_DINT", "a standard function"),
            (
                "any_bit",
                "`ANY_BIT` is an IEC 61131-3 keyword: a generic data type",
            ),
            (
                "ANY_MAGNITUDE",
                "`ANY_MAGNITUDE` is an IEC 61131-3 keyword: a generic data type",
            ),
            (
                "Lreal",
                "`LREAL` is an IEC 61131-3 keyword: an elementary data type",
            ),
            (
                "ltime",
                "`LTIME` is an IEC 61131-3 keyword: an elementary data type",
            ),
        ] {
            let e = check_iec(name).unwrap_err();
            assert!(e.contains(message), "{name}: {e}");
            let e = check_block_name(name).unwrap_err();
            assert!(e.contains("keyword"), "{name}: {e}");
        }
        // Words that only look like a conversion or a standard name stay usable.
        for ok in [
            "HOME_TO_END",
            "INT_TO",
            "TO_HOME",
            "tone",
            "TONx",
            "ctu1",
            "leftLimit",
            "Move2",
            "INT_TO_INT_TO",
            "trunc_x",
        ] {
            assert_eq!(check_iec(ok), Ok(()), "{ok}");
        }
        // The one list covers every category.
        for kind in [
            IecWord::Keyword,
            IecWord::ElementaryType,
            IecWord::GenericType,
            IecWord::Function,
            IecWord::FunctionBlock,
        ] {
            assert!(IEC_KEYWORDS.iter().any(|&(_, k)| k == kind), "{kind:?}");
        }
        let mut words: Vec<&str> = IEC_KEYWORDS.iter().map(|&(w, _)| w).collect();
        words.sort_unstable();
        let all = words.len();
        words.dedup();
        assert_eq!(words.len(), all, "a word listed twice");
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
