//! Harmonic balance (`whirl hbm`): the periodic response followed over speed, with Floquet
//! stability, the time-marching comparisons and the harmonic-count study, reported by the
//! library as the command line writes it.

use std::sync::Arc;

use pyo3::prelude::*;
use whirl::hbm::{
    settled_response, sweep_with_progress, CageModel, MarchSettings, Sweep, SweepOptions,
    SweepReport,
};
use whirl::model::Model;

use crate::error::to_py;
use crate::model::PyModel;
use crate::nsv::choice;
use crate::report::PyReport;
use crate::watch::{fraction_progress, run_watched, Watch};

/// The run's options, resolved by the Python package from its keyword arguments (the
/// command line's options and defaults; speeds in rad/s, times in s).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct HbmArgs {
    from: f64,
    to: f64,
    harmonics: usize,
    nodes: Vec<usize>,
    contact: String,
    cage: String,
    cage_positions: usize,
    contact_smoothing: f64,
    samples: Option<usize>,
    reduce: Option<usize>,
    stability: bool,
    stability_modes: usize,
    compare_time: Vec<f64>,
    settle: f64,
    record: f64,
    harmonics_study: Vec<usize>,
}

/// The library's options for `harmonics` harmonics, as the command line builds them.
fn sweep_options(a: &HbmArgs, harmonics: usize) -> PyResult<SweepOptions> {
    let mut o = SweepOptions::new(a.from, a.to, harmonics);
    o.contact = choice("contact", &a.contact)?;
    o.cage = CageModel::new(choice("cage", &a.cage)?, Some(a.cage_positions));
    o.contact_smoothing = a.contact_smoothing;
    o.samples = a.samples;
    o.stability = a.stability;
    o.stability_modes = a.stability_modes;
    o.reduction = a.reduce;
    o.exact_speeds = a.compare_time.clone();
    Ok(o)
}

/// The sweep, telling `watch` the fraction of the speed range followed and stopping when
/// it is asked to.
fn sweep_watched(model: &Model, o: &SweepOptions, watch: &Arc<Watch>) -> whirl::Result<Sweep> {
    let progress = fraction_progress(watch);
    sweep_with_progress(model, o, Some(&progress))
}

/// The harmonic-balance run as `whirl hbm` makes it: the sweep, a time-marching run at each
/// of `compare_time` read at the first node, and the sweep again (without stability) for
/// each harmonic count of `harmonics_study`; `progress(done, 1000)` is told each sweep's
/// fraction of the speed range.
#[pyfunction]
#[pyo3(signature = (model, options, progress = None))]
pub fn hbm(
    py: Python<'_>,
    model: &PyModel,
    options: HbmArgs,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<PyReport> {
    let o = sweep_options(&options, options.harmonics)?;
    let studied = options
        .harmonics_study
        .iter()
        .map(|&h| {
            let mut o = sweep_options(&options, h)?;
            o.stability = false;
            Ok(o)
        })
        .collect::<PyResult<Vec<_>>>()?;
    let model = &model.model;
    let report = run_watched(py, progress.as_ref(), |watch| {
        let sweep = sweep_watched(model, &o, watch)?;
        let settings = MarchSettings {
            settle: options.settle,
            record: options.record,
            contact: o.contact,
            ..MarchSettings::default()
        };
        let comparisons = options
            .compare_time
            .iter()
            .map(|&w| settled_response(model, w, options.nodes[0], options.harmonics, &settings))
            .collect::<whirl::Result<Vec<_>>>()?;
        let study = studied
            .iter()
            .map(|s| Ok((s.harmonics, sweep_watched(model, s, watch)?)))
            .collect::<whirl::Result<Vec<_>>>()?;
        Ok::<_, whirl::Error>(SweepReport {
            options: o.clone(),
            sweep,
            nodes: options.nodes.clone(),
            comparisons,
            study,
        })
    })?
    .map_err(to_py)?;
    PyReport::with_figures(&report, whirl_figures::harmonic_balance(&report))
}
