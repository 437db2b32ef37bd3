//! Roller bearing contact: force law against closed forms, exact tangent against finite
//! differences, static equilibrium on the reference rotor's bearings.

use std::f64::consts::PI;

use whirl::bearing::{hertz_bearings, HertzBearing, RollerGeometry};
use whirl::fe::Bearings;
use whirl::force::{Kinematics, NonlinearForce};
use whirl::model::{Clearance, Model, Ring, RollerBearing, Waviness, WavinessForm};
use whirl::system::build;
use whirl::time::static_equilibrium;

use crate::common::{reference_bearing, reference_rotor};

fn spinning(speed_hz: f64, t: f64) -> Kinematics {
    let w = 2.0 * PI * speed_hz;
    Kinematics {
        time: t,
        speed: w,
        angle: w * t,
    }
}

/// Force of a bearing on coordinates 0..m at (q, v).
fn force(b: &mut HertzBearing, at: &Kinematics, q: &[f64], v: &[f64]) -> Vec<f64> {
    let mut f = vec![0.0; q.len()];
    b.force(at, q, v, &mut f);
    f
}

#[test]
fn one_roller_at_the_bottom_gives_the_hertz_force() {
    // Roller 0 straight down (cage angle -90 deg); the shaft pressed down by clearance + d
    // loads only that roller (its neighbours sit 45 deg away and approach by
    // (gamma + d) cos 45 - gamma < 0). Closed form K d^(10/9) + C d', to round-off.
    let mut bearing = reference_bearing();
    bearing.cage_angle = -PI / 2.0;
    let gamma = 20e-6;
    bearing.clearance = Clearance::Constant(gamma);
    let mut hertz = HertzBearing::new(&bearing, vec![0, 1]).unwrap();
    let d = 3e-6;
    let vy = -1e-3;
    let at = Kinematics {
        time: 0.0,
        speed: 0.0,
        angle: 0.0,
    };
    let f = force(&mut hertz, &at, &[0.0, -(gamma + d)], &[0.0, vy]);
    let expected = bearing.contact_stiffness * d.powf(10.0 / 9.0) + bearing.contact_damping * -vy;
    assert!(f[0].abs() < 1e-9 * expected, "{f:?}");
    assert!(
        (f[1] - expected).abs() < 1e-12 * expected,
        "{f:?} vs {expected}"
    );
}

#[test]
fn rollers_never_pull() {
    // Leaving the contact fast: damping would make the force tensile; it is clamped to 0.
    let mut bearing = reference_bearing();
    bearing.cage_angle = -PI / 2.0;
    bearing.clearance = Clearance::Constant(0.0);
    let mut hertz = HertzBearing::new(&bearing, vec![0, 1]).unwrap();
    let at = spinning(0.0, 0.0);
    let f = force(&mut hertz, &at, &[0.0, -1e-7], &[0.0, 10.0]);
    assert_eq!(f, vec![0.0, 0.0]);
}

/// A bearing with everything switched on: tilt slices, skew, inner and outer waviness,
/// contact damping, spinning.
fn everything() -> RollerBearing {
    let mut b = reference_bearing();
    b.roller_tilt = true;
    b.slices = 7;
    b.skew_angle = 0.5f64.to_radians();
    b.waviness = vec![
        Waviness {
            ring: Ring::Outer,
            form: WavinessForm::Thesis,
            order: 5,
            amplitude: 1e-6,
            phase: 0.3,
        },
        Waviness {
            ring: Ring::Inner,
            form: WavinessForm::Thesis,
            order: 3,
            amplitude: 0.5e-6,
            phase: -1.0,
        },
    ];
    b
}

#[test]
fn tangent_equals_finite_differences_to_1e_6() {
    let mut hertz = HertzBearing::new(&everything(), vec![0, 1, 2, 3]).unwrap();
    let at = spinning(330.0, 1.234e-3);
    // Shaft 32 um down and 9 um sideways with 0.2 mrad slope: several rollers in contact,
    // no slice within 1e-8 m of the contact edge, so the law is smooth around this state.
    let q = [9e-6, -32e-6, 2e-4, -1.5e-4];
    let v = [3e-3, -2e-3, 0.1, 0.05];
    let m = 4;
    let (mut dfdq, mut dfdv) = (vec![0.0; 16], vec![0.0; 16]);
    hertz.jacobian(&at, &q, &v, &mut dfdq, &mut dfdv);
    // Central differences: truncation ~ (h/delta)^2 ~ 1e-8 with h = 1e-10 m against
    // approaches of ~1e-5 m, round-off ~ 1e-16 F / h ~ 1e-9 relative: 1e-6 has margin.
    let steps = [1e-10, 1e-10, 1e-9, 1e-9];
    let vsteps = [1e-6; 4];
    let mut worst: f64 = 0.0;
    let scale_q = dfdq.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let scale_v = dfdv.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for b in 0..m {
        let shifted = |x: &[f64; 4], s: f64| {
            let mut y = *x;
            y[b] += s;
            y
        };
        let fq = |s: f64| force(&mut hertz.clone(), &at, &shifted(&q, s), &v);
        let fv = |s: f64| force(&mut hertz.clone(), &at, &q, &shifted(&v, s));
        let (qp, qm) = (fq(steps[b]), fq(-steps[b]));
        let (vp, vm) = (fv(vsteps[b]), fv(-vsteps[b]));
        for a in 0..m {
            let fd_q = (qp[a] - qm[a]) / (2.0 * steps[b]);
            let fd_v = (vp[a] - vm[a]) / (2.0 * vsteps[b]);
            worst = worst.max((fd_q - dfdq[a * m + b]).abs() / scale_q);
            worst = worst.max((fd_v - dfdv[a * m + b]).abs() / scale_v);
        }
    }
    assert!(scale_q > 1e7, "the state must be in contact: {scale_q}");
    assert!(worst < 1e-6, "largest relative difference {worst:e}");
}

#[test]
fn aligned_sliced_roller_carries_the_unsliced_force() {
    // Tilt on with a level shaft: the 10 slices share the roller's stiffness equally.
    let plain = reference_bearing();
    let mut sliced = plain.clone();
    sliced.roller_tilt = true;
    sliced.slices = 10;
    let at = spinning(100.0, 2e-3);
    let f1 = force(
        &mut HertzBearing::new(&plain, vec![0, 1]).unwrap(),
        &at,
        &[4e-6, -30e-6],
        &[0.0; 2],
    );
    let f10 = force(
        &mut HertzBearing::new(&sliced, vec![0, 1, 2, 3]).unwrap(),
        &at,
        &[4e-6, -30e-6, 0.0, 0.0],
        &[0.0; 4],
    );
    for a in 0..2 {
        assert!(
            (f1[a] - f10[a]).abs() < 1e-12 * f1[1].abs(),
            "{f1:?} {f10:?}"
        );
    }
    assert!(f10[2].abs() < 1e-9 && f10[3].abs() < 1e-9);
}

#[test]
fn cage_speed_and_passage_frequency() {
    // Eq. 3.4: w_c = (1 - D_b/D_p) Omega / 2; eq. 4.4: w_vc = N_b w_c.
    let g = RollerGeometry::new(&reference_bearing());
    let omega = 2.0 * PI * 330.0;
    let expected = (1.0 - 6.1 / 69.6) * omega / 2.0;
    assert!((g.cage_speed(omega) - expected).abs() < 1e-12 * expected);
    assert!((g.varying_compliance_frequency(omega) - 8.0 * expected).abs() < 1e-9 * expected);
}

#[test]
fn a_measured_cage_speed_ratio_sets_every_cage_frequency() {
    // The thesis' 330 Hz spectra put N_b w_c at 1103 Hz: a ratio of 1103 / (8 x 330).
    let text = whirl::examples::REFERENCE_ROTOR.replacen(
        "[[roller_bearing]]\n",
        "[[roller_bearing]]\ncage_speed_ratio = 0.4178\n",
        1,
    );
    let model = Model::from_toml_str(&text, None).unwrap();
    let g = RollerGeometry::new(&model.roller_bearings[0]);
    let omega = 2.0 * PI * 330.0;
    let hz = g.varying_compliance_frequency(omega) / (2.0 * PI);
    // 4 significant digits given: 1103 Hz to the ratio's rounding.
    assert!((hz - 1103.0).abs() < 0.2, "{hz} Hz");
    // The other bearing keeps the kinematic ratio.
    let other = RollerGeometry::new(&model.roller_bearings[1]);
    let expected = (1.0 - 6.1 / 69.6) * omega / 2.0;
    assert!((other.cage_speed(omega) - expected).abs() < 1e-12 * expected);
    for bad in ["0", "1", "-0.2", "1.5"] {
        let text = whirl::examples::REFERENCE_ROTOR.replacen(
            "[[roller_bearing]]\n",
            &format!("[[roller_bearing]]\ncage_speed_ratio = {bad}\n"),
            1,
        );
        let message = Model::from_toml_str(&text, None).unwrap_err().to_string();
        assert!(
            message.contains("roller_bearing[0].cage_speed_ratio") && message.contains("0.4562"),
            "{bad}: {message}"
        );
    }
}

#[test]
fn static_equilibrium_on_roller_bearings_carries_the_weight() {
    // 8 rollers: one roller at the bottom carries each bearing's load. 16 rollers: the
    // bottom roller's neighbours (22.5 degrees away) touch too, just past their contact
    // edge, where the Hertz law's curvature is unbounded.
    hang_in_bearings(8);
    hang_in_bearings(16);
}

fn hang_in_bearings(rollers: usize) {
    // Full reference rotor hanging in its two Hertz bearings under gravity: the contact
    // forces add up to the weight (to the solver tolerance) and the shaft drops by more
    // than the clearance at each bearing; u_x stays 0 (not unique with a bottom roller).
    let mut model = reference_rotor();
    for b in &mut model.roller_bearings {
        b.rollers = rollers;
    }
    let mut problem = build(&model, None, Bearings::NonlinearApart, &hertz_bearings)
        .unwrap()
        .system;
    let gravity = problem.constant_force.clone();
    let n = problem.size();
    let q = static_equilibrium(&mut problem, &vec![0.0; n], 0.0).unwrap();
    let weight: f64 = -gravity.iter().skip(1).step_by(4).sum::<f64>();
    let mut carried = 0.0;
    for b in &model.roller_bearings {
        let node = b.station.node;
        let mut hertz = HertzBearing::new(b, vec![0, 1]).unwrap();
        let at = spinning(0.0, 0.0);
        let u = [q[4 * node], q[4 * node + 1]];
        let f = force(&mut hertz, &at, &u, &[0.0; 2]);
        carried += f[1];
        assert!(u[1] < -20e-6, "drops past the clearance: {u:?}");
        // cos(3 pi / 2) is -1.8e-16, not 0, so the bottom roller couples x weakly to a
        // direction with no stiffness: u_x moves by round-off, far below the clearance.
        assert!(u[0].abs() < 1e-9, "u_x stays 0: {u:?}");
    }
    assert!(weight > 100.0);
    assert!(
        (carried - weight).abs() < 1e-8 * weight,
        "{carried} vs {weight}"
    );
}
