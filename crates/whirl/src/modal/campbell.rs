//! Campbell diagram: damped whirl frequencies versus spin speed (thesis fig. 2.11).
//!
//! Branches are followed from speed to speed by mode-shape correlation (the complex modal
//! assurance criterion, mass-weighted in the modal basis), not by sorting, so that a
//! forward branch crossing a backward one stays itself. The complex MAC of a forward and a
//! backward circular whirl of the same shape is zero, which keeps the two apart.
//!
//! At exactly zero speed an isotropic rotor has double roots whose eigenvectors are any
//! mix of the two planes; the solve there uses a tiny speed (1e-6 of the largest, at least
//! 1e-3 rad/s) so that the forward and backward shapes are already separated. The
//! frequency error this makes is below 1e-8 relative.
//!
//! Critical speeds: where a branch crosses an excitation line f = k Omega / 2 pi, found by
//! a sign change between two speeds and linear interpolation.

mod report;
mod request;

pub use report::CampbellSummary;
pub use request::{
    CampbellRequest, DEFAULT_BRANCHES, DEFAULT_CAMPBELL_SPEEDS, DEFAULT_ORDER, MAX_ORDER,
};

use serde::Serialize;

use super::complex::{ComplexMode, ModalBasis, Whirl};
use crate::error::{Error, Result};
use crate::fe::Matrices;
use crate::progress::{map_told, Progress};

/// Options of a Campbell diagram.
#[derive(Debug, Clone)]
pub struct CampbellOptions {
    /// Spin speeds, rad/s, ascending.
    pub speeds: Vec<f64>,
    /// Number of whirl branches to follow.
    pub modes: usize,
    /// Excitation orders whose crossings are critical speeds (1 = synchronous).
    pub orders: Vec<f64>,
    /// Size of the modal basis; `None` solves the full system at every speed.
    pub basis_size: Option<usize>,
    /// Roots more damped than this are left out (overdamped or spurious).
    pub max_damping_ratio: f64,
}

impl CampbellOptions {
    /// Defaults: 8 branches, 1X, zeta <= 0.9, and a basis of the 2 x 8 + 8 lowest undamped
    /// modes (see [`CampbellOptions::default_basis`]).
    pub fn new(speeds: Vec<f64>) -> Self {
        CampbellOptions {
            speeds,
            modes: DEFAULT_BRANCHES,
            orders: vec![DEFAULT_ORDER],
            basis_size: Some(Self::default_basis(DEFAULT_BRANCHES)),
            max_damping_ratio: 0.9,
        }
    }

    /// Basis size for following `modes` branches: twice as many undamped modes plus eight,
    /// which kept every branch of the reference rotors within 2e-4 of the full solve
    /// (tests/suite/campbell.rs).
    pub fn default_basis(modes: usize) -> usize {
        2 * modes + 8
    }
}

/// One followed branch.
#[derive(Debug, Clone, Serialize)]
pub struct ModeBranch {
    /// Branch number, 0-based, ordered by frequency at the first speed.
    pub index: usize,
    /// Whirl direction at the highest speed (where it is best defined).
    pub whirl: Whirl,
    /// Damped frequency at each speed, Hz (NaN where the branch was lost).
    pub frequency_hz: Vec<f64>,
    /// Damping ratio at each speed.
    pub damping_ratio: Vec<f64>,
    /// Logarithmic decrement at each speed.
    pub log_decrement: Vec<f64>,
    /// Whirl direction at each speed.
    pub whirl_at: Vec<Whirl>,
}

/// A crossing of a branch with an excitation line.
#[derive(Debug, Clone, Serialize)]
pub struct CriticalSpeed {
    /// Spin speed, Hz.
    pub speed_hz: f64,
    /// Spin speed, rpm.
    pub speed_rpm: f64,
    /// Whirl frequency there, Hz.
    pub frequency_hz: f64,
    /// Excitation order.
    pub order: f64,
    /// Branch index.
    pub branch: usize,
    /// Whirl direction of the branch there.
    pub whirl: Whirl,
    /// Damping ratio of the branch there.
    pub damping_ratio: f64,
}

/// A Campbell diagram.
#[derive(Debug, Clone, Serialize)]
pub struct CampbellResult {
    /// Spin speeds, Hz.
    pub speeds_hz: Vec<f64>,
    /// Followed branches.
    pub branches: Vec<ModeBranch>,
    /// Excitation orders.
    pub orders: Vec<f64>,
    /// Critical speeds, ascending.
    pub critical_speeds: Vec<CriticalSpeed>,
    /// Size of the modal basis used (the DOF count when solved in full).
    pub basis_size: usize,
}

/// Computes a Campbell diagram, telling `progress` after every speed.
///
/// # Errors
/// [`Error::InvalidOption`] for no speeds, more than
/// [`MAX_RANGE_COUNT`](crate::units::MAX_RANGE_COUNT), or speeds that are not ascending; the errors of
/// [`ModalBasis::truncated`] and [`ModalBasis::modes_at`]; [`Error::Interrupted`] when
/// `progress` stopped it.
pub fn campbell(
    system: &impl Matrices,
    options: &CampbellOptions,
    progress: Option<&Progress>,
) -> Result<CampbellResult> {
    if options.speeds.is_empty() {
        return Err(Error::InvalidOption(
            "a Campbell diagram needs at least one speed".into(),
        ));
    }
    crate::units::check_count(options.speeds.len(), "Campbell speeds")?;
    if options.speeds.windows(2).any(|w| w[1] < w[0]) {
        return Err(Error::InvalidOption(
            "Campbell speeds must be ascending".into(),
        ));
    }
    let basis = match options.basis_size {
        Some(p) if p < system.dofs() => ModalBasis::truncated(system, p, progress)?,
        _ => ModalBasis::full(system)?,
    };
    let top = options.speeds.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    let floor = (1e-6 * top).max(1e-3);
    // A few more roots than branches, so that a branch can be found again after a crossing
    // with a mode that was not among the first ones.
    let wanted = options.modes + 4;
    let count = options.speeds.len();
    let per_speed: Vec<Vec<ComplexMode>> = map_told(
        &options.speeds,
        progress,
        (0, count),
        ("the Campbell diagram", "speeds"),
        |&w| {
            let w = if w.abs() < floor { floor } else { w };
            basis
                .modes_at(w, options.max_damping_ratio, wanted)
                .map(|mut modes| {
                    // Tracking needs the basis coordinates only; the physical shapes of
                    // every speed would take speeds x modes x DOFs memory (1.2 GB for 161
                    // speeds of a 10,000-element rotor).
                    modes.iter_mut().for_each(|m| m.shape = Vec::new());
                    modes
                })
        },
    )?;
    let branches = track(&per_speed, options.modes);
    let speeds_hz: Vec<f64> = options
        .speeds
        .iter()
        .map(|w| w / (2.0 * std::f64::consts::PI))
        .collect();
    let critical_speeds = critical_speeds(&speeds_hz, &branches, &options.orders);
    Ok(CampbellResult {
        speeds_hz,
        branches,
        orders: options.orders.clone(),
        critical_speeds,
        basis_size: basis.size(),
    })
}

/// Complex MAC: |a^H b|^2 / (|a|^2 |b|^2).
fn mac(a: &[faer::c64], b: &[faer::c64]) -> f64 {
    let dot: faer::c64 = a.iter().zip(b).map(|(x, y)| x.conj() * y).sum();
    let na: f64 = a.iter().map(|x| x.norm_sqr()).sum();
    let nb: f64 = b.iter().map(|x| x.norm_sqr()).sum();
    if na == 0.0 || nb == 0.0 {
        0.0
    } else {
        dot.norm_sqr() / (na * nb)
    }
}

/// Follows `count` branches through the speeds by greedy best-MAC assignment.
fn track(per_speed: &[Vec<ComplexMode>], count: usize) -> Vec<ModeBranch> {
    let speeds = per_speed.len();
    let count = count.min(per_speed[0].len());
    let mut branches: Vec<ModeBranch> = (0..count)
        .map(|index| ModeBranch {
            index,
            whirl: Whirl::Mixed,
            frequency_hz: vec![f64::NAN; speeds],
            damping_ratio: vec![f64::NAN; speeds],
            log_decrement: vec![f64::NAN; speeds],
            whirl_at: vec![Whirl::Mixed; speeds],
        })
        .collect();
    // The last shape seen of each branch.
    let mut last: Vec<Option<Vec<faer::c64>>> = vec![None; count];
    for (s, modes) in per_speed.iter().enumerate() {
        let assignment = if s == 0 {
            (0..count).map(Some).collect()
        } else {
            assign(&last, modes)
        };
        for (b, pick) in assignment.into_iter().enumerate() {
            if let Some(k) = pick {
                let m = &modes[k];
                let br = &mut branches[b];
                br.frequency_hz[s] = m.damped_frequency_hz;
                br.damping_ratio[s] = m.damping_ratio;
                br.log_decrement[s] = m.log_decrement;
                br.whirl_at[s] = m.whirl;
                last[b] = Some(m.coordinates.clone());
            }
        }
    }
    for br in &mut branches {
        if let Some(s) = (0..speeds).rev().find(|&s| br.frequency_hz[s].is_finite()) {
            br.whirl = br.whirl_at[s];
        }
    }
    branches
}

/// Pairs each branch with a mode of the new speed: highest MAC first, each mode used once.
/// A branch whose best remaining match correlates below 0.5 is lost at this speed.
fn assign(last: &[Option<Vec<faer::c64>>], modes: &[ComplexMode]) -> Vec<Option<usize>> {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (b, shape) in last.iter().enumerate() {
        if let Some(shape) = shape {
            for (k, m) in modes.iter().enumerate() {
                pairs.push((mac(shape, &m.coordinates), b, k));
            }
        }
    }
    pairs.sort_by(|x, y| y.0.total_cmp(&x.0));
    let mut out = vec![None; last.len()];
    let mut used = vec![false; modes.len()];
    for (value, b, k) in pairs {
        if value < 0.5 || out[b].is_some() || used[k] {
            continue;
        }
        out[b] = Some(k);
        used[k] = true;
    }
    out
}

fn critical_speeds(
    speeds_hz: &[f64],
    branches: &[ModeBranch],
    orders: &[f64],
) -> Vec<CriticalSpeed> {
    let mut out = Vec::new();
    for br in branches {
        for &order in orders {
            for s in 1..speeds_hz.len() {
                let (f0, f1) = (br.frequency_hz[s - 1], br.frequency_hz[s]);
                if !(f0.is_finite() && f1.is_finite()) {
                    continue;
                }
                let g0 = f0 - order * speeds_hz[s - 1];
                let g1 = f1 - order * speeds_hz[s];
                if g0 > 0.0 && g1 <= 0.0 {
                    let t = g0 / (g0 - g1);
                    let speed = speeds_hz[s - 1] + t * (speeds_hz[s] - speeds_hz[s - 1]);
                    let zeta = br.damping_ratio[s - 1]
                        + t * (br.damping_ratio[s] - br.damping_ratio[s - 1]);
                    out.push(CriticalSpeed {
                        speed_hz: speed,
                        speed_rpm: speed * 60.0,
                        frequency_hz: order * speed,
                        order,
                        branch: br.index,
                        whirl: br.whirl_at[s],
                        damping_ratio: zeta,
                    });
                }
            }
        }
    }
    out.sort_by(|a, b| a.speed_hz.total_cmp(&b.speed_hz));
    out
}
