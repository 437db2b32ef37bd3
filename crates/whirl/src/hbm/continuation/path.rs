//! The path follower: from a converged point, predictor, corrector and step control along
//! the branch until the range's end, with Floquet stability of each point solved on a
//! second thread while the path goes on.

use super::restart::{chord, climb_on, jump_ahead, retraced, stalled, step_over, turn_at_corner};
use super::ContinuationOptions;
use crate::error::{Error, Result};
use crate::hbm::arclength::{
    correct, land_on, newton_on_arclength, rescaled, unit_tangent, Scaling,
};
use crate::hbm::balance::HbSolution;
use crate::hbm::branch::{BranchEnd, BranchPoint, Path};
use crate::hbm::newton::FULL_STEPS;
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
    range: (f64, f64),
    options: &ContinuationOptions,
    on_point: &mut dyn FnMut(&mut H, usize, &BranchPoint) -> Result<()>,
) -> Result<Path> {
    let mut path = Follower::start(hb, first, orientation, range, options)?;
    let end = loop {
        path.tell(on_point)?;
        if let Some(end) = path.advance()? {
            break end;
        }
    };
    path.tell(on_point)?;
    Ok(path.finish(end))
}

/// A path being followed: where it is, how it got there, and how it goes on. Each
/// [`Follower::advance`] predicts along the tangent and corrects onto the branch
/// ([`Follower::attempt`]), judges the tangent's turn ([`Follower::next_point`]), gets past
/// a corner or restarts where the corrector fails at the smallest step
/// ([`Follower::get_past`]), lands on the range's end ([`Follower::land`]), takes the point
/// and adapts the step ([`Follower::accept`]), and restarts ahead where the path stalls,
/// retraces itself or leaves the range too far ([`Follower::restart_ahead`]).
struct Follower<'a, H> {
    hb: &'a mut H,
    options: &'a ContinuationOptions,
    /// The range, rad/s, and the sign of `to - from`.
    from: f64,
    to: f64,
    direction: f64,
    /// The scales at the last point, and the unit tangent there in them.
    scaling: Scaling,
    tangent: Vec<f64>,
    points: Vec<BranchPoint>,
    /// Scaled arclength travelled to each point (chords; a restart counts its jump).
    travelled: Vec<f64>,
    step: f64,
    corners: Vec<f64>,
    jumps: Vec<(f64, f64)>,
    /// Indices of the points after which the path jumped: no fold or bifurcation is looked
    /// for across them.
    boundaries: Vec<usize>,
    /// The furthest speed reached, times `direction`, and its point.
    furthest: f64,
    furthest_index: usize,
    /// The turn of the last attempt rejected for turning too much.
    rejected_turn: Option<f64>,
    /// How many points `on_point` was told of.
    told: usize,
    /// Whether the stall and retrace tests are on: off after a restart ahead failed, until
    /// the path passes its furthest point.
    armed: bool,
}

/// What an attempt at the next point gives.
enum Next {
    /// A point to take, with its unit tangent (in the scales of the last point).
    Point(Vec<f64>, HbSolution),
    /// Nothing yet: try again with half the step.
    Halve,
    /// Nothing gets past the last point.
    End(BranchEnd),
}

impl<'a, H: Periodic> Follower<'a, H> {
    /// The path at its first point, its tangent oriented by `orientation` in frequency.
    fn start(
        hb: &'a mut H,
        first: HbSolution,
        orientation: f64,
        (from, to): (f64, f64),
        options: &'a ContinuationOptions,
    ) -> Result<Self> {
        let scaling = Scaling::at(&first);
        let mut start_direction = vec![0.0; first.coefficients.len() + 1];
        start_direction[first.coefficients.len()] = orientation;
        let tangent = unit_tangent(hb, &first, &scaling, &start_direction)?;
        let direction = (to - from).signum();
        let furthest = direction * first.frequency;
        let points = vec![branch_point(first, &tangent, &scaling)];
        Ok(Follower {
            hb,
            options,
            from,
            to,
            direction,
            scaling,
            tangent,
            points,
            travelled: vec![0.0],
            step: options.initial_step,
            corners: Vec::new(),
            jumps: Vec::new(),
            boundaries: Vec::new(),
            furthest,
            furthest_index: 0,
            rejected_turn: None,
            told: 0,
            armed: true,
        })
    }

    /// Tells the problem and `on_point` of the points not yet told of.
    fn tell(
        &mut self,
        on_point: &mut dyn FnMut(&mut H, usize, &BranchPoint) -> Result<()>,
    ) -> Result<()> {
        for (index, point) in self.points.iter().enumerate().skip(self.told) {
            self.hb.on_path(&point.solution);
            on_point(self.hb, index, point)?;
        }
        self.told = self.points.len();
        Ok(())
    }

    /// One step of the path: a new point, a shorter step, or the end (`Some`).
    fn advance(&mut self) -> Result<Option<BranchEnd>> {
        if self.points.len() >= self.options.max_points {
            return Ok(Some(BranchEnd::PointLimit));
        }
        self.check_stop()?;
        let (tangent, solution) = match self.next_point() {
            Next::Point(tangent, solution) => (tangent, solution),
            Next::Halve => {
                self.step /= 2.0;
                return Ok(None);
            }
            Next::End(end) => return Ok(Some(end)),
        };
        if self.direction * (solution.frequency - self.to) >= 0.0 {
            return Ok(Some(self.land(&tangent, solution)));
        }
        let outside = self.direction * (solution.frequency - self.from) < 0.0;
        if outside && self.options.stall_points == 0 {
            return Ok(Some(BranchEnd::LeftRange));
        }
        // A leg that turns back out of the range is followed out there, where it may turn
        // again and come back: the branch a sweep from further down follows. Restarted
        // ahead instead, the path skipped what that leg leads to (on the reference rotor
        // with 120 um, from 425 Hz, the leg below the fold at 436.9 Hz, which returns at
        // 384 Hz, and all its solutions up to 568 Hz).
        let excursion = self.from * EXCURSION.powf(self.direction);
        let beyond = outside && self.direction * (solution.frequency - excursion) < 0.0;
        if !beyond {
            self.accept(&tangent, solution);
        }
        // A path that goes that far out of the range, wiggles on the spot, or retraces
        // what it followed is restarted ahead of the furthest point, from it.
        if beyond || self.wandering() {
            return Ok(self.restart_ahead(beyond));
        }
        Ok(None)
    }

    /// [`Error::Interrupted`] when the caller asked the path to stop.
    fn check_stop(&self) -> Result<()> {
        if !self.hb.stop_requested() {
            return Ok(());
        }
        let last = &self.points[self.points.len() - 1].solution;
        Err(Error::Interrupted(format!(
            "the harmonic-balance path was stopped at {:.1} Hz",
            last.frequency / std::f64::consts::TAU
        )))
    }

    /// Predicts along the tangent by the step and corrects onto the branch
    /// ([`correct_on_path`]): the point, with its unit tangent.
    fn attempt(&mut self) -> Result<(Vec<f64>, HbSolution)> {
        let last = &self.points[self.points.len() - 1].solution;
        let y0 = self.scaling.scaled(last);
        let (scaling, options) = (&self.scaling, self.options);
        let s = correct_on_path(self.hb, &y0, &self.tangent, self.step, scaling, options)?;
        Ok((unit_tangent(self.hb, &s, scaling, &self.tangent)?, s))
    }

    /// The next point, judged by how far the tangent turned: taken when it turned less
    /// than `max_turn`, or at a corner; otherwise tried again with half the step. Where the
    /// corrector fails at the smallest step, [`Follower::get_past`].
    fn next_point(&mut self) -> Next {
        let attempt = self.attempt();
        let turn = attempt.as_ref().map_or(f64::NAN, |(t, _)| {
            dot(t, &self.tangent).clamp(-1.0, 1.0).acos()
        });
        let rejected_before = self.rejected_turn.take();
        let smallest = self.step / 2.0 < self.options.min_step;
        match attempt {
            Ok((tangent, s)) if turn <= self.options.max_turn => Next::Point(tangent, s),
            // On a smooth branch the turn halves with the step. One that does not shrink
            // (by less than a quarter), or persists at the smallest step, is a corner of a
            // non-smooth branch (a contact opening or closing), not an unresolved fold:
            // accept it.
            Ok((tangent, s))
                if smallest || rejected_before.is_some_and(|before| turn > 0.75 * before) =>
            {
                self.corners.push(s.frequency);
                Next::Point(tangent, s)
            }
            Ok(_) => {
                self.rejected_turn = Some(turn);
                Next::Halve
            }
            Err(e) if smallest => self.get_past(&e),
            Err(_) => Next::Halve,
        }
    }

    /// Where the corrector failed at the smallest step: past a corner by Newton at a fixed
    /// frequency ([`step_over`], [`turn_at_corner`]), else restarted ahead ([`jump_ahead`],
    /// [`climb_on`]); the path ends where none converges.
    fn get_past(&mut self, error: &Error) -> Next {
        let last = &self.points[self.points.len() - 1].solution;
        let (tangent, scaling) = (&self.tangent, &self.scaling);
        let past = step_over(self.hb, last, tangent, scaling)
            .or_else(|| turn_at_corner(self.hb, last, tangent, scaling));
        if let Some((t, s)) = past {
            self.corners.push(s.frequency);
            self.step = self.options.initial_step;
            return Next::Point(t, s);
        }
        let guesses = [last, &self.points[0].solution];
        let (furthest, to, direction) = (self.furthest, self.to, self.direction);
        let restart = jump_ahead(
            self.hb,
            &guesses,
            (direction * furthest, to),
            direction,
            scaling,
        )
        .or_else(|| climb_on(self.hb, last, tangent, furthest, to, direction, scaling));
        let Some((t, s)) = restart else {
            return Next::End(BranchEnd::StepTooSmall {
                frequency: last.frequency,
                message: error.to_string(),
            });
        };
        self.jumps.push((last.frequency, s.frequency));
        self.boundaries.push(self.points.len() - 1);
        self.step = self.options.initial_step;
        Next::Point(t, s)
    }

    /// The path passed the range's end with `solution` (`tangent` its tangent): the point
    /// exactly on the end closes it.
    fn land(&mut self, tangent: &[f64], solution: HbSolution) -> BranchEnd {
        let last = &self.points[self.points.len() - 1].solution;
        let scaling = &self.scaling;
        let end_point = land_on(self.hb, last, &solution, self.to).and_then(|p| {
            let t = unit_tangent(self.hb, &p, scaling, tangent)?;
            Ok(branch_point(p, &t, scaling))
        });
        match end_point {
            Ok(point) => {
                self.points.push(point);
                BranchEnd::Reached
            }
            Err(e) => BranchEnd::EndNotConverged {
                message: e.to_string(),
            },
        }
    }

    /// Takes `solution` onto the path, and lengthens or shortens the step by how quickly
    /// it converged ([`next_step`]).
    fn accept(&mut self, tangent: &[f64], solution: HbSolution) {
        self.step = next_step(self.step, solution.iterations, self.options);
        if self.direction * solution.frequency > self.furthest {
            self.furthest = self.direction * solution.frequency;
            self.furthest_index = self.points.len();
            self.armed = true;
        }
        self.push(tangent, solution);
    }

    /// Appends `solution`, moving the scales to it and `tangent` with them.
    fn push(&mut self, tangent: &[f64], solution: HbSolution) {
        (self.scaling, self.tangent) = rescaled(&self.scaling, tangent, &solution);
        let along = chord(&self.scaling, &self.points, &solution);
        self.travelled
            .push(self.travelled[self.travelled.len() - 1] + along);
        self.points
            .push(branch_point(solution, &self.tangent, &self.scaling));
    }

    /// Whether the path, its tests on, wiggles on the spot ([`stalled`]) or walks back over
    /// what it followed ([`retraced`]).
    fn wandering(&self) -> bool {
        let count = self.options.stall_points;
        self.armed
            && (stalled(&self.points, count) || retraced(&self.points, &self.travelled, count))
    }

    /// Restarts the path ahead of its furthest point, from it ([`jump_ahead`]), after it went
    /// `beyond` the range's start by [`EXCURSION`], stalled or retraced itself; the end of
    /// the path (`Some`) where that reached the range's end, or where nothing converged
    /// ahead of a path gone beyond.
    fn restart_ahead(&mut self, beyond: bool) -> Option<BranchEnd> {
        let base = &self.points[self.furthest_index].solution;
        // The last point too: after a retrace it lies on another stretch of the branch
        // than the furthest, and Newton ahead may converge from it alone.
        let guesses = [
            base,
            &self.points[self.points.len() - 1].solution,
            &self.points[0].solution,
        ];
        let ahead = (self.direction * self.furthest, self.to);
        let Some((t, s)) = jump_ahead(self.hb, &guesses, ahead, self.direction, &self.scaling)
        else {
            if !beyond {
                // Nothing converges ahead (the furthest point is a fold whose other leg
                // lies far off), but the path itself can go on, and round an overhang it
                // comes back past the furthest point on another leg: follow it, the tests
                // off until it does. Ending here made the outcome hang on round-off (on
                // the reference rotor with 60 um, a 1e-12 change of the disk mass stopped
                // the sweep at 154 Hz).
                self.armed = false;
                return None;
            }
            return Some(BranchEnd::StepTooSmall {
                frequency: base.frequency,
                message: "the path turned back, stalled or retraced itself; no restart converged"
                    .into(),
            });
        };
        self.jumps.push((base.frequency, s.frequency));
        self.boundaries.push(self.points.len() - 1);
        self.furthest = self.direction * s.frequency;
        self.furthest_index = self.points.len();
        self.step = self.options.initial_step;
        let reached = s.frequency == self.to;
        self.push(&t, s);
        reached.then_some(BranchEnd::Reached)
    }

    /// The path as followed, ended by `end`.
    fn finish(self, end: BranchEnd) -> Path {
        Path {
            points: self.points,
            corners: self.corners,
            jumps: self.jumps,
            boundaries: self.boundaries,
            end,
        }
    }
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
