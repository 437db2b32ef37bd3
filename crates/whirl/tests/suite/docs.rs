//! The repository explains itself: no tracked file points to documents outside it.
//!
//! whirl's theory lives in `docs/theory.md` and its departures from the thesis in
//! `docs/theory-errata.md`; a clone of the repository has nothing beside it, so a path
//! into a sibling folder or a file named as the project's outside contract would be a
//! dangling reference for every reader.

use std::fs;
use std::path::{Path, PathBuf};

/// Strings that point outside the repository. Spelled in pieces so that this file does not
/// match itself.
fn forbidden() -> [String; 3] {
    [
        format!("../{}", "shared"),
        format!("{}.md", "SPEC"),
        format!("shared/{}", "seed"),
    ]
}

/// Folders that are not the product: build output, version control, the Python
/// environment that scripts/test-all builds.
const SKIPPED: [&str; 3] = ["target", ".git", ".venv"];

fn text_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let entries = fs::read_dir(dir).unwrap_or_else(|e| panic!("read {}: {e}", dir.display()));
    for entry in entries {
        let path = entry.expect("directory entry").path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if path.is_dir() {
            if !SKIPPED.contains(&name) && !name.starts_with("target") {
                text_files(&path, out);
            }
        } else {
            out.push(path);
        }
    }
}

#[test]
fn no_file_points_outside_the_repository() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    text_files(&root, &mut files);
    // Guards against a walk that silently finds nothing (a wrong root).
    assert!(
        files.iter().any(|f| f.ends_with("docs/theory.md")),
        "docs/theory.md not found under {}",
        root.display()
    );
    let patterns = forbidden();
    let mut offenders = Vec::new();
    for file in &files {
        // Binary files (figures, fonts) are not read as text.
        let Ok(text) = fs::read_to_string(file) else {
            continue;
        };
        for (number, line) in text.lines().enumerate() {
            if let Some(p) = patterns.iter().find(|p| line.contains(p.as_str())) {
                offenders.push(format!("{}:{}: {p}", file.display(), number + 1));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "files that cite documents outside the repository (cite docs/theory.md or the \
         thesis by title instead):\n{}",
        offenders.join("\n")
    );
}
