//! Assembly of the global matrices and force vectors (thesis eq. 2.4).
//!
//! Rigid disks add m_d to the translations and I_d to the rotations, and I_p to the
//! gyroscopic matrix as G[tx, ty] = I_p, G[ty, tx] = -I_p (thesis eq. 2.13 with the sign
//! derived in [`super::beam`]). Rayleigh damping C = alpha M + beta K uses the rotor's own
//! M and K (shaft and disks), not the bearings', then the bearings' damping is added.

use std::borrow::Cow;

use faer::{c64, Mat};

use super::beam::{beam_matrices, BeamMatrices, BeamProperties, Mat8};
use super::timoshenko::{shear_rigidity, timoshenko_matrices};
use super::{dof, Direction, DOFS_PER_NODE};
use crate::error::{Error, Result};
use crate::linalg::{bandwidths, Band};
use crate::model::{BeamTheory, Model, ShaftSection};

/// How roller bearings enter the assembled matrices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bearings {
    /// Roller bearings contribute their `linear_stiffness` and `linear_damping`
    /// (linear analyses: modal, Campbell, unbalance response).
    Linearised,
    /// Roller bearings are left out; their nonlinear contact forces act instead.
    NonlinearApart,
}

/// The assembled linear system `M q'' + (Omega G + C) q' + K q = F`.
#[derive(Debug, Clone)]
pub struct SystemMatrices {
    /// Mass matrix, symmetric positive definite.
    pub mass: Mat<f64>,
    /// Stiffness of rotor and bearings (not symmetric when bearings are cross-coupled).
    pub stiffness: Mat<f64>,
    /// Gyroscopic matrix, skew-symmetric; multiplied by the spin speed.
    pub gyroscopic: Mat<f64>,
    /// Damping: Rayleigh damping of the rotor plus bearing damping.
    pub damping: Mat<f64>,
}

impl SystemMatrices {
    /// Number of DOFs.
    pub fn dofs(&self) -> usize {
        self.mass.nrows()
    }

    /// M, K, C and G, for what looks at all four (their sizes, their band structure).
    pub fn all(&self) -> [&Mat<f64>; 4] {
        [&self.mass, &self.stiffness, &self.damping, &self.gyroscopic]
    }
}

/// M, K, G and C of the assembled model as bands: a finite-element rotor couples only the
/// two nodes of an element, and bearings and disks act at one node, so every entry lies
/// within [`HALF_BANDWIDTH`] of the diagonal and the matrices take O(n) memory instead of
/// the dense form's O(n^2) (12.8 GB each for a 10,000-element rotor).
#[derive(Debug, Clone)]
pub struct BandedSystem {
    pub(crate) mass: Band,
    pub(crate) stiffness: Band,
    pub(crate) gyroscopic: Band,
    pub(crate) damping: Band,
    /// How K and C were made, when assembled from a model.
    pub(crate) parts: Option<Parts>,
}

/// The parts of K and C of an assembled model: K = K_rotor + K_supports, C = alpha M +
/// beta K_rotor + C_supports. On a fine mesh K_rotor's entries are many orders of magnitude
/// above the stiffness of the lowest modes (5e17 N/m for 10,000 elements of the reference
/// rotor, against 1e6 N/m), so a projection on those modes computed from K or C loses most
/// of its digits; with the parts it is computed from the modes' own w^2 instead
/// ([`crate::modal::ModalBasis`]).
#[derive(Debug, Clone)]
pub(crate) struct Parts {
    /// Rayleigh damping coefficients (alpha, beta) of the rotor.
    pub(crate) rayleigh: (f64, f64),
    /// The bearings' stiffness.
    pub(crate) support_stiffness: Band,
    /// The bearings' damping.
    pub(crate) support_damping: Band,
    /// The housings' mass (in M, not in the Rayleigh damping).
    pub(crate) support_mass: Band,
}

/// How far from the diagonal the assembled matrices reach: an element couples the eight
/// DOFs of its two nodes.
pub const HALF_BANDWIDTH: usize = 2 * DOFS_PER_NODE - 1;

impl BandedSystem {
    /// Number of DOFs.
    pub fn dofs(&self) -> usize {
        self.mass.size()
    }

    /// K, M, C and G, in the order of a dynamic stiffness's terms.
    pub(crate) fn bands(&self) -> [&Band; 4] {
        [&self.stiffness, &self.mass, &self.damping, &self.gyroscopic]
    }

    /// The dense matrices (n^2 memory each: for the small models the dense solvers take).
    pub fn to_dense(&self) -> SystemMatrices {
        SystemMatrices {
            mass: self.mass.to_dense(),
            stiffness: self.stiffness.to_dense(),
            gyroscopic: self.gyroscopic.to_dense(),
            damping: self.damping.to_dense(),
        }
    }
}

/// M, K, G and C however they are stored: banded (the assembled model) or dense (a reduced
/// model, or one assembled dense). The analyses that need a few modes take either and choose
/// the dense or the banded solver by size ([`crate::modal::solves_dense`]).
pub trait Matrices: Sync {
    /// Number of DOFs.
    fn dofs(&self) -> usize;
    /// The banded form (a dense matrix gives a band as wide as its entries reach).
    fn banded(&self) -> Cow<'_, BandedSystem>;
    /// The dense form (n^2 memory each).
    fn dense(&self) -> Cow<'_, SystemMatrices>;
    /// How far from the diagonal the entries reach (the largest half bandwidth of the four).
    fn reach(&self) -> usize;
}

impl Matrices for BandedSystem {
    fn dofs(&self) -> usize {
        self.dofs()
    }
    fn banded(&self) -> Cow<'_, BandedSystem> {
        Cow::Borrowed(self)
    }
    fn dense(&self) -> Cow<'_, SystemMatrices> {
        Cow::Owned(self.to_dense())
    }
    fn reach(&self) -> usize {
        self.bands()
            .iter()
            .map(|b| {
                let (lower, upper) = b.widths();
                lower.max(upper)
            })
            .max()
            .unwrap_or(0)
    }
}

impl Matrices for SystemMatrices {
    fn dofs(&self) -> usize {
        self.dofs()
    }
    fn banded(&self) -> Cow<'_, BandedSystem> {
        Cow::Owned(BandedSystem {
            mass: Band::of_dense(&self.mass),
            stiffness: Band::of_dense(&self.stiffness),
            gyroscopic: Band::of_dense(&self.gyroscopic),
            damping: Band::of_dense(&self.damping),
            parts: None,
        })
    }
    fn dense(&self) -> Cow<'_, SystemMatrices> {
        Cow::Borrowed(self)
    }
    fn reach(&self) -> usize {
        [&self.stiffness, &self.mass, &self.damping, &self.gyroscopic]
            .iter()
            .map(|m| {
                let (lower, upper) = bandwidths(m);
                lower.max(upper)
            })
            .max()
            .unwrap_or(0)
    }
}

/// A linear support as assembled: the [ux, uy] DOFs of its inner side, those of its outer
/// side (`None`: the ground), its stiffness and damping (x, y).
struct Support {
    inner: [usize; 2],
    outer: Option<[usize; 2]>,
    stiffness: [[f64; 2]; 2],
    damping: [[f64; 2]; 2],
}

impl Support {
    /// The largest distance from the diagonal of the entries it adds.
    fn reach(&self) -> usize {
        self.outer
            .map_or(1, |o| self.inner[1].max(o[1]) - self.inner[0].min(o[0]))
    }
}

fn add_element(global: &mut Band, local: &Mat8, first_dof: usize, scale: f64) {
    for i in 0..8 {
        for j in 0..8 {
            global.add(first_dof + i, first_dof + j, scale * local[i][j]);
        }
    }
}

/// Assembles M, K, G and C of a model, dense: for the small models and the solvers that
/// work on dense matrices; see [`assemble_banded`].
pub fn assemble(model: &Model, bearings: Bearings) -> SystemMatrices {
    assemble_banded(model, bearings).to_dense()
}

/// Most DOFs an analysis may hold as dense matrices: four of them take 32 n^2 bytes (about
/// 0.5 GB here; 640 elements of the reference rotor, 2,564 DOFs, take 0.2 GB) and their
/// solves grow as n^3. Larger models go through the banded, few-mode or reduced paths.
pub const MAX_DENSE_DOFS: usize = 4_000;

/// The refusal of a model of `dofs` DOFs above [`MAX_DENSE_DOFS`], raised before anything
/// is allocated; `fix` says what to do instead.
pub fn too_large_for_dense(dofs: usize, fix: &str) -> Error {
    let gigabytes = 32.0 * (dofs as f64).powi(2) / 1e9;
    Error::Unsupported(format!(
        "the model has {dofs} DOFs ({} nodes): its dense matrices would take \
         {gigabytes:.1} GB and their solves grow as the cube of that; dense analyses are \
         limited to {MAX_DENSE_DOFS} DOFs. {fix}",
        dofs / DOFS_PER_NODE
    ))
}

/// [`assemble`] for the analyses that solve the dense matrices, refused above
/// [`MAX_DENSE_DOFS`] before anything is allocated.
///
/// # Errors
/// [`Error::Unsupported`] above [`MAX_DENSE_DOFS`], with `fix` in its message.
pub fn assemble_dense(model: &Model, bearings: Bearings, fix: &str) -> Result<SystemMatrices> {
    let dofs = model.dof_count();
    if dofs > MAX_DENSE_DOFS {
        return Err(too_large_for_dense(dofs, fix));
    }
    Ok(assemble(model, bearings))
}

/// How far from the diagonal the matrices [`assemble_banded`] makes of `model` reach: an
/// element's [`HALF_BANDWIDTH`], or further for a support between the shaft and a housing,
/// whose DOFs follow all the shaft's.
pub fn band_reach(model: &Model, bearings: Bearings) -> usize {
    reach(&supports(model, bearings))
}

/// The reach of an element or, further, of one of `supports`.
fn reach(supports: &[Support]) -> usize {
    supports
        .iter()
        .map(Support::reach)
        .fold(HALF_BANDWIDTH, usize::max)
}

/// Assembles M, K, G and C of a model as bands. A bearing between the shaft and a housing
/// widens the band to reach the housing's DOFs, which follow the shaft's.
pub fn assemble_banded(model: &Model, bearings: Bearings) -> BandedSystem {
    let n = model.dof_count();
    let supports = supports(model, bearings);
    let width = reach(&supports);
    let band = |_| Band::from_fn(n, (width, width), |_, _| 0.0);
    let [mut mass, mut stiffness, mut gyroscopic] = [0; 3].map(band);
    let opts = model.options;

    let mut element = 0;
    for section in &model.sections {
        let e = element_matrices(section);
        let rotary = if opts.rotary_inertia { 1.0 } else { 0.0 };
        let gyro = if opts.gyroscopic { 1.0 } else { 0.0 };
        for _ in 0..section.elements {
            let first = 4 * element;
            add_element(&mut mass, &e.mass_translational, first, 1.0);
            add_element(&mut mass, &e.mass_rotary, first, rotary);
            add_element(&mut stiffness, &e.stiffness, first, 1.0);
            add_element(&mut stiffness, &e.stiffness_axial, first, opts.axial_load);
            add_element(&mut gyroscopic, &e.gyroscopic, first, gyro);
            element += 1;
        }
    }

    for d in &model.disks {
        let node = d.station.node;
        let at = |direction| dof(node, direction);
        mass.add(at(Direction::Ux), at(Direction::Ux), d.mass);
        mass.add(at(Direction::Uy), at(Direction::Uy), d.mass);
        mass.add(at(Direction::Tx), at(Direction::Tx), d.diametral_inertia);
        mass.add(at(Direction::Ty), at(Direction::Ty), d.diametral_inertia);
        gyroscopic.add(at(Direction::Tx), at(Direction::Ty), d.polar_inertia);
        gyroscopic.add(at(Direction::Ty), at(Direction::Tx), -d.polar_inertia);
    }

    // Rayleigh damping is the rotor's own: the housings' mass is added after it.
    let r = model.damping;
    let mut damping = mass.map(|i, j, m| r.alpha * m + r.beta * stiffness.get(i, j));
    let [mut support_stiffness, mut support_damping, mut support_mass] = [0; 3].map(band);

    for (h, housing) in model.housings.iter().enumerate() {
        for d in model.housing_dofs(h) {
            mass.add(d, d, housing.mass);
            support_mass.add(d, d, housing.mass);
        }
    }
    for s in &supports {
        add_support(&mut stiffness, &mut damping, s);
        add_support(&mut support_stiffness, &mut support_damping, s);
    }
    if bearings == Bearings::Linearised {
        for s in squeeze_films_linearised(model, &mass, &stiffness) {
            add_block(&mut damping, &s, &s.damping);
            add_block(&mut support_damping, &s, &s.damping);
        }
    }

    BandedSystem {
        mass,
        stiffness,
        gyroscopic,
        damping,
        parts: Some(Parts {
            rayleigh: (r.alpha, r.beta),
            support_stiffness,
            support_damping,
            support_mass,
        }),
    }
}

/// The matrices of one of a section's (equal) elements, by the section's beam theory.
pub fn element_matrices(section: &ShaftSection) -> BeamMatrices {
    let p = BeamProperties {
        length: section.length / section.elements as f64,
        area: section.area(),
        second_moment: section.second_moment(),
        young_modulus: section.material.young_modulus,
        density: section.material.density,
    };
    match section.beam {
        BeamTheory::EulerBernoulli => beam_matrices(&p),
        BeamTheory::Timoshenko => {
            let ks = shear_rigidity(&p, section.material.poisson_ratio, section.shear_factor);
            timoshenko_matrices(&p, ks)
        }
    }
}

/// K_e u_e for one element of length `length` under the axial load `axial_load`: the
/// forces at its ends (see [`crate::statics`]). The bending part is taken from the
/// element's deformation, u_e less the rigid motion that carries its first node's
/// translations and its chord's rotation, which bending turns into no force: the same
/// product in exact arithmetic, but its round-off is that of the deformation, not of the
/// motion. On a fine mesh an element's stiffness (12 EI / l^3, 5e17 N/m for 10,000
/// elements of the reference rotor) times its motion (1e-4 m) loses every digit of the
/// forces its bending carries (1e2 N).
pub fn element_forces(e: &BeamMatrices, length: f64, axial_load: f64, u: &[f64]) -> [f64; 8] {
    // Chord rotations: x plane (ux, ty = d(ux)/dz), y plane (uy, tx = -d(uy)/dz).
    let chord_x = (u[4] - u[0]) / length;
    let chord_y = (u[5] - u[1]) / length;
    let bent = [
        0.0,
        0.0,
        u[2] + chord_y,
        u[3] - chord_x,
        0.0,
        0.0,
        u[6] + chord_y,
        u[7] - chord_x,
    ];
    std::array::from_fn(|i| {
        let bending: f64 = [2, 3, 6, 7]
            .iter()
            .map(|&j| e.stiffness[i][j] * bent[j])
            .sum();
        let geometric: f64 = (0..8).map(|j| e.stiffness_axial[i][j] * u[j]).sum();
        bending + axial_load * geometric
    })
}

/// K x for the stiffness [`assemble_banded`] makes of `model` (`supports`: its parts' support
/// stiffness), each element's part by [`element_forces`]: the product of a fine mesh's
/// stiffness without the round-off of its largest entries.
pub(crate) fn stiffness_product(model: &Model, supports: &Band, x: &[f64], out: &mut [f64]) {
    out.iter_mut().for_each(|o| *o = 0.0);
    let mut element = 0;
    for section in &model.sections {
        let e = element_matrices(section);
        let length = section.length / section.elements as f64;
        for _ in 0..section.elements {
            let first = DOFS_PER_NODE * element;
            let f = element_forces(&e, length, model.options.axial_load, &x[first..first + 8]);
            for (o, fi) in out[first..first + 8].iter_mut().zip(f) {
                *o += fi;
            }
            element += 1;
        }
    }
    supports.mul_add(x, out);
}

/// Every linear support of `model`: the linear bearings, the roller bearings' linearised
/// stiffness when `bearings` says so, and the housings' mountings, each between its inner
/// side and its outer side (a housing, or the ground).
fn supports(model: &Model, bearings: Bearings) -> Vec<Support> {
    let shaft = |node| [dof(node, Direction::Ux), dof(node, Direction::Uy)];
    let mut supports: Vec<Support> = model
        .bearings
        .iter()
        .map(|b| Support {
            inner: shaft(b.station.node),
            outer: model.outer_dofs(b.housing),
            stiffness: b.stiffness,
            damping: b.damping,
        })
        .collect();
    if bearings == Bearings::Linearised {
        supports.extend(model.roller_bearings.iter().map(|b| {
            let (k, c) = (b.linear_stiffness, b.linear_damping);
            Support {
                inner: shaft(b.station.node),
                outer: model.outer_dofs(b.housing),
                stiffness: [[k, 0.0], [0.0, k]],
                damping: [[c, 0.0], [0.0, c]],
            }
        }));
    }
    supports.extend(
        model
            .housings
            .iter()
            .enumerate()
            .map(|(h, housing)| Support {
                inner: model.housing_dofs(h),
                outer: model.outer_dofs(housing.on),
                stiffness: housing.stiffness,
                damping: housing.damping,
            }),
    );
    supports
}

/// The squeeze-film dampers linearised at the static position (see
/// [`crate::squeeze_film`]): supports of damping only.
/// The static position is that of the linear model without the dampers (`mass` and
/// `stiffness`), under gravity: a film carries no load at rest.
fn squeeze_films_linearised(model: &Model, mass: &Band, stiffness: &Band) -> Vec<Support> {
    if model.housings.iter().all(|h| h.squeeze_film.is_none()) {
        return Vec::new();
    }
    let statics = static_deflection(model, mass, stiffness);
    model
        .housings
        .iter()
        .enumerate()
        .filter_map(|(h, housing)| {
            let damper = housing.squeeze_film.as_ref()?;
            let inner = model.housing_dofs(h);
            let outer = model.outer_dofs(housing.on);
            let at = |d: [usize; 2]| d.map(|i| statics.as_ref().map_or(0.0, |u| u[i]));
            let base = outer.map_or([0.0; 2], at);
            let here = at(inner);
            let c = crate::squeeze_film::Film::new(damper)
                .linearised_damping([here[0] - base[0], here[1] - base[1]]);
            Some(Support {
                inner,
                outer,
                stiffness: [[0.0; 2]; 2],
                damping: [[c[0], c[1]], [c[2], c[3]]],
            })
        })
        .collect()
}

/// The static deflection of M, K under the model's gravity; `None` when K is singular
/// (a model not held, which the analyses refuse on their own terms).
fn static_deflection(model: &Model, mass: &Band, stiffness: &Band) -> Option<Vec<f64>> {
    let n = stiffness.size();
    let (lower, upper) = stiffness.widths();
    let lu = crate::linalg::banded::BandedLu::new(n, lower, upper, |i, j| stiffness.get(i, j))?;
    let mut u = vertical_load(model, mass);
    lu.solve(&mut u);
    Some(u)
}

/// Adds a support's stiffness and damping (see [`add_block`]).
fn add_support(stiffness: &mut Band, damping: &mut Band, s: &Support) {
    add_block(stiffness, s, &s.stiffness);
    add_block(damping, s, &s.damping);
}

/// Adds a support's 2x2 matrix `m`: on the inner side's DOFs, and, against a housing, with
/// the opposite sign between inner and outer and on the outer side's DOFs (the force
/// depends on the relative motion and acts on both, opposite).
fn add_block(band: &mut Band, s: &Support, m: &[[f64; 2]; 2]) {
    let mut sides = vec![(s.inner, s.inner, 1.0)];
    if let Some(outer) = s.outer {
        sides.extend([
            (s.inner, outer, -1.0),
            (outer, s.inner, -1.0),
            (outer, outer, 1.0),
        ]);
    }
    for (rows, cols, sign) in sides {
        for a in 0..2 {
            for b in 0..2 {
                band.add(rows[a], cols[b], sign * m[a][b]);
            }
        }
    }
}

/// Gravity load, consistent with the mass matrix: F = M r (-g), where r is the rigid
/// translation along y. Gives -m g on each translation and the consistent end moments of
/// the distributed shaft weight.
pub fn gravity_force(model: &Model, matrices: &impl Matrices) -> Vec<f64> {
    vertical_load(model, &matrices.banded().mass)
}

/// F = M r (-g) for the mass band `mass`, r the rigid translation along y of the shaft and
/// the housings.
fn vertical_load(model: &Model, mass: &Band) -> Vec<f64> {
    let n = mass.size();
    let (lower, upper) = mass.widths();
    let mut f = vec![0.0; n];
    let vertical = (0..model.node_count())
        .map(|node| dof(node, Direction::Uy))
        .chain((0..model.housings.len()).map(|h| model.housing_dofs(h)[1]));
    for col in vertical {
        for (i, fi) in f
            .iter_mut()
            .enumerate()
            .take((col + lower + 1).min(n))
            .skip(col.saturating_sub(upper))
        {
            *fi -= model.gravity * mass.get(i, col);
        }
    }
    f
}

/// Complex amplitude of the unbalance force per unit Omega^2, so that the force is
/// `Re(F Omega^2 e^{i Omega t})`: at each unbalance `m e e^{i phi}` on ux and
/// `-i m e e^{i phi}` on uy (a force turning with the shaft, towards +y first).
pub fn unbalance_force(model: &Model, dofs: usize) -> Vec<c64> {
    let mut f = vec![c64::new(0.0, 0.0); dofs];
    for u in &model.unbalances {
        let a = c64::from_polar(u.mass_radius, u.phase);
        f[dof(u.station.node, Direction::Ux)] += a;
        f[dof(u.station.node, Direction::Uy)] += c64::new(0.0, -1.0) * a;
    }
    f
}
