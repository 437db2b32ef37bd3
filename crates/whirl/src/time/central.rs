//! Explicit central difference (the thesis' "explicit Newmark", eqs. 4.1-4.3):
//!
//! ```text
//! (M/h^2 + D/2h) q_{n+1} = F_n + A q_n + B q_{n-1},   A = 2M/h^2 - K,  B = D/2h - M/h^2,
//! D = C + Omega G,   q_{-1} = q_0 - h q'_0 + h^2/2 q''_0                          (eq. 4.2)
//! ```
//!
//! The left-hand matrix is factorised once per speed, and a step takes one of two forms
//! that give the same q_{n+1} up to round-off:
//!
//! - dense, q_{n+1} = [P | Q] [q_n; q_{n-1}] + S F_n with S = (M/h^2 + D/2h)^-1, P = S A,
//!   Q = S B: 2 n^2 multiplications, best for small or dense (Craig-Bampton reduced)
//!   models. F_n = F_0 + c_re u_re + c_im u_im + F_nl, so S F_0, S u_re and S u_im are
//!   formed once and the nonlinear forces need only the columns of S at their coordinates.
//! - banded, A q_n + B q_{n-1} + F_n with band products, then a banded LU solve: about
//!   6 n b multiplications for half-bandwidth b, best for finite-element models, whose
//!   matrices are banded while P, Q and S are dense.
//!
//! The form is chosen from the matrices' actual bandwidth. Nonlinear forces are evaluated at
//! q_n with the backward-difference velocity (q_n - q_{n-1}) / h, which keeps the method
//! explicit. A step allocates nothing.
//!
//! Stability: h < 2 / w_max, w_max the highest natural frequency of (K + K_nl, M) with the
//! nonlinear forces' largest tangent stiffness. A larger step is refused with the limit in
//! the message (docs/theory.md section 6). During a speed ramp the change of Omega G since the last
//! factorisation acts as an explicit force, and the step is rebuilt whenever the speed has
//! moved by 1 % of the top speed.

use faer::Mat;

use super::{check_marchable, check_state, MarchOptions, Observer};
use crate::bearing::LagrangeContacts;
use crate::error::{Error, Result};
use crate::linalg::{axpy, vectorised, Band, BandLu, Columns, Layout, Turning};
use crate::reduce::explicit_stability_limit;
use crate::system::{NlScratch, SpeedProfile, System};

/// The cheaper step form for this problem (see the module documentation): per row the
/// dense step multiplies 2 n times, the banded one makes two band products and a solve.
fn choose_layout(problem: &System) -> Layout {
    Layout::choose(problem.matrices.all(), 2, 2 * problem.size())
}

/// The force of one step, F_n = F_0 + c_re u_re + c_im u_im + `extra`.
struct Load<'a> {
    /// [c_re, c_im] from [`SpeedProfile::unbalance_coefficients`].
    unbalance: [f64; 2],
    /// Nonlinear forces, and during a speed ramp the change of the gyroscopic force.
    extra: &'a [f64],
    /// The coordinates where `extra` can be nonzero, or `None` for anywhere.
    extra_dofs: Option<&'a [usize]>,
}

/// q_{n+1} = [P | Q] [q_n; q_{n-1}] + S F_n, with S applied to F_n term by term.
struct DenseStep {
    pq: Columns,
    s: Columns,
    s_constant: Vec<f64>,
    s_unbalance_re: Vec<f64>,
    s_unbalance_im: Vec<f64>,
}

impl DenseStep {
    fn new(problem: &System, lhs: &Mat<f64>, a: &Mat<f64>, b: &Mat<f64>) -> Result<Self> {
        let n = problem.size();
        let mut s = Mat::<f64>::identity(n, n);
        faer::linalg::solvers::Solve::solve_in_place(&lhs.partial_piv_lu(), s.as_mut());
        if s.col_iter().any(|c| c.iter().any(|v| !v.is_finite())) {
            return Err(singular());
        }
        let (p, q) = (&s * a, &s * b);
        let times_s = |v: &[f64]| {
            let x = &s * Mat::<f64>::from_fn(n, 1, |i, _| v[i]);
            (0..n).map(|i| x[(i, 0)]).collect()
        };
        Ok(DenseStep {
            pq: Columns::from_fn(
                n,
                2 * n,
                |i, j| {
                    if j < n {
                        p[(i, j)]
                    } else {
                        q[(i, j - n)]
                    }
                },
            ),
            s: Columns::from_fn(n, n, |i, j| s[(i, j)]),
            s_constant: times_s(&problem.constant_force),
            s_unbalance_re: times_s(&problem.unbalance_re),
            s_unbalance_im: times_s(&problem.unbalance_im),
        })
    }

    #[inline(always)]
    fn advance(&self, history: &[f64], load: &Load<'_>, out: &mut [f64]) {
        let [c_re, c_im] = load.unbalance;
        for i in 0..out.len() {
            out[i] =
                self.s_constant[i] + c_re * self.s_unbalance_re[i] + c_im * self.s_unbalance_im[i];
        }
        self.pq.mul_add(history, out);
        match load.extra_dofs {
            Some(dofs) => {
                for &j in dofs {
                    axpy(load.extra[j], self.s.column(j), out);
                }
            }
            None => self.s.mul_add(load.extra, out),
        }
    }
}

/// (M/h^2 + D/2h) q_{n+1} = A q_n + B q_{n-1} + F_n with band products and a banded LU.
struct BandedStep {
    lu: BandLu,
    a: Band,
    b: Band,
    constant: Vec<f64>,
    unbalance_re: Vec<f64>,
    unbalance_im: Vec<f64>,
    /// The right-hand side with the zeros around it that the solve needs.
    padded: Vec<f64>,
}

impl BandedStep {
    /// `None` when the left-hand matrix is not safe to factorise without row swaps: then
    /// the dense form, with its pivoting LU, takes over. M/h^2 + D/2h is safe when its
    /// symmetric part M/h^2 + (C + C^T)/4h is positive definite, which holds for any
    /// positive semi-definite damping; the gyroscopic part Omega G/2h is skew and smaller
    /// than M/h^2 by a factor of order Omega h.
    fn new(
        problem: &System,
        widths: (usize, usize),
        lhs: &Mat<f64>,
        a: &Mat<f64>,
        b: &Mat<f64>,
    ) -> Option<Self> {
        let n = problem.size();
        let band = |m: &Mat<f64>| Band::from_fn(n, widths, |i, j| m[(i, j)]);
        let w = widths.0.max(widths.1);
        let symmetric = Band::from_fn(n, (w, w), |i, j| 0.5 * (lhs[(i, j)] + lhs[(j, i)]));
        if !BandLu::new(&symmetric)?.pivots_positive() {
            return None;
        }
        let lu = BandLu::new(&band(lhs))?;
        let (before, after) = lu.padding();
        Some(BandedStep {
            lu,
            padded: vec![0.0; before + n + after],
            a: band(a),
            b: band(b),
            constant: problem.constant_force.clone(),
            unbalance_re: problem.unbalance_re.clone(),
            unbalance_im: problem.unbalance_im.clone(),
        })
    }

    /// `load.extra` is a full vector (zero off its coordinates), so it is added whole.
    #[inline(always)]
    fn advance(&mut self, history: &[f64], load: &Load<'_>, out: &mut [f64]) {
        let n = out.len();
        let [c_re, c_im] = load.unbalance;
        let start = self.lu.padding().0;
        let rhs = &mut self.padded[start..start + n];
        for i in 0..n {
            rhs[i] = self.constant[i]
                + c_re * self.unbalance_re[i]
                + c_im * self.unbalance_im[i]
                + load.extra[i];
        }
        let (q_cur, q_prev) = history.split_at(n);
        self.a.mul_add(q_cur, rhs);
        self.b.mul_add(q_prev, rhs);
        self.lu.solve_padded(&mut self.padded);
        out.copy_from_slice(&self.padded[start..start + n]);
    }
}

/// The two forms of a step; see the module documentation.
enum StepForm {
    Dense(DenseStep),
    Banded(BandedStep),
}

/// The step at one speed.
struct Step {
    speed: f64,
    form: StepForm,
    /// Columns of S = (M/h^2 + D/2h)^-1 at the Lagrange-constrained coordinates.
    contact: Option<ContactColumns>,
}

/// S restricted to the constrained coordinates: its columns (each n long, one after the
/// other) and the c x c block on those coordinates, row-major.
struct ContactColumns {
    columns: Vec<f64>,
    block: Vec<f64>,
}

impl ContactColumns {
    fn new(lhs: &Mat<f64>, coordinates: &[usize]) -> Result<ContactColumns> {
        let n = lhs.nrows();
        let c = coordinates.len();
        let mut x = Mat::<f64>::from_fn(n, c, |i, k| f64::from(u8::from(i == coordinates[k])));
        faer::linalg::solvers::Solve::solve_in_place(&lhs.partial_piv_lu(), x.as_mut());
        if x.col_iter().any(|col| col.iter().any(|v| !v.is_finite())) {
            return Err(singular());
        }
        let columns = (0..c)
            .flat_map(|k| (0..n).map(move |i| (k, i)))
            .map(|(k, i)| x[(i, k)]);
        let block = (0..c).flat_map(|a| (0..c).map(move |b| (a, b)));
        Ok(ContactColumns {
            columns: columns.collect(),
            block: block.map(|(a, b)| x[(coordinates[a], b)]).collect(),
        })
    }
}

impl Step {
    fn new(
        problem: &System,
        layout: Layout,
        speed: f64,
        h: f64,
        constrained: &[usize],
    ) -> Result<Step> {
        let n = problem.size();
        let (m, k) = (&problem.matrices.mass, &problem.matrices.stiffness);
        let d = |i: usize, j: usize| {
            problem.matrices.damping[(i, j)] + speed * problem.matrices.gyroscopic[(i, j)]
        };
        let lhs = Mat::<f64>::from_fn(n, n, |i, j| m[(i, j)] / (h * h) + d(i, j) / (2.0 * h));
        let a = Mat::<f64>::from_fn(n, n, |i, j| 2.0 * m[(i, j)] / (h * h) - k[(i, j)]);
        let b = Mat::<f64>::from_fn(n, n, |i, j| d(i, j) / (2.0 * h) - m[(i, j)] / (h * h));
        let banded = match layout {
            Layout::Banded(l, u) => BandedStep::new(problem, (l, u), &lhs, &a, &b),
            Layout::Dense => None,
        };
        let form = match banded {
            Some(banded) => StepForm::Banded(banded),
            None => StepForm::Dense(DenseStep::new(problem, &lhs, &a, &b)?),
        };
        let contact = if constrained.is_empty() {
            None
        } else {
            Some(ContactColumns::new(&lhs, constrained)?)
        };
        Ok(Step {
            speed,
            form,
            contact,
        })
    }

    /// q_{n+1} into `out` from `history` = [q_n; q_{n-1}].
    fn advance(&mut self, history: &[f64], load: &Load<'_>, out: &mut [f64]) {
        vectorised(
            #[inline(always)]
            || match &mut self.form {
                StepForm::Dense(s) => s.advance(history, load, out),
                StepForm::Banded(s) => s.advance(history, load, out),
            },
        )
    }
}

/// Adds the time to a contact failure.
fn at_time(e: Error, t: f64) -> Error {
    e.map_message(|m| format!("at t = {t:.6e} s: {m}"))
}

fn singular() -> Error {
    Error::singular(
        "central-difference matrix",
        "the central-difference matrix M/h^2 + D/2h is singular".into(),
    )
}

/// The largest stable step for this problem, s.
///
/// # Errors
/// [`Error::Singular`] for a mass matrix that is not positive definite and
/// [`Error::NotConverged`] when the eigen-solver fails: the errors of
/// [`crate::reduce::explicit_stability_limit`].
pub fn central_difference_limit(problem: &System) -> Result<f64> {
    let n = problem.size();
    let all: Vec<usize> = (0..n).collect();
    let bound = problem.nonlinear_stiffness_bound();
    explicit_stability_limit(&problem.matrices, Some((&all, &bound)))
}

/// Marches `problem` from (q0, v0) with the central difference; `observe` sees every step.
///
/// # Errors
/// [`Error::InvalidOption`] when the matrices and vectors of `problem` differ in size, a
/// nonlinear force acts on a coordinate outside it ([`System::check`]), or
/// `options.step` is at or above the stability limit (the limit is in the message); the
/// errors of [`central_difference_limit`]; [`Error::Singular`] when M/h^2 + D/2h is
/// singular; [`Error::Diverged`] when a coordinate leaves `options.divergence_bound` or is
/// not finite (checked every 64 steps).
pub fn central_difference(
    problem: &mut System,
    q0: &[f64],
    v0: &[f64],
    options: &MarchOptions,
    observe: Observer<'_>,
) -> Result<()> {
    march(
        problem,
        choose_layout(problem),
        q0,
        v0,
        options,
        None,
        observe,
    )
}

/// The central difference with roller contacts as Lagrange-multiplier constraints: after
/// each step's prediction, `contacts` corrects q_{n+1} so that no roller penetrates
/// (forward-increment Lagrange multipliers, see [`crate::bearing::lagrange`]). The
/// multipliers acting at each observed instant are recorded in `contacts`.
///
/// # Errors
/// The errors of [`central_difference`]; and, at the time of the step, those of
/// [`LagrangeContacts::correct`]: [`Error::Singular`] for a roller with no compliance,
/// [`Error::NotConverged`] when the contact forces are not found.
pub fn central_difference_constrained(
    problem: &mut System,
    q0: &[f64],
    v0: &[f64],
    options: &MarchOptions,
    contacts: &mut LagrangeContacts,
    observe: Observer<'_>,
) -> Result<()> {
    let layout = choose_layout(problem);
    march(problem, layout, q0, v0, options, Some(contacts), observe)
}

fn march(
    problem: &mut System,
    layout: Layout,
    q0: &[f64],
    v0: &[f64],
    options: &MarchOptions,
    mut contacts: Option<&mut LagrangeContacts>,
    observe: Observer<'_>,
) -> Result<()> {
    check_marchable(problem)?;
    let h = options.step;
    check_step(problem, h)?;
    let n = problem.size();
    let mut scratch = problem.scratch();
    let nonlinear_dofs = problem.nonlinear_dofs();
    let speed_profile = options.speed;
    let constant_speed = speed_profile.is_constant();
    let needs_velocity = !(nonlinear_dofs.is_empty() && constant_speed);
    let gyroscopic = Band::from_fn(n, layout.widths(n), |i, j| {
        problem.matrices.gyroscopic[(i, j)]
    });
    let (mut history, speed) = start(problem, &speed_profile, q0, v0, h, &mut scratch)?;
    let mut extra = vec![0.0; n];
    let mut gyroscopic_force = vec![0.0; n];
    let mut q_next = vec![0.0; n];
    let mut v_back = v0.to_vec();
    let mut v_central = vec![0.0; n];

    let top = speed_profile.max_speed().max(1.0);
    // Multiplications instead of a division per coordinate: the same to an ulp, and
    // division is one of the slowest instructions.
    let over_2h = 1.0 / (2.0 * h);
    let over_h = 1.0 / h;
    let constrained: Vec<usize> = contacts
        .as_ref()
        .map_or(Vec::new(), |c| c.coordinates().to_vec());
    if let Some(c) = contacts.as_deref_mut() {
        c.start_recording(options.steps);
    }
    let mut step_now = Step::new(problem, layout, speed, h, &constrained)?;
    let mut spin = Turning::default();
    for step in 0..options.steps {
        let t = step as f64 * h;
        let (at, unbalance) = speed_profile.unbalance_coefficients_by(t, |a| spin.sin_cos(a));
        let (q_cur, q_prev) = history.split_at(n);
        if step > 0 && needs_velocity {
            for i in 0..n {
                v_back[i] = (q_cur[i] - q_prev[i]) * over_h;
            }
        }
        if constant_speed {
            nonlinear_dofs.iter().for_each(|&d| extra[d] = 0.0);
        } else {
            extra.iter_mut().for_each(|x| *x = 0.0);
        }
        problem.add_nonlinear(&at, q_cur, &v_back, &mut extra, &mut scratch);
        if !constant_speed {
            if (at.speed - step_now.speed).abs() > 0.01 * top {
                step_now = Step::new(problem, layout, at.speed, h, &constrained)?;
            }
            let change = at.speed - step_now.speed;
            gyroscopic_force.iter_mut().for_each(|x| *x = 0.0);
            vectorised(|| gyroscopic.mul_add(&v_back, &mut gyroscopic_force));
            axpy(-change, &gyroscopic_force, &mut extra);
        }
        let load = Load {
            unbalance,
            extra: &extra,
            extra_dofs: constant_speed.then_some(&nonlinear_dofs[..]),
        };
        step_now.advance(&history, &load, &mut q_next);
        if let (Some(c), Some(columns)) = (contacts.as_deref_mut(), &step_now.contact) {
            c.record();
            let (next, _) = speed_profile.at(t + h);
            c.correct(&next, &mut q_next, &columns.block, |k, factor, q| {
                axpy(factor, &columns.columns[k * n..(k + 1) * n], q)
            })
            .map_err(|e| at_time(e, t + h))?;
        }
        let (q_cur, q_prev) = history.split_at(n);
        for i in 0..n {
            v_central[i] = (q_next[i] - q_prev[i]) * over_2h;
        }
        if step % 64 == 0 {
            check_state(t, q_cur, options.divergence_bound)?;
        }
        if observe(t, q_cur, &v_central).is_break() {
            return Ok(());
        }
        history.copy_within(..n, n);
        history[..n].copy_from_slice(&q_next);
    }
    Ok(())
}

/// [q_0; q_{-1}] with q_{-1} from eq. 4.2 and the initial acceleration from the equation of
/// motion, and the speed at t = 0.
fn start(
    problem: &mut System,
    speed: &SpeedProfile,
    q0: &[f64],
    v0: &[f64],
    h: f64,
    scratch: &mut NlScratch,
) -> Result<(Vec<f64>, f64)> {
    let n = problem.size();
    let mut force = vec![0.0; n];
    let at = problem.external_force(speed, 0.0, &mut force);
    problem.add_nonlinear(&at, q0, v0, &mut force, scratch);
    let a0 = problem.acceleration(q0, v0, &force, at.speed);
    let q_before = (0..n).map(|i| q0[i] - h * v0[i] + 0.5 * h * h * a0[i]);
    Ok((q0.iter().copied().chain(q_before).collect(), at.speed))
}

/// Refuses a step at or above the stability limit, with the limit in the message.
fn check_step(problem: &System, h: f64) -> Result<()> {
    let limit = central_difference_limit(problem)?;
    if h >= limit {
        return Err(Error::InvalidOption(format!(
            "the time step {h:.3e} s is above the central difference's stability limit \
             {limit:.3e} s (2 / w_max, w_max = {:.4e} rad/s with the contacts' tangent \
             stiffness): use a step below {limit:.3e} s, reduce the model (Craig-Bampton \
             removes the highest frequencies), or use the implicit Newmark method",
            2.0 / limit
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::time::fixtures::{self, full_rotor};

    /// Every (q, v) of a run, one step after another.
    fn run(
        problem: &mut System,
        speed: SpeedProfile,
        layout: Layout,
        h: f64,
        steps: usize,
    ) -> Vec<f64> {
        let n = problem.size();
        let (q0, v0) = fixtures::start(n);
        let options = MarchOptions {
            speed,
            step: h,
            steps,
            divergence_bound: 1.0,
        };
        let mut history = Vec::with_capacity(2 * n * steps);
        march(problem, layout, &q0, &v0, &options, None, &mut |_, q, v| {
            history.extend_from_slice(q);
            history.extend_from_slice(v);
            std::ops::ControlFlow::Continue(())
        })
        .unwrap();
        history
    }

    /// Eq. 4.1 as written, with a dense solve per step: the slow, obviously-correct
    /// reference (constant speed).
    fn reference(problem: &mut System, profile: SpeedProfile, h: f64, steps: usize) -> Vec<f64> {
        let n = problem.size();
        let q0: Vec<f64> = (0..n).map(|i| 1e-5 * ((i as f64) * 0.7).sin()).collect();
        let v0: Vec<f64> = (0..n).map(|i| 1e-3 * ((i as f64) * 1.3).cos()).collect();
        let speed = profile.max_speed();
        let (m, k) = (
            problem.matrices.mass.clone(),
            problem.matrices.stiffness.clone(),
        );
        let d = &problem.matrices.damping + speed * &problem.matrices.gyroscopic;
        let lhs = &m * (1.0 / (h * h)) + &d * (0.5 / h);
        let lu = lhs.partial_piv_lu();
        let mut scratch = problem.scratch();
        let mut force = vec![0.0; n];
        let at = problem.external_force(&profile, 0.0, &mut force);
        problem.add_nonlinear(&at, &q0, &v0, &mut force, &mut scratch);
        let a0 = problem.acceleration(&q0, &v0, &force, speed);
        let mut q_prev: Vec<f64> = (0..n)
            .map(|i| q0[i] - h * v0[i] + 0.5 * h * h * a0[i])
            .collect();
        let mut q = q0.clone();
        let mut v_back = v0.clone();
        let mut history = Vec::with_capacity(2 * n * steps);
        for step in 0..steps {
            let at = problem.external_force(&profile, step as f64 * h, &mut force);
            if step > 0 {
                v_back = (0..n).map(|i| (q[i] - q_prev[i]) / h).collect();
            }
            problem.add_nonlinear(&at, &q, &v_back, &mut force, &mut scratch);
            let mut rhs = Mat::<f64>::from_fn(n, 1, |i, _| {
                force[i]
                    - (0..n)
                        .map(|j| {
                            (k[(i, j)] - 2.0 * m[(i, j)] / (h * h)) * q[j]
                                + (m[(i, j)] / (h * h) - d[(i, j)] / (2.0 * h)) * q_prev[j]
                        })
                        .sum::<f64>()
            });
            faer::linalg::solvers::Solve::solve_in_place(&lu, rhs.as_mut());
            history.extend_from_slice(&q);
            history.extend((0..n).map(|i| (rhs[(i, 0)] - q_prev[i]) / (2.0 * h)));
            q_prev = std::mem::replace(&mut q, (0..n).map(|i| rhs[(i, 0)]).collect());
        }
        history
    }

    /// Largest difference of two runs' displacements, relative to the largest displacement.
    fn difference(a: &[f64], b: &[f64], n: usize) -> f64 {
        let q = |h: &[f64]| -> Vec<f64> {
            h.chunks_exact(2 * n)
                .flat_map(|c| c[..n].to_vec())
                .collect()
        };
        let (qa, qb) = (q(a), q(b));
        let scale = qa.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        let worst = qa
            .iter()
            .zip(&qb)
            .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
        worst / scale
    }

    // The tolerances below: every formulation rounds differently, and the displacement form
    // amplifies round-off. Its right-hand side adds 2M/h^2 q_n and -M/h^2 q_{n-1}, each
    // about (w h)^-2 ~ 1e5 times the elastic force K q that moves the low modes, and the
    // consistent mass matrix mixes metres and radians (condition ~1e6), so each step leaves
    // an error of ~1e-14 of the largest displacement that the low modes carry along. Measured
    // over 2,000 steps: 1e-11 to 4e-11 between any two of the forms; 1e-9 leaves room and
    // would still catch a wrong term, which shows at 1e-3 or more.
    const STEPS: usize = 2_000;
    const TOLERANCE: f64 = 1e-9;

    #[test]
    fn the_full_model_is_marched_banded() {
        let problem = full_rotor(false);
        assert_eq!(choose_layout(&problem), Layout::Banded(7, 7));
    }

    #[test]
    fn dense_and_banded_steps_match_the_plain_equation() {
        let h = 3.8e-6;
        for nonlinear in [false, true] {
            let speed = SpeedProfile::Constant(2.0 * PI * 50.0);
            let mut problem = full_rotor(nonlinear);
            let n = problem.size();
            let plain = reference(&mut problem, speed, h, STEPS);
            for layout in [Layout::Dense, Layout::Banded(7, 7)] {
                let fast = run(&mut problem, speed, layout, h, STEPS);
                let e = difference(&plain, &fast, n);
                assert!(e < TOLERANCE, "{layout:?}, nonlinear {nonlinear}: {e:e}");
            }
        }
    }

    #[test]
    fn dense_and_banded_steps_agree_during_a_speed_ramp() {
        let ramp = SpeedProfile::Ramp {
            from: 2.0 * PI * 10.0,
            to: 2.0 * PI * 200.0,
            start: 0.0,
            duration: 2e-3,
        };
        let h = 3.8e-6;
        let mut problem = full_rotor(true);
        let n = problem.size();
        let dense = run(&mut problem, ramp, Layout::Dense, h, STEPS);
        let banded = run(&mut problem, ramp, Layout::Banded(7, 7), h, STEPS);
        // The ramp crosses many rebuilds of the step (every 1 % of the top speed).
        let e = difference(&dense, &banded, n);
        assert!(e < TOLERANCE, "{e:e}");
    }

    #[test]
    fn a_matrix_unsafe_without_row_swaps_falls_back_to_the_dense_form() {
        // A negative mass entry makes the symmetric part indefinite.
        let mut problem = full_rotor(false);
        problem.matrices.mass[(0, 0)] = -problem.matrices.mass[(0, 0)];
        let step = Step::new(&problem, Layout::Banded(7, 7), 0.0, 3.8e-6, &[]).unwrap();
        assert!(matches!(step.form, StepForm::Dense(_)));
    }
}
