//! A hand-written surrogate plant model, read far enough to couple it to a controller.
//!
//! In: the text of an SMV file. Out: a [`Plant`]: the file as-is plus what the coupling
//! convention needs: the formal parameters of `MODULE plant(...)` and the names it declares
//! (`VAR`, `IVAR`, `FROZENVAR`, `DEFINE`), each with its line. This is a scanner, not a full SMV
//! parser: NuSMV itself checks the rest, and its errors are mapped back to this file's lines.

use crate::ecc::ident::CONTROLLER_MODULE;
use std::path::{Path, PathBuf};

/// A name in the plant file and the line it is declared on (1-based).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Declared {
    /// The name as written.
    pub name: String,
    /// 1-based line of the declaration (or of the parameter in `MODULE plant(...)`).
    pub line: usize,
}

/// The plant file with the parts of `MODULE plant` the coupling needs.
#[derive(Debug, Clone)]
pub struct Plant {
    /// Path of the plant file (for messages and for mapping NuSMV's errors back).
    pub file: PathBuf,
    /// The whole file as read, copied unchanged into the closed-loop model.
    pub text: String,
    /// Line of `MODULE plant`.
    pub module_line: usize,
    /// Formal parameters: controller outputs the plant reads.
    pub params: Vec<Declared>,
    /// Variables and defines of module `plant`.
    pub names: Vec<Declared>,
    /// The names among [`Plant::names`] that are instances of other modules of the file
    /// (`aux : helper(vs);`): the closed loop reaches into them through the plant's defines,
    /// never by a bare name.
    pub instances: Vec<String>,
}

/// A plant file that does not follow the coupling convention.
#[derive(Debug, thiserror::Error)]
pub enum PlantError {
    /// The file cannot be read, has a line over the limit or is too large.
    #[error(transparent)]
    Read(#[from] crate::files::FileReadError),
    /// A construct that breaks the convention (no or a second `MODULE plant`, a `main` or
    /// controller module, a specification, a `process`, a bad parameter list).
    #[error("{file}:{line}: {message}")]
    At {
        /// Path of the plant file.
        file: PathBuf,
        /// 1-based line of the offending construct (1 when `MODULE plant` is missing).
        line: usize,
        /// What is wrong and what the convention asks for.
        message: String,
    },
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Ident(String),
    Sym(&'static str),
    Other,
}

/// Tokens with their lines; `--` comments dropped.
fn tokens(text: &str) -> Vec<(Tok, usize)> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.find("--").map_or(raw, |k| &raw[..k]);
        let cs: Vec<char> = line.chars().collect();
        let mut k = 0;
        while k < cs.len() {
            let c = cs[k];
            if c.is_whitespace() {
                k += 1;
            } else if c.is_ascii_alphabetic() || c == '_' {
                let start = k;
                while k < cs.len() && (cs[k].is_ascii_alphanumeric() || "_$#".contains(cs[k])) {
                    k += 1;
                }
                out.push((Tok::Ident(cs[start..k].iter().collect()), i + 1));
            } else {
                let two: String = cs[k..(k + 2).min(cs.len())].iter().collect();
                let sym = match (two.as_str(), c) {
                    (":=", _) => Some(":="),
                    (_, ':') => Some(":"),
                    (_, ';') => Some(";"),
                    (_, '(') => Some("("),
                    (_, ')') => Some(")"),
                    (_, '{') => Some("{"),
                    (_, '}') => Some("}"),
                    (_, '[') => Some("["),
                    (_, ']') => Some("]"),
                    (_, ',') => Some(","),
                    _ => None,
                };
                match sym {
                    Some(s) => {
                        k += s.len();
                        out.push((Tok::Sym(s), i + 1));
                    }
                    None => {
                        k += 1;
                        out.push((Tok::Other, i + 1));
                    }
                }
            }
        }
    }
    out
}

const SECTIONS: &[&str] = &[
    "VAR",
    "IVAR",
    "FROZENVAR",
    "DEFINE",
    "ASSIGN",
    "TRANS",
    "INIT",
    "INVAR",
    "FAIRNESS",
    "JUSTICE",
    "COMPASSION",
    "CONSTANTS",
    "ISA",
];

/// Sections that state properties rather than model the plant.
const SPECS: &[&str] = &[
    "SPEC",
    "CTLSPEC",
    "LTLSPEC",
    "INVARSPEC",
    "PSLSPEC",
    "COMPUTE",
];

impl Plant {
    /// The lines of `MODULE plant` that define, assign or constrain `name` (its `DEFINE`,
    /// `ASSIGN`, `INIT`, `INVAR` and `TRANS` lines that mention it), for a message that points
    /// at what decides its values. Declarations and fairness constraints are left out: they do
    /// not decide which values a state shows.
    pub(crate) fn lines_constraining(&self, name: &str) -> Vec<usize> {
        let (mut in_plant, mut section) = (false, "");
        let mut lines: Vec<usize> = Vec::new();
        for (tok, line) in tokens(&self.text) {
            let Tok::Ident(w) = tok else { continue };
            if w == "MODULE" {
                (in_plant, section) = (line == self.module_line, "");
            } else if let Some(s) = SECTIONS.iter().find(|s| **s == w) {
                section = s;
            } else if in_plant
                && w == name
                && ["DEFINE", "ASSIGN", "INIT", "INVAR", "TRANS"].contains(&section)
                && lines.last() != Some(&line)
            {
                lines.push(line);
            }
        }
        lines
    }
}

/// Scans a plant file.
pub(crate) fn parse_plant(file: &Path, text: &str) -> Result<Plant, PlantError> {
    let mut scan = Scanner {
        file,
        text,
        toks: tokens(text),
        k: 0,
        plant: None,
        in_plant: false,
        section: "",
        depth: 0,
        stmt_start: false,
    };
    while scan.k < scan.toks.len() {
        scan.token()?;
    }
    match scan.plant.take() {
        Some(plant) => Ok(plant),
        None => Err(scan.at(
            1,
            "no MODULE plant(...) in this file: the plant must be a module named plant whose parameters are controller outputs".into(),
        )),
    }
}

/// The scanner's place in the token list and what it has found.
struct Scanner<'a> {
    file: &'a Path,
    text: &'a str,
    toks: Vec<(Tok, usize)>,
    /// The next token.
    k: usize,
    plant: Option<Plant>,
    /// Inside `MODULE plant`.
    in_plant: bool,
    /// The section keyword in force (`VAR`, `DEFINE`, ...; empty after a `MODULE`).
    section: &'static str,
    /// Open brackets and `case`s.
    depth: i32,
    /// Whether the next token starts a statement (at depth 0, after a section keyword or `;`).
    stmt_start: bool,
}

impl Scanner<'_> {
    /// An error at `line` of the file.
    fn at(&self, line: usize, message: String) -> PlantError {
        PlantError::At {
            file: self.file.to_path_buf(),
            line,
            message,
        }
    }

    /// Reads the next token (a whole module header for `MODULE`).
    fn token(&mut self) -> Result<(), PlantError> {
        let (tok, line) = (&self.toks[self.k].0, self.toks[self.k].1);
        match tok {
            Tok::Ident(w) if w == "MODULE" && self.depth == 0 => return self.module(line),
            // A specification in the plant would be checked with the user's properties, and
            // its verdicts would be taken for theirs.
            Tok::Ident(w) if self.depth == 0 && SPECS.contains(&w.as_str()) => {
                return Err(self.at(
                    line,
                    format!("the plant file must not hold a specification ({w}): properties go in the LTL file given with --ltl"),
                ));
            }
            // NuSMV runs processes interleaved, so the closed loop would not be the
            // synchronous scan cycle the controller is synthesized for.
            Tok::Ident(w) if w == "process" => {
                return Err(self.at(
                    line,
                    "the plant must not instantiate a process: the closed loop is synchronous (one scan per step), NuSMV would interleave processes".into(),
                ));
            }
            Tok::Ident(w) if self.depth == 0 && SECTIONS.contains(&w.as_str()) => {
                self.section = SECTIONS[SECTIONS.iter().position(|s| s == w).expect("member")];
                self.stmt_start = true;
            }
            Tok::Ident(w) if w == "case" => {
                self.depth += 1;
                self.stmt_start = false;
            }
            Tok::Ident(w) if w == "esac" => {
                self.depth -= 1;
                self.stmt_start = false;
            }
            Tok::Ident(_) => {
                self.name(line);
                self.stmt_start = false;
            }
            Tok::Sym("(") | Tok::Sym("{") | Tok::Sym("[") => {
                self.depth += 1;
                self.stmt_start = false;
            }
            Tok::Sym(")") | Tok::Sym("}") | Tok::Sym("]") => {
                self.depth -= 1;
                self.stmt_start = false;
            }
            Tok::Sym(";") => self.stmt_start = self.depth == 0,
            _ => self.stmt_start = false,
        }
        self.k += 1;
        Ok(())
    }

    /// The identifier at `k`, on `line`: a declaration of `MODULE plant` when it starts a
    /// statement of a declaring section and the declaring symbol (`:` or `:=`) follows.
    fn name(&mut self, line: usize) {
        let declares = match self.section {
            "VAR" | "IVAR" | "FROZENVAR" => Some(":"),
            "DEFINE" => Some(":="),
            _ => None,
        };
        if !(self.in_plant && self.stmt_start && self.depth == 0) {
            return;
        }
        let (Tok::Ident(w), Some(want), Some((Tok::Sym(next), _))) =
            (&self.toks[self.k].0, declares, self.toks.get(self.k + 1))
        else {
            return;
        };
        if *next == want {
            let instance = want == ":" && self.is_instance(self.k + 2);
            let p = self.plant.as_mut().expect("in_plant implies plant");
            if instance {
                p.instances.push(w.clone());
            }
            p.names.push(Declared {
                name: w.clone(),
                line,
            });
        }
    }

    /// Whether the type starting at token `k` of a `VAR` declaration names a module: an
    /// identifier that is no type keyword, followed by its arguments or the end of the
    /// declaration (a range such as `lo..hi` over defined constants is followed by `.`).
    fn is_instance(&self, k: usize) -> bool {
        const TYPES: &[&str] = &[
            "boolean", "integer", "real", "word", "unsigned", "signed", "array", "process",
        ];
        match (self.toks.get(k), self.toks.get(k + 1)) {
            (Some((Tok::Ident(w), _)), Some((Tok::Sym("(" | ";"), _))) => {
                !TYPES.contains(&w.as_str())
            }
            _ => false,
        }
    }

    /// `MODULE name` on `line`, and for `MODULE plant` its parameter list; the module
    /// `main` and the controller's are synth's to generate.
    fn module(&mut self, line: usize) -> Result<(), PlantError> {
        let Some((Tok::Ident(name), _)) = self.toks.get(self.k + 1) else {
            return Err(self.at(line, "MODULE without a name".into()));
        };
        if name == "main" || name == CONTROLLER_MODULE {
            return Err(self.at(
                line,
                format!("the plant file must not define MODULE {name}: synth generates it to connect the plant to the controller"),
            ));
        }
        self.in_plant = name == "plant";
        self.section = "";
        self.stmt_start = false;
        self.k += 2;
        if !self.in_plant {
            return Ok(());
        }
        if self.plant.is_some() {
            return Err(self.at(line, "MODULE plant is defined twice".into()));
        }
        let params = self.params()?;
        self.plant = Some(Plant {
            file: self.file.to_path_buf(),
            text: self.text.to_string(),
            module_line: line,
            params,
            names: Vec::new(),
            instances: Vec::new(),
        });
        Ok(())
    }

    /// The parameter list of `MODULE plant`, if one follows.
    fn params(&mut self) -> Result<Vec<Declared>, PlantError> {
        let mut params = Vec::new();
        if self.toks.get(self.k).map(|t| &t.0) != Some(&Tok::Sym("(")) {
            return Ok(params);
        }
        self.k += 1;
        while let Some((t, l)) = self.toks.get(self.k) {
            self.k += 1;
            match t {
                Tok::Sym(")") => break,
                Tok::Sym(",") => {}
                Tok::Ident(p) => params.push(Declared {
                    name: p.clone(),
                    line: *l,
                }),
                _ => {
                    return Err(self.at(
                        *l,
                        "unexpected token in the parameter list of MODULE plant".into(),
                    ))
                }
            }
        }
        Ok(params)
    }
}

/// A fairness constraint of `MODULE plant` that reads a controller output.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct UnfairToController {
    /// `FAIRNESS`, `JUSTICE` or `COMPASSION`.
    pub(crate) keyword: &'static str,
    /// 1-based line of the constraint.
    pub(crate) line: usize,
    /// The parameter (controller output) it reads, directly or through defines.
    pub(crate) output: String,
}

/// One statement of a section of `MODULE plant`: its section, first line and the identifiers
/// it holds, in order.
struct Statement {
    section: &'static str,
    line: usize,
    idents: Vec<String>,
}

/// The statements of `MODULE plant` (a `;` at depth 0, a section keyword or a `MODULE` ends
/// one).
fn plant_statements(text: &str) -> Vec<Statement> {
    let toks = tokens(text);
    let (mut out, mut cur, mut section) = (Vec::new(), None::<Statement>, "");
    let (mut in_plant, mut depth) = (false, 0i32);
    for (k, (tok, line)) in toks.iter().enumerate() {
        match tok {
            Tok::Ident(w) if w == "MODULE" && depth == 0 => {
                out.extend(cur.take());
                in_plant = matches!(toks.get(k + 1), Some((Tok::Ident(n), _)) if n == "plant");
                section = "";
                continue;
            }
            Tok::Ident(w) if depth == 0 && SECTIONS.contains(&w.as_str()) => {
                out.extend(cur.take());
                section = SECTIONS[SECTIONS.iter().position(|s| s == w).expect("member")];
                continue;
            }
            Tok::Sym(";") if depth == 0 => {
                out.extend(cur.take());
                continue;
            }
            Tok::Ident(w) if w == "case" => depth += 1,
            Tok::Ident(w) if w == "esac" => depth -= 1,
            Tok::Sym("(") | Tok::Sym("{") | Tok::Sym("[") => depth += 1,
            Tok::Sym(")") | Tok::Sym("}") | Tok::Sym("]") => depth -= 1,
            _ => {}
        }
        if !in_plant || section.is_empty() {
            continue;
        }
        let stmt = cur.get_or_insert_with(|| Statement {
            section,
            line: *line,
            idents: Vec::new(),
        });
        if let Tok::Ident(w) = tok {
            stmt.idents.push(w.clone());
        }
    }
    out.extend(cur);
    out
}

impl Plant {
    /// The fairness constraints (`FAIRNESS`, `JUSTICE`, `COMPASSION`) of `MODULE plant` that
    /// read a parameter, a controller output, directly or through its defines. NuSMV's LTL
    /// checking ignores unfair runs, so such a constraint can discard the runs where the
    /// controller gives some output, and with them the runs that violate a property.
    pub(crate) fn fairness_reading_outputs(&self) -> Vec<UnfairToController> {
        let statements = plant_statements(&self.text);
        let defines: Vec<(&str, &[String])> = (statements.iter())
            .filter(|s| s.section == "DEFINE")
            .filter_map(|s| Some((s.idents.first()?.as_str(), s.idents.get(1..)?)))
            .collect();
        let params: Vec<&str> = self.params.iter().map(|p| p.name.as_str()).collect();
        // The output a name reads, through defines (`seen` cuts a cycle NuSMV refuses anyway).
        fn reads<'a>(
            name: &str,
            params: &[&'a str],
            defines: &[(&str, &'a [String])],
            seen: &mut Vec<String>,
        ) -> Option<String> {
            if params.contains(&name) {
                return Some(name.to_string());
            }
            if seen.iter().any(|s| s == name) {
                return None;
            }
            seen.push(name.to_string());
            let (_, body) = defines.iter().find(|(d, _)| *d == name)?;
            body.iter().find_map(|n| reads(n, params, defines, seen))
        }
        (statements.iter())
            .filter(|s| ["FAIRNESS", "JUSTICE", "COMPASSION"].contains(&s.section))
            .filter_map(|s| {
                let output =
                    (s.idents.iter()).find_map(|n| reads(n, &params, &defines, &mut Vec::new()))?;
                Some(UnfairToController {
                    keyword: s.section,
                    line: s.line,
                    output,
                })
            })
            .collect()
    }
}

/// Reads and scans a plant file.
pub fn read_plant(file: &Path) -> Result<Plant, PlantError> {
    let text = crate::files::read_text(file, Some(crate::files::MAX_LINE_BYTES))?;
    parse_plant(file, &text)
}

#[cfg(test)]
mod tests {
    use super::*;

    const PLANT: &str = "\
-- a door
MODULE motor(on)
VAR pos : 0..3;
MODULE plant(open, close)
VAR
  pos : 0..2;   -- position
  m : motor(open);
IVAR
  push : boolean;
DEFINE
  isOpen := pos = 2;
  mode := case open : 1; TRUE : 0; esac;
  isClosed := pos = 0;
ASSIGN
  init(pos) := 0;
  next(pos) := case open & pos < 2 : pos + 1; TRUE : pos; esac;
";

    #[test]
    fn finds_parameters_and_declarations_of_module_plant_only() {
        let p = parse_plant(Path::new("p.smv"), PLANT).unwrap();
        let names: Vec<&str> = p.names.iter().map(|d| d.name.as_str()).collect();
        assert_eq!(
            names,
            vec!["pos", "m", "push", "isOpen", "mode", "isClosed"]
        );
        let params: Vec<&str> = p.params.iter().map(|d| d.name.as_str()).collect();
        assert_eq!(params, vec!["open", "close"]);
        assert_eq!(p.module_line, 4);
        assert_eq!(p.names[3].line, 11);
        assert_eq!(p.instances, vec!["m"]);
    }

    #[test]
    fn the_lines_deciding_a_name_are_its_definitions_and_constraints_in_module_plant() {
        let text = format!("{PLANT}INVAR pos != 1 -> push\nFAIRNESS pos = 2\n");
        let p = parse_plant(Path::new("p.smv"), &text).unwrap();
        // Not the declarations (lines 3, 6), nor the fairness constraint (line 18).
        assert_eq!(p.lines_constraining("pos"), vec![11, 13, 15, 16, 17]);
        assert_eq!(p.lines_constraining("push"), vec![17]);
        assert_eq!(p.lines_constraining("isOpen"), vec![11]);
    }

    #[test]
    fn module_instances_are_told_from_typed_variables() {
        let text = "MODULE h(x)\nVAR s : boolean;\nMODULE g\nVAR t : boolean;\n\
            MODULE plant(a)\nVAR\n  b : boolean;\n  r : lo..hi;\n  w : word[2];\n  \
            h1 : h(a);\n  g1 : g;\nDEFINE lo := 0; hi := 2; s := h1.s;\n";
        let p = parse_plant(Path::new("p.smv"), text).unwrap();
        assert_eq!(p.instances, vec!["h1", "g1"]);
        let names: Vec<&str> = p.names.iter().map(|d| d.name.as_str()).collect();
        assert_eq!(names, vec!["b", "r", "w", "h1", "g1", "lo", "hi", "s"]);
    }

    /// A fairness constraint that reads a parameter, directly or through a chain of defines,
    /// is found with its line; one over the plant's own variables is not.
    #[test]
    fn fairness_that_reads_an_output_is_found_with_its_line() {
        let text =
            "MODULE plant(lamp, fan)\nVAR b : boolean;\nDEFINE\n  lit := on;\n  on := lamp & b;\n\
                    FAIRNESS b\nJUSTICE !lit\nFAIRNESS case fan : b; TRUE : !b; esac;\n";
        let plant = parse_plant(Path::new("p.smv"), text).unwrap();
        let found = plant.fairness_reading_outputs();
        let at: Vec<(&str, usize, &str)> = (found.iter())
            .map(|u| (u.keyword, u.line, u.output.as_str()))
            .collect();
        assert_eq!(at, vec![("JUSTICE", 7, "lamp"), ("FAIRNESS", 8, "fan")]);
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse_plant(Path::new("p.smv"), "MODULE main\nVAR x : boolean;\n").unwrap_err();
        assert!(e
            .to_string()
            .starts_with("p.smv:1: the plant file must not define MODULE main"));
        let e = parse_plant(Path::new("p.smv"), "MODULE ECC(a)\nVAR x : boolean;\n").unwrap_err();
        assert!(e
            .to_string()
            .starts_with("p.smv:1: the plant file must not define MODULE ECC"));
        let e = parse_plant(Path::new("p.smv"), "MODULE other\n").unwrap_err();
        assert!(e.to_string().starts_with("p.smv:1: no MODULE plant(...)"));
    }

    #[test]
    fn specifications_and_processes_are_refused_at_their_line() {
        for (spec, line) in [("LTLSPEC G x", 3), ("CTLSPEC AG x", 3), ("INVARSPEC x", 3)] {
            let text = format!("MODULE plant(a)\nVAR x : boolean;\n{spec}\n");
            let e = parse_plant(Path::new("p.smv"), &text).unwrap_err();
            assert!(
                e.to_string().starts_with(&format!(
                    "p.smv:{line}: the plant file must not hold a specification"
                )),
                "{e}"
            );
        }
        let text = "MODULE m\nVAR y : boolean;\nMODULE plant(a)\nVAR\n  p : process m;\n";
        let e = parse_plant(Path::new("p.smv"), text).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("p.smv:5: the plant must not instantiate a process"),
            "{e}"
        );
    }
}
