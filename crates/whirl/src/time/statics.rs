//! Static equilibrium under the constant load (gravity): K q - F_0 - F_nl(q, 0) = 0.
//!
//! The nonlinear forces act on few coordinates u (a bearing node's, k of n); the rest, w,
//! are balanced linearly, K_ww w = F_w - K_wu u, so they follow from u exactly and the
//! balance condenses onto u (static condensation):
//!
//! ```text
//! R(u) = S u - g - F_nl(u) = 0,   S = K_uu - K_uw K_ww^-1 K_wu,   g = F_u - K_uw K_ww^-1 F_w
//! ```
//!
//! K and M are held on their bands and K_ww is factorised once on its band, so memory and
//! cost grow with n (times the bandwidths), not n^2 and n^3; the nonlinear forces'
//! tangents are their k x k block ([`crate::system::TangentBlock`]), and every iteration
//! works on k x k matrices: the mesh size leaves the iteration alone.
//!
//! On a fine mesh an element's stiffness (12 EI / l^3: 5e17 N/m for 10,000 elements of the
//! reference rotor) times the shaft's motion (1e-4 m) rounds away the forces its bending
//! carries, so S and g, formed from such products, lost their digits as the fourth power
//! of the element count (the bearing loads of a 10,000-element reference rotor were 6e-4
//! off, its sag 2.5e-4). S and g are therefore taken as S's column b = (K t_b)_u and
//! g = F_u - (K [0; w0])_u, t_b the static mode [e_b; -K_ww^-1 K_wb], with K x computed
//! from each element's deformation when the caller has that product
//! ([`crate::fe::element_forces`]), and each solve with K_ww is refined once against it:
//! the same 10,000-element rotor then comes within 3e-6 (loads) and 1e-7 (deflections) of
//! the 20-element solution, which cubic elements make exact at the nodes.
//!
//! R is solved by Newton's method with the nonlinear forces' tangent stiffness, made
//! robust for contacts with clearance in the Levenberg-Marquardt way: the step solves
//! (S + K_t + mu M_c) du = -R, M_c the mass condensed with the same static modes (Guyan's
//! reduction, exact for rigid-body motion). With mu = 0 it is Newton; when S + K_t is
//! singular (a rotor
//! hanging free inside its clearances, before any roller touches) or a step fails its line
//! search, mu is raised, which turns the step into a damped fall along the load towards
//! contact. Once in contact mu returns to zero and convergence is quadratic. A step is
//! taken whole when it lowers |R| enough (Armijo) or the residual still points along it;
//! otherwise it stops where the residual turns against it. Directions with neither
//! stiffness nor load (u_x with one roller at the bottom) keep their starting value: from
//! u = 0 the horizontal position stays 0 (docs/theory.md section 6).
//!
//! A spinning bearing's damping acts on the cage's motion over the rollers even at rest,
//! a force that is not the gradient of any energy: with many rollers at speed there may be
//! no equilibrium at all. The error then says so, and [`super::simulate`] starts from rest.

use crate::error::{Error, Result};
use crate::force::{Kinematics, NonlinearForce};
use crate::linalg::{dot_in_order as dot, norm, solve_small, Band, Factors};
use crate::system::{add_forces, forces_tangent, NlScratch, System, TangentBlock};

/// Scale of mu, a squared circular frequency, (rad/s)^2. The first regularised step uses
/// 1e-6 of it: a free rotor's trial fall g / mu is then far past any clearance and the
/// line search finds the contact on the way.
const FIRST_MU: f64 = 4e3;

/// The least mu once a step has been taken: mu M_c is then about 1e-3 N/m, eleven orders
/// below a roller's contact stiffness, so Newton's convergence is unchanged, but it holds
/// still the directions that neither stiffness nor load sets (u_x on one bottom roller).
/// The load there is round-off (cos 270 deg = -1.8e-16 of the roller's force) and S's
/// stiffness too: exact Newton moved the reference rotor sideways by that load over S's
/// round-off, 5e-11 m on the band's products and 1.6e-7 m on the elements' more exact ones.
const LEAST_MU: f64 = FIRST_MU * 1e-8;

/// Levenberg-Marquardt steps before giving up. A rotor that starts free takes about 20
/// (mu falls by 10 per accepted step from its largest), contact Newton a few more.
const ITERATIONS: usize = 400;

/// Armijo's sufficient decrease of |R|^2 for a whole step (see the Newmark module).
const ARMIJO: f64 = 1e-4;

/// Static equilibrium of `problem` with the shaft spinning at `speed` (rad/s; the contact
/// laws' cage and roller positions follow it), starting from `guess` (only its entries on
/// the nonlinear forces' coordinates matter: the rest follow from them).
///
/// # Errors
/// [`Error::InvalidOption`] from [`System::check`] (sizes that differ, a nonlinear
/// force on a coordinate outside the problem); [`Error::Singular`] when the stiffness
/// without the nonlinear forces' coordinates is singular (part of the structure is free);
/// [`Error::NotConverged`] when the Levenberg-Marquardt iteration does not bring the
/// residual below its tolerance.
pub fn static_equilibrium(problem: &mut System, guess: &[f64], speed: f64) -> Result<Vec<f64>> {
    problem.check()?;
    let structure = Structure {
        stiffness: &Band::of_dense(&problem.matrices.stiffness),
        mass: &Band::of_dense(&problem.matrices.mass),
        constant_force: &problem.constant_force,
        product: None,
    };
    equilibrium(&structure, &mut problem.nonlinear, guess, speed)
}

/// The linear part of a static balance on its bands: K, M (for the regularisation) and the
/// constant load F_0, in coordinates that the nonlinear forces index.
pub(crate) struct Structure<'a> {
    pub(crate) stiffness: &'a Band,
    pub(crate) mass: &'a Band,
    pub(crate) constant_force: &'a [f64],
    /// out = K x without the round-off of K's largest entries, when the caller has it (an
    /// assembled mesh, [`crate::fe::stiffness_product`]); else K's band times x.
    pub(crate) product: Option<&'a Product<'a>>,
}

/// out = K x, for [`Structure::product`].
pub(crate) type Product<'a> = dyn Fn(&[f64], &mut [f64]) + 'a;

impl Structure<'_> {
    /// K x, by [`Structure::product`] when given.
    fn times(&self, x: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; x.len()];
        match self.product {
            Some(product) => product(x, &mut out),
            None => self.stiffness.mul_add(x, &mut out),
        }
        out
    }
}

/// [`static_equilibrium`] of `structure` with the nonlinear forces `forces` (whose
/// coordinates lie inside it): its memory and cost grow with the size times the bandwidths,
/// so a 10,000-element rotor's balance is solved where its dense matrices would not fit.
///
/// # Errors
/// Those of [`static_equilibrium`] but the size checks.
pub(crate) fn equilibrium(
    structure: &Structure<'_>,
    forces: &mut [Box<dyn NonlinearForce>],
    guess: &[f64],
    speed: f64,
) -> Result<Vec<f64>> {
    let at = Kinematics {
        time: 0.0,
        speed,
        angle: 0.0,
    };
    let mut condensed = Condensed::new(structure, forces)?;
    let scale = norm(structure.constant_force).max(1e-12);
    let mut u: Vec<f64> = condensed.dofs().iter().map(|&d| guess[d]).collect();
    let mut r = condensed.residual(forces, &at, &u);
    let mut mu = 0.0;
    for _ in 0..ITERATIONS {
        if norm(&r) <= 1e-10 * scale {
            return Ok(condensed.expand(&u));
        }
        let tangent = condensed.tangent(forces, &at, &u);
        match descend(&mut condensed, forces, &at, &tangent, mu, &u, &r) {
            Some((trial, rt)) => {
                u = trial;
                r = rt;
                mu = (mu / 10.0).max(LEAST_MU);
            }
            None => {
                mu = if mu == 0.0 {
                    FIRST_MU * 1e-6
                } else {
                    mu * 10.0
                };
                if mu > FIRST_MU * 1e12 {
                    break;
                }
            }
        }
    }
    if norm(&r) <= 1e-8 * scale {
        return Ok(condensed.expand(&u));
    }
    Err(Error::not_converged(
        "static equilibrium",
        None,
        Some(norm(&r)),
        format!(
            "the static equilibrium did not converge (residual {:.3e} N against a load of \
         {scale:.3e} N); with a spinning bearing's contact damping there may be none: \
         check that every bearing can carry the load, or start from rest",
            norm(&r)
        ),
    ))
}

/// The balance condensed onto the nonlinear forces' coordinates (module documentation).
struct Condensed {
    /// w: the coordinates but the nonlinear forces' (u, which are `tangent.dofs`).
    others: Vec<usize>,
    /// S, row-major k x k.
    s: Vec<f64>,
    /// g.
    g: Vec<f64>,
    /// M_c = T^T M T, T the static modes (u, -K_ww^-1 K_wu u), row-major k x k.
    mass: Vec<f64>,
    /// K_ww^-1 F_w.
    w0: Vec<f64>,
    /// Column a is K_ww^-1 K_w,dofs[a], at a * (n - k).
    columns: Vec<f64>,
    /// Full-size q, v and force for the nonlinear forces; only entries at `dofs` are used.
    q: Vec<f64>,
    zero: Vec<f64>,
    force: Vec<f64>,
    /// The nonlinear forces' tangents on u.
    tangent: TangentBlock,
    scratch: NlScratch,
}

impl Condensed {
    fn new(structure: &Structure<'_>, forces: &[Box<dyn NonlinearForce>]) -> Result<Condensed> {
        let k_full = structure.stiffness;
        let n = k_full.size();
        let tangent = TangentBlock::new(forces);
        let dofs = &tangent.dofs;
        let others: Vec<usize> = (0..n).filter(|i| dofs.binary_search(i).is_err()).collect();
        let m = others.len();
        let k_ww = remaining_band(k_full, &others);
        let mut factors = Factors::of_band(&k_ww).ok_or_else(|| {
            Error::singular(
                "static stiffness",
                "the static equilibrium needs the structure held when the nonlinear forces' \
                 coordinates are fixed, and part of it is free (its stiffness without them \
                 is singular); add a support, or start from rest"
                    .into(),
            )
        })?;
        // Every solve with K_ww is refined once against K x of the structure (Higham,
        // "Accuracy and Stability of Numerical Algorithms", 2nd ed., chapter 12): with an
        // accurate product the solution regains the digits that K's largest entries take
        // from a fine mesh's factorisation (module documentation). One step: a second and
        // a third moved the 10,000-element reference rotor's results by no more than
        // their scatter (1e-6 on the bearing loads).
        let spread = |on_w: &[f64], unit: Option<usize>| {
            let mut x = vec![0.0; n];
            for (&i, &v) in others.iter().zip(on_w) {
                x[i] = v;
            }
            if let Some(a) = unit {
                x[dofs[a]] = 1.0;
            }
            x
        };
        let on_w = |x: &[f64]| -> Vec<f64> { others.iter().map(|&i| x[i]).collect() };
        let mut refined = |rhs: &[f64], residual: &dyn Fn(&[f64]) -> Vec<f64>| {
            let mut x = vec![0.0; m];
            factors.solve(rhs, &mut x);
            let mut correction = vec![0.0; m];
            factors.solve(&residual(&x), &mut correction);
            x.iter_mut().zip(&correction).for_each(|(x, c)| *x += c);
            x
        };
        // K_ww w0 = F_w: the residual is F_w - (K [0; w0])_w.
        let f_w = on_w(structure.constant_force);
        let w0 = refined(&f_w, &|w| {
            let kx = structure.times(&spread(w, None));
            f_w.iter().zip(on_w(&kx)).map(|(f, k)| f - k).collect()
        });
        // K_ww c_a = K_w,dofs[a]: the static mode t_a = [e_a; -c_a] has (K t_a)_w =
        // K_w,dofs[a] - K_ww c_a, the residual.
        let k = dofs.len();
        let mode = |c: &[f64], a: usize| {
            let minus: Vec<f64> = c.iter().map(|x| -x).collect();
            structure.times(&spread(&minus, Some(a)))
        };
        let mut columns = Vec::with_capacity(m * k);
        for (a, &d) in dofs.iter().enumerate() {
            let k_wd: Vec<f64> = others.iter().map(|&i| k_full.get(i, d)).collect();
            columns.extend(refined(&k_wd, &|c| on_w(&mode(c, a))));
        }
        // S's column b is (K t_b)_u; g = F_u - (K [0; w0])_u.
        let mut s = vec![0.0; k * k];
        for b in 0..k {
            let kt = mode(&columns[b * m..(b + 1) * m], b);
            for (a, &d) in dofs.iter().enumerate() {
                s[a * k + b] = kt[d];
            }
        }
        let held = structure.times(&spread(&w0, None));
        let g: Vec<f64> = dofs
            .iter()
            .map(|&d| structure.constant_force[d] - held[d])
            .collect();
        let mass = condensed_mass(structure.mass, dofs, &others, &columns);
        Ok(Condensed {
            others,
            s,
            g,
            mass,
            w0,
            columns,
            q: vec![0.0; n],
            zero: vec![0.0; n],
            force: vec![0.0; n],
            scratch: NlScratch::new(forces),
            tangent,
        })
    }

    /// u's coordinates.
    fn dofs(&self) -> &[usize] {
        &self.tangent.dofs
    }

    /// R(u) = S u - g - F_nl(u).
    fn residual(
        &mut self,
        forces: &mut [Box<dyn NonlinearForce>],
        at: &Kinematics,
        u: &[f64],
    ) -> Vec<f64> {
        let k = u.len();
        for (&d, &x) in self.tangent.dofs.iter().zip(u) {
            self.q[d] = x;
            self.force[d] = 0.0;
        }
        add_forces(
            forces,
            at,
            &self.q,
            &self.zero,
            &mut self.force,
            &mut self.scratch,
        );
        (0..k)
            .map(|a| {
                let su: f64 = (0..k).map(|b| self.s[a * k + b] * u[b]).sum();
                su - self.g[a] - self.force[self.tangent.dofs[a]]
            })
            .collect()
    }

    /// dR/du = S + K_t, row-major.
    fn tangent(
        &mut self,
        forces: &mut [Box<dyn NonlinearForce>],
        at: &Kinematics,
        u: &[f64],
    ) -> Vec<f64> {
        for (&d, &x) in self.tangent.dofs.iter().zip(u) {
            self.q[d] = x;
        }
        forces_tangent(
            forces,
            at,
            &self.q,
            &self.zero,
            &mut self.tangent,
            &mut self.scratch,
        );
        self.s
            .iter()
            .zip(&self.tangent.stiffness)
            .map(|(s, kt)| s + kt)
            .collect()
    }

    /// The full q of u: w = K_ww^-1 (F_w - K_wu u).
    fn expand(&self, u: &[f64]) -> Vec<f64> {
        let m = self.others.len();
        let mut q = vec![0.0; u.len() + m];
        for (&d, &x) in self.tangent.dofs.iter().zip(u) {
            q[d] = x;
        }
        for (i, &w) in self.others.iter().enumerate() {
            let coupled: f64 = u
                .iter()
                .enumerate()
                .map(|(a, x)| self.columns[a * m + i] * x)
                .sum();
            q[w] = self.w0[i] - coupled;
        }
        q
    }
}

/// The band of K_ww: `k`'s rows and columns `others` (ascending), as narrow as its
/// nonzero entries reach, as [`Band::of_dense`] would make it.
fn remaining_band(k: &Band, others: &[usize]) -> Band {
    let n = k.size();
    let mut position = vec![None; n];
    for (i, &w) in others.iter().enumerate() {
        position[w] = Some(i);
    }
    let (lower, upper) = k.widths();
    let (mut below, mut above) = (0, 0);
    for (i, &row) in others.iter().enumerate() {
        for j in row.saturating_sub(lower)..(row + upper + 1).min(n) {
            if let Some(c) = position[j].filter(|_| k.get(row, j) != 0.0) {
                below = below.max(i.saturating_sub(c));
                above = above.max(c.saturating_sub(i));
            }
        }
    }
    Band::from_fn(others.len(), (below, above), |i, j| {
        k.get(others[i], others[j])
    })
}

/// One regularised Newton step du = -(T + mu M_c)^-1 R, taken whole when it lowers
/// |R| by Armijo's test or R still points along it at its end; otherwise shortened to where
/// R's component along it changes sign (the line minimum of the potential energy when the
/// forces are conservative: a norm test alone would stall while the rotor falls through
/// its clearance, where R does not change at all). `None` when the step is not a descent
/// direction or not finite.
fn descend(
    condensed: &mut Condensed,
    forces: &mut [Box<dyn NonlinearForce>],
    at: &Kinematics,
    tangent: &[f64],
    mu: f64,
    u: &[f64],
    r: &[f64],
) -> Option<(Vec<f64>, Vec<f64>)> {
    let k = u.len();
    let mut a: Vec<f64> = tangent
        .iter()
        .zip(&condensed.mass)
        .map(|(t, m)| t + mu * m)
        .collect();
    let mut du: Vec<f64> = r.iter().map(|x| -x).collect();
    solve_small(&mut a, &mut du);
    if du.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let slope0 = dot(r, &du);
    if slope0 >= 0.0 {
        return None;
    }
    let mut at_t = |t: f64| {
        let trial: Vec<f64> = (0..k).map(|i| u[i] + t * du[i]).collect();
        let rt = condensed.residual(forces, at, &trial);
        let slope = dot(&rt, &du);
        (trial, rt, slope)
    };
    let full = at_t(1.0);
    let decrease = dot(&full.1, &full.1) <= (1.0 - 2.0 * ARMIJO) * dot(r, r);
    if decrease || full.2 <= 0.0 {
        return Some((full.0, full.1));
    }
    // Bisection for the sign change of the slope on (0, 1).
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut best = full;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        let trial = at_t(mid);
        if trial.2 <= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        let done = trial.2.abs() <= 1e-3 * slope0.abs();
        best = trial;
        if done {
            break;
        }
    }
    (best.1.iter().all(|x| x.is_finite())).then_some((best.0, best.1))
}

/// M_c = T^T M T, T's column a the static mode of coordinate dofs[a]: 1 there, minus
/// `columns`' column a on `others`.
fn condensed_mass(mass: &Band, dofs: &[usize], others: &[usize], columns: &[f64]) -> Vec<f64> {
    let (n, k, m) = (mass.size(), dofs.len(), others.len());
    let modes: Vec<Vec<f64>> = (0..k)
        .map(|a| {
            let mut t = vec![0.0; n];
            t[dofs[a]] = 1.0;
            for (i, &w) in others.iter().enumerate() {
                t[w] = -columns[a * m + i];
            }
            t
        })
        .collect();
    let products: Vec<Vec<f64>> = modes
        .iter()
        .map(|t| {
            let mut product = vec![0.0; n];
            mass.mul_add(t, &mut product);
            product
        })
        .collect();
    let mut out = vec![0.0; k * k];
    for a in 0..k {
        for b in 0..k {
            out[a * k + b] = dot(&modes[a], &products[b]);
        }
    }
    out
}
