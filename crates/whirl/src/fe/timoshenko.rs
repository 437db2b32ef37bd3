//! Shear-deformable (Timoshenko) rotating beam element, 8x8, with the interdependent
//! interpolation of Nelson (1980), "A finite rotating shaft element using Timoshenko beam
//! theory", J. Mech. Des. 102.
//!
//! The cross-section rotates by beta, which differs from the slope w' by the shear strain
//! gamma = w' - beta. The strain energy has a bending and a shear part,
//!
//! ```text
//! U = 1/2 int E I (beta')^2 ds + 1/2 int kappa G A (w' - beta)^2 ds
//! ```
//!
//! with kappa the section's shear factor and G = E / (2 (1 + nu)). The nodal rotations are
//! section rotations (tx = -beta_y, ty = beta_x), so rotary inertia and gyroscopic moments
//! act on beta. With phi = 12 E I / (kappa G A l^2) and x = s / l, the shape functions that
//! solve the homogeneous Timoshenko equations on the element (so the static stiffness is
//! exact and gamma is constant along the element) are
//!
//! ```text
//! w    = [(1 + phi - phi x - 3x^2 + 2x^3) w1 + l (x (1 + phi/2) - (2 + phi/2) x^2 + x^3) b1
//!         + (phi x + 3x^2 - 2x^3) w2 + l (-(phi/2) x - (1 - phi/2) x^2 + x^3) b2] / (1 + phi)
//! beta = [6 (x^2 - x)/l w1 + (1 + phi - (4 + phi) x + 3x^2) b1
//!         - 6 (x^2 - x)/l w2 + ((phi - 2) x + 3x^2) b2] / (1 + phi)
//! ```
//!
//! At phi = 0 they are the Hermite cubics of the Euler-Bernoulli element and beta = w'. The
//! matrices are integrated by the same Gauss rule as [`super::beam`] (the integrands are
//! polynomials of degree 6 at most), which gives the closed-form stiffness
//! `E I / ((1 + phi) l^3) [[12, 6l, -12, 6l], [6l, (4 + phi) l^2, -6l, (2 - phi) l^2], ...]`.

use super::beam::{integrate, BeamMatrices, BeamProperties, Interpolation};

/// Shear rigidity kappa G A of a section, N, with G = E / (2 (1 + nu)).
pub fn shear_rigidity(p: &BeamProperties, poisson_ratio: f64, shear_factor: f64) -> f64 {
    shear_factor * p.young_modulus / (2.0 * (1.0 + poisson_ratio)) * p.area
}

/// Integrates the Timoshenko element's matrices; `shear_rigidity` is kappa G A, N.
pub fn timoshenko_matrices(p: &BeamProperties, shear_rigidity: f64) -> BeamMatrices {
    let l = p.length;
    let phi = 12.0 * p.young_modulus * p.second_moment / (shear_rigidity * l * l);
    integrate(p, shear_rigidity, |s| nelson(s / l, l, phi))
}

/// Nelson's interpolation at x = s / l and its derivatives along s.
fn nelson(x: f64, l: f64, phi: f64) -> Interpolation {
    let d = 1.0 / (1.0 + phi);
    let (x2, x3) = (x * x, x * x * x);
    Interpolation {
        deflection: [
            d * (1.0 + phi - phi * x - 3.0 * x2 + 2.0 * x3),
            d * l * ((1.0 + 0.5 * phi) * x - (2.0 + 0.5 * phi) * x2 + x3),
            d * (phi * x + 3.0 * x2 - 2.0 * x3),
            d * l * (-0.5 * phi * x - (1.0 - 0.5 * phi) * x2 + x3),
        ],
        slope: [
            d * (-phi - 6.0 * x + 6.0 * x2) / l,
            d * (1.0 + 0.5 * phi - (4.0 + phi) * x + 3.0 * x2),
            d * (phi + 6.0 * x - 6.0 * x2) / l,
            d * (-0.5 * phi - (2.0 - phi) * x + 3.0 * x2),
        ],
        rotation: [
            d * 6.0 * (x2 - x) / l,
            d * (1.0 + phi - (4.0 + phi) * x + 3.0 * x2),
            -d * 6.0 * (x2 - x) / l,
            d * ((phi - 2.0) * x + 3.0 * x2),
        ],
        curvature: [
            d * 6.0 * (2.0 * x - 1.0) / (l * l),
            d * (6.0 * x - 4.0 - phi) / l,
            -d * 6.0 * (2.0 * x - 1.0) / (l * l),
            d * (6.0 * x + phi - 2.0) / l,
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::super::beam::beam_matrices;
    use super::*;

    fn props() -> BeamProperties {
        // A short, thick element (l/d = 0.5) where shear matters: phi is about 0.9.
        BeamProperties {
            length: 0.025,
            area: std::f64::consts::PI / 4.0 * 0.05f64.powi(2),
            second_moment: std::f64::consts::PI / 64.0 * 0.05f64.powi(4),
            young_modulus: 2.1e11,
            density: 7800.0,
        }
    }

    #[test]
    fn stiffness_matches_the_closed_form() {
        let p = props();
        let ks = shear_rigidity(&p, 0.3, crate::model::circular_shear_factor(0.05, 0.0, 0.3));
        let e = timoshenko_matrices(&p, ks);
        let l = p.length;
        let phi = 12.0 * p.young_modulus * p.second_moment / (ks * l * l);
        assert!(phi > 0.5, "the test element must be shear-dominated: {phi}");
        let c = p.young_modulus * p.second_moment / ((1.0 + phi) * l.powi(3));
        let want = [
            [12.0, 6.0 * l, -12.0, 6.0 * l],
            [6.0 * l, (4.0 + phi) * l * l, -6.0 * l, (2.0 - phi) * l * l],
            [-12.0, -6.0 * l, 12.0, -6.0 * l],
            [6.0 * l, (2.0 - phi) * l * l, -6.0 * l, (4.0 + phi) * l * l],
        ];
        // x-z plane DOFs (ux, ty) are (w, beta) directly.
        let idx = [0, 3, 4, 7];
        for a in 0..4 {
            for b in 0..4 {
                let got = e.stiffness[idx[a]][idx[b]];
                // Gauss quadrature is exact for these polynomials: round-off only.
                assert!((got - c * want[a][b]).abs() < 1e-10 * c * 12.0, "{a} {b}");
            }
        }
    }

    #[test]
    fn mass_matrices_match_przemienieckis_closed_forms() {
        // Translational and rotary mass of the Timoshenko element in the plane (w, beta)
        // (Przemieniecki 1968; Friswell et al. 2010, eq. 5.106-5.107).
        let p = props();
        let ks = shear_rigidity(&p, 0.3, crate::model::circular_shear_factor(0.05, 0.0, 0.3));
        let e = timoshenko_matrices(&p, ks);
        let l = p.length;
        let f = 12.0 * p.young_modulus * p.second_moment / (ks * l * l);
        let mt = p.density * p.area * l / (840.0 * (1.0 + f).powi(2));
        let (a, b, c, d) = (
            312.0 + 588.0 * f + 280.0 * f * f,
            (44.0 + 77.0 * f + 35.0 * f * f) * l,
            108.0 + 252.0 * f + 140.0 * f * f,
            (26.0 + 63.0 * f + 35.0 * f * f) * l,
        );
        let (g, h) = (
            (8.0 + 14.0 * f + 7.0 * f * f) * l * l,
            (6.0 + 14.0 * f + 7.0 * f * f) * l * l,
        );
        let translational = [[a, b, c, -d], [b, g, d, -h], [c, d, a, -b], [-d, -h, -b, g]];
        let mr = p.density * p.second_moment / (30.0 * (1.0 + f).powi(2) * l);
        let (r1, r2, r3, r4) = (
            36.0,
            (3.0 - 15.0 * f) * l,
            (4.0 + 5.0 * f + 10.0 * f * f) * l * l,
            (-1.0 - 5.0 * f + 5.0 * f * f) * l * l,
        );
        let rotary = [
            [r1, r2, -r1, r2],
            [r2, r3, -r2, r4],
            [-r1, -r2, r1, -r2],
            [r2, r4, -r2, r3],
        ];
        let idx = [0, 3, 4, 7];
        for i in 0..4 {
            for j in 0..4 {
                let (gi, gj) = (idx[i], idx[j]);
                // Exact quadrature: round-off of the largest entry only.
                let t = e.mass_translational[gi][gj] - mt * translational[i][j];
                assert!(t.abs() < 1e-12 * mt * a, "translational {i} {j}");
                let r = e.mass_rotary[gi][gj] - mr * rotary[i][j];
                assert!(r.abs() < 1e-12 * mr * r3 / (l * l) * 10.0, "rotary {i} {j}");
            }
        }
    }

    #[test]
    fn without_shear_deformation_it_is_the_euler_bernoulli_element() {
        // kappa G A -> infinity gives phi -> 0: the interpolation becomes Hermite's.
        let p = props();
        let t = timoshenko_matrices(&p, 1e30);
        let e = beam_matrices(&p);
        for i in 0..8 {
            for j in 0..8 {
                // phi ~ 1e-20 here: differences are round-off of the largest entries.
                let close = |a: f64, b: f64, scale: f64| (a - b).abs() < 1e-9 * scale;
                assert!(close(
                    t.stiffness[i][j],
                    e.stiffness[i][j],
                    e.stiffness[0][0]
                ));
                assert!(close(
                    t.mass_translational[i][j],
                    e.mass_translational[i][j],
                    e.mass_translational[0][0]
                ));
                assert!(close(
                    t.gyroscopic[i][j],
                    e.gyroscopic[i][j],
                    e.mass_rotary[0][0]
                ));
            }
        }
    }
}
