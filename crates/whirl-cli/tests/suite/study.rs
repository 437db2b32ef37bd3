//! `whirl study` end to end: a small study runs, writes its tables and plots, resumes from
//! its checkpoint with the same numbers, refuses a checkpoint of another study, and reports
//! bad study files at their line without writing anything.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use serde_json::Value;

use crate::reference::reference_rotor_path;

/// A study file in `dir` on the reference rotor with this body after `model = ...`.
fn write_study(dir: &Path, body: &str) -> PathBuf {
    let file = dir.join("study.toml");
    let text = format!(
        "model = {:?}\n{body}",
        reference_rotor_path().display().to_string()
    );
    std::fs::write(&file, text).unwrap();
    file
}

/// Three speeds and short runs: the machinery is under test here, not the physics (the
/// cascade's own tests check that), so each point takes a fraction of a second.
const SMALL: &str =
    "[cascade]\nspeeds = \"100:300Hz:3\"\nsettle = \"0.05 s\"\nrecord = \"0.1 s\"\n\
    [[sweep]]\nname = \"clearance\"\nparameter = \"roller_bearing[*].clearance\"\n\
    values = [\"20 um\", \"120 um\"]\n";

fn study(file: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    Command::cargo_bin("whirl")
        .unwrap()
        .arg("study")
        .arg(file)
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

fn summary(out: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn a_small_study_runs_resumes_and_refuses_another_studys_points() {
    let tmp = tempfile::tempdir().unwrap();
    let file = write_study(tmp.path(), SMALL);
    let out = tmp.path().join("out");
    let first = study(&file, &out, &[]);
    let stderr = String::from_utf8_lossy(&first.stderr);
    assert!(first.status.success(), "{stderr}");
    for f in [
        "points.csv",
        "sweeps.csv",
        "fits.csv",
        "ranking.csv",
        "ranking_by_parameter.csv",
        "cascades_0.png",
        "nsv_0.svg",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let s1 = summary(&out);
    assert_eq!(s1["points"].as_array().unwrap().len(), 2);
    assert_eq!(s1["ranking"][0]["sweep"], "clearance");
    // The points are in the checkpoint beside the output folder.
    let points = tmp.path().join("out.points").join("points");
    assert_eq!(std::fs::read_dir(&points).unwrap().count(), 2);

    // Run again: both points come from the checkpoint, with the same numbers.
    let again = study(&file, &out, &[]);
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert!(again.status.success(), "{stderr}");
    assert_eq!(stderr.matches("from the checkpoint").count(), 2, "{stderr}");
    assert_eq!(summary(&out)["sweeps"], s1["sweeps"]);

    // Another study on the same checkpoint is refused, naming the way out.
    let other = write_study(tmp.path(), &SMALL.replace("120 um", "60 um"));
    let refused = study(&other, &out, &[]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success());
    assert!(stderr.contains("different study"), "{stderr}");
    assert!(stderr.contains("--restart"), "{stderr}");
}

#[test]
fn points_that_differ_only_in_their_threshold_share_one_cascade() {
    let tmp = tempfile::tempdir().unwrap();
    let body = SMALL.replace(
        "parameter = \"roller_bearing[*].clearance\"\nvalues = [\"20 um\", \"120 um\"]",
        "parameter = \"cascade.nsv_threshold\"\nvalues = [\"1 um\", \"10 um\"]",
    );
    assert_ne!(body, SMALL);
    let file = write_study(tmp.path(), &body);
    let out = tmp.path().join("out");
    let run = study(&file, &out, &[]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert_eq!(
        stderr
            .matches("its cascade shared with another point")
            .count(),
        1,
        "{stderr}"
    );
    // The same spectra read at two thresholds: the largest NSV is one number.
    let largest = &summary(&out)["sweeps"][0]["largest_nsv"];
    assert_eq!(largest[0], largest[1], "{largest}");
    // Every point finished: no cascade is left half done.
    assert!(!tmp.path().join("out.points").join("partial").exists());
}

#[test]
fn a_bad_value_is_reported_at_its_line_and_nothing_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let file = write_study(
        tmp.path(),
        "[[sweep]]\nparameter = \"roller_bearing[*].rollers\"\nvalues = [8, 2]\n",
    );
    let out = tmp.path().join("out");
    let r = study(&file, &out, &[]);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success());
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains("study.toml:4:14"), "{stderr}");
    assert!(stderr.contains("roller_bearing[0].rollers"), "{stderr}");
    assert!(!out.exists());
    assert!(!tmp.path().join("out.points").exists());
}

#[test]
fn a_record_too_long_for_a_spectrum_fails_every_point_without_an_abort() {
    // 1e9 s recorded is some 1e13 samples: the cascade of each point refuses it before its
    // spectrum is planned (the plan was a 123 TB allocation), and a study whose every point
    // failed exits nonzero.
    let tmp = tempfile::tempdir().unwrap();
    let file = write_study(
        tmp.path(),
        &SMALL.replace("record = \"0.1 s\"", "record = \"1000000000 s\""),
    );
    let run = study(&file, &tmp.path().join("out"), &[]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "{stderr}");
    assert!(
        !stderr.contains("panicked") && !stderr.contains("memory allocation"),
        "{stderr}"
    );
    assert!(
        stderr.contains("record") && stderr.contains("4194304"),
        "{stderr}"
    );
}
