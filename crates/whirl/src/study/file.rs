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

/// `[cascade]`, after the sweeps' edits: every field optional.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CascadeFile {
    /// Speeds `start:stop:count`, e.g. `"1:750Hz:150"`.
    pub speeds: Option<String>,
    /// Settling time discarded at each speed, e.g. `"0.5 s"`.
    pub settle: Option<toml::Value>,
    /// Recorded time analysed at each speed, e.g. `"0.5 s"`.
    pub record: Option<toml::Value>,
    /// Bearing contact law: `"hertz"`, `"lagrange"`, `"forcing"` or `"linear"`.
    pub contact: Option<String>,
    /// Central-difference time step, e.g. `"5 us"` (default: 0.9 of the stability limit).
    pub step: Option<toml::Value>,
    /// Craig-Bampton modes; 0 for the full model.
    pub reduce: Option<i64>,
    /// The node whose response is analysed (default: the first disk's).
    pub node: Option<i64>,
    /// Its displacement analysed: `"uy"` (default) or `"ux"`.
    pub component: Option<String>,
    /// Top of the analysed band, e.g. `"1000 Hz"`.
    pub max_frequency: Option<toml::Value>,
    /// NSV below this does not count for the onset speed, e.g. `"1 um"`.
    pub nsv_threshold: Option<toml::Value>,
    /// Longest settling time, e.g. `"4 s"` (each speed settles until its start has died).
    pub settle_max: Option<toml::Value>,
    /// Initial state: `"static"` (default) or `"rest"`.
    pub start: Option<String>,
    /// Whether the speed grid is refined (default true).
    pub refine: Option<bool>,
}
