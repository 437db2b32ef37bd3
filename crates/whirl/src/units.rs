//! Physical quantities with units, as a person writes them in a model file or on the
//! command line.
//!
//! A plain number always means SI (m, kg, rad/s, ...). A string carries its unit:
//! `"3000 rpm"`, `"50 Hz"`, `"20 um"`, `"1.3 m"`. Units are converted to SI once, here,
//! at the file boundary; everything inside whirl is SI.
//!
//! Speed ranges on the command line are written `start:stop:count`, with the unit on
//! any of the bounds (`0:800Hz:161`, `1:750Hz:150`, `0Hz:3000rpm:31`). A unit given on
//! one bound applies to a bound that has none. A range holds at most [`MAX_RANGE_COUNT`]
//! values, checked before any is made.

use std::f64::consts::PI;
use std::fmt;

/// The most values a `start:stop:count` range may hold. Each value is at least one
/// analysis (a modal solve, a time simulation of a cascade speed: tens of milliseconds to
/// seconds each), so 100,000 is already hours of work and far beyond what a plot or a
/// table can show; the cap is checked before the list is made, so a mistyped count fails
/// at once instead of exhausting the memory.
pub const MAX_RANGE_COUNT: usize = 100_000;

/// Refuses a list of more than [`MAX_RANGE_COUNT`] speeds however it was given (a range,
/// an explicit list, an array from Python): the cap is the work each value costs, not
/// how the values were written.
///
/// # Errors
/// [`Error::InvalidOption`](crate::Error::InvalidOption) naming `what` and the count.
pub fn check_count(count: usize, what: &str) -> crate::Result<()> {
    if count <= MAX_RANGE_COUNT {
        return Ok(());
    }
    Err(crate::Error::InvalidOption(format!(
        "{count} {what}: at most {MAX_RANGE_COUNT} (each is a whole solve; that many would \
         take hours and no plot can show them): give fewer"
    )))
}

/// The largest spin speed or frequency whirl accepts, rad/s (1.6 MHz): a hundred times the
/// fastest rotors built (micro gas turbines and dental drills reach about 1e5 rad/s). Far
/// beyond it the gyroscopic and speed-squared terms overflow the eigen-solvers.
pub const MAX_ANGULAR_SPEED: f64 = 1e7;

/// What a quantity measures; decides which unit names are accepted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dimension {
    /// Metres (m, mm, um, µm, in).
    Length,
    /// Angular speed in rad/s (Hz, rpm, rad/s). `Hz` means revolutions per second.
    AngularSpeed,
    /// Kilograms (kg, g).
    Mass,
    /// Time in seconds (s, ms, us).
    Time,
    /// Force in newtons (N, kN).
    Force,
}

impl Dimension {
    /// Each accepted unit with its factor to SI as numerator and denominator.
    fn units(self) -> &'static [(&'static str, f64, f64)] {
        match self {
            Dimension::Length => &[
                ("m", 1.0, 1.0),
                ("mm", 1.0, 1e3),
                ("um", 1.0, 1e6),
                ("µm", 1.0, 1e6),
                ("micron", 1.0, 1e6),
                ("in", 0.0254, 1.0),
            ],
            Dimension::AngularSpeed => &[
                ("rad/s", 1.0, 1.0),
                ("Hz", 2.0 * PI, 1.0),
                ("rpm", 2.0 * PI, 60.0),
            ],
            Dimension::Mass => &[("kg", 1.0, 1.0), ("g", 1.0, 1e3)],
            Dimension::Time => &[("s", 1.0, 1.0), ("ms", 1.0, 1e3), ("us", 1.0, 1e6)],
            Dimension::Force => &[("N", 1.0, 1.0), ("kN", 1e3, 1.0)],
        }
    }

    /// The SI unit name, for messages.
    pub fn si_name(self) -> &'static str {
        match self {
            Dimension::Length => "m",
            Dimension::AngularSpeed => "rad/s",
            Dimension::Mass => "kg",
            Dimension::Time => "s",
            Dimension::Force => "N",
        }
    }

    fn accepted(self) -> String {
        self.units()
            .iter()
            .map(|(n, _, _)| *n)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl fmt::Display for Dimension {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = match self {
            Dimension::Length => "length",
            Dimension::AngularSpeed => "speed",
            Dimension::Mass => "mass",
            Dimension::Time => "time",
            Dimension::Force => "force",
        };
        f.write_str(name)
    }
}

/// Why a quantity could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UnitError {
    /// The number part is not a finite number.
    #[error("`{text}` is not a finite number with a unit (expected e.g. {example})")]
    BadNumber {
        /// The text as given.
        text: String,
        /// A valid value of this dimension.
        example: String,
    },
    /// The unit is not one this dimension accepts.
    #[error("unknown {dimension} unit `{unit}` in `{text}` (accepted: {accepted})")]
    BadUnit {
        /// The text as given.
        text: String,
        /// The unit read from it.
        unit: String,
        /// The dimension asked for.
        dimension: Dimension,
        /// The units this dimension accepts.
        accepted: String,
    },
    /// A speed beyond [`MAX_ANGULAR_SPEED`].
    #[error("`{text}` is {value:e} rad/s, beyond the {MAX_ANGULAR_SPEED:e} rad/s (1.6 MHz) whirl accepts: a hundred times the fastest rotors built")]
    TooFast {
        /// The text as given.
        text: String,
        /// Its value, rad/s.
        value: f64,
    },
    /// A range is not `start:stop:count`.
    #[error("`{text}` is not a range `start:stop:count` (e.g. `0:800Hz:161`): {why}")]
    BadRange {
        /// The text as given.
        text: String,
        /// What is wrong with it.
        why: String,
    },
}

fn example(dimension: Dimension) -> String {
    match dimension {
        Dimension::Length => "\"20 um\"".into(),
        Dimension::AngularSpeed => "\"3000 rpm\"".into(),
        Dimension::Mass => "\"10 kg\"".into(),
        Dimension::Time => "\"0.5 s\"".into(),
        Dimension::Force => "\"60 N\"".into(),
    }
}

/// Splits `"3000 rpm"` or `"3000rpm"` into the number and the unit (possibly empty).
fn split_number_unit(text: &str) -> (&str, &str) {
    let t = text.trim();
    let end = t
        .char_indices()
        .find(|&(i, c)| {
            !(c.is_ascii_digit()
                || c == '.'
                || c == '+'
                || c == '-'
                || ((c == 'e' || c == 'E') && exponent_follows(&t[i..])))
        })
        .map(|(i, _)| i)
        .unwrap_or(t.len());
    (t[..end].trim(), t[end..].trim())
}

/// True when an `e` starts a numeric exponent (`e-5`, `e3`) rather than a unit.
fn exponent_follows(rest: &str) -> bool {
    let mut chars = rest.chars().skip(1);
    match chars.next() {
        Some(c) if c.is_ascii_digit() => true,
        Some('+') | Some('-') => chars.next().is_some_and(|c| c.is_ascii_digit()),
        _ => false,
    }
}

/// Reads a quantity such as `"3000 rpm"` into SI. A bare number is SI.
///
/// # Errors
/// [`UnitError`] for text that is not a number with an optional unit, a unit of another
/// dimension, or a speed above [`MAX_ANGULAR_SPEED`].
pub fn parse_quantity(text: &str, dimension: Dimension) -> Result<f64, UnitError> {
    parse_with_default_unit(text, dimension, None)
}

fn parse_with_default_unit(
    text: &str,
    dimension: Dimension,
    default_unit: Option<&str>,
) -> Result<f64, UnitError> {
    let (number, unit) = split_number_unit(text);
    let value: f64 = number.parse().map_err(|_| UnitError::BadNumber {
        text: text.to_string(),
        example: example(dimension),
    })?;
    if !value.is_finite() {
        return Err(UnitError::BadNumber {
            text: text.to_string(),
            example: example(dimension),
        });
    }
    let unit = if unit.is_empty() {
        default_unit.unwrap_or("")
    } else {
        unit
    };
    if unit.is_empty() {
        check_speed(value, text, dimension)?;
        return Ok(value);
    }
    let factor = dimension
        .units()
        .iter()
        .find(|(name, _, _)| *name == unit)
        .map(|(_, num, den)| (*num, *den))
        .ok_or_else(|| UnitError::BadUnit {
            text: text.to_string(),
            unit: unit.to_string(),
            dimension,
            accepted: dimension.accepted(),
        })?;
    // Multiply then divide, so that "20 um" is exactly 2e-5.
    let si = value * factor.0 / factor.1;
    check_speed(si, text, dimension)?;
    if !si.is_finite() {
        // 1e308 Hz is a finite number but not a finite speed in rad/s.
        return Err(UnitError::BadNumber {
            text: text.to_string(),
            example: example(dimension),
        });
    }
    Ok(si)
}

/// Refuses a speed beyond [`MAX_ANGULAR_SPEED`] (other dimensions pass).
///
/// # Errors
/// [`UnitError::TooFast`] for an angular speed above [`MAX_ANGULAR_SPEED`].
pub fn check_speed(value: f64, text: &str, dimension: Dimension) -> Result<(), UnitError> {
    if dimension == Dimension::AngularSpeed && value.abs() > MAX_ANGULAR_SPEED {
        return Err(UnitError::TooFast {
            text: text.to_string(),
            value,
        });
    }
    Ok(())
}

/// Reads `start:stop:count` into `count` equally spaced SI values (inclusive bounds).
/// `start:stop` alone (no count) is refused: the caller decides a default count.
///
/// # Errors
/// [`UnitError::BadRange`] for text that is not `start:stop:count` with a count of at least
/// 2, and the errors of [`parse_quantity`] for its bounds.
pub fn parse_range(text: &str, dimension: Dimension) -> Result<Vec<f64>, UnitError> {
    let bad = |why: &str| UnitError::BadRange {
        text: text.to_string(),
        why: why.to_string(),
    };
    let parts: Vec<&str> = text.split(':').collect();
    if parts.len() != 3 {
        return Err(bad("expected three parts separated by ':'"));
    }
    let count: usize = parts[2]
        .trim()
        .parse()
        .map_err(|_| bad("the count must be a whole number"))?;
    if count == 0 {
        return Err(bad("the count must be at least 1"));
    }
    if count > MAX_RANGE_COUNT {
        return Err(bad(&format!(
            "at most {MAX_RANGE_COUNT} values (each one is an analysis: more would take \
             hours and show nothing more)"
        )));
    }
    let unit_of = |s: &str| split_number_unit(s).1.to_string();
    let (u0, u1) = (unit_of(parts[0]), unit_of(parts[1]));
    let shared = if !u1.is_empty() {
        u1.clone()
    } else {
        u0.clone()
    };
    // The bound that carries the shared unit is read first, so that a misspelt unit is
    // reported where it was written (`800Hx`), not on the bound that borrowed it.
    let read = |s: &str| parse_with_default_unit(s, dimension, Some(&shared));
    let (start, stop) = if u1.is_empty() {
        (read(parts[0])?, read(parts[1])?)
    } else {
        let stop = read(parts[1])?;
        (read(parts[0])?, stop)
    };
    if count == 1 {
        if start != stop {
            return Err(bad("a count of 1 needs start equal to stop"));
        }
        return Ok(vec![start]);
    }
    if stop < start {
        return Err(bad("stop must not be below start"));
    }
    let step = (stop - start) / (count - 1) as f64;
    if !step.is_finite() {
        return Err(bad(
            "the span stop - start overflows; give bounds nearer each other",
        ));
    }
    Ok((0..count).map(|i| start + step * i as f64).collect())
}

/// Reads a speed range `low:high` (`1:750Hz`, the unit shared by both bounds as in
/// [`parse_range`]; plain numbers are rad/s) into its bounds in rad/s. A reversed or empty
/// range is read as given: whoever sweeps it says what is wrong with it.
///
/// # Errors
/// [`UnitError::BadRange`] for text that is not two bounds, and the errors of
/// [`parse_quantity`] for a bound.
pub fn parse_speed_range(text: &str) -> Result<(f64, f64), UnitError> {
    if text.split(':').count() != 2 {
        return Err(UnitError::BadRange {
            text: text.to_string(),
            why: "expected two speeds `low:high`, e.g. `1:750Hz`".into(),
        });
    }
    let (low, high) = text.split_once(':').unwrap_or((text, ""));
    let unit = split_number_unit(high.trim()).1.to_string();
    let shared = if unit.is_empty() {
        split_number_unit(low.trim()).1.to_string()
    } else {
        unit
    };
    let read = |s: &str| parse_with_default_unit(s.trim(), Dimension::AngularSpeed, Some(&shared));
    Ok((read(low)?, read(high)?))
}

/// Reads an angular acceleration: a speed per second (`20Hz/s`, `1200rpm/s`, `5 rad/s/s`),
/// or a plain number in rad/s^2; returned in rad/s^2. Its sign is the caller's to check.
///
/// # Errors
/// The errors of [`parse_quantity`] for the speed before `/s`.
pub fn parse_angular_acceleration(text: &str) -> Result<f64, UnitError> {
    let trimmed = text.trim();
    parse_quantity(
        trimmed.strip_suffix("/s").unwrap_or(trimmed),
        Dimension::AngularSpeed,
    )
}

/// Converts rad/s to Hz (revolutions or cycles per second).
pub fn rad_s_to_hz(w: f64) -> f64 {
    w / (2.0 * PI)
}

/// Converts Hz to rad/s.
pub fn hz_to_rad_s(f: f64) -> f64 {
    f * 2.0 * PI
}

/// `value +- error` with no more digits than the error allows: the error rounded to one
/// significant digit (two when that digit is 1, as in 0.14), the value to the same
/// decimal place; a zero or non-finite error prints the value with `default_decimals`.
pub fn with_uncertainty(value: f64, error: f64, default_decimals: usize) -> String {
    if !(error.is_finite() && error > 0.0) {
        return format!("{value:.default_decimals$}");
    }
    let exponent = error.log10().floor() as i32;
    let leading = (error / 10f64.powi(exponent)).floor();
    let digits = if leading < 2.0 { 2 } else { 1 };
    let decimals = (digits - 1 - exponent).max(0) as usize;
    format!("{value:.decimals$} +- {error:.decimals$}")
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_value_is_printed_to_the_digits_its_error_allows() {
        use super::with_uncertainty;
        assert_eq!(with_uncertainty(1.4861, 0.157, 3), "1.49 +- 0.16");
        assert_eq!(with_uncertainty(1.4861, 0.3, 3), "1.5 +- 0.3");
        assert_eq!(with_uncertainty(148.28, 3.3, 2), "148 +- 3");
        assert_eq!(with_uncertainty(2.63, 0.0, 3), "2.630");
    }

    use super::*;

    #[test]
    fn a_misspelt_unit_is_reported_on_the_bound_that_carries_it() {
        let e = parse_range("0:800Hx:161", Dimension::AngularSpeed)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`800Hx`"), "{e}");
        let e = parse_range("0Hx:800:161", Dimension::AngularSpeed)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`0Hx`"), "{e}");
    }

    #[test]
    fn speeds_convert_to_rad_per_second() {
        let rpm = parse_quantity("3000 rpm", Dimension::AngularSpeed).unwrap();
        let hz = parse_quantity("50Hz", Dimension::AngularSpeed).unwrap();
        // 3000 rpm = 50 Hz = 100 pi rad/s exactly; only the last bit may differ.
        assert!((rpm - 100.0 * PI).abs() < 1e-12);
        assert!((hz - 100.0 * PI).abs() < 1e-12);
        assert_eq!(
            parse_quantity("12.5", Dimension::AngularSpeed).unwrap(),
            12.5
        );
    }

    #[test]
    fn lengths_with_exponents_and_micro_units() {
        assert_eq!(parse_quantity("20 um", Dimension::Length).unwrap(), 20e-6);
        assert_eq!(parse_quantity("2e-5", Dimension::Length).unwrap(), 2e-5);
        assert_eq!(parse_quantity("2e-5 m", Dimension::Length).unwrap(), 2e-5);
        assert!((parse_quantity("1 in", Dimension::Length).unwrap() - 0.0254).abs() < 1e-15);
    }

    #[test]
    fn forces_in_newtons() {
        assert_eq!(parse_quantity("60N", Dimension::Force).unwrap(), 60.0);
        assert_eq!(parse_quantity("1.5 kN", Dimension::Force).unwrap(), 1500.0);
        assert!(parse_quantity("60 kg", Dimension::Force).is_err());
    }

    #[test]
    fn bad_units_and_numbers_are_named() {
        let e = parse_quantity("20 furlongs", Dimension::Length).unwrap_err();
        assert!(e.to_string().contains("furlongs"));
        assert!(parse_quantity("fast", Dimension::AngularSpeed).is_err());
        assert!(parse_quantity("inf Hz", Dimension::AngularSpeed).is_err());
        assert!(parse_quantity("NaN", Dimension::Length).is_err());
        // Finite as written, infinite once converted to rad/s.
        assert!(parse_quantity("1e308Hz", Dimension::AngularSpeed).is_err());
        // Finite, but it made faer's Schur solver panic.
        let e = parse_quantity("1e308", Dimension::AngularSpeed).unwrap_err();
        assert!(e.to_string().contains("fastest rotors"), "{e}");
        assert!(parse_quantity("1e308", Dimension::Length).is_ok());
        // A speed unit is not a length unit.
        assert!(parse_quantity("3 rpm", Dimension::Length).is_err());
    }

    #[test]
    fn ranges_share_the_unit_given_on_one_bound() {
        let r = parse_range("0:800Hz:161", Dimension::AngularSpeed).unwrap();
        assert_eq!(r.len(), 161);
        assert_eq!(r[0], 0.0);
        assert!((r[160] - hz_to_rad_s(800.0)).abs() < 1e-9);
        assert!((r[1] - hz_to_rad_s(5.0)).abs() < 1e-9);
        let mixed = parse_range("0Hz:3000rpm:3", Dimension::AngularSpeed).unwrap();
        assert!((mixed[2] - 100.0 * PI).abs() < 1e-9);
    }

    #[test]
    fn malformed_ranges_are_refused() {
        for bad in [
            "0:800Hz",
            "0:800Hz:0",
            "800:0Hz:5",
            "a:b:c",
            "0:1:2.5",
            // Refused before 1e10 values (80 GB) are allocated.
            "1:750Hz:10000000000",
            "1:750Hz:100001",
            "1e308Hz:1e308Hz:2",
            "-1.7e308:1.7e308:3",
        ] {
            assert!(parse_range(bad, Dimension::AngularSpeed).is_err(), "{bad}");
        }
    }
}
