//! The library's layers, read from its sources: the graph of `crate::<module>` paths between
//! the top-level modules of `src/` has no cycle, and the force interface and the bearings
//! (`force`, `bearing`) reach no solver layer, not even through another module.
//!
//! A tiny scan, not a parser: comments, strings and character literals are blanked out, and
//! every `crate::name` (or each first name of a `crate::{a::.., b}` group) that names a
//! top-level module is an edge from the module whose files hold it. `super::` never leaves a
//! top-level module (none of its files is at the crate root), so `crate::` paths are all
//! the edges. Test modules count too: a `#[cfg(test)]` import is a dependency all the same.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The modules that solve (march, balance, sweep, reduce, respond); the force interface and
/// the contact laws are below them, so the solvers can consume any law.
const SOLVERS: [&str; 8] = [
    "time", "hbm", "nsv", "study", "modal", "reduce", "statics", "response",
];

/// The modules that must not reach a solver.
const BELOW_SOLVERS: [&str; 2] = ["bearing", "force"];

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The top-level modules declared in lib.rs (`mod name;`, whatever its visibility).
fn modules() -> Vec<String> {
    let lib = fs::read_to_string(src().join("lib.rs")).expect("read src/lib.rs");
    let modules: Vec<String> = lib
        .lines()
        .filter_map(|line| {
            let line = line.trim();
            let rest = &line[line.find("mod ")?..];
            let name = rest.strip_prefix("mod ")?.strip_suffix(';')?;
            let declared = line.starts_with("mod ") || line.starts_with("pub");
            (declared && is_identifier(name)).then(|| name.to_string())
        })
        .collect();
    // A scan that found no modules would pass every check below.
    assert!(
        modules.len() > 10 && modules.iter().any(|m| m == "bearing"),
        "lib.rs declares only {modules:?}"
    );
    modules
}

fn is_identifier(s: &str) -> bool {
    !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Every .rs file of a module: `name.rs` and everything under `name/`.
fn files_of(module: &str) -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in fs::read_dir(dir).expect("read a source folder") {
            let path = entry.expect("directory entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    let mut files = Vec::new();
    let file = src().join(format!("{module}.rs"));
    if file.is_file() {
        files.push(file);
    }
    let dir = src().join(module);
    if dir.is_dir() {
        walk(&dir, &mut files);
    }
    assert!(!files.is_empty(), "no source file for module {module}");
    files
}

/// The source with comments, string and character literals replaced by spaces (lifetimes
/// are kept: `'a` is not a literal).
fn code_only(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let blank = |out: &mut String, from: usize, to: usize| {
        out.extend(std::iter::repeat_n(' ', to.min(c.len()) - from));
    };
    while i < c.len() {
        let next = c.get(i + 1).copied();
        let start = i;
        if c[i] == '/' && next == Some('/') {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if c[i] == '/' && next == Some('*') {
            // Block comments nest in Rust.
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if c[i] == 'r'
            && (i == 0 || !(c[i - 1].is_alphanumeric() || c[i - 1] == '_'))
            && matches!(next, Some('"') | Some('#'))
            && c[i + 1..].iter().find(|&&x| x != '#') == Some(&'"')
        {
            // Raw string r#".."#: ends at a quote followed by as many hashes.
            let hashes = c[i + 1..].iter().take_while(|&&x| x == '#').count();
            i += 2 + hashes;
            while i < c.len() {
                if c[i] == '"'
                    && c[i + 1..]
                        .iter()
                        .take(hashes)
                        .filter(|&&x| x == '#')
                        .count()
                        == hashes
                {
                    i += 1 + hashes;
                    break;
                }
                i += 1;
            }
        } else if c[i] == '"' {
            i += 1;
            while i < c.len() && c[i] != '"' {
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
        } else if c[i] == '\'' && (next == Some('\\') || c.get(i + 2) == Some(&'\'')) {
            // A character literal ('x', '\n', '\''), not a lifetime.
            i += if next == Some('\\') { 3 } else { 2 };
            while i < c.len() && c[i] != '\'' {
                i += 1;
            }
            i += 1;
        } else {
            out.push(c[i]);
            i += 1;
            continue;
        }
        blank(&mut out, start, i);
    }
    out
}

/// The first names of the `crate::` paths in `code`: `crate::a::X` gives `a`,
/// `crate::{a::X, b}` gives `a` and `b`.
fn crate_paths(code: &str) -> Vec<String> {
    let mut names = Vec::new();
    for (at, _) in code.match_indices("crate::") {
        // `pub(crate)`, `$crate::` and an identifier ending in `crate` are not paths from the root.
        if code[..at]
            .chars()
            .next_back()
            .is_some_and(|p| p.is_alphanumeric() || p == '_' || p == '$')
        {
            continue;
        }
        let rest = code[at + "crate::".len()..].trim_start();
        if let Some(group) = rest.strip_prefix('{') {
            let mut depth = 0;
            let mut item_start = true;
            for (k, ch) in group.char_indices() {
                match ch {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => item_start = true,
                    ch if item_start && !ch.is_whitespace() => {
                        item_start = false;
                        names.push(leading_identifier(&group[k..]));
                    }
                    _ => {}
                }
            }
        } else {
            names.push(leading_identifier(rest));
        }
    }
    names
}

fn leading_identifier(s: &str) -> String {
    s.chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
        .collect()
}

/// Module -> the other top-level modules its files name through `crate::`.
fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let modules = modules();
    modules
        .iter()
        .map(|m| {
            let uses = files_of(m)
                .iter()
                .flat_map(|f| {
                    let text = fs::read_to_string(f).expect("read a source file");
                    crate_paths(&code_only(&text))
                })
                .filter(|name| name != m && modules.contains(name))
                .collect();
            (m.clone(), uses)
        })
        .collect()
}

/// Every module reachable from each module (transitive closure, by a walk from each).
fn reachable(graph: &BTreeMap<String, BTreeSet<String>>) -> BTreeMap<String, BTreeSet<String>> {
    graph
        .keys()
        .map(|from| {
            let mut seen = BTreeSet::new();
            let mut stack: Vec<&String> = graph[from].iter().collect();
            while let Some(m) = stack.pop() {
                if seen.insert(m.clone()) {
                    stack.extend(graph[m].iter());
                }
            }
            (from.clone(), seen)
        })
        .collect()
}

#[test]
fn the_scan_sees_paths_and_skips_comments_and_strings() {
    let code = "use crate::{fe::{A, B}, model::Model};\n\
                // crate::time in a comment\n\
                /* crate::hbm /* nested */ crate::nsv */\n\
                let s = \"crate::study\"; let r = r#\"crate::\"reduce\"#; let q = '\"'; let e = '\\''; let n = '\\n';\n\
                pub(crate) fn f<'a>(x: &'a crate::force::Kinematics) -> crate::Result<()> {}\n";
    assert_eq!(
        crate_paths(&code_only(code)),
        ["fe", "model", "force", "Result"],
    );
}

#[test]
fn no_module_cycle_in_the_library() {
    let graph = graph();
    // The scan must see the library's known layering at all (system builds on fe).
    assert!(graph["system"].contains("fe"), "graph: {graph:?}");
    let reach = reachable(&graph);
    let mut cycles = Vec::new();
    for (a, from_a) in &reach {
        for b in from_a.iter().filter(|b| a < *b) {
            if reach[b].contains(a) {
                cycles.push(format!("{a} <-> {b}"));
            }
        }
    }
    assert!(
        cycles.is_empty(),
        "modules that reach each other through crate:: paths (a strongly connected \
         component of more than one module): {}\ngraph: {graph:#?}",
        cycles.join(", ")
    );
}

#[test]
fn bearing_and_force_reach_no_solver() {
    let graph = graph();
    let reach = reachable(&graph);
    for low in BELOW_SOLVERS {
        let solvers: Vec<&String> = reach[low]
            .iter()
            .filter(|m| SOLVERS.contains(&m.as_str()))
            .collect();
        assert!(
            solvers.is_empty(),
            "{low} reaches the solver layers {solvers:?} (directly: {:?})",
            graph[low]
        );
    }
}
