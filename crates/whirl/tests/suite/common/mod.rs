//! The test models shared by the library's tests (a module of their binary, `suite`) and,
//! through `#[path]`, by the benchmarks and the command line's tests: each model once, with
//! the closed forms the tests check it against beside it.
//!
//! - [`reference`]: the reference rotor of docs/theory.md section 9, as a model and as a
//!   file of the repository's `examples/`;
//! - [`oscillator`]: the single-DOF oscillator (natural frequency, receptance) and the
//!   Duffing oscillator (first-order harmonic balance: frequency-amplitude relation, folds);
//! - [`jeffcott`]: the isotropic Jeffcott rotor (critical speed, unbalance response, its
//!   peak), as a system and as a model file, and the Jeffcott rotor in a clearance ring
//!   (the exact synchronous circular orbit and its fold).

pub mod jeffcott;
pub mod oscillator;
pub mod reference;

pub use jeffcott::{Jeffcott, RingRotor, ONE_MASS};
pub use oscillator::{Duffing, Oscillator};
pub use reference::{
    assert_same_resonance, example_path, reference_bearing, reference_rotor, reference_rotor_path,
    reference_rotor_text_meshed,
};
