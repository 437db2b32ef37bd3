//! What `whirl check` reports ([`crate::report`]): the model as read (mesh, masses,
//! supports) with its first undamped natural frequencies, and its nodes.

use serde::Serialize;

use super::sound::trusted_modes;
use crate::error::Result;
use crate::model::{Clearance, LinearBearing, Model, RollerBearing};
use crate::report::{Report, Table};
use crate::units::rad_s_to_hz as hz;

/// Undamped frequencies listed.
const FREQUENCIES: usize = 6;

/// Speeds at which a speed-dependent clearance is tabulated.
const CLEARANCE_SPEEDS: usize = 101;

/// A validated model with its first undamped natural frequencies.
#[derive(Debug, Clone)]
pub struct ModelCheck {
    /// The model.
    pub model: Model,
    /// Its first six undamped natural frequencies (linearised bearings), Hz.
    pub frequencies_hz: Vec<f64>,
}

/// Checks that `model` can be solved: its first six undamped natural frequencies with
/// linearised bearings.
///
/// # Errors
/// The errors of [`trusted_modes`]: a rotor unstable at rest, a rotor its supports do not
/// hold, a mesh too fine for its sections.
pub fn check_model(model: &Model) -> Result<ModelCheck> {
    let modes = trusted_modes(model, FREQUENCIES)?;
    Ok(ModelCheck {
        model: model.clone(),
        frequencies_hz: modes.frequencies_hz,
    })
}

impl ModelCheck {
    /// Shaft elements.
    pub fn elements(&self) -> usize {
        self.model.sections.iter().map(|s| s.elements).sum()
    }

    /// Mass of the disks, kg.
    pub fn disk_mass(&self) -> f64 {
        self.model.disks.iter().map(|d| d.mass).sum()
    }
}

/// The key numbers of a [`ModelCheck`]: the model as read, with units in the keys.
#[derive(Debug, Clone, Serialize)]
pub struct CheckSummary {
    /// Nodes.
    pub nodes: usize,
    /// Degrees of freedom.
    pub dofs: usize,
    /// Shaft elements.
    pub elements: usize,
    /// Shaft sections.
    pub shaft_sections: usize,
    /// Shaft length, m.
    pub shaft_length_m: f64,
    /// Shaft mass, kg.
    pub shaft_mass_kg: f64,
    /// Mass of the disks, kg.
    pub disk_mass_kg: f64,
    /// Rotor mass, kg.
    pub total_mass_kg: f64,
    /// Gravity, m/s^2.
    pub gravity_m_per_s2: f64,
    /// The disks.
    pub disks: Vec<DiskSummary>,
    /// The linear bearings.
    pub bearings: Vec<LinearBearingSummary>,
    /// The roller bearings.
    pub roller_bearings: Vec<RollerBearingSummary>,
    /// The unbalances.
    pub unbalances: Vec<UnbalanceEntry>,
    /// Rayleigh damping of the rotor.
    pub rayleigh_damping: RayleighEntries,
    /// The operating range, Hz.
    pub operating_speed_hz: Option<[f64; 2]>,
    /// The first six undamped natural frequencies, Hz.
    pub undamped_frequencies_hz: Vec<f64>,
}

/// One disk.
#[derive(Debug, Clone, Serialize)]
pub struct DiskSummary {
    /// Name.
    pub name: String,
    /// Node.
    pub node: usize,
    /// Axial position, m.
    pub z_m: f64,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Polar moment of inertia, kg m^2.
    pub polar_inertia_kg_m2: f64,
    /// Diametral moment of inertia, kg m^2.
    pub diametral_inertia_kg_m2: f64,
}

/// One linear bearing.
#[derive(Debug, Clone, Serialize)]
pub struct LinearBearingSummary {
    /// Name.
    pub name: String,
    /// Node.
    pub node: usize,
    /// Axial position, m.
    pub z_m: f64,
    /// Stiffness, N/m.
    pub stiffness_n_per_m: StiffnessEntries,
    /// Damping, N s/m.
    pub damping_n_s_per_m: DampingEntries,
}

/// A 2x2 stiffness, N/m.
#[derive(Debug, Clone, Serialize)]
pub struct StiffnessEntries {
    /// Entry xx.
    pub kxx: f64,
    /// Entry xy.
    pub kxy: f64,
    /// Entry yx.
    pub kyx: f64,
    /// Entry yy.
    pub kyy: f64,
}

/// A 2x2 damping, N s/m.
#[derive(Debug, Clone, Serialize)]
pub struct DampingEntries {
    /// Entry xx.
    pub cxx: f64,
    /// Entry xy.
    pub cxy: f64,
    /// Entry yx.
    pub cyx: f64,
    /// Entry yy.
    pub cyy: f64,
}

/// One roller bearing.
#[derive(Debug, Clone, Serialize)]
pub struct RollerBearingSummary {
    /// Name.
    pub name: String,
    /// Node.
    pub node: usize,
    /// Axial position, m.
    pub z_m: f64,
    /// Rollers.
    pub rollers: usize,
    /// Pitch diameter, m.
    pub pitch_diameter_m: f64,
    /// Roller diameter, m.
    pub roller_diameter_m: f64,
    /// Roller length, m.
    pub roller_length_m: f64,
    /// Radial clearance at rest, m.
    pub clearance_at_rest_m: f64,
    /// Hertz contact stiffness, N/m^n.
    pub contact_stiffness_n_per_m_pow_n: f64,
    /// Hertz exponent n.
    pub contact_exponent: f64,
    /// Contact damping, N s/m.
    pub contact_damping_n_s_per_m: f64,
    /// Stiffness of the linearised bearing, N/m.
    pub linear_stiffness_n_per_m: f64,
    /// Damping of the linearised bearing, N s/m.
    pub linear_damping_n_s_per_m: f64,
}

/// One unbalance.
#[derive(Debug, Clone, Serialize)]
pub struct UnbalanceEntry {
    /// Node.
    pub node: usize,
    /// Axial position, m.
    pub z_m: f64,
    /// Mass times radius, kg m.
    pub mass_radius_kg_m: f64,
    /// Phase, degrees.
    pub phase_deg: f64,
}

/// Rayleigh damping coefficients.
#[derive(Debug, Clone, Serialize)]
pub struct RayleighEntries {
    /// Mass-proportional coefficient, 1/s.
    pub alpha_per_s: f64,
    /// Stiffness-proportional coefficient, s.
    pub beta_s: f64,
}

impl Report for ModelCheck {
    type Summary = CheckSummary;

    fn summary(&self) -> CheckSummary {
        let model = &self.model;
        let (shaft, disks) = (model.shaft_mass(), self.disk_mass());
        CheckSummary {
            nodes: model.node_count(),
            dofs: model.dof_count(),
            elements: self.elements(),
            shaft_sections: model.sections.len(),
            shaft_length_m: model.length(),
            shaft_mass_kg: shaft,
            disk_mass_kg: disks,
            total_mass_kg: shaft + disks,
            gravity_m_per_s2: model.gravity,
            disks: model
                .disks
                .iter()
                .map(|d| DiskSummary {
                    name: d.name.clone(),
                    node: d.station.node,
                    z_m: d.station.z,
                    mass_kg: d.mass,
                    polar_inertia_kg_m2: d.polar_inertia,
                    diametral_inertia_kg_m2: d.diametral_inertia,
                })
                .collect(),
            bearings: model.bearings.iter().map(bearing_summary).collect(),
            roller_bearings: model.roller_bearings.iter().map(roller_summary).collect(),
            unbalances: model
                .unbalances
                .iter()
                .map(|u| UnbalanceEntry {
                    node: u.station.node,
                    z_m: u.station.z,
                    mass_radius_kg_m: u.mass_radius,
                    phase_deg: u.phase.to_degrees(),
                })
                .collect(),
            rayleigh_damping: RayleighEntries {
                alpha_per_s: model.damping.alpha,
                beta_s: model.damping.beta,
            },
            operating_speed_hz: model.operating.map(|(a, b)| [hz(a), hz(b)]),
            undamped_frequencies_hz: self.frequencies_hz.clone(),
        }
    }

    /// `nodes` (each node's position and what sits there), `frequencies`, and `clearance`
    /// when a clearance depends on speed.
    fn tables(&self) -> Vec<Table> {
        let model = &self.model;
        let mut nodes = Table::new("nodes");
        nodes
            .counts("node", 0..model.node_count())
            .numbers("z_m", model.node_positions())
            .text("features", model.node_features());
        let f = &self.frequencies_hz;
        let mut frequencies = Table::new("frequencies");
        frequencies
            .counts("mode", (0..f.len()).map(|i| i + 1))
            .numbers("frequency_hz", f.iter().copied());
        let mut tables = vec![nodes, frequencies];
        if let Some(curve) = self.clearance_over_speed() {
            let mut clearance = Table::new("clearance");
            clearance.numbers("speed_hz", curve.speeds_hz.iter().copied());
            for (name, values) in &curve.bearings {
                clearance.numbers(format!("{name}_m"), values.iter().copied());
            }
            tables.push(clearance);
        }
        tables
    }
}

/// Each roller bearing's clearance over speed (thesis eq. 3.1, fig. 3.3).
#[derive(Debug, Clone, PartialEq)]
pub struct ClearanceCurve {
    /// Speeds from rest to the top of the operating range (800 Hz without one), Hz.
    pub speeds_hz: Vec<f64>,
    /// Per roller bearing, its name and clearance at each speed, m.
    pub bearings: Vec<(String, Vec<f64>)>,
}

impl ModelCheck {
    /// The clearances over speed when any roller bearing's clearance depends on speed
    /// (a polynomial); `None` when every clearance is constant.
    pub fn clearance_over_speed(&self) -> Option<ClearanceCurve> {
        let bearings = &self.model.roller_bearings;
        if !bearings
            .iter()
            .any(|b| matches!(b.clearance, Clearance::Polynomial(_)))
        {
            return None;
        }
        // Up to the top of the operating range, where validation has checked the clearance
        // (a polynomial fitted to measurements need not hold beyond it), else 800 Hz.
        let top = self
            .model
            .operating
            .map_or(2.0 * std::f64::consts::PI * 800.0, |(_, max)| max);
        let step = top / (CLEARANCE_SPEEDS - 1) as f64;
        let speeds: Vec<f64> = (0..CLEARANCE_SPEEDS).map(|i| i as f64 * step).collect();
        Some(ClearanceCurve {
            speeds_hz: speeds.iter().map(|&w| hz(w)).collect(),
            bearings: bearings
                .iter()
                .map(|b| {
                    let c = speeds.iter().map(|&w| b.clearance.at_speed(w)).collect();
                    (b.name.clone(), c)
                })
                .collect(),
        })
    }
}

fn bearing_summary(b: &LinearBearing) -> LinearBearingSummary {
    LinearBearingSummary {
        name: b.name.clone(),
        node: b.station.node,
        z_m: b.station.z,
        stiffness_n_per_m: StiffnessEntries {
            kxx: b.stiffness[0][0],
            kxy: b.stiffness[0][1],
            kyx: b.stiffness[1][0],
            kyy: b.stiffness[1][1],
        },
        damping_n_s_per_m: DampingEntries {
            cxx: b.damping[0][0],
            cxy: b.damping[0][1],
            cyx: b.damping[1][0],
            cyy: b.damping[1][1],
        },
    }
}

fn roller_summary(b: &RollerBearing) -> RollerBearingSummary {
    RollerBearingSummary {
        name: b.name.clone(),
        node: b.station.node,
        z_m: b.station.z,
        rollers: b.rollers,
        pitch_diameter_m: b.pitch_diameter,
        roller_diameter_m: b.roller_diameter,
        roller_length_m: b.roller_length,
        clearance_at_rest_m: b.clearance.at_speed(0.0),
        contact_stiffness_n_per_m_pow_n: b.contact_stiffness,
        contact_exponent: b.contact_exponent,
        contact_damping_n_s_per_m: b.contact_damping,
        linear_stiffness_n_per_m: b.linear_stiffness,
        linear_damping_n_s_per_m: b.linear_damping,
    }
}
