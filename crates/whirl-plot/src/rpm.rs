//! Speed axes in revolutions per minute. Figures are built with speeds in Hz; for readers
//! who think in rpm, [`SpeedInRpm::speed_in_rpm`] multiplies everything placed along the
//! speed axis by 60, says `[rpm]` where the axis label said `[Hz]`, and writes each speed
//! that the texts at points and lines on that axis give (`49.9 Hz`, `max operating 750 Hz`)
//! in rpm; [`SpeedInRpm::speed_texts_in_rpm`] does the texts alone, for a figure whose
//! axes are not speeds but whose marks name them (a polar plot's peaks). Titles keep what
//! they say.

use crate::{Annotation, Figure2d, Grid, HeatMap, RefLine};

/// Revolutions per minute in one hertz.
pub const RPM_PER_HZ: f64 = 60.0;

/// The axis of a figure that shows a speed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpeedAxis {
    /// The horizontal axis.
    X,
    /// The vertical axis.
    Y,
}

/// A figure whose speed axis can be shown in rpm.
pub trait SpeedInRpm: Sized {
    /// The same figure with its speed axis (`axis`, in Hz) in rpm.
    fn speed_in_rpm(self, axis: SpeedAxis) -> Self;

    /// The same figure with the speeds its annotations and reference lines name in rpm.
    fn speed_texts_in_rpm(self) -> Self;
}

/// `text` with each speed written as a number followed by ` Hz` (`49.9 Hz`) as whole rpm
/// (`2994 rpm`); the rest of the text as it was.
fn speeds_in_rpm(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(" Hz") {
        let (before, after) = rest.split_at(at);
        let after = &after[" Hz".len()..];
        // The number is the run of digits and points (and a leading minus) before " Hz".
        let start = before
            .rfind(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
            .map_or(0, |i| i + 1);
        let ends_word = !after.starts_with(|c: char| c.is_alphanumeric());
        match before[start..].parse::<f64>() {
            Ok(hz) if ends_word => {
                out.push_str(&before[..start]);
                out.push_str(&format!("{:.0} rpm", hz * RPM_PER_HZ));
            }
            _ => {
                out.push_str(before);
                out.push_str(" Hz");
            }
        }
        rest = after;
    }
    out.push_str(rest);
    out
}

fn texts_in_rpm(annotations: &mut [Annotation], lines: &mut [RefLine]) {
    for a in annotations {
        a.text = speeds_in_rpm(&a.text);
    }
    for label in lines.iter_mut().filter_map(|l| l.label.as_mut()) {
        *label = speeds_in_rpm(label);
    }
}

fn scale(values: &mut [f64]) {
    values.iter_mut().for_each(|v| *v *= RPM_PER_HZ);
}

fn scale_range(range: &mut Option<(f64, f64)>) {
    if let Some((lo, hi)) = range {
        *lo *= RPM_PER_HZ;
        *hi *= RPM_PER_HZ;
    }
}

fn relabel(label: &mut String) {
    *label = label.replace("[Hz]", "[rpm]");
}

impl SpeedInRpm for Figure2d {
    fn speed_in_rpm(mut self, axis: SpeedAxis) -> Self {
        match axis {
            SpeedAxis::X => {
                self.series.iter_mut().for_each(|s| scale(&mut s.x));
                self.annotations.iter_mut().for_each(|a| a.x *= RPM_PER_HZ);
                self.vertical_lines
                    .iter_mut()
                    .for_each(|l| l.value *= RPM_PER_HZ);
                scale_range(&mut self.x_range);
                relabel(&mut self.x_label);
                texts_in_rpm(&mut self.annotations, &mut self.vertical_lines);
            }
            SpeedAxis::Y => {
                self.series.iter_mut().for_each(|s| scale(&mut s.y));
                self.annotations.iter_mut().for_each(|a| a.y *= RPM_PER_HZ);
                self.horizontal_lines
                    .iter_mut()
                    .for_each(|l| l.value *= RPM_PER_HZ);
                scale_range(&mut self.y_range);
                relabel(&mut self.y_label);
                texts_in_rpm(&mut self.annotations, &mut self.horizontal_lines);
            }
        }
        self
    }

    fn speed_texts_in_rpm(mut self) -> Self {
        texts_in_rpm(&mut self.annotations, &mut self.vertical_lines);
        texts_in_rpm(&mut self.annotations, &mut self.horizontal_lines);
        self
    }
}

impl SpeedInRpm for Grid {
    fn speed_in_rpm(mut self, axis: SpeedAxis) -> Self {
        self.panels = self
            .panels
            .into_iter()
            .map(|p| p.speed_in_rpm(axis))
            .collect();
        self
    }

    fn speed_texts_in_rpm(mut self) -> Self {
        self.panels = self
            .panels
            .into_iter()
            .map(SpeedInRpm::speed_texts_in_rpm)
            .collect();
        self
    }
}

impl SpeedInRpm for HeatMap {
    fn speed_in_rpm(mut self, axis: SpeedAxis) -> Self {
        match axis {
            SpeedAxis::X => {
                scale(&mut self.x);
                self.overlays.iter_mut().for_each(|s| scale(&mut s.x));
                relabel(&mut self.x_label);
            }
            SpeedAxis::Y => {
                scale(&mut self.y);
                self.overlays.iter_mut().for_each(|s| scale(&mut s.y));
                relabel(&mut self.y_label);
            }
        }
        self
    }

    fn speed_texts_in_rpm(self) -> Self {
        // A heat map's texts are its axis labels and its overlays' legend entries.
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Annotation, RefLine, Series};

    #[test]
    fn only_the_speed_axis_moves() {
        let mut fig = Figure2d::new("t", "Spin speed [Hz]", "Frequency [Hz]");
        fig.series
            .push(Series::new(vec![10.0, 20.0], vec![10.0, 20.0]));
        fig.annotations.push(Annotation::new(10.0, 10.0, "10 Hz"));
        fig.vertical_lines
            .push(RefLine::new(15.0).label("max operating 15 Hz"));
        fig.x_range = Some((0.0, 25.0));
        let fig = fig.speed_in_rpm(SpeedAxis::X);
        assert_eq!(fig.x_label, "Spin speed [rpm]");
        assert_eq!(fig.y_label, "Frequency [Hz]");
        assert_eq!(fig.series[0].x, vec![600.0, 1200.0]);
        assert_eq!(fig.series[0].y, vec![10.0, 20.0]);
        assert_eq!((fig.annotations[0].x, fig.annotations[0].y), (600.0, 10.0));
        assert_eq!(fig.annotations[0].text, "600 rpm");
        assert_eq!(fig.vertical_lines[0].value, 900.0);
        assert_eq!(
            fig.vertical_lines[0].label.as_deref(),
            Some("max operating 900 rpm")
        );
        assert_eq!(fig.x_range, Some((0.0, 1500.0)));
    }

    #[test]
    fn speeds_in_texts_are_rewritten_and_nothing_else() {
        assert_eq!(speeds_in_rpm("49.9 Hz, AF 3.2"), "2994 rpm, AF 3.2");
        assert_eq!(
            speeds_in_rpm("24.9 Hz B/F / 30.1 Hz F"),
            "1494 rpm B/F / 1806 rpm F"
        );
        assert_eq!(speeds_in_rpm("min operating 1 Hz"), "min operating 60 rpm");
        // Not a speed in Hz: left alone.
        assert_eq!(speeds_in_rpm("1X"), "1X");
        assert_eq!(speeds_in_rpm("a Hzb"), "a Hzb");
        assert_eq!(speeds_in_rpm("x Hz"), "x Hz");
        assert_eq!(speeds_in_rpm("12 Hzz"), "12 Hzz");
    }
}
