//! Roller bearings in [`super::simulate`]: the rigid-roller static start and the
//! constraints of the Lagrange law, and the probes that evaluate each roller from the
//! recorded motion of its bearing's node.

use crate::bearing::{
    contact_coordinates_of, hertz_bearings, ContactLaw, HertzBearing, LagrangeContacts,
};
use crate::error::Result;
use crate::fe::{dof, Bearings, Direction};
use crate::force::Kinematics;
use crate::model::{Model, RollerBearing};
use crate::system::{build, Coordinates, RecoveryRow, SpeedProfile};
use crate::time::statics::static_equilibrium;
use crate::time::RollerRecord;

/// Rigid rollers are approached in the static solve by Hertz contacts this many times
/// stiffer than the model's: their penetration, (1/RIGID_STIFFENING)^(1/n) = 2.5e-4 times
/// the Hertz one for n = 10/9, is a fraction of a nanometre, and the first Lagrange
/// correction removes it without a noticeable jolt.
const RIGID_STIFFENING: f64 = 1e4;

/// The static equilibrium on rigid rollers (see [`RIGID_STIFFENING`]), in the coordinates
/// of `reduction`, at the starting speed of `speed`.
pub(super) fn rigid_static_equilibrium(
    model: &Model,
    reduction: Option<usize>,
    speed: &SpeedProfile,
) -> Result<Vec<f64>> {
    let mut stiff = model.clone();
    for b in &mut stiff.roller_bearings {
        b.contact_stiffness *= RIGID_STIFFENING;
    }
    let mut problem = build(&stiff, reduction, Bearings::NonlinearApart, &hertz_bearings)?.system;
    let n = problem.size();
    static_equilibrium(&mut problem, &vec![0.0; n], speed.at(0.0).0.speed)
}

/// Every roller bearing's rollers as Lagrange-multiplier constraints.
pub(super) fn lagrange_contacts(model: &Model, coords: &Coordinates) -> Result<LagrangeContacts> {
    let map = |physical: usize| coords.coordinate_of(physical);
    let mut coordinates = Vec::new();
    if let Some(b) = model.roller_bearings.iter().find(|b| b.housing.is_some()) {
        return Err(crate::error::Error::Unsupported(format!(
            "{} sits in a housing: the Lagrange contacts constrain the shaft against a fixed              outer ring; use the Hertz or forcing-function law for bearings in housings",
            b.name
        )));
    }
    for b in &model.roller_bearings {
        coordinates.extend(contact_coordinates_of(
            b,
            &[Direction::Ux, Direction::Uy],
            &map,
        )?);
    }
    LagrangeContacts::new(&model.roller_bearings, coordinates)
}

/// The recorded nodes: those asked for, then (for a contact law) every roller bearing's
/// node not among them, ascending.
pub(super) fn recorded_nodes(
    model: &Model,
    mut nodes: Vec<usize>,
    law: Option<ContactLaw>,
) -> Vec<usize> {
    if law.is_some() {
        let mut extra: Vec<usize> = model
            .roller_bearings
            .iter()
            .map(|b| b.station.node)
            .filter(|n| !nodes.contains(n))
            .collect();
        extra.sort_unstable();
        extra.dedup();
        nodes.extend(extra);
    }
    nodes
}

/// Evaluates one roller bearing's rollers from its node's recorded motion.
pub(super) struct RollerProbe {
    contact: HertzBearing,
    /// Rows of the node's [ux, uy] (and [tx, ty] with tilt).
    rows: Vec<RecoveryRow>,
    /// Per-roller forces are NaN here: a law without rollers, or Lagrange multipliers,
    /// filled in after the march.
    no_forces: bool,
    q: Vec<f64>,
    v: Vec<f64>,
    pub(super) record: RollerRecord,
}

impl RollerProbe {
    pub(super) fn new(
        model: &Model,
        bearing: &RollerBearing,
        law: ContactLaw,
        coords: &Coordinates,
        capacity: usize,
    ) -> Result<Self> {
        // Rigid rollers are one constraint each, without tilt or skew (see
        // [`crate::bearing::lagrange`]): their approach is that of the plain bearing.
        let mut plain = bearing.clone();
        if law == ContactLaw::Lagrange {
            plain.roller_tilt = false;
            plain.slices = 1;
            plain.skew_angle = 0.0;
        }
        let bearing = &plain;
        let mut directions = vec![Direction::Ux, Direction::Uy];
        if bearing.roller_tilt {
            directions.extend([Direction::Tx, Direction::Ty]);
        }
        let node = bearing.station.node;
        // In a housing the rollers see the shaft's translations relative to the housing's.
        let outer = model.outer_dofs(bearing.housing);
        let rows: Vec<RecoveryRow> = directions
            .iter()
            .enumerate()
            .map(|(k, &d)| {
                let row = coords.recovery_row(dof(node, d));
                match outer {
                    Some(o) if k < 2 => row.minus(&coords.recovery_row(o[k])),
                    _ => row,
                }
            })
            .collect();
        let m = rows.len();
        Ok(RollerProbe {
            contact: HertzBearing::new(bearing, (0..m).collect())?,
            rows,
            no_forces: matches!(law, ContactLaw::Forcing | ContactLaw::Lagrange),
            q: vec![0.0; m],
            v: vec![0.0; m],
            record: RollerRecord::new(bearing, capacity),
        })
    }

    pub(super) fn record(&mut self, at: &Kinematics, q: &[f64], v: &[f64]) {
        for (k, row) in self.rows.iter().enumerate() {
            self.q[k] = row.dot(q);
            self.v[k] = row.dot(v);
        }
        for r in self.contact.rollers(at, &self.q, &self.v) {
            self.record.angle.push(r.angle);
            self.record.approach.push(r.approach);
            self.record
                .force
                .push(if self.no_forces { f64::NAN } else { r.force });
        }
    }
}

/// Puts the multipliers of `history` (every step, every roller of every bearing) into the
/// records, which hold every `every`-th step.
pub(super) fn fill_multipliers(records: &mut [RollerRecord], history: &[f64], every: usize) {
    let total: usize = records.iter().map(|r| r.rollers).sum();
    let mut first = 0;
    for r in records {
        for i in 0..r.samples() {
            let step = &history[i * every * total..(i * every + 1) * total];
            r.force[i * r.rollers..(i + 1) * r.rollers]
                .copy_from_slice(&step[first..first + r.rollers]);
        }
        first += r.rollers;
    }
}
