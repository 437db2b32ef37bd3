//! A second-order system ready to march in time, in the integrator's coordinates:
//!
//! ```text
//! M q'' + (C + Omega(t) G) q' + K q = F_0 + Re(f (Omega^2 - i Omega') e^{i phi(t)}) + sum F_nl
//! ```
//!
//! F_0 is constant (gravity), f the unbalance phasor per Omega^2 (see
//! [`crate::fe::unbalance_force`]); the Omega' term is the tangential force of an unbalance
//! on a shaft that speeds up. The gyroscopic effect of angular acceleration (a stiffness
//! proportional to Omega') is neglected, as is usual for run-ups.

use faer::traits::pulp::Arch;
use faer::Mat;

use crate::error::{Error, Result};
use crate::force::{Kinematics, NonlinearForce};

/// Spin speed over time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpeedProfile {
    /// Constant speed, rad/s.
    Constant(f64),
    /// Linear ramp from `from` to `to` (rad/s) over `duration` (s), then constant.
    Ramp { from: f64, to: f64, duration: f64 },
}

impl SpeedProfile {
    /// Speed, angle and acceleration at time t.
    pub fn at(&self, t: f64) -> (Kinematics, f64) {
        match *self {
            SpeedProfile::Constant(w) => (
                Kinematics {
                    time: t,
                    speed: w,
                    angle: w * t,
                },
                0.0,
            ),
            SpeedProfile::Ramp { from, to, duration } => {
                let rate = (to - from) / duration;
                if t <= duration {
                    let k = Kinematics {
                        time: t,
                        speed: from + rate * t,
                        angle: from * t + 0.5 * rate * t * t,
                    };
                    (k, rate)
                } else {
                    let end = from * duration + 0.5 * rate * duration * duration;
                    (
                        Kinematics {
                            time: t,
                            speed: to,
                            angle: end + to * (t - duration),
                        },
                        0.0,
                    )
                }
            }
        }
    }

    /// Largest speed, rad/s.
    pub fn max_speed(&self) -> f64 {
        match *self {
            SpeedProfile::Constant(w) => w.abs(),
            SpeedProfile::Ramp { from, to, .. } => from.abs().max(to.abs()),
        }
    }

    /// True for a constant speed.
    pub fn is_constant(&self) -> bool {
        matches!(self, SpeedProfile::Constant(_))
    }
}

/// The system to integrate.
pub struct TimeProblem {
    /// Mass matrix.
    pub mass: Mat<f64>,
    /// Stiffness matrix (without the nonlinear forces).
    pub stiffness: Mat<f64>,
    /// Damping matrix.
    pub damping: Mat<f64>,
    /// Gyroscopic matrix (times the spin speed).
    pub gyroscopic: Mat<f64>,
    /// Constant force (gravity).
    pub constant_force: Vec<f64>,
    /// Real part of the unbalance phasor per Omega^2.
    pub unbalance_re: Vec<f64>,
    /// Imaginary part of the unbalance phasor per Omega^2.
    pub unbalance_im: Vec<f64>,
    /// Nonlinear forces.
    pub nonlinear: Vec<Box<dyn NonlinearForce>>,
    /// Spin speed over time.
    pub speed: SpeedProfile,
}

impl TimeProblem {
    /// The acceleration M^-1 (F - (C + Omega G) v - K q) under the total force `force`
    /// (external and nonlinear), used to start the integrators.
    pub(crate) fn acceleration(&self, q: &[f64], v: &[f64], force: &[f64], speed: f64) -> Vec<f64> {
        let n = self.size();
        let mut rhs = Mat::<f64>::from_fn(n, 1, |i, _| {
            force[i]
                - (0..n)
                    .map(|j| {
                        self.stiffness[(i, j)] * q[j]
                            + (self.damping[(i, j)] + speed * self.gyroscopic[(i, j)]) * v[j]
                    })
                    .sum::<f64>()
        });
        faer::linalg::solvers::Solve::solve_in_place(&self.mass.partial_piv_lu(), rhs.as_mut());
        (0..n).map(|i| rhs[(i, 0)]).collect()
    }

    /// Number of coordinates.
    pub fn size(&self) -> usize {
        self.mass.nrows()
    }

    /// Checks sizes and the nonlinear forces' coordinates.
    pub fn check(&self) -> Result<()> {
        let n = self.size();
        let square = |m: &Mat<f64>| m.nrows() == n && m.ncols() == n;
        if !(square(&self.stiffness) && square(&self.damping) && square(&self.gyroscopic))
            || self.constant_force.len() != n
            || self.unbalance_re.len() != n
            || self.unbalance_im.len() != n
        {
            return Err(Error::InvalidOption(
                "time problem matrices and vectors differ in size".into(),
            ));
        }
        for f in &self.nonlinear {
            if let Some(&d) = f.dofs().iter().find(|&&d| d >= n) {
                return Err(Error::InvalidOption(format!(
                    "{} acts on coordinate {d} of {n}",
                    f.name()
                )));
            }
        }
        Ok(())
    }

    /// The spin kinematics at time t and the coefficients [c_re, c_im] that give the
    /// unbalance force as c_re u_re + c_im u_im (u = `unbalance_re`, `unbalance_im`):
    ///
    /// ```text
    /// Re(f (w^2 - i w') e^{i phi}) = (w^2 cos phi + w' sin phi) u_re + (-w^2 sin phi + w' cos phi) u_im
    /// ```
    ///
    /// The one definition of the time dependence of the linear force: integrators that keep
    /// products with u_re and u_im precomputed scale them by these coefficients.
    pub fn unbalance_coefficients(&self, t: f64) -> (Kinematics, [f64; 2]) {
        let (k, accel) = self.speed.at(t);
        let (s, c) = k.angle.sin_cos();
        let w2 = k.speed * k.speed;
        (k, [w2 * c + accel * s, accel * c - w2 * s])
    }

    /// Linear external force at time t (gravity and unbalance) into `out`.
    pub fn external_force(&self, t: f64, out: &mut [f64]) -> Kinematics {
        let (k, [c_re, c_im]) = self.unbalance_coefficients(t);
        for i in 0..out.len() {
            out[i] =
                self.constant_force[i] + c_re * self.unbalance_re[i] + c_im * self.unbalance_im[i];
        }
        k
    }

    /// The coordinates some nonlinear force acts on, ascending and without repeats.
    pub fn nonlinear_dofs(&self) -> Vec<usize> {
        let mut dofs: Vec<usize> = self
            .nonlinear
            .iter()
            .flat_map(|f| f.dofs().iter().copied())
            .collect();
        dofs.sort_unstable();
        dofs.dedup();
        dofs
    }

    /// Adds the nonlinear forces at (q, v) into `out`; `scratch_*` hold one force's values.
    pub fn add_nonlinear(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
        scratch: &mut NlScratch,
    ) {
        for f in self.nonlinear.iter_mut() {
            let m = scratch.gather(f.dofs(), q, v);
            f.force(at, &scratch.q[..m], &scratch.v[..m], &mut scratch.f[..m]);
            for a in 0..m {
                out[scratch.idx[a]] += scratch.f[a];
            }
        }
    }

    /// Total tangent stiffness bound of the nonlinear forces, as a dense matrix.
    pub fn nonlinear_stiffness_bound(&self) -> Mat<f64> {
        let n = self.size();
        let mut k = Mat::<f64>::zeros(n, n);
        for f in &self.nonlinear {
            let dofs = f.dofs();
            let b = f.stiffness_bound();
            let m = dofs.len();
            for a in 0..m {
                for c in 0..m {
                    k[(dofs[a], dofs[c])] += b[a * m + c];
                }
            }
        }
        k
    }

    /// Adds the nonlinear forces' tangent stiffness (-dF/dq) and damping (-dF/dv) at (q, v).
    pub fn add_nonlinear_tangent(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        kt: &mut Mat<f64>,
        ct: &mut Mat<f64>,
        scratch: &mut NlScratch,
    ) {
        for f in self.nonlinear.iter_mut() {
            let m = scratch.gather(f.dofs(), q, v);
            f.jacobian(
                at,
                &scratch.q[..m],
                &scratch.v[..m],
                &mut scratch.jq[..m * m],
                &mut scratch.jv[..m * m],
            );
            for a in 0..m {
                for c in 0..m {
                    let (i, j) = (scratch.idx[a], scratch.idx[c]);
                    kt[(i, j)] -= scratch.jq[a * m + c];
                    ct[(i, j)] -= scratch.jv[a * m + c];
                }
            }
        }
    }

    /// Work buffers sized for the largest nonlinear force.
    pub fn scratch(&self) -> NlScratch {
        let m = self
            .nonlinear
            .iter()
            .map(|f| f.dofs().len())
            .max()
            .unwrap_or(0);
        NlScratch {
            idx: vec![0; m],
            q: vec![0.0; m],
            v: vec![0.0; m],
            f: vec![0.0; m],
            jq: vec![0.0; m * m],
            jv: vec![0.0; m * m],
        }
    }
}

/// Work buffers for evaluating nonlinear forces without allocating.
#[derive(Debug, Clone)]
pub struct NlScratch {
    idx: Vec<usize>,
    q: Vec<f64>,
    v: Vec<f64>,
    f: Vec<f64>,
    jq: Vec<f64>,
    jv: Vec<f64>,
}

impl NlScratch {
    /// Copies a force's coordinates and their displacements and velocities; returns the count.
    fn gather(&mut self, dofs: &[usize], q: &[f64], v: &[f64]) -> usize {
        for (a, &d) in dofs.iter().enumerate() {
            self.idx[a] = d;
            self.q[a] = q[d];
            self.v[a] = v[d];
        }
        dofs.len()
    }
}

/// A dense row-major matrix for the small products of the time-step loop, where a plain
/// loop over contiguous rows vectorises and has no call overhead.
#[derive(Debug, Clone)]
pub(crate) struct Dense {
    pub cols: usize,
    pub data: Vec<f64>,
}

impl Dense {
    pub fn from_mat(m: &Mat<f64>) -> Dense {
        let (rows, cols) = (m.nrows(), m.ncols());
        let mut data = Vec::with_capacity(rows * cols);
        for i in 0..rows {
            for j in 0..cols {
                data.push(m[(i, j)]);
            }
        }
        Dense { cols, data }
    }

    /// out += self * x.
    #[inline]
    pub fn mul_add(&self, x: &[f64], out: &mut [f64]) {
        for (row, o) in self.data.chunks_exact(self.cols).zip(out.iter_mut()) {
            *o += row.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
        }
    }
}

// Kernels of the central difference's step: products and solves that vectorise and whose
// results do not depend on the vector width. Each output element is computed in an order
// fixed by the source (the compiler may not reassociate floating-point sums), and vector
// lanes only hold different elements or different fixed partial sums. They allocate nothing.

/// Runs `f` compiled for the widest vector instructions the processor has (AVX2 and FMA on
/// most x86-64, chosen at run time; the default build targets baseline x86-64, two doubles
/// per instruction). The kernels below are `inline(always)` so that they are compiled
/// inside it. Rust never fuses a multiply and an add unasked, so results are the same on
/// every processor.
#[inline(always)]
pub(crate) fn vectorised<R>(f: impl FnOnce() -> R) -> R {
    Arch::new().dispatch(f)
}

/// a . b with eight partial sums, so the loop vectorises and pipelines: a single running sum
/// is a chain of dependent additions. Rows shorter than eight are summed in order.
#[inline(always)]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    debug_assert_eq!(a.len(), b.len());
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: f64 = a8
        .remainder()
        .iter()
        .zip(b8.remainder())
        .map(|(x, y)| x * y)
        .sum();
    let mut acc = [0.0; 8];
    for (x, y) in a8.zip(b8) {
        for k in 0..8 {
            acc[k] += x[k] * y[k];
        }
    }
    let pairs = [
        acc[0] + acc[4],
        acc[1] + acc[5],
        acc[2] + acc[6],
        acc[3] + acc[7],
    ];
    ((pairs[0] + pairs[2]) + (pairs[1] + pairs[3])) + tail
}

/// Solves the k x k row-major system in place by Gaussian elimination with partial
/// pivoting; b becomes the solution. A singular system leaves non-finite values, for the caller to
/// report.
pub(crate) fn solve_small(a: &mut [f64], b: &mut [f64]) {
    let k = b.len();
    for col in 0..k {
        let pivot = (col..k)
            .max_by(|&r, &s| a[r * k + col].abs().total_cmp(&a[s * k + col].abs()))
            .unwrap_or(col);
        if pivot != col {
            for j in 0..k {
                a.swap(col * k + j, pivot * k + j);
            }
            b.swap(col, pivot);
        }
        for r in col + 1..k {
            let m = a[r * k + col] / a[col * k + col];
            for j in col..k {
                a[r * k + j] -= m * a[col * k + j];
            }
            b[r] -= m * b[col];
        }
    }
    for col in (0..k).rev() {
        let s: f64 = (col + 1..k).map(|j| a[col * k + j] * b[j]).sum();
        b[col] = (b[col] - s) / a[col * k + col];
    }
}

/// y += alpha x.
#[inline(always)]
pub(crate) fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    debug_assert_eq!(x.len(), y.len());
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}

/// A dense matrix stored by columns. Its product is a sum of scaled columns, four at a time,
/// so the loop runs along contiguous columns, vectorises across rows and needs no
/// horizontal sums (which a row-by-row dot product of short rows spends much of its time
/// on).
#[derive(Debug, Clone)]
pub(crate) struct Columns {
    rows: usize,
    data: Vec<f64>,
}

impl Columns {
    pub fn from_fn(rows: usize, cols: usize, f: impl Fn(usize, usize) -> f64) -> Columns {
        let data = (0..cols)
            .flat_map(|j| (0..rows).map(move |i| (i, j)))
            .map(|(i, j)| f(i, j))
            .collect();
        Columns { rows, data }
    }

    /// Column j.
    #[inline(always)]
    pub fn column(&self, j: usize) -> &[f64] {
        &self.data[j * self.rows..(j + 1) * self.rows]
    }

    /// out += self * x.
    #[inline(always)]
    pub fn mul_add(&self, x: &[f64], out: &mut [f64]) {
        let n = self.rows;
        let out = &mut out[..n];
        let blocks = self.data.chunks_exact(4 * n);
        let rest = blocks.remainder();
        let x4 = x.chunks_exact(4);
        let x_rest = x4.remainder();
        for (block, xs) in blocks.zip(x4) {
            let (c0, block) = block.split_at(n);
            let (c1, block) = block.split_at(n);
            let (c2, c3) = block.split_at(n);
            for i in 0..n {
                out[i] += (xs[0] * c0[i] + xs[1] * c1[i]) + (xs[2] * c2[i] + xs[3] * c3[i]);
            }
        }
        for (column, &xj) in rest.chunks_exact(n).zip(x_rest) {
            axpy(xj, column, out);
        }
    }
}

/// The lower and upper bandwidths of a square matrix: the largest i - j and j - i of its
/// nonzero entries.
pub(crate) fn bandwidths(m: &Mat<f64>) -> (usize, usize) {
    let n = m.nrows();
    let (mut lower, mut upper) = (0, 0);
    for j in 0..n {
        for i in 0..n {
            if m[(i, j)] != 0.0 {
                lower = lower.max(i.saturating_sub(j));
                upper = upper.max(j.saturating_sub(i));
            }
        }
    }
    (lower, upper)
}

/// A square band matrix with `lower` sub- and `upper` super-diagonals, stored by diagonals:
/// the product adds one diagonal at a time along contiguous memory, which vectorises,
/// where rows of a band are too short to.
#[derive(Debug, Clone)]
pub(crate) struct Band {
    n: usize,
    lower: usize,
    upper: usize,
    /// Diagonal k (offset d = k - lower) holds a[i, i + d] at k * n + i; zero where i + d
    /// falls outside the matrix.
    diagonals: Vec<f64>,
}

impl Band {
    /// The band of `f(i, j)`; entries outside it are taken as zero.
    pub fn from_fn(
        n: usize,
        (lower, upper): (usize, usize),
        f: impl Fn(usize, usize) -> f64,
    ) -> Band {
        let mut diagonals = vec![0.0; n * (lower + upper + 1)];
        for k in 0..=lower + upper {
            for i in Band::rows(n, lower, k) {
                diagonals[k * n + i] = f(i, i + k - lower);
            }
        }
        Band {
            n,
            lower,
            upper,
            diagonals,
        }
    }

    /// The rows where diagonal k lies inside an n by n matrix (none if it lies outside).
    #[inline(always)]
    fn rows(n: usize, lower: usize, k: usize) -> std::ops::Range<usize> {
        let start = lower.saturating_sub(k);
        let end = n.saturating_sub(k.saturating_sub(lower));
        if start < end {
            start..end
        } else {
            0..0
        }
    }

    /// out += self * x.
    #[inline(always)]
    pub fn mul_add(&self, x: &[f64], out: &mut [f64]) {
        let n = self.n;
        for k in 0..=self.lower + self.upper {
            let rows = Band::rows(n, self.lower, k);
            if rows.is_empty() {
                continue;
            }
            let columns = rows.start + k - self.lower..rows.end + k - self.lower;
            let diagonal = &self.diagonals[k * n..(k + 1) * n][rows.clone()];
            for ((o, a), xj) in out[rows].iter_mut().zip(diagonal).zip(&x[columns]) {
                *o += a * xj;
            }
        }
    }

    /// Entry (i, j), zero outside the band.
    fn get(&self, i: usize, j: usize) -> f64 {
        if j + self.lower < i || i + self.upper < j {
            0.0
        } else {
            self.diagonals[(j + self.lower - i) * self.n + i]
        }
    }
}

/// LU factors of a band matrix without row swaps, so that L and U keep the band and both
/// triangular solves run row by row. Without swaps the factorisation is reliable when the
/// matrix's symmetric part is positive definite and its skew part is small against it
/// (Golub & Van Loan, Matrix Computations, "unsymmetric positive definite systems"); the
/// caller checks that, see [`BandLu::pivots_positive`].
#[derive(Debug, Clone)]
pub(crate) struct BandLu {
    lower: usize,
    upper: usize,
    /// Row i of L left of the diagonal, L[i, i - lower..i], at i * lower (zero before
    /// column 0).
    l: Vec<f64>,
    /// Row i of U right of the diagonal, divided by the diagonal: U[i, i + 1..=i + upper] /
    /// U[i, i] at i * upper (zero past the last column).
    u: Vec<f64>,
    /// 1 / U[i, i].
    inverse_diagonal: Vec<f64>,
}

impl BandLu {
    /// Factorises `a`; `None` when a pivot is zero or not finite.
    pub fn new(a: &Band) -> Option<BandLu> {
        let (n, kl, ku) = (a.n, a.lower, a.upper);
        let mut l = vec![0.0; n * kl];
        let mut u = vec![0.0; n * ku];
        let mut inverse_diagonal = vec![0.0; n];
        // Row i of the work band covers columns i - kl..=i + ku; eliminated entries hold L.
        let width = kl + ku + 1;
        let at = |i: usize, j: usize| i * width + j + kl - i;
        let mut w = vec![0.0; n * width];
        for i in 0..n {
            for j in i.saturating_sub(kl)..(i + ku + 1).min(n) {
                w[at(i, j)] = a.get(i, j);
            }
        }
        for k in 0..n {
            let pivot = w[at(k, k)];
            if !(pivot.is_finite() && pivot != 0.0) {
                return None;
            }
            let below = k + 1..(k + kl + 1).min(n);
            let right = k + 1..(k + ku + 1).min(n);
            for i in below {
                let m = w[at(i, k)] / pivot;
                w[at(i, k)] = m;
                for j in right.clone() {
                    w[at(i, j)] -= m * w[at(k, j)];
                }
            }
            inverse_diagonal[k] = 1.0 / pivot;
            for j in right {
                u[k * ku + j - k - 1] = w[at(k, j)] / pivot;
            }
            for j in k.saturating_sub(kl)..k {
                l[k * kl + j + kl - k] = w[at(k, j)];
            }
        }
        Some(BandLu {
            lower: kl,
            upper: ku,
            l,
            u,
            inverse_diagonal,
        })
    }

    /// True when every pivot is positive: for a symmetric matrix, exactly when it is
    /// positive definite (its leading minors, the products of the pivots, are positive).
    pub fn pivots_positive(&self) -> bool {
        self.inverse_diagonal.iter().all(|&d| d > 0.0)
    }

    /// Zeros needed before and after the right-hand side by [`BandLu::solve_padded`].
    pub fn padding(&self) -> (usize, usize) {
        (self.lower, self.upper)
    }

    /// Solves A x = b in place, b in `padded` after [`BandLu::padding`]'s zeros before it
    /// and followed by its zeros after (which stay zero): padding makes every row of L and U
    /// the same length, so the loops clip nothing. Each row's sum leaves the entry just
    /// solved for last, so the rest of the row is summed while that entry is still being
    /// computed: the chain from one row to the next is one multiplication and one
    /// subtraction.
    #[inline(always)]
    pub fn solve_padded(&self, padded: &mut [f64]) {
        let n = self.inverse_diagonal.len();
        let (kl, ku) = (self.lower, self.upper);
        assert_eq!(padded.len(), kl + n + ku);
        if let Some(last) = kl.checked_sub(1) {
            // Row i of L covers padded[i..i + kl]; b_i is at padded[kl + i].
            for (i, row) in self.l.chunks_exact(kl).enumerate() {
                let s = dot(&row[..last], &padded[i..i + last]);
                padded[kl + i] = (padded[kl + i] - s) - row[last] * padded[kl + i - 1];
            }
        }
        for i in (0..n).rev() {
            let at = kl + i;
            let scaled = padded[at] * self.inverse_diagonal[i];
            padded[at] = match self.u[i * ku..(i + 1) * ku].split_first() {
                Some((near, far)) => {
                    let s = dot(far, &padded[at + 2..at + 1 + ku]);
                    (scaled - s) - near * padded[at + 1]
                }
                None => scaled,
            };
        }
    }
}

/// A square matrix factorised for repeated solves: a band LU without row swaps when a band
/// is given and that is safe, else the dense inverse from a pivoting LU.
pub(crate) enum Factors {
    Banded {
        lu: BandLu,
        /// The right-hand side with the zeros around it that the solve needs.
        padded: Vec<f64>,
    },
    Inverse(Columns),
}

impl Factors {
    /// Banded with bandwidths `band` when given and the matrix's symmetric part is positive
    /// definite, which makes the factorisation without row swaps safe (see [`BandLu`]);
    /// otherwise the dense inverse. `None` when the matrix is singular.
    pub fn new(band: Option<(usize, usize)>, a: &Mat<f64>) -> Option<Factors> {
        if let Some(lu) = band.and_then(|widths| banded_lu(a, widths)) {
            let (before, after) = lu.padding();
            let padded = vec![0.0; before + a.nrows() + after];
            return Some(Factors::Banded { lu, padded });
        }
        let n = a.nrows();
        let mut inverse = Mat::<f64>::identity(n, n);
        faer::linalg::solvers::Solve::solve_in_place(&a.partial_piv_lu(), inverse.as_mut());
        if inverse.col_iter().any(|c| c.iter().any(|v| !v.is_finite())) {
            return None;
        }
        Some(Factors::Inverse(Columns::from_fn(n, n, |i, j| {
            inverse[(i, j)]
        })))
    }

    /// out = A^-1 rhs.
    #[inline(always)]
    pub fn solve(&mut self, rhs: &[f64], out: &mut [f64]) {
        match self {
            Factors::Banded { lu, padded } => {
                let start = lu.padding().0;
                padded[start..start + rhs.len()].copy_from_slice(rhs);
                lu.solve_padded(padded);
                out.copy_from_slice(&padded[start..start + rhs.len()]);
            }
            Factors::Inverse(inverse) => {
                out.iter_mut().for_each(|x| *x = 0.0);
                inverse.mul_add(rhs, out);
            }
        }
    }
}

/// The band LU of `a` when its symmetric part has positive pivots, else `None`.
fn banded_lu(a: &Mat<f64>, widths: (usize, usize)) -> Option<BandLu> {
    let n = a.nrows();
    let w = widths.0.max(widths.1);
    let symmetric = Band::from_fn(n, (w, w), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    if !BandLu::new(&symmetric)?.pivots_positive() {
        return None;
    }
    BandLu::new(&Band::from_fn(n, widths, |i, j| a[(i, j)]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reproducible, unstructured value for entry (i, j).
    fn entry(i: usize, j: usize) -> f64 {
        ((i * 31 + j * 17) as f64 * 0.618).sin()
    }

    /// A band matrix (lower 3, upper 2) whose symmetric part is positive definite, as dense.
    fn banded(n: usize) -> Mat<f64> {
        Mat::from_fn(n, n, |i, j| {
            if i == j {
                10.0 + entry(i, i).abs()
            } else if j + 3 >= i && j <= i + 2 {
                entry(i, j)
            } else {
                0.0
            }
        })
    }

    fn dense_product(a: &Mat<f64>, x: &[f64]) -> Vec<f64> {
        (0..a.nrows())
            .map(|i| (0..a.ncols()).map(|j| a[(i, j)] * x[j]).sum())
            .collect()
    }

    fn close(a: &[f64], b: &[f64]) -> f64 {
        let scale = b.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        a.iter()
            .zip(b)
            .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()))
            / scale
    }

    #[test]
    fn unbalance_coefficients_give_the_complex_force() {
        let problem = TimeProblem {
            mass: Mat::identity(2, 2),
            stiffness: Mat::zeros(2, 2),
            damping: Mat::zeros(2, 2),
            gyroscopic: Mat::zeros(2, 2),
            constant_force: vec![1.0, -2.0],
            unbalance_re: vec![0.3, -0.1],
            unbalance_im: vec![0.2, 0.5],
            nonlinear: Vec::new(),
            speed: SpeedProfile::Ramp {
                from: 10.0,
                to: 300.0,
                duration: 2.0,
            },
        };
        let mut out = [0.0; 2];
        for t in [0.0, 0.7, 1.9, 2.5] {
            let (k, accel) = problem.speed.at(t);
            problem.external_force(t, &mut out);
            let spin = num_complex::Complex64::new(k.speed * k.speed, -accel)
                * num_complex::Complex64::from_polar(1.0, k.angle);
            for i in 0..2 {
                let f =
                    num_complex::Complex64::new(problem.unbalance_re[i], problem.unbalance_im[i]);
                let expected = problem.constant_force[i] + (f * spin).re;
                // A few roundings of numbers up to 1e5 (Omega^2).
                assert!((out[i] - expected).abs() < 1e-10 * expected.abs().max(1.0));
            }
        }
    }

    #[test]
    fn band_product_and_lu_match_dense_algebra() {
        for n in [1, 2, 5, 40] {
            let a = banded(n);
            let band = Band::from_fn(n, (3, 2), |i, j| a[(i, j)]);
            let x: Vec<f64> = (0..n).map(|i| entry(i, 7)).collect();
            let mut product = vec![0.0; n];
            band.mul_add(&x, &mut product);
            // The same sums in another order: a few roundings of O(10) terms.
            assert!(close(&product, &dense_product(&a, &x)) < 1e-14);

            let lu = BandLu::new(&band).expect("diagonally dominant");
            let (before, after) = lu.padding();
            let mut padded = vec![0.0; before + n + after];
            padded[before..before + n].copy_from_slice(&product);
            lu.solve_padded(&mut padded);
            let solved = &padded[before..before + n];
            // The matrix is well conditioned (diagonally dominant), so x comes back to a
            // few units of round-off.
            assert!(close(solved, &x) < 1e-13, "n = {n}");
        }
    }

    #[test]
    fn pivots_tell_positive_definite_from_indefinite() {
        let mut a = banded(6);
        let symmetric =
            |a: &Mat<f64>| Band::from_fn(6, (3, 3), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
        assert!(BandLu::new(&symmetric(&a)).unwrap().pivots_positive());
        a[(4, 4)] = -a[(4, 4)];
        assert!(!BandLu::new(&symmetric(&a)).unwrap().pivots_positive());
    }

    #[test]
    fn column_product_matches_dense_algebra_on_every_instruction_set() {
        for (rows, cols) in [(1, 1), (3, 7), (20, 40), (21, 42)] {
            let a = Mat::from_fn(rows, cols, entry);
            let columns = Columns::from_fn(rows, cols, |i, j| a[(i, j)]);
            let x: Vec<f64> = (0..cols).map(|j| entry(j, 3)).collect();
            let (mut plain, mut wide) = (vec![0.5; rows], vec![0.5; rows]);
            columns.mul_add(&x, &mut plain);
            vectorised(|| columns.mul_add(&x, &mut wide));
            // Lanes hold different rows, never parts of one sum: bit for bit the same.
            assert_eq!(plain, wide);
            let expected: Vec<f64> = dense_product(&a, &x).iter().map(|v| v + 0.5).collect();
            assert!(close(&plain, &expected) < 1e-14);
        }
    }
}
