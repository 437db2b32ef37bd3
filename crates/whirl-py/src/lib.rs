//! `whirl._whirl`, the compiled half of the Python package `whirl`.
//!
//! A thin layer over the library, like the command line: it reads models, calls the same
//! library functions with the options given, and hands the results to Python. An analysis
//! the library reports whole (`whirl::report::Report`: hbm, reduce) comes back as the one
//! result type of `report.rs`, its summary and tables the library's own, as the command
//! line writes them; the others as dicts of numpy arrays and plain values, which the Python
//! package (`whirl/`) shapes into the command line's tables and summaries.

#![forbid(unsafe_code)]

mod analyses;
mod cluster;
mod error;
mod given;
mod hbm;
mod map;
mod modal;
mod model;
mod nsv;
mod report;
mod response;
mod ross;
mod runup;
mod study;
mod time;
mod units;
mod watch;

use pyo3::prelude::*;

#[pymodule]
fn _whirl(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // As in the command line: whirl parallelises across speeds with rayon, and faer's own
    // threads would only compete with them.
    faer::set_global_parallelism(faer::Par::Seq);
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("BUILD_ID", whirl::BUILD_ID)?;
    error::register(m)?;
    // The command line's defaults, defined once in the library.
    m.add("DEFAULT_SPEED_COUNT", whirl::nsv::DEFAULT_SPEED_COUNT)?;
    m.add("MAX_HARMONICS", whirl::hbm::MAX_HARMONICS)?;
    m.add("MAX_AFT_SAMPLES", whirl::hbm::MAX_SAMPLES)?;
    m.add(
        "DEFAULT_STABILITY_MODES",
        whirl::hbm::DEFAULT_STABILITY_MODES,
    )?;
    m.add_class::<report::PyReport>()?;
    m.add_function(wrap_pyfunction!(report::save_figures, m)?)?;
    // The colours of a figure's series that name none, by index (`whirl.plot.draw`).
    let palette = (0..whirl_plot::PALETTE.len()).map(|i| whirl_plot::Colour::Palette(i).hex());
    m.add("PALETTE", palette.collect::<Vec<_>>())?;
    m.add_function(wrap_pyfunction!(hbm::hbm, m)?)?;
    m.add_function(wrap_pyfunction!(map::map, m)?)?;
    m.add_function(wrap_pyfunction!(map::map_value, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::reduce, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::statics, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::stiffness, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::ucs, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::frf, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::fit_forcing, m)?)?;
    m.add_class::<model::PyModel>()?;
    m.add_function(wrap_pyfunction!(units::parse_speed, m)?)?;
    m.add_function(wrap_pyfunction!(units::parse_speeds, m)?)?;
    m.add_function(wrap_pyfunction!(modal::check, m)?)?;
    m.add_function(wrap_pyfunction!(modal::campbell, m)?)?;
    m.add_function(wrap_pyfunction!(modal::convergence, m)?)?;
    m.add_function(wrap_pyfunction!(modal::modal, m)?)?;
    m.add_function(wrap_pyfunction!(response::unbalance, m)?)?;
    m.add_function(wrap_pyfunction!(ross::ross_to_toml, m)?)?;
    m.add_function(wrap_pyfunction!(runup::runup, m)?)?;
    m.add_function(wrap_pyfunction!(nsv::cascade, m)?)?;
    m.add_function(wrap_pyfunction!(nsv::cascade_point, m)?)?;
    m.add_function(wrap_pyfunction!(nsv::cascade_checkpoint, m)?)?;
    m.add_function(wrap_pyfunction!(nsv::cascade_default_speeds, m)?)?;
    m.add_function(wrap_pyfunction!(nsv::cascade_resolved, m)?)?;
    m.add_function(wrap_pyfunction!(nsv::other_start, m)?)?;
    m.add_function(wrap_pyfunction!(nsv::cascade_report, m)?)?;
    m.add_class::<nsv::RawCascade>()?;
    m.add_function(wrap_pyfunction!(units::quantity, m)?)?;
    m.add_function(wrap_pyfunction!(units::range, m)?)?;
    m.add_function(wrap_pyfunction!(study::study, m)?)?;
    m.add_function(wrap_pyfunction!(time::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(study::study_point, m)?)?;
    Ok(())
}
