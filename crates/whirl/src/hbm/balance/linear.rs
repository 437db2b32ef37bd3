//! The linear part of the balance per harmonic: L(w) x with its w-derivative, the matrix
//! L(w) itself, and the external force.

use super::HarmonicBalance;
use crate::hbm::fourier::{cos_slot, sin_slot};
use crate::linalg::add_product;
use faer::Mat;

impl HarmonicBalance {
    /// The damping operator D = C + w G.
    pub(crate) fn damping_operator(&self, frequency: f64) -> Mat<f64> {
        &self.problem.matrices.damping + &self.problem.matrices.gyroscopic * faer::Scale(frequency)
    }

    /// L(w) as a matrix.
    pub(crate) fn linear_matrix(&self, frequency: f64) -> Mat<f64> {
        let n = self.problem.size();
        let p = &self.problem;
        let d = self.damping_operator(frequency);
        let mut l = Mat::zeros(self.unknowns(), self.unknowns());
        for i in 0..n {
            for j in 0..n {
                l[(i, j)] = p.matrices.stiffness[(i, j)];
                for r in 1..=self.options.harmonics {
                    let rw = r as f64 * frequency;
                    let z = p.matrices.stiffness[(i, j)] - rw * rw * p.matrices.mass[(i, j)];
                    let (c, s) = (cos_slot(r) * n, sin_slot(r) * n);
                    l[(c + i, c + j)] = z;
                    l[(s + i, s + j)] = z;
                    l[(c + i, s + j)] = rw * d[(i, j)];
                    l[(s + i, c + j)] = -rw * d[(i, j)];
                }
            }
        }
        l
    }

    /// A Nabla, with Nabla the derivative in the Fourier basis, by moving and scaling
    /// columns: Nabla maps b_r to r w on a_r and a_r to -r w on b_r, so column a_r of the
    /// product is -r w times column b_r of A and column b_r is r w times column a_r. A
    /// dense product would cost (n (2H + 1))^3.
    pub(crate) fn times_derivative(&self, a: &Mat<f64>, frequency: f64) -> Mat<f64> {
        let n = self.problem.size();
        let mut product = Mat::zeros(a.nrows(), a.ncols());
        for r in 1..=self.options.harmonics {
            let rw = r as f64 * frequency;
            for dof in 0..n {
                let (c, s) = (cos_slot(r) * n + dof, sin_slot(r) * n + dof);
                for i in 0..a.nrows() {
                    product[(i, c)] = -rw * a[(i, s)];
                    product[(i, s)] = rw * a[(i, c)];
                }
            }
        }
        product
    }

    /// out += L(w) x, block by block.
    pub(super) fn add_linear(&self, x: &[f64], frequency: f64, out: &mut [f64]) {
        let n = self.problem.size();
        let p = &self.problem;
        let d = self.damping_operator(frequency);
        let block = |slot: usize| &x[slot * n..(slot + 1) * n];
        add_product(&p.matrices.stiffness, 1.0, block(0), &mut out[..n]);
        for r in 1..=self.options.harmonics {
            let rw = r as f64 * frequency;
            let (c, s) = (cos_slot(r), sin_slot(r));
            for (row, own, other, sign) in [(c, c, s, 1.0), (s, s, c, -1.0)] {
                let out = &mut out[row * n..(row + 1) * n];
                add_product(&p.matrices.stiffness, 1.0, block(own), out);
                add_product(&p.matrices.mass, -rw * rw, block(own), out);
                add_product(&d, sign * rw, block(other), out);
            }
        }
    }

    /// out += dL/dw x.
    pub(super) fn add_linear_frequency_derivative(
        &self,
        x: &[f64],
        frequency: f64,
        out: &mut [f64],
    ) {
        let n = self.problem.size();
        let p = &self.problem;
        // d(r w D(w))/dw = r (D + w G) = r (C + 2 w G).
        let d_rwd = &p.matrices.damping + &p.matrices.gyroscopic * faer::Scale(2.0 * frequency);
        let block = |slot: usize| &x[slot * n..(slot + 1) * n];
        for r in 1..=self.options.harmonics {
            let rf = r as f64;
            let (c, s) = (cos_slot(r), sin_slot(r));
            for (row, own, other, sign) in [(c, c, s, 1.0), (s, s, c, -1.0)] {
                let out = &mut out[row * n..(row + 1) * n];
                add_product(
                    &p.matrices.mass,
                    -2.0 * rf * rf * frequency,
                    block(own),
                    out,
                );
                add_product(&d_rwd, sign * rf, block(other), out);
            }
        }
    }

    /// F_ext(w): constant force and the first harmonic of unbalance and fixed forcing;
    /// Re((u + i v) e^{i w t}) = u cos(w t) - v sin(w t).
    pub(super) fn external_force(&self, frequency: f64) -> Vec<f64> {
        let n = self.problem.size();
        let p = &self.problem;
        let w2 = frequency * frequency;
        let mut f = vec![0.0; self.unknowns()];
        for dof in 0..n {
            f[dof] = p.constant_force[dof];
            f[cos_slot(1) * n + dof] = w2 * p.unbalance_re[dof] + p.harmonic_re[dof];
            f[sin_slot(1) * n + dof] = -(w2 * p.unbalance_im[dof] + p.harmonic_im[dof]);
        }
        f
    }
}
