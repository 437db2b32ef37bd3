//! One harness run over every public [`NonlinearForce`] of the library: the linear support
//! and cubic spring of `whirl::force`, and the contact laws (Hertz rollers, the same with
//! the cage made periodic for harmonic balance, the forcing-function law). Each must give
//! the Jacobian of its own force (against central differences, in displacement and
//! velocity); each contact law must never pull the rotor outwards and must be exactly zero,
//! with a zero Jacobian, while the journal stays inside the clearance.

use std::f64::consts::PI;

use whirl::bearing::{ForcingBearing, HertzBearing};
use whirl::force::{CubicSpring, Kinematics, LinearSupport, NonlinearForce};
use whirl::hbm::{CageModel, CagedBearing};
use whirl::model::ForcingFunction;

mod common;
use common::reference_bearing;

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

/// Every public implementation, on coordinates [0, 1] (one coordinate for the spring).
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
    ]
}

fn force_at(f: &mut dyn NonlinearForce, q: &[f64], v: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; q.len()];
    f.force(&spinning(), q, v, &mut out);
    out
}

/// Largest difference between the Jacobian and central differences of the force, relative
/// to the Jacobian's largest entry: (in displacement, in velocity).
fn jacobian_error(f: &mut dyn NonlinearForce, q: &[f64], v: &[f64]) -> (f64, f64) {
    let m = q.len();
    let (mut dq, mut dv) = (vec![0.0; m * m], vec![0.0; m * m]);
    f.jacobian(&spinning(), q, v, &mut dq, &mut dv);
    // Steps: 1e-11 m against approaches of ~1 um and 1e-7 m/s against velocities of
    // ~1 mm/s; truncation (h/scale)^2 ~ 1e-10 and round-off 1e-16 * scale / h ~ 1e-10
    // relative, so 1e-6 leaves a wide margin while a wrong entry misses it by far.
    let steps = [1e-11, 1e-7];
    let mut worst = [0.0f64; 2];
    for (which, (jac, h)) in [(&dq, steps[0]), (&dv, steps[1])].into_iter().enumerate() {
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

/// States beyond the clearance in several directions, moving: 3 to 6 um beyond it, so
/// that even midway between two of the 8 rollers (22.5 degrees off each, where the nearest
/// roller's approach is r cos 22.5 - gamma) at least one roller is loaded.
fn states_in_contact() -> Vec<([f64; 2], [f64; 2])> {
    (0..7)
        .map(|k| {
            let angle = -PI / 2.0 + 0.37 + 0.9 * k as f64;
            let r = CLEARANCE + 1e-6 * (3.0 + 0.5 * k as f64);
            let v = [
                1e-3 * (0.3 * k as f64).cos(),
                -2e-3 * (0.5 * k as f64).sin(),
            ];
            ([r * angle.cos(), r * angle.sin()], v)
        })
        .collect()
}

#[test]
fn every_force_gives_the_jacobian_of_its_force() {
    for Case { mut force, contact } in every_force() {
        let states: Vec<([f64; 2], [f64; 2])> = if contact {
            states_in_contact()
        } else {
            vec![([3e-5, -2e-5], [1e-3, 2e-3]), ([-1e-4, 4e-5], [-3e-3, 0.0])]
        };
        let m = force.dofs().len();
        for (q, v) in states {
            // A zero force would pass with a zero Jacobian: every state must load the force.
            let f = force_at(force.as_mut(), &q[..m], &v[..m]);
            assert!(
                f.iter().any(|x| x.abs() > 1e-3),
                "{}: no force at q = {q:?}",
                force.name()
            );
            let (eq, ev) = jacobian_error(force.as_mut(), &q[..m], &v[..m]);
            assert!(
                eq < 1e-6 && ev < 1e-6,
                "{}: Jacobian off by {eq:e} (dq), {ev:e} (dv) relative at q = {q:?}",
                force.name()
            );
        }
    }
}

#[test]
fn no_contact_law_pulls_the_rotor_outwards() {
    for Case { mut force, .. } in every_force().into_iter().filter(|c| c.contact) {
        // Beyond the clearance, moving in every direction: a roller pushes or lets go.
        for r in [21e-6, 25e-6, 40e-6] {
            for k in 0..24 {
                let angle = 2.0 * PI * k as f64 / 24.0 + 0.1;
                let q = [r * angle.cos(), r * angle.sin()];
                for v in [[0.0, 0.0], [5e-2, 0.0], [0.0, -5e-2], [-3e-2, 3e-2]] {
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
        for r in [0.0, 5e-6, 19.9e-6] {
            for k in 0..12 {
                let angle = 2.0 * PI * k as f64 / 12.0 + 0.2;
                let (q, v) = ([r * angle.cos(), r * angle.sin()], [2e-2, -1e-2]);
                assert_eq!(
                    force_at(force.as_mut(), &q, &v),
                    [0.0, 0.0],
                    "{}",
                    force.name()
                );
                let (mut dq, mut dv) = ([1.0; 4], [1.0; 4]);
                force.jacobian(&spinning(), &q, &v, &mut dq, &mut dv);
                assert_eq!((dq, dv), ([0.0; 4], [0.0; 4]), "{}", force.name());
            }
        }
    }
}
