//! Assembly of the global matrices and force vectors (thesis eq. 2.4).
//!
//! Rigid disks add m_d to the translations and I_d to the rotations, and I_p to the
//! gyroscopic matrix as G[tx, ty] = I_p, G[ty, tx] = -I_p (thesis eq. 2.13 with the sign
//! derived in [`super::beam`]). Rayleigh damping C = alpha M + beta K uses the rotor's own
//! M and K (shaft and disks), not the bearings', then the bearings' damping is added.

use faer::{c64, Mat};

use super::beam::{beam_matrices, BeamMatrices, BeamProperties, Mat8};
use super::timoshenko::{shear_rigidity, timoshenko_matrices};
use super::{dof, Direction};
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

fn add_element(global: &mut Mat<f64>, local: &Mat8, first_dof: usize, scale: f64) {
    for i in 0..8 {
        for j in 0..8 {
            global[(first_dof + i, first_dof + j)] += scale * local[i][j];
        }
    }
}

/// Assembles M, K, G and C of a model.
pub fn assemble(model: &Model, bearings: Bearings) -> SystemMatrices {
    let n = 4 * model.node_count();
    let mut mass = Mat::<f64>::zeros(n, n);
    let mut stiffness = Mat::<f64>::zeros(n, n);
    let mut gyroscopic = Mat::<f64>::zeros(n, n);
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
        mass[(dof(node, Direction::Ux), dof(node, Direction::Ux))] += d.mass;
        mass[(dof(node, Direction::Uy), dof(node, Direction::Uy))] += d.mass;
        mass[(dof(node, Direction::Tx), dof(node, Direction::Tx))] += d.diametral_inertia;
        mass[(dof(node, Direction::Ty), dof(node, Direction::Ty))] += d.diametral_inertia;
        gyroscopic[(dof(node, Direction::Tx), dof(node, Direction::Ty))] += d.polar_inertia;
        gyroscopic[(dof(node, Direction::Ty), dof(node, Direction::Tx))] -= d.polar_inertia;
    }

    let r = model.damping;
    let mut damping = Mat::<f64>::zeros(n, n);
    for j in 0..n {
        for i in 0..n {
            damping[(i, j)] = r.alpha * mass[(i, j)] + r.beta * stiffness[(i, j)];
        }
    }

    for b in &model.bearings {
        add_support(
            &mut stiffness,
            &mut damping,
            b.station.node,
            &b.stiffness,
            &b.damping,
        );
    }
    if bearings == Bearings::Linearised {
        for b in &model.roller_bearings {
            let k = b.linear_stiffness;
            let c = b.linear_damping;
            add_support(
                &mut stiffness,
                &mut damping,
                b.station.node,
                &[[k, 0.0], [0.0, k]],
                &[[c, 0.0], [0.0, c]],
            );
        }
    }

    SystemMatrices {
        mass,
        stiffness,
        gyroscopic,
        damping,
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
    stiffness: &mut Mat<f64>,
    damping: &mut Mat<f64>,
    node: usize,
    k: &[[f64; 2]; 2],
    c: &[[f64; 2]; 2],
) {
    let idx = [dof(node, Direction::Ux), dof(node, Direction::Uy)];
    for a in 0..2 {
        for b in 0..2 {
            stiffness[(idx[a], idx[b])] += k[a][b];
            damping[(idx[a], idx[b])] += c[a][b];
        }
    }
}

/// Gravity load, consistent with the mass matrix: F = M r (-g), where r is the rigid
/// translation along y. Gives -m g on each translation and the consistent end moments of
/// the distributed shaft weight.
pub fn gravity_force(model: &Model, matrices: &SystemMatrices) -> Vec<f64> {
    let n = matrices.dofs();
    let mut f = vec![0.0; n];
    for node in 0..n / 4 {
        let col = dof(node, Direction::Uy);
        for (i, fi) in f.iter_mut().enumerate() {
            *fi -= model.gravity * matrices.mass[(i, col)];
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
