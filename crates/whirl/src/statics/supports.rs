//! Bearing reactions of a static solution, and the load of each roller.

use serde::Serialize;

use super::RollerSupport;
use crate::bearing::{bearing_life, BearingLife, HertzBearing, LifeLoads};
use crate::error::Result;
use crate::fe::{dof, Direction};
use crate::force::{Kinematics, NonlinearForce};
use crate::model::{Model, RollerBearing};

/// One roller of a roller bearing at the static equilibrium.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct RollerLoad {
    /// Roller angle, degrees from +x towards +y (270 is the bottom).
    pub angle_deg: f64,
    /// Approach (positive = compressed), m.
    pub approach: f64,
    /// Contact load, N.
    pub force: f64,
}

/// What a bearing does to the shaft at the static equilibrium.
#[derive(Debug, Clone, Serialize)]
pub struct BearingReaction {
    /// The bearing's name.
    pub name: String,
    /// Its node.
    pub node: usize,
    /// Its axial position, m.
    pub z: f64,
    /// `linear`, `roller (linear)` or `roller (hertz)`.
    pub kind: &'static str,
    /// The shaft's displacement there [ux, uy] (relative to its housing's, for a bearing
    /// in a housing), m.
    pub displacement: [f64; 2],
    /// The bearing's force on the shaft [Fx, Fy], N (Fy > 0 holds the rotor up).
    pub force: [f64; 2],
    /// Each roller's load (roller bearings with Hertz contacts; empty otherwise).
    pub rollers: Vec<RollerLoad>,
    /// The fatigue life under this load (roller and ball bearings with Hertz contacts).
    pub life: Option<BearingLife>,
}

/// Reactions of every bearing for the displacements `q`.
pub(super) fn reactions(
    model: &Model,
    q: &[f64],
    rollers: RollerSupport,
) -> Result<Vec<BearingReaction>> {
    // The shaft's translations relative to the bearing's outer side (a housing, or the
    // ground), which is what its force depends on.
    let at_node = |node: usize, housing: Option<usize>| {
        let outer = model
            .outer_dofs(housing)
            .map_or([0.0; 2], |o| o.map(|d| q[d]));
        [
            q[dof(node, Direction::Ux)] - outer[0],
            q[dof(node, Direction::Uy)] - outer[1],
        ]
    };
    let linear = |u: [f64; 2], k: &[[f64; 2]; 2]| {
        [
            -(k[0][0] * u[0] + k[0][1] * u[1]),
            -(k[1][0] * u[0] + k[1][1] * u[1]),
        ]
    };
    let mut out: Vec<BearingReaction> = model
        .bearings
        .iter()
        .map(|b| {
            let u = at_node(b.station.node, b.housing);
            BearingReaction {
                name: b.name.clone(),
                node: b.station.node,
                z: b.station.z,
                kind: "linear",
                displacement: u,
                force: linear(u, &b.stiffness),
                rollers: Vec::new(),
                life: None,
            }
        })
        .collect();
    for b in &model.roller_bearings {
        let u = at_node(b.station.node, b.housing);
        let reaction = match rollers {
            RollerSupport::Linear => {
                let k = b.linear_stiffness;
                BearingReaction {
                    name: b.name.clone(),
                    node: b.station.node,
                    z: b.station.z,
                    kind: "roller (linear)",
                    displacement: u,
                    force: linear(u, &[[k, 0.0], [0.0, k]]),
                    rollers: Vec::new(),
                    life: None,
                }
            }
            RollerSupport::Hertz => hertz_reaction(b, q, u)?,
        };
        out.push(reaction);
    }
    Ok(out)
}

/// A Hertz roller bearing's force and roller loads at rest (spin angle 0).
fn hertz_reaction(b: &RollerBearing, q: &[f64], u: [f64; 2]) -> Result<BearingReaction> {
    let node = b.station.node;
    let mut directions = vec![Direction::Ux, Direction::Uy];
    if b.roller_tilt {
        directions.extend([Direction::Tx, Direction::Ty]);
    }
    let mut local: Vec<f64> = directions.iter().map(|&d| q[dof(node, d)]).collect();
    // The rollers see the relative translations `u`.
    local[..2].copy_from_slice(&u);
    let mut contact = HertzBearing::new(b, (0..local.len()).collect())?;
    let rest = Kinematics {
        time: 0.0,
        speed: 0.0,
        angle: 0.0,
    };
    let still = vec![0.0; local.len()];
    let mut force = vec![0.0; local.len()];
    contact.force(&rest, &local, &still, &mut force);
    let states = contact.rollers(&rest, &local, &still);
    let mut loads = LifeLoads::default();
    let elements: Vec<f64> = states.iter().map(|r| r.force).collect();
    loads.add(b, force[0].hypot(force[1]), &elements);
    let rollers = states
        .iter()
        .map(|r| RollerLoad {
            angle_deg: r.angle.to_degrees().rem_euclid(360.0),
            approach: r.approach,
            force: r.force,
        })
        .collect();
    Ok(BearingReaction {
        name: b.name.clone(),
        node,
        z: b.station.z,
        kind: if b.is_ball() {
            "ball (hertz)"
        } else {
            "roller (hertz)"
        },
        displacement: u,
        force: [force[0], force[1]],
        rollers,
        // At rest: the life in revolutions (no speed for hours).
        life: bearing_life(b, &loads, 0.0),
    })
}
