//! Data series and how they are drawn: clipped line runs, markers, legend entries.

use plotters::chart::SeriesAnno;
use plotters::prelude::*;

use crate::axis::Axis;
use crate::chart::{draw_error, font, Built};
use crate::clip::{clip_polyline, split_sharp_turns, Point};
use crate::marker::{LegendSample, MarkerElement, LEGEND_SAMPLE};
use crate::style::{Line, Marker, Style};
use crate::PlotError;

/// One curve or point set.
///
/// Points where x or y is NaN or infinite (or not positive on a logarithmic axis) are not drawn
/// and break the line, so a tracked branch that disappears and comes back shows a gap.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Series {
    /// Legend text; `None` (or empty) keeps the series out of the legend.
    pub label: Option<String>,
    /// Abscissae, same length as `y`.
    pub x: Vec<f64>,
    /// Ordinates, same length as `x`.
    pub y: Vec<f64>,
    /// Look; the default is a solid line in the palette colour of the series' index.
    pub style: Style,
}

impl Series {
    /// A solid line through the points `(x[i], y[i])`, unlabelled.
    pub fn new(x: Vec<f64>, y: Vec<f64>) -> Self {
        Series {
            label: None,
            x,
            y,
            style: Style::default(),
        }
    }

    /// The same series with a legend label.
    pub fn label(self, label: impl Into<String>) -> Self {
        Series {
            label: Some(label.into()),
            ..self
        }
    }

    /// The same series with another style.
    pub fn style(self, style: Style) -> Self {
        Series { style, ..self }
    }

    /// Fails if x and y differ in length.
    pub(crate) fn check(&self, index: usize) -> Result<(), PlotError> {
        if self.x.len() == self.y.len() {
            return Ok(());
        }
        Err(PlotError::LengthMismatch {
            label: self.label.clone().unwrap_or_else(|| format!("#{index}")),
            x_len: self.x.len(),
            y_len: self.y.len(),
        })
    }

    /// The points in chart space, `None` where a point cannot be drawn.
    pub(crate) fn chart_points<'s>(
        &'s self,
        x: &'s Axis,
        y: &'s Axis,
    ) -> impl Iterator<Item = Option<Point>> + 's {
        self.x
            .iter()
            .zip(&self.y)
            .map(|(a, b)| Some((x.to_chart(*a)?, y.to_chart(*b)?)))
    }

    fn legend_text(&self) -> Option<&str> {
        self.label.as_deref().filter(|l| !l.is_empty())
    }
}

/// Where the legend box goes inside the plotting area.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LegendPosition {
    /// Top right corner.
    #[default]
    UpperRight,
    /// Top left corner.
    UpperLeft,
    /// Bottom left corner.
    LowerLeft,
    /// Bottom right corner.
    LowerRight,
    /// Top, centred.
    UpperMiddle,
    /// Bottom, centred.
    LowerMiddle,
    /// Right edge, centred vertically.
    MiddleRight,
    /// Left edge, centred vertically.
    MiddleLeft,
    /// No legend.
    Hidden,
}

/// Draws every series (line runs first, then markers) and registers their legend entries.
pub(crate) fn draw_all<'a, DB: DrawingBackend + 'a>(
    built: &mut Built<'a, DB>,
    series: &[Series],
) -> Result<(), PlotError> {
    let rect = built.rect();
    let m = built.m;
    let (dash, dash_gap) = (m.upx(10.0), m.upx(6.0));
    let (dot, dot_gap) = (m.stroke(2), m.upx(5.0));
    for (index, s) in series.iter().enumerate() {
        let style = s.style;
        let colour = style.colour_for(index).to_plotters();
        let stroke = colour.stroke_width(m.stroke(style.line_width));
        let scale = m.scale;
        let points: Vec<Option<Point>> = s.chart_points(&built.x, &built.y).collect();
        let mut label = s.legend_text();
        let attach = |anno: &mut SeriesAnno<'a, DB>, label: &mut Option<&str>| {
            if let Some(text) = label.take() {
                anno.label(text).legend(move |at| LegendSample {
                    at,
                    style,
                    colour,
                    scale,
                });
            }
        };
        if style.line != Line::None {
            let clipped = clip_polyline(points.iter().copied(), &rect);
            let coords = built.chart.as_coord_spec();
            let to_px = |p: Point| {
                let (x, y) = coords.translate(&p);
                (f64::from(x), f64::from(y))
            };
            let runs: Vec<Vec<Point>> = clipped
                .iter()
                .flat_map(|run| split_sharp_turns(run, to_px))
                .collect();
            for run in runs {
                let chart = &mut built.chart;
                let anno = match style.line {
                    Line::Dashed => {
                        chart.draw_series(DashedLineSeries::new(run, dash, dash_gap, stroke))
                    }
                    Line::Dotted => {
                        chart.draw_series(DashedLineSeries::new(run, dot, dot_gap, stroke))
                    }
                    _ => chart.draw_series(LineSeries::new(run, stroke)),
                };
                attach(anno.map_err(draw_error)?, &mut label);
            }
        }
        let marks: Vec<MarkerElement<Point>> = points
            .iter()
            .flatten()
            .filter(|p| style.marker != Marker::None && rect.contains(**p))
            .map(|p| MarkerElement {
                at: *p,
                marker: style.marker,
                size: style.marker_size,
                colour,
                scale,
            })
            .collect();
        if !marks.is_empty() {
            attach(
                built.chart.draw_series(marks).map_err(draw_error)?,
                &mut label,
            );
        }
        // Nothing visible: still give the legend its entry.
        if label.is_some() {
            let empty = LineSeries::new(Vec::<Point>::new(), stroke);
            attach(
                built.chart.draw_series(empty).map_err(draw_error)?,
                &mut label,
            );
        }
    }
    Ok(())
}

/// Draws the legend box if any series has a label and the position is not hidden.
pub(crate) fn draw_legend<'a, DB: DrawingBackend + 'a>(
    built: &mut Built<'a, DB>,
    series: &[Series],
    position: LegendPosition,
) -> Result<(), PlotError> {
    let m = built.m;
    use SeriesLabelPosition as P;
    let position = match position {
        LegendPosition::Hidden => return Ok(()),
        LegendPosition::UpperRight => P::UpperRight,
        LegendPosition::UpperLeft => P::UpperLeft,
        LegendPosition::LowerLeft => P::LowerLeft,
        LegendPosition::LowerRight => P::LowerRight,
        LegendPosition::UpperMiddle => P::UpperMiddle,
        LegendPosition::LowerMiddle => P::LowerMiddle,
        LegendPosition::MiddleRight => P::MiddleRight,
        LegendPosition::MiddleLeft => P::MiddleLeft,
    };
    if series.iter().all(|s| s.legend_text().is_none()) {
        return Ok(());
    }
    built
        .chart
        .configure_series_labels()
        .position(position)
        .label_font(font(m.legend))
        .legend_area_size(m.upx(f64::from(LEGEND_SAMPLE) + 6.0))
        .margin(m.upx(8.0))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.5).stroke_width(m.stroke(1)))
        .draw()
        .map_err(draw_error)
}
