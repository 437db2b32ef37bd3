//! Internal forces along the shaft from the elements' end forces (see the module above).

use serde::Serialize;

use crate::fe::{dof, element_forces, element_matrices, Direction};
use crate::model::Model;

/// The state of the shaft at one end of an element.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Station {
    /// Node index.
    pub node: usize,
    /// Axial position, m.
    pub z: f64,
    /// The element whose end this is (0 from z = 0).
    pub element: usize,
    /// Deflection [ux, uy], m.
    pub deflection: [f64; 2],
    /// Slope [d(ux)/dz, d(uy)/dz], rad: the cross-section's rotation (for Timoshenko
    /// elements it differs from the slope of the axis by the shear strain).
    pub slope: [f64; 2],
    /// Bending moment of the x and y deflections, E I d(slope)/dz, N m; positive where the
    /// shaft is concave towards +x (+y), i.e. sagging under gravity between supports.
    pub moment: [f64; 2],
    /// Shear force dM/dz of each plane, N.
    pub shear: [f64; 2],
}

/// Stations at both ends of every element, for the displacements `q` of a static solution.
pub fn station_forces(model: &Model, q: &[f64]) -> Vec<Station> {
    let z = model.node_positions();
    let mut out = Vec::with_capacity(2 * (z.len() - 1));
    let mut element = 0;
    for section in &model.sections {
        let e = element_matrices(section);
        let length = section.length / section.elements as f64;
        for _ in 0..section.elements {
            let first = 4 * element;
            let u = &q[first..first + 8];
            let k = element_forces(&e, length, model.options.axial_load, u);
            // The element's own weight, consistent with its mass: -g times the uy columns.
            let f: Vec<f64> = (0..8)
                .map(|i| {
                    k[i] + model.gravity * (e.mass_translational[i][1] + e.mass_translational[i][5])
                })
                .collect();
            let at = |node: usize, sign: f64, base: usize| {
                let beta = [q[dof(node, Direction::Ty)], -q[dof(node, Direction::Tx)]];
                Station {
                    node,
                    z: z[node],
                    element,
                    deflection: [q[dof(node, Direction::Ux)], q[dof(node, Direction::Uy)]],
                    slope: beta,
                    // x plane: f_beta = f_ty; y plane: f_beta = -f_tx.
                    moment: [-sign * f[base + 3], sign * f[base + 2]],
                    shear: [sign * f[base], sign * f[base + 1]],
                }
            };
            out.push(at(element, 1.0, 0));
            out.push(at(element + 1, -1.0, 4));
            element += 1;
        }
    }
    out
}
