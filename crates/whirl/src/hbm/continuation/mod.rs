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

mod crossing;
mod fold;
mod path;
mod restart;

use super::balance::HbSolution;
use super::bifurcation::locate_bifurcations;
use crate::error::{Error, Result};
use fold::{locate_folds, stability_contradicts_folds};
use path::{trace, trace_with_stability};

pub use super::branch::{Branch, BranchEnd, BranchPoint, Fold};
pub use super::periodic::{Derivatives, Periodic};
pub use crossing::{solutions_at, Crossing, SolutionsAt};

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
