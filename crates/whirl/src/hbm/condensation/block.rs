//! One harmonic's block of the linear part condensed onto the kept coordinates: its entries
//! by part, the Schur complement with the reduced force, and their w-derivatives from the
//! same factorisation.

use super::matrices::PlainMatrices;
use super::{Block, BlockDerivative, BlockEntries};
use crate::error::{Error, Result};
use crate::linalg::banded::BandedLu;
use faer::Mat;

/// What condensing a block reads: the linear matrices and the split of the coordinates,
/// all shared, so the harmonics are condensed on several threads at once (the balance
/// itself holds its nonlinear forces, which are not `Sync`).
pub(super) struct Condenser<'a> {
    pub(super) plain: &'a PlainMatrices,
    /// The coordinates kept and condensed, ascending, as
    /// [`CondensedBalance`](super::CondensedBalance)'s.
    pub(super) kept: &'a [usize],
    pub(super) rest: &'a [usize],
    /// Half-bandwidth of the linear matrices among the `rest` coordinates.
    pub(super) rest_bandwidth: usize,
}

impl Condenser<'_> {
    /// Row/column indices of the kept and condensed coordinates in a block of
    /// `copies` (1 for the constant term, 2 for cos and sin) copies of the n coordinates.
    /// Kept ones are in slot order (all cos, then all sin), as the unknowns; condensed ones
    /// interleave the copies of each coordinate, which keeps D_bb banded.
    pub(super) fn partition(&self, copies: usize) -> (Vec<usize>, Vec<usize>) {
        let n = self.plain.n;
        let kept = (0..copies)
            .flat_map(|c| self.kept.iter().map(move |d| c * n + d))
            .collect();
        let rest = self
            .rest
            .iter()
            .flat_map(|d| (0..copies).map(move |c| c * n + d))
            .collect();
        (kept, rest)
    }

    /// Harmonic r's dynamic stiffness at w.
    pub(super) fn harmonic(&self, r: usize, frequency: f64) -> HarmonicBlock<'_> {
        HarmonicBlock {
            matrices: self.plain,
            r,
            frequency,
        }
    }

    /// Condenses one block D with its force f. One factorisation of D_bb serves X and z
    /// here and their w-derivatives later ([`Self::differentiate`]). Only entries within
    /// the band of D_bb are formed, so the cost grows linearly with the model size.
    pub(super) fn condense_block(&self, block: &HarmonicBlock<'_>, f: &[f64]) -> Result<Block> {
        let frequency = block.frequency;
        let copies = f.len() / self.plain.n;
        let (a, b) = self.partition(copies);
        let band = self.rest_band(copies);
        let d_bb = self.rest_pairs(block, copies);
        let singular = || {
            Error::singular(
                "condensed linear part",
                format!(
                    "condensation at {frequency} rad/s: the linear part with the nonlinear \
                 coordinates held is singular (a resonance of the condensed coordinates)"
                ),
            )
        };
        let lu =
            BandedLu::new(b.len(), band, band, |i, k| d_bb.entry(i, k).0).ok_or_else(singular)?;
        // [X | z] = D_bb^-1 [D_ba | f_b], row by row (one column per kept coordinate, then z).
        let (nb, cols) = (b.len(), a.len() + 1);
        let d_ba = self.entries(block, copies, Part::Rest, Part::Kept);
        let mut solution = vec![0.0; nb * cols];
        for (i, row) in solution.chunks_mut(cols).enumerate() {
            for (j, r) in row.iter_mut().take(a.len()).enumerate() {
                *r = d_ba[i * a.len() + j].0;
            }
            row[a.len()] = f[b[i]];
        }
        lu.solve_rows(&mut solution, cols);
        if !solution.iter().all(|v| v.is_finite()) {
            return Err(singular());
        }
        let (transfer, particular) = split(&solution, nb, a.len());
        let d_ab = self.entries(block, copies, Part::Kept, Part::Rest);
        let d_aa = self.entries(block, copies, Part::Kept, Part::Kept);
        let coupling = matrix(&d_ab, a.len(), |e| e.0);
        let schur = matrix(&d_aa, a.len(), |e| e.0) - &coupling * &transfer;
        let force = pick(f, &a) - &coupling * &particular;
        Ok(Block {
            schur,
            force: column(force),
            transfer,
            particular: column(particular),
            coupling,
            lu,
            entries: BlockEntries {
                rest_rest: d_bb,
                rest_kept: d_ba,
                kept_rest: d_ab,
                kept_kept: d_aa,
            },
            solution,
        })
    }

    /// The w-derivatives of a block condensed by [`Self::condense_block`], df/dw its
    /// force's: [dX | dz] = D_bb^-1 ([dD_ba | df_b] - dD_bb [X | z]) with the same
    /// factorisation, then dS = dD_aa - dD_ab X - D_ab dX and dg = df_a - dD_ab z - D_ab dz.
    pub(super) fn differentiate(&self, values: &Block, df: &[f64]) -> BlockDerivative {
        let copies = df.len() / self.plain.n;
        let (a, b) = self.partition(copies);
        let band = self.rest_band(copies);
        let entries = &values.entries;
        let (d_bb, d_ba) = (&entries.rest_rest, &entries.rest_kept);
        let (nb, cols) = (b.len(), a.len() + 1);
        let particular = Mat::from_fn(nb, 1, |i, _| values.particular[i]);
        let solution = &values.solution;
        let mut derivative_solution = vec![0.0; nb * cols];
        for (i, row) in derivative_solution.chunks_mut(cols).enumerate() {
            for (j, r) in row.iter_mut().take(a.len()).enumerate() {
                *r = d_ba[i * a.len() + j].1;
            }
            row[a.len()] = df[b[i]];
            for k in i.saturating_sub(band)..(i + band + 1).min(nb) {
                let c = d_bb.entry(i, k).1;
                if c != 0.0 {
                    for (r, y) in row.iter_mut().zip(&solution[k * cols..(k + 1) * cols]) {
                        *r -= c * y;
                    }
                }
            }
        }
        values.lu.solve_rows(&mut derivative_solution, cols);
        let (d_transfer, d_particular) = split(&derivative_solution, nb, a.len());
        let d_coupling = matrix(&entries.kept_rest, a.len(), |e| e.1);
        let schur = matrix(&entries.kept_kept, a.len(), |e| e.1)
            - &d_coupling * &values.transfer
            - &values.coupling * &d_transfer;
        let force = pick(df, &a) - &d_coupling * &particular - &values.coupling * &d_particular;
        BlockDerivative {
            schur,
            force: column(force),
        }
    }

    /// Half-bandwidth of D_bb in a block of `copies` copies: interleaved, its rows couple
    /// at most `copies` times the band of the coordinates apart.
    fn rest_band(&self, copies: usize) -> usize {
        copies * (self.rest_bandwidth + 1) - 1
    }

    /// The entries of D_bb and dD_bb/dw in a block of `copies` copies, formed once per
    /// pair of condensed coordinates within the matrices' band.
    fn rest_pairs(&self, block: &HarmonicBlock<'_>, copies: usize) -> RestPairs {
        let (count, reach) = (self.rest.len(), self.rest_bandwidth);
        let span = 2 * reach + 1;
        let mut pairs = vec![PairEntries::ZERO; count * span];
        for (ic, &row) in self.rest.iter().enumerate() {
            for kc in ic.saturating_sub(reach)..(ic + reach + 1).min(count) {
                pairs[ic * span + kc + reach - ic] = block.pair(row, self.rest[kc]);
            }
        }
        RestPairs {
            pairs,
            // One or two copies: a shift and a mask instead of divisions in the inner loops.
            shift: copies.trailing_zeros(),
            reach,
        }
    }

    /// The entries of a block of `copies` copies, and their w-derivatives, on the rows of
    /// the coordinates `rows` and the columns of `cols`, row-major in the layout of
    /// [`Self::partition`]; each pair of coordinates is formed once for all its copies.
    fn entries(
        &self,
        block: &HarmonicBlock<'_>,
        copies: usize,
        rows: Part,
        cols: Part,
    ) -> Vec<(f64, f64)> {
        let (row_dofs, col_dofs) = (self.dofs(rows), self.dofs(cols));
        let width = copies * col_dofs.len();
        let mut out = vec![(0.0, 0.0); copies * row_dofs.len() * width];
        for (ic, &row) in row_dofs.iter().enumerate() {
            for (jc, &col) in col_dofs.iter().enumerate() {
                let pair = block.pair(row, col);
                for (ci, cj) in (0..copies).flat_map(|ci| (0..copies).map(move |cj| (ci, cj))) {
                    let i = rows.position(ic, ci, row_dofs.len(), copies);
                    let j = cols.position(jc, cj, col_dofs.len(), copies);
                    out[i * width + j] = pair.at(ci, cj);
                }
            }
        }
        out
    }

    /// The coordinates of `part`.
    fn dofs(&self, part: Part) -> &[usize] {
        match part {
            Part::Kept => self.kept,
            Part::Rest => self.rest,
        }
    }
}

/// The kept (a) or the condensed (b) coordinates of a block.
#[derive(Clone, Copy)]
enum Part {
    Kept,
    Rest,
}

impl Part {
    /// Row (or column) of copy `copy` of the `index`-th of `count` coordinates in a block
    /// of `copies` copies, as [`Condenser::partition`] lays them out: kept ones in slot
    /// order (all cos, then all sin), condensed ones interleaving the copies.
    fn position(self, index: usize, copy: usize, count: usize, copies: usize) -> usize {
        match self {
            Part::Kept => copy * count + index,
            Part::Rest => copies * index + copy,
        }
    }
}

/// The matrix of `part` (the value or the w-derivative) of row-major entries with `rows`
/// rows.
pub(super) fn matrix(
    entries: &[(f64, f64)],
    rows: usize,
    part: impl Fn((f64, f64)) -> f64,
) -> Mat<f64> {
    let cols = entries.len() / rows;
    Mat::from_fn(rows, cols, |i, j| part(entries[i * cols + j]))
}

/// The entries `rows` of v as a column.
fn pick(v: &[f64], rows: &[usize]) -> Mat<f64> {
    Mat::from_fn(rows.len(), 1, |i, _| v[rows[i]])
}

/// A column's entries.
fn column(m: Mat<f64>) -> Vec<f64> {
    (0..m.nrows()).map(|i| m[(i, 0)]).collect()
}

/// The row-major solution [Y | y] of `rows` rows and `kept` + 1 columns as the matrix Y
/// and the column y.
pub(super) fn split(solution: &[f64], rows: usize, kept: usize) -> (Mat<f64>, Mat<f64>) {
    let cols = kept + 1;
    (
        Mat::from_fn(rows, kept, |i, j| solution[i * cols + j]),
        Mat::from_fn(rows, 1, |i, _| solution[i * cols + kept]),
    )
}

/// The dynamic stiffness of one harmonic r at w: the constant term's K for r = 0, else the
/// real form D_r(w) on (cos r, sin r) of the module documentation; entries are made on
/// demand for rows and columns given as (copy, coordinate), copy 0 for cos and 1 for sin.
pub(super) struct HarmonicBlock<'a> {
    matrices: &'a PlainMatrices,
    r: usize,
    frequency: f64,
}

impl HarmonicBlock<'_> {
    /// The entries of D_r and dD_r/dw that the coordinates `row` and `col` give in every
    /// pair of copies.
    fn pair(&self, row: usize, col: usize) -> PairEntries {
        let p = self.matrices;
        let at = row * p.n + col;
        if self.r == 0 {
            return PairEntries {
                diagonal: (p.stiffness[at], 0.0),
                coupling: (0.0, 0.0),
            };
        }
        let (rf, w) = (self.r as f64, self.frequency);
        let rw = rf * w;
        let damping = p.damping[at] + w * p.gyroscopic[at];
        PairEntries {
            diagonal: (
                p.stiffness[at] - rw * rw * p.mass[at],
                -2.0 * rf * rw * p.mass[at],
            ),
            // d(r w (C + w G))/dw = r (C + 2 w G).
            coupling: (rw * damping, rf * (damping + w * p.gyroscopic[at])),
        }
    }
}

/// D_bb's entries by pairs of condensed coordinates: pair (ic, kc) at
/// `ic * (2 reach + 1) + kc + reach - ic` for |ic - kc| <= reach, the half-bandwidth of the
/// matrices among them (coordinates further apart are not coupled).
pub(super) struct RestPairs {
    pub(super) pairs: Vec<PairEntries>,
    /// log2 of the copies (1 or 2).
    pub(super) shift: u32,
    pub(super) reach: usize,
}

impl RestPairs {
    /// Entry (i, k) of D_bb and of its w-derivative, rows and columns interleaving the
    /// copies of each coordinate; zero outside the band.
    fn entry(&self, i: usize, k: usize) -> (f64, f64) {
        let (ic, kc) = (i >> self.shift, k >> self.shift);
        if ic.abs_diff(kc) > self.reach {
            return (0.0, 0.0);
        }
        let copy = (1 << self.shift) - 1;
        self.pairs[ic * (2 * self.reach + 1) + kc + self.reach - ic].at(i & copy, k & copy)
    }
}

/// Entry (value, w-derivative) of D_r for one pair of coordinates: Z_r on the copies'
/// diagonal, r w D from sin to cos and -r w D from cos to sin.
#[derive(Clone, Copy)]
pub(super) struct PairEntries {
    diagonal: (f64, f64),
    coupling: (f64, f64),
}

impl PairEntries {
    const ZERO: PairEntries = PairEntries {
        diagonal: (0.0, 0.0),
        coupling: (0.0, 0.0),
    };

    /// The entry in the row of copy `row` and the column of copy `col` (0 cos, 1 sin).
    fn at(self, row: usize, col: usize) -> (f64, f64) {
        match (row, col) {
            (0, 0) | (1, 1) => self.diagonal,
            (0, _) => self.coupling,
            _ => (-self.coupling.0, -self.coupling.1),
        }
    }
}
