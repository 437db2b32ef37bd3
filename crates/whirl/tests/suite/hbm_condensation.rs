//! Exact dynamic condensation of harmonic balance onto the coordinates that carry nonlinear
//! forces: the reference rotor solved condensed and in full gives the same Fourier
//! coefficients, faster; and an isotropic rotor in a clearance ring
//! reproduces the exact synchronous circular orbit through the multi-valued resonance.

use std::f64::consts::TAU;
use std::time::Instant;

use faer::Mat;
use whirl::fe;
use whirl::force::{CubicSpring, NonlinearForce};
use whirl::hbm::{continuation, CondensedBalance, ContinuationOptions, HarmonicBalance, HbOptions};
use whirl::system::System;

use crate::common;
use crate::common::{Jeffcott, RingRotor};

const HARMONICS: usize = 3;

/// The reference rotor on linearised bearings with hardening cubic springs on both
/// directions of bearing A (node 0) and bearing B (node 20): four nonlinear coordinates out
/// of 84. `cubic` k3 in N/m^3.
fn reference_rotor(cubic: f64) -> System {
    let model = common::reference_rotor();
    let system = fe::assemble(&model, fe::Bearings::Linearised);
    let n = system.dofs();
    let unbalance = fe::unbalance_force(&model, n);
    let dofs = [
        fe::dof(0, fe::Direction::Ux),
        fe::dof(0, fe::Direction::Uy),
        fe::dof(20, fe::Direction::Ux),
        fe::dof(20, fe::Direction::Uy),
    ];
    System {
        // A constant load on bearing A makes the cubic springs generate even harmonics too.
        constant_force: (0..n)
            .map(|d| if d == dofs[1] { -200.0 } else { 0.0 })
            .collect(),
        unbalance_re: unbalance.iter().map(|f| f.re).collect(),
        unbalance_im: unbalance.iter().map(|f| f.im).collect(),
        nonlinear: dofs
            .iter()
            .map(|&d| Box::new(CubicSpring::new(d, 0.0, cubic, 1e-4)) as Box<dyn NonlinearForce>)
            .collect(),
        ..System::unloaded(system)
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
        let start_full = linear.recover(&start).unwrap();
        let bearing = largest(&start.coefficients);

        let clock = Instant::now();
        let reference = full.solve(w, &start_full).unwrap();
        let full_solve = clock.elapsed().as_secs_f64();

        let clock = Instant::now();
        let solution = condensed.solve(w, &start.coefficients).unwrap();
        let recovered = condensed.recover(&solution).unwrap();
        let condensed_solve = clock.elapsed().as_secs_f64();

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
            "{hz} Hz: largest bearing coefficient {bearing:.3e} m, nonlinear shift \
             {moved:.2e}, condensed vs full {relative:.2e} relative; Newton solve full \
             {:.2} ms ({} iterations), condensed {:.2} ms ({} iterations, condensation and \
             recovery included)",
            1e3 * full_solve,
            reference.iterations,
            1e3 * condensed_solve,
            solution.iterations,
        );
        full_time += full_solve;
        condensed_time += condensed_solve;
        // The nonlinearity must matter, or the check would only test linear algebra.
        assert!(moved > 1e-3, "nonlinear shift {moved:e}");
        // Both are converged to a relative residual 1e-10 by quadratic Newton (so in fact
        // to round-off), and the condensation is exact: they agree to round-off of the
        // dynamic stiffness solves, amplified by its conditioning near the criticals.
        assert!(relative < 1e-9, "condensed vs full {relative:e}");
    }
    eprintln!(
        "mean time per Newton solve: full {:.2} ms, condensed {:.2} ms",
        1e3 * full_time / 3.0,
        1e3 * condensed_time / 3.0
    );
    assert!(condensed_time < full_time);
}

#[test]
fn condensed_continuation_lands_where_full_continuation_lands() {
    // The same path on the reference rotor through the first critical speed, condensed (4
    // unknowns per slot) and full (84): the points differ (steps are scaled by each
    // problem's own coefficients) but both land on the end frequency by Newton, where they
    // must agree as the single solves do.
    let options = HbOptions::new(HARMONICS);
    let path = ContinuationOptions {
        stability: false,
        ..ContinuationOptions::default()
    };
    let (from, to) = (TAU * 150.0, TAU * 200.0);
    let mut full = HarmonicBalance::new(reference_rotor(CUBIC), options).unwrap();
    let mut condensed = CondensedBalance::new(reference_rotor(CUBIC), options).unwrap();
    let clock = Instant::now();
    let zero = vec![0.0; full.unknowns()];
    let full_branch = continuation(&mut full, from, to, &zero, &path).unwrap();
    let full_time = clock.elapsed();
    let clock = Instant::now();
    let zero = vec![0.0; condensed.unknowns()];
    let condensed_branch = continuation(&mut condensed, from, to, &zero, &path).unwrap();
    let condensed_time = clock.elapsed();
    let (a, b) = (
        full_branch.points.last().unwrap(),
        condensed_branch.points.last().unwrap(),
    );
    assert_eq!(a.solution.frequency, to);
    assert_eq!(b.solution.frequency, to);
    let recovered = condensed.recover(&b.solution).unwrap();
    let difference: Vec<f64> = recovered
        .iter()
        .zip(&a.solution.coefficients)
        .map(|(x, y)| x - y)
        .collect();
    let relative = largest(&difference) / largest(&a.solution.coefficients);
    eprintln!(
        "continuation 150-200 Hz: full {} points in {full_time:?}, condensed {} points in \
         {condensed_time:?}; end points agree to {relative:.2e}",
        full_branch.points.len(),
        condensed_branch.points.len()
    );
    // As for the single solves: both converged to round-off, condensation exact.
    assert!(relative < 1e-9, "end points differ by {relative:e}");
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

/// Jeffcott rotor in the ring: m = 1, k = 1, damping ratio 2.5 %, contact 10 times stiffer
/// than the shaft, unbalance m e = 0.2 whose free resonance amplitude 4 is far beyond the
/// clearance 1, so the orbit hits the ring and the resonance bends over (multi-valued).
const RING: RingRotor = RingRotor {
    rotor: Jeffcott {
        mass: 1.0,
        stiffness: 1.0,
        damping: 0.05,
        unbalance: 0.2,
    },
    contact: 10.0,
    clearance: 1.0,
};

/// Radius of the first harmonic of x, and the largest departure from a forward circular
/// orbit relative to it: y = r sin(w t - phi) has y_cos = -x_sin and y_sin = x_cos, and the
/// constant term and higher harmonics vanish.
fn ring_orbit(x: &[f64]) -> (f64, f64) {
    let n = 2;
    let (xc, xs, yc, ys) = (x[n], x[2 * n], x[n + 1], x[2 * n + 1]);
    let r = xc.hypot(xs);
    let others = x
        .iter()
        .enumerate()
        .filter(|&(i, _)| !(n..3 * n).contains(&i))
        .fold(0.0f64, |m, (_, v)| m.max(v.abs()));
    (r, ((yc + xs).abs() + (ys - xc).abs() + others) / r)
}

#[test]
fn clearance_ring_reproduces_the_exact_circular_orbit_through_the_overhang() {
    let options = HbOptions::new(HARMONICS);
    // Every coordinate carries the contact force: the condensation keeps both and
    // condenses nothing, and continuation runs on the condensed problem.
    let mut hb = CondensedBalance::new(RING.system(), options).unwrap();
    let guess = vec![0.0; hb.unknowns()];
    let path = ContinuationOptions {
        stability: false,
        ..ContinuationOptions::default()
    };
    // The contact branch (r > gamma) is smooth: it leaves the free branch at w = 0.92,
    // where the free orbit reaches the ring, bends over to a fold near the stiffened
    // resonance and comes back (middle branch) to meet the free branch at a corner
    // (r = gamma, w = 1.1145), where the contact stiffness jumps; the path turns there onto
    // the free branch and follows it to the end.
    let branch = continuation(&mut hb, 0.95, 5.0, &guess, &path).unwrap();
    let (mut worst_orbit, mut worst_closed, mut widest) = (0.0f64, 0.0f64, 0.0f64);
    let mut check = |x: &[f64], w: f64| {
        let (r, orbit) = ring_orbit(x);
        worst_orbit = worst_orbit.max(orbit);
        worst_closed = worst_closed.max(RING.defect(w, r).abs());
        r
    };
    for p in &branch.points {
        widest = widest.max(check(&p.solution.coefficients, p.solution.frequency));
    }
    // At w = 2 three orbits coexist: on the upper and middle contact branches and free.
    let w = 2.0;
    let crossings: Vec<f64> = branch
        .points
        .windows(2)
        .filter(|p| (p[0].solution.frequency - w) * (p[1].solution.frequency - w) <= 0.0)
        .map(|p| ring_orbit(&p[0].solution.coefficients).0)
        .collect();
    let free = hb.solve(w, &guess).unwrap();
    let free_radius = check(&free.coefficients, w);
    let lowest_middle = branch
        .points
        .iter()
        .filter(|p| p.frequency_slope < 0.0)
        .map(|p| p.solution.frequency)
        .fold(f64::INFINITY, f64::min);
    let fold = RING.fold();
    let fold_error = (branch.folds[0].frequency - fold).abs() / fold;
    eprintln!("clearance ring: closed-form fold {fold:.12} rad/s, located to {fold_error:.2e}");
    eprintln!(
        "clearance ring: {} points, folds at {:?} rad/s, largest radius {widest:.3}, middle \
         branch down to {lowest_middle:.4} rad/s; radii at w = 2: contact {crossings:.3?}, \
         free {free_radius:.3}; worst circularity {worst_orbit:.2e}, worst closed-form \
         defect {worst_closed:.2e} ({:?})",
        branch.points.len(),
        branch.folds.iter().map(|f| f.frequency).collect::<Vec<_>>(),
        branch.end
    );
    // The multi-valued part: the fold and the corner, and at w = 2 the two contact orbits
    // and the free one, all three on the path.
    assert_eq!(branch.folds.len(), 2);
    assert_eq!(crossings.len(), 3);
    assert!(crossings[..2].iter().all(|&r| r > RING.clearance));
    assert!(crossings[2] < RING.clearance && free_radius < RING.clearance);
    assert!(widest > 2.0 * RING.clearance);
    assert!(matches!(branch.end, whirl::hbm::BranchEnd::Reached));
    // The corner, where the free orbit's radius m e w^2 / |k - m w^2 + i c w| equals
    // gamma: with u = w^2, (m^2 - (m e)^2 / gamma^2) u^2 + (c^2 - 2 k m) u + k^2 = 0 (larger
    // root). The tangent jumps there, yet the sign change of its frequency component is
    // bracketed down to the corner itself by the regula falsi (measured 1.7e-12).
    let corner = RING.corner();
    let corner_error = (branch.folds[1].frequency - corner).abs() / corner;
    eprintln!("clearance ring: corner {corner:.6} rad/s, located to {corner_error:.1e}");
    assert!(
        corner_error < 1e-8,
        "corner {corner} located to {corner_error:e}"
    );
    assert!(
        lowest_middle < 1.25,
        "middle branch ends at {lowest_middle}"
    );
    // Newton converges to a relative residual of 1e-10 and the circular orbit is exact in
    // the Fourier basis (constant radius: the sampled contact force has no other harmonic),
    // so both defects are at the solver's tolerance, well below 1e-8.
    assert!(worst_orbit < 1e-8, "circularity {worst_orbit:e}");
    assert!(worst_closed < 1e-9, "closed form {worst_closed:e}");
    // The fold is located on the branch as accurately as the corrector converges; the
    // frequency is flat there (dw/dr = 0), so it is better than the radius.
    assert!(fold_error < 1e-9, "fold {fold_error:e}");
}

/// The same ring with a smaller unbalance, m e = 0.15 (free resonance amplitude 3, still
/// three clearances), followed with default options from w = 0.2, where the orbit is 200
/// times smaller than at the fold: the arclength is scaled at each point, so the steps
/// grow with the orbit and the fold is reached and located.
#[test]
fn clearance_ring_fold_is_reached_from_a_small_start_amplitude() {
    let ring = RingRotor {
        rotor: Jeffcott {
            unbalance: 0.15,
            ..RING.rotor
        },
        ..RING
    };
    let mut hb = CondensedBalance::new(ring.system(), HbOptions::new(HARMONICS)).unwrap();
    let guess = vec![0.0; hb.unknowns()];
    let branch = continuation(&mut hb, 0.2, 5.0, &guess, &ContinuationOptions::default()).unwrap();
    let start = ring_orbit(&branch.points[0].solution.coefficients).0;
    let widest = branch
        .points
        .iter()
        .map(|p| ring_orbit(&p.solution.coefficients).0)
        .fold(0.0f64, f64::max);
    let fold = ring.fold();
    eprintln!(
        "clearance ring, m e = 0.15: {} points, start radius {start:.2e}, largest {widest:.3}, \
         folds {:?} (closed form {fold:.10}), jumps {:?}, {:?}",
        branch.points.len(),
        branch.folds.iter().map(|f| f.frequency).collect::<Vec<_>>(),
        branch.jumps,
        branch.end
    );
    assert!(matches!(branch.end, whirl::hbm::BranchEnd::Reached));
    assert!(branch.jumps.is_empty());
    assert!(widest > 100.0 * start);
    // The fold, then the corner where the path rejoins the free branch.
    assert_eq!(branch.folds.len(), 2);
    let error = (branch.folds[0].frequency - fold).abs() / fold;
    // As with m e = 0.2: located on the branch to the corrector's tolerance.
    assert!(
        error < 1e-9,
        "fold {} against {fold}: {error:e}",
        branch.folds[0].frequency
    );
}

/// The Floquet stability of the condensed path (the monodromy matrix of a Craig-Bampton
/// model of the linear part with the nonlinear coordinates as boundary) against Hill's
/// method on the full model, an independent route (a different model, the exponents from
/// an eigenproblem in the frequency domain): the exponents of the low modes and the largest
/// real part agree.
#[test]
fn condensed_floquet_stability_matches_full_hill_on_the_reference_rotor() {
    // H = 5, the sweep's: Hill's exponents converge in H (at H = 3 the least damped ones
    // lay 0.13 rad/s from the monodromy's at 330 Hz, at H = 5 0.055 rad/s), the monodromy's
    // in the samples (the same to 1e-2 rad/s with 256 and 1024). The orbit is free of
    // aliasing from 32 samples on, so both models solve the same one.
    let options = HbOptions {
        samples: 256,
        ..HbOptions::new(5)
    };
    let mut full = HarmonicBalance::new(reference_rotor(CUBIC), options).unwrap();
    let mut condensed = CondensedBalance::new(reference_rotor(CUBIC), options).unwrap();
    for hz in [120.0, 330.0] {
        let w = TAU * hz;
        let zero = vec![0.0; condensed.unknowns()];
        let solution = condensed.solve(w, &zero).unwrap();
        let recovered = condensed.recover(&solution).unwrap();
        let clock = Instant::now();
        let reduced = condensed.stability(&solution.coefficients, w).unwrap();
        let reduced_time = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let reference = hill_exponents(&mut full, &recovered, w);
        let full_time = clock.elapsed().as_secs_f64();
        let reference_max = reference.iter().map(|e| e.0).fold(f64::MIN, f64::max);
        // Every exponent of the reduced model against the nearest of the full model,
        // relative to the half-width of the strip (the scale of the folded exponents).
        let nearest = |e: &(f64, f64)| {
            reference
                .iter()
                .map(|f| (e.0 - f.0).hypot(folded_distance(e.1, f.1, w)))
                .fold(f64::INFINITY, f64::min)
        };
        let mut by_damping = reduced.exponents.clone();
        by_damping.sort_by(|a, b| b.0.total_cmp(&a.0));
        let distances: Vec<f64> = by_damping.iter().map(nearest).collect();
        // The least damped pair of pairs (the bearing modes near 50 Hz) decide stability.
        let worst = distances[..4].iter().fold(0.0f64, |m, d| m.max(*d)) / (0.5 * w);
        eprintln!(
            "{hz} Hz: {} reduced exponents, distance to the nearest full one (rad/s, least \
             damped first) {}; largest real part reduced {:.6e}, full {:.6e} 1/s; monodromy \
             reduced {:.1} ms, Hill full {:.0} ms",
            reduced.exponents.len(),
            distances
                .iter()
                .map(|d| format!("{d:.1e}"))
                .collect::<Vec<_>>()
                .join(" "),
            reduced.max_real,
            reference_max,
            1e3 * reduced_time,
            1e3 * full_time
        );
        assert_eq!(reduced.stable, reference_max < 0.0);
        // The least damped exponents belong to the lowest pairs, which the fixed-interface
        // truncation leaves almost untouched (measured 3.5e-3 rad/s at 120 Hz and 5.5e-2 at
        // 330 Hz, 5e-5 of w/2, mostly Hill's truncation in H); higher pairs carry the
        // reduction's truncation error (up to 2e-2 rad/s per rad/s of their frequency with
        // 4 modes), which does not decide stability here.
        assert!(
            worst < 1e-4,
            "least damped exponents differ by {worst:e} of w/2"
        );
        // The largest real part is the stability margin: measured 1.6e-4 (120 Hz) and
        // 1.1e-3 (330 Hz) relative, of the order of the full Hill problem's own eigenvalue
        // error: its companion matrix reaches |A| ~ 1e11 (the mesh's highest modes), and
        // two full solves from coefficients that differ by 1e-12 gave real parts 1.1e-3
        // apart.
        let margin = (reduced.max_real - reference_max).abs() / reference_max.abs();
        assert!(margin < 3e-3, "largest real part differs by {margin:e}");
    }
}

/// Floquet exponents by Hill's method (Lazarus & Thomas 2010; Peletan et al. 2013): a
/// perturbation e^{lambda t} p(t), p periodic in the Fourier basis of the solution, solves
/// (lambda^2 M + lambda (D + 2 M Nabla - G[dF/dv]) + dR/dx) p = 0, per slot M and D = C + w G,
/// Nabla the time derivative in the Fourier basis. Of the copies lambda + i k w of each
/// exponent, those of smallest |Im| converge first: the 2n of smallest |Im|, folded into the
/// strip |Im| <= w/2, with repeats (other copies, within 1e-3 w) skipped.
fn hill_exponents(hb: &mut HarmonicBalance, x: &[f64], w: f64) -> Vec<(f64, f64)> {
    let matrices = &hb.problem().matrices;
    let (n, harmonics) = (matrices.mass.nrows(), hb.options().harmonics);
    let size = n * (2 * harmonics + 1);
    let mut mass_inverse = Mat::<f64>::identity(n, n);
    faer::linalg::solvers::Solve::solve_in_place(
        &matrices.mass.partial_piv_lu(),
        mass_inverse.as_mut(),
    );
    let d = &matrices.damping + &matrices.gyroscopic * faer::Scale(w);
    let per_slot = |a: &Mat<f64>| {
        Mat::from_fn(size, size, |i, j| {
            if i / n == j / n {
                a[(i % n, j % n)]
            } else {
                0.0
            }
        })
    };
    let (mass, mass_inverse) = (per_slot(&matrices.mass), per_slot(&mass_inverse));
    // A Nabla: column cos r of the product is -r w times column sin r of A, column sin r is
    // r w times column cos r (slots 2r - 1 and 2r).
    let nabla = |a: &Mat<f64>| {
        Mat::from_fn(size, size, |i, j| {
            let (slot, dof) = (j / n, j % n);
            if slot == 0 {
                return 0.0;
            }
            let rw = slot.div_ceil(2) as f64 * w;
            if slot % 2 == 1 {
                -rw * a[(i, (slot + 1) * n + dof)]
            } else {
                rw * a[(i, (slot - 1) * n + dof)]
            }
        })
    };
    let lin = hb.linearise(x, w);
    let delta_1 = per_slot(&d) + nabla(&mass) * faer::Scale(2.0) - &lin.velocity_galerkin;
    let (stiffness_part, damping_part) = (&mass_inverse * &lin.jacobian, &mass_inverse * &delta_1);
    let companion = Mat::<f64>::from_fn(2 * size, 2 * size, |i, j| match (i < size, j < size) {
        (true, true) => 0.0,
        (true, false) => f64::from(u8::from(j - size == i)),
        (false, true) => -stiffness_part[(i - size, j)],
        (false, false) => -damping_part[(i - size, j - size)],
    });
    let mut values: Vec<(f64, f64)> = companion
        .eigenvalues()
        .unwrap()
        .iter()
        .map(|v| (v.re, v.im))
        .collect();
    values.sort_by(|a, b| a.1.abs().total_cmp(&b.1.abs()));
    let mut kept: Vec<(f64, f64)> = Vec::new();
    for (re, im) in values {
        let folded = im - w * (im / w).round();
        let repeated = kept
            .iter()
            .any(|&(r, i)| (re - r).abs() <= 1e-3 * w && folded_distance(folded, i, w) <= 1e-3 * w);
        if !repeated && kept.len() < 2 * n {
            kept.push((re, folded));
        }
    }
    kept
}

/// Distance between two imaginary parts in the strip, which wraps at +-w/2.
fn folded_distance(a: f64, b: f64, w: f64) -> f64 {
    let d = (a - b).abs() % w;
    d.min(w - d)
}
