//! Equivalent stiffness of a roller bearing and its force-deflection surfaces (thesis
//! section 3.4, eqs. 3.20-3.25; docs/theory.md section 5).
//!
//! With the cage held still and no damping, the bearing's force on the journal depends on
//! the journal displacement u = (u_x, u_y) alone (eq. 3.20, with the sign of the force on
//! the shaft):
//!
//! ```text
//! F(u) = -sum_j K_c delta_j^n g_j,   delta_j = g_j . u - gamma_0,   g_j = (cos theta_j, sin theta_j)
//! K(u) = -dF/du = sum_j n K_c delta_j^(n-1) g_j g_j^T      (eq. 3.25, rollers with delta_j > 0)
//! ```
//!
//! so K is symmetric (k_xy = k_yx, as the thesis notes). This module gives K three ways:
//!
//! - at a given displacement ([`FrozenBearing::tangent`]): eq. 3.25 as printed;
//! - at the static equilibrium F(u) + W = 0 under the load W the rotor puts on the bearing,
//!   cage frozen ([`FrozenBearing::equilibrium`]);
//! - averaged over one roller passage ([`passage_average`]): the cage is turned through one
//!   roller pitch 2 pi / N_b, the equilibrium solved again at each position, and the
//!   tangents averaged. The rotor meets every cage position at the same rate, so this is the
//!   stiffness a slowly turning rotor feels on average; its spread is the varying compliance.
//!
//! Why three: with one roller on the load line and its neighbours clear (every clearance
//! above a few um for the reference bearing under its share of the rotor weight), the
//! equilibrium is statically determinate. That roller carries the whole load,
//! delta = (W / K_c)^(1/n), u = -(gamma_0 + delta) along the load, and k = n K_c
//! delta^(n-1): the tangent does not depend on the clearance at all. Two rollers in contact
//! are determinate too (two contact forces, two equations), so the equilibrium stiffness,
//! frozen or averaged, depends on the clearance only where three or more rollers share the
//! load: at clearances comparable to the Hertz deflection, or under large loads
//! ([`PassageAverage::most_rollers`] tells). At a fixed displacement a smaller clearance
//! always presses more rollers harder, so there the stiffness falls with clearance
//! (docs/theory-errata.md has the numbers).
//!
//! The equivalent stiffness is that of the round bearing: ring waviness and race defects (a
//! forcing, not a stiffness) and contact damping are left out, and with roller tilt only the
//! translational block of eq. 3.22-3.23 is computed (the thesis ignores the angular one). Roller skew,
//! a constant part of each slice's approach, is kept.

mod report;
mod request;

pub use report::{clearance_label, StiffnessReport, StiffnessSummary};
pub use request::{
    stiffness_report, StiffnessRequest, DEFAULT_CAGE_STEPS, DEFAULT_CLEARANCES, DEFAULT_GRID,
    DEFAULT_LOAD_ANGLE_DEG, DEFAULT_SURFACE_CLEARANCES,
};

use std::f64::consts::PI;

use faer::Mat;
use serde::Serialize;

use super::hertz::HertzBearing;
use crate::error::{Error, InputError, Result};
use crate::fe::{assemble_dense, dof, gravity_force, Bearings, Direction};
use crate::force::{Kinematics, NonlinearForce};
use crate::model::{Clearance, Model, RollerBearing};

/// Equilibria stop when the force balance is met to this fraction of the load. Round-off in
/// the sum over rollers is about 1e-15 of the load; 1e-11 leaves room for it and is far
/// below anything a stiffness depends on.
const BALANCE_TOLERANCE: f64 = 1e-11;

/// Newton iterations before an equilibrium is given up. From the Hertz start a few steps
/// suffice; a fall through the clearance with the Levenberg-Marquardt shift takes tens.
const MAX_ITERATIONS: usize = 200;

/// First Levenberg-Marquardt shift, as a fraction of the Hertz stiffness of the load. Small
/// enough that a shifted step is nearly Newton's, large enough to bridge a singular tangent.
const FIRST_SHIFT: f64 = 1e-6;

/// A shift this large (a step of ~1e-12 of Newton's) means no progress is possible.
const LARGEST_SHIFT: f64 = 1e12;

/// A 2x2 translational stiffness, N/m: force on the bearing per journal displacement,
/// K = -dF/du with F the bearing's force on the shaft.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Stiffness2 {
    /// dF_x/du_x, negated.
    pub kxx: f64,
    /// dF_x/du_y, negated.
    pub kxy: f64,
    /// dF_y/du_x, negated.
    pub kyx: f64,
    /// dF_y/du_y, negated.
    pub kyy: f64,
}

impl Stiffness2 {
    fn from_rows(k: [[f64; 2]; 2]) -> Self {
        Stiffness2 {
            kxx: k[0][0],
            kxy: k[0][1],
            kyx: k[1][0],
            kyy: k[1][1],
        }
    }

    /// Entry by entry with `f`.
    fn zip(&self, other: &Stiffness2, f: impl Fn(f64, f64) -> f64) -> Stiffness2 {
        Stiffness2 {
            kxx: f(self.kxx, other.kxx),
            kxy: f(self.kxy, other.kxy),
            kyx: f(self.kyx, other.kyx),
            kyy: f(self.kyy, other.kyy),
        }
    }

    /// Every entry times `s`.
    fn scaled(&self, s: f64) -> Stiffness2 {
        self.zip(self, |a, _| a * s)
    }
}

/// A roller that carries load.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LoadedRoller {
    /// Roller index, 0-based (roller 0 sits at the cage angle).
    pub index: usize,
    /// Roller angle theta_j, rad from +x towards +y.
    pub angle: f64,
    /// Approach delta_j (penetration), m.
    pub approach: f64,
    /// Contact force, N.
    pub force: f64,
}

/// Force and tangent stiffness of the frozen bearing at one journal displacement.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Tangent {
    /// Journal displacement (u_x, u_y) relative to the housing, m.
    pub displacement: [f64; 2],
    /// Force of the bearing on the shaft (F_x, F_y), N.
    pub force: [f64; 2],
    /// Tangent stiffness -dF/du, N/m (eq. 3.25).
    pub stiffness: Stiffness2,
    /// The rollers in contact.
    pub rollers: Vec<LoadedRoller>,
}

/// The static equilibrium F(u) + W = 0 of the frozen bearing under a load.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Equilibrium {
    /// Load W the rotor puts on the bearing (W_x, W_y), N.
    pub load: [f64; 2],
    /// Angle of roller 0, rad.
    pub cage_angle: f64,
    /// Displacement, force, stiffness and loaded rollers at the equilibrium.
    pub tangent: Tangent,
    /// Newton iterations taken.
    pub iterations: usize,
    /// |F(u) + W| / |W| at the solution.
    pub relative_residual: f64,
}

/// One cage position of a roller passage.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PassageSample {
    /// Angle of roller 0, rad.
    pub cage_angle: f64,
    /// Equilibrium displacement, m.
    pub displacement: [f64; 2],
    /// Tangent stiffness there, N/m.
    pub stiffness: Stiffness2,
    /// Indices of the rollers in contact.
    pub rollers: Vec<usize>,
}

/// The equilibrium stiffness over one roller passage.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PassageAverage {
    /// Mean tangent stiffness over the passage, N/m.
    pub mean: Stiffness2,
    /// Smallest value of each entry over the passage, N/m.
    pub min: Stiffness2,
    /// Largest value of each entry over the passage, N/m.
    pub max: Stiffness2,
    /// Mean equilibrium displacement, m.
    pub mean_displacement: [f64; 2],
    /// The most rollers in contact at any cage position. At most 2 means every equilibrium
    /// of the passage is statically determinate, and then its stiffness does not depend on
    /// the clearance.
    pub most_rollers: usize,
    /// Each cage position, in order.
    pub samples: Vec<PassageSample>,
}

/// The three stiffnesses of one clearance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClearanceStiffness {
    /// Internal radial clearance gamma_0, m.
    pub clearance: f64,
    /// Static equilibrium under the load with the cage frozen.
    pub frozen: Equilibrium,
    /// Equilibrium stiffness averaged over one roller passage.
    pub averaged: PassageAverage,
    /// Tangent at the study's fixed displacement (frozen cage).
    pub fixed: Tangent,
}

/// What [`stiffness_versus_clearance`] computes.
#[derive(Debug, Clone, PartialEq)]
pub struct StiffnessOptions {
    /// Clearances, m, each non-negative.
    pub clearances: Vec<f64>,
    /// Load W the rotor puts on the bearing, N (not zero).
    pub load: [f64; 2],
    /// Angle of roller 0 for the frozen cage, rad; `None` puts roller 0 on the load line
    /// (at the bottom under gravity, docs/theory.md section 5).
    pub cage_angle: Option<f64>,
    /// Cage positions per roller passage for the average (at least 1).
    pub cage_steps: usize,
    /// Displacement for the fixed-displacement stiffness, m; `None` takes the frozen-cage
    /// equilibrium displacement at the largest clearance, where that bearing carries the
    /// load; smaller clearances are then pressed harder at the same journal position.
    pub fixed_displacement: Option<[f64; 2]>,
}

/// Equivalent stiffness versus clearance: all three kinds at every clearance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StiffnessStudy {
    /// Bearing name.
    pub bearing: String,
    /// Load W, N.
    pub load: [f64; 2],
    /// Angle of roller 0 for the frozen cage, rad.
    pub cage_angle: f64,
    /// Cage positions per roller passage.
    pub cage_steps: usize,
    /// Displacement of the fixed-displacement stiffness, m.
    pub fixed_displacement: [f64; 2],
    /// One entry per clearance, in the order given.
    pub clearances: Vec<ClearanceStiffness>,
}

/// Force-deflection surfaces F_x, F_y, F_r over a grid of displacements (eqs. 3.20-3.21,
/// figs. 3.8-3.9), cage frozen.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForceSurface {
    /// Clearance, m.
    pub clearance: f64,
    /// Angle of roller 0, rad.
    pub cage_angle: f64,
    /// Grid abscissae u_x, m.
    pub ux: Vec<f64>,
    /// Grid ordinates u_y, m.
    pub uy: Vec<f64>,
    /// Force of the bearing on the shaft along x, N; `fx[j][i]` at `(ux[i], uy[j])`.
    pub fx: Vec<Vec<f64>>,
    /// Force along y, N.
    pub fy: Vec<Vec<f64>>,
    /// Radial force sqrt(F_x^2 + F_y^2), N (eq. 3.21).
    pub fr: Vec<Vec<f64>>,
    /// Number of rollers in contact.
    pub contacts: Vec<Vec<usize>>,
}

/// A roller bearing with its cage held at one angle, at rest, without damping: its contact
/// force is a function of the journal displacement alone.
#[derive(Debug, Clone)]
pub struct FrozenBearing {
    hertz: HertzBearing,
    clearance: f64,
    contact_stiffness: f64,
    exponent: f64,
}

/// The bearing at rest: spin angle 0 puts roller 0 at the cage angle.
const AT_REST: Kinematics = Kinematics {
    time: 0.0,
    speed: 0.0,
    angle: 0.0,
};

impl FrozenBearing {
    /// `bearing` with clearance `clearance` (m) and roller 0 at `cage_angle` (rad).
    ///
    /// # Errors
    /// [`Error::Input`] naming `clearance` when `clearance` is negative, not finite, or not
    /// smaller than the rollers (as a model file's clearance must be).
    pub fn new(bearing: &RollerBearing, clearance: f64, cage_angle: f64) -> Result<Self> {
        if !(clearance.is_finite() && clearance >= 0.0) {
            return Err(InputError::field(
                "clearance",
                format!("a clearance must be a non-negative length, got {clearance} m"),
            )
            .into());
        }
        if clearance >= bearing.roller_diameter {
            return Err(InputError::field(
                "clearance",
                format!(
                    "a clearance of {clearance} m is not smaller than the rollers ({} m in \
                     diameter): the rings could not hold them",
                    bearing.roller_diameter
                ),
            )
            .help("radial clearances are micrometres: about 1e-4 to 1e-3 of the pitch diameter")
            .into());
        }
        let mut round = bearing.clone();
        round.clearance = Clearance::Constant(clearance);
        round.cage_angle = cage_angle;
        round.contact_damping = 0.0;
        round.waviness.clear();
        round.defects.clear();
        round.roller_tilt = false;
        Ok(FrozenBearing {
            hertz: HertzBearing::new(&round, vec![0, 1])?,
            clearance,
            contact_stiffness: bearing.contact_stiffness,
            exponent: bearing.contact_exponent,
        })
    }

    /// Force of the bearing on the shaft at displacement `u`, N.
    pub fn force(&mut self, u: [f64; 2]) -> [f64; 2] {
        let mut f = [0.0; 2];
        self.hertz.force(&AT_REST, &u, &[0.0; 2], &mut f);
        f
    }

    /// Tangent stiffness -dF/du at `u`, rows [[kxx, kxy], [kyx, kyy]], N/m.
    pub fn stiffness(&mut self, u: [f64; 2]) -> [[f64; 2]; 2] {
        let (mut dfdq, mut dfdv) = ([0.0; 4], [0.0; 4]);
        self.hertz
            .jacobian(&AT_REST, &u, &[0.0; 2], &mut dfdq, &mut dfdv);
        [[-dfdq[0], -dfdq[1]], [-dfdq[2], -dfdq[3]]]
    }

    /// The rollers in contact at `u`.
    pub fn loaded_rollers(&self, u: [f64; 2]) -> Vec<LoadedRoller> {
        self.hertz
            .rollers(&AT_REST, &u, &[0.0; 2])
            .iter()
            .enumerate()
            .filter(|(_, r)| r.force > 0.0)
            .map(|(index, r)| LoadedRoller {
                index,
                angle: r.angle,
                approach: r.approach,
                force: r.force,
            })
            .collect()
    }

    /// Force, stiffness and loaded rollers at `u` (eq. 3.25 at a given displacement).
    pub fn tangent(&mut self, u: [f64; 2]) -> Tangent {
        Tangent {
            displacement: u,
            force: self.force(u),
            stiffness: Stiffness2::from_rows(self.stiffness(u)),
            rollers: self.loaded_rollers(u),
        }
    }

    /// Contact deflection of one roller carrying `load` (N): (W / K_c)^(1/n), m.
    pub fn hertz_deflection(&self, load: f64) -> f64 {
        (load / self.contact_stiffness).powf(1.0 / self.exponent)
    }

    /// The static equilibrium F(u) + W = 0 under the load `load` (N), by Newton's method
    /// with the exact tangent.
    ///
    /// The start drops the journal along the load by the clearance plus the Hertz deflection
    /// of one roller carrying it all, divided by the cosine to the nearest roller, so that
    /// at least that roller is in contact. Steps solve (K + mu I) du = F + W: Newton's when
    /// mu = 0; a singular K (one roller in contact, a load off its line) raises mu, which
    /// turns the step towards the load until more rollers touch. A step is taken whole when
    /// it lowers the residual, otherwise to the line minimum of the potential energy (where
    /// (F + W) . du changes sign), which always exists because the energy is convex.
    ///
    /// # Errors
    /// [`Error::Input`] naming `load` for a load that is zero or not finite;
    /// [`Error::NotConverged`] when no equilibrium is found within the iteration limit or the
    /// shift grows too large (the rollers cannot carry a load in that direction).
    pub fn equilibrium(&mut self, load: [f64; 2]) -> Result<Equilibrium> {
        let magnitude = norm(load);
        if !(magnitude.is_finite() && magnitude > 0.0) {
            return Err(InputError::field(
                "load",
                format!("the bearing load must be a non-zero finite force, got {load:?} N"),
            )
            .into());
        }
        let scale = self.load_stiffness(magnitude);
        let mut u = self.start(load);
        let mut r = self.residual(u, load);
        let mut shift = 0.0;
        let mut iterations = 0;
        while norm(r) > BALANCE_TOLERANCE * magnitude {
            iterations += 1;
            if iterations > MAX_ITERATIONS || shift > LARGEST_SHIFT * scale {
                return Err(self.no_equilibrium(load, norm(r)));
            }
            let k = self.stiffness(u);
            match shifted_solve(k, shift, r).and_then(|du| self.line_step(u, du, r, load)) {
                Some((next, rn)) => {
                    (u, r) = (next, rn);
                    shift = if shift <= FIRST_SHIFT * scale {
                        0.0
                    } else {
                        shift / 10.0
                    };
                }
                None if shift == 0.0 => shift = FIRST_SHIFT * scale,
                None => shift *= 10.0,
            }
        }
        Ok(Equilibrium {
            load,
            cage_angle: self.hertz.geometry().cage_angle,
            tangent: self.tangent(u),
            iterations,
            relative_residual: norm(r) / magnitude,
        })
    }

    /// Tangent stiffness of one roller carrying `load` alone, N/m: the scale of the shift.
    fn load_stiffness(&self, load: f64) -> f64 {
        let delta = self.hertz_deflection(load);
        self.exponent * self.contact_stiffness * delta.powf(self.exponent - 1.0)
    }

    /// The Hertz start of [`FrozenBearing::equilibrium`].
    fn start(&self, load: [f64; 2]) -> [f64; 2] {
        let magnitude = norm(load);
        let w = [load[0] / magnitude, load[1] / magnitude];
        let geometry = self.hertz.geometry();
        let nearest = (0..geometry.rollers)
            .map(|j| {
                let t = geometry.roller_angle(j, 0.0);
                t.cos() * w[0] + t.sin() * w[1]
            })
            .fold(f64::NEG_INFINITY, f64::max);
        // A nearest roller more than 84 deg off the load (only with very few rollers) would
        // throw the start far away: the reach is capped at ten drops, and Levenberg-Marquardt
        // finds the contact from there.
        let reach = (self.clearance + self.hertz_deflection(magnitude)) / nearest.max(0.1);
        [reach * w[0], reach * w[1]]
    }

    /// F(u) + W: the force left over at `u`, N.
    fn residual(&mut self, u: [f64; 2], load: [f64; 2]) -> [f64; 2] {
        let f = self.force(u);
        [f[0] + load[0], f[1] + load[1]]
    }

    /// The step from `u` along `du`: whole when it lowers the residual or the energy falls
    /// all the way, else to the line minimum of the potential energy by bisection. `None`
    /// when `du` is not a descent step.
    fn line_step(
        &mut self,
        u: [f64; 2],
        du: [f64; 2],
        r0: [f64; 2],
        load: [f64; 2],
    ) -> Option<([f64; 2], [f64; 2])> {
        // The energy's slope along du is -r . du (r = F + W is minus its gradient).
        let slope0 = -dot(r0, du);
        if slope0.is_nan() || slope0 >= 0.0 {
            return None;
        }
        let mut at = |t: f64| {
            let p = [u[0] + t * du[0], u[1] + t * du[1]];
            let r = self.residual(p, load);
            (p, r, -dot(r, du))
        };
        let whole = at(1.0);
        if norm(whole.1) < norm(r0) || whole.2 <= 0.0 {
            return Some((whole.0, whole.1));
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        let mut best = whole;
        // 60 halvings reach the resolution of f64 on (0, 1).
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            best = at(mid);
            if best.2 <= 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
            // A slope a thousandth of the first is close enough to the minimum: Newton
            // takes over from there.
            if best.2.abs() <= 1e-3 * slope0.abs() {
                break;
            }
        }
        // The energy is convex and its slope was negative at 0, so it fell on the way to
        // the line minimum even where the residual's norm did not.
        Some((best.0, best.1))
    }

    fn no_equilibrium(&self, load: [f64; 2], residual: f64) -> Error {
        Error::not_converged(
            "bearing equilibrium",
            None,
            Some(residual),
            format!(
                "no static equilibrium of the bearing at clearance {:.3} um under the load \
             ({:.4}, {:.4}) N (force left over {residual:.3e} N): the rollers cannot carry a \
             load in this direction",
                self.clearance * 1e6,
                load[0],
                load[1]
            ),
        )
    }
}

/// Solves (K + mu I) du = r for the 2x2 K; `None` when the matrix is singular.
fn shifted_solve(k: [[f64; 2]; 2], mu: f64, r: [f64; 2]) -> Option<[f64; 2]> {
    let (a, b, c, d) = (k[0][0] + mu, k[0][1], k[1][0], k[1][1] + mu);
    let det = a * d - b * c;
    // Relative to the diagonal's scale: one roller exactly on an axis leaves a determinant
    // of round-off size, which must count as singular.
    let size = (a.abs() + d.abs()).powi(2);
    if det.is_nan() || det.abs() <= 1e-12 * size {
        return None;
    }
    let du = [(d * r[0] - b * r[1]) / det, (a * r[1] - c * r[0]) / det];
    du.iter().all(|x| x.is_finite()).then_some(du)
}

/// The frozen-cage tangents of a roller passage: the equilibrium under `load` with roller 0
/// at `cage_angle + 2 pi k / (N_b steps)`, k = 0..steps, and their mean.
///
/// # Errors
/// The errors of [`FrozenBearing::new`] and [`FrozenBearing::equilibrium`] at each cage
/// position: [`Error::Input`] for a negative clearance or a zero load,
/// [`Error::NotConverged`] when an equilibrium is not found.
pub fn passage_average(
    bearing: &RollerBearing,
    clearance: f64,
    cage_angle: f64,
    load: [f64; 2],
    steps: usize,
) -> Result<PassageAverage> {
    let steps = steps.max(1);
    let pitch = 2.0 * PI / bearing.rollers as f64;
    let samples = (0..steps)
        .map(|k| {
            let angle = cage_angle + pitch * k as f64 / steps as f64;
            let e = FrozenBearing::new(bearing, clearance, angle)?.equilibrium(load)?;
            Ok(PassageSample {
                cage_angle: angle,
                displacement: e.tangent.displacement,
                stiffness: e.tangent.stiffness,
                rollers: e.tangent.rollers.iter().map(|r| r.index).collect(),
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let first = samples[0].stiffness;
    let n = steps as f64;
    let sum = samples
        .iter()
        .skip(1)
        .fold(first, |acc, s| acc.zip(&s.stiffness, |a, b| a + b));
    let min = samples
        .iter()
        .fold(first, |acc, s| acc.zip(&s.stiffness, f64::min));
    let max = samples
        .iter()
        .fold(first, |acc, s| acc.zip(&s.stiffness, f64::max));
    let mean_displacement =
        [0, 1].map(|a| samples.iter().map(|s| s.displacement[a]).sum::<f64>() / n);
    Ok(PassageAverage {
        mean: sum.scaled(1.0 / n),
        min,
        max,
        mean_displacement,
        most_rollers: samples.iter().map(|s| s.rollers.len()).max().unwrap_or(0),
        samples,
    })
}

/// Angle that puts roller 0 on the line of `load`, rad.
pub fn cage_angle_on_load_line(load: [f64; 2]) -> f64 {
    load[1].atan2(load[0])
}

/// The three stiffnesses of `bearing` at every clearance of `options`.
///
/// # Errors
/// [`Error::Input`] naming `clearances` when there are none and
/// `options.fixed_displacement` is not given; the errors of [`FrozenBearing::new`],
/// [`FrozenBearing::equilibrium`] and [`passage_average`] at each clearance
/// ([`Error::Input`] for a negative clearance or a zero load, [`Error::NotConverged`] when
/// an equilibrium is not found).
pub fn stiffness_versus_clearance(
    bearing: &RollerBearing,
    options: &StiffnessOptions,
) -> Result<StiffnessStudy> {
    let cage_angle = options
        .cage_angle
        .unwrap_or_else(|| cage_angle_on_load_line(options.load));
    let frozen = options
        .clearances
        .iter()
        .map(|&c| FrozenBearing::new(bearing, c, cage_angle)?.equilibrium(options.load))
        .collect::<Result<Vec<_>>>()?;
    let fixed_displacement = match options.fixed_displacement {
        Some(u) => u,
        None => largest_clearance_deflection(&options.clearances, &frozen)?,
    };
    let clearances = options
        .clearances
        .iter()
        .zip(frozen)
        .map(|(&clearance, frozen)| {
            Ok(ClearanceStiffness {
                clearance,
                averaged: passage_average(
                    bearing,
                    clearance,
                    cage_angle,
                    options.load,
                    options.cage_steps,
                )?,
                fixed: FrozenBearing::new(bearing, clearance, cage_angle)?
                    .tangent(fixed_displacement),
                frozen,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(StiffnessStudy {
        bearing: bearing.name.clone(),
        load: options.load,
        cage_angle,
        cage_steps: options.cage_steps.max(1),
        fixed_displacement,
        clearances,
    })
}

/// The frozen equilibrium displacement at the largest clearance.
fn largest_clearance_deflection(clearances: &[f64], frozen: &[Equilibrium]) -> Result<[f64; 2]> {
    clearances
        .iter()
        .zip(frozen)
        .max_by(|a, b| a.0.total_cmp(b.0))
        .map(|(_, e)| e.tangent.displacement)
        .ok_or_else(|| InputError::field("clearances", "give at least one clearance").into())
}

/// F_x, F_y and F_r of `bearing` at clearance `clearance` over the grid `ux` x `uy` (m),
/// roller 0 at `cage_angle`.
///
/// # Errors
/// The errors of [`FrozenBearing::new`]: [`Error::Input`] naming `clearance` when it is
/// negative or not finite.
pub fn force_surface(
    bearing: &RollerBearing,
    clearance: f64,
    cage_angle: f64,
    ux: &[f64],
    uy: &[f64],
) -> Result<ForceSurface> {
    let mut frozen = FrozenBearing::new(bearing, clearance, cage_angle)?;
    let rows = uy.len();
    let mut surface = ForceSurface {
        clearance,
        cage_angle,
        ux: ux.to_vec(),
        uy: uy.to_vec(),
        fx: Vec::with_capacity(rows),
        fy: Vec::with_capacity(rows),
        fr: Vec::with_capacity(rows),
        contacts: Vec::with_capacity(rows),
    };
    for &y in uy {
        let forces: Vec<[f64; 2]> = ux.iter().map(|&x| frozen.force([x, y])).collect();
        surface.fx.push(forces.iter().map(|f| f[0]).collect());
        surface.fy.push(forces.iter().map(|f| f[1]).collect());
        surface.fr.push(forces.iter().map(|&f| norm(f)).collect());
        surface.contacts.push(
            ux.iter()
                .map(|&x| frozen.loaded_rollers([x, y]).len())
                .collect(),
        );
    }
    Ok(surface)
}

/// The load the rotor's weight puts on roller bearing `index` of `model`, N: the reaction of
/// its linearised support in a linear static solve K q = F_gravity with every roller bearing
/// replaced by its `linear_stiffness`. On two supports the shaft is statically determinate
/// and the reaction does not depend on those stiffnesses.
///
/// # Errors
/// [`Error::Input`] naming `bearing` when `index` is not a roller bearing of `model`;
/// [`Error::Singular`] when the linearised rotor cannot carry its weight (the reaction is
/// not finite: a support that leaves it free); [`Error::Unsupported`] above
/// [`crate::fe::MAX_DENSE_DOFS`].
pub fn gravity_load(model: &Model, index: usize) -> Result<[f64; 2]> {
    let bearing = model.roller_bearings.get(index).ok_or_else(|| {
        Error::from(InputError::field(
            "bearing",
            format!(
                "the model has {} roller bearing(s); there is no index {index}",
                model.roller_bearings.len()
            ),
        ))
    })?;
    let system = assemble_dense(
        model,
        Bearings::Linearised,
        "the bearing's gravity load comes from a dense static solve; give the load with \
         `--load` or use fewer elements",
    )?;
    let f = gravity_force(model, &system);
    let n = f.len();
    let mut q = Mat::<f64>::from_fn(n, 1, |i, _| f[i]);
    faer::linalg::solvers::Solve::solve_in_place(&system.stiffness.partial_piv_lu(), q.as_mut());
    let node = bearing.station.node;
    // Relative to the housing, when the bearing sits in one.
    let outer = model
        .outer_dofs(bearing.housing)
        .map_or([0.0; 2], |o| o.map(|d| q[(d, 0)]));
    let u = [
        q[(dof(node, Direction::Ux), 0)] - outer[0],
        q[(dof(node, Direction::Uy), 0)] - outer[1],
    ];
    // The linearised support pushes the shaft with -k u; the shaft loads it with k u.
    let load = u.map(|x| bearing.linear_stiffness * x);
    if load.iter().all(|x| x.is_finite()) {
        Ok(load)
    } else {
        Err(Error::singular(
            "linearised stiffness",
            "the linearised rotor cannot carry its weight (its supports leave it free); give \
             each roller bearing a positive linear_stiffness"
                .into(),
        ))
    }
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shifted_solve_refuses_a_singular_matrix() {
        // One roller straight down: K = k e_y e_y^T, singular.
        assert!(shifted_solve([[0.0, 0.0], [0.0, 1e8]], 0.0, [0.0, 1.0]).is_none());
        let du = shifted_solve([[0.0, 0.0], [0.0, 1e8]], 1.0, [2.0, 1e8]).unwrap();
        assert_eq!(du, [2.0, 1e8 / (1e8 + 1.0)]);
    }
}
