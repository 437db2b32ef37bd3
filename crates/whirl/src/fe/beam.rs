//! Euler-Bernoulli rotating beam element, 8x8 (thesis eqs. 2.6-2.12; Nelson & McVaugh
//! 1976; Lalanne & Ferraris 1998).
//!
//! Element DOFs, in this order: `[ux1, uy1, tx1, ty1, ux2, uy2, tx2, ty2]` with
//! `ty = d(ux)/dz` and `tx = -d(uy)/dz` (docs/theory.md section 1). With Hermite cubics
//! psi_1..psi_4 of eq. 2.9 on s in [0, l]:
//!
//! ```text
//! ux(s) =  psi1 ux1 + psi2 ty1 + psi3 ux2 + psi4 ty2
//! uy(s) =  psi1 uy1 - psi2 tx1 + psi3 uy2 - psi4 tx2
//! tx(s) = -uy'(s),   ty(s) = ux'(s)
//! ```
//!
//! The matrices are the integrals of eqs. 2.7, 2.10 and 2.12, evaluated by 4-point Gauss
//! quadrature, which is exact for the polynomial degrees involved (at most 6), rather than
//! typed in from appendix A, whose signs and positions were garbled by text extraction:
//!
//! ```text
//! M_T = int rho A  Psi^T Psi            (translational mass)
//! M_R = int rho I  Phi^T Phi            (rotary inertia)
//! K   = int E I    Psi''^T Psi''        (bending)
//! K_F = int F_z    Psi'^T Psi'          (axial load, eq. 2.3; tension stiffens)
//! G   = int rho Ip (Phi_x^T Phi_y - Phi_y^T Phi_x),  Ip = 2 I (polar, per unit area)
//! ```
//!
//! The gyroscopic sign follows from the angular momentum of a spinning section
//! H = Id (tx', ty') + Ip Omega (ty, -tx): the moments are Ip Omega (ty', -tx'), so the
//! equation of motion M q'' + Omega G q' + K q = F has G[tx, ty] = +Ip, G[ty, tx] = -Ip.
//! With this sign forward whirl frequencies rise with speed (checked in the tests).

/// An 8x8 element matrix, row-major.
pub type Mat8 = [[f64; 8]; 8];

/// Cross-section and material of one element.
#[derive(Debug, Clone, Copy)]
pub struct BeamProperties {
    /// Element length, m.
    pub length: f64,
    /// Area, m^2.
    pub area: f64,
    /// Second moment of area, m^4.
    pub second_moment: f64,
    /// Young's modulus, Pa.
    pub young_modulus: f64,
    /// Density, kg/m^3.
    pub density: f64,
}

/// The element's matrices.
#[derive(Debug, Clone)]
pub struct BeamMatrices {
    /// Translational mass.
    pub mass_translational: Mat8,
    /// Rotary-inertia mass.
    pub mass_rotary: Mat8,
    /// Bending stiffness.
    pub stiffness: Mat8,
    /// Geometric stiffness per newton of axial tension.
    pub stiffness_axial: Mat8,
    /// Gyroscopic matrix (to be multiplied by the spin speed).
    pub gyroscopic: Mat8,
}

/// Hermite shape functions and their first and second derivatives at s in [0, l].
fn hermite(s: f64, l: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let x = s / l;
    let n = [
        1.0 - 3.0 * x * x + 2.0 * x * x * x,
        s * (1.0 - 2.0 * x + x * x),
        3.0 * x * x - 2.0 * x * x * x,
        l * (-x * x + x * x * x),
    ];
    let d1 = [
        (-6.0 * x + 6.0 * x * x) / l,
        1.0 - 4.0 * x + 3.0 * x * x,
        (6.0 * x - 6.0 * x * x) / l,
        -2.0 * x + 3.0 * x * x,
    ];
    let d2 = [
        (-6.0 + 12.0 * x) / (l * l),
        (-4.0 + 6.0 * x) / l,
        (6.0 - 12.0 * x) / (l * l),
        (-2.0 + 6.0 * x) / l,
    ];
    (n, d1, d2)
}

/// Rows giving (ux, uy) at a section from shape-function values `f` (eq. 2.8, Psi).
fn displacement_rows(f: &[f64; 4]) -> [[f64; 8]; 2] {
    [
        [f[0], 0.0, 0.0, f[1], f[2], 0.0, 0.0, f[3]],
        [0.0, f[0], -f[1], 0.0, 0.0, f[2], -f[3], 0.0],
    ]
}

/// Rows giving (tx, ty) = (-uy', ux') from first derivatives `d` (eq. 2.8, Phi).
fn rotation_rows(d: &[f64; 4]) -> [[f64; 8]; 2] {
    let [ux, uy] = displacement_rows(d);
    [uy.map(|v| -v), ux]
}

/// Adds `w * a^T b` to `m`.
fn add_outer(m: &mut Mat8, w: f64, a: &[f64; 8], b: &[f64; 8]) {
    for i in 0..8 {
        for j in 0..8 {
            m[i][j] += w * a[i] * b[j];
        }
    }
}

/// 4-point Gauss-Legendre nodes and weights on [-1, 1].
const GAUSS4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_8),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_8),
];

/// Interpolation of one plane at a point of the element: the deflection w and the section
/// rotation beta in terms of the plane's nodal values (w1, theta1, w2, theta2), with their
/// derivatives along the axis. Euler-Bernoulli elements have beta = w'; shear-deformable
/// ones (see [`super::timoshenko`]) do not.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Interpolation {
    /// w.
    pub deflection: [f64; 4],
    /// dw/ds.
    pub slope: [f64; 4],
    /// beta, the rotation of the cross-section.
    pub rotation: [f64; 4],
    /// d(beta)/ds, the bending curvature.
    pub curvature: [f64; 4],
}

/// Integrates the element matrices of the Euler-Bernoulli element.
pub fn beam_matrices(p: &BeamProperties) -> BeamMatrices {
    integrate(p, 0.0, |s| {
        let (n, d1, d2) = hermite(s, p.length);
        Interpolation {
            deflection: n,
            slope: d1,
            rotation: d1,
            curvature: d2,
        }
    })
}

/// Integrates the element matrices for an interpolation; `shear_rigidity` kappa G A (N) adds
/// the shear strain energy int kappa G A (w' - beta)^2 ds (zero for Euler-Bernoulli, where
/// beta = w' makes the shear strain vanish anyway).
pub(crate) fn integrate(
    p: &BeamProperties,
    shear_rigidity: f64,
    shape: impl Fn(f64) -> Interpolation,
) -> BeamMatrices {
    let z = [[0.0; 8]; 8];
    let mut out = BeamMatrices {
        mass_translational: z,
        mass_rotary: z,
        stiffness: z,
        stiffness_axial: z,
        gyroscopic: z,
    };
    let l = p.length;
    let rho_a = p.density * p.area;
    let rho_i = p.density * p.second_moment;
    let ei = p.young_modulus * p.second_moment;
    for (xi, wg) in GAUSS4 {
        let s = 0.5 * l * (xi + 1.0);
        let w = 0.5 * l * wg;
        let f = shape(s);
        let psi = displacement_rows(&f.deflection);
        let phi = rotation_rows(&f.rotation);
        let slope = displacement_rows(&f.slope);
        let curvature = displacement_rows(&f.curvature);
        let section = displacement_rows(&f.rotation);
        for r in 0..2 {
            add_outer(&mut out.mass_translational, w * rho_a, &psi[r], &psi[r]);
            add_outer(&mut out.mass_rotary, w * rho_i, &phi[r], &phi[r]);
            add_outer(&mut out.stiffness, w * ei, &curvature[r], &curvature[r]);
            add_outer(&mut out.stiffness_axial, w, &slope[r], &slope[r]);
            if shear_rigidity > 0.0 {
                let mut gamma = slope[r];
                for (g, b) in gamma.iter_mut().zip(&section[r]) {
                    *g -= b;
                }
                add_outer(&mut out.stiffness, w * shear_rigidity, &gamma, &gamma);
            }
        }
        // Polar inertia per length is rho * 2I for a circular section.
        let jp = 2.0 * rho_i;
        add_outer(&mut out.gyroscopic, w * jp, &phi[0], &phi[1]);
        add_outer(&mut out.gyroscopic, -w * jp, &phi[1], &phi[0]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn props() -> BeamProperties {
        BeamProperties {
            length: 0.065,
            area: 2.454e-3,
            second_moment: 4.79e-7,
            young_modulus: 2.11e11,
            density: 7810.0,
        }
    }

    /// Textbook closed forms in the plane (w, w') (Friswell et al. 2010, ch. 5).
    type Mat4 = [[f64; 4]; 4];

    fn planar_reference(p: &BeamProperties) -> (Mat4, Mat4, Mat4) {
        let l = p.length;
        let m = p.density * p.area * l / 420.0;
        let mt = [
            [156.0, 22.0 * l, 54.0, -13.0 * l],
            [22.0 * l, 4.0 * l * l, 13.0 * l, -3.0 * l * l],
            [54.0, 13.0 * l, 156.0, -22.0 * l],
            [-13.0 * l, -3.0 * l * l, -22.0 * l, 4.0 * l * l],
        ]
        .map(|r| r.map(|v| v * m));
        let r = p.density * p.second_moment / (30.0 * l);
        let mr = [
            [36.0, 3.0 * l, -36.0, 3.0 * l],
            [3.0 * l, 4.0 * l * l, -3.0 * l, -l * l],
            [-36.0, -3.0 * l, 36.0, -3.0 * l],
            [3.0 * l, -l * l, -3.0 * l, 4.0 * l * l],
        ]
        .map(|row| row.map(|v| v * r));
        let k = p.young_modulus * p.second_moment / l.powi(3);
        let kb = [
            [12.0, 6.0 * l, -12.0, 6.0 * l],
            [6.0 * l, 4.0 * l * l, -6.0 * l, 2.0 * l * l],
            [-12.0, -6.0 * l, 12.0, -6.0 * l],
            [6.0 * l, 2.0 * l * l, -6.0 * l, 4.0 * l * l],
        ]
        .map(|row| row.map(|v| v * k));
        (mt, mr, kb)
    }

    #[test]
    fn xz_plane_matches_the_closed_forms() {
        let p = props();
        let e = beam_matrices(&p);
        let (mt, mr, kb) = planar_reference(&p);
        // x-z plane DOFs (ux, ty) are (w, w') directly.
        let idx = [0, 3, 4, 7];
        for a in 0..4 {
            for b in 0..4 {
                let (i, j) = (idx[a], idx[b]);
                // Gauss quadrature is exact here: agreement to round-off.
                assert!((e.mass_translational[i][j] - mt[a][b]).abs() < 1e-12 * mt[0][0]);
                assert!((e.mass_rotary[i][j] - mr[a][b]).abs() < 1e-12 * mr[0][0]);
                assert!((e.stiffness[i][j] - kb[a][b]).abs() < 1e-9 * kb[0][0]);
            }
        }
    }

    #[test]
    fn yz_plane_flips_the_rotation_sign() {
        let p = props();
        let e = beam_matrices(&p);
        let (_, _, kb) = planar_reference(&p);
        // y-z plane DOFs (uy, tx) are (w, -w').
        let idx = [1, 2, 5, 6];
        let sign = [1.0, -1.0, 1.0, -1.0];
        for a in 0..4 {
            for b in 0..4 {
                let want = sign[a] * sign[b] * kb[a][b];
                assert!((e.stiffness[idx[a]][idx[b]] - want).abs() < 1e-9 * kb[0][0]);
            }
        }
    }

    #[test]
    fn symmetry_and_skew_symmetry() {
        let e = beam_matrices(&props());
        for i in 0..8 {
            for j in 0..8 {
                let tol = 1e-12;
                assert!((e.mass_translational[i][j] - e.mass_translational[j][i]).abs() < tol);
                assert!((e.stiffness[i][j] - e.stiffness[j][i]).abs() < 1e-3);
                assert!((e.gyroscopic[i][j] + e.gyroscopic[j][i]).abs() < tol);
            }
        }
    }

    #[test]
    fn gyroscopic_is_twice_the_rotary_inertia_pattern() {
        // For a circular section G couples (ux, ty) with (uy, tx) and its entries have the
        // magnitude of the rotary mass times 2 (Nelson & McVaugh 1976): G[1][0]... checked
        // through the identity G = 2 (Phi_x^T Phi_y - Phi_y^T Phi_x) rho I.
        let e = beam_matrices(&props());
        // ty1-tx1 entry: 2 rho I * int (psi2')^2 ds = 2 * Mr[ty1][ty1].
        assert!((e.gyroscopic[2][3] - 2.0 * e.mass_rotary[3][3]).abs() < 1e-15);
        assert!((e.gyroscopic[3][2] + 2.0 * e.mass_rotary[3][3]).abs() < 1e-15);
    }
}
