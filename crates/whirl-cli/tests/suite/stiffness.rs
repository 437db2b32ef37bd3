//! `whirl stiffness` end to end: the files and key numbers on the reference rotor, and bad
//! input refused with a clear message and no output folder.

use std::path::PathBuf;

use assert_cmd::Command;
use serde_json::Value;

use crate::reference::reference_rotor_text;

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

/// Runs `whirl stiffness <model> <args> --out <tmp>` on `model` text; returns the output,
/// the folder and the temporary directory that holds both.
fn run(model: &str, args: &[&str]) -> (std::process::Output, PathBuf, tempfile::TempDir) {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("model.toml");
    std::fs::write(&file, model).unwrap();
    let out = tmp.path().join("out");
    let output = Command::cargo_bin("whirl")
        .unwrap()
        .arg("stiffness")
        .arg(&file)
        .args(args)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    (output, out, tmp)
}

/// The run fails without a panic, says every `expected` text, and writes no folder.
fn fails(model: &str, args: &[&str], expected: &[&str]) {
    let (output, out, _tmp) = run(model, args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "succeeded: {args:?}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // miette wraps long lines: compare words, margin bars left out.
    let flat = |t: &str| {
        t.split_whitespace()
            .filter(|w| *w != "│" && *w != "|")
            .collect::<Vec<_>>()
            .join(" ")
    };
    for e in expected {
        assert!(flat(&stderr).contains(&flat(e)), "`{e}` not in:\n{stderr}");
    }
    assert!(!out.exists(), "an output folder was written");
}

#[test]
fn stiffness_of_the_reference_bearing() {
    let (output, dir, _tmp) = run(
        &reference_rotor_text(),
        &[
            "--clearances",
            "10um:60um:6",
            "--cage-steps",
            "8",
            "--grid",
            "11",
        ],
    );
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for file in [
        "stiffness.csv",
        "passage.csv",
        "surfaces_20um.csv",
        "surfaces_60um.csv",
        "stiffness_vs_clearance.png",
        "stiffness_vs_clearance.svg",
        "surface_20um_fx.png",
        "surface_60um_fr.svg",
        "summary.json",
    ] {
        let len = std::fs::metadata(dir.join(file))
            .map(|m| m.len())
            .unwrap_or(0);
        assert!(len > 0, "{file} missing or empty");
    }
    let s: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    // Half the weight of 24.92 kg of shaft and the 10 kg disk: 171.3 N, downwards.
    let load = &s["load_n"];
    assert!(
        (f(&load[1]) + 171.3).abs() < 0.1 && f(&load[0]).abs() < 1e-9,
        "{load}"
    );
    assert!(s["load_source"].as_str().unwrap().contains("weight"));
    assert!(s["kinds"]["averaged"].as_str().unwrap().contains("passage"));
    let rows = s["clearances"].as_array().unwrap();
    assert_eq!(rows.len(), 6);
    // A bottom roller carries the weight alone: the same frozen stiffness at every
    // clearance (statically determinate); the fixed-displacement stiffness falls.
    let kyy = |r: &Value, kind: &str| f(&r[kind]["stiffness_n_per_m"]["kyy"]);
    for w in rows.windows(2) {
        assert!((kyy(&w[1], "frozen") - kyy(&w[0], "frozen")).abs() < 1e-6 * kyy(&w[0], "frozen"));
        assert!(kyy(&w[1], "fixed") < kyy(&w[0], "fixed"));
    }
    let csv = std::fs::read_to_string(dir.join("stiffness.csv")).unwrap();
    assert_eq!(csv.lines().count(), 7);
    assert!(csv.starts_with("clearance_um,frozen_ux_um,frozen_uy_um,frozen_rollers,"));
    // 11 x 11 grid points and a header.
    let surface = std::fs::read_to_string(dir.join("surfaces_20um.csv")).unwrap();
    assert_eq!(surface.lines().count(), 122);
}

#[test]
fn a_model_without_roller_bearings_is_refused() {
    let text = reference_rotor_text();
    let cut = text.find("[[roller_bearing]]").unwrap();
    let end = text.find("[damping]").unwrap();
    let linear = "[[bearing]]\nnode = 0\nkxx = 1e8\nkyy = 1e8\n\n\
                  [[bearing]]\nnode = 20\nkxx = 1e8\nkyy = 1e8\n\n";
    let m = format!("{}{linear}{}", &text[..cut], &text[end..]);
    fails(&m, &[], &["no [[roller_bearing]]"]);
}

#[test]
fn a_bearing_index_out_of_range_is_refused() {
    fails(
        &reference_rotor_text(),
        &["--bearing", "5"],
        &[
            "--bearing",
            "there is no bearing 5",
            "0 = bearing A, 1 = bearing B",
        ],
    );
}

#[test]
fn negative_clearances_are_refused() {
    let m = reference_rotor_text();
    fails(
        &m,
        &["--clearances=-10um:60um:8"],
        &["--clearances", "must not be negative"],
    );
    fails(
        &m,
        &["--surface-clearances=20um,-5um"],
        &["--surface-clearances", "must not be negative"],
    );
}

#[test]
fn bad_loads_are_refused() {
    let m = reference_rotor_text();
    fails(&m, &["--load", "0N"], &["--load", "must be positive"]);
    fails(&m, &["--load", "60 kg"], &["--load", "kg"]);
    // A direction without a load: the weight's direction is not the user's to change.
    fails(&m, &["--load-angle", "-45"], &["--load"]);
}
