//! Where a branch loses or regains stability, and how.
//!
//! Between two successive points of different stability a Floquet exponent crosses the
//! imaginary axis; its imaginary part (in the strip |Im| <= w/2 that Hill's method keeps)
//! tells the kind of bifurcation (Seydel, "Practical Bifurcation and Stability Analysis",
//! ch. 7):
//!
//! - Im = 0, Floquet multiplier +1: a fold (turning point), or a branch point;
//! - |Im| = w/2, multiplier -1: period doubling, a subharmonic at w/2 appears;
//! - otherwise, a complex pair: Neimark-Sacker, a component at the non-synchronous
//!   frequency |Im| (and its combinations with w) appears; this is where
//!   non-synchronous vibration starts.

use super::continuation::BranchPoint;

/// How a periodic solution loses (or regains) stability.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum BifurcationKind {
    /// A real exponent crosses zero.
    Fold,
    /// An exponent crosses at |Im| = w/2.
    PeriodDoubling,
    /// A complex pair crosses elsewhere.
    NeimarkSacker,
}

/// A change of stability between two successive branch points.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct Bifurcation {
    /// The kind, from the crossing exponent.
    pub kind: BifurcationKind,
    /// Frequency where the largest real part crosses zero, linearly interpolated between
    /// the two points, rad/s. At a fold the real part grows as the square root of the
    /// distance, so [`super::Fold::frequency`] is the sharper estimate there.
    pub frequency: f64,
    /// |Im| of the crossing exponent, rad/s: the frequency of the emerging component at a
    /// Neimark-Sacker point.
    pub exponent_frequency: f64,
    /// Index of the branch point before it.
    pub after: usize,
    /// True when stability is lost along the path, false when regained.
    pub loses_stability: bool,
}

/// Exponents within 1% of w of the real axis or of w/2 count as there: the truncated Hill
/// matrix places them there up to a truncation error far below that.
const ON_AXIS: f64 = 0.01;

/// The changes of stability along `points` (those without stability are skipped).
pub fn bifurcations(points: &[BranchPoint]) -> Vec<Bifurcation> {
    let mut found = Vec::new();
    for (i, pair) in points.windows(2).enumerate() {
        let (Some(a), Some(b)) = (&pair[0].stability, &pair[1].stability) else {
            continue;
        };
        if a.stable == b.stable {
            continue;
        }
        let unstable = if a.stable { b } else { a };
        // Hill's method keeps 2n >= 2 exponents; a hand-built point without any has no
        // crossing to classify.
        let Some(crossing) = unstable.exponents.iter().max_by(|x, y| x.0.total_cmp(&y.0)) else {
            continue;
        };
        let w = pair[1].solution.frequency;
        let im = crossing.1.abs();
        let kind = if im <= ON_AXIS * w {
            BifurcationKind::Fold
        } else if im >= (0.5 - ON_AXIS) * w {
            BifurcationKind::PeriodDoubling
        } else {
            BifurcationKind::NeimarkSacker
        };
        let (w0, w1) = (pair[0].solution.frequency, w);
        let u = a.max_real / (a.max_real - b.max_real);
        found.push(Bifurcation {
            kind,
            frequency: w0 + u * (w1 - w0),
            exponent_frequency: im,
            after: i,
            loses_stability: a.stable,
        });
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hbm::{HbSolution, Stability};

    fn point(frequency: f64, exponents: Vec<(f64, f64)>) -> BranchPoint {
        let max_real = exponents.iter().map(|e| e.0).fold(f64::MIN, f64::max);
        BranchPoint {
            solution: HbSolution {
                frequency,
                coefficients: Vec::new(),
                iterations: 0,
                relative_residual: 0.0,
            },
            frequency_slope: 1.0,
            stability: Some(Stability {
                exponents,
                max_real,
                stable: max_real < 0.0,
            }),
        }
    }

    #[test]
    fn crossing_exponents_are_classified_by_their_imaginary_part() {
        let points = [
            point(10.0, vec![(-0.1, 3.0), (-0.1, -3.0)]),
            // A complex pair at 3 rad/s crosses between 10 and 11 rad/s, at 10.25.
            point(11.0, vec![(0.3, 3.1), (0.3, -3.1)]),
            // The same pair crosses back between 11 and 12: stability regained.
            point(12.0, vec![(-0.2, 6.0), (-0.2, -6.0)]),
            point(13.0, vec![(-0.1, 0.0), (-0.2, 0.0)]),
            point(14.0, vec![(0.1, 0.0), (-0.2, 0.0)]),
        ];
        let found = bifurcations(&points);
        let kinds: Vec<_> = found.iter().map(|b| b.kind).collect();
        assert_eq!(
            kinds,
            [
                BifurcationKind::NeimarkSacker,
                BifurcationKind::NeimarkSacker,
                BifurcationKind::Fold
            ]
        );
        assert!((found[0].frequency - 10.25).abs() < 1e-12);
        assert!((found[0].exponent_frequency - 3.1).abs() < 1e-12);
        assert!(found[0].loses_stability && !found[1].loses_stability);
        assert!((found[2].frequency - 13.5).abs() < 1e-12);

        let doubling = [
            point(12.0, vec![(-0.2, 6.0), (-0.2, -6.0)]),
            point(12.2, vec![(0.2, 6.1), (0.2, -6.1)]),
        ];
        assert_eq!(
            bifurcations(&doubling)[0].kind,
            BifurcationKind::PeriodDoubling
        );
    }
}
