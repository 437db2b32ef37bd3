//! # whirl
//!
//! Dynamics of rotors on rolling-element bearings: finite-element rotor models, modal
//! analysis, Campbell diagrams, unbalance and frequency responses, statics, and the
//! nonlinear roller bearing with internal radial clearance that causes non-synchronous
//! vibration (NSV): its stiffness, time simulation with Hertz, Lagrange-multiplier or
//! forcing-function contacts, harmonic balance with stability, and the cascade diagram of
//! NSV over a speed range. The model follows the thesis *Non-synchronous Vibration due to
//! Internal Radial Clearance in Roller Bearings*; the repository's `docs/theory.md` states
//! the theory whirl implements (conventions, elements, bearing, methods) and
//! `docs/theory-errata.md` where and why whirl departs from the thesis.
//!
//! Data flows one way: a model file is read and validated into a [`model::Model`]; the
//! finite-element layer ([`fe`]) assembles its matrices; the roller bearings' contact laws
//! ([`bearing`]) and the squeeze-film dampers ([`squeeze_film`]) implement the
//! nonlinear-force interface ([`force`]); [`system::build`] makes
//! the one linear system with its loads and contact forces ([`system::System`], full or
//! Craig-Bampton reduced by [`reduce`]) that time marching and harmonic balance both solve;
//! the solvers ([`modal`], [`response`], [`statics`], [`time`], [`hbm`], [`map`], [`nsv`],
//! [`study`]) turn those into results types that serialize to JSON and CSV. Units are SI everywhere inside (m, kg, s,
//! rad/s); [`units`] converts what people write (`"750 Hz"`, `"20 um"`).
//!
//! **Build profile.** faer, the linear algebra underneath, is about 70 times slower
//! unoptimised. A project that depends on whirl must optimise its dev profile, or every
//! analysis crawls:
//!
//! ```toml
//! [profile.dev]
//! opt-level = 3
//!
//! [profile.dev.package."*"]
//! opt-level = 3
//! ```
//!
//! # A model from a string
//!
//! A model is the TOML text of a model file (see `docs/model-file.md`). A uniform steel
//! shaft on near-rigid supports, without rotary inertia, is the pinned-pinned
//! Euler-Bernoulli beam, whose first frequency is (pi / (2 L^2)) sqrt(E I / (rho A)):
//!
//! ```
//! use whirl::{fe, modal, model::Model};
//! let text = r#"
//!     name = "pinned-pinned shaft"
//!     [[material]]
//!     name = "steel"
//!     young_modulus = 2.11e11
//!     density = 7810
//!     [[shaft]]
//!     length = "1 m"
//!     outer_diameter = "50 mm"
//!     material = "steel"
//!     elements = 20
//!     [elements]
//!     rotary_inertia = false
//!     gyroscopic = false
//!     [[bearing]]
//!     node = 0
//!     kxx = 1e12
//!     kyy = 1e12
//!     [[bearing]]
//!     node = 20
//!     kxx = 1e12
//!     kyy = 1e12
//! "#;
//! let model = Model::from_toml_str(text, None)?;
//! let system = fe::assemble(&model, fe::Bearings::Linearised);
//! let modes = modal::undamped_modes(&system, 2)?;
//! let (e, rho, d, l): (f64, f64, f64, f64) = (2.11e11, 7810.0, 0.05, 1.0);
//! let closed = std::f64::consts::PI / (2.0 * l * l) * (e * d * d / 16.0 / rho).sqrt();
//! // 20 elements are within 0.1 % of the closed form for the first modes.
//! assert!((modes.frequencies_hz[0] / closed - 1.0).abs() < 1e-3);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Modes and the Campbell diagram
//!
//! The bundled reference rotor ([`examples::REFERENCE_ROTOR`]) on its linearised bearings:
//!
//! ```
//! use whirl::{fe, modal, model::Model, units};
//! let model = Model::from_toml_str(whirl::examples::REFERENCE_ROTOR, None)?;
//! let system = fe::assemble(&model, fe::Bearings::Linearised);
//! let modes = modal::undamped_modes(&system, 2)?;
//! // About 49.8 Hz (each lateral mode comes as a pair, one per plane).
//! assert!((modes.frequencies_hz[0] - 49.8).abs() < 0.5);
//!
//! let speeds = units::parse_range("0:400Hz:21", units::Dimension::AngularSpeed)?;
//! let diagram = modal::campbell(&system, &modal::CampbellOptions::new(speeds), None)?;
//! // Where a branch crosses the 1X line: the first critical speed, near the first mode.
//! let first = &diagram.critical_speeds[0];
//! assert!((first.speed_hz - 49.8).abs() < 3.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Unbalance response
//!
//! The steady synchronous response to the model's unbalance, at the disk (node 10):
//!
//! ```
//! use whirl::{fe, model::Model, response};
//! let model = Model::from_toml_str(whirl::examples::REFERENCE_ROTOR, None)?;
//! let system = fe::assemble(&model, fe::Bearings::Linearised);
//! let speeds_hz: Vec<f64> = (0..=100).map(|i| 40.0 + 0.2 * i as f64).collect();
//! let speeds: Vec<f64> = speeds_hz.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
//! let result = response::unbalance_response(&model, &system, &speeds, &[10])?;
//! let amplitude = &result.nodes[0].uy_amplitude;
//! let peak = (0..amplitude.len()).max_by(|&a, &b| amplitude[a].total_cmp(&amplitude[b])).unwrap();
//! // The resonance sits at the first critical speed, near 50 Hz.
//! assert!((speeds_hz[peak] - 49.8).abs() < 2.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Time simulation on roller bearings
//!
//! The reference rotor on its Hertz roller contacts (the default with roller bearings) at
//! 50 Hz, Craig-Bampton reduced to 12 modes; every other setting at its default: from the
//! static equilibrium under gravity, at 0.9 times the central difference's stability
//! limit, the second half of the run settled:
//!
//! ```
//! use whirl::{model::Model, system::SpeedProfile, time};
//! let model = Model::from_toml_str(whirl::examples::REFERENCE_ROTOR, None)?;
//! let options = time::SimulationOptions {
//!     duration: 0.2,
//!     reduction: Some(time::DEFAULT_MODES),
//!     nodes: Some(vec![10]),
//!     ..time::SimulationOptions::new(SpeedProfile::Constant(2.0 * std::f64::consts::PI * 50.0))
//! };
//! let run = time::simulate(&model, &options)?;
//! let disk = run.channels.iter().find(|c| c.name == "n10.uy").unwrap();
//! // The disk hangs below the bearings' centre (gravity along -y) and whirls about it.
//! let mean = disk.values.iter().sum::<f64>() / disk.values.len() as f64;
//! assert!(mean < 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # The cascade of non-synchronous vibration
//!
//! Two speeds, short records, no refinement (a real cascade uses the defaults of
//! [`nsv::CascadeOptions::new`], 150 speeds or more, and a checkpoint folder):
//!
//! ```
//! use whirl::{model::Model, nsv};
//! let model = Model::from_toml_str(whirl::examples::REFERENCE_ROTOR, None)?;
//! let speeds = vec![2.0 * std::f64::consts::PI * 100.0, 2.0 * std::f64::consts::PI * 200.0];
//! let mut options = nsv::CascadeOptions::new(&model, speeds);
//! options.settle = 0.1;
//! options.settle_max = 0.1;
//! options.record = 0.1;
//! options.refine.enabled = false;
//! let result = nsv::cascade(&model, &options, None, None)?;
//! assert_eq!(result.points.len(), 2);
//! // The 1X line is the unbalance response; the summary gives onset, largest NSV, classes.
//! assert!(result.points.iter().all(|p| p.one_x_m > 0.0));
//! let summary = result.nsv_summary(nsv::DEFAULT_THRESHOLD_M);
//! println!("NSV onset {:?} Hz, largest {:?}", summary.onset_speed_hz, summary.largest);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Numerical kernels index several arrays in step; index loops read like the equations.
#![allow(clippy::needless_range_loop)]

pub mod bearing;
pub mod error;
pub mod examples;
pub mod fe;
pub mod force;
pub mod given;
pub mod hbm;
pub(crate) mod linalg;
pub mod lock;
pub mod map;
pub mod modal;
pub mod model;
pub mod nsv;
pub mod post;
pub mod progress;
pub mod reduce;
pub mod report;
pub mod response;
pub mod runup;
pub mod squeeze_film;
pub mod statics;
pub mod study;
pub mod system;
pub mod time;
pub mod units;

pub use error::{Error, InputError, Result};

/// What identifies this build's numbers: whirl's version and a hash of the library's
/// source. Checkpoints of cascades and studies record it and are resumed only by the same
/// build, since any change of the code may change the answers while the version stays.
pub const BUILD_ID: &str = concat!(env!("CARGO_PKG_VERSION"), "+", env!("WHIRL_SOURCE_HASH"));

/// The Rust examples of the repository's README.md, run as doc-tests so that the entry
/// page cannot drift from the library (only under `cfg(doctest)`: the published crate does
/// not carry the file).
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeExamples;

/// The Rust examples of the repository's docs/rust.md, run as doc-tests.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/rust.md")]
pub struct RustGuideExamples;
