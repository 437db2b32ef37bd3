//! Getting on where the path cannot: past a corner of a non-smooth branch by Newton at a
//! fixed frequency, and restarts ahead of the furthest point where the path stalls, walks
//! back over what it followed, or the corrector fails at the smallest step.

use crate::hbm::arclength::{unit_tangent, Scaling};
use crate::hbm::balance::HbSolution;
use crate::hbm::branch::BranchPoint;
use crate::hbm::periodic::Periodic;
use crate::linalg::{difference, dot_in_order as dot, norm};

/// Past a point where the arclength corrector fails at every step (a non-smooth corner
/// where Newton on the augmented system cycles): Newton at fixed frequency a little ahead
/// in the direction of travel, 1e-5, 1e-4 then 1e-3 of its frequency, from `last`. The new point
/// is converged like any other; what lies between is not followed.
pub(super) fn step_over(
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
pub(super) fn turn_at_corner(
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
pub(super) fn stalled(points: &[BranchPoint], count: usize) -> bool {
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
pub(super) fn chord(scaling: &Scaling, points: &[BranchPoint], next: &HbSolution) -> f64 {
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
pub(super) fn retraced(points: &[BranchPoint], travelled: &[f64], stall_points: usize) -> bool {
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
pub(super) fn jump_ahead(
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
/// the furthest point (`furthest`, signed by `direction` as in
/// [`trace`](super::path::trace)) and nothing converges ahead of the furthest point: Newton
/// at fixed frequency ahead of the last point instead ([`jump_ahead`] from `last`), so the
/// path goes on along the leg it is on, which round an overhang is the leg that comes back
/// past the furthest point. Ending there instead made the outcome hang on round-off: on the
/// reference rotor with 60 um and 160 AFT samples the path passed a fold at 153.99 Hz,
/// walked back down to 139.2 Hz, turned, and climbing again met a corner at 145.185 Hz
/// where Newton cycled at 1e-6 to 1e-3 of the frequency ahead (a residual stuck at 2e-6 to
/// 2e-5 relative) and converged at 1e-2, on the same leg (0.077 along the tangent for a
/// 0.01 change of the speed, the tangent's frequency component 0.13): the sweep stopped
/// there, where 80 and 320 samples reach 750 Hz. A leg the path walks back down (against
/// the range) is left to [`step_over`]: sent ahead, it would climb back over what it
/// followed.
pub(super) fn climb_on(
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
}
