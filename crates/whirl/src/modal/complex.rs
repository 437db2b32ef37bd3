//! Complex (damped, gyroscopic) modes at a spin speed (thesis eqs. 2.21-2.27).
//!
//! In first-order form with the state z = (q, q') (thesis eq. 2.24, rearranged):
//!
//! ```text
//! z' = A z,   A = [ 0            I                   ]
//!                 [ -M^-1 K      -M^-1 (C + Omega G) ]
//! ```
//!
//! solved in modal coordinates for conditioning (see [`ModalBasis`]).
//!
//! Eigenvalues lambda = -zeta w_n +- i w_d; only the root with w_d > 0 of each pair is
//! kept, and overdamped (real) roots are dropped from the results: Rayleigh damping makes
//! the highest modes overdamped, and when spinning those can show up as spurious slow roots.
//!
//! [`ModalBasis`] holds the system in modal coordinates, on all undamped modes (exact) or on
//! the lowest ones, which makes each speed of a Campbell diagram much cheaper. The
//! truncation error on the retained whirl modes is tested against the full solve.

use faer::{c64, Mat};
use serde::Serialize;

use super::undamped::{undamped_modes_told, UndampedModes};
use super::CampbellOptions;
use crate::error::{Error, Result};
use crate::fe::{dof, BandedSystem, Direction, Matrices};
use crate::progress::Progress;

/// The largest model, in DOFs, whose full complex eigen-problem is solved: 2,000 DOFs make a
/// 4,000 x 4,000 state matrix, whose eigen-solve takes minutes and ~0.5 GB; larger models
/// are solved on a truncated basis.
pub const FULL_LIMIT: usize = 2000;

/// Whirl direction of a mode, from the orbits of its nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Whirl {
    /// Every node whirls with the spin.
    Forward,
    /// Every node whirls against the spin.
    Backward,
    /// Some nodes each way.
    Mixed,
}

impl Whirl {
    /// Lower-case name for tables.
    pub fn name(self) -> &'static str {
        match self {
            Whirl::Forward => "forward",
            Whirl::Backward => "backward",
            Whirl::Mixed => "mixed",
        }
    }
}

/// Names branches by whirl direction and rank: the first forward branch is `1F`, the
/// second `2F`, the first backward `1B`; mixed ones `1M`. Input in ascending frequency.
pub fn branch_labels(whirls: &[Whirl]) -> Vec<String> {
    let (mut f, mut b, mut m) = (0, 0, 0);
    whirls
        .iter()
        .map(|w| match w {
            Whirl::Forward => {
                f += 1;
                format!("{f}F")
            }
            Whirl::Backward => {
                b += 1;
                format!("{b}B")
            }
            Whirl::Mixed => {
                m += 1;
                format!("{m}M")
            }
        })
        .collect()
}

/// One damped mode at one speed.
#[derive(Debug, Clone, Serialize)]
pub struct ComplexMode {
    /// Eigenvalue, 1/s: (real, imaginary).
    pub eigenvalue: (f64, f64),
    /// Damped natural frequency w_d / 2 pi, Hz.
    pub damped_frequency_hz: f64,
    /// Undamped natural frequency |lambda| / 2 pi, Hz.
    pub natural_frequency_hz: f64,
    /// Damping ratio -Re(lambda) / |lambda|.
    pub damping_ratio: f64,
    /// Logarithmic decrement 2 pi zeta / sqrt(1 - zeta^2).
    pub log_decrement: f64,
    /// Whirl direction.
    pub whirl: Whirl,
    /// Displacement shape over the global DOFs, scaled so that the largest translation is 1.
    #[serde(skip)]
    pub shape: Vec<c64>,
    /// The eigenvector in the basis' own coordinates, for mode tracking.
    #[serde(skip)]
    pub coordinates: Vec<c64>,
}

impl ComplexMode {
    /// Forward and backward orbit radii (R_f, R_b) of a node: with ux = a e^{i w t},
    /// uy = b e^{i w t}, the orbit x + i y = (a + i b)/2 e^{i w t} + conj(a - i b)/2 e^{-i w t}.
    pub fn orbit_radii(&self, node: usize) -> (f64, f64) {
        let a = self.shape[dof(node, Direction::Ux)];
        let b = self.shape[dof(node, Direction::Uy)];
        let i = c64::new(0.0, 1.0);
        ((a + i * b).norm() / 2.0, (a - i * b).norm() / 2.0)
    }
}

/// The system in modal coordinates q = Phi eta (Phi^T M Phi = I), on all or on the
/// lowest undamped modes.
///
/// The first-order form uses the scaled state y = (S eta, eta'), S = diag(max(w_k, 1 rad/s)),
/// so that the state matrix
///
/// ```text
/// A = [ 0          S              ]
///     [ -K~ S^-1   -(C~ + Omega G~) ]
/// ```
///
/// has entries of the size of the frequencies rather than of their squares. With all modes
/// this is an exact similarity transform of the physical problem, and much better
/// conditioned than M^-1 K (whose eigenvalue errors reached 3e-5 relative on the reference
/// rotor, against 1e-12 here).
#[derive(Debug, Clone)]
pub struct ModalBasis {
    /// Phi^T K Phi S^-1.
    k_scaled: Mat<f64>,
    /// Phi^T C Phi.
    c: Mat<f64>,
    /// Phi^T G Phi.
    g: Mat<f64>,
    /// The scale S of each coordinate.
    scale: Vec<f64>,
    /// Physical shapes of the coordinates, one per column.
    shapes: Mat<f64>,
}

impl ModalBasis {
    /// All modes: exact, one 2n x 2n eigen-solve per speed.
    ///
    /// # Errors
    /// [`Error::Unsupported`] above [`FULL_LIMIT`] DOFs; then as [`ModalBasis::truncated`].
    pub fn full(system: &impl Matrices) -> Result<ModalBasis> {
        let n = system.dofs();
        if n > FULL_LIMIT {
            return Err(Error::Unsupported(format!(
                "the full complex eigen-problem of this model ({n} DOFs, a {m} x {m} state \
                 matrix) is too large (at most {FULL_LIMIT} DOFs): use a truncated modal basis \
                 (leave out --full)",
                m = 2 * n
            )));
        }
        ModalBasis::truncated(system, n, None)
    }

    /// How many undamped modes make the basis for the `modes` lowest damped modes of a model
    /// of `dofs` DOFs: every mode while the model is solved dense ([`super::solves_dense`]
    /// for that basis), else [`CampbellOptions::default_basis`].
    pub fn size_for(dofs: usize, modes: usize) -> usize {
        let basis = CampbellOptions::default_basis(modes);
        if super::solves_dense(dofs, basis) {
            dofs
        } else {
            basis
        }
    }

    /// The `count` lowest undamped modes, telling `progress` after every iteration of the
    /// eigen-solver when it iterates (minutes for 400 modes of a 10,000-element rotor).
    ///
    /// # Errors
    /// [`Error::Singular`] when the mass is not positive definite or the rotor is unstable at
    /// rest, [`Error::NotConverged`] when the eigen-solver fails (see
    /// [`super::undamped_modes`]); [`Error::Interrupted`] when `progress` stopped it.
    pub fn truncated(
        system: &impl Matrices,
        count: usize,
        progress: Option<&Progress>,
    ) -> Result<ModalBasis> {
        Ok(ModalBasis::of_modes(
            system,
            undamped_modes_told(system, count, progress)?,
        ))
    }

    /// The basis of `modes`, the lowest undamped modes of `system` (mass-normalised).
    pub(crate) fn of_modes(system: &impl Matrices, modes: UndampedModes) -> ModalBasis {
        let count = modes.frequencies_hz.len();
        let phi = modes.shapes;
        let scale: Vec<f64> = modes
            .frequencies_hz
            .iter()
            .map(|f| (2.0 * std::f64::consts::PI * f).max(1.0))
            .collect();
        let [k, c, g] = if super::solves_dense(system.dofs(), count) {
            let dense = system.dense();
            let project = |a: &Mat<f64>| phi.transpose() * a * &phi;
            [&dense.stiffness, &dense.damping, &dense.gyroscopic].map(project)
        } else {
            let lambda: Vec<f64> = modes
                .frequencies_hz
                .iter()
                .map(|f| (2.0 * std::f64::consts::PI * f).powi(2))
                .collect();
            project_banded(&system.banded(), &phi, &lambda)
        };
        let p = scale.len();
        ModalBasis {
            k_scaled: Mat::from_fn(p, p, |i, j| k[(i, j)] / scale[j]),
            c,
            g,
            scale,
            shapes: phi,
        }
    }

    /// Number of coordinates.
    pub fn size(&self) -> usize {
        self.scale.len()
    }

    /// The `count` lowest damped modes at spin speed `omega` (rad/s), ascending in damped
    /// frequency, overdamped roots and roots with damping ratio above `max_damping_ratio`
    /// left out.
    ///
    /// # Errors
    /// [`Error::NotConverged`] when the eigen-solver does not converge at this speed.
    pub fn modes_at(
        &self,
        omega: f64,
        max_damping_ratio: f64,
        count: usize,
    ) -> Result<Vec<ComplexMode>> {
        let p = self.size();
        let a = Mat::<f64>::from_fn(2 * p, 2 * p, |i, j| match (i < p, j < p) {
            (true, true) => 0.0,
            (true, false) => {
                if i + p == j {
                    self.scale[i]
                } else {
                    0.0
                }
            }
            (false, true) => -self.k_scaled[(i - p, j)],
            (false, false) => -(self.c[(i - p, j - p)] + omega * self.g[(i - p, j - p)]),
        });
        let eig = a.eigen().map_err(|_| {
            Error::not_converged(
                "eigen-solver",
                None,
                None,
                format!(
                "the eigen-solver did not converge at {omega} rad/s; check the model's matrices"
            ),
            )
        })?;
        let values = eig.S().column_vector();
        let vectors = eig.U();
        let largest = (0..2 * p).map(|k| values[k].norm()).fold(0.0, f64::max);
        let mut roots = Vec::new();
        for k in 0..2 * p {
            let lambda = values[k];
            let norm = lambda.norm();
            // Keep one root of each complex pair; real roots (overdamped, or rigid-body
            // roots at 0) have no whirl frequency.
            if lambda.im <= 1e-9 * largest.max(1.0) || norm == 0.0 {
                continue;
            }
            let zeta = -lambda.re / norm;
            if zeta > max_damping_ratio {
                continue;
            }
            let coordinates: Vec<c64> = (0..p).map(|i| vectors[(i, k)] / self.scale[i]).collect();
            roots.push((lambda, zeta, coordinates));
        }
        let hz = |lambda: c64| lambda.im / (2.0 * std::f64::consts::PI);
        roots.sort_by(|a, b| hz(a.0).total_cmp(&hz(b.0)));
        // Physical shapes only for the modes returned: each costs DOFs x basis size.
        roots.truncate(count);
        Ok(roots
            .into_iter()
            .map(|(lambda, zeta, coordinates)| {
                let shape = self.physical(&coordinates);
                make_mode(lambda, zeta, coordinates, shape)
            })
            .collect())
    }

    fn physical(&self, coordinates: &[c64]) -> Vec<c64> {
        let phi = &self.shapes;
        let mut shape: Vec<c64> = (0..phi.nrows())
            .map(|i| {
                (0..coordinates.len())
                    .map(|j| coordinates[j] * phi[(i, j)])
                    .sum()
            })
            .collect();
        normalise(&mut shape);
        shape
    }
}

/// Phi^T K Phi, Phi^T C Phi and Phi^T G Phi on undamped modes Phi (M-orthonormal, with w^2
/// `lambda`) of a banded model. With the parts of K and C known (see
/// [`crate::fe::BandedSystem`]), the rotor's share comes from the modes' w^2 rather than
/// from its large entries: Phi^T K_sym Phi = Lambda, so
///
/// ```text
/// Phi^T K Phi = Lambda + Phi^T skew(K_s) Phi
/// Phi^T C Phi = alpha (I - Phi^T M_s Phi) + beta (Lambda - Phi^T sym(K_s) Phi) + Phi^T C_s Phi
/// ```
///
/// with K_s and C_s the bearings' and M_s the housings' mass (in M but not in the rotor's
/// Rayleigh damping). Without the parts the bands are projected as they are.
fn project_banded(system: &BandedSystem, phi: &Mat<f64>, lambda: &[f64]) -> [Mat<f64>; 3] {
    let g = system.gyroscopic.project(phi);
    let Some(parts) = &system.parts else {
        return [
            system.stiffness.project(phi),
            system.damping.project(phi),
            g,
        ];
    };
    let p = lambda.len();
    let supports = parts.support_stiffness.project(phi);
    let support_damping = parts.support_damping.project(phi);
    let housings = parts.support_mass.project(phi);
    let (alpha, beta) = parts.rayleigh;
    let diagonal = |i: usize, j: usize| if i == j { lambda[i] } else { 0.0 };
    let k = Mat::from_fn(p, p, |i, j| {
        diagonal(i, j) + 0.5 * (supports[(i, j)] - supports[(j, i)])
    });
    let c = Mat::from_fn(p, p, |i, j| {
        let identity = if i == j { 1.0 } else { 0.0 };
        let rotor = diagonal(i, j) - 0.5 * (supports[(i, j)] + supports[(j, i)]);
        alpha * (identity - housings[(i, j)]) + beta * rotor + support_damping[(i, j)]
    });
    [k, c, g]
}

/// Scales a shape so that its largest translation is 1 (real, positive).
fn normalise(shape: &mut [c64]) {
    let largest = shape
        .iter()
        .enumerate()
        .filter(|(i, _)| i % 4 < 2)
        .map(|(_, v)| *v)
        .max_by(|a, b| a.norm().total_cmp(&b.norm()));
    if let Some(v) = largest.filter(|v| v.norm() > 0.0) {
        let s = v.conj() / v.norm() / v.norm();
        shape.iter_mut().for_each(|x| *x *= s);
    }
}

fn make_mode(lambda: c64, zeta: f64, coordinates: Vec<c64>, shape: Vec<c64>) -> ComplexMode {
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut mode = ComplexMode {
        eigenvalue: (lambda.re, lambda.im),
        damped_frequency_hz: lambda.im / two_pi,
        natural_frequency_hz: lambda.norm() / two_pi,
        damping_ratio: zeta,
        log_decrement: two_pi * zeta / (1.0 - zeta * zeta).max(1e-300).sqrt(),
        whirl: Whirl::Mixed,
        shape,
        coordinates,
    };
    mode.whirl = classify_whirl(&mode);
    mode
}

/// Forward if every node that moves noticeably (orbit above 1 % of the largest) whirls
/// forward, backward if every such node whirls backward, mixed otherwise.
fn classify_whirl(mode: &ComplexMode) -> Whirl {
    let nodes = mode.shape.len() / 4;
    let radii: Vec<(f64, f64)> = (0..nodes).map(|n| mode.orbit_radii(n)).collect();
    let largest = radii.iter().map(|(f, b)| f + b).fold(0.0, f64::max);
    let (mut forward, mut backward) = (false, false);
    for &(f, b) in &radii {
        if f + b < 0.01 * largest {
            continue;
        }
        if f >= b {
            forward = true;
        } else {
            backward = true;
        }
    }
    match (forward, backward) {
        (true, false) => Whirl::Forward,
        (false, true) => Whirl::Backward,
        _ => Whirl::Mixed,
    }
}

/// Damped modes of the full system at spin speed `omega` (rad/s); see [`ModalBasis`].
///
/// # Errors
/// As [`ModalBasis::full`] and [`ModalBasis::modes_at`].
pub fn complex_modes(system: &impl Matrices, omega: f64) -> Result<Vec<ComplexMode>> {
    let basis = ModalBasis::full(system)?;
    basis.modes_at(omega, 1.0, 2 * basis.size())
}
