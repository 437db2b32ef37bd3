//! Equivalent stiffness of the roller bearing (thesis 3.4, docs/theory.md section 5): tangent
//! against finite differences, the statically determinate bottom-roller equilibrium against its
//! closed form, symmetry, force balance, and the fall of stiffness with clearance.

use std::f64::consts::PI;

use whirl::bearing::stiffness::{
    force_surface, gravity_load, passage_average, stiffness_versus_clearance, FrozenBearing,
    StiffnessOptions, StiffnessStudy,
};

use crate::common::{reference_bearing, reference_rotor};

/// Half the reference rotor's weight, N, straight down: what each bearing carries.
fn half_weight() -> [f64; 2] {
    gravity_load(&reference_rotor(), 0).unwrap()
}

const UM: f64 = 1e-6;
const BOTTOM: f64 = -PI / 2.0;

#[test]
fn tangent_equals_central_differences() {
    // Shaft 32 um down and 9 um sideways in a 20 um clearance: three rollers touch, none
    // within 1e-8 m of the contact edge, so the force is smooth around this point.
    let mut b = FrozenBearing::new(&reference_bearing(), 20.0 * UM, 0.3).unwrap();
    let u = [9.0 * UM, -32.0 * UM];
    let t = b.tangent(u);
    assert!(t.rollers.len() >= 2, "{:?}", t.rollers);
    let k = [
        [t.stiffness.kxx, t.stiffness.kxy],
        [t.stiffness.kyx, t.stiffness.kyy],
    ];
    let scale = k.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
    // Truncation ~ (h / delta)^2 ~ 1e-8 with h = 1e-10 m against approaches of ~1e-5 m;
    // round-off ~ 1e-16 F / h ~ 1e-9 relative: 1e-6 leaves margin for both.
    let h = 1e-10;
    for col in 0..2 {
        let shifted = |s: f64| {
            let mut p = u;
            p[col] += s;
            p
        };
        let (fp, fm) = (b.force(shifted(h)), b.force(shifted(-h)));
        for row in 0..2 {
            let fd = -(fp[row] - fm[row]) / (2.0 * h);
            assert!(
                (fd - k[row][col]).abs() < 1e-6 * scale,
                "k[{row}][{col}] = {} vs difference {fd}",
                k[row][col]
            );
        }
    }
}

#[test]
fn bottom_roller_equilibrium_is_the_closed_form_at_every_clearance() {
    // One roller straight down carries W alone: u_y = -(gamma + (W/K_c)^(9/10)),
    // k_yy = (10/9) K_c delta^(1/9), k_xx = k_xy = 0, whatever the clearance (from 10 um
    // on, the neighbours 45 deg away stay clear under the reference load).
    let bearing = reference_bearing();
    let w = half_weight()[1].abs();
    let n = bearing.contact_exponent;
    let kc = bearing.contact_stiffness;
    let delta = (w / kc).powf(1.0 / n);
    let k_closed = n * kc * delta.powf(n - 1.0);
    for gamma in [10.0, 20.0, 60.0, 120.0].map(|g| g * UM) {
        let e = FrozenBearing::new(&bearing, gamma, BOTTOM)
            .unwrap()
            .equilibrium([0.0, -w])
            .unwrap();
        let t = &e.tangent;
        let uy = -(gamma + delta);
        // The force balance holds to 1e-11 of W (the solver's tolerance); through the
        // tangent that moves u by ~1e-11 delta and k by ~1e-12 k: 1e-9 is ample.
        assert!((t.displacement[1] - uy).abs() < 1e-9 * delta, "{t:?}");
        assert!(
            (t.stiffness.kyy - k_closed).abs() < 1e-9 * k_closed,
            "{t:?}"
        );
        // cos(-pi/2) = 6e-17, not 0: the x entries are round-off of k_yy.
        assert!(t.stiffness.kxx.abs() < 1e-12 * k_closed);
        assert!(t.stiffness.kxy.abs() < 1e-12 * k_closed);
        assert_eq!(t.rollers.len(), 1, "{:?}", t.rollers);
        assert!((t.rollers[0].angle - BOTTOM).abs() < 1e-12);
    }
}

#[test]
fn symmetric_loading_has_no_cross_coupling() {
    // Vertical load, cage symmetric about the y axis: two rollers straddling the bottom
    // (at -90 +- 22.5 deg), and the passage average over cage angles symmetric about it.
    let bearing = reference_bearing();
    let load = half_weight();
    let straddle = BOTTOM + PI / 8.0;
    let e = FrozenBearing::new(&bearing, 20.0 * UM, straddle)
        .unwrap()
        .equilibrium(load)
        .unwrap();
    let s = e.tangent.stiffness;
    assert_eq!(e.tangent.rollers.len(), 2, "{:?}", e.tangent.rollers);
    // Round-off of the two rollers' terms, each ~k_yy: 1e-12 of k_yy.
    assert!(s.kxy.abs() < 1e-12 * s.kyy, "{s:?}");
    assert!(
        s.kxx > 0.1 * s.kyy,
        "two rollers give horizontal stiffness: {s:?}"
    );
    assert!(e.tangent.displacement[0].abs() < 1e-9 * UM);
    let avg = passage_average(&bearing, 20.0 * UM, BOTTOM, load, 32).unwrap();
    // Cage angles -90 + k 45/32 deg pair off as mirror images (k and 32 - k), so the
    // cross terms cancel to round-off of the sum of 32 tangents.
    assert!(avg.mean.kxy.abs() < 1e-10 * avg.mean.kyy, "{:?}", avg.mean);
    assert!((avg.mean.kxy - avg.mean.kyx).abs() < 1e-12 * avg.mean.kyy);
}

#[test]
fn equilibrium_balances_the_load() {
    // Loads in several directions and sizes, cages at odd angles: |F(u) + W| <= 1e-9 |W|
    // (the solver stops at 1e-11).
    let bearing = reference_bearing();
    for (k, (magnitude, direction, cage, gamma)) in [
        (171.0, -90.0, -90.0, 20.0),
        (171.0, -90.0, -73.0, 20.0),
        (60.0, -120.0, 10.0, 45.0),
        (2000.0, 33.0, 0.0, 10.0),
        (5.0, 180.0, 7.0, 120.0),
        (1e4, -90.0, -90.0 + 22.5, 0.0),
    ]
    .into_iter()
    .enumerate()
    {
        let a: f64 = f64::to_radians(direction);
        let load = [magnitude * a.cos(), magnitude * a.sin()];
        let mut b = FrozenBearing::new(&bearing, gamma * UM, f64::to_radians(cage)).unwrap();
        let e = b.equilibrium(load).unwrap();
        let f = b.force(e.tangent.displacement);
        let left = (f[0] + load[0]).hypot(f[1] + load[1]);
        assert!(left <= 1e-9 * magnitude, "case {k}: {left} N left over");
        assert!(!e.tangent.rollers.is_empty());
        // The journal moves into the load, beyond the clearance.
        let along =
            (e.tangent.displacement[0] * load[0] + e.tangent.displacement[1] * load[1]) / magnitude;
        assert!(along > gamma * UM, "case {k}: {e:?}");
    }
}

#[test]
fn gravity_load_is_half_the_weight_of_the_symmetric_rotor() {
    // 1.3 m of 55.9 mm steel shaft and the 10 kg disk, on two bearings at the ends.
    let model = reference_rotor();
    let area = PI / 4.0 * 0.0559f64.powi(2);
    let weight = (7810.0 * area * 1.3 + 10.0) * 9.81;
    for b in 0..2 {
        let w = gravity_load(&model, b).unwrap();
        // The consistent mass matrix carries the exact total mass; the solve adds
        // round-off of the ~1e8 N/m stiffnesses: 1e-9 relative.
        assert!(
            (w[1] + weight / 2.0).abs() < 1e-9 * weight,
            "{w:?} vs {weight}"
        );
        assert!(w[0].abs() < 1e-9 * weight);
    }
    assert!(gravity_load(&model, 2).is_err());
}

/// The three stiffnesses at `clearances` (um) under a downward load (N), a roller at the
/// bottom of the frozen cage, 32 cage positions per passage.
fn study(clearances: &[f64], load: f64) -> StiffnessStudy {
    stiffness_versus_clearance(
        &reference_bearing(),
        &StiffnessOptions {
            clearances: clearances.iter().map(|c| c * UM).collect(),
            load: [0.0, -load],
            cage_angle: None,
            cage_steps: 32,
            fixed_displacement: None,
        },
    )
    .unwrap()
}

fn print(study: &StiffnessStudy) {
    println!("load {:?} N", study.load);
    println!("gamma_um frozen_kxx frozen_kyy avg_kxx avg_kyy most_rollers fixed_kxx fixed_kyy");
    for c in &study.clearances {
        println!(
            "{:6.1} {:11.4e} {:11.4e} {:11.4e} {:11.4e} {} {:11.4e} {:11.4e}",
            c.clearance / UM,
            c.frozen.tangent.stiffness.kxx,
            c.frozen.tangent.stiffness.kyy,
            c.averaged.mean.kxx,
            c.averaged.mean.kyy,
            c.averaged.most_rollers,
            c.fixed.stiffness.kxx,
            c.fixed.stiffness.kyy,
        );
    }
}

/// Each entry below the one before, strictly (`strict`) or not.
fn falls(values: &[f64], strict: bool) -> bool {
    values
        .windows(2)
        .all(|w| w[1] < w[0] || (!strict && w[1] == w[0]))
}

#[test]
fn equilibrium_stiffness_ignores_clearance_once_two_rollers_carry_the_load() {
    // Reference bearing under half the rotor weight (171 N, Hertz deflection 1.7 um), the
    // default sweep 10..120 um: at every cage position one or two rollers carry the load,
    // two equations for two contact forces, so the approaches and the tangent are the same
    // at every clearance, frozen and averaged. Only the fixed displacement shows a fall.
    let load = half_weight()[1].abs();
    let clearances: Vec<f64> = (1..=12).map(|i| 10.0 * i as f64).collect();
    let s = study(&clearances, load);
    print(&s);
    let first = &s.clearances[0];
    for c in &s.clearances {
        assert!(c.averaged.most_rollers <= 2);
        // Each equilibrium balances to 1e-11 of the load: 1e-9 between clearances.
        for (a, b) in [
            (
                c.frozen.tangent.stiffness.kyy,
                first.frozen.tangent.stiffness.kyy,
            ),
            (c.averaged.mean.kyy, first.averaged.mean.kyy),
            (c.averaged.mean.kxx, first.averaged.mean.kxx),
        ] {
            assert!((a - b).abs() < 1e-9 * b, "{a} vs {b}");
        }
    }
    let fixed_kyy: Vec<f64> = s.clearances.iter().map(|c| c.fixed.stiffness.kyy).collect();
    assert!(falls(&fixed_kyy, true), "{fixed_kyy:?}");
    let fixed_kxx: Vec<f64> = s.clearances.iter().map(|c| c.fixed.stiffness.kxx).collect();
    assert!(falls(&fixed_kxx, false), "{fixed_kxx:?}");
    // At the largest clearance the fixed displacement is that clearance's equilibrium.
    let last = s.clearances.last().unwrap();
    let k = last.fixed.stiffness.kyy;
    assert!((k - last.frozen.tangent.stiffness.kyy).abs() < 1e-9 * k);
}

#[test]
fn averaged_stiffness_falls_with_clearance_while_three_rollers_share_the_load() {
    // Clearances comparable to the Hertz deflection: a third roller joins, the equilibrium is
    // statically indeterminate and a smaller clearance shares the load among more rollers.
    let load = half_weight()[1].abs();
    let s = study(&[0.0, 0.5, 1.0, 2.0, 3.0, 4.0], load);
    print(&s);
    let kxx: Vec<f64> = s.clearances.iter().map(|c| c.averaged.mean.kxx).collect();
    let kyy: Vec<f64> = s.clearances.iter().map(|c| c.averaged.mean.kyy).collect();
    assert!(falls(&kxx, true) && falls(&kyy, true), "{kxx:?} {kyy:?}");
    assert!(s.clearances.iter().all(|c| c.averaged.most_rollers >= 3));
    // A load of 10 kN (Hertz deflection 37 um, of the order of the unbalance force at top
    // speed) keeps three rollers in contact across the whole sweep: the fall spans it.
    let s = study(&[10.0, 20.0, 40.0, 60.0, 80.0, 100.0, 120.0], 1e4);
    print(&s);
    let kxx: Vec<f64> = s.clearances.iter().map(|c| c.averaged.mean.kxx).collect();
    let kyy: Vec<f64> = s.clearances.iter().map(|c| c.averaged.mean.kyy).collect();
    assert!(falls(&kxx, true) && falls(&kyy, true), "{kxx:?} {kyy:?}");
}

#[test]
fn force_surface_is_zero_inside_the_clearance_and_symmetric() {
    let bearing = reference_bearing();
    let gamma = 20.0 * UM;
    let axis: Vec<f64> = (-20..=20).map(|i| 3.0 * UM * i as f64).collect();
    let s = force_surface(&bearing, gamma, BOTTOM, &axis, &axis).unwrap();
    let n = axis.len();
    for j in 0..n {
        for i in 0..n {
            let r = axis[i].hypot(axis[j]);
            if r <= gamma {
                assert_eq!(s.fr[j][i], 0.0, "no force inside the clearance");
            }
            // Eq. 3.21, and the radial force is the largest of the three.
            assert!(s.fr[j][i] >= s.fx[j][i].abs() && s.fr[j][i] >= s.fy[j][i].abs());
            // Mirror in x: the cage with a bottom roller is symmetric about the y axis.
            let m = n - 1 - i;
            let tol = 1e-9 * s.fr[j][i].max(1.0);
            assert!((s.fx[j][i] + s.fx[j][m]).abs() < tol);
            assert!((s.fy[j][i] - s.fy[j][m]).abs() < tol);
        }
    }
    // At (0, -27 um) the bottom roller alone (its neighbours approach by 27 cos 45 - 20 < 0)
    // carries K_c (7 um)^(10/9), pushing up.
    let j = axis
        .iter()
        .position(|&y| (y + 27.0 * UM).abs() < 1e-12)
        .unwrap();
    let expected = bearing.contact_stiffness * (7.0 * UM).powf(bearing.contact_exponent);
    assert!((s.fy[j][n / 2] - expected).abs() < 1e-9 * expected);
}

#[test]
fn a_negative_clearance_is_refused() {
    let e = FrozenBearing::new(&reference_bearing(), -UM, 0.0).unwrap_err();
    assert!(e.to_string().contains("non-negative"), "{e}");
}
