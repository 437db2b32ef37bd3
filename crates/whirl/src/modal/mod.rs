//! Modal analysis (thesis 2.2, docs/theory.md section 3).
//!
//! - [`undamped_modes`]: K v = w^2 M v, mass-normalised shapes.
//! - [`complex_modes`]: the damped gyroscopic system at a spin speed in first-order form
//!   (thesis eqs. 2.21-2.27): eigenvalues lambda = -zeta w_n +- i w_d, whirl direction.
//! - [`campbell`]: whirl frequencies over speed, tracked by mode-shape correlation, with
//!   critical speeds where a branch crosses an excitation order.
//! - [`convergence`]: frequencies versus element count (thesis fig. 2.8).
//! - [`critical_speed_map`]: undamped critical speeds against bearing stiffness (API 684).
//! - [`check_model`]: a model as read with its first undamped frequencies (`whirl check`).
//! - [`modal_report`]: the undamped and damped modes at one speed, as `whirl modal`
//!   reports them.

mod campbell;
mod check;
mod complex;
mod convergence;
mod report;
mod request;
mod sound;
mod subspace;
mod ucs;
mod undamped;

pub use campbell::{
    campbell, CampbellOptions, CampbellRequest, CampbellResult, CampbellSummary, CriticalSpeed,
    ModeBranch, DEFAULT_BRANCHES, DEFAULT_CAMPBELL_SPEEDS, DEFAULT_ORDER, MAX_ORDER,
};
pub use check::{check_model, CheckSummary, ClearanceCurve, ModelCheck};
pub use complex::{branch_labels, complex_modes, ComplexMode, ModalBasis, Whirl, FULL_LIMIT};
pub use convergence::{
    check_element_count, convergence, default_element_counts, ConvergenceResult,
    ConvergenceSummary, DEFAULT_CONVERGENCE_MODES,
};
pub use report::{modal_report, DampedSummary, ModalReport, ModalSummary};
pub use request::{ModalRequest, DEFAULT_MODAL_MODES};
pub use sound::trusted_modes;
pub(crate) use subspace::largest_eigenvalue;
pub use ucs::{
    critical_speed_map, default_stiffnesses, log_space, stiffness_range, BearingCut,
    BearingStiffness, CriticalSpeedMap, CriticalSpeedSummary, UcsRequest, DEFAULT_UCS_MODES,
    MAX_STIFFNESSES,
};
pub(crate) use undamped::{lowest_modes, symmetric_modes};
pub use undamped::{solves_dense, undamped_modes, UndampedModes, DENSE_LIMIT};
