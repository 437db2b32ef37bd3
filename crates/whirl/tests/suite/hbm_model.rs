//! Harmonic balance of the reference rotor on its roller bearings: the thesis'
//! fig. 4.27a check against time marching, and the reduced model against the full one.

use std::f64::consts::TAU;

use whirl::fe::{dof, Direction};
use whirl::hbm::sweep::model_problem;
use whirl::hbm::{
    settled_response, sweep, CondensedBalance, HbOptions, MarchSettings, SweepOptions,
};
use whirl::model::Model;

fn reference(clearance: &str) -> Model {
    let text = whirl::examples::REFERENCE_ROTOR.replace(
        "clearance = \"20 um\"",
        &format!("clearance = \"{clearance}\""),
    );
    Model::from_toml_str(&text, None).unwrap()
}

#[test]
fn first_harmonic_at_330_hz_with_10_um_matches_time_marching() {
    let model = reference("10 um");
    let mut options = SweepOptions::new(TAU, TAU * 330.0, 3);
    options.stability = false;
    options.reduction = Some(12);
    let result = sweep(&model, &options).unwrap();
    let last = result.branch.points.len() - 1;
    assert_eq!(result.branch.points[last].solution.frequency, TAU * 330.0);
    let time = settled_response(&model, TAU * 330.0, 10, 3, &MarchSettings::default()).unwrap();
    for (k, d) in [Direction::Ux, Direction::Uy].into_iter().enumerate() {
        let hb = result.amplitude(last, dof(10, d), 1);
        let marched = if k == 0 { time.ux[0] } else { time.uy[0] };
        let difference = (hb - marched) / marched;
        eprintln!("330 Hz, 10 um, disk {d:?}: 1X harmonic balance {hb:.4e} m, time marching {marched:.4e} m ({:+.2} %)", 100.0 * difference);
        // Far above the first critical the disk's response is mass-controlled and the
        // passage-averaged bearing stands in well for the rollers: measured -0.3 % (ux)
        // and +1.1 % (uy) here (H = 3, reduced; -0.2 % and -0.8 % with H = 5 on the full
        // model). 2 % leaves room for the time record's leakage from the
        // varying-compliance lines and for the 0.5 s settling.
        assert!(difference.abs() < 0.02, "{d:?}: {difference:e}");
    }
}

#[test]
fn reduced_and_full_models_give_the_same_branch_through_the_first_resonance() {
    let model = reference("20 um");
    let mut options = SweepOptions::new(TAU, TAU * 60.0, 2);
    let full = sweep(&model, &options).unwrap();
    options.reduction = Some(12);
    let reduced = sweep(&model, &options).unwrap();
    let disk = dof(10, Direction::Uy);
    let (a, b) = (
        full.amplitude(full.branch.points.len() - 1, disk, 1),
        reduced.amplitude(reduced.branch.points.len() - 1, disk, 1),
    );
    let first_loss = |s: &whirl::hbm::Sweep| {
        s.branch
            .bifurcations
            .iter()
            .find(|b| b.loses_stability)
            .map(|b| b.frequency / TAU)
            .unwrap()
    };
    let (fa, fb) = (first_loss(&full), first_loss(&reduced));
    eprintln!(
        "60 Hz disk 1X: full {a:.5e}, reduced {b:.5e} m; first loss of stability full {fa:.3} Hz, reduced {fb:.3} Hz; {} / {} points",
        full.branch.points.len(),
        reduced.branch.points.len()
    );
    // Craig-Bampton with 12 modes moves the first pair of the rotor by 1e-7 relative and the
    // fourth by 2e-3 (tests of reduce): the 1X and the stability loss near the first
    // critical move by far less than 1 % (measured 2e-5 and below 1e-4).
    assert!((a - b).abs() / a < 1e-2, "{a} vs {b}");
    assert!((fa - fb).abs() / fa < 1e-2, "{fa} vs {fb}");
}

/// The answer at a speed does not depend on where the sweep ends: the arclength is scaled
/// at each point (not by the range), so the path up to 330 Hz is the same for every end,
/// and the solution is solved at exactly 330 Hz on each crossing of the branch.
#[test]
fn the_solution_at_330_hz_does_not_depend_on_the_end_of_the_range() {
    let model = reference("10 um");
    let disk = dof(10, Direction::Uy);
    let w = TAU * 330.0;
    let mut answers = Vec::new();
    for end in [330.0, 400.0, 750.0] {
        let mut options = SweepOptions::new(TAU, TAU * end, 5);
        options.stability = false;
        options.exact_speeds = vec![w];
        let result = sweep(&model, &options).unwrap();
        let amplitudes: Vec<f64> = result
            .at_speeds
            .iter()
            .map(|a| result.amplitude_of(&a.coefficients, disk, 1))
            .collect();
        eprintln!(
            "1:{end}Hz: {} points, {:?}, jumps {:?}; disk 1X at 330 Hz {amplitudes:?} m",
            result.branch.points.len(),
            result.branch.end,
            result.branch.jumps
        );
        assert!(!amplitudes.is_empty());
        answers.push(amplitudes[0]);
    }
    for a in &answers[1..] {
        // The same path to the same orbit: equal to the corrector's tolerance; the must is
        // 0.1 %.
        assert!((a - answers[0]).abs() < 1e-3 * answers[0], "{answers:?}");
    }
}

/// Round-off must not decide where a branch goes. With 60 um the branch above
/// the first resonance folds back at 154 Hz, where nothing converges just ahead. Unchanged,
/// the path followed the overhang round on its own and reached 750 Hz; with the disk mass
/// 1e-12 larger it walked back over what it had followed, was restarted ahead of the fold,
/// failed, and ended at 154.03 Hz. The path now goes on round the overhang in both cases.
/// Shorter ranges do not show it (30-70 Hz and 120-220 Hz end on the same orbit with and
/// without the change, before the fix too).
#[test]
#[ignore = "a minute: two 1-750 Hz sweeps of 1707 and 1283 points (about 40 s of CPU); \
            run with --ignored"]
fn a_round_off_change_of_the_disk_mass_leaves_the_60_um_branch_where_it_was() {
    let model = reference("60 um");
    let text = whirl::examples::REFERENCE_ROTOR
        .replace("clearance = \"20 um\"", "clearance = \"60 um\"")
        .replace("mass = \"10 kg\"", "mass = \"10.00000000001 kg\"");
    let perturbed = Model::from_toml_str(&text, None).unwrap();
    assert_ne!(model.disks, perturbed.disks, "the mass must change");
    let mut options = SweepOptions::new(TAU, TAU * 750.0, 5);
    options.stability = false;
    let ends: Vec<[f64; 2]> = [&model, &perturbed]
        .into_iter()
        .map(|m| {
            let result = sweep(m, &options).unwrap();
            let last = result.branch.points.len() - 1;
            eprintln!(
                "{} points, {:?}, jumps {:?}",
                result.branch.points.len(),
                result.branch.end,
                result.branch.jumps
            );
            assert!(
                matches!(result.branch.end, whirl::hbm::BranchEnd::Reached),
                "{:?}",
                result.branch.end
            );
            [dof(10, Direction::Uy), dof(0, Direction::Uy)].map(|d| result.amplitude(last, d, 1))
        })
        .collect();
    for (a, b) in ends[0].iter().zip(&ends[1]) {
        // The same orbit at 750 Hz (measured equal to 2e-12): Newton converges each to a
        // relative residual of 1e-10 and the mass differs by 1e-12; 1e-6 is the
        // continuation's own test for one orbit.
        assert!((a - b).abs() < 1e-6 * a, "{ends:?}");
    }
}

/// With 60 um and the default 160 AFT samples, the branch from 120 Hz passes a fold at
/// 154 Hz, walks back down to 139 Hz, turns, and climbing again meets a corner at
/// 145.185 Hz where the corrector fails at every step and Newton at fixed speed cycles up
/// to 1e-3 of the speed ahead, and nothing converges ahead of the fold: the sweep used to
/// end there (as the 1-750 Hz sweep did, where 80 and 320 samples reach 750 Hz). It must
/// go on along the leg it climbs, to the end of the range.
#[test]
fn the_60_um_branch_climbs_on_past_a_corner_below_its_furthest_point() {
    let mut options = SweepOptions::new(TAU * 120.0, TAU * 160.0, 5);
    options.stability = false;
    let result = sweep(&reference("60 um"), &options).unwrap();
    let branch = &result.branch;
    assert!(
        matches!(branch.end, whirl::hbm::BranchEnd::Reached),
        "{:?}, jumps {:?}",
        branch.end,
        branch.jumps
    );
    let last = &branch.points[branch.points.len() - 1].solution;
    assert_eq!(last.frequency, TAU * 160.0);
}

/// With 60 um the branch from 140 Hz passes the fold at 154.04 Hz and walks back below
/// 140 Hz, to 137.3 Hz, before it turns up again. A sweep from 140 Hz used to restart ahead
/// of the fold when its path left the range, found nothing converging there and stopped at
/// 154.04 Hz, where a sweep from 120 Hz follows the leg round and goes on. The leg out of
/// the range must be followed back, to the orbit the sweep from 120 Hz ends on.
#[test]
fn a_branch_that_turns_back_below_the_first_speed_is_followed_back_into_the_range() {
    let model = reference("60 um");
    let mut options = SweepOptions::new(TAU * 140.0, TAU * 170.0, 5);
    options.stability = false;
    let from_140 = sweep(&model, &options).unwrap();
    let branch = &from_140.branch;
    assert!(
        matches!(branch.end, whirl::hbm::BranchEnd::Reached),
        "{:?}, jumps {:?}",
        branch.end,
        branch.jumps
    );
    let (lowest, highest) = branch.speed_span();
    assert!(lowest < TAU * 139.0, "{} Hz", lowest / TAU);
    assert_eq!(highest, TAU * 170.0);
    let from_120 = sweep(
        &model,
        &SweepOptions {
            from: TAU * 120.0,
            ..options.clone()
        },
    )
    .unwrap();
    let disk = dof(10, Direction::Uy);
    let last = |s: &whirl::hbm::Sweep| s.amplitude(s.branch.points.len() - 1, disk, 1);
    let (a, b) = (last(&from_140), last(&from_120));
    // Newton solutions at exactly 170 Hz to a relative residual of 1e-10 on one orbit
    // (disk 1X 13.5 um; they agree to 1e-15 measured); another orbit differs by percents.
    assert!((a - b).abs() < 1e-6 * b, "{a:e} vs {b:e}");
}

/// At 200 Hz with 20 um the unbalance carries the orbit far from the static equilibrium
/// and Newton from it does not converge: a sweep that starts there used to stop at its
/// first point. It must start on the branch followed up from standstill, on the same
/// orbit as a sweep from 1 Hz.
#[test]
fn a_sweep_that_starts_high_starts_on_the_branch_from_standstill() {
    let model = reference("20 um");
    let mut high = SweepOptions::new(TAU * 200.0, TAU * 202.0, 5);
    high.stability = false;
    let started = sweep(&model, &high).unwrap();
    assert_eq!(started.approached_from, Some(TAU));
    let whole = sweep(
        &model,
        &SweepOptions {
            from: TAU,
            ..high.clone()
        },
    )
    .unwrap();
    let disk = dof(10, Direction::Uy);
    let last = |s: &whirl::hbm::Sweep| {
        let k = s.branch.points.len() - 1;
        assert_eq!(s.branch.points[k].solution.frequency, TAU * 202.0);
        s.amplitude(k, disk, 1)
    };
    let (a, b) = (last(&started), last(&whole));
    // Both are Newton solutions at exactly 202 Hz to a relative residual of 1e-10 on one
    // orbit (disk 1X 16.5 um); another orbit of the branch differs by percents.
    assert!((a - b).abs() < 1e-6 * b, "{a:e} vs {b:e}");
}

/// With 120 um the branch turns at 436.9 Hz and loses stability there by a real multiplier
/// through +1: the fold. The fold locator places this turn by its Hermite estimate
/// (436.890 Hz against the crossing's 436.877 Hz), not on the branch, and the crossing was
/// then named symmetry breaking, a multiplier at +1 where the branch does not turn.
#[test]
fn a_loss_where_the_branch_turns_is_a_fold_also_at_an_estimated_turn() {
    let result = sweep(
        &reference("120 um"),
        &SweepOptions::new(TAU * 425.0, TAU * 450.0, 5),
    )
    .unwrap();
    let branch = &result.branch;
    let loss = branch
        .bifurcations
        .iter()
        .find(|b| b.loses_stability)
        .expect("the branch loses stability at its turn");
    let turn = branch
        .folds
        .iter()
        .find(|f| f.after == loss.after)
        .expect("the branch turns where it loses stability");
    // The crossing and the turn are one point: 1e-3 allows the Hermite estimate's error
    // (3e-5 measured); the next change of the branch is tens of Hz away.
    assert!(
        (turn.frequency - loss.frequency).abs() < 1e-3 * loss.frequency,
        "{} vs {} rad/s",
        turn.frequency,
        loss.frequency
    );
    assert_eq!(loss.kind, whirl::hbm::BifurcationKind::Fold, "{loss:?}");
}

/// The monodromy matrix is integrated over the AFT samples of the orbit (the exponential
/// midpoint rule): its verdict must not depend on their number. The same orbits of the
/// reference rotor's branch through the first resonance (20 um, H = 5, solved with the
/// default 160 samples) are checked with 160, 320 and 640.
#[test]
fn floquet_stability_converges_in_the_samples_on_the_reference_rotor() {
    let model = reference("20 um");
    let mut options = SweepOptions::new(TAU, TAU * 60.0, 5);
    options.stability = false;
    let result = sweep(&model, &options).unwrap();
    let balance = |samples: usize| {
        let (problem, _, _) =
            model_problem(&model, None, TAU, options.contact, options.cage, 0.0).unwrap();
        let hb_options = HbOptions {
            samples,
            ..HbOptions::new(5)
        };
        CondensedBalance::new(problem, hb_options).unwrap()
    };
    let mut balances = [balance(160), balance(320), balance(640)];
    let mut unstable = 0;
    for p in result.branch.points.iter().step_by(7) {
        let s = &p.solution;
        let verdicts: Vec<_> = balances
            .iter_mut()
            .map(|hb| hb.stability(&s.coefficients, s.frequency).unwrap())
            .collect();
        let largest: Vec<f64> = verdicts.iter().map(|v| v.max_real).collect();
        eprintln!(
            "{:.4} Hz: largest real part with 160 / 320 / 640 samples {largest:.4?} 1/s",
            s.frequency / TAU
        );
        // Measured: the same verdict at each of these 31 points, the margins of the stable
        // ones within 6 % (their least damped exponent about -6 1/s, the bearing modes'
        // damping) or, in the folded stretch at 45.75 Hz where the margin is small (-2.2,
        // -3.1 and -3.4 1/s), within 1.3 1/s; those of the unstable ones (10-55 1/s in the
        // first resonance, where contacts open and close within a period and the rule is of
        // first order) within a factor of 2.
        assert!(
            verdicts.iter().all(|v| v.stable == verdicts[0].stable),
            "{} Hz: {largest:?}",
            s.frequency / TAU
        );
        if verdicts[0].stable {
            assert!(
                largest
                    .iter()
                    .all(|l| (l - largest[2]).abs() < (0.06 * largest[2].abs()).max(1.5)),
                "{largest:?}"
            );
        } else {
            unstable += 1;
            assert!(largest
                .iter()
                .all(|l| *l < 2.0 * largest[2] && 2.0 * l > largest[2]));
        }
    }
    // The check covers the unstable stretch of the first resonance.
    assert!(unstable >= 5, "{unstable} unstable points");
}

/// The amplitude of the w/2 component of `signal`, sampled every `step` from t = 0, over
/// its first and its last four periods 2 pi / w (two periods of w/2, over which the
/// harmonics of w are orthogonal to it).
fn half_order_at_both_ends(signal: &[f64], step: f64, w: f64) -> [f64; 2] {
    let window = (4.0 * TAU / w / step).round() as usize;
    let amplitude = |start: usize| {
        let (mut c, mut s) = (0.0, 0.0);
        for (k, x) in signal[start..start + window].iter().enumerate() {
            let phase = 0.5 * w * (start + k) as f64 * step;
            c += x * phase.cos();
            s += x * phase.sin();
        }
        2.0 * c.hypot(s) / window as f64
    };
    [amplitude(0), amplitude(signal.len() - window)]
}

/// The Floquet multipliers say whether the harmonic-balance model's own periodic orbit is
/// stable; time marching of the same model (the Craig-Bampton model with 12 modes and the
/// passage-averaged roller force that the balance uses, not the individual rollers of
/// `--compare-time`), started on the orbit with a small kick, must agree. At 165 Hz the
/// monodromy finds a period doubling (multiplier about -1.18, 27 1/s): the march's w/2
/// component grows from the kick and saturates. At 39.9 Hz it finds a stable orbit (with 4
/// stability modes it found a period doubling, at -1.10, which this march refuted): the
/// march stays on the orbit with no w/2 growth.
#[test]
fn marching_the_harmonic_balance_model_confirms_its_floquet_verdicts() {
    use std::ops::ControlFlow;
    use whirl::system::SpeedProfile;
    use whirl::time::{central_difference, central_difference_limit, MarchOptions};
    let model = reference("20 um");
    let speeds = [TAU * 39.9, TAU * 165.0];
    let mut options = SweepOptions::new(TAU, TAU * 166.0, 5);
    options.reduction = Some(12);
    options.stability = false;
    options.exact_speeds = speeds.to_vec();
    let result = sweep(&model, &options).unwrap();
    let n = result.dofs;
    for (w, growing) in speeds.into_iter().zip([false, true]) {
        let at = &result.at_speeds.iter().find(|a| a.speed == w).unwrap();
        let (mut problem, _, _) =
            model_problem(&model, Some(12), w, options.contact, options.cage, 0.0).unwrap();
        // q(0) and q'(0) of the orbit, the first bearing coordinate kicked by 10 nm.
        let x = &at.coefficients;
        let (mut q0, mut v0) = (x[..n].to_vec(), vec![0.0; n]);
        for r in 1..=5 {
            for d in 0..n {
                q0[d] += x[(2 * r - 1) * n + d];
                v0[d] += r as f64 * w * x[2 * r * n + d];
            }
        }
        let bearing = problem.nonlinear_dofs()[0];
        q0[bearing] += 1e-8;
        let step = 0.9 * central_difference_limit(&problem).unwrap();
        // 0.5 s: 82 periods at 165 Hz, where 27 1/s grows a perturbation 8e5-fold.
        let steps = (0.5 / step) as usize;
        let march = MarchOptions {
            speed: SpeedProfile::Constant(w),
            step,
            steps,
            divergence_bound: 1.0,
        };
        let mut signal = Vec::with_capacity(steps);
        let mut observe = |_: f64, q: &[f64], _: &[f64]| {
            signal.push(q[bearing]);
            ControlFlow::Continue(())
        };
        central_difference(&mut problem, &q0, &v0, &march, &mut observe).unwrap();
        let [first, last] = half_order_at_both_ends(&signal, step, w);
        let largest = at
            .stability
            .multipliers
            .iter()
            .copied()
            .max_by(|a, b| a.0.hypot(a.1).total_cmp(&b.0.hypot(b.1)))
            .unwrap();
        eprintln!(
            "{:.1} Hz: stable {}, largest multiplier {largest:?}; marched w/2 of u_x at the \
             bearing {first:.3e} m over the first 4 periods, {last:.3e} m over the last 4",
            w / TAU,
            at.stability.stable
        );
        if growing {
            // A period doubling: one real multiplier beyond -1, and the march's w/2
            // component (measured 1e-8 to 3e-7 m) grown far above the kick's 10 nm.
            assert!(!at.stability.stable && largest.0 < -1.0 && largest.1 == 0.0);
            assert!(last > 10.0 * first && last > 1e-7, "{first:e} -> {last:e}");
        } else {
            // Stable: the w/2 content stays at the kick's level or decays (measured
            // 3e-9 m at both ends: the leakage of the harmonics of w through a window cut
            // to whole steps).
            assert!(at.stability.stable);
            assert!(last < 2.0 * first.max(1e-9), "{first:e} -> {last:e}");
        }
    }
}
