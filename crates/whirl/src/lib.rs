//! # whirl
//!
//! Dynamics of rotors on rolling-element bearings: finite-element rotor models, modal
//! analysis, Campbell diagrams, unbalance response, and (in later modules) the nonlinear
//! roller-bearing contact with internal radial clearance that causes non-synchronous
//! vibration (thesis "Non-synchronous Vibration due to Internal Radial Clearance in Roller
//! Bearings"; the project's contract is `SPEC.md`).
//!
//! Data flows one way: a model file is read and validated into a [`model::Model`]; the
//! finite-element layer ([`fe`]) assembles its matrices; solvers ([`modal`],
//! [`response`]) turn those into results types that serialize to JSON and CSV.
//!
//! ```
//! use whirl::{model::Model, fe, modal};
//! let model = Model::from_toml_str(whirl::examples::REFERENCE_ROTOR, None).unwrap();
//! let system = fe::assemble(&model, fe::Bearings::Linearised);
//! let modes = modal::undamped_modes(&system, 2).unwrap();
//! // SPEC section 10: about 49.8 Hz and 254 Hz.
//! assert!((modes.frequencies_hz[0] - 49.8).abs() < 0.5);
//! ```
//!
//! Units: SI everywhere inside (m, kg, s, rad/s); [`units`] converts what people write.

// Numerical kernels index several arrays in step; index loops read like the equations.
#![allow(clippy::needless_range_loop)]

pub mod bearing;
pub mod error;
pub mod examples;
pub mod fe;
pub mod hbm;
pub mod lock;
pub mod modal;
pub mod model;
pub mod nsv;
pub mod post;
pub mod reduce;
pub mod response;
pub mod statics;
pub mod study;
pub mod time;
pub mod units;

pub use error::{Error, InputError, Result};
