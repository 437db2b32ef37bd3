//! The README's tutorial, run top to bottom as a new user would: each command of its `sh`
//! block, in order, in an empty folder that holds only the examples.

use std::path::{Path, PathBuf};

use assert_cmd::Command;

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The argument lists of the `whirl` commands in the README's `## Tutorial` code block
/// (the `alias` line, which makes `whirl` the binary, left out; comments stripped).
fn tutorial_commands(readme: &str) -> Vec<Vec<String>> {
    let after = readme
        .split_once("\n## Tutorial\n")
        .expect("README.md has a `## Tutorial` section")
        .1;
    let block = after
        .split_once("```sh\n")
        .and_then(|(_, rest)| rest.split_once("\n```"))
        .expect("the tutorial section opens with a ```sh block")
        .0;
    block
        .lines()
        .filter(|line| !line.trim().is_empty() && !line.starts_with("alias "))
        .map(|line| {
            let command = line.split(" #").next().unwrap_or_default();
            let mut words = command.split_whitespace().map(str::to_string);
            assert_eq!(
                words.next().as_deref(),
                Some("whirl"),
                "not a whirl command: {line}"
            );
            words.collect()
        })
        .collect()
}

fn copy_examples(to: &Path) {
    let from = repository().join("examples");
    let target = to.join("examples");
    std::fs::create_dir_all(&target).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        // The model and study files; not the folders of scripts (examples/python).
        if path.is_file() {
            std::fs::copy(&path, target.join(path.file_name().unwrap())).unwrap();
        }
    }
}

fn run(dir: &Path, args: &[String]) {
    let started = std::time::Instant::now();
    let output = Command::cargo_bin("whirl")
        .unwrap()
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "`whirl {}` failed:\n{}",
        args.join(" "),
        String::from_utf8_lossy(&output.stderr)
    );
    eprintln!(
        "{:6.1} s  whirl {}",
        started.elapsed().as_secs_f64(),
        args.join(" ")
    );
}

#[test]
fn readme_tutorial_runs_top_to_bottom() {
    let readme = std::fs::read_to_string(repository().join("README.md")).unwrap();
    let commands = tutorial_commands(&readme);
    // Every analysis the tutorial teaches is there: losing one (a parse that stops early)
    // would make this test pass on nothing.
    assert!(commands.len() >= 18, "{} commands", commands.len());
    let dir = tempfile::tempdir().unwrap();
    copy_examples(dir.path());
    for args in &commands {
        run(dir.path(), args);
    }
    // Each command wrote its summary into its own folder.
    for name in [
        "check",
        "static",
        "unbalance",
        "hbm",
        "cascade",
        "quick_study",
        "map",
    ] {
        let summary = dir.path().join("out").join(name).join("summary.json");
        assert!(summary.is_file(), "{} missing", summary.display());
    }
    // The cascade's checkpoint stays behind; another cascade into the same folder with
    // other speeds must not be blocked by it, and the tutorial's own command run again
    // resumes from it.
    let cascade = commands
        .iter()
        .find(|a| a[0] == "cascade")
        .expect("the tutorial runs a cascade");
    let mut other = cascade.clone();
    let at = other.iter().position(|a| a == "--speeds").unwrap();
    other[at + 1] = "150Hz:350Hz:3".into();
    run(dir.path(), &other);
    run(dir.path(), cascade);
}
