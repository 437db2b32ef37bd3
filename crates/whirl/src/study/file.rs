//! The study file as written (TOML), before validation. The reference for users is
//! `docs/study-file.md`.

use serde::Deserialize;
use toml::Spanned;

/// The whole study file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudyFile {
    /// The model file, relative to the study file's folder.
    pub model: Spanned<String>,
    /// A title for plots and summaries.
    pub title: Option<String>,
    /// Cascade settings shared by every point (see `docs/study-file.md`).
    pub cascade: Option<Spanned<toml::Table>>,
    /// Values set at every point of every sweep, path = value, before each sweep's own
    /// `set` (e.g. the damping of a whole study: `set = { "damping.scale" = 2.5 }`).
    pub set: Option<Spanned<toml::Table>>,
    /// The NSV statistic the fits and the ranking use: `"mean"` (default), `"median"`,
    /// `"p90"` or `"largest"`.
    pub metric: Option<Spanned<String>>,
    /// The sweeps.
    #[serde(default)]
    pub sweep: Vec<Spanned<SweepFile>>,
}

/// `[[sweep]]`: one parameter over a list of values.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    /// A name for plots and tables (default: the parameter path).
    pub name: Option<String>,
    /// The parameter's path in the model file (`roller_bearing[*].clearance`) or in the
    /// cascade settings (`cascade.contact`).
    pub parameter: Spanned<String>,
    /// The values, written as in the model file (`"20 um"`, `16`, `"lagrange"`).
    pub values: Spanned<Vec<Spanned<toml::Value>>>,
    /// Other values set at every point of this sweep, path = value.
    pub set: Option<Spanned<toml::Table>>,
    /// Fit of the largest NSV versus the parameter: `"linear"`, `"quadratic"`, `"cubic"`.
    pub fit: Option<Spanned<String>>,
}
