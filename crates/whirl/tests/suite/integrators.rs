//! Time integrators against closed forms and against the linear
//! unbalance response.

use std::f64::consts::PI;
use std::ops::ControlFlow;

use faer::Mat;
use whirl::bearing::ContactLaw;
use whirl::bearing::LagrangeContacts;
use whirl::fe::SystemMatrices;
use whirl::fe::{assemble, Bearings};
use whirl::force::CubicSpring;
use whirl::progress::Progress;
use whirl::response::unbalance_response;
use whirl::system::{SpeedProfile, System};
use whirl::time::{
    central_difference, central_difference_constrained, newmark, runge_kutta, simulate,
    stable_step, Initial, MarchOptions, Method, NewmarkScheme, Observer, RkTolerances, RunStatus,
    SimulationOptions,
};

use crate::common;
use crate::common::Oscillator;

const M: f64 = 2.0;
const WN: f64 = 2.0 * PI * 10.0;
const ZETA: f64 = 0.05;
const F0: f64 = 3.0;
const W: f64 = 2.0 * PI * 7.0;

fn mat1(x: f64) -> Mat<f64> {
    Mat::from_fn(1, 1, |_, _| x)
}

/// Every integrator of the library as a caller picks it: each [`Method`] (Newmark with and
/// without the HHT dissipation) and the central difference with roller contacts as
/// Lagrange-multiplier constraints.
#[derive(Clone, Copy, Debug)]
enum Integrator {
    Plain(Method),
    /// The central difference with the reference bearing's rollers as constraints on
    /// coordinates [0, 1].
    ConstrainedCentralDifference,
}

impl Integrator {
    /// Marches `problem` from (q0, v0), as [`whirl::time::simulate`] would with this choice.
    fn march(
        self,
        problem: &mut System,
        (q0, v0): (&[f64], &[f64]),
        options: &MarchOptions,
        observe: Observer<'_>,
    ) {
        match self {
            Integrator::Plain(Method::CentralDifference) => {
                central_difference(problem, q0, v0, options, observe).unwrap()
            }
            Integrator::Plain(Method::Newmark(scheme)) => {
                newmark(problem, q0, v0, scheme, options, observe).unwrap()
            }
            Integrator::Plain(Method::RungeKutta(tolerances)) => {
                runge_kutta(problem, q0, v0, &tolerances, options, observe).unwrap();
            }
            Integrator::ConstrainedCentralDifference => {
                let mut contacts =
                    LagrangeContacts::new(&[common::reference_bearing()], vec![0, 1]).unwrap();
                central_difference_constrained(problem, q0, v0, options, &mut contacts, observe)
                    .unwrap()
            }
        }
    }
}

/// Runge-Kutta at a tolerance far below the second-order methods' errors.
const TIGHT: RkTolerances = RkTolerances {
    relative: 1e-10,
    displacement: 1e-14,
    velocity: 1e-12,
};

/// Every [`Method`]: HHT at a light and at the strongest dissipation it allows.
fn every_method() -> [Method; 5] {
    [
        Method::CentralDifference,
        Method::Newmark(NewmarkScheme::AverageAcceleration),
        Method::Newmark(NewmarkScheme::Hht(-0.1)),
        Method::Newmark(NewmarkScheme::Hht(-1.0 / 3.0)),
        Method::RungeKutta(TIGHT),
    ]
}

/// The methods whose step is the step: all but Runge-Kutta.
fn fixed_step_methods() -> impl Iterator<Item = Method> {
    every_method()
        .into_iter()
        .filter(|m| !matches!(m, Method::RungeKutta(_)))
}

/// What a run at step `step` must show against the closed form.
struct Expected {
    integrator: Integrator,
    step: f64,
    /// Largest error allowed at `step`, relative to the initial amplitude.
    error: f64,
    /// The order of accuracy: halving the step divides the error by 2^order. `None` for
    /// Runge-Kutta, whose step is only the output interval (its own steps follow its
    /// tolerance).
    order: Option<f64>,
}

/// The table every integrator is checked against, on the free decay of a damped oscillator
/// at w_n h = 0.063 for 0.5 s. The error is the methods' phase error: the central
/// difference's frequency is w (1 + (w h)^2 / 24), so the error at time t is
/// w t (w h)^2 / 24 e^(-zeta w t) of the initial amplitude, largest at w t = 1 / zeta:
/// (w h)^2 / (24 zeta e) = 1.21e-3; the trapezoidal rule's period error is twice the
/// central difference's, 2.42e-3; HHT lengthens the period further and dissipates, both
/// growing with -alpha and both of second order (Hilber, Hughes and Taylor 1977): 3.04e-3 at
/// alpha = -0.1 and 3.64e-3 at -1/3 here. Each bound is that figure with a 30 % margin (the
/// runs are deterministic; a method off by a term of lower order misses by far). Runge-Kutta
/// at a 1e-10 tolerance gives 2e-9.
fn integrator_table() -> Vec<Expected> {
    let second_order = |integrator, error| Expected {
        integrator,
        step: 1e-3,
        error,
        order: Some(2.0),
    };
    vec![
        second_order(Integrator::Plain(Method::CentralDifference), 1.6e-3),
        second_order(Integrator::ConstrainedCentralDifference, 1.6e-3),
        second_order(
            Integrator::Plain(Method::Newmark(NewmarkScheme::AverageAcceleration)),
            3.2e-3,
        ),
        second_order(
            Integrator::Plain(Method::Newmark(NewmarkScheme::Hht(-0.1))),
            4.0e-3,
        ),
        second_order(
            Integrator::Plain(Method::Newmark(NewmarkScheme::Hht(-1.0 / 3.0))),
            4.8e-3,
        ),
        Expected {
            integrator: Integrator::Plain(Method::RungeKutta(TIGHT)),
            step: 1e-3,
            error: 1e-8,
            order: None,
        },
    ]
}

/// Initial amplitude of the free decay, m: a quarter of the reference bearing's clearance,
/// so the constrained central difference's rollers never touch: what is checked is its
/// march, which must stay the central difference's while no roller is in contact.
const X0: f64 = 5e-6;

/// The oscillator on two coordinates (a journal's x and y, uncoupled), free.
fn free_journal() -> System {
    let one = Oscillator::tuned(M, WN, ZETA);
    let diagonal = |x: f64| Mat::from_fn(2, 2, |i, j| if i == j { x } else { 0.0 });
    System::unloaded(SystemMatrices {
        mass: diagonal(one.mass),
        stiffness: diagonal(one.stiffness),
        damping: diagonal(one.damping),
        gyroscopic: diagonal(0.0),
    })
}

/// The free decay from displacement x0 and velocity v0:
/// x(t) = e^(-zeta w_n t) (x0 cos w_d t + (v0 + zeta w_n x0) / w_d sin w_d t).
fn free_decay(x0: f64, v0: f64, t: f64) -> f64 {
    let wd = WN * (1.0 - ZETA * ZETA).sqrt();
    (-ZETA * WN * t).exp() * (x0 * (wd * t).cos() + (v0 + ZETA * WN * x0) / wd * (wd * t).sin())
}

/// Largest error over 0.5 s of free decay at step `h`, relative to `X0`: x starts
/// displaced, y starts moving, a near-circular orbit of radius `X0`.
fn free_decay_error(integrator: Integrator, h: f64) -> f64 {
    let (q0, v0) = ([X0, 0.0], [0.0, X0 * WN]);
    let options = MarchOptions {
        speed: SpeedProfile::Constant(2.0 * PI * 50.0),
        step: h,
        steps: (0.5 / h).round() as usize + 1,
        divergence_bound: 1.0,
    };
    let mut worst = 0.0f64;
    let mut observe = |t: f64, q: &[f64], _: &[f64]| {
        for k in 0..2 {
            let exact = free_decay(q0[k], v0[k], t);
            worst = worst.max((q[k] - exact).abs() / X0);
        }
        ControlFlow::Continue(())
    };
    integrator.march(&mut free_journal(), (&q0, &v0), &options, &mut observe);
    worst
}

#[test]
fn every_integrator_follows_the_free_decay_to_its_order() {
    let table = integrator_table();
    // Every method is in the table, and the constrained central difference.
    for method in every_method() {
        assert!(
            table
                .iter()
                .any(|e| matches!(e.integrator, Integrator::Plain(m) if m == method)),
            "{method:?} missing"
        );
    }
    for Expected {
        integrator,
        step,
        error,
        order,
    } in table
    {
        let e = free_decay_error(integrator, step);
        assert!(e < error, "{integrator:?}: error {e:e} at h = {step}");
        if let Some(p) = order {
            // Halving the step: the error at w h = 0.03 and 0.06 is deep in the asymptotic
            // range (the next term is (w h)^2 smaller; measured within 1e-3 of p), so 0.1
            // is a wide margin, while a first-order method or start procedure gives 1.
            let observed = (e / free_decay_error(integrator, step / 2.0)).log2();
            assert!(
                (observed - p).abs() < 0.1,
                "{integrator:?}: order {observed} (expected {p})"
            );
        }
    }
}

/// Steady state X = F0 / (k - m W^2 + i c W), as (amplitude, phase).
fn closed_form() -> (f64, f64) {
    let x = Oscillator::tuned(M, WN, ZETA).steady_state(F0, W);
    (x.norm(), x.arg())
}

/// m x'' + c x' + k x = F0 cos(W t), written as an "unbalance" F0 / W^2 turning at W.
fn oscillator() -> System {
    System {
        unbalance_re: vec![F0 / (W * W)],
        ..Oscillator::tuned(M, WN, ZETA).system()
    }
}

/// Least-squares fit of a + b cos(w t) + c sin(w t): (amplitude, phase of cos(w t + phase)).
fn harmonic_fit(t: &[f64], x: &[f64], w: f64) -> (f64, f64) {
    let basis = |ti: f64| [1.0, (w * ti).cos(), (w * ti).sin()];
    let mut ata = [[0.0; 3]; 3];
    let mut atb = [0.0; 3];
    for (&ti, &xi) in t.iter().zip(x) {
        let b = basis(ti);
        for i in 0..3 {
            atb[i] += b[i] * xi;
            for j in 0..3 {
                ata[i][j] += b[i] * b[j];
            }
        }
    }
    let a = Mat::from_fn(3, 3, |i, j| ata[i][j]);
    let mut rhs = Mat::from_fn(3, 1, |i, _| atb[i]);
    faer::linalg::solvers::Solve::solve_in_place(&a.partial_piv_lu(), rhs.as_mut());
    let (c, s) = (rhs[(1, 0)], rhs[(2, 0)]);
    // c cos + s sin = A cos(w t + phase) with A cos(phase) = c, -A sin(phase) = s.
    ((c * c + s * s).sqrt(), (-s).atan2(c))
}

/// Runs an integrator from the exact steady state for 2 s and fits the last second:
/// (relative amplitude error, phase error).
fn steady_error(method: Method, h: f64) -> (f64, f64) {
    let (amp, phase) = closed_form();
    let q0 = [amp * phase.cos()];
    let v0 = [-amp * W * phase.sin()];
    let options = MarchOptions {
        speed: SpeedProfile::Constant(W),
        step: h,
        steps: (2.0 / h).round() as usize,
        divergence_bound: 1.0,
    };
    let (mut t, mut x) = (Vec::new(), Vec::new());
    let mut observe = |ti: f64, q: &[f64], _: &[f64]| {
        if ti >= 1.0 {
            t.push(ti);
            x.push(q[0]);
        }
        ControlFlow::Continue(())
    };
    Integrator::Plain(method).march(&mut oscillator(), (&q0, &v0), &options, &mut observe);
    let (a, ph) = harmonic_fit(&t, &x, W);
    ((a - amp).abs() / amp, (ph - phase).abs())
}

#[test]
fn every_integrator_reaches_the_closed_form_steady_state() {
    for method in every_method() {
        let (amp_err, phase_err) = steady_error(method, 1e-3);
        // Second-order methods at w h = 0.06: errors of order (w h)^2 / 12 = 3e-4, so 2e-3
        // leaves room (HHT's dissipation, a forced response's amplitude error, is of the
        // same order); Runge-Kutta at a 1e-10 tolerance is far tighter.
        let tol = match method {
            Method::RungeKutta(_) => 1e-8,
            _ => 2e-3,
        };
        assert!(amp_err < tol, "{method:?}: amplitude error {amp_err:e}");
        assert!(phase_err < tol, "{method:?}: phase error {phase_err:e}");
    }
}

#[test]
fn every_fixed_step_method_converges_to_the_steady_state_at_second_order() {
    for method in fixed_step_methods() {
        let (e1, p1) = steady_error(method, 2e-3);
        let (e2, p2) = steady_error(method, 1e-3);
        // Halving the step divides both errors by four for a second-order method; the fit
        // and the leftover transient blur that a little, hence 3 to 5, for the amplitude
        // and for the phase alike.
        let (ra, rp) = (e1 / e2, p1 / p2);
        assert!(
            (3.0..5.0).contains(&ra) && (3.0..5.0).contains(&rp),
            "{method:?}: ratios {ra} {rp} ({e1:e} {e2:e} {p1:e} {p2:e})"
        );
    }
}

#[test]
fn undamped_free_vibration_conserves_energy() {
    let model = common::reference_rotor();
    let mut sys = assemble(&model, Bearings::Linearised);
    sys.damping = Mat::zeros(84, 84);
    let cb = whirl::reduce::CraigBampton::new(&sys, &whirl::reduce::boundary_dofs(&model, &[]), 12)
        .unwrap();
    let r = &cb.reduced;
    let n = cb.size();
    let energy = |q: &[f64], v: &[f64]| {
        let mut e = 0.0;
        for i in 0..n {
            for j in 0..n {
                e += 0.5 * (r.mass[(i, j)] * v[i] * v[j] + r.stiffness[(i, j)] * q[i] * q[j]);
            }
        }
        e
    };
    // Start from the static sag under gravity, spinning at 100 Hz (gyroscopic forces do no work).
    let g = cb.reduce_vector(&whirl::fe::gravity_force(&model, &sys));
    let mut q0 = Mat::from_fn(n, 1, |i, _| g[i]);
    faer::linalg::solvers::Solve::solve_in_place(&r.stiffness.partial_piv_lu(), q0.as_mut());
    let q0: Vec<f64> = (0..n).map(|i| q0[(i, 0)]).collect();
    let v0 = vec![0.0; n];
    let e0 = energy(&q0, &v0);
    let newmark_rule = Method::Newmark(NewmarkScheme::AverageAcceleration);
    for (method, h, tol) in [
        (Method::CentralDifference, 1e-5, 1e-2),
        (newmark_rule, 1e-4, 1e-10),
    ] {
        let mut problem = System::unloaded(SystemMatrices {
            mass: r.mass.clone(),
            stiffness: r.stiffness.clone(),
            damping: Mat::zeros(n, n),
            gyroscopic: r.gyroscopic.clone(),
        });
        let mut worst = 0.0f64;
        let mut observe = |_: f64, q: &[f64], v: &[f64]| {
            worst = worst.max((energy(q, v) - e0).abs() / e0);
            ControlFlow::Continue(())
        };
        let options = MarchOptions {
            speed: SpeedProfile::Constant(2.0 * PI * 100.0),
            step: h,
            steps: (0.2 / h) as usize,
            divergence_bound: 1.0,
        };
        Integrator::Plain(method).march(&mut problem, (&q0, &v0), &options, &mut observe);
        // The trapezoidal rule conserves the energy of a linear system exactly (round-off
        // only). The central difference conserves a modified energy: the plain one
        // oscillates by O((w_max h)^2) without drifting; w_max h = 0.45 here, and the
        // central velocity makes the measured swing about 1e-3.
        assert!(worst < tol, "{method:?}: energy error {worst:e}");
    }
}

fn reference_simulation(method: Method, step: f64, reduction: Option<usize>) -> f64 {
    let model = common::reference_rotor();
    let options = SimulationOptions {
        speed: SpeedProfile::Constant(2.0 * PI * 100.0),
        duration: 2.0,
        step: Some(step),
        method,
        reduction,
        settle: Some(1.5),
        nodes: Some(vec![10]),
        initial: Initial::StaticEquilibrium,
        divergence_bound: 1.0,
        contact: Some(ContactLaw::Linear),
        record_every: Some(1),
        record_rollers: true,
        progress: None,
    };
    let r = simulate(&model, &options).unwrap().completed().unwrap();
    let start = r.settled_start();
    let x = &r.channels[0].values[start..];
    harmonic_fit(&r.time[start..], x, 2.0 * PI * 100.0).0
}

#[test]
fn settled_unbalance_response_matches_the_frequency_domain() {
    let model = common::reference_rotor();
    let sys = assemble(&model, Bearings::Linearised);
    let linear = unbalance_response(&model, &sys, &[2.0 * PI * 100.0], &[10]).unwrap();
    let expected = linear.nodes[0].ux_amplitude[0];
    for (method, step, reduction) in [
        (
            Method::Newmark(NewmarkScheme::AverageAcceleration),
            1e-4,
            None,
        ),
        (Method::CentralDifference, 1e-5, Some(12)),
    ] {
        let a = reference_simulation(method, step, reduction);
        // Within 0.5 %. The transient from the static start has decayed to 1e-4
        // after 1.5 s at 2 % damping, and the reduction error at 100 Hz is ~1e-6.
        let err = (a - expected).abs() / expected;
        assert!(
            err < 5e-3,
            "{}: {a:e} vs {expected:e} ({err:e})",
            method.name()
        );
    }
}

#[test]
fn an_unstable_central_difference_step_is_refused() {
    let model = common::reference_rotor();
    let options = SimulationOptions {
        speed: SpeedProfile::Constant(2.0 * PI * 50.0),
        duration: 0.01,
        step: Some(1e-5),
        method: Method::CentralDifference,
        reduction: None,
        settle: Some(0.0),
        nodes: Some(vec![10]),
        initial: Initial::Rest,
        divergence_bound: 1.0,
        contact: Some(ContactLaw::Linear),
        record_every: Some(1),
        record_rollers: true,
        progress: None,
    };
    let e = simulate(&model, &options).unwrap_err().to_string();
    // docs/theory.md section 6: w_max is about 5e5 rad/s for the full model, so the limit
    // is ~4e-6 s.
    assert!(e.contains("stability limit 3.94"), "{e}");
    assert!(e.contains("reduce the model"), "{e}");
}

#[test]
fn stable_step_is_the_limit_the_simulation_reports_and_progress_is_told() {
    let model = common::reference_rotor();
    let reports = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
    let seen = reports.clone();
    for reduction in [None, Some(12)] {
        let limit = stable_step(&model, reduction, ContactLaw::Linear).unwrap();
        let options = SimulationOptions {
            speed: SpeedProfile::Constant(2.0 * PI * 50.0),
            duration: 0.02,
            step: Some(0.9 * limit),
            method: Method::CentralDifference,
            reduction,
            settle: Some(0.0),
            nodes: Some(vec![10]),
            initial: Initial::StaticEquilibrium,
            divergence_bound: 1.0,
            contact: Some(ContactLaw::Linear),
            record_every: Some(1),
            record_rollers: true,
            progress: Some(Progress::new({
                let seen = seen.clone();
                move |r| {
                    seen.lock().unwrap().push(r.fraction());
                    ControlFlow::Continue(())
                }
            })),
        };
        let r = simulate(&model, &options).unwrap().completed().unwrap();
        // The same matrices, the same eigenvalue solve: equal to the last bit.
        assert_eq!(limit, r.stable_step, "{reduction:?}");
    }
    let reports = reports.lock().unwrap();
    // Two runs of about 5600 and 500 steps: at most a thousand reports each, rising from 0 to
    // within one step of the end.
    assert!(
        reports.len() > 100 && reports.len() <= 2000,
        "{}",
        reports.len()
    );
    assert_eq!(reports[0], 0.0);
    let last = reports[reports.len() - 1];
    assert!(last > 0.99 && last <= 1.0, "{last}");
}

#[test]
fn a_progress_that_says_stop_ends_the_run_there() {
    let model = common::reference_rotor();
    let options = SimulationOptions {
        duration: 0.02,
        reduction: Some(12),
        contact: Some(ContactLaw::Linear),
        record_every: Some(1),
        progress: Some(Progress::new(|r| {
            if r.fraction() >= 0.5 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })),
        ..SimulationOptions::new(SpeedProfile::Constant(2.0 * PI * 50.0))
    };
    let r = simulate(&model, &options).unwrap();
    // Reports come every 1/1000 of the run: the first at or past half the duration stops
    // it, and nothing after it is recorded.
    let RunStatus::Stopped { time } = r.status else {
        panic!("{:?}", r.status)
    };
    assert!((0.01..0.01 + 2e-5 + r.step).contains(&time), "{time}");
    assert!(
        r.time.last().is_some_and(|&t| t < time),
        "{:?}",
        r.time.last()
    );
    assert!(matches!(r.completed(), Err(whirl::Error::Interrupted(_))));
}

#[test]
fn integrators_agree_on_a_duffing_oscillator() {
    let run = |method: Method, h: f64| {
        let mut p = oscillator();
        p.matrices.stiffness = mat1(0.0);
        p.nonlinear.push(Box::new(CubicSpring::new(
            0,
            M * WN * WN,
            4e5 * M * WN * WN,
            0.05,
        )));
        let options = MarchOptions {
            speed: SpeedProfile::Constant(W),
            step: h,
            steps: (1.0 / h).round() as usize,
            divergence_bound: 1.0,
        };
        // Compare at t = 0.5 s, a time every step size lands on.
        let mut last = 0.0;
        let mut observe = |t: f64, q: &[f64], _: &[f64]| {
            if (t - 0.5).abs() < 0.25 * h {
                last = q[0];
            }
            ControlFlow::Continue(())
        };
        Integrator::Plain(method).march(&mut p, (&[0.0], &[0.0]), &options, &mut observe);
        last
    };
    let reference = run(Method::RungeKutta(RkTolerances::default()), 1e-3);
    for method in fixed_step_methods() {
        let x = run(method, 1e-4);
        // Second order at w h ~ 0.007 over 10 periods: phase error ~ 1e-4 of the amplitude.
        assert!(
            (x - reference).abs() < 2e-3 * reference.abs().max(1e-4),
            "{method:?}: {x} vs {reference}"
        );
    }
}

#[test]
fn divergence_is_reported_with_its_time() {
    let mut p = oscillator();
    p.matrices.stiffness = mat1(-M * WN * WN);
    let options = MarchOptions {
        speed: SpeedProfile::Constant(W),
        step: 1e-3,
        steps: 10_000,
        divergence_bound: 1e-2,
    };
    let e = newmark(
        &mut p,
        &[1e-4],
        &[0.0],
        NewmarkScheme::AverageAcceleration,
        &options,
        &mut |_, _, _| ControlFlow::Continue(()),
    )
    .unwrap_err();
    match e {
        whirl::Error::Diverged { time, .. } => assert!(time > 0.0 && time < 10.0),
        other => panic!("expected divergence, got {other}"),
    }
}
