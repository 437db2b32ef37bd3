//! Whether a model's lowest undamped modes can be trusted as an answer, checked by
//! `whirl check` and `whirl modal` before they report them:
//!
//! - the supports hold the rotor: a mode at 0 Hz is a rigid-body motion (a mechanism), not
//!   a natural frequency, and comes from a support without stiffness;
//! - the mesh is not finer than round-off allows: the element stiffness grows as 12 EI / h^3
//!   while the lowest modes' stiffness stays, so on elements short against their section the
//!   lowest frequencies drift by per cent (a 100 mm reference shaft: 640.44 Hz converged,
//!   666.21 Hz at 6,000 elements). Whether round-off has taken over is judged by the mesh's
//!   own convergence: the same rotor on half, a quarter, ... of the elements; once a coarser
//!   mesh has converged (cubic elements converge as h^4), a finer one that strays from it
//!   is round-off.

use super::undamped::{undamped_modes, UndampedModes};
use crate::error::{Error, InputError, Result};
use crate::fe::{assemble_banded, Bearings};
use crate::model::Model;

/// A lowest frequency below this is a rigid-body mode, Hz: the neutral bound the eigen-solver
/// already grants round-off of a 0 Hz mode (a motion growing this slowly is no vibration).
const RIGID_BODY_HZ: f64 = 0.1;

/// A mesh whose first frequency changed less than this (relative) from half its elements
/// has converged: cubic elements converge as h^4, so every finer mesh adds less than a
/// fifteenth of it.
const CONVERGED_CHANGE: f64 = 1e-5;

/// How far a finer mesh's first frequency may stray from a converged coarser one before it
/// is refused as round-off: the reference rotor at the 10,000-element limit strays 6e-5
/// from 2,500 elements, round-off too but far below any engineering use of a frequency.
const ROUND_OFF_CHANGE: f64 = 1e-4;

/// The first `count` undamped modes of `model` (linearised bearings), checked as the module
/// says: what `whirl check` and `whirl import-ross` report.
///
/// # Errors
/// Those of [`undamped_modes`] and `sound_modes`.
pub fn trusted_modes(model: &Model, count: usize) -> Result<UndampedModes> {
    let system = assemble_banded(model, Bearings::Linearised);
    sound_modes(model, undamped_modes(&system, count))
}

/// The checks of the module on `modes`, the result of the undamped solve of `model`.
/// A solve that failed is passed through unless the mesh explains the failure (a
/// coarser mesh of the same rotor solves): round-off makes the stiffness look indefinite,
/// and "unstable at rest" would be a false diagnosis.
///
/// # Errors
/// [`Error::Input`] naming `shaft[*].elements` for a mesh too fine for its sections, or the
/// bearings without stiffness for a rotor with a rigid-body mode; the solve's own error.
pub(crate) fn sound_modes(model: &Model, modes: Result<UndampedModes>) -> Result<UndampedModes> {
    let first = modes.as_ref().ok().and_then(|m| m.frequencies_hz.first());
    mesh_converges(model, first.copied())?;
    let modes = modes?;
    held_by_supports(model, &modes)?;
    Ok(modes)
}

/// Refuses a rotor whose first mode is a rigid-body motion, naming the supports that have
/// no stiffness.
fn held_by_supports(model: &Model, modes: &UndampedModes) -> Result<()> {
    match modes.frequencies_hz.first() {
        Some(&f) if f < RIGID_BODY_HZ => Err(mechanism(model, f)),
        _ => Ok(()),
    }
}

/// The error of a rotor left free to move as a rigid body.
fn mechanism(model: &Model, first_hz: f64) -> Error {
    let mut free: Vec<String> = model
        .roller_bearings
        .iter()
        .enumerate()
        .filter(|(_, b)| b.linear_stiffness == 0.0)
        .map(|(i, b)| format!("roller_bearing[{i}] `{}` (linear_stiffness = 0)", b.name))
        .collect();
    free.extend(
        model
            .bearings
            .iter()
            .enumerate()
            .filter(|(_, b)| b.stiffness[0][0] == 0.0 || b.stiffness[1][1] == 0.0)
            .map(|(i, b)| format!("bearing[{i}] `{}` (kxx or kyy = 0)", b.name)),
    );
    let cause = if free.is_empty() {
        "the supports do not hold both its ends".to_string()
    } else {
        format!("these supports have no stiffness: {}", free.join(", "))
    };
    InputError::field(
        "bearing",
        format!(
            "the rotor is a mechanism: its first mode ({first_hz:.3} Hz) is a rigid-body \
             motion, not a natural frequency; {cause}"
        ),
    )
    .help(
        "give every support a stiffness (a roller bearing's linear_stiffness is what the \
         linear analyses use), or support the rotor at two nodes at least",
    )
    .into()
}

/// Refuses a mesh on which round-off has overtaken convergence: the first frequency
/// `fine_hz` (`None` when the solve failed) against the coarsest mesh of the halving ladder
/// ([`coarser_ladder`]) that had converged. A model without a converged coarser mesh is
/// not judged (its mesh is coarse, or cannot be halved).
fn mesh_converges(model: &Model, fine_hz: Option<f64>) -> Result<()> {
    let ladder = coarser_ladder(model);
    let change = |a: f64, b: f64| (a - b).abs() / b.abs().max(f64::MIN_POSITIVE);
    let Some(&(reference_elements, reference_hz)) = ladder
        .windows(2)
        .find(|w| change(w[1].1, w[0].1) < CONVERGED_CHANGE)
        .map(|w| &w[1])
    else {
        return Ok(());
    };
    if fine_hz.is_some_and(|f| change(f, reference_hz) <= ROUND_OFF_CHANGE) {
        return Ok(());
    }
    let elements: usize = model.sections.iter().map(|s| s.elements).sum();
    let found = fine_hz.map_or("no stable solution".to_string(), |f| format!("{f:.6} Hz"));
    Err(InputError::field(
        "shaft[*].elements",
        format!(
            "{elements} elements are too many for sections this short: round-off in the \
             stiffness of elements so short against their diameter swamps the lowest modes \
             (first mode {found}, where {reference_elements} elements had converged to \
             {reference_hz:.6} Hz)"
        ),
    )
    .help(format!(
        "use fewer elements: {reference_elements} already give the first mode to \
         {CONVERGED_CHANGE:e} (`whirl convergence` shows how many the other modes need)"
    ))
    .into())
}

/// The first frequency of `model` on coarser meshes of the same rotor, coarsest first, as
/// (elements, Hz): each section's count divided by 2 or more, then by at least twice
/// that, ... (by a common divisor of the counts, so that the sections keep their
/// proportions). A divisor that would move a feature off the nodes is passed over; the
/// ladder stops at a mesh that does not solve.
fn coarser_ladder(model: &Model) -> Vec<(usize, f64)> {
    let counts: Vec<usize> = model.sections.iter().map(|s| s.elements).collect();
    let common = counts.iter().fold(0, |g, &n| gcd(g, n));
    let mut ladder = Vec::new();
    let mut last = 1;
    for divisor in 2..=common {
        if common % divisor != 0 || divisor < 2 * last {
            continue;
        }
        let coarse: Vec<usize> = counts.iter().map(|n| n / divisor).collect();
        let Ok(mesh) = model.remeshed(&coarse) else {
            continue;
        };
        let solved = undamped_modes(&assemble_banded(&mesh, Bearings::Linearised), 1);
        let Some(first) = solved.ok().and_then(|m| m.frequencies_hz.first().copied()) else {
            break;
        };
        ladder.push((coarse.iter().sum(), first));
        last = divisor;
    }
    ladder.reverse();
    ladder
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}
