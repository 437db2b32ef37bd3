//! Sensitivity studies of non-synchronous vibration (thesis ch. 5, docs/theory.md section 8):
//! sweeps of model parameters, each point a cascade.
//!
//! A study file names a model file, the cascade settings shared by every point, and a list
//! of sweeps; a sweep varies one parameter, addressed by its path in the model file
//! ([`path`]), over a list of values written as in the model file. Each value of each sweep
//! is a point: the model file's text with the sweep's edits applied, validated by the
//! model's own validation. Points with the same input (the base point of several sweeps)
//! are computed once.
//!
//! From the points' NSV summaries a study derives the largest NSV versus a parameter with a
//! least-squares polynomial ([`fit`], thesis eq. 5.1 and table 5.1) and a ranking of the
//! sweeps by their effect on the largest NSV ([`ranking`]). Finished points are kept in a
//! checkpoint folder ([`store`]) so that an interrupted study continues.
//!
//! The file format is described in `docs/study-file.md`.

// Validation runs once per study file; a large error type on this cold path is fine.
#![allow(clippy::result_large_err)]

pub mod file;
pub mod fit;
pub mod path;
pub mod point;
pub mod ranking;
pub mod report;
pub mod results;
pub mod settings;
pub mod store;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use serde::Serialize;
use toml::Spanned;
use toml_edit::DocumentMut;

use crate::error::{Error, InputError, Result};
use crate::model::Model;
use crate::nsv::CascadeRequest;
use crate::units::{parse_quantity, Dimension};
use file::{StudyFile, SweepFile};
use path::{ParameterPath, PATH_HELP};
use results::Metric;
use settings::cascade_settings;

/// The most points a study may have: each is a whole cascade.
pub const MAX_POINTS: usize = 1000;

/// A validated study.
#[derive(Debug, Clone)]
pub struct Study {
    /// Title for plots and summaries.
    pub title: String,
    /// The model file, as resolved from the study file's folder.
    pub model_file: PathBuf,
    /// Fingerprint of what the study computes: its sweeps and its points' inputs.
    pub fingerprint: String,
    /// The sweeps, in file order.
    pub sweeps: Vec<Sweep>,
    /// The distinct points; sweeps refer to them by index.
    pub points: Vec<Point>,
    /// The NSV statistic the fits and the ranking use.
    pub metric: Metric,
}

/// One sweep of a study.
#[derive(Debug, Clone, Serialize)]
pub struct Sweep {
    /// Name for plots and tables.
    pub name: String,
    /// The parameter's path.
    pub parameter: String,
    /// The values as written, each with its SI number when it has one.
    pub values: Vec<SweepValue>,
    /// Degree of the polynomial fitted to the largest NSV versus the values, if asked for.
    pub fit_degree: Option<usize>,
    /// The point of each value: an index into [`Study::points`].
    pub points: Vec<usize>,
}

/// A value of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepValue {
    /// As written in the study file, a string without its quotes (`20 um`, `16`).
    pub text: String,
    /// In SI, for numbers and quantities with a unit; `None` for words (`"lagrange"`).
    pub si: Option<f64>,
}

/// One point: a model and cascade settings.
#[derive(Debug, Clone)]
pub struct Point {
    /// Fingerprint of its validated model and cascade settings (and whirl's build, [`crate::BUILD_ID`]):
    /// names its file in the checkpoint folder.
    pub key: String,
    /// Fingerprint of its cascade alone: the key without the NSV threshold, which only
    /// reads the cascade. Points that differ only in their threshold share one cascade,
    /// computed once ([`Point::partial_dir`]).
    pub cascade_key: String,
    /// What differs from the base model and settings, `path = value`, in order.
    pub changes: Vec<(String, String)>,
    /// The validated model.
    pub model: Model,
    /// The model file's text after the edits.
    pub model_text: String,
    /// The cascade settings.
    pub cascade: CascadeRequest,
}

impl Point {
    /// The folder under a study's checkpoint folder `store_dir` where this point's cascade
    /// keeps its finished speeds while the study runs: one per cascade, so a second point
    /// with the same cascade (another threshold) resumes it whole instead of computing it
    /// again. [`store::remove_partial`] empties them once every point is finished.
    pub fn partial_dir(&self, store_dir: &Path) -> PathBuf {
        store_dir.join(store::PARTIAL).join(&self.cascade_key)
    }

    /// A short label: the changes, or "base" when there are none.
    pub fn label(&self) -> String {
        if self.changes.is_empty() {
            return "base".into();
        }
        let short = |p: &str| p.rsplit('.').next().unwrap_or(p).to_string();
        self.changes
            .iter()
            .map(|(p, v)| format!("{} = {}", short(p), v.trim_matches('"')))
            .collect::<Vec<_>>()
            .join("; ")
    }
}

impl Study {
    /// Reads a study file and the model file it names, and validates every point.
    ///
    /// # Errors
    /// [`Error::Io`] when a file cannot be read; the errors of [`Study::from_toml_str`].
    pub fn from_file(path: &Path) -> Result<Study> {
        let text = crate::model::read_input(path).map_err(|source| Error::Io {
            action: "read the study file",
            path: path.to_path_buf(),
            source,
        })?;
        Study::from_toml_str(&text, path)
    }

    /// Validates a study given as TOML text; `path` names it in messages, and the model
    /// file is found relative to its folder.
    ///
    /// # Errors
    /// [`Error::Input`] for a study file or a model file (as changed at each point) that does
    /// not validate, located in its file; [`Error::Io`] when the model file cannot be read.
    pub fn from_toml_str(text: &str, path: &Path) -> Result<Study> {
        let located = |e: InputError| Error::from(e.locate(Some(path.to_path_buf()), text));
        let raw: StudyFile = toml::from_str(text).map_err(|e| {
            let mut err = InputError::field("study", e.message().to_string());
            err.field = None;
            err.span = e.span();
            if err.message.contains("unknown field") {
                err.help = Some("see docs/study-file.md for the fields of a study file".into());
            }
            located(err)
        })?;
        let model_file = path
            .parent()
            .unwrap_or(Path::new(""))
            .join(raw.model.get_ref());
        let model_text = crate::model::read_input(&model_file).map_err(|e| {
            located(
                InputError::field(
                    "model",
                    format!("cannot read the model file `{}`: {e}", model_file.display()),
                )
                .at(raw.model.span())
                .help("the path is relative to the study file's folder"),
            )
        })?;
        // The base model must be valid on its own; its errors point into its own file.
        Model::from_toml_str(&model_text, Some(model_file.clone()))?;
        let base = Base::new(&raw, &model_text).map_err(located)?;
        let mut expander = Expander::default();
        let mut sweeps = Vec::new();
        for (i, sweep) in raw.sweep.iter().enumerate() {
            sweeps.push(expander.sweep(i, sweep, &base).map_err(located)?);
        }
        if sweeps.is_empty() {
            return Err(located(
                InputError::field("sweep", "the study has no sweep").help(
                    "add one, e.g. [[sweep]] parameter = \"roller_bearing[*].clearance\" \
                     values = [\"20 um\", \"60 um\", \"120 um\"]",
                ),
            ));
        }
        // What the study computes and concludes, not how its files are written: a comment
        // or a unit written differently changes nothing.
        let metric = metric(&raw).map_err(located)?;
        let mut parts = vec![serde_json::to_string(&sweeps).unwrap_or_default()];
        if metric != Metric::default() {
            parts.push(metric.name().to_string());
        }
        parts.extend(expander.points.iter().map(|p| p.key.clone()));
        let parts: Vec<&str> = parts.iter().map(String::as_str).collect();
        Ok(Study {
            title: raw.title.unwrap_or_else(|| "study".into()),
            fingerprint: store::fingerprint(&parts),
            model_file,
            sweeps,
            points: expander.points,
            metric,
        })
    }
}

/// The study's `metric`, by its name.
fn metric(raw: &StudyFile) -> std::result::Result<Metric, InputError> {
    let Some(name) = &raw.metric else {
        return Ok(Metric::default());
    };
    Metric::ALL
        .into_iter()
        .find(|m| m.name() == name.get_ref())
        .ok_or_else(|| {
            InputError::field(
                "metric",
                format!("`{}` is not a metric whirl knows", name.get_ref()),
            )
            .at(name.span())
            .help("use \"mean\" (default), \"median\", \"p90\" or \"largest\"")
        })
}

/// The base model and cascade settings as editable documents.
struct Base {
    model: DocumentMut,
    cascade: DocumentMut,
    /// Where `[cascade]` is in the study file, for its errors.
    cascade_span: std::ops::Range<usize>,
    /// The study's own `set`, applied to every point before the sweep's.
    set: Vec<Edit>,
}

impl Base {
    fn new(raw: &StudyFile, model_text: &str) -> std::result::Result<Base, InputError> {
        let model = model_text
            .parse::<DocumentMut>()
            .map_err(|e| InputError::field("model", format!("cannot edit the model file: {e}")))?;
        let (table, cascade_span) = raw
            .cascade
            .as_ref()
            .map_or((toml::Table::new(), 0..0), |c| {
                (c.get_ref().clone(), c.span())
            });
        cascade_settings(&table).map_err(|e| e.at(cascade_span.clone()))?;
        let cascade = table
            .to_string()
            .parse::<DocumentMut>()
            .map_err(|e| InputError::field("cascade", e.to_string()))?;
        let set = set_edits("set", raw.set.as_ref(), 0..0)?;
        check_study_set(&set, &model)?;
        Ok(Base {
            model,
            cascade,
            cascade_span,
            set,
        })
    }
}

/// Builds the points of each sweep, computing each distinct input once.
#[derive(Default)]
struct Expander {
    points: Vec<Point>,
    by_key: HashMap<String, usize>,
}

/// One edit of a point: a path, its value, and where the value is in the study file.
struct Edit {
    path: ParameterPath,
    value: toml_edit::Value,
    text: String,
    field: String,
    span: std::ops::Range<usize>,
}

impl Expander {
    fn sweep(
        &mut self,
        i: usize,
        sweep: &Spanned<SweepFile>,
        base: &Base,
    ) -> std::result::Result<Sweep, InputError> {
        let s = sweep.get_ref();
        let field = |f: &str| format!("sweep[{i}].{f}");
        let parameter = ParameterPath::parse(s.parameter.get_ref()).map_err(|why| {
            InputError::field(field("parameter"), why)
                .at(s.parameter.span())
                .help(PATH_HELP)
        })?;
        let values = s.values.get_ref();
        if values.is_empty() || values.len() > 200 {
            return Err(InputError::field(
                field("values"),
                format!("must hold 1 to 200 values, got {}", values.len()),
            )
            .at(s.values.span())
            .help("e.g. values = [\"20 um\", \"60 um\", \"120 um\"]"));
        }
        let fixed = set_edits(&field("set"), s.set.as_ref(), sweep.span())?;
        let fit_degree = fit_degree(i, s)?;
        let mut swept = Vec::new();
        let mut points = Vec::new();
        for (j, v) in values.iter().enumerate() {
            let edit = Edit {
                path: parameter.clone(),
                value: to_edit_value(v.get_ref()),
                text: v.get_ref().to_string(),
                field: format!("sweep[{i}].values[{j}]"),
                span: v.span(),
            };
            swept.push(SweepValue {
                text: plain_text(v.get_ref()),
                si: si_value(v.get_ref()),
            });
            let edits: Vec<&Edit> = base
                .set
                .iter()
                .chain(&fixed)
                .chain(std::iter::once(&edit))
                .collect();
            points.push(self.point(&edits, base)?);
        }
        if fit_degree.is_some() {
            if let Some(j) = swept.iter().position(|v| v.si.is_none()) {
                return Err(InputError::field(
                    field("fit"),
                    format!(
                        "the value {} is not a number, so nothing can be fitted",
                        swept[j].text
                    ),
                )
                .at(s.fit.as_ref().map_or(s.values.span(), |f| f.span()))
                .help("fit only sweeps of numbers or quantities; remove `fit` from this sweep"));
            }
        }
        Ok(Sweep {
            name: s.name.clone().unwrap_or_else(|| parameter.to_string()),
            parameter: parameter.to_string(),
            values: swept,
            fit_degree,
            points,
        })
    }

    /// The point made by `edits` on the base: validated, and shared when seen before.
    fn point(&mut self, edits: &[&Edit], base: &Base) -> std::result::Result<usize, InputError> {
        let (model, cascade) = edited(edits, &base.model, &base.cascade)?;
        let last = edits.last().map(|e| (e.field.clone(), e.span.clone()));
        let (field, span) = last.unwrap_or_else(|| ("cascade".into(), base.cascade_span.clone()));
        let model_text = model.to_string();
        let valid = Model::from_toml_str(&model_text, None)
            .map_err(|e| invalid(&field, &describe(edits), "model", e).at(span.clone()))?;
        let table: toml::Table = toml::from_str(&cascade.to_string())
            .map_err(|e| InputError::field(&field, e.message().to_string()).at(span.clone()))?;
        let settings = cascade_settings(&table).map_err(|e| {
            invalid(&field, &describe(edits), "cascade", Error::from(e)).at(span.clone())
        })?;
        // The key is that of the validated model and settings, so that "60 um" and 6e-5 are
        // one point.
        let model_json = serde_json::to_string(&valid).unwrap_or_default();
        let cascade_json = serde_json::to_string(&settings).unwrap_or_default();
        let key = store::fingerprint(&[crate::BUILD_ID, &model_json, &cascade_json]);
        let unread = CascadeRequest {
            threshold: None,
            ..settings.clone()
        };
        let unread_json = serde_json::to_string(&unread).unwrap_or_default();
        let cascade_key = store::fingerprint(&[crate::BUILD_ID, &model_json, &unread_json]);
        if let Some(&k) = self.by_key.get(&key) {
            return Ok(k);
        }
        if self.points.len() == MAX_POINTS {
            return Err(InputError::field(
                &field,
                format!("the study has more than {MAX_POINTS} distinct points"),
            )
            .at(span)
            .help("split it into several studies"));
        }
        self.points.push(Point {
            key: key.clone(),
            cascade_key,
            changes: edits
                .iter()
                .map(|e| (e.path.to_string(), e.text.clone()))
                .collect(),
            model: valid,
            model_text,
            cascade: settings,
        });
        self.by_key.insert(key, self.points.len() - 1);
        Ok(self.points.len() - 1)
    }
}

/// A model or settings made by `edits` and refused by their own validation, reported at
/// `field` (a study file's value, a map's value) with the validation's own message and
/// help.
pub(crate) fn invalid(field: &str, edits: &str, what: &str, e: Error) -> InputError {
    let (message, help) = match e {
        Error::Input(inner) => {
            let place = inner.field.map(|f| format!("`{f}`: ")).unwrap_or_default();
            (format!("{place}{}", inner.message), inner.help)
        }
        other => (other.to_string(), None),
    };
    let mut err = InputError::field(field, format!("{edits} makes an invalid {what}: {message}"));
    err.help = help;
    err
}

/// The `set = { path = value }` edits of a sweep or of the whole study; `field` names it in
/// errors, `outer` is where to point when the table's own place is unknown.
fn set_edits(
    field: &str,
    set: Option<&Spanned<toml::Table>>,
    outer: std::ops::Range<usize>,
) -> std::result::Result<Vec<Edit>, InputError> {
    let Some(set) = set else {
        return Ok(Vec::new());
    };
    let mut edits = Vec::new();
    for (key, value) in set.get_ref() {
        let path = ParameterPath::parse(key)
            .map_err(|why| InputError::field(field, why).at(set.span()).help(PATH_HELP))?;
        edits.push(Edit {
            path,
            value: to_edit_value(value),
            text: value.to_string(),
            field: field.to_string(),
            span: if set.span().is_empty() {
                outer.clone()
            } else {
                set.span()
            },
        });
    }
    Ok(edits)
}

/// The model and cascade documents with `edits` applied in order.
fn edited(
    edits: &[&Edit],
    model: &DocumentMut,
    cascade: &DocumentMut,
) -> std::result::Result<(DocumentMut, DocumentMut), InputError> {
    let (mut model, mut cascade) = (model.clone(), cascade.clone());
    for e in edits {
        let fail = |why: String| {
            InputError::field(&e.field, format!("`{}`: {why}", e.path))
                .at(e.span.clone())
                .help(PATH_HELP)
        };
        let (doc, path) = if e.path.root() == "cascade" {
            let mut inner = e.path.clone();
            inner.segments.remove(0);
            if inner.segments.is_empty() {
                return Err(fail(
                    "name a cascade setting, e.g. `cascade.contact`".into(),
                ));
            }
            (&mut cascade, inner)
        } else {
            (&mut model, e.path.clone())
        };
        path.set(doc.as_table_mut(), &e.value).map_err(fail)?;
    }
    Ok((model, cascade))
}

/// The study-wide `set` on the model alone: a misspelt path there is reported at `set`, not
/// at the first sweep value it would otherwise meet.
fn check_study_set(set: &[Edit], model: &DocumentMut) -> std::result::Result<(), InputError> {
    let model_edits: Vec<&Edit> = set.iter().filter(|e| e.path.root() != "cascade").collect();
    let Some(first) = model_edits.first() else {
        return Ok(());
    };
    let (edited_model, _) = edited(&model_edits, model, &DocumentMut::new())?;
    Model::from_toml_str(&edited_model.to_string(), None)
        .map(|_| ())
        .map_err(|e| invalid("set", &describe(&model_edits), "model", e).at(first.span.clone()))
}

/// The edits as an error names them: `path` = value, ...
fn describe(edits: &[&Edit]) -> String {
    edits
        .iter()
        .map(|e| format!("`{}` = {}", e.path, e.text))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `fit = "cubic"` as a polynomial degree.
fn fit_degree(i: usize, s: &SweepFile) -> std::result::Result<Option<usize>, InputError> {
    let Some(fit) = &s.fit else {
        return Ok(None);
    };
    let degree = match fit.get_ref().as_str() {
        "linear" => 1,
        "quadratic" => 2,
        "cubic" => 3,
        other => {
            return Err(InputError::field(
                format!("sweep[{i}].fit"),
                format!("`{other}` is not a fit whirl knows"),
            )
            .at(fit.span())
            .help("use \"linear\", \"quadratic\" or \"cubic\" (thesis eq. 5.1 is cubic)"))
        }
    };
    if s.values.get_ref().len() <= degree {
        return Err(InputError::field(
            format!("sweep[{i}].fit"),
            format!(
                "a {} fit needs at least {} values, the sweep has {}",
                fit.get_ref(),
                degree + 1,
                s.values.get_ref().len()
            ),
        )
        .at(fit.span())
        .help("add values to the sweep, or fit a lower degree"));
    }
    Ok(Some(degree))
}

/// A TOML value of the study file as a value to put into a document.
pub(crate) fn to_edit_value(v: &toml::Value) -> toml_edit::Value {
    // A value read from TOML prints back as TOML, which reads back the same.
    v.to_string()
        .parse::<toml_edit::Value>()
        .unwrap_or_else(|_| toml_edit::Value::from(v.to_string()))
}

/// The SI number of a value: a number as it is, a quantity with a unit converted.
pub(crate) fn si_value(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Integer(n) => Some(*n as f64),
        toml::Value::Float(x) => Some(*x),
        toml::Value::String(s) => [
            Dimension::Length,
            Dimension::AngularSpeed,
            Dimension::Mass,
            Dimension::Time,
            Dimension::Force,
        ]
        .iter()
        .find_map(|&d| parse_quantity(s, d).ok()),
        _ => None,
    }
}

/// A value as a person reads it: a string without its quotes, anything else as TOML.
pub(crate) fn plain_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}
