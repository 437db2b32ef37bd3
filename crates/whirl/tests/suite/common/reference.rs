//! The reference rotor of docs/theory.md section 9: a 1.3 m shaft in 20 elements, a 10 kg disk
//! at node 10, roller bearings (8 rollers, 20 um clearance) at nodes 0 and 20. The model
//! file is bundled with the library (`whirl::examples::REFERENCE_ROTOR`) and linked from
//! the repository's `examples/` for the command line.

use std::path::{Path, PathBuf};

use whirl::model::{Model, RollerBearing};

/// The validated reference rotor.
pub fn reference_rotor() -> Model {
    Model::from_toml_str(whirl::examples::REFERENCE_ROTOR, None)
        .expect("the bundled reference rotor is valid")
}

/// The reference rotor's first roller bearing (bearing A, node 0): 8 rollers, 20 um
/// clearance, contact damping 200 N s/m per roller, no tilt or waviness.
pub fn reference_bearing() -> RollerBearing {
    reference_rotor().roller_bearings[0].clone()
}

/// A file of the repository's `examples/` folder (the library's and the command line's
/// crates are both two levels below the repository).
pub fn example_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// `examples/reference_rotor.toml`, the file the command line reads.
pub fn reference_rotor_path() -> PathBuf {
    example_path("reference_rotor.toml")
}

/// The text of `examples/reference_rotor.toml`, for edits that the command line then reads.
pub fn reference_rotor_text() -> String {
    std::fs::read_to_string(reference_rotor_path()).expect("examples/reference_rotor.toml")
}

/// The reference rotor's text with its shaft in `elements` elements: the disk and the
/// unbalance at mid-span, the bearings at the ends (the models of BENCHMARKS.md's
/// "Large models").
pub fn reference_rotor_text_meshed(elements: usize) -> String {
    whirl::examples::REFERENCE_ROTOR
        .replace("elements = 20 ", &format!("elements = {elements} "))
        .replace("node = 10", &format!("node = {}", elements / 2))
        .replace("node = 20", &format!("node = {elements}"))
}

/// Asserts that the resonance `fine`, found on the reference rotor refined to thousands of
/// elements (where round-off makes the curve ripple), is the 20-element rotor's `coarse`.
/// The meshes' first critical speeds differ by 1e-4 relative; round-off moves the samples
/// near the top by up to about 1 %, and the curve falls there as (distance / 1 Hz)^2, so the
/// top's place is uncertain by some 0.1 Hz and its height and half-power band by about 1 %.
pub fn assert_same_resonance(
    fine: &whirl::response::ResponsePeak,
    coarse: &whirl::response::ResponsePeak,
) {
    let (p, q) = (fine, coarse);
    assert!(
        (p.speed_hz - q.speed_hz).abs() < 0.15,
        "{} vs {}",
        p.speed_hz,
        q.speed_hz
    );
    assert!(
        (p.amplitude / q.amplitude - 1.0).abs() < 1e-2,
        "{} vs {}",
        p.amplitude,
        q.amplitude
    );
    let (af, af_coarse) = (
        p.amplification_factor.unwrap(),
        q.amplification_factor.unwrap(),
    );
    assert!(
        (af / af_coarse - 1.0).abs() < 3e-2,
        "AF {af} vs {af_coarse}"
    );
}
