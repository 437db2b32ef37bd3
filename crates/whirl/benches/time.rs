//! Benchmarks of time marching on the reference rotor; figures go to BENCHMARKS.md.
//! Run with `cargo bench -p whirl-rotordynamics --bench time`.

mod common;
// The test models; a benchmark uses only the reference rotor.
#[allow(dead_code)]
#[path = "../tests/suite/common/reference.rs"]
mod reference;

use std::f64::consts::PI;

use reference::reference_rotor;
use whirl::bearing::ContactLaw;
use whirl::system::SpeedProfile;
use whirl::time::{simulate, Initial, Method, NewmarkScheme, SimulationOptions};

fn options(step: f64, method: Method, reduction: Option<usize>) -> SimulationOptions {
    SimulationOptions {
        speed: SpeedProfile::Constant(2.0 * PI * 50.0),
        duration: 1.0,
        step: Some(step),
        method,
        reduction,
        settle: Some(0.5),
        nodes: Some(vec![10]),
        initial: Initial::StaticEquilibrium,
        divergence_bound: 1.0,
        contact: Some(ContactLaw::Linear),
        record_every: Some(1),
        record_rollers: true,
        progress: None,
    }
}

fn main() {
    faer::set_global_parallelism(faer::Par::Seq);
    let model = reference_rotor();
    let report = |name: &str, o: SimulationOptions, runs: usize| {
        let mut march = 0.0;
        common::time(name, runs, || {
            let r = simulate(&model, &o).expect("runs");
            march = r.wall_time_s;
            r
        });
        println!("{:<55} (march alone {:.3} ms)", "", march * 1e3);
    };
    report(
        "1 s, reduced 8+12, central difference, h = 1e-5",
        options(1e-5, Method::CentralDifference, Some(12)),
        10,
    );
    report(
        "1 s, full 84 DOFs, central difference, h = 3.9e-6",
        options(3.9e-6, Method::CentralDifference, None),
        3,
    );
    report(
        "1 s, reduced 8+12, Newmark, h = 1e-5",
        options(
            1e-5,
            Method::Newmark(NewmarkScheme::AverageAcceleration),
            Some(12),
        ),
        3,
    );
    report(
        "1 s, full 84 DOFs, Newmark, h = 1e-4",
        options(
            1e-4,
            Method::Newmark(NewmarkScheme::AverageAcceleration),
            None,
        ),
        3,
    );
    report(
        "1 s, full 84 DOFs, Dormand-Prince 5(4), output 1e-5",
        options(1e-5, Method::RungeKutta(Default::default()), None),
        1,
    );
}
