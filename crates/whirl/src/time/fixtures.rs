//! Test fixtures shared by the integrators' tests.

use crate::fe::{assemble, gravity_force, unbalance_force, Bearings};
use crate::force::{CubicSpring, LinearSupport};
use crate::model::Model;
use crate::time::{SpeedProfile, TimeProblem};

/// The reference rotor's full model (84 DOFs, half-bandwidth 7) with unbalance at `speed`,
/// and a stiff cubic spring and a cross-coupled linear support on node 10 when `nonlinear`.
pub(crate) fn full_rotor(speed: SpeedProfile, nonlinear: bool) -> TimeProblem {
    let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
    let full = assemble(&model, Bearings::Linearised);
    let unbalance = unbalance_force(&model, full.dofs());
    let mut problem = TimeProblem {
        mass: full.mass.clone(),
        stiffness: full.stiffness.clone(),
        damping: full.damping.clone(),
        gyroscopic: full.gyroscopic.clone(),
        constant_force: gravity_force(&model, &full),
        unbalance_re: unbalance.iter().map(|c| c.re).collect(),
        unbalance_im: unbalance.iter().map(|c| c.im).collect(),
        nonlinear: Vec::new(),
        speed,
    };
    if nonlinear {
        let (ux, uy) = (40, 41);
        problem
            .nonlinear
            .push(Box::new(CubicSpring::new(uy, 1e6, 1e14, 1e-4)));
        problem.nonlinear.push(Box::new(LinearSupport::new(
            "cross-coupled",
            [ux, uy],
            [[1e6, 3e5], [-3e5, 1e6]],
            [[100.0, 0.0], [0.0, 100.0]],
        )));
    }
    problem
}

/// A start (q0, v0) for n coordinates that excites every mode.
pub(crate) fn start(n: usize) -> (Vec<f64>, Vec<f64>) {
    let q0 = (0..n).map(|i| 1e-5 * ((i as f64) * 0.7).sin()).collect();
    let v0 = (0..n).map(|i| 1e-3 * ((i as f64) * 1.3).cos()).collect();
    (q0, v0)
}
