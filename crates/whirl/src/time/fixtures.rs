//! Test fixtures shared by the integrators' tests.

use crate::fe::Bearings;
use crate::force::{no_forces, CubicSpring, LinearSupport};
use crate::model::Model;
use crate::system::{build, System};

/// The reference rotor's full model (84 DOFs, half-bandwidth 7) with gravity and unbalance,
/// and a stiff cubic spring and a cross-coupled linear support on node 10 when `nonlinear`.
pub(crate) fn full_rotor(nonlinear: bool) -> System {
    let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
    let mut problem = build(&model, None, Bearings::Linearised, &no_forces)
        .unwrap()
        .system;
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
