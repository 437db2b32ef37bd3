//! What following a branch gives: its points, folds and changes of stability, and why it
//! ended ([`Branch`]); the path as the follower leaves it, before folds and bifurcations
//! are located ([`Path`]). Types only: [`continuation`](mod@super::continuation) follows
//! the path, [`bifurcation`](super::bifurcation) locates its changes of stability and
//! [`resolution`](super::resolution) checks them, each reading and writing these.

use super::balance::HbSolution;
use super::stability::Stability;
use super::HbOptions;

/// A converged point of a branch.
#[derive(Debug, Clone, serde::Serialize)]
pub struct BranchPoint {
    /// The periodic solution.
    pub solution: HbSolution,
    /// dw/ds, rad/s per unit of scaled arclength: negative between two folds of a
    /// hardening overhang.
    pub frequency_slope: f64,
    /// Floquet stability, when asked for.
    pub stability: Option<Stability>,
}

/// A turning point (saddle-node) of the branch.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct Fold {
    /// Frequency of the fold, rad/s.
    pub frequency: f64,
    /// True when located on the branch (regula falsi), false for the Hermite estimate.
    pub refined: bool,
    /// Index of the branch point before it.
    pub after: usize,
}

/// Why a branch stopped.
#[derive(Debug, Clone, serde::Serialize)]
pub enum BranchEnd {
    /// The end frequency was reached (the last point lies on it).
    Reached,
    /// The branch turned back past the start frequency.
    LeftRange,
    /// The point limit was reached.
    PointLimit,
    /// The path passed the end frequency but the solution exactly on it did not converge;
    /// the last point is the one before.
    EndNotConverged {
        /// What failed.
        message: String,
    },
    /// The corrector failed with the smallest step: the path ends at the last point.
    StepTooSmall {
        /// Frequency of the last converged point, rad/s.
        frequency: f64,
        /// What failed.
        message: String,
    },
}

/// A continued branch of periodic solutions.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Branch {
    /// Discretisation used.
    pub options: HbOptions,
    /// Converged points in path order; no unconverged point is ever stored.
    pub points: Vec<BranchPoint>,
    /// Folds, in path order.
    pub folds: Vec<Fold>,
    /// Frequencies (rad/s) of corners, which non-smooth forces (contacts that open and
    /// close) produce: points where the tangent turned by more than `max_turn` and halving
    /// the step did not shrink the turn, or that were reached by stepping over a point where the corrector
    /// failed at every step (Newton at fixed frequency just ahead).
    pub corners: Vec<f64>,
    /// Restarts (from, to) in rad/s where the path stalled (a non-smooth stretch wiggling
    /// on the spot for `stall_points` points), turned back out of the range, walked back
    /// over what it followed, or where the
    /// corrector failed even at the smallest step: Newton at fixed frequency ahead of the
    /// furthest point (or, where nothing converges there, ahead of the last point of a leg
    /// that climbs below it). What lies between is not followed, as in a
    /// sweep experiment that jumps.
    pub jumps: Vec<(f64, f64)>,
    /// Indices of the points after which the path jumped ([`Branch::jumps`]): what lies
    /// between such a point and the next was not followed.
    pub jumped_after: Vec<usize>,
    /// Changes of stability, in path order (empty without stability).
    pub bifurcations: Vec<Bifurcation>,
    /// Folds (their speeds, rad/s) across which no real Floquet multiplier crosses +1:
    /// the stability verdicts contradict the balance's own turning points, as they do where
    /// the harmonics are too few for the linearisation about the truncated orbit to be the
    /// balance's (docs/theory.md section 7). Empty without stability, and when every fold
    /// shows its crossing.
    pub folds_without_crossing: Vec<f64>,
    /// Why the branch ended.
    pub end: BranchEnd,
}

impl Branch {
    /// The first change of stability along the path that loses it: where the synchronous
    /// orbit followed from the first speed first gives way (to a jump, a subharmonic or a
    /// non-synchronous component, by its kind); `None` when stability is never lost.
    pub fn first_stability_loss(&self) -> Option<&Bifurcation> {
        self.bifurcations.iter().find(|b| b.loses_stability)
    }

    /// The lowest and the highest speed of the points, rad/s: the range followed, wider
    /// than the sweep's where the branch turned back out of it and came back.
    pub fn speed_span(&self) -> (f64, f64) {
        self.points
            .iter()
            .map(|p| p.solution.frequency)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), w| {
                (lo.min(w), hi.max(w))
            })
    }
}

/// A followed path before its folds and bifurcations are located.
pub(super) struct Path {
    pub(super) points: Vec<BranchPoint>,
    pub(super) corners: Vec<f64>,
    pub(super) jumps: Vec<(f64, f64)>,
    /// Indices of the points after which the path jumped.
    pub(super) boundaries: Vec<usize>,
    pub(super) end: BranchEnd,
}

/// How a periodic solution loses (or regains) stability.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
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
    /// The kind, from the multipliers that cross ([`super::bifurcation`] gives the rule).
    pub kind: BifurcationKind,
    /// Frequency where the largest real part of the exponents crosses zero, rad/s: located
    /// on the branch when `located`, otherwise linearly interpolated between the two
    /// nearest branch points the search reached (the path's or its trial points). At a
    /// fold, the fold's frequency.
    pub frequency: f64,
    /// True when located on the branch by regula falsi to a bracket of 1e-5 of the speed
    /// (or at a located fold).
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

/// The check of one bifurcation at more samples (and, in a sweep, more stability modes).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Resolution {
    /// AFT samples per period of the check (twice the branch's in a sweep).
    pub samples: usize,
    /// Speeds of the orbits checked before and after the bifurcation along the path, rad/s:
    /// [`RESOLUTION_TOLERANCE`](super::RESOLUTION_TOLERANCE) of its speed away (or 0.8-1.4
    /// times that where Newton stalled at it), or the last point before a jump or the
    /// branch's end when the path stops closer.
    pub speeds: [f64; 2],
    /// Their stability at `samples`; `None` where Newton did not converge.
    pub stable: [Option<bool>; 2],
    /// The kind named by the largest multiplier at `samples` of the side that should be
    /// unstable, when it is.
    pub kind: Option<BifurcationKind>,
    /// The same change at `samples`: stable on one side, unstable on the other, as the
    /// branch says, and the same kind of crossing.
    pub resolved: bool,
}
