//! What a modal analysis reports ([`crate::report`]): the undamped modes and the damped
//! whirl modes at one speed with their shapes, as `whirl modal` writes them.
//!
//! At zero speed an isotropic rotor's forward and backward modes coincide and their shapes
//! are any mix of the two; as in the Campbell diagram, a speed below 1e-3 rad/s is solved
//! at 1e-3 rad/s, where they separate (frequency change below 1e-8 relative).

use serde::Serialize;

use super::sound::sound_modes;
use super::undamped::undamped_modes_told;
use super::{branch_labels, ComplexMode, ModalBasis, UndampedModes, Whirl};
use crate::error::Result;
use crate::fe::{assemble_banded, dof, Bearings, Direction};
use crate::model::Model;
use crate::progress::Progress;
use crate::report::{Report, Table};
use crate::units::rad_s_to_hz as hz;

/// Roots more damped than this are left out (overdamped or spurious, docs/theory.md
/// section 3).
const MAX_DAMPING_RATIO: f64 = 0.9;

/// Smallest speed solved, rad/s (see the module doc).
const SPEED_FLOOR: f64 = 1e-3;

/// The undamped modes and the damped modes at one speed.
#[derive(Debug, Clone)]
pub struct ModalReport {
    /// Spin speed of the damped modes, rad/s (as asked; solved at least at 1e-3).
    pub speed: f64,
    /// Axial position of each node, m.
    pub z: Vec<f64>,
    /// The undamped modes at rest.
    pub undamped: UndampedModes,
    /// The damped modes at the speed, ascending in frequency.
    pub damped: Vec<ComplexMode>,
    /// `1F`, `1B`, ... of the damped modes.
    pub labels: Vec<String>,
}

/// The key numbers of a [`ModalReport`].
#[derive(Debug, Clone, Serialize)]
pub struct ModalSummary {
    /// Spin speed, Hz.
    pub speed_hz: f64,
    /// Spin speed, rpm.
    pub speed_rpm: f64,
    /// Undamped natural frequencies, Hz.
    pub undamped_frequencies_hz: Vec<f64>,
    /// The damped modes.
    pub damped_modes: Vec<DampedSummary>,
    /// How the shapes are scaled and what is left out.
    pub notes: [&'static str; 3],
}

/// One damped mode.
#[derive(Debug, Clone, Serialize)]
pub struct DampedSummary {
    /// `1F`, `1B`, ...
    pub label: String,
    /// Damped natural frequency, Hz.
    pub damped_frequency_hz: f64,
    /// Undamped natural frequency of the root, Hz.
    pub natural_frequency_hz: f64,
    /// Damping ratio.
    pub damping_ratio: f64,
    /// Logarithmic decrement.
    pub log_decrement: f64,
    /// Whirl direction.
    pub whirl: Whirl,
}

/// The first `modes` undamped modes of `model` (linearised bearings) at rest and its first
/// `modes` damped modes at `speed` (rad/s) with damping ratio up to 0.9, telling `progress`
/// how the eigen-solver gets on (minutes for 200 modes of a 10,000-element rotor).
///
/// # Errors
/// The errors of [`super::undamped_modes`], of the checks of the module `sound` (a rotor
/// its supports do not hold, a mesh too fine for its sections), [`ModalBasis::truncated`] and
/// [`ModalBasis::modes_at`]; [`crate::Error::Interrupted`] when `progress` stopped it.
pub fn modal_report(
    model: &Model,
    speed: f64,
    modes: usize,
    progress: Option<&Progress>,
) -> Result<ModalReport> {
    let system = assemble_banded(model, Bearings::Linearised);
    // One eigen-solve: the basis's undamped modes, whose lowest `modes` are reported.
    let basis_modes = sound_modes(
        model,
        undamped_modes_told(
            &system,
            ModalBasis::size_for(system.dofs(), modes),
            progress,
        ),
    )?;
    let undamped = basis_modes.lowest(modes);
    let basis = ModalBasis::of_modes(&system, basis_modes);
    let damped = basis.modes_at(speed.max(SPEED_FLOOR), MAX_DAMPING_RATIO, modes)?;
    let labels = branch_labels(&damped.iter().map(|m| m.whirl).collect::<Vec<_>>());
    Ok(ModalReport {
        speed,
        z: model.node_positions(),
        undamped,
        damped,
        labels,
    })
}

impl Report for ModalReport {
    type Summary = ModalSummary;

    fn summary(&self) -> ModalSummary {
        ModalSummary {
            speed_hz: hz(self.speed),
            speed_rpm: 60.0 * hz(self.speed),
            undamped_frequencies_hz: self.undamped.frequencies_hz.clone(),
            damped_modes: self
                .damped
                .iter()
                .zip(&self.labels)
                .map(|(m, label)| DampedSummary {
                    label: label.clone(),
                    damped_frequency_hz: m.damped_frequency_hz,
                    natural_frequency_hz: m.natural_frequency_hz,
                    damping_ratio: m.damping_ratio,
                    log_decrement: m.log_decrement,
                    whirl: m.whirl,
                })
                .collect(),
            notes: [
                "undamped shapes are mass-normalised (phi^T M phi = 1)",
                "damped shapes are scaled so that the largest translation is 1",
                "roots with damping ratio above 0.9 are left out",
            ],
        }
    }

    /// `undamped_modes` (mode, frequency), `undamped_shapes` (mass-normalised shapes, one
    /// row per mode and node), `damped_modes` (damped and natural frequency, damping ratio,
    /// log decrement, whirl direction, eigenvalue) and `damped_shapes` (amplitude and phase
    /// of ux, uy and the forward/backward orbit radii per node, largest translation 1).
    fn tables(&self) -> Vec<Table> {
        let f = &self.undamped.frequencies_hz;
        let mut modes = Table::new("undamped_modes");
        modes
            .counts("mode", (0..f.len()).map(|j| j + 1))
            .numbers("frequency_hz", f.iter().copied());
        let cells: Vec<(usize, usize)> = (0..f.len())
            .flat_map(|j| (0..self.z.len()).map(move |n| (j, n)))
            .collect();
        let mut shapes = Table::new("undamped_shapes");
        shapes
            .counts("mode", cells.iter().map(|&(j, _)| j + 1))
            .numbers("frequency_hz", cells.iter().map(|&(j, _)| f[j]))
            .counts("node", cells.iter().map(|&(_, n)| n))
            .numbers("z_m", cells.iter().map(|&(_, n)| self.z[n]));
        for d in Direction::ALL {
            shapes.numbers(
                d.name(),
                cells
                    .iter()
                    .map(|&(j, n)| self.undamped.shapes[(dof(n, d), j)]),
            );
        }
        vec![modes, shapes, self.damped_modes(), self.damped_shapes()]
    }
}

impl ModalReport {
    fn damped_modes(&self) -> Table {
        let m = &self.damped;
        let mut t = Table::new("damped_modes");
        t.counts("mode", (0..m.len()).map(|i| i + 1))
            .text("label", self.labels.iter().map(String::as_str))
            .numbers(
                "damped_frequency_hz",
                m.iter().map(|m| m.damped_frequency_hz),
            )
            .numbers(
                "natural_frequency_hz",
                m.iter().map(|m| m.natural_frequency_hz),
            )
            .numbers("damping_ratio", m.iter().map(|m| m.damping_ratio))
            .numbers("log_decrement", m.iter().map(|m| m.log_decrement))
            .text("whirl", m.iter().map(|m| m.whirl.name()))
            .numbers("eigenvalue_real_per_s", m.iter().map(|m| m.eigenvalue.0))
            .numbers(
                "eigenvalue_imag_rad_per_s",
                m.iter().map(|m| m.eigenvalue.1),
            );
        t
    }

    fn damped_shapes(&self) -> Table {
        let cells: Vec<(usize, usize)> = (0..self.damped.len())
            .flat_map(|i| (0..self.z.len()).map(move |n| (i, n)))
            .collect();
        let at = |&(i, n): &(usize, usize), d| self.damped[i].shape[dof(n, d)];
        let radii = |&(i, n): &(usize, usize)| self.damped[i].orbit_radii(n);
        let mut t = Table::new("damped_shapes");
        t.counts("mode", cells.iter().map(|&(i, _)| i + 1))
            .text("label", cells.iter().map(|&(i, _)| self.labels[i].as_str()))
            .counts("node", cells.iter().map(|&(_, n)| n))
            .numbers("z_m", cells.iter().map(|&(_, n)| self.z[n]))
            .numbers(
                "ux_amplitude",
                cells.iter().map(|c| at(c, Direction::Ux).norm()),
            )
            .numbers(
                "ux_phase_deg",
                cells
                    .iter()
                    .map(|c| at(c, Direction::Ux).arg().to_degrees()),
            )
            .numbers(
                "uy_amplitude",
                cells.iter().map(|c| at(c, Direction::Uy).norm()),
            )
            .numbers(
                "uy_phase_deg",
                cells
                    .iter()
                    .map(|c| at(c, Direction::Uy).arg().to_degrees()),
            )
            .numbers("forward_radius", cells.iter().map(|c| radii(c).0))
            .numbers("backward_radius", cells.iter().map(|c| radii(c).1));
        t
    }
}
