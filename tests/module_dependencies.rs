//! The module graphs of the harness and of the solver, read from the sources: the paths that
//! start with `crate::`, `super::` (resolved from the file's module) and `self::`, outside
//! comments, strings and `#[cfg(test)]` items, a file declared `#[cfg(test)] mod x;` left out as a
//! whole. A path that names an item the crate root re-exports (`crate::SolverError`) counts as an
//! import of the module the item comes from.
//!
//! Checked:
//! - the top-level modules (a file or a folder each) of both crates import one another without a
//!   cycle;
//! - inside every folder, the modules side by side (its files and sub-folders) import one
//!   another without a cycle;
//! - the solver's top-level modules keep the layer order of `docs/architecture.md`: a module
//!   imports only from layers below its own;
//! - only the harness's registry imports the kinds of case and their report sections.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

mod source_text;
use source_text::{is_ident, strip};

/// The solver's layers, lowest first: a top-level module of `solver/src` imports only from the
/// layers before its own (`docs/architecture.md`, "The modules as layers").
const SOLVER_LAYERS: &[&[&str]] = &[
    // The error vocabulary of every layer (`SolverError` and the reports its variants carry),
    // random numbers, the geometry of one tetrahedron, the geometric queries (boxes, closest
    // points) that contact and the mesh operations share.
    // Values at nodes stored for a rank's nodes only.
    &["error", "rng", "kinematics", "geometry", "nodal"],
    &["mesh"],
    &["material"],
    &["model"],
    &["contact", "distributed"],
    // The complete input of an analysis (a model and what acts on it, contact pairs included);
    // the writers and the observer trait, the snapshot and frame types.
    &["problem", "output"],
    &["dynamics", "statics"],
    &["remesh"],
    &["scene"],
    &["analysis"],
    &["restart"],
];

/// A module path from the crate root: `["report", "beam", "plots"]`.
type ModPath = Vec<String>;

/// One path that reaches into the crate, with where it is written.
#[derive(Debug, Clone)]
struct Import {
    /// The file, relative to the crate's source folder.
    file: String,
    /// The module the path is written in.
    from: ModPath,
    /// The path, absolute from the crate root (items and modules alike).
    to: ModPath,
    /// The path as written (for messages).
    text: String,
}

/// A crate's sources read as imports.
struct Crate {
    /// Every module that has a file (and the folders above them).
    modules: BTreeSet<ModPath>,
    /// Every path into the crate, outside test code.
    imports: Vec<Import>,
}

/// Reads an identifier at `i` (after spaces); returns it and the index after it.
fn ident_at(b: &[u8], mut i: usize) -> Option<(String, usize)> {
    while i < b.len() && b[i].is_ascii_whitespace() {
        i += 1;
    }
    let start = i;
    while i < b.len() && is_ident(b[i]) {
        i += 1;
    }
    (i > start && !b[start].is_ascii_digit())
        .then(|| (String::from_utf8_lossy(&b[start..i]).into_owned(), i))
}

/// Skips spaces and `::`; true when `::` was there.
fn colons_at(b: &[u8], i: &mut usize) -> bool {
    let mut j = *i;
    while j < b.len() && b[j].is_ascii_whitespace() {
        j += 1;
    }
    if b.get(j) == Some(&b':') && b.get(j + 1) == Some(&b':') {
        *i = j + 2;
        true
    } else {
        false
    }
}

/// The paths of a path tree starting at `i` (`a::b::{c, d::e}`), each as its segments; `i` ends
/// after the tree.
fn path_tree(b: &[u8], i: &mut usize) -> Vec<ModPath> {
    let mut prefix = Vec::new();
    loop {
        let mut j = *i;
        while j < b.len() && b[j].is_ascii_whitespace() {
            j += 1;
        }
        if b.get(j) == Some(&b'{') {
            *i = j + 1;
            let mut all = Vec::new();
            loop {
                for mut p in path_tree(b, i) {
                    let mut full = prefix.clone();
                    full.append(&mut p);
                    all.push(full);
                }
                while *i < b.len() && b[*i].is_ascii_whitespace() {
                    *i += 1;
                }
                match b.get(*i) {
                    Some(b',') => *i += 1,
                    Some(b'}') => {
                        *i += 1;
                        break;
                    }
                    _ => break,
                }
                // A trailing comma before `}`.
                let mut k = *i;
                while k < b.len() && b[k].is_ascii_whitespace() {
                    k += 1;
                }
                if b.get(k) == Some(&b'}') {
                    *i = k + 1;
                    break;
                }
            }
            return all;
        }
        if b.get(j) == Some(&b'*') {
            *i = j + 1;
            return vec![prefix];
        }
        match ident_at(b, *i) {
            Some((name, next)) => {
                prefix.push(name);
                *i = next;
            }
            None => return vec![prefix],
        }
        if !colons_at(b, i) {
            // `as alias`, `;`, `,`, `(`: the path ends.
            return vec![prefix];
        }
    }
}

/// The paths (absolute from the crate root) that the code of a file at module `module` names,
/// with the module each is written in (inline modules such as `mod x { ... }` included), and the
/// names of the child modules it declares as test code (`#[cfg(test)] mod x;`).
fn scan(text: &str, module: &ModPath) -> (Vec<(ModPath, ModPath, String)>, BTreeSet<String>) {
    let code = strip(text);
    let b = code.as_bytes();
    let mut found = Vec::new();
    let mut test_children = BTreeSet::new();
    if code.contains("#![cfg(test)]") {
        return (found, test_children);
    }
    // Inline modules open at a brace depth: (name, depth).
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let boundary = i == 0 || !is_ident(b[i - 1]) && b[i - 1] != b':';
        if code[i..].starts_with("#[cfg(test)]") {
            // Skip the item: to its `;` or over its braced body.
            let mut j = i + "#[cfg(test)]".len();
            if let Some((kw, after)) = ident_at(b, j) {
                let name_at = if kw == "mod" {
                    ident_at(b, after)
                } else if kw == "pub" {
                    ident_at(b, after)
                        .and_then(|(m, a)| (m == "mod").then_some(a))
                        .and_then(|a| ident_at(b, a))
                } else {
                    None
                };
                if let Some((name, a)) = name_at {
                    let mut k = a;
                    while k < b.len() && b[k].is_ascii_whitespace() {
                        k += 1;
                    }
                    if b.get(k) == Some(&b';') {
                        test_children.insert(name);
                    }
                }
            }
            while j < b.len() && b[j] != b';' && b[j] != b'{' {
                j += 1;
            }
            if b.get(j) == Some(&b'{') {
                let mut d = 0;
                while j < b.len() {
                    match b[j] {
                        b'{' => d += 1,
                        b'}' => {
                            d -= 1;
                            if d == 0 {
                                break;
                            }
                        }
                        _ => {}
                    }
                    j += 1;
                }
            }
            i = j + 1;
            continue;
        }
        match c {
            b'{' => depth += 1,
            b'}' => {
                depth = depth.saturating_sub(1);
                if inline.last().is_some_and(|(_, d)| *d == depth) {
                    inline.pop();
                }
            }
            _ => {}
        }
        if boundary && code[i..].starts_with("mod ") {
            if let Some((name, after)) = ident_at(b, i + 3) {
                let mut k = after;
                while k < b.len() && b[k].is_ascii_whitespace() {
                    k += 1;
                }
                if b.get(k) == Some(&b'{') {
                    inline.push((name, depth));
                    depth += 1;
                    i = k + 1;
                    continue;
                }
            }
        }
        let here: ModPath = module
            .iter()
            .cloned()
            .chain(inline.iter().map(|(n, _)| n.clone()))
            .collect();
        for head in ["crate", "super", "self"] {
            if boundary
                && code[i..].starts_with(head)
                && b.get(i + head.len()).is_some_and(|&x| !is_ident(x))
            {
                let mut j = i + head.len();
                if !colons_at(b, &mut j) {
                    continue;
                }
                let mut base: ModPath = match head {
                    "crate" => Vec::new(),
                    _ => here.clone(),
                };
                let mut ok = true;
                if head == "super" {
                    ok = base.pop().is_some();
                    // Further `super::` segments.
                    loop {
                        let mut k = j;
                        match ident_at(b, k) {
                            Some((s, a)) if s == "super" => {
                                k = a;
                                if !colons_at(b, &mut k) {
                                    break;
                                }
                                ok &= base.pop().is_some();
                                j = k;
                            }
                            _ => break,
                        }
                    }
                }
                let start = i;
                let paths = path_tree(b, &mut j);
                if ok {
                    let text: String = code[start..j]
                        .split_whitespace()
                        .collect::<Vec<_>>()
                        .join(" ");
                    for p in paths {
                        let mut to = base.clone();
                        to.extend(p);
                        found.push((here.clone(), to, text.clone()));
                    }
                }
                i = j;
                break;
            }
        }
        i += 1;
    }
    (found, test_children)
}

/// The module path of a source file: `a/b.rs` and `a/b/mod.rs` are `a::b`; the crate root is
/// empty.
fn module_of(rel: &Path) -> ModPath {
    let mut m: ModPath = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if let Some(last) = m.last_mut() {
        *last = last.trim_end_matches(".rs").to_string();
    }
    if matches!(m.last().map(String::as_str), Some("mod")) {
        m.pop();
    }
    if m.len() == 1 && matches!(m[0].as_str(), "lib" | "main") {
        m.clear();
    }
    m
}

/// Reads the crate whose root file is `root/lib.rs`; the binary's root `main.rs` is another
/// crate and is left out.
fn read_crate(root: &Path) -> Crate {
    fn files(dir: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap()
            .flatten()
            .map(|e| e.path())
            .collect();
        entries.sort();
        for path in entries {
            if path.is_dir() {
                files(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    let mut all = Vec::new();
    files(root, &mut all);
    let mut scanned = Vec::new();
    let mut test_modules: BTreeSet<ModPath> = BTreeSet::new();
    for path in &all {
        let rel = path.strip_prefix(root).unwrap();
        if rel == Path::new("main.rs") {
            continue;
        }
        let module = module_of(rel);
        let text = std::fs::read_to_string(path).unwrap();
        let (found, test_children) = scan(&text, &module);
        for child in test_children {
            let mut m = module.clone();
            m.push(child);
            test_modules.insert(m);
        }
        scanned.push((rel.to_string_lossy().into_owned(), module, found));
    }
    // Items the crate root re-exports: `pub use error::SolverError;` makes `crate::SolverError`
    // an import of `error`.
    let mut reexports: BTreeMap<String, ModPath> = BTreeMap::new();
    let lib = strip(&std::fs::read_to_string(root.join("lib.rs")).unwrap());
    for statement in lib.split(';') {
        let s = statement.trim();
        if let Some(rest) = s.strip_prefix("pub use ") {
            let b = rest.as_bytes();
            let mut i = 0;
            for p in path_tree(b, &mut i) {
                if let Some(last) = p.last() {
                    reexports.insert(last.clone(), p.clone());
                }
            }
        }
    }
    let mut modules = BTreeSet::new();
    let mut imports = Vec::new();
    for (file, module, found) in scanned {
        if test_modules.iter().any(|t| module.starts_with(t)) {
            continue;
        }
        for k in 1..=module.len() {
            modules.insert(module[..k].to_vec());
        }
        for (from, mut to, text) in found {
            if let Some(first) = to.first() {
                if let Some(path) = reexports.get(first) {
                    to = path.iter().cloned().chain(to.into_iter().skip(1)).collect();
                }
            }
            imports.push(Import {
                file: file.clone(),
                from,
                to,
                text,
            });
        }
    }
    Crate { modules, imports }
}

/// A graph of modules: module -> the modules it imports, each with one import that makes the
/// edge (for messages).
type Graph = BTreeMap<String, BTreeMap<String, Import>>;

impl Crate {
    /// The graph of the top-level modules.
    fn top_level(&self) -> Graph {
        self.siblings_in(&[])
    }

    /// The graph of the modules directly inside `parent` (its files and folders): an import
    /// from `parent::a::...` of `parent::b::...` is an edge `a -> b`.
    fn siblings_in(&self, parent: &[String]) -> Graph {
        let k = parent.len();
        let mut g = Graph::new();
        for m in &self.modules {
            if m.len() == k + 1 && m.starts_with(parent) {
                g.entry(m[k].clone()).or_default();
            }
        }
        for import in &self.imports {
            if import.from.len() <= k
                || import.to.len() <= k
                || !import.from.starts_with(parent)
                || !import.to.starts_with(parent)
            {
                continue;
            }
            let (a, b) = (&import.from[k], &import.to[k]);
            if a != b && g.contains_key(a) && g.contains_key(b) {
                g.get_mut(a)
                    .unwrap()
                    .entry(b.clone())
                    .or_insert_with(|| import.clone());
            }
        }
        g
    }

    /// Every folder's module path (the crate root included).
    fn folders(&self) -> Vec<ModPath> {
        let mut f: BTreeSet<ModPath> = self
            .modules
            .iter()
            .map(|m| m[..m.len() - 1].to_vec())
            .collect();
        f.insert(Vec::new());
        f.into_iter().collect()
    }
}

/// A cycle through `start`, if any (depth-first search).
fn cycle_through(g: &Graph, start: &str) -> Option<Vec<String>> {
    fn visit(
        g: &Graph,
        at: &str,
        start: &str,
        path: &mut Vec<String>,
        seen: &mut BTreeSet<String>,
    ) -> bool {
        for next in g[at].keys() {
            if next == start {
                return true;
            }
            if seen.insert(next.clone()) {
                path.push(next.clone());
                if visit(g, next, start, path, seen) {
                    return true;
                }
                path.pop();
            }
        }
        false
    }
    let mut path = vec![start.to_string()];
    visit(g, start, start, &mut path, &mut BTreeSet::new()).then_some(path)
}

/// The cycles of `g` (one per module on one), each written with the import behind every edge.
fn cycles(g: &Graph, inside: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut reported: BTreeSet<BTreeSet<String>> = BTreeSet::new();
    for m in g.keys() {
        if let Some(cycle) = cycle_through(g, m) {
            if !reported.insert(cycle.iter().cloned().collect()) {
                continue;
            }
            let edges: Vec<String> = cycle
                .iter()
                .zip(cycle.iter().skip(1).chain(std::iter::once(&cycle[0])))
                .map(|(a, b)| {
                    let i = &g[a][b];
                    format!("{a} -> {b} ({}: `{}`)", i.file, i.text)
                })
                .collect();
            found.push(format!("in {inside}: {}", edges.join(", ")));
        }
    }
    found
}

fn root(dir: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(dir)
}

/// The cycles among side-by-side modules in every folder of a crate.
fn folder_cycles(c: &Crate, name: &str) -> Vec<String> {
    c.folders()
        .iter()
        .flat_map(|f| {
            let inside = if f.is_empty() {
                name.to_string()
            } else {
                format!("{name}::{}", f.join("::"))
            };
            cycles(&c.siblings_in(f), &inside)
        })
        .collect()
}

#[test]
fn harness_modules_import_each_other_without_a_cycle() {
    let c = read_crate(&root("harness"));
    let g = c.top_level();
    assert!(g.len() > 10, "the harness's modules were found: {g:?}");
    let found = folder_cycles(&c, "harness");
    assert!(found.is_empty(), "import cycles:\n{}", found.join("\n"));
}

#[test]
fn solver_modules_import_each_other_without_a_cycle() {
    let c = read_crate(&root("solver/src"));
    let g = c.top_level();
    assert!(g.len() > 10, "the solver's modules were found: {g:?}");
    let found = cycles(&g, "solver");
    assert!(found.is_empty(), "import cycles:\n{}", found.join("\n"));
    // Nor inside a folder: no circle of files or folders side by side.
    let found = folder_cycles(&c, "solver");
    assert!(found.is_empty(), "import cycles:\n{}", found.join("\n"));
}

#[test]
fn solver_modules_import_only_from_lower_layers() {
    let c = read_crate(&root("solver/src"));
    let g = c.top_level();
    let layer_of = |m: &str| SOLVER_LAYERS.iter().position(|l| l.contains(&m));
    let mut wrong = Vec::new();
    for (m, deps) in &g {
        let Some(own) = layer_of(m) else {
            wrong.push(format!(
                "`{m}` is in no layer: add it to SOLVER_LAYERS here and to docs/architecture.md"
            ));
            continue;
        };
        for (d, import) in deps {
            let theirs = layer_of(d).unwrap_or(usize::MAX);
            if theirs >= own {
                let theirs = if theirs == usize::MAX {
                    "in no layer".to_string()
                } else {
                    format!("layer {theirs}")
                };
                wrong.push(format!(
                    "solver/src/{} imports `{}`: `{m}` (layer {own}) may import only from the \
                     layers below its own, and `{d}` is {theirs}",
                    import.file, import.text
                ));
            }
        }
    }
    for layer in SOLVER_LAYERS {
        for m in *layer {
            if !g.contains_key(*m) {
                wrong.push(format!("SOLVER_LAYERS names `{m}`, which solver/src lacks"));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn only_the_registry_imports_the_kinds_of_case() {
    let g = read_crate(&root("harness")).top_level();
    // What the registry imports, besides the interfaces it fills in, are the kinds and the
    // modules of their sections.
    let kinds: BTreeSet<String> = g["registry"]
        .keys()
        .filter(|m| !matches!(m.as_str(), "case_kind" | "report"))
        .cloned()
        .collect();
    for kind in [
        "scene_case",
        "material_point",
        "contact_problems",
        "crosscheck",
        "determinism",
    ] {
        assert!(kinds.contains(kind), "{kind} is registered: {kinds:?}");
    }
    for module in [
        "catalogue",
        "case_file",
        "case_kind",
        "runner",
        "judge",
        "report",
        "results",
    ] {
        let named: Vec<&String> = g[module].keys().filter(|m| kinds.contains(*m)).collect();
        assert!(
            named.is_empty(),
            "`{module}` imports the kinds {named:?}: they belong behind `dyn CaseKind` or `dyn Section`"
        );
    }
}

#[test]
fn the_reader_finds_the_paths_outside_test_code() {
    let text = r#"
//! `crate::docs` in a comment is no import.
use crate::{error::Result, mesh::{Mesh, boundary}};
use super::sibling::Thing;
const S: &str = "crate::in_a_string";
#[cfg(test)]
mod tests;
#[cfg(test)]
fn helper() { crate::test_only::f(); }
fn f() -> char { let _ = '{'; super::super::top::g(); '}' }
mod inline {
    use super::super::other::X;
}
#[cfg(test)]
mod more {
    use crate::never;
}
"#;
    let module: ModPath = vec!["a".into(), "b".into()];
    let (found, test_children) = scan(text, &module);
    let to: BTreeSet<String> = found.iter().map(|(_, to, _)| to.join("::")).collect();
    let expected: BTreeSet<String> = [
        "error::Result",
        "mesh::Mesh",
        "mesh::boundary",
        "a::sibling::Thing",
        "top::g",
        "a::other::X",
    ]
    .into_iter()
    .map(String::from)
    .collect();
    assert_eq!(to, expected);
    assert_eq!(test_children, BTreeSet::from(["tests".to_string()]));
}
