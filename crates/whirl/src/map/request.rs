//! What a map computes: one model parameter, addressed as a study file addresses it
//! ([`ParameterPath`]), set to each of a list of values by editing the model file's text, each
//! edited model validated by the model's own validation, and one harmonic-balance sweep with
//! stability per value over the same speed range.

// Validation runs once per map; a large error type on this cold path is fine.
#![allow(clippy::result_large_err)]

use std::path::PathBuf;

use serde::Serialize;
use toml_edit::DocumentMut;

use crate::error::{Error, InputError, Result};
use crate::given::{unknown_option, Given, SetByName};
use crate::hbm::{SweepOptions, SweepSettings};
use crate::model::Model;
use crate::study::path::{ParameterPath, PATH_HELP};
use crate::study::{invalid, plain_text, si_value, to_edit_value};

use super::check::DEFAULT_CHECK_LEVEL_M;

/// The parameter a map varies when a request names none: the internal radial clearance of
/// every roller bearing, the parameter that sets where non-synchronous vibration begins.
pub const DEFAULT_PARAMETER: &str = "roller_bearing[*].clearance";

/// The most values a map may have: each is a whole sweep with stability (about 10 s of CPU
/// on the reference rotor).
pub const MAX_VALUES: usize = 200;

/// A map of the synchronous orbit's stability over speed and one model parameter.
#[derive(Debug, Clone, Default)]
pub struct MapRequest {
    /// The model file's text.
    pub model_text: String,
    /// The model file, to name it in messages.
    pub model_file: Option<PathBuf>,
    /// The parameter's path in the model file; `None` for [`DEFAULT_PARAMETER`].
    pub parameter: Option<String>,
    /// The values, each written as in the model file (`"20 um"`, `16`, `2.5e-5`); a text
    /// that is not a TOML value (`20um`) is taken as a string.
    pub values: Vec<String>,
    /// First speed of every sweep, rad/s.
    pub from: f64,
    /// Last speed of every sweep, rad/s.
    pub to: f64,
    /// The sweeps' discretisation and bearing model. The stability is always computed: it
    /// is what the map reports.
    pub settings: SweepSettings,
    /// The design query's speed, rad/s: which values keep the orbit free of unstable bands
    /// below it ([`super::MapReport::clear_below`]); `None` for no query.
    pub clear_below: Option<f64>,
    /// Values (among `values`, as written there) at which the default cascade is run and
    /// compared with the map ([`super::check`]); empty for no check.
    pub check: Vec<String>,
    /// The check's NSV level, m; `None` for [`super::check::DEFAULT_CHECK_LEVEL_M`].
    pub check_level_m: Option<f64>,
    /// Run the default cascade of the largest value clear below `clear_below`, up to that
    /// speed, and report whether its NSV stays below the check's level.
    pub confirm: bool,
}

/// One value of a map: its model and how it was written.
#[derive(Debug, Clone, Serialize)]
pub struct MapValue {
    /// As given, a string without its quotes (`20 um`, `16`).
    pub text: String,
    /// In SI, for numbers and quantities with a unit; `None` for words.
    pub si: Option<f64>,
    /// The validated model with the value set.
    #[serde(skip)]
    pub model: Model,
}

impl MapRequest {
    /// The parameter's path, given or [`DEFAULT_PARAMETER`].
    pub fn parameter(&self) -> &str {
        self.parameter.as_deref().unwrap_or(DEFAULT_PARAMETER)
    }

    /// The options of every sweep: the settings with the stability on.
    pub fn sweep_options(&self) -> SweepOptions {
        let mut settings = self.settings.clone();
        settings.stability = Some(true);
        settings.options(self.from, self.to)
    }

    /// Every value's model, edited from the model file's text and validated.
    ///
    /// # Errors
    /// [`Error::Input`] naming `parameter` for a malformed path or one the model file does
    /// not have, `values` for an empty or too long list, `values[j]` with the value for a
    /// model the value makes invalid, `clear_below` for a speed outside the range;
    /// [`Error::InvalidOption`] for a speed range that does not rise.
    pub fn values(&self) -> Result<Vec<MapValue>> {
        self.check_speeds()?;
        let path = ParameterPath::parse(self.parameter())
            .map_err(|why| InputError::field("parameter", why).help(PATH_HELP))?;
        if self.values.is_empty() || self.values.len() > MAX_VALUES {
            return Err(InputError::field(
                "values",
                format!(
                    "must hold 1 to {MAX_VALUES} values, got {}",
                    self.values.len()
                ),
            )
            .help("e.g. values 10um,20um,60um,120um")
            .into());
        }
        let base = self
            .model_text
            .parse::<DocumentMut>()
            .map_err(|e| InputError::field("model", format!("cannot edit the model file: {e}")))?;
        // The base model must be valid on its own; its errors point into its own file.
        Model::from_toml_str(&self.model_text, self.model_file.clone())?;
        let values: Vec<MapValue> = self
            .values
            .iter()
            .enumerate()
            .map(|(j, text)| edited(&base, &path, j, text))
            .collect::<Result<_>>()?;
        self.check_checked(&values)?;
        Ok(values)
    }

    /// The check's level, given or the default.
    pub fn check_level(&self) -> f64 {
        self.check_level_m.unwrap_or(DEFAULT_CHECK_LEVEL_M)
    }

    /// Every value to check is one of the map's, and the level is a positive amplitude.
    fn check_checked(&self, values: &[MapValue]) -> Result<()> {
        for (j, text) in self.check.iter().enumerate() {
            let wanted = plain_text(&toml_value(text));
            if !values.iter().any(|v| v.text == wanted) {
                return Err(InputError::field(
                    format!("check[{j}]"),
                    format!("`{wanted}` is not one of the map's values"),
                )
                .help("check values the map sweeps, written as in `values`")
                .into());
            }
        }
        if self.confirm && self.clear_below.is_none() {
            return Err(InputError::field(
                "confirm",
                "confirms the design query's answer, and no query was asked",
            )
            .help("give clear_below (e.g. 600 Hz) with confirm")
            .into());
        }
        let level = self.check_level();
        if !(level.is_finite() && level > 0.0) {
            return Err(InputError::field(
                "check_level",
                format!("must be a positive amplitude, got {level} m"),
            )
            .help("e.g. 10 um, the cascade's upper onset level")
            .into());
        }
        Ok(())
    }

    fn check_speeds(&self) -> Result<()> {
        if !(self.from.is_finite() && self.to.is_finite() && self.from > 0.0 && self.to > self.from)
        {
            return Err(Error::InvalidOption(format!(
                "a map needs a rising range of positive speeds, got {} to {} rad/s",
                self.from, self.to
            )));
        }
        match self.clear_below {
            Some(w) if !(w > self.from && w <= self.to) => Err(InputError::field(
                "clear_below",
                format!(
                    "{w} rad/s is outside the swept range, {} to {} rad/s",
                    self.from, self.to
                ),
            )
            .help("ask for a speed inside the range the sweeps cover")
            .into()),
            _ => Ok(()),
        }
    }
}

/// The map's own options that [`MapRequest::set`] knows (the sweeps' are
/// [`crate::hbm::HbmRequest`]'s).
const MAP_OPTIONS: [&str; 6] = [
    "parameter",
    "values",
    "clear_below",
    "check",
    "check_level",
    "confirm",
];

impl SetByName for MapRequest {
    /// Sets the map's option `name`: the parameter's path, its values (each as the model
    /// file writes it), the design query's speed, the values to check and the check's level.
    fn set(&mut self, name: &str, value: &Given) -> std::result::Result<(), InputError> {
        match name {
            "parameter" => self.parameter = Some(written(value)),
            "values" => self.values = value.items().iter().map(written).collect(),
            "clear_below" => self.clear_below = Some(value.speed(name)?),
            "check" => self.check = value.items().iter().map(written).collect(),
            "check_level" => self.check_level_m = Some(value.length(name)?),
            "confirm" => self.confirm = value.flag(name)?,
            _ => return Err(unknown_option(name, &MAP_OPTIONS, "map")),
        }
        Ok(())
    }
}

/// A value as written: text as given, a number as Rust writes it (which TOML reads back).
fn written(value: &Given) -> String {
    match value {
        Given::Text(t) => t.trim().to_string(),
        Given::Whole(n) => n.to_string(),
        Given::Number(x) => x.to_string(),
        Given::Flag(b) => b.to_string(),
        Given::List(items) => items.iter().map(written).collect::<Vec<_>>().join(","),
    }
}

/// The model of value `j`, written `text`: the path set to it in `base` and validated.
fn edited(base: &DocumentMut, path: &ParameterPath, j: usize, text: &str) -> Result<MapValue> {
    let value = toml_value(text);
    let mut document = base.clone();
    path.set(document.as_table_mut(), &to_edit_value(&value))
        .map_err(|why| {
            InputError::field("parameter", format!("`{path}`: {why}")).help(PATH_HELP)
        })?;
    let edit = format!("`{path}` = {}", plain_text(&value));
    let model = Model::from_toml_str(&document.to_string(), None).map_err(|e| {
        let last = path.segments.last().map_or("", |s| s.key.as_str());
        if e.to_string().contains(&format!("unknown field `{last}`")) {
            // The path added a key the model does not know: the path is wrong, not the value.
            InputError::field(
                "parameter",
                format!("`{path}`: the model file has no `{last}` there ({e})"),
            )
            .help(PATH_HELP)
        } else {
            invalid(&format!("values[{j}]"), &edit, "model", e)
        }
    })?;
    Ok(MapValue {
        text: plain_text(&value),
        si: si_value(&value),
        model,
    })
}

/// A value as TOML: a number, a boolean or a quoted string as written, anything else as a
/// string (`20um`, `20 um`).
pub(super) fn toml_value(text: &str) -> toml::Value {
    let text = text.trim();
    toml::from_str::<toml::Table>(&format!("v = {text}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(text.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_read_as_a_model_file_writes_them() {
        assert_eq!(toml_value("16"), toml::Value::Integer(16));
        assert_eq!(toml_value("2.5e-5"), toml::Value::Float(2.5e-5));
        assert_eq!(toml_value("20um"), toml::Value::String("20um".into()));
        assert_eq!(toml_value("\"20 um\""), toml::Value::String("20 um".into()));
    }
}
