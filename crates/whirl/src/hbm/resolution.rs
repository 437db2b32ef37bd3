//! Whether a located bifurcation holds at twice the AFT samples and twice the stability
//! model's modes.
//!
//! On a branch whose orbit grazes the contacts the Floquet multipliers stay within a few
//! hundredths of the unit circle over long stretches, and the alternating frequency-time
//! transform of a law whose curvature is unbounded at first contact converges slowly in the
//! samples: some changes of stability move, or come and go, with the sample count N. The
//! monodromy matrix is formed on a Craig-Bampton model with M fixed-interface modes, and
//! the multipliers move with M too (the reference rotor's period doubling at 160-171 Hz,
//! which time marching of the same model confirms, is missed with 4 modes).
//! Each bifurcation is therefore checked at 2N samples (the balance and the monodromy
//! matrix both) and 2M modes, on a problem the caller sets up so (`fine` of [`check`]): on
//! either side of it along the path, at a distance of [`RESOLUTION_TOLERANCE`] of its
//! speed, the orbit is solved again by Newton at fixed speed from the branch's, and its
//! multipliers formed. The bifurcation is resolved when the
//! side it leaves is stable (for a loss; unstable for a regain), the side it reaches is
//! not, and the unstable side's largest multiplier names the same kind of crossing (+1,
//! -1 or a complex pair). This says that the change holds at 2N and 2M within the
//! tolerance; it does not bound where it lies within it, nor prove that 4N or 4M would
//! agree, and it cannot find a change the branch does not show.

use super::bifurcation::crossing_kind;
use super::branch::{Bifurcation, BifurcationKind, Branch, BranchPoint};
use super::periodic::Periodic;
use super::stability::Stability;
use crate::error::Result;

pub use super::branch::Resolution;

/// The sides are this fraction of the bifurcation's speed from it. On the reference rotor
/// (20 um, H = 5) the changes that hold from 160 samples on move by up to 0.45 % between N
/// and 2N, and the narrowest window that holds (about 507-511 Hz) is 0.75 % wide, while
/// the windows that come and go with N are 0.02-0.23 % wide (BENCHMARKS.md, harmonic balance): at
/// 0.5 % the former are resolved and the latter are not. A real window narrower than this
/// is reported unresolved.
pub const RESOLUTION_TOLERANCE: f64 = 0.005;

/// The distances of a side, in [`RESOLUTION_TOLERANCE`]s, tried in turn. Newton at fixed
/// speed can stall (a relative residual of about 1e-6 on the reference rotor, at 134.4 and
/// 182.0 Hz) where a time sample sits at a contact's edge, where the contact damping makes
/// the force jump; a slightly different speed moves the samples off it.
const DISTANCES: [f64; 4] = [1.0, 1.2, 0.8, 1.4];

/// Checks `bifurcation` of `branch` with `fine`, the same problem at more AFT samples per
/// period (in [`super::sweep()`] twice the branch's, and twice the stability modes:
/// [`CondensedBalance::with_samples`](super::CondensedBalance::with_samples)).
///
/// # Errors
/// When a Floquet problem cannot be built or solved (a singular mass matrix, a tangent
/// that is not finite); a Newton failure at a side is reported in [`Resolution::stable`].
pub fn check(
    fine: &mut impl Periodic,
    branch: &Branch,
    bifurcation: &Bifurcation,
) -> Result<Resolution> {
    let (points, boundaries) = (&branch.points, &branch.jumped_after);
    let mut speeds = [0.0; 2];
    let mut verdicts: [Option<Stability>; 2] = [None, None];
    for (k, forward) in [false, true].into_iter().enumerate() {
        for distance in DISTANCES {
            let reach = distance * RESOLUTION_TOLERANCE * bifurcation.frequency;
            let (speed, guess) = side(points, boundaries, bifurcation, forward, reach);
            speeds[k] = speed;
            if let Ok(orbit) = fine.solve(speed, &guess) {
                verdicts[k] = Some(fine.floquet_problem(&orbit.coefficients, speed)?.solve()?);
                break;
            }
        }
    }
    let stable = [0, 1].map(|k| verdicts[k].as_ref().map(|s| s.stable));
    // A loss leaves a stable side and reaches an unstable one; a regain the reverse.
    let unstable_side = usize::from(bifurcation.loses_stability);
    let expected = [
        Some(bifurcation.loses_stability),
        Some(!bifurcation.loses_stability),
    ];
    let at_fold = bifurcation.kind == BifurcationKind::Fold;
    let kind = verdicts[unstable_side]
        .as_ref()
        .filter(|s| !s.stable)
        .map(|s| crossing_kind(s, at_fold));
    Ok(Resolution {
        samples: fine.options().samples,
        speeds,
        stable,
        kind,
        resolved: stable == expected && kind == Some(bifurcation.kind),
    })
}

/// The speed where the path is `reach` (rad/s) away from the bifurcation's speed, walking
/// backwards along the path (`forward` false) or forwards, and the guess
/// there: the linear interpolation of the two path points around that speed. Round a fold
/// both sides lie on the same side in speed, on its two legs. The walk stops at a jump or
/// the branch's end, and takes the last point it reached.
fn side(
    points: &[BranchPoint],
    boundaries: &[usize],
    bifurcation: &Bifurcation,
    forward: bool,
    reach: f64,
) -> (f64, Vec<f64>) {
    let (w, i) = (bifurcation.frequency, bifurcation.after);
    let walk: Vec<usize> = if forward {
        (i + 1..points.len()).collect()
    } else {
        (0..=i).rev().collect()
    };
    // The point on the bifurcation's side of the next one walked to.
    let mut previous = if forward { i } else { i + 1 };
    for k in walk {
        // The first step crosses the bifurcation, never a jump.
        if k.min(previous) != i && boundaries.contains(&k.min(previous)) {
            break;
        }
        let (a, b) = (&points[previous].solution, &points[k].solution);
        if (b.frequency - w).abs() >= reach {
            let speed = w + (b.frequency - w).signum() * reach;
            let u = if a.frequency == b.frequency {
                1.0
            } else {
                ((speed - a.frequency) / (b.frequency - a.frequency)).clamp(0.0, 1.0)
            };
            let guess = a
                .coefficients
                .iter()
                .zip(&b.coefficients)
                .map(|(x, y)| x + u * (y - x))
                .collect();
            return (speed, guess);
        }
        previous = k;
    }
    let last = &points[previous].solution;
    (last.frequency, last.coefficients.clone())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hbm::HbSolution;

    fn path(frequencies: &[f64]) -> Vec<BranchPoint> {
        frequencies
            .iter()
            .map(|&frequency| BranchPoint {
                solution: HbSolution {
                    frequency,
                    coefficients: vec![frequency],
                    iterations: 0,
                    relative_residual: 0.0,
                },
                frequency_slope: 0.0,
                stability: None,
            })
            .collect()
    }

    fn at(frequency: f64, after: usize) -> Bifurcation {
        Bifurcation {
            kind: BifurcationKind::SymmetryBreaking,
            frequency,
            located: true,
            multiplier: (1.0, 0.0),
            exponent_frequency: 0.0,
            after,
            loses_stability: true,
            resolution: None,
        }
    }

    #[test]
    fn sides_lie_the_tolerance_away_along_the_path() {
        // Points every 0.2 rad/s, the bifurcation at 100.05: the sides at 100.05 -+ 0.50025,
        // with the guess interpolated between the points around them (the coefficient is
        // the frequency, so the guess equals the side's speed).
        let points = path(&[
            99.0, 99.2, 99.4, 99.6, 99.8, 100.0, 100.2, 100.4, 100.6, 100.8,
        ]);
        let b = at(100.05, 5);
        for (forward, expected) in [(false, 100.05 - 0.50025), (true, 100.05 + 0.50025)] {
            let (speed, guess) = side(
                &points,
                &[],
                &b,
                forward,
                RESOLUTION_TOLERANCE * b.frequency,
            );
            assert!((speed - expected).abs() < 1e-12, "{forward}: {speed}");
            assert!((guess[0] - expected).abs() < 1e-12, "{forward}: {guess:?}");
        }
    }

    #[test]
    fn round_a_fold_both_sides_lie_below_it_on_its_two_legs() {
        // The path turns at about 100 rad/s: the loss just before the turn has its sides at
        // 99.5 on the way up and on the way back.
        let points = path(&[98.0, 99.0, 99.8, 100.0, 99.8, 99.0, 98.0]);
        let mut b = at(99.9, 2);
        b.kind = BifurcationKind::Fold;
        for forward in [false, true] {
            let (speed, _) = side(
                &points,
                &[],
                &b,
                forward,
                RESOLUTION_TOLERANCE * b.frequency,
            );
            assert!((speed - 99.9 * (1.0 - RESOLUTION_TOLERANCE)).abs() < 1e-12);
        }
    }

    #[test]
    fn a_jump_or_the_end_stops_the_walk_at_the_last_point() {
        let points = path(&[99.0, 99.8, 100.0, 100.1, 100.2, 103.0]);
        let b = at(99.9, 1);
        let reach = RESOLUTION_TOLERANCE * b.frequency;
        // Forwards the path jumps after point 4 (100.2): the side is that point.
        assert_eq!(side(&points, &[4], &b, true, reach).0, 100.2);
        // Backwards it reaches 99.0, beyond the tolerance: interpolated.
        let (speed, _) = side(&points, &[4], &b, false, reach);
        assert!((speed - 99.9 * (1.0 - RESOLUTION_TOLERANCE)).abs() < 1e-12);
        // The branch ends at 100.2 without a jump: the last point again.
        let short = path(&[99.0, 99.8, 100.0, 100.1, 100.2]);
        assert_eq!(side(&short, &[], &b, true, reach).0, 100.2);
    }
}
