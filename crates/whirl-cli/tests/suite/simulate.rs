//! `whirl simulate` end to end: the settled 1X against `whirl unbalance`, the .npy file,
//! refused steps and bad arguments; with roller bearings the contact outputs and the
//! contact frequencies in the spectrum.

use std::path::Path;

use assert_cmd::Command;
use serde_json::Value;

use crate::reference::{example_path, reference_rotor_path};

/// Runs `whirl <args> reference --out <dir>`, expects success and returns summary.json.
fn run(dir: &Path, args: &[&str]) -> Value {
    run_on(&reference_rotor_path(), dir, args)
}

/// Runs `whirl <args> <model> --out <dir>`, expects success and returns summary.json.
fn run_on(model: &Path, dir: &Path, args: &[&str]) -> Value {
    let mut cmd = Command::cargo_bin("whirl").unwrap();
    let output = cmd
        .args(args)
        .arg(model)
        .arg("--out")
        .arg(dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{args:?} failed:\n{stderr}");
    // stderr is not a terminal here: no redrawn progress line (a run that takes longer
    // than progress::LOG_INTERVAL, as the full model does on a loaded machine, logs plain
    // lines, which is what a pipe should get).
    assert!(!stderr.contains('\r'), "{stderr}");
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
        .arg(reference_rotor_path())
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

/// Simulates at 50 Hz (at the first critical speed, the hardest case for settling) with
/// the roller bearings linearised, as `whirl unbalance` has them, and compares the settled
/// 1X of n10 with the frequency-domain response.
fn settled_one_x_matches_unbalance(extra: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let expected = unbalance_at_50hz(&tmp.path().join("unbalance"));
    let mut args = vec![
        "simulate",
        "--contact",
        "linear",
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
        // Within 0.5 %. Modes 1F/1B have 2 % damping at 49.8 Hz, so the transient
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
    // Hertz contacts by default: the model has roller bearings.
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
    assert_eq!(s["contact"], "hertz", "{s}");
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
        "contacts_bearing_a.csv",
        "contacts_bearing_b.csv",
        "contact_line_bearing_a.png",
        "contact_line_bearing_b.svg",
        "contact_zone_bearing_a.png",
        "contact_zone_bearing_b.svg",
    ] {
        assert!(dir.join(file).is_file(), "{file} missing");
    }
    // The default step of the central difference is 0.9 x its stability limit.
    assert!(
        (f(&s["step_s"]) / f(&s["stable_step_s"]) - 0.9).abs() < 1e-12,
        "{s}"
    );
    // The reduced model's step (3.2e-5 s) is above 1e-5 s: every step is recorded.
    assert_eq!(s["record_every"], 1, "{s}");
    // The nodes asked for, then bearing B's node, which a contact law always records.
    let csv = std::fs::read_to_string(dir.join("time_history.csv")).unwrap();
    assert!(
        csv.starts_with("time_s,n10.ux,n10.uy,n0.ux,n0.uy,n20.ux,n20.uy\n"),
        "{}",
        &csv[..60]
    );
    let rows = csv.lines().count() - 1;
    assert_eq!(rows as u64, s["samples"].as_u64().unwrap());
    let columns = 7;

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
        header.contains(&format!("'shape': ({rows}, {columns})")),
        "{header}"
    );
    assert_eq!(npy.len(), data + rows * columns * 8);
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
    assert_eq!(value(columns), second[0]);
    assert_eq!(value(columns + 1), second[1]);
    assert!((value(columns) - f(&s["sample_interval_s"])).abs() < 1e-18);

    // contacts_<bearing>.csv: time, rollers in contact, 8 forces, 8 approaches; as many
    // rows as samples, the forces never negative.
    let contacts = std::fs::read_to_string(dir.join("contacts_bearing_a.csv")).unwrap();
    let mut lines = contacts.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(head.len(), 2 + 2 * 8);
    assert_eq!(head[..3], ["time_s", "in_contact", "roller_0_force_n"]);
    assert_eq!(head[17], "roller_7_approach_m");
    let mut count = 0;
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let touching = v[2..10].iter().filter(|&&q| q > 0.0).count();
        assert!(v[2..10].iter().all(|&q| q >= 0.0), "{line}");
        assert_eq!(v[1], touching as f64, "{line}");
        count += 1;
    }
    assert_eq!(count, rows);
}

#[test]
fn an_unstable_central_difference_step_is_refused_with_the_limit() {
    // docs/theory.md section 6: w_max of the full model is about 5e5 rad/s, so 1e-5 s is unstable.
    fails(
        &[
            "--speed",
            "50Hz",
            "--duration",
            "10ms",
            "--step",
            "1e-5",
            "--contact",
            "linear",
        ],
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
            // The first recorded displacement beyond the bound, named by node and direction:
            // bearing A's node resting on its bottom roller (u_x = 0 there).
            "n0.uy is -2.1",
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
        &["--speed", "50Hz", "--contact", "rigid"],
        &[
            "'rigid'",
            "--contact",
            "possible values: hertz, lagrange, forcing, linear",
        ],
    );
    fails(
        &["--speed", "50Hz", "--record-every", "0"],
        &["--record-every", "whole number, 1 or more"],
    );
    // The reference rotor's bearings have no forcing function.
    fails(
        &["--speed", "50Hz", "--contact", "forcing"],
        &["forcing_function", "whirl fit-forcing"],
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
    fails(
        &["--speed", "50Hz", "--hht-alpha", "-0.1"],
        &["--hht-alpha", "newmark method only"],
    );
    fails(
        &[
            "--speed",
            "50Hz",
            "--method",
            "newmark",
            "--hht-alpha",
            "-0.5",
        ],
        &["--hht-alpha", "outside [-1/3, 0]"],
    );
}

/// Waviness from the command line: the spectrum at each bearing shows the
/// varying-compliance frequency N_b w_c and its outer ring's waviness frequency
/// (N_w - 1) w_c within one FFT bin (crates/whirl/tests/suite/roller_simulation.rs explains
/// the speed and the record length).
#[test]
fn the_spectrum_shows_the_contact_frequencies() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("sim");
    let s = run_on(
        &example_path("reference_rotor_waviness.toml"),
        &dir,
        &[
            "simulate",
            "--speed",
            "20Hz",
            "--duration",
            "4s",
            "--reduce",
            "12",
            "--nodes",
            "10",
        ],
    );
    let bearings = s["bearings"].as_array().unwrap();
    assert_eq!(bearings.len(), 2);
    for (b, order) in bearings.iter().zip([5.0, 10.0]) {
        let cage = f(&b["cage_speed_hz"]);
        // w_c = (1 - D_b/D_p) Omega / 2 with D_b/D_p = 6.1/69.6.
        assert!((cage - 0.5 * (1.0 - 6.1 / 69.6) * 20.0).abs() < 1e-9, "{b}");
        assert!(
            (f(&b["varying_compliance_hz"]) - 8.0 * cage).abs() < 1e-9,
            "{b}"
        );
        assert!(
            (f(&b["waviness_hz"][0]) - (order - 1.0) * cage).abs() < 1e-9,
            "{b}"
        );
        let bin = f(&b["spectrum_resolution_hz"]);
        // 2 s settled: 0.5 Hz bins.
        assert!((bin - 0.5).abs() < 1e-3, "{b}");
        let frequencies = b["frequencies"].as_array().unwrap();
        assert_eq!(frequencies.len(), 2);
        for check in frequencies {
            // The larger peak of the node's u_x and u_y.
            let best = check["measured"]
                .as_array()
                .unwrap()
                .iter()
                .max_by(|x, y| f(&x["amplitude_m"]).total_cmp(&f(&y["amplitude_m"])))
                .unwrap();
            let offset = f(&best["offset_bins"]);
            eprintln!(
                "{} {}: predicted {:.4} Hz, measured {:.4} Hz in {}, {offset:+.3} bins",
                b["name"],
                check["source"],
                f(&check["predicted_hz"]),
                f(&best["frequency_hz"]),
                best["channel"]
            );
            assert!(offset.abs() <= 1.0, "{check}");
        }
        let settled = &b["settled"];
        let penetration = f(&settled["largest_penetration_m"]);
        assert!(penetration > 0.0 && penetration < 1e-5, "{b}");
        let (low, high) = (&settled["min_in_contact"], &settled["max_in_contact"]);
        assert!(
            low.as_u64().unwrap() >= 1 && high.as_u64().unwrap() <= 8,
            "{b}"
        );
    }
}

#[test]
fn a_thinned_run_records_every_nth_step() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("sim");
    let s = run(
        &dir,
        &[
            "simulate",
            "--speed",
            "100Hz",
            "--duration",
            "50ms",
            "--reduce",
            "12",
            "--record-every",
            "4",
        ],
    );
    assert_eq!(s["record_every"], 4, "{s}");
    let interval = f(&s["sample_interval_s"]);
    assert!((interval - 4.0 * f(&s["step_s"])).abs() < 1e-18, "{s}");
    let steps = (0.05 / f(&s["step_s"])).round() as u64;
    assert_eq!(s["samples"].as_u64().unwrap(), steps.div_ceil(4), "{s}");
}

#[test]
fn the_full_model_records_about_every_ten_microseconds() {
    // Its stable step with the Hertz contacts is a few microseconds: by default as many
    // steps as fit in 1e-5 s are one sample.
    let tmp = tempfile::tempdir().unwrap();
    let s = run(
        &tmp.path().join("sim"),
        &["simulate", "--speed", "100Hz", "--duration", "20ms"],
    );
    let every = s["record_every"].as_u64().unwrap();
    let interval = f(&s["sample_interval_s"]);
    assert!(
        every > 1 && interval <= 1e-5 && interval + f(&s["step_s"]) > 1e-5,
        "{s}"
    );
}

#[test]
fn lagrange_contacts_hold_the_rollers_rigid() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("sim");
    let s = run(
        &dir,
        &[
            "simulate",
            "--speed",
            "100Hz",
            "--duration",
            "200ms",
            "--reduce",
            "12",
            "--contact",
            "lagrange",
        ],
    );
    assert_eq!(s["contact"], "lagrange", "{s}");
    for b in s["bearings"].as_array().unwrap() {
        let settled = &b["settled"];
        // No penetration beyond round-off; the multipliers carry the rotor.
        assert!(f(&settled["largest_penetration_m"]) < 1e-13, "{b}");
        assert!(f(&settled["largest_force_n"]) > 50.0, "{b}");
        assert!(settled["max_in_contact"].as_u64().unwrap() >= 1, "{b}");
    }
    assert!(dir.join("contact_zone_bearing_a.png").is_file());
    // Constraints on the central difference's predictor: no other integrator.
    fails(
        &[
            "--speed",
            "100Hz",
            "--duration",
            "10ms",
            "--contact",
            "lagrange",
            "--method",
            "newmark",
        ],
        &["Lagrange-multiplier contacts work with the central difference only"],
    );
}

#[test]
fn a_forcing_function_law_records_approaches_without_roller_forces() {
    let tmp = tempfile::tempdir().unwrap();
    // The reference rotor with a forcing function on both bearings.
    let text = std::fs::read_to_string(reference_rotor_path())
        .unwrap()
        .replace(
        "linear_stiffness = 1e8",
        "linear_stiffness = 1e8\nforcing_function = { a0 = 1.5e9, a1 = 0.0, b0 = 1.15, b1 = 0.0 }",
    );
    let model = tmp.path().join("forcing.toml");
    std::fs::write(&model, text).unwrap();
    let dir = tmp.path().join("sim");
    let s = run_on(
        &model,
        &dir,
        &[
            "simulate",
            "--speed",
            "100Hz",
            "--duration",
            "100ms",
            "--reduce",
            "12",
            "--contact",
            "forcing",
        ],
    );
    assert_eq!(s["contact"], "forcing", "{s}");
    for b in s["bearings"].as_array().unwrap() {
        // One radial law: no roller forces, but the rollers' geometric approach.
        assert!(b["settled"]["largest_force_n"].is_null(), "{b}");
        assert!(f(&b["settled"]["largest_penetration_m"]) > 0.0, "{b}");
    }
    let contacts = std::fs::read_to_string(dir.join("contacts_bearing_a.csv")).unwrap();
    let row: Vec<&str> = contacts.lines().nth(1).unwrap().split(',').collect();
    assert!(row[2..10].iter().all(|c| c.is_empty()), "{row:?}");
    assert!(
        row[10..18].iter().all(|c| c.parse::<f64>().is_ok()),
        "{row:?}"
    );
}
