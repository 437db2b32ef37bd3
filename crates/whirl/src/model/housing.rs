//! Bearing housings, pedestals and casings: masses that move in x and y, each mounted on
//! the ground or on another housing by a linear support, with an optional squeeze-film
//! damper in parallel (docs/theory.md, "Housings and squeeze-film dampers").
//!
//! A housing has two DOFs, its translations: the bearings carry forces only (their 2x2
//! stiffness and damping act on translations), so a housing's tilt would couple to nothing
//! and its rotary inertia would never matter. The housings' DOFs follow the shaft's, in the
//! file's order: housing h has DOFs `4 N + 2 h` (ux) and `4 N + 2 h + 1` (uy), N the
//! number of shaft nodes ([`super::Model::housing_dofs`]).

use serde::Serialize;

/// Whether the film carries pressure all round or only where it is squeezed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Cavitation {
    /// Cavitated ("pi film"): the film carries pressure only where the gap closes (half
    /// the land on a circular centred orbit); negative pressures are cut to zero.
    Pi,
    /// Uncavitated ("2 pi film", "full film"): the whole film carries the pressure
    /// Reynolds' equation gives, negative included.
    Full,
}

/// A short-bearing squeeze-film damper (no rotation of the journal, L/D small).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SqueezeFilm {
    /// Journal (land) radius R, m.
    pub radius: f64,
    /// Land length L, m.
    pub length: f64,
    /// Radial clearance c, m.
    pub clearance: f64,
    /// Oil dynamic viscosity mu, Pa s.
    pub viscosity: f64,
    /// Cavitated or not.
    pub cavitation: Cavitation,
    /// The damper's centre from the housing's unloaded position [x, y], m.
    pub offset: [f64; 2],
}

/// A housing: a mass on a linear support, optionally with a squeeze-film damper.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Housing {
    /// Name for outputs and references.
    pub name: String,
    /// Mass, kg (the same in x and y).
    pub mass: f64,
    /// The housing it is mounted on (index in [`super::Model::housings`]); `None`: ground.
    pub on: Option<usize>,
    /// Support stiffness [[kxx, kxy], [kyx, kyy]], N/m, between the housing and `on`.
    pub stiffness: [[f64; 2]; 2],
    /// Support damping [[cxx, cxy], [cyx, cyy]], N s/m.
    pub damping: [[f64; 2]; 2],
    /// A squeeze-film damper in parallel with the support.
    pub squeeze_film: Option<SqueezeFilm>,
}
