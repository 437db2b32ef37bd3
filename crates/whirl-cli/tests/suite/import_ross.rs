//! `whirl import-ross`: a ROSS rotor file becomes a whirl model that the other commands
//! take, with ROSS's frequencies; what whirl cannot represent is refused with exit 1.

use std::path::{Path, PathBuf};

use assert_cmd::Command;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../whirl/tests/fixtures/ross")
        .join(name)
}

#[test]
fn a_ross_rotor_becomes_a_model_the_other_commands_take() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("import");
    let run = Command::cargo_bin("whirl")
        .unwrap()
        .args(["import-ross"])
        .arg(fixture("rotor_example_eb.toml"))
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(run.status.success(), "{run:?}");
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    // ROSS's first frequency of this file (frequencies.json beside it), to round-off.
    let first = summary["frequencies_hz"][0].as_f64().unwrap();
    assert!((first - 14.618255159712845).abs() < 1e-6, "{first}");
    let check = Command::cargo_bin("whirl")
        .unwrap()
        .arg("check")
        .arg(out.join("model.toml"))
        .arg("--out")
        .arg(tmp.path().join("check"))
        .output()
        .unwrap();
    assert!(check.status.success(), "{check:?}");
}

#[test]
fn a_rotor_with_speed_dependent_bearings_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("import");
    let run = Command::cargo_bin("whirl")
        .unwrap()
        .arg("import-ross")
        .arg(fixture("compressor_example.toml"))
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(1), "{run:?}");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("ROSS element"), "{stderr}");
    assert!(!out.exists());
}
