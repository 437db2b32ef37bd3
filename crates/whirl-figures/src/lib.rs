//! What each whirl analysis's figures show: the series, axes, marks and labels of every
//! figure, built from the library's results as [`whirl_plot`] figures.
//!
//! Data flows one way: the library's result (or report) -> the figures of this crate (a
//! specification: plain data, serialisable) -> a renderer. The command line saves them as
//! PNG and SVG with [`whirl_plot`]; the Python package saves the same files through this
//! crate and draws the same specification with matplotlib, so the two cannot drift.
//!
//! Each analysis has one function returning its figures in the order the command line writes
//! them, each named by the stem of its files ([`NamedFigure`]); [`plots`] holds the function
//! of each figure. Lengths are shown in mm (the rotor) or µm (responses), speeds in Hz
//! ([`NamedFigure::in_rpm`] turns them into rpm).
//!
//! ```no_run
//! let model = whirl::model::Model::from_file("examples/reference_rotor.toml".as_ref())?;
//! let check = whirl::modal::check_model(&model)?;
//! for figure in whirl_figures::check(&check) {
//!     figure.save_in(std::path::Path::new("out"))?; // out/rotor.png, out/rotor.svg
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

use whirl::bearing::stiffness::{clearance_label, StiffnessReport};
use whirl::hbm::{BifurcationKind, SweepReport};
use whirl::map::MapReport;
use whirl::modal::{CampbellResult, ConvergenceResult, CriticalSpeedMap, ModalReport, ModelCheck};
use whirl::model::Model;
use whirl::nsv::CascadeReport;
use whirl::reduce::ReductionReport;
use whirl::response::{FrfKind, FrfResult, UnbalanceResult};
use whirl::runup::RunupReport;
use whirl::statics::StaticResult;
use whirl::study::report::StudyReport;
use whirl::time::{ForcingFitReport, SimulationReport};
use whirl_plot::{NamedFigure, SpeedAxis};

pub mod hbm;
pub mod plots;

pub use whirl_plot::{Figure, SpeedMarks};

/// The name of excitation order `k`: `1X`, `0.5X`.
pub fn order_name(k: f64) -> String {
    format!("{k}X")
}

/// The short name of a bifurcation in figures and tables: F, SB, PD, NS.
pub fn kind_label(kind: BifurcationKind) -> &'static str {
    match kind {
        BifurcationKind::Fold => "F",
        BifurcationKind::SymmetryBreaking => "SB",
        BifurcationKind::PeriodDoubling => "PD",
        BifurcationKind::NeimarkSacker => "NS",
    }
}

/// `whirl check`: the rotor's layout; with a speed-dependent clearance, the clearance over
/// speed.
pub fn check(check: &ModelCheck) -> Vec<NamedFigure> {
    let mut figures = vec![NamedFigure::new("rotor", plots::rotor_layout(&check.model))];
    if let Some(curve) = check.clearance_over_speed() {
        figures.push(NamedFigure::new(
            "clearance",
            plots::clearance_over_speed(&curve),
        ));
    }
    figures
}

/// `whirl convergence`: each mode's frequency over the element count, and its change.
pub fn convergence(result: &ConvergenceResult) -> Vec<NamedFigure> {
    vec![
        NamedFigure::new("convergence", plots::convergence(result)),
        NamedFigure::new("convergence_change", plots::convergence_change(result)),
    ]
}

/// `whirl campbell`: the Campbell diagram and the branches' logarithmic decrement.
pub fn campbell(model: &Model, diagram: &CampbellResult) -> Vec<NamedFigure> {
    let labels = diagram.labels();
    vec![
        NamedFigure::new("campbell", plots::campbell(model, diagram, &labels))
            .speed_axis(SpeedAxis::X),
        NamedFigure::new("log_decrement", plots::log_decrement(diagram, &labels))
            .speed_axis(SpeedAxis::X),
    ]
}

/// `whirl modal`: the undamped mode shapes and the damped modes' orbits.
pub fn modal(model: &Model, modes: &ModalReport) -> Vec<NamedFigure> {
    let speed_hz = whirl::units::rad_s_to_hz(modes.speed);
    vec![
        NamedFigure::new("mode_shapes", plots::mode_shapes(model, &modes.undamped)),
        NamedFigure::new(
            "damped_orbits",
            plots::damped_orbits(model, &modes.damped, &modes.labels, speed_hz),
        ),
    ]
}

/// `whirl unbalance`: the Bode plot, the polar plot and the orbit size over speed.
pub fn unbalance(result: &UnbalanceResult) -> Vec<NamedFigure> {
    vec![
        NamedFigure::new("bode", plots::bode(result)).speed_axis(SpeedAxis::X),
        NamedFigure::new("polar", plots::polar(result)).speed_texts(),
        NamedFigure::new("orbit_major", plots::orbit_major(result)).speed_axis(SpeedAxis::X),
    ]
}

/// `whirl static`: the deflected rotor and, with roller bearings, their rollers' loads.
pub fn statics(model: &Model, result: &StaticResult) -> Vec<NamedFigure> {
    let mut figures = vec![NamedFigure::new(
        "static_response",
        plots::static_response(model, result),
    )];
    if result.has_rollers() {
        figures.push(NamedFigure::new(
            "roller_loads",
            plots::roller_loads(model, result),
        ));
    }
    figures
}

/// `whirl reduce`: each mode's error and the stable time step over the basis size.
pub fn reduce(report: &ReductionReport) -> Vec<NamedFigure> {
    vec![
        NamedFigure::new("reduction_error", plots::reduction_error(&report.study)),
        NamedFigure::new("stable_step", plots::stable_steps(&report.study)),
    ]
}

/// `whirl frf`: receptance, mobility and accelerance.
pub fn frf(model: &Model, result: &FrfResult) -> Vec<NamedFigure> {
    FrfKind::ALL
        .into_iter()
        .map(|kind| NamedFigure::new(kind.name(), plots::frf(model, result, kind)))
        .collect()
}

/// `whirl ucs`: the undamped critical speeds over the support stiffness.
pub fn ucs(model: &Model, map: &CriticalSpeedMap) -> Vec<NamedFigure> {
    vec![NamedFigure::new("ucs", plots::critical_speed_map(model, map)).speed_axis(SpeedAxis::Y)]
}

/// `whirl stiffness`: stiffness over clearance, and each force surface's components.
pub fn stiffness(report: &StiffnessReport) -> Vec<NamedFigure> {
    let mut figures = vec![NamedFigure::new(
        "stiffness_vs_clearance",
        plots::stiffness::stiffness_vs_clearance(&report.study),
    )];
    for surface in &report.surfaces {
        let label = clearance_label(surface.clearance);
        for component in plots::stiffness::Component::ALL {
            figures.push(NamedFigure::new(
                format!("surface_{label}_{}", component.name()),
                plots::stiffness::force_surface(surface, component),
            ));
        }
    }
    figures
}

/// `whirl cascade`: the NSV from both starts (when compared), the waterfall, the cascade
/// map up to `map_top_hz` (default [`plots::default_map_top_hz`]), the NSV amplitude, and
/// with the full solution its map.
pub fn cascade(report: &CascadeReport, map_top_hz: Option<f64>) -> Vec<NamedFigure> {
    let (result, threshold) = (&report.cascade, report.threshold_m);
    let mut figures = Vec::new();
    if let Some(starts) = &report.starts {
        figures.push(
            NamedFigure::new(
                "starts",
                plots::nsv_from_both_starts(result, starts, threshold),
            )
            .speed_axis(SpeedAxis::X),
        );
    }
    let top = map_top_hz.unwrap_or_else(|| plots::default_map_top_hz(result));
    figures.extend([
        NamedFigure::new("waterfall", plots::waterfall(result)).speed_axis(SpeedAxis::Y),
        NamedFigure::new("cascade_map", plots::cascade_map(result, threshold, top))
            .speed_axis(SpeedAxis::X),
        NamedFigure::new("nsv", plots::nsv_amplitude(result, threshold)).speed_axis(SpeedAxis::X),
    ]);
    if result.options.full {
        figures.push(
            NamedFigure::new("full_map", plots::full_map(result, top)).speed_axis(SpeedAxis::X),
        );
    }
    figures
}

/// `whirl runup`: each sweep's time-frequency map up to `map_top_hz` (default twice the
/// fastest speed, at most the resolved band), and the amplitudes over speed.
pub fn runup(report: &RunupReport, map_top_hz: Option<f64>) -> Vec<NamedFigure> {
    let r = &report.runup;
    let fastest = whirl::units::rad_s_to_hz(r.options.high);
    let top = map_top_hz
        .unwrap_or(2.0 * fastest)
        .min(r.resolved.max_frequency_hz);
    vec![
        NamedFigure::new("runup_map", plots::runup_maps(r, top)),
        NamedFigure::new("runup_nsv", plots::runup_amplitudes(r)).speed_axis(SpeedAxis::X),
    ]
}

/// `whirl map`: the unstable bands over speed and the parameter.
pub fn map(report: &MapReport) -> Vec<NamedFigure> {
    vec![NamedFigure::new("map", plots::map::map_plot(report)).speed_axis(SpeedAxis::X)]
}

/// `whirl study`: for each sweep its cascades side by side and the NSV over the parameter.
pub fn study(report: &StudyReport) -> Vec<NamedFigure> {
    let (study, results, outcome) = (&report.study, &report.results, &report.outcome);
    let mut figures = Vec::new();
    for (i, sweep) in outcome.sweeps.iter().enumerate() {
        let maps: Vec<_> = study.sweeps[i]
            .points
            .iter()
            .map(|&p| results[p].as_ref().ok().map(|r| &r.map))
            .collect();
        figures.push(NamedFigure::new(
            format!("cascades_{i}"),
            plots::study::cascade_grid(sweep, &maps),
        ));
        figures.push(NamedFigure::new(
            format!("nsv_{i}"),
            plots::study::nsv_versus_parameter(sweep, study.metric),
        ));
    }
    figures
}

/// `whirl simulate`: per roller bearing its contact line, contact zone and load zone, then
/// the time history, the orbits (with each roller bearing's clearance circle at the final
/// speed) and the spectrum (with the bearings' characteristic and waviness frequencies).
pub fn simulate(model: &Model, report: &SimulationReport) -> Vec<NamedFigure> {
    let result = &report.result;
    let mut figures = Vec::new();
    for b in &report.bearings {
        let r = report.record(b);
        figures.extend([
            NamedFigure::new(
                format!("contact_line_{}", b.stem),
                plots::contact_line(r, &result.time, b.line_window.clone()),
            ),
            NamedFigure::new(
                format!("contact_zone_{}", b.stem),
                plots::contact_zone(r, b.settled_range.clone(), b.clearance),
            ),
            NamedFigure::new(
                format!("load_zone_{}", b.stem),
                plots::load_zone(r, b.settled_range.clone()),
            ),
        ]);
    }
    // Every recorded node: those asked for and the bearing nodes a contact law adds.
    let mut recorded: Vec<usize> = result.channels.iter().map(|c| c.node).collect();
    recorded.dedup();
    let circles = plots::clearance_circles(model, report.final_speed());
    let markers = plots::spectrum_markers(&report.bearings);
    figures.extend([
        NamedFigure::new("time_history", plots::time_history(result, &recorded)),
        NamedFigure::new("orbits", plots::orbits(result, &recorded, &circles)),
        NamedFigure::new(
            "spectrum",
            plots::spectrum(&report.channels, report.running_hz(), &markers),
        ),
    ]);
    figures
}

/// `whirl fit-forcing`: the force over the deflection, samples and fit per speed.
pub fn fit_forcing(report: &ForcingFitReport) -> Vec<NamedFigure> {
    vec![NamedFigure::new(
        "force_deflection",
        plots::fit::force_deflection(&report.fit),
    )]
}

/// `whirl hbm`: the harmonics over speed, the stability (when computed) and the harmonics
/// study (when asked).
pub fn harmonic_balance(report: &SweepReport) -> Vec<NamedFigure> {
    let (result, node) = (&report.sweep, report.nodes[0]);
    let mut figures = vec![NamedFigure::new(
        "harmonics",
        hbm::harmonics_plot(result, node, &report.comparisons, report.options.from),
    )
    .speed_axis(SpeedAxis::X)];
    if report.options.stability {
        figures.push(
            NamedFigure::new("stability", hbm::stability_plot(result)).speed_axis(SpeedAxis::X),
        );
    }
    if !report.study.is_empty() {
        figures.push(
            NamedFigure::new("harmonics_study", hbm::study_plot(&report.study, node))
                .speed_axis(SpeedAxis::X),
        );
    }
    figures
}
