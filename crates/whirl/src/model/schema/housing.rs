//! `[[housing]]` as written: a bearing housing, pedestal or casing, and the squeeze-film
//! damper that may sit between it and what it is mounted on.

use serde::Deserialize;
use toml::Spanned;

use super::Q;

/// `[[housing]]`: a mass that moves in x and y, mounted on the ground or on another housing
/// (`on`) by a linear support (and, with `squeeze_film`, a squeeze-film damper in parallel).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HousingFile {
    /// The name bearings (`housing = "..."`) and other housings (`on = "..."`) refer to.
    pub name: Spanned<String>,
    /// Mass moving with the housing, kg.
    pub mass: Q,
    /// The housing it is mounted on; the ground when absent.
    pub on: Option<Spanned<String>>,
    pub kxx: Option<Spanned<f64>>,
    pub kyy: Option<Spanned<f64>>,
    pub kxy: Option<Spanned<f64>>,
    pub kyx: Option<Spanned<f64>>,
    pub cxx: Option<Spanned<f64>>,
    pub cyy: Option<Spanned<f64>>,
    pub cxy: Option<Spanned<f64>>,
    pub cyx: Option<Spanned<f64>>,
    /// A squeeze-film damper between the housing and what it is mounted on.
    pub squeeze_film: Option<Spanned<SqueezeFilmFile>>,
}

/// `squeeze_film = { ... }`: a short-bearing squeeze-film damper.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SqueezeFilmFile {
    /// Journal (damper land) radius R.
    pub radius: Q,
    /// Land length L (axial).
    pub length: Q,
    /// Radial clearance c.
    pub clearance: Q,
    /// Dynamic viscosity of the oil, Pa s.
    pub viscosity: Spanned<f64>,
    /// `"pi"` (cavitated, the default: the film carries pressure over half the land) or
    /// `"full"` (uncavitated, 2 pi film).
    pub cavitation: Option<Spanned<String>>,
    /// Where the damper's centre sits, along x and y, from the housing's position with the
    /// support unloaded (a static offset; default 0: centred).
    pub offset_x: Option<Q>,
    pub offset_y: Option<Q>,
}
