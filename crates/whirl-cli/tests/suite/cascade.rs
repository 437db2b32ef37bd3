//! `whirl cascade` end to end: the files and the summary; a run that lost some finished
//! speeds (as a killed run does) resumes from its checkpoint to the same bytes as an
//! uninterrupted run, and so does a run on one thread; a cascade with other options keeps
//! its own checkpoint beside the first's, and `--restart` computes anew; the refinement
//! adds speeds marked as added; bad input names the option.

use std::path::{Path, PathBuf};
use std::process::Output;

use assert_cmd::Command;
use serde_json::Value;

use crate::reference::reference_rotor_path;

/// Four speeds, 0.1 s settled (fixed) and 0.1 s recorded, no refinement: a quick cascade
/// (10 Hz bins).
const QUICK: [&str; 9] = [
    "--speeds",
    "40Hz:400Hz:4",
    "--settle",
    "0.1s",
    "--settle-max",
    "0.1s",
    "--record",
    "0.1s",
    "--no-refine",
];

fn whirl(out: &Path, args: &[&str]) -> Output {
    whirl_on(out, args, None)
}

/// `whirl cascade` on `threads` rayon threads (default: one per core).
fn whirl_on(out: &Path, args: &[&str], threads: Option<usize>) -> Output {
    let mut command = Command::cargo_bin("whirl").unwrap();
    if let Some(n) = threads {
        command.env("RAYON_NUM_THREADS", n.to_string());
    }
    command
        .arg("cascade")
        .arg(reference_rotor_path())
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

fn read(path: PathBuf) -> Vec<u8> {
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn summary(out: &Path) -> Value {
    serde_json::from_slice(&read(out.join("summary.json"))).unwrap()
}

#[test]
fn writes_the_cascade_and_resumes_to_the_same_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("cascade");
    let first = whirl(&out, &QUICK);
    assert!(first.status.success(), "{first:?}");
    for file in [
        "summary.json",
        "cascade.csv",
        "nsv.csv",
        "waterfall.png",
        "waterfall.svg",
        "cascade_map.png",
        "cascade_map.svg",
        "nsv.png",
        "nsv.svg",
    ] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
    let s = summary(&out);
    assert_eq!(s["speeds"], 4);
    assert_eq!(s["resumed_speeds"], 0);
    assert!(s["nsv"]["threshold_m"].as_f64() == Some(1e-6), "{s}");
    let cascade_csv = read(out.join("cascade.csv"));
    let nsv_csv = read(out.join("nsv.csv"));
    // Long format: a header and one row per speed and bin.
    let text = String::from_utf8(cascade_csv.clone()).unwrap();
    assert!(text.starts_with("speed_hz,frequency_hz,amplitude_m,added\n"));

    // A killed run keeps the speeds it finished and loses the rest: remove two.
    let checkpoints = |root: &Path| -> Vec<PathBuf> {
        let mut dirs: Vec<PathBuf> = std::fs::read_dir(root)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        dirs.sort();
        dirs
    };
    let root = tmp.path().join("cascade.partial");
    let first_checkpoint = checkpoints(&root);
    assert_eq!(first_checkpoint.len(), 1);
    let checkpoint = &first_checkpoint[0];
    for index in [1, 3] {
        std::fs::remove_file(checkpoint.join(format!("point-{index:05}.json"))).unwrap();
    }
    let again = whirl(&out, &QUICK);
    assert!(again.status.success(), "{again:?}");
    assert_eq!(summary(&out)["resumed_speeds"], 2);
    assert!(
        read(out.join("cascade.csv")) == cascade_csv,
        "cascade.csv differs"
    );
    assert!(read(out.join("nsv.csv")) == nsv_csv, "nsv.csv differs");

    // One thread, from scratch: the same bytes again.
    let serial = tmp.path().join("serial");
    assert!(whirl_on(&serial, &QUICK, Some(1)).status.success());
    assert!(
        read(serial.join("cascade.csv")) == cascade_csv,
        "1 thread differs"
    );
    assert!(read(serial.join("nsv.csv")) == nsv_csv, "1 thread differs");

    // Other options into the same output folder: their own checkpoint beside the first's,
    // which stays for the first cascade's next run.
    let mut longer = QUICK.to_vec();
    longer[7] = "0.2s";
    let other = whirl(&out, &longer);
    assert!(other.status.success(), "{other:?}");
    assert_eq!(summary(&out)["record_s"], 0.2);
    assert_eq!(checkpoints(&root).len(), 2);
    let back = whirl(&out, &QUICK);
    assert!(back.status.success());
    assert_eq!(summary(&out)["resumed_speeds"], 4);
    longer.push("--restart");
    let restarted = whirl(&out, &longer);
    assert!(restarted.status.success(), "{restarted:?}");
    assert_eq!(summary(&out)["resumed_speeds"], 0);
}

#[test]
fn refinement_adds_speeds_marked_as_added() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("cascade");
    let mut args = QUICK.to_vec();
    args.pop();
    args.extend(["--refine-budget", "3"]);
    let run = whirl(&out, &args);
    assert!(run.status.success(), "{run:?}");
    let s = summary(&out);
    assert_eq!(s["nsv"]["added_speeds"], 3, "{s}");
    assert_eq!(s["speeds"], 7);
    let nsv = String::from_utf8(read(out.join("nsv.csv"))).unwrap();
    assert!(nsv.starts_with("speed_hz,added,settled,settle_s,"));
    let added = nsv
        .lines()
        .skip(1)
        .filter(|l| l.split(',').nth(1) == Some("1"));
    assert_eq!(added.count(), 3);
}

#[test]
fn bad_input_names_the_option() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("cascade");
    for (args, words) in [
        (vec!["--speeds", "0:100Hz:3"], vec!["--speeds", "positive"]),
        (vec!["--node", "99"], vec!["--node", "node 99", "0 to 20"]),
        (vec!["--record", "0.1ms"], vec!["--record", "samples"]),
        (vec!["--tolerance", "-1"], vec!["--tolerance", "bins"]),
    ] {
        let output = whirl(&out, &args);
        assert!(!output.status.success(), "{args:?} succeeded");
        let err = String::from_utf8_lossy(&output.stderr);
        for w in words {
            assert!(err.contains(w), "{args:?}: `{w}` not in {err}");
        }
        assert!(!out.exists(), "{args:?} wrote an output folder");
    }
}

#[test]
fn default_speeds_are_the_librarys_over_the_operating_range() {
    // Without --speeds the cascade takes whirl::nsv::default_speeds (as a study and Python
    // do): 150 speeds over the reference rotor's [operating] range, 1 to 750 Hz. The too
    // short record stops the run once they are announced.
    let tmp = tempfile::tempdir().unwrap();
    let output = whirl(&tmp.path().join("cascade"), &["--record", "0.1ms"]);
    assert!(!output.status.success());
    let err = String::from_utf8_lossy(&output.stderr);
    assert!(
        err.contains("speeds (default): 150 values from 1.0000 to 750.0000 Hz"),
        "{err}"
    );
}

/// At 660 Hz running speed the reference rotor has two steady motions: from the static
/// equilibrium a 5.4 um whirl of the first mode (standard error 0.09 um), from rest a
/// 0.13 um super-harmonic orbit (measured); at 640 and 670 Hz both starts settle on the
/// same 0.13 um motion. 650 Hz holds both motions too, and which one the static
/// equilibrium's run falls on changes with round-off (both seen when the time step's
/// arithmetic changed), so it may or may not be marked. `--compare-starts` marks 660 Hz
/// and never the speeds with one motion.
#[test]
fn compare_starts_marks_the_speed_with_two_motions() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("cascade");
    let run = whirl(
        &out,
        &[
            "--speeds",
            "640Hz:670Hz:4",
            "--no-refine",
            "--compare-starts",
        ],
    );
    assert!(run.status.success(), "{run:?}");
    let s = summary(&out);
    let starts = &s["starts"];
    assert_eq!(starts["other_start"], "rest");
    assert_eq!(starts["compared_speeds"], 4);
    let differing: Vec<f64> = starts["differing_speeds_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let marked = |hz: f64| differing.iter().any(|d| (d - hz).abs() < 1e-6);
    assert!(marked(660.0), "{differing:?}");
    assert!(!marked(640.0) && !marked(670.0), "{differing:?}");
    let table = String::from_utf8(read(out.join("starts.csv"))).unwrap();
    assert_eq!(table.lines().count(), 5, "{table}");
    assert!(out.join("starts.png").exists() && out.join("starts.svg").exists());
}
