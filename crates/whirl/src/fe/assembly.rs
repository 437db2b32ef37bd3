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
use crate::linalg::Band;
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
}

/// A bearing as assembled: its node, stiffness and damping (x, y).
type Support = (usize, [[f64; 2]; 2], [[f64; 2]; 2]);

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
    let dofs = DOFS_PER_NODE * model.node_count();
    if dofs > MAX_DENSE_DOFS {
        return Err(too_large_for_dense(dofs, fix));
    }
    Ok(assemble(model, bearings))
}

/// Assembles M, K, G and C of a model as bands.
pub fn assemble_banded(model: &Model, bearings: Bearings) -> BandedSystem {
    let n = 4 * model.node_count();
    let band = |_| Band::from_fn(n, (HALF_BANDWIDTH, HALF_BANDWIDTH), |_, _| 0.0);
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

    let r = model.damping;
    let mut damping = mass.map(|i, j, m| r.alpha * m + r.beta * stiffness.get(i, j));
    let [mut support_stiffness, mut support_damping] = [0; 2].map(band);

    let mut supports: Vec<Support> = model
        .bearings
        .iter()
        .map(|b| (b.station.node, b.stiffness, b.damping))
        .collect();
    if bearings == Bearings::Linearised {
        supports.extend(model.roller_bearings.iter().map(|b| {
            let (k, c) = (b.linear_stiffness, b.linear_damping);
            (b.station.node, [[k, 0.0], [0.0, k]], [[c, 0.0], [0.0, c]])
        }));
    }
    for (node, k, c) in &supports {
        add_support(&mut stiffness, &mut damping, *node, k, c);
        add_support(&mut support_stiffness, &mut support_damping, *node, k, c);
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

fn add_support(
    stiffness: &mut Band,
    damping: &mut Band,
    node: usize,
    k: &[[f64; 2]; 2],
    c: &[[f64; 2]; 2],
) {
    let idx = [dof(node, Direction::Ux), dof(node, Direction::Uy)];
    for a in 0..2 {
        for b in 0..2 {
            stiffness.add(idx[a], idx[b], k[a][b]);
            damping.add(idx[a], idx[b], c[a][b]);
        }
    }
}

/// Gravity load, consistent with the mass matrix: F = M r (-g), where r is the rigid
/// translation along y. Gives -m g on each translation and the consistent end moments of
/// the distributed shaft weight.
pub fn gravity_force(model: &Model, matrices: &impl Matrices) -> Vec<f64> {
    let banded = matrices.banded();
    let mass = &banded.mass;
    let n = mass.size();
    let (lower, upper) = mass.widths();
    let mut f = vec![0.0; n];
    for node in 0..n / 4 {
        let col = dof(node, Direction::Uy);
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
