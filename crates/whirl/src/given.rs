//! Options as a user gives them, before they are read: a flag, a number, text with a unit
//! (`"0.5s"`, `"3000Hz"`), a list of numbers. The Python package and the study file hand
//! each option to an analysis's request by name ([`crate::nsv::CascadeRequest::set`],
//! [`crate::runup::RunupRequest::set`]), which reads it with the methods here: one
//! reading of each kind of value, and one message per mistake, whichever front end the
//! value came from. The command line fills the same requests from its typed flags.
//!
//! Plain numbers are SI, as on the command line: seconds, metres, rad/s (also for a
//! frequency, which the requests then hold in Hz).

// Options are read once per request, as the study file reads its own; a large error type
// on this cold path is fine.
#![allow(clippy::result_large_err)]

use crate::error::InputError;
use crate::units::{parse_angular_acceleration, parse_quantity, parse_range, rad_s_to_hz};
use crate::units::{parse_speed_range, Dimension};

/// An option's value as given.
#[derive(Debug, Clone, PartialEq)]
pub enum Given {
    /// `true` or `false`.
    Flag(bool),
    /// A whole number.
    Whole(i64),
    /// A number, SI.
    Number(f64),
    /// Text: a quantity with its unit, a range, or a name.
    Text(String),
    /// A list of values (speeds, nodes, harmonic counts).
    List(Vec<Given>),
}

/// An option error naming the option `field`.
fn bad(field: &str, message: String, help: &str) -> InputError {
    InputError::field(field, message).help(help)
}

/// `x` when it is finite.
fn finite(field: &str, x: f64, help: &str) -> Result<f64, InputError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(bad(field, format!("must be finite, got {x}"), help))
    }
}

impl Given {
    /// What the value is, for messages.
    fn kind(&self) -> String {
        match self {
            Given::Flag(b) => format!("the flag {b}"),
            Given::Whole(n) => format!("the number {n}"),
            Given::Number(x) => format!("the number {x}"),
            Given::Text(t) => format!("`{t}`"),
            Given::List(_) => "a list".into(),
        }
    }

    /// A quantity of `dimension`: a number (SI) or text with a unit.
    fn quantity(
        &self,
        field: &str,
        dimension: Dimension,
        example: &str,
    ) -> Result<f64, InputError> {
        let Given::Text(t) = self else {
            return self.number(field);
        };
        let x = parse_quantity(t, dimension)
            .map_err(|e| bad(field, e.to_string(), &format!("e.g. {example}")))?;
        finite(field, x, &format!("e.g. {example}"))
    }

    /// A quantity of `dimension` that is positive, or 0 or more with `zero`; `what` names
    /// it and its SI unit in the message.
    fn signed(
        &self,
        field: &str,
        dimension: Dimension,
        example: &str,
        what: (&str, &str),
        zero: bool,
    ) -> Result<f64, InputError> {
        let x = self.quantity(field, dimension, example)?;
        if x > 0.0 || (zero && x == 0.0) {
            return Ok(x);
        }
        let rule = if zero {
            "must not be negative"
        } else {
            "must be positive"
        };
        Err(bad(
            field,
            format!("{} {rule}, got {x} {}", what.0, what.1),
            &format!("e.g. {example}"),
        ))
    }

    /// A force, N, positive.
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything but a positive force.
    pub fn force(&self, field: &str) -> Result<f64, InputError> {
        self.signed(
            field,
            Dimension::Force,
            "\"60N\"",
            ("the force", "N"),
            false,
        )
    }

    /// Lengths, m, each 0 or more: a range `start:stop:count` (`"10um:120um:12"`), text
    /// separated by commas (`"20um,60um"`), or numbers in m.
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything else.
    pub fn lengths(&self, field: &str) -> Result<Vec<f64>, InputError> {
        if let Given::Text(t) = self {
            if t.matches(':').count() == 2 {
                return parse_range(t, Dimension::Length)
                    .map_err(|e| bad(field, e.to_string(), "e.g. 10um:120um:12"));
            }
        }
        self.items()
            .iter()
            .map(|x| x.length_or_zero(field))
            .collect()
    }

    /// A time, s, 0 or more (the ranges particular to an option are the analysis's).
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything but a time of 0 or more.
    pub fn time(&self, field: &str) -> Result<f64, InputError> {
        self.signed(field, Dimension::Time, "\"0.5s\"", ("a time", "s"), true)
    }

    /// A frequency, returned in Hz: text with a unit (`"3000Hz"`, `"180000rpm"`) or a
    /// number in rad/s; positive.
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything but a positive frequency.
    pub fn frequency_hz(&self, field: &str) -> Result<f64, InputError> {
        let w = self.signed(
            field,
            Dimension::AngularSpeed,
            "\"3000Hz\"",
            ("the frequency", "rad/s"),
            false,
        )?;
        Ok(rad_s_to_hz(w))
    }

    /// A length, m: a number or text with a unit (`"1um"`); positive.
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything but a positive length.
    pub fn length(&self, field: &str) -> Result<f64, InputError> {
        self.signed(
            field,
            Dimension::Length,
            "\"1um\"",
            ("the length", "m"),
            false,
        )
    }

    /// An angular acceleration, rad/s^2: text (`"20Hz/s"`, `"1200rpm/s"`) or a number in
    /// rad/s^2 (its sign is the analysis's to check).
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything else.
    pub fn acceleration(&self, field: &str) -> Result<f64, InputError> {
        match self {
            Given::Text(t) => parse_angular_acceleration(t)
                .map_err(|e| bad(field, e.to_string(), "e.g. \"20Hz/s\"")),
            _ => self.number(field),
        }
    }

    /// A plain number (a fraction, a ratio, a count of bins).
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything but a finite number.
    pub fn number(&self, field: &str) -> Result<f64, InputError> {
        let help = "e.g. 2 or 0.05";
        let x = match self {
            Given::Whole(n) => *n as f64,
            Given::Number(x) => *x,
            Given::Text(t) => t
                .trim()
                .parse::<f64>()
                .map_err(|_| bad(field, format!("`{t}` is not a number"), help))?,
            other => {
                return Err(bad(
                    field,
                    format!("expected a number, got {}", other.kind()),
                    help,
                ))
            }
        };
        finite(field, x, help)
    }

    /// A whole number from `min` to `max`.
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything else.
    pub fn whole(&self, field: &str, min: usize, max: usize) -> Result<usize, InputError> {
        let n = match self {
            Given::Whole(n) => Some(*n),
            Given::Number(x) if x.fract() == 0.0 && x.abs() < 1e15 => Some(*x as i64),
            Given::Text(t) => t.trim().parse::<i64>().ok(),
            _ => None,
        };
        match n {
            Some(n) if n >= min as i64 && n <= max as i64 => Ok(n as usize),
            _ => Err(bad(
                field,
                format!("{} is not a whole number from {min} to {max}", self.kind()),
                &format!("e.g. {}", min.max(1)),
            )),
        }
    }

    /// A length, m, 0 or more: 0 switches something off (a smoothing).
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything but a length of 0 or more.
    pub fn length_or_zero(&self, field: &str) -> Result<f64, InputError> {
        self.signed(
            field,
            Dimension::Length,
            "\"0.01um\"",
            ("the length", "m"),
            true,
        )
    }

    /// One speed, rad/s, 0 or more: text with a unit (`"100Hz"`, `"3000rpm"`) or a number in
    /// rad/s.
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything else.
    pub fn speed(&self, field: &str) -> Result<f64, InputError> {
        self.signed(
            field,
            Dimension::AngularSpeed,
            "\"100Hz\"",
            ("the speed", "rad/s"),
            true,
        )
    }

    /// The items of a list, or of text separated by commas (`"100Hz,330Hz"`); a single
    /// value as a list of one.
    pub fn items(&self) -> Vec<Given> {
        match self {
            Given::List(items) => items.clone(),
            Given::Text(t) if t.contains(',') => t
                .split(',')
                .map(|x| Given::Text(x.trim().to_string()))
                .collect(),
            other => vec![other.clone()],
        }
    }

    /// Whole numbers from `min` to `max`: a list, text `"1,3,5"`, or a rising range
    /// `"1..5"` (both ends included).
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything else.
    pub fn wholes(&self, field: &str, min: usize, max: usize) -> Result<Vec<usize>, InputError> {
        if let Given::Text(t) = self {
            if let Some((a, b)) = t.split_once("..") {
                let a = Given::Text(a.into()).whole(field, min, max)?;
                let b = Given::Text(b.into()).whole(field, min, max)?;
                if b < a {
                    return Err(bad(
                        field,
                        format!("`{t}`: the range must not run backwards"),
                        "e.g. 1..5",
                    ));
                }
                return Ok((a..=b).collect());
            }
        }
        self.items()
            .iter()
            .map(|x| x.whole(field, min, max))
            .collect()
    }

    /// `true` or `false`.
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything else.
    pub fn flag(&self, field: &str) -> Result<bool, InputError> {
        match self {
            Given::Flag(b) => Ok(*b),
            other => Err(bad(
                field,
                format!("expected true or false, got {}", other.kind()),
                "e.g. true",
            )),
        }
    }

    /// One of the names of `T`, in any case.
    ///
    /// # Errors
    /// [`InputError`] naming `field` and listing the names.
    pub fn choice<T: Choice>(&self, field: &str) -> Result<T, InputError> {
        match self {
            Given::Text(t) => T::from_name(field, t),
            other => Err(T::unknown(field, &other.kind())),
        }
    }

    /// Speeds, rad/s, each positive: a range `start:stop:count` (`"1:750Hz:150"`) or numbers
    /// in rad/s.
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything else.
    pub fn speeds(&self, field: &str) -> Result<Vec<f64>, InputError> {
        self.speeds_above(field, false)
    }

    /// Spin speeds, rad/s, each 0 or more (a linear analysis may start from rest): a range
    /// (`"0:800Hz:161"`) or numbers in rad/s.
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything else.
    pub fn spin_speeds(&self, field: &str) -> Result<Vec<f64>, InputError> {
        self.speeds_above(field, true)
    }

    /// Speeds, each positive, or 0 or more with `rest`.
    fn speeds_above(&self, field: &str, rest: bool) -> Result<Vec<f64>, InputError> {
        let (help, which) = match rest {
            true => (
                "give a range such as \"0:800Hz:161\", or speeds of 0 or more in rad/s",
                "must not be negative",
            ),
            false => (
                "give a range such as \"1:750Hz:150\", or positive speeds in rad/s",
                "must be positive",
            ),
        };
        let w = match self {
            Given::Text(t) => parse_range(t, Dimension::AngularSpeed)
                .map_err(|e| bad(field, e.to_string(), help))?,
            Given::List(items) => items
                .iter()
                .map(|x| x.number(field))
                .collect::<Result<_, _>>()?,
            other => {
                return Err(bad(
                    field,
                    format!("expected speeds, got {}", other.kind()),
                    help,
                ))
            }
        };
        let allowed = |x: f64| x.is_finite() && (x > 0.0 || (rest && x == 0.0));
        if w.is_empty() || w.iter().any(|&x| !allowed(x)) {
            return Err(bad(field, format!("{}: speeds {which}", self.kind()), help));
        }
        Ok(w)
    }

    /// A speed range `(low, high)`, rad/s: text `low:high` (`"1:750Hz"`) or two numbers in
    /// rad/s.
    ///
    /// # Errors
    /// [`InputError`] naming `field` for anything else.
    pub fn speed_range(&self, field: &str) -> Result<(f64, f64), InputError> {
        let help = "give a range such as \"1:750Hz\", or (low, high) in rad/s";
        match self {
            Given::Text(t) => parse_speed_range(t).map_err(|e| bad(field, e.to_string(), help)),
            Given::List(items) if items.len() == 2 => {
                Ok((items[0].number(field)?, items[1].number(field)?))
            }
            other => Err(bad(
                field,
                format!("expected a speed range, got {}", other.kind()),
                help,
            )),
        }
    }
}

impl TryFrom<&toml::Value> for Given {
    type Error = String;

    /// A value of a TOML file; tables, dates and lists of anything but numbers are not
    /// options.
    fn try_from(value: &toml::Value) -> Result<Self, String> {
        Ok(match value {
            toml::Value::Boolean(b) => Given::Flag(*b),
            toml::Value::Integer(n) => Given::Whole(*n),
            toml::Value::Float(x) => Given::Number(*x),
            toml::Value::String(s) => Given::Text(s.clone()),
            toml::Value::Array(a) => {
                Given::List(a.iter().map(Given::try_from).collect::<Result<_, _>>()?)
            }
            other => {
                return Err(format!(
                    "expected an option's value, got {}",
                    other.type_str()
                ))
            }
        })
    }
}

/// A request whose options are set by name, as the Python package's keywords and the study
/// file's entries give them.
pub trait SetByName {
    /// Sets the option named `name` to `value`, read as that option reads.
    ///
    /// # Errors
    /// [`InputError`] naming `name` for a value it does not read, or an unknown name.
    fn set(&mut self, name: &str, value: &Given) -> Result<(), InputError>;
}

/// Most fixed-interface modes a reduction may keep (the bound of every mode-count option).
pub const MAX_MODES: usize = 200;

/// `n` when it is a count of modes, 1 to [`MAX_MODES`], with the message every mode count
/// gives otherwise.
///
/// # Errors
/// [`InputError`] naming `field`.
pub fn mode_count(field: &str, n: usize) -> Result<usize, InputError> {
    Given::Whole(i64::try_from(n).unwrap_or(i64::MAX)).whole(field, 1, MAX_MODES)
}

/// The error for an option `name` that `analysis` does not have, listing those it has.
pub fn unknown_option(name: &str, known: &[&str], analysis: &str) -> InputError {
    InputError::field(name, format!("the {analysis} has no option `{name}`"))
        .help(format!("its options are {}", known.join(", ")))
}

/// An option with a fixed set of values, each by the name every front end gives it.
pub trait Choice: Copy + PartialEq + 'static {
    /// Every value and its name, in the order the help lists them.
    const NAMES: &'static [(&'static str, Self)];

    /// The value named `name` (in any case).
    ///
    /// # Errors
    /// [`InputError`] naming `field` and listing the names.
    fn from_name(field: &str, name: &str) -> Result<Self, InputError> {
        let wanted = name.trim().to_lowercase();
        Self::NAMES
            .iter()
            .find(|(n, _)| *n == wanted)
            .map(|(_, v)| *v)
            .ok_or_else(|| Self::unknown(field, &format!("`{name}`")))
    }

    /// Its name.
    fn choice_name(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(_, v)| *v == self)
            .map_or("", |(n, _)| n)
    }

    /// The error for `what`, which names none of the values.
    fn unknown(field: &str, what: &str) -> InputError {
        let names: Vec<&str> = Self::NAMES.iter().map(|(n, _)| *n).collect();
        InputError::field(field, format!("{what} is not one of {}", names.join(", ")))
            .help(format!("use one of: {}", names.join(", ")))
    }
}

/// [`Choice`] for an enum: each value with its name. Each module names its own enums'
/// values beside them, so this module depends on no analysis.
macro_rules! choice {
    ($t:ty { $($name:literal => $v:expr),+ $(,)? }) => {
        impl $crate::given::Choice for $t {
            const NAMES: &'static [(&'static str, Self)] = &[$(($name, $v)),+];
        }
    };
}
pub(crate) use choice;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quantity_reads_with_its_unit_or_as_si() {
        assert_eq!(Given::Text("0.5s".into()).time("settle"), Ok(0.5));
        assert_eq!(Given::Number(0.25).time("settle"), Ok(0.25));
        assert_eq!(Given::Text("3000Hz".into()).frequency_hz("f"), Ok(3000.0));
        // A plain number is rad/s, held in Hz.
        let f = Given::Number(std::f64::consts::TAU)
            .frequency_hz("f")
            .unwrap();
        assert!((f - 1.0).abs() < 1e-15);
        let e = Given::Text("-1 s".into()).time("settle").unwrap_err();
        assert_eq!(e.field.as_deref(), Some("settle"));
        let e = Given::Text("glue".into())
            .choice::<Law>("contact")
            .unwrap_err();
        assert_eq!(e.message, "`glue` is not one of hertz, linear");
    }

    /// An option with two values, named as a module names its own.
    #[derive(Debug, Clone, Copy, PartialEq)]
    enum Law {
        Hertz,
        Linear,
    }
    choice!(Law { "hertz" => Law::Hertz, "linear" => Law::Linear });

    #[test]
    fn every_name_reads_back_as_its_value() {
        fn round_trip<T: Choice + std::fmt::Debug>() {
            for (name, v) in T::NAMES {
                assert_eq!(T::from_name("x", &name.to_uppercase()), Ok(*v));
                assert_eq!(v.choice_name(), *name);
            }
        }
        round_trip::<Law>();
    }
}
