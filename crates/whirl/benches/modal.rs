//! Benchmarks of the linear analyses on the reference rotor (84 DOFs).
//! Run with `cargo bench -p whirl-rotordynamics --bench modal`; figures go to BENCHMARKS.md.

mod common;
// The test models; a benchmark uses only the reference rotor.
#[allow(dead_code)]
#[path = "../tests/suite/common/reference.rs"]
mod reference;

use std::f64::consts::PI;

use reference::reference_rotor;
use whirl::fe::{assemble, Bearings};
use whirl::modal::{campbell, undamped_modes, CampbellOptions};
use whirl::model::Model;
use whirl::response::unbalance_response;

fn main() {
    // Parallelism is across speeds (rayon); faer's own threads only oversubscribe 2 cores.
    faer::set_global_parallelism(faer::Par::Seq);
    let model = reference_rotor();
    println!("threads: {}", rayon::current_num_threads());

    common::time("parse + validate reference_rotor.toml", 200, || {
        Model::from_toml_str(whirl::examples::REFERENCE_ROTOR, None)
    });
    common::time("assemble M, K, G, C (84 DOFs)", 200, || {
        assemble(&model, Bearings::Linearised)
    });
    common::time("assemble + undamped modal (all 84 modes)", 100, || {
        let sys = assemble(&model, Bearings::Linearised);
        undamped_modes(&sys, 84)
    });

    let sys = assemble(&model, Bearings::Linearised);
    let speeds: Vec<f64> = (0..161).map(|i| 2.0 * PI * 5.0 * i as f64).collect();
    let options = CampbellOptions::new(speeds.clone());
    common::time(
        "Campbell 161 speeds, 8 branches, basis 24 (default)",
        10,
        || campbell(&sys, &options, None),
    );
    let mut full = CampbellOptions::new(speeds);
    full.basis_size = None;
    common::time(
        "Campbell 161 speeds, 8 branches, full 168x168 solve",
        3,
        || campbell(&sys, &full, None),
    );

    let speeds: Vec<f64> = (1..=800).map(|i| 2.0 * PI * i as f64).collect();
    common::time("unbalance response, 800 speeds, 2 nodes", 10, || {
        unbalance_response(&model, &sys, &speeds, &[0, 10])
    });
}
