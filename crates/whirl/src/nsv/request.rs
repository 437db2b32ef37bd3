//! A cascade as `whirl cascade` and `whirl.cascade` ask for it, in the terms of their
//! options; [`CascadeRequest::options`] turns it into the library's [`CascadeOptions`], so
//! the command line and the Python package map their options in one place.

use super::{default_speeds, CascadeOptions, Component};
use crate::bearing::ContactLaw;
use crate::error::Result;
use crate::model::Model;
use crate::post::Window;
use crate::time::Initial;

/// The options of a cascade as the user gives them; `None` leaves the library's default
/// ([`CascadeOptions::new`], [`default_speeds`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CascadeRequest {
    /// Spin speeds, rad/s.
    pub speeds: Option<Vec<f64>>,
    /// Shortest settling time, s.
    pub settle: Option<f64>,
    /// Longest settling time, s.
    pub settle_max: Option<f64>,
    /// Initial state of every run.
    pub start: Option<Initial>,
    /// False to compute only the requested speeds.
    pub refine: Option<bool>,
    /// Most speeds the refinement adds.
    pub refine_budget: Option<usize>,
    /// Smallest spacing of an added speed from its neighbours, Hz.
    pub refine_spacing_hz: Option<f64>,
    /// Time recorded at each speed, s.
    pub record: Option<f64>,
    /// Most records averaged at a settled speed (the fewest follow it down to 1).
    pub max_records: Option<usize>,
    /// Averaging stops once the NSV's standard error is within this fraction of it.
    pub average_tolerance: Option<f64>,
    /// Contact law of the roller bearings.
    pub contact: Option<ContactLaw>,
    /// Fixed-interface modes of the Craig-Bampton reduction; `Some(None)` for the full
    /// model.
    pub reduce: Option<Option<usize>>,
    /// Time step, s.
    pub step: Option<f64>,
    /// The node whose response is analysed.
    pub node: Option<usize>,
    /// The displacement of the one-sided spectrum.
    pub component: Option<Component>,
    /// Data window of the spectra.
    pub window: Option<Window>,
    /// Top of the frequency band, Hz.
    pub max_frequency_hz: Option<f64>,
    /// Bins within which a peak counts as synchronous.
    pub tolerance_bins: Option<f64>,
    /// Also the full spectrum of x + i y.
    pub full: Option<bool>,
}

impl CascadeRequest {
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
