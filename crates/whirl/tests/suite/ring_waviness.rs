//! A waviness fixed to the outer ring pushes a centred shaft only for the orders
//! N_w = k N_b +- 1, and then at k N_b w_c; the thesis' form (eq. 3.18 as printed) pushes
//! at (N_w - 1) w_c for every order.

use std::f64::consts::PI;

use whirl::bearing::{contact_frequencies, HertzBearing};
use whirl::force::{Kinematics, NonlinearForce};
use whirl::model::{Clearance, Ring, RollerBearing, Waviness, WavinessForm};

use crate::common::reference_bearing;

/// Samples over one cage revolution: enough bins to hold 2 N_b + 1 = 17 cage orders and
/// their images apart.
const SAMPLES: usize = 64;
const AMPLITUDE: f64 = 1e-6;
const SPEED: f64 = 2.0 * PI * 50.0;

/// The reference bearing preloaded by 10 um with a linear contact law and no damping, so
/// that every roller touches all the time and the force is linear in the waviness: then
/// the closed form below holds exactly. (With the 10/9 law the waviness' harmonics m N_w
/// add the orders with m N_w = k N_b +- 1 too.)
fn preloaded(ring: Ring, order: usize, form: WavinessForm) -> RollerBearing {
    let mut b = reference_bearing();
    b.clearance = Clearance::Constant(-10e-6);
    b.contact_exponent = 1.0;
    b.contact_damping = 0.0;
    b.waviness = vec![Waviness {
        ring,
        form,
        order,
        amplitude: AMPLITUDE,
        phase: 0.7,
    }];
    b
}

/// The complex force F_x + i F_y on a centred shaft at `SAMPLES` instants over one cage
/// revolution.
fn force_over_a_cage_turn(bearing: &RollerBearing) -> Vec<(f64, f64)> {
    let mut hertz = HertzBearing::new(bearing, vec![0, 1]).unwrap();
    let turn = 2.0 * PI / bearing.cage_speed_ratio;
    (0..SAMPLES)
        .map(|k| {
            let angle = turn * k as f64 / SAMPLES as f64;
            let at = Kinematics {
                time: angle / SPEED,
                speed: SPEED,
                angle,
            };
            let mut f = [0.0; 2];
            hertz.force(&at, &[0.0, 0.0], &[0.0, 0.0], &mut f);
            (f[0], f[1])
        })
        .collect()
}

/// |DFT| of the complex force at cage order m (positive: turning with the cage), N.
fn line(force: &[(f64, f64)], m: i64) -> f64 {
    let (mut re, mut im) = (0.0, 0.0);
    for (k, &(fx, fy)) in force.iter().enumerate() {
        let a = -2.0 * PI * (m * k as i64) as f64 / force.len() as f64;
        let (s, c) = a.sin_cos();
        re += fx * c - fy * s;
        im += fx * s + fy * c;
    }
    (re * re + im * im).sqrt() / force.len() as f64
}

/// The largest line over every cage order, with its order.
fn strongest(force: &[(f64, f64)]) -> (i64, f64) {
    let half = SAMPLES as i64 / 2;
    (-half + 1..=half)
        .map(|m| (m, line(force, m)))
        .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a })
}

#[test]
fn an_outer_ring_fixed_waviness_pushes_only_for_orders_next_to_multiples_of_the_rollers() {
    let k = reference_bearing().contact_stiffness;
    // The closed form: sum_j K A cos(N_w theta_j + xi) e^(i theta_j) = K A N_b / 2 turning
    // at (N_w +- 1) w_c when N_w +- 1 is a multiple of N_b, else exactly 0.
    let full = k * AMPLITUDE * 8.0 / 2.0;
    // Round-off: eight terms of about K (gamma + A) = 4.5e3 N summed, each to 1e-16 of
    // itself; 1e-9 of the full line leaves a factor 1000 above that.
    let zero = 1e-9 * full;
    for order in [2, 3, 4, 5, 6, 8, 10, 11, 12, 16] {
        let force = force_over_a_cage_turn(&preloaded(Ring::Outer, order, WavinessForm::RingFixed));
        let largest = force.iter().map(|f| f.0.hypot(f.1)).fold(0.0, f64::max);
        assert!(largest <= zero, "order {order}: |F| up to {largest} N");
    }
    // N_w = k N_b - 1 turns with the cage (the e^(i (N_w + 1) theta_j) term), k N_b + 1
    // against it.
    for (order, cage_order) in [(7, 8), (9, -8), (15, 16), (17, -16)] {
        let bearing = preloaded(Ring::Outer, order, WavinessForm::RingFixed);
        let force = force_over_a_cage_turn(&bearing);
        let (m, value) = strongest(&force);
        // The line's size is exact up to round-off (1e-9 as above).
        assert_eq!(m, cage_order, "order {order}");
        assert!(
            (value - full).abs() <= 1e-9 * full,
            "order {order}: {value} N, not {full}"
        );
        let predicted = contact_frequencies(&bearing, SPEED)[1].frequency_hz;
        let cage_hz = bearing.cage_speed_ratio * SPEED / (2.0 * PI);
        // The same products in another order: 1e-12 relative.
        assert!((predicted - m.abs() as f64 * cage_hz).abs() <= 1e-12 * predicted);
    }
}

#[test]
fn the_thesis_form_pushes_at_n_w_minus_1_cage_orders_for_any_order() {
    let k = reference_bearing().contact_stiffness;
    let full = k * AMPLITUDE * 8.0 / 2.0;
    for order in [2, 3, 5, 6, 10] {
        let bearing = preloaded(Ring::Outer, order, WavinessForm::Thesis);
        let (m, value) = strongest(&force_over_a_cage_turn(&bearing));
        // Roller j meets A cos(N_w w_c t + theta_j - w_c t + xi): the sum keeps the term
        // turning at (N_w - 1) w_c against the cage, of size K A N_b / 2 (1e-9: round-off).
        assert_eq!(m, -(order as i64 - 1), "order {order}");
        assert!(
            (value - full).abs() <= 1e-9 * full,
            "order {order}: {value} N"
        );
    }
}
