//! What keeps Newton's method on a harmonic balance honest, for every Newton run of hbm/
//! (at a fixed frequency, full or condensed, and the arclength corrector): when a run that
//! has not converged gives up ([`GiveUp`]), and the backtracking line search
//! ([`line_search`]) that breaks cycles between contact states.

use crate::linalg::norm;

/// The residual and its size.
pub(crate) struct Residual {
    pub values: Vec<f64>,
    /// |L x| + |F_ext| + |F_nl|.
    pub scale: f64,
}

/// |R| / scale; zero when every term vanishes (no load, no motion).
pub(crate) fn relative(residual: &Residual) -> f64 {
    let r = norm(&residual.values);
    if r == 0.0 {
        0.0
    } else {
        r / residual.scale
    }
}

/// Halvings of a Newton step before the line search takes the best length it tried: down
/// to 1/256 of the step, short enough to leave a contact state the full step overshoots.
pub(crate) const LINE_SEARCH_HALVINGS: usize = 8;

/// Plain Newton (every step taken whole): no halving.
pub(crate) const FULL_STEPS: usize = 0;

/// When a Newton run that has not converged gives up before `max_iterations`: only once it
/// has shown it cannot converge, so a run that converges takes every iteration it took
/// before and ends where it ended; only the failing runs get cheaper. Counted on the
/// reference rotor's 1-750 Hz sweeps (20 um with stability, 60 and 120 um without; every
/// corrector run of the path and of the fold and bifurcation locators, every Newton run at
/// fixed speed), the runs that failed spent 57-66 % of all condensations (a corrector
/// iteration, and each trial length of its line search, lies at its own speed), and failed
/// in two ways:
///
/// - plain Newton cycles between two contact states: most of the failing runs alternate
///   between two residuals that repeat to round-off from about the sixth iteration to the
///   thirtieth ([`GiveUp::two_cycle`]), the rest wander or run out of the range;
/// - with the line search, the residual creeps down by fractions of a percent, or cycles
///   with a period of 5-10 iterations, never near the tolerance ([`GiveUp::stalled`]).
///
/// Plain runs that converged did so after up to 25 iterations, with excursions up to 1800
/// times their first residual, so no rule on the residual's progress stops plain runs
/// early with a margin: only the cycle does (124 of the 203 failing plain runs, most at
/// the sixth or seventh iteration).
pub(crate) struct GiveUp {
    /// Whether the run shortens its steps (a line search): only then is it stopped
    /// for stalling (plain runs that converged had excursions of up to 20 iterations above
    /// their first residual).
    line_search: bool,
    /// Relative residuals of the iterates so far.
    residuals: Vec<f64>,
}

/// Two residuals closer than this, relative, are the same value repeated: the two-cycles
/// measured end repeating to round-off (44 of the 61 failing plain runs of the 20 and
/// 120 um sweeps) or to 1e-7-3e-6 while still settling onto the cycle; no run that
/// converged, on the three sweeps or in the tests, had two such repeats in a row.
const REPEATS: f64 = 1e-6;

/// Iterations over which a line-search run whose smallest residual has not fallen by
/// [`STALL_GAIN`] gives up. Of the 13 line-search runs that converged on the three sweeps,
/// 12 never went more than 2 iterations without a 10 % gain, one (60 um, 46.04 Hz, 21
/// iterations, creeping by 1-3 % an iteration before converging) went 5; 8 leaves that
/// margin and still stops the failing corrector runs (80-270 condensations each, a median
/// of 161) after a median of 13 iterations instead of 30.
const STALL_WINDOW: usize = 8;

/// The fall of the smallest residual that counts as progress over [`STALL_WINDOW`].
const STALL_GAIN: f64 = 0.9;

impl GiveUp {
    /// For a run whose steps are shortened up to `halvings` times.
    pub(crate) fn new(halvings: usize) -> GiveUp {
        GiveUp {
            line_search: halvings > 0,
            residuals: Vec::new(),
        }
    }

    /// Records the relative residual of the newest iterate, not converged, and says
    /// whether the run should stop there.
    pub(crate) fn now(&mut self, relative: f64) -> bool {
        self.residuals.push(relative);
        self.two_cycle() || (self.line_search && self.stalled())
    }

    /// The last four residuals alternate between two different values: Newton cycles. (A
    /// residual that stays the same is no cycle: where one term dominates the others, the
    /// relative residual stays at 1 while Newton walks to the root.)
    fn two_cycle(&self) -> bool {
        let r = &self.residuals;
        let n = r.len();
        let same = |a: f64, b: f64| (a - b).abs() <= REPEATS * a.abs();
        n >= 4 && same(r[n - 1], r[n - 3]) && same(r[n - 2], r[n - 4]) && !same(r[n - 1], r[n - 2])
    }

    /// The smallest residual has not fallen below [`STALL_GAIN`] of what it was
    /// [`STALL_WINDOW`] iterations before.
    fn stalled(&self) -> bool {
        let n = self.residuals.len();
        let smallest = |r: &[f64]| r.iter().copied().fold(f64::INFINITY, f64::min);
        n > STALL_WINDOW
            && smallest(&self.residuals)
                > STALL_GAIN * smallest(&self.residuals[..n - STALL_WINDOW])
    }
}

/// Armijo's sufficient decrease: the residual must fall by this fraction of what the
/// linear model promises, a weak condition that the full Newton step meets wherever Newton
/// converges quadratically (so converging iterations are unchanged by the search).
const SUFFICIENT_DECREASE: f64 = 1e-4;

/// The next Newton iterate x - lambda d and its residual, by backtracking on |R|: the full
/// step when it lowers |R| enough ([`SUFFICIENT_DECREASE`]), else the step halved, up to
/// `halvings` times, until it does, else the tried length with the smallest finite |R|
/// (with no halving, the full step: plain Newton). Newton on a contact force that switches
/// on and off can cycle between contact states with full steps (each step's linearisation
/// holds in one state only); a shorter step that lowers |R| breaks the cycle. `residual_at`
/// gives R at a trial point (not finite where it cannot be evaluated).
pub(crate) fn line_search(
    x: &[f64],
    d: &[f64],
    current: &Residual,
    halvings: usize,
    mut residual_at: impl FnMut(&[f64]) -> Residual,
) -> (Vec<f64>, Residual) {
    let size = norm(&current.values);
    let mut at = |lambda: f64| {
        let trial: Vec<f64> = x.iter().zip(d).map(|(xi, di)| xi - lambda * di).collect();
        let residual = residual_at(&trial);
        let trial_size = norm(&residual.values);
        let sufficient = trial_size <= (1.0 - SUFFICIENT_DECREASE * lambda) * size;
        (trial, residual, trial_size, sufficient)
    };
    let (trial, residual, trial_size, sufficient) = at(1.0);
    if sufficient {
        return (trial, residual);
    }
    // The full step is kept when no length gives a finite residual (the caller then stops
    // on it); a finite one replaces it, and a smaller one that.
    let mut best = (trial, residual, trial_size);
    let mut lambda = 1.0;
    for _ in 0..halvings {
        lambda /= 2.0;
        let (trial, residual, trial_size, sufficient) = at(lambda);
        if sufficient {
            return (trial, residual);
        }
        if trial_size < best.2 || (trial_size.is_finite() && !best.2.is_finite()) {
            best = (trial, residual, trial_size);
        }
    }
    (best.0, best.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The iteration (index of the residual) at which [`GiveUp`] stops a run with these
    /// relative residuals, none of them converged; None if it runs them all.
    fn gives_up_at(halvings: usize, residuals: &[f64]) -> Option<usize> {
        let mut give_up = GiveUp::new(halvings);
        residuals.iter().position(|&r| give_up.now(r))
    }

    #[test]
    fn newton_gives_up_on_a_two_cycle_or_a_stalled_line_search_and_never_on_a_slow_convergence() {
        // Relative residuals of corrector runs on the reference rotor's sweeps (the
        // counts in GiveUp's documentation). Plain Newton at 185.03 Hz, 20 um, cycling
        // between two contact states from the fourth iteration: it stops at the seventh,
        // where the last four residuals alternate.
        let (a, b) = (9.463898e-6, 9.420180e-6);
        let mut cycle = vec![6.121659e-3, 6.646233e-5, 9.463291e-6, 9.420219e-6];
        cycle.extend([a, b].repeat(13));
        assert_eq!(gives_up_at(FULL_STEPS, &cycle), Some(7));
        // The line-search run that followed it: a cycle of period 4-5 over 4.2e-6 to
        // 5.2e-6, stopped once its best has not fallen by 10 % in 8 iterations.
        let stalled = [
            6.121659e-3,
            6.646233e-5,
            9.463291e-6,
            9.420219e-6,
            4.733734e-6,
            4.437923e-6,
            4.299261e-6,
            4.265677e-6,
            4.249016e-6,
            5.209792e-6,
            4.885783e-6,
            4.275254e-6,
            4.241860e-6,
            5.216907e-6,
            4.879535e-6,
            4.269790e-6,
        ];
        assert_eq!(gives_up_at(LINE_SEARCH_HALVINGS, &stalled), Some(13));
        // The slowest that converged: plain Newton at 151.86 Hz, 60 um, 25 iterations up
        // and down by up to 50 times its first residual, and a line search at 46.04 Hz,
        // 60 um, creeping by 1-3 % an iteration for 16 iterations (the last residual of
        // each, converged, left out).
        let wandering = [
            5.547826e-3,
            2.445871e-2,
            1.755266e-3,
            2.552512e-2,
            2.326325e-1,
            4.424150e-2,
            7.612341e-3,
            1.756591e-2,
            2.688398e-3,
            9.744496e-3,
            2.939257e-2,
            2.181356e-3,
            1.193341e-2,
            1.651289e-2,
            1.472694e-3,
            8.770716e-3,
            4.911663e-3,
            5.856507e-3,
            3.089925e-3,
            2.935656e-1,
            6.993161e-2,
            1.437615e-2,
            2.009592e-3,
            1.170507e-4,
            3.171623e-7,
        ];
        assert_eq!(gives_up_at(FULL_STEPS, &wandering), None);
        let creeping = [
            3.752332e-3,
            3.717771e-3,
            3.450466e-3,
            3.532954e-3,
            3.536239e-3,
            3.416188e-3,
            3.246943e-3,
            3.200607e-3,
            3.104589e-3,
            3.085152e-3,
            2.370957e-3,
            2.366700e-3,
            2.333748e-3,
            2.230596e-3,
            2.164513e-3,
            2.000171e-3,
            1.971801e-3,
            1.196965e-3,
            1.798222e-4,
            3.981347e-5,
            3.455877e-7,
        ];
        assert_eq!(gives_up_at(LINE_SEARCH_HALVINGS, &creeping), None);
        // A residual that stays put is no cycle (the saturating force below keeps the
        // relative residual at 1 while Newton walks to the root).
        assert_eq!(gives_up_at(FULL_STEPS, &[1.0; 30]), None);
    }
}
