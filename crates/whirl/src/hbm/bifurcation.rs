//! Where a branch loses or regains stability, and how, from the Floquet multipliers.
//!
//! Stability changes where a Floquet multiplier mu (an eigenvalue of the monodromy matrix,
//! [`super::stability`]) crosses the unit circle, and where it crosses names the bifurcation
//! (Seydel, "Practical Bifurcation and Stability Analysis", ch. 7; Nayfeh & Balachandran,
//! "Applied Nonlinear Dynamics", ch. 5):
//!
//! - a real multiplier at +1: a fold (turning point) when the branch turns there, otherwise
//!   a symmetry-breaking (pitchfork) or branch point;
//! - a real multiplier at -1: period doubling, a subharmonic at w/2 appears;
//! - a complex-conjugate pair exp(+-i theta): Neimark-Sacker, a component at theta / T
//!   (and its combinations k w +- theta / T) appears; this is where non-synchronous
//!   vibration starts.
//!
//! The monodromy matrix is real, so its real eigenvalues come out real (an imaginary part
//! of exactly zero) and the others in conjugate pairs: the kind is read off the crossing
//! multiplier directly. Each change found between two branch points is located by the
//! Illinois regula falsi on the largest real part of the exponents along the arclength,
//! every trial point corrected onto the branch and its monodromy matrix formed; the
//! multiplier is read where it crosses.

use super::continuation::{arclength_frame, correct, BranchPoint, Fold, Periodic};
use super::resolution::Resolution;
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
    /// The crossing multiplier, (real, imaginary), at the trial point nearest the crossing
    /// (of a complex pair, the one with positive imaginary part).
    pub multiplier: (f64, f64),
    /// |Im| of the crossing exponent, rad/s, in [0, w/2]: the frequency of the emerging
    /// component (0 at +1, w/2 at period doubling); at a Neimark-Sacker point it appears
    /// with its combinations k w +- this.
    pub exponent_frequency: f64,
    /// Index of the branch point before it.
    pub after: usize,
    /// True when stability is lost along the path, false when regained.
    pub loses_stability: bool,
    /// Whether the change holds at twice the AFT samples and stability modes
    /// ([`super::resolution`]); `None` when not checked (a branch from
    /// [`super::continuation()`] itself, or twice the samples above the most).
    pub resolution: Option<Resolution>,
}

/// A multiplier is real when its imaginary part is below this fraction of its modulus:
/// the real Schur form gives real eigenvalues an imaginary part of exactly zero, and a
/// complex pair this close to the axis would be a collision of two real multipliers,
/// resolved to round-off only.
const ON_AXIS: f64 = 1e-9;

/// The regula falsi stops when the bracket is this short in scaled arclength (a relative
/// change of 1e-5 of the speed or the orbit: 5 mHz at 500 Hz, 0.4 mHz at 40 Hz; the last
/// step's interpolation makes a simple crossing more accurate still), or after
/// [`MAX_TRIALS`] trial points. What the answer resolves is far coarser: the AFT sample
/// count moves the reference rotor's bifurcations by 0.1 to 2 Hz, and each is checked at
/// 0.5 % of its speed either side ([`super::resolution`]). Where the largest real part
/// jumps across zero (a contact opening at a corner) the bracket only halves per trial:
/// 1e-7 cost 7 more trials each there, and a trial whose corrector failed left the
/// crossing interpolated between the path's points instead (on the 20 um sweep the loss
/// at 44.981 Hz, located now, had been interpolated at 44.951 Hz).
const BRACKET: f64 = 1e-5;
const MAX_TRIALS: usize = 40;

/// The changes of stability along `points`, each located on the branch, except across
/// `boundaries` (indices after which the path jumped). `folds` are the branch's turning
/// points: a +1 crossing in the same interval is that fold.
///
/// # Errors
/// When the Floquet problem cannot be built (a singular mass matrix).
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
            .floquet_problem(&point.coefficients, point.frequency)?
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

/// The kind of the crossing from the multiplier of largest modulus nearest the crossing.
fn classify(crossing: Located, after: usize, loses_stability: bool, at_fold: bool) -> Bifurcation {
    let w = crossing.frequency;
    let (kind, (re, im)) = crossing_kind(&crossing.nearest, at_fold);
    let period = std::f64::consts::TAU / w;
    Bifurcation {
        kind,
        frequency: w,
        located: crossing.located,
        multiplier: (re, im.abs()),
        exponent_frequency: im.abs().atan2(re) / period,
        after,
        loses_stability,
        resolution: None,
    }
}

/// The kind named by the multiplier of largest modulus of `stability`, and that multiplier;
/// `at_fold` when the branch turns there.
pub(super) fn crossing_kind(stability: &Stability, at_fold: bool) -> (BifurcationKind, (f64, f64)) {
    let (re, im) = stability
        .multipliers
        .iter()
        .copied()
        .max_by(|x, y| x.0.hypot(x.1).total_cmp(&y.0.hypot(y.1)))
        .unwrap_or((1.0, 0.0));
    let real = im.abs() <= ON_AXIS * re.hypot(im);
    let kind = match (real, re > 0.0) {
        (true, true) if at_fold => BifurcationKind::Fold,
        (true, true) => BifurcationKind::SymmetryBreaking,
        (true, false) => BifurcationKind::PeriodDoubling,
        (false, _) => BifurcationKind::NeimarkSacker,
    };
    (kind, (re, im))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A crossing at w whose nearest trial has these multipliers.
    fn crossing(frequency: f64, multipliers: Vec<(f64, f64)>) -> Located {
        let period = std::f64::consts::TAU / frequency;
        let exponents: Vec<(f64, f64)> = multipliers
            .iter()
            .map(|&(re, im)| (re.hypot(im).ln() / period, im.atan2(re) / period))
            .collect();
        let max_real = exponents.iter().map(|e| e.0).fold(f64::MIN, f64::max);
        Located {
            frequency,
            located: true,
            nearest: Stability {
                multipliers,
                exponents,
                max_real,
                stable: false,
            },
        }
    }

    #[test]
    fn crossing_multipliers_name_the_bifurcation() {
        let w = 10.0;
        let kind = |multipliers, fold| classify(crossing(w, multipliers), 0, true, fold).kind;
        let on_circle = |turns: f64| {
            let a = std::f64::consts::TAU * turns;
            (1.000001 * a.cos(), 1.000001 * a.sin())
        };
        // A complex pair at +-0.3 turns, with a damped real multiplier.
        let (c, s) = on_circle(0.3);
        assert_eq!(
            kind(vec![(c, s), (c, -s), (0.2, 0.0)], false),
            BifurcationKind::NeimarkSacker
        );
        // A complex pair close to -1 (0.49 turns) is still a pair.
        let (c, s) = on_circle(0.49);
        assert_eq!(
            kind(vec![(c, s), (c, -s)], false),
            BifurcationKind::NeimarkSacker
        );
        // One real multiplier through -1.
        let doubling = vec![(-1.000001, 0.0), (0.3, 0.1), (0.3, -0.1)];
        assert_eq!(kind(doubling, false), BifurcationKind::PeriodDoubling);
        // A real multiplier through +1: a fold where the branch turns, symmetry breaking
        // elsewhere.
        let real = vec![(1.000001, 0.0), (0.3, 0.2), (0.3, -0.2)];
        assert_eq!(kind(real.clone(), true), BifurcationKind::Fold);
        assert_eq!(kind(real, false), BifurcationKind::SymmetryBreaking);
    }

    #[test]
    fn the_emerging_frequency_is_the_multiplier_s_angle_per_period() {
        // A pair at +-i: a quarter turn per period T = 2 pi / 10, so 2.5 rad/s.
        let b = classify(
            crossing(10.0, vec![(0.0, 1.0), (0.0, -1.0)]),
            3,
            false,
            false,
        );
        assert_eq!(b.kind, BifurcationKind::NeimarkSacker);
        assert_eq!(b.multiplier, (0.0, 1.0));
        assert!((b.exponent_frequency - 2.5).abs() < 1e-15);
        assert!(!b.loses_stability && b.after == 3);
        // Period doubling: half a turn, w / 2.
        let b = classify(crossing(10.0, vec![(-1.0, 0.0)]), 0, true, false);
        assert!((b.exponent_frequency - 5.0).abs() < 1e-15);
    }
}
