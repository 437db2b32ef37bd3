//! Benchmarks of harmonic balance on the reference rotor; figures go to BENCHMARKS.md.
//! Run with `cargo bench -p whirl-rotordynamics --bench hbm`.

mod common;
// The test models; a benchmark uses only the reference rotor.
#[allow(dead_code)]
#[path = "../tests/suite/common/reference.rs"]
mod reference;

use std::f64::consts::TAU;

use reference::reference_rotor;
use whirl::hbm::{sweep, SweepOptions};

fn main() {
    // faer's own threads off: the stability of a branch's points is solved on a second thread.
    faer::set_global_parallelism(faer::Par::Seq);
    let model = reference_rotor();
    for (stability, reduction, name) in [
        (false, None, "1-750 Hz, H = 5, full model, no stability"),
        (true, None, "1-750 Hz, H = 5, full model, Floquet stability"),
        (
            true,
            Some(12),
            "1-750 Hz, H = 5, reduced 8+12, Floquet stability",
        ),
    ] {
        let mut options = SweepOptions::new(TAU, TAU * 750.0, 5);
        options.stability = stability;
        options.reduction = reduction;
        let mut points = 0;
        common::time(name, 3, || {
            let s = sweep(&model, &options).expect("the sweep runs");
            points = s.branch.points.len();
            s
        });
        println!("{:<55} ({points} points)", "");
    }
}
