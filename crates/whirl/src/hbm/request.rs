//! A harmonic-balance run as `whirl hbm` and `whirl.hbm` ask for it: the sweep over speed,
//! time-marching comparisons at some speeds, and the sweep again for other harmonic counts.
//! The command line fills [`HbmRequest`] from its flags, the Python package by name
//! ([`HbmRequest::set`]); [`HbmRequest::run`] composes the workflow, so both run the same
//! one, every option left out (`None`) at the library's default.

// Options are read once per request, as the study file reads its own; a large error type
// on this cold path is fine.
#![allow(clippy::result_large_err)]

use serde::Serialize;

use super::bearings::{CageKind, CageModel};
use super::compare::{settled_response, MarchSettings};
use super::fourier::MAX_HARMONICS;
use super::report::SweepReport;
use super::settings::SweepSettings;
use super::sweep::{Sweep, SweepOptions};
use crate::error::{InputError, Result};
use crate::given::{unknown_option, Given, SetByName, MAX_MODES};
use crate::model::Model;
use crate::units::rad_s_to_hz;

/// The lowest speed of the default range, rad/s (1 Hz): harmonic balance needs a running
/// speed.
pub const DEFAULT_LOW_SPEED: f64 = std::f64::consts::TAU;

/// The options [`HbmRequest::set`] reads: the command line's flags with `_` for `-`.
pub const HBM_OPTIONS: [&str; 16] = [
    "speeds",
    "harmonics",
    "nodes",
    "contact",
    "cage",
    "cage_positions",
    "contact_smoothing",
    "samples",
    "reduce",
    "no_stability",
    "stability_modes",
    "compare_time",
    "settle",
    "record",
    "harmonics_study",
    "stability",
];

/// The options of a harmonic-balance run as the user gives them; `None` (or empty) leaves
/// the library's default.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct HbmRequest {
    /// Lowest and highest speed, rad/s; `None` for [`DEFAULT_LOW_SPEED`] to 1.2 times the
    /// model's top operating speed ([`Model::default_speeds`]).
    pub speeds: Option<(f64, f64)>,
    /// The discretisation and bearing model of the sweep (its cage from `cage` and
    /// `cage_positions`).
    pub settings: SweepSettings,
    /// How the roller passage is made periodic.
    pub cage: Option<CageKind>,
    /// Cage positions per roller pitch of the passage average.
    pub cage_positions: Option<usize>,
    /// Nodes whose harmonics the branch table gives, the first compared and studied;
    /// `None` for every disk and bearing node, disks first.
    pub nodes: Option<Vec<usize>>,
    /// Speeds at which the time integrator runs and is compared, rad/s.
    pub compare_time: Vec<f64>,
    /// Settling time of the comparison runs, s ([`MarchSettings::default`]).
    pub settle: Option<f64>,
    /// Recorded time of the comparison runs, s ([`MarchSettings::default`]).
    pub record: Option<f64>,
    /// Harmonic counts the sweep is repeated for (without stability).
    pub harmonics_study: Vec<usize>,
}

impl HbmRequest {
    /// The sweep's settings, its cage made of `cage` and `cage_positions`.
    pub fn sweep_settings(&self) -> SweepSettings {
        let cage = match (self.cage, self.cage_positions) {
            (None, None) => None,
            (kind, positions) => Some(CageModel::new(kind.unwrap_or(CageKind::Passage), positions)),
        };
        SweepSettings {
            cage,
            ..self.settings.clone()
        }
    }

    /// The options of the sweep for `model` with `harmonics` harmonics.
    ///
    /// # Errors
    /// [`crate::Error::Input`] naming `speeds` when the range does not rise through
    /// positive speeds.
    pub fn sweep_options(&self, model: &Model, harmonics: usize) -> Result<SweepOptions> {
        let (from, to) = match self.speeds {
            Some(range) => range,
            None => {
                let w = model.default_speeds(DEFAULT_LOW_SPEED, 2);
                (w[0], w[1])
            }
        };
        if !(from > 0.0 && to > from && to.is_finite()) {
            return Err(InputError::field(
                "speeds",
                format!(
                    "harmonic balance needs a rising range of positive speeds, got {:.4} to \
                     {:.4} Hz",
                    rad_s_to_hz(from),
                    rad_s_to_hz(to)
                ),
            )
            .help("e.g. 1:750Hz")
            .into());
        }
        let mut settings = self.sweep_settings();
        settings.harmonics = Some(harmonics);
        let mut options = settings.options(from, to);
        options.exact_speeds = self.compare_time.clone();
        Ok(options)
    }

    /// The nodes reported, the first compared and studied: those given (each once, in
    /// order), or every disk and bearing node, disks first.
    ///
    /// # Errors
    /// [`crate::Error::Input`] naming `nodes` for a node off the shaft, or a model with no
    /// disk or bearing when none are given.
    pub fn nodes(&self, model: &Model) -> Result<Vec<usize>> {
        let last = model.node_count() - 1;
        let nodes = match &self.nodes {
            Some(given) => {
                if let Some(n) = given.iter().find(|&&n| n > last) {
                    return Err(InputError::field(
                        "nodes",
                        format!("node {n} is not on the shaft"),
                    )
                    .help(format!("nodes are numbered 0 to {last}"))
                    .into());
                }
                let mut nodes: Vec<usize> = Vec::new();
                for &n in given {
                    if !nodes.contains(&n) {
                        nodes.push(n);
                    }
                }
                nodes
            }
            None => disks_then_bearings(model),
        };
        if nodes.is_empty() {
            return Err(InputError::field(
                "nodes",
                "the model has no disk or bearing to report by default",
            )
            .help("give the nodes to report, e.g. 0,10")
            .into());
        }
        Ok(nodes)
    }

    /// Runs the workflow on `model`: the sweep, a time-marching run at each speed of
    /// `compare_time` read at the first node, and the sweep again without stability for
    /// each harmonic count of `harmonics_study`. `sweep` follows each branch (the caller's
    /// progress and interruption around [`super::sweep_with_progress`]).
    ///
    /// # Errors
    /// The errors of [`HbmRequest::sweep_options`], [`HbmRequest::nodes`], `sweep` and
    /// [`settled_response`].
    pub fn run(
        &self,
        model: &Model,
        sweep: &mut dyn FnMut(&SweepOptions) -> Result<Sweep>,
    ) -> Result<SweepReport> {
        let nodes = self.nodes(model)?;
        let options = self.sweep_options(model, self.settings.harmonics())?;
        let studied = self
            .harmonics_study
            .iter()
            .map(|&h| {
                let mut o = self.sweep_options(model, h)?;
                o.stability = false;
                Ok(o)
            })
            .collect::<Result<Vec<_>>>()?;
        let branch = sweep(&options)?;
        let defaults = MarchSettings::default();
        let march = MarchSettings {
            settle: self.settle.unwrap_or(defaults.settle),
            record: self.record.unwrap_or(defaults.record),
            contact: options.contact,
            ..defaults
        };
        let comparisons = self
            .compare_time
            .iter()
            .map(|&w| settled_response(model, w, nodes[0], options.harmonics, &march))
            .collect::<Result<Vec<_>>>()?;
        let study = studied
            .iter()
            .map(|o| Ok((o.harmonics, sweep(o)?)))
            .collect::<Result<Vec<_>>>()?;
        Ok(SweepReport {
            options,
            sweep: branch,
            nodes,
            comparisons,
            study,
        })
    }

    /// The most harmonics any of the run's sweeps solves with: the costliest sweep.
    pub fn most_harmonics(&self) -> usize {
        self.harmonics_study
            .iter()
            .copied()
            .fold(self.settings.harmonics(), usize::max)
    }
}

/// A speed range `(from, to)`, rad/s: text `low:high` or `low:high:count` (the count
/// ignored: continuation chooses its steps), or speeds (the first and last).
fn span(field: &str, v: &Given) -> std::result::Result<(f64, f64), InputError> {
    match v {
        Given::Text(t) if t.split(':').count() == 3 => {
            let w = v.speeds(field)?;
            Ok((w[0], w[w.len() - 1]))
        }
        Given::Text(_) => v.speed_range(field),
        _ => {
            let w = v.speeds(field)?;
            Ok((w[0], w[w.len() - 1]))
        }
    }
}

/// Every disk and bearing node, each once: the disks' first (ascending), then the
/// bearings'.
fn disks_then_bearings(model: &Model) -> Vec<usize> {
    let mut disks: Vec<usize> = model.disks.iter().map(|d| d.station.node).collect();
    disks.sort_unstable();
    disks.dedup();
    let mut others: Vec<usize> = model
        .bearing_nodes()
        .into_iter()
        .filter(|n| !disks.contains(n))
        .collect();
    others.sort_unstable();
    others.dedup();
    disks.extend(others);
    disks
}

impl SetByName for HbmRequest {
    /// Sets the option named `name` (one of [`HBM_OPTIONS`]) to `value`.
    ///
    /// # Errors
    /// [`InputError`] naming `name` for a value it does not read, or an unknown name.
    fn set(&mut self, name: &str, value: &Given) -> std::result::Result<(), InputError> {
        let v = value;
        let s = &mut self.settings;
        match name {
            "speeds" => self.speeds = Some(span(name, v)?),
            "harmonics" => s.harmonics = Some(v.whole(name, 1, MAX_HARMONICS)?),
            "nodes" => {
                let nodes = v.wholes(name, 0, usize::MAX >> 1)?;
                self.nodes = (!nodes.is_empty()).then_some(nodes);
            }
            "contact" => s.contact = Some(v.choice(name)?),
            "cage" => self.cage = Some(v.choice(name)?),
            "cage_positions" => self.cage_positions = Some(v.whole(name, 1, MAX_MODES)?),
            "contact_smoothing" => s.contact_smoothing = Some(v.length_or_zero(name)?),
            "samples" => s.samples = Some(v.whole(name, 1, usize::MAX >> 1)?),
            "reduce" => s.reduction = Some(v.whole(name, 1, MAX_MODES)?),
            "stability" => s.stability = Some(v.flag(name)?),
            "no_stability" => s.stability = Some(!v.flag(name)?),
            "stability_modes" => s.stability_modes = Some(v.whole(name, 1, MAX_MODES)?),
            "compare_time" => {
                self.compare_time = v
                    .items()
                    .iter()
                    .map(|w| w.speed(name))
                    .collect::<std::result::Result<_, _>>()?;
            }
            "settle" => self.settle = Some(v.time(name)?),
            "record" => self.record = Some(v.time(name)?),
            "harmonics_study" => self.harmonics_study = v.wholes(name, 1, MAX_HARMONICS)?,
            _ => return Err(unknown_option(name, &HBM_OPTIONS, "harmonic-balance run")),
        }
        Ok(())
    }
}
