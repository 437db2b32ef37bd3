//! The bundled example models, shared by tests, benchmarks and documentation.
//!
//! The files live in the crate's `models/` folder, so that the published crate carries
//! them; the repository's `examples/` links to them for the command line.

/// The reference rotor of docs/theory.md section 9 (`examples/reference_rotor.toml`).
pub const REFERENCE_ROTOR: &str = include_str!("../models/reference_rotor.toml");

/// The reference rotor on 1e6 N/m supports (`examples/reference_rotor_soft.toml`).
pub const REFERENCE_ROTOR_SOFT: &str = include_str!("../models/reference_rotor_soft.toml");
