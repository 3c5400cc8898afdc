//! The library's layers: which top-level module of `src/` uses which, read from the source.
//! Production code only (test files and `#[cfg(test)] mod tests` blocks are left out, as are
//! comments): the graph has no cycle, the model (`ecc`) uses nothing above it, and the SAT
//! encodings and the NuSMV driver never use each other (the loop joining them is `pipeline`'s).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Graph = BTreeMap<String, BTreeSet<String>>;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if path.is_dir() {
            if name != "tests" {
                rust_files(&path, out);
            }
        } else if name.ends_with(".rs") && name != "tests.rs" {
            out.push(path);
        }
    }
}

/// The production part of a file: without comments and without its test module.
fn production(text: &str) -> String {
    let mut out = String::new();
    let mut lines = text.lines().peekable();
    while let Some(line) = lines.next() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("#[cfg(test)]")
            && lines
                .peek()
                .is_some_and(|next| next.trim_start().starts_with("mod tests"))
        {
            break;
        }
        if !trimmed.starts_with("//") {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// Top-level modules named after `crate::` in `text`, including those inside
/// `use crate::{a::.., b};`.
fn uses(text: &str) -> BTreeSet<String> {
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut found = BTreeSet::new();
    for (at, _) in text.match_indices("crate::") {
        let rest = &text[at + "crate::".len()..];
        match rest.strip_prefix('{') {
            Some(group) => {
                // Only the group's top-level items: nested braces' contents are skipped.
                let mut depth = 0;
                let mut item_start = true;
                for (i, c) in group.char_indices() {
                    match c {
                        '{' => depth += 1,
                        '}' if depth == 0 => break,
                        '}' => depth -= 1,
                        ',' if depth == 0 => item_start = true,
                        c if item_start && depth == 0 && !c.is_whitespace() => {
                            found.insert(ident(&group[i..]));
                            item_start = false;
                        }
                        _ => {}
                    }
                }
            }
            None => {
                found.insert(ident(rest));
            }
        }
    }
    found.retain(|m| !m.is_empty());
    found
}

fn graph() -> Graph {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut graph = Graph::new();
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        if matches!(stem.as_str(), "lib" | "main" | "bin") {
            continue;
        }
        let mut files = Vec::new();
        match path.is_dir() {
            true => rust_files(&path, &mut files),
            false if stem != "tests" => files.push(path.clone()),
            false => {}
        }
        let used = graph.entry(stem.clone()).or_default();
        for file in files {
            let text = std::fs::read_to_string(&file).unwrap();
            used.extend(uses(&production(&text)));
        }
        used.remove(&stem);
    }
    let modules: BTreeSet<String> = graph.keys().cloned().collect();
    for used in graph.values_mut() {
        used.retain(|m| modules.contains(m));
    }
    graph
}

/// A cycle of the graph, if it has one (depth-first search).
fn cycle(graph: &Graph) -> Option<Vec<String>> {
    fn visit(
        graph: &Graph,
        node: &str,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|n| n == node) {
            let mut cycle = path[at..].to_vec();
            cycle.push(node.to_string());
            return Some(cycle);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in &graph[node] {
            if let Some(c) = visit(graph, next, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    (graph.keys()).find_map(|m| visit(graph, m, &mut Vec::new(), &mut done))
}

#[test]
fn the_reader_sees_the_uses_it_should() {
    let text = "use crate::ecc::{Ecc, Size};\nuse crate::{plant::{a, b}, sat};\n// crate::game\n";
    let found = uses(&production(text));
    assert_eq!(
        found,
        BTreeSet::from(["ecc", "plant", "sat"].map(String::from))
    );
    let graph = Graph::from([
        ("a".to_string(), BTreeSet::from(["b".to_string()])),
        ("b".to_string(), BTreeSet::from(["a".to_string()])),
    ]);
    assert_eq!(
        cycle(&graph),
        Some(vec!["a".into(), "b".into(), "a".into()])
    );
}

#[test]
fn the_top_level_modules_form_no_cycle() {
    let graph = graph();
    assert!(graph.len() > 10, "{graph:?}");
    assert_eq!(cycle(&graph), None, "{graph:#?}");
}

#[test]
fn the_model_uses_nothing_above_it_and_sat_and_nusmv_stay_apart() {
    let graph = graph();
    assert!(graph["ecc"].is_empty(), "ecc uses {:?}", graph["ecc"]);
    assert!(!graph["sat"].contains("nusmv"), "{:?}", graph["sat"]);
    assert!(!graph["nusmv"].contains("sat"), "{:?}", graph["nusmv"]);
}
