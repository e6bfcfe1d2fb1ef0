//! The length of every library function of the solver, the harness and the references, read
//! from the sources: from its `fn` line to its closing brace, comments and literals blanked
//! before braces are matched. Test code is left out: folders `tests/`, `benches/`,
//! `examples/`, files named `tests.rs`, and items under `#[cfg(test)]`.
//!
//! Checked: no function is over [`LIMIT`] lines, except those of [`KNOWN`], which may only
//! shrink, and leave the list once they are short. `python3 scripts/long_functions.py` prints
//! the same list.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod source_text;

use std::path::{Path, PathBuf};

use source_text::{is_ident, strip};

/// The most lines a library function may have.
const LIMIT: usize = 150;

/// The functions over [`LIMIT`] lines when this test was written: file, name, and its length
/// then, a ceiling it may not pass. Each is a job for a split into named steps.
#[rustfmt::skip]
const KNOWN: &[(&str, &str, usize)] = &[
];

/// The folders read, from the repository root.
const ROOTS: &[&str] = &["solver/src", "harness", "references"];

/// Folders of test code and build output, left out.
const SKIP: &[&str] = &["tests", "benches", "examples", "target"];

/// A function: its name, the line of its `fn` (1-based) and its number of lines.
#[derive(Debug, PartialEq)]
struct Function {
    name: String,
    line: usize,
    lines: usize,
}

/// The index of the brace that closes the one at `open`.
fn block_end(b: &[u8], open: usize) -> usize {
    let mut depth = 0usize;
    for (j, &c) in b.iter().enumerate().skip(open) {
        if c == b'{' {
            depth += 1;
        } else if c == b'}' {
            depth -= 1;
            if depth == 0 {
                return j;
            }
        }
    }
    b.len().saturating_sub(1)
}

/// The byte ranges of the items under `#[cfg(test)]` that have a body (a module, a function).
fn test_items(b: &[u8], code: &str) -> Vec<(usize, usize)> {
    let mut ranges = Vec::new();
    let mut from = 0;
    while let Some(at) = code[from..].find("#[cfg(test)]").map(|p| p + from) {
        from = at + 1;
        let rest = &code[at + 12..];
        let brace = rest.find('{');
        let semi = rest.find(';');
        if let Some(brace) = brace.filter(|&p| semi.is_none_or(|s| p < s)) {
            ranges.push((at, block_end(b, at + 12 + brace)));
        }
    }
    ranges
}

/// The functions with a body in `text`, outside test items.
fn functions(text: &str) -> Vec<Function> {
    let code = strip(text);
    let b = code.as_bytes();
    let tests = test_items(b, &code);
    let line_of = |i: usize| 1 + b[..i].iter().filter(|&&c| c == b'\n').count();
    let mut out = Vec::new();
    let mut i = 0;
    while let Some(at) = code[i..].find("fn ").map(|p| p + i) {
        i = at + 3;
        if at > 0 && is_ident(b[at - 1]) || tests.iter().any(|&(s, e)| (s..=e).contains(&at)) {
            continue;
        }
        let name: String = code[at + 3..]
            .trim_start()
            .bytes()
            .take_while(|&c| is_ident(c))
            .map(char::from)
            .collect();
        if name.is_empty() {
            continue;
        }
        // The body's brace: the first `{` outside parentheses and brackets, unless a `;` ends
        // a declaration first.
        let mut depth = 0i32;
        let mut body = None;
        for (j, &c) in b.iter().enumerate().skip(i) {
            match c {
                b'(' | b'[' => depth += 1,
                b')' | b']' => depth -= 1,
                b';' if depth == 0 => break,
                b'{' if depth == 0 => {
                    body = Some(j);
                    break;
                }
                _ => {}
            }
        }
        if let Some(open) = body {
            let first = line_of(at);
            out.push(Function {
                name,
                line: first,
                lines: line_of(block_end(b, open)) - first + 1,
            });
        }
    }
    out
}

/// The library sources under `dir`, sorted.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            if !SKIP.contains(&name.as_str()) {
                sources(&path, out);
            }
        } else if name.ends_with(".rs") && name != "tests.rs" {
            out.push(path);
        }
    }
}

#[test]
fn no_library_function_is_over_the_limit_but_the_known_ones_and_those_only_shrink() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut problems = Vec::new();
    let mut seen = Vec::new();
    for root in ROOTS {
        let mut files = Vec::new();
        sources(&repo.join(root), &mut files);
        for path in files {
            let rel = path
                .strip_prefix(repo)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            let text = std::fs::read_to_string(&path).unwrap();
            for f in functions(&text).into_iter().filter(|f| f.lines > LIMIT) {
                match KNOWN
                    .iter()
                    .find(|(file, name, _)| *file == rel && *name == f.name)
                {
                    Some(&(_, _, ceiling)) if f.lines <= ceiling => {
                        seen.push((rel.clone(), f.name))
                    }
                    Some(&(_, _, ceiling)) => problems.push(format!(
                        "{rel}:{} `{}` grew to {} lines (at most {ceiling}, and {LIMIT} is the \
                         aim): split it into named steps",
                        f.line, f.name, f.lines
                    )),
                    None => problems.push(format!(
                        "{rel}:{} `{}` has {} lines, more than {LIMIT}: split it into named steps",
                        f.line, f.name, f.lines
                    )),
                }
            }
        }
    }
    for (file, name, _) in KNOWN {
        if !seen.iter().any(|(f, n)| f == file && n == name) {
            problems.push(format!(
                "{file} `{name}` is no longer over {LIMIT} lines (or moved): remove it from KNOWN"
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn a_function_runs_from_its_fn_line_to_its_closing_brace() {
    let text = r#"
fn short() { let s = "}"; let c = '{'; }

/// A doc comment with fn inside { and a brace.
pub(crate) fn long<T: Into<[u8; 2]>>(x: T)
where
    T: Copy,
{
    let s = "a string
over two lines }";
    /* a comment
       } */
}

trait Declares {
    fn declared(&self) -> usize;
}

#[cfg(test)]
mod tests {
    fn left_out() {}
}
"#;
    let found = functions(text);
    let at = |name: &str| {
        found
            .iter()
            .find(|f| f.name == name)
            .map(|f| (f.line, f.lines))
    };
    assert_eq!(at("short"), Some((2, 1)));
    assert_eq!(at("long"), Some((5, 9)));
    assert_eq!(at("declared"), None);
    assert_eq!(at("left_out"), None);
}
