//! Bad input, end to end: every case exits nonzero, says what is wrong (the field or the
//! cause, and for model files the file:line:column), never panics, and writes nothing.

use assert_cmd::Command;

use crate::reference::{reference_rotor_path, reference_rotor_text};

/// The reference rotor with the first `from` replaced by `to` (which must be there).
fn edited(from: &str, to: &str) -> String {
    let text = reference_rotor_text();
    assert!(text.contains(from), "the reference rotor has no `{from}`");
    text.replacen(from, to, 1)
}

/// Runs whirl with `args` (a `{model}` argument is replaced by the model file written from
/// `model`) and checks the failure: nonzero exit, no panic, every expected text in stderr,
/// no output folder.
fn fails(model: Option<&str>, args: &[&str], expected: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("bad.toml");
    if let Some(text) = model {
        std::fs::write(&file, text).unwrap();
    }
    let out = tmp.path().join("out");
    let mut cmd = Command::cargo_bin("whirl").unwrap();
    for a in args {
        if *a == "{model}" {
            cmd.arg(&file);
        } else {
            cmd.arg(a);
        }
    }
    let output = cmd.arg("--out").arg(&out).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "succeeded: {args:?}\n{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // miette wraps long lines; compare with the wrapping (and its margin bars) undone.
    let flat = flatten(&stderr);
    for e in expected {
        assert!(flat.contains(&flatten(e)), "`{e}` not in:\n{stderr}");
    }
    assert!(!out.exists(), "an output folder was written");
    let leftovers = std::fs::read_dir(tmp.path()).unwrap().count();
    assert!(leftovers <= 1, "temporary files left behind");
}

/// Words separated by single spaces, miette's margin bars left out.
fn flatten(text: &str) -> String {
    text.split_whitespace()
        .filter(|w| *w != "│" && *w != "|")
        .collect::<Vec<_>>()
        .join(" ")
}

/// `whirl check` on a model text.
fn check_fails(model: &str, expected: &[&str]) {
    fails(Some(model), &["check", "{model}"], expected);
}

#[test]
fn malformed_toml() {
    let m = edited("name = \"reference rotor\"", "name = \"reference rotor");
    check_fails(&m, &["bad.toml:4:", "`name`", "invalid basic string"]);
}

#[test]
fn unknown_field_typo() {
    let m = edited(
        "outer_diameter = \"55.9 mm\"",
        "outer_diamter = \"55.9 mm\"",
    );
    check_fails(
        &m,
        &[
            "bad.toml:14:1",
            "unknown field `outer_diamter`",
            "`outer_diameter`",
        ],
    );
}

#[test]
fn wrong_type() {
    let m = edited("elements = 20 ", "elements = \"twenty\" ");
    check_fails(
        &m,
        &["bad.toml:16:12", "`elements`", "expected a whole number"],
    );
}

#[test]
fn negative_length() {
    let m = edited("length = \"1.3 m\"", "length = \"-1.3 m\"");
    check_fails(
        &m,
        &["bad.toml:13:10", "shaft[0].length", "must be positive"],
    );
}

#[test]
fn zero_elements() {
    let m = edited("elements = 20 ", "elements = 0 ");
    check_fails(&m, &["bad.toml:16:", "shaft[0].elements", "from 1 to"]);
}

#[test]
fn bore_not_smaller_than_the_outer_diameter() {
    let m = edited(
        "outer_diameter = \"55.9 mm\"",
        "outer_diameter = \"55.9 mm\"\ninner_diameter = \"60 mm\"",
    );
    check_fails(
        &m,
        &["bad.toml:15:", "shaft[0].inner_diameter", "must be smaller"],
    );
}

#[test]
fn node_outside_the_shaft() {
    let m = edited("node = 10", "node = 25");
    check_fails(&m, &["disk[0].node", "from 0 to 20", "nodes are numbered"]);
}

#[test]
fn z_not_at_a_node() {
    let m = edited("node = 10", "z = \"0.6 m\"");
    check_fails(
        &m,
        &["disk[0].z", "is not at a node", "the nearest node is 9"],
    );
}

#[test]
fn unknown_material() {
    let m = edited("material = \"steel\"", "material = \"stele\"");
    check_fails(
        &m,
        &[
            "shaft[0].material",
            "unknown material `stele`",
            "defined materials: steel",
        ],
    );
}

#[test]
fn infinite_and_nan_quantities() {
    let m = edited("length = \"1.3 m\"", "length = \"inf m\"");
    check_fails(&m, &["shaft[0].length", "not a finite number"]);
    let m = edited(
        "outer_diameter = \"55.9 mm\"",
        "outer_diameter = \"NaN mm\"",
    );
    check_fails(&m, &["shaft[0].outer_diameter", "not a finite number"]);
}

#[test]
fn unknown_unit() {
    let m = edited("clearance = \"20 um\"", "clearance = \"20 furlongs\"");
    check_fails(
        &m,
        &["roller_bearing[0].clearance", "furlongs", "accepted: m, mm"],
    );
}

#[test]
fn disk_without_its_inertia() {
    let m = edited("polar_inertia = 0.05", "");
    check_fails(&m, &["disk[0]", "missing `polar_inertia`"]);
}

#[test]
fn unbalance_without_a_disk_or_mass() {
    let m = edited("[[unbalance]]\nnode = 10", "[[unbalance]]\nnode = 5");
    check_fails(&m, &["unbalance[0]", "no disk at node 5", "give `mass`"]);
}

#[test]
fn roller_larger_than_the_pitch_circle() {
    let m = edited(
        "roller_diameter = \"6.1 mm\"",
        "roller_diameter = \"80 mm\"",
    );
    check_fails(
        &m,
        &[
            "roller_bearing[0].roller_diameter",
            "smaller than the pitch diameter",
        ],
    );
}

#[test]
fn too_many_rollers() {
    let m = edited("rollers = 8", "rollers = 40");
    check_fails(
        &m,
        &[
            "roller_bearing[0].rollers",
            "do not fit",
            "at most 35 rollers fit",
        ],
    );
}

#[test]
fn damping_ratios_that_need_a_negative_coefficient() {
    let m = edited(
        "alpha = 10.5",
        "ratios = [0.01, 0.5]\nfrequencies = [\"10 Hz\", \"100 Hz\"]\n#",
    );
    let m = m.replacen("beta = 2.1e-5", "#", 1);
    check_fails(&m, &["`damping`", "negative coefficient"]);
}

#[test]
fn empty_model() {
    check_fails("", &["`shaft`", "the model has no shaft"]);
}

#[test]
fn missing_file() {
    fails(
        None,
        &["check", "{model}"],
        &["cannot read the model file", "bad.toml"],
    );
}

#[test]
fn bad_speed_ranges() {
    let m = reference_rotor_text();
    let campbell = |range: &str, expected: &[&str]| {
        fails(
            Some(&m),
            &["campbell", "{model}", "--speeds", range],
            expected,
        );
    };
    campbell("0:800Hz", &["--speeds", "three parts"]);
    campbell("800:0Hz:5", &["--speeds", "stop must not be below start"]);
    campbell("0:800furlongs:5", &["--speeds", "furlongs"]);
}

#[test]
fn bad_single_speeds() {
    let m = reference_rotor_text();
    fails(
        Some(&m),
        &["modal", "{model}", "--speed", "20 furlongs"],
        &["--speed", "furlongs"],
    );
    fails(
        Some(&m),
        &["modal", "{model}", "--speed", "inf"],
        &["--speed", "not a finite number"],
    );
    fails(
        Some(&m),
        &["modal", "{model}", "--modes", "0"],
        &["--modes", "from 1 to 200"],
    );
}

#[test]
fn nodes_outside_the_shaft() {
    fails(
        Some(&reference_rotor_text()),
        &[
            "unbalance",
            "{model}",
            "--speeds",
            "1:100Hz:10",
            "--nodes",
            "10,99",
        ],
        &["--nodes", "node 99 is not on the shaft", "0 (z = 0) to 20"],
    );
}

#[test]
fn unbalance_response_of_a_model_without_unbalance() {
    let text = reference_rotor_text();
    let cut = text.find("[[unbalance]]").unwrap();
    let end = text.find("[operating]").unwrap();
    let m = format!("{}{}", &text[..cut], &text[end..]);
    fails(
        Some(&m),
        &["unbalance", "{model}", "--speeds", "1:100Hz:10"],
        &["no [[unbalance]]"],
    );
}

#[test]
fn meshes_that_miss_the_features() {
    fails(
        Some(&reference_rotor_text()),
        &["convergence", "{model}", "--counts", "3,5"],
        &["--counts", "[3, 5]"],
    );
}

#[test]
fn unknown_command() {
    fails(
        Some(&reference_rotor_text()),
        &["frobnicate", "{model}"],
        &["unrecognized subcommand", "frobnicate"],
    );
}

#[test]
fn out_folder_that_is_not_a_whirl_result_is_left_alone() {
    let tmp = tempfile::tempdir().unwrap();
    let docs = tmp.path().join("docs");
    std::fs::create_dir(&docs).unwrap();
    std::fs::write(docs.join("thesis.txt"), "precious").unwrap();
    let output = Command::cargo_bin("whirl")
        .unwrap()
        .arg("check")
        .arg(reference_rotor_path())
        .arg("--out")
        .arg(&docs)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("--out") && stderr.contains("not a whirl output folder"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(docs.join("thesis.txt")).unwrap(),
        "precious"
    );
    assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), 1);
    // Refused before the work, not after it: a cascade announces its default speeds when it
    // starts computing, and must not get that far.
    let output = Command::cargo_bin("whirl")
        .unwrap()
        .arg("cascade")
        .arg(reference_rotor_path())
        .arg("--out")
        .arg(&docs)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("not a whirl output folder") && !stderr.contains("speeds (default)"),
        "{stderr}"
    );
}

// Limits: nothing crashes, nothing runs away, nothing impossible is accepted.

#[test]
fn an_error_past_column_65535_is_located_not_a_panic() {
    // miette cannot draw a label past column 65,535; the message alone locates it.
    let m = format!("name = \"{}\n", "a".repeat(70_000));
    check_fails(&m, &["bad.toml:1:70009:", "invalid basic string"]);
}

#[test]
fn huge_speed_counts_are_refused_before_any_allocation() {
    // 1e10 speeds would be 80 GB before their cap was checked (SIGABRT).
    let huge = "1:750Hz:10000000000";
    for command in ["campbell", "unbalance", "cascade", "fit-forcing"] {
        fails(
            Some(&reference_rotor_text()),
            &[command, "{model}", "--speeds", huge],
            &["at most 100000 values"],
        );
    }
    fails(
        Some(&reference_rotor_text()),
        &["hbm", "{model}", "--speeds", huge],
        &["at most 100000 values"],
    );
    fails(
        Some(&reference_rotor_text()),
        &["hbm", "{model}", "--samples", "1000000000"],
        &["`samples`", "at most 65536"],
    );
    // 1e-8 s makes a speed's longest run (4 s settling + 32 records of 0.5 s overlapping by
    // half, 8.25 s) 1.225e9 steps, beyond the 5e8 a run may take: refused before any speed
    // starts.
    fails(
        Some(&reference_rotor_text()),
        &["cascade", "{model}", "--step", "1e-8s"],
        &[
            "--step",
            "1.000e-8 s steps make 1.225e9 time steps",
            "at most 5e8",
        ],
    );
    // A 1e9 s record is 1e14 samples: its spectrum's plan was a 123 TB allocation
    // (SIGABRT, found by the long fuzz run).
    fails(
        Some(&reference_rotor_text()),
        &["cascade", "{model}", "--record", "1000000000"],
        &["--record", "from 8 to 4194304"],
    );
    // With the default step too: settling up to 1e5 s is some 1e11 steps a speed.
    fails(
        Some(&reference_rotor_text()),
        &["cascade", "{model}", "--settle-max", "100000s"],
        &["--settle-max", "time steps", "at most 5e8"],
    );
    // 200 harmonics would make each point minutes of dense Newton solves: refused at once.
    fails(
        Some(&reference_rotor_text()),
        &["hbm", "{model}", "--harmonics", "200"],
        &["--harmonics", "from 1 to 50"],
    );
    fails(
        Some(&reference_rotor_text()),
        &["hbm", "{model}", "--harmonics-study", "1..60"],
        &["--harmonics-study", "from 1 to 50"],
    );
}

#[test]
fn a_speed_that_overflows_in_rad_per_second_is_an_input_error() {
    // 1e308 Hz is finite, 2 pi 1e308 rad/s is not: refused where it is read, not by the
    // eigen-solver.
    fails(
        Some(&reference_rotor_text()),
        &["modal", "{model}", "--speed", "1e308Hz"],
        &["--speed", "1e308Hz", "is inf rad/s, beyond the 1e7 rad/s"],
    );
    // Finite in rad/s, but far beyond any rotor: it made faer's Schur solver panic.
    fails(
        Some(&reference_rotor_text()),
        &["modal", "{model}", "--speed", "1e308"],
        &["--speed", "beyond the 1e7 rad/s (1.6 MHz) whirl accepts"],
    );
    let m = edited("max_speed = \"750 Hz\"", "max_speed = 1e300");
    check_fails(&m, &["operating.max_speed", "beyond the 1e7 rad/s"]);
}

#[test]
fn a_clearance_larger_than_the_rollers_is_refused() {
    let m = edited("clearance = \"20 um\"", "clearance = \"7 mm\"");
    check_fails(
        &m,
        &[
            "bad.toml:38:",
            "roller_bearing[0].clearance",
            "not smaller than the rollers",
        ],
    );
}

#[test]
fn a_clearance_in_metres_is_refused() {
    // A plain number is SI: `clearance = 20` is 20 m, not 20 um.
    let m = edited("clearance = \"20 um\"", "clearance = 20");
    check_fails(
        &m,
        &[
            "roller_bearing[0].clearance",
            "a clearance of 20 m is not smaller than the rollers",
        ],
    );
}

/// `whirl check` on a model text succeeds; returns its warnings (stderr).
fn check_warnings(model: &str) -> String {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("odd.toml");
    std::fs::write(&file, model).unwrap();
    let output = Command::cargo_bin("whirl")
        .unwrap()
        .arg("check")
        .arg(&file)
        .arg("--out")
        .arg(tmp.path().join("out"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    assert!(output.status.success(), "{stderr}");
    stderr
}

#[test]
fn the_reference_rotor_draws_no_warning() {
    let stderr = check_warnings(&reference_rotor_text());
    assert!(!stderr.contains("warning"), "{stderr}");
}

#[test]
fn a_clearance_of_a_large_part_of_the_rollers_draws_a_warning() {
    // 0.5 mm on 6.1 mm rollers: 8.2 % of them (above 5 %), 0.72 % of the 69.6 mm pitch
    // diameter (below the 1 % that warned before).
    let stderr = check_warnings(&edited("clearance = \"20 um\"", "clearance = \"0.5 mm\""));
    assert!(
        stderr.contains(
            "roller_bearing[0].clearance: 0.0005 m is 8.2 % of the roller diameter and 0.72 % \
             of the pitch diameter"
        ),
        "{stderr}"
    );
    assert!(stderr.contains("\"20 um\""), "{stderr}");
}

#[test]
fn densities_no_engineering_solid_has_draw_a_warning() {
    for (density, shown) in [("1e-3", "0.001"), ("3e4", "30000")] {
        let stderr = check_warnings(&edited("density = 7810", &format!("density = {density}")));
        assert!(
            stderr.contains(&format!(
                "material[0].density: {shown} kg/m^3 (material `steel`) is outside the 100 to \
                 25000 kg/m^3"
            )),
            "{stderr}"
        );
    }
    // The near-massless shaft is named as well: 1e-3 kg/m^3 makes 3.2 mg of shaft.
    let stderr = check_warnings(&edited("density = 7810", "density = 1e-3"));
    assert!(
        stderr.contains("shaft: its mass (0.00000319049 kg)"),
        "{stderr}"
    );
}

#[test]
fn a_clearance_polynomial_negative_at_speed_is_refused() {
    // 20 um at rest, falling 0.1 um per Hz: negative above 200 Hz, inside 1-750 Hz.
    let m = edited(
        "clearance = \"20 um\"",
        "clearance = { coefficients = [20, -0.1], clearance_unit = \"um\", speed_unit = \"Hz\" }",
    );
    check_fails(
        &m,
        &[
            "bad.toml:38:",
            "roller_bearing[0].clearance",
            "must not be negative",
            "Hz",
        ],
    );
}

#[test]
fn waviness_far_above_the_clearance_is_refused() {
    let m = edited(
        "linear_stiffness = 1e8              # N/m, for linear analyses",
        "linear_stiffness = 1e8\nwaviness = [{ ring = \"outer\", order = 5, amplitude = \"5 mm\" }]",
    );
    check_fails(
        &m,
        &["roller_bearing[0].waviness[0].amplitude", "clearance scale"],
    );
}

#[test]
fn a_polar_inertia_above_twice_the_diametral_is_refused() {
    let m = edited("polar_inertia = 0.05", "polar_inertia = 0.06");
    check_fails(
        &m,
        &["bad.toml:26:", "disk[0].polar_inertia", "I_p <= 2 I_d"],
    );
}

#[test]
fn a_contact_exponent_far_from_one_to_two_is_refused() {
    for exponent in ["1e-300", "0.5", "3"] {
        let m = edited(
            "contact_exponent = 1.1111111111111112   # 10/9",
            &format!("contact_exponent = {exponent}   # 10/9"),
        );
        check_fails(
            &m,
            &["bad.toml:40:", "contact_exponent", "must lie in [1, 2]"],
        );
    }
}

#[test]
fn a_forcing_law_negative_at_speed_is_refused() {
    // a = 1e7 - 1e4 W turns negative at W = 1000 rad/s (159 Hz), inside 1-750 Hz.
    let m = edited(
        "linear_stiffness = 1e8              # N/m, for linear analyses",
        "linear_stiffness = 1e8\nforcing_function = { a0 = 1e7, a1 = -1e4, b0 = 1.1, b1 = 0 }",
    );
    check_fails(
        &m,
        &[
            "roller_bearing[0].forcing_function",
            "must stay positive",
            "750 Hz",
        ],
    );
}

#[test]
fn a_rotor_on_one_bearing_or_none_is_refused() {
    let one = edited("node = 20\nrollers", "node = 0\nrollers");
    check_fails(&one, &["`bearing`", "one node only (0)", "free to tilt"]);
    let text = reference_rotor_text();
    let start = text.find("[[roller_bearing]]").unwrap();
    let end = text.find("[damping]").unwrap();
    let none = format!("{}{}", &text[..start], &text[end..]);
    check_fails(&none, &["`bearing`", "no bearing"]);
}

#[test]
fn a_structure_unstable_at_rest_says_so_instead_of_zero_hertz() {
    // Euler buckling of the pinned 1.3 m shaft: pi^2 E I / L^2 = 5.9e5 N; 17 times that in
    // compression makes the stiffness indefinite.
    let m = edited("gyroscopic = true", "gyroscopic = true\naxial_load = -1e7");
    check_fails(&m, &["unstable at rest", "axial_load"]);
}

#[test]
fn a_load_no_bearing_can_carry_is_refused() {
    fails(
        Some(&reference_rotor_text()),
        &["stiffness", "{model}", "--load", "1e30N"],
        &["--load", "more than a tenth of its diameter"],
    );
}

#[test]
fn time_sampled_lengths_are_refused_before_any_allocation() {
    // 10,000 s of the reference rotor at its stable step, every step recorded with the
    // rollers: 2.8e8 samples of 55 series, 120 GB. Refused before the records are made.
    fails(
        Some(&reference_rotor_text()),
        &[
            "simulate",
            "{model}",
            "--speed",
            "100Hz",
            "--duration",
            "10000s",
            "--reduce",
            "12",
        ],
        &["55 series", "at most 268435456", "record less often"],
    );
    // The forcing-function fit marches too: 1e5 s is 2.8e9 steps at the stable step.
    fails(
        Some(&reference_rotor_text()),
        &[
            "fit-forcing",
            "{model}",
            "--speeds",
            "100Hz:200Hz:2",
            "--duration",
            "100000s",
        ],
        &["steps is too many"],
    );
    // The time-marching comparison of harmonic balance (after a short sweep): a 1e9 s
    // record.
    fails(
        Some(&reference_rotor_text()),
        &[
            "hbm",
            "{model}",
            "--speeds",
            "100Hz:110Hz",
            "--no-stability",
            "--compare-time",
            "105Hz",
            "--record",
            "1000000000s",
        ],
        &["steps is too many"],
    );
}

#[test]
fn a_device_or_huge_file_is_refused_not_read_to_the_end() {
    // `/dev/zero` never ends: before the cap it was read until memory ran out.
    fails(
        None,
        &["check", "/dev/zero"],
        &["cannot read the model file", "more than 64 MiB"],
    );
}

#[test]
fn an_error_beside_a_2_mb_line_does_not_echo_it() {
    // The error is on the short line 2; miette shows a line of context on either side, and
    // line 1 is 2 MB long (2,000,285 bytes of stderr before).
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("long.toml");
    std::fs::write(
        &file,
        format!("name = \"{}\"\nfoo = [\n", "x".repeat(2_000_000)),
    )
    .unwrap();
    let output = Command::cargo_bin("whirl")
        .unwrap()
        .arg("check")
        .arg(&file)
        .arg("--out")
        .arg(tmp.path().join("out"))
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("long.toml:3:1"), "{stderr}");
    assert!(stderr.len() < 2_000, "{} bytes of stderr", stderr.len());
}

#[test]
fn a_stiffness_clearance_as_large_as_the_rollers_is_refused() {
    // 6.1 mm is the reference rotor's roller diameter: the rings could not hold them.
    fails(
        Some(&reference_rotor_text()),
        &["stiffness", "{model}", "--clearances", "6.1mm:7mm:2"],
        &["clearance", "not smaller than the rollers"],
    );
}
