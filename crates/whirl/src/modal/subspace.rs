//! The lowest modes of a large banded pencil K v = lambda M v by shift-invert subspace
//! iteration (Bathe, *Finite Element Procedures*, 2nd ed., section 11.6), at a cost that
//! grows linearly with the DOF count instead of the dense solver's cube.
//!
//! With a shift sigma below every eigenvalue, A = K - sigma M is positive definite and is
//! factorised once as a band (O(n b^2), b the half-bandwidth). Each iteration, from
//! M-orthonormal vectors X (n x q):
//!
//! ```text
//! Y = A^-1 M X                          q band solves
//! K_r = Y^T M X  (= Y^T A Y),  M_r = Y^T M Y
//! K_r z = mu M_r z                      q x q, dense; mu = lambda - sigma
//! X <- Y Z                              Ritz vectors, M-orthonormal
//! ```
//!
//! Vector j converges as (mu_j / mu_(q+1))^k, so q = max(2p, p + 8) vectors are iterated for
//! p modes. The Rayleigh-Ritz step needs no product with K, whose entries span the whole
//! frequency range of the mesh; only M and the factors of A enter.
//!
//! The shift doubles as the test of stability at rest: A has a pivot that is not positive
//! exactly when an eigenvalue lies below sigma (Sylvester's law of inertia applied to its
//! LDL^T factors).
//!
//! The critical-speed map's pencil M_eff v = mu K_p v has an indefinite M_eff (a disk's and
//! the shaft's polar inertia) but a positive definite K_p: [`largest_roots`] iterates it the
//! same way with K_p as the inner product, which needs no definite mass.

use std::ops::ControlFlow;

use faer::Mat;

use crate::error::{Error, Result};
use crate::linalg::{Band, BandLu};
use crate::progress::{tell, Progress};

/// Converged when, for every wanted Ritz pair (mu_j, x_j) with |x_j|_M = 1, the inverse
/// iteration moves the vector by at most this: |mu_j A^-1 M x_j - x_j|_M <= TOLERANCE (the
/// same for [`largest_roots`] in its own inner product). The change is the vector's error
/// along the other modes, and the eigenvalue's error is of its square (over the relative gap
/// to the next, Kato-Temple), far below round-off.
const TOLERANCE: f64 = 1e-9;

/// On fine meshes round-off sets a floor above [`TOLERANCE`]: the stiffness of an element
/// grows as 1 / length^3, so K's entries (5e17 N/m for the 10,000-element reference rotor)
/// dwarf the stiffness of the lowest modes (1e6 N/m) and the solves with A lose the
/// difference in digits (the change stalls at 5e-9 for 2,000 elements, 7e-7 for 10,000; for
/// the critical-speed map's roots, at up to 1.3e-6 for 10,000).
/// The iteration has then converged as far as double precision allows, which is recognised
/// when the change stops falling (by less than half in one iteration) while the wanted Ritz
/// values stay put to this amount, relative to the largest of them: a slow but genuine
/// convergence changes them by the square of the vectors' change, far more. Relative to the
/// largest, not to each: round-off in the solves moves every Ritz value by about the same
/// absolute amount, so a nearly rigid mode (w^2 1e-8 of the largest wanted, on bearings of
/// 1e4 N/m) jitters by 1e-10 of itself and would never count as steady.
const STALLED_VALUES: f64 = 1e-11;

/// Whether an iteration has converged, from the largest change of a wanted vector in this
/// iteration and the last, and the wanted values now and then: the change is within
/// [`TOLERANCE`], or it has stopped falling (by less than half) at a round-off floor while
/// the values stay put to [`STALLED_VALUES`] of the largest.
fn converged(change: f64, previous_change: f64, values: &[f64], previous: &[f64]) -> bool {
    let steady = || {
        let scale = values.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
        previous.len() == values.len()
            && values
                .iter()
                .zip(previous)
                .all(|(v, p)| (v - p).abs() <= STALLED_VALUES * scale)
    };
    change <= TOLERANCE || (change > 0.5 * previous_change && steady())
}

/// Iterations before giving up; the reference rotors converge in a few tens, with each
/// iteration dividing the error by mu_(q+1) / mu_p, at least 2 for isolated modes.
const MAX_ITERATIONS: usize = 300;

/// The `count` lowest eigenpairs of K v = lambda M v (K's symmetric part, M positive
/// definite), both bands of one size: lambda ascending and M-orthonormal vectors as columns.
/// `shift` is sigma: every eigenvalue must lie above it. `progress` is told after every
/// iteration ([`told`]).
///
/// # Errors
/// [`Error::Singular`] when M is not positive definite, or when K - sigma M is not (an
/// eigenvalue lies below the shift: `below_shift` gives the message); [`Error::NotConverged`]
/// when the iteration does not meet its tolerance in [`MAX_ITERATIONS`];
/// [`Error::Interrupted`] when `progress` stopped it.
pub(crate) fn lowest_modes(
    stiffness: &Band,
    mass: &Band,
    count: usize,
    shift: f64,
    below_shift: impl FnOnce() -> Error,
    progress: Option<&Progress>,
) -> Result<(Vec<f64>, Mat<f64>)> {
    let n = mass.size();
    let p = count.min(n);
    let q = (2 * p).max(p + 8).min(n);
    let factors = factorise(stiffness, mass, shift, below_shift)?;
    let mut padded = {
        let (before, after) = factors.padding();
        vec![0.0; before + n + after]
    };
    let mut x = starting_vectors(n, q);
    let mut mu: Vec<f64> = Vec::new();
    let mut previous_mu: Vec<f64> = Vec::new();
    let mut largest_change = f64::INFINITY;
    let mut first_change = None;
    for iteration in 0..=MAX_ITERATIONS {
        let mx = mass.times(&x);
        let y = solve(&factors, &mx, &mut padded);
        if !mu.is_empty() {
            let previous = largest_change;
            largest_change = (0..p)
                .map(|j| change(mass, mu[j], y.col_as_slice(j), x.col_as_slice(j)))
                .fold(0.0, f64::max);
            let previous_wanted = previous_mu.get(..p).unwrap_or(&[]);
            if converged(largest_change, previous, &mu[..p], previous_wanted) {
                let lambda = mu[..p].iter().map(|m| m + shift).collect();
                let vectors = Mat::from_fn(n, p, |i, j| x[(i, j)]);
                return Ok((lambda, vectors));
            }
            let first = *first_change.get_or_insert(largest_change);
            told(progress, p, iteration, first, largest_change)?;
        }
        if iteration == MAX_ITERATIONS {
            break;
        }
        // Y made M-orthonormal first: its columns lean towards the lowest modes (by
        // mu_1 / mu_k), and left so M_r would be singular in floating point.
        let (mut y, mut mx) = (y, mx);
        let mut my = mass.times(&y);
        orthonormalise(&mut y, &mut my, Some(&mut mx));
        let k_r = symmetric(&(y.transpose() * &mx));
        let m_r = symmetric(&(y.transpose() * &my));
        let (values, z) = crate::modal::symmetric_modes(&k_r, &m_r, q)?;
        x = &y * &z;
        previous_mu = std::mem::replace(&mut mu, values);
    }
    Err(Error::not_converged(
        "subspace iteration",
        Some(MAX_ITERATIONS),
        Some(largest_change),
        format!(
            "the lowest {p} modes did not converge in {MAX_ITERATIONS} iterations of subspace \
             iteration (the largest change of a mode shape in the last one was {largest_change:.2e}, \
             the tolerance {TOLERANCE:.0e}): the model has many modes of nearly equal \
             frequency; ask for fewer modes"
        ),
    ))
}

/// The `count` largest positive roots theta of M v = theta A v, descending, for bands A
/// symmetric positive definite and M symmetric but possibly indefinite (fewer when fewer are
/// positive), by subspace iteration on A^-1 M in the inner product of A. A^-1 M is
/// self-adjoint in it (A A^-1 M = M is symmetric), so its roots are real, its eigenvectors
/// A-orthogonal, and the Rayleigh-Ritz step on q vectors,
///
/// ```text
/// Y = A^-1 M X,  B = A Y = M X
/// M_r = Y^T M Y,  A_r = Y^T B,  M_r z = theta A_r z,  X <- Y Z
/// ```
///
/// needs M definite nowhere: it is A that normalises, and no product with A is formed (B is
/// M X, so A's huge entries on a fine mesh cost no digits). The iteration converges to the
/// roots of largest magnitude, negative ones included: root j at the rate
/// |theta_(q+1)| / |theta_j| per iteration, so the few negative roots of disks with
/// I_p > I_d take places in the q = max(2p, p + 8) vectors without slowing the wanted ones.
/// A root's change is |A^-1 M x_j - theta_j x_j|_A / |theta_j|, the same measure as
/// [`lowest_modes`]'s, with the same test of convergence.
///
/// # Errors
/// `not_definite()` when A is not positive definite; [`Error::NotConverged`] when the
/// iteration does not converge ([`converged`]) in [`MAX_ITERATIONS`].
pub(crate) fn largest_roots(
    mass: &Band,
    stiffness: &Band,
    count: usize,
    not_definite: impl FnOnce() -> Error,
) -> Result<Vec<f64>> {
    let n = stiffness.size();
    let p = count.min(n);
    let q = (2 * p).max(p + 8).min(n);
    let factors = match BandLu::new(stiffness) {
        Some(lu) if lu.pivots_positive() => lu,
        _ => return Err(not_definite()),
    };
    let mut padded = {
        let (before, after) = factors.padding();
        vec![0.0; before + n + after]
    };
    let mut x = starting_vectors(n, q);
    // A X, and the Ritz values descending, once a Rayleigh-Ritz step has made them.
    let mut ritz: Option<(Mat<f64>, Vec<f64>)> = None;
    let mut previous_wanted: Vec<f64> = Vec::new();
    let mut largest_change = f64::INFINITY;
    for iteration in 0..=MAX_ITERATIONS {
        let mx = mass.times(&x);
        let y = solve(&factors, &mx, &mut padded);
        if let Some((ax, theta)) = &ritz {
            let wanted: Vec<usize> = (0..p).filter(|&j| theta[j] > 0.0).collect();
            let previous = largest_change;
            largest_change = wanted
                .iter()
                .map(|&j| {
                    root_change(
                        theta[j],
                        y.col_as_slice(j),
                        x.col_as_slice(j),
                        mx.col_as_slice(j),
                        ax.col_as_slice(j),
                    )
                })
                .fold(0.0, f64::max);
            let roots: Vec<f64> = wanted.iter().map(|&j| theta[j]).collect();
            if converged(largest_change, previous, &roots, &previous_wanted) {
                return Ok(roots);
            }
            previous_wanted = roots;
        }
        if iteration == MAX_ITERATIONS {
            break;
        }
        let (mut y, mut b) = (y, mx);
        orthonormalise(&mut y, &mut b, None);
        let a_r = symmetric(&(y.transpose() * &b));
        let m_r = symmetric(&mass.project(&y));
        // Ascending from the dense solver; the wanted roots are the largest, so reversed.
        let (values, z) = crate::modal::symmetric_modes(&m_r, &a_r, q)?;
        let z = Mat::from_fn(q, q, |i, j| z[(i, q - 1 - j)]);
        x = &y * &z;
        ritz = Some((&b * &z, values.into_iter().rev().collect()));
    }
    Err(Error::not_converged(
        "subspace iteration",
        Some(MAX_ITERATIONS),
        Some(largest_change),
        format!(
            "the largest {p} roots did not converge in {MAX_ITERATIONS} iterations of subspace \
             iteration (the largest change of a root's vector in the last one was \
             {largest_change:.2e} of the root, the tolerance {TOLERANCE:.0e}): the model has \
             many modes of nearly equal frequency; ask for fewer modes"
        ),
    ))
}

/// |s|_A / |theta| for s = y - theta x, y = A^-1 M x: how far one inverse iteration moves the
/// A-normalised Ritz vector x of root theta, relative to the root. A s = M x - theta A x
/// comes from the products at hand, not from A.
fn root_change(theta: f64, y: &[f64], x: &[f64], mx: &[f64], ax: &[f64]) -> f64 {
    let s: Vec<f64> = y.iter().zip(x).map(|(y, x)| y - theta * x).collect();
    let a_s: Vec<f64> = mx.iter().zip(ax).map(|(m, a)| m - theta * a).collect();
    crate::linalg::dot_in_order(&s, &a_s).max(0.0).sqrt() / theta.abs()
}

/// Tells `progress` how far the iteration for `p` modes has got after `iteration`
/// iterations: the change falls geometrically, so its way from the `first` change to
/// [`TOLERANCE`] on a log scale paces the time left (a few seconds for the first modes of a
/// 10,000-element rotor, minutes for 200 of them).
fn told(
    progress: Option<&Progress>,
    p: usize,
    iteration: usize,
    first: f64,
    change: f64,
) -> Result<()> {
    let share = (first / change).ln() / (first / TOLERANCE).ln();
    let done = if share.is_nan() {
        0.0
    } else {
        share.clamp(0.0, 1.0)
    };
    let message =
        || format!("{p} modes, iteration {iteration}, change {change:.1e} (to {TOLERANCE:.0e})");
    match tell(progress, done, 1.0, message) {
        ControlFlow::Continue(()) => Ok(()),
        ControlFlow::Break(()) => Err(Error::Interrupted(format!(
            "the lowest {p} modes were stopped after {iteration} iterations: nothing was kept"
        ))),
    }
}

/// Relative precision of [`largest_eigenvalue`]: far below what a stable step is quoted to,
/// and some thirty bisections from the first bracket.
const LARGEST_TOLERANCE: f64 = 1e-12;

/// The largest eigenvalue of K v = lambda M v (K's symmetric part, M positive definite), by
/// bisection on Sylvester's law of inertia: sigma M - K is positive definite (every pivot of
/// its band factors positive) exactly when sigma lies above every eigenvalue. The bracket
/// starts from max K_ii / M_ii, a Rayleigh quotient and so at most lambda_max, doubled until
/// it is above. Each test is one band factorisation, linear in the DOF count; the dense
/// solver finds the same value to round-off.
///
/// # Errors
/// [`Error::Singular`] when M is not positive definite.
pub(crate) fn largest_eigenvalue(stiffness: &Band, mass: &Band) -> Result<f64> {
    if !BandLu::new(mass).is_some_and(|lu| lu.pivots_positive()) {
        return Err(super::undamped::mass_not_definite());
    }
    let n = mass.size();
    let (kl, ku) = stiffness.widths();
    let (ml, mu) = mass.widths();
    let w = kl.max(ku).max(ml).max(mu);
    let above = |sigma: f64| {
        let a = Band::from_fn(n, (w, w), |i, j| {
            sigma * mass.get(i, j) - 0.5 * (stiffness.get(i, j) + stiffness.get(j, i))
        });
        BandLu::new(&a).is_some_and(|lu| lu.pivots_positive())
    };
    let mut low = (0..n)
        .map(|i| stiffness.get(i, i) / mass.get(i, i))
        .fold(0.0, f64::max);
    if low == 0.0 {
        // No positive diagonal stiffness: every eigenvalue is at most 0.
        return Ok(0.0);
    }
    let mut high = 2.0 * low;
    while !above(high) {
        (low, high) = (high, 2.0 * high);
        if !high.is_finite() {
            return Err(super::undamped::mass_not_definite());
        }
    }
    while high - low > LARGEST_TOLERANCE * high {
        let middle = 0.5 * (low + high);
        if above(middle) {
            high = middle;
        } else {
            low = middle;
        }
    }
    Ok(high)
}

/// The factors of A = K_sym - sigma M, after checking that M and A are positive definite.
fn factorise(
    stiffness: &Band,
    mass: &Band,
    shift: f64,
    below_shift: impl FnOnce() -> Error,
) -> Result<BandLu> {
    let mass_definite = BandLu::new(mass).is_some_and(|lu| lu.pivots_positive());
    if !mass_definite {
        return Err(super::undamped::mass_not_definite());
    }
    let (kl, ku) = stiffness.widths();
    let (ml, mu) = mass.widths();
    let w = kl.max(ku).max(ml).max(mu);
    let a = Band::from_fn(mass.size(), (w, w), |i, j| {
        0.5 * (stiffness.get(i, j) + stiffness.get(j, i)) - shift * mass.get(i, j)
    });
    match BandLu::new(&a) {
        Some(lu) if lu.pivots_positive() => Ok(lu),
        _ => Err(below_shift()),
    }
}

/// Reproducible start vectors with a component along every mode: entries spread over
/// [-1, 1) by a fixed integer hash (splitmix64), so results never depend on a seed.
fn starting_vectors(n: usize, q: usize) -> Mat<f64> {
    Mat::from_fn(n, q, |i, j| {
        let mut z = ((j * n + i) as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    })
}

/// A^-1 B, column by column.
fn solve(factors: &BandLu, b: &Mat<f64>, padded: &mut [f64]) -> Mat<f64> {
    let n = b.nrows();
    let start = factors.padding().0;
    let mut out = Mat::<f64>::zeros(n, b.ncols());
    for j in 0..b.ncols() {
        padded[start..start + n].copy_from_slice(b.col_as_slice(j));
        factors.solve_padded(padded);
        out.col_as_slice_mut(j)
            .copy_from_slice(&padded[start..start + n]);
    }
    out
}

/// |v|_M = sqrt(v^T M v).
fn mass_norm(mass: &Band, v: &[f64]) -> f64 {
    let mut mv = vec![0.0; v.len()];
    mass.mul_add(v, &mut mv);
    crate::linalg::dot_in_order(v, &mv).max(0.0).sqrt()
}

/// Y T with columns orthonormal in the inner product of a positive definite G, given
/// `image` = G Y (modified Gram-Schmidt, twice, as one pass loses orthogonality in proportion
/// to Y's condition). The same column operations keep `image` = G (Y T), and `tracked`, a
/// product B = A Y, = A (Y T).
fn orthonormalise(y: &mut Mat<f64>, image: &mut Mat<f64>, mut tracked: Option<&mut Mat<f64>>) {
    // Column j -= r column k.
    fn subtract(m: &mut Mat<f64>, j: usize, k: usize, r: f64) {
        let (left, right) = m.as_mut().split_at_col_mut(j);
        let (target, source) = (right.col_mut(0), left.col(k));
        for (t, s) in target.iter_mut().zip(source.iter()) {
            *t -= r * s;
        }
    }
    fn scale(m: &mut Mat<f64>, j: usize, norm: f64) {
        m.col_as_slice_mut(j).iter_mut().for_each(|v| *v /= norm);
    }
    for j in 0..y.ncols() {
        for _ in 0..2 {
            for k in 0..j {
                let r = crate::linalg::dot_in_order(image.col_as_slice(k), y.col_as_slice(j));
                subtract(y, j, k, r);
                if let Some(b) = tracked.as_deref_mut() {
                    subtract(b, j, k, r);
                }
                subtract(image, j, k, r);
            }
        }
        let norm = crate::linalg::dot_in_order(y.col_as_slice(j), image.col_as_slice(j))
            .max(0.0)
            .sqrt();
        if norm > 0.0 {
            scale(y, j, norm);
            if let Some(b) = tracked.as_deref_mut() {
                scale(b, j, norm);
            }
            scale(image, j, norm);
        }
    }
}

/// |mu y - x|_M: how far one inverse iteration moves the M-normalised Ritz vector x.
fn change(mass: &Band, mu: f64, y: &[f64], x: &[f64]) -> f64 {
    let r: Vec<f64> = y.iter().zip(x).map(|(y, x)| mu * y - x).collect();
    mass_norm(mass, &r)
}

/// (A + A^T) / 2: the Rayleigh-Ritz matrices are symmetric but for round-off.
fn symmetric(a: &Mat<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::{assemble_banded, Bearings};
    use crate::model::Model;

    /// The reference rotor's bands at 160 elements (644 DOFs): small enough for the dense
    /// solver, which gives every root to compare with.
    fn bands() -> (Band, Band) {
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None)
            .unwrap()
            .remeshed(&[160])
            .unwrap();
        let s = assemble_banded(&model, Bearings::Linearised);
        (s.stiffness, s.mass)
    }

    #[test]
    fn the_largest_eigenvalue_by_inertia_equals_the_dense_one() {
        let (k, m) = bands();
        let (all, _) =
            crate::modal::symmetric_modes(&k.to_dense(), &m.to_dense(), m.size()).unwrap();
        let dense = all[all.len() - 1];
        let bisected = largest_eigenvalue(&k, &m).unwrap();
        // The dense solver's round-off is eps lambda_max; the bisection stops at 1e-12.
        assert!(
            (bisected / dense - 1.0).abs() < 1e-10,
            "{bisected} vs {dense}"
        );
    }
}
