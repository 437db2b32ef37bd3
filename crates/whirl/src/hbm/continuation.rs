//! Pseudo-arclength continuation of periodic solutions in the excitation frequency.
//!
//! The path y(s) = (x, w) is followed in variables scaled at each point (x by the largest
//! coefficient of that point, w by its frequency), so that one unit of arclength is a
//! relative change of either, whatever the solution's size: a branch started at a small
//! amplitude takes steps as long, relative to the orbit, when the orbit has grown a
//! hundredfold, and the path up to a frequency does not depend on where the range ends.
//! From a converged point y_0 with unit tangent t_0:
//!
//! - predictor: y = y_0 + h t_0;
//! - corrector: Newton on R(x, w) = 0 together with t_0 . (y - y_0) = h (Keller 1977),
//!   whose augmented Jacobian stays regular at turning points, where dR/dx alone is singular;
//! - tangent: [dR/dy; t_0^T] t = [0; 1], normalised, which keeps the direction of travel
//!   through turning points.
//!
//! The step grows after quick convergence and shrinks after slow or failed convergence, or
//! when the tangent turns by more than `max_turn`, which keeps turning points resolved.
//! A fold is where the tangent's frequency component t_w changes sign. It is located by
//! regula falsi (Illinois variant) on t_w(sigma), sigma the arclength along the tangent of
//! the point before it, each trial point being corrected onto the branch: the fold is then
//! as accurate as the corrector, whatever the step. Should a corrector fail there, the
//! extremum of the cubic Hermite interpolant of w(s) between the two points stands in.

use super::arclength::{
    arclength_frame, correct, land_on, newton_on_arclength, rescaled, unit_tangent, Scaling,
};
use super::balance::{HbSolution, FULL_STEPS};
use super::bifurcation::locate_bifurcations;
use super::branch::Path;
use super::parallel::on_threads;
use super::stability::{outside_circle, FloquetProblem, Stability};
use crate::error::{Error, Result};
use crate::linalg::{difference, dot_in_order as dot, norm};
use std::sync::{mpsc, Mutex, PoisonError};

pub use super::branch::{Branch, BranchEnd, BranchPoint, Fold};
pub use super::periodic::{Derivatives, Periodic};

/// Step control of the continuation; lengths are in scaled arclength (relative changes:
/// a step of 0.1 moves the speed or the orbit's largest coefficient by up to 10 %).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ContinuationOptions {
    /// First step.
    pub initial_step: f64,
    /// Smallest step before the path is given up.
    pub min_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Largest angle between successive tangents, rad.
    pub max_turn: f64,
    /// Largest number of points.
    pub max_points: usize,
    /// Compute the Floquet stability at every point.
    pub stability: bool,
    /// When this many successive points advance by less than 1 % (a chord of 0.01 in
    /// scaled arclength: the path wiggles or crawls on the spot), or
    /// the path walks back over what it followed or turns back out of the range further
    /// than a quarter of its first speed (a leg that turns back out of the range is
    /// followed out there, back into it), it is
    /// restarted ahead of the furthest point ([`Branch::jumps`]); where no restart
    /// converges, a path still in the range goes on with the stall and retrace tests off
    /// until it passes its furthest point; 0 never (the path then ends with
    /// [`BranchEnd::LeftRange`] as soon as it turns back out of the range).
    pub stall_points: usize,
}

impl Default for ContinuationOptions {
    /// Steps from 1e-6 to 0.1 (up to 10 % of the speed a step; folds are located on the
    /// branch, not interpolated, so long steps cost no accuracy there), 0.15 rad of turn
    /// (which keeps the predictor near the branch round turning points), up to 5000
    /// points, with stability.
    fn default() -> Self {
        ContinuationOptions {
            initial_step: 0.005,
            min_step: 1e-6,
            max_step: 0.1,
            max_turn: 0.15,
            max_points: 5000,
            stability: true,
            stall_points: 100,
        }
    }
}

/// Follows the periodic solution from frequency `from` to `to` (rad/s), starting from
/// `guess` at `from`.
///
/// # Errors
/// [`Error::NotConverged`] or [`Error::Singular`] when the first point does not converge,
/// [`Error::InvalidOption`] when the range is empty;
/// later failures end the branch ([`BranchEnd::StepTooSmall`]) and keep what converged.
pub fn continuation<H: Periodic + Send>(
    hb: &mut H,
    from: f64,
    to: f64,
    guess: &[f64],
    options: &ContinuationOptions,
) -> Result<Branch> {
    continuation_sharing(hb, &mut [], from, to, guess, options)
}

/// As [`continuation`], with `helpers`, copies of the same problem: the folds and the
/// bifurcations are located on rayon's threads, one problem a thread, `hb` among them.
/// Each is located from the path's points alone on whichever problem takes it, so the
/// branch is the same to the bit with or without helpers, except where the problem refines
/// residuals ([`Periodic::refine_residuals`]): a refined residual's round-off depends on
/// the condensation the problem's last search left, so refinement is asked for only
/// without helpers.
///
/// # Errors
/// As [`continuation`].
pub fn continuation_sharing<H: Periodic + Send>(
    hb: &mut H,
    helpers: &mut [H],
    from: f64,
    to: f64,
    guess: &[f64],
    options: &ContinuationOptions,
) -> Result<Branch> {
    check_range(from, to)?;
    let first = hb.solve(from, guess)?;
    follow(
        hb,
        helpers,
        first,
        (to - from).signum(),
        (from, to),
        options,
    )
}

/// Restarts a branch from a saved point within the range `from`..`to` (rad/s), in the
/// direction of travel its frequency slope records (towards `to` if the slope is zero).
/// The point is solved again first, so a point edited or computed with other options is
/// never continued unconverged. Steps are scaled by the resumed point's coefficients.
///
/// # Errors
/// As [`continuation`].
pub fn resume<H: Periodic + Send>(
    hb: &mut H,
    point: &BranchPoint,
    from: f64,
    to: f64,
    options: &ContinuationOptions,
) -> Result<Branch> {
    check_range(from, to)?;
    let first = hb.solve(point.solution.frequency, &point.solution.coefficients)?;
    let orientation = if point.frequency_slope != 0.0 {
        point.frequency_slope.signum()
    } else {
        (to - from).signum()
    };
    follow(hb, &mut [], first, orientation, (from, to), options)
}

fn check_range(from: f64, to: f64) -> Result<()> {
    if to.is_finite() && from.is_finite() && to != from {
        Ok(())
    } else {
        Err(Error::InvalidOption(format!(
            "continuation needs two different frequencies, got {from} and {to} rad/s"
        )))
    }
}

/// The branch from the converged point `first` (see [`trace`]), with its folds and
/// bifurcations, located on `hb` and `helpers` ([`continuation_sharing`]).
fn follow<H: Periodic + Send>(
    hb: &mut H,
    helpers: &mut [H],
    first: HbSolution,
    orientation: f64,
    range: (f64, f64),
    options: &ContinuationOptions,
) -> Result<Branch> {
    let path = if options.stability {
        trace_with_stability(hb, first, orientation, range, options)?
    } else {
        trace(
            hb,
            first,
            orientation,
            range,
            options,
            &mut |_, _, _| Ok(()),
        )?
    };
    let options = *hb.options();
    let mut problems: Vec<&mut H> = std::iter::once(hb).chain(helpers).collect();
    let refine = problems.len() == 1;
    problems[0].refine_residuals(refine);
    let located = locate_folds(&mut problems, &path.points, &path.boundaries).and_then(|folds| {
        let bifurcations =
            locate_bifurcations(&mut problems, &path.points, &folds, &path.boundaries)?;
        Ok((folds, bifurcations))
    });
    problems[0].refine_residuals(false);
    let (folds, bifurcations) = located?;
    let folds_without_crossing = stability_contradicts_folds(&path.points, &folds, &path.corners);
    Ok(Branch {
        options,
        folds_without_crossing,
        folds,
        corners: path.corners,
        jumps: path.jumps,
        jumped_after: path.boundaries,
        bifurcations,
        points: path.points,
        end: path.end,
    })
}

/// The speeds of the folds in `folds` across which the parity of the number of real
/// Floquet multipliers above 1 does not change as it must: at a fold of an exact periodic
/// solution a real multiplier crosses +1 (the Jacobian of the balance and I - Phi are
/// singular together, and det(I - Phi), of the sign of that parity, changes sign).
/// Stability computed about a truncated orbit need not obey this: on the Duffing
/// oscillator (c = 0.1, k3 = 1, F = 0.5, 512 samples) 1 and 2 harmonics put the +1
/// crossing at 1.8787 rad/s, before the fold at 2.2047, and call the middle branch stable,
/// while from 3 harmonics on each fold carries its crossing and the middle branch is
/// unstable.
///
/// The monodromy is a discretisation of its own (N samples), so its crossing lies near the
/// balance's fold, not on it: folds closer together than [`FOLD_CLUSTER`] of their speed
/// (a small overhang: the reference rotor's 20 um branch turns at 52.792 and 52.798 Hz,
/// and three times within 0.04 Hz near 184.35 Hz) are judged together, the parity across
/// the cluster against their count. A fold at a corner (a contact opening, within
/// [`FOLD_CLUSTER`]), where the branch is not smooth and no crossing is owed, is not
/// judged. Judged fold by fold, 7 of that branch's 8 folds were reported.
fn stability_contradicts_folds(
    points: &[BranchPoint],
    folds: &[Fold],
    corners: &[f64],
) -> Vec<f64> {
    let parity = |p: &BranchPoint| {
        p.stability.as_ref().map(|s| {
            let above = s
                .multipliers
                .iter()
                .filter(|&&(re, im)| im == 0.0 && re > 0.0 && outside_circle((re, im)));
            above.count() % 2
        })
    };
    let near = |a: f64, b: f64| (a - b).abs() <= FOLD_CLUSTER * a.abs().max(b.abs());
    let mut contradicted = Vec::new();
    let mut k = 0;
    while k < folds.len() {
        let mut end = k + 1;
        while end < folds.len() && near(folds[end].frequency, folds[end - 1].frequency) {
            end += 1;
        }
        let cluster = &folds[k..end];
        k = end;
        let at_corner = cluster
            .iter()
            .any(|f| corners.iter().any(|&c| near(f.frequency, c)));
        let first = cluster.iter().map(|f| f.after).min().unwrap_or(0);
        let last = cluster.iter().map(|f| f.after + 1).max().unwrap_or(0);
        let (Some(a), Some(b)) = (points.get(first), points.get(last)) else {
            continue;
        };
        let owed = cluster.len() % 2;
        let kept = matches!((parity(a), parity(b)), (Some(x), Some(y)) if (x + owed) % 2 != y);
        if kept && !at_corner {
            contradicted.extend(cluster.iter().map(|f| f.frequency));
        }
    }
    contradicted
}

/// Folds within this fraction of their speed of each other are one overhang for
/// [`stability_contradicts_folds`].
const FOLD_CLUSTER: f64 = 1e-3;

/// Floquet problems queued for the second thread at most: each holds N matrices of
/// (2 n)^2 entries, and the path's thread blocks when it is this far ahead.
const FLOQUET_QUEUE: usize = 16;

/// [`trace`] with Floquet stability at every point. Building a point's problem needs the
/// harmonic balance and so the path's thread; solving it does not, and takes about as long
/// as a continuation step, so the solves run on a second thread while the path goes on,
/// and the path's thread joins them once the path has ended. Every verdict is the one a
/// solve after the path would give.
fn trace_with_stability<H: Periodic>(
    hb: &mut H,
    first: HbSolution,
    orientation: f64,
    range: (f64, f64),
    options: &ContinuationOptions,
) -> Result<Path> {
    let (sender, receiver) = mpsc::sync_channel::<(usize, FloquetProblem)>(FLOQUET_QUEUE);
    let jobs = Mutex::new(receiver);
    let verdicts = Mutex::new(Vec::new());
    let solve_queued = || loop {
        // The lock is held only to take the next job; a poisoned lock (a panicking solve)
        // still hands out jobs.
        let job = jobs.lock().unwrap_or_else(PoisonError::into_inner).recv();
        let Ok((index, problem)) = job else { break };
        let verdict = problem.solve();
        verdicts
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push((index, verdict));
    };
    let path = std::thread::scope(|scope| {
        scope.spawn(solve_queued);
        let mut submit = |hb: &mut H, index: usize, point: &BranchPoint| {
            let s = &point.solution;
            let problem = hb.floquet_problem(&s.coefficients, s.frequency)?;
            sender.send((index, problem)).map_err(|_| {
                Error::Internal("the thread solving the Floquet problems stopped".into())
            })
        };
        let path = trace(hb, first, orientation, range, options, &mut submit);
        drop(sender);
        solve_queued();
        path
    });
    let mut path = path?;
    let verdicts = verdicts
        .into_inner()
        .unwrap_or_else(PoisonError::into_inner);
    if verdicts.len() != path.points.len() {
        return Err(Error::Internal(
            "the thread solving the Floquet problems stopped before the last point".into(),
        ));
    }
    for (index, verdict) in verdicts {
        path.points[index].stability = Some(verdict?);
    }
    Ok(path)
}

/// The continuation loop from the converged point `first`, leaving it with increasing
/// frequency when `orientation` is positive and decreasing when negative; `on_point` is
/// told of every point (its index and the point) once it is on the path for good.
fn trace<H: Periodic>(
    hb: &mut H,
    first: HbSolution,
    orientation: f64,
    (from, to): (f64, f64),
    options: &ContinuationOptions,
    on_point: &mut dyn FnMut(&mut H, usize, &BranchPoint) -> Result<()>,
) -> Result<Path> {
    let direction = (to - from).signum();
    let mut scaling = Scaling::at(&first);
    let mut start_direction = vec![0.0; first.coefficients.len() + 1];
    start_direction[first.coefficients.len()] = orientation;
    let mut tangent = unit_tangent(hb, &first, &scaling, &start_direction)?;
    let first_frequency = first.frequency;
    let mut points = vec![branch_point(first, &tangent, &scaling)];
    // Scaled arclength travelled to each point (chords; a restart counts its jump).
    let mut travelled = vec![0.0];
    let mut step = options.initial_step;
    let mut corners = Vec::new();
    let mut jumps = Vec::new();
    let (mut furthest, mut furthest_index) = (direction * first_frequency, 0);
    // Indices of the points after which the path jumped: no fold or bifurcation is looked
    // for across them.
    let mut boundaries: Vec<usize> = Vec::new();
    // The turn of the last attempt rejected for turning too much.
    let mut rejected_turn: Option<f64> = None;
    let mut told = 0;
    // Whether the stall and retrace tests are on: off after a restart ahead failed, until
    // the path passes its furthest point.
    let mut armed = true;
    let end = loop {
        for (index, point) in points.iter().enumerate().skip(told) {
            hb.on_path(&point.solution);
            on_point(hb, index, point)?;
        }
        told = points.len();
        if points.len() >= options.max_points {
            break BranchEnd::PointLimit;
        }
        let last = &points[points.len() - 1].solution;
        if hb.stop_requested() {
            return Err(Error::Interrupted(format!(
                "the harmonic-balance path was stopped at {:.1} Hz",
                last.frequency / std::f64::consts::TAU
            )));
        }
        let y0 = scaling.scaled(last);
        let attempt = correct_on_path(hb, &y0, &tangent, step, &scaling, options)
            .and_then(|s| Ok((unit_tangent(hb, &s, &scaling, &tangent)?, s)));
        let turn = attempt
            .as_ref()
            .map_or(f64::NAN, |(t, _)| dot(t, &tangent).clamp(-1.0, 1.0).acos());
        let rejected_before = rejected_turn.take();
        let accepted = match attempt {
            Ok((next_tangent, s)) if turn <= options.max_turn => Some((next_tangent, s)),
            // On a smooth branch the turn halves with the step. One that does not shrink
            // (by less than a quarter), or persists at the smallest step, is a corner of a
            // non-smooth branch (a contact opening or closing), not an unresolved fold:
            // accept it.
            Ok((next_tangent, s))
                if step / 2.0 < options.min_step
                    || rejected_before.is_some_and(|before| turn > 0.75 * before) =>
            {
                corners.push(s.frequency);
                Some((next_tangent, s))
            }
            Ok(_) => {
                rejected_turn = Some(turn);
                None
            }
            Err(e) if step / 2.0 < options.min_step => {
                let past = step_over(hb, last, &tangent, &scaling)
                    .or_else(|| turn_at_corner(hb, last, &tangent, &scaling));
                match past {
                    Some((next_tangent, s)) => {
                        corners.push(s.frequency);
                        step = options.initial_step;
                        Some((next_tangent, s))
                    }
                    None => {
                        let guesses = [last, &points[0].solution];
                        let ahead = (direction * furthest, to);
                        let restart =
                            jump_ahead(hb, &guesses, ahead, direction, &scaling).or_else(|| {
                                climb_on(hb, last, &tangent, furthest, to, direction, &scaling)
                            });
                        match restart {
                            Some((next_tangent, s)) => {
                                jumps.push((last.frequency, s.frequency));
                                boundaries.push(points.len() - 1);
                                step = options.initial_step;
                                Some((next_tangent, s))
                            }
                            None => {
                                break BranchEnd::StepTooSmall {
                                    frequency: last.frequency,
                                    message: e.to_string(),
                                }
                            }
                        }
                    }
                }
            }
            Err(_) => None,
        };
        let Some((next_tangent, solution)) = accepted else {
            step /= 2.0;
            continue;
        };
        if direction * (solution.frequency - to) >= 0.0 {
            match land_on(hb, last, &solution, to).and_then(|p| {
                let t = unit_tangent(hb, &p, &scaling, &next_tangent)?;
                Ok(branch_point(p, &t, &scaling))
            }) {
                Ok(end_point) => {
                    points.push(end_point);
                    break BranchEnd::Reached;
                }
                Err(e) => {
                    break BranchEnd::EndNotConverged {
                        message: e.to_string(),
                    }
                }
            }
        }
        let outside = direction * (solution.frequency - from) < 0.0;
        if outside && options.stall_points == 0 {
            break BranchEnd::LeftRange;
        }
        // A leg that turns back out of the range is followed out there, where it may turn
        // again and come back: the branch a sweep from further down follows. Restarted
        // ahead instead, the path skipped what that leg leads to (on the reference rotor
        // with 120 um, from 425 Hz, the leg below the fold at 436.9 Hz, which returns at
        // 384 Hz, and all its solutions up to 568 Hz).
        let beyond =
            outside && direction * (solution.frequency - from * EXCURSION.powf(direction)) < 0.0;
        if !beyond {
            step = next_step(step, solution.iterations, options);
            if direction * solution.frequency > furthest {
                (furthest, furthest_index) = (direction * solution.frequency, points.len());
                armed = true;
            }
            (scaling, tangent) = rescaled(&scaling, &next_tangent, &solution);
            travelled.push(travelled[travelled.len() - 1] + chord(&scaling, &points, &solution));
            points.push(branch_point(solution, &tangent, &scaling));
        }
        // A path that goes that far out of the range, wiggles on the spot, or retraces
        // what it followed is restarted ahead of the furthest point, from it.
        if beyond
            || (armed
                && (stalled(&points, options.stall_points)
                    || retraced(&points, &travelled, options.stall_points)))
        {
            let base = &points[furthest_index].solution;
            let ahead = (direction * furthest, to);
            // The last point too: after a retrace it lies on another stretch of the
            // branch than the furthest, and Newton ahead may converge from it alone.
            let guesses = [
                base,
                &points[points.len() - 1].solution,
                &points[0].solution,
            ];
            let Some((t, s)) = jump_ahead(hb, &guesses, ahead, direction, &scaling) else {
                if !beyond {
                    // Nothing converges ahead (the furthest point is a fold whose other
                    // leg lies far off), but the path itself can go on, and round an
                    // overhang it comes back past the furthest point on another leg:
                    // follow it, the tests off until it does. Ending here made the
                    // outcome hang on round-off (on the reference rotor with 60 um, a
                    // 1e-12 change of the disk mass stopped the sweep at 154 Hz).
                    armed = false;
                    continue;
                }
                break BranchEnd::StepTooSmall {
                    frequency: base.frequency,
                    message:
                        "the path turned back, stalled or retraced itself; no restart converged"
                            .into(),
                };
            };
            jumps.push((base.frequency, s.frequency));
            boundaries.push(points.len() - 1);
            (furthest, furthest_index, step) =
                (direction * s.frequency, points.len(), options.initial_step);
            let reached = s.frequency == to;
            (scaling, tangent) = rescaled(&scaling, &t, &s);
            travelled.push(travelled[travelled.len() - 1] + chord(&scaling, &points, &s));
            points.push(branch_point(s, &tangent, &scaling));
            if reached {
                break BranchEnd::Reached;
            }
        }
    };
    for (index, point) in points.iter().enumerate().skip(told) {
        hb.on_path(&point.solution);
        on_point(hb, index, point)?;
    }
    Ok(Path {
        points,
        corners,
        jumps,
        boundaries,
        end,
    })
}

/// A periodic solution at one exact frequency, where the branch crosses it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Crossing {
    /// Index of the branch point before the crossing (the point itself when it lies
    /// exactly on the frequency).
    pub after: usize,
    /// The solution, converged at exactly the frequency.
    pub solution: HbSolution,
    /// Its Floquet stability.
    pub stability: Stability,
}

/// Coexisting solutions closer than this, relative to the largest coefficient, are one:
/// two crossings of a wiggling stretch that Newton brings to the same orbit. The corrector
/// converges to a relative residual of 1e-10, so one orbit is found twice far closer.
const SAME_ORBIT: f64 = 1e-6;

/// Every solution of `branch` at exactly `frequency` (rad/s), in path order: Newton at
/// that frequency from the linear interpolation of the two points that bracket it (a
/// point lying on it is taken as it is), with Floquet stability. Where the branch crosses the
/// frequency several times (coexisting orbits: a fold's overhang, a loop) each distinct
/// orbit is given, so the answer does not depend on which one a sweep ends on. Stretches
/// the path jumped over are not crossings, and a crossing where Newton fails is left out:
/// the answer says where either happened ([`SolutionsAt`]), since the branch may hold
/// orbits at this speed that the list lacks.
///
/// # Errors
/// When the Floquet problem cannot be built or solved.
pub fn solutions_at(
    hb: &mut impl Periodic,
    branch: &Branch,
    frequency: f64,
) -> Result<SolutionsAt> {
    let points = &branch.points;
    let jumped_over = branch
        .jumps
        .iter()
        .copied()
        .filter(|&(a, b)| (a - frequency) * (b - frequency) <= 0.0)
        .collect();
    let mut unconverged = Vec::new();
    let mut found: Vec<(usize, HbSolution)> = Vec::new();
    for (i, p) in points.iter().enumerate() {
        let s = &p.solution;
        if s.frequency == frequency {
            found.push((i, s.clone()));
            continue;
        }
        let Some(next) = points.get(i + 1).map(|n| &n.solution) else {
            continue;
        };
        let brackets = (s.frequency - frequency) * (next.frequency - frequency) < 0.0;
        if brackets && !branch.jumped_after.contains(&i) {
            match land_on(hb, s, next, frequency) {
                Ok(solution) => found.push((i, solution)),
                Err(_) => unconverged.push(i),
            }
        }
    }
    let mut distinct: Vec<(usize, HbSolution)> = Vec::new();
    for (i, s) in found {
        let largest = s.coefficients.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let seen = distinct.iter().any(|(_, d)| {
            norm(&difference(&d.coefficients, &s.coefficients)) <= SAME_ORBIT * largest
        });
        if !seen {
            distinct.push((i, s));
        }
    }
    let crossings = distinct
        .into_iter()
        .map(|(after, solution)| {
            let stability = hb
                .floquet_problem(&solution.coefficients, solution.frequency)?
                .solve()?;
            Ok(Crossing {
                after,
                solution,
                stability,
            })
        })
        .collect::<Result<_>>()?;
    Ok(SolutionsAt {
        crossings,
        jumped_over,
        unconverged,
    })
}

/// The solutions of a branch at one speed ([`solutions_at`]), and where the list may be
/// incomplete.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SolutionsAt {
    /// Every distinct solution where the path crosses the speed, in path order.
    pub crossings: Vec<Crossing>,
    /// The jumps (from, to) of [`Branch::jumps`], rad/s, that span the speed: the path did
    /// not follow the branch there, and orbits at this speed on the stretch it skipped are
    /// missing from `crossings`.
    pub jumped_over: Vec<(f64, f64)>,
    /// Indices of the points after which the path crosses the speed but Newton at it did
    /// not converge: those crossings are missing too.
    pub unconverged: Vec<usize>,
}

impl SolutionsAt {
    /// True when every crossing of the branch was solved and the path jumped over none:
    /// `crossings` is then every orbit of the branch at this speed that the path followed.
    pub fn complete(&self) -> bool {
        self.jumped_over.is_empty() && self.unconverged.is_empty()
    }
}

/// Past a point where the arclength corrector fails at every step (a non-smooth corner
/// where Newton on the augmented system cycles): Newton at fixed frequency a little ahead
/// in the direction of travel, 1e-5, 1e-4 then 1e-3 of its frequency, from `last`. The new point
/// is converged like any other; what lies between is not followed.
fn step_over(
    hb: &mut impl Periodic,
    last: &HbSolution,
    tangent: &[f64],
    scaling: &Scaling,
) -> Option<(Vec<f64>, HbSolution)> {
    let travel = tangent[tangent.len() - 1].signum();
    [1e-5, 1e-4, 1e-3].into_iter().find_map(|fraction| {
        let frequency = last.frequency + travel * fraction * scaling.frequency;
        let s = hb.solve(frequency, &last.coefficients).ok()?;
        let t = unit_tangent(hb, &s, scaling, tangent).ok()?;
        Some((t, s))
    })
}

/// Scaled distances along the reflected tangent at which [`turn_at_corner`] tries a
/// point: from a small fraction of the orbit up to a few percent, the steps the path takes
/// near a corner.
const TURN_REACH: [f64; 3] = [1e-3, 1e-2, 3e-2];

/// Where neither the corrector nor [`step_over`] gets past `last`: a corner where the
/// branch turns back in speed by more than a right angle, as where a clearance ring's
/// middle (contact) branch, walking down in speed as its orbit shrinks, ends on the free
/// branch at the grazing orbit, which goes on up in speed with the orbit shrinking still.
/// No point lies ahead along the tangent (the arclength hyperplane misses the branch
/// beyond the corner) nor at a speed further on. The orbit goes on the way it was going
/// and the speed turns back: Newton at fixed speed from the tangent reflected in the speed,
/// at [`TURN_REACH`] from `last`. A point whose orbit moved against the tangent is the
/// leg the path came by, and is refused. Restarted ahead of the furthest point instead,
/// the path jumped from the corner past the fold (a ring with m e = 0.5: 1.41 to 3.28
/// rad/s), and the free orbit between was missing.
fn turn_at_corner(
    hb: &mut impl Periodic,
    last: &HbSolution,
    tangent: &[f64],
    scaling: &Scaling,
) -> Option<(Vec<f64>, HbSolution)> {
    let n = tangent.len() - 1;
    let mut reflected = tangent.to_vec();
    reflected[n] = -reflected[n];
    let y0 = scaling.scaled(last);
    TURN_REACH.into_iter().find_map(|reach| {
        let guess: Vec<f64> = y0
            .iter()
            .zip(&reflected)
            .map(|(y, t)| y + reach * t)
            .collect();
        let (coefficients, frequency) = scaling.unscaled(&guess);
        let s = hb.solve(frequency, &coefficients).ok()?;
        let moved = difference(&scaling.scaled(&s), &y0);
        let onward = dot(&moved[..n], &tangent[..n]) > 0.0;
        let t = unit_tangent(hb, &s, scaling, &reflected).ok()?;
        onward.then_some((t, s))
    })
}

/// Progress, in scaled arclength (a relative change of the orbit or of the speed), below
/// which `stall_points` successive points have stalled: a non-smooth stretch wiggling on
/// the spot or crawling with the smallest steps. A fold is not a stall, however slowly its
/// frequency changes: the orbit changes there, and the chord across a turning point is at
/// least 2 / pi of the arc (a half circle), steps of 1e-3 and more giving 100 points a
/// chord far above this.
const STALL_PROGRESS: f64 = 1e-2;

/// True when the last `count` points (0: never) advanced less than [`STALL_PROGRESS`]: the
/// chord between the first and the last of them, scaled at the last.
fn stalled(points: &[BranchPoint], count: usize) -> bool {
    if count == 0 || points.len() <= count {
        return false;
    }
    let last = &points[points.len() - 1].solution;
    let scaling = Scaling::at(last);
    let chord = difference(
        &scaling.scaled(last),
        &scaling.scaled(&points[points.len() - count].solution),
    );
    norm(&chord) < STALL_PROGRESS
}

/// The chord from the last of `points` to `next`, in `scaling`.
fn chord(scaling: &Scaling, points: &[BranchPoint], next: &HbSolution) -> f64 {
    let last = &points[points.len() - 1].solution;
    norm(&difference(&scaling.scaled(next), &scaling.scaled(last)))
}

/// Arclength, scaled, beyond which a return near a point passed is a retrace: 5 % of the
/// orbit or the speed, far more than the path travels round a corner or a tight fold.
const RETRACE_ARC: f64 = 0.05;

/// A point closer than this fraction of the arclength travelled since to a point the path
/// passed is on what it followed already. Across a turning point the two legs are a chord
/// apart of at least 2 / pi of the arc between (a half circle); a path that crossed a
/// hairpin onto the leg it came by, and walks it back, comes within the corrector's
/// tolerance of its own points: on the reference rotor with 60 um it had walked back from
/// 46.14 to 41.6 Hz over 600 points (each within 1e-4 to 1e-3 of a point passed, over
/// arcs of 0.1 and more) before the stall test caught it; with this test the sweep takes
/// 1241 points instead of 1864 to the same restart speeds and the same branch beyond.
const RETRACE_RATIO: f64 = 1e-3;

/// True when the last of `points` (arclengths `travelled`) retraces the path: it lies
/// within [`RETRACE_RATIO`] of the arclength since to a point passed more than
/// [`RETRACE_ARC`] before. Off, like the stall test, when `stall_points` is 0.
fn retraced(points: &[BranchPoint], travelled: &[f64], stall_points: usize) -> bool {
    if stall_points == 0 {
        return false;
    }
    let last = &points[points.len() - 1].solution;
    let scaling = Scaling::at(last);
    let here = scaling.scaled(last);
    let now = travelled[travelled.len() - 1];
    points.iter().zip(travelled).any(|(p, &then)| {
        let along = now - then;
        along > RETRACE_ARC
            && norm(&difference(&here, &scaling.scaled(&p.solution))) < RETRACE_RATIO * along
    })
}

/// Newton at fixed frequency 1e-3, 1e-2, 3e-2, 0.1 then 0.3 of its frequency beyond `furthest`
/// (rad/s) in `direction`, but not beyond `to`, from each of `guesses` in turn (points of
/// the path, the first point of the branch last: a cold start that does not carry the
/// resonance's large orbit past it); the new point's tangent points along the range.
fn jump_ahead(
    hb: &mut impl Periodic,
    guesses: &[&HbSolution],
    (furthest, to): (f64, f64),
    direction: f64,
    scaling: &Scaling,
) -> Option<(Vec<f64>, HbSolution)> {
    let size = guesses[0].coefficients.len();
    let mut along = vec![0.0; size + 1];
    along[size] = direction;
    let fractions = [1e-3, 1e-2, 3e-2, 0.1, 0.3];
    fractions.into_iter().find_map(|fraction| {
        let ahead = furthest + direction * fraction * furthest.abs();
        let frequency = if direction * (ahead - to) > 0.0 {
            to
        } else {
            ahead
        };
        guesses.iter().find_map(|guess| {
            let s = hb.solve(frequency, &guess.coefficients).ok()?;
            let t = unit_tangent(hb, &s, scaling, &along).ok()?;
            Some((t, s))
        })
    })
}

/// Where the corrector and [`step_over`] fail on a leg that climbs along the range below
/// the furthest point (`furthest`, signed by `direction` as in [`trace`]) and nothing
/// converges ahead of the furthest point: Newton at fixed frequency ahead of the last
/// point instead ([`jump_ahead`] from `last`), so the path goes on along the leg it is on,
/// which round an overhang is the leg that comes back past the furthest point. Ending there
/// instead made the outcome hang on round-off: on the reference rotor with 60 um and 160
/// AFT samples the path passed a fold at 153.99 Hz, walked back down to 139.2 Hz, turned,
/// and climbing again met a corner at 145.185 Hz where Newton cycled at 1e-6 to 1e-3 of the
/// frequency ahead (a residual stuck at 2e-6 to 2e-5 relative) and converged at 1e-2, on the
/// same leg (0.077 along the tangent for a 0.01 change of the speed, the tangent's
/// frequency component 0.13): the sweep stopped there, where 80 and 320 samples reach
/// 750 Hz. A leg the path walks back down (against the range) is left to [`step_over`]:
/// sent ahead, it would climb back over what it followed.
fn climb_on(
    hb: &mut impl Periodic,
    last: &HbSolution,
    tangent: &[f64],
    furthest: f64,
    to: f64,
    direction: f64,
    scaling: &Scaling,
) -> Option<(Vec<f64>, HbSolution)> {
    let climbing = direction * tangent[tangent.len() - 1] > 0.0;
    let behind = direction * last.frequency < furthest;
    if !(climbing && behind) {
        return None;
    }
    jump_ahead(hb, &[last], (last.frequency, to), direction, scaling)
}

/// How far out of the range, as a factor of the speed it starts at, the path follows a
/// leg that turned back out of it ([`trace`]) before it is restarted ahead: the reference
/// rotor's 120 um branch from 425 Hz goes down to 186 Hz and comes back.
const EXCURSION: f64 = 0.25;

/// Quick convergence (at most 3 iterations) lengthens the step by half, slow convergence
/// (more than 6) shortens it: the corrector then works in its quadratic range.
fn next_step(step: f64, iterations: usize, options: &ContinuationOptions) -> f64 {
    let factor = match iterations {
        0..=3 => 1.5,
        4..=6 => 1.0,
        _ => 0.5,
    };
    (step * factor).clamp(options.min_step, options.max_step)
}

fn branch_point(solution: HbSolution, tangent: &[f64], scaling: &Scaling) -> BranchPoint {
    BranchPoint {
        solution,
        frequency_slope: tangent[tangent.len() - 1] * scaling.frequency,
        stability: None,
    }
}

/// The path's corrector: plain Newton while the step can still be halved, and [`correct`]
/// (plain, then with a line search) only at the smallest step, before the path steps over
/// or jumps. A line search costs a condensation per trial length, and on the path a
/// halved step from a nearer predictor does what it would: on the reference rotor at
/// 20 um all 16 line-search runs that followed failed plain runs failed too, at 1,016 of
/// the path's 3,457 condensations; without them the path is the same to the bit at 20 um
/// and follows the same branches at 60 and 120 um (BENCHMARKS.md, harmonic balance).
fn correct_on_path(
    hb: &mut impl Periodic,
    y0: &[f64],
    t0: &[f64],
    step: f64,
    scaling: &Scaling,
    options: &ContinuationOptions,
) -> Result<HbSolution> {
    if step / 2.0 < options.min_step {
        correct(hb, y0, t0, step, scaling)
    } else {
        newton_on_arclength(hb, y0, t0, step, scaling, FULL_STEPS)
    }
}

/// Folds between successive points whose frequency slopes differ in sign, located on
/// `problems` ([`on_threads`]).
///
/// # Errors
/// None in practice: a fold whose search fails is estimated instead.
fn locate_folds<H: Periodic + Send>(
    problems: &mut [&mut H],
    points: &[BranchPoint],
    boundaries: &[usize],
) -> Result<Vec<Fold>> {
    let turning: Vec<usize> = points
        .windows(2)
        .enumerate()
        .filter(|(i, p)| {
            p[0].frequency_slope * p[1].frequency_slope < 0.0 && !boundaries.contains(i)
        })
        .map(|(i, _)| i)
        .collect();
    on_threads(problems, turning.len(), |hb, k| {
        Ok(fold_after(&mut **hb, points, turning[k]))
    })
}

/// The fold between points `i` and `i + 1`: located on the branch, or where its search
/// fails, the extremum of the Hermite interpolant.
fn fold_after(hb: &mut impl Periodic, points: &[BranchPoint], i: usize) -> Fold {
    let (p, q) = (&points[i], &points[i + 1]);
    let (before, after) = (&p.solution, &q.solution);
    match refine_fold(hb, before, after) {
        Ok(frequency) => Fold {
            frequency,
            refined: true,
            after: i,
        },
        Err(_) => {
            let scaling = Scaling::at(before);
            let chord = difference(&scaling.scaled(after), &scaling.scaled(before));
            Fold {
                frequency: hermite_extremum(
                    before.frequency,
                    after.frequency,
                    p.frequency_slope,
                    q.frequency_slope,
                    norm(&chord),
                ),
                refined: false,
                after: i,
            }
        }
    }
}

/// The fold locator's trials stop once the tangent's frequency component t_w is below
/// this: w is stationary at the fold, so its error is of order t_w^2, and 1e-9 leaves it
/// exact to round-off.
const FOLD_SLOPE: f64 = 1e-9;

/// ... or once the bracket is shorter than this fraction of the chord between the two
/// points. Where the fold sits on a corner (a contact opening) t_w jumps sign across it
/// and never falls below [`FOLD_SLOPE`]: on the reference rotor the bracket reaches 1e-6
/// of the chord by about the 20th trial, where the trial's speed is already within 1e-10
/// relative of the 40th's (1e-12 to 6e-11 at the 20 um sweep's corner folds).
const FOLD_BRACKET: f64 = 1e-6;

/// ... or after this many trials.
const FOLD_TRIALS: usize = 40;

/// The fold between `before` and `after`: the root of the tangent's frequency component
/// along the arclength from `before`, by the Illinois regula falsi.
fn refine_fold(hb: &mut impl Periodic, before: &HbSolution, after: &HbSolution) -> Result<f64> {
    let (y0, t0, length, scaling) = arclength_frame(hb, before, after)?;
    let scaling = &scaling;
    let chord = difference(&scaling.scaled(after), &y0);
    let last = t0.len() - 1;
    let (mut a, mut ga) = (0.0, t0[last]);
    // Both tangents are oriented along the chord, the direction of travel.
    let (mut b, mut gb) = (length, unit_tangent(hb, after, scaling, &chord)?[last]);
    let mut frequency = before.frequency;
    let mut kept_side = 0;
    for _ in 0..FOLD_TRIALS {
        let sigma = (a * gb - b * ga) / (gb - ga);
        let point = correct(hb, &y0, &t0, sigma, scaling)?;
        let g = unit_tangent(hb, &point, scaling, &t0)?[last];
        frequency = point.frequency;
        if g.abs() < FOLD_SLOPE {
            break;
        }
        // Illinois: halve the value kept twice in a row, so both ends move.
        if g * ga > 0.0 {
            (a, ga) = (sigma, g);
            if kept_side == 1 {
                gb /= 2.0;
            }
            kept_side = 1;
        } else {
            (b, gb) = (sigma, g);
            if kept_side == -1 {
                ga /= 2.0;
            }
            kept_side = -1;
        }
        if (b - a).abs() < FOLD_BRACKET * length {
            break;
        }
    }
    Ok(frequency)
}

/// The extreme value of the cubic Hermite interpolant on [0, h] with end values w0, w1 and
/// end slopes m0, m1 of opposite signs, where its derivative vanishes.
fn hermite_extremum(w0: f64, w1: f64, m0: f64, m1: f64, h: f64) -> f64 {
    // p(u) = h00 w0 + h h10 m0 + h01 w1 + h h11 m1 on u in [0, 1]; p'(u) = a u^2 + b u + c.
    let a = 6.0 * (w0 - w1) + 3.0 * h * (m0 + m1);
    let b = -6.0 * (w0 - w1) - h * (4.0 * m0 + 2.0 * m1);
    let c = h * m0;
    let u = if a.abs() <= 1e-12 * (b.abs() + c.abs()) {
        -c / b
    } else {
        let root = (b * b - 4.0 * a * c).max(0.0).sqrt();
        let (plus, minus) = ((-b + root) / (2.0 * a), (-b - root) / (2.0 * a));
        // p' changes sign on [0, 1], so one root lies in it; take the nearer to its middle.
        if (plus - 0.5).abs() <= (minus - 0.5).abs() {
            plus
        } else {
            minus
        }
    };
    let (u2, u3) = (u * u, u * u * u);
    (2.0 * u3 - 3.0 * u2 + 1.0) * w0
        + h * (u3 - 2.0 * u2 + u) * m0
        + (-2.0 * u3 + 3.0 * u2) * w1
        + h * (u3 - u2) * m1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points at (u, v) of a plane through the solution space: one coefficient 1 + u, the
    /// frequency 100 (1 + v), and the arclength travelled to each.
    fn path(uv: &[(f64, f64)]) -> (Vec<BranchPoint>, Vec<f64>) {
        let mut points: Vec<BranchPoint> = Vec::new();
        let mut travelled = vec![0.0];
        for &(u, v) in uv {
            let solution = HbSolution {
                frequency: 100.0 * (1.0 + v),
                coefficients: vec![1.0 + u],
                iterations: 0,
                relative_residual: 0.0,
            };
            if !points.is_empty() {
                let along = chord(&Scaling::at(&solution), &points, &solution);
                travelled.push(travelled[travelled.len() - 1] + along);
            }
            points.push(BranchPoint {
                solution,
                frequency_slope: 1.0,
                stability: None,
            });
        }
        (points, travelled)
    }

    #[test]
    fn a_path_walking_back_over_itself_retraces_and_a_fold_does_not() {
        // Out 0.3 in u and back 0.15 over the same points: the last point is a point
        // passed 0.3 of arclength before.
        let back: Vec<(f64, f64)> = (0..=60)
            .chain((30..60).rev())
            .map(|k| (0.005 * k as f64, 0.0))
            .collect();
        let (points, travelled) = path(&back);
        assert!(retraced(&points, &travelled, 100));
        assert!(!retraced(&points, &travelled, 0), "off with the stall test");
        // A turning point as tight as a half circle of radius 0.01 and back along a leg
        // 0.02 from the first: the legs stay a chord of 2 / pi of the arc apart.
        let fold: Vec<(f64, f64)> = (0..=40)
            .map(|k| (0.005 * k as f64, 0.0))
            .chain((1..=20).map(|k| {
                let angle = std::f64::consts::PI * k as f64 / 20.0;
                (0.2 + 0.01 * angle.sin(), 0.01 * (1.0 - angle.cos()))
            }))
            .chain((1..=40).map(|k| (0.2 - 0.005 * k as f64, 0.02)))
            .collect();
        let (points, travelled) = path(&fold);
        assert!(!retraced(&points, &travelled, 100));
        // Crawling on the spot is the stall test's business: 0.01 of arclength in all.
        let crawl: Vec<(f64, f64)> = (0..200).map(|k| (1e-4 * (k % 3) as f64, 0.0)).collect();
        let (points, travelled) = path(&crawl);
        assert!(!retraced(&points, &travelled, 100));
    }

    #[test]
    fn hermite_extremum_of_a_parabola_is_its_vertex() {
        // w(s) = 3 - (s - 0.3)^2 on [0, 1]: exact in a cubic interpolant.
        let w = |s: f64| 3.0 - (s - 0.3) * (s - 0.3);
        let slope = |s: f64| -2.0 * (s - 0.3);
        let top = hermite_extremum(w(0.0), w(1.0), slope(0.0), slope(1.0), 1.0);
        assert!((top - 3.0).abs() < 1e-14);
    }
}
