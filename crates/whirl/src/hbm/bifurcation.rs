//! Where a branch loses or regains stability, and how, from the Floquet multipliers.
//!
//! A Floquet exponent lambda (Hill's method, folded into the strip |Im| <= w/2) belongs to
//! the multiplier mu = exp(lambda T), T = 2 pi / w. Stability changes where a multiplier
//! crosses the unit circle, and where it crosses names the bifurcation (Seydel, "Practical
//! Bifurcation and Stability Analysis", ch. 7; Nayfeh & Balachandran, "Applied Nonlinear
//! Dynamics", ch. 5):
//!
//! - a real multiplier at +1 (Im lambda = 0): a fold (turning point) when the branch turns
//!   there, otherwise a symmetry-breaking (pitchfork) or branch point;
//! - a real multiplier at -1 (Im lambda = w/2, with no conjugate partner: lambda and its
//!   conjugate are one multiplier): period doubling, a subharmonic at w/2 appears;
//! - a complex-conjugate pair exp(+-i theta) (two exponents with the same real part and
//!   opposite imaginary parts): Neimark-Sacker, a component at |Im lambda| (and its
//!   combinations k w +- |Im lambda|) appears; this is where non-synchronous vibration
//!   starts.
//!
//! Each change found between two branch points is located by the Illinois regula falsi on
//! the largest real part along the arclength, every trial point corrected onto the branch
//! and its Hill problem solved; the multiplier is read where it crosses.

use super::continuation::{arclength_frame, correct, BranchPoint, Fold, Periodic};
use super::stability::Stability;
use crate::error::Result;

/// How a periodic solution loses (or regains) stability.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum BifurcationKind {
    /// A real multiplier crosses +1 where the branch turns.
    Fold,
    /// A real multiplier crosses +1 where the branch does not turn: a pitchfork or branch
    /// point, where another branch (often a less symmetric orbit) meets this one.
    SymmetryBreaking,
    /// A real multiplier crosses -1.
    PeriodDoubling,
    /// A complex-conjugate pair of multipliers crosses the unit circle.
    NeimarkSacker,
}

/// A change of stability between two successive branch points.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct Bifurcation {
    /// The kind, from the crossing multiplier.
    pub kind: BifurcationKind,
    /// Frequency where the largest real part of the exponents crosses zero, rad/s: located
    /// on the branch when `located`, otherwise linearly interpolated between the two
    /// points. At a fold, the fold's frequency.
    pub frequency: f64,
    /// True when located on the branch by regula falsi (or at a located fold).
    pub located: bool,
    /// The crossing multiplier exp(lambda T), (real, imaginary), at the located point (of a
    /// complex pair, the one with positive imaginary part).
    pub multiplier: (f64, f64),
    /// |Im| of the crossing exponent, rad/s, in [0, w/2]: the frequency of the emerging
    /// component (0 at +1, w/2 at period doubling); at a Neimark-Sacker point it appears
    /// with its combinations k w +- this.
    pub exponent_frequency: f64,
    /// Index of the branch point before it.
    pub after: usize,
    /// True when stability is lost along the path, false when regained.
    pub loses_stability: bool,
}

/// Exponents whose multiplier lies within 1 % of a half turn of +1 or -1 are real: the
/// truncated Hill matrix places them there up to a truncation error far below that.
const ON_AXIS: f64 = 0.01;

/// Two exponents are a conjugate pair when their imaginary parts are opposite (modulo w)
/// within this fraction of w, the tolerance by which Hill's method merges copies
/// ([`super::stability`]), and their real parts agree within [`PAIR_REAL`] of w.
const PAIR_IMAGINARY: f64 = 1e-3;

/// A conjugate pair of eigenvalues of the real Hill matrix has equal real parts to
/// round-off; 1e-6 of w is far above it and far below the gap to any other exponent at a
/// crossing.
const PAIR_REAL: f64 = 1e-6;

/// The regula falsi stops when the bracket is this short in scaled arclength (a relative
/// change of 1e-7 of the speed or the orbit: 0.05 mHz at 500 Hz, far below what is
/// printed; the last step's interpolation makes a simple crossing more accurate still), or
/// after [`MAX_TRIALS`] trial points. Where the largest real part jumps across zero (a
/// contact opening at a corner) the bracket only halves per trial, and a tighter one cost
/// 7 more trials each with no change in what is printed.
const BRACKET: f64 = 1e-7;
const MAX_TRIALS: usize = 40;

/// The changes of stability along `points`, each located on the branch, except across
/// `boundaries` (indices after which the path jumped). `folds` are the branch's turning
/// points: a +1 crossing in the same interval is that fold.
///
/// # Errors
/// When Hill's eigenproblem cannot be built (a singular mass matrix).
pub(super) fn locate_bifurcations(
    hb: &mut impl Periodic,
    points: &[BranchPoint],
    folds: &[Fold],
    boundaries: &[usize],
) -> Result<Vec<Bifurcation>> {
    let mut found = Vec::new();
    for (i, pair) in points.windows(2).enumerate() {
        let (Some(a), Some(b)) = (&pair[0].stability, &pair[1].stability) else {
            continue;
        };
        if a.stable == b.stable || boundaries.contains(&i) {
            continue;
        }
        let fold = folds.iter().find(|f| f.after == i && f.refined);
        let crossing = match fold {
            // The exponent crosses zero as the square root of the distance at a fold,
            // which regula falsi converges to slowly: the fold is already on the branch.
            Some(f) => Located {
                frequency: f.frequency,
                located: true,
                nearest: if a.stable { b.clone() } else { a.clone() },
            },
            None => crossing(hb, (&pair[0], a), (&pair[1], b))?,
        };
        found.push(classify(crossing, i, a.stable, fold.is_some()));
    }
    Ok(found)
}

/// Where the largest real part crosses zero, and the stability nearest the crossing (the
/// unstable end when it was not located).
struct Located {
    frequency: f64,
    located: bool,
    nearest: Stability,
}

/// Illinois regula falsi on g(sigma) = the largest real part at the branch point at
/// arclength sigma from `before` (along its tangent, corrected onto the branch). Should a
/// corrector fail (a corner between the points), the linear interpolation of g between
/// the two points stands in.
fn crossing(
    hb: &mut impl Periodic,
    (before, sa): (&BranchPoint, &Stability),
    (after, sb): (&BranchPoint, &Stability),
) -> Result<Located> {
    let (w0, w1) = (before.solution.frequency, after.solution.frequency);
    let interpolated = || {
        let u = sa.max_real / (sa.max_real - sb.max_real);
        Located {
            frequency: w0 + u * (w1 - w0),
            located: false,
            nearest: if sa.stable { sb.clone() } else { sa.clone() },
        }
    };
    let Ok((y0, t0, chord_length, scaling)) =
        arclength_frame(hb, &before.solution, &after.solution)
    else {
        return Ok(interpolated());
    };
    // Bracket ends (arclength, the value the Illinois rule works with, true value, w).
    let mut a = (0.0, sa.max_real, sa.max_real, w0);
    let mut b = (chord_length, sb.max_real, sb.max_real, w1);
    let mut nearest = if sa.stable { sb.clone() } else { sa.clone() };
    let mut kept_side = 0;
    for _ in 0..MAX_TRIALS {
        if (b.0 - a.0).abs() < BRACKET {
            break;
        }
        let sigma = (a.0 * b.1 - b.0 * a.1) / (b.1 - a.1);
        let Ok(point) = correct(hb, &y0, &t0, sigma, &scaling) else {
            return Ok(interpolated());
        };
        let verdict = hb
            .hill_problem(&point.coefficients, point.frequency)?
            .solve()?;
        let g = verdict.max_real;
        // The crossing exponent is read at the trial nearest the crossing, on either side:
        // it is the one with the largest real part on both.
        if g.abs() < nearest.max_real.abs() {
            nearest = verdict;
        }
        let trial = (sigma, g, g, point.frequency);
        // Illinois: halve the value kept twice in a row, so both ends move.
        if g * a.2 > 0.0 {
            a = trial;
            if kept_side == 1 {
                b.1 /= 2.0;
            }
            kept_side = 1;
        } else {
            b = trial;
            if kept_side == -1 {
                a.1 /= 2.0;
            }
            kept_side = -1;
        }
    }
    // The largest real part is linear in the arclength through a simple crossing.
    let u = a.2 / (a.2 - b.2);
    Ok(Located {
        frequency: a.3 + u * (b.3 - a.3),
        located: true,
        nearest,
    })
}

/// The kind of the crossing from the multiplier of the exponent with the largest real part
/// nearest the crossing.
fn classify(crossing: Located, after: usize, loses_stability: bool, at_fold: bool) -> Bifurcation {
    let w = crossing.frequency;
    let exponents = &crossing.nearest.exponents;
    let (re, im) = exponents
        .iter()
        .copied()
        .max_by(|x, y| x.0.total_cmp(&y.0))
        .unwrap_or((0.0, 0.0));
    let period = std::f64::consts::TAU / w;
    // Of a conjugate pair, the member in the upper half plane.
    let angle = im.abs() * period;
    let modulus = (re * period).exp();
    let multiplier = (modulus * angle.cos(), modulus * angle.sin());
    let half_turns = angle / std::f64::consts::PI;
    let has_partner = exponents.iter().any(|&(r, i)| {
        let opposite = (i + im) / w;
        (r - re).abs() <= PAIR_REAL * w
            && (opposite - opposite.round()).abs() <= PAIR_IMAGINARY
            && (i - im).abs() > PAIR_IMAGINARY * w
    });
    let kind = if half_turns <= ON_AXIS {
        if at_fold {
            BifurcationKind::Fold
        } else {
            BifurcationKind::SymmetryBreaking
        }
    } else if half_turns >= 1.0 - ON_AXIS && !has_partner {
        BifurcationKind::PeriodDoubling
    } else {
        BifurcationKind::NeimarkSacker
    };
    Bifurcation {
        kind,
        frequency: w,
        located: crossing.located,
        multiplier,
        exponent_frequency: im.abs(),
        after,
        loses_stability,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn crossing(frequency: f64, exponents: Vec<(f64, f64)>) -> Located {
        let max_real = exponents.iter().map(|e| e.0).fold(f64::MIN, f64::max);
        Located {
            frequency,
            located: true,
            nearest: Stability {
                exponents,
                max_real,
                stable: false,
            },
        }
    }

    #[test]
    fn crossing_multipliers_name_the_bifurcation() {
        let w = 10.0;
        let kind = |exponents, fold| classify(crossing(w, exponents), 0, true, fold).kind;
        // A complex pair at +-3 rad/s: multipliers exp(+-0.6 pi i).
        let pair = vec![(1e-9, 3.0), (1e-9, -3.0), (-0.2, 0.0)];
        assert_eq!(kind(pair, false), BifurcationKind::NeimarkSacker);
        // A complex pair close to -1 (+-4.9 rad/s of w / 2 = 5) is still a pair.
        let near_half = vec![(1e-9, 4.9), (1e-9, -4.9)];
        assert_eq!(kind(near_half, false), BifurcationKind::NeimarkSacker);
        // One real multiplier at -1: lambda = i w / 2 is its own conjugate (mod i w).
        let doubling = vec![(1e-9, 5.0), (-0.3, 1.0), (-0.3, -1.0)];
        assert_eq!(kind(doubling, false), BifurcationKind::PeriodDoubling);
        // A real multiplier at +1: a fold where the branch turns, symmetry breaking elsewhere.
        let real = vec![(1e-9, 0.0), (-0.3, 2.0), (-0.3, -2.0)];
        assert_eq!(kind(real.clone(), true), BifurcationKind::Fold);
        assert_eq!(kind(real, false), BifurcationKind::SymmetryBreaking);
    }

    #[test]
    fn the_multiplier_is_on_the_unit_circle_at_the_crossing() {
        let b = classify(
            crossing(10.0, vec![(0.0, 2.5), (0.0, -2.5)]),
            3,
            false,
            false,
        );
        // exp(i 2.5 T), T = 2 pi / 10: a quarter turn.
        assert!(b.multiplier.0.abs() < 1e-15 && (b.multiplier.1 - 1.0).abs() < 1e-15);
        assert_eq!(b.exponent_frequency, 2.5);
        assert!(!b.loses_stability && b.after == 3);
    }
}
