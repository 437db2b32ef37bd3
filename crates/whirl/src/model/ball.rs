//! Ball bearings (deep-groove and angular-contact): the point contact's geometry and its
//! Hertz stiffness (Harris, *Rolling Bearing Analysis*, the chapters on contact stress and
//! deformation and on internal load distribution; docs/theory.md section 5, "Ball bearings").
//!
//! A ball of diameter D sits in grooves of radii f_i D (inner) and f_o D (outer), f the
//! conformity (> 1/2). The groove curvature centres lie A = (f_i + f_o - 1) D apart when
//! the ball just touches both. A ball bearing is a [`RollerBearing`] whose rollers are
//! balls: its `contact_stiffness` is K_n of one ball (inner and outer contacts in series,
//! load exponent 3/2) and its `ball` holds what the point contact adds (conformities,
//! contact angle, axial load).
//!
//! Each contact's stiffness follows from its curvature sum (Hamrock & Brewe's
//! approximations of the contact ellipse, as given by Harris):
//!
//! ```text
//! 1/R_x = 2 / (D (1 -+ g)),  1/R_y = (2 f - 1) / (f D),  g = D cos(alpha) / d_m
//! 1/R = 1/R_x + 1/R_y,       k = 1.0339 (R_y/R_x)^0.636        (ellipticity a/b)
//! E(k) = 1.0003 + 0.5968 R_x/R_y,  F(k) = 1.5277 + 0.6023 ln(R_y/R_x)
//! Q = K delta^(3/2),         K = pi k E' sqrt(2 E(k) R / (9 F(k)^3))
//! K_n = (K_i^(-2/3) + K_o^(-2/3))^(-3/2)
//! ```
//!
//! (upper sign inner race), E' = E / (1 - nu^2) for balls and rings of one steel.

use serde::Serialize;

use super::RollerBearing;

/// Bearing steel's Young modulus, Pa (Harris uses 2.075e11 for AISI 52100).
pub const BEARING_STEEL_MODULUS: f64 = 2.075e11;

/// Bearing steel's Poisson ratio.
pub const BEARING_STEEL_POISSON: f64 = 0.3;

/// What a ball bearing's point contacts add to a [`RollerBearing`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BallContact {
    /// Inner groove radius over ball diameter, f_i > 1/2.
    pub inner_conformity: f64,
    /// Outer groove radius over ball diameter, f_o > 1/2.
    pub outer_conformity: f64,
    /// Contact angle alpha_0 at which a ball touches both races once the radial clearance is
    /// taken up with the rings concentric, rad (0 for a deep-groove bearing). The groove
    /// centres then lie A cos(alpha_0) - gamma apart radially at rest.
    pub contact_angle: f64,
    /// Axial load (or preload) the bearing carries, N, held constant: the rings' axial
    /// separation is solved for it at every evaluation (the finite-element model is lateral).
    pub axial_load: f64,
    /// The contact angle under the axial load alone with the shaft centred, rad: the angle
    /// the cage speed, the characteristic frequencies and the contact stiffness are taken at.
    pub running_angle: f64,
    /// Young's modulus of balls and rings, Pa.
    pub young_modulus: f64,
    /// Poisson's ratio of balls and rings.
    pub poisson_ratio: f64,
}

impl BallContact {
    /// Distance between the groove curvature centres when the ball just touches both
    /// races, A = (f_i + f_o - 1) D, m.
    pub fn centre_distance(&self, ball_diameter: f64) -> f64 {
        (self.inner_conformity + self.outer_conformity - 1.0) * ball_diameter
    }

    /// E' = E / (1 - nu^2), Pa: the plane-strain modulus of two bodies of one material
    /// (Hamrock's 2 / ((1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2)).
    pub fn effective_modulus(&self) -> f64 {
        self.young_modulus / (1.0 - self.poisson_ratio * self.poisson_ratio)
    }
}

/// One point contact's Hertz constants.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PointContact {
    /// Curvature sum 1/R_x + 1/R_y, 1/m.
    pub curvature_sum: f64,
    /// Curvature difference F(rho) = (1/R_x - 1/R_y) / (1/R_x + 1/R_y), R_x along the
    /// rolling direction (Harris's F(rho)).
    pub curvature_difference: f64,
    /// Ellipticity k = a / b of the contact ellipse.
    pub ellipticity: f64,
    /// Load-deflection constant K of Q = K delta^(3/2), N/m^(3/2).
    pub stiffness: f64,
}

/// The Hertz constants of a ball of diameter `ball` on a groove of conformity `conformity`,
/// with g = D cos(alpha)/d_m and `inner` telling which race: the inner race is convex along
/// the rolling direction (1 - g), the outer concave (1 + g).
pub fn point_contact(
    ball: f64,
    conformity: f64,
    g: f64,
    inner: bool,
    effective_modulus: f64,
) -> PointContact {
    let rolling = if inner { 1.0 - g } else { 1.0 + g };
    let rx = 0.5 * ball * rolling;
    let ry = conformity * ball / (2.0 * conformity - 1.0);
    let sum = 1.0 / rx + 1.0 / ry;
    let ratio = ry / rx;
    let k = 1.0339 * ratio.powf(0.636);
    let second = 1.0003 + 0.5968 / ratio;
    let first = 1.5277 + 0.6023 * ratio.ln();
    let r = 1.0 / sum;
    let stiffness = std::f64::consts::PI
        * k
        * effective_modulus
        * (2.0 * second * r / (9.0 * first.powi(3))).sqrt();
    PointContact {
        curvature_sum: sum,
        curvature_difference: (1.0 / rx - 1.0 / ry) / sum,
        ellipticity: k,
        stiffness,
    }
}

/// The inner and outer contacts of one ball at contact angle `angle` (rad) and their
/// series stiffness K_n = (K_i^(-2/3) + K_o^(-2/3))^(-3/2), N/m^(3/2).
pub fn ball_stiffness(
    ball: f64,
    pitch: f64,
    contact: &BallContact,
    angle: f64,
) -> (PointContact, PointContact, f64) {
    let g = ball * angle.cos() / pitch;
    let e = contact.effective_modulus();
    let inner = point_contact(ball, contact.inner_conformity, g, true, e);
    let outer = point_contact(ball, contact.outer_conformity, g, false, e);
    let series = (inner.stiffness.powf(-2.0 / 3.0) + outer.stiffness.powf(-2.0 / 3.0)).powf(-1.5);
    (inner, outer, series)
}

impl RollerBearing {
    /// True when the rolling elements are balls.
    pub fn is_ball(&self) -> bool {
        self.ball.is_some()
    }

    /// The contact angle the kinematics use, rad: a ball bearing's running angle, 0 for a
    /// cylindrical roller bearing.
    pub fn running_contact_angle(&self) -> f64 {
        self.ball.as_ref().map_or(0.0, |b| b.running_angle)
    }
}
