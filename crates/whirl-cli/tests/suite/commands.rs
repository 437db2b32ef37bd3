//! Every command on the reference rotor: exit status, the folder's files, key numbers.

use std::path::Path;

use assert_cmd::Command;
use serde_json::Value;

use crate::reference::reference_rotor_path;

/// Runs `whirl <args> reference --out <dir>` and returns summary.json.
fn run(dir: &Path, args: &[&str]) -> Value {
    let mut cmd = Command::cargo_bin("whirl").unwrap();
    cmd.args(args)
        .arg(reference_rotor_path())
        .arg("--out")
        .arg(dir);
    cmd.assert().success();
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// The files exist and are not empty; CSV files start with the expected header.
fn assert_files(dir: &Path, files: &[&str]) {
    for f in files {
        let path = dir.join(f);
        let len = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        assert!(len > 0, "{} missing or empty", path.display());
    }
}

fn header(dir: &Path, csv: &str) -> String {
    let text = std::fs::read_to_string(dir.join(csv)).unwrap();
    text.lines().next().unwrap_or_default().to_string()
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

// docs/theory.md section 9: the first undamped frequency of the reference rotor is about 49.8 Hz;
// the window of +-0.5 Hz allows for the mesh and for gyroscopic splitting at the speeds used.
const FIRST: std::ops::Range<f64> = 49.3..50.3;

#[test]
fn check_summarises_the_reference_rotor() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("check");
    let s = run(&dir, &["check"]);
    assert_files(
        &dir,
        &[
            "summary.json",
            "nodes.csv",
            "frequencies.csv",
            "rotor.png",
            "rotor.svg",
        ],
    );
    assert_eq!(s["nodes"], 21);
    assert_eq!(s["dofs"], 84);
    assert_eq!(s["elements"], 20);
    assert!(FIRST.contains(&f(&s["undamped_frequencies_hz"][0])), "{s}");
    // Shaft 7810 kg/m^3 x pi/4 x 0.0559^2 m^2 x 1.3 m = 24.92 kg, plus the 10 kg disk.
    assert!((f(&s["total_mass_kg"]) - 34.92).abs() < 0.01, "{s}");
    assert_eq!(s["roller_bearings"].as_array().map(Vec::len), Some(2));
    assert_eq!(header(&dir, "nodes.csv"), "node,z_m,features");
}

#[test]
fn modal_reports_forward_and_backward_modes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("modal");
    let s = run(&dir, &["modal", "--speed", "3000rpm", "--modes", "4"]);
    assert_files(
        &dir,
        &[
            "undamped_modes.csv",
            "undamped_shapes.csv",
            "damped_modes.csv",
            "damped_shapes.csv",
            "mode_shapes.png",
            "mode_shapes.svg",
            "damped_orbits.png",
            "damped_orbits.svg",
        ],
    );
    assert!((f(&s["speed_hz"]) - 50.0).abs() < 1e-9);
    let modes = s["damped_modes"].as_array().unwrap();
    assert_eq!(modes.len(), 4);
    assert!(FIRST.contains(&f(&modes[0]["damped_frequency_hz"])));
    // The first pair splits into a backward (lower) and a forward (higher) whirl.
    assert_eq!(modes[0]["whirl"], "backward");
    assert_eq!(modes[1]["whirl"], "forward");
    // About 2 % damping on the first modes (docs/theory.md section 9).
    assert!((f(&modes[0]["damping_ratio"]) - 0.02).abs() < 0.003);
    assert_eq!(
        header(&dir, "undamped_shapes.csv"),
        "mode,frequency_hz,node,z_m,ux,uy,tx,ty"
    );
}

#[test]
fn campbell_finds_the_first_critical_speed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("campbell");
    let s = run(
        &dir,
        &["campbell", "--speeds", "0:800Hz:81", "--orders", "1,2"],
    );
    assert_files(
        &dir,
        &[
            "campbell.csv",
            "critical_speeds.csv",
            "campbell.png",
            "campbell.svg",
            "log_decrement.png",
            "log_decrement.svg",
        ],
    );
    let crit = s["critical_speeds"].as_array().unwrap();
    let synchronous: Vec<f64> = crit
        .iter()
        .filter(|c| f(&c["order"]) == 1.0)
        .map(|c| f(&c["speed_hz"]))
        .collect();
    assert!(FIRST.contains(&synchronous[0]), "{s}");
    // The 2X line crosses the first pair at half that speed.
    assert!(
        (f(&crit[0]["speed_hz"]) - synchronous[0] / 2.0).abs() < 0.5,
        "{s}"
    );
    // docs/theory.md section 1 sign check: forward branches rise with speed, backward ones fall.
    for b in s["branches"].as_array().unwrap() {
        let (first, last) = (
            f(&b["frequency_at_first_speed_hz"]),
            f(&b["frequency_at_last_speed_hz"]),
        );
        match b["whirl"].as_str() {
            Some("forward") => assert!(last > first, "{b}"),
            Some("backward") => assert!(last < first, "{b}"),
            _ => {}
        }
    }
    assert!(header(&dir, "campbell.csv").starts_with("speed_hz,speed_rpm,1B_frequency_hz,"));
    let rows = std::fs::read_to_string(dir.join("campbell.csv")).unwrap();
    assert_eq!(rows.lines().count(), 82);
}

#[test]
fn convergence_follows_the_frequencies_over_meshes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("convergence");
    let s = run(
        &dir,
        &["convergence", "--counts", "3,4,10,20", "--modes", "2"],
    );
    assert_files(
        &dir,
        &[
            "convergence.csv",
            "convergence.png",
            "convergence.svg",
            "convergence_change.png",
            "convergence_change.svg",
        ],
    );
    assert_eq!(s["element_counts"], serde_json::json!([4, 10, 20]));
    // 3 elements put no node under the disk at mid-span.
    assert_eq!(s["skipped_element_counts"], serde_json::json!([3]));
    assert!(FIRST.contains(&f(&s["finest_mesh_frequencies_hz"][0])));
    assert_eq!(
        header(&dir, "convergence.csv"),
        "elements,mode1_frequency_hz,mode2_frequency_hz,mode1_relative_change,mode2_relative_change"
    );
}

#[test]
fn convergence_leaves_modes_a_coarse_mesh_lacks_empty() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("convergence");
    let mut cmd = Command::cargo_bin("whirl").unwrap();
    cmd.args(["convergence", "--counts", "2,4,20", "--modes", "40"])
        .arg(reference_rotor_path())
        .arg("--out")
        .arg(&dir);
    let output = cmd.output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    // 4 DOFs per node: 2 elements (3 nodes) have 12 modes, 4 elements 20, 20 elements 84.
    assert!(
        stderr.contains("2 of the meshes have fewer than the 40 modes asked for (2 elements: 12, 4 elements: 20)"),
        "{stderr}"
    );
    let s: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["modes_found"], serde_json::json!([12, 20, 40]));
    assert_eq!(
        s["meshes_with_fewer_modes"],
        serde_json::json!([{"elements": 2, "modes": 12}, {"elements": 4, "modes": 20}])
    );
    assert!(s["frequencies_hz"][0][12].is_null());
    // Every row has 1 + 2 x 40 cells; the 2-element mesh's modes 13 to 40 are empty.
    let text = std::fs::read_to_string(dir.join("convergence.csv")).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    assert!(rows.iter().all(|r| r.len() == 81), "{text}");
    assert!(!rows[1][12].is_empty() && rows[1][13].is_empty());
    // The finest mesh has every frequency; a change is empty where the previous mesh lacks
    // the mode (mode 21 on 20 elements after 4), present where both have it (mode 20).
    assert!(rows[3][1..=40].iter().all(|c| !c.is_empty()));
    assert!(!rows[3][40 + 20].is_empty() && rows[3][40 + 21].is_empty());
}

#[test]
fn api617_margins_are_not_applicable_to_a_range_from_1_hz() {
    // The reference rotor runs from 1 Hz to 750 Hz: a run-up, not a running range.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("unbalance");
    let s = run(
        &dir,
        &["unbalance", "--speeds", "1:100Hz:199", "--nodes", "10"],
    );
    let status = s["api617_status"].as_str().unwrap();
    assert!(
        status.starts_with("not applicable: the operating range starts at 1.00 Hz")
            && status.contains("set [operating] min_speed"),
        "{status}"
    );
    assert!(s["nodes"][0]["peaks"][0]["meets_api617"].is_null());
    let peaks = std::fs::read_to_string(dir.join("peaks.csv")).unwrap();
    assert!(
        peaks.lines().nth(1).unwrap().ends_with(",not applicable"),
        "{peaks}"
    );
}

#[test]
fn unbalance_peaks_at_the_first_critical_speed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("unbalance");
    let s = run(&dir, &["unbalance", "--speeds", "1:100Hz:199"]);
    assert_files(
        &dir,
        &[
            "unbalance.csv",
            "peaks.csv",
            "bode.png",
            "bode.svg",
            "polar.png",
            "polar.svg",
            "orbit_major.png",
            "orbit_major.svg",
        ],
    );
    // Default nodes: the disk (10) and the bearings (0 and 20).
    let nodes: Vec<u64> = s["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|n| n["node"].as_u64())
        .collect();
    assert_eq!(nodes, vec![0, 10, 20]);
    let disk = &s["nodes"][1];
    let peak = &disk["peaks"][0];
    assert!(FIRST.contains(&f(&peak["speed_hz"])), "{peak}");
    // About 2 % damping: amplification factor near 1 / (2 zeta) = 25.
    assert!(
        (f(&peak["amplification_factor"]) - 25.0).abs() < 5.0,
        "{peak}"
    );
    assert!(header(&dir, "unbalance.csv").starts_with("speed_hz,speed_rpm,n0_ux_amplitude_m,"));
}

#[test]
fn static_reactions_carry_the_weight() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("static");
    let s = run(&dir, &["static"]);
    assert_files(
        &dir,
        &[
            "stations.csv",
            "reactions.csv",
            "rollers.csv",
            "static_response.png",
            "static_response.svg",
            "roller_loads.png",
            "roller_loads.svg",
        ],
    );
    // The Newton solve stops at 1e-10 of the load.
    assert!(
        (f(&s["reaction_sum_over_weight"]) - 1.0).abs() < 1e-8,
        "{s}"
    );
    // The disk (node 10) sags most.
    assert_eq!(s["max_deflection"]["node"], 10);
    assert!(header(&dir, "stations.csv").starts_with("z_m,node,element,ux_m,uy_m,"));
}

#[test]
fn frf_peaks_at_the_first_natural_frequency() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("frf");
    let s = run(
        &dir,
        &[
            "frf",
            "--input",
            "10:ux",
            "--output",
            "10:ux,0:uy",
            "--frequencies",
            "1:100Hz:199",
        ],
    );
    assert_files(
        &dir,
        &[
            "frf.csv",
            "peaks.csv",
            "receptance.png",
            "mobility.svg",
            "accelerance.png",
        ],
    );
    let peak = &s["outputs"][0]["peaks"][0];
    assert!(FIRST.contains(&f(&peak["frequency_hz"])), "{peak}");
    assert!(header(&dir, "frf.csv").starts_with("frequency_hz,n10.ux_receptance_re,"));
}

#[test]
fn ucs_cuts_the_bearing_stiffness_at_the_first_critical() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("ucs");
    let s = run(&dir, &["ucs", "--stiffness", "1e6:1e10:41", "--modes", "2"]);
    assert_files(&dir, &["ucs.csv", "bearings.csv", "ucs.png", "ucs.svg"]);
    let first = f(&s["bearings"][0]["critical_speeds_hz"][0]);
    assert!(FIRST.contains(&first), "{s}");
    assert_eq!(
        header(&dir, "ucs.csv"),
        "stiffness_n_per_m,mode1_hz,mode2_hz"
    );
}

#[test]
fn reduce_compares_the_reduced_and_full_models() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("reduce");
    let s = run(&dir, &["reduce", "--modes", "12"]);
    assert_files(
        &dir,
        &[
            "reduce.csv",
            "study.csv",
            "reduction_error.png",
            "reduction_error.svg",
            "stable_step.png",
            "stable_step.svg",
        ],
    );
    // Boundary: the four DOFs of each bearing node, named.
    assert_eq!(s["boundary_dofs"].as_array().map(Vec::len), Some(8), "{s}");
    assert_eq!(s["boundary_dofs"][0], "n0.ux");
    assert_eq!(s["reduced_coordinates"], 20);
    let errors = s["relative_errors"].as_array().unwrap();
    assert_eq!(errors.len(), 12);
    // Craig-Bampton is a Ritz method: no frequency falls below the full model's (round-off
    // aside), and with 12 modes the first pair is within 1e-6.
    assert!(errors.iter().all(|e| f(e) > -1e-12), "{s}");
    assert!(f(&errors[0]) < 1e-6, "{s}");
    // docs/theory.md section 6: w_max of the full model is about 5e5 rad/s, a limit near 4e-6 s,
    // and the reduction raises it.
    let full = f(&s["full_stable_step_s"]);
    assert!((3.5e-6..4.5e-6).contains(&full), "{s}");
    assert!(f(&s["reduced_stable_step_s"]) > 5.0 * full, "{s}");
    // The study runs over 1 to 24 fixed-interface modes; errors shrink as modes are added.
    let study = s["study"].as_array().unwrap();
    assert_eq!(study.len(), 24);
    let first_mode = |row: &Value| f(&row["relative_errors"][0]);
    assert!(first_mode(&study[23]) < first_mode(&study[0]), "{s}");
    assert!(header(&dir, "study.csv")
        .starts_with("fixed_interface_modes,coordinates,stable_step_s,mode1_relative_error"));
}

#[test]
fn json_prints_the_summary_and_a_rerun_replaces_the_folder() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    std::fs::create_dir(&dir).unwrap();
    std::fs::write(dir.join("summary.json"), "{}").unwrap();
    std::fs::write(dir.join("stale.csv"), "old").unwrap();
    let output = Command::cargo_bin("whirl")
        .unwrap()
        .args(["check", "--json", "--out"])
        .arg(&dir)
        .arg(reference_rotor_path())
        .output()
        .unwrap();
    assert!(output.status.success());
    let printed: Value = serde_json::from_slice(&output.stdout).unwrap();
    let written: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(printed, written);
    assert_eq!(printed["command"], "check");
    assert!(
        !dir.join("stale.csv").exists(),
        "the old result must be replaced as a whole"
    );
    // No temporary folders are left beside it.
    let leftovers: Vec<_> = std::fs::read_dir(tmp.path())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("whirl-"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn every_speed_is_announced_in_hz_and_a_misspelt_unit_named_where_written() {
    let tmp = tempfile::tempdir().unwrap();
    let out = Command::cargo_bin("whirl")
        .unwrap()
        .args(["campbell", "--speeds", "0:800:11"])
        .arg(reference_rotor_path())
        .arg("--out")
        .arg(tmp.path().join("c"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    // 800 rad/s is 127.324 Hz: the plain number is rad/s, and the command says so.
    assert!(
        stderr.contains("has no unit, so it is rad/s") && stderr.contains("127.3240 Hz"),
        "{stderr}"
    );
    let out = Command::cargo_bin("whirl")
        .unwrap()
        .args(["campbell", "--speeds", "0:800Hx:161"])
        .arg(reference_rotor_path())
        .arg("--out")
        .arg(tmp.path().join("d"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("`800Hx`"), "{stderr}");
}

#[test]
fn every_default_is_stated_once_in_the_help() {
    // clap appends `[default: ...]` for an argument with a default value; a doc comment that
    // also states it printed it twice ("[default: 0] [default: 0]").
    for command in [
        "check",
        "modal",
        "campbell",
        "convergence",
        "unbalance",
        "reduce",
        "simulate",
        "stiffness",
        "fit-forcing",
        "hbm",
        "map",
        "cascade",
        "runup",
        "study",
        "static",
        "frf",
        "ucs",
        "import-ross",
    ] {
        let output = Command::cargo_bin("whirl")
            .unwrap()
            .args([command, "--help"])
            .output()
            .unwrap();
        assert!(output.status.success(), "`whirl {command} --help` failed");
        let help = String::from_utf8_lossy(&output.stdout);
        for line in help.lines() {
            assert!(
                line.matches("[default:").count() <= 1,
                "`whirl {command} --help` states a default twice: {line}"
            );
        }
    }
}
