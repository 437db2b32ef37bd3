//! `whirl simulate` end to end: the settled 1X against `whirl unbalance`, the .npy file,
//! refused steps and bad arguments.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use serde_json::Value;

fn reference() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/reference_rotor.toml")
}

/// Runs `whirl <args> reference --out <dir>`, expects success and returns summary.json.
fn run(dir: &Path, args: &[&str]) -> Value {
    let mut cmd = Command::cargo_bin("whirl").unwrap();
    let output = cmd
        .args(args)
        .arg(reference())
        .arg("--out")
        .arg(dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{args:?} failed:\n{stderr}");
    // stderr is not a terminal here: no progress line.
    assert!(!stderr.contains("simulating"), "{stderr}");
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// Runs `whirl simulate reference <args>` and checks the failure: nonzero exit, no panic,
/// each expected text in stderr, no output folder.
fn fails(args: &[&str], expected: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let output = Command::cargo_bin("whirl")
        .unwrap()
        .arg("simulate")
        .arg(reference())
        .args(args)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "succeeded: {args:?}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // miette wraps long lines; compare with the wrapping (and its margin bars) undone.
    let flat = flatten(&stderr);
    for e in expected {
        assert!(flat.contains(e), "`{e}` not in:\n{stderr}");
    }
    assert!(!out.exists(), "an output folder was written");
    assert_eq!(
        std::fs::read_dir(tmp.path()).unwrap().count(),
        0,
        "temporary files left behind"
    );
}

fn flatten(text: &str) -> String {
    text.split_whitespace()
        .filter(|w| *w != "│" && *w != "|")
        .collect::<Vec<_>>()
        .join(" ")
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

/// Amplitude (m) and phase (deg) of n10's ux and uy from `whirl unbalance` at 50 Hz.
fn unbalance_at_50hz(dir: &Path) -> [(f64, f64); 2] {
    run(
        dir,
        &["unbalance", "--speeds", "50Hz:50Hz:1", "--nodes", "10"],
    );
    let text = std::fs::read_to_string(dir.join("unbalance.csv")).unwrap();
    let mut lines = text.lines();
    let names: Vec<&str> = lines.next().unwrap().split(',').collect();
    let values: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap_or(f64::NAN))
        .collect();
    let column = |name: &str| values[names.iter().position(|n| *n == name).unwrap()];
    [
        (column("n10_ux_amplitude_m"), column("n10_ux_phase_deg")),
        (column("n10_uy_amplitude_m"), column("n10_uy_phase_deg")),
    ]
}

/// Simulates at 50 Hz (at the first critical speed, the hardest case for settling) and
/// compares the settled 1X of n10 with the frequency-domain response.
fn settled_one_x_matches_unbalance(extra: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let expected = unbalance_at_50hz(&tmp.path().join("unbalance"));
    let mut args = vec![
        "simulate",
        "--speed",
        "50Hz",
        "--duration",
        "1.5s",
        "--settle",
        "1.2s",
        "--nodes",
        "10",
    ];
    args.extend_from_slice(extra);
    let s = run(&tmp.path().join("simulate"), &args);
    assert_eq!(s["status"], "completed", "{s}");
    for (channel, (amplitude, phase)) in s["channels"].as_array().unwrap().iter().zip(expected) {
        let a = f(&channel["one_x_amplitude_m"]);
        let p = f(&channel["one_x_phase_deg"]);
        let error = (a - amplitude).abs() / amplitude;
        eprintln!(
            "{extra:?} {}: simulate {a:.6e} m {p:.3} deg, unbalance {amplitude:.6e} m \
             {phase:.3} deg, relative difference {error:.2e}, wall {:.3} s",
            channel["name"],
            f(&s["wall_time_s"])
        );
        // Issue 4: within 0.5 %. Modes 1F/1B have 2 % damping at 49.8 Hz, so the transient
        // from the static start decays as exp(-6.3 t): 5e-4 of its size (about the orbit's)
        // after the 1.2 s settling time. The step error at 50 Hz is below 1e-5 and the
        // reduction's error at mode 1 is 1e-7.
        assert!(error < 5e-3, "{channel}: {a:e} vs {amplitude:e}");
        // The same transient, as a phase: 5e-4 rad = 0.03 deg; 0.3 deg leaves room.
        assert!((p - phase).abs() < 0.3, "{channel}: {p} deg vs {phase} deg");
    }
}

#[test]
fn settled_one_x_of_the_reduced_model_matches_unbalance() {
    settled_one_x_matches_unbalance(&["--reduce", "12"]);
}

#[test]
fn settled_one_x_of_the_full_model_matches_unbalance() {
    settled_one_x_matches_unbalance(&[]);
}

#[test]
fn outputs_are_complete_and_the_npy_file_parses() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("sim");
    let s = run(
        &dir,
        &[
            "simulate",
            "--speed",
            "3000rpm",
            "--duration",
            "100ms",
            "--reduce",
            "12",
            "--nodes",
            "10,0",
        ],
    );
    for file in [
        "time_history.csv",
        "time_history.npy",
        "spectrum.csv",
        "peaks.csv",
        "time_history.png",
        "time_history.svg",
        "orbits.png",
        "orbits.svg",
        "spectrum.png",
        "spectrum.svg",
    ] {
        assert!(dir.join(file).is_file(), "{file} missing");
    }
    // The default step of the central difference is 0.9 x its stability limit.
    assert!(
        (f(&s["step_s"]) / f(&s["stable_step_s"]) - 0.9).abs() < 1e-12,
        "{s}"
    );
    let csv = std::fs::read_to_string(dir.join("time_history.csv")).unwrap();
    assert!(
        csv.starts_with("time_s,n10.ux,n10.uy,n0.ux,n0.uy\n"),
        "{}",
        &csv[..60]
    );
    let rows = csv.lines().count() - 1;
    assert_eq!(rows as u64, s["samples"].as_u64().unwrap());

    let npy = std::fs::read(dir.join("time_history.npy")).unwrap();
    assert_eq!(&npy[..8], b"\x93NUMPY\x01\x00");
    let header_len = u16::from_le_bytes([npy[8], npy[9]]) as usize;
    let data = 10 + header_len;
    // NumPy 1.0 format: the data starts on a 64-byte boundary, the header ends in a newline.
    assert_eq!(data % 64, 0);
    let header = std::str::from_utf8(&npy[10..data]).unwrap();
    assert!(header.ends_with('\n'), "{header}");
    assert!(header.contains("'descr': '<f8'"), "{header}");
    assert!(header.contains("'fortran_order': False"), "{header}");
    assert!(
        header.contains(&format!("'shape': ({rows}, 5)")),
        "{header}"
    );
    assert_eq!(npy.len(), data + rows * 5 * 8);
    // Row 1 (C order): the time of the second sample, then n10.ux there, as in the CSV.
    let value =
        |k: usize| f64::from_le_bytes(npy[data + 8 * k..data + 8 * k + 8].try_into().unwrap());
    let second: Vec<f64> = csv
        .lines()
        .nth(2)
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(value(5), second[0]);
    assert_eq!(value(6), second[1]);
    assert!((value(5) - f(&s["step_s"])).abs() < 1e-18);
}

#[test]
fn an_unstable_central_difference_step_is_refused_with_the_limit() {
    // SPEC section 7: w_max of the full model is about 5e5 rad/s, so 1e-5 s is unstable.
    fails(
        &["--speed", "50Hz", "--duration", "10ms", "--step", "1e-5"],
        &["stability limit 3.943e-6 s", "reduce the model"],
    );
}

#[test]
fn a_diverged_run_says_when_and_writes_nothing() {
    // A bound below the static sag stops the run at once.
    fails(
        &[
            "--speed",
            "50Hz",
            "--duration",
            "10ms",
            "--reduce",
            "12",
            "--divergence-bound",
            "1e-9",
        ],
        &[
            "diverged at t = 0.000000 s",
            "bound 1e-9",
            "nothing was written",
        ],
    );
}

#[test]
fn bad_arguments_are_explained() {
    fails(
        &["--speed", "50Hz", "--duration", "-1s"],
        &["--duration", "must not be negative"],
    );
    fails(
        &["--speed", "50Hz", "--duration", "0s"],
        &["--duration", "must be positive"],
    );
    fails(
        &["--speed", "50Hz", "--duration", "1s", "--settle", "1s"],
        &["--settle", "not shorter than the duration 1 s"],
    );
    fails(
        &["--speed", "50Hz", "--method", "euler"],
        &["'euler'", "--method", "cd, newmark, rk"],
    );
    fails(
        &["--speed", "50Hz", "--contact", "hertz"],
        &["'hertz'", "--contact", "possible values: linear"],
    );
    fails(
        &["--speed", "50Hz", "--duration", "1 fortnight"],
        &["--duration", "fortnight"],
    );
    fails(
        &["--speed", "50Hz", "--ramp-to", "100Hz", "--settle", "0"],
        &["--ramp-to", "settling time"],
    );
    fails(
        &["--speed", "50Hz", "--nodes", "99"],
        &["--nodes", "node 99"],
    );
}
