//! Export formats of an ECC, and writing them to files.
//!
//! In: a valid [`Ecc`] and the formats wanted. Out: text in each format (pure emitters, one
//! module each: [`json`], [`fbt`], [`st`], [`plcopen`], [`dot`], [`pnml`], and the SMV module
//! of [`crate::smv::ecc_module`]), or files written atomically by [`write_all`].
//!
//! The names that become code (IEC 61131-3 in `.fbt` and `.st`) are checked here with
//! [`check_iec_identifier`]; names that reach SMV are checked by [`crate::smv`]; both rules
//! live in [`crate::ecc::ident`]. Files are written by [`crate::files`], as ordinary files.

pub(crate) mod dot;
pub(crate) mod fbt;
pub mod guard_text;
pub mod json;
pub mod modular;
pub(crate) mod network;
pub(crate) mod plcopen;
pub(crate) mod pnml;
pub(crate) mod st;
pub(crate) mod waveform;

#[cfg(test)]
pub(crate) mod samples;

pub(crate) use crate::ecc::ident::check_iec as check_iec_identifier;

use crate::ecc::Ecc;
use crate::files::{self, Folders, WriteError};
use crate::smv::{ecc_module, SmvError};
use std::collections::HashMap;
use std::fmt;
use std::io;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// An export format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// The JSON contract ([`json`]).
    Json,
    /// IEC 61499 basic FB type ([`fbt`]).
    Fbt,
    /// NuSMV module ([`crate::smv::ecc_module`]).
    Smv,
    /// Graphviz drawing ([`dot`]); an SVG as well when Graphviz is installed.
    Dot,
    /// IEC 61131-3 Structured Text function block ([`st`]).
    St,
    /// Place/transition net for process-mining tools ([`pnml`]), labelled with the signal
    /// names; not among the defaults.
    Pnml,
    /// PLCopen TC6 XML project with the block as an ST function block ([`plcopen`]), written
    /// as `<stem>.xml`; not among the defaults.
    Plcopen,
}

impl Format {
    /// Every format, in the order `--help` lists them.
    pub(crate) const ALL: [Format; 7] = [
        Format::Json,
        Format::Fbt,
        Format::Smv,
        Format::Dot,
        Format::St,
        Format::Pnml,
        Format::Plcopen,
    ];

    /// The format's name on the command line, which is also its file extension.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Format::Json => "json",
            Format::Fbt => "fbt",
            Format::Smv => "smv",
            Format::Dot => "dot",
            Format::St => "st",
            Format::Pnml => "pnml",
            Format::Plcopen => "plcopen",
        }
    }

    /// File extension, without the dot: the name, except `xml` for PLCopen.
    pub(crate) fn extension(self) -> &'static str {
        match self {
            Format::Plcopen => "xml",
            f => f.name(),
        }
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A format name that is not one of [`Format::ALL`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown export format {}; valid formats: json, fbt, smv, dot, st, pnml, plcopen",
    crate::quote::backquote(given)
)]
pub struct UnknownFormat {
    /// The name as given.
    pub(crate) given: String,
}

impl FromStr for Format {
    type Err = UnknownFormat;

    /// Parses `json`, `fbt`, `smv`, `dot`, `st`, `pnml` or `plcopen` (ignoring case and
    /// surrounding blanks).
    fn from_str(s: &str) -> Result<Format, UnknownFormat> {
        let wanted = s.trim().to_ascii_lowercase();
        Format::ALL
            .into_iter()
            .find(|f| f.name() == wanted)
            .ok_or_else(|| UnknownFormat {
                given: s.to_string(),
            })
    }
}

/// Why [`write_all`] wrote nothing, or stopped.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// The ECC breaks an invariant of the model (a bug upstream, not user input).
    #[error("the ECC is inconsistent: {0}")]
    InvalidEcc(String),
    /// A name (the stem, or an interface name) cannot be used in a format.
    #[error("cannot export as {format}")]
    Name {
        /// The format that cannot use the name.
        format: Format,
        /// Which name, and why.
        #[source]
        source: NameError,
    },
    /// A name cannot be used in the SMV module.
    #[error("cannot export as smv")]
    Smv(#[source] SmvError),
    /// Creating, writing or renaming a file failed.
    #[error("cannot write {}", path.display())]
    Write {
        /// The file that could not be written.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: io::Error,
    },
    /// Graphviz is installed but failed to render the drawing.
    #[error("cannot render {}", path.display())]
    Render {
        /// The SVG file that was to be written.
        path: PathBuf,
        /// Graphviz's failure.
        #[source]
        source: io::Error,
    },
}

/// The text of one export of `ecc` (named `stem` where the format names the block); the
/// names are checked for the format first.
pub fn text(ecc: &Ecc, stem: &str, format: Format) -> Result<String, ExportError> {
    ecc.validate().map_err(ExportError::InvalidEcc)?;
    let name_error = |source| ExportError::Name { format, source };
    Ok(match format {
        Format::Json => json::to_string(ecc),
        Format::Dot => dot::to_string(ecc),
        Format::Smv => ecc_module::ecc_module_to_string(ecc, stem).map_err(ExportError::Smv)?,
        Format::Fbt => {
            fbt::check_names(ecc, stem).map_err(name_error)?;
            let options = fbt::FbtOptions {
                type_name: stem.to_string(),
                ..fbt::FbtOptions::default()
            };
            fbt::to_string(ecc, &options).expect("names are checked")
        }
        Format::St => {
            st::check_names(ecc, stem).map_err(name_error)?;
            st::to_string(ecc, stem).expect("names are checked")
        }
        Format::Pnml => {
            let mut buf = Vec::new();
            pnml::write_pnml_labelled(
                ecc,
                &pnml::Labels::names(ecc),
                stem,
                pnml::Dialect::Iso,
                &mut buf,
            )
            .expect("writing into memory cannot fail");
            String::from_utf8(buf).expect("the emitter writes UTF-8")
        }
        Format::Plcopen => {
            plcopen::check_names(ecc, stem).map_err(name_error)?;
            let options = plcopen::PlcopenOptions {
                block_name: stem.to_string(),
                created: plcopen::creation_time(),
            };
            plcopen::to_string(ecc, &options).expect("names are checked")
        }
    })
}

/// Writes `ecc` in every format of `formats` (repeats ignored) to `dir/stem.<extension>`, plus
/// `dir/stem.svg` when [`Format::Dot`] is wanted and Graphviz's `dot` is installed. Returns
/// the paths written, in the order of `formats`, the SVG right after the DOT file.
///
/// `stem` also names the block: the `.fbt` type, the `.st` function block and the SMV module
/// are called `stem`, so it must be an identifier for those formats (4diac expects the type
/// name to match the file name).
///
/// Every text is produced and every name checked before the first file is touched, and each
/// file is written to a temporary file in `dir` and renamed over its target, so a failure
/// never leaves a half-written file, and a bad name leaves no file at all.
pub(crate) fn write_all(
    ecc: &Ecc,
    dir: &Path,
    stem: &str,
    formats: &[Format],
) -> Result<Vec<PathBuf>, ExportError> {
    ecc.validate().map_err(ExportError::InvalidEcc)?;
    let mut wanted: Vec<Format> = Vec::new();
    for &f in formats {
        if !wanted.contains(&f) {
            wanted.push(f);
        }
    }
    let texts: Vec<(Format, String)> = wanted
        .iter()
        .map(|&format| Ok((format, text(ecc, stem, format)?)))
        .collect::<Result<_, ExportError>>()?;

    let named = texts
        .into_iter()
        .map(|(format, text)| (format!("{stem}.{}", format.extension()), text));
    write_texts(dir, named)
}

/// Writes each `(file, text)` to `dir/file` ([`write_file`]), and right after each Graphviz
/// file (`.dot`) its drawing beside it (`.svg`) when Graphviz's `dot` is installed. Returns the
/// paths written, in that order.
pub(crate) fn write_texts(
    dir: &Path,
    texts: impl IntoIterator<Item = (String, String)>,
) -> Result<Vec<PathBuf>, ExportError> {
    let mut written = Vec::new();
    for (file, text) in texts {
        let path = dir.join(&file);
        write_file(&path, text.as_bytes())?;
        written.push(path.clone());
        if file.ends_with(".dot") {
            let svg = path.with_extension("svg");
            match dot::render_svg(&text, &svg) {
                Ok(true) => written.push(svg),
                Ok(false) => {}
                Err(source) => return Err(ExportError::Render { path: svg, source }),
            }
        }
    }
    Ok(written)
}

/// Writes one export file atomically as an ordinary file (0666 less the umask), into `dir`
/// as it is: a missing folder is an error, not created.
pub(crate) fn write_file(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    files::write_atomic_in(path, bytes, Folders::MustExist)
        .map_err(|WriteError { path, source }| ExportError::Write { path, source })
}

/// A name that cannot be used in an exported program.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{role} {} cannot be used in {format}: {reason}",
    crate::quote::backquote(name)
)]
pub struct NameError {
    /// Where the name comes from: `type name`, `input 3`, `output 1` (1-based).
    pub(crate) role: String,
    /// The name as given.
    pub(crate) name: String,
    /// The format that cannot use it, e.g. `an IEC 61499 .fbt file`.
    pub(crate) format: &'static str,
    /// Which rule the name breaks.
    pub(crate) reason: String,
}

impl From<NameError> for io::Error {
    fn from(e: NameError) -> io::Error {
        io::Error::new(io::ErrorKind::InvalidInput, e)
    }
}

/// Checks the block name and every interface name of `ecc` for a format with IEC 61131-3
/// names: each an IEC identifier, none equal to a name the emitter generates (`reserved`), and
/// the interface names distinct, everything ignoring case.
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
    if reserved.contains(&block_name.to_ascii_uppercase()) {
        return Err(bad(
            "type name".into(),
            block_name,
            "the exported block uses this name itself".into(),
        ));
    }
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

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn formats_parse_and_list_the_valid_ones() {
        assert_eq!("json".parse(), Ok(Format::Json));
        assert_eq!(" FBT ".parse(), Ok(Format::Fbt));
        for f in Format::ALL {
            assert_eq!(f.name().parse(), Ok(f));
        }
        assert_eq!(Format::St.extension(), "st");
        let e = "svg".parse::<Format>().unwrap_err();
        assert_eq!(
            e.to_string(),
            "unknown export format `svg`; valid formats: json, fbt, smv, dot, st, pnml, plcopen"
        );
    }

    fn files_in(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn write_all_writes_each_format_once_and_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let ecc = samples::tri();
        std::fs::write(dir.path().join("Pnp.json"), "old content").unwrap();
        let formats = [
            Format::St,
            Format::Json,
            Format::Smv,
            Format::Fbt,
            Format::Dot,
        ];
        let mut with_repeat = formats.to_vec();
        with_repeat.push(Format::Json);
        let paths = write_all(&ecc, dir.path(), "Pnp", &with_repeat).unwrap();

        let svg = which::which("dot").is_ok();
        let mut expected: Vec<String> = formats
            .iter()
            .map(|f| format!("Pnp.{}", f.extension()))
            .collect();
        if svg {
            expected.push("Pnp.svg".into());
        }
        let returned: Vec<String> = paths
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        let mut in_order = expected.clone();
        if svg {
            // The SVG follows the DOT file.
            in_order.pop();
            in_order.insert(5, "Pnp.svg".into());
        }
        assert_eq!(returned, in_order);
        expected.sort();
        assert_eq!(files_in(dir.path()), expected, "no temporary file is left");

        let read = |ext: &str| std::fs::read_to_string(dir.path().join(format!("Pnp.{ext}")));
        assert_eq!(read("json").unwrap(), json::to_string(&ecc));
        assert_eq!(read("dot").unwrap(), dot::to_string(&ecc));
        assert_eq!(read("st").unwrap(), st::to_string(&ecc, "Pnp").unwrap());
        assert_eq!(
            read("smv").unwrap(),
            ecc_module::ecc_module_to_string(&ecc, "Pnp").unwrap()
        );
        assert!(read("fbt").unwrap().contains(r#"<FBType Name="Pnp""#));
    }

    /// The machine files are ordinary files: 0644 under the usual umask 022, not the 0600 of
    /// the temporary file they were written to.
    #[cfg(unix)]
    #[test]
    fn written_files_are_world_readable_under_umask_022() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        // SAFETY: umask only swaps the process's file mode mask; the old one is restored below.
        // 022 is the mask tests run under anyway, so parallel tests see no change.
        let old = unsafe { libc::umask(0o022) };
        let written = write_all(&samples::tri(), dir.path(), "SynthesizedFB", &Format::ALL);
        unsafe { libc::umask(old) };
        let written = written.unwrap();
        assert!(written.len() >= Format::ALL.len());
        for path in written {
            let mode = std::fs::metadata(&path).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode, 0o644, "{}", path.display());
        }
    }

    #[test]
    fn a_bad_name_leaves_no_file_at_all() {
        let dir = tempfile::tempdir().unwrap();
        let e = write_all(
            &samples::tri(),
            dir.path(),
            "pick-place",
            &[Format::Json, Format::Dot, Format::Fbt],
        )
        .unwrap_err();
        assert_eq!(e.to_string(), "cannot export as fbt");
        let cause = std::error::Error::source(&e).unwrap().to_string();
        assert!(
            cause.starts_with("type name `pick-place` cannot be used"),
            "{cause}"
        );
        assert!(files_in(dir.path()).is_empty());

        let e = write_all(
            &samples::tri(),
            dir.path(),
            "next",
            &[Format::Json, Format::Smv],
        )
        .unwrap_err();
        assert!(
            matches!(e, ExportError::Smv(SmvError::Identifier { .. })),
            "{e:?}"
        );
        assert!(files_in(dir.path()).is_empty());
    }

    #[test]
    fn a_missing_directory_is_a_write_error_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("no/such/dir");
        let e = write_all(&samples::tri(), &missing, "m", &[Format::Json]).unwrap_err();
        match e {
            ExportError::Write { path, .. } => assert_eq!(path, missing.join("m.json")),
            e => panic!("{e:?}"),
        }
    }

    #[test]
    fn an_inconsistent_ecc_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let mut ecc = samples::tri();
        ecc.initial_outputs.pop();
        let e = write_all(&ecc, dir.path(), "m", &[Format::Json]).unwrap_err();
        assert!(matches!(e, ExportError::InvalidEcc(_)), "{e:?}");
        assert!(files_in(dir.path()).is_empty());
    }
}
