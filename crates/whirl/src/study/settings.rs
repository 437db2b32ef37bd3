//! The `[cascade]` table of a study: the settings of every point's cascade, validated.

// Validation runs once per study file; a large error type on this cold path is fine.
#![allow(clippy::result_large_err)]

use serde::Serialize;

use super::file::CascadeFile;
use crate::bearing::ContactLaw;
use crate::error::InputError;
use crate::time::Initial;
use crate::units::{parse_quantity, parse_range, Dimension};

/// Contact laws a study's cascade may use.
pub const CONTACT_LAWS: [ContactLaw; 4] = [
    ContactLaw::Hertz,
    ContactLaw::Lagrange,
    ContactLaw::Forcing,
    ContactLaw::Linear,
];

/// Cascade settings of one point; `None` leaves the cascade's default.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct CascadeSettings {
    /// Spin speeds, rad/s.
    pub speeds: Option<Vec<f64>>,
    /// Settling time per speed, s.
    pub settle: Option<f64>,
    /// Recorded (analysed) time per speed, s.
    pub record: Option<f64>,
    /// Central-difference time step, s. Left out of the point's key when absent, as every
    /// setting added later must be, so that checkpoints written before it stay valid.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step: Option<f64>,
    /// Contact law of the roller bearings.
    pub contact: Option<ContactLaw>,
    /// Craig-Bampton modes; `Some(0)` for the full model.
    pub reduce: Option<usize>,
    /// Node whose response is analysed.
    pub node: Option<usize>,
    /// Its displacement analysed: `"ux"` or `"uy"`.
    pub component: Option<String>,
    /// Top of the analysed frequency band, Hz.
    pub max_frequency_hz: Option<f64>,
    /// NSV smaller than this does not count for the onset speed, m.
    pub nsv_threshold: Option<f64>,
    /// Longest settling time per speed, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settle_max: Option<f64>,
    /// Initial state of every run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start: Option<Initial>,
    /// Whether the speed grid is refined.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refine: Option<bool>,
}

/// Validates a `[cascade]` table; errors name the field as `cascade.<field>`.
///
/// # Errors
/// An [`InputError`] naming `cascade.<field>` for an unknown field or a value out of range.
pub fn cascade_settings(table: &toml::Table) -> Result<CascadeSettings, InputError> {
    let raw: CascadeFile =
        toml::Value::Table(table.clone())
            .try_into()
            .map_err(|e: toml::de::Error| {
                InputError::field("cascade", e.message().to_string()).help(
                    "the [cascade] fields are speeds, settle, settle_max, record, step, contact, \
                 reduce, node, component, max_frequency, nsv_threshold, start and refine \
                 (docs/study-file.md)",
                )
            })?;
    Ok(CascadeSettings {
        speeds: raw.speeds.as_deref().map(speeds).transpose()?,
        settle: raw.settle.as_ref().map(|v| time(v, "settle")).transpose()?,
        record: raw.record.as_ref().map(|v| time(v, "record")).transpose()?,
        step: raw.step.as_ref().map(|v| time(v, "step")).transpose()?,
        contact: raw.contact.map(contact).transpose()?,
        reduce: raw
            .reduce
            .map(|n| whole(n, "reduce", 0, 200, "0 for the full model, e.g. 12"))
            .transpose()?,
        node: raw
            .node
            .map(|n| whole(n, "node", 0, 100_000, "a node of the model, e.g. 10"))
            .transpose()?,
        component: raw.component.map(component).transpose()?,
        max_frequency_hz: raw.max_frequency.as_ref().map(max_frequency).transpose()?,
        nsv_threshold: raw.nsv_threshold.as_ref().map(threshold).transpose()?,
        settle_max: raw
            .settle_max
            .as_ref()
            .map(|v| time(v, "settle_max"))
            .transpose()?,
        start: raw.start.map(start).transpose()?,
        refine: raw.refine,
    })
}

fn start(name: String) -> Result<Initial, InputError> {
    match name.as_str() {
        "static" => Ok(Initial::StaticEquilibrium),
        "rest" => Ok(Initial::Rest),
        _ => Err(InputError::field(
            "cascade.start",
            format!("`{name}` is not an initial state whirl knows"),
        )
        .help("use \"static\" (the static equilibrium under gravity) or \"rest\"")),
    }
}

fn speeds(text: &str) -> Result<Vec<f64>, InputError> {
    let bad = |why: String| {
        InputError::field("cascade.speeds", why)
            .help("write start:stop:count, e.g. \"1:750Hz:150\"")
    };
    let w = parse_range(text, Dimension::AngularSpeed).map_err(|e| bad(e.to_string()))?;
    if w.first().is_some_and(|&w0| w0 <= 0.0) {
        return Err(bad(format!("`{text}`: speeds must be positive")));
    }
    Ok(w)
}

fn time(value: &toml::Value, field: &str) -> Result<f64, InputError> {
    let name = format!("cascade.{field}");
    let t = match value {
        toml::Value::Float(x) => Ok(*x),
        toml::Value::Integer(n) => Ok(*n as f64),
        toml::Value::String(s) => parse_quantity(s, Dimension::Time).map_err(|e| e.to_string()),
        other => Err(format!("expected a time, got {}", other.type_str())),
    }
    .map_err(|why| InputError::field(&name, why).help("write a time such as \"0.5 s\""))?;
    if !(t.is_finite() && t > 0.0) {
        return Err(InputError::field(
            &name,
            format!("must be a positive time, got {t} s"),
        ));
    }
    Ok(t)
}

fn contact(law: String) -> Result<ContactLaw, InputError> {
    let lower = law.to_lowercase();
    CONTACT_LAWS
        .into_iter()
        .find(|c| c.name() == lower)
        .ok_or_else(|| {
            let names: Vec<&str> = CONTACT_LAWS.iter().map(|c| c.name()).collect();
            InputError::field(
                "cascade.contact",
                format!("`{law}` is not a contact law of the cascade"),
            )
            .help(format!("use one of: {}", names.join(", ")))
        })
}

fn component(name: String) -> Result<String, InputError> {
    match name.to_lowercase().as_str() {
        c @ ("ux" | "uy") => Ok(c.to_string()),
        _ => Err(InputError::field(
            "cascade.component",
            format!("`{name}` is not a displacement of the node"),
        )
        .help("use \"uy\" (vertical, the thesis' cascades) or \"ux\" (horizontal)")),
    }
}

fn max_frequency(value: &toml::Value) -> Result<f64, InputError> {
    let bad = |why: String| {
        InputError::field("cascade.max_frequency", why)
            .help("write a frequency such as \"1000 Hz\"")
    };
    let w = match value {
        toml::Value::String(s) => {
            parse_quantity(s, Dimension::AngularSpeed).map_err(|e| bad(e.to_string()))?
        }
        other => {
            return Err(bad(format!(
                "expected a frequency with its unit, got {other}"
            )))
        }
    };
    if !(w.is_finite() && w > 0.0) {
        return Err(bad(format!("must be positive, got {w} rad/s")));
    }
    Ok(crate::units::rad_s_to_hz(w))
}

fn whole(n: i64, field: &str, min: i64, max: i64, example: &str) -> Result<usize, InputError> {
    if (min..=max).contains(&n) {
        Ok(n as usize)
    } else {
        Err(InputError::field(
            format!("cascade.{field}"),
            format!("must be a whole number from {min} to {max}, got {n}"),
        )
        .help(example.to_string()))
    }
}

fn threshold(value: &toml::Value) -> Result<f64, InputError> {
    let bad = |why: String| {
        InputError::field("cascade.nsv_threshold", why).help("write a length such as \"1 um\"")
    };
    let x = match value {
        toml::Value::Float(x) => *x,
        toml::Value::Integer(n) => *n as f64,
        toml::Value::String(s) => {
            parse_quantity(s, Dimension::Length).map_err(|e| bad(e.to_string()))?
        }
        other => return Err(bad(format!("expected a length, got {other}"))),
    };
    if !(x.is_finite() && x >= 0.0) {
        return Err(bad(format!("must not be negative, got {x} m")));
    }
    Ok(x)
}
