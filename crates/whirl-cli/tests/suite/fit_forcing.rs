//! `whirl fit-forcing` end to end: the files, the coefficients with units, the pasted line
//! accepted by the model file, and a missing bearing refused without an output folder.

use std::path::PathBuf;

use assert_cmd::Command;
use serde_json::Value;

use crate::reference::reference_rotor_text;

/// Runs `whirl <args> <model> --out <tmp>/out` on `model` text; returns the output, the
/// folder and the temporary directory that holds both.
fn run(
    command: &str,
    model: &str,
    args: &[&str],
) -> (std::process::Output, PathBuf, tempfile::TempDir) {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("model.toml");
    std::fs::write(&file, model).unwrap();
    let out = tmp.path().join("out");
    let output = Command::cargo_bin("whirl")
        .unwrap()
        .arg(command)
        .arg(&file)
        .args(args)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    (output, out, tmp)
}

#[test]
fn fits_the_reference_bearing_and_the_line_pastes_back() {
    let (output, out, _tmp) = run(
        "fit-forcing",
        &reference_rotor_text(),
        &["--speeds", "100Hz:500Hz:3", "--bearing", "1"],
    );
    assert!(output.status.success(), "{output:?}");
    for file in [
        "fit.csv",
        "summary.json",
        "forcing_function.toml",
        "force_deflection.png",
        "force_deflection.svg",
    ] {
        assert!(out.join(file).exists(), "{file} missing");
    }
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["bearing"]["name"], "bearing B");
    assert_eq!(summary["coefficients"]["a0"]["unit"], "N/m^b");
    assert_eq!(summary["speeds"].as_array().unwrap().len(), 3);
    // The cage-averaged Hertz force follows one smooth curve: a close fit.
    assert!(summary["r_squared"].as_f64().unwrap() > 0.99, "{summary}");
    let rows = std::fs::read_to_string(out.join("fit.csv")).unwrap();
    assert_eq!(
        rows.lines().next().unwrap(),
        "speed_hz,speed_rad_s,deflection_m,force_n,fitted_force_n"
    );
    assert_eq!(
        rows.lines().count() - 1,
        summary["points"].as_u64().unwrap() as usize
    );

    // The line goes into bearing B's block, the last [[roller_bearing]] before [damping].
    let block = std::fs::read_to_string(out.join("forcing_function.toml")).unwrap();
    let line = block
        .lines()
        .find(|l| l.starts_with("forcing_function = {"))
        .unwrap();
    let model = reference_rotor_text().replacen("\n[damping]", &format!("{line}\n\n[damping]"), 1);
    let (checked, _, _tmp) = run("check", &model, &[]);
    assert!(checked.status.success(), "{checked:?}");
}

#[test]
fn a_missing_bearing_is_refused_without_output() {
    let (output, out, _tmp) = run(
        "fit-forcing",
        &reference_rotor_text(),
        &["--speeds", "100Hz:200Hz:2", "--bearing", "2"],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("no roller bearing 2"), "{stderr}");
    assert!(stderr.contains("numbered 0 to 1"), "{stderr}");
    assert!(!out.exists());
}
