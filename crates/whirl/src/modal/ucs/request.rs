//! What an undamped critical-speed map is asked for (`whirl ucs`, `whirl.ucs`): each option
//! left out takes the library's default, written here once, and one reading of a
//! stiffness range whichever front end gave it.

// Options are read once per map; a large error type on this cold path is fine.
#![allow(clippy::result_large_err)]

use super::{default_stiffnesses, log_space};
use crate::error::InputError;
use crate::given::{mode_count, unknown_option, Given, SetByName, MAX_MODES};
use crate::model::Model;

/// Critical speeds (curves) drawn when none are asked for.
pub const DEFAULT_UCS_MODES: usize = 4;

/// Most stiffnesses a range may hold.
pub const MAX_STIFFNESSES: usize = 10_000;

/// An undamped critical-speed map as asked for; `None` (and `false`) is the library's
/// default.
#[derive(Debug, Clone, Default)]
pub struct UcsRequest {
    /// Bearing stiffnesses, N/m, each positive; `None` for [`default_stiffnesses`].
    pub stiffness: Option<Vec<f64>>,
    /// Critical speeds, 1 to [`MAX_MODES`]; `None` for [`DEFAULT_UCS_MODES`].
    pub modes: Option<usize>,
    /// Natural frequencies at rest instead of synchronous critical speeds.
    pub at_rest: bool,
}

/// The options [`UcsRequest::set`] knows.
const OPTIONS: [&str; 3] = ["stiffness", "modes", "at_rest"];

/// How a stiffness range is written.
const RANGE_HELP: &str = "give start:stop:count in N/m, spaced logarithmically, e.g. 1e5:1e10:51";

impl UcsRequest {
    /// The stiffnesses (N/m) and the number of critical speeds for `model`, every default
    /// filled in.
    ///
    /// # Errors
    /// [`InputError`] naming `modes` for a count out of range.
    pub fn resolved(&self, model: &Model) -> Result<(Vec<f64>, usize), InputError> {
        let modes = mode_count("modes", self.modes.unwrap_or(DEFAULT_UCS_MODES))?;
        let stiffness = self
            .stiffness
            .clone()
            .unwrap_or_else(|| default_stiffnesses(model));
        Ok((stiffness, modes))
    }
}

/// Stiffnesses `start:stop:count` (N/m, `N/m` after a bound allowed), spaced
/// logarithmically.
///
/// # Errors
/// [`InputError`] naming `stiffness` for anything else.
pub fn stiffness_range(text: &str) -> Result<Vec<f64>, InputError> {
    let bad =
        |why: String| InputError::field("stiffness", format!("`{text}`: {why}")).help(RANGE_HELP);
    let parts: Vec<&str> = text.split(':').collect();
    let [a, b, n] = parts[..] else {
        return Err(bad("expected start:stop:count".into()));
    };
    let bound = |s: &str, name: &str| match s.trim().trim_end_matches("N/m").trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(bad(format!(
            "the {name} `{s}` is not a positive stiffness in N/m"
        ))),
    };
    let (lo, hi) = (bound(a, "start")?, bound(b, "stop")?);
    match n.trim().parse::<usize>() {
        Ok(count) if (2..=MAX_STIFFNESSES).contains(&count) && hi > lo => {
            Ok(log_space(lo, hi, count))
        }
        _ => Err(bad(format!(
            "give stop above start and a count from 2 to {MAX_STIFFNESSES}"
        ))),
    }
}

impl SetByName for UcsRequest {
    fn set(&mut self, name: &str, value: &Given) -> Result<(), InputError> {
        match name {
            "stiffness" => {
                self.stiffness = Some(match value {
                    Given::Text(t) => stiffness_range(t)?,
                    list => positive_stiffnesses(name, list)?,
                })
            }
            "modes" => self.modes = Some(value.whole(name, 1, MAX_MODES)?),
            "at_rest" => self.at_rest = value.flag(name)?,
            _ => return Err(unknown_option(name, &OPTIONS, "critical-speed map")),
        }
        Ok(())
    }
}

/// Stiffnesses given one by one, each positive (N/m).
fn positive_stiffnesses(name: &str, list: &Given) -> Result<Vec<f64>, InputError> {
    let k = list
        .items()
        .iter()
        .map(|x| x.number(name))
        .collect::<Result<Vec<_>, _>>()?;
    if k.is_empty() || k.len() > MAX_STIFFNESSES || k.iter().any(|x| *x <= 0.0) {
        return Err(InputError::field(
            name,
            format!("give 1 to {MAX_STIFFNESSES} positive stiffnesses in N/m"),
        )
        .help(RANGE_HELP));
    }
    Ok(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_range_is_read_once_whichever_front_end_gave_it() {
        let k = stiffness_range("1e5:1e7 N/m:3").unwrap();
        assert_eq!(k.len(), 3);
        assert!((k[1] - 1e6).abs() < 1e-6, "{k:?}");
        for bad in ["1e5:1e10", "1e7:1e5:3", "0:1e5:3", "1e5:1e7:1", "a:b:c"] {
            let e = stiffness_range(bad).unwrap_err();
            assert_eq!(e.field.as_deref(), Some("stiffness"), "{bad}");
            assert!(e.message.contains(bad), "{}", e.message);
        }
        let mut r = UcsRequest::default();
        let e = r
            .set("stiffness", &Given::List(vec![Given::Number(-1.0)]))
            .unwrap_err();
        assert!(e.message.contains("positive"), "{}", e.message);
    }
}
