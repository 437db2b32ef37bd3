//! The linear matrices as condensation reads them: entry by entry, and by rows of nonzeros
//! for products with vectors.

use crate::system::System;
use faer::Mat;

/// M, K, C and G row-major: the condensation reads single entries in its inner loops.
pub(super) struct PlainMatrices {
    pub(super) n: usize,
    pub(super) mass: Vec<f64>,
    pub(super) stiffness: Vec<f64>,
    pub(super) damping: Vec<f64>,
    pub(super) gyroscopic: Vec<f64>,
}

impl PlainMatrices {
    pub(super) fn new(p: &System) -> PlainMatrices {
        let n = p.size();
        let plain = |m: &Mat<f64>| (0..n * n).map(|k| m[(k / n, k % n)]).collect::<Vec<f64>>();
        PlainMatrices {
            n,
            mass: plain(&p.matrices.mass),
            stiffness: plain(&p.matrices.stiffness),
            damping: plain(&p.matrices.damping),
            gyroscopic: plain(&p.matrices.gyroscopic),
        }
    }
}

/// M, K, C and G by rows of the nonzeros of any of them, for products of D_r(w) with
/// vectors.
pub(super) struct SparseMatrices {
    pub(super) n: usize,
    /// Row i's entries are `starts[i]..starts[i + 1]`.
    pub(super) starts: Vec<usize>,
    pub(super) columns: Vec<usize>,
    /// K, M, C and G at each entry.
    pub(super) values: Vec<[f64; 4]>,
}

impl SparseMatrices {
    pub(super) fn new(p: &PlainMatrices) -> SparseMatrices {
        let n = p.n;
        let mut starts = vec![0];
        let (mut columns, mut values) = (Vec::new(), Vec::new());
        for i in 0..n {
            for j in 0..n {
                let at = i * n + j;
                let entry = [p.stiffness[at], p.mass[at], p.damping[at], p.gyroscopic[at]];
                if entry.iter().any(|&e| e != 0.0) {
                    columns.push(j);
                    values.push(entry);
                }
            }
            starts.push(columns.len());
        }
        SparseMatrices {
            n,
            starts,
            columns,
            values,
        }
    }

    /// D_r(w) v for a vector v of block r laid out as copies of the n coordinates (one for
    /// r = 0, cos then sin otherwise; the real form of the module documentation), and
    /// |D_r(w)| |v| row by row, the size of the terms summed.
    pub(super) fn apply(&self, r: usize, frequency: f64, v: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let n = self.n;
        let mut y = vec![0.0; v.len()];
        let mut size = vec![0.0; v.len()];
        let rw = r as f64 * frequency;
        for i in 0..n {
            for e in self.starts[i]..self.starts[i + 1] {
                let j = self.columns[e];
                let [k, m, c, g] = self.values[e];
                if r == 0 {
                    y[i] += k * v[j];
                    size[i] += (k * v[j]).abs();
                    continue;
                }
                let z = k - rw * rw * m;
                let coupling = rw * (c + frequency * g);
                y[i] += z * v[j] + coupling * v[n + j];
                y[n + i] += z * v[n + j] - coupling * v[j];
                size[i] += (z * v[j]).abs() + (coupling * v[n + j]).abs();
                size[n + i] += (z * v[n + j]).abs() + (coupling * v[j]).abs();
            }
        }
        (y, size)
    }
}

/// The largest |i - j| over nonzero entries (i, j) of M, K, C and G among `dofs` (indices
/// into `dofs`).
pub(super) fn bandwidth(problem: &System, dofs: &[usize]) -> usize {
    let matrices = problem.matrices.all();
    let mut width = 0;
    for (i, &r) in dofs.iter().enumerate() {
        for (j, &c) in dofs.iter().enumerate().skip(i + width + 1) {
            if matrices
                .iter()
                .any(|m| m[(r, c)] != 0.0 || m[(c, r)] != 0.0)
            {
                width = j - i;
            }
        }
    }
    width
}
