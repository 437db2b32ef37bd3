//! Forced responses of the linear model.
//!
//! - [`unbalance_response`]: the steady synchronous response to unbalance over a speed
//!   range, with peaks, amplification factors and API 617 separation margins.

mod peaks;
mod unbalance;

pub use peaks::{separation_margin, ResponsePeak};
pub use unbalance::{unbalance_response, NodeResponse, UnbalanceResult};
