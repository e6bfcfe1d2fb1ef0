//! The harness's module graph (issue 18): its top-level modules import one another without a
//! cycle, and only the registry imports the kinds of case and their report sections. The graph
//! is read from the sources (`crate::<module>` paths outside comments and test modules), the
//! same way `grep` would.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

type Graph = BTreeMap<String, BTreeSet<String>>;

/// The modules `text` names as `crate::<module>`, comments and `#[cfg(test)]` blocks (which sit
/// at the end of the files here) left out, and nothing for a file that is a test module as a
/// whole (`#![cfg(test)]`).
fn imports(text: &str) -> BTreeSet<String> {
    if text.contains("#![cfg(test)]") {
        return BTreeSet::new();
    }
    let code = text.split("#[cfg(test)]").next().unwrap_or("");
    let mut found = BTreeSet::new();
    for line in code.lines() {
        let line = line.split("//").next().unwrap_or("");
        let mut rest = line;
        while let Some(i) = rest.find("crate::") {
            rest = &rest[i + "crate::".len()..];
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_lowercase() || *c == '_')
                .collect();
            if !name.is_empty() {
                found.insert(name);
            }
        }
    }
    found
}

/// Top-level module -> the top-level modules its files import.
fn graph(root: &Path) -> Graph {
    fn walk(dir: &Path, root: &Path, graph: &mut Graph) {
        for entry in std::fs::read_dir(dir).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(&path, root, graph);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let rel = path.strip_prefix(root).unwrap();
                let top = rel
                    .components()
                    .next()
                    .unwrap()
                    .as_os_str()
                    .to_string_lossy()
                    .trim_end_matches(".rs")
                    .to_string();
                let text = std::fs::read_to_string(&path).unwrap();
                graph.entry(top).or_default().extend(imports(&text));
            }
        }
    }
    let mut g = Graph::new();
    walk(root, root, &mut g);
    g.remove("main");
    g.remove("lib");
    let modules: BTreeSet<String> = g.keys().cloned().collect();
    for (m, deps) in g.iter_mut() {
        deps.retain(|d| d != m && modules.contains(d));
    }
    g
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
        for next in &g[at] {
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

#[test]
fn harness_modules_import_each_other_without_a_cycle() {
    let g = graph(&Path::new(env!("CARGO_MANIFEST_DIR")).join("harness"));
    assert!(g.len() > 10, "the harness's modules were found: {g:?}");
    for m in g.keys() {
        if let Some(cycle) = cycle_through(&g, m) {
            panic!("import cycle: {} -> {m}", cycle.join(" -> "));
        }
    }
}

#[test]
fn only_the_registry_imports_the_kinds_of_case() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("harness");
    let g = graph(&root);
    // What the registry imports, besides the interfaces it fills in, are the kinds and the
    // modules of their sections.
    let kinds: BTreeSet<String> = g["registry"]
        .iter()
        .filter(|m| !matches!(m.as_str(), "case_kind" | "report"))
        .cloned()
        .collect();
    for kind in [
        "scene_case",
        "material_point",
        "contact_problems",
        "crosscheck",
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
        let named: Vec<&String> = g[module].intersection(&kinds).collect();
        assert!(
            named.is_empty(),
            "`{module}` imports the kinds {named:?}: they belong behind `dyn CaseKind` or `dyn Section`"
        );
    }
}
