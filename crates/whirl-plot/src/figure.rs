//! The x-y figure: lines and markers on linear or logarithmic axes, with reference lines and
//! text annotations.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::axis::{to_chart, Axis, PAD_X, PAD_Y};
use crate::chart::{draw_error, draw_mesh, draw_title, font, split_title, Built, Frame};
use crate::font::Metrics;
use crate::render::{save, Render};
use crate::series::{draw_all, draw_legend, LegendPosition, Series};
use crate::style::Colour;
use crate::{PlotError, FIGURE_SIZE};

/// A text label at a data point, drawn above and beside it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Annotation {
    /// Abscissa of the labelled point, in data units.
    pub x: f64,
    /// Ordinate of the labelled point, in data units.
    pub y: f64,
    /// The text.
    pub text: String,
    /// Also draw a small dot at the point.
    pub mark: bool,
}

impl Annotation {
    /// Text at `(x, y)` without a dot.
    pub fn new(x: f64, y: f64, text: impl Into<String>) -> Self {
        Annotation {
            x,
            y,
            text: text.into(),
            mark: false,
        }
    }

    /// The same annotation with a dot at the point.
    pub fn marked(self) -> Self {
        Annotation { mark: true, ..self }
    }
}

/// A dashed vertical or horizontal line across the plot at a fixed value, e.g. a critical speed
/// or an alarm level.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RefLine {
    /// Position on the axis it crosses, in data units.
    pub value: f64,
    /// Text written next to the line.
    pub label: Option<String>,
    /// Colour of the line and its label.
    pub colour: Colour,
}

impl RefLine {
    /// A grey unlabelled line at `value`.
    pub fn new(value: f64) -> Self {
        RefLine {
            value,
            label: None,
            colour: Colour::GREY,
        }
    }

    /// The same line with a label.
    pub fn label(self, label: impl Into<String>) -> Self {
        RefLine {
            label: Some(label.into()),
            ..self
        }
    }
}

/// An x-y figure.
///
/// Axis ranges not given explicitly fit the drawable points (those inside the other axis' explicit
/// range, if it has one) with a small margin. Reference lines and annotations do not widen the
/// ranges; those outside are not drawn.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Figure2d {
    /// Title above the plot; empty for none.
    pub title: String,
    /// x axis description, with unit: `"Speed [rpm]"`.
    pub x_label: String,
    /// y axis description, with unit.
    pub y_label: String,
    /// The curves, drawn in order (later on top).
    pub series: Vec<Series>,
    /// Fixed x limits in data units; `None` fits the data.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y limits in data units; `None` fits the data.
    pub y_range: Option<(f64, f64)>,
    /// Logarithmic x axis (points with x <= 0 are not drawn).
    pub log_x: bool,
    /// Logarithmic y axis (points with y <= 0 are not drawn).
    pub log_y: bool,
    /// Same scale on x and y, for orbits: the ranges are widened until one data unit spans as
    /// many pixels on both axes. Ignored when an axis is logarithmic.
    pub equal_aspect: bool,
    /// Where the legend goes. Only labelled series appear in it.
    pub legend: LegendPosition,
    /// Text labels at data points.
    pub annotations: Vec<Annotation>,
    /// Vertical reference lines at fixed x.
    pub vertical_lines: Vec<RefLine>,
    /// Horizontal reference lines at fixed y.
    pub horizontal_lines: Vec<RefLine>,
    /// Size in pixels when saved on its own (ignored inside a [`crate::Grid`]).
    pub size: (u32, u32),
}

impl Default for Figure2d {
    fn default() -> Self {
        Figure2d {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            series: Vec::new(),
            x_range: None,
            y_range: None,
            log_x: false,
            log_y: false,
            equal_aspect: false,
            legend: LegendPosition::default(),
            annotations: Vec::new(),
            vertical_lines: Vec::new(),
            horizontal_lines: Vec::new(),
            size: FIGURE_SIZE,
        }
    }
}

impl Figure2d {
    /// An empty figure with a title and axis descriptions.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Figure2d {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Figure2d::default()
        }
    }

    /// The same figure with one more series.
    pub fn with_series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Writes `stem.png` and `stem.svg` (creating the parent directory if needed) and returns
    /// their paths, PNG first.
    pub fn save(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        save(self, stem)
    }

    /// Resolves both axes from explicit ranges or the data.
    pub(crate) fn axes(&self) -> Result<(Axis, Axis), PlotError> {
        for (i, s) in self.series.iter().enumerate() {
            s.check(i)?;
        }
        let inside =
            |v: f64, range: Option<(f64, f64)>| range.is_none_or(|(lo, hi)| v >= lo && v <= hi);
        let points: Vec<(f64, f64)> = self
            .series
            .iter()
            .flat_map(|s| s.x.iter().copied().zip(s.y.iter().copied()))
            .filter(|&(x, y)| {
                to_chart(x, self.log_x).is_some()
                    && to_chart(y, self.log_y).is_some()
                    && inside(x, self.x_range)
                    && inside(y, self.y_range)
            })
            .collect();
        let x = Axis::resolve(
            "x",
            points.iter().map(|p| p.0),
            self.x_range,
            self.log_x,
            PAD_X,
        )?;
        let y = Axis::resolve(
            "y",
            points.iter().map(|p| p.1),
            self.y_range,
            self.log_y,
            PAD_Y,
        )?;
        Ok((x, y))
    }

    /// The axes frame of this figure.
    fn frame(&self, m: Metrics, min_y_area: u32) -> Result<Frame<'_>, PlotError> {
        let (x, y) = self.axes()?;
        Ok(Frame {
            x,
            y,
            x_label: &self.x_label,
            y_label: &self.y_label,
            m,
            equal_aspect: self.equal_aspect,
            min_y_area,
        })
    }

    /// Width of the y label area this figure needs on `area`, without drawing anything.
    pub(crate) fn y_area_on<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        m: Metrics,
    ) -> Result<u32, PlotError> {
        let (_, plot_area) = split_title(area, &self.title, m);
        let y_area = self.frame(m, 0)?.build(&plot_area)?.y_area;
        Ok(y_area)
    }

    /// Draws the figure on `area`; `min_y_area` widens the y label area (device pixels).
    pub(crate) fn draw_on<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        m: Metrics,
        min_y_area: u32,
    ) -> Result<(), PlotError> {
        let (strip, plot_area) = split_title(area, &self.title, m);
        if let Some(strip) = strip {
            draw_title(&strip, &self.title, m)?;
        }
        let frame = self.frame(m, min_y_area)?;
        let mut built = frame.build(&plot_area)?;
        draw_mesh(&mut built, &frame, true)?;
        draw_ref_lines(&built, &self.vertical_lines, &self.horizontal_lines)?;
        draw_all(&mut built, &self.series)?;
        draw_annotations(&built, &self.annotations)?;
        draw_legend(&mut built, &self.series, self.legend)
    }
}

impl Render for Figure2d {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn check(&self) -> Result<(), PlotError> {
        self.axes().map(|_| ())
    }

    fn render<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        scale: f64,
    ) -> Result<(), PlotError> {
        self.draw_on(root, Metrics::FULL.scaled(scale), 0)
    }
}

/// Whether chart-space `c` lies in the right quarter of `axis`, where text should go leftwards.
fn near_high_end(axis: &Axis, c: f64) -> bool {
    c > axis.lo + 0.75 * (axis.hi - axis.lo)
}

/// Horizontal pixel spans of the labels drawn so far, per row.
#[derive(Default)]
struct LabelRows(Vec<Vec<(f64, f64)>>);

impl LabelRows {
    /// The first row where `span` overlaps no label, and records it there.
    fn place(&mut self, span: (f64, f64)) -> usize {
        let free = |row: &Vec<(f64, f64)>| row.iter().all(|&(a, b)| span.1 < a || span.0 > b);
        let row = self.0.iter().position(free).unwrap_or(self.0.len());
        if row == self.0.len() {
            self.0.push(Vec::new());
        }
        self.0[row].push(span);
        row
    }
}

fn draw_ref_lines<DB: DrawingBackend>(
    built: &Built<'_, DB>,
    vertical: &[RefLine],
    horizontal: &[RefLine],
) -> Result<(), PlotError> {
    let (x, y, m) = (built.x, built.y, built.m);
    let (dash, gap, width) = (m.upx(8.0), m.upx(5.0), m.stroke(2));
    let area = built.chart.plotting_area();
    let mut rows = LabelRows::default();
    for line in vertical {
        let Some(c) = x.to_chart(line.value).filter(|c| x.contains(*c)) else {
            continue;
        };
        let colour = line.colour.to_plotters();
        let path = vec![(c, y.lo), (c, y.hi)];
        area.draw(&DashedPathElement::new(
            path,
            dash,
            gap,
            colour.stroke_width(width),
        ))
        .map_err(draw_error)?;
        if let Some(label) = &line.label {
            let (h, dx) = if near_high_end(&x, c) {
                (HPos::Right, -5.0)
            } else {
                (HPos::Left, 5.0)
            };
            let style = font(m.legend).color(&colour).pos(Pos::new(h, VPos::Top));
            // Labels of close lines would overprint: each goes down to the first row where
            // it clears the labels already drawn.
            let (px, _) = area.map_coordinate(&(c, y.hi));
            let width =
                0.6 * m.legend * m.scale * label.chars().count() as f64 + m.px(dx).abs() as f64;
            let span = match h {
                HPos::Right => (px as f64 - width, px as f64),
                _ => (px as f64, px as f64 + width),
            };
            let row = rows.place(span);
            let offset = (m.px(dx), m.px(5.0 + 1.3 * m.legend * row as f64));
            let element = EmptyElement::at((c, y.hi)) + Text::new(label.clone(), offset, style);
            area.draw(&element).map_err(draw_error)?;
        }
    }
    for line in horizontal {
        let Some(c) = y.to_chart(line.value).filter(|c| y.contains(*c)) else {
            continue;
        };
        let colour = line.colour.to_plotters();
        let path = vec![(x.lo, c), (x.hi, c)];
        area.draw(&DashedPathElement::new(
            path,
            dash,
            gap,
            colour.stroke_width(width),
        ))
        .map_err(draw_error)?;
        if let Some(label) = &line.label {
            let (v, dy) = if near_high_end(&y, c) {
                (VPos::Top, 4.0)
            } else {
                (VPos::Bottom, -4.0)
            };
            let style = font(m.legend).color(&colour).pos(Pos::new(HPos::Right, v));
            let offset = (m.px(-6.0), m.px(dy));
            let element = EmptyElement::at((x.hi, c)) + Text::new(label.clone(), offset, style);
            area.draw(&element).map_err(draw_error)?;
        }
    }
    Ok(())
}

fn draw_annotations<DB: DrawingBackend>(
    built: &Built<'_, DB>,
    annotations: &[Annotation],
) -> Result<(), PlotError> {
    let (rect, m) = (built.rect(), built.m);
    let area = built.chart.plotting_area();
    for a in annotations {
        let Some(p) = built.x.to_chart(a.x).zip(built.y.to_chart(a.y)) else {
            continue;
        };
        if !rect.contains(p) {
            continue;
        }
        let (h, dx) = if near_high_end(&built.x, p.0) {
            (HPos::Right, -6.0)
        } else {
            (HPos::Left, 6.0)
        };
        let style = font(m.legend).color(&BLACK).pos(Pos::new(h, VPos::Bottom));
        let offset = (m.px(dx), m.px(-4.0));
        let text = EmptyElement::at(p) + Text::new(a.text.clone(), offset, style);
        area.draw(&text).map_err(draw_error)?;
        if a.mark {
            area.draw(&Circle::new(p, m.px(3.5), BLACK.filled()))
                .map_err(draw_error)?;
        }
    }
    Ok(())
}
