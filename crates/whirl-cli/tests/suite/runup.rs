//! `whirl runup` end to end: the files and the summary of a short sweep in both directions
//! with its steady cascade; bad input names the option.

use std::path::Path;
use std::process::Output;

use assert_cmd::Command;
use serde_json::Value;

use crate::reference::reference_rotor_path;

fn whirl(out: &Path, args: &[&str]) -> Output {
    Command::cargo_bin("whirl")
        .unwrap()
        .arg("runup")
        .arg(reference_rotor_path())
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

#[test]
fn a_short_sweep_writes_its_tables_plots_and_summary() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("runup");
    // 100-140 Hz at 40 Hz/s: two sweeps of 1 s after the 1 s hold, and a steady cascade of
    // three speeds from one start.
    let run = whirl(
        &out,
        &[
            "--speeds",
            "100:140Hz",
            "--rate",
            "40Hz/s",
            "--steady",
            "cascade",
            "--steady-speeds",
            "3",
        ],
    );
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for file in [
        "summary.json",
        "runup.csv",
        "runup_spectra.csv",
        "steady.csv",
        "hysteresis.csv",
        "bands.csv",
        "runup_map.png",
        "runup_map.svg",
        "runup_nsv.png",
        "runup_nsv.svg",
    ] {
        assert!(out.join(file).exists(), "{file} missing");
    }
    let summary: Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["sweeps"].as_array().unwrap().len(), 2);
    // The default window at 40 Hz/s is 1 / sqrt(40) = 0.158 s, to a length of few primes.
    let window = summary["resolved"]["window_s"].as_f64().unwrap();
    assert!((window - 40f64.sqrt().recip()).abs() < 0.01, "{window}");
    // Each sweep's speeds run from 100 to 140 Hz, read every quarter window (1.6 Hz).
    let windows = summary["sweeps"][0]["windows"].as_u64().unwrap();
    assert!((20..=30).contains(&windows), "{windows}");
    assert_eq!(summary["against_steady"].as_array().unwrap().len(), 2);
}

#[test]
fn bad_sweeps_name_the_option() {
    let dir = tempfile::tempdir().unwrap();
    for (args, flag) in [
        (&["--rate", "0Hz/s"][..], "--rate"),
        (&["--rate", "-5Hz/s"][..], "--rate"),
        (&["--speeds", "300:300Hz"][..], "--speeds"),
        (&["--speeds", "300:100Hz"][..], "--speeds"),
        (&["--overlap", "1"][..], "--overlap"),
    ] {
        let out = dir.path().join("bad");
        let run = whirl(&out, args);
        assert!(!run.status.success(), "{args:?} ran");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(stderr.contains(flag), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} wrote its folder");
    }
}
