//! Implicit Newmark integration with Newton iterations on the nonlinear forces.
//!
//! HHT-alpha form (Hilber, Hughes & Taylor 1977), alpha in [-1/3, 0], gamma = (1 - 2 alpha)/2,
//! beta = (1 - alpha)^2 / 4; alpha = 0 is the average-acceleration (trapezoidal) rule,
//! unconditionally stable and without numerical damping; alpha < 0 damps the highest
//! frequencies. The balance at step n+1 is
//!
//! ```text
//! M a1 + (1+alpha)(D1 v1 + K q1 - F_nl(q1, v1) - F1) - alpha (D0 v0 + K q0 - F_nl(q0, v0) - F0) = 0
//! a1 = (q1 - q0 - h v0) / (beta h^2) - (1/(2 beta) - 1) a0,   v1 = v0 + h ((1 - gamma) a0 + gamma a1)
//! ```
//!
//! solved for q1 by Newton with the Jacobian J = J0 + (1+alpha)(C_t gamma/(beta h) + K_t),
//! J0 = M/(beta h^2) + (1+alpha)(D gamma/(beta h) + K), D = C + Omega G.
//!
//! J0 depends only on the speed, so it is formed and factorised once per speed (at every
//! step of a speed ramp), banded without row swaps when the matrices are banded and that is
//! safe, else as a dense inverse; the residual's products use the same band or dense
//! row-major kernels as the central difference. The nonlinear tangent K_t, C_t lives on the
//! few coordinates the nonlinear forces act on, so each Newton iteration applies J^-1 by the
//! Sherman-Morrison-Woodbury formula: one solve with J0 and a k x k system for k such
//! coordinates. That is exact Newton with the same Jacobian as a full factorisation, so it
//! converges in the same iterations to the same tolerance, without an n x n factorisation
//! per iteration. Without nonlinear forces the step is linear and J0 its exact matrix: one
//! iteration solves it. At constant speed a linear step allocates nothing.
//!
//! Forces that jump defeat plain Newton: a damped contact that closes adds C times the
//! approach rate at once, and for some predictors the balance then has no root, so the
//! iteration cycles. Each Newton step is therefore shortened by a backtracking line search
//! until |r|^2 falls enough (Armijo), and a step whose iteration still fails is done in two
//! halves, each halved again as needed (the jump's rootless interval shrinks as the step
//! squared), down to h / 4096; the next step starts from h again, and the observer sees
//! the times k h only. J0 is kept per halving depth.

use faer::Mat;

use super::{check_marchable, check_state, MarchOptions, Observer};
use crate::error::{Error, InputError, Result};
use crate::force::Kinematics;
use crate::linalg::{axpy, solve_small, vectorised, Band, Columns, Factors, Layout};
use crate::system::{NlScratch, SpeedProfile, System, TangentBlock};

/// Which member of the Newmark family.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NewmarkScheme {
    /// gamma = 1/2, beta = 1/4.
    AverageAcceleration,
    /// HHT-alpha with the given alpha in [-1/3, 0].
    Hht(f64),
}

impl NewmarkScheme {
    /// Refuses an HHT alpha outside [-1/3, 0], where the scheme is no longer unconditionally
    /// stable and second-order accurate.
    ///
    /// # Errors
    /// [`crate::Error::Input`] naming `hht_alpha`.
    pub fn check(self) -> Result<()> {
        let alpha = self.alpha();
        if (-1.0 / 3.0..=0.0).contains(&alpha) {
            return Ok(());
        }
        Err(
            InputError::field("hht_alpha", format!("{alpha} is outside [-1/3, 0]"))
                .help("e.g. -0.05; 0 is the average-acceleration rule")
                .into(),
        )
    }

    fn alpha(self) -> f64 {
        match self {
            NewmarkScheme::AverageAcceleration => 0.0,
            NewmarkScheme::Hht(a) => a,
        }
    }
}

/// The scheme's constants and the step.
#[derive(Debug, Clone, Copy)]
struct Coefficients {
    alpha: f64,
    gamma: f64,
    beta: f64,
    h: f64,
}

impl Coefficients {
    /// a1 and v1 of a trial q1 (the Newmark relations of the module documentation).
    #[inline(always)]
    fn kinematics(
        &self,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        q1: &[f64],
        a1: &mut [f64],
        v1: &mut [f64],
    ) {
        let Coefficients { gamma, beta, h, .. } = *self;
        for i in 0..q.len() {
            a1[i] = (q1[i] - q[i] - h * v[i]) / (beta * h * h) - (0.5 / beta - 1.0) * a[i];
            v1[i] = v[i] + h * ((1.0 - gamma) * a[i] + gamma * a1[i]);
        }
    }
}

/// How the step's matrices are stored and J0 solved: per row a linear step multiplies
/// 6 n times dense (five products and the inverse), banded it makes five band products
/// and a solve.
fn choose_layout(problem: &System) -> Layout {
    Layout::choose(problem.matrices.all(), 5, 6 * problem.size())
}

/// A matrix of the residual's products, in the layout's fast form.
enum Matrix {
    Banded(Band),
    Dense(Columns),
}

impl Matrix {
    fn new(layout: Layout, n: usize, f: impl Fn(usize, usize) -> f64) -> Matrix {
        match layout {
            Layout::Banded(l, u) => Matrix::Banded(Band::from_fn(n, (l, u), f)),
            Layout::Dense => Matrix::Dense(Columns::from_fn(n, n, f)),
        }
    }

    /// out += self * x.
    #[inline(always)]
    fn mul_add(&self, x: &[f64], out: &mut [f64]) {
        match self {
            Matrix::Banded(b) => b.mul_add(x, out),
            Matrix::Dense(c) => c.mul_add(x, out),
        }
    }
}

/// J0 = M/(beta h^2) + (1+alpha)(D gamma/(beta h) + K) at `speed`.
fn effective_matrix(problem: &System, speed: f64, c: Coefficients) -> Mat<f64> {
    let Coefficients {
        alpha,
        gamma,
        beta,
        h,
    } = c;
    Mat::from_fn(problem.size(), problem.size(), |i, j| {
        problem.matrices.mass[(i, j)] / (beta * h * h)
            + (1.0 + alpha)
                * ((problem.matrices.damping[(i, j)] + speed * problem.matrices.gyroscopic[(i, j)])
                    * gamma
                    / (beta * h)
                    + problem.matrices.stiffness[(i, j)])
    })
}

/// What depends on the speed: D = C + Omega G, J0's factors, and J0^-1 at the nonlinear
/// coordinates for the Woodbury correction.
struct AtSpeed {
    speed: f64,
    damping: Matrix,
    factors: Factors,
    /// Column a is J0^-1 e_{dofs[a]}, at a * n.
    columns: Vec<f64>,
    /// Entry (a, b) is column b at coordinate dofs[a], at a * k + b.
    block: Vec<f64>,
}

impl AtSpeed {
    fn new(
        problem: &System,
        layout: Layout,
        speed: f64,
        c: Coefficients,
        dofs: &[usize],
    ) -> Result<AtSpeed> {
        let n = problem.size();
        let damping = Matrix::new(layout, n, |i, j| {
            problem.matrices.damping[(i, j)] + speed * problem.matrices.gyroscopic[(i, j)]
        });
        let mut factors = Factors::new(layout.band(), &effective_matrix(problem, speed, c))
            .ok_or_else(|| {
                Error::singular(
                    "Newmark matrix",
                    "the Newmark matrix M/(beta h^2) + (1+alpha)(D gamma/(beta h) + K) is \
                     singular"
                        .into(),
                )
            })?;
        let mut columns = vec![0.0; n * dofs.len()];
        let mut unit = vec![0.0; n];
        for (&d, column) in dofs.iter().zip(columns.chunks_exact_mut(n)) {
            unit[d] = 1.0;
            factors.solve(&unit, column);
            unit[d] = 0.0;
        }
        let block = dofs
            .iter()
            .flat_map(|&d| columns.chunks_exact(n).map(move |column| column[d]))
            .collect();
        Ok(AtSpeed {
            speed,
            damping,
            factors,
            columns,
            block,
        })
    }
}

/// The Woodbury correction that turns J0^-1 into J^-1 for a tangent on k coordinates:
/// with X = J0^-1 P (P the unit columns at the coordinates) and T the k x k tangent block,
/// J^-1 r = y - X (I + T P^T X)^-1 T P^T y, y = J0^-1 r. Buffers sized once.
struct Tangent {
    /// K_t and C_t on the nonlinear forces' coordinates (its `dofs` are the P above).
    block: TangentBlock,
    /// T, then the k x k system I + T P^T X, row-major.
    t: Vec<f64>,
    system: Vec<f64>,
    z: Vec<f64>,
}

impl Tangent {
    fn new(block: TangentBlock) -> Tangent {
        let k = block.size();
        Tangent {
            block,
            t: vec![0.0; k * k],
            system: vec![0.0; k * k],
            z: vec![0.0; k],
        }
    }

    /// Turns y = J0^-1 r into J^-1 r, J with the nonlinear tangent at (q1, v1).
    #[allow(clippy::too_many_arguments)]
    fn correct(
        &mut self,
        problem: &mut System,
        at: &Kinematics,
        q1: &[f64],
        v1: &[f64],
        c: Coefficients,
        speed: &AtSpeed,
        scratch: &mut NlScratch,
        y: &mut [f64],
    ) {
        let (k, n) = (self.block.size(), y.len());
        problem.nonlinear_tangent(at, q1, v1, &mut self.block, scratch);
        let damping_factor = c.gamma / (c.beta * c.h);
        for ((t, kt), ct) in self
            .t
            .iter_mut()
            .zip(&self.block.stiffness)
            .zip(&self.block.damping)
        {
            *t = (1.0 + c.alpha) * (ct * damping_factor + kt);
        }
        let dofs = &self.block.dofs;
        for a in 0..k {
            self.z[a] = (0..k).map(|b| self.t[a * k + b] * y[dofs[b]]).sum();
            for b in 0..k {
                let tx: f64 = (0..k)
                    .map(|e| self.t[a * k + e] * speed.block[e * k + b])
                    .sum();
                self.system[a * k + b] = f64::from(u8::from(a == b)) + tx;
            }
        }
        solve_small(&mut self.system, &mut self.z);
        for (column, &z) in speed.columns.chunks_exact(n).zip(&self.z) {
            axpy(-z, column, y);
        }
    }
}

/// Vectors of a step, allocated once.
struct Workspace {
    /// External force at the end of the step.
    force: Vec<f64>,
    /// External force at the start of the step.
    force_prev: Vec<f64>,
    /// Everything in the residual but the unknown's own terms:
    /// r = M a1 + (1+alpha)(D1 v1 + K q1 - F_nl1) - known.
    known: Vec<f64>,
    /// D v + K q at the start of the step.
    linear: Vec<f64>,
    /// Nonlinear forces at the start of the step.
    nl_prev: Vec<f64>,
    residual: Vec<f64>,
    /// Nonlinear forces at the trial end of the step.
    nl: Vec<f64>,
    a1: Vec<f64>,
    v1: Vec<f64>,
    q1: Vec<f64>,
    /// The iterate a line search starts from.
    base: Vec<f64>,
    dq: Vec<f64>,
}

impl Workspace {
    fn new(n: usize) -> Workspace {
        let zeros = || vec![0.0; n];
        Workspace {
            force: zeros(),
            force_prev: zeros(),
            known: zeros(),
            linear: zeros(),
            nl_prev: zeros(),
            residual: zeros(),
            nl: zeros(),
            a1: zeros(),
            v1: zeros(),
            q1: zeros(),
            base: zeros(),
            dq: zeros(),
        }
    }
}

/// out = D v + K q.
#[inline(always)]
fn linear_force(speed: &AtSpeed, stiffness: &Matrix, q: &[f64], v: &[f64], out: &mut [f64]) {
    out.iter_mut().for_each(|x| *x = 0.0);
    speed.damping.mul_add(v, out);
    stiffness.mul_add(q, out);
}

/// Replaces `nl` by the nonlinear forces at (q, v). Only `dofs` are reset: `nl` stays zero
/// elsewhere, so a step touches k entries, not n.
fn nonlinear_force(
    problem: &mut System,
    at: &Kinematics,
    q: &[f64],
    v: &[f64],
    dofs: &[usize],
    nl: &mut [f64],
    scratch: &mut NlScratch,
) {
    dofs.iter().for_each(|&d| nl[d] = 0.0);
    problem.add_nonlinear(at, q, v, nl, scratch);
}

/// Newton iterations per attempt at a step. A smooth step converges in 2 to 5; one that
/// needs more is cycling on a force that jumps (a damped contact closing), and half the
/// step is then cheaper than iterating on.
const NEWTON_ITERATIONS: usize = 30;

/// Armijo's sufficient decrease (Nocedal & Wright, Numerical Optimization, eq. 3.4, with
/// their usual c = 1e-4): a step length lambda along the Newton direction is accepted when
/// |r|^2 falls to (1 - 2 c lambda) of itself, c lambda of what the linearisation promises.
const ARMIJO: f64 = 1e-4;

/// Halvings of the line search's step length before an attempt is given up: below
/// 1/2^8 of the Newton step the direction is no use, and a shorter time step is.
const BACKTRACKS: usize = 8;

/// Halvings of the time step before the march gives up: the shortest sub-step is
/// h / 2^12. A damped contact's force jump leaves an interval of predictors without a root
/// whose width shrinks as the sub-step squared, so a few halvings always find one; twelve
/// (a 4096-fold cut) only fail when the forces themselves are broken.
const MAX_HALVINGS: u32 = 12;

/// How an attempt at a step ended.
enum Attempt {
    Converged,
    /// The Newton iteration failed; the residual's 2-norm where it stopped.
    Failed(f64),
}

/// The scheme's J0 and friends for each sub-step tried: entry d is for h / 2^d, at the
/// speed it was formed at (formed when first needed, again when the speed changes).
struct Levels {
    layout: Layout,
    base: Coefficients,
    at: Vec<Option<AtSpeed>>,
}

impl Levels {
    fn coefficients(&self, depth: u32) -> Coefficients {
        Coefficients {
            h: self.base.h / f64::from(1u32 << depth),
            ..self.base
        }
    }

    /// The matrices of sub-step `depth` at `speed`.
    fn get(
        &mut self,
        problem: &System,
        depth: u32,
        speed: f64,
        dofs: &[usize],
    ) -> Result<&mut AtSpeed> {
        let c = self.coefficients(depth);
        let slot = &mut self.at[depth as usize];
        let current = match slot.take() {
            Some(formed) if formed.speed == speed => formed,
            _ => AtSpeed::new(problem, self.layout, speed, c, dofs)?,
        };
        Ok(slot.insert(current))
    }
}

/// One march: the state at the start of the next step and everything a step needs but
/// the [`Levels`], which the march lends to each step.
struct Stepper<'p> {
    problem: &'p mut System,
    profile: SpeedProfile,
    dofs: Vec<usize>,
    mass: Matrix,
    stiffness: Matrix,
    tangent: Tangent,
    scratch: NlScratch,
    w: Workspace,
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
}

impl Stepper<'_> {
    /// Advances the state from t0 to t1, in one step of sub-step `depth` if its Newton
    /// iteration converges, else in two halves, each again halved as needed: the step
    /// is cut where the forces need it and grows back for the next.
    fn advance(&mut self, levels: &mut Levels, t0: f64, t1: f64, depth: u32) -> Result<()> {
        match self.attempt(levels, t1, depth)? {
            Attempt::Converged => Ok(()),
            Attempt::Failed(_) if depth < MAX_HALVINGS => {
                let middle = 0.5 * (t0 + t1);
                self.advance(levels, t0, middle, depth + 1)?;
                self.advance(levels, middle, t1, depth + 1)
            }
            Attempt::Failed(residual) => {
                let why = if residual.is_finite() {
                    format!(
                        "residual {residual:.3e} N; the forces jump there more than any step \
                         resolves"
                    )
                } else {
                    "the forces are not finite there".to_string()
                };
                Err(Error::not_converged(
                    "Newmark Newton iteration",
                    None,
                    residual.is_finite().then_some(residual),
                    format!(
                        "Newmark's Newton iterations did not converge at t = {t1:.6} s even with \
                     the step cut {} times to {:.3e} s ({why}): check the model's nonlinear \
                     forces (contact parameters), or use the central difference \
                     (--method cd)",
                        1u32 << depth,
                        levels.coefficients(depth).h
                    ),
                ))
            }
        }
    }

    /// One step of sub-step `depth` to t1: Newton on the balance with a backtracking line
    /// search. On convergence the state moves to t1; otherwise it stays where it was.
    fn attempt(&mut self, levels: &mut Levels, t1: f64, depth: u32) -> Result<Attempt> {
        let c = levels.coefficients(depth);
        let at1 = self
            .problem
            .external_force(&self.profile, t1, &mut self.w.force);
        let speed = levels.get(self.problem, depth, at1.speed, &self.dofs)?;
        let Stepper {
            problem,
            dofs,
            mass,
            stiffness,
            tangent,
            scratch,
            w,
            q,
            v,
            a,
            ..
        } = self;
        let (alpha, h, n) = (c.alpha, c.h, q.len());
        let linear = dofs.is_empty();
        for i in 0..n {
            w.known[i] =
                (1.0 + alpha) * w.force[i] - alpha * (w.force_prev[i] + w.nl_prev[i] - w.linear[i]);
            // Predictor: constant acceleration.
            w.q1[i] = q[i] + h * v[i] + 0.5 * h * h * a[i];
        }
        let evaluate =
            |problem: &mut System, scratch: &mut NlScratch, speed: &AtSpeed, w: &mut Workspace| {
                c.kinematics(q, v, a, &w.q1, &mut w.a1, &mut w.v1);
                nonlinear_force(problem, &at1, &w.q1, &w.v1, dofs, &mut w.nl, scratch);
                vectorised(|| residual(speed, mass, stiffness, alpha, w))
            };
        let mut norm_r = evaluate(problem, scratch, speed, w);
        for _ in 0..NEWTON_ITERATIONS {
            if !norm_r.is_finite() {
                break;
            }
            vectorised(|| speed.factors.solve(&w.residual, &mut w.dq));
            if !linear {
                let (q1, v1) = (&w.q1, &w.v1);
                tangent.correct(problem, &at1, q1, v1, c, speed, scratch, &mut w.dq);
            }
            let mut norm_dq = 0.0f64;
            let mut norm_q = 0.0f64;
            for i in 0..n {
                norm_dq = norm_dq.max(w.dq[i].abs());
                norm_q = norm_q.max((w.q1[i] - w.dq[i]).abs());
            }
            if !norm_dq.is_finite() {
                break;
            }
            // A linear step is solved exactly by its first Newton iteration.
            if linear || norm_dq <= 1e-10 * norm_q + 1e-15 {
                axpy(-1.0, &w.dq, &mut w.q1);
                self.commit(at1, c, speed);
                return Ok(Attempt::Converged);
            }
            match line_search(w, norm_r, |w| evaluate(problem, scratch, speed, w)) {
                Some(norm) => norm_r = norm,
                None => break,
            }
        }
        Ok(Attempt::Failed(norm_r))
    }

    /// Moves the state to the converged w.q1 at the end of a step with coefficients `c`,
    /// whose matrices at the step's speed are `speed`.
    fn commit(&mut self, at1: Kinematics, c: Coefficients, speed: &AtSpeed) {
        let w = &mut self.w;
        c.kinematics(&self.q, &self.v, &self.a, &w.q1, &mut w.a1, &mut w.v1);
        self.q.copy_from_slice(&w.q1);
        self.v.copy_from_slice(&w.v1);
        self.a.copy_from_slice(&w.a1);
        let (q, v) = (&self.q, &self.v);
        nonlinear_force(
            self.problem,
            &at1,
            q,
            v,
            &self.dofs,
            &mut w.nl_prev,
            &mut self.scratch,
        );
        vectorised(|| linear_force(speed, &self.stiffness, q, v, &mut w.linear));
        std::mem::swap(&mut w.force, &mut w.force_prev);
    }
}

/// Moves w.q1 along -w.dq to the first of the lengths 1, 1/2, 1/4, ... whose residual
/// passes Armijo's test against `norm_r`, the residual's 2-norm at w.q1; `evaluate`
/// forms the residual at w.q1 and returns its norm. Returns the new norm, or `None` (w.q1
/// then at the last length tried) when no length passes.
fn line_search(
    w: &mut Workspace,
    norm_r: f64,
    mut evaluate: impl FnMut(&mut Workspace) -> f64,
) -> Option<f64> {
    w.base.copy_from_slice(&w.q1);
    let mut lambda = 1.0;
    for _ in 0..=BACKTRACKS {
        for i in 0..w.q1.len() {
            w.q1[i] = w.base[i] - lambda * w.dq[i];
        }
        let trial = evaluate(w);
        if trial * trial <= (1.0 - 2.0 * ARMIJO * lambda) * norm_r * norm_r {
            return Some(trial);
        }
        lambda *= 0.5;
    }
    None
}

/// Marches `problem` from (q0, v0) with implicit Newmark; `observe` sees every step.
///
/// A step whose Newton iteration does not converge (within `NEWTON_ITERATIONS`, each
/// shortened by a backtracking line search until the residual falls enough) is done in
/// two halves, recursively, down to h / 2^`MAX_HALVINGS`; `observe` still sees the
/// times k h only. Below that the march stops with an error naming the time, the
/// sub-step and the residual.
///
/// # Errors
/// [`Error::InvalidOption`] when the matrices and vectors of `problem` differ in size or a
/// nonlinear force acts on a coordinate outside it ([`System::check`]); [`Error::Input`]
/// naming `hht_alpha` when the HHT alpha of `scheme` lies outside [-1/3, 0];
/// [`Error::Singular`] when the Newmark matrix
/// M/(beta h^2) + (1+alpha)(D gamma/(beta h) + K) is singular at a speed the run reaches;
/// [`Error::NotConverged`] when a step's Newton iteration fails even with the step halved
/// `MAX_HALVINGS` times (the time and residual are in the error); [`Error::Diverged`] when a
/// coordinate leaves `options.divergence_bound` or is not finite (checked every 64 steps).
pub fn newmark(
    problem: &mut System,
    q0: &[f64],
    v0: &[f64],
    scheme: NewmarkScheme,
    options: &MarchOptions,
    observe: Observer<'_>,
) -> Result<()> {
    check_marchable(problem)?;
    scheme.check()?;
    let alpha = scheme.alpha();
    let c = Coefficients {
        alpha,
        gamma: (1.0 - 2.0 * alpha) / 2.0,
        beta: (1.0 - alpha).powi(2) / 4.0,
        h: options.step,
    };
    march(problem, choose_layout(problem), q0, v0, c, options, observe)
}

/// [`newmark`] in a given layout, so that tests can run both on one problem.
fn march(
    problem: &mut System,
    layout: Layout,
    q0: &[f64],
    v0: &[f64],
    c: Coefficients,
    options: &MarchOptions,
    observe: Observer<'_>,
) -> Result<()> {
    let n = problem.size();
    let dofs = problem.nonlinear_dofs();
    let mut w = Workspace::new(n);
    let mut scratch = problem.scratch();
    let at = problem.external_force(&options.speed, 0.0, &mut w.force_prev);
    let (q, v) = (q0.to_vec(), v0.to_vec());
    nonlinear_force(problem, &at, &q, &v, &dofs, &mut w.nl_prev, &mut scratch);
    let a = problem.acceleration(&q, &v, &sum(&w.force_prev, &w.nl_prev), at.speed);
    let mut levels = Levels {
        layout,
        base: c,
        at: (0..=MAX_HALVINGS).map(|_| None).collect(),
    };
    let stiffness = Matrix::new(layout, n, |i, j| problem.matrices.stiffness[(i, j)]);
    let speed = levels.get(problem, 0, at.speed, &dofs)?;
    vectorised(|| linear_force(speed, &stiffness, &q, &v, &mut w.linear));
    let mut stepper = Stepper {
        mass: Matrix::new(layout, n, |i, j| problem.matrices.mass[(i, j)]),
        stiffness,
        tangent: Tangent::new(problem.tangent_block()),
        problem,
        profile: options.speed,
        dofs,
        scratch,
        w,
        q,
        v,
        a,
    };

    if observe(0.0, &stepper.q, &stepper.v).is_break() {
        return Ok(());
    }
    for step in 1..options.steps {
        let (t0, t1) = ((step - 1) as f64 * c.h, step as f64 * c.h);
        stepper.advance(&mut levels, t0, t1, 0)?;
        if step % 64 == 0 {
            check_state(t1, &stepper.q, options.divergence_bound)?;
        }
        if observe(t1, &stepper.q, &stepper.v).is_break() {
            return Ok(());
        }
    }
    Ok(())
}

/// The residual r = M a1 + (1+alpha)(D1 v1 + K q1 - F_nl1) - known into `w.residual`;
/// returns its 2-norm.
#[inline(always)]
fn residual(
    speed: &AtSpeed,
    mass: &Matrix,
    stiffness: &Matrix,
    alpha: f64,
    w: &mut Workspace,
) -> f64 {
    linear_force(speed, stiffness, &w.q1, &w.v1, &mut w.residual);
    for i in 0..w.residual.len() {
        w.residual[i] = (1.0 + alpha) * (w.residual[i] - w.nl[i]) - w.known[i];
    }
    mass.mul_add(&w.a1, &mut w.residual);
    w.residual.iter().map(|r| r * r).sum::<f64>().sqrt()
}

/// Element-wise a + b.
fn sum(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x + y).collect()
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::time::fixtures::{full_rotor, start};

    fn coefficients(alpha: f64, h: f64) -> Coefficients {
        Coefficients {
            alpha,
            gamma: (1.0 - 2.0 * alpha) / 2.0,
            beta: (1.0 - alpha).powi(2) / 4.0,
            h,
        }
    }

    /// Every (q, v) of a run, one step after another.
    fn run(
        problem: &mut System,
        speed: SpeedProfile,
        layout: Layout,
        c: Coefficients,
        steps: usize,
    ) -> Vec<f64> {
        let (q0, v0) = start(problem.size());
        let options = MarchOptions {
            speed,
            step: c.h,
            steps,
            divergence_bound: 1.0,
        };
        let mut history = Vec::new();
        march(problem, layout, &q0, &v0, c, &options, &mut |_, q, v| {
            history.extend_from_slice(q);
            history.extend_from_slice(v);
            std::ops::ControlFlow::Continue(())
        })
        .unwrap();
        history
    }

    /// The nonlinear tangents K_t, C_t at (q, v) as full n x n matrices.
    fn full_tangents(
        problem: &mut System,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        scratch: &mut NlScratch,
    ) -> (Mat<f64>, Mat<f64>) {
        let mut block = problem.tangent_block();
        problem.nonlinear_tangent(at, q, v, &mut block, scratch);
        let (n, k, dofs) = (q.len(), block.size(), &block.dofs);
        let full = |entries: &[f64]| {
            let mut m = Mat::<f64>::zeros(n, n);
            for a in 0..k {
                for b in 0..k {
                    m[(dofs[a], dofs[b])] = entries[a * k + b];
                }
            }
            m
        };
        (full(&block.stiffness), full(&block.damping))
    }

    /// The balance of the module documentation solved as written: a dense residual and a
    /// dense Jacobian with the full tangent, factorised at every Newton iteration. The slow,
    /// obviously-correct reference.
    fn reference(
        problem: &mut System,
        speed: SpeedProfile,
        c: Coefficients,
        steps: usize,
    ) -> Vec<f64> {
        let Coefficients {
            alpha,
            gamma,
            beta,
            h,
        } = c;
        let n = problem.size();
        let (mut q, mut v) = start(n);
        let mut scratch = problem.scratch();
        let d = |p: &System, s: f64| &p.matrices.damping + s * &p.matrices.gyroscopic;
        let (mut f0, mut f1, mut nl) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut at = problem.external_force(&speed, 0.0, &mut f0);
        problem.add_nonlinear(&at, &q, &v, &mut nl, &mut scratch);
        let mut a = problem.acceleration(&q, &v, &sum(&f0, &nl), at.speed);
        let mut history = Vec::new();
        history.extend_from_slice(&q);
        history.extend_from_slice(&v);
        let column = |x: &[f64]| Mat::<f64>::from_fn(n, 1, |i, _| x[i]);
        for step in 1..steps {
            let at1 = problem.external_force(&speed, step as f64 * h, &mut f1);
            let lin0 =
                &d(problem, at.speed) * column(&v) + &problem.matrices.stiffness * column(&q);
            let known: Vec<f64> = (0..n)
                .map(|i| (1.0 + alpha) * f1[i] - alpha * (f0[i] + nl[i] - lin0[(i, 0)]))
                .collect();
            let mut q1: Vec<f64> = (0..n)
                .map(|i| q[i] + h * v[i] + 0.5 * h * h * a[i])
                .collect();
            let (mut a1, mut v1) = (vec![0.0; n], vec![0.0; n]);
            for iteration in 0.. {
                assert!(iteration < 30, "no convergence at step {step}");
                c.kinematics(&q, &v, &a, &q1, &mut a1, &mut v1);
                nl.iter_mut().for_each(|x| *x = 0.0);
                problem.add_nonlinear(&at1, &q1, &v1, &mut nl, &mut scratch);
                let d1 = d(problem, at1.speed);
                let lin1 = &d1 * column(&v1) + &problem.matrices.stiffness * column(&q1);
                let mut r = &problem.matrices.mass * column(&a1);
                for i in 0..n {
                    r[(i, 0)] += (1.0 + alpha) * (lin1[(i, 0)] - nl[i]) - known[i];
                }
                let (kt, ct) = full_tangents(problem, &at1, &q1, &v1, &mut scratch);
                let j = &problem.matrices.mass * (1.0 / (beta * h * h))
                    + ((&d1 + &ct) * (gamma / (beta * h)) + &problem.matrices.stiffness + &kt)
                        * (1.0 + alpha);
                faer::linalg::solvers::Solve::solve_in_place(&j.partial_piv_lu(), r.as_mut());
                let (mut norm_dq, mut norm_q) = (0.0f64, 0.0f64);
                for i in 0..n {
                    q1[i] -= r[(i, 0)];
                    norm_dq = norm_dq.max(r[(i, 0)].abs());
                    norm_q = norm_q.max(q1[i].abs());
                }
                if norm_dq <= 1e-10 * norm_q + 1e-15 {
                    break;
                }
            }
            c.kinematics(&q, &v, &a, &q1, &mut a1, &mut v1);
            (q, v, a) = (q1, v1, a1);
            nl.iter_mut().for_each(|x| *x = 0.0);
            problem.add_nonlinear(&at1, &q, &v, &mut nl, &mut scratch);
            std::mem::swap(&mut f0, &mut f1);
            at = at1;
            history.extend_from_slice(&q);
            history.extend_from_slice(&v);
        }
        history
    }

    /// Largest difference of two runs, relative to the largest value.
    fn difference(a: &[f64], b: &[f64]) -> f64 {
        let scale = a.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        let worst = a
            .iter()
            .zip(b)
            .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
        worst / scale
    }

    // Every formulation rounds differently; measured 1e-14 to 1e-13 between the fast
    // layouts and the reference over these runs. 1e-9 leaves room and still catches a wrong
    // term (1e-3 or more) or a Newton step that stops short of the tolerance (1e-10 of q
    // per step, which the velocities, ~1e3 times q, would show at 1e-7).
    const TOLERANCE: f64 = 1e-9;
    const STEPS: usize = 400;

    #[test]
    fn the_full_model_is_marched_banded_and_a_reduced_one_dense() {
        let problem = full_rotor(false);
        assert_eq!(choose_layout(&problem), Layout::Banded(7, 7));
        let keep = |m: &Mat<f64>| Mat::from_fn(20, 20, |i, j| m[(i, j)]);
        let m = &problem.matrices;
        let small = System::unloaded(crate::fe::SystemMatrices {
            mass: keep(&m.mass),
            stiffness: keep(&m.stiffness),
            damping: keep(&m.damping),
            gyroscopic: keep(&m.gyroscopic),
        });
        assert_eq!(choose_layout(&small), Layout::Dense);
    }

    #[test]
    fn both_layouts_match_the_plain_newton_iteration() {
        let ramp = SpeedProfile::Ramp {
            from: 2.0 * PI * 10.0,
            to: 2.0 * PI * 200.0,
            start: 0.0,
            duration: 2e-3,
        };
        let constant = SpeedProfile::Constant(2.0 * PI * 50.0);
        for (speed, nonlinear, alpha) in [
            (constant, false, 0.0),
            (constant, true, 0.0),
            (constant, true, -0.1),
            (ramp, true, 0.0),
            (ramp, false, -0.1),
        ] {
            let c = coefficients(alpha, 1e-5);
            let mut problem = full_rotor(nonlinear);
            let plain = reference(&mut problem, speed, c, STEPS);
            for layout in [Layout::Dense, Layout::Banded(7, 7)] {
                let fast = run(&mut problem, speed, layout, c, STEPS);
                let e = difference(&plain, &fast);
                assert!(
                    e < TOLERANCE,
                    "{layout:?}, {speed:?}, nonlinear {nonlinear}, alpha {alpha}: {e:e}"
                );
            }
        }
    }

    #[test]
    fn a_matrix_unsafe_without_row_swaps_is_inverted_densely() {
        // A negative mass entry makes the symmetric part indefinite.
        let mut problem = full_rotor(false);
        problem.matrices.mass[(0, 0)] = -problem.matrices.mass[(0, 0)];
        let j0 = effective_matrix(&problem, 0.0, coefficients(0.0, 1e-5));
        let factors = Factors::new(Some((7, 7)), &j0).unwrap();
        assert!(matches!(factors, Factors::Inverse(_)));
    }

    #[test]
    fn the_woodbury_correction_applies_the_full_jacobian() {
        let profile = SpeedProfile::Constant(2.0 * PI * 50.0);
        let mut problem = full_rotor(true);
        let n = problem.size();
        let c = coefficients(-0.1, 1e-4);
        let dofs = problem.nonlinear_dofs();
        for layout in [Layout::Dense, Layout::Banded(7, 7)] {
            let mut speed = AtSpeed::new(&problem, layout, 2.0 * PI * 50.0, c, &dofs).unwrap();
            let (mut q, v) = start(n);
            // Engage the cubic spring beyond its clearance.
            q[41] = 3e-4;
            let (at, _) = profile.at(0.0);
            let r: Vec<f64> = (0..n).map(|i| ((i as f64) * 0.3).cos()).collect();
            let mut y = vec![0.0; n];
            speed.factors.solve(&r, &mut y);
            let mut scratch = problem.scratch();
            let mut tangent = Tangent::new(problem.tangent_block());
            tangent.correct(&mut problem, &at, &q, &v, c, &speed, &mut scratch, &mut y);

            let (kt, ct) = full_tangents(&mut problem, &at, &q, &v, &mut scratch);
            let j = effective_matrix(&problem, at.speed, c)
                + (&ct * (c.gamma / (c.beta * c.h)) + &kt) * (1.0 + c.alpha);
            let mut x = Mat::<f64>::from_fn(n, 1, |i, _| r[i]);
            faer::linalg::solvers::Solve::solve_in_place(&j.partial_piv_lu(), x.as_mut());
            let x: Vec<f64> = (0..n).map(|i| x[(i, 0)]).collect();
            // Measured 4e-15 (a few roundings; J is well conditioned, M/(beta h^2)
            // dominates it), where J0^-1 alone misses the tangent by 8e-6.
            assert!(difference(&x, &y) < 1e-13, "{layout:?}");
            speed.factors.solve(&r, &mut y);
            assert!(difference(&x, &y) > 1e-6, "{layout:?}");
        }
    }

    #[test]
    fn small_systems_are_solved_with_pivoting() {
        // A zero leading entry needs the row swap.
        let mut a = vec![0.0, 2.0, 1.0, 3.0, 1.0, 0.0, 1.0, 1.0, 4.0];
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| a[i * 3 + j] * x[j]).sum())
            .collect();
        solve_small(&mut a, &mut b);
        assert!(difference(&x, &b) < 1e-15, "{b:?}");
    }
}
