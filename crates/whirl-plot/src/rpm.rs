//! Speed axes in revolutions per minute. Figures are built with speeds in Hz; for readers
//! who think in rpm, [`SpeedInRpm::speed_in_rpm`] multiplies everything placed along the
//! speed axis by 60 and says `[rpm]` where the axis label said `[Hz]`. Texts in the figure
//! (titles, annotations) keep what they say.

use crate::{Figure2d, Grid, HeatMap};

/// Revolutions per minute in one hertz.
pub const RPM_PER_HZ: f64 = 60.0;

/// The axis of a figure that shows a speed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
            }
            SpeedAxis::Y => {
                self.series.iter_mut().for_each(|s| scale(&mut s.y));
                self.annotations.iter_mut().for_each(|a| a.y *= RPM_PER_HZ);
                self.horizontal_lines
                    .iter_mut()
                    .for_each(|l| l.value *= RPM_PER_HZ);
                scale_range(&mut self.y_range);
                relabel(&mut self.y_label);
            }
        }
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
        fig.vertical_lines.push(RefLine::new(15.0));
        fig.x_range = Some((0.0, 25.0));
        let fig = fig.speed_in_rpm(SpeedAxis::X);
        assert_eq!(fig.x_label, "Spin speed [rpm]");
        assert_eq!(fig.y_label, "Frequency [Hz]");
        assert_eq!(fig.series[0].x, vec![600.0, 1200.0]);
        assert_eq!(fig.series[0].y, vec![10.0, 20.0]);
        assert_eq!((fig.annotations[0].x, fig.annotations[0].y), (600.0, 10.0));
        assert_eq!(fig.vertical_lines[0].value, 900.0);
        assert_eq!(fig.x_range, Some((0.0, 1500.0)));
    }
}
