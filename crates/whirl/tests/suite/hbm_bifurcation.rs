//! Bifurcations named by the crossing Floquet multiplier and located on the branch, on two
//! systems whose stability boundaries are known independently of harmonic balance:
//!
//! - a Jeffcott rotor with internal (rotating) damping, which loses stability through a
//!   complex pair (Neimark-Sacker) at the closed-form threshold speed;
//! - a damped Mathieu oscillator under a constant load, whose first parametric resonance
//!   is bounded by period doublings, located against the monodromy matrix integrated over
//!   one period by Runge-Kutta (independent of the library's exponential midpoint rule);
//!   unloaded, its second resonance, bounded by a real multiplier through +1.

use std::f64::consts::TAU;

use whirl::force::{Kinematics, NonlinearForce};
use whirl::hbm::{
    continuation, resolution, solutions_at, Bifurcation, BifurcationKind, Branch,
    ContinuationOptions, Derivatives, FloquetProblem, HarmonicBalance, HbOptions, HbSolution,
    Periodic, RESOLUTION_TOLERANCE,
};
use whirl::system::System;
use whirl::Result;

use crate::common::{Jeffcott, Oscillator, RingRotor};

/// What a spinning shaft adds to a Jeffcott rotor in the fixed frame (w the speed, J the
/// quarter turn):
/// - internal damping c_i, acting on the velocity relative to the shaft: F = -c_i (v - w J
///   q), (F_x, F_y) = -c_i (x' + w y, y' - w x);
/// - a stiffness asymmetry, k (1 +- e) along the shaft's two principal axes: beside the
///   mean k in the matrices, F = -k e [[cos 2wt, sin 2wt], [sin 2wt, -cos 2wt]] q.
struct RotatingShaft {
    dofs: [usize; 2],
    internal_damping: f64,
    asymmetry: f64,
}

impl NonlinearForce for RotatingShaft {
    fn name(&self) -> String {
        "internal damping and shaft asymmetry".into()
    }
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn force(&mut self, at: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]) {
        let (mut dfdq, mut dfdv) = ([0.0; 4], [0.0; 4]);
        self.jacobian(at, q, v, &mut dfdq, &mut dfdv);
        // Linear in (q, v): F = dF/dq q + dF/dv v.
        for (i, f) in out.iter_mut().enumerate() {
            *f = (0..2)
                .map(|j| dfdq[2 * i + j] * q[j] + dfdv[2 * i + j] * v[j])
                .sum();
        }
    }
    fn jacobian(
        &mut self,
        at: &Kinematics,
        _: &[f64],
        _: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        let (c, w, k) = (self.internal_damping, at.speed, self.asymmetry);
        let (cos, sin) = ((2.0 * at.angle).cos(), (2.0 * at.angle).sin());
        dfdq.copy_from_slice(&[-k * cos, -c * w - k * sin, c * w - k * sin, k * cos]);
        dfdv.copy_from_slice(&[-c, 0.0, 0.0, -c]);
    }
    fn stiffness_bound(&self) -> Vec<f64> {
        vec![self.asymmetry; 4]
    }
}

/// m = 1, k = 1 (natural frequency 1 rad/s), external damping 0.02, internal 0.04,
/// unbalance m e = 0.01.
const EXTERNAL: f64 = 0.02;
const INTERNAL: f64 = 0.04;

/// The Jeffcott rotor with internal damping.
fn internally_damped() -> System {
    internally_damped_with(EXTERNAL)
}

/// The Jeffcott rotor with internal damping [`INTERNAL`] and external damping `external`:
/// its threshold speed is 1 + external / [`INTERNAL`] rad/s.
fn internally_damped_with(external: f64) -> System {
    let rotor = Jeffcott {
        mass: 1.0,
        stiffness: 1.0,
        damping: external,
        unbalance: 0.01,
    };
    System {
        nonlinear: vec![Box::new(RotatingShaft {
            dofs: [0, 1],
            internal_damping: INTERNAL,
            asymmetry: 0.0,
        })],
        ..rotor.system()
    }
}

#[test]
fn internal_damping_loses_stability_by_neimark_sacker_at_the_threshold_speed() {
    let mut hb = HarmonicBalance::new(internally_damped(), HbOptions::new(3)).unwrap();
    let guess = vec![0.0; hb.unknowns()];
    let branch = continuation(&mut hb, 0.5, 3.0, &guess, &ContinuationOptions::default()).unwrap();
    // With z = x + i y: m z'' + (c_e + c_i) z' + (k - i c_i w) z = 0 has the root z = e^{i
    // w_n t} when (c_e + c_i) w_n = c_i w: the threshold speed w_n (1 + c_e / c_i), where
    // the forward whirl at w_n = 1 rad/s starts to grow (e.g. Genta, "Dynamics of Rotating
    // Systems", 2005, section 7.2).
    let threshold = 1.0 + EXTERNAL / INTERNAL;
    eprintln!("internal damping: {:?}", branch.bifurcations);
    assert_eq!(branch.bifurcations.len(), 1);
    let b = branch.bifurcations[0];
    assert_eq!(b.kind, BifurcationKind::NeimarkSacker);
    assert!(b.loses_stability && b.located);
    let error = (b.frequency - threshold).abs() / threshold;
    // The orbit is linear in the unbalance and the tangents constant, so the monodromy
    // matrix is exp(A T) and its exponents the eigenvalues of the linear system to
    // round-off; the regula falsi stops
    // at a bracket of 1e-7 relative and interpolates linearly across it, exact for a real
    // part linear in the speed.
    assert!(
        error < 1e-7,
        "threshold {threshold}, located {}",
        b.frequency
    );
    // The whirl at w_n = 1 rad/s, seen in the strip |Im| <= w / 2 as w - w_n = 0.5.
    assert!((b.exponent_frequency - (threshold - 1.0)).abs() < 1e-6);
    assert!((b.multiplier.0.hypot(b.multiplier.1) - 1.0).abs() < 1e-6);
}

/// The same threshold placed at 1.5, 2 and 2.25 times the natural frequency. At 2 the
/// forward whirl's exponent i w_n sits at exactly half the speed, so its multipliers, the
/// conjugate pair exp(+-i w_n T), meet at -1 there: still a pair crossing the circle
/// (Neimark-Sacker), though at the crossing itself it cannot be told from a real -1 by its
/// imaginary part. Read there, it was named period doubling.
#[test]
fn a_complex_pair_crossing_at_minus_one_is_still_neimark_sacker() {
    for threshold in [1.5, 2.0, 2.25] {
        let external = (threshold - 1.0) * INTERNAL;
        let mut hb =
            HarmonicBalance::new(internally_damped_with(external), HbOptions::new(3)).unwrap();
        let guess = vec![0.0; hb.unknowns()];
        let branch =
            continuation(&mut hb, 0.5, 3.0, &guess, &ContinuationOptions::default()).unwrap();
        eprintln!("threshold {threshold}: {:?}", branch.bifurcations);
        assert_eq!(branch.bifurcations.len(), 1);
        let b = branch.bifurcations[0];
        assert_eq!(b.kind, BifurcationKind::NeimarkSacker, "at {threshold}");
        assert!(b.loses_stability && b.located);
        // As in the test above: the exponents are the linear system's to round-off and the
        // bracket is interpolated linearly, exact for a real part linear in the speed.
        assert!((b.frequency - threshold).abs() < 1e-7 * threshold);
        // The whirl at 1 rad/s seen in the strip |Im| <= w / 2: w - 1 up to w = 2, where it
        // is w / 2, and 1 above.
        let seen = (threshold - 1.0_f64).min(1.0);
        assert!((b.exponent_frequency - seen).abs() < 1e-6);
    }
}

/// The parametric stiffness -k e cos(w t) x of a Mathieu oscillator: a force that depends
/// on the phase, the same at every w for a given orbit.
struct Parametric {
    dofs: [usize; 1],
    amplitude: f64,
}

impl NonlinearForce for Parametric {
    fn name(&self) -> String {
        "parametric stiffness".into()
    }
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn force(&mut self, at: &Kinematics, q: &[f64], _: &[f64], out: &mut [f64]) {
        out[0] = -self.amplitude * at.angle.cos() * q[0];
    }
    fn jacobian(
        &mut self,
        at: &Kinematics,
        _: &[f64],
        _: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        dfdq[0] = -self.amplitude * at.angle.cos();
        dfdv[0] = 0.0;
    }
    fn stiffness_bound(&self) -> Vec<f64> {
        vec![self.amplitude]
    }
}

/// x'' + c x' + (1 + e cos w t) x = 1: a constant load on a damped Mathieu oscillator.
const MATHIEU_DAMPING: f64 = 0.02;
const MATHIEU_DEPTH: f64 = 0.2;

/// The trace and determinant of the monodromy matrix of x'' + c x' + (1 + e cos w t) x = 0
/// over one period, by classical Runge-Kutta with 4000 fixed steps (error of order
/// (T / 4000)^4, below 1e-12 here).
fn monodromy(w: f64, depth: f64) -> (f64, f64) {
    let steps = 4000;
    let h = TAU / w / steps as f64;
    let field = |t: f64, y: [f64; 2]| {
        [
            y[1],
            -MATHIEU_DAMPING * y[1] - (1.0 + depth * (w * t).cos()) * y[0],
        ]
    };
    let mut columns = [[1.0, 0.0], [0.0, 1.0]];
    for y in &mut columns {
        for k in 0..steps {
            let t = k as f64 * h;
            let k1 = field(t, *y);
            let k2 = field(
                t + h / 2.0,
                [y[0] + h / 2.0 * k1[0], y[1] + h / 2.0 * k1[1]],
            );
            let k3 = field(
                t + h / 2.0,
                [y[0] + h / 2.0 * k2[0], y[1] + h / 2.0 * k2[1]],
            );
            let k4 = field(t + h, [y[0] + h * k3[0], y[1] + h * k3[1]]);
            for i in 0..2 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
    }
    let trace = columns[0][0] + columns[1][1];
    let determinant = columns[0][0] * columns[1][1] - columns[1][0] * columns[0][1];
    (trace, determinant)
}

/// A boundary of an instability tongue: where a multiplier is `mu` (-1 for the first
/// tongue, +1 for the second), i.e. the characteristic polynomial mu^2 - tr mu + det
/// vanishes there. Bisection between `lo` and `hi`, which bracket it.
fn tongue_boundary(depth: f64, mu: f64, mut lo: f64, mut hi: f64) -> f64 {
    let f = |w: f64| {
        let (trace, determinant) = monodromy(w, depth);
        mu * mu - mu * trace + determinant
    };
    let f_lo = f(lo);
    assert!(f_lo * f(hi) < 0.0);
    while hi - lo > 1e-12 {
        let mid = 0.5 * (lo + hi);
        if f(mid) * f_lo > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The loaded Mathieu oscillator.
fn mathieu() -> System {
    mathieu_of_depth(MATHIEU_DEPTH)
}

/// The loaded Mathieu oscillator with stiffness 1 + `depth` cos w t.
fn mathieu_of_depth(depth: f64) -> System {
    mathieu_loaded(depth, 1.0)
}

/// The Mathieu oscillator with stiffness 1 + `depth` cos w t under a constant `load`.
fn mathieu_loaded(depth: f64, load: f64) -> System {
    let oscillator = Oscillator {
        mass: 1.0,
        stiffness: 1.0,
        damping: MATHIEU_DAMPING,
    };
    System {
        constant_force: vec![load],
        nonlinear: vec![Box::new(Parametric {
            dofs: [0],
            amplitude: depth,
        })],
        ..oscillator.system()
    }
}

/// The loaded Mathieu oscillator's harmonic balance, H = 8 and 1024 samples: the
/// exponential midpoint rule's error in the tongue's boundaries falls as (2 pi / N)^2
/// (measured against the Runge-Kutta monodromy: 2.2e-5 relative at N = 64, 1.4e-6 at
/// 256); 1024 samples put it near 1e-7.
fn fine_mathieu() -> HarmonicBalance {
    let mut options = HbOptions::new(8);
    options.samples = 1024;
    HarmonicBalance::new(mathieu(), options).unwrap()
}

/// The boundaries of the first tongue by the Runge-Kutta monodromy, rad/s. Undamped, to
/// first order in e, the tongue is (w / 2)^2 = 1 +- e / 2: w = 1.897 and 2.098; damping
/// narrows it.
fn mathieu_tongue() -> [f64; 2] {
    [
        tongue_boundary(MATHIEU_DEPTH, -1.0, 1.85, 2.0),
        tongue_boundary(MATHIEU_DEPTH, -1.0, 2.0, 2.15),
    ]
}

#[test]
fn mathieu_tongue_is_bounded_by_period_doublings_where_the_monodromy_matrix_says() {
    let mut hb = fine_mathieu();
    let guess = vec![0.0; hb.unknowns()];
    let branch = continuation(&mut hb, 1.5, 2.5, &guess, &ContinuationOptions::default()).unwrap();
    eprintln!("Mathieu: {:?}", branch.bifurcations);
    let reference = mathieu_tongue();
    assert_eq!(branch.bifurcations.len(), 2);
    for (b, exact) in branch.bifurcations.iter().zip(reference) {
        let error = (b.frequency - exact).abs() / exact;
        eprintln!(
            "period doubling at {:.10} rad/s, monodromy {exact:.10}, relative {error:.1e}",
            b.frequency
        );
        assert_eq!(b.kind, BifurcationKind::PeriodDoubling);
        assert!(b.located);
        // The midpoint rule at 1024 samples is within about 1e-7 (above); the regula falsi
        // brackets to 1e-5 and interpolates linearly across the bracket (exact for a
        // simple crossing to second order in it), and the reference monodromy is
        // integrated to 1e-12. 1e-6 leaves room for the corrector's tolerance.
        assert!(error < 1e-6, "{} against {exact}", b.frequency);
        assert!((b.exponent_frequency - b.frequency / 2.0).abs() < 1e-6 * b.frequency);
        // The multiplier is read at the trial nearest the crossing, not interpolated: up
        // to a bracket (1e-5 of the arclength) from it, where |mu| differs from 1 by that
        // times d|mu|/ds (measured 6.2e-5 and 3.0e-6 off -1 at the two boundaries). Real
        // and near -1 is what names the doubling.
        assert!((b.multiplier.0 + 1.0).abs() < 3e-4 && b.multiplier.1 == 0.0);
    }
    assert!(branch.bifurcations[0].loses_stability && !branch.bifurcations[1].loses_stability);
}

/// A Mathieu tongue narrower than the path's spacing, between two stable points. Outside
/// the tongue the oscillator's two exponents share the real part -c/2 at every point, so
/// the largest real part is flat and the window probe has no extremum to follow; the pair
/// meets the negative axis only just before the tongue. The path's points are 10 % apart
/// and straddle the tongue (depth 0.08: about 1.97-2.03 rad/s); the mode (1 rad/s) meets
/// half the speed there, where the tongue probe samples and finds it, and both edges are
/// located where the monodromy matrix puts them.
#[test]
fn a_period_doubling_tongue_between_two_stable_points_is_found() {
    let depth = 0.08;
    let reference = [
        tongue_boundary(depth, -1.0, 1.9, 2.0),
        tongue_boundary(depth, -1.0, 2.0, 2.1),
    ];
    let system = mathieu_of_depth(depth);
    found_between_stable_points(
        system,
        [1.6, 2.5],
        reference,
        BifurcationKind::PeriodDoubling,
    );
}

/// The Mathieu oscillator's second tongue, where the mode (1 rad/s) meets the speed and a
/// real multiplier leaves the circle at +1 where the branch does not turn: narrower than
/// the path's spacing and between two stable points, as the first tongue in the test above.
/// Unloaded, so the orbit is the rest at every speed (a load would meet the +1 multiplier
/// as a resonance, the periodic forced response having no bound there). Depth 0.4: the
/// second tongue is of order e^2 wide and damping closes it below about e = 0.3; here it
/// spans about 0.969-1.004 rad/s, between points at 0.944 and 1.038.
#[test]
fn a_tongue_through_plus_one_between_two_stable_points_is_found() {
    let depth = 0.4;
    let reference = [
        tongue_boundary(depth, 1.0, 0.94, 0.985),
        tongue_boundary(depth, 1.0, 0.99, 1.02),
    ];
    let system = mathieu_loaded(depth, 0.0);
    found_between_stable_points(
        system,
        [0.78, 1.3],
        reference,
        BifurcationKind::SymmetryBreaking,
    );
}

/// Follows `system` over `range` (rad/s) with points 10 % apart, every one of them stable,
/// and finds one tongue of `kind` between two of them, its edges at `reference`.
fn found_between_stable_points(
    system: System,
    [from, to]: [f64; 2],
    reference: [f64; 2],
    kind: BifurcationKind,
) {
    let mut options = HbOptions::new(8);
    options.samples = 1024;
    let mut hb = HarmonicBalance::new(system, options).unwrap();
    let steps = ContinuationOptions {
        initial_step: 0.1,
        max_step: 0.1,
        ..ContinuationOptions::default()
    };
    let guess = vec![0.0; hb.unknowns()];
    let branch = continuation(&mut hb, from, to, &guess, &steps).unwrap();
    let speeds: Vec<f64> = branch.points.iter().map(|p| p.solution.frequency).collect();
    eprintln!(
        "narrow Mathieu tongue {reference:?}: points {speeds:?}, {:?}",
        branch.bifurcations
    );
    // Every point of the path is stable: the tongue lies between two of them.
    assert!(branch
        .points
        .iter()
        .all(|p| p.stability.as_ref().is_some_and(|s| s.stable)));
    assert_eq!(branch.bifurcations.len(), 2);
    for (b, exact) in branch.bifurcations.iter().zip(reference) {
        assert_eq!(b.kind, kind);
        // As for the wide tongue above: the midpoint rule at 1024 samples and the bracket.
        assert!(
            (b.frequency - exact).abs() < 1e-6 * exact,
            "{} against {exact}",
            b.frequency
        );
    }
    assert!(branch.bifurcations[0].loses_stability && !branch.bifurcations[1].loses_stability);
}

/// The resolution check at twice the samples confirms the Mathieu tongue's boundaries (a
/// smooth problem: the boundaries move by about 1e-5 relative from 64 to 128 samples, far
/// inside the check's 0.5 %), and refuses a change the doubled count does not show: the
/// same boundaries moved outside the tongue, or named by the wrong multiplier.
#[test]
fn resolution_check_confirms_the_mathieu_boundaries_and_refuses_false_ones() {
    let mut options = HbOptions::new(8);
    options.samples = 64;
    let mut hb = HarmonicBalance::new(mathieu(), options).unwrap();
    let guess = vec![0.0; hb.unknowns()];
    let branch = continuation(&mut hb, 1.5, 2.5, &guess, &ContinuationOptions::default()).unwrap();
    assert_eq!(branch.bifurcations.len(), 2);
    let mut fine = hb.with_samples(128).unwrap();
    for b in &branch.bifurcations {
        let r = resolution::check(&mut fine, &branch, b).unwrap();
        eprintln!("{:.6} rad/s: {r:?}", b.frequency);
        assert_eq!(r.samples, 128);
        // The sides, 0.5 % of the speed away along the path (inside the tongue, 1.9-2.1
        // rad/s, and the range), interpolated exactly there.
        for (speed, sign) in r.speeds.iter().zip([-1.0, 1.0]) {
            let expected = b.frequency * (1.0 + sign * RESOLUTION_TOLERANCE);
            assert!((speed - expected).abs() < 1e-12 * expected, "{speed}");
        }
        assert!(r.resolved, "{r:?}");
        assert_eq!(r.kind, Some(BifurcationKind::PeriodDoubling));
    }
    // Outside the tongue both sides are stable: a loss claimed at 1.8 rad/s is not resolved.
    let mut moved = branch.bifurcations[0];
    let below = branch
        .points
        .iter()
        .position(|p| p.solution.frequency > 1.8)
        .unwrap();
    (moved.frequency, moved.after) = (1.8, below - 1);
    let r = resolution::check(&mut fine, &branch, &moved).unwrap();
    assert_eq!(r.stable, [Some(true), Some(true)]);
    assert!(!r.resolved);
    // The right place, the wrong multiplier: a doubling is not a Neimark-Sacker point.
    let mut misnamed = branch.bifurcations[0];
    misnamed.kind = BifurcationKind::NeimarkSacker;
    let r = resolution::check(&mut fine, &branch, &misnamed).unwrap();
    assert_eq!(r.kind, Some(BifurcationKind::PeriodDoubling));
    assert!(!r.resolved);
}

/// A harmonic balance with a corner between every two points of its path: while its
/// bifurcations are located (the only time continuation asks for refined residuals,
/// [`Periodic::refine_residuals`]) every residual is NaN, so every trial point's arclength
/// corrector fails, as it does at a corner of the reference rotor's branch where a contact
/// opens. Newton at a fixed speed ([`Periodic::solve`]) is untouched.
struct Cornered {
    hb: HarmonicBalance,
    locating: bool,
}

impl Periodic for Cornered {
    fn options(&self) -> &HbOptions {
        self.hb.options()
    }
    fn solve(&mut self, frequency: f64, guess: &[f64]) -> Result<HbSolution> {
        self.hb.solve(frequency, guess)
    }
    fn residual_at(&mut self, x: &[f64], frequency: f64) -> (Vec<f64>, f64) {
        if self.locating {
            (vec![f64::NAN; x.len()], f64::NAN)
        } else {
            Periodic::residual_at(&mut self.hb, x, frequency)
        }
    }
    fn derivatives(&mut self, x: &[f64], frequency: f64) -> Derivatives {
        Periodic::derivatives(&mut self.hb, x, frequency)
    }
    fn floquet_problem(&mut self, x: &[f64], frequency: f64) -> Result<FloquetProblem> {
        Periodic::floquet_problem(&mut self.hb, x, frequency)
    }
    fn refine_residuals(&mut self, on: bool) {
        self.locating = on;
    }
}

/// The branch of `hb` from `from` to `to` (rad/s) from rest, with a corner between every
/// two of its points ([`Cornered`]).
fn cornered_branch(hb: HarmonicBalance, from: f64, to: f64) -> Branch {
    let guess = vec![0.0; hb.unknowns()];
    let mut cornered = Cornered {
        hb,
        locating: false,
    };
    continuation(
        &mut cornered,
        from,
        to,
        &guess,
        &ContinuationOptions::default(),
    )
    .unwrap()
}

/// The speed where the largest real part crosses zero, interpolated linearly between the
/// two path points around `b`: where a locator that gives up at a corner puts it.
fn between_points(branch: &Branch, b: &Bifurcation) -> f64 {
    let (p, q) = (&branch.points[b.after], &branch.points[b.after + 1]);
    let (ga, gb) = (
        p.stability.as_ref().unwrap().max_real,
        q.stability.as_ref().unwrap().max_real,
    );
    let (wa, wb) = (p.solution.frequency, q.solution.frequency);
    wa + ga / (ga - gb) * (wb - wa)
}

/// Where every arclength trial fails, the crossing is still located on the branch, by
/// Newton at fixed speed (the branch does not turn there), as accurately as along the
/// arclength: the Jeffcott threshold and the Mathieu boundaries of the tests above, to the
/// same tolerances. Interpolated between the path's points instead, each would be off by
/// far more (checked, so that this test can fail).
#[test]
fn a_crossing_the_arclength_corrector_cannot_reach_is_located_at_fixed_speed() {
    let hb = HarmonicBalance::new(internally_damped(), HbOptions::new(3)).unwrap();
    let branch = cornered_branch(hb, 0.5, 3.0);
    let threshold = 1.0 + EXTERNAL / INTERNAL;
    assert_eq!(branch.bifurcations.len(), 1);
    let b = branch.bifurcations[0];
    assert_eq!(b.kind, BifurcationKind::NeimarkSacker);
    assert!(b.loses_stability && b.located);
    // The exponents are the linear system's to round-off (the first test), smooth in the
    // speed; the regula falsi in the speed stops at a bracket of 1e-5 relative and
    // interpolates linearly across it, an error of the order of the bracket squared times
    // the real part's curvature: measured 4e-14. Across the path's points (a few hundredths
    // apart) the same interpolation is 5.6e-7 off.
    let error = (b.frequency - threshold).abs() / threshold;
    let interpolated = (between_points(&branch, &b) - threshold).abs() / threshold;
    eprintln!("cornered Jeffcott: located {error:.1e} off, between points {interpolated:.1e}");
    assert!(
        error < 1e-9,
        "threshold {threshold}, located {}",
        b.frequency
    );
    assert!(interpolated > 1e-7, "{interpolated}");

    let branch = cornered_branch(fine_mathieu(), 1.5, 2.5);
    let reference = mathieu_tongue();
    assert_eq!(branch.bifurcations.len(), 2);
    for (b, exact) in branch.bifurcations.iter().zip(reference) {
        let error = (b.frequency - exact).abs() / exact;
        let interpolated = (between_points(&branch, b) - exact).abs() / exact;
        eprintln!("cornered Mathieu: located {error:.1e} off, between points {interpolated:.1e}");
        assert_eq!(b.kind, BifurcationKind::PeriodDoubling);
        assert!(b.located);
        // The tolerance of the Mathieu test above (the midpoint rule at 1024 samples,
        // about 1e-7; the bracket 1e-5 of the speed, interpolated across).
        assert!(error < 1e-6, "{} against {exact}", b.frequency);
        assert!(interpolated > 1e-5, "{interpolated}");
    }
}

/// An unloaded asymmetric shaft (m = k = 1, damping c = 0.02, asymmetry e = 0.03) is
/// unstable between its two critical speeds where the damping does not hold it: in the
/// rotating frame (x + i y = e^{i w t} zeta) its equation has constant coefficients, and a
/// real exponent crosses zero where (k - m w^2)^2 + c^2 w^2 = (k e)^2, at about 0.98866
/// and 1.01102 rad/s (a multiplier +1 where the branch, the rotor at rest, does not turn:
/// symmetry breaking). Outside that window the largest real part is -c / (2 m), flat; it
/// rises only within about 0.4 % of the edges. Steps of 3.89 % from 0.95 rad/s put the
/// path's points at 0.95, 0.98696 (on the rising shoulder) and 1.02535 rad/s: every point
/// is stable, and the window between them is found only by probing round the shoulder's
/// extremum, then both edges are located.
#[test]
fn a_window_narrower_than_the_point_spacing_is_probed_and_located() {
    let (damping, asymmetry) = (0.02, 0.03);
    let rotor = Jeffcott {
        mass: 1.0,
        stiffness: 1.0,
        damping,
        unbalance: 0.0,
    };
    let system = System {
        nonlinear: vec![Box::new(RotatingShaft {
            dofs: [0, 1],
            internal_damping: 0.0,
            asymmetry,
        })],
        ..rotor.system()
    };
    // The exponential midpoint rule's error falls as (2 pi / N)^2: 2e-6 of the edges at
    // N = 256, 1.3e-7 at 1024 (as on the Mathieu tongue above).
    let mut options = HbOptions::new(3);
    options.samples = 1024;
    let mut hb = HarmonicBalance::new(system, options).unwrap();
    let steps = ContinuationOptions {
        initial_step: 0.0389,
        max_step: 0.0389,
        ..ContinuationOptions::default()
    };
    let rest = vec![0.0; hb.unknowns()];
    let branch = continuation(&mut hb, 0.95, 1.1, &rest, &steps).unwrap();
    let speeds: Vec<f64> = branch.points.iter().map(|p| p.solution.frequency).collect();
    eprintln!(
        "asymmetric shaft: points {speeds:?}, {:?}",
        branch.bifurcations
    );
    assert!(speeds.iter().any(|&w| (0.985..0.9886).contains(&w)));
    assert!(branch
        .points
        .iter()
        .all(|p| p.stability.as_ref().unwrap().stable));
    // (1 - u)^2 + c^2 u = e^2 in u = w^2.
    let b = 2.0 - damping * damping;
    let root = (b * b - 4.0 * (1.0 - asymmetry * asymmetry)).sqrt();
    let edges = [((b - root) / 2.0).sqrt(), ((b + root) / 2.0).sqrt()];
    assert_eq!(branch.bifurcations.len(), 2);
    for (found, (edge, loses)) in branch
        .bifurcations
        .iter()
        .zip(edges.into_iter().zip([true, false]))
    {
        assert_eq!(found.loses_stability, loses);
        assert_eq!(found.kind, BifurcationKind::SymmetryBreaking);
        assert!(found.located);
        // The midpoint rule (above) and the bracket of 1e-5, interpolated across: 1e-6.
        let error = (found.frequency - edge).abs() / edge;
        assert!(error < 1e-6, "{} against {edge}", found.frequency);
    }
}

/// A Jeffcott rotor in a clearance ring (m = k = 1, c = 0.05, contact 10 times the shaft's
/// stiffness, clearance 1) with the internal damping above: threshold 1 + 0.05 / 0.04 =
/// 2.25 rad/s, on the free orbit (inside the ring the contact adds nothing).
fn damped_ring(unbalance: f64) -> RingRotor {
    RingRotor {
        rotor: Jeffcott {
            mass: 1.0,
            stiffness: 1.0,
            damping: 0.05,
            unbalance,
        },
        contact: 10.0,
        clearance: 1.0,
    }
}

/// With m e = 0.15 and 0.5 the orbit hits the ring below resonance, the contact branch
/// bends over to a fold (3.16 and 3.28 rad/s) and its middle leg comes back down to the
/// grazing corner (1.080 and 1.412 rad/s), where it ends on the free branch, which goes
/// back up in speed. With 0.5 the turn there is sharper than a right angle: the path found
/// nothing ahead and jumped from the corner past the fold (1.41 to 3.28 rad/s), the free
/// orbit over that stretch missing, the internal-damping threshold on it too, and
/// `solutions_at` gave 2 of the 3 orbits at 2 rad/s without a word.
#[test]
fn the_path_turns_at_the_grazing_corner_onto_the_free_orbit() {
    for unbalance in [0.15, 0.5] {
        let ring = damped_ring(unbalance);
        let mut system = ring.system();
        system.nonlinear.push(Box::new(RotatingShaft {
            dofs: [0, 1],
            internal_damping: INTERNAL,
            asymmetry: 0.0,
        }));
        let mut hb = HarmonicBalance::new(system, HbOptions::new(3)).unwrap();
        let guess = vec![0.0; hb.unknowns()];
        let branch =
            continuation(&mut hb, 0.2, 6.0, &guess, &ContinuationOptions::default()).unwrap();
        let kinds: Vec<_> = branch
            .bifurcations
            .iter()
            .map(|b| (b.kind, b.frequency))
            .collect();
        eprintln!(
            "ring, m e = {unbalance}: jumps {:?}, corners {:?}, folds {:?}, {kinds:?}",
            branch.jumps,
            branch.corners,
            branch.folds.iter().map(|f| f.frequency).collect::<Vec<_>>()
        );
        assert!(branch.jumps.is_empty(), "m e = {unbalance}");
        let corner = ring.corner();
        assert!(branch
            .points
            .iter()
            .any(|p| (p.solution.frequency - corner).abs() < 0.01 * corner));
        // The threshold on the free orbit, where the contact adds nothing: as on the rotor
        // without the ring, the exponents are the linear system's (1e-7, the test above).
        let threshold = 1.0 + 0.05 / INTERNAL;
        assert!(branch
            .bifurcations
            .iter()
            .any(|b| b.kind == BifurcationKind::NeimarkSacker
                && (b.frequency - threshold).abs() < 1e-7 * threshold));
        // At 2 rad/s: the upper and middle contact orbits and the free one, all followed.
        let at = solutions_at(&mut hb, &branch, 2.0).unwrap();
        let radii: Vec<f64> = at
            .crossings
            .iter()
            .map(|c| c.solution.coefficients[2].hypot(c.solution.coefficients[4]))
            .collect();
        eprintln!("m e = {unbalance}, radii at 2 rad/s: {radii:?}");
        assert!(at.complete());
        assert_eq!(radii.len(), 3);
        assert_eq!(radii.iter().filter(|&&r| r < ring.clearance).count(), 1);
    }
}

/// Where the path jumps, `solutions_at` says the list may lack orbits: the ring with
/// m e = 0.5 restarted by hand past the fold, as the path did before it turned at corners.
#[test]
fn solutions_at_names_the_jump_a_speed_lies_in() {
    let mut hb = HarmonicBalance::new(damped_ring(0.5).system(), HbOptions::new(3)).unwrap();
    let guess = vec![0.0; hb.unknowns()];
    let mut branch =
        continuation(&mut hb, 0.2, 6.0, &guess, &ContinuationOptions::default()).unwrap();
    // The middle leg ends at the corner, its lowest speed after the fold; the free orbit
    // goes on up from there.
    let fold = branch.folds[0].after;
    let speed = |i: usize| branch.points[i].solution.frequency;
    let corner = (fold..branch.points.len())
        .min_by(|&i, &j| speed(i).total_cmp(&speed(j)))
        .unwrap();
    let resumed = (corner..branch.points.len())
        .find(|&i| speed(i) > 3.3)
        .unwrap();
    branch.points.drain(corner + 1..resumed);
    let (from, to) = (
        branch.points[corner].solution.frequency,
        branch.points[corner + 1].solution.frequency,
    );
    branch.jumps = vec![(from, to)];
    branch.jumped_after = vec![corner];
    let at = solutions_at(&mut hb, &branch, 2.0).unwrap();
    assert_eq!(at.crossings.len(), 2);
    assert_eq!(at.jumped_over, vec![(from, to)]);
    assert!(!at.complete());
    assert!(solutions_at(&mut hb, &branch, 5.0).unwrap().complete());
}
