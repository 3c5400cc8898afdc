//! PLCopen TC6 XML (version 2.01) project holding the ECC as one IEC 61131-3 function block in
//! Structured Text, the exchange format of CODESYS, TwinCAT and Beremiz/OpenPLC.
//!
//! In: a valid [`Ecc`] and [`PlcopenOptions`]. Out: one `<project>` in the namespace
//! [`NAMESPACE`] with
//! - `fileHeader` (company `fbsynth`, the creation time of the options) and `contentHeader`
//!   (the project name, the coordinate scaling the schema requires);
//! - one `<pou pouType="functionBlock">` named after the block: `REQ` and the inputs as
//!   `inputVars`, `CNF` and the outputs as `outputVars` (an output that starts TRUE has the
//!   `initialValue` TRUE), `state : INT := 0` as `localVars`; all signals `BOOL`;
//! - its body in ST: the statements of the [`st`] export, character for character,
//!   in one XHTML paragraph (`<xhtml:p>`, as Beremiz writes it);
//! - no configuration (`<instances><configurations/>`): the block is a library element that
//!   the engineer instantiates in their own program.
//!
//! So importing the project gives the same block as pasting the `.st` file, and the names are
//! checked by the same rule ([`st::check_names`]).

use super::st;
use super::NameError;
use crate::ecc::Ecc;
use crate::files::xml::XmlWriter;
use std::io::{self, Write};

/// The XML namespace of PLCopen TC6 XML 2.01.
pub(crate) const NAMESPACE: &str = "http://www.plcopen.org/xml/tc6_0201";

/// The XHTML namespace the ST body is written in.
const XHTML: &str = "http://www.w3.org/1999/xhtml";

/// Options of the PLCopen export.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct PlcopenOptions {
    /// The function block's name (an IEC 61131-3 identifier), also the project's name.
    pub(crate) block_name: String,
    /// `creationDateTime` of the file header, an `xsd:dateTime` such as
    /// `2026-12-03T09:00:00Z`; [`creation_time`] gives the one the command line uses.
    pub(crate) created: String,
}

/// The creation time of an export: `SOURCE_DATE_EPOCH` (seconds since the Unix epoch, the
/// reproducible-builds convention) when it is set and valid, otherwise the clock; in UTC,
/// as an `xsd:dateTime`.
pub(crate) fn creation_time() -> String {
    let seconds = std::env::var("SOURCE_DATE_EPOCH")
        .ok()
        .and_then(|s| s.trim().parse::<i64>().ok())
        .unwrap_or_else(|| time::OffsetDateTime::now_utc().unix_timestamp());
    let t = time::OffsetDateTime::from_unix_timestamp(seconds)
        .unwrap_or(time::OffsetDateTime::UNIX_EPOCH);
    format!(
        "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}Z",
        t.year(),
        u8::from(t.month()),
        t.day(),
        t.hour(),
        t.minute(),
        t.second()
    )
}

/// Checks the block name and the interface names, as for Structured Text.
pub(crate) fn check_names(ecc: &Ecc, block_name: &str) -> Result<(), NameError> {
    st::check_names(ecc, block_name)
}

/// Writes the project; fails with [`io::ErrorKind::InvalidInput`] (wrapping a [`NameError`])
/// before writing anything if a name is unusable.
pub(crate) fn write_plcopen(
    ecc: &Ecc,
    options: &PlcopenOptions,
    w: &mut impl Write,
) -> io::Result<()> {
    let name = options.block_name.as_str();
    check_names(ecc, name)?;
    let pou = Pou::of_ecc(ecc, name)?;
    write_project(name, &options.created, &ecc_comment(ecc), &[pou], w)
}

/// A variable of a POU's interface.
pub(crate) struct Var {
    /// Its name.
    pub(crate) name: String,
    /// An elementary type (`BOOL`, `INT`), or a function block type for an instance.
    pub(crate) type_name: TypeName,
    /// Its initial value as IEC 61131-3 text, if it has one.
    pub(crate) initial: Option<&'static str>,
}

/// The type of a [`Var`].
pub(crate) enum TypeName {
    /// An elementary type: `<BOOL/>`.
    Elementary(&'static str),
    /// A POU of the project: `<derived name="..."/>`.
    Derived(String),
}

impl Var {
    /// A `BOOL`, TRUE at the start when `initial`.
    pub(crate) fn boolean(name: &str, initial: bool) -> Var {
        Var {
            name: name.to_string(),
            type_name: TypeName::Elementary("BOOL"),
            initial: initial.then_some("TRUE"),
        }
    }
}

/// One function block of a project: its interface and its body in ST.
pub(crate) struct Pou {
    /// The block's type name.
    pub(crate) name: String,
    /// `REQ` first, then the inputs.
    pub(crate) inputs: Vec<Var>,
    /// `CNF` first, then the outputs.
    pub(crate) outputs: Vec<Var>,
    /// Internal variables (the state, module instances).
    pub(crate) locals: Vec<Var>,
    /// The statements.
    pub(crate) body: String,
}

impl Pou {
    /// The POU of one ECC, named `name`: the `.st` export's interface and statements.
    pub(crate) fn of_ecc(ecc: &Ecc, name: &str) -> io::Result<Pou> {
        let mut body = Vec::new();
        st::write_statements(ecc, &mut body)?;
        Ok(Pou {
            name: name.to_string(),
            inputs: std::iter::once(Var::boolean("REQ", false))
                .chain(ecc.inputs.iter().map(|i| Var::boolean(i, false)))
                .collect(),
            outputs: std::iter::once(Var::boolean("CNF", false))
                .chain(
                    (ecc.outputs.iter())
                        .zip(&ecc.initial_outputs)
                        .map(|(z, &init)| Var::boolean(z, init)),
                )
                .collect(),
            locals: vec![Var {
                name: "state".into(),
                type_name: TypeName::Elementary("INT"),
                initial: Some("0"),
            }],
            body: String::from_utf8(body).expect("the ST emitter writes UTF-8 only"),
        })
    }
}

/// Writes a project named `name` holding `pous` (names already checked).
pub(crate) fn write_project(
    name: &str,
    created: &str,
    description: &str,
    pous: &[Pou],
    w: &mut impl Write,
) -> io::Result<()> {
    let mut x = XmlWriter::new(w);
    x.declaration()?;
    x.open(
        0,
        "project",
        &[("xmlns", NAMESPACE), ("xmlns:xhtml", XHTML)],
    )?;
    x.leaf(
        1,
        "fileHeader",
        &[
            ("companyName", "fbsynth"),
            ("productName", "fbsynth"),
            ("productVersion", env!("CARGO_PKG_VERSION")),
            ("creationDateTime", created),
            ("contentDescription", description),
        ],
    )?;
    x.open(1, "contentHeader", &[("name", name)])?;
    x.open(2, "coordinateInfo", &[])?;
    for language in ["fbd", "ld", "sfc"] {
        x.indent(3)?;
        x.start(language, &[])?;
        x.empty("scaling", &[("x", "1"), ("y", "1")])?;
        x.end(language)?;
        x.newline()?;
    }
    x.close(2, "coordinateInfo")?;
    x.close(1, "contentHeader")?;
    x.open(1, "types", &[])?;
    x.leaf(2, "dataTypes", &[])?;
    x.open(2, "pous", &[])?;
    for pou in pous {
        x.open(
            3,
            "pou",
            &[("name", &pou.name), ("pouType", "functionBlock")],
        )?;
        x.open(4, "interface", &[])?;
        for (list, vars) in [
            ("inputVars", &pou.inputs),
            ("outputVars", &pou.outputs),
            ("localVars", &pou.locals),
        ] {
            x.open(5, list, &[])?;
            for var in vars {
                variable(&mut x, var)?;
            }
            x.close(5, list)?;
        }
        x.close(4, "interface")?;
        x.open(4, "body", &[])?;
        x.indent(5)?;
        x.start("ST", &[])?;
        x.start("xhtml:p", &[])?;
        x.text(&pou.body)?;
        x.end("xhtml:p")?;
        x.end("ST")?;
        x.newline()?;
        x.close(4, "body")?;
        x.close(3, "pou")?;
    }
    x.close(2, "pous")?;
    x.close(1, "types")?;
    x.open(1, "instances", &[])?;
    x.leaf(2, "configurations", &[])?;
    x.close(1, "instances")?;
    x.close(0, "project")
}

/// The file header's description: what the block is and its size.
fn ecc_comment(ecc: &Ecc) -> String {
    format!(
        "Function block synthesized by fbsynth ({}): each call with REQ = TRUE is one REQ \
         event of the IEC 61499 ECC",
        ecc.size()
    )
}

/// One `<variable>`, with its initial value if any.
fn variable<W: Write>(x: &mut XmlWriter<W>, var: &Var) -> io::Result<()> {
    x.indent(6)?;
    x.start("variable", &[("name", &var.name)])?;
    x.start("type", &[])?;
    match &var.type_name {
        TypeName::Elementary(t) => x.empty(t, &[])?,
        TypeName::Derived(t) => x.empty("derived", &[("name", t)])?,
    }
    x.end("type")?;
    if let Some(value) = var.initial {
        x.start("initialValue", &[])?;
        x.empty("simpleValue", &[("value", value)])?;
        x.end("initialValue")?;
    }
    x.end("variable")?;
    x.newline()
}

/// [`write_plcopen`] into a string.
pub(crate) fn to_string(ecc: &Ecc, options: &PlcopenOptions) -> io::Result<String> {
    let mut buf = Vec::new();
    write_plcopen(ecc, options, &mut buf)?;
    Ok(String::from_utf8(buf).expect("the emitter writes UTF-8"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::events::xes::elements;
    use crate::export::samples;

    fn options() -> PlcopenOptions {
        PlcopenOptions {
            block_name: "Fb".into(),
            created: "2026-12-03T09:00:00Z".into(),
        }
    }

    /// One snapshot per sample ECC, named after the sample.
    #[test]
    fn snapshots() {
        samples::snapshot_each_sample!(|ecc| to_string(ecc, &options()).unwrap());
    }

    /// The body is the `.st` export's statements, and the interface declares what they use.
    #[test]
    fn the_body_is_the_structured_text_of_the_st_export() {
        for (name, ecc) in samples::all() {
            let xml = to_string(&ecc, &options()).unwrap();
            let st = st::to_string(&ecc, "Fb").unwrap();
            let statements =
                &st[st.find("CNF := FALSE;").unwrap()..st.rfind("END_FUNCTION_BLOCK").unwrap()];
            let body = &xml[xml.find("<xhtml:p>").unwrap() + 9..xml.find("</xhtml:p>").unwrap()];
            let unescaped = body
                .replace("&lt;", "<")
                .replace("&gt;", ">")
                .replace("&amp;", "&");
            assert_eq!(unescaped, statements, "{name}");
            let declared: Vec<String> = elements(&xml)
                .into_iter()
                .filter(|(n, _)| n == "variable")
                .map(|(_, a)| a[0].1.clone())
                .collect();
            let mut expected = vec!["REQ".to_string()];
            expected.extend(ecc.inputs.iter().cloned());
            expected.push("CNF".into());
            expected.extend(ecc.outputs.iter().cloned());
            expected.push("state".into());
            assert_eq!(declared, expected, "{name}");
        }
    }

    #[test]
    fn reserved_names_are_refused_before_writing() {
        let mut ecc = samples::tri();
        ecc.outputs[0] = "cnf".into();
        let mut buf = Vec::new();
        let e = write_plcopen(&ecc, &options(), &mut buf).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        assert!(buf.is_empty());
    }

    #[test]
    fn the_creation_time_is_an_xsd_date_time() {
        let t = creation_time();
        assert_eq!(t.len(), 20, "{t}");
        assert!(t.ends_with('Z') && t.as_bytes()[10] == b'T', "{t}");
    }
}
