//! One harness run over every public [`NonlinearForce`] of the library: the linear support
//! and cubic spring of `whirl::force`, the squeeze-film damper (cavitated and full film,
//! between two housings), and the contact laws (Hertz rollers, the same with the cage made
//! periodic for harmonic balance, the forcing-function law, and Hertz rollers mounted in a
//! moving housing). Each must give the Jacobian of its own force (against central
//! differences, in displacement and velocity), and `force_and_jacobian`, the one call the
//! harmonic-balance residual makes, must give what `force` and `jacobian` give apart; each
//! contact law must never pull the rotor outwards and must be exactly zero, with a zero
//! Jacobian, while the journal stays inside the clearance.

use std::f64::consts::PI;

use whirl::bearing::{ForcingBearing, HertzBearing, Housed};
use whirl::force::{CubicSpring, Kinematics, LinearSupport, NonlinearForce};
use whirl::hbm::{CageModel, CagedBearing};
use whirl::model::{Cavitation, ForcingFunction, SqueezeFilm};
use whirl::squeeze_film::SqueezeFilmForce;

use crate::common::reference_bearing;

/// The clearance of the reference bearing, m (constant in speed).
const CLEARANCE: f64 = 20e-6;

/// 330 Hz, the speed of the harmonic-balance comparison, at an arbitrary instant.
fn spinning() -> Kinematics {
    let w = 2.0 * PI * 330.0;
    Kinematics {
        time: 1.3e-3,
        speed: w,
        angle: w * 1.3e-3,
    }
}

/// A force under test and whether it is a contact with the reference clearance.
struct Case {
    force: Box<dyn NonlinearForce>,
    contact: bool,
}

/// A damper of 0.2 mm clearance, so that the smooth states (up to 0.11 mm off centre) keep
/// the eccentricity ratio below 0.6, where the film is smooth and finite.
fn damper(cavitation: Cavitation) -> SqueezeFilm {
    SqueezeFilm {
        radius: 0.05,
        length: 0.02,
        clearance: 2e-4,
        viscosity: 0.02,
        cavitation,
        offset: [0.0, 0.0],
    }
}

/// Every public implementation, on coordinates [0, 1] (one coordinate for the spring), and
/// [2, 3] for the outer housing of the damper and the housed bearing.
fn every_force() -> Vec<Case> {
    let bearing = reference_bearing();
    let mut forcing = bearing.clone();
    // A law with a speed trend in coefficient and exponent, so both are exercised.
    forcing.forcing_function = Some(ForcingFunction {
        a0: 2.5e9,
        a1: 1.5e5,
        b0: 1.2,
        b1: -1.5e-5,
    });
    let hertz = || HertzBearing::new(&bearing, vec![0, 1]).unwrap();
    let case = |force: Box<dyn NonlinearForce>, contact| Case { force, contact };
    vec![
        case(
            Box::new(LinearSupport::new(
                "support",
                [0, 1],
                [[1e8, 2e6], [-3e6, 8e7]],
                [[300.0, 0.0], [10.0, 250.0]],
            )),
            false,
        ),
        case(Box::new(CubicSpring::new(0, 1e6, 1e16, 1e-4)), false),
        case(Box::new(hertz()), true),
        case(
            Box::new(CagedBearing::new(hertz(), CageModel::DEFAULT).unwrap()),
            true,
        ),
        case(
            Box::new(CagedBearing::new(hertz(), CageModel::Frozen).unwrap()),
            true,
        ),
        case(
            Box::new(ForcingBearing::new(&forcing, 0, [0, 1], (0.0, 2.0 * PI * 800.0)).unwrap()),
            true,
        ),
        case(Box::new(Housed::new(Box::new(hertz()), [2, 3])), true),
        case(
            Box::new(SqueezeFilmForce::new(
                "pi film",
                &damper(Cavitation::Pi),
                vec![0, 1, 2, 3],
            )),
            false,
        ),
        case(
            Box::new(SqueezeFilmForce::new(
                "full film",
                &damper(Cavitation::Full),
                vec![0, 1, 2, 3],
            )),
            false,
        ),
    ]
}

fn force_at(f: &mut dyn NonlinearForce, q: &[f64], v: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; q.len()];
    f.force(&spinning(), q, v, &mut out);
    out
}

/// dF/dq and dF/dv from `jacobian`, row-major.
type Jacobians = (Vec<f64>, Vec<f64>);

fn jacobian_at(f: &mut dyn NonlinearForce, q: &[f64], v: &[f64]) -> Jacobians {
    let m = q.len();
    let (mut dq, mut dv) = (vec![0.0; m * m], vec![0.0; m * m]);
    f.jacobian(&spinning(), q, v, &mut dq, &mut dv);
    (dq, dv)
}

/// The force and Jacobians from the one call `force_and_jacobian`.
fn force_and_jacobian_at(
    f: &mut dyn NonlinearForce,
    q: &[f64],
    v: &[f64],
) -> (Vec<f64>, Jacobians) {
    let m = q.len();
    let (mut out, mut dq, mut dv) = (vec![0.0; m], vec![0.0; m * m], vec![0.0; m * m]);
    f.force_and_jacobian(&spinning(), q, v, &mut out, &mut dq, &mut dv);
    (out, (dq, dv))
}

/// Largest difference between the Jacobians `(dq, dv)` and central differences of the
/// force, relative to each Jacobian's largest entry: (in displacement, in velocity).
fn jacobian_error(
    f: &mut dyn NonlinearForce,
    q: &[f64],
    v: &[f64],
    (dq, dv): &Jacobians,
) -> (f64, f64) {
    let m = q.len();
    // Steps: 1e-11 m against approaches of ~1 um and 1e-7 m/s against velocities of
    // ~1 mm/s; truncation (h/scale)^2 ~ 1e-10 and round-off 1e-16 * scale / h ~ 1e-10
    // relative, so 1e-6 leaves a wide margin while a wrong entry misses it by far.
    let steps = [1e-11, 1e-7];
    let mut worst = [0.0f64; 2];
    for (which, (jac, h)) in [(dq, steps[0]), (dv, steps[1])].into_iter().enumerate() {
        let scale = jac.iter().fold(f64::MIN_POSITIVE, |s, x| s.max(x.abs()));
        for b in 0..m {
            let (mut qp, mut qm, mut vp, mut vm) = (q.to_vec(), q.to_vec(), v.to_vec(), v.to_vec());
            if which == 0 {
                qp[b] += h;
                qm[b] -= h;
            } else {
                vp[b] += h;
                vm[b] -= h;
            }
            let (fp, fm) = (force_at(f, &qp, &vp), force_at(f, &qm, &vm));
            for a in 0..m {
                let fd = (fp[a] - fm[a]) / (2.0 * h);
                let error = (fd - jac[a * m + b]).abs() / scale;
                // A derivative that is zero both ways is exact, whatever the scale.
                if fd != jac[a * m + b] {
                    worst[which] = worst[which].max(error);
                }
            }
        }
    }
    (worst[0], worst[1])
}

/// Largest difference between two vectors relative to the larger's largest entry.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = a
        .iter()
        .chain(b)
        .fold(f64::MIN_POSITIVE, |s, x| s.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0, |d, (x, y)| d.max((x - y).abs() / scale))
}

/// A state of the four coordinates [shaft x, y, housing x, y]: the forces on two
/// coordinates read its first two.
type State = ([f64; 4], [f64; 4]);

/// States beyond the clearance in several directions, moving: 3 to 6 um beyond it, so
/// that even midway between two of the 8 rollers (22.5 degrees off each, where the nearest
/// roller's approach is r cos 22.5 - gamma) at least one roller is loaded. The housing
/// moves by 0.36 um at most, which leaves every relative approach loaded.
fn states_in_contact() -> Vec<State> {
    (0..7)
        .map(|k| {
            let angle = -PI / 2.0 + 0.37 + 0.9 * k as f64;
            let r = CLEARANCE + 1e-6 * (3.0 + 0.5 * k as f64);
            let v = [
                1e-3 * (0.3 * k as f64).cos(),
                -2e-3 * (0.5 * k as f64).sin(),
                2e-4,
                -1e-4 * k as f64,
            ];
            ([r * angle.cos(), r * angle.sin(), 3e-7, -2e-7], v)
        })
        .collect()
}

/// States of the smooth laws, each coordinate displaced and moving.
fn smooth_states() -> Vec<State> {
    vec![
        ([3e-5, -2e-5, 4e-6, -1e-6], [1e-3, 2e-3, -5e-4, 3e-4]),
        ([-1e-4, 4e-5, -6e-6, 2e-6], [-3e-3, 0.0, 1e-3, 2e-3]),
    ]
}

/// Runs `check` on every force at each of its states (on its own coordinates), and asserts
/// that the state loads the force: a zero force would pass with a zero Jacobian.
fn at_every_loaded_state(mut check: impl FnMut(&mut dyn NonlinearForce, &[f64], &[f64])) {
    for Case { mut force, contact } in every_force() {
        let states = if contact {
            states_in_contact()
        } else {
            smooth_states()
        };
        let m = force.dofs().len();
        for (q, v) in states {
            let (q, v) = (&q[..m], &v[..m]);
            // The check first: its first call is the first at this state, so a force that
            // kept the previous state's values would be caught.
            check(force.as_mut(), q, v);
            let f = force_at(force.as_mut(), q, v);
            assert!(
                f.iter().any(|x| x.abs() > 1e-3),
                "{}: no force at q = {q:?}",
                force.name()
            );
        }
    }
}

#[test]
fn every_force_gives_the_jacobian_of_its_force() {
    at_every_loaded_state(|force, q, v| {
        let jacobians = jacobian_at(force, q, v);
        let (eq, ev) = jacobian_error(force, q, v, &jacobians);
        assert!(
            eq < 1e-6 && ev < 1e-6,
            "{}: Jacobian off by {eq:e} (dq), {ev:e} (dv) relative at q = {q:?}",
            force.name()
        );
    });
}

#[test]
fn force_and_jacobian_gives_the_force_and_the_jacobian() {
    at_every_loaded_state(|force, q, v| {
        let (f, jacobians) = force_and_jacobian_at(force, q, v);
        let (apart_f, (apart_dq, apart_dv)) = (force_at(force, q, v), jacobian_at(force, q, v));
        // The same law at the same state: a one-pass evaluation may only sum the same
        // terms in another order, a few ulps of the largest entry (a roller bearing sums
        // 8 rollers, the cage average 16 angles), so 1e-12 relative; a term missed or
        // doubled is of the order of one roller's share, 1e-2 or more.
        for (what, one_call, apart) in [
            ("force", &f, &apart_f),
            ("dF/dq", &jacobians.0, &apart_dq),
            ("dF/dv", &jacobians.1, &apart_dv),
        ] {
            let d = relative_difference(one_call, apart);
            assert!(
                d < 1e-12,
                "{}: {what} from force_and_jacobian off by {d:e} relative at q = {q:?}",
                force.name()
            );
        }
        // And against differences of the force, as the separate Jacobian (same margin).
        let (eq, ev) = jacobian_error(force, q, v, &jacobians);
        assert!(
            eq < 1e-6 && ev < 1e-6,
            "{}: force_and_jacobian's Jacobian off by {eq:e} (dq), {ev:e} (dv) at q = {q:?}",
            force.name()
        );
    });
}

/// `q` and `v` on the shaft's [x, y], the other coordinates of `force` (a housing's) at rest.
fn on_shaft(force: &dyn NonlinearForce, q: [f64; 2], v: [f64; 2]) -> (Vec<f64>, Vec<f64>) {
    let m = force.dofs().len();
    let pad = |x: [f64; 2]| {
        x.into_iter()
            .chain(std::iter::repeat(0.0))
            .take(m)
            .collect()
    };
    (pad(q), pad(v))
}

#[test]
fn no_contact_law_pulls_the_rotor_outwards() {
    for Case { mut force, .. } in every_force().into_iter().filter(|c| c.contact) {
        // Beyond the clearance, moving in every direction: a roller pushes or lets go.
        for r in [21e-6, 25e-6, 40e-6] {
            for k in 0..24 {
                let angle = 2.0 * PI * k as f64 / 24.0 + 0.1;
                let shaft = [r * angle.cos(), r * angle.sin()];
                for w in [[0.0, 0.0], [5e-2, 0.0], [0.0, -5e-2], [-3e-2, 3e-2]] {
                    let (q, v) = on_shaft(force.as_ref(), shaft, w);
                    let f = force_at(force.as_mut(), &q, &v);
                    let outward = f[0] * q[0] + f[1] * q[1];
                    assert!(
                        outward <= 0.0,
                        "{} pulls outwards at q = {q:?}, v = {v:?}: F = {f:?}",
                        force.name()
                    );
                }
            }
        }
    }
}

#[test]
fn every_contact_law_is_zero_inside_the_clearance() {
    for Case { mut force, .. } in every_force().into_iter().filter(|c| c.contact) {
        let m = force.dofs().len();
        for r in [0.0, 5e-6, 19.9e-6] {
            for k in 0..12 {
                let angle = 2.0 * PI * k as f64 / 12.0 + 0.2;
                let shaft = [r * angle.cos(), r * angle.sin()];
                let (q, v) = on_shaft(force.as_ref(), shaft, [2e-2, -1e-2]);
                assert!(
                    force_at(force.as_mut(), &q, &v).iter().all(|&x| x == 0.0),
                    "{}",
                    force.name()
                );
                let (mut dq, mut dv) = (vec![1.0; m * m], vec![1.0; m * m]);
                force.jacobian(&spinning(), &q, &v, &mut dq, &mut dv);
                assert!(dq.iter().chain(&dv).all(|&x| x == 0.0), "{}", force.name());
            }
        }
    }
}
