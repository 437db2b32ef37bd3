//! Models written by ROSS (`Rotor.save`) read by whirl: the undamped natural frequencies of
//! the translated model equal the ones ROSS computed for the same file.
//!
//! The fixtures in tests/fixtures/ross were written by ROSS 2.3.0 itself; `make_fixtures.py`
//! beside them is the script (and its docstring the command) that made them, with ROSS's
//! frequencies in `<name>.frequencies.json`. `rotor_example_with_damping_ross3.toml` was
//! written by ROSS 3.1.0 (`make_ross3_fixture.py`), its damped modes held below. ROSS is not
//! needed to run these tests.

use std::path::PathBuf;

use whirl::fe::{assemble, Bearings};
use whirl::modal::{complex_modes, undamped_modes};
use whirl::model::ross::from_ross_toml;
use whirl::model::Model;
use whirl::Error;

fn fixture(name: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/ross")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn ross_frequencies(name: &str) -> Vec<f64> {
    let json: serde_json::Value =
        serde_json::from_str(&fixture(&format!("{name}.frequencies.json"))).unwrap();
    json["frequencies_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}

/// The first frequencies of the ROSS file `name` from whirl, and ROSS's own.
fn both(name: &str) -> (Vec<f64>, Vec<f64>) {
    let import = from_ross_toml(&fixture(&format!("{name}.toml")), name).unwrap();
    let model =
        Model::from_toml_str(&import.toml, None).unwrap_or_else(|e| panic!("{e}\n{}", import.toml));
    let ross = ross_frequencies(name);
    let whirl = undamped_modes(&assemble(&model, Bearings::Linearised), ross.len())
        .unwrap()
        .frequencies_hz;
    (whirl, ross)
}

/// Both codes build the same element matrices (consistent mass with rotary inertia from
/// the cubic shape functions; Timoshenko with Cowper's coefficient) and solve the same
/// symmetric eigenproblem in double precision, so they agree to round-off. Measured: 1e-13
/// to 1e-11 on ROSS's rotor_example (both forms); up to 2.0e-9 on the damped example, whose
/// 1-cm elements make the stiffest modes 1e10 times the first (ROSS's own two eigen-solvers
/// differ there by 2.3e-9 on the same file). 1e-7 leaves that margin, and a modelling
/// difference (Euler-Bernoulli against Timoshenko is 0.06-0.6 % here) would show ten
/// thousand times over.
const ROUND_OFF: f64 = 1e-7;

fn assert_same(name: &str) {
    let (whirl, ross) = both(name);
    assert_eq!(whirl.len(), ross.len());
    for (i, (w, r)) in whirl.iter().zip(&ross).enumerate() {
        let error = (w - r).abs() / r;
        println!(
            "{name} mode {}: whirl {w} Hz, ROSS {r} Hz ({error:.1e})",
            i + 1
        );
        assert!(
            error < ROUND_OFF,
            "{name} mode {}: whirl {w} Hz, ROSS {r} Hz ({error:.1e})",
            i + 1
        );
    }
}

#[test]
fn ross_rotor_example_with_euler_bernoulli_elements() {
    assert_same("rotor_example_eb");
}

#[test]
fn ross_rotor_example_with_timoshenko_elements() {
    assert_same("rotor_example");
}

#[test]
fn ross_rotor_example_with_damping_and_33_elements_of_several_lengths() {
    assert_same("rotor_example_with_damping");
    let import = from_ross_toml(
        &fixture("rotor_example_with_damping.toml"),
        "rotor_example_with_damping",
    )
    .unwrap();
    // Its shaft elements' proportional damping becomes the rotor's, with a note.
    assert!(
        import.notes.iter().any(|n| n.contains("also acts on")),
        "{:?}",
        import.notes
    );
}

#[test]
fn what_whirl_cannot_represent_is_refused_naming_the_element() {
    // ROSS's compressor has seals and bearings whose coefficients vary with frequency.
    let refused = from_ross_toml(&fixture("compressor_example.toml"), "compressor");
    match refused {
        Err(Error::Input(e)) => {
            assert!(e.message.contains("ROSS element `"), "{}", e.message);
            assert!(
                e.message.contains("SealElement") || e.message.contains("varying with frequency"),
                "{}",
                e.message
            );
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
    let tapered = fixture("rotor_example_eb.toml").replacen("idr = 0.0", "idr = 0.01", 1);
    match from_ross_toml(&tapered, "tapered") {
        Err(Error::Input(e)) => assert!(
            e.message.contains("Shaft Element 0") && e.message.contains("tapered"),
            "{}",
            e.message
        ),
        other => panic!("expected a refusal, got {other:?}"),
    }
}

/// ROSS's damped lateral modes of rotor_example_with_damping_ross3.toml, (damped frequency
/// Hz, damping ratio), at rest and at 500 rad/s: printed by `make_ross3_fixture.py` beside the
/// fixture with ROSS 3.1.0 (Python 3.13), `Rotor.load(...).run_modal(speed, num_modes=24)`,
/// the first six modes whose `mode_type` is "Lateral".
const ROSS3_DAMPED_MODES: [(f64, [(f64, f64); 6]); 2] = [
    (
        0.0,
        [
            (28.921959412620417, 0.02387301010525878),
            (29.844745382662744, 0.022340730265892707),
            (85.9124020797667, 0.015843528264990865),
            (92.5896455948164, 0.009411859179477048),
            (152.72992706657766, 0.0235269982688158),
            (157.4193679561983, 0.007818701912669033),
        ],
    ),
    (
        500.0,
        [
            (28.53854394767734, 0.02347685544377559),
            (30.201308706155903, 0.022694188109210405),
            (85.64115118493181, 0.01569682090249031),
            (92.69966398456896, 0.009559416284331974),
            (151.5418668409032, 0.021296608244568593),
            (158.05132957293873, 0.010001745172182346),
        ],
    ),
];

/// ROSS 3 saves the rotor's Rayleigh damping (`Rotor(alpha=8.0501, beta=1e-5)`) in
/// `[parameters]`; read as whirl's `[damping]`, the damped modes are ROSS's. Both codes solve
/// the same quadratic eigenproblem in double precision: measured 1.7e-9 at most in frequency
/// and 5.3e-8 in damping ratio (the highest mode at 500 rad/s). The 1e-6 bound is the goal
/// the translation is held to, and leaves that round-off of the stiff 1-cm elements a margin, while a dropped damping (0.1 % against 2.4 %
/// in the first mode) or ROSS 2's element damping (which misses the disks) fails at once.
#[test]
fn ross3_rotor_damping_gives_ross_damped_modes() {
    let import = from_ross_toml(
        &fixture("rotor_example_with_damping_ross3.toml"),
        "rotor_example_with_damping",
    )
    .unwrap();
    assert!(
        import.notes.iter().any(|n| n.contains("rotor damping")),
        "{:?}",
        import.notes
    );
    let model = Model::from_toml_str(&import.toml, None).unwrap();
    let system = assemble(&model, Bearings::Linearised);
    for (speed, ross) in ROSS3_DAMPED_MODES {
        // Spinning, whirl also finds a critically damped pair (zeta 0.99999999 at 1.8 Hz,
        // 500 rad/s) that ROSS's lateral modes leave out: no vibration mode.
        let modes: Vec<_> = complex_modes(&system, speed)
            .unwrap()
            .into_iter()
            .filter(|m| m.damping_ratio < 0.5)
            .collect();
        for (i, (mode, (frequency, ratio))) in modes.iter().zip(ross).enumerate() {
            let df = (mode.damped_frequency_hz - frequency).abs() / frequency;
            let dz = (mode.damping_ratio - ratio).abs() / ratio;
            println!(
                "{speed} rad/s mode {}: {} Hz ({df:.1e}), zeta {} ({dz:.1e})",
                i + 1,
                mode.damped_frequency_hz,
                mode.damping_ratio
            );
            assert!(df < 1e-6 && dz < 1e-6, "{speed} rad/s mode {}", i + 1);
        }
    }
}

#[test]
fn ross3_parameters_whirl_does_not_read_are_named() {
    let text = fixture("rotor_example_with_damping_ross3.toml").replacen(
        "[parameters]\n",
        "[parameters]\nrated_w = 300.0\nmin_w = 100.0\nmax_w = 400.0\nnew_thing = 1\n",
        1,
    );
    let import = from_ross_toml(&text, "rotor").unwrap();
    for named in ["rated_w", "new_thing"] {
        assert!(
            import.notes.iter().any(|n| n.contains(named)),
            "{named}: {:?}",
            import.notes
        );
    }
    assert!(
        import
            .toml
            .contains("[operating]\nmin_speed = 100.0\nmax_speed = 400.0"),
        "{}",
        import.toml
    );
    let modal = text.replacen(
        "[parameters]\n",
        "[parameters]\nmodal_damping_ratio = [0.01]\n",
        1,
    );
    assert!(from_ross_toml(&modal, "rotor").is_err());
}

#[test]
fn a_missing_kyy_is_kxx_as_in_ross_not_zero() {
    // ROSS's BearingElement defaults kyy (cyy) to kxx (cxx); read as 0, the bearing let the
    // rotor fall freely in y. Exact: the value is copied, not computed.
    let text = fixture("rotor_example.toml").replace("kyy = [ 800000.0,]\n", "");
    let import = from_ross_toml(&text, "rotor_example").unwrap();
    let model = Model::from_toml_str(&import.toml, None).unwrap();
    assert!(!model.bearings.is_empty());
    for b in &model.bearings {
        assert_eq!(b.stiffness[1][1], b.stiffness[0][0], "{}", b.name);
    }
}
