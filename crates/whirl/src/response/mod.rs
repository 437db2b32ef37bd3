//! Forced responses of the linear model.
//!
//! - [`frf`]: receptance, mobility and accelerance between any two DOFs at a spin speed,
//!   and [`harmonic_response`] to harmonic forces of any frequency; [`frf_refined`] adds
//!   frequencies near the peaks so they are resolved.
//! - [`unbalance_response`]: the steady synchronous response to unbalance over a speed
//!   range, with peaks, amplification factors and API 617 separation margins;
//!   [`unbalance_response_refined`] adds speeds near the peaks so they are resolved.

mod frf;
mod peaks;
mod unbalance;

pub use frf::{
    default_frequencies, dof_spec, frf, frf_refined, harmonic_response, DofSpec, FrfChannel,
    FrfKind, FrfReport, FrfRequest, FrfResult, FrfSummary, ResolvedFrf, DEFAULT_FRF_FORCE,
};
pub use peaks::{
    margins_not_applicable, separation_margin, ResponsePeak, API617_MIN_SPEED_RATIO, BAND_SAMPLES,
};
pub use unbalance::{
    default_unbalance_speeds, unbalance_response, unbalance_response_refined, NodeResponse,
    UnbalanceResult, UnbalanceSummary, DEFAULT_UNBALANCE_FROM_HZ, DEFAULT_UNBALANCE_SPEEDS,
};
