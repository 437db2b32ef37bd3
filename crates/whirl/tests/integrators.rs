//! Time integrators against closed forms and against the linear
//! unbalance response.

use std::f64::consts::PI;
use std::ops::ControlFlow;

use faer::Mat;
use whirl::bearing::ContactLaw;
use whirl::fe::SystemMatrices;
use whirl::fe::{assemble, Bearings};
use whirl::force::CubicSpring;
use whirl::progress::Progress;
use whirl::response::unbalance_response;
use whirl::system::{SpeedProfile, System};
use whirl::time::{
    central_difference, newmark, runge_kutta, simulate, stable_step, Initial, MarchOptions, Method,
    NewmarkScheme, RkTolerances, RunStatus, SimulationOptions,
};

mod common;
use common::Oscillator;

const M: f64 = 2.0;
const WN: f64 = 2.0 * PI * 10.0;
const ZETA: f64 = 0.05;
const F0: f64 = 3.0;
const W: f64 = 2.0 * PI * 7.0;

fn mat1(x: f64) -> Mat<f64> {
    Mat::from_fn(1, 1, |_, _| x)
}

/// m x'' + c x' + k x = F0 cos(W t), written as an "unbalance" F0 / W^2 turning at W.
fn oscillator() -> System {
    System {
        unbalance_re: vec![F0 / (W * W)],
        ..Oscillator::tuned(M, WN, ZETA).system()
    }
}

/// Steady state X = F0 / (k - m W^2 + i c W), as (amplitude, phase).
fn closed_form() -> (f64, f64) {
    let x = Oscillator::tuned(M, WN, ZETA).steady_state(F0, W);
    (x.norm(), x.arg())
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

/// Runs an integrator from the exact steady state for 2 s and fits the last second.
fn steady_error(method: &str, h: f64) -> (f64, f64) {
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
    let mut p = oscillator();
    match method {
        "cd" => central_difference(&mut p, &q0, &v0, &options, &mut observe).unwrap(),
        "newmark" => newmark(
            &mut p,
            &q0,
            &v0,
            NewmarkScheme::AverageAcceleration,
            &options,
            &mut observe,
        )
        .unwrap(),
        _ => {
            let tol = RkTolerances {
                relative: 1e-10,
                displacement: 1e-14,
                velocity: 1e-12,
            };
            runge_kutta(&mut p, &q0, &v0, &tol, &options, &mut observe).unwrap();
        }
    }
    let (a, ph) = harmonic_fit(&t, &x, W);
    ((a - amp).abs() / amp, (ph - phase).abs())
}

#[test]
fn every_integrator_reaches_the_closed_form_steady_state() {
    for (method, h, tol) in [
        ("cd", 1e-3, 2e-3),
        ("newmark", 1e-3, 2e-3),
        ("rk", 1e-3, 1e-8),
    ] {
        let (amp_err, phase_err) = steady_error(method, h);
        // Second-order methods at w h = 0.06: errors of order (w h)^2 / 12 = 3e-4, so 2e-3
        // leaves room; Runge-Kutta at a 1e-10 tolerance is far tighter.
        assert!(amp_err < tol, "{method}: amplitude error {amp_err:e}");
        assert!(phase_err < tol, "{method}: phase error {phase_err:e}");
    }
}

#[test]
fn central_difference_and_newmark_are_second_order() {
    for method in ["cd", "newmark"] {
        let (e1, p1) = steady_error(method, 2e-3);
        let (e2, p2) = steady_error(method, 1e-3);
        // Halving the step divides the error by four for a second-order method; the fit and
        // the leftover transient blur that a little, hence 3 to 5.
        let (ra, rp) = (e1 / e2, p1 / p2);
        assert!(
            (3.0..5.0).contains(&ra) || (3.0..5.0).contains(&rp),
            "{method}: ratios {ra} {rp} ({e1:e} {e2:e} {p1:e} {p2:e})"
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
    for (method, h, tol) in [("cd", 1e-5, 1e-2), ("newmark", 1e-4, 1e-10)] {
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
        match method {
            "cd" => central_difference(&mut problem, &q0, &v0, &options, &mut observe).unwrap(),
            _ => newmark(
                &mut problem,
                &q0,
                &v0,
                NewmarkScheme::AverageAcceleration,
                &options,
                &mut observe,
            )
            .unwrap(),
        }
        // The trapezoidal rule conserves the energy of a linear system exactly (round-off
        // only). The central difference conserves a modified energy: the plain one
        // oscillates by O((w_max h)^2) without drifting; w_max h = 0.45 here, and the
        // central velocity makes the measured swing about 1e-3.
        assert!(worst < tol, "{method}: energy error {worst:e}");
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
    let run = |method: &str, h: f64| {
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
        match method {
            "cd" => central_difference(&mut p, &[0.0], &[0.0], &options, &mut observe).unwrap(),
            "newmark" => newmark(
                &mut p,
                &[0.0],
                &[0.0],
                NewmarkScheme::AverageAcceleration,
                &options,
                &mut observe,
            )
            .unwrap(),
            _ => {
                runge_kutta(
                    &mut p,
                    &[0.0],
                    &[0.0],
                    &RkTolerances::default(),
                    &options,
                    &mut observe,
                )
                .unwrap();
            }
        }
        last
    };
    let reference = run("rk", 1e-3);
    for method in ["cd", "newmark"] {
        let x = run(method, 1e-4);
        // Second order at w h ~ 0.007 over 10 periods: phase error ~ 1e-4 of the amplitude.
        assert!(
            (x - reference).abs() < 2e-3 * reference.abs().max(1e-4),
            "{method}: {x} vs {reference}"
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
