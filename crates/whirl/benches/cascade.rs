//! Benchmark of the cascade on the reference rotor; figures go to BENCHMARKS.md.
//! Run with `cargo bench -p whirl-rotordynamics --bench cascade`.

mod common;
// The test models; a benchmark uses only the reference rotor.
#[allow(dead_code)]
#[path = "../tests/suite/common/reference.rs"]
mod reference;

use reference::reference_rotor;
use whirl::nsv::{cascade, CascadeOptions};
use whirl::units::{parse_range, Dimension};

fn main() {
    faer::set_global_parallelism(faer::Par::Seq);
    let model = reference_rotor();
    let speeds = parse_range("1:750Hz:150", Dimension::AngularSpeed).expect("range");
    // The defaults: 0.5 s settling + 0.5 s recorded, reduced 8 + 12, Hertz, Hann.
    let options = CascadeOptions::new(&model, speeds);
    let threads = rayon::current_num_threads();
    let whole = common::time(
        &format!("cascade, 150 speeds 1-750 Hz, 1 s each, {threads} threads"),
        3,
        || cascade(&model, &options, None, None).expect("runs"),
    );
    println!(
        "{:<55} {:.1} ms of wall time per speed, {:.1} ms of CPU per speed",
        "",
        whole.as_secs_f64() * 1e3 / 150.0,
        whole.as_secs_f64() * 1e3 * threads as f64 / 150.0
    );
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    for hz in [50.0, 300.0, 600.0] {
        let mut single = options.clone();
        single.speeds = vec![2.0 * std::f64::consts::PI * hz];
        common::time(&format!("one speed, {hz} Hz, 1 thread"), 5, || {
            one.install(|| cascade(&model, &single, None, None).expect("runs"))
        });
    }
}
