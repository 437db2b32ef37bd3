//! Short-bearing squeeze-film damper (SFD) between a housing (the journal: a bearing's
//! outer ring in its cage) and what the housing is mounted on (docs/theory.md, "Squeeze-film
//! dampers").
//!
//! The journal does not spin, so Reynolds' equation of the short bearing (L/D small: the
//! axial pressure gradient dominates) is
//!
//! ```text
//! d/dz (h^3 / (12 mu) dp/dz) = dh/dt,   h = c - x cos(theta) - y sin(theta)
//! ```
//!
//! with (x, y) the journal's position from the damper's centre. With p = 0 at the land's
//! ends z = +-L/2, p = 6 mu (z^2 - L^2/4) h_t / h^3, whose axial integral is
//! -mu L^3 h_t / h^3, and the film's force on the journal is
//!
//! ```text
//! F = -mu R L^3 int (v . n) n / h^3 dtheta,   n = (cos theta, sin theta), v = (x', y')
//! ```
//!
//! over the whole film (uncavitated, "2 pi film") or over the part that is being squeezed,
//! v . n > 0, where p > 0 (cavitated, "pi film": negative pressures cut to zero; on a
//! circular orbit that is half the land). The integrand vanishes at the edges of that part,
//! so the Jacobians are the integrals of the derivatives:
//!
//! ```text
//! dF/dv = -mu R L^3 int n n^T / h^3,   dF/dq = -3 mu R L^3 int (v . n) n n^T / h^4
//! ```
//!
//! The integrals are taken by composite Gauss-Legendre quadrature in the angle, which the
//! tests check against the closed forms of centred circular orbits (Vance, "Rotordynamics of
//! Turbomachinery", 1988, section 6; San Andres, "Squeeze film dampers", Texas A&M
//! lecture notes, 2010):
//!
//! ```text
//! pi film:   F_r = -mu R L^3 w / c^2 * 2 eps^2 / (1 - eps^2)^2
//!            F_t = -mu R L^3 w / c^2 * pi eps / (2 (1 - eps^2)^(3/2))
//! full film: F_r = 0,  F_t = -mu R L^3 w / c^2 * pi eps / (1 - eps^2)^(3/2)
//! ```
//!
//! Linear analyses take the damper linearised at its static position q0 (the film carries no
//! static load: at rest its force is zero, so q0 is that of the linear model without it):
//! no stiffness, damping C = mu R L^3 int n n^T / h0^3 over the whole film; the pi film's
//! damping depends on the direction of motion, and its average over all directions is half
//! of that (each angle is squeezed for half of the directions).

use crate::error::{Error, Result};
use crate::force::{Kinematics, NonlinearForce};
use crate::model::{Cavitation, Model, SqueezeFilm};

/// Gauss-Legendre points and weights on [-1, 1], 8 points.
const GAUSS: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_2, 0.101_228_536_290_376_26),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (0.960_289_856_497_536_2, 0.101_228_536_290_376_26),
];

/// Panels over half the film (pi radians): 24 panels of 8 points integrate the film on
/// centred circular orbits to 1e-14 of the closed forms up to eps = 0.95 (measured).
const PANELS: usize = 24;

/// The film's integrals at a state: the force, and the Jacobians' integrals.
#[derive(Debug, Clone, Copy, Default)]
struct FilmIntegrals {
    /// int (v . n) n / h^3.
    squeeze: [f64; 2],
    /// int n n^T / h^3 (row-major).
    damping: [f64; 4],
    /// int (v . n) n n^T / h^4.
    stiffness: [f64; 4],
}

/// The damper's film: geometry and oil.
#[derive(Debug, Clone)]
pub struct Film {
    /// mu R L^3, N s m.
    scale: f64,
    clearance: f64,
    cavitation: Cavitation,
    offset: [f64; 2],
    /// The quadrature over a half circle from angle 0: (cos, sin, weight) of each point.
    points: Vec<(f64, f64, f64)>,
}

/// Composite Gauss-Legendre points over [0, pi]: [`PANELS`] panels of [`GAUSS`].
fn half_circle() -> Vec<(f64, f64, f64)> {
    let width = std::f64::consts::PI / PANELS as f64;
    (0..PANELS)
        .flat_map(|p| {
            GAUSS.iter().map(move |&(x, w)| {
                let theta = (p as f64 + 0.5 + 0.5 * x) * width;
                (theta.cos(), theta.sin(), 0.5 * width * w)
            })
        })
        .collect()
}

impl Film {
    /// The film of `damper`.
    pub fn new(damper: &SqueezeFilm) -> Film {
        Film {
            scale: damper.viscosity * damper.radius * damper.length.powi(3),
            clearance: damper.clearance,
            cavitation: damper.cavitation,
            offset: damper.offset,
            points: half_circle(),
        }
    }

    /// The integrals over `halves` half circles of angles from `start` at journal
    /// position `q` (from the damper's centre) and velocity `v`. Each point's direction is
    /// the half circle's first rotated by the point's offset (no trigonometry per point).
    fn integrate(
        &self,
        q: [f64; 2],
        v: [f64; 2],
        start: f64,
        halves: usize,
        out: &mut FilmIntegrals,
    ) {
        for k in 0..halves {
            let (sb, cb) = (start + k as f64 * std::f64::consts::PI).sin_cos();
            for &(c, s, weight) in &self.points {
                let n = [cb * c - sb * s, sb * c + cb * s];
                let h = self.clearance - q[0] * n[0] - q[1] * n[1];
                let h3 = h * h * h;
                let squeeze = v[0] * n[0] + v[1] * n[1];
                let nn = [n[0] * n[0], n[0] * n[1], n[1] * n[0], n[1] * n[1]];
                for k in 0..2 {
                    out.squeeze[k] += weight * squeeze * n[k] / h3;
                }
                for k in 0..4 {
                    out.damping[k] += weight * nn[k] / h3;
                    out.stiffness[k] += weight * squeeze * nn[k] / (h3 * h);
                }
            }
        }
    }

    /// The integrals over the pressurised film at position `q` (from the damper's centre)
    /// and velocity `v`.
    fn film(&self, q: [f64; 2], v: [f64; 2]) -> FilmIntegrals {
        let mut out = FilmIntegrals::default();
        match self.cavitation {
            Cavitation::Full => {
                self.integrate(q, v, 0.0, 2, &mut out);
            }
            Cavitation::Pi => {
                // Squeezed where v . n > 0: the half circle centred on v's direction.
                if v[0] != 0.0 || v[1] != 0.0 {
                    let direction = v[1].atan2(v[0]);
                    let half = std::f64::consts::FRAC_PI_2;
                    self.integrate(q, v, direction - half, 1, &mut out);
                }
            }
        }
        out
    }

    /// The journal's position from the damper's centre, for a housing displaced `u`
    /// relative to what it is mounted on.
    fn position(&self, u: [f64; 2]) -> [f64; 2] {
        [u[0] - self.offset[0], u[1] - self.offset[1]]
    }

    /// The film's force on the journal at relative displacement `u` and velocity `v`, N.
    pub fn force(&self, u: [f64; 2], v: [f64; 2]) -> [f64; 2] {
        let i = self.film(self.position(u), v);
        [-self.scale * i.squeeze[0], -self.scale * i.squeeze[1]]
    }

    /// The force and its Jacobians dF/du and dF/dv (row-major 2x2).
    pub fn force_and_jacobian(&self, u: [f64; 2], v: [f64; 2]) -> ([f64; 2], [f64; 4], [f64; 4]) {
        let i = self.film(self.position(u), v);
        let s = self.scale;
        (
            [-s * i.squeeze[0], -s * i.squeeze[1]],
            i.stiffness.map(|k| -3.0 * s * k),
            i.damping.map(|c| -s * c),
        )
    }

    /// The damping matrix of the film linearised at relative displacement `u` at rest
    /// (row-major): the whole film's, halved for the pi film (see the module
    /// documentation). No stiffness: the film's force at rest is zero whatever `u`.
    pub fn linearised_damping(&self, u: [f64; 2]) -> [f64; 4] {
        let mut out = FilmIntegrals::default();
        let q = self.position(u);
        self.integrate(q, [0.0; 2], 0.0, 2, &mut out);
        let share = match self.cavitation {
            Cavitation::Full => 1.0,
            Cavitation::Pi => 0.5,
        };
        out.damping.map(|c| share * self.scale * c)
    }

    /// The eccentricity ratio |q| / c of the journal at relative displacement `u`.
    pub fn eccentricity_ratio(&self, u: [f64; 2]) -> f64 {
        let q = self.position(u);
        q[0].hypot(q[1]) / self.clearance
    }
}

/// Equivalent coefficients of a damper on a centred circular orbit of eccentricity ratio
/// `eps` whirling forward at `w` rad/s: the direct stiffness K = -F_r / e and damping
/// C = -F_t / (e w) from the film's force (the radial and tangential parts).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitCoefficients {
    /// Radial force, N (negative: towards the centre).
    pub radial_force: f64,
    /// Tangential force, N (negative: against the whirl).
    pub tangential_force: f64,
    /// K = -F_r / e, N/m.
    pub stiffness: f64,
    /// C = -F_t / (e w), N s/m.
    pub damping: f64,
}

/// The film's force and equivalent coefficients on a centred circular orbit (journal at
/// (e, 0) moving at (0, e w)), by the film's quadrature.
pub fn circular_orbit(damper: &SqueezeFilm, eps: f64, w: f64) -> OrbitCoefficients {
    let centred = SqueezeFilm {
        offset: [0.0; 2],
        ..damper.clone()
    };
    let e = eps * damper.clearance;
    let [radial, tangential] = Film::new(&centred).force([e, 0.0], [0.0, e * w]);
    OrbitCoefficients {
        radial_force: radial,
        tangential_force: tangential,
        stiffness: -radial / e,
        damping: -tangential / (e * w),
    }
}

/// The short-bearing closed form of [`circular_orbit`] (Vance 1988; San Andres 2010; see
/// the module documentation).
pub fn circular_orbit_closed_form(damper: &SqueezeFilm, eps: f64, w: f64) -> OrbitCoefficients {
    let scale =
        damper.viscosity * damper.radius * damper.length.powi(3) * w / damper.clearance.powi(2);
    let pi = std::f64::consts::PI;
    let one = 1.0 - eps * eps;
    let (radial, tangential) = match damper.cavitation {
        Cavitation::Pi => (
            -scale * 2.0 * eps * eps / (one * one),
            -scale * pi * eps / (2.0 * one.powf(1.5)),
        ),
        Cavitation::Full => (0.0, -scale * pi * eps / one.powf(1.5)),
    };
    let e = eps * damper.clearance;
    OrbitCoefficients {
        radial_force: radial,
        tangential_force: tangential,
        stiffness: -radial / e,
        damping: -tangential / (e * w),
    }
}

/// A squeeze-film damper as a [`NonlinearForce`] on a housing's [ux, uy] (mounted on the
/// ground) or on [housing ux, uy, mounting ux, uy] (mounted on another housing).
pub struct SqueezeFilmForce {
    name: String,
    film: Film,
    dofs: Vec<usize>,
    /// The largest |dF/du| expected, for the explicit stability bound (see
    /// [`NonlinearForce::stiffness_bound`]): the film's stiffness-like term is
    /// proportional to the velocity, so this is a bound at `bound_velocity`.
    bound: f64,
}

/// The journal speed (m/s) at which the stiffness bound is taken: 0.1 m/s is a 90 um
/// orbit at 180 Hz, what the reference rotor's dampers reach at 120 um roller clearance
/// and 712 Hz (measured). With 0.05 m/s and eps 0.8 the step from the limit was 2.6e-5 s
/// there and the disk's NSV came out 2.5 times the converged one (1.2e-5 and 6e-6 s agree).
const BOUND_VELOCITY: f64 = 0.1;

/// The eccentricity ratio at which the stiffness bound is taken. The film's velocity-borne
/// stiffness grows as 1/h^4 without limit as the journal nears the wall: a bound for every
/// orbit would allow no step at all. An orbit past this ratio at that speed may need a
/// smaller step than the limit says; its divergence is caught by the divergence bound.
const BOUND_ECCENTRICITY: f64 = 0.9;

impl SqueezeFilmForce {
    /// The damper `damper` named `name` on coordinates `dofs` ([housing ux, uy] and, when
    /// mounted on another housing, that one's [ux, uy]).
    pub fn new(name: impl Into<String>, damper: &SqueezeFilm, dofs: Vec<usize>) -> Self {
        let film = Film::new(damper);
        let h = damper.clearance * (1.0 - BOUND_ECCENTRICITY);
        // 3 mu R L^3 int |v| / h^4 over the film, at the closest gap all round.
        let bound = 3.0 * film.scale * BOUND_VELOCITY * 2.0 * std::f64::consts::PI / h.powi(4);
        SqueezeFilmForce {
            name: name.into(),
            film,
            dofs,
            bound,
        }
    }

    /// The relative displacement and velocity of the journal.
    fn relative(&self, q: &[f64], v: &[f64]) -> ([f64; 2], [f64; 2]) {
        if self.dofs.len() == 4 {
            ([q[0] - q[2], q[1] - q[3]], [v[0] - v[2], v[1] - v[3]])
        } else {
            ([q[0], q[1]], [v[0], v[1]])
        }
    }

    /// Spreads a 2x2 Jacobian of the relative motion to the coordinates.
    fn spread(&self, j: &[f64; 4], out: &mut [f64]) {
        let m = self.dofs.len();
        for r in 0..m {
            for c in 0..m {
                let sign = if (r < 2) == (c < 2) { 1.0 } else { -1.0 };
                out[r * m + c] = sign * j[(r % 2) * 2 + c % 2];
            }
        }
    }
}

impl NonlinearForce for SqueezeFilmForce {
    fn name(&self) -> String {
        self.name.clone()
    }
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn force(&mut self, _: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]) {
        let (u, w) = self.relative(q, v);
        let f = self.film.force(u, w);
        out[..2].copy_from_slice(&f);
        if out.len() == 4 {
            out[2] = -f[0];
            out[3] = -f[1];
        }
    }
    fn jacobian(
        &mut self,
        _: &Kinematics,
        q: &[f64],
        v: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        let (u, w) = self.relative(q, v);
        let (_, jq, jv) = self.film.force_and_jacobian(u, w);
        self.spread(&jq, dfdq);
        self.spread(&jv, dfdv);
    }
    fn stiffness_bound(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.dofs.len().pow(2)];
        self.spread(&[self.bound, 0.0, 0.0, self.bound], &mut out);
        out
    }
}

/// The squeeze-film dampers of `model`'s housings as nonlinear forces, their DOFs mapped
/// to coordinates by `coordinate`.
///
/// # Errors
/// [`Error::Unsupported`] when `coordinate` does not keep a housing's DOFs.
pub fn squeeze_film_forces(
    model: &Model,
    coordinate: &dyn Fn(usize) -> Option<usize>,
) -> Result<Vec<Box<dyn NonlinearForce>>> {
    let mut out: Vec<Box<dyn NonlinearForce>> = Vec::new();
    for (h, housing) in model.housings.iter().enumerate() {
        let Some(damper) = &housing.squeeze_film else {
            continue;
        };
        let mut physical = model.housing_dofs(h).to_vec();
        physical.extend(model.outer_dofs(housing.on).into_iter().flatten());
        let dofs = physical
            .iter()
            .map(|&d| {
                coordinate(d).ok_or_else(|| {
                    Error::Unsupported(format!(
                        "the squeeze-film damper of housing \"{}\": DOF {d} is not kept by \
                         the reduction; housings' DOFs must be boundary DOFs",
                        housing.name
                    ))
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let name = format!("squeeze-film damper of {}", housing.name);
        out.push(Box::new(SqueezeFilmForce::new(name, damper, dofs)));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn damper(cavitation: Cavitation) -> SqueezeFilm {
        SqueezeFilm {
            radius: 0.04,
            length: 0.012,
            clearance: 120e-6,
            viscosity: 0.02,
            cavitation,
            offset: [0.0; 2],
        }
    }

    /// The quadrature against the short-bearing closed forms on centred circular orbits.
    /// The closed forms are exact for this film model, so what is left is the quadrature's
    /// error: 24 panels of 8 Gauss points per half circle resolve the 1/h^3 peak (width
    /// ~ 1 - eps = 0.1 rad at eps = 0.9) to round-off (measured 1e-14); 1e-10 leaves room
    /// for other platforms' libm.
    #[test]
    fn circular_orbits_match_the_closed_forms() {
        for cavitation in [Cavitation::Pi, Cavitation::Full] {
            let d = damper(cavitation);
            for eps in [0.05, 0.2, 0.4, 0.6, 0.8, 0.9] {
                let w = 2.0 * std::f64::consts::PI * 100.0;
                let q = circular_orbit(&d, eps, w);
                let exact = circular_orbit_closed_form(&d, eps, w);
                let scale = exact.tangential_force.abs();
                assert!(
                    (q.tangential_force - exact.tangential_force).abs() < 1e-10 * scale,
                    "{cavitation:?} eps {eps}: {q:?} against {exact:?}"
                );
                assert!(
                    (q.radial_force - exact.radial_force).abs() < 1e-10 * scale,
                    "{cavitation:?} eps {eps}: {q:?} against {exact:?}"
                );
            }
        }
    }

    /// The Jacobians against central differences of the force, at an eccentric state
    /// moving obliquely (a pi film's squeezed half not aligned with anything). Steps of
    /// 1e-11 m and 1e-8 m/s against a 60 um gap and 0.05 m/s: truncation ~1e-11,
    /// round-off ~1e-16 / 1e-7 = 1e-9 relative: 1e-6 has margin.
    #[test]
    fn jacobians_are_the_derivatives_of_the_force() {
        for cavitation in [Cavitation::Pi, Cavitation::Full] {
            let film = Film::new(&damper(cavitation));
            let (u, v) = ([30e-6, -45e-6], [0.03, 0.04]);
            let (_, jq, jv) = film.force_and_jacobian(u, v);
            let scale = jv.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            let kscale = jq.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            for j in 0..2 {
                let (hq, hv) = (1e-11, 1e-8);
                let (mut up, mut um) = (u, u);
                up[j] += hq;
                um[j] -= hq;
                let (fp, fm) = (film.force(up, v), film.force(um, v));
                let (mut vp, mut vm) = (v, v);
                vp[j] += hv;
                vm[j] -= hv;
                let (gp, gm) = (film.force(u, vp), film.force(u, vm));
                for i in 0..2 {
                    let dq = (fp[i] - fm[i]) / (2.0 * hq);
                    let dv = (gp[i] - gm[i]) / (2.0 * hv);
                    assert!((dq - jq[2 * i + j]).abs() < 1e-6 * kscale, "{dq} {jq:?}");
                    assert!((dv - jv[2 * i + j]).abs() < 1e-6 * scale, "{dv} {jv:?}");
                }
            }
        }
    }

    /// Centred, the whole film's damping is pi mu R L^3 / c^3 in each direction (the
    /// full-film closed form's limit eps -> 0), and the pi film's half of it.
    #[test]
    fn the_linearised_damping_at_the_centre_is_the_closed_form() {
        for (cavitation, share) in [(Cavitation::Full, 1.0), (Cavitation::Pi, 0.5)] {
            let d = damper(cavitation);
            let c = Film::new(&d).linearised_damping([0.0; 2]);
            let exact = share * std::f64::consts::PI * d.viscosity * d.radius * d.length.powi(3)
                / d.clearance.powi(3);
            // Quadrature of a constant integrand of cos^2: exact to round-off.
            assert!((c[0] / exact - 1.0).abs() < 1e-12, "{c:?} {exact}");
            assert!((c[3] / exact - 1.0).abs() < 1e-12, "{c:?} {exact}");
            assert!(c[1].abs() < 1e-12 * exact);
        }
    }
}
