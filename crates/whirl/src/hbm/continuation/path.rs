//! The path follower: from a converged point, predictor, corrector and step control along
//! the branch until the range's end, with Floquet stability of each point solved on a
//! second thread while the path goes on.

use super::restart::{chord, climb_on, jump_ahead, retraced, stalled, step_over, turn_at_corner};
use super::ContinuationOptions;
use crate::error::{Error, Result};
use crate::hbm::arclength::{
    correct, land_on, newton_on_arclength, rescaled, unit_tangent, Scaling,
};
use crate::hbm::balance::{HbSolution, FULL_STEPS};
use crate::hbm::branch::{BranchEnd, BranchPoint, Path};
use crate::hbm::periodic::Periodic;
use crate::hbm::stability::FloquetProblem;
use crate::linalg::dot_in_order as dot;
use std::sync::{mpsc, Mutex, PoisonError};

/// Floquet problems queued for the second thread at most: each holds N matrices of
/// (2 n)^2 entries, and the path's thread blocks when it is this far ahead.
const FLOQUET_QUEUE: usize = 16;

/// [`trace`] with Floquet stability at every point. Building a point's problem needs the
/// harmonic balance and so the path's thread; solving it does not, and takes about as long
/// as a continuation step, so the solves run on a second thread while the path goes on,
/// and the path's thread joins them once the path has ended. Every verdict is the one a
/// solve after the path would give.
pub(super) fn trace_with_stability<H: Periodic>(
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
pub(super) fn trace<H: Periodic>(
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
