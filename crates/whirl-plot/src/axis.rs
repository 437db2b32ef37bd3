//! Axis ranges and ticks.
//!
//! Everything is worked out in *chart space*: the value itself on a linear axis and `log10` of it
//! on a logarithmic one, so that the drawing code never needs to know which kind it has. Ticks
//! follow the usual 1-2-5 rule: the step is the "nice" number in `{1, 2, 5} x 10^k` nearest to
//! span / (wanted count).

use crate::PlotError;

/// Fraction of the span added on each side of an automatic range.
pub(crate) const PAD_X: f64 = 0.02;
/// Fraction of the span added above and below an automatic range.
pub(crate) const PAD_Y: f64 = 0.05;

/// A resolved axis: its limits in chart space and whether it is logarithmic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Axis {
    /// Lower limit in chart space.
    pub lo: f64,
    /// Upper limit in chart space, always above `lo`.
    pub hi: f64,
    /// True when chart space is `log10` of the data.
    pub log: bool,
}

impl Axis {
    /// Maps a data value to chart space; `None` when it cannot be drawn on this axis
    /// (not finite, or not positive on a logarithmic axis).
    pub fn to_chart(self, v: f64) -> Option<f64> {
        to_chart(v, self.log)
    }

    /// Whether a chart-space value lies within the limits (with a little slack for rounding).
    pub fn contains(&self, c: f64) -> bool {
        let slack = 1e-9 * (self.hi - self.lo);
        c >= self.lo - slack && c <= self.hi + slack
    }

    /// The axis over the data values `data` unless `explicit` limits (in data units) are given.
    ///
    /// `pad` is the fraction of the data span added on each side of an automatic range. With no
    /// drawable value the range is 0..1 (1..10 when logarithmic); a zero span is widened.
    pub fn resolve(
        name: &'static str,
        data: impl IntoIterator<Item = f64>,
        explicit: Option<(f64, f64)>,
        log: bool,
        pad: f64,
    ) -> Result<Axis, PlotError> {
        let invalid = |lo, hi, reason| PlotError::InvalidRange {
            axis: name,
            lo,
            hi,
            reason,
        };
        if let Some((lo, hi)) = explicit {
            if !lo.is_finite() || !hi.is_finite() {
                return Err(invalid(lo, hi, "limits must be finite"));
            }
            if lo > hi {
                return Err(invalid(lo, hi, "lower limit is above upper limit"));
            }
            if log && lo <= 0.0 {
                return Err(invalid(lo, hi, "a logarithmic axis needs positive limits"));
            }
            let (clo, chi) = if log {
                (lo.log10(), hi.log10())
            } else {
                (lo, hi)
            };
            let (clo, chi) = widen_if_degenerate(clo, chi, log);
            return Ok(Axis {
                lo: clo,
                hi: chi,
                log,
            });
        }
        let mut bounds: Option<(f64, f64)> = None;
        for c in data.into_iter().filter_map(|v| to_chart(v, log)) {
            bounds = Some(match bounds {
                None => (c, c),
                Some((lo, hi)) => (lo.min(c), hi.max(c)),
            });
        }
        let (lo, hi) = bounds.unwrap_or((0.0, 1.0));
        if !(hi - lo).is_finite() {
            return Err(invalid(lo, hi, "the data span overflows a 64-bit float"));
        }
        let (lo, hi) = widen_if_degenerate(lo, hi, log);
        let margin = pad * (hi - lo);
        Ok(Axis {
            lo: lo - margin,
            hi: hi + margin,
            log,
        })
    }

    /// Major ("bold") and minor ("light") tick positions for about `wanted` major ticks.
    pub fn ticks(&self, wanted: usize) -> Ticks {
        let wanted = wanted.max(2);
        if self.log {
            log_ticks(self.lo, self.hi, wanted)
        } else {
            linear_ticks(self.lo, self.hi, wanted)
        }
    }

    /// Widens the range about its centre to `span` (chart units) if it is narrower.
    pub fn widen_to(&mut self, span: f64) {
        let current = self.hi - self.lo;
        if span.is_finite() && span > current {
            let centre = 0.5 * (self.lo + self.hi);
            self.lo = centre - 0.5 * span;
            self.hi = centre + 0.5 * span;
        }
    }
}

/// Maps a data value to chart space (`log10` when `log`); `None` if it cannot be drawn.
pub(crate) fn to_chart(v: f64, log: bool) -> Option<f64> {
    if !v.is_finite() {
        None
    } else if log {
        (v > 0.0).then(|| v.log10())
    } else {
        Some(v)
    }
}

/// Widens a range whose span is zero (or lost in rounding) so it can be drawn.
pub(crate) fn widen_if_degenerate(lo: f64, hi: f64, log: bool) -> (f64, f64) {
    let scale = lo.abs().max(hi.abs());
    if hi - lo > 1e-12 * scale && hi > lo {
        return (lo, hi);
    }
    let centre = 0.5 * (lo + hi);
    let half = if log {
        0.5 // half a decade each way
    } else if scale > f64::MIN_POSITIVE * 1e3 {
        0.05 * centre.abs().max(scale)
    } else {
        1.0
    };
    (centre - half, centre + half)
}

/// Tick positions in chart space and how to label them.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Ticks {
    /// Labelled ticks with a grid line.
    pub bold: Vec<f64>,
    /// Unlabelled minor grid lines.
    pub light: Vec<f64>,
    format: Format,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Format {
    /// Fixed-point with this many decimals.
    Fixed(usize),
    /// Mantissa with this many decimals times `10^exponent`.
    Scientific { decimals: usize, exponent: i32 },
    /// The label is `10^value`.
    Log,
}

impl Ticks {
    /// The same labelling without any tick.
    pub fn without_ticks(self) -> Ticks {
        Ticks {
            bold: Vec::new(),
            light: Vec::new(),
            ..self
        }
    }

    /// The text for the tick at chart-space position `c`.
    pub fn label(&self, c: f64) -> String {
        match self.format {
            Format::Fixed(d) => format!("{:.*}", d, c),
            Format::Scientific { decimals, exponent } => {
                let m = shift_decimal(c, exponent);
                if m.abs() < 0.5 * 10f64.powi(-(decimals as i32)) {
                    "0".to_string()
                } else {
                    format!("{m:.decimals$}e{exponent}")
                }
            }
            Format::Log => log_label(c),
        }
    }
}

/// The nice step in `{1, 2, 5} x 10^k` nearest to `raw`, and its mantissa.
fn nice_step(raw: f64) -> (f64, u8) {
    let mag = 10f64.powf(raw.log10().floor());
    let r = raw / mag;
    let (m, factor) = if r < 1.5 {
        (1, 1.0)
    } else if r < 3.5 {
        (2, 2.0)
    } else if r < 7.5 {
        (5, 5.0)
    } else {
        (1, 10.0)
    };
    (factor * mag, m)
}

/// Multiples of `step` within `lo..=hi`, or `None` when there would be more than `limit`.
fn multiples(lo: f64, hi: f64, step: f64, limit: f64) -> Option<Vec<f64>> {
    if !(step.is_finite() && step > 0.0) {
        return None;
    }
    let first = (lo / step - 1e-9).ceil();
    let last = (hi / step + 1e-9).floor();
    if !(first.is_finite() && last.is_finite()) || last - first > limit {
        return None;
    }
    let mut out = Vec::new();
    let mut k = first;
    while k <= last {
        let v = k * step;
        // Snap values that should be zero but carry rounding noise (-1.2e-17 -> 0).
        out.push(if v.abs() < 1e-9 * step { 0.0 } else { v });
        k += 1.0;
    }
    Some(out)
}

fn linear_ticks(lo: f64, hi: f64, wanted: usize) -> Ticks {
    let (step, mantissa) = nice_step((hi - lo) / wanted as f64);
    let Some(bold) = multiples(lo, hi, step, 100.0) else {
        // Only reachable for spans at the edge of floating point: label the two ends.
        return Ticks {
            bold: vec![lo, hi],
            light: vec![],
            format: Format::Scientific {
                decimals: 3,
                exponent: exponent_of(lo.abs().max(hi.abs())),
            },
        };
    };
    let minor = step / if mantissa == 2 { 4.0 } else { 5.0 };
    let light = multiples(lo, hi, minor, 500.0).unwrap_or_default();
    let step_exp = exponent_of(step);
    let max_abs = lo.abs().max(hi.abs());
    let format = if !(1e-3..1e6).contains(&max_abs) {
        let exponent = exponent_of(max_abs);
        Format::Scientific {
            decimals: (exponent - step_exp).max(0) as usize,
            exponent,
        }
    } else {
        Format::Fixed((-step_exp).max(0) as usize)
    };
    Ticks {
        bold,
        light,
        format,
    }
}

/// `v / 10^exponent`, in two steps so that neither power overflows or underflows for the
/// exponents of subnormal or huge values (10^-320 is not a normal float, 10^320 is infinite).
fn shift_decimal(v: f64, exponent: i32) -> f64 {
    let half = exponent / 2;
    v / 10f64.powi(half) / 10f64.powi(exponent - half)
}

/// `floor(log10(v))`, robust to `log10(0.1) = -0.99999...`.
fn exponent_of(v: f64) -> i32 {
    if v > 0.0 && v.is_finite() {
        (v.log10() + 1e-9).floor() as i32
    } else {
        0
    }
}

fn log_ticks(lo: f64, hi: f64, wanted: usize) -> Ticks {
    let within = |c: &f64| *c >= lo - 1e-9 && *c <= hi + 1e-9;
    let first = lo.floor();
    let last = hi.ceil();
    if !(first.is_finite() && last.is_finite()) {
        return Ticks {
            bold: vec![lo, hi],
            light: vec![],
            format: Format::Log,
        };
    }
    // Positions log10(m * 10^k) for the mantissas `ms` over all decades touching the range.
    let sub_decades = |ms: &[f64]| -> Vec<f64> {
        let mut out = Vec::new();
        let mut k = first;
        while k <= last {
            out.extend(ms.iter().map(|m| k + m.log10()).filter(within));
            k += 1.0;
        }
        out
    };
    let decades: Vec<f64> = sub_decades(&[1.0]);
    let all: Vec<f64> = (2..=9).map(f64::from).collect();
    if decades.len() >= 2 {
        // Label every decade, or every 2nd, 5th, 10th, 20th, ... decade, on multiples of that.
        let need = decades.len().div_ceil(wanted).max(1);
        let stride = [1.0, 2.0, 5.0]
            .iter()
            .flat_map(|s| (0..6).map(move |k| s * 10f64.powi(k)))
            .filter(|s| *s >= need as f64)
            .fold(f64::INFINITY, f64::min);
        let mut bold: Vec<f64> = decades
            .iter()
            .copied()
            .filter(|k| (k / stride).round() * stride == *k)
            .collect();
        if bold.len() < 2 {
            bold = vec![decades[0], decades[decades.len() - 1]];
        }
        let light = if stride == 1.0 && decades.len() <= 12 {
            sub_decades(&all)
        } else {
            Vec::new()
        };
        return Ticks {
            bold,
            light,
            format: Format::Log,
        };
    }
    let mut bold = sub_decades(&[1.0, 2.0, 5.0]);
    if bold.len() < 3 {
        bold = sub_decades(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
    }
    Ticks {
        bold,
        light: sub_decades(&all),
        format: Format::Log,
    }
}

/// Label for the logarithmic tick at `c = log10(value)`: "0.01", "200", "5e-6", "1e9".
fn log_label(c: f64) -> String {
    let value = 10f64.powf(c);
    let exponent = exponent_of(value);
    if (-3..5).contains(&exponent) {
        let decimals = (-exponent).max(0) as usize;
        format!("{value:.decimals$}")
    } else {
        let mantissa = shift_decimal(value, exponent);
        if (mantissa - mantissa.round()).abs() < 1e-6 {
            format!("{}e{exponent}", mantissa.round())
        } else {
            format!("{mantissa:.1}e{exponent}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degenerate_data_is_padded() {
        let a = Axis::resolve("y", [3.0, 3.0], None, false, 0.0).unwrap();
        assert!(a.lo < 3.0 && a.hi > 3.0);
        let z = Axis::resolve("y", [0.0], None, false, 0.0).unwrap();
        assert_eq!((z.lo, z.hi), (-1.0, 1.0));
        let l = Axis::resolve("y", [100.0], None, true, 0.0).unwrap();
        assert_eq!((l.lo, l.hi), (1.5, 2.5));
    }

    #[test]
    fn nothing_drawable_gives_unit_range() {
        let a = Axis::resolve("y", [f64::NAN, f64::INFINITY], None, false, 0.0).unwrap();
        assert_eq!((a.lo, a.hi), (0.0, 1.0));
        let l = Axis::resolve("y", [-1.0, 0.0], None, true, 0.0).unwrap();
        assert_eq!((l.lo, l.hi), (0.0, 1.0));
    }

    #[test]
    fn bad_explicit_ranges_are_errors() {
        assert!(Axis::resolve("x", [], Some((1.0, f64::NAN)), false, 0.0).is_err());
        assert!(Axis::resolve("x", [], Some((2.0, 1.0)), false, 0.0).is_err());
        assert!(Axis::resolve("x", [], Some((0.0, 1.0)), true, 0.0).is_err());
        assert!(Axis::resolve("x", [-f64::MAX, f64::MAX], None, false, 0.0).is_err());
    }

    #[test]
    fn linear_ticks_are_nice() {
        let t = linear_ticks(0.0, 10.0, 5);
        assert_eq!(t.bold, vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(t.label(4.0), "4");
        let t = linear_ticks(-0.3, 0.3, 6);
        assert_eq!(t.label(0.1), "0.1");
        assert!(t.bold.contains(&0.0), "rounding noise at zero is snapped");
        let t = linear_ticks(0.0, 3e-6, 6);
        assert_eq!(t.label(1.5e-6), "1.5e-6");
        assert_eq!(t.label(0.0), "0");
        let t = linear_ticks(0.0, 1e-320, 5);
        assert!(t
            .bold
            .iter()
            .all(|c| !t.label(*c).contains("inf") && !t.label(*c).contains("NaN")));
    }

    #[test]
    fn log_ticks_use_decades_or_125() {
        let t = log_ticks(-3.0, 2.0, 8);
        assert_eq!(t.bold.len(), 6);
        assert_eq!(t.label(-3.0), "0.001");
        assert_eq!(t.label(2.0), "100");
        assert_eq!(t.label(-6.0), "1e-6");
        let t = log_ticks(-33.0, 30.5, 8);
        assert_eq!(
            t.bold.first(),
            Some(&-30.0),
            "strided decades sit on multiples of the stride"
        );
        assert_eq!(t.bold.last(), Some(&30.0));
        let t = log_ticks(0.1, 0.9, 8); // 1.26 .. 7.9
        let labels: Vec<_> = t.bold.iter().map(|c| t.label(*c)).collect();
        assert!(labels.contains(&"2".to_string()) && labels.contains(&"5".to_string()));
    }
}
