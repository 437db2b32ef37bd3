//! Every solution of a followed branch at one speed, where the branch crosses it.

use crate::error::Result;
use crate::hbm::arclength::land_on;
use crate::hbm::balance::HbSolution;
use crate::hbm::branch::Branch;
use crate::hbm::periodic::Periodic;
use crate::hbm::stability::Stability;
use crate::linalg::{difference, norm};

/// A periodic solution at one exact frequency, where the branch crosses it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Crossing {
    /// Index of the branch point before the crossing (the point itself when it lies
    /// exactly on the frequency).
    pub after: usize,
    /// The solution, converged at exactly the frequency.
    pub solution: HbSolution,
    /// Its Floquet stability.
    pub stability: Stability,
}

/// Coexisting solutions closer than this, relative to the largest coefficient, are one:
/// two crossings of a wiggling stretch that Newton brings to the same orbit. The corrector
/// converges to a relative residual of 1e-10, so one orbit is found twice far closer.
const SAME_ORBIT: f64 = 1e-6;

/// Every solution of `branch` at exactly `frequency` (rad/s), in path order: Newton at
/// that frequency from the linear interpolation of the two points that bracket it (a
/// point lying on it is taken as it is), with Floquet stability. Where the branch crosses the
/// frequency several times (coexisting orbits: a fold's overhang, a loop) each distinct
/// orbit is given, so the answer does not depend on which one a sweep ends on. Stretches
/// the path jumped over are not crossings, and a crossing where Newton fails is left out:
/// the answer says where either happened ([`SolutionsAt`]), since the branch may hold
/// orbits at this speed that the list lacks.
///
/// # Errors
/// When the Floquet problem cannot be built or solved.
pub fn solutions_at(
    hb: &mut impl Periodic,
    branch: &Branch,
    frequency: f64,
) -> Result<SolutionsAt> {
    let points = &branch.points;
    let jumped_over = branch
        .jumps
        .iter()
        .copied()
        .filter(|&(a, b)| (a - frequency) * (b - frequency) <= 0.0)
        .collect();
    let mut unconverged = Vec::new();
    let mut found: Vec<(usize, HbSolution)> = Vec::new();
    for (i, p) in points.iter().enumerate() {
        let s = &p.solution;
        if s.frequency == frequency {
            found.push((i, s.clone()));
            continue;
        }
        let Some(next) = points.get(i + 1).map(|n| &n.solution) else {
            continue;
        };
        let brackets = (s.frequency - frequency) * (next.frequency - frequency) < 0.0;
        if brackets && !branch.jumped_after.contains(&i) {
            match land_on(hb, s, next, frequency) {
                Ok(solution) => found.push((i, solution)),
                Err(_) => unconverged.push(i),
            }
        }
    }
    let mut distinct: Vec<(usize, HbSolution)> = Vec::new();
    for (i, s) in found {
        let largest = s.coefficients.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let seen = distinct.iter().any(|(_, d)| {
            norm(&difference(&d.coefficients, &s.coefficients)) <= SAME_ORBIT * largest
        });
        if !seen {
            distinct.push((i, s));
        }
    }
    let crossings = distinct
        .into_iter()
        .map(|(after, solution)| {
            let stability = hb
                .floquet_problem(&solution.coefficients, solution.frequency)?
                .solve()?;
            Ok(Crossing {
                after,
                solution,
                stability,
            })
        })
        .collect::<Result<_>>()?;
    Ok(SolutionsAt {
        crossings,
        jumped_over,
        unconverged,
    })
}

/// The solutions of a branch at one speed ([`solutions_at`]), and where the list may be
/// incomplete.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SolutionsAt {
    /// Every distinct solution where the path crosses the speed, in path order.
    pub crossings: Vec<Crossing>,
    /// The jumps (from, to) of [`Branch::jumps`], rad/s, that span the speed: the path did
    /// not follow the branch there, and orbits at this speed on the stretch it skipped are
    /// missing from `crossings`.
    pub jumped_over: Vec<(f64, f64)>,
    /// Indices of the points after which the path crosses the speed but Newton at it did
    /// not converge: those crossings are missing too.
    pub unconverged: Vec<usize>,
}

impl SolutionsAt {
    /// True when every crossing of the branch was solved and the path jumped over none:
    /// `crossings` is then every orbit of the branch at this speed that the path followed.
    pub fn complete(&self) -> bool {
        self.jumped_over.is_empty() && self.unconverged.is_empty()
    }
}
