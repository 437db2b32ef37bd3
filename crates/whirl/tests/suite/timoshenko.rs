//! Timoshenko beam elements against Timoshenko's closed form for a simply supported,
//! shear-deformable beam with rotary inertia.

use std::f64::consts::PI;

use faer::Mat;
use whirl::fe::{assemble, Bearings, SystemMatrices};
use whirl::modal::undamped_modes;
use whirl::model::{circular_shear_factor, Model};

use crate::common::reference_rotor;

const E: f64 = 2.1e11;
const RHO: f64 = 7800.0;
const NU: f64 = 0.3;
const D: f64 = 0.1;
/// L/d = 5: a short, thick shaft.
const L: f64 = 0.5;

fn beam(theory: &str, elements: usize) -> Model {
    let text = format!(
        r#"
        [[material]]
        name = "steel"
        young_modulus = {E}
        density = {RHO}
        poisson_ratio = {NU}
        [[shaft]]
        length = {L}
        outer_diameter = {D}
        material = "steel"
        elements = {elements}
        [elements]
        beam = "{theory}"
        rotary_inertia = true
        "#
    );
    Model::from_toml_str(&text, None).expect("test model is valid")
}

/// The matrices without the rows and columns of `fixed` DOFs: exact pins, where stiff
/// springs would add an error of their own on so stiff a beam.
fn constrained(s: &SystemMatrices, fixed: &[usize]) -> SystemMatrices {
    let keep: Vec<usize> = (0..s.dofs()).filter(|i| !fixed.contains(i)).collect();
    let pick =
        |m: &Mat<f64>| Mat::<f64>::from_fn(keep.len(), keep.len(), |i, j| m[(keep[i], keep[j])]);
    SystemMatrices {
        mass: pick(&s.mass),
        stiffness: pick(&s.stiffness),
        gyroscopic: pick(&s.gyroscopic),
        damping: pick(&s.damping),
    }
}

/// The first three distinct natural frequencies (Hz) of the pinned-pinned beam.
fn pinned_pinned(model: &Model) -> Vec<f64> {
    let last = model.node_count() - 1;
    // ux and uy of the end nodes: pins in both planes; rotations free.
    let fixed = [0, 1, 4 * last, 4 * last + 1];
    let system = constrained(&assemble(model, Bearings::Linearised), &fixed);
    let modes = undamped_modes(&system, 6).unwrap();
    // The x and y planes give each frequency twice.
    modes.frequencies_hz.chunks(2).map(|p| p[0]).collect()
}

/// Timoshenko's frequency equation for a simply supported beam (Timoshenko 1921).
///
/// With the section rotation beta and the deflection w, free vibration at w (rad/s) obeys
///
/// ```text
/// kappa G A (w'' - beta') + rho A w^2 w = 0
/// E I beta'' + kappa G A (w' - beta) + rho I w^2 beta = 0
/// ```
///
/// Pinned ends (w = 0, moment E I beta' = 0) are met by w = W sin(k z), beta = B cos(k z)
/// with k = n pi / L. Substituting:
///
/// ```text
/// (rho A w^2 - kappa G A k^2) W + kappa G A k B = 0
/// kappa G A k W + (rho I w^2 - E I k^2 - kappa G A) B = 0
/// ```
///
/// and a zero determinant gives a quadratic in w^2:
///
/// ```text
/// rho A rho I w^4 - [rho A (E I k^2 + kappa G A) + rho I kappa G A k^2] w^2 + kappa G A E I k^4 = 0
/// ```
///
/// whose lower root is the bending mode (the upper one is the shear mode). Written as
/// 2c / (b + sqrt(b^2 - 4ac)) to avoid cancellation.
fn timoshenko_closed_form(n: usize) -> f64 {
    let a_area = PI * D * D / 4.0;
    let i = PI * D.powi(4) / 64.0;
    let kga = circular_shear_factor(D, 0.0, NU) * E / (2.0 * (1.0 + NU)) * a_area;
    let k = n as f64 * PI / L;
    let a = RHO * a_area * RHO * i;
    let b = RHO * a_area * (E * i * k * k + kga) + RHO * i * kga * k * k;
    let c = kga * E * i * k.powi(4);
    let w2 = 2.0 * c / (b + (b * b - 4.0 * a * c).sqrt());
    w2.sqrt() / (2.0 * PI)
}

#[test]
fn short_pinned_pinned_beam_matches_timoshenkos_frequency_equation() {
    let fe = pinned_pinned(&beam("timoshenko", 80));
    let euler = pinned_pinned(&beam("euler-bernoulli", 80));
    for n in 1..=3 {
        let exact = timoshenko_closed_form(n);
        let error = fe[n - 1] / exact - 1.0;
        let eb = euler[n - 1] / exact - 1.0;
        println!(
            "mode {n}: closed form {exact:.3} Hz, Timoshenko FE {:.3} Hz ({:+.5} %), \
             Euler-Bernoulli FE {:.3} Hz ({:+.3} %)",
            fe[n - 1],
            100.0 * error,
            euler[n - 1],
            100.0 * eb
        );
        // The bound asked for: 0.1 %. The element solves the static equations exactly; the
        // error is the consistent mass's. In elements much shorter than the diameter (phi
        // = 12 E I / (kappa G A h^2) is about 140 at h = d / 8) the section rotation is
        // interpolated almost linearly and the error falls as h^2: measured for mode 3,
        // 0.32 %, 0.080 %, 0.020 %, 0.005 % with 20, 40, 80, 160 elements. 80 elements
        // leave a factor 5 to the bound.
        assert!(error.abs() < 1e-3, "mode {n}: {error}");
        // Without shear deformation the beam is too stiff: Euler-Bernoulli overestimates
        // each frequency, by more for higher modes (shorter wavelengths). At L/d = 5 the
        // first mode is already several percent high.
        assert!(eb > 0.02, "mode {n}: Euler-Bernoulli only {eb} above");
        if n > 1 {
            assert!(eb > euler[n - 2] / timoshenko_closed_form(n - 1) - 1.0);
        }
    }
}

#[test]
fn euler_bernoulli_stays_the_default() {
    // A model that names no beam theory is the same model as one that asks for
    // Euler-Bernoulli: every number computed before Timoshenko elements existed is kept.
    let text = whirl::examples::REFERENCE_ROTOR;
    let default = Model::from_toml_str(text, None).unwrap();
    let explicit = Model::from_toml_str(
        &text.replace("[elements]\n", "[elements]\nbeam = \"euler-bernoulli\"\n"),
        None,
    )
    .unwrap();
    assert_eq!(default, explicit);
    let timoshenko = Model::from_toml_str(
        &text.replace("[elements]\n", "[elements]\nbeam = \"timoshenko\"\n"),
        None,
    )
    .unwrap();
    assert_ne!(default, timoshenko);
}

#[test]
fn a_section_can_choose_its_own_theory_and_shear_factor() {
    let text = whirl::examples::REFERENCE_ROTOR.replace(
        "elements = 20 ",
        "elements = 20\nbeam = \"timoshenko\"\nshear_factor = 0.5\n#",
    );
    let model = Model::from_toml_str(&text, None).unwrap();
    assert_eq!(model.sections[0].beam.name(), "timoshenko");
    assert_eq!(model.sections[0].shear_factor, 0.5);
    // A softer shear factor lowers the frequencies below the Euler-Bernoulli ones.
    let f = |m: &Model| {
        undamped_modes(&assemble(m, Bearings::Linearised), 4)
            .unwrap()
            .frequencies_hz
    };
    let eb = f(&reference_rotor());
    let t = f(&model);
    assert!(t[2] < eb[2], "{t:?} vs {eb:?}");
}

#[test]
fn an_unknown_beam_theory_is_refused_by_name() {
    let text = whirl::examples::REFERENCE_ROTOR
        .replace("[elements]\n", "[elements]\nbeam = \"rayleigh\"\n");
    let e = Model::from_toml_str(&text, None).unwrap_err().to_string();
    assert!(e.contains("rayleigh") || e.contains("elements.beam"), "{e}");
}
