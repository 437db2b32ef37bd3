//! Undamped critical-speed map (API 684): the lowest critical speeds against a bearing
//! stiffness that every bearing shares, swept over decades, and where the bearings' own
//! stiffness cuts the curves.
//!
//! With every bearing isotropic (k in x and y, no cross-coupling, no damping) the x and y
//! planes are alike, so one plane, the DOFs (ux, ty) of every node, carries the problem. A
//! critical speed is a spin speed equal to a forward whirl frequency. In forward circular
//! whirl at w the other plane follows as uy = -i ux, tx = i ty, and the gyroscopic moments
//! of spin Omega enter the plane as w Omega G_p with G_p[a, ux_j] = G[a, uy_j],
//! G_p[a, ty_j] = -G[a, tx_j] (a disk's I_p on its ty). At Omega = w:
//!
//! ```text
//! K_p v = w^2 (M_p - G_p) v        (synchronous; a disk's I_d becomes I_d - I_p)
//! K_p v = w^2 M_p v                (at rest, without gyroscopic moments)
//! ```
//!
//! M_p - G_p need not be positive definite (a thin disk has I_p > I_d, and its rocking mode
//! has no forward critical speed; the shaft's own polar inertia, twice its diametral, does the
//! same in every element), but K_p is once every bearing has k > 0, so the pencil is solved
//! as M_eff v = mu K_p v with w = 1 / sqrt(mu) for each mu > 0. With K_p as the inner
//! product this is a definite problem, whatever the sign of M_eff: K_p^-1 M_eff is
//! self-adjoint in it, its roots real. A small plane ([`super::solves_dense`]) has every
//! root from the dense solver (Cholesky of K_p); a larger one the largest mu from subspace
//! iteration on the bands in K_p's inner product ([`super::subspace::largest_roots`]), at a
//! cost linear in the elements.

mod report;
mod request;

pub use report::{BearingCut, CriticalSpeedSummary};
pub use request::{stiffness_range, UcsRequest, DEFAULT_UCS_MODES, MAX_STIFFNESSES};

use serde::Serialize;

use super::{solves_dense, subspace, symmetric_modes};
use crate::error::{Error, Result};
use crate::fe::{
    assemble_banded, dof, too_large_for_dense, Bearings, Direction, DOFS_PER_NODE, HALF_BANDWIDTH,
    MAX_DENSE_DOFS,
};
use crate::linalg::Band;
use crate::model::Model;
use crate::progress::{map_told, Progress};

/// A bearing's actual stiffness, drawn over the map.
#[derive(Debug, Clone, Serialize)]
pub struct BearingStiffness {
    /// Bearing name and direction, e.g. `bearing A kxx`.
    pub label: String,
    /// Stiffness, N/m.
    pub stiffness: f64,
    /// The critical speeds where this stiffness cuts the curves (log-log interpolation),
    /// Hz, one per mode; `None` where it lies outside the sweep or a curve is missing.
    pub critical_speeds_hz: Vec<Option<f64>>,
}

/// The critical-speed map.
#[derive(Debug, Clone, Serialize)]
pub struct CriticalSpeedMap {
    /// Bearing stiffnesses swept, N/m, ascending.
    pub stiffness: Vec<f64>,
    /// Critical speeds, Hz: `critical_speeds_hz[mode][k]`, NaN where a mode has none.
    pub critical_speeds_hz: Vec<Vec<f64>>,
    /// Whether the gyroscopic moments of synchronous spin were included.
    pub synchronous: bool,
    /// The model's bearings' own stiffnesses.
    pub bearings: Vec<BearingStiffness>,
}

/// Stiffnesses of a map when none are given: 61, spaced logarithmically over two decades
/// either side of the bearings' own stiffnesses (linear bearings' k_xx and k_yy, roller
/// bearings' linear stiffness), widened to whole decades; 1e5 to 1e10 N/m without any.
pub fn default_stiffnesses(model: &Model) -> Vec<f64> {
    let ks: Vec<f64> = model
        .bearings
        .iter()
        .flat_map(|b| [b.stiffness[0][0], b.stiffness[1][1]])
        .chain(model.roller_bearings.iter().map(|b| b.linear_stiffness))
        .filter(|k| *k > 0.0)
        .collect();
    let lo = ks.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = ks.iter().copied().fold(0.0, f64::max);
    let (lo, hi) = if lo.is_finite() && hi > 0.0 {
        ((lo / 100.0).log10().floor(), (hi * 100.0).log10().ceil())
    } else {
        (5.0, 10.0)
    };
    log_space(10f64.powf(lo), 10f64.powf(hi), 61)
}

/// `count` (2 or more) values from `lo` to `hi` (both positive), evenly spaced in their
/// logarithm.
pub fn log_space(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    let (a, b) = (lo.log10(), hi.log10());
    (0..count)
        .map(|i| 10f64.powf(a + (b - a) * i as f64 / (count - 1) as f64))
        .collect()
}

/// The map over `stiffness` (N/m, positive), `modes` curves; the stiffnesses in parallel,
/// `progress` told after each.
///
/// # Errors
/// [`Error::InvalidOption`] for a stiffness that is not positive, [`Error::Unsupported`]
/// for a model without bearings, or above [`crate::fe::MAX_DENSE_DOFS`] when `modes` asks
/// for the dense solver (a quarter of the plane's DOFs or more), [`Error::Singular`] when the
/// rotor is not held, [`Error::NotConverged`] when the iteration fails, [`Error::Interrupted`]
/// when `progress` stopped it.
pub fn critical_speed_map(
    model: &Model,
    stiffness: &[f64],
    modes: usize,
    synchronous: bool,
    progress: Option<&Progress>,
) -> Result<CriticalSpeedMap> {
    if model.bearings.is_empty() && model.roller_bearings.is_empty() {
        return Err(Error::Unsupported(
            "the critical-speed map needs bearings: the model has none".into(),
        ));
    }
    if let Some(h) = model.housings.first() {
        return Err(Error::Unsupported(format!(
            "the critical-speed map sweeps the stiffness of bearings on the ground; the model              has housings (\"{}\"), whose mass and mounting the map would leave out: use \
             the Campbell diagram instead",
            h.name
        )));
    }
    if let Some(k) = stiffness.iter().find(|k| !(k.is_finite() && **k > 0.0)) {
        return Err(Error::InvalidOption(format!(
            "bearing stiffness {k} N/m: the map needs positive stiffnesses"
        )));
    }
    let per_stiffness = map_told(
        stiffness,
        progress,
        (0, stiffness.len()),
        ("the critical-speed map", "stiffnesses"),
        |&k| critical_speeds(model, k, modes, synchronous),
    )?;
    let mut curves = vec![Vec::with_capacity(stiffness.len()); modes];
    for speeds in per_stiffness {
        for (m, curve) in curves.iter_mut().enumerate() {
            curve.push(speeds.get(m).copied().unwrap_or(f64::NAN));
        }
    }
    let mut bearings = Vec::new();
    for b in &model.bearings {
        for (dir, k) in [("kxx", b.stiffness[0][0]), ("kyy", b.stiffness[1][1])] {
            bearings.push((format!("{} {dir}", b.name), k));
        }
    }
    for b in &model.roller_bearings {
        bearings.push((format!("{} linear", b.name), b.linear_stiffness));
    }
    let bearings = bearings
        .into_iter()
        .map(|(label, k)| BearingStiffness {
            label,
            stiffness: k,
            critical_speeds_hz: curves
                .iter()
                .map(|c| log_interpolate(stiffness, c, k))
                .collect(),
        })
        .collect();
    Ok(CriticalSpeedMap {
        stiffness: stiffness.to_vec(),
        critical_speeds_hz: curves,
        synchronous,
        bearings,
    })
}

/// The lowest `modes` critical speeds (Hz) with every bearing of stiffness `k`.
fn critical_speeds(model: &Model, k: f64, modes: usize, synchronous: bool) -> Result<Vec<f64>> {
    let pencil = plane_pencil(model, k, synchronous);
    let not_held = || {
        Error::singular(
            "stiffness matrix",
            format!(
                "with every bearing at {k:.3e} N/m the stiffness is not positive definite: the \
             rotor needs bearings at two nodes at least"
            ),
        )
    };
    let mu = if solves_dense(pencil.stiffness.size(), modes) {
        let dofs = model.dof_count();
        if dofs > MAX_DENSE_DOFS {
            return Err(too_large_for_dense(
                dofs,
                "the critical-speed map solves every root when a quarter of the plane's DOFs \
                 or more are asked for; ask for fewer modes",
            ));
        }
        pencil.dense_roots(modes).map_err(|_| not_held())?
    } else {
        pencil.banded_roots(modes, not_held)?
    };
    Ok(mu
        .iter()
        .map(|m| 1.0 / m.sqrt() / (2.0 * std::f64::consts::PI))
        .collect())
}

/// The plane problem M_eff v = mu K_p v of the module's doc, as bands over the DOFs (ux, ty)
/// of every node in turn.
struct PlanePencil {
    /// K_p, N/m (N m/rad on the tilts).
    stiffness: Band,
    /// M_eff = M_p - G_p (M_p at rest), kg (kg m^2 on the tilts).
    effective_mass: Band,
}

/// The plane pencil of `model` with every bearing isotropic of stiffness `k` and undamped.
fn plane_pencil(model: &Model, k: f64, synchronous: bool) -> PlanePencil {
    let mut m = model.clone();
    for b in &mut m.bearings {
        b.stiffness = [[k, 0.0], [0.0, k]];
        b.damping = [[0.0; 2]; 2];
    }
    for b in &mut m.roller_bearings {
        b.linear_stiffness = k;
        b.linear_damping = 0.0;
    }
    let s = assemble_banded(&m, Bearings::Linearised);
    let nodes = m.node_count();
    let plane: Vec<usize> = (0..nodes)
        .flat_map(|n| [dof(n, Direction::Ux), dof(n, Direction::Ty)])
        .collect();
    // The partner of each plane DOF in the other plane, and the sign of i it carries.
    let partner: Vec<(usize, f64)> = (0..nodes)
        .flat_map(|n| [(dof(n, Direction::Uy), 1.0), (dof(n, Direction::Tx), -1.0)])
        .collect();
    // Plane DOFs come from full DOFs within the assembly's half-bandwidth, so from nodes at
    // most `reach` apart, and lie within `width` of each other.
    let reach = HALF_BANDWIDTH.div_ceil(DOFS_PER_NODE);
    let width = 2 * reach + 1;
    let p = plane.len();
    PlanePencil {
        stiffness: Band::from_fn(p, (width, width), |a, b| {
            s.stiffness.get(plane[a], plane[b])
        }),
        effective_mass: Band::from_fn(p, (width, width), |a, b| {
            let gyro = if synchronous {
                partner[b].1 * s.gyroscopic.get(plane[a], partner[b].0)
            } else {
                0.0
            };
            s.mass.get(plane[a], plane[b]) - gyro
        }),
    }
}

impl PlanePencil {
    /// The `modes` largest positive mu, descending, from every root by the dense solver.
    fn dense_roots(&self, modes: usize) -> Result<Vec<f64>> {
        let (kp, meff) = (self.stiffness.to_dense(), self.effective_mass.to_dense());
        let (mu, _) = symmetric_modes(&meff, &kp, kp.nrows())?;
        Ok(mu
            .into_iter()
            .rev()
            .filter(|&m| m > 0.0)
            .take(modes)
            .collect())
    }

    /// The `modes` largest positive mu, descending, by subspace iteration on the bands
    /// (their symmetric parts, as the dense solver takes them); `not_held()` when K_p is not
    /// positive definite.
    fn banded_roots(&self, modes: usize, not_held: impl FnOnce() -> Error) -> Result<Vec<f64>> {
        let symmetric = |b: &Band| b.map(|i, j, v| 0.5 * (v + b.get(j, i)));
        subspace::largest_roots(
            &symmetric(&self.effective_mass),
            &symmetric(&self.stiffness),
            modes,
            not_held,
        )
    }
}

/// `y` at `x` by linear interpolation of log y over log x; `None` outside `xs` or where `y`
/// is missing.
fn log_interpolate(xs: &[f64], ys: &[f64], x: f64) -> Option<f64> {
    let j = xs.windows(2).position(|w| w[0] <= x && x <= w[1])?;
    let (x0, x1, y0, y1) = (xs[j], xs[j + 1], ys[j], ys[j + 1]);
    if !(y0 > 0.0 && y1 > 0.0) {
        return None;
    }
    let t = (x / x0).ln() / (x1 / x0).ln();
    Some((y0.ln() + t * (y1 / y0).ln()).exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest absolute row sum of a band: a bound on its 2-norm.
    fn norm(b: &Band) -> f64 {
        let (lower, upper) = b.widths();
        (0..b.size())
            .map(|i| {
                (i.saturating_sub(lower)..(i + upper + 1).min(b.size()))
                    .map(|j| b.get(i, j).abs())
                    .sum::<f64>()
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn subspace_iteration_finds_the_dense_solvers_critical_speeds() {
        // 160 elements: 322 plane DOFs, past the dense limit, so the map iterates on the
        // bands; the dense solver takes every root of the same pencil for comparison. In
        // synchronous whirl the disk's I_p = 2 I_d and the shaft's own polar inertia make
        // M_eff indefinite.
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None)
            .unwrap()
            .remeshed(&[160])
            .unwrap();
        for synchronous in [true, false] {
            for k in [1e4, 1e6, 1e8, 1e10, 1e12] {
                let pencil = plane_pencil(&model, k, synchronous);
                assert!(!solves_dense(pencil.stiffness.size(), 6));
                let banded = pencil
                    .banded_roots(6, || Error::Unsupported("not held".into()))
                    .unwrap();
                let (kp, meff) = (
                    pencil.stiffness.to_dense(),
                    pencil.effective_mass.to_dense(),
                );
                let (mu, shapes) = symmetric_modes(&meff, &kp, kp.nrows()).unwrap();
                let n = mu.len();
                // The pencil the iteration must cope with: indefinite in synchronous whirl.
                assert_eq!(mu[0] < 0.0, synchronous);
                assert_eq!(banded.len(), 6);
                for (j, b) in banded.iter().enumerate() {
                    let (d, x) = (mu[n - 1 - j], shapes.col(n - 1 - j));
                    // Both solvers are backward stable: each root is exact for K_p and
                    // M_eff perturbed by some eps of their norms, which moves mu by
                    // eps (|K_p| |x|^2 / x^T K_p x + |M_eff| |x|^2 / |x^T M_eff x|) to first
                    // order. The bound is large where a mode's x^T K_p x / |x|^2 is small
                    // against |K_p|: the rigid modes on 1e4 N/m bearings (1e4 N/m spread over
                    // 161 nodes against the elements' 2e12 N/m; bound 1.6e-5). Measured: the
                    // two differ by at most 0.05 of the bound (7.8e-7 there, 4e-9 or less on
                    // 1e6 N/m bearings or stiffer).
                    let xx = x.squared_norm_l2();
                    let bound = f64::EPSILON
                        * (norm(&pencil.stiffness) * xx / (x.transpose() * &kp * x)
                            + norm(&pencil.effective_mass) * xx
                                / (x.transpose() * &meff * x).abs());
                    let error = (b / d - 1.0).abs();
                    assert!(error <= bound, "k = {k} N/m, root {j}: {b} vs {d}");
                }
            }
        }
    }
}
