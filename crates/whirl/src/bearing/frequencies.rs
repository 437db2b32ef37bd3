//! The characteristic frequencies of a rolling bearing, which a diagnostician reads a
//! spectrum by (Harris, *Rolling Bearing Analysis*, the kinematics chapter; docs/theory.md
//! section 5). With the outer ring fixed, the shaft turning at Omega, d the roller (ball)
//! diameter, D_p the pitch diameter and alpha the contact angle (0 for a cylindrical roller
//! bearing):
//!
//! ```text
//! FTF  = w_c = c Omega,       c = (1 - d cos(alpha) / D_p) / 2   (cage, thesis eq. 3.4)
//! BPFO = N_b c Omega                                              (= N_b w_c, eq. 4.4)
//! BPFI = N_b (1 - c) Omega
//! BSF  = c (D_p + d cos(alpha)) / d Omega = D_p / (2 d) (1 - (d cos(alpha) / D_p)^2) Omega
//! ```
//!
//! BSF is a roller's spin relative to the cage, from rolling without slip on the outer
//! raceway (whose diameter is D_p + d cos alpha). Everything is written with the cage ratio
//! c so that a measured cage ratio (`cage_speed_ratio` in the model file) moves every line
//! consistently; with the default ratio the textbook forms above follow. A spot on a roller
//! strikes both races once per spin turn, so a roller defect shows at 2 BSF.

use serde::Serialize;

use crate::model::RollerBearing;

/// The characteristic frequencies of one bearing, in the unit of the spin frequency they
/// were computed from (orders of the spin speed when it is 1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CharacteristicFrequencies {
    /// Fundamental train (cage) frequency w_c.
    pub ftf: f64,
    /// Roller pass frequency over a point of the outer race.
    pub bpfo: f64,
    /// Roller pass frequency over a point of the inner race.
    pub bpfi: f64,
    /// A roller's spin relative to the cage.
    pub bsf: f64,
    /// The varying-compliance frequency N_b w_c: the rate at which rollers pass the fixed
    /// load zone, equal to BPFO with the outer ring fixed.
    pub varying_compliance: f64,
}

/// The characteristic frequencies of `bearing` at spin frequency `spin` (any unit; the
/// result is in the same one).
pub fn characteristic_frequencies(bearing: &RollerBearing, spin: f64) -> CharacteristicFrequencies {
    let rollers = bearing.rollers as f64;
    let cage = bearing.cage_speed_ratio;
    // The outer raceway's diameter at the contact: D_p + d cos(alpha), with a cylindrical
    // roller bearing's alpha = 0 and a ball bearing's running contact angle.
    let outer_raceway =
        bearing.pitch_diameter + bearing.roller_diameter * bearing.running_contact_angle().cos();
    CharacteristicFrequencies {
        ftf: cage * spin,
        bpfo: rollers * cage * spin,
        bpfi: rollers * (1.0 - cage) * spin,
        bsf: cage * outer_raceway / bearing.roller_diameter * spin,
        varying_compliance: rollers * cage * spin,
    }
}

impl CharacteristicFrequencies {
    /// Short names and values for reference lines, lowest first. BPFO and the varying
    /// compliance coincide (the outer ring is fixed), so they share one line.
    pub fn lines(&self) -> [(&'static str, f64); 4] {
        [
            ("FTF", self.ftf),
            ("BPFO = N_b w_c", self.bpfo),
            ("BPFI", self.bpfi),
            ("BSF", self.bsf),
        ]
    }
}

/// One bearing's characteristic frequencies as orders of the spin speed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BearingOrders {
    /// The bearing's name.
    pub bearing: String,
    /// Its frequencies per unit spin frequency.
    pub orders: CharacteristicFrequencies,
}

/// [`BearingOrders`] of every roller bearing of `bearings`.
pub fn bearing_orders(bearings: &[RollerBearing]) -> Vec<BearingOrders> {
    bearings
        .iter()
        .map(|b| BearingOrders {
            bearing: b.name.clone(),
            orders: characteristic_frequencies(b, 1.0),
        })
        .collect()
}
