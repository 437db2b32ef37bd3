//! Harmonic balance on the Duffing oscillator x'' + c x' + k x + k3 x^3 = F cos(w t):
//! one harmonic against the closed-form frequency-amplitude relation and its folds, five
//! harmonics against long time integration, and the Floquet stability of the overhang.

use std::f64::consts::TAU;
use std::ops::ControlFlow;
use std::time::Instant;

use faer::Mat;
use whirl::hbm::{
    continuation, resume, BifurcationKind, Branch, BranchEnd, ContinuationOptions, HarmonicBalance,
    HbOptions,
};
use whirl::system::{SpeedProfile, System};
use whirl::time::{runge_kutta, MarchOptions, RkTolerances};

use crate::common;
use crate::common::Duffing;

/// m = 1, c = 0.1, k = 1, k3 = 1, F = 0.3: a hardening peak that bends over and jumps.
const DUFFING: Duffing = Duffing {
    mass: 1.0,
    damping: 0.1,
    stiffness: 1.0,
    cubic: 1.0,
    force: 0.3,
    reach: 5.0,
};
/// The sweep: below the linear resonance to well past the jump-down of the hardening peak.
const FROM: f64 = 0.5;
const TO: f64 = 3.0;

/// The Duffing oscillator forced for time marching, which has no fixed-amplitude force: the
/// unbalance force Re(f w^2 e^{i w t}) is F cos(w t) at this one speed.
fn duffing_time_problem(frequency: f64) -> System {
    System {
        unbalance_re: vec![DUFFING.force / (frequency * frequency)],
        ..DUFFING.system()
    }
}

fn duffing_hb(harmonics: usize) -> HarmonicBalance {
    let problem = System {
        harmonic_re: vec![DUFFING.force],
        ..DUFFING.system()
    };
    // The monodromy matrix is integrated over the AFT samples (the exponential midpoint
    // rule, error of order (2 pi / N)^2), so its +1 crossing lies near the balance's fold,
    // not on it: with the aliasing-free 32 samples the first point past the fold
    // (1.7797 rad/s) came out stable; 512 (an error 256 times smaller) leave every point
    // on the side of the folds it lies on.
    let options = HbOptions {
        samples: 512,
        ..HbOptions::new(harmonics)
    };
    HarmonicBalance::new(problem, options).unwrap()
}

fn branch(harmonics: usize) -> Branch {
    let mut hb = duffing_hb(harmonics);
    let guess = vec![0.0; hb.unknowns()];
    let started = Instant::now();
    let branch = continuation(&mut hb, FROM, TO, &guess, &ContinuationOptions::default())
        .expect("the first point converges");
    eprintln!(
        "H = {harmonics}: {} points, {:?} ({:?})",
        branch.points.len(),
        started.elapsed(),
        branch.end
    );
    branch
}

/// First-harmonic amplitude sqrt(a_1^2 + b_1^2) of the single coordinate.
fn first_harmonic(coefficients: &[f64]) -> f64 {
    coefficients[1].hypot(coefficients[2])
}

#[test]
fn one_harmonic_matches_the_closed_form_along_the_overhang() {
    let branch = branch(1);
    assert!(matches!(branch.end, BranchEnd::Reached));
    let mut worst = 0.0f64;
    for p in &branch.points {
        let s = &p.solution;
        worst = worst.max(
            DUFFING
                .defect(s.frequency, first_harmonic(&s.coefficients))
                .abs(),
        );
    }
    let overhang = branch
        .points
        .iter()
        .filter(|p| p.frequency_slope < 0.0)
        .count();
    eprintln!("worst closed-form defect {worst:e}, {overhang} points on the overhang");
    // Newton stops at a residual of 1e-10 of the balancing terms; the relation squares the
    // amplitude terms, so its defect is a few times that.
    assert!(worst < 1e-8);
    assert!(overhang > 5, "the branch passes the overhang");
}

#[test]
fn both_folds_are_located_at_the_closed_form_frequencies() {
    let branch = branch(1);
    assert_eq!(branch.folds.len(), 2, "{:?}", branch.folds);
    for fold in &branch.folds {
        let p = &branch.points[fold.after].solution;
        let exact = DUFFING.fold(first_harmonic(&p.coefficients).powi(2), p.frequency);
        let error = (fold.frequency - exact).abs() / exact;
        eprintln!(
            "fold at {:.10} rad/s, closed form {exact:.10}, relative error {error:e}",
            fold.frequency
        );
        // Located on the branch to within the corrector's tolerance (relative residual
        // 1e-10), whatever the step.
        assert!(fold.refined);
        assert!(error < 1e-9);
    }
}

/// Settled amplitude (max - min) / 2 of Runge-Kutta started on the harmonic balance
/// solution, after `periods` periods, over the last 5.
fn time_integrated_amplitude(frequency: f64, coefficients: &[f64], harmonics: usize) -> f64 {
    let mut problem = duffing_time_problem(frequency);
    let q0: f64 = (0..=harmonics)
        .map(|r| coefficients[if r == 0 { 0 } else { 2 * r - 1 }])
        .sum();
    let v0: f64 = (1..=harmonics)
        .map(|r| r as f64 * frequency * coefficients[2 * r])
        .sum();
    let period = TAU / frequency;
    let per_period = 400;
    // Transients start at the truncation error of harmonic balance and decay as
    // e^{-c t / 2}: 60 periods make them negligible below 1e-3.
    let periods = 60;
    let options = MarchOptions {
        speed: SpeedProfile::Constant(frequency),
        step: period / per_period as f64,
        steps: periods * per_period,
        divergence_bound: 100.0,
    };
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    let settled = (periods - 5) as f64 * period;
    runge_kutta(
        &mut problem,
        &[q0],
        &[v0],
        &RkTolerances::default(),
        &options,
        &mut |t, q, _| {
            if t >= settled {
                low = low.min(q[0]);
                high = high.max(q[0]);
            }
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    (high - low) / 2.0
}

/// (max - min) / 2 of the harmonic balance waveform.
fn hb_amplitude(coefficients: &[f64], harmonics: usize) -> f64 {
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for j in 0..4000 {
        let theta = TAU * j as f64 / 4000.0;
        let q: f64 = coefficients[0]
            + (1..=harmonics)
                .map(|r| {
                    let rt = r as f64 * theta;
                    coefficients[2 * r - 1] * rt.cos() + coefficients[2 * r] * rt.sin()
                })
                .sum::<f64>();
        low = low.min(q);
        high = high.max(q);
    }
    (high - low) / 2.0
}

#[test]
fn five_harmonics_match_time_integration_and_the_middle_branch_is_unstable() {
    let harmonics = 5;
    let branch = branch(harmonics);
    assert_eq!(branch.folds.len(), 2);
    let (first, second) = (branch.folds[0], branch.folds[1]);
    // Between the folds in path order: the middle (saddle) branch.
    for p in &branch.points[first.after + 1..=second.after] {
        let stability = p.stability.as_ref().unwrap();
        assert!(
            !stability.stable,
            "middle branch at {}",
            p.solution.frequency
        );
    }
    // Stability changes exactly at the two folds, by a real exponent.
    assert_eq!(branch.bifurcations.len(), 2);
    for (b, fold) in branch.bifurcations.iter().zip([first, second]) {
        assert_eq!(b.kind, BifurcationKind::Fold);
        assert_eq!(b.after, fold.after);
        let relative = (b.frequency - fold.frequency).abs() / fold.frequency;
        eprintln!(
            "stability change at {:.8} rad/s, fold at {:.8}",
            b.frequency, fold.frequency
        );
        // Linear interpolation of an exponent that grows as the square root of the distance
        // to the fold: off by a fraction of the (small) step there.
        assert!(relative < 1e-4);
    }
    let outside = branch.points[..=first.after]
        .iter()
        .chain(&branch.points[second.after + 1..]);
    for p in outside {
        assert!(p.stability.as_ref().unwrap().stable);
    }
    // A few stable points: below resonance, on the upper and on the lower branch in the
    // middle of the overhang, and past the jump-down.
    let middle = 0.5 * (first.frequency + second.frequency);
    let last = branch.points.len() - 1;
    let targets = [
        (0.8, 0..=first.after),
        (middle, 0..=first.after),
        (middle, second.after + 1..=last),
        (2.8, second.after + 1..=last),
    ];
    for (target, range) in targets {
        let p = branch.points[range]
            .iter()
            .min_by(|a, b| {
                (a.solution.frequency - target)
                    .abs()
                    .total_cmp(&(b.solution.frequency - target).abs())
            })
            .unwrap();
        let s = &p.solution;
        let started = Instant::now();
        let marched = time_integrated_amplitude(s.frequency, &s.coefficients, harmonics);
        let balanced = hb_amplitude(&s.coefficients, harmonics);
        let difference = (marched - balanced).abs() / balanced;
        eprintln!(
            "w = {:.4}: HB {balanced:.8}, RK {marched:.8}, relative {difference:e} ({:?})",
            s.frequency,
            started.elapsed()
        );
        // RK's maximum over 400 samples per period misses the peak by up to
        // (pi / 400)^2 / 2 = 3e-5 of it, and H = 5 leaves out harmonics 7 and up. Measured
        // 5e-6 to 2e-5, at the level of the sampling error.
        assert!(difference < 1e-4);
    }
}

#[test]
fn a_branch_resumes_from_a_saved_point_on_the_middle_branch() {
    let full = branch(1);
    let (first, second) = (full.folds[0], full.folds[1]);
    let saved = &full.points[(first.after + second.after) / 2];
    assert!(saved.frequency_slope < 0.0, "a middle-branch point");
    // The branch serialises (results files are JSON).
    let json = serde_json::to_string(&full).unwrap();
    assert!(json.contains("\"Reached\""));
    let mut hb = duffing_hb(1);
    let resumed = resume(&mut hb, saved, FROM, TO, &ContinuationOptions::default()).unwrap();
    assert!(matches!(resumed.end, BranchEnd::Reached));
    // Only the lower fold lies ahead of a middle-branch point.
    assert_eq!(resumed.folds.len(), 1);
    let fold = resumed.folds[0];
    let before = &resumed.points[fold.after].solution;
    let exact = DUFFING.fold(
        first_harmonic(&before.coefficients).powi(2),
        before.frequency,
    );
    let error = (fold.frequency - exact).abs() / exact;
    eprintln!(
        "resumed: fold at {:.10} rad/s, closed form {exact:.10}, relative error {error:e}",
        fold.frequency
    );
    // As for the first run.
    assert!(fold.refined);
    assert!(error < 1e-9);
    for p in &resumed.points {
        let s = &p.solution;
        assert!(
            DUFFING
                .defect(s.frequency, first_harmonic(&s.coefficients))
                .abs()
                < 1e-8
        );
    }
}

#[test]
fn linear_rotor_matches_the_unbalance_response() {
    // The reference rotor on linearised bearings: harmonic balance without nonlinear forces
    // must reproduce the complex unbalance response, gyroscopic and damping terms included,
    // and leave the higher harmonics at zero.
    use faer::c64;
    use whirl::fe;
    let model = common::reference_rotor();
    let system = fe::assemble(&model, fe::Bearings::Linearised);
    let n = system.dofs();
    let unbalance = fe::unbalance_force(&model, n);
    let problem = System {
        unbalance_re: unbalance.iter().map(|f| f.re).collect(),
        unbalance_im: unbalance.iter().map(|f| f.im).collect(),
        ..System::unloaded(system.clone())
    };
    let mut hb = HarmonicBalance::new(problem, HbOptions::new(2)).unwrap();
    let w = TAU * 180.0;
    let zero = vec![0.0; hb.unknowns()];
    let solution = hb.solve(w, &zero).unwrap();
    // (K - w^2 M + i w (C + w G)) Q = w^2 f, the unbalance response of whirl::response.
    let dynamic = Mat::<c64>::from_fn(n, n, |i, j| {
        c64::new(
            system.stiffness[(i, j)] - w * w * system.mass[(i, j)],
            w * (system.damping[(i, j)] + w * system.gyroscopic[(i, j)]),
        )
    });
    let mut rhs = Mat::<c64>::from_fn(n, 1, |i, _| unbalance[i] * (w * w));
    faer::linalg::solvers::Solve::solve_in_place(&dynamic.partial_piv_lu(), rhs.as_mut());
    let phasor: Vec<c64> = (0..n).map(|i| rhs[(i, 0)]).collect();
    let largest = phasor.iter().fold(0.0f64, |m, q| m.max(q.norm()));
    let x = &solution.coefficients;
    let mut worst = 0.0f64;
    for (dof, q) in phasor.iter().enumerate() {
        // Re(Q e^{i w t}) = Re Q cos(w t) - Im Q sin(w t).
        worst = worst
            .max((x[n + dof] - q.re).abs())
            .max((x[2 * n + dof] + q.im).abs())
            .max(x[dof].abs())
            .max(x[3 * n + dof].abs())
            .max(x[4 * n + dof].abs());
    }
    eprintln!("linear rotor: largest |Q| {largest:e} m, worst difference {worst:e} m");
    // Two LU solves of the same well-conditioned dynamic stiffness (180 Hz is between the
    // first two critical speeds): round-off relative to the response.
    assert!(worst < 1e-9 * largest);
}

#[test]
fn a_downward_sweep_finds_the_same_folds() {
    let mut hb = duffing_hb(1);
    let guess = vec![0.0; hb.unknowns()];
    let down = continuation(&mut hb, TO, FROM, &guess, &ContinuationOptions::default()).unwrap();
    let up = branch(1);
    assert!(matches!(down.end, BranchEnd::Reached));
    assert_eq!(down.folds.len(), 2);
    // Met in the opposite order; both on the branch to the corrector's tolerance.
    for (d, u) in down.folds.iter().zip(up.folds.iter().rev()) {
        assert!((d.frequency - u.frequency).abs() < 1e-9 * u.frequency);
    }
    let last = &down.points[down.points.len() - 1].solution;
    assert_eq!(last.frequency, FROM);
}

#[test]
fn both_folds_are_passed_with_any_maximum_step() {
    let reference = branch(1);
    for max_step in [0.005, 0.01, 0.03, 0.1, 0.2, 0.5] {
        let mut hb = duffing_hb(1);
        let guess = vec![0.0; hb.unknowns()];
        let options = ContinuationOptions {
            max_step,
            initial_step: 0.005f64.min(max_step),
            stability: false,
            ..ContinuationOptions::default()
        };
        let path = continuation(&mut hb, FROM, TO, &guess, &options).unwrap();
        eprintln!(
            "max step {max_step}: {} points, folds {:?}, jumps {:?}, {:?}",
            path.points.len(),
            path.folds.iter().map(|f| f.frequency).collect::<Vec<_>>(),
            path.jumps,
            path.end
        );
        assert!(matches!(path.end, BranchEnd::Reached), "{max_step}");
        assert!(path.jumps.is_empty(), "{max_step}: {:?}", path.jumps);
        assert_eq!(path.folds.len(), 2, "{max_step}");
        // Both on the branch, to the corrector's tolerance, as with the default step.
        for (f, r) in path.folds.iter().zip(&reference.folds) {
            assert!(f.refined);
            assert!((f.frequency - r.frequency).abs() < 1e-9 * r.frequency);
        }
    }
}

/// The Duffing oscillator forced harder, F = 0.5, at `harmonics`, 512 samples as above.
fn strong_duffing_branch(harmonics: usize) -> Branch {
    let strong = Duffing {
        force: 0.5,
        ..DUFFING
    };
    let problem = System {
        harmonic_re: vec![strong.force],
        ..strong.system()
    };
    let options = HbOptions {
        samples: 512,
        ..HbOptions::new(harmonics)
    };
    let mut hb = HarmonicBalance::new(problem, options).unwrap();
    let guess = vec![0.0; hb.unknowns()];
    continuation(&mut hb, FROM, TO, &guess, &ContinuationOptions::default()).unwrap()
}

/// With F = 0.5 the Floquet stability about the orbit truncated to 1 or 2 harmonics (the
/// even ones are zero, so 2 is 1) contradicts the balance's own folds: a real multiplier
/// crosses +1 at 1.8787 rad/s on the middle branch, none crosses at the upper fold at
/// 2.2047, and the middle branch from there down to 1.8787 is called stable. From 3 harmonics on each fold
/// carries its crossing and the middle branch is unstable. The branch says which folds show
/// no crossing.
#[test]
fn stability_that_contradicts_the_folds_is_flagged() {
    for harmonics in 1..=4 {
        let branch = strong_duffing_branch(harmonics);
        let (first, second) = (branch.folds[0], branch.folds[1]);
        let middle: Vec<bool> = branch.points[first.after + 1..=second.after]
            .iter()
            .map(|p| p.stability.as_ref().unwrap().stable)
            .collect();
        let kinds: Vec<_> = branch
            .bifurcations
            .iter()
            .map(|b| (b.kind, b.frequency))
            .collect();
        eprintln!(
            "H = {harmonics}: folds at {:.4} and {:.4}, {} of {} middle points stable, {kinds:?}, \
             flagged {:?}",
            first.frequency,
            second.frequency,
            middle.iter().filter(|&&s| s).count(),
            middle.len(),
            branch.folds_without_crossing
        );
        if harmonics < 3 {
            // The middle branch stable from the upper fold down to 1.8787 rad/s (13 of its
            // 25 points), where the +1 crossing is named symmetry breaking.
            assert!(middle[0] && middle.iter().any(|&s| !s));
            assert_eq!(branch.folds_without_crossing, vec![first.frequency]);
        } else {
            assert!(middle.iter().all(|&s| !s));
            assert!(branch.folds_without_crossing.is_empty());
            assert!(kinds.iter().all(|(k, _)| *k == BifurcationKind::Fold));
        }
    }
}
