//! A cascade as `whirl cascade`, `whirl.cascade` and a study's `[cascade]` table ask for
//! it, in the terms of their options: the command line fills it from its flags, the Python
//! package and the study file by name ([`CascadeRequest::set`]), and
//! [`CascadeRequest::options`] turns it into the library's [`CascadeOptions`]. Every
//! default is the library's ([`CascadeOptions::new`]): a front end leaves an option out
//! (`None`) rather than restating it.

// Options are read once per request, as the study file reads its own; a large error type
// on this cold path is fine.
#![allow(clippy::result_large_err)]

use serde::Serialize;

use super::{default_speeds, CascadeOptions, Component, DEFAULT_THRESHOLD_M};
use crate::bearing::ContactLaw;
use crate::error::{InputError, Result};
use crate::given::{unknown_option, Given, SetByName, MAX_MODES};
use crate::model::Model;
use crate::post::Window;
use crate::time::Initial;

/// The options of a cascade as the user gives them; `None` leaves the library's default
/// ([`CascadeOptions::new`], [`default_speeds`], [`DEFAULT_THRESHOLD_M`]). Serialised
/// without the options left out.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct CascadeRequest {
    /// Spin speeds, rad/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speeds: Option<Vec<f64>>,
    /// Shortest settling time, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settle: Option<f64>,
    /// Longest settling time, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settle_max: Option<f64>,
    /// Initial state of every run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start: Option<Initial>,
    /// False to compute only the requested speeds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refine: Option<bool>,
    /// Most speeds the refinement adds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refine_budget: Option<usize>,
    /// Smallest spacing of an added speed from its neighbours, Hz.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refine_spacing_hz: Option<f64>,
    /// Time recorded at each speed, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub record: Option<f64>,
    /// Most records averaged at a settled speed (the fewest follow it down to 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_records: Option<usize>,
    /// Averaging stops once the NSV's standard error is within this fraction of it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub average_tolerance: Option<f64>,
    /// Contact law of the roller bearings.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactLaw>,
    /// Fixed-interface modes of the Craig-Bampton reduction; `Some(None)` for the full
    /// model.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reduce: Option<Option<usize>>,
    /// Time step, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step: Option<f64>,
    /// The node whose response is analysed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub node: Option<usize>,
    /// The displacement of the one-sided spectrum.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub component: Option<Component>,
    /// Data window of the spectra.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub window: Option<Window>,
    /// Top of the frequency band, Hz.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_frequency_hz: Option<f64>,
    /// Bins within which a peak counts as synchronous.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance_bins: Option<f64>,
    /// Also the full spectrum of x + i y.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub full: Option<bool>,
    /// NSV amplitude (zero-to-peak) from which a speed counts in the summary, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub threshold: Option<f64>,
}

/// The cascade's own options by name, which [`CascadeRequest::set`] reads beside the
/// [`RUN_SETTINGS`]: the command line's flags with `_` for `-`, and the study file's
/// `refine` and `nsv_threshold`.
pub const CASCADE_OPTIONS: [&str; 13] = [
    "speeds",
    "settle",
    "settle_max",
    "refine",
    "no_refine",
    "refine_budget",
    "refine_spacing",
    "record",
    "max_records",
    "average_tolerance",
    "full",
    "threshold",
    "nsv_threshold",
];

/// The cascade's options that also set a run-up's sweeps ([`crate::runup::RunupRequest`]):
/// how each run is made and measured.
pub const RUN_SETTINGS: [&str; 10] = [
    "start",
    "contact",
    "reduce",
    "full_model",
    "step",
    "node",
    "component",
    "window",
    "max_frequency",
    "tolerance",
];

impl CascadeRequest {
    /// Sets the run setting named `name` (one of [`RUN_SETTINGS`]); any other name is
    /// refused as an option `analysis` does not have, listing `own` and the run settings.
    /// `reduce = 0` and `full_model = true` both ask for the full model.
    ///
    /// # Errors
    /// [`InputError`] naming `name` for a value it does not read, or an unknown name.
    pub fn set_run_setting(
        &mut self,
        name: &str,
        value: &Given,
        own: &[&str],
        analysis: &str,
    ) -> std::result::Result<(), InputError> {
        let v = value;
        match name {
            "start" => self.start = Some(v.choice(name)?),
            "contact" => self.contact = Some(v.choice(name)?),
            // 0 modes: the full model (the study file's way to ask for it).
            "reduce" => {
                let modes = v.whole(name, 0, MAX_MODES)?;
                self.reduce = Some((modes > 0).then_some(modes));
            }
            "full_model" => {
                if v.flag(name)? {
                    self.reduce = Some(None);
                }
            }
            "step" => self.step = Some(v.time(name)?),
            "node" => self.node = Some(v.whole(name, 0, usize::MAX >> 1)?),
            "component" => self.component = Some(v.choice(name)?),
            "window" => self.window = Some(v.choice(name)?),
            "max_frequency" => self.max_frequency_hz = Some(v.frequency_hz(name)?),
            "tolerance" => self.tolerance_bins = Some(v.number(name)?),
            _ => {
                let known: Vec<&str> = own.iter().chain(&RUN_SETTINGS).copied().collect();
                return Err(unknown_option(name, &known, analysis));
            }
        }
        Ok(())
    }

    /// The summary's threshold, m: the one given, else [`DEFAULT_THRESHOLD_M`].
    pub fn threshold_m(&self) -> f64 {
        self.threshold.unwrap_or(DEFAULT_THRESHOLD_M)
    }

    /// The library's options for `model`: each option given replaces its default.
    ///
    /// # Errors
    /// The errors of [`default_speeds`] when no speeds are given. The values themselves are
    /// checked where the cascade starts ([`super::cascade`]).
    pub fn options(&self, model: &Model) -> Result<CascadeOptions> {
        let speeds = match &self.speeds {
            Some(w) => w.clone(),
            None => default_speeds(model)?,
        };
        let mut o = CascadeOptions::new(model, speeds);
        let set = |to: &mut f64, given: Option<f64>| {
            if let Some(x) = given {
                *to = x;
            }
        };
        set(&mut o.settle, self.settle);
        set(&mut o.settle_max, self.settle_max);
        set(&mut o.refine.min_spacing_hz, self.refine_spacing_hz);
        set(&mut o.record, self.record);
        set(&mut o.averaging.relative_error, self.average_tolerance);
        set(&mut o.tolerance_bins, self.tolerance_bins);
        o.initial = self.start.unwrap_or(o.initial);
        o.refine.enabled = self.refine.unwrap_or(o.refine.enabled);
        o.refine.max_added = self.refine_budget.unwrap_or(o.refine.max_added);
        if let Some(n) = self.max_records {
            o.averaging.max_records = n;
            // Fewer records asked for than the least averaged: that many, at least one.
            o.averaging.min_records = o.averaging.min_records.min(n.max(1));
        }
        o.law = self.contact.unwrap_or(o.law);
        o.reduction = self.reduce.unwrap_or(o.reduction);
        o.step = self.step.or(o.step);
        o.node = self.node.unwrap_or(o.node);
        o.component = self.component.unwrap_or(o.component);
        o.window = self.window.unwrap_or(o.window);
        o.max_frequency_hz = self.max_frequency_hz.or(o.max_frequency_hz);
        o.full = self.full.unwrap_or(o.full);
        Ok(o)
    }
}

impl SetByName for CascadeRequest {
    /// Sets the option named `name` (one of [`CASCADE_OPTIONS`] or [`RUN_SETTINGS`]) to
    /// `value`, read as that option reads: times and frequencies with a unit or SI, names
    /// of the enums.
    ///
    /// # Errors
    /// [`InputError`] naming `name` for a value it does not read, or an unknown name.
    fn set(&mut self, name: &str, value: &Given) -> std::result::Result<(), InputError> {
        let v = value;
        match name {
            "speeds" => self.speeds = Some(v.speeds(name)?),
            "settle" => self.settle = Some(v.time(name)?),
            "settle_max" => self.settle_max = Some(v.time(name)?),
            "refine" => self.refine = Some(v.flag(name)?),
            "no_refine" => self.refine = Some(!v.flag(name)?),
            "refine_budget" => self.refine_budget = Some(v.whole(name, 0, usize::MAX >> 1)?),
            "refine_spacing" => self.refine_spacing_hz = Some(v.frequency_hz(name)?),
            "record" => self.record = Some(v.time(name)?),
            "max_records" => self.max_records = Some(v.whole(name, 1, usize::MAX >> 1)?),
            "average_tolerance" => self.average_tolerance = Some(v.number(name)?),
            "full" => self.full = Some(v.flag(name)?),
            "threshold" | "nsv_threshold" => self.threshold = Some(v.length(name)?),
            _ => return self.set_run_setting(name, v, &CASCADE_OPTIONS, "cascade"),
        }
        Ok(())
    }
}
